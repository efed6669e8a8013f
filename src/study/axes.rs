//! Sweep axes: which scene keys vary over which values, and how they combine into runs.
//!
//! Axes multiply (Cartesian product, first written axis slowest); a zip group varies its axes
//! together, at the position of its first written axis; replicates repeat every grid point with
//! consecutive placement seeds (fastest of all).

use std::ops::Range;

use super::ParamValue;
pub use super::axis_error::Spacing;
use super::axis_error::{AxisError, Written};
use super::errors::StudyError;
use super::file::{Document, KeyPath, StudyFile, dotted, quoted_key};

/// The most runs one study may expand to.
pub const MAX_RUNS: usize = 1_000_000;

/// One swept scene key and its values.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Axis {
    /// Key path into the scene, e.g. `["material", "friction"]`.
    pub path: KeyPath,
    /// Where the axis is written in `[sweep]`.
    pub span: Range<usize>,
    /// The values, in order.
    pub values: Vec<ParamValue>,
}

impl Axis {
    /// The scene key, dotted: `material.friction`.
    pub fn key(&self) -> String {
        dotted(&self.path)
    }

    /// The axis as named in the study file: `sweep."material.friction"`.
    pub fn label(&self) -> String {
        label(&self.path)
    }
}

/// An axis of scene key `path` as named in the study file.
fn label(path: &[String]) -> String {
    format!("sweep.{}", quoted_key(&dotted(path)))
}

/// All axes of a study and how they combine.
#[derive(Debug)]
pub(super) struct Sweep {
    /// The axes, in written order.
    pub axes: Vec<Axis>,
    /// Dimensions of the product, slowest first; each lists the axes (indices) that vary together.
    pub dimensions: Vec<Vec<usize>>,
    /// Runs per grid point, each with its own placement seed.
    pub replicates: usize,
    /// Where `replicates` is written.
    pub replicates_span: Option<Range<usize>>,
}

impl Sweep {
    /// No axes and no replicates: a single run.
    pub fn single() -> Self {
        Self { axes: Vec::new(), dimensions: Vec::new(), replicates: 1, replicates_span: None }
    }

    /// Number of runs: grid points times replicates.
    pub fn run_count(&self) -> usize {
        self.dimensions.iter().map(|d| self.axes[d[0]].values.len()).product::<usize>() * self.replicates
    }

    /// For run `index`: the value index of every axis (in axis order) and the replicate index.
    pub fn point(&self, index: usize) -> (Vec<usize>, usize) {
        let mut rest = index / self.replicates;
        let mut chosen = vec![0; self.axes.len()];
        for dimension in self.dimensions.iter().rev() {
            let n = self.axes[dimension[0]].values.len();
            dimension.iter().for_each(|&a| chosen[a] = rest % n);
            rest /= n;
        }
        (chosen, index % self.replicates)
    }
}

/// Reads `[sweep]`: the well-formed axes, and every malformed axis, zip group or count.
pub(super) fn parse(doc: &Document, file: &StudyFile) -> (Sweep, Vec<StudyError>) {
    let mut sweep = Sweep::single();
    let Some(table) = doc.section("sweep").and_then(|s| s.as_table()) else {
        return (sweep, Vec::new());
    };
    let span = |key: &[&str]| doc.span(&key.iter().map(|s| s.to_string()).collect::<Vec<_>>());
    let mut errors = Vec::new();
    let mut zip = None;
    for (key, value) in table {
        match key.as_str() {
            "replicates" => match replicates(value) {
                Ok(k) => (sweep.replicates, sweep.replicates_span) = (k, span(&["sweep", key])),
                Err(reason) => errors.push(file.error(span(&["sweep", key]), "sweep.replicates", reason.to_string())),
            },
            "zip" => zip = Some(value),
            _ if !value.is_table() && !key.contains('.') => {
                errors.push(file.error(span(&["sweep", key]), format!("sweep.{key}"), misplaced_key(key)))
            }
            _ => collect_axes(
                doc,
                file,
                &mut vec!["sweep".to_string(), key.clone()],
                value,
                &mut sweep.axes,
                &mut errors,
            ),
        }
    }
    sweep.axes.sort_by_key(|a| a.span.start);
    errors.extend(duplicate_axes(&sweep.axes, file));
    let groups = match zip {
        Some(value) => {
            let at = span(&["sweep", "zip"]);
            zip_groups(value, &sweep.axes).map_err(|reason| file.error(at, "sweep.zip", reason.to_string()))
        }
        None => Ok(Vec::new()),
    };
    match groups {
        Ok(groups) => sweep.dimensions = dimensions(&sweep.axes, groups),
        Err(e) => errors.push(e),
    }
    if errors.is_empty() {
        let at = span(&["sweep"]);
        check_size(&sweep).map_err(|reason| errors.push(file.error(at, "sweep", reason.to_string()))).ok();
    }
    (sweep, errors)
}

/// Walks `value` (at document key path `doc_path`): axis specs become axes, other tables nest keys.
fn collect_axes(
    doc: &Document,
    file: &StudyFile,
    doc_path: &mut KeyPath,
    value: &toml::Value,
    axes: &mut Vec<Axis>,
    errors: &mut Vec<StudyError>,
) {
    if let Some(table) = value.as_table().filter(|t| !is_range_spec(t)) {
        for (key, inner) in table {
            doc_path.push(key.clone());
            collect_axes(doc, file, doc_path, inner, axes, errors);
            doc_path.pop();
        }
        return;
    }
    let path: KeyPath = doc_path[1..].iter().flat_map(|k| k.split('.')).map(String::from).collect();
    let span = doc.span(doc_path).unwrap_or(0..0);
    match axis_values(value) {
        Ok(values) => axes.push(Axis { path, span, values }),
        Err(reason) => errors.push(file.error(Some(span), label(&path), reason.to_string())),
    }
}

/// Why a plain `[sweep]` key that is neither `replicates`, `zip` nor a dotted scene path is wrong,
/// naming the keyword it is a typo of (`replicate = 3`: did you mean `replicates`?).
fn misplaced_key(key: &str) -> String {
    let not_axis =
        format!("`{key}` is not a sweep axis (axes are dotted scene key paths such as \"material.friction\")");
    match ["replicates", "zip"].into_iter().find(|keyword| edit_distance(key, keyword) <= 2) {
        Some(keyword) => format!("{not_axis}; did you mean `{keyword}`?"),
        None => format!("{not_axis}, nor `replicates` or `zip`"),
    }
}

/// Levenshtein distance between two short words.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let substitution = diagonal + usize::from(ca != *cb);
            diagonal = row[j + 1];
            row[j + 1] = substitution.min(row[j] + 1).min(diagonal + 1);
        }
    }
    row[b.len()]
}

pub(crate) fn is_range_spec(table: &toml::Table) -> bool {
    ["linear", "log", "steps"].iter().any(|k| table.contains_key(*k))
}

/// An axis is written twice (e.g. once quoted, once as nested tables).
fn duplicate_axes(axes: &[Axis], file: &StudyFile) -> Vec<StudyError> {
    let mut errors = Vec::new();
    for (i, later) in axes.iter().enumerate() {
        if let Some(first) = axes[..i].iter().find(|a| a.path == later.path) {
            let line = file.locate(first.span.start).line;
            errors.push(file.error(
                Some(later.span.clone()),
                later.label(),
                format!("swept twice (also on line {line})"),
            ));
        }
    }
    errors
}

fn replicates(value: &toml::Value) -> Result<usize, AxisError> {
    match value.as_integer() {
        Some(k) if (1..=MAX_RUNS as i64).contains(&k) => Ok(k as usize),
        Some(k) => Err(AxisError::Replicates { written: Written::Integer(k), max: MAX_RUNS }),
        None => Err(AxisError::Replicates { written: Written::Other(value.type_str()), max: MAX_RUNS }),
    }
}

/// The values of one axis: a list `[v1, v2, ...]`, `{ linear = [a, b], steps = n }` or
/// `{ log = [a, b], steps = n }` (both ends included).
pub(super) fn axis_values(spec: &toml::Value) -> Result<Vec<ParamValue>, AxisError> {
    const SHAPE: &str =
        "an axis is a list [v1, v2, ...], { linear = [a, b], steps = n } or { log = [a, b], steps = n }";
    match spec {
        toml::Value::Array(items) if items.is_empty() => Err(AxisError::EmptyAxis),
        toml::Value::Array(items) => items.iter().map(scalar).collect(),
        toml::Value::Table(table) => range_values(table).map(|v| v.into_iter().map(ParamValue::Float).collect()),
        other => Err(AxisError::Shape { shape: SHAPE, found: other.type_str() }),
    }
}

/// A list element as a parameter value.
pub(crate) fn scalar(value: &toml::Value) -> Result<ParamValue, AxisError> {
    match value {
        toml::Value::Float(v) => Ok(ParamValue::Float(*v)),
        toml::Value::Integer(v) => Ok(ParamValue::Int(*v)),
        toml::Value::Boolean(v) => Ok(ParamValue::Bool(*v)),
        toml::Value::String(v) => Ok(ParamValue::Text(v.clone())),
        other => Err(AxisError::NotScalar(other.type_str())),
    }
}

/// The ends of a `{ linear = [a, b] }` or `{ log = [a, b] }` table: a study axis (with `steps`) or a
/// tune lever.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RangeEnds {
    /// How values are spaced between the ends.
    pub spacing: Spacing,
    /// The first end, as written.
    pub a: f64,
    /// The second end, as written.
    pub b: f64,
    /// Whether both ends are written as integers.
    pub integer: bool,
}

/// Reads a range table whose keys are `linear` or `log` and those in `extra`; `shape` (what such
/// a table looks like) ends the error messages.
pub(crate) fn range_ends(table: &toml::Table, extra: &[&str], shape: &'static str) -> Result<RangeEnds, AxisError> {
    let known = |k: &str| ["linear", "log"].contains(&k) || extra.contains(&k);
    if let Some(unknown) = table.keys().find(|k| !known(k)) {
        let valid = ["linear", "log"].iter().chain(extra).copied();
        let nearest = super::errors::nearest(unknown, valid).map(String::from);
        return Err(AxisError::UnknownKey { key: unknown.clone(), nearest, shape });
    }
    let (spacing, ends) = match (table.get("linear"), table.get("log")) {
        (Some(ends), None) => (Spacing::Linear, ends),
        (None, Some(ends)) => (Spacing::Log, ends),
        _ => return Err(AxisError::OneSpacing { shape }),
    };
    let (a, b) = endpoints(ends).map_err(|written| AxisError::Ends { spacing, written })?;
    if spacing == Spacing::Log && (a <= 0.0 || b <= 0.0) {
        return Err(AxisError::LogEnds { a, b });
    }
    let integer = ends.as_array().is_some_and(|ends| ends.iter().all(toml::Value::is_integer));
    Ok(RangeEnds { spacing, a, b, integer })
}

/// Evenly spaced values of a `linear` or `log` range table.
fn range_values(table: &toml::Table) -> Result<Vec<f64>, AxisError> {
    const SHAPE: &str = "an axis range is { linear = [a, b], steps = n } or { log = [a, b], steps = n }";
    let RangeEnds { spacing, a, b, .. } = range_ends(table, &["steps"], SHAPE)?;
    let steps = match table.get("steps").map(|s| s.as_integer()) {
        Some(Some(n)) if n >= 1 => n as usize,
        Some(Some(n)) => return Err(AxisError::StepsBelowOne(n)),
        Some(None) => return Err(AxisError::StepsNotInteger),
        None => return Err(AxisError::NoSteps(spacing)),
    };
    if steps == 1 && a != b {
        return Err(AxisError::OneStep { a, b });
    }
    if steps > MAX_RUNS {
        return Err(AxisError::TooManySteps { steps, max: MAX_RUNS });
    }
    Ok(match spacing {
        Spacing::Log => log_range(a, b, steps),
        Spacing::Linear => linear_range(a, b, steps),
    })
}

/// The two finite ends `[a, b]`; else the value as written when it is no pair of numbers (None:
/// numbers, not finite).
fn endpoints(value: &toml::Value) -> Result<(f64, f64), Option<toml::Value>> {
    let number = |v: &toml::Value| v.as_float().or_else(|| v.as_integer().map(|i| i as f64));
    let ends: Option<Vec<f64>> = value.as_array().filter(|a| a.len() == 2).and_then(|a| a.iter().map(number).collect());
    match ends.as_deref() {
        Some(&[a, b]) if a.is_finite() && b.is_finite() => Ok((a, b)),
        Some(_) => Err(None),
        None => Err(Some(value.clone())),
    }
}

/// `steps` values from `a` to `b` (both exact), evenly spaced.
pub(super) fn linear_range(a: f64, b: f64, steps: usize) -> Vec<f64> {
    spaced(steps, a, b, |t| a + (b - a) * t)
}

/// `steps` values from `a` to `b` (both exact, > 0), evenly spaced in log scale.
pub(super) fn log_range(a: f64, b: f64, steps: usize) -> Vec<f64> {
    spaced(steps, a, b, |t| a * (b / a).powf(t))
}

/// Ends exact; interior points `at(i / (steps - 1))` rounded to 12 significant digits,
/// so that `linear = [0, 0.6], steps = 4` gives 0.2 and 0.4 as written.
fn spaced(steps: usize, a: f64, b: f64, at: impl Fn(f64) -> f64) -> Vec<f64> {
    let round = |v: f64| format!("{v:.11e}").parse::<f64>().unwrap_or(v);
    (0..steps)
        .map(|i| match i {
            0 => a,
            i if i == steps - 1 => b,
            i => round(at(i as f64 / (steps - 1) as f64)),
        })
        .collect()
}

/// `zip = ["a", "b"]` (one group) or `zip = [["a", "b"], ["c", "d"]]`: groups of axis indices.
fn zip_groups(value: &toml::Value, axes: &[Axis]) -> Result<Vec<Vec<usize>>, AxisError> {
    let list = value.as_array().ok_or(AxisError::ZipShape)?;
    let names: Vec<Vec<&toml::Value>> = if list.iter().all(|v| v.is_str()) {
        vec![list.iter().collect()]
    } else {
        list.iter()
            .map(|g| g.as_array().map(|g| g.iter().collect()).ok_or(AxisError::ZipShape))
            .collect::<Result<_, _>>()?
    };
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for group in names {
        let indices = group.iter().map(|name| zip_member(name, axes, &groups)).collect::<Result<Vec<_>, _>>()?;
        check_group(&indices, axes)?;
        groups.push(indices);
    }
    Ok(groups)
}

fn zip_member(name: &toml::Value, axes: &[Axis], earlier: &[Vec<usize>]) -> Result<usize, AxisError> {
    let name = name.as_str().ok_or(AxisError::ZipName)?;
    let k = axes.iter().position(|a| a.key() == name).ok_or_else(|| AxisError::ZipUnknown(name.to_string()))?;
    if earlier.iter().flatten().any(|&j| j == k) {
        return Err(AxisError::ZipTwice(name.to_string()));
    }
    Ok(k)
}

fn check_group(group: &[usize], axes: &[Axis]) -> Result<(), AxisError> {
    let names = || group.iter().map(|&k| axes[k].key()).collect::<Vec<_>>();
    if group.len() < 2 {
        return Err(AxisError::ZipTooSmall(names()));
    }
    if group.iter().any(|&k| group.iter().filter(|&&j| j == k).count() > 1) {
        return Err(AxisError::ZipRepeated(names()));
    }
    let lengths: Vec<usize> = group.iter().map(|&k| axes[k].values.len()).collect();
    if lengths.iter().any(|&n| n != lengths[0]) {
        return Err(AxisError::ZipLengths(group.iter().map(|&k| (axes[k].key(), axes[k].values.len())).collect()));
    }
    Ok(())
}

/// The product's dimensions in written order: single axes, and zip groups at their first axis.
fn dimensions(axes: &[Axis], groups: Vec<Vec<usize>>) -> Vec<Vec<usize>> {
    let mut dims: Vec<Vec<usize>> =
        (0..axes.len()).filter(|k| !groups.iter().flatten().any(|j| j == k)).map(|k| vec![k]).collect();
    dims.extend(groups.into_iter().map(|mut g| {
        g.sort();
        g
    }));
    dims.sort_by_key(|d| d[0]);
    dims
}

fn check_size(sweep: &Sweep) -> Result<(), AxisError> {
    let grid = sweep.dimensions.iter().try_fold(1usize, |n, d| n.checked_mul(sweep.axes[d[0]].values.len()));
    match grid.and_then(|n| n.checked_mul(sweep.replicates)) {
        Some(n) if n <= MAX_RUNS => Ok(()),
        _ => Err(AxisError::TooManyRuns { max: MAX_RUNS }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn values(spec: &str) -> Result<Vec<ParamValue>, String> {
        let table: toml::Table = toml::from_str(&format!("a = {spec}")).unwrap();
        axis_values(&table["a"]).map_err(|e| e.to_string())
    }

    #[test]
    fn ranges_hit_their_ends_exactly() {
        assert_eq!(linear_range(0.0, 0.6, 4), vec![0.0, 0.2, 0.4, 0.6]);
        assert_eq!(log_range(1e8, 1e10, 3), vec![1e8, 1e9, 1e10]);
        assert_eq!(log_range(1e-3, 1e-1, 5)[4], 1e-1);
        assert_eq!(linear_range(0.3, 0.3, 1), vec![0.3]);
        let odd = linear_range(0.1, 0.9, 7);
        assert_eq!((odd[0], odd[6], odd.len()), (0.1, 0.9, 7));
        assert!((odd[3] - 0.5).abs() < 1e-15);
    }

    #[test]
    fn lists_keep_their_types() {
        let v = values("[1, 2.5, true, \"linear\"]").unwrap();
        assert_eq!(
            v,
            vec![ParamValue::Int(1), ParamValue::Float(2.5), ParamValue::Bool(true), ParamValue::Text("linear".into())]
        );
        assert_eq!(
            values("{ linear = [1, 2], steps = 2 }").unwrap(),
            vec![ParamValue::Float(1.0), ParamValue::Float(2.0)]
        );
    }

    #[test]
    fn malformed_axes_say_why() {
        assert!(values("[]").unwrap_err().contains("at least one value"));
        assert!(values("0.5").unwrap_err().contains("got a single float"));
        assert!(values("[[1, 2]]").unwrap_err().contains("found an array"));
        assert!(values("{ log = [0, 1], steps = 3 }").unwrap_err().contains("log: the ends must be > 0"));
        assert!(values("{ log = [-1, 1], steps = 3 }").unwrap_err().contains("must be > 0"));
        assert!(values("{ linear = [0, 1], steps = 0 }").unwrap_err().contains("at least 1, got 0"));
        assert!(values("{ linear = [0, 1], steps = 1 }").unwrap_err().contains("ends 0 and 1 differ"));
        assert!(values("{ linear = [0, 1] }").unwrap_err().contains("needs steps"));
        assert!(values("{ linear = [0, 1, 2], steps = 2 }").unwrap_err().contains("two numbers"));
        assert!(values("{ linear = [0, 1], log = [1, 2], steps = 2 }").unwrap_err().contains("exactly one"));
        assert!(values("{ lin = [0, 1], steps = 2 }").unwrap_err().contains("unknown key \"lin\""));
    }
}

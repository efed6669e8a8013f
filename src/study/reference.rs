//! `[report] reference = { "material.restitution" = 0.5, "material.friction" = 0.6 }`: the grid
//! point the report's answer compares every other point with (as `demsweep compare` does).

use super::ParamValue;
use super::axes::{self, Sweep};
use super::errors::{StudyError, did_you_mean};
use super::file::{Document, StudyFile, dotted, leaves};

/// The keys of `[report]`.
const KEYS: [&str; 1] = ["reference"];

/// The problems of `[report]`: unknown keys, a reference that is not a table, keys that are not
/// swept parameters, values that are not among their axis's values, swept dimensions left unnamed.
/// While an axis is `faulty` (its own error reported), a key matching no axis and a dimension left
/// unnamed are not problems of their own: the reference may well name what the axis meant.
pub(super) fn check(file: &StudyFile, doc: &Document, sweep: &Sweep, faulty: &[bool]) -> Vec<StudyError> {
    let Some(report) = doc.section("report").and_then(|r| r.as_table()) else {
        return Vec::new();
    };
    let at = |path: &[&str]| {
        let path: Vec<String> = path.iter().map(|s| s.to_string()).collect();
        (doc.nearest_span(&path), dotted(&path))
    };
    let mut errors = Vec::new();
    for key in report.keys().filter(|k| !KEYS.contains(&k.as_str())) {
        let (span, name) = at(&["report", key]);
        let hint = did_you_mean(key, KEYS).unwrap_or_else(|| format!("[report] has {}", KEYS.join(", ")));
        errors.push(file.error(span, name, format!("unknown key ({hint})")));
    }
    let Some(reference) = report.get("reference") else {
        return errors;
    };
    let (span, name) = at(&["report", "reference"]);
    let Some(reference) = reference.as_table() else {
        let reason = "must be a table of swept values, e.g. { \"material.friction\" = 0.6 }";
        errors.push(file.error(span, name, reason));
        return errors;
    };
    let swept: Vec<String> = sweep.axes.iter().filter(|a| !is_seed(&a.key())).map(|a| a.key()).collect();
    // For each axis: the value indices the reference's value matches (None: not named).
    let mut matched: Vec<Option<Vec<usize>>> = vec![None; sweep.axes.len()];
    for (path, value) in leaves(reference) {
        let key = path.join(".");
        let (span, name) = (doc.nearest_span(&full_path(&path)), format!("report.reference.{}", dotted(&path)));
        let Some(axis) = sweep.axes.iter().position(|a| a.path.join(".") == key && !is_seed(&key)) else {
            if faulty.contains(&true) {
                continue;
            }
            let reason = format!("`{key}` is not a swept parameter; the swept parameters are: {}", swept.join(", "));
            errors.push(file.error(span, name, reason));
            continue;
        };
        let values = &sweep.axes[axis].values;
        let hits: Vec<usize> = match axes::scalar(value) {
            Ok(wanted) => (0..values.len()).filter(|&i| same(&values[i], &wanted)).collect(),
            Err(reason) => {
                errors.push(file.error(span, name, reason.to_string()));
                continue;
            }
        };
        if hits.is_empty() {
            let listed: Vec<String> = values.iter().map(ToString::to_string).collect();
            let reason = format!("{value} is not a value of this axis; its values are: {}", listed.join(", "));
            errors.push(file.error(span, name, reason));
        }
        matched[axis] = Some(hits);
    }
    if errors.is_empty() && !faulty.contains(&true) {
        errors.extend(unnamed_or_mismatched(sweep, &matched).map(|reason| file.error(span, name, reason)));
    }
    errors
}

/// A grid dimension the reference names no axis of, or whose zipped axes it names at different positions.
fn unnamed_or_mismatched(sweep: &Sweep, matched: &[Option<Vec<usize>>]) -> Option<String> {
    for dimension in &sweep.dimensions {
        let keys: Vec<String> = dimension.iter().map(|&a| sweep.axes[a].key()).collect();
        if keys.iter().all(|k| is_seed(k)) {
            continue;
        }
        let named: Vec<&Vec<usize>> = dimension.iter().filter_map(|&a| matched[a].as_ref()).collect();
        let Some(first) = named.first() else {
            return Some(format!("names no value of {}: a reference is one grid point", keys.join(" / ")));
        };
        if !first.iter().any(|i| named.iter().all(|n| n.contains(i))) {
            return Some(format!("the values of the zipped axes {} are not at one position", keys.join(", ")));
        }
    }
    None
}

/// `report.reference.<path>` as a key path of the document.
fn full_path(path: &[String]) -> Vec<String> {
    ["report", "reference"].iter().map(|s| s.to_string()).chain(path.iter().cloned()).collect()
}

/// The placement seed is not a grid coordinate: a point holds every seed.
fn is_seed(key: &str) -> bool {
    key == "placement.seed"
}

/// Whether two axis values are the same (floats within a relative 1e-9, integers as floats).
fn same(a: &ParamValue, b: &ParamValue) -> bool {
    let number = |v: &ParamValue| match v {
        ParamValue::Float(x) => Some(*x),
        ParamValue::Int(i) => Some(*i as f64),
        _ => None,
    };
    match (number(a), number(b)) {
        (Some(x), Some(y)) => (x - y).abs() <= 1e-9 * x.abs().max(y.abs()),
        _ => a == b,
    }
}

/// The reference point a study's text names, as `demsweep compare --reference` takes it
/// (`material.restitution=0.5,material.friction=0.6`); `None` when it names none.
pub fn reference_spec(study_text: &str) -> Option<String> {
    let study: toml::Table = toml::from_str(study_text).ok()?;
    let reference = study.get("report")?.as_table()?.get("reference")?.as_table()?;
    let pairs: Vec<String> = leaves(reference)
        .into_iter()
        .map(|(path, value)| match value {
            toml::Value::String(text) => format!("{}={text}", path.join(".")),
            other => format!("{}={other}", path.join(".")),
        })
        .collect();
    (!pairs.is_empty()).then(|| pairs.join(","))
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;

    fn errors(report: &str) -> Vec<String> {
        let text = format!(
            "[scene.particles]\ncount = 4\n[sweep]\n\"material.restitution\" = [0.1, 0.5]\n\"material.friction\" = [0.2, 0.6]\nreplicates = 2\n{report}"
        );
        let file = StudyFile::new(Path::new("s.toml"), text);
        let doc = Document::parse(&file).unwrap();
        let (sweep, sweep_errors) = axes::parse(&doc, &file);
        assert!(sweep_errors.is_empty());
        check(&file, &doc, &sweep, &[false, false]).iter().map(|e| format!("{}: {}", e.key, e.reason)).collect()
    }

    #[test]
    fn a_reference_names_one_grid_point_by_swept_values() {
        let good = "[report]\nreference = { \"material.restitution\" = 0.5, \"material.friction\" = 0.6 }\n";
        assert_eq!(errors(good), Vec::<String>::new());
        let unknown = errors("[report]\nreferense = 1\nreference = { \"material.density\" = 1.0 }\n");
        assert!(unknown[0].starts_with("report.referense: unknown key"), "{unknown:?}");
        assert!(unknown[1].contains("`material.density` is not a swept parameter"), "{unknown:?}");
        let off_grid =
            errors("[report]\nreference = { \"material.restitution\" = 0.4, \"material.friction\" = 0.6 }\n");
        assert!(off_grid[0].contains("0.4 is not a value of this axis; its values are: 0.1, 0.5"), "{off_grid:?}");
        let partial = errors("[report]\nreference = { \"material.restitution\" = 0.5 }\n");
        assert!(partial[0].starts_with("report.reference: names no value of material.friction"), "{partial:?}");
        assert!(errors("[report]\nreference = 0.5\n")[0].contains("must be a table"));
    }

    #[test]
    fn the_spec_is_what_compare_takes() {
        let text = "[report]\nreference = { \"material.restitution\" = 0.5, \"material.friction\" = 0.6 }\n";
        assert_eq!(reference_spec(text).as_deref(), Some("material.friction=0.6,material.restitution=0.5"));
        assert_eq!(reference_spec("name = \"x\"\n"), None);
    }
}

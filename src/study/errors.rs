//! What is wrong with a study: every problem names the file, line (and column), key and reason.

use std::collections::HashMap;
use std::fmt;
use std::path::PathBuf;

use crate::physics::number::exact;
use crate::physics::warning::WarningKind;

/// A position in a text file, 1-based.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Location {
    /// Line number, from 1.
    pub line: usize,
    /// Column (character) number, from 1.
    pub column: usize,
}

/// A problem's file, location, key, value and reason (none for a warning, which is one per rule: see
/// [`ErrorSink::by_kind`]).
type Identity = (PathBuf, Option<Location>, String, Option<String>, Option<WarningKind>, Option<String>);

/// One problem with a study.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct StudyError {
    /// The file the problem is in (the study file, or a placement CSV).
    pub file: PathBuf,
    /// Where in the file, when known.
    pub location: Option<Location>,
    /// The key it concerns, as written in the study (e.g. `sweep."material.friction"`); empty for the
    /// file as a whole.
    pub key: String,
    /// The swept value involved, when the problem depends on it.
    pub value: Option<String>,
    /// The first run affected, when the problem belongs to runs.
    pub run: Option<String>,
    /// How many runs are affected (0 when the problem is not run-specific).
    pub runs_affected: usize,
    /// The validity rule a predicted warning is about; None for every other problem.
    pub rule: Option<WarningKind>,
    /// What is wrong, in words.
    pub reason: String,
}

impl StudyError {
    /// A problem at `location` of `file` with `key`, not tied to a run or value.
    pub fn new(
        file: impl Into<PathBuf>,
        location: Option<Location>,
        key: impl Into<String>,
        reason: impl Into<String>,
    ) -> Self {
        Self {
            file: file.into(),
            location,
            key: key.into(),
            value: None,
            run: None,
            runs_affected: 0,
            rule: None,
            reason: reason.into(),
        }
    }

    /// The same problem, caused by the swept `value`.
    pub fn with_value(mut self, value: impl Into<String>) -> Self {
        self.value = Some(value.into());
        self
    }

    /// The same problem, found in run `run`.
    pub fn in_run(mut self, run: &str) -> Self {
        self.run = Some(run.to_string());
        self.runs_affected = 1;
        self
    }

    /// The same problem, a predicted warning about the validity rule `rule`.
    pub fn of_rule(mut self, rule: WarningKind) -> Self {
        self.rule = Some(rule);
        self
    }

    /// Everything that identifies the problem apart from which runs have it; with `reason` false,
    /// the kind of problem (its place, key, value and rule) without the words, which hold its numbers.
    fn identity(&self, reason: bool) -> Identity {
        let words = reason.then(|| self.reason.clone());
        (self.file.clone(), self.location, self.key.clone(), self.value.clone(), self.rule, words)
    }
}

impl fmt::Display for StudyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(at) = self.location {
            write!(f, ":{}:{}", at.line, at.column)?;
        }
        if !self.key.is_empty() {
            write!(f, ": {}", self.key)?;
        }
        if let Some(value) = &self.value {
            write!(f, ": value {value}")?;
        }
        if let Some(run) = &self.run {
            match self.runs_affected {
                0 | 1 => write!(f, " (run {run})")?,
                2 => write!(f, " (run {run} and 1 more run)")?,
                n => write!(f, " (run {run} and {} more runs)", n - 1)?,
            }
        }
        write!(f, ":")?;
        write!(f, " {}", self.reason)
    }
}

/// All problems of a study, reported together before any run starts.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct StudyErrors(pub Vec<StudyError>);

impl StudyErrors {
    /// Sorted by file and position, for reading top to bottom.
    pub(crate) fn sorted(mut errors: Vec<StudyError>) -> Self {
        errors.sort_by(|a, b| (&a.file, a.location).cmp(&(&b.file, b.location)));
        Self(errors)
    }
}

impl fmt::Display for StudyErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, error) in self.0.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "{error}")?;
        }
        Ok(())
    }
}

impl std::error::Error for StudyErrors {}

impl From<StudyError> for StudyErrors {
    fn from(error: StudyError) -> Self {
        Self(vec![error])
    }
}

/// Rust type names in a deserializer's message, and what to write instead.
const PLAIN_TYPES: [(&str, &str); 9] = [
    ("usize", "a whole number ≥ 0"),
    ("u64", "a whole number ≥ 0"),
    ("u32", "a whole number ≥ 0"),
    ("u16", "a whole number ≥ 0"),
    ("u8", "a whole number ≥ 0"),
    ("i64", "a whole number"),
    ("i32", "a whole number"),
    ("f64", "a number"),
    ("f32", "a number"),
];

/// A deserializer's message about `value` in the study's words: `expected f64` becomes `expected a
/// number`, `expected usize` `expected a whole number ≥ 0`, and a float of `value` that serde writes
/// long (`1e200` as 201 digits) is written as given ([`exact`]).
pub(crate) fn plain_types(message: &str, value: &toml::Value) -> String {
    let message = &short_floats(message, value);
    let Some((head, tail)) = message.split_once("expected ") else { return message.to_string() };
    let word_end = tail.find(|c: char| !c.is_ascii_alphanumeric()).unwrap_or(tail.len());
    match PLAIN_TYPES.iter().find(|(rust, _)| *rust == &tail[..word_end]) {
        Some((_, plain)) => format!("{head}expected {plain}{}", &tail[word_end..]),
        None => message.to_string(),
    }
}

/// The valid word nearest to `word` when it is near enough to be a slip of the keyboard: within a
/// Damerau-Levenshtein distance (an insertion, deletion, substitution or swap of neighbours each
/// counts one; letter case is ignored) of a third of the valid word's length, at least 1; the first
/// of equally near words.
pub fn nearest<'a>(word: &str, valid: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let word = word.to_lowercase();
    valid
        .into_iter()
        .map(|candidate| (strsim::damerau_levenshtein(&word, &candidate.to_lowercase()), candidate))
        .filter(|(distance, candidate)| *distance <= (candidate.chars().count() / 3).max(1))
        .min_by_key(|(distance, _)| *distance)
        .map(|(_, candidate)| candidate)
}

/// "did you mean `x`?" for the valid word `x` nearest to `word` ([`nearest`]); `None` when none is near.
pub fn did_you_mean<'a>(word: &str, valid: impl IntoIterator<Item = &'a str>) -> Option<String> {
    nearest(word, valid).map(|meant| format!("did you mean `{meant}`?"))
}

/// A deserializer's ``unknown field `x`, expected …`` or ``unknown variant `x`, expected …`` with
/// the list of valid words replaced by the one `x` most likely meant ([`nearest`]); unchanged when
/// none is near.
pub(crate) fn suggest_nearest(message: &str) -> String {
    let Some((head, list)) = message.split_once(", expected ") else { return message.to_string() };
    let unknown = ["unknown field `", "unknown variant `"].iter().find_map(|start| head.strip_prefix(start));
    let Some(word) = unknown.and_then(|rest| rest.strip_suffix('`')) else { return message.to_string() };
    let valid = list.split('`').skip(1).step_by(2);
    match did_you_mean(word, valid) {
        Some(hint) => format!("{head}: {hint}"),
        None => message.to_string(),
    }
}

/// `message` with serde's text of each float of `value` written as [`exact`] where that text is
/// long (`15.0` stays: it says the value was a float).
fn short_floats(message: &str, value: &toml::Value) -> String {
    match value {
        toml::Value::Float(x) => {
            let serde_text = serde_float(*x);
            if serde_text.len() > 24 {
                message.replace(&format!("`{serde_text}`"), &format!("`{}`", exact(*x)))
            } else {
                message.to_string()
            }
        }
        toml::Value::Array(items) => items.iter().fold(message.to_string(), |m, item| short_floats(&m, item)),
        toml::Value::Table(table) => table.values().fold(message.to_string(), |m, item| short_floats(&m, item)),
        _ => message.to_string(),
    }
}

/// How serde writes a float in its messages (`Unexpected::Float`): in full, with a decimal point.
fn serde_float(x: f64) -> String {
    let text = x.to_string();
    if x.is_finite() && !text.contains('.') { format!("{text}.0") } else { text }
}

/// Collects problems; the same problem found in several runs is kept once, with the first run and a count.
#[derive(Default)]
pub(crate) struct ErrorSink {
    errors: Vec<StudyError>,
    seen: HashMap<Identity, usize>,
    /// Whether problems of one kind (place, key, swept value and rule) count as the same whatever
    /// their reasons say (see [`StudyError::identity`]).
    by_kind: bool,
}

impl ErrorSink {
    /// A sink that keeps one problem per kind and place: the first run's, with the count of runs.
    /// For warnings, whose reasons give each run's numbers (an overlap of 0.81 or of 0.93 radii).
    pub fn by_kind() -> Self {
        Self { by_kind: true, ..Self::default() }
    }

    /// Adds a problem, or counts one more run for a problem already seen.
    pub fn push(&mut self, error: StudyError) {
        let identity = error.identity(!self.by_kind);
        match self.seen.get(&identity) {
            Some(&k) => self.errors[k].runs_affected += error.runs_affected,
            None => {
                self.seen.insert(identity, self.errors.len());
                self.errors.push(error);
            }
        }
    }

    /// Adds every problem of `errors`.
    pub fn extend(&mut self, errors: impl IntoIterator<Item = StudyError>) {
        errors.into_iter().for_each(|e| self.push(e));
    }

    /// Whether nothing is wrong so far.
    pub fn is_empty(&self) -> bool {
        self.errors.is_empty()
    }

    /// The problems found, sorted by position.
    pub fn into_errors(self) -> StudyErrors {
        StudyErrors::sorted(self.errors)
    }

    /// The problems found, or `ok` when there are none.
    pub fn into_result<T>(self, ok: T) -> Result<T, StudyErrors> {
        if self.errors.is_empty() { Ok(ok) } else { Err(self.into_errors()) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn error() -> StudyError {
        let at = Some(Location { line: 12, column: 1 });
        StudyError::new(
            "studies/x.toml",
            at,
            "sweep.\"material.poisson_ratio\"",
            "Poisson's ratio must lie in (-1, 0.5]",
        )
    }

    #[test]
    fn display_names_file_line_key_value_run_and_reason() {
        let e = error().with_value("0.7").in_run("r0003");
        assert_eq!(
            e.to_string(),
            "studies/x.toml:12:1: sweep.\"material.poisson_ratio\": value 0.7 (run r0003): Poisson's ratio must lie in (-1, 0.5]"
        );
        let bare = StudyError::new("x.toml", None, "", "cannot read the study file: gone");
        assert_eq!(bare.to_string(), "x.toml: cannot read the study file: gone");
    }

    #[test]
    fn sink_merges_the_same_problem_across_runs() {
        let mut sink = ErrorSink::default();
        for run in ["r0001", "r0004", "r0007"] {
            sink.push(error().with_value("0.7").in_run(run));
        }
        sink.push(error().with_value("0.9").in_run("r0002"));
        let errors = sink.into_result(()).unwrap_err().0;
        assert_eq!(errors.len(), 2);
        assert_eq!(errors[0].run.as_deref(), Some("r0001"));
        assert_eq!(errors[0].runs_affected, 3);
        assert!(errors[0].to_string().contains("(run r0001 and 2 more runs)"));
        assert_eq!(errors[1].runs_affected, 1);
    }

    #[test]
    fn rust_type_names_become_what_to_write() {
        let plain = |message: &str| plain_types(message, &toml::Value::Boolean(true));
        assert_eq!(plain("invalid type: string \"x\", expected f64"), "invalid type: string \"x\", expected a number");
        assert_eq!(
            plain("invalid type: floating point `1.5`, expected usize"),
            "invalid type: floating point `1.5`, expected a whole number ≥ 0"
        );
        assert_eq!(
            plain("invalid value: integer `-1`, expected u64 here"),
            "invalid value: integer `-1`, expected a whole number ≥ 0 here"
        );
        assert_eq!(plain("expected f64s"), "expected f64s", "whole words only");
        assert_eq!(plain("unknown field `x`, expected one of `a`"), "unknown field `x`, expected one of `a`");
    }

    #[test]
    fn a_long_float_is_written_as_given_from_the_value() {
        let huge = format!("invalid type: floating point `1{}.0`, expected usize", "0".repeat(200));
        let expected = "invalid type: floating point `1e200`, expected a whole number ≥ 0";
        assert_eq!(plain_types(&huge, &toml::Value::Float(1e200)), expected);
        let inside: toml::Value = toml::from_str("x = [2.0, 1e200]").unwrap();
        assert_eq!(plain_types(&huge, &inside), expected, "a float inside an array or table");
        let short = "floating point `15.0`, expected u8";
        assert_eq!(plain_types(short, &toml::Value::Float(15.0)), "floating point `15.0`, expected a whole number ≥ 0");
    }

    #[test]
    fn the_nearest_valid_word_is_suggested_for_a_slip() {
        let fields = ["density", "youngs_modulus", "poisson_ratio", "restitution", "friction", "rolling_friction"];
        assert_eq!(nearest("frictoin", fields), Some("friction"));
        assert_eq!(nearest("Restitutin", fields), Some("restitution"));
        assert_eq!(nearest("rolling_frict", fields), Some("rolling_friction"));
        assert_eq!(nearest("frict", fields), None, "too far from every field");
        assert_eq!(nearest("colour", fields), None);
        let message = "unknown field `frictoin`, expected one of `density`, `friction`, `rolling_friction`";
        assert_eq!(suggest_nearest(message), "unknown field `frictoin`: did you mean `friction`?");
        let variant = "unknown variant `randon`, expected one of `random`, `lattice`, `file`";
        assert_eq!(suggest_nearest(variant), "unknown variant `randon`: did you mean `random`?");
        assert_eq!(suggest_nearest("unknown field `bb`, expected `a` or `b`"), "unknown field `bb`: did you mean `b`?");
        let far = "unknown field `colour`, expected one of `density`, `friction`";
        assert_eq!(suggest_nearest(far), far, "no suggestion: the list stays");
    }

    #[test]
    fn warnings_of_one_kind_are_one_whatever_their_numbers() {
        let predicted = |reason: &str, rule| StudyError::new("s.toml", None, "scene", reason).of_rule(rule);
        let mut sink = ErrorSink::by_kind();
        sink.push(predicted("overlap 0.81 radii", WarningKind::ImpactOverlap).in_run("r0000"));
        sink.push(predicted("overlap 0.93 radii", WarningKind::ImpactOverlap).in_run("r0001"));
        sink.push(predicted("time step 0.3 of the contact time", WarningKind::ContactTimeFraction).in_run("r0001"));
        sink.push(StudyError::new("s.toml", None, "scene.run.frame_interval", "2 s").in_run("r0000"));
        sink.push(StudyError::new("s.toml", None, "scene.run.frame_interval", "3 s").in_run("r0002"));
        let errors = sink.into_errors().0;
        let seen: Vec<(&str, usize)> = errors.iter().map(|e| (e.reason.as_str(), e.runs_affected)).collect();
        assert_eq!(
            seen,
            [("overlap 0.81 radii", 2), ("time step 0.3 of the contact time", 1), ("2 s", 2)],
            "one per rule and key, the first run's words"
        );
        let mut exact = ErrorSink::default();
        exact.push(StudyError::new("s.toml", None, "scene", "overlap 0.81 radii").in_run("r0000"));
        exact.push(StudyError::new("s.toml", None, "scene", "overlap 0.93 radii").in_run("r0001"));
        assert_eq!(exact.into_errors().0.len(), 2, "errors differ by their reasons");
    }
}

//! The tune's section of the report: written by `demsweep tune` next to the results, read back by
//! every report of that file.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::html::{self, escape};
use super::table::Table;
use crate::output::OutputError;
use crate::output::guard::{self, Existing};

/// The section a tune adds to the report of its results file: `demsweep tune` writes it next to the
/// results as `<name>_tune.json` ([`tune_section_path`]), and every report of that file shows it.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TuneSection {
    /// The recommendation, one paragraph of plain text.
    pub recommendation: String,
    /// Cost against largest |difference| / tolerance, as an SVG document.
    pub chart_svg: String,
    /// Every evaluated setting, one row each (as in `<name>_candidates.csv`), under the columns' labels.
    pub candidates: Table,
}

/// `<results folder>/<study name>_tune.json`: the tune's section of the report, when the file holds a tune.
pub fn tune_section_path(results: &Path, study_name: &str) -> PathBuf {
    results.with_file_name(format!("{study_name}_tune.json"))
}

/// Writes the tune's section next to its results file (see [`TuneSection`]), marked as demsweep's
/// (`"dc:creator": "demsweep"`), replacing a file there as `existing` allows.
pub fn write_tune_section(
    results: &Path,
    study_name: &str,
    section: &TuneSection,
    existing: Existing,
) -> Result<PathBuf, OutputError> {
    let path = tune_section_path(results, study_name);
    let mut json = serde_json::to_value(section).map_err(|e| OutputError::new(&path, e.to_string()))?;
    json["dc:creator"] = "demsweep".into();
    guard::write_with(&path, &[results], existing, |out| out.write_all(json.to_string().as_bytes()))
        .map_err(|e| OutputError::new(&path, e.refusal_text()))?;
    Ok(path)
}

/// The tune section next to a results file, if there is one: its path and the section, or why it
/// cannot be read (a note in its place).
pub(super) fn read_tune_section(
    results: &Path,
    study_name: &str,
) -> Option<(PathBuf, serde_json::Result<TuneSection>)> {
    let path = tune_section_path(results, study_name);
    let text = std::fs::read_to_string(&path).ok()?;
    let section = serde_json::from_str(&text);
    Some((path, section))
}

/// The tune's answer (its lines: indented ones, the pile metrics, as a list with those beyond 2σ
/// marked), chart and candidate table.
pub(super) fn tune_section(tune: &TuneSection) -> String {
    let mut answer = String::new();
    let mut list = String::new();
    for line in tune.recommendation.lines() {
        match line.strip_prefix("  ") {
            Some(item) => {
                let class = if item.contains("beyond 2σ") { " class=\"flag\"" } else { "" };
                list += &format!("<li{class}>{}</li>", escape(item));
            }
            None => {
                if !list.is_empty() {
                    answer += &format!("<ul class=\"metrics\">{}</ul>", std::mem::take(&mut list));
                }
                answer += &format!("<p class=\"recommendation\">{}</p>", escape(line));
            }
        }
    }
    if !list.is_empty() {
        answer += &format!("<ul class=\"metrics\">{list}</ul>");
    }
    format!(
        "<h2 id=\"tune\">Tune: the answer</h2>{answer}<div class=\"chart\">{}</div><h3>Candidates</h3><div class=\"scroll\">{}</div>",
        tune.chart_svg,
        html::static_table(&tune.candidates)
    )
}

//! What a tune tells: the answer sheet (the recommendation or why there is none, said up front when
//! the reference itself breaks a rule of thumb), `<name>_best.toml` (a runnable study of the
//! recommended scene), `<name>_scene_change.toml` (the `[scene]` keys to set in the user's file),
//! `<name>_candidates.csv` (every setting that ran), `<name>_skipped.csv` (those predicted invalid
//! and not run) and the charts.
//!
//! `sheet` writes the answer sheet from the parts in `recommendation` (what it says of a
//! recommendation) and `course` (how the tune went), over the phrases of `phrases`; `tables` makes
//! the tables of settings, `charts` the charts' data and the report's section, `files` writes them.

mod charts;
mod course;
mod files;
mod phrases;
mod recommendation;
mod sheet;
mod tables;
#[cfg(test)]
mod tests;

pub use charts::report_section;
pub use course::reference_breaks;
pub use files::{WriteError, Written, best_study, files, scene_change, write_all};
pub use phrases::{failure_reason, settings, spend};
pub use recommendation::rate_upper_bound;
pub use sheet::{paragraph, run_counts};
pub use tables::{candidate_records, skipped_records};

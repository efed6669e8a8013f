//! The morning-after report: one self-contained HTML page per results file (inline CSS, inline SVG
//! charts, a little inline JavaScript, no network request of any kind).
//!
//! Top to bottom: what was run; how the runs ended and their warnings grouped by kind; the
//! per-point table (columns under header groups with their units, sortable by any column,
//! filterable by status; [`crate::stats::points`]); the study charts (settle time with 95 %
//! intervals, heatmap) and the pile-metric charts; the tune, when the file holds one; a section per
//! charted run (energies, unbalanced force ratio, stress profile, final pile, and a player of its
//! frames when it has some), the runs `demsweep plot` chooses, each linked from its point's row.

//!
//! Built from a results file and the tables of its runs (their summary and per-point statistics):
//! those a sweep computed ([`ReportSink`], the page `demsweep run` writes) or those of the file's
//! runs ([`write_report`], `demsweep report`), through the same builder (`page.rs`).

mod html;
mod page;
mod player;
mod sections;
mod sink;
mod svgs;
mod table;
mod tune;
mod verdict;

pub use crate::output::report_path;
pub use page::{ReportContext, Written, write_report, write_report_of};
pub use sink::ReportSink;
pub use table::{Cell, Table};
pub use tune::{TuneSection, tune_section_path, write_tune_section};

use svgs::{CHART_SIZE, Svgs};

//! Exports of stored runs to other codes' formats, read from a results file. Every format is one
//! file of this module and one row of [`FORMATS`] (its `--format` name, what it writes, its writer);
//! `demsweep export --format` offers the table's names.
//!
//! Everything is written into a temporary sibling of the output folder, which is renamed to its
//! final name only once complete: a failed export leaves nothing under that name. Export folders
//! hold a `.demsweep-export` marker: `--force` replaces only such a folder (see [`crate::output::guard`]).

pub mod csv;
mod error;
mod format;
pub mod lammps;
mod request;
pub mod vtk;

pub use error::{ExportError, WriteError};
pub(crate) use format::write_file;
pub use format::{Format, RunToExport, State};
pub use request::{ExportRequest, ExportSummary, FORMATS, MARKER_KIND, export, format};

//! What an export format is ([`Format`], a row of the table) and what its writer is given: the run
//! ([`RunToExport`]) and its states ([`State`]), with [`write_file`] to write each file.

use std::path::Path;

use super::WriteError;
use crate::output::guard;
use crate::output::row::SummaryRow;
use crate::output::stored::StoredRun;
use crate::physics::record::Snapshot;

/// One export format: a row of `FORMATS`.
pub struct Format {
    /// Its `--format` name.
    pub name: &'static str,
    /// What it writes, in a line (the CLI's help).
    pub description: &'static str,
    /// Writes the states of one run into a folder.
    pub write_run: fn(&Path, &RunToExport, &[State]) -> Result<(), WriteError>,
}

impl std::fmt::Debug for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Format({})", self.name)
    }
}

/// A run being exported: its summary row and its stored data.
pub struct RunToExport<'a> {
    /// The run's summary row (id, status, per-run quantities).
    pub row: &'a SummaryRow,
    /// The run's stored scene and states.
    pub run: &'a StoredRun,
}

/// One state to write: the run it belongs to, its name in file names and the snapshot.
pub struct State<'a> {
    /// The run's id.
    pub run: &'a str,
    /// `final`, or `frame_<k>` (zero-padded).
    pub label: String,
    /// The state.
    pub snapshot: &'a Snapshot,
}

/// Creates `folder/name` and writes what `body` produces into it through a buffer.
pub(crate) fn write_file(
    folder: &Path,
    name: &str,
    body: impl FnOnce(&mut dyn std::io::Write) -> std::io::Result<()>,
) -> Result<(), WriteError> {
    let path = folder.join(name);
    let file = guard::create_file(&path, &[]).map_err(WriteError::Create)?;
    let mut buffer = std::io::BufWriter::new(file);
    let written = body(&mut buffer).and_then(|()| std::io::Write::flush(&mut buffer));
    written.map_err(|source| WriteError::Write { path, source })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_that_cannot_be_created_or_written_is_a_typed_error_naming_it() {
        let missing = std::env::temp_dir().join(format!("demsweep-export-missing-{}", std::process::id()));
        let created = write_file(&missing, "r0000_final.csv", |out| out.write_all(b"x"));
        assert!(
            matches!(&created, Err(WriteError::Create(e)) if e.path == missing.join("r0000_final.csv")),
            "{created:?}"
        );
        // A writer whose bytes do not go in (the disk full): the file is created, then the write fails.
        let folder = std::env::temp_dir();
        let name = format!("demsweep-export-full-{}.csv", std::process::id());
        let full = write_file(&folder, &name, |_| Err(std::io::ErrorKind::StorageFull.into()));
        std::fs::remove_file(folder.join(&name)).unwrap();
        let Err(WriteError::Write { path, source }) = &full else { panic!("{full:?}") };
        assert_eq!((path, source.kind()), (&folder.join(&name), std::io::ErrorKind::StorageFull));
    }
}

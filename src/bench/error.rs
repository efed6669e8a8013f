//! Why a benchmark could not finish: the run, placement, tune or file that failed, typed; the text
//! is made by [`std::fmt::Display`].

use std::fmt;
use std::path::PathBuf;

use crate::output::guard::GuardError;
use crate::physics::RunError;
use crate::physics::placement::PlacementError;
use crate::plot::PlotError;
use crate::study::StudyErrors;
use crate::tune::TuneError;
use crate::tune::report::WriteError;

/// Why a benchmark could not finish.
#[derive(Debug)]
pub enum BenchError {
    /// A scene would not run.
    Run(RunError),
    /// A scene's disks could not be placed.
    Placement(PlacementError),
    /// A study or tune file's problems.
    File(StudyErrors),
    /// A tune stopped.
    Tune(TuneError),
    /// A tune's files could not be written.
    TuneFiles(WriteError),
    /// A folder could not be made.
    CreateFolder {
        /// The folder.
        dir: PathBuf,
        /// Why.
        error: std::io::Error,
    },
    /// A file could not be copied.
    Copy {
        /// The file.
        path: PathBuf,
        /// Why.
        error: std::io::Error,
    },
    /// A file was refused or could not be written.
    Write(GuardError),
    /// A chart could not be drawn.
    Chart(PlotError),
    /// Nothing to measure (the benchmark's words).
    Nothing(&'static str),
}

/// Makes the folder `dir` and every folder above it.
pub fn create_folder(dir: &std::path::Path) -> Result<(), BenchError> {
    std::fs::create_dir_all(dir).map_err(|error| BenchError::CreateFolder { dir: dir.to_path_buf(), error })
}

impl fmt::Display for BenchError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BenchError::Run(e) => write!(f, "{e}"),
            BenchError::Placement(e) => write!(f, "{e}"),
            BenchError::File(e) => write!(f, "{e}"),
            BenchError::Tune(e) => write!(f, "{e}"),
            BenchError::TuneFiles(e) => write!(f, "{e}"),
            BenchError::CreateFolder { dir, error } => write!(f, "{}: cannot create folder: {error}", dir.display()),
            BenchError::Copy { path, error } => write!(f, "{}: {error}", path.display()),
            BenchError::Write(e) => write!(f, "{e}"),
            BenchError::Chart(e) => write!(f, "{e}"),
            BenchError::Nothing(what) => write!(f, "{what}"),
        }
    }
}

impl std::error::Error for BenchError {}

/// `From` for each error a benchmark passes on as it is.
macro_rules! from {
    ($($variant:ident($error:ty)),*) => {$(
        impl From<$error> for BenchError {
            fn from(error: $error) -> Self {
                BenchError::$variant(error)
            }
        }
    )*};
}

from!(
    Run(RunError),
    Placement(PlacementError),
    File(StudyErrors),
    Tune(TuneError),
    TuneFiles(WriteError),
    Write(GuardError),
    Chart(PlotError)
);

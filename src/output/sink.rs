//! Where a sweep's results go. A [`ResultSink`] takes finished runs one at a time, makes them durable
//! at each commit, and at the end receives the tables of its runs (the summary and the per-point
//! statistics, computed above the sink by the runner). The caller of the runner chooses the sinks:
//! the HDF5 results file ([`super::ResultsWriter`]) is the durable one, its CSV tables
//! ([`super::CsvTables`]) another, written only after the file's last commit (they follow it in the
//! list); the Python module's in-memory results ([`super::MemorySink`]) are another; a new output
//! format (VTK, LAMMPS dumps …) is one more implementation, handed to the runner by its caller.
//!
//! Each sink says what can go wrong with it ([`ResultSink::Error`]); the runner drives a list of
//! sinks of different kinds, so there each is a [`DynSink`], whose errors are [`SinkError`]s.

use std::convert::Infallible;
use std::fmt;
use std::sync::Arc;

use super::OutputError;
use super::row::SummaryRow;
use super::table::SummaryTable;
use crate::physics::SceneConfig;
use crate::physics::record::RunRecord;

/// A destination for the runs of a sweep, driven from one thread: [`Self::accept`] for each run,
/// [`Self::commit`] now and then, [`Self::finish`] once, after which it is dropped. Each does nothing
/// unless the sink says otherwise: a sink that keeps only the tables implements only `finish`.
pub trait ResultSink: Send {
    /// What can go wrong: [`OutputError`] for a file, [`Infallible`] for memory.
    type Error: Into<SinkError>;

    /// Takes one finished run; it need not be durable before the next [`Self::commit`].
    fn accept(&mut self, _run: &RunResult) -> Result<(), Self::Error> {
        Ok(())
    }

    /// Makes every accepted run durable: a crash after it loses none of them.
    fn commit(&mut self) -> Result<(), Self::Error> {
        Ok(())
    }

    /// Receives the tables of every run of the sweep (when resuming, the stored runs' too, though
    /// [`Self::accept`] sees only the runs made now), keeps what it keeps of them, and closes the sink.
    fn finish(&mut self, _tables: &Tables) -> Result<(), Self::Error> {
        Ok(())
    }
}

/// A sink lent to the runner: the caller keeps it, and reads what it holds after the sweep.
impl<S: ResultSink + ?Sized> ResultSink for &mut S {
    type Error = S::Error;

    fn accept(&mut self, run: &RunResult) -> Result<(), Self::Error> {
        (**self).accept(run)
    }

    fn commit(&mut self) -> Result<(), Self::Error> {
        (**self).commit()
    }

    fn finish(&mut self, tables: &Tables) -> Result<(), Self::Error> {
        (**self).finish(tables)
    }
}

/// A sink of any kind, as the runner drives it: a list of sinks needs one error type. It lives as
/// long as `'a`: a sink lent by the caller (`&mut S`) is one.
pub type DynSink<'a> = Box<dyn ResultSink<Error = SinkError> + 'a>;

/// `sink` as a [`DynSink`]: its errors become [`SinkError`]s.
pub fn dyn_sink<'a, S: ResultSink + 'a>(sink: S) -> DynSink<'a> {
    Box::new(Erased(sink))
}

/// A sink whose errors are converted to [`SinkError`].
struct Erased<S>(S);

impl<S: ResultSink> ResultSink for Erased<S> {
    type Error = SinkError;

    fn accept(&mut self, run: &RunResult) -> Result<(), SinkError> {
        self.0.accept(run).map_err(Into::into)
    }

    fn commit(&mut self) -> Result<(), SinkError> {
        self.0.commit().map_err(Into::into)
    }

    fn finish(&mut self, tables: &Tables) -> Result<(), SinkError> {
        self.0.finish(tables).map_err(Into::into)
    }
}

/// What went wrong in a sink: a results-file problem (kept typed: the runner reports it as one), or
/// the error of another kind of sink.
#[derive(Clone, Debug)]
pub enum SinkError {
    /// A results-file problem.
    Output(OutputError),
    /// Another sink's error.
    Other(Arc<dyn std::error::Error + Send + Sync>),
}

impl SinkError {
    /// The error `error` of a sink other than a results file.
    pub fn other(error: impl std::error::Error + Send + Sync + 'static) -> Self {
        SinkError::Other(Arc::new(error))
    }
}

impl From<OutputError> for SinkError {
    fn from(error: OutputError) -> Self {
        SinkError::Output(error)
    }
}

impl From<Infallible> for SinkError {
    fn from(never: Infallible) -> Self {
        match never {}
    }
}

/// Results-file errors compare by value; other errors only to themselves (they need not be
/// comparable).
impl PartialEq for SinkError {
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (SinkError::Output(a), SinkError::Output(b)) => a == b,
            (SinkError::Other(a), SinkError::Other(b)) => Arc::ptr_eq(a, b),
            _ => false,
        }
    }
}

impl fmt::Display for SinkError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SinkError::Output(e) => write!(f, "{e}"),
            SinkError::Other(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for SinkError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SinkError::Output(e) => Some(e),
            SinkError::Other(e) => Some(e.as_ref()),
        }
    }
}

/// One run as the writer stores it.
#[derive(Clone, Debug)]
pub struct RunResult {
    /// Its summary row.
    pub row: SummaryRow,
    /// The run's complete scene (key values are stored as `scene.*` attributes).
    pub scene: SceneConfig,
    /// The simulation record; `None` when the run failed before producing one.
    pub record: Option<RunRecord>,
}

/// The tables a finished results file holds.
#[derive(Clone, Debug, PartialEq)]
pub struct Tables {
    /// One row per run (`/summary`).
    pub summary: SummaryTable,
    /// One row per grid point (`/points`).
    pub points: SummaryTable,
}

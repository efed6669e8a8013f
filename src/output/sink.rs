//! Where a sweep's results go. A [`ResultSink`] takes finished runs one at a time, makes them durable
//! at each commit, and at the end receives the tables of the whole file (the summary and the
//! per-point statistics, computed above the sink by the runner). The HDF5 + CSV results file
//! ([`super::ResultsWriter`]) is one sink; another output format (VTK, LAMMPS dumps …) is another
//! implementation, driven by the runner's writer thread the same way.

use super::OutputError;
use super::row::SummaryRow;
use super::table::SummaryTable;
use crate::physics::SceneConfig;
use crate::physics::record::RunRecord;

/// A destination for the runs of a sweep, driven from one thread: [`Self::accept`] for each run,
/// [`Self::commit`] now and then, [`Self::finish`] once.
pub trait ResultSink: Send {
    /// Takes one finished run; it need not be durable before the next [`Self::commit`].
    fn accept(&mut self, run: &RunResult) -> Result<(), OutputError>;

    /// Makes every accepted run durable: a crash after it loses none of them.
    fn commit(&mut self) -> Result<(), OutputError>;

    /// Receives the tables of every run the results hold (earlier sweeps' when resuming included),
    /// writes what the sink keeps of them, and closes the sink.
    fn finish(self: Box<Self>, tables: &Tables) -> Result<(), OutputError>;
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

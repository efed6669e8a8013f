//! Result files: one HDF5 file per study (or shard) and a CSV summary next to it.
//!
//! Data flows one way: runner → [`ResultSink`]s; the results file ([`ResultsWriter`])
//! is one: run groups committed in batches, then `/summary` and `/points` from the tables the runner
//! computes; its CSV tables ([`CsvTables`], [`write_csv_files`]) another. This layer reads and writes; it computes no statistics. The
//! layout is in [`layout`] and docs/results.md.

pub mod checkpoint;
mod companions;
pub(crate) mod compound;
pub(crate) mod copy;
pub(crate) mod csv;
mod csv_tables;
mod error;
pub mod guard;
pub mod header;
pub mod history;
pub mod layout;
mod layout_error;
pub mod lock;
mod memory;
pub mod reader;
pub mod row;
pub mod run_attrs;
mod sink;
pub mod stored;
pub mod summary;
pub mod table;
pub mod terminal;
mod writer;

pub use companions::{check_companions, check_not_companion, csv_path, points_csv_path, report_path, write_csv_files};
pub use compound::Field;
pub use csv_tables::CsvTables;
pub(crate) use error::hdf5_error;
pub use error::{OutputError, OutputReason};
pub use header::{FileHeader, ShardInfo, ShardSpec};
pub use layout_error::{LayoutError, LayoutProblem};
pub use memory::MemorySink;
pub use row::SummaryRow;
pub use sink::{DynSink, ResultSink, RunResult, SinkError, Tables, dyn_sink};
pub use table::SummaryTable;
pub use writer::ResultsWriter;

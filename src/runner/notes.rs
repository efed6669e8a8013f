//! What a sweep found in its results file and did about it, and how it set itself up: typed notes,
//! put in words only where they are printed (`note:` lines before the runs start).

use std::fmt;
use std::path::Path;

use super::progress::ProgressMode;
use crate::study::IdentityChange;

/// Stored run ids named in a note before "and N more".
const NAMED_RUNS: usize = 10;

/// One thing a user should know before the runs start.
#[derive(Clone, Debug, PartialEq)]
pub enum RunNote {
    /// Stored runs made by another demsweep version are reused, as `--accept-version` asks.
    OtherVersions {
        /// How many.
        runs: usize,
        /// The first of them, and the version that made it.
        first: (String, String),
    },
    /// Planned runs match stored runs by their swept values but not by their identity: they run again.
    IdentityChanged {
        /// How many.
        runs: usize,
        /// What differs.
        changed: Vec<IdentityChange>,
    },
    /// Stored runs lack an output the study asks for (`[output]`): they run again.
    LackingOutput {
        /// How many.
        runs: usize,
    },
    /// Stored runs the study no longer plans: kept in the file, or deleted (`--drop-unplanned`).
    Unplanned {
        /// Their ids.
        ids: Vec<String>,
        /// Whether they were deleted.
        deleted: bool,
    },
    /// Fewer worker threads than `--jobs` asked for.
    WorkersCapped {
        /// Threads asked for.
        asked: usize,
        /// Threads used.
        used: usize,
        /// What capped them.
        by: WorkerCap,
    },
}

/// What caps the worker threads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WorkerCap {
    /// The runs left to do (this many).
    Runs(usize),
    /// The machine's cores (this many).
    Cores(usize),
}

/// Which of a sweep's notes it prints before its runs start.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum NotePolicy {
    /// Every note.
    #[default]
    All,
    /// All but the stored runs the plan does not hold: the plan is the part run so far of one that
    /// grows (a tune's batches), so that only its caller knows at the end which stored runs it left.
    PlanGrows,
}

impl NotePolicy {
    /// Whether `note` is printed.
    pub fn prints(self, note: &RunNote) -> bool {
        self == NotePolicy::All || !matches!(note, RunNote::Unplanned { .. })
    }
}

impl RunNote {
    /// Whether the note is about stored results (runs that run again, are reused or deleted): such
    /// notes are shown whatever the progress display, the others not when it is quiet.
    pub fn about_stored_runs(&self) -> bool {
        !matches!(self, RunNote::WorkersCapped { .. })
    }

    /// The note in words, those about stored runs after the `results` file's path.
    pub fn line(&self, results: &Path) -> String {
        if self.about_stored_runs() { format!("{}: {self}", results.display()) } else { self.to_string() }
    }

    /// Prints the notes a sweep into `results` shows with the `progress` display, as `note:` lines.
    pub fn print_all<'a>(notes: impl IntoIterator<Item = &'a RunNote>, results: &Path, progress: ProgressMode) {
        for note in notes.into_iter().filter(|n| n.about_stored_runs() || progress != ProgressMode::Quiet) {
            crate::output::terminal::err(format_args!("note: {}\n", note.line(results)));
        }
    }
}

impl fmt::Display for RunNote {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RunNote::OtherVersions { runs, first: (id, version) } => write!(
                f,
                "reusing {runs} stored run(s) made by another demsweep version (run {id} by {version}; this is {}), \
                 as --accept-version asks; /summary/demsweep_version says which made each",
                crate::output::row::DEMSWEEP_VERSION
            ),
            RunNote::IdentityChanged { runs, changed } => {
                let changed: Vec<String> = changed.iter().map(ToString::to_string).collect();
                write!(
                    f,
                    "{runs} run(s) of this study match stored runs by their swept values but not by what they \
                     depend on ({} changed): they run again",
                    changed.join(", ")
                )
            }
            RunNote::LackingOutput { runs } => {
                write!(f, "{runs} stored run(s) lack an output this study asks for ([output]): they run again")
            }
            RunNote::Unplanned { ids, deleted: true } => {
                write!(f, "deleted {} stored run(s) no longer planned", ids.len())
            }
            RunNote::Unplanned { ids, deleted: false } => {
                let named = ids.iter().take(NAMED_RUNS).map(String::as_str).collect::<Vec<_>>().join(", ");
                let more = match ids.len().saturating_sub(NAMED_RUNS) {
                    0 => String::new(),
                    more => format!(" and {more} more"),
                };
                write!(
                    f,
                    "{} stored run(s) are no longer planned by this study (stored as {named}{more}): kept in the \
                     file, left out of the summary, points and report; `--drop-unplanned` deletes them",
                    ids.len()
                )
            }
            RunNote::WorkersCapped { asked, used, by } => {
                let why = match by {
                    WorkerCap::Runs(runs) => format!("{runs} runs to do"),
                    WorkerCap::Cores(cores) => format!("{cores} cores"),
                };
                write!(f, "--jobs {asked} capped to {used} worker threads ({why})")
            }
        }
    }
}

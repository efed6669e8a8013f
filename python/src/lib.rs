//! `demsweep._native`: the demsweep library bound to Python (PyO3). Each function converts its
//! arguments, calls the library (scenes become studies through `study::scene_study`, runs go through
//! the runner, files through `workflow` and the output readers) and converts the answer; the thin
//! `demsweep` package (`python/demsweep/__init__.py`) wraps tables as pandas DataFrames.
//!
//! Long calls run with the interpreter released (other Python threads go on) on a helper thread,
//! while this one checks for Ctrl-C: an interrupt stops the runs (finished runs of a study stay in
//! its file) and raises `KeyboardInterrupt`.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use demsweep::output::table::ColumnData;
use demsweep::output::{self, Field, MemorySink, OutputError, SummaryTable, dyn_sink, layout, reader, stored};
use demsweep::physics::quantity::{self, HISTORY_SERIES, SeriesValues};
use demsweep::physics::record::{DISK_FIELDS, Snapshot};
use demsweep::runner::{self, ProgressMode, RunCounts, RunOptions};
use demsweep::study::{self, Seeds, StudyErrors};
use demsweep::tune::TuneOptions;
use demsweep::workflow::{self, LoadError};
use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyKeyboardInterrupt, PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyInt, PyList, PyString, PyTuple};

/// The `demsweep` command-line interface (src/cli.rs and src/cli/), compiled into the module from
/// the same source as the `demsweep` binary, so that `pip install .` gives the command too (the
/// wheel's console entry point calls [`main`]).
#[path = "../../src"]
#[allow(dead_code)] // the binary's `cli::main` reads the process's arguments; the module passes its own
mod command {
    pub mod cli;
}

create_exception!(_native, DemsweepError, PyException, "Any error the demsweep library reports.");
create_exception!(
    _native,
    StudyError,
    DemsweepError,
    "A study, scene or tune file the library refuses: the message is what `demsweep check` prints; \
     `problems` lists each problem (file, line, column, key, value, reason) and `study_text` is the \
     study that was checked, when it was made from a scene."
);
create_exception!(
    _native,
    ResultsError,
    DemsweepError,
    "A results file that cannot be read or written (the message names it and says why)."
);

/// The scene's name in errors: `<scene>`, or `<scenes[k]>` in a batch.
fn scene_label(batch: Option<usize>) -> PathBuf {
    PathBuf::from(batch.map_or("<scene>".to_string(), |k| format!("<scenes[{k}]>")))
}

/// A `StudyError` with the library's text of `errors`, its problems and the study text checked.
fn study_error(py: Python<'_>, errors: &StudyErrors, study_text: Option<&str>) -> PyErr {
    let error = StudyError::new_err(errors.to_string());
    let attach = || -> PyResult<()> {
        let value = error.value(py);
        let problems = PyList::empty(py);
        for e in &errors.0 {
            let problem = PyDict::new(py);
            problem.set_item("file", e.file.display().to_string())?;
            problem.set_item("line", e.location.map(|l| l.line))?;
            problem.set_item("column", e.location.map(|l| l.column))?;
            problem.set_item("key", &e.key)?;
            problem.set_item("value", &e.value)?;
            problem.set_item("reason", &e.reason)?;
            problems.append(problem)?;
        }
        value.setattr("problems", problems)?;
        value.setattr("study_text", study_text)
    };
    attach().err().unwrap_or(error)
}

fn results_error(error: impl std::fmt::Display) -> PyErr {
    ResultsError::new_err(error.to_string())
}

/// A Python value as TOML; `Err((key path, reason))` for one TOML cannot hold.
fn to_toml(value: &Bound<'_, PyAny>, key: &mut Vec<String>) -> Result<toml::Value, (String, String)> {
    let fail = |key: &[String], what: String| Err((key.join("."), what));
    if let Ok(b) = value.cast::<PyBool>() {
        return Ok(toml::Value::Boolean(b.is_true()));
    }
    if let Ok(s) = value.cast::<PyString>() {
        return Ok(toml::Value::String(s.to_string()));
    }
    if let Ok(dict) = value.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in dict.iter() {
            let Ok(name) = k.cast::<PyString>().map(|s| s.to_string()) else {
                return fail(key, format!("keys must be strings, not {}", type_name(&k)));
            };
            key.push(name.clone());
            let item = to_toml(&v, key).and_then(|item| insert_dotted(&mut table, &name, item, key));
            key.pop();
            item?;
        }
        return Ok(toml::Value::Table(table));
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let items: Vec<Bound<'_, PyAny>> =
            value.try_iter().and_then(|i| i.collect()).map_err(|e| (key.join("."), e.to_string()))?;
        return items.iter().map(|item| to_toml(item, key)).collect::<Result<_, _>>().map(toml::Value::Array);
    }
    if value.is_instance_of::<PyInt>() || value.hasattr("__index__").unwrap_or(false) {
        return value
            .extract::<i64>()
            .map(toml::Value::Integer)
            .or_else(|_| fail(key, "is out of range of a 64-bit integer".into()));
    }
    if let Ok(x) = value.extract::<f64>() {
        return Ok(toml::Value::Float(x)); // a float, or anything with __float__ (NumPy's floats)
    }
    fail(
        key,
        format!(
            "a Python {} cannot be a study value (numbers, strings, booleans, lists and dicts can)",
            type_name(value)
        ),
    )
}

/// Sets `item` at the dotted key `name` of `table` (`"material.friction"` is `friction` in the table
/// `material`, as TOML's dotted keys); tables given both ways merge, a value given twice is an error
/// naming `key` (the path to `name`).
fn insert_dotted(
    table: &mut toml::Table,
    name: &str,
    item: toml::Value,
    key: &[String],
) -> Result<(), (String, String)> {
    let (head, rest) = match name.split_once('.') {
        Some((head, rest)) if !head.is_empty() && !rest.is_empty() => (head, Some(rest)),
        _ => (name, None),
    };
    let twice = || (key.join("."), format!("`{name}` is given twice (as a dotted key and in a dict)"));
    match (rest, table.get_mut(head)) {
        (None, None) => {
            table.insert(head.to_string(), item);
            Ok(())
        }
        (None, Some(toml::Value::Table(existing))) => match item {
            toml::Value::Table(more) => more.into_iter().try_for_each(|(k, v)| insert_dotted(existing, &k, v, key)),
            _ => Err(twice()),
        },
        (None, Some(_)) => Err(twice()),
        (Some(rest), None) => {
            let mut inner = toml::Table::new();
            insert_dotted(&mut inner, rest, item, key)?;
            table.insert(head.to_string(), toml::Value::Table(inner));
            Ok(())
        }
        (Some(rest), Some(toml::Value::Table(existing))) => insert_dotted(existing, rest, item, key),
        (Some(_), Some(_)) => Err(twice()),
    }
}

fn type_name(value: &Bound<'_, PyAny>) -> String {
    value.get_type().name().map_or_else(|_| "object".into(), |n| n.to_string())
}

/// A scene (a dict, or TOML text, of the keys of a study's `[scene]`) as a table.
fn scene_table(py: Python<'_>, scene: &Bound<'_, PyAny>, label: &Path) -> PyResult<toml::Table> {
    if let Ok(text) = scene.cast::<PyString>() {
        return study::parse_table(label, text.to_string()).map_err(|e| study_error(py, &e, None));
    }
    if !scene.is_instance_of::<PyDict>() {
        return Err(PyTypeError::new_err(format!(
            "a scene is a dict or TOML text of the keys of a study's [scene], not a {}",
            type_name(scene)
        )));
    }
    match to_toml(scene, &mut vec!["scene".into()]) {
        Ok(toml::Value::Table(table)) => Ok(table),
        Ok(_) => unreachable!("a dict becomes a table"),
        Err((key, reason)) => {
            Err(study_error(py, &StudyErrors(vec![study::StudyError::new(label, None, key, reason)]), None))
        }
    }
}

/// `seeds`: None (the scene's own seed), a count of replicates, or a list of seeds.
fn seeds_of(seeds: Option<&Bound<'_, PyAny>>) -> PyResult<Seeds> {
    let Some(seeds) = seeds.filter(|s| !s.is_none()) else { return Ok(Seeds::Scene) };
    if let Ok(n) = seeds.extract::<usize>() {
        return Ok(Seeds::Replicates(n));
    }
    seeds.extract::<Vec<i64>>().map(Seeds::List).map_err(|_| {
        PyTypeError::new_err("seeds is a number of replicate seeds or a list of placement seeds (integers)")
    })
}

/// The plan of each scene: every scene checked, every problem of all of them in one error.
fn plans(py: Python<'_>, scenes: &[Bound<'_, PyAny>], seeds: &Seeds, batch: bool) -> PyResult<Vec<study::Plan>> {
    let (mut plans, mut problems, mut texts) = (Vec::new(), Vec::new(), Vec::new());
    for (k, scene) in scenes.iter().enumerate() {
        let label = scene_label(batch.then_some(k));
        let text = study::scene_study(scene_table(py, scene, &label)?, seeds);
        match study::load_text(&label, text.clone()) {
            Ok(plan) => plans.push(plan),
            Err(errors) => {
                problems.extend(errors.0);
                texts.push(text);
            }
        }
    }
    match problems.is_empty() {
        true => Ok(plans),
        false => Err(study_error(py, &StudyErrors(problems), Some(&texts.join("\n")))),
    }
}

/// Runs `work` on a helper thread with the interpreter released, checking for Ctrl-C meanwhile:
/// then `stop` is set, the work is waited for and `KeyboardInterrupt` raised.
fn detached<T: Send>(py: Python<'_>, stop: &AtomicBool, work: impl FnOnce() -> T + Send) -> PyResult<T> {
    std::thread::scope(|scope| {
        let handle = scope.spawn(work);
        let mut interrupt = None;
        loop {
            let finished = py.detach(|| {
                for _ in 0..10 {
                    if handle.is_finished() {
                        return true;
                    }
                    std::thread::sleep(Duration::from_millis(5));
                }
                false
            });
            if finished {
                break;
            }
            if let Err(e) = py.check_signals() {
                stop.store(true, Ordering::SeqCst);
                interrupt = Some(e);
                py.detach(|| {
                    while !handle.is_finished() {
                        std::thread::sleep(Duration::from_millis(5))
                    }
                });
                break;
            }
        }
        let done = handle.join().map_err(|_| PyRuntimeError::new_err("the demsweep library panicked"));
        match interrupt {
            Some(e) => Err(e),
            None => done,
        }
    })
}

/// A table as a dict of columns (name → list), in column order.
fn columns<'py>(py: Python<'py>, table: &SummaryTable) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for column in &table.columns {
        match &column.data {
            ColumnData::Float(v) => dict.set_item(&column.name, v)?,
            ColumnData::Int(v) => dict.set_item(&column.name, v)?,
            ColumnData::Bool(v) => dict.set_item(&column.name, v)?,
            ColumnData::Text(v) => dict.set_item(&column.name, v)?,
        }
    }
    Ok(dict)
}

/// `run_batch(scenes, seeds=None, jobs=0)`: every run of every scene on `jobs` worker threads (0 =
/// one per core); one summary table (a dict of columns) per scene, in order, and the warnings (the
/// scenes', and how many runs failed).
#[pyfunction]
#[pyo3(signature = (scenes, seeds=None, jobs=0))]
fn run_batch<'py>(
    py: Python<'py>,
    scenes: Vec<Bound<'py, PyAny>>,
    seeds: Option<&Bound<'py, PyAny>>,
    jobs: usize,
) -> PyResult<(Vec<Bound<'py, PyDict>>, Vec<String>)> {
    let plans = plans(py, &scenes, &seeds_of(seeds)?, true)?;
    let tables = run_in_memory(py, &plans, jobs)?;
    let warnings = warnings(&plans, &tables);
    Ok((tables.iter().map(|table| columns(py, table)).collect::<PyResult<_>>()?, warnings))
}

/// Runs every run of `plans` on `jobs` worker threads into memory: each plan's summary table.
fn run_in_memory(py: Python<'_>, plans: &[study::Plan], jobs: usize) -> PyResult<Vec<SummaryTable>> {
    let mut results: Vec<MemorySink> = plans.iter().map(|_| MemorySink::default()).collect();
    let batches = (plans.iter().zip(&mut results))
        .map(|(plan, memory)| runner::Batch { runs: plan.runs.iter().collect(), sinks: vec![dyn_sink(memory)] })
        .collect();
    let stop = Arc::new(AtomicBool::new(false));
    detached(py, &stop, || runner::run_batches(batches, jobs, &stop))?.map_err(results_error)?;
    let complete =
        |(plan, memory): (&study::Plan, MemorySink)| memory.into_summary().filter(|t| t.len() == plan.runs.len());
    let tables: Option<Vec<_>> = plans.iter().zip(results).map(complete).collect();
    tables.ok_or_else(|| PyKeyboardInterrupt::new_err("interrupted"))
}

/// The warnings of `plans` and, when some of the runs in their summary `tables` diverged or failed,
/// how many.
fn warnings(plans: &[study::Plan], tables: &[SummaryTable]) -> Vec<String> {
    let statuses = tables.iter().flat_map(|table| match table.column("status").map(|c| &c.data) {
        Some(ColumnData::Text(statuses)) => statuses.as_slice(),
        _ => &[],
    });
    let counts = RunCounts::of(tables.iter().map(SummaryTable::len).sum(), statuses.map(String::as_str));
    let failed = (counts.failed() > 0).then(|| counts.to_string());
    plans.iter().flat_map(|plan| plan.warnings.iter().map(ToString::to_string)).chain(failed).collect()
}

/// `scene_study(scene, seeds=None)`: the study text a scene runs as (what `demsweep check` checks).
#[pyfunction]
#[pyo3(signature = (scene, seeds=None))]
fn scene_study(py: Python<'_>, scene: &Bound<'_, PyAny>, seeds: Option<&Bound<'_, PyAny>>) -> PyResult<String> {
    Ok(study::scene_study(scene_table(py, scene, &scene_label(None))?, &seeds_of(seeds)?))
}

/// `run(scene, seeds=None, jobs=0)`: the runs of one scene; its summary table (a dict of columns)
/// and the warnings (the scene's, and how many runs failed).
#[pyfunction]
#[pyo3(signature = (scene, seeds=None, jobs=0))]
fn run<'py>(
    py: Python<'py>,
    scene: Bound<'py, PyAny>,
    seeds: Option<&Bound<'py, PyAny>>,
    jobs: usize,
) -> PyResult<(Bound<'py, PyDict>, Vec<String>)> {
    let plans = plans(py, std::slice::from_ref(&scene), &seeds_of(seeds)?, false)?;
    let tables = run_in_memory(py, &plans, jobs)?;
    Ok((columns(py, &tables[0])?, warnings(&plans, &tables)))
}

fn progress_mode(name: &str) -> PyResult<ProgressMode> {
    match name {
        "auto" => Ok(ProgressMode::Auto),
        "bars" => Ok(ProgressMode::Bars),
        "lines" => Ok(ProgressMode::Lines),
        "quiet" => Ok(ProgressMode::Quiet),
        other => Err(PyTypeError::new_err(format!("progress is auto, bars, lines or quiet, not {other:?}"))),
    }
}

/// A checkpoint interval in seconds (`None`: no checkpoints) as the runner takes it.
fn checkpoint_interval(seconds: Option<f64>) -> PyResult<Option<Duration>> {
    let Some(seconds) = seconds else { return Ok(None) };
    match Duration::try_from_secs_f64(seconds) {
        Ok(interval) if !interval.is_zero() => Ok(Some(interval)),
        _ => Err(PyValueError::new_err(format!("checkpoint_every must be > 0 seconds (or None), not {seconds}"))),
    }
}

/// `run_study(path, out=None, resume=False, force=False, jobs=0, progress="quiet",
/// checkpoint_every=None)`: `demsweep run` (`checkpoint_every`: `--checkpoint-every` in seconds,
/// `None` off; the package's `run_study` passes the command's default).
#[pyfunction]
#[pyo3(signature = (path, out=None, resume=false, force=false, jobs=0, progress="quiet", checkpoint_every=None))]
#[allow(clippy::too_many_arguments)] // the command's options, as keyword arguments
fn run_study<'py>(
    py: Python<'py>,
    path: PathBuf,
    out: Option<PathBuf>,
    resume: bool,
    force: bool,
    jobs: usize,
    progress: &str,
    checkpoint_every: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let checkpoint_every = checkpoint_interval(checkpoint_every)?;
    let (plan, space) = workflow::load_study(&path, out.as_deref()).map_err(|e| match e {
        LoadError::Invalid(errors) => study_error(py, &errors, None),
        tune_file => StudyError::new_err(tune_file.to_string()),
    })?;
    let stop = Arc::new(AtomicBool::new(false));
    let options = RunOptions {
        jobs,
        out_dir: out,
        resume,
        force,
        progress: progress_mode(progress)?,
        stop: stop.clone(),
        checkpoint_every,
        ..RunOptions::default()
    };
    let run = detached(py, &stop, || workflow::run_study(&plan, &options, Vec::new()))?.map_err(results_error)?;
    let report = &run.report;
    let counts = report.counts();
    let failed = (counts.failed() > 0 && !report.interrupted).then(|| counts.to_string());
    let warnings: Vec<String> = plan.warnings.iter().map(ToString::to_string).chain(space).chain(failed).collect();
    let answer = PyDict::new(py);
    answer.set_item("results", &report.results)?;
    answer.set_item("summary_csv", &report.summary_csv)?;
    answer.set_item("points_csv", &report.points_csv)?;
    answer.set_item("report", run.page.as_ref().ok().map(|(page, ..)| page))?;
    answer.set_item("selected", report.selected)?;
    answer.set_item("already_done", report.already_done)?;
    answer.set_item("ran", report.ran)?;
    answer.set_item("failed", report.failed())?;
    answer.set_item("missing", report.missing())?;
    answer.set_item("exit_code", report.exit_code())?;
    answer.set_item("warnings", warnings)?;
    let notes: Vec<String> = report.notes.iter().map(|note| note.line(&report.results)).collect();
    answer.set_item("notes", notes)?;
    answer
        .set_item("run_warnings", report.warnings.groups.iter().map(|g| g.example.to_string()).collect::<Vec<_>>())?;
    Ok(answer)
}

/// `tune(path, out=None, resume=False, force=False, jobs=0, verbose=False)`: `demsweep tune`.
#[pyfunction]
#[pyo3(signature = (path, out=None, resume=false, force=false, jobs=0, verbose=false))]
fn tune<'py>(
    py: Python<'py>,
    path: PathBuf,
    out: Option<PathBuf>,
    resume: bool,
    force: bool,
    jobs: usize,
    verbose: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let (mut spec, warnings) = workflow::load_tune(&path).map_err(|e| study_error(py, &e, None))?;
    let stop = Arc::new(AtomicBool::new(false));
    let options = TuneOptions { jobs, out_dir: out, resume, force, verbose, stop: stop.clone(), ..Default::default() };
    let run = detached(py, &stop, || workflow::tune_file(&mut spec, &options))?.map_err(results_error)?;
    let result = &run.report.result;
    let answer = PyDict::new(py);
    answer.set_item("results", &run.report.results)?;
    answer.set_item("recommendation", &run.recommendation)?;
    let best = result.recommended.map(|k| demsweep::tune::report::settings(&spec, &result.candidates[k]));
    answer.set_item("recommended", best)?;
    answer.set_item("files", &run.written.files)?;
    answer.set_item("report", run.page.as_ref().ok().map(|(page, ..)| page))?;
    answer.set_item("ran", run.report.ran)?;
    answer.set_item("reused", run.report.reused)?;
    answer.set_item("particle_steps", run.report.total_particle_steps)?;
    answer.set_item("warnings", warnings)?;
    Ok(answer)
}

/// `units()`: the SI unit of every summary column, history series, stress profile column and disk
/// field (empty: none).
#[pyfunction]
fn units(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let dict = PyDict::new(py);
    for q in quantity::per_run() {
        dict.set_item(q.name, q.unit)?;
    }
    for series in &HISTORY_SERIES {
        dict.set_item(series.quantity.name, series.quantity.unit)?;
    }
    for field in &DISK_FIELDS {
        dict.set_item(field.name, field.unit)?;
    }
    for (name, unit, _) in layout::stress_profile_columns(&Default::default()) {
        dict.set_item(name, unit)?;
    }
    Ok(dict)
}

/// `column_units(names)`: the unit of each named column that has one (`quantity::unit`: the units
/// line of the CSV files), `""` when dimensionless; columns without one are left out.
#[pyfunction]
fn column_units(py: Python<'_>, names: Vec<String>) -> PyResult<Bound<'_, PyDict>> {
    let dict = PyDict::new(py);
    for name in &names {
        if let Some(unit) = quantity::unit(name) {
            dict.set_item(name, unit)?;
        }
    }
    Ok(dict)
}

/// A results file written by `run`, `merge` or `tune`, read through the library's readers.
#[pyclass(frozen, module = "demsweep._native")]
struct Results {
    path: PathBuf,
}

/// A field of a library table as a list.
fn field_list<'py>(py: Python<'py>, field: Field<'_>) -> PyResult<Bound<'py, PyAny>> {
    match field {
        Field::F64(v) => v.into_pyobject(py),
        Field::U32(v) => v.into_pyobject(py),
        Field::I64(v) => v.into_pyobject(py),
        Field::Bool(v) => v.into_pyobject(py),
        Field::Text(v) => v.into_pyobject(py),
    }
}

/// A state (final or frame): `time`, one list per disk field and `contacts` (one list per field).
fn snapshot<'py>(py: Python<'py>, state: &Snapshot) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    dict.set_item("time", state.time)?;
    for (name, field) in layout::state_table(state) {
        dict.set_item(name, field_list(py, field)?)?;
    }
    let contacts = PyDict::new(py);
    for (name, field) in layout::contact_table(&state.contacts) {
        contacts.set_item(name, field_list(py, field)?)?;
    }
    dict.set_item("contacts", contacts)?;
    Ok(dict)
}

impl Results {
    /// The stored run `run` (an id such as `r0007`, or a run index) among the runs of the summary
    /// (a grown file also holds runs its study no longer plans, under the ids they had).
    fn stored(&self, run: &Bound<'_, PyAny>) -> PyResult<stored::StoredRun> {
        let path = &self.path;
        let file = reader::open(path).map_err(results_error)?;
        let summary = reader::summary(&file, path).map_err(results_error)?;
        let rows: Vec<output::SummaryRow> = match summary.rows() {
            Some(rows) => rows.into_iter().map(|(row, _)| row).collect(),
            None => reader::rows(&file, path).map_err(results_error)?,
        };
        let wanted = |row: &&output::SummaryRow| match run.extract::<usize>() {
            Ok(index) => row.index == index,
            Err(_) => run.extract::<String>().is_ok_and(|id| row.id == id),
        };
        let row = rows.iter().find(wanted).ok_or_else(|| {
            results_error(OutputError::new(
                path,
                format!("no run `{run}` in this file (see its summary for the run ids)"),
            ))
        })?;
        stored::read_run(&file, path, row).map_err(results_error)
    }
}

#[pymethods]
impl Results {
    /// The results file `path`, or the one results file in the folder `path` (as the commands take it).
    #[new]
    fn new(path: PathBuf) -> PyResult<Self> {
        let path = reader::locate(&path).map_err(results_error)?;
        let file = reader::open(&path).map_err(results_error)?;
        reader::header(&file, &path).map_err(results_error)?;
        Ok(Self { path })
    }

    /// The results file.
    #[getter]
    fn path(&self) -> &Path {
        &self.path
    }

    /// The summary: one row per run (a dict of columns).
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        columns(py, &output::summary::read(&self.path).map_err(results_error)?)
    }

    /// The statistics of every grid point (a dict of columns).
    fn points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        columns(py, &demsweep::stats::points::read(&self.path).map_err(results_error)?)
    }

    /// The run's histories: one list per series; `None` when the file has none for it.
    fn history<'py>(&self, py: Python<'py>, run: &Bound<'py, PyAny>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(history) = self.stored(run)?.history else { return Ok(None) };
        let dict = PyDict::new(py);
        for series in &HISTORY_SERIES {
            match (series.quantity.value)(&history) {
                SeriesValues::Real(v) => dict.set_item(series.quantity.name, v)?,
                SeriesValues::Count(v) => dict.set_item(series.quantity.name, v)?,
            }
        }
        Ok(Some(dict))
    }

    /// The run's stress profile: its columns (one list per field, a value per height band) and
    /// their units; `None` when the file has none for it.
    fn stress_profile<'py>(
        &self,
        py: Python<'py>,
        run: &Bound<'py, PyAny>,
    ) -> PyResult<Option<(Bound<'py, PyDict>, Bound<'py, PyDict>)>> {
        let Some(profile) = self.stored(run)?.stress_profile else { return Ok(None) };
        let (columns, units) = (PyDict::new(py), PyDict::new(py));
        for (name, unit, values) in layout::stress_profile_columns(&profile) {
            columns.set_item(name, values)?;
            units.set_item(name, unit)?;
        }
        Ok(Some((columns, units)))
    }

    /// The run's final state (see `snapshot`); `None` when the file has none for it.
    fn final_state<'py>(&self, py: Python<'py>, run: &Bound<'py, PyAny>) -> PyResult<Option<Bound<'py, PyDict>>> {
        self.stored(run)?.final_state.map(|s| snapshot(py, &s)).transpose()
    }

    /// The run's recorded frames, in time order.
    fn frames<'py>(&self, py: Python<'py>, run: &Bound<'py, PyAny>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.stored(run)?.frames.iter().map(|s| snapshot(py, s)).collect()
    }

    /// The run's complete scene, as JSON text.
    fn scene_json(&self, run: &Bound<'_, PyAny>) -> PyResult<String> {
        serde_json::to_string(&self.stored(run)?.scene).map_err(|e| PyRuntimeError::new_err(e.to_string()))
    }
}

/// `main(argv)`: runs the `demsweep` command with `argv` (the program's name first, as `sys.argv`)
/// and ends the process with its exit status, as the `demsweep` binary does: the console entry
/// point of the wheel. SIGPIPE and SIGINT get their command-line defaults first (a closed pipe ends
/// the command quietly; Ctrl-C stops a sweep as it does the binary's).
#[pyfunction]
fn main(py: Python<'_>, argv: Vec<String>) -> PyResult<()> {
    #[allow(unsafe_code)]
    // SAFETY: the process is about to become the command; SIG_DFL is a valid disposition.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    let code = py.detach(|| command::cli::main_with(argv));
    let status = (0..=u8::MAX).find(|&k| std::process::ExitCode::from(k) == code).unwrap_or(1);
    std::process::exit(i32::from(status))
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("DemsweepError", py.get_type::<DemsweepError>())?;
    m.add("StudyError", py.get_type::<StudyError>())?;
    m.add("ResultsError", py.get_type::<ResultsError>())?;
    m.add_class::<Results>()?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(run_batch, m)?)?;
    m.add_function(wrap_pyfunction!(scene_study, m)?)?;
    m.add_function(wrap_pyfunction!(run_study, m)?)?;
    m.add_function(wrap_pyfunction!(tune, m)?)?;
    m.add_function(wrap_pyfunction!(units, m)?)?;
    m.add_function(wrap_pyfunction!(column_units, m)?)?;
    m.add_function(wrap_pyfunction!(main, m)?)?;
    Ok(())
}

//! Command line: one enum variant and one function per subcommand.

// Everything the command prints goes through `demsweep::output::terminal` (escaped; a write to a
// closed pipe or a full disk never ends the process midway): hence these macros instead of
// `println!`. Defined before the child modules, so that they have them too.

/// `print!` through the text edge, to standard output.
macro_rules! out {
    ($($arg:tt)*) => { demsweep::output::terminal::out(format_args!($($arg)*)) };
}

/// `println!` through the text edge, to standard output.
macro_rules! outln {
    () => { demsweep::output::terminal::out(format_args!("\n")) };
    ($($arg:tt)*) => { demsweep::output::terminal::out(format_args!("{}\n", format_args!($($arg)*))) };
}

/// `eprintln!` through the text edge, to standard error.
macro_rules! errln {
    ($($arg:tt)*) => { demsweep::output::terminal::err(format_args!("{}\n", format_args!($($arg)*))) };
}

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use estimate::{SECONDS_PER_PARTICLE_STEP, duration};
use exit::{INVALID_STUDY, refuse_warnings};

mod bench;
mod estimate;
mod exit;
mod export;
mod fill;
mod plot;
use demsweep::study::Plan;
use demsweep::workflow::{self, LoadError};

mod results;
mod slurm;
mod tune;

#[derive(Parser)]
#[command(
    name = "demsweep",
    version,
    about = "Batch parameter sweeps of 2D DEM simulations of granular deposition",
    long_about = "Batch parameter sweeps of 2D DEM simulations of granular deposition (the BMEDEM2D model).\n\n\
                  A study file (TOML) holds a base [scene] and [sweep] axes; demsweep expands it into runs. \
                  The study file format is described in docs/studies.md.",
    after_help = "Examples:\n  demsweep check studies/damping_sweep.toml\n  demsweep plan studies/damping_sweep.toml\n  \
                  demsweep run studies/damping_sweep.toml\n  demsweep plot results/damping_sweep/damping_sweep.h5"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// List the runs a study expands to (id and swept parameters) and estimate their cost; or a tune file's levers and budget.
    #[command(
        long_about = "List the runs a study expands to, in run order: each run's id, its swept parameters, \
                      disk count and time steps, then the total cost in particle-steps and a rough wall-time \
                      estimate (50 ns per particle-step on one core, divided by the cores; runs that settle \
                      early finish sooner). The study is checked first, as by `demsweep check`. Given a tune \
                      file ([levers], [keep], [search]; see `demsweep tune`), it prints the levers, the \
                      reference scene's predicted warnings and the cost bound of the budget.",
        after_help = "Examples:\n  demsweep plan studies/damping_sweep.toml --cores 8\n  \
                      demsweep plan studies/tune_deposition.toml"
    )]
    Plan(PlanArgs),
    /// Check a study or tune file without running anything: prints "ok: N runs" or every problem.
    #[command(
        long_about = "Check a study file (or a tune file: [levers], [keep], [search]) without running \
                      anything. Every problem of the whole file is reported at once, each with file, line, key \
                      and reason (unknown keys, wrong types, impossible values, malformed sweep axes or \
                      levers, disks that do not fit, unreadable placement files). Warnings do not fail the \
                      check: what the pre-run validity estimate predicts, and values implausible in their SI \
                      unit (units are SI: `material.youngs_modulus = 10` is 10 Pa; the warning says what it \
                      would be in GPa). Prints \"ok: N runs\" and exits 0 when the file is valid, else exits 2 \
                      (with --strict, also when there is a warning). \
                      Every scene key with its default, unit and range: `demsweep keys`.",
        after_help = "Examples:\n  demsweep check studies/damping_sweep.toml && echo valid\n  \
                      demsweep check studies/tune_deposition.toml"
    )]
    Check(CheckArgs),
    /// Run a study: all runs in parallel, results in one HDF5 file and a CSV summary.
    #[command(
        long_about = "Run every run of a study in parallel (one simulation per worker thread) and write \
                      OUT/<study name>.h5 (HDF5: every run's parameters, status, histories, final state and \
                      frames; layout in docs/results.md) and OUT/<study name>_summary.csv (one \
                      row per run). Finished runs are committed as they finish, so nothing finished is lost \
                      to a crash or kill: continue with --resume. Ctrl-C, SIGTERM and SIGHUP stop cleanly \
                      (exit 130); a second signal quits at once.\n\nExit status:\n  0    every run recorded (settled or not \
                      settled)\n  1    no run gave a result (every one diverged, failed with an error or is missing), \
                      or the results could not be written\n  2    the study is invalid (with --strict: or has a \
                      warning); nothing was run\n  4    some runs diverged, failed with an error or are missing \
                      (how many is printed); the others are recorded\n  130  interrupted (finished runs are kept; \
                      continue with --resume)",
        after_help = "Examples:\n  demsweep run studies/damping_sweep.toml\n  \
                      demsweep run studies/damping_sweep.toml --jobs 8 --out /scratch/damping\n  \
                      demsweep run studies/damping_sweep.toml --resume\n  \
                      demsweep run studies/damping_sweep.toml --shard 2/8 --out results/shards"
    )]
    Run(results::RunArgs),
    /// Print the summary of a results file (one row per run, or per grid point), or export it as CSV.
    #[command(
        long_about = "Print the summary of a results file as an aligned table: run_id, index, the swept \
                      parameters, status, then settle_time, the pile metrics `compare` keeps by default \
                      (packing_fraction_interior, coordination_number, floor_load_ratio, fabric_anisotropy; \
                      packing_fraction and pile_height in files older than them), particle_steps (steps \
                      when there is none), wall_time and the number of warnings (--metric and --all print \
                      others). With --csv, write it as a CSV file instead. Works on a file \
                      whose run was killed, too (the summary is then rebuilt from the committed runs).\n\n\
                      With --by-point, one row per grid point (the runs that differ only by placement seed): \
                      n, status counts and, per numeric column, n, mean, sample standard deviation, 95 % \
                      confidence half-width (Student t), min and max (printed as mean ± half-width for a few \
                      metrics; --csv writes every statistic, as does /points). Settle time is over the \
                      settled runs; `unsettled` counts the others. Files written before /points existed \
                      get it computed from their summary.",
        after_help = "Examples:\n  demsweep summary results/damping_sweep/damping_sweep.h5\n  \
                      demsweep summary results/damping_sweep/damping_sweep.h5 --csv damping.csv\n  \
                      demsweep summary results/damping_sweep/damping_sweep.h5 --by-point --metric settle_time\n  \
                      demsweep summary results/damping_sweep/damping_sweep.h5 --by-point --csv points.csv"
    )]
    Summary(results::SummaryArgs),
    /// Compare every grid point with a reference point: equivalent, different or undecided per metric.
    #[command(
        long_about = "Compare every grid point of a results file with a reference point. For every kept \
                      metric (relative tolerance TOL: margin = TOL x |reference mean|) it prints the difference \
                      of means with its 90 % Welch interval and the decision of two one-sided tests \
                      (Schuirmann 1987): equivalent (the interval lies inside ± margin), different (wholly \
                      outside) or undecided (and roughly how many seeds per point would decide). Then the cost \
                      (particle-steps, or steps in older files) and wall time of each point relative to the \
                      reference with 95 % intervals (delta method on logs). A point is acceptable when every \
                      kept metric is equivalent. Exit status 2 for an unknown point or metric.",
        after_help = "Examples:\n  demsweep compare results/damping_sweep/damping_sweep.h5 \
                      --reference material.restitution=0.5,material.friction=0.6\n  \
                      demsweep compare results/damping_sweep/damping_sweep.h5 --reference r0000 \
                      --keep packing_fraction=0.005 --keep pile_height=0.01 --csv compare.csv --plot"
    )]
    Compare(results::CompareArgs),
    /// Print one run's histories (energies, UBF, contacts over time) as CSV.
    #[command(
        long_about = "Print the sampled histories of one run as CSV on stdout: the series' names, their \
                      units, then one line per sample (docs/results.md, CSV files): time t (s); the energies \
                      (J) kinetic_translational, kinetic_rotational, potential, elastic, dissipated, \
                      numerical_damping_dissipated, total (kinetic + potential) and mechanical (+ elastic); \
                      unbalanced_force_ratio, contacts and max_overlap_ratio (overlap / radius).",
        after_help = "Example:\n  demsweep history results/damping_sweep/damping_sweep.h5 r0007 > r0007.csv"
    )]
    History(results::HistoryArgs),
    /// Merge shard files (from `run --shard K/N`), or results files of different studies, into one.
    #[command(
        long_about = "Merge the shard files of one study (written by `demsweep run --shard K/N`) into \
                      OUT/<study name>.h5 and its CSV summary, the same files a one-machine run writes \
                      (but for the creation time and wall times), copying one run at a time. Refuses shards \
                      of one study whose input files or demsweep version differ, and runs present in two shards. Missing shards, missing runs and \
                      runs that failed with an error do not stop it: it merges what there is, lists them, \
                      prints the commands that run those shards again and merge again, and exits 1. A complete merge exits \
                      as `run` does: 0, or 4 when some runs diverged, 1 when every one did. Results files \
                      of different studies merge run by run: each run identity (settings, input files, physics \
                      version) once, renumbered r0000, ... in the order given; files written before run \
                      identities and files of different physics versions are refused.",
        after_help = "Examples:\n  demsweep merge results/damping_sweep results/shards\n  \
                      demsweep merge merged damping_sweep.shard-1-of-2.h5 damping_sweep.shard-2-of-2.h5"
    )]
    Merge(results::MergeArgs),
    /// Export stored piles for ParaView, LAMMPS or a restart (the formats: --format below).
    #[command(
        long_about = "Export the final state (and with --frames every recorded frame) of runs of a results \
                      file into --out, in one of the formats listed under --format (the export table of \
                      docs/export.md). The folder is written under a temporary name and renamed when complete.",
        after_help = "Examples:\n  demsweep export results/damping_sweep/damping_sweep.h5 --format vtk --out piles\n  \
                      demsweep export results/damping_sweep/damping_sweep.h5 --format lammps --run r0003 --out lmp\n  \
                      demsweep export results/damping_sweep/damping_sweep.h5 --format csv --run r0003 --out restart"
    )]
    Export(export::ExportArgs),
    /// Draw charts of a results file: energies, UBF and pile snapshots per run; settle time per study.
    #[command(
        long_about = "Draw PNG (or SVG) charts of a results file into --out (default: plots/ next to the \
                      file, i.e. results/<study name>/plots/). Per study: settle_time (settle time against \
                      the first swept numeric parameter, one line per value of the second) and, with two \
                      such parameters, settle_time_heatmap; diverged runs are red crosses, runs that did \
                      not settle grey. Per run: <id>_energy (kinetic, potential, elastic, total), <id>_ubf \
                      (unbalanced force ratio, log scale, settle threshold and settle time marked) and \
                      <id>_frame_<k> for each frame recorded (the scene's run.frame_times or \
                      run.frame_interval) plus <id>_final: the disks to scale in the box, coloured by speed \
                      or contact force. Per-run charts are drawn for every run of a study of up to 20 \
                      runs, else for 20 runs spread over it unless --run or --all-runs says otherwise.",
        after_help = "Examples:\n  demsweep plot results/damping_sweep/damping_sweep.h5\n  \
                      demsweep plot results/paper_table1/paper_table1.h5 --colour-by force --format both\n  \
                      demsweep plot results/damping_sweep/damping_sweep.h5 --run r0003 --run r0012 --out figs"
    )]
    Plot(plot::PlotArgs),
    /// Write the morning-after report of a results file: one self-contained HTML page.
    #[command(
        long_about = "Write one self-contained HTML page about a results file (inline CSS, SVG charts and a \
                      little JavaScript, no network request; open it anywhere, attach it to an e-mail): what \
                      was run; the answer (the fastest-settling grid points and, when the study names a \
                      `[report] reference` point, which points make an equivalent pile at what cost, as \
                      `compare` decides); how the runs ended with their warnings grouped, the per-point table (mean ± 95 % \
                      interval of settle time, cost and pile metrics; sortable by any column, filterable by \
                      status), the settle-time charts, and a section per charted run (energies, unbalanced \
                      force ratio, final pile) linked from its point's row. `run`, `merge` and `tune` write \
                      it next to their results as <study name>_report.html (a shard's as \
                      <study name>.shard-K-of-N_report.html).",
        after_help = "Examples:\n  demsweep report results/damping_sweep/damping_sweep.h5\n  \
                      demsweep report results/damping_sweep/damping_sweep.h5 --out ~/damping.html"
    )]
    Report(results::ReportArgs),
    /// List every scene key with its default, SI unit, allowed values and description.
    #[command(
        long_about = "List every key of a scene (the [scene] table of a study or tune file) with its default, \
                      its SI unit, the values it allows and what it is, from the same declaration the \
                      configuration is read with (src/physics/config/). A PREFIX shows only the keys that \
                      start with it; --markdown prints the table the docs hold (docs/studies.md).",
        after_help = "Examples:\n  demsweep keys\n  demsweep keys material\n  demsweep keys --markdown"
    )]
    Keys(KeysArgs),
    /// Benchmarks: accuracy against cost, stability map, stress scenarios, skipping savings, tune against a ladder.
    #[command(
        long_about = "Benchmarks of the engine, each writing CSV, Markdown (and charts) into --out \
                      (default results/bench_latest, which git ignores; --update-results writes the \
                      committed results/bench instead) and printing its Markdown summary: `accuracy` (work-precision of \
                      both integrators), `stability` (where runs blow up against the predicted safe time step), \
                      `stress` (edge-case scenes and their statuses), `skipping` (time saved by stopping at \
                      settle, sparse diagnostics and frictionless shortcuts), `tune` (tune against a \
                      brute-force ladder over its levers).",
        after_help = "Example:\n  demsweep bench stability --out /tmp/bench"
    )]
    Bench(bench::BenchArgs),
    /// Write (and with --submit, submit) a Slurm array job, one task per shard, and a merge job.
    #[command(
        long_about = "Write two Slurm batch scripts into OUT/slurm/: an array job with one task per shard, \
                      each running `demsweep run STUDY --shard K/N --out OUT/shards --resume` on --jobs CPUs \
                      (logs in OUT/logs/), and a merge job writing OUT/<study name>.h5 and its CSV summary. \
                      Without --submit, prints how to submit them; with --submit, submits both with sbatch, \
                      the merge with --dependency=afterany on the array job (it runs when every task ended), \
                      and prints the job ids. A failed task leaves the other shards intact; the merge then \
                      merges them, exits 1 and prints the commands that complete it: `sbatch --array=K \
                      OUT/slurm/array.sbatch` (the task resumes its shard) and the merge again.",
        after_help = "Examples:\n  demsweep slurm studies/damping_sweep.toml --shards 16 --time 02:00:00 --submit\n  \
                      demsweep slurm studies/damping_sweep.toml --shards 8 --jobs 4 --partition long \
                      --out /scratch/damping --print"
    )]
    Slurm(slurm::SlurmArgs),
    /// Find the fastest deposition that still makes the same pile (a tune file: [scene], [levers], [keep], [search]).
    #[command(
        long_about = "Search the levers of a tune file for the cheapest setting whose settled pile is the same as \
                      the reference scene's: every kept metric equivalent by the two one-sided tests (90 % Welch \
                      interval of the difference inside the tolerance), every run settled, the runs together within \
                      the validity limits (a limit the reference itself breaks: no worse than the reference). The \
                      reference runs on several seeds; then the time step alone, from the largest valid fraction of \
                      the contact time down to the reference's, until the cheapest valid and equivalent step is \
                      verified on fresh seeds; then, with what the spend limit leaves, the other standard settings, \
                      a Halton design and a pattern search. Runs go in parallel batches through the ordinary runner \
                      into OUT/<name>.h5 (every run is kept: --resume after a kill replays the search from the \
                      file). Prints the answer sheet and writes OUT/<name>_best.toml (a runnable study), \
                      OUT/<name>_scene_change.toml (the [scene] keys to set in the tune file), \
                      OUT/<name>_candidates.csv (what ran), OUT/<name>_skipped.csv (settings never run: predicted past a validity limit, or, on a check \
                      the reference itself breaks, more than 5 % past the reference's figure) and \
                      charts in OUT/plots/.\n\nExit status:\n  0    done, with or without a recommendation\n  1    \
                      a run, the results file or a chart failed, or the reference diverged or did not settle\n  2    \
                      the tune file is invalid (nothing was run)\n  3    a kept metric cannot be decided: the \
                      reference's own seed-to-seed spread is too wide for its tolerance (only the reference ran)\n  \
                      130  interrupted by Ctrl-C (finished runs are kept; continue with --resume)",
        after_help = "Examples:\n  demsweep tune studies/tune_deposition.toml\n  \
                      demsweep tune studies/tune_deposition.toml --jobs 2 --out /tmp/tune --resume"
    )]
    Tune(tune::TuneArgs),
}

#[derive(Args)]
struct PlanArgs {
    /// The study file (TOML).
    study: PathBuf,
    /// Cores to assume for the wall-time estimate (default: this machine's).
    #[arg(long)]
    cores: Option<usize>,
}

#[derive(Args)]
struct KeysArgs {
    /// Only the keys that start with this (e.g. `material`, `contact.linear`).
    prefix: Option<String>,
    /// Print a Markdown table (as in docs/studies.md).
    #[arg(long)]
    markdown: bool,
}

#[derive(Args)]
struct CheckArgs {
    /// The study file (TOML).
    study: PathBuf,
    /// Treat warnings as errors (exit status 2), for scripts and CI.
    #[arg(long)]
    strict: bool,
}

/// Parses the command line and runs the subcommand; a failed write to standard output makes a
/// successful command fail, naming it.
pub fn main() -> ExitCode {
    main_with(std::env::args_os())
}

/// Parses `args` (the program's name first, as `std::env::args_os` gives them) and runs the
/// subcommand: the Python module's `demsweep` console command runs the CLI this way. A failure to
/// write standard output fails the command, naming it.
pub fn main_with<I: IntoIterator<Item = T>, T: Into<std::ffi::OsString> + Clone>(args: I) -> ExitCode {
    let code = match Cli::try_parse_from(args) {
        Ok(cli) => dispatch(cli.command),
        Err(e) => usage(&e),
    };
    match demsweep::output::terminal::stdout_failure() {
        None => code,
        Some(e) => {
            errln!("error: {e}");
            if code == ExitCode::SUCCESS { ExitCode::FAILURE } else { code }
        }
    }
}

/// Prints clap's help, version or usage error through the text edge; its exit status (0 for help and
/// version, 2 for a usage error).
fn usage(error: &clap::Error) -> ExitCode {
    let text = error.render().to_string();
    if error.use_stderr() {
        errln!("{}", text.trim_end());
    } else {
        outln!("{}", text.trim_end());
    }
    ExitCode::from(error.exit_code().clamp(0, 255) as u8)
}

/// Runs one subcommand.
fn dispatch(command: Command) -> ExitCode {
    match command {
        Command::Plan(args) => plan(&args),
        Command::Check(args) => check(&args),
        Command::Run(args) => match load_or_report(args.study(), args.out(), args.strict()) {
            Ok(plan) => {
                note_long_cost(&plan, args.jobs().unwrap_or(usize::MAX).min(machine_cores()));
                results::run(&args, &plan)
            }
            Err(code) => code,
        },
        Command::Summary(args) => results::summary(&args),
        Command::Compare(args) => results::compare(&args),
        Command::History(args) => results::history(&args),
        Command::Merge(args) => results::merge(&args),
        Command::Export(args) => export::run(&args),
        Command::Plot(args) => plot::plot(&args),
        Command::Report(args) => results::report(&args),
        Command::Keys(args) => keys(&args),
        Command::Bench(args) => bench::bench(&args),
        Command::Slurm(args) => match load_or_report(args.study(), args.out(), false) {
            Ok(plan) => slurm::slurm(&args, &plan),
            Err(code) => code,
        },
        Command::Tune(args) => tune::run(&args),
    }
}

/// The study's plan, its warnings printed to stderr (with one about the space its results need in
/// `out`, default `results/<name>/`); or its problems printed and the exit status for an invalid
/// study, which warnings are too when `strict`.
fn load_or_report(path: &Path, out: Option<&Path>, strict: bool) -> Result<Plan, ExitCode> {
    let (plan, space) = workflow::load_study(path, out).map_err(|e| {
        match e {
            LoadError::TuneFile(_) => errln!("error: {e}"),
            LoadError::Invalid(errors) => {
                errln!("{errors}");
                errln!("{}: {} problem(s); nothing was run", path.display(), errors.0.len());
            }
        }
        ExitCode::from(INVALID_STUDY)
    })?;
    let warnings: Vec<String> = plan.warnings.iter().map(ToString::to_string).chain(space).collect();
    for warning in &warnings {
        errln!("warning: {warning}");
    }
    refuse_warnings(path, warnings.len(), strict)?;
    Ok(plan)
}

fn check(args: &CheckArgs) -> ExitCode {
    if demsweep::tune::is_tune_file(&args.study) {
        return tune::check(&args.study, args.strict);
    }
    match load_or_report(&args.study, None, args.strict) {
        Ok(plan) => {
            note_long_cost(&plan, machine_cores());
            let warnings = match plan.warnings.len() {
                0 => String::new(),
                1 => " (1 warning above)".into(),
                n => format!(" ({n} warnings above)"),
            };
            outln!("ok: {}{warnings}", runs(plan.runs.len()));
            size_notes(&plan).iter().chain(&fill::fill_notes(&plan)).for_each(|note| outln!("{note}"));
            ExitCode::SUCCESS
        }
        Err(code) => code,
    }
}

fn plan(args: &PlanArgs) -> ExitCode {
    if demsweep::tune::is_tune_file(&args.study) {
        let cores = args.cores.unwrap_or_else(machine_cores).max(1);
        return tune::plan(&args.study, cores);
    }
    let plan = match load_or_report(&args.study, None, false) {
        Ok(plan) => plan,
        Err(code) => return code,
    };
    let cores = args.cores.unwrap_or_else(machine_cores).max(1);
    outln!(
        "study {} ({}), fingerprint {}, {} runs",
        plan.name,
        plan.study_path.display(),
        plan.fingerprint,
        plan.runs.len()
    );
    out!("{}", run_table(&plan));
    let total = plan.total_cost();
    let seconds = total * SECONDS_PER_PARTICLE_STEP;
    outln!(
        "total {total:.3e} particle-steps (upper bound: runs stop when settled); about {} on 1 core, {} on {cores} cores",
        duration(seconds),
        duration(seconds / cores as f64),
    );
    ExitCode::SUCCESS
}

/// Estimated wall time past which `check` and `run` print it (s): an hour.
const LONG_SWEEP: f64 = 3600.0;

/// This machine's cores (at least 1).
fn machine_cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Prints the wall-time estimate of `plan` on `cores` (the figure `plan` gives) when it is long.
fn note_long_cost(plan: &Plan, cores: usize) {
    let seconds = plan.total_cost() * SECONDS_PER_PARTICLE_STEP / cores.max(1) as f64;
    if seconds > LONG_SWEEP {
        errln!(
            "note: {}: about {} on {cores} cores ({:.4e} particle-steps; runs that settle stop sooner): see `demsweep plan {}`",
            plan.study_path.display(),
            duration(seconds),
            plan.total_cost(),
            plan.study_path.display()
        );
    }
}

/// What each distinct `particles.size_distribution` of the plan gives its disks: the count of each
/// class of a discrete mixture, or the range and mean drawn with the first run's placement seed
/// (none for a placement file, whose disks keep their own radii).
fn size_notes(plan: &Plan) -> Vec<String> {
    use demsweep::physics::number::significant;
    let mut seen = Vec::new();
    let mut notes = Vec::new();
    for run in plan.runs.iter().filter(|run| !run.scene.placement.kind.reads_file()) {
        let p = &run.scene.particles;
        let Some(distribution) = p.size_distribution.as_ref().filter(|d| !seen.contains(&(*d, p.count))) else {
            continue;
        };
        seen.push((distribution, p.count));
        let drawn = distribution.drawn(p.count, run.scene.placement.seed);
        let m = |x: f64| format!("{} m", significant(x, 3));
        let what = if drawn.classes.is_empty() {
            let seed = run.scene.placement.seed;
            format!(
                "{} disks, {}: with placement seed {seed} (run {}) radii {} to {}, mean {}",
                drawn.count,
                drawn.kind.name(),
                run.id,
                m(drawn.min),
                m(drawn.max),
                m(drawn.mean)
            )
        } else {
            let classes: Vec<String> = drawn.classes.iter().map(|(r, n)| format!("{n} of radius {}", m(*r))).collect();
            format!("{} disks: {} (in an order drawn with each run's placement seed)", drawn.count, classes.join(", "))
        };
        notes.push(format!("particles.size_distribution: {what}"));
    }
    notes
}

/// One aligned line per run: id, swept parameters, disks, steps, particle-steps.
fn run_table(plan: &Plan) -> String {
    let names = plan.runs.first().map(|r| r.parameters.iter().map(|(k, _)| k.clone()).collect()).unwrap_or_default();
    let header: Vec<String> = [
        vec!["id".to_string()],
        names,
        vec!["disks".into(), "time_step".into(), "steps".into(), "particle-steps".into()],
    ]
    .concat();
    let rows = plan.runs.iter().map(|run| {
        let values = run.parameters.iter().map(|(_, v)| v.to_string());
        let cost = [
            run.scene.particles.count.to_string(),
            format!("{:.3e}", run.time_step),
            format!("{:.0}", run.estimated_cost / run.scene.particles.count.max(1) as f64),
            format!("{:.3e}", run.estimated_cost),
        ];
        std::iter::once(run.id.clone()).chain(values).chain(cost).collect::<Vec<_>>()
    });
    let table: Vec<Vec<String>> = std::iter::once(header).chain(rows).collect();
    let widths: Vec<usize> =
        (0..table[0].len()).map(|c| table.iter().map(|row| row[c].len()).max().unwrap_or(0)).collect();
    table
        .iter()
        .map(|row| {
            let cells: Vec<String> = row.iter().zip(&widths).map(|(cell, w)| format!("{cell:<w$}")).collect();
            format!("{}\n", cells.join("  ").trim_end())
        })
        .collect()
}

fn keys(args: &KeysArgs) -> ExitCode {
    let prefix = args.prefix.as_deref().unwrap_or("");
    let keys: Vec<_> =
        demsweep::physics::keys::scene_keys().into_iter().filter(|k| k.path.starts_with(prefix)).collect();
    if keys.is_empty() {
        errln!("error: no scene key starts with `{prefix}`: `demsweep keys` lists them all");
        return ExitCode::FAILURE;
    }
    if args.markdown {
        out!("{}", demsweep::physics::keys::markdown_table(&keys));
        return ExitCode::SUCCESS;
    }
    let width = keys.iter().map(|k| k.path.len() + k.default.len() + 3).max().unwrap_or(0);
    for k in &keys {
        let setting = format!("{} = {}", k.path, k.default);
        let unit = if k.unit.is_empty() { String::new() } else { format!(" [{}]", k.unit) };
        let range = if k.range.is_empty() { String::new() } else { format!(" ({})", k.range) };
        outln!("{setting:<width$}  {}{unit}{range}", k.description);
    }
    ExitCode::SUCCESS
}

/// `1 run`, `18 runs`.
fn runs(n: usize) -> String {
    if n == 1 { "1 run".into() } else { format!("{n} runs") }
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    use super::*;

    /// `tune --help` states the skip rule docs/tune.md states, with the slack the judge applies.
    #[test]
    fn tune_help_states_the_skip_rule_of_the_docs() {
        let help = Cli::command().find_subcommand("tune").unwrap().get_long_about().unwrap().to_string();
        let slack = demsweep::tune::judge::PREDICTED_SLACK * 100.0;
        assert!(help.contains(&format!("more than {slack} % past the reference's figure")), "{help}");
        assert!(help.contains("predicted past a validity limit"), "{help}");
        let docs = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/tune.md")).unwrap();
        let docs = docs.split_whitespace().collect::<Vec<_>>().join(" ");
        assert!(docs.contains(&format!("within {slack} % of the reference's figure")), "docs/tune.md");
        assert!(docs.contains("a setting predicted past one is recorded (`_skipped.csv`) and never run"));
    }
}

//! `demsweep tune FILE`: the fastest deposition that still makes the same pile; and what `check` and
//! `plan` say about a tune file.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use clap::Args;
use demsweep::physics::number::short;
use demsweep::runner::interrupt;
use demsweep::tune::{self, TuneError, TuneOptions, TuneSpec};
use demsweep::workflow::{self, TuneRunError};

use super::estimate::{SECONDS_PER_PARTICLE_STEP, duration};
use super::exit::{INVALID_STUDY, refuse_warnings};

/// Exit status of a tune that stopped because a kept metric's tolerance cannot be decided.
pub const UNDECIDABLE: u8 = 3;

#[derive(Args)]
pub struct TuneArgs {
    /// The tune file (TOML: [scene], [levers], [keep], [search]).
    file: PathBuf,
    /// Worker threads, one simulation each (default: all cores). The answer does not depend on it.
    #[arg(long, short = 'j')]
    jobs: Option<usize>,
    /// Output directory (default: results/<name>/).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Reuse the runs of an existing results file (after a kill, Ctrl-C or crash) and go on.
    #[arg(long, conflicts_with = "force")]
    resume: bool,
    /// With --resume: reuse runs made by another demsweep version of the same physics version
    /// (else such a resume is refused, naming the run and both versions).
    #[arg(long, requires = "resume")]
    accept_version: bool,
    /// Replace an existing results file, and any file at the tune's output paths (by default only
    /// files demsweep wrote).
    #[arg(long)]
    force: bool,
    /// No line per batch.
    #[arg(long)]
    quiet: bool,
    /// Most reference depositions the tune may spend, instead of the file's `[search] max_spend`:
    /// with --resume, a tune the spend left undecided continues from its stored runs.
    #[arg(long, value_name = "N")]
    max_spend: Option<f64>,
}

/// The tune file's spec, or its problems printed to stderr and the exit status of an invalid file.
/// The warnings of a valid file (clipped lever ranges, the reference scene's predicted validity
/// warnings) go to stderr, and are errors when `strict`; returns their number with the spec.
pub fn load_or_report(path: &Path, strict: bool) -> Result<(TuneSpec, usize), ExitCode> {
    let (spec, warnings) = workflow::load_tune(path).map_err(|errors| {
        errln!("{errors}");
        errln!("{}: {} problem(s); nothing was run", path.display(), errors.0.len());
        ExitCode::from(INVALID_STUDY)
    })?;
    for warning in &warnings {
        errln!("warning: {warning}");
    }
    refuse_warnings(path, warnings.len(), strict)?;
    Ok((spec, warnings.len()))
}

/// `demsweep check` of a tune file.
pub fn check(path: &Path, strict: bool) -> ExitCode {
    match load_or_report(path, strict) {
        Ok((spec, warnings)) => {
            let above = match warnings {
                0 => String::new(),
                1 => " (1 warning above)".into(),
                n => format!(" ({n} warnings above)"),
            };
            outln!(
                "ok: tune file, {} levers, {} kept metrics, budget {} runs{above}",
                spec.levers.len(),
                spec.keep.len(),
                spec.search.budget
            );
            outln!("{}", spend_text(&spec));
            ExitCode::SUCCESS
        }
        Err(code) => code,
    }
}

/// `demsweep plan` of a tune file: levers, seeds and the budget's cost bound.
pub fn plan(path: &Path, cores: usize) -> ExitCode {
    let spec = match load_or_report(path, false) {
        Ok((spec, _)) => spec,
        Err(code) => return code,
    };
    let s = &spec.search;
    outln!("tune {} ({}), fingerprint {}", spec.name, spec.path.display(), spec.fingerprint);
    outln!("levers:");
    for lever in &spec.levers {
        let range = match &lever.range {
            tune::LeverRange::Linear { low, high, .. } => format!("linear {low} .. {high}"),
            tune::LeverRange::Log { low, high, .. } => format!("log {low} .. {high}"),
            tune::LeverRange::List(values) => {
                format!("one of {}", values.iter().map(|v| v.to_string()).collect::<Vec<_>>().join(", "))
            }
        };
        outln!("  {}: {range}", lever.key);
    }
    match spec.standards.is_empty() {
        true => outln!("standard settings: none (no lever has a standard value)"),
        false => outln!("standard settings (standard values of the levers), evaluated first:"),
    }
    for standard in &spec.standards {
        outln!("  {}", standard.name);
    }
    outln!("keep:");
    for keep in &spec.keep {
        let kind = if keep.absolute { "absolute" } else { "relative" };
        outln!("  {}: within ±{} ({kind})", keep.metric, keep.tolerance);
    }
    outln!(
        "search: objective {}, {} seeds per candidate (up to {}), reference {} seeds, verification {} fresh seeds, \
         budget {} runs and {} reference depositions, seed {}",
        s.objective.name(),
        s.seeds,
        s.max_seeds,
        s.reference_seeds(),
        s.verify_seeds(),
        s.budget,
        s.max_spend,
        s.seed
    );
    outln!("{}", spend_text(&spec));
    // The dearest run over the reference and every lever's extremes bounds the cost of a run.
    let cost = |scene: demsweep::physics::SceneConfig| {
        demsweep::study::PlannedRun::new(String::new(), 0, Vec::new(), scene, spec.initial.clone()).estimated_cost
    };
    let reference_cost = cost(spec.reference.clone());
    let mut dearest = reference_cost;
    for (d, lever) in spec.levers.iter().enumerate() {
        for u in [0.0, 1.0] {
            // Only lever d's value is set on the reference scene: the other coordinates do not matter.
            let mut point = vec![0.5; spec.levers.len()];
            point[d] = u;
            let mut values: Vec<_> = spec.values(&point);
            values.retain(|(k, _)| *k == lever.key);
            if let Ok(scene) = spec.scene(&values) {
                dearest = dearest.max(cost(scene));
            }
        }
    }
    let bound = dearest * s.budget as f64;
    let seconds = bound * SECONDS_PER_PARTICLE_STEP;
    outln!(
        "reference run: {reference_cost:.3e} particle-steps at most (full duration); budget bound {bound:.3e} \
         particle-steps ({} runs x {dearest:.3e}, the dearest lever extreme): about {} on 1 core, {} on {cores} cores \
         (runs stop when settled, so far less)",
        s.budget,
        duration(seconds),
        duration(seconds / cores as f64)
    );
    ExitCode::SUCCESS
}

/// What the spend limit buys before any run ([`tune::search::spend_plan`]), as `check` and `plan`
/// say it: where it buys no candidate at the reference's cost, the `max_spend` or
/// `reference_seeds` that would.
fn spend_text(spec: &TuneSpec) -> String {
    let s = &spec.search;
    let p = tune::search::spend_plan(&tune::search_config(spec));
    let mut text = format!(
        "spend: the reference's {} runs take {} of max_spend = {} reference depositions; the {} left pay for {} \
         candidate(s) at the reference's cost per run ({} seeds each, a verification round of {} in reserve)",
        s.reference_seeds(),
        short(p.reference),
        short(s.max_spend),
        short(p.left),
        p.candidates,
        s.seeds,
        s.verify_seeds()
    );
    if p.candidates == 0 {
        if let Some(cap) = p.cut_at {
            text += &format!(
                "; the first candidate's seeds run cut at {} of the reference's cost, where its verification still fits",
                short(cap)
            );
        }
        text += &format!("; one candidate at the reference's cost needs max_spend = {}", short(p.max_spend));
        if let Some(n) = p.reference_seeds {
            text += &format!(" or reference_seeds = {n}");
        }
    }
    text
}

/// `demsweep tune FILE`.
pub fn run(args: &TuneArgs) -> ExitCode {
    let mut spec = match load_or_report(&args.file, false) {
        Ok((spec, _)) => spec,
        Err(code) => return code,
    };
    if let Some(n) = args.max_spend {
        if !(n >= 1.0 && n.is_finite()) {
            errln!("tune: --max-spend must be at least 1 reference deposition, got {n}; nothing was run");
            return ExitCode::from(INVALID_STUDY);
        }
        spec.search.max_spend = n;
    }
    let stop = Arc::new(AtomicBool::new(false));
    if let Err(e) = interrupt::install_ctrl_c(stop.clone()) {
        errln!("warning: {e}");
    }
    let options = TuneOptions {
        jobs: args.jobs.unwrap_or(0),
        out_dir: args.out.clone(),
        resume: args.resume,
        accept_version: args.accept_version,
        force: args.force,
        verbose: !args.quiet,
        stop,
    };
    let started = std::time::Instant::now();
    let run = match workflow::tune_file(&mut spec, &options) {
        Ok(run) => run,
        Err(TuneRunError::Tune(TuneError::Interrupted)) => {
            errln!("tune: {}", TuneError::Interrupted);
            return ExitCode::from(interrupt::EXIT_INTERRUPTED as u8);
        }
        Err(e) => {
            errln!("tune: {e}");
            return ExitCode::FAILURE;
        }
    };
    let (outcome, written) = (&run.report, &run.written);
    outln!();
    outln!("{}", run.recommendation);
    outln!();
    outln!("wrote {}", outcome.results.display());
    for file in &written.files {
        outln!("wrote {}", file.display());
    }
    match &run.section {
        Ok(path) => outln!("wrote {}", path.display()),
        Err(e) => errln!("warning: no tune section for the report: {e}"),
    }
    let paged = super::results::page_written(&outcome.results, run.page);
    for e in &written.chart_errors {
        errln!("chart not drawn: {e}");
    }
    if outcome.unplanned > 0 {
        errln!(
            "note: {}: {} stored run(s) were not replayed by this tune (an earlier tune of this file went \
             another way): kept in the file, left out of its summary and report",
            outcome.results.display(),
            outcome.unplanned
        );
    }
    outln!(
        "{} runs ({} made now, {} from the file), {:.3e} particle-steps, {:.1} s",
        outcome.ran + outcome.reused,
        outcome.ran,
        outcome.reused,
        outcome.total_particle_steps,
        started.elapsed().as_secs_f64()
    );
    if !outcome.result.undecidable.is_empty() {
        ExitCode::from(UNDECIDABLE)
    } else if written.chart_errors.is_empty() && paged {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

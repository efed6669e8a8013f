//! `demsweep bench accuracy|stability|stable-step|stress|skipping|tune`: the benchmarks of `demsweep::bench`.

use std::error::Error;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Subcommand};
use demsweep::bench::BenchError;
use demsweep::bench::accuracy::{AccuracyOptions, accuracy};
use demsweep::bench::skipping::{SkippingOptions, skipping};
use demsweep::bench::stability_map::{StabilityMapOptions, stability_map};
use demsweep::bench::stable_step::{StableStepOptions, stable_step};
use demsweep::bench::stress::{StressOptions, stress};
use demsweep::bench::tune::{TuneBenchOptions, tune_bench};
use demsweep::study;

#[derive(Args)]
pub struct BenchArgs {
    #[command(subcommand)]
    which: Which,
    /// Folder for the CSV, Markdown and chart files (default: results/bench_latest, which git ignores).
    #[arg(long, global = true, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Write into results/bench, the committed figures the docs quote, instead.
    #[arg(long, global = true, conflicts_with = "out")]
    update_results: bool,
}

#[derive(Subcommand)]
enum Which {
    /// Work-precision: error against run time of both integrators, time steps t_c/5 … t_c/400
    /// (binary Hertz impact and a 300-disk deposition; about a minute).
    Accuracy,
    /// Stability map: blow-ups and runs that never come to rest, each case also restarted mid-run, over
    /// time step × stiffness × damping × friction against the predicted safe time step (a few thousand
    /// small runs on all cores; a few minutes).
    Stability,
    /// The largest step of each integrator at which 300-disk depositions settle, straight through and
    /// restarted mid-way, by restitution: the measurement behind the engine's stable-step limit (about
    /// 800 depositions; ten minutes on two cores).
    StableStep,
    /// Stress scenarios: Table 1, too-large steps, 50 m/s impact, dense lattice, 0, 1 and 100 000 disks,
    /// β = 50, frictionless (about ten seconds).
    Stress,
    /// Time saved by stopping at settle, sparse diagnostics and frictionless shortcuts (on the 80 runs of
    /// the default study: about six minutes on one core).
    Skipping {
        /// Study whose runs the stop-at-settle saving is measured on (the first run also for sampling and
        /// friction).
        #[arg(long, default_value = "studies/damping_sweep.toml")]
        study: PathBuf,
    },
    /// `demsweep tune` against a brute-force ladder over its levers (standard settings, time-step rungs,
    /// a grid and its half-steps, on fresh seeds) on each tune file: tune's verified cost against the
    /// ladder's cheapest valid, equivalent rung, and tune's spend (minutes to hours on 2 cores).
    Tune {
        /// Tune files (default: studies/tune_deposition.toml and studies/tune_polydisperse.toml).
        #[arg(long = "tune", value_name = "FILE")]
        tunes: Vec<PathBuf>,
        /// Worker threads (default: all cores).
        #[arg(long, short = 'j')]
        jobs: Option<usize>,
        /// Fresh seeds of the ladder's rungs (2 to 1000; default 10; the reference's count when
        /// larger); as many again confirm its best.
        #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(2..=1000))]
        ladder_seeds: Option<u64>,
    },
}

/// Runs one benchmark; prints its Markdown summary.
pub fn bench(args: &BenchArgs) -> ExitCode {
    let out = match (&args.out, args.update_results) {
        (_, true) => PathBuf::from(demsweep::bench::COMMITTED_DIR),
        (Some(dir), false) => dir.clone(),
        (None, false) => PathBuf::from(demsweep::bench::LATEST_DIR),
    };
    let result = match &args.which {
        Which::Accuracy => {
            accuracy(&AccuracyOptions { out_dir: out.clone(), ..Default::default() }).map(|_| "accuracy.md")
        }
        Which::Stability => stability_map(&StabilityMapOptions { out_dir: out.clone(), ..Default::default() })
            .map(|_| "stability_map.md"),
        Which::StableStep => {
            stable_step(&StableStepOptions { out_dir: out.clone(), ..Default::default() }).map(|_| "stable_step.md")
        }
        Which::Stress => stress(&StressOptions { out_dir: out.clone(), ..Default::default() }).map(|_| "stress.md"),
        Which::Skipping { study } => {
            skipping_options(study, out.clone()).and_then(|o| skipping(&o)).map(|_| "skipping.md")
        }
        Which::Tune { tunes, jobs, ladder_seeds } => {
            let defaults = TuneBenchOptions::default();
            let options = TuneBenchOptions {
                tunes: if tunes.is_empty() { defaults.tunes } else { tunes.clone() },
                jobs: jobs.unwrap_or(0),
                work_dir: out.join("tune_work"),
                out_dir: out.clone(),
                ladder_seeds: ladder_seeds.map_or(defaults.ladder_seeds, |n| n as usize),
            };
            tune_bench(&options).map(|_| "tune.md")
        }
    };
    match result.map_err(Box::<dyn Error>::from).and_then(|summary| print_file(&out.join(summary))) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            errln!("bench: {error}");
            ExitCode::FAILURE
        }
    }
}

/// Skipping options measuring every run of `study`.
fn skipping_options(study: &Path, out_dir: PathBuf) -> Result<SkippingOptions, BenchError> {
    let plan = study::load(study)?;
    Ok(SkippingOptions {
        source: format!("every run of {}", study.display()),
        scenes: plan.runs.into_iter().map(|r| r.scene).collect(),
        out_dir,
        ..Default::default()
    })
}

fn print_file(path: &Path) -> Result<(), Box<dyn Error>> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    out!("{text}");
    Ok(())
}

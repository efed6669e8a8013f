//! The `slurm` command: write (and submit) the array and merge jobs of a study.

use std::error::Error;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;
use demsweep::slurm::{self, ArrayJob, Scripts};
use demsweep::study::Plan;

use super::exit::FAILED;

#[derive(Args)]
pub struct SlurmArgs {
    /// The study file (TOML).
    study: PathBuf,
    /// Number of shards, i.e. array tasks.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    shards: u32,
    /// Worker threads per task (each task asks Slurm for this many CPUs).
    #[arg(long, short = 'j', default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    jobs: u32,
    /// Output directory (default: results/<study name>/): gets shards/, logs/, slurm/ and the merged results.
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Slurm partition (default: the site's default partition).
    #[arg(long)]
    partition: Option<String>,
    /// Time limit of each task and of the merge, in a Slurm format such as 02:00:00 (default: the partition's).
    #[arg(long)]
    time: Option<String>,
    /// The demsweep executable the jobs run (default: this one, by its absolute path: the one
    /// `cargo install --locked --path .` put on the PATH; a cargo build folder's is warned about).
    #[arg(long, value_name = "PATH")]
    demsweep: Option<PathBuf>,
    /// Also print both scripts.
    #[arg(long)]
    print: bool,
    /// Submit the jobs with sbatch (otherwise only write the scripts and say how to submit them).
    #[arg(long)]
    submit: bool,
}

impl SlurmArgs {
    /// The study file.
    pub fn study(&self) -> &Path {
        &self.study
    }

    /// The output directory, when given.
    pub fn out(&self) -> Option<&Path> {
        self.out.as_deref()
    }
}

/// `demsweep slurm`: exit 0 when the scripts were written (and submitted), 1 otherwise.
pub fn slurm(args: &SlurmArgs, plan: &Plan) -> ExitCode {
    match array_job(args, plan).and_then(|job| write_and_submit(args, &job)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            errln!("error: {e}");
            ExitCode::from(FAILED)
        }
    }
}

/// The job to write, with absolute paths (jobs may start in another directory).
fn array_job(args: &SlurmArgs, plan: &Plan) -> Result<ArrayJob, Box<dyn Error>> {
    let shards = args.shards as usize;
    if shards > plan.runs.len() {
        return Err(format!("--shards {shards}: the study has only {} runs", plan.runs.len()).into());
    }
    let demsweep = match &args.demsweep {
        Some(path) => path.clone(),
        None => {
            let this =
                std::env::current_exe().map_err(|e| format!("cannot find this executable (use --demsweep): {e}"))?;
            warn_if_build_folder(&this);
            this
        }
    };
    let out = args.out.clone().unwrap_or_else(|| Path::new("results").join(&plan.name));
    Ok(ArrayJob {
        study: absolute(&args.study)?,
        study_name: plan.name.clone(),
        out_dir: absolute(&out)?,
        shards,
        jobs: args.jobs as usize,
        partition: args.partition.clone(),
        time: args.time.clone(),
        demsweep: absolute(&demsweep)?,
    })
}

/// Warns when the jobs would run a cargo build folder's binary (`cargo run -- slurm ...`): the next
/// `cargo build` replaces it under queued jobs.
fn warn_if_build_folder(exe: &Path) {
    // Cargo keeps its build state in `.fingerprint/` beside the binaries of a profile folder.
    if exe.parent().is_some_and(|profile| profile.join(".fingerprint").is_dir()) {
        errln!(
            "warning: the jobs will run {}, a cargo build folder's binary, which the next cargo build replaces \
             under queued jobs: install demsweep (cargo install --locked --path .) and run `demsweep slurm` from the PATH, \
             or pass --demsweep PATH",
            exe.display()
        );
    }
}

fn absolute(path: &Path) -> Result<PathBuf, Box<dyn Error>> {
    std::path::absolute(path).map_err(|e| format!("{}: {e}", path.display()).into())
}

fn write_and_submit(args: &SlurmArgs, job: &ArrayJob) -> Result<(), Box<dyn Error>> {
    let scripts = job.write_scripts()?;
    if args.print {
        for path in [&scripts.array, &scripts.merge] {
            let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
            outln!("==> {} <==\n{text}", path.display());
        }
    }
    outln!(
        "wrote {} ({} array tasks, one per shard) and {}",
        scripts.array.display(),
        job.shards,
        scripts.merge.display()
    );
    if !args.submit {
        print_how_to_submit(&scripts);
        return Ok(());
    }
    let ids = slurm::submit(&scripts)?;
    outln!(
        "submitted array job {} ({} tasks) and merge job {} (starts when every task ended)",
        ids.array_id,
        job.shards,
        ids.merge_id
    );
    outln!("watch: squeue -j {},{}; logs in {}", ids.array_id, ids.merge_id, job.log_dir().display());
    outln!(
        "results: {}; if a task fails, see docs/cluster.md",
        job.out_dir.join(format!("{}.h5", job.study_name)).display()
    );
    Ok(())
}

fn print_how_to_submit(scripts: &Scripts) {
    outln!(
        "submit with:\n  ARRAY=$(sbatch --parsable {})\n  sbatch --dependency=afterany:$ARRAY {}\n\
         (or run this command again with --submit)",
        scripts.array.display(),
        scripts.merge.display()
    );
}

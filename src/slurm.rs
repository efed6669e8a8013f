//! Scale-out on Slurm: batch scripts that run a study as an array job (one task per shard, each
//! `demsweep run --shard K/N --resume`) and a merge job that runs after every task ended (whether it
//! succeeded or not: the merge merges what there is and names the shards to run again), and their
//! submission.
//!
//! The scripts are the templates in `scripts/slurm/` with their `{{PLACEHOLDERS}}` filled in.
//! Layout under the output directory: `shards/` (shard files), `logs/` (job output), `slurm/` (scripts);
//! the merge writes `<study name>.h5` and its CSV summary into the output directory itself.

use std::fmt;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus};

use crate::output::guard::GuardError;

const ARRAY_TEMPLATE: &str = include_str!("../scripts/slurm/array.sbatch.template");
const MERGE_TEMPLATE: &str = include_str!("../scripts/slurm/merge.sbatch.template");

/// Why the batch scripts could not be made, written or submitted.
#[derive(Debug)]
pub enum SlurmError {
    /// An `#SBATCH --option` value Slurm would misread.
    Directive {
        /// The option (`partition`, `time`).
        option: &'static str,
        /// The value given.
        value: String,
    },
    /// An output path Slurm cannot use in an `#SBATCH` line.
    OutputPath(PathBuf),
    /// A directory that could not be created.
    CreateDir {
        /// The directory.
        dir: PathBuf,
        /// Why.
        error: std::io::Error,
    },
    /// A script that could not be written.
    Write(GuardError),
    /// `sbatch` could not be started.
    Start {
        /// The script it was to submit.
        script: PathBuf,
        /// Why.
        error: std::io::Error,
    },
    /// `sbatch` refused the script.
    Refused {
        /// The script.
        script: PathBuf,
        /// How `sbatch` ended.
        status: ExitStatus,
        /// What it printed on stderr.
        stderr: String,
    },
    /// `sbatch` printed no job id.
    NoJobId {
        /// What it printed.
        stdout: String,
    },
    /// The merge job was not submitted, after the array job was.
    Merge {
        /// The array job's id.
        array_id: String,
        /// The merge script.
        script: PathBuf,
        /// Why.
        error: Box<SlurmError>,
    },
}

impl fmt::Display for SlurmError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SlurmError::Directive { option, value } => {
                write!(f, "--{option} `{value}`: must be non-empty, without spaces, quotes, backslashes or `%`")
            }
            SlurmError::OutputPath(path) => write!(
                f,
                "{}: Slurm cannot use an output path with spaces, quotes, backslashes, `%` or non-UTF-8 characters",
                path.display()
            ),
            SlurmError::CreateDir { dir, error } => write!(f, "{}: cannot create directory: {error}", dir.display()),
            SlurmError::Write(e) => write!(f, "{e}"),
            SlurmError::Start { script, error } if error.kind() == std::io::ErrorKind::NotFound => write!(
                f,
                "`sbatch` is not on PATH: run this on a Slurm login node, or submit the scripts there (script {})",
                script.display()
            ),
            SlurmError::Start { script, error } => {
                write!(f, "cannot run `sbatch`: {error} (script {})", script.display())
            }
            SlurmError::Refused { script, status, stderr } => {
                write!(f, "sbatch {} failed ({status}): {stderr}", script.display())
            }
            SlurmError::NoJobId { stdout } => write!(f, "sbatch printed no job id (output: `{stdout}`)"),
            SlurmError::Merge { array_id, script, error } => write!(
                f,
                "{error}\nthe array job {array_id} was submitted; submit the merge by hand: sbatch \
                 --dependency=afterany:{array_id} {}",
                script.display()
            ),
        }
    }
}

impl std::error::Error for SlurmError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SlurmError::CreateDir { error, .. } | SlurmError::Start { error, .. } => Some(error),
            SlurmError::Write(e) => Some(e),
            SlurmError::Merge { error, .. } => Some(error.as_ref()),
            _ => None,
        }
    }
}

/// One study split into shards, run as a Slurm array job plus a merge job.
#[derive(Clone, Debug, PartialEq)]
pub struct ArrayJob {
    /// The study file (absolute: jobs may start in another directory).
    pub study: PathBuf,
    /// The study name (for the job names).
    pub study_name: String,
    /// Output directory (absolute).
    pub out_dir: PathBuf,
    /// Number of shards = array tasks.
    pub shards: usize,
    /// Worker threads per task, and CPUs requested per task.
    pub jobs: usize,
    /// Slurm partition (`--partition`); the site default when `None`.
    pub partition: Option<String>,
    /// Time limit per task (`--time`, e.g. `02:00:00`); the partition default when `None`.
    pub time: Option<String>,
    /// The `demsweep` executable the jobs run (absolute).
    pub demsweep: PathBuf,
}

/// Paths of the written batch scripts.
#[derive(Clone, Debug, PartialEq)]
pub struct Scripts {
    /// The array job script.
    pub array: PathBuf,
    /// The merge job script.
    pub merge: PathBuf,
}

/// Ids of the submitted jobs.
#[derive(Clone, Debug, PartialEq)]
pub struct Submitted {
    /// The array job.
    pub array_id: String,
    /// The merge job (starts when every array task ended).
    pub merge_id: String,
}

impl ArrayJob {
    /// Where the array tasks write their shard files.
    pub fn shard_dir(&self) -> PathBuf {
        self.out_dir.join("shards")
    }

    /// Where Slurm writes the jobs' output.
    pub fn log_dir(&self) -> PathBuf {
        self.out_dir.join("logs")
    }

    /// Where the batch scripts are written.
    pub fn script_dir(&self) -> PathBuf {
        self.out_dir.join("slurm")
    }

    /// The array job script.
    pub fn array_script(&self) -> Result<String, SlurmError> {
        self.render(ARRAY_TEMPLATE)
    }

    /// The merge job script (its dependency on the array job is given at submission).
    pub fn merge_script(&self) -> Result<String, SlurmError> {
        self.render(MERGE_TEMPLATE)
    }

    /// Writes both scripts into [`Self::script_dir`], creating it and the shard and log directories
    /// (Slurm does not create the directory of `--output`).
    pub fn write_scripts(&self) -> Result<Scripts, SlurmError> {
        let (array, merge) = (self.array_script()?, self.merge_script()?);
        for dir in [self.shard_dir(), self.log_dir(), self.script_dir()] {
            std::fs::create_dir_all(&dir).map_err(|error| SlurmError::CreateDir { dir, error })?;
        }
        let scripts = self.script_paths();
        for (path, text) in [(&scripts.array, array), (&scripts.merge, merge)] {
            crate::output::guard::write(path, text.as_bytes(), &[&self.study]).map_err(SlurmError::Write)?;
        }
        Ok(scripts)
    }

    fn script_paths(&self) -> Scripts {
        Scripts { array: self.script_dir().join("array.sbatch"), merge: self.script_dir().join("merge.sbatch") }
    }

    fn render(&self, template: &str) -> Result<String, SlurmError> {
        let log_dir = directive_path(&self.log_dir())?;
        let scripts = self.script_paths();
        let extra: String = [("partition", &self.partition), ("time", &self.time)]
            .into_iter()
            .filter_map(|(option, value)| value.as_ref().map(|v| directive(option, v)))
            .collect::<Result<_, _>>()?;
        let values = [
            ("{{JOB_NAME}}", job_name(&self.study_name)),
            ("{{SHARDS}}", self.shards.to_string()),
            // Log files' task ids zero-padded (Slurm's `%2a`), as demsweep pads the shards' file names.
            ("{{TASK_DIGITS}}", self.shards.to_string().len().to_string()),
            ("{{JOBS}}", self.jobs.to_string()),
            ("{{LOG_DIR}}", log_dir),
            ("{{EXTRA_DIRECTIVES}}\n", extra),
            ("{{DEMSWEEP}}", shell_quote(&self.demsweep)),
            ("{{STUDY}}", shell_quote(&self.study)),
            ("{{OUT}}", shell_quote(&self.out_dir)),
            ("{{SHARD_DIR}}", shell_quote(&self.shard_dir())),
            ("{{ARRAY_SCRIPT}}", shell_quote(&scripts.array)),
            ("{{MERGE_SCRIPT}}", shell_quote(&scripts.merge)),
        ];
        Ok(values.iter().fold(template.to_string(), |text, (key, value)| text.replace(key, value)))
    }
}

/// Submits the array job, then the merge job with `--dependency=afterany:<array job>`.
pub fn submit(scripts: &Scripts) -> Result<Submitted, SlurmError> {
    let array_id = sbatch(&[], &scripts.array)?;
    let dependency = format!("--dependency=afterany:{array_id}");
    let merge_id = sbatch(&[&dependency], &scripts.merge).map_err(|error| SlurmError::Merge {
        array_id: array_id.clone(),
        script: scripts.merge.clone(),
        error: Box::new(error),
    })?;
    Ok(Submitted { array_id, merge_id })
}

/// Runs `sbatch --parsable ARGS SCRIPT` and returns the job id.
fn sbatch(args: &[&str], script: &Path) -> Result<String, SlurmError> {
    let output = Command::new("sbatch")
        .arg("--parsable")
        .args(args)
        .arg(script)
        .output()
        .map_err(|error| SlurmError::Start { script: script.to_path_buf(), error })?;
    if !output.status.success() {
        return Err(SlurmError::Refused {
            script: script.to_path_buf(),
            status: output.status,
            stderr: String::from_utf8_lossy(&output.stderr).trim().to_string(),
        });
    }
    parse_job_id(&String::from_utf8_lossy(&output.stdout))
}

/// The job id from `sbatch --parsable` output: `ID` or `ID;CLUSTER`.
fn parse_job_id(stdout: &str) -> Result<String, SlurmError> {
    let id = stdout.trim().split(';').next().unwrap_or_default();
    if !id.is_empty() && id.chars().all(|c| c.is_ascii_digit()) {
        Ok(id.to_string())
    } else {
        Err(SlurmError::NoJobId { stdout: stdout.trim().to_string() })
    }
}

/// The study name reduced to characters safe in a job name.
fn job_name(study_name: &str) -> String {
    let safe: String =
        study_name.chars().map(|c| if c.is_ascii_alphanumeric() || "-_.".contains(c) { c } else { '_' }).collect();
    format!("demsweep-{safe}")
}

/// Whether Slurm reads `value` verbatim in an `#SBATCH` line (no spaces, quotes, backslashes or `%`).
fn slurm_safe(value: &str) -> bool {
    !value.is_empty() && !value.chars().any(|c| c.is_whitespace() || "\"'\\%".contains(c))
}

/// An `#SBATCH --option=value` line.
fn directive(option: &'static str, value: &str) -> Result<String, SlurmError> {
    if !slurm_safe(value) {
        return Err(SlurmError::Directive { option, value: value.to_string() });
    }
    Ok(format!("#SBATCH --{option}={value}\n"))
}

/// A path usable in an `#SBATCH` line.
fn directive_path(path: &Path) -> Result<String, SlurmError> {
    match path.to_str() {
        Some(text) if slurm_safe(text) => Ok(text.to_string()),
        _ => Err(SlurmError::OutputPath(path.to_path_buf())),
    }
}

/// The path as one shell word (single-quoted unless plainly safe).
fn shell_quote(path: &Path) -> String {
    let text = path.to_string_lossy();
    if !text.is_empty() && text.chars().all(|c| c.is_ascii_alphanumeric() || "/._-+=:,@".contains(c)) {
        text.into_owned()
    } else {
        format!("'{}'", text.replace('\'', r"'\''"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn job() -> ArrayJob {
        ArrayJob {
            study: "/data/my study's.toml".into(),
            study_name: "damping sweep".into(),
            out_dir: "/scratch/out".into(),
            shards: 4,
            jobs: 2,
            partition: None,
            time: None,
            demsweep: "/opt/bin/demsweep".into(),
        }
    }

    #[test]
    fn array_script_runs_one_shard_per_task_with_resume() {
        let script = job().array_script().unwrap();
        assert!(!script.contains("{{"), "placeholder left:\n{script}");
        for line in [
            "#SBATCH --job-name=demsweep-damping_sweep\n",
            "#SBATCH --array=1-4\n",
            "#SBATCH --cpus-per-task=2\n",
            "#SBATCH --output=/scratch/out/logs/%x_%A_%1a.out\nset -euo pipefail\n",
            "exec /opt/bin/demsweep run '/data/my study'\\''s.toml' --shard \"${SLURM_ARRAY_TASK_ID}/4\" \
             --out /scratch/out/shards \\\n    --jobs 2 --resume",
        ] {
            assert!(script.contains(line), "missing {line:?} in:\n{script}");
        }
        assert!(!script.contains("--partition") && !script.contains("--time"));
    }

    #[test]
    fn merge_script_merges_the_shard_directory_into_the_output_directory() {
        let script = job().merge_script().unwrap();
        assert!(!script.contains("{{"), "placeholder left:\n{script}");
        assert!(script.contains("#SBATCH --job-name=demsweep-damping_sweep-merge\n"));
        assert!(script.contains(
            "exec /opt/bin/demsweep merge /scratch/out /scratch/out/shards --force \\\n    \
             --array-script /scratch/out/slurm/array.sbatch\n"
        ));
    }

    #[test]
    fn partition_and_time_become_directives_of_both_scripts() {
        let job = ArrayJob { partition: Some("long".into()), time: Some("02:00:00".into()), ..job() };
        for script in [job.array_script().unwrap(), job.merge_script().unwrap()] {
            assert!(script.contains("#SBATCH --partition=long\n#SBATCH --time=02:00:00\nset -euo"), "{script}");
        }
        let bad = ArrayJob { partition: Some("a b".into()), ..job };
        assert!(bad.array_script().unwrap_err().to_string().contains("--partition `a b`"));
    }

    #[test]
    fn output_paths_slurm_would_misread_are_refused() {
        let job = ArrayJob { out_dir: "/scratch/my out".into(), ..job() };
        assert!(job.array_script().unwrap_err().to_string().starts_with("/scratch/my out/logs: Slurm cannot use"));
    }

    #[test]
    fn job_ids_are_parsed_from_parsable_output() {
        assert_eq!(parse_job_id("1234\n").unwrap(), "1234");
        assert_eq!(parse_job_id("77;cluster1\n").unwrap(), "77");
        let none = parse_job_id("Submitted batch job 5\n").unwrap_err().to_string();
        assert_eq!(none, "sbatch printed no job id (output: `Submitted batch job 5`)");
    }
}

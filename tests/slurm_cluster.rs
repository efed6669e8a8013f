//! `demsweep slurm --submit` against a real (throw-away, single-node) Slurm cluster started with
//! `scripts/slurm/cluster.sh`: a 4-task array job whose task 2 fails still gets its merge job, which
//! merges the other shards and prints the commands that complete it; those commands give the
//! one-machine result, and a lost shard re-run alone (`sbatch --array=K`) then merged again gives it too.
//!
//! Needs root and apt-get (as CI has). Where no cluster can be started this test FAILS, saying so,
//! unless DEMSWEEP_ALLOW_NO_SLURM=1 is set (then it only prints that it did not run).

mod slurm_common;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use demsweep::output::summary;
use slurm_common::{NAME, demsweep, succeeded};

/// How long the jobs may take to finish (each needs well under a second).
const JOB_TIMEOUT: Duration = Duration::from_secs(180);
/// cluster.sh's exit status for "cannot provide a cluster here".
const NO_CLUSTER: i32 = 3;

/// A running test cluster, stopped (only the daemons it started, by PID) when dropped.
struct Cluster {
    state: PathBuf,
}

impl Cluster {
    /// Installs and starts a cluster; `None` when this machine cannot provide one and that is allowed.
    fn start() -> Option<Cluster> {
        // The munge user must reach the state directory: a fresh one in the world-traversable temp dir.
        let cluster =
            Cluster { state: std::env::temp_dir().join(format!("demsweep-slurm-test-{}", std::process::id())) };
        for args in [vec!["install"], vec!["start", cluster.state.to_str().unwrap()]] {
            let out = cluster_sh(&args);
            if out.status.code() == Some(NO_CLUSTER) {
                let why = String::from_utf8_lossy(&out.stderr);
                // Straight to the stderr stream: libtest would hide eprintln! output of a passing test.
                let loud = format!("\n*** SLURM TEST NOT RUN: cannot start a cluster here: {} ***\n", why.trim());
                let _ = std::io::stderr().write_all(loud.as_bytes());
                assert!(
                    std::env::var("DEMSWEEP_ALLOW_NO_SLURM").is_ok_and(|v| v == "1"),
                    "no Slurm cluster (needs root and apt-get): {why}; set DEMSWEEP_ALLOW_NO_SLURM=1 to skip knowingly"
                );
                return None;
            }
            succeeded(&format!("cluster.sh {}", args[0]), &out);
        }
        Some(cluster)
    }

    fn conf(&self) -> PathBuf {
        self.state.join("slurm.conf")
    }

    /// `COMMAND ARGS` talking to this cluster; its stdout.
    fn slurm(&self, command: &str, args: &[&str]) -> String {
        let out = Command::new(command).args(args).env("SLURM_CONF", self.conf()).output().unwrap();
        succeeded(&format!("{command} {args:?}"), &out)
    }

    /// `sbatch --parsable ARGS`: the job id.
    fn sbatch(&self, args: &[&str]) -> String {
        self.slurm("sbatch", &[&["--parsable"], args].concat()).trim().to_string()
    }

    /// The states of a job (one per array task), from `scontrol show job -o`.
    fn job_states(&self, id: &str) -> Vec<String> {
        let text = self.slurm("scontrol", &["show", "job", "-o", id]);
        let field = |line: &str, key: &str| line.split(' ').find_map(|f| f.strip_prefix(key)).map(str::to_string);
        text.lines()
            .filter_map(|line| {
                let state = field(line, "JobState=")?;
                Some(match field(line, "Reason=") {
                    Some(reason) if reason == "DependencyNeverSatisfied" => format!("{state}({reason})"),
                    _ => state,
                })
            })
            .collect()
    }

    /// Waits until every task of every job has ended; returns their states (panics with the logs
    /// after [`JOB_TIMEOUT`]).
    fn wait_ended(&self, ids: &[&str], logs: &Path) -> Vec<String> {
        let started = Instant::now();
        loop {
            let states: Vec<String> = ids.iter().flat_map(|id| self.job_states(id)).collect();
            let running = ["PENDING", "CONFIGURING", "RUNNING", "COMPLETING"];
            if !states.iter().any(|s| running.contains(&s.as_str())) {
                return states;
            }
            if started.elapsed() > JOB_TIMEOUT {
                panic!("jobs {ids:?} still {states:?} after {:?}; logs:\n{}", started.elapsed(), read_logs(logs));
            }
            std::thread::sleep(Duration::from_millis(200));
        }
    }

    /// Waits until every task of every job has ended; panics with the logs unless all completed.
    fn wait_completed(&self, ids: &[&str], logs: &Path) {
        let states = self.wait_ended(ids, logs);
        if states.iter().any(|s| s != "COMPLETED") {
            panic!("jobs {ids:?} ended as {states:?}; logs:\n{}", read_logs(logs));
        }
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        let out = cluster_sh(&["stop", self.state.to_str().unwrap()]);
        if !out.status.success() {
            eprintln!("cluster.sh stop failed: {}", String::from_utf8_lossy(&out.stderr));
        }
        let _ = std::fs::remove_dir_all(&self.state);
    }
}

fn cluster_sh(args: &[&str]) -> Output {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/slurm/cluster.sh");
    Command::new(script).args(args).output().unwrap()
}

fn read_logs(dir: &Path) -> String {
    let mut logs: Vec<PathBuf> = std::fs::read_dir(dir).map_or(vec![], |d| d.flatten().map(|e| e.path()).collect());
    logs.sort();
    logs.iter().map(|p| format!("--- {}\n{}", p.display(), std::fs::read_to_string(p).unwrap_or_default())).collect()
}

/// "... array job 12 (4 tasks) and merge job 13 ..." → ("12", "13").
fn job_ids(stdout: &str) -> (String, String) {
    let after = |key: &str| {
        let rest = &stdout[stdout.find(key).unwrap_or_else(|| panic!("no `{key}` in:\n{stdout}")) + key.len()..];
        rest.split_whitespace().next().unwrap().to_string()
    };
    (after("array job "), after("merge job "))
}

/// The text of the log of merge job `id` in `logs`.
fn merge_log(logs: &Path, id: &str) -> String {
    let entries = std::fs::read_dir(logs).unwrap().flatten().map(|e| e.path());
    let log = entries.into_iter().find(|p| p.to_string_lossy().ends_with(&format!("-merge_{id}.out")));
    std::fs::read_to_string(log.unwrap_or_else(|| panic!("no log of merge job {id}:\n{}", read_logs(logs)))).unwrap()
}

#[test]
fn array_job_and_merge_on_a_real_cluster_equal_a_local_run() {
    let Some(cluster) = Cluster::start() else { return };
    let dir = slurm_common::scratch("cluster");
    let study = slurm_common::write_study(&dir);
    let out = dir.join("out");
    let logs = out.join("logs");
    let scripts = out.join("slurm");
    // Shard 2 cannot write its file (a directory is in the way): its task fails with exit status 1.
    let blocked = out.join(format!("shards/{NAME}.shard-2-of-4.h5"));
    std::fs::create_dir_all(blocked.join("in_the_way")).unwrap();
    let started = Instant::now();
    let args = ["slurm", study.to_str().unwrap(), "--shards", "4", "--out", out.to_str().unwrap(), "--submit"];
    let stdout = succeeded("demsweep slurm --submit", &demsweep(&args, &[("SLURM_CONF", &cluster.conf())]));
    let (array_id, merge_id) = job_ids(&stdout);
    let mut states = cluster.wait_ended(&[&array_id], &logs);
    states.sort();
    assert_eq!(states, ["COMPLETED", "COMPLETED", "COMPLETED", "FAILED"], "one task per shard, task 2 failed");
    // The merge runs all the same: it merges the 3 other shards, names shard 2 and exits 1.
    assert_eq!(cluster.wait_ended(&[&merge_id], &logs), ["FAILED"]);
    eprintln!("4-task array job and merge done in {:.1} s", started.elapsed().as_secs_f64());
    let merge_log = merge_log(&logs, &merge_id);
    assert!(merge_log.contains("merged 6 of 8 runs from 3 of 4 shards\n"), "{merge_log}");
    assert!(merge_log.contains("error: the merge is incomplete:\n  shard 2/4: no file given\n"), "{merge_log}");
    let array_script = scripts.join("array.sbatch");
    let rerun = format!("  ARRAY=$(sbatch --parsable --array=2 {})\n", array_script.display());
    let merge_again = format!("  sbatch --dependency=afterany:$ARRAY {}\n", scripts.join("merge.sbatch").display());
    assert!(merge_log.ends_with(&format!("run them again, then merge again:\n{rerun}{merge_again}")), "{merge_log}");
    assert_eq!(summary::read(&out.join(format!("{NAME}.h5"))).unwrap().len(), 6, "what there was was merged");

    // Out of the way, the printed commands complete the study.
    std::fs::remove_dir_all(&blocked).unwrap();
    let rerun_id = cluster.sbatch(&["--array=2", array_script.to_str().unwrap()]);
    let dependency = format!("--dependency=afterany:{rerun_id}");
    let merge_again = cluster.sbatch(&[&dependency, scripts.join("merge.sbatch").to_str().unwrap()]);
    cluster.wait_completed(&[&rerun_id, &merge_again], &logs);
    let local = slurm_common::local_summary(&study, &dir.join("local"));
    assert_eq!(slurm_common::merged_summary(&out), local, "merged on the cluster vs. one machine");

    // Shard 3 lost: the merge names it; the other shards stay; re-running task 3 alone fixes it.
    let lost = out.join(format!("shards/{NAME}.shard-3-of-4.h5"));
    std::fs::remove_file(&lost).unwrap();
    let refused =
        demsweep(&["merge", dir.join("refused").to_str().unwrap(), out.join("shards").to_str().unwrap()], &[]);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(!refused.status.success() && stderr.contains("shard 3/4: no file given"), "{stderr}");
    let rerun_id = cluster.sbatch(&["--array=3", array_script.to_str().unwrap()]);
    let dependency = format!("--dependency=afterany:{rerun_id}");
    let merge_again = cluster.sbatch(&[&dependency, scripts.join("merge.sbatch").to_str().unwrap()]);
    cluster.wait_completed(&[&rerun_id, &merge_again], &logs);
    assert_eq!(cluster.job_states(&rerun_id).len(), 1, "only shard 3 ran again");
    assert!(lost.is_file());
    assert_eq!(slurm_common::merged_summary(&out), local, "merged after re-running shard 3 vs. one machine");
}

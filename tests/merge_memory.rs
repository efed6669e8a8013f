//! `demsweep merge` streams: its peak memory stays at a few runs, below the data of one shard
//! (which it used to read whole); a sweep's peak grows by a few kilobytes a run. Linux only:
//! the peak is the child process's `ru_maxrss`.

#![cfg(target_os = "linux")]

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// 128 runs of 300 disks recording 200 frames each (3.4 MB of data a run): shards of about 220 MB of
/// data (compressed to files of about 25 MB).
const STUDY: &str = r#"name = "merge_memory"
[scene]
run.duration = 0.02
run.frame_interval = 1e-4
[sweep]
replicates = 128
"#;

fn demsweep() -> Command {
    Command::new(env!("CARGO_BIN_EXE_demsweep"))
}

/// Runs `command` and returns its exit status and peak resident memory (bytes).
#[allow(unsafe_code)]
fn peak_memory(command: &mut Command) -> (i32, u64) {
    #[allow(clippy::zombie_processes)] // reaped by wait4 below, which also gives its resource usage
    let child = command.stdout(Stdio::null()).spawn().unwrap();
    let (mut status, mut usage) = (0, std::mem::MaybeUninit::<libc::rusage>::uninit());
    // SAFETY: the pid is our unwaited child; `status` and `usage` are valid places for wait4 to fill.
    let pid = unsafe { libc::wait4(child.id() as i32, &mut status, 0, usage.as_mut_ptr()) };
    assert_eq!(pid, child.id() as i32);
    // SAFETY: wait4 returned the child, so it filled `usage`.
    let usage = unsafe { usage.assume_init() };
    (libc::WEXITSTATUS(status), usage.ru_maxrss as u64 * 1024)
}

fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The bytes of data the datasets under `group` hold, decoded (what reading them whole costs).
fn data_bytes(group: &hdf5_pure::Group) -> u64 {
    let datasets = group
        .iter_datasets()
        .unwrap()
        .map(|(_, d)| d.shape().unwrap().iter().product::<u64>() * u64::from(d.datatype().unwrap().type_size()));
    let groups = group.iter_groups().unwrap().map(|(_, g)| data_bytes(&g));
    datasets.chain(groups).sum()
}

#[test]
fn merge_memory_stays_below_one_shard() {
    // The shards are written by child processes, so that this process stays small: a child's peak
    // memory starts from its parent's.
    let dir = scratch("merge_memory");
    let study = dir.join("merge_memory.toml");
    std::fs::write(&study, STUDY).unwrap();
    let shards = dir.join("shards");
    for shard in ["1/2", "2/2"] {
        let out = demsweep()
            .args(["run", study.to_str().unwrap(), "--shard", shard, "--out", shards.to_str().unwrap()])
            .args(["--progress", "quiet"])
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    }
    let shard = |k: usize| hdf5_pure::File::open(shards.join(format!("merge_memory.shard-{k}-of-2.h5"))).unwrap();
    let largest = (1..=2).map(|k| data_bytes(&shard(k).root())).max().unwrap();
    let merged = dir.join("merged");
    let (status, peak) = peak_memory(demsweep().args(["merge", merged.to_str().unwrap(), shards.to_str().unwrap()]));
    assert_eq!(status, 0);
    eprintln!("merge peak memory {:.1} MB, largest shard's data {:.1} MB", peak as f64 / 1e6, largest as f64 / 1e6);
    assert!(peak < largest, "merge peak memory {peak} bytes, largest shard's data {largest} bytes");
}

/// The peak memory of `demsweep run` on `runs` runs of one disk for 10 steps (bytes).
fn peak_of_a_tiny_sweep(dir: &Path, runs: usize) -> u64 {
    let study = dir.join(format!("tiny{runs}.toml"));
    let text = format!(
        "name = \"tiny{runs}\"\n[scene]\nparticles.count = 1\nrun.duration = 1e-3\nintegrator.time_step = 1e-4\n\
         [sweep]\n\"material.friction\" = {{ linear = [0.0, 1.0], steps = {runs} }}\n"
    );
    std::fs::write(&study, text).unwrap();
    let args = ["run", study.to_str().unwrap(), "--out", dir.to_str().unwrap(), "--progress", "quiet"];
    let (status, peak) = peak_memory(demsweep().args(args));
    assert_eq!(status, 0);
    peak
}

#[test]
fn a_sweep_holds_a_few_kilobytes_per_run() {
    // Each finished run used to stay in memory until the end (about 40 KB a run: 3.3 GB at 80 000
    // runs). What grows now is the rows the statistics need and the closing report's tables.
    let dir = scratch("sweep_memory");
    let (small, large) = (peak_of_a_tiny_sweep(&dir, 1000), peak_of_a_tiny_sweep(&dir, 4000));
    let per_run = large.saturating_sub(small) / 3000;
    eprintln!("sweep peak memory {:.1} MB at 1000 runs, {:.1} MB at 4000", small as f64 / 1e6, large as f64 / 1e6);
    assert!(per_run < 15_000, "{per_run} bytes of peak memory per run");
}

//! `demsweep slurm` without a cluster: the written scripts, run by hand as Slurm would run them,
//! give the one-machine result; submitting without sbatch and too many shards are refused clearly.

mod slurm_common;

use std::path::Path;
use std::process::Command;

use slurm_common::{NAME, demsweep, succeeded};

/// Runs a batch script with bash, as one Slurm task (`task` sets SLURM_ARRAY_TASK_ID).
fn run_script(script: &Path, task: Option<usize>) {
    let mut command = Command::new("bash");
    command.arg(script);
    if let Some(k) = task {
        command.env("SLURM_ARRAY_TASK_ID", k.to_string());
    }
    succeeded(&format!("{} (task {task:?})", script.display()), &command.output().unwrap());
}

#[test]
fn scripts_run_as_slurm_would_give_the_one_machine_result() {
    let dir = slurm_common::scratch("scripts");
    let study = slurm_common::write_study(&dir);
    let out = dir.join("out");
    let stdout = succeeded(
        "demsweep slurm",
        &demsweep(&["slurm", study.to_str().unwrap(), "--shards", "3", "--out", out.to_str().unwrap()], &[]),
    );
    let (array, merge) = (out.join("slurm/array.sbatch"), out.join("slurm/merge.sbatch"));
    assert!(stdout.contains(&format!("sbatch --dependency=afterany:$ARRAY {}", merge.display())), "{stdout}");
    assert!(out.join("logs").is_dir(), "Slurm needs the log directory to exist before the jobs start");

    for k in 1..=3 {
        run_script(&array, Some(k));
    }
    assert!(out.join(format!("shards/{NAME}.shard-2-of-3.h5")).is_file());
    run_script(&merge, None);
    let local = slurm_common::local_summary(&study, &dir.join("local"));
    assert_eq!(slurm_common::merged_summary(&out), local);

    // A task run again resumes its complete shard (nothing to do) and the merge replaces its result.
    run_script(&array, Some(2));
    run_script(&merge, None);
    assert_eq!(slurm_common::merged_summary(&out), local);
}

#[test]
fn submitting_without_sbatch_or_with_too_many_shards_is_refused() {
    let dir = slurm_common::scratch("refusals");
    let study = slurm_common::write_study(&dir);
    let out = dir.join("out");
    let (study, out_arg) = (study.to_str().unwrap(), out.to_str().unwrap());
    let empty_path = dir.join("empty_bin");
    std::fs::create_dir_all(&empty_path).unwrap();

    let no_sbatch =
        demsweep(&["slurm", study, "--shards", "2", "--out", out_arg, "--submit"], &[("PATH", &empty_path)]);
    let stderr = String::from_utf8_lossy(&no_sbatch.stderr);
    assert_eq!(no_sbatch.status.code(), Some(1));
    assert!(stderr.contains("`sbatch` is not on PATH") && stderr.contains("array.sbatch"), "{stderr}");
    assert!(out.join("slurm/array.sbatch").is_file(), "the scripts are written even when they cannot be submitted");

    let too_many = demsweep(&["slurm", study, "--shards", "9", "--out", out_arg], &[]);
    let stderr = String::from_utf8_lossy(&too_many.stderr);
    assert_eq!(too_many.status.code(), Some(1));
    assert!(stderr.contains("--shards 9: the study has only 8 runs"), "{stderr}");
}

/// Runs `command`, whose program may be a binary copied a moment ago: while another test thread
/// forks, its child holds the copy's write handle open until it execs, and running the copy fails with
/// "text file busy" (ETXTBSY) for that moment; the run is tried again.
fn run_copied(command: &mut Command) -> std::process::Output {
    for _ in 0..100 {
        match command.output() {
            Err(e) if e.kind() == std::io::ErrorKind::ExecutableFileBusy => {
                std::thread::sleep(std::time::Duration::from_millis(50))
            }
            result => return result.unwrap(),
        }
    }
    command.output().unwrap()
}

#[test]
fn the_jobs_run_the_demsweep_that_wrote_them_and_a_build_folder_binary_is_warned_about() {
    let dir = slurm_common::scratch("which_binary");
    let study = slurm_common::write_study(&dir);
    let (study, out) = (study.to_str().unwrap(), dir.join("out"));
    let written = |demsweep: &Path| {
        let args = ["slurm", study, "--shards", "2", "--out", out.to_str().unwrap()];
        let out = run_copied(Command::new(demsweep).args(args));
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let script = std::fs::read_to_string(dir.join("out/slurm/array.sbatch")).unwrap();
        (script, String::from_utf8_lossy(&out.stderr).into_owned())
    };
    let build = Path::new(env!("CARGO_BIN_EXE_demsweep"));
    let (script, stderr) = written(build);
    assert!(script.contains(&format!("exec {} run", build.display())), "{script}");
    assert!(
        stderr.contains("a cargo build folder's binary") && stderr.contains("cargo install --locked --path ."),
        "{stderr}"
    );

    let installed = dir.join("bin/demsweep");
    std::fs::create_dir_all(installed.parent().unwrap()).unwrap();
    std::fs::copy(build, &installed).unwrap();
    let (script, stderr) = written(&installed);
    assert!(script.contains(&format!("exec {} run", installed.display())), "{script}");
    assert!(stderr.is_empty(), "{stderr}");
}

//! Checkpoints mid-run: a run resumed from its saved state ends with the bits of the run never
//! stopped (stages, histories, frames and the final state), whether the state was saved at a
//! sample or when the run was stopped between two samples.

use std::sync::atomic::{AtomicBool, Ordering};

mod runner_common;

use demsweep::physics::Threads;
use demsweep::physics::config::{PlacementKind, SceneConfig, StageConfig};
use demsweep::physics::contact::HertzMindlin;
use demsweep::physics::placement;
use demsweep::physics::record::{RunRecord, RunStatus};
use demsweep::physics::run_state::{Checkpoints, NoCheckpoints, RunState};
use demsweep::physics::simulation::{Control, Simulation};

/// 200 polydisperse disks poured into a box, a damped fill stage first, frames on the way.
fn deposition() -> SceneConfig {
    let mut s = SceneConfig::default();
    (s.particles.count, s.particles.radius, s.particles.radius_max) = (200, 0.004, Some(0.008));
    (s.domain.width, s.domain.height) = (0.25, 0.4);
    s.material.restitution = Some(0.4);
    s.integrator.time_step = Some(2e-5);
    (s.run.duration, s.run.stop_at_settle) = (0.5, false);
    s.run.frame_times = vec![0.1, 0.2001, 0.45];
    s.placement.seed = 11;
    s.stages = vec![stage("name = \"fill\"\nuntil.time = 0.15\ndamping.local = 0.3\nintegrator.time_step = 1e-5\n")];
    s
}

fn stage(toml_text: &str) -> StageConfig {
    toml::from_str(toml_text).expect("a stage")
}

fn simulation(scene: &SceneConfig, threads: usize) -> Simulation<HertzMindlin> {
    let disks = placement::generate(scene).expect("placement");
    let mut sim = Simulation::new(scene, &disks);
    sim.set_threads(Threads { count: threads, min_disks: 0 });
    sim
}

/// Keeps the state of the `at`-th sample and the one handed over when the run stops.
#[derive(Default)]
struct Keep {
    samples: u64,
    at: u64,
    kept: Vec<RunState>,
}

impl Checkpoints for Keep {
    fn due(&mut self, _: u64) -> bool {
        self.samples += 1;
        self.samples == self.at
    }
    fn save(&mut self, state: RunState) {
        self.kept.push(state);
    }
}

/// The record as text: every number written to the bit (Debug writes floats round-trip).
fn text(record: &RunRecord) -> String {
    format!("{record:?}")
}

fn resumed(scene: &SceneConfig, state: &RunState, threads: usize) -> RunRecord {
    let mut sim = simulation(scene, threads);
    let from = sim.resume(state).expect("the state reads back");
    sim.run_resumable(Some(from), &AtomicBool::new(false), &mut |_| Control::Continue, &mut NoCheckpoints)
}

#[test]
fn a_run_resumed_from_a_checkpoint_is_bit_identical_to_the_straight_run() {
    let scene = deposition();
    let straight = simulation(&scene, 1).run(&mut |_| Control::Continue);
    assert_eq!(straight.frames.len(), 3);
    assert!(straight.stage_ends[0].time.is_some(), "the fill stage ended");
    // States saved at a sample in the fill stage and one in the physical stage, then the run that
    // saved the second stopped by its observer at a later sample.
    for (at, threads) in [(3, 1), (40, 2)] {
        let mut keep = Keep { at, ..Keep::default() };
        let mut samples = 0;
        let mut stop_late = |_: &_| {
            samples += 1;
            if samples == at + 5 { Control::Stop } else { Control::Continue }
        };
        let sim = simulation(&scene, threads);
        let stopped = sim.run_resumable(None, &AtomicBool::new(false), &mut stop_late, &mut keep);
        assert_eq!(stopped.status, RunStatus::Interrupted);
        assert_eq!(keep.kept.len(), 2, "one state at sample {at}, one when stopped");
        assert!(keep.kept[0].step < keep.kept[1].step);
        for state in &keep.kept {
            assert_eq!(text(&resumed(&scene, state, 1)), text(&straight), "from step {}", state.step);
        }
        assert_eq!(text(&resumed(&scene, &keep.kept[1], 2)), text(&straight), "on two threads");
    }
}

#[test]
fn a_run_stopped_between_samples_resumes_to_the_same_bits() {
    let mut scene = deposition();
    // Samples far apart: a stop lands between two of them.
    scene.run.sample_interval = 0.05;
    let straight = simulation(&scene, 1).run(&mut |_| Control::Continue);
    let stop = AtomicBool::new(false);
    let mut keep = Keep::default();
    let mut samples = 0;
    let mut late = |_: &_| {
        samples += 1;
        if samples == 4 {
            // Read after the next step: the run stops one step past this sample.
            stop.store(true, Ordering::Relaxed);
        }
        Control::Continue
    };
    let stopped = simulation(&scene, 1).run_resumable(None, &stop, &mut late, &mut keep);
    assert_eq!(stopped.status, RunStatus::Interrupted);
    let state = &keep.kept[0];
    assert!(state.step % 2500 != 0, "step {} is between samples", state.step);
    assert_eq!(text(&resumed(&scene, state, 1)), text(&straight));
}

#[test]
fn a_pour_resumed_mid_insertion_is_bit_identical_to_the_straight_run() {
    let mut scene = SceneConfig::default();
    (scene.particles.count, scene.domain.width, scene.domain.height) = (60, 0.2, 0.3);
    scene.placement.kind = PlacementKind::Pour;
    (scene.placement.seed, scene.placement.pour.rate) = (5, Some(300.0));
    (scene.placement.pour.velocity, scene.placement.pour.velocity_spread) = ([0.0, -0.5], 0.1);
    (scene.run.duration, scene.run.stop_at_settle) = (0.5, false);
    let straight = simulation(&scene, 1).run(&mut |_| Control::Continue);
    let pour = straight.pour.expect("a pour");
    assert_eq!(pour.inserted + pour.refused, 60);
    // Saved while disks are still coming: part of the stream inserted, its random draws half used.
    let mut keep = Keep { at: 20, ..Keep::default() };
    let mut samples = 0;
    let mut stop_late = |_: &_| {
        samples += 1;
        if samples == 25 { Control::Stop } else { Control::Continue }
    };
    simulation(&scene, 1).run_resumable(None, &AtomicBool::new(false), &mut stop_late, &mut keep);
    assert_eq!(keep.kept.len(), 2);
    for state in &keep.kept {
        assert!(state.time < 60.0 / 300.0, "saved at {} s, before the last disk", state.time);
        assert_eq!(text(&resumed(&scene, state, 1)), text(&straight), "from step {}", state.step);
    }
}

#[test]
fn a_state_of_another_scene_or_damaged_is_refused_naming_the_piece() {
    let scene = deposition();
    let mut keep = Keep { at: 2, ..Keep::default() };
    let mut first = |_: &_| Control::Continue;
    let mut short = scene.clone();
    short.run.duration = 0.01;
    simulation(&short, 1).run_resumable(None, &AtomicBool::new(false), &mut first, &mut keep);
    let state = keep.kept.pop().expect("a state");
    let mut fewer = scene.clone();
    fewer.particles.count = 150;
    let error = simulation(&fewer, 1).resume(&state).err().expect("refused");
    assert_eq!(error.piece, "particles", "{error}");
    let cut = RunState { bytes: state.bytes[..state.bytes.len() / 2].to_vec(), ..state.clone() };
    let error = simulation(&scene, 1).resume(&cut).err().expect("refused");
    assert!(error.to_string().starts_with("run state cut short in "), "{error}");
}

#[test]
fn a_checkpoint_file_reads_back_only_for_its_own_run_and_physics() {
    use demsweep::output::checkpoint::{self, CheckpointError};
    let dir = std::env::temp_dir().join(format!("demsweep-checkpoint-{}", std::process::id()));
    let results = dir.join("study.h5");
    let path = checkpoint::checkpoint_path(&results, "r0003");
    assert_eq!(path, dir.join("study.checkpoints").join("r0003.checkpoint"));
    let state = RunState { step: 12, time: 0.5, bytes: vec![1, 2, 3, 250] };
    checkpoint::write(&path, "run three", &state).expect("written");
    assert_eq!(checkpoint::read(&path, "run three").expect("read"), Some(state.clone()));
    let other = checkpoint::read(&path, "run four").unwrap_err();
    assert_eq!(other.error, CheckpointError::OtherRun { found: "run three".into() });
    assert!(other.to_string().ends_with("r0003.checkpoint: checkpoint of another run (run three)"), "{other}");
    let mut bytes = std::fs::read(&path).unwrap();
    let last = bytes.len() - 6;
    bytes[last] ^= 1;
    std::fs::write(&path, &bytes).unwrap();
    assert_eq!(checkpoint::read(&path, "run three").unwrap_err().error, CheckpointError::Damaged);
    bytes[8] = 9;
    std::fs::write(&path, &bytes).unwrap();
    assert_eq!(checkpoint::read(&path, "run three").unwrap_err().error, CheckpointError::Format { found: 9 });
    // Another file under the name is not removed; the checkpoint is, with its folder.
    let stranger = checkpoint::checkpoint_path(&results, "r0004");
    std::fs::write(&stranger, b"notes").unwrap();
    checkpoint::remove(&stranger).unwrap();
    assert!(stranger.exists());
    std::fs::remove_file(&stranger).unwrap();
    checkpoint::write(&path, "run three", &state).expect("written");
    checkpoint::remove(&path).unwrap();
    assert!(!path.exists() && !path.parent().unwrap().exists());
    assert_eq!(checkpoint::read(&path, "run three").unwrap(), None);
    std::fs::remove_dir_all(&dir).ok();
}

mod cli {
    use std::path::{Path, PathBuf};
    use std::process::{Child, Command, Stdio};
    use std::time::{Duration, Instant};

    use super::runner_common;
    use demsweep::output::{reader, stored, summary};

    /// Two runs of 300 disks for 3 s with a fill stage of another time step and frames: about a
    /// second each on a quiet machine, long enough to be stopped midway (at 0.8 s, a run ended
    /// within the 150 ms between its first checkpoint and the stop one time in three).
    const STUDY: &str = r#"name = "ckpt"
[scene]
particles.count = 300
particles.radius = 0.003
domain.width = 0.2
domain.height = 0.3
integrator.time_step = 2e-5
run.duration = 3.0
run.stop_at_settle = false
run.frame_times = [0.1, 0.5]

[[scene.stages]]
name = "fill"
until.time = 0.1
damping.local = 0.3
integrator.time_step = 1e-5

[sweep]
"material.restitution" = [0.3, 0.6]
"#;

    fn start(dir: &Path, out: &str, extra: &[&str]) -> Child {
        Command::new(env!("CARGO_BIN_EXE_demsweep"))
            .args(["run", "ckpt.toml", "--out", out, "--jobs", "2", "--progress", "quiet"])
            .args(extra)
            .current_dir(dir)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    }

    /// Every stored value of every run, numbers as round-trip text (timing columns aside).
    fn contents(results: &Path) -> String {
        let table = summary::read(results).unwrap();
        let file = reader::open(results).unwrap();
        let rows = reader::rows(&file, results).unwrap();
        let runs: Vec<String> = rows
            .iter()
            .map(|row| {
                let run = stored::read_run(&file, results, row).unwrap();
                format!("{:?}{:?}{:?}", run.history, run.final_state, run.frames)
            })
            .collect();
        format!("{:?}\n{runs:?}", table.without_timing())
    }

    /// Starts the study with checkpoints every 0.1 s, waits for one, then stops it with `stop`;
    /// resumes it and returns its contents, the checkpoints having gone.
    fn stopped_then_resumed(test: &str, stop: impl FnOnce(&mut Child)) -> (String, String) {
        let dir = runner_common::scratch(test);
        std::fs::write(dir.join("ckpt.toml"), STUDY).unwrap();
        let straight = start(&dir, "straight", &["--checkpoint-every", "off"]).wait_with_output().unwrap();
        assert_eq!(straight.status.code(), Some(0), "{}", String::from_utf8_lossy(&straight.stderr));
        let mut child = start(&dir, "stopped", &["--checkpoint-every", "0.1s"]);
        let saved = dir.join("stopped/ckpt.checkpoints");
        let waited = Instant::now();
        while !std::fs::read_dir(&saved).is_ok_and(|mut d| d.next().is_some()) {
            assert!(child.try_wait().unwrap().is_none(), "the sweep ended before a checkpoint");
            assert!(waited.elapsed() < Duration::from_secs(120), "no checkpoint within two minutes");
            std::thread::sleep(Duration::from_millis(5));
        }
        std::thread::sleep(Duration::from_millis(150));
        stop(&mut child);
        child.wait().unwrap();
        let files: Vec<PathBuf> = std::fs::read_dir(&saved).unwrap().map(|e| e.unwrap().path()).collect();
        assert!(!files.is_empty(), "checkpoints of the runs in progress are kept");
        let resumed = start(&dir, "stopped", &["--resume"]).wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&resumed.stderr);
        assert_eq!(resumed.status.code(), Some(0), "{stderr}");
        assert!(!stderr.contains("afresh"), "every checkpoint read back: {stderr}");
        let continued = stderr.matches("note: the run continues from ").count();
        assert!((1..=2).contains(&continued), "{stderr}");
        assert!(!saved.exists(), "the checkpoints of finished runs are removed");
        (contents(&dir.join("straight/ckpt.h5")), contents(&dir.join("stopped/ckpt.h5")))
    }

    #[test]
    fn killed_with_sigkill_mid_run_then_resumed_from_its_checkpoint_stores_the_same_bits() {
        let (straight, resumed) = stopped_then_resumed("checkpoint_kill", |child| child.kill().unwrap());
        assert_eq!(resumed, straight);
    }

    #[test]
    fn stopped_by_sigterm_saves_its_runs_in_progress_and_resumes_to_the_same_bits() {
        let terminate = |child: &mut Child| {
            // SAFETY: kill(2) on the id of a child process of this test.
            assert_eq!(unsafe { libc::kill(child.id() as i32, libc::SIGTERM) }, 0);
        };
        let (straight, resumed) = stopped_then_resumed("checkpoint_term", terminate);
        assert_eq!(resumed, straight);
    }

    /// A short run (r0000) beside a run about seven times as long (r0001), no frames.
    const SHORT_AND_LONG: &str = r#"name = "ckpt"
[scene]
particles.count = 300
particles.radius = 0.003
domain.width = 0.2
domain.height = 0.3
integrator.time_step = 2e-5
run.stop_at_settle = false
[output]
frames = false
[sweep]
"run.duration" = [0.6, 4.0]
"#;

    #[test]
    fn a_runs_checkpoint_goes_once_the_run_is_stored_while_the_sweep_goes_on_and_other_files_stay() {
        let dir = runner_common::scratch("checkpoint_stored");
        std::fs::write(dir.join("ckpt.toml"), SHORT_AND_LONG).unwrap();
        let saved = dir.join("out/ckpt.checkpoints");
        std::fs::create_dir_all(&saved).unwrap();
        std::fs::write(saved.join("notes.txt"), "mine").unwrap();
        // Commits every 0.2 s store the short run while the long one goes on, however fast the machine.
        let mut child = start(&dir, "out", &["--checkpoint-every", "0.1s", "--commit-interval", "0.2"]);
        let (short, long) = (saved.join("r0000.checkpoint"), saved.join("r0001.checkpoint"));
        let waited = Instant::now();
        let mut wait_for = |what: &str, done: &dyn Fn() -> bool| {
            while !done() {
                assert!(child.try_wait().unwrap().is_none(), "the sweep ended before {what}");
                assert!(waited.elapsed() < Duration::from_secs(120), "not within two minutes: {what}");
                std::thread::sleep(Duration::from_millis(5));
            }
        };
        wait_for("the short run's checkpoint", &|| short.exists());
        wait_for("the short run's checkpoint went", &|| !short.exists());
        assert!(child.try_wait().unwrap().is_none() && long.exists(), "the long run goes on, with its checkpoint");
        let out = child.wait_with_output().unwrap();
        assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
        let left: Vec<_> = std::fs::read_dir(&saved).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(left, ["notes.txt"], "only the checkpoints go");
    }

    #[test]
    fn a_bad_interval_is_refused_naming_the_flag() {
        let dir = runner_common::scratch("checkpoint_flag");
        std::fs::write(dir.join("ckpt.toml"), STUDY).unwrap();
        for (value, reason) in [("10", "needs a unit"), ("-1m", "must be > 0"), ("xm", "not a number")] {
            let flag = format!("--checkpoint-every={value}");
            let out = start(&dir, "out", &[&flag]).wait_with_output().unwrap();
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{stderr}");
            assert!(stderr.contains("--checkpoint-every") && stderr.contains(reason), "{stderr}");
        }
    }
}

/// Times checkpoints of 10 000 and 40 000 disks (encoding the state, writing the file): run by
/// hand for results/bench/checkpoint.md (`--ignored --nocapture`); asserts nothing about time.
#[test]
#[ignore]
fn measure_checkpoint_cost() {
    use demsweep::output::checkpoint;
    use std::time::{Duration, Instant};
    struct Timed {
        asked: Option<Instant>,
        encode: Vec<Duration>,
        write: Vec<Duration>,
        path: std::path::PathBuf,
        bytes: usize,
    }
    impl Checkpoints for Timed {
        fn due(&mut self, step: u64) -> bool {
            self.asked = (step > 0).then(Instant::now);
            self.asked.is_some()
        }
        fn save(&mut self, state: RunState) {
            if let Some(asked) = self.asked.take() {
                self.encode.push(asked.elapsed());
                let started = Instant::now();
                checkpoint::write(&self.path, "measure", &state).unwrap();
                self.write.push(started.elapsed());
                self.bytes = std::fs::metadata(&self.path).unwrap().len() as usize;
            }
        }
    }
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("checkpoint_measure");
    for count in [10_000, 40_000] {
        let mut scene = SceneConfig::default();
        (scene.particles.count, scene.particles.radius) = (count, 0.002);
        let side = (count as f64).sqrt() * 0.0065;
        (scene.domain.width, scene.domain.height) = (side, 2.0 * side);
        scene.integrator.time_step = Some(1e-5);
        (scene.run.sample_interval, scene.run.duration, scene.run.stop_at_settle) = (1e-4, 1.2e-3, false);
        let path = dir.join(format!("{count}.checkpoint"));
        let mut timed = Timed { asked: None, encode: Vec::new(), write: Vec::new(), path, bytes: 0 };
        let started = Instant::now();
        let sim = simulation(&scene, 1);
        let built = started.elapsed();
        sim.run_resumable(None, &AtomicBool::new(false), &mut |_| Control::Continue, &mut timed);
        let median = |v: &mut Vec<Duration>| {
            v.sort();
            v[v.len() / 2].as_secs_f64() * 1e3
        };
        println!(
            "{count} disks: {} checkpoints of {:.1} MB, median encode {:.2} ms, write {:.2} ms; built in {:.2} s, run {:.2} s",
            timed.write.len(),
            timed.bytes as f64 / 1e6,
            median(&mut timed.encode),
            median(&mut timed.write),
            built.as_secs_f64(),
            started.elapsed().as_secs_f64() - built.as_secs_f64(),
        );
    }
}

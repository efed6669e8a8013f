//! One run on several threads gives the same bits as on one: the parallel path of the step (the
//! integrator's chunks, the contact blocks, the per-disk sums, the neighbour search) is taken here on
//! scenes far below its size threshold, which the tests lower, so that an order-dependent sum would
//! show as a difference in the last bits of the final state.

use std::path::Path;
use std::process::Command;
use std::sync::atomic::AtomicBool;

use demsweep::output::{history, reader, stored};
use demsweep::physics::config::{ContactLawKind, IntegratorKind, SceneConfig};
use demsweep::physics::record::RunRecord;
use demsweep::physics::simulation::Control;
use demsweep::physics::{Threads, run_scene_on};

/// A deposition of `count` disks over `duration` s in a box widened with them, with friction.
fn scene(count: usize, duration: f64) -> SceneConfig {
    let mut s = SceneConfig::default();
    s.particles.count = count;
    s.domain.width = 0.4 * count as f64 / 300.0;
    s.material.restitution = Some(0.5);
    s.material.friction = 0.5;
    s.integrator.contact_time_fraction = Some(0.1);
    s.run.duration = duration;
    s.run.stop_at_settle = false;
    s
}

/// Runs `scene` on a pool of `threads` threads, the parallel path from any size on.
fn run_on(scene: &SceneConfig, threads: usize) -> RunRecord {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    let given = Threads { count: threads, min_disks: 0 };
    pool.install(|| run_scene_on(scene, None, None, given, &AtomicBool::new(false), &mut |_| Control::Continue))
        .unwrap()
}

#[test]
fn periodic_pile_is_bit_identical_on_1_2_and_3_threads() {
    let mut s = scene(1100, 0.25);
    s.domain.periodic_x = true;
    let f = same_bits_on_1_2_and_3_threads(&s).final_state;
    let c = &f.contacts;
    let across = (0..c.len()).filter(|&k| {
        usize::try_from(c.second[k]).is_ok_and(|j| (f.x[j] - f.x[c.first[k] as usize]).abs() > 0.5 * s.domain.width)
    });
    assert!(across.count() > 0, "contacts across the boundary");
    assert!(c.second.iter().all(|&w| w != -2 && w != -3), "no side wall touched");
}

/// The bits of a run's final state, histories and energy balance.
fn bits(record: &RunRecord) -> Vec<u64> {
    let f = &record.final_state;
    let h = &record.history;
    let columns =
        [&f.x, &f.y, &f.vx, &f.vy, &f.omega, &f.angle, &f.contact_force, &h.kinetic_translational, &h.dissipated];
    let mut bits: Vec<u64> = columns.iter().flat_map(|c| c.iter().map(|v| v.to_bits())).collect();
    bits.push(record.energy_balance_error.to_bits());
    bits
}

/// The scene run on 1, 2 and 3 threads: bit-identical, and it had contacts, walls and spin; the
/// run on one thread.
fn same_bits_on_1_2_and_3_threads(scene: &SceneConfig) -> RunRecord {
    let one = run_on(scene, 1);
    let f = &one.final_state;
    let contacts = *one.history.contacts.last().unwrap() as usize;
    assert!(contacts > f.x.len(), "{contacts} contacts at the end of {} disks", f.x.len());
    assert!(f.omega.iter().any(|w| *w != 0.0) && f.y.iter().any(|y| *y < 0.011), "spinning disks on the floor");
    for threads in [2, 3] {
        let other = run_on(scene, threads);
        assert_eq!(other.steps, one.steps);
        assert!(bits(&other) == bits(&one), "{threads} threads differ from one");
    }
    one
}

#[test]
fn adams_bashforth_moulton_pile_is_bit_identical_on_1_2_and_3_threads() {
    // 1 600 disks: four of the integrator's 512-disk chunks, dozens of contact blocks.
    same_bits_on_1_2_and_3_threads(&scene(1600, 0.3));
}

#[test]
fn verlet_with_rolling_friction_damping_and_a_law_with_state_is_bit_identical_on_1_2_and_3_threads() {
    let mut s = scene(1100, 0.25);
    s.integrator.scheme = IntegratorKind::VelocityVerlet;
    s.material.rolling_friction = 0.05;
    s.damping.local = 0.1;
    s.contact.law = ContactLawKind::HystereticLinear;
    same_bits_on_1_2_and_3_threads(&s);
}

/// The stored final state's bits and history text of the one run of `results`.
fn stored_run(results: &Path) -> (Vec<u64>, Vec<u8>) {
    let file = reader::open(results).unwrap();
    let rows = reader::rows(&file, results).unwrap();
    let state = stored::read_run(&file, results, &rows[0]).unwrap().final_state.unwrap();
    let bits = [&state.x, &state.y, &state.vx, &state.vy, &state.omega]
        .iter()
        .flat_map(|c| c.iter().map(|v| v.to_bits()))
        .collect();
    let mut text = Vec::new();
    history::to_csv(results, &rows[0].id, &mut text).unwrap();
    (bits, text)
}

#[test]
fn one_run_through_the_cli_gives_the_same_results_with_jobs_1_and_2() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("engine_threads_cli");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let study = dir.join("one_pile.toml");
    let text = "name = \"one_pile\"\n[scene]\nparticles.count = 1100\ndomain.width = 1.5\nmaterial.restitution = 0.5\n\
                material.friction = 0.5\nintegrator.contact_time_fraction = 0.1\nrun.duration = 0.25\nrun.stop_at_settle = false\n";
    std::fs::write(&study, text).unwrap();
    let run = |jobs: &str| {
        let out = dir.join(format!("jobs_{jobs}"));
        let done = Command::new(env!("CARGO_BIN_EXE_demsweep"))
            .args([
                "run",
                study.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
                "--jobs",
                jobs,
                "--progress",
                "quiet",
            ])
            .env("DEMSWEEP_PARALLEL_MIN_DISKS", "1")
            .output()
            .unwrap();
        assert!(done.status.success(), "{}", String::from_utf8_lossy(&done.stderr));
        stored_run(&out.join("one_pile.h5"))
    };
    let (one, two) = (run("1"), run("2"));
    assert!(one.1.len() > 1000 && one.0.len() == 5 * 1100);
    assert!(one == two, "--jobs 1 and --jobs 2 stored different bits");
    let bad = Command::new(env!("CARGO_BIN_EXE_demsweep"))
        .args(["run", study.to_str().unwrap(), "--out", dir.join("bad").to_str().unwrap()])
        .env("DEMSWEEP_PARALLEL_MIN_DISKS", "many")
        .output()
        .unwrap();
    let message = String::from_utf8_lossy(&bad.stderr);
    assert!(
        !bad.status.success() && message.contains("DEMSWEEP_PARALLEL_MIN_DISKS") && message.contains("\"many\""),
        "{message}"
    );
}

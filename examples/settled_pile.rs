//! Engine cost in the settled state, where every disk has contacts: the reference deposition at N
//! disks (box widened with N) is run to `settle` seconds once and its state cached in the build
//! folder this example was built into (`target/`, or `$CARGO_TARGET_DIR`);
//! then `steps` steps are timed from that state, best of 7.
//!
//! `cargo run --release --example settled_pile -- N SETTLE STEPS [FRICTION]`, e.g. `300 0.5 1000`
//! (friction μ of disks and walls, default 0.5; 0: no tangential forces and no rotation). Under
//! `valgrind --tool=callgrind` (after one plain run has cached the state) it gives an instruction
//! count that, unlike a time, does not drift with what else the machine is doing.

use std::time::Instant;

use demsweep::physics::config::SceneConfig;
use demsweep::physics::contact::HertzMindlin;
use demsweep::physics::particles::InitialDisk;
use demsweep::physics::simulation::Simulation;

fn scene(n: usize, friction: f64) -> SceneConfig {
    let mut s = SceneConfig::default();
    s.material.restitution = Some(0.5);
    s.material.friction = friction;
    s.integrator.time_step = Some(1e-5);
    s.particles.count = n;
    s.domain.width = 0.4 * n as f64 / 300.0;
    s
}

/// The build folder this example runs from: `<target>/release/examples/settled_pile`.
fn build_folder() -> std::path::PathBuf {
    let exe = std::env::current_exe().expect("this executable's path");
    exe.ancestors().nth(3).expect("built in <target>/<profile>/examples/").to_path_buf()
}

/// The state after `settle` seconds, from the cache or computed (and cached, bit-exact).
fn settled(s: &SceneConfig, settle: f64) -> Vec<InitialDisk> {
    let (n, friction) = (s.particles.count, s.material.friction);
    let name = if friction == 0.5 { format!("{n}_{settle}") } else { format!("{n}_{settle}_{friction}") };
    let path = build_folder().join(format!("settled_pile_{name}.txt"));
    if let Ok(text) = std::fs::read_to_string(&path) {
        return text
            .lines()
            .map(|line| {
                let v: Vec<f64> = line.split(' ').map(|b| f64::from_bits(b.parse().expect("cached bits"))).collect();
                InitialDisk { x: v[0], y: v[1], r: v[2], vx: v[3], vy: v[4], omega: v[5], ..Default::default() }
            })
            .collect();
    }
    let disks = demsweep::physics::placement::generate(s).expect("placement");
    let mut sim = Simulation::<HertzMindlin>::new(s, &disks);
    for _ in 0..(settle / s.integrator.fixed_time_step().unwrap_or_default()).round() as u64 {
        sim.advance(false);
    }
    // The cache keeps no angles: they start at zero whether read back or computed.
    let state: Vec<InitialDisk> =
        sim.snapshot().initial_disks().into_iter().map(|d| InitialDisk { angle: 0.0, ..d }).collect();
    let text: String = state
        .iter()
        .map(|d| {
            format!(
                "{} {} {} {} {} {}\n",
                d.x.to_bits(),
                d.y.to_bits(),
                d.r.to_bits(),
                d.vx.to_bits(),
                d.vy.to_bits(),
                d.omega.to_bits()
            )
        })
        .collect();
    std::fs::write(&path, text).expect("cache the settled state");
    state
}

fn main() {
    let args: Vec<f64> = std::env::args().skip(1).map(|a| a.parse().expect("N SETTLE STEPS [FRICTION]")).collect();
    let (n, settle, steps, friction) = match args[..] {
        [n, settle, steps] => (n, settle, steps, 0.5),
        [n, settle, steps, friction] => (n, settle, steps, friction),
        _ => panic!("usage: settled_pile N SETTLE STEPS [FRICTION]"),
    };
    let s = scene(n as usize, friction);
    let mut sim = Simulation::<HertzMindlin>::new(&s, &settled(&s, settle));
    let mut best = f64::INFINITY;
    for _ in 0..7 {
        let start = Instant::now();
        for _ in 0..steps as u64 {
            sim.advance(false);
        }
        best = best.min(start.elapsed().as_secs_f64() * 1e9 / (n * steps));
    }
    println!("N = {n}, μ = {friction}, at {settle} s: {best:.1} ns/particle-step (best of 7 x {steps} steps)");
}

use demsweep::physics::config::SceneConfig;
use demsweep::physics::simulation::{Control, run_scene};
fn main() {
    let n: usize = std::env::args().nth(1).unwrap().parse().unwrap();
    let dur: f64 = std::env::args().nth(2).unwrap().parse().unwrap();
    let mut s = SceneConfig::default();
    s.material.restitution = Some(0.5);
    s.material.friction = 0.5;
    s.integrator.time_step = 1e-5;
    s.run.duration = dur;
    s.run.stop_at_settle = false;
    s.particles.count = n;
    s.domain.width = 0.4 * n as f64 / 300.0;
    let t = std::time::Instant::now();
    let rec = run_scene(&s, None, &mut |_| Control::Continue).unwrap();
    println!("N={n} {:.1} ns/particle-step", t.elapsed().as_secs_f64() * 1e9 / (n as f64 * rec.steps as f64));
}

//! The tiny tune file shared by the tune tests.

/// 30 disks falling 15 cm (about 30-60 ms of computing per run): two levers, one kept metric; the
/// tune is named `tiny_tune`.
pub const TUNE: &str = r#"name = "tiny_tune"
[scene]
particles.count = 30
particles.radius = 0.005
domain.width = 0.1
domain.height = 0.15
material.youngs_modulus = 5e10
material.restitution = 0.5
integrator.time_step = 7e-6
run.duration = 1.0
run.sample_interval = 2e-3
settle.hold_time = 0.03

[levers]
"material.restitution" = { linear = [0.2, 0.8] }
"integrator.time_step" = { log = [5e-6, 2.5e-5] }

[keep]
pile_height = 0.25

[search]
seeds = 2
max_seeds = 4
reference_seeds = 4
verify_seeds = 3
budget = 40
seed = 3
"#;

//! The disks of a pour placement as the run's estimates see them (the simulation pours them:
//! [`crate::physics::pour`]).

use crate::physics::config::SceneConfig;
use crate::physics::particles::InitialDisk;

/// The disks of a pour as the run's estimates see them (time step, stability, energy scale): every
/// radius at the top of the inlet's middle with the inlet's velocity. They overlap: they are never
/// simulated together.
pub fn reference(scene: &SceneConfig, radii: &[f64]) -> Vec<InitialDisk> {
    let largest = radii.iter().copied().fold(0.0, f64::max);
    let pour = &scene.placement.pour;
    let [x0, x1, _, y1] = pour.inlet(scene.domain.width, scene.domain.height, largest);
    let [vx, vy] = pour.velocity;
    let reference = |&r: &f64| InitialDisk { x: 0.5 * (x0 + x1), y: y1 - r, r, vx, vy, ..Default::default() };
    radii.iter().map(reference).collect()
}

//! Rolling resistance: EDEM's constant directional torque `μ0 F_n R` (spec), summed per disk by
//! the contact stage into `Particles::rolling`.

use super::particles::Particles;

/// Applies each disk's rolling resistance to its spin after the integrator's update, as the change
/// `Δω = −sign(ω) min(|ω|, M_r Δt / I)`: it can stop a spin within one step but never reverse it
/// (as a torque inside a multistep scheme it would overshoot and chatter). Returns the kinetic
/// energy removed (J).
pub(super) fn apply(p: &mut Particles, dt: f64) -> f64 {
    let mut removed = 0.0;
    for i in 0..p.len() {
        let w = p.omega[i];
        if p.rolling[i] > 0.0 && w != 0.0 {
            let slowed = (w.abs() - p.rolling[i] * p.inv_inertia[i] * dt).max(0.0).copysign(w);
            removed += 0.5 * (w * w - slowed * slowed) / p.inv_inertia[i];
            p.omega[i] = slowed;
        }
    }
    removed
}

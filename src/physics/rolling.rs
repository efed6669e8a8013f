//! Rolling resistance: EDEM's constant directional torque `μ0 F_n R` (spec), summed per disk by
//! the contact stage into `Particles::rolling`.

use std::sync::Mutex;

use super::parallel::{Split, Team};
use super::particles::Particles;

/// Disks per unit of the pass on several threads.
const DISKS_PER_UNIT: usize = 512;

/// Scratch of the pass on several threads: each run's removed energies, and per part where its
/// run starts and how many it removed.
#[derive(Debug, Default)]
pub(super) struct Removed {
    terms: Vec<f64>,
    parts: Vec<Mutex<(usize, usize)>>,
}

/// Applies each disk's rolling resistance to its spin after the integrator's update, as the change
/// `Δω = −sign(ω) min(|ω|, M_r Δt / I)`: it can stop a spin within one step but never reverse it
/// (as a torque inside a multistep scheme it would overshoot and chatter). Returns the kinetic
/// energy removed (J), summed in disk order. On a `team` of several threads the disks are shared
/// out in runs; each run keeps the energies its disks lost, in order, and they are summed run after
/// run: the same additions in the same order as on one thread, so the same bits. Clears the
/// resistances, which it reads last, for the next contact stage (in the same pass).
pub(super) fn apply(p: &mut Particles, dt: f64, team: &Team, scratch: &mut Removed) -> f64 {
    if team.parts() <= 1 {
        let mut total = 0.0;
        for i in 0..p.len() {
            if let Some(term) = slow_down(&mut p.omega[i], std::mem::take(&mut p.rolling[i]), p.inv_inertia[i], dt) {
                total += term;
            }
        }
        return total;
    }
    scratch.terms.resize(p.len(), 0.0);
    scratch.parts.resize_with(team.parts(), Mutex::default);
    for part in &mut scratch.parts {
        *part.get_mut().expect("no panic while held") = (0, 0);
    }
    let run = Spins {
        first: 0,
        omega: &mut p.omega,
        rolling: &mut p.rolling,
        inv_inertia: &p.inv_inertia,
        terms: &mut scratch.terms,
    };
    let parts = &scratch.parts;
    team.for_each_part(run, &|run: Spins<'_>, number| {
        let mut kept = 0;
        for k in 0..run.omega.len() {
            if let Some(term) =
                slow_down(&mut run.omega[k], std::mem::take(&mut run.rolling[k]), run.inv_inertia[k], dt)
            {
                run.terms[kept] = term;
                kept += 1;
            }
        }
        *parts[number].lock().expect("a slot per part") = (run.first, kept);
    });
    let mut total = 0.0;
    for part in &mut scratch.parts {
        let (first, kept) = *part.get_mut().expect("no panic while held");
        total = scratch.terms[first..first + kept].iter().fold(total, |total, term| total + term);
    }
    total
}

/// Slows spin `omega` by rolling resistance `moment` (N·m) over `dt`; returns the energy removed,
/// if there was resistance and spin.
#[inline(always)]
fn slow_down(omega: &mut f64, moment: f64, inv_inertia: f64, dt: f64) -> Option<f64> {
    let w = *omega;
    if moment > 0.0 && w != 0.0 {
        let slowed = (w.abs() - moment * inv_inertia * dt).max(0.0).copysign(w);
        *omega = slowed;
        return Some(0.5 * (w * w - slowed * slowed) / inv_inertia);
    }
    None
}

/// A run of disks (from disk `first`): spins, resistances, and room for the energies removed.
struct Spins<'a> {
    first: usize,
    omega: &'a mut [f64],
    rolling: &'a mut [f64],
    inv_inertia: &'a [f64],
    terms: &'a mut [f64],
}

impl Split for Spins<'_> {
    fn units(&self) -> usize {
        self.omega.len().div_ceil(DISKS_PER_UNIT)
    }

    fn split_at(self, at: usize) -> (Self, Self) {
        let mid = (at * DISKS_PER_UNIT).min(self.omega.len());
        let (o0, o1) = self.omega.split_at_mut(mid);
        let ((r0, r1), (i0, i1)) = (self.rolling.split_at_mut(mid), self.inv_inertia.split_at(mid));
        let (t0, t1) = self.terms.split_at_mut(mid);
        let first = Spins { first: self.first, omega: o0, rolling: r0, inv_inertia: i0, terms: t0 };
        (first, Spins { first: self.first + mid, omega: o1, rolling: r1, inv_inertia: i1, terms: t1 })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::particles::InitialDisk;
    use crate::physics::rng::Rng;

    #[test]
    fn spins_and_removed_energy_on_several_threads_are_the_bits_of_one() {
        let mut rng = Rng::new(11);
        let disks: Vec<InitialDisk> = (0..6000)
            .map(|i| InitialDisk {
                x: i as f64,
                r: 0.004 + 0.004 * rng.unit(),
                omega: if i % 5 == 0 { 0.0 } else { 200.0 * (rng.unit() - 0.5) },
                ..Default::default()
            })
            .collect();
        let mut p = Particles::new(&disks, 2500.0, 1.0);
        for (i, moment) in p.rolling.iter_mut().enumerate() {
            *moment = if i % 7 == 0 { 0.0 } else { 1e-3 * rng.unit() };
        }
        let run = |threads: usize| {
            let mut p = p.clone();
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let removed = pool.install(|| apply(&mut p, 1e-4, &Team::new(threads), &mut Removed::default()));
            assert!(p.rolling.iter().all(|&m| m == 0.0), "{threads} threads: resistances cleared for the next stage");
            (removed.to_bits(), p.omega.iter().map(|w| w.to_bits()).collect::<Vec<_>>())
        };
        let one = run(1);
        assert!(f64::from_bits(one.0) > 0.0 && one.1.iter().zip(&p.omega).any(|(w, v)| f64::from_bits(*w) != *v));
        assert_eq!(run(2), one);
        assert_eq!(run(3), one);
    }
}

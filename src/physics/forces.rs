//! Contact forces of one step: disk pairs in blocks, then disk-wall contacts.
//!
//! Disk pairs are taken in blocks of [`BLOCK`] neighbour-list candidates, each in three stages:
//! 1. **narrow phase**: which candidates touch. Their geometry is appended to a small table without
//!    a branch (whether two disks touch is unpredictable, and a mispredicted branch costs more than
//!    the test);
//! 2. **coefficients**: distance, unit normal, overlap and the law's stiffness and damping for every
//!    touching pair of the block, as one loop over contiguous arrays that the compiler vectorises.
//!    Its three square roots and one division per contact are the most expensive operations of a
//!    step, and the divide/square-root unit does two (SSE2) or four (AVX2) of them for the price of
//!    one. On x86-64 CPUs with AVX2 this loop runs in a copy compiled for AVX2; both copies do the
//!    same IEEE operations in the same order, so results are bit-identical;
//! 3. **forces**: relative velocities, the tangential spring with its Coulomb limit, and the forces
//!    and torques on both disks, pair after pair in list order, so that every sum is always added up
//!    in the same order (determinism).

use super::contact::{self, Coefficients, ContactForce, ContactLaw, ContactOptions, Kinematics, PairProperties};
use super::diagnostics::ContactTotals;
use super::material::ContactMaterial;
use super::neighbors::{NeighborPair, WallPair};
use super::particles::{Forces, State};
use super::walls::Wall;

/// Candidates per block: the block's table of touching pairs stays in the L1 cache.
const BLOCK: usize = 256;

/// What all contacts of one kind (disk-disk or disk-wall) share.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactKind {
    /// Material constants of the contact.
    pub material: ContactMaterial,
    /// Law-independent options (tension, tangential forces, μ).
    pub options: ContactOptions,
    /// Whether torques are accumulated (false when nothing can spin).
    pub rotation: bool,
    /// Time step (s), for the tangential spring.
    pub dt: f64,
}

impl ContactKind {
    fn pair_properties(&self, r_star: f64, m_star: f64) -> PairProperties {
        let m = &self.material;
        PairProperties { e_star: m.e_star, g_star: m.g_star, r_star, m_star, beta: m.beta }
    }

    /// Resolves one contact from its coefficients and relative motion, updating its `spring`.
    #[inline(always)]
    fn resolve(&self, c: &Coefficients, k: &Kinematics, spring: &mut f64) -> ContactForce {
        contact::resolve(c, &self.options, k, spring, self.dt)
    }

    /// Adds contact `c` to body `b` of radius `r` whose unit normal towards the other body is
    /// `(nx, ny)`: force `−F_n n + F_t t` with `t = (−n_y, n_x)`, torque `F_t r`, rolling resistance
    /// `μ0 F_n r`. The other body gets the same call with `−n` (which also flips `t`).
    #[inline(always)]
    fn apply<const SAMPLE: bool>(&self, f: &mut Forces<'_>, b: usize, c: &ContactForce, nx: f64, ny: f64, r: f64) {
        f.fx[b] += -c.normal * nx - c.tangential * ny;
        f.fy[b] += -c.normal * ny + c.tangential * nx;
        if self.rotation {
            f.torque[b] += c.tangential * r;
        }
        if self.material.rolling_friction > 0.0 {
            f.rolling[b] += self.material.rolling_friction * c.normal.max(0.0) * r;
        }
        if SAMPLE {
            f.contact_force[b] += c.magnitude();
        }
    }
}

/// The touching pairs of one block, one array per quantity: the narrow phase fills the geometry,
/// the coefficient stage the rest.
/// Fixed-size arrays: indexing them with one row number costs one bounds check for all of them.
#[derive(Clone, Debug)]
pub struct TouchingPairs {
    len: usize,
    /// Index of the pair in its block.
    candidate: [usize; BLOCK],
    dx: [f64; BLOCK],
    dy: [f64; BLOCK],
    distance_squared: [f64; BLOCK],
    reach: [f64; BLOCK],
    r_star: [f64; BLOCK],
    m_star: [f64; BLOCK],
    nx: [f64; BLOCK],
    ny: [f64; BLOCK],
    overlap: [f64; BLOCK],
    normal_force: [f64; BLOCK],
    normal_damping: [f64; BLOCK],
    tangential_stiffness: [f64; BLOCK],
    tangential_damping: [f64; BLOCK],
}

impl Default for TouchingPairs {
    fn default() -> Self {
        Self {
            len: 0,
            candidate: [0; BLOCK],
            dx: [0.0; BLOCK],
            dy: [0.0; BLOCK],
            distance_squared: [0.0; BLOCK],
            reach: [0.0; BLOCK],
            r_star: [0.0; BLOCK],
            m_star: [0.0; BLOCK],
            nx: [0.0; BLOCK],
            ny: [0.0; BLOCK],
            overlap: [0.0; BLOCK],
            normal_force: [0.0; BLOCK],
            normal_damping: [0.0; BLOCK],
            tangential_stiffness: [0.0; BLOCK],
            tangential_damping: [0.0; BLOCK],
        }
    }
}

impl TouchingPairs {
    /// Adds all disk-disk contact forces (and with `SAMPLE`, the contact sums to `totals`).
    #[allow(clippy::too_many_arguments)]
    pub fn disk_contacts<L: ContactLaw, const SAMPLE: bool>(
        &mut self,
        law: &L,
        kind: &ContactKind,
        pairs: &[NeighborPair],
        springs: &mut [f64],
        s: &State<'_>,
        f: &mut Forces<'_>,
        totals: &mut ContactTotals,
    ) {
        for (block, block_springs) in pairs.chunks(BLOCK).zip(springs.chunks_mut(BLOCK)) {
            self.collect(s, block, block_springs);
            self.compute_coefficients(law, &kind.material);
            self.apply::<L, SAMPLE>(law, kind, block, block_springs, s, f, totals);
        }
    }

    /// Stage 1: appends the touching pairs of `block` to the table; pairs out of contact lose their spring.
    fn collect(&mut self, s: &State<'_>, block: &[NeighborPair], springs: &mut [f64]) {
        let n = s.x.len();
        let mut len = 0;
        let (candidate, dx_out, dy_out) = (&mut self.candidate, &mut self.dx, &mut self.dy);
        let (d2_out, reach_out) = (&mut self.distance_squared, &mut self.reach);
        let (r_star, m_star) = (&mut self.r_star, &mut self.m_star);
        for (k, (pair, spring)) in block.iter().zip(springs.iter_mut()).enumerate() {
            let (i, j) = (pair.i as usize, pair.j as usize);
            assert!(i < n && j < n, "neighbour pair out of range");
            let (dx, dy) = (s.x[j] - s.x[i], s.y[j] - s.y[i]);
            let reach = s.r[i] + s.r[j];
            let d2 = dx * dx + dy * dy;
            // NaN distances count as touching, so a diverging state reaches the forces.
            if d2 >= reach * reach {
                // Written only when set, so pairs out of contact leave their cache line clean.
                if *spring != 0.0 {
                    *spring = 0.0;
                }
                continue;
            }
            candidate[len] = k;
            dx_out[len] = dx;
            dy_out[len] = dy;
            d2_out[len] = d2;
            reach_out[len] = reach;
            r_star[len] = pair.r_star;
            m_star[len] = pair.m_star;
            len += 1;
        }
        self.len = len;
    }

    /// Stage 2: normals, overlaps and coefficients of all touching pairs, in the widest vector
    /// instructions the CPU has.
    fn compute_coefficients<L: ContactLaw>(&mut self, law: &L, m: &ContactMaterial) {
        #[cfg(target_arch = "x86_64")]
        #[allow(unsafe_code)]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            unsafe { self.coefficients_avx2(law, m) };
            return;
        }
        self.coefficients_portable(law, m);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn coefficients_avx2<L: ContactLaw>(&mut self, law: &L, m: &ContactMaterial) {
        self.coefficients_portable(law, m);
    }

    #[inline(always)]
    fn coefficients_portable<L: ContactLaw>(&mut self, law: &L, m: &ContactMaterial) {
        let n = self.len;
        // Equal-length slices: no bounds checks, so the loop vectorises.
        let (dx, dy, d2, reach) = (&self.dx[..n], &self.dy[..n], &self.distance_squared[..n], &self.reach[..n]);
        let (r_star, m_star) = (&self.r_star[..n], &self.m_star[..n]);
        let (nx, ny, overlap) = (&mut self.nx[..n], &mut self.ny[..n], &mut self.overlap[..n]);
        let (fne, cn) = (&mut self.normal_force[..n], &mut self.normal_damping[..n]);
        let (kt, ct) = (&mut self.tangential_stiffness[..n], &mut self.tangential_damping[..n]);
        for c in 0..n {
            let d = d2[c].sqrt();
            let inv_d = 1.0 / d;
            // Coincident centres: any unit normal will do.
            let apart = d > 0.0;
            nx[c] = if apart { dx[c] * inv_d } else { 1.0 };
            ny[c] = if apart { dy[c] * inv_d } else { 0.0 };
            overlap[c] = reach[c] - d;
            let pair = PairProperties {
                e_star: m.e_star,
                g_star: m.g_star,
                r_star: r_star[c],
                m_star: m_star[c],
                beta: m.beta,
            };
            let k = law.coefficients(&pair, overlap[c]);
            fne[c] = k.normal_force;
            cn[c] = k.normal_damping;
            kt[c] = k.tangential_stiffness;
            ct[c] = k.tangential_damping;
        }
    }

    /// Stage 3: forces of the touching pairs on both disks, in list order.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn apply<L: ContactLaw, const SAMPLE: bool>(
        &self,
        law: &L,
        kind: &ContactKind,
        block: &[NeighborPair],
        springs: &mut [f64],
        s: &State<'_>,
        f: &mut Forces<'_>,
        totals: &mut ContactTotals,
    ) {
        let n = s.x.len();
        for c in 0..self.len {
            let k = self.candidate[c];
            let (i, j) = (block[k].i as usize, block[k].j as usize);
            assert!(i < n && j < n, "neighbour pair out of range");
            let (nx, ny) = (self.nx[c], self.ny[c]);
            let (ri, rj) = (s.r[i], s.r[j]);
            let (dvx, dvy) = (s.vx[i] - s.vx[j], s.vy[i] - s.vy[j]);
            let motion = Kinematics {
                overlap: self.overlap[c],
                approach_speed: dvx * nx + dvy * ny,
                tangential_speed: -dvx * ny + dvy * nx + s.omega[i] * ri + s.omega[j] * rj,
            };
            let coefficients = Coefficients {
                normal_force: self.normal_force[c],
                normal_damping: self.normal_damping[c],
                tangential_stiffness: self.tangential_stiffness[c],
                tangential_damping: self.tangential_damping[c],
            };
            let spring = &mut springs[k];
            let force = kind.resolve(&coefficients, &motion, spring);
            kind.apply::<SAMPLE>(f, i, &force, nx, ny, ri);
            kind.apply::<SAMPLE>(f, j, &force, -nx, -ny, rj);
            if SAMPLE {
                let pair = kind.pair_properties(self.r_star[c], self.m_star[c]);
                let energy = contact::elastic_energy(law, &pair, motion.overlap, &force, *spring);
                totals.add(energy, force.magnitude(), motion.overlap / ri.min(rj));
            }
        }
    }
}

/// Adds all disk-wall contact forces (and with `SAMPLE`, the contact sums to `totals`).
#[allow(clippy::too_many_arguments)]
pub fn wall_contacts<L: ContactLaw, const SAMPLE: bool>(
    law: &L,
    kind: &ContactKind,
    walls: &[Wall],
    candidates: &[WallPair],
    springs: &mut [f64],
    s: &State<'_>,
    f: &mut Forces<'_>,
    totals: &mut ContactTotals,
) {
    let n = s.x.len();
    for (candidate, spring) in candidates.iter().zip(springs.iter_mut()) {
        let (i, wall) = (candidate.i as usize, &walls[candidate.wall as usize]);
        assert!(i < n, "wall candidate out of range");
        let (x, y, r) = (s.x[i], s.y[i], s.r[i]);
        let overlap = wall.overlap(x, y, r);
        if overlap <= 0.0 {
            *spring = 0.0;
            continue;
        }
        let [nx, ny] = wall.normal;
        let motion = Kinematics {
            overlap,
            approach_speed: s.vx[i] * nx + s.vy[i] * ny,
            tangential_speed: -s.vx[i] * ny + s.vy[i] * nx + s.omega[i] * r,
        };
        let pair = kind.pair_properties(r, s.mass[i]);
        let force = kind.resolve(&law.coefficients(&pair, overlap), &motion, spring);
        kind.apply::<SAMPLE>(f, i, &force, nx, ny, r);
        if SAMPLE {
            let energy = contact::elastic_energy(law, &pair, overlap, &force, *spring);
            totals.add(energy, force.magnitude(), overlap / r);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::contact::HertzMindlin;

    fn material() -> ContactMaterial {
        ContactMaterial { e_star: 5e8, g_star: 2e8, beta: 0.2, friction: 0.5, rolling_friction: 0.0 }
    }

    /// A table of touching pairs with assorted geometry, including coincident centres.
    fn table() -> TouchingPairs {
        let mut t = TouchingPairs { len: 200, ..Default::default() };
        for c in 0..t.len {
            let a = c as f64 * 0.37;
            let d = if c == 7 { 0.0 } else { 0.0199 - 1e-6 * (c % 13) as f64 };
            t.dx[c] = d * a.cos();
            t.dy[c] = d * a.sin();
            t.distance_squared[c] = t.dx[c] * t.dx[c] + t.dy[c] * t.dy[c];
            t.reach[c] = 0.02;
            t.r_star[c] = 0.005 + 1e-5 * c as f64;
            t.m_star[c] = 0.1 + 1e-3 * c as f64;
        }
        t
    }

    #[test]
    fn vector_stage_equals_one_contact_at_a_time_bit_for_bit() {
        let (law, m) = (HertzMindlin, material());
        let mut t = table();
        t.compute_coefficients(&law, &m);
        for c in 0..t.len {
            let d = t.distance_squared[c].sqrt();
            let (nx, ny) = if d > 0.0 { (t.dx[c] * (1.0 / d), t.dy[c] * (1.0 / d)) } else { (1.0, 0.0) };
            assert_eq!((t.nx[c].to_bits(), t.ny[c].to_bits()), (nx.to_bits(), ny.to_bits()), "normal of {c}");
            assert_eq!(t.overlap[c].to_bits(), (t.reach[c] - d).to_bits());
            let pair = PairProperties {
                e_star: m.e_star,
                g_star: m.g_star,
                r_star: t.r_star[c],
                m_star: t.m_star[c],
                beta: m.beta,
            };
            let k = law.coefficients(&pair, t.reach[c] - d);
            assert_eq!(t.normal_force[c].to_bits(), k.normal_force.to_bits(), "normal force of {c}");
            assert_eq!(t.normal_damping[c].to_bits(), k.normal_damping.to_bits());
            assert_eq!(t.tangential_stiffness[c].to_bits(), k.tangential_stiffness.to_bits());
            assert_eq!(t.tangential_damping[c].to_bits(), k.tangential_damping.to_bits());
        }
        let mut portable = table();
        portable.coefficients_portable(&law, &m);
        for (a, b) in
            [(&t.nx, &portable.nx), (&t.ny, &portable.ny), (&t.tangential_damping, &portable.tangential_damping)]
        {
            assert!(a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits()));
        }
        assert_eq!(t.nx[7], 1.0);
    }
}

//! Stage 2, the force stages: distances, unit normals and overlaps, the law's coefficients, and the
//! resolved forces and torques of every touching pair of the table, in branch-free loops that the
//! compiler vectorises (with copies compiled for AVX2 and AVX-512 that do the same IEEE operations
//! in the same order).

use super::table::{ContactParameters, TouchingPairs};
use crate::physics::contact::{Coefficients, ContactLaw, Kinematics};
use crate::physics::vector::{self, Width};

/// Where stage 2's normals and overlaps come from: in the table already (walls: the narrow phase
/// put them there), computed from the centres (disk pairs), or computed and checked (rows gathered
/// unchanged: whether their pairs all still touch).
pub(super) const GIVEN: u8 = 0;
pub(super) const COMPUTED: u8 = 1;
pub(super) const CHECKED: u8 = 2;

/// Unit normal from centre i to centre j and overlap of two disks `(dx, dy) = x_j − x_i` apart
/// (coincident centres: any unit normal will do). Shared by the block loops and the one-contact
/// evaluation, so that both compute the same bits.
#[inline(always)]
pub(in crate::physics) fn unit_normal_and_overlap(dx: f64, dy: f64, ri: f64, rj: f64) -> ([f64; 2], f64) {
    let d = (dx * dx + dy * dy).sqrt();
    let inv_d = 1.0 / d;
    let unit = if d > 0.0 { [dx * inv_d, dy * inv_d] } else { [1.0, 0.0] };
    (unit, (ri + rj) - d)
}

/// Whether two disks `d²` apart (squared distance, m²) with radii summing to `reach` touch: the
/// one test of the narrow phase, whether it takes a block afresh or gathers it unchanged (so both
/// find the same rows). NaN distances count as touching, so a diverging state reaches the forces.
/// (Written as a negated comparison, which says just that in one instruction; `< || is_nan`
/// takes two.)
#[inline(always)]
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub(super) fn touches(d2: f64, reach: f64) -> bool {
    !(d2 >= reach * reach)
}

/// Relative motion of a contact with unit normal `n`, `v_i − v_j` = `dv` and spin terms
/// `ω_i r_i`, `ω_j r_j` (conventions of [`super::contact`]).
#[inline(always)]
pub(in crate::physics) fn relative_motion(overlap: f64, n: [f64; 2], dv: [f64; 2], spin: [f64; 2]) -> Kinematics {
    let ([nx, ny], [dvx, dvy]) = (n, dv);
    Kinematics {
        overlap,
        approach_speed: dvx * nx + dvy * ny,
        tangential_speed: -dvx * ny + dvy * nx + spin[0] + spin[1],
    }
}

impl<S: Copy + Default + PartialEq> TouchingPairs<S> {
    /// Stage 2: normals, overlaps, coefficients and forces of all touching pairs, in the widest
    /// vector instructions the CPU runs well ([`vector::width`]). (Dispatched here rather than
    /// through [`vector::widest`]: behind its closure these loops no longer vectorise.)
    /// `GEOMETRY`: where normals and overlaps come from ([`GIVEN`], [`COMPUTED`], [`CHECKED`]).
    /// Returns whether the rows' pairs all touch (always, unless `CHECKED`; if not, the forces are
    /// not computed).
    pub(super) fn compute_forces<L: ContactLaw<State = S>, const GEOMETRY: u8>(
        &mut self,
        law: &L,
        kind: &ContactParameters,
    ) -> bool {
        #[cfg(target_arch = "x86_64")]
        #[allow(unsafe_code)]
        match vector::width() {
            // SAFETY: `vector::width` names only widths the CPU supports.
            Width::Avx512 => return unsafe { self.forces_avx512::<L, GEOMETRY>(law, kind) },
            // SAFETY: as above.
            Width::Avx2 => return unsafe { self.forces_avx2::<L, GEOMETRY>(law, kind) },
            Width::Baseline => {}
        }
        self.forces_portable::<L, GEOMETRY>(law, kind)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512vl,avx512dq")]
    pub(super) fn forces_avx512<L: ContactLaw<State = S>, const GEOMETRY: u8>(
        &mut self,
        law: &L,
        kind: &ContactParameters,
    ) -> bool {
        self.forces_portable::<L, GEOMETRY>(law, kind)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    pub(super) fn forces_avx2<L: ContactLaw<State = S>, const GEOMETRY: u8>(
        &mut self,
        law: &L,
        kind: &ContactParameters,
    ) -> bool {
        self.forces_portable::<L, GEOMETRY>(law, kind)
    }

    #[inline(always)]
    pub(super) fn forces_portable<L: ContactLaw<State = S>, const GEOMETRY: u8>(
        &mut self,
        law: &L,
        kind: &ContactParameters,
    ) -> bool {
        let all_touch = match GEOMETRY {
            CHECKED => self.geometry::<true>(),
            COMPUTED => self.geometry::<false>(),
            _ => true,
        };
        if !all_touch {
            return false;
        }
        self.coefficients(law, kind);
        self.resolve_all(kind);
        true
    }

    /// Distances, unit normals and overlaps: a loop of its own, short enough that the CPU overlaps
    /// many contacts' square root and division, which follow one another within a contact. With
    /// `CHECK`, returns whether all rows' pairs touch (else true).
    #[inline(always)]
    pub(super) fn geometry<const CHECK: bool>(&mut self) -> bool {
        let n = self.rows.len;
        // Equal-length slices: no bounds checks, so the loop vectorises.
        let (dx, dy, ri, rj) = (&self.dx[..n], &self.dy[..n], &self.rows.ri[..n], &self.rows.rj[..n]);
        let (unit_x, unit_y, overlap) = (&mut self.unit_x[..n], &mut self.unit_y[..n], &mut self.overlap[..n]);
        let mut all_touch = true;
        for c in 0..n {
            let ([ux, uy], o) = unit_normal_and_overlap(dx[c], dy[c], ri[c], rj[c]);
            (unit_x[c], unit_y[c], overlap[c]) = (ux, uy, o);
            if CHECK {
                all_touch &= touches(dx[c] * dx[c] + dy[c] * dy[c], ri[c] + rj[c]);
            }
        }
        all_touch
    }

    /// The law's stiffness and damping at each overlap: a loop of its own, for the same reason.
    #[inline(always)]
    pub(super) fn coefficients<L: ContactLaw<State = S>>(&mut self, law: &L, kind: &ContactParameters) {
        let n = self.rows.len;
        let (overlap, r_star, m_star) = (&self.overlap[..n], &self.rows.r_star[..n], &self.rows.m_star[..n]);
        let state = &mut self.state[..n];
        let (elastic, normal_damping) = (&mut self.elastic[..n], &mut self.normal_damping[..n]);
        let (stiffness, tangential_damping) = (&mut self.tangential_stiffness[..n], &mut self.tangential_damping[..n]);
        for c in 0..n {
            let k = law.coefficients(&kind.pair_properties(r_star[c], m_star[c]), overlap[c], &mut state[c]);
            (elastic[c], normal_damping[c], stiffness[c], tangential_damping[c]) =
                (k.normal_force, k.normal_damping, k.tangential_stiffness, k.tangential_damping);
        }
    }

    /// The resolved forces and torques, from the geometry and coefficients.
    #[inline(always)]
    pub(super) fn resolve_all(&mut self, kind: &ContactParameters) {
        let n = self.rows.len;
        // Equal-length slices: no bounds checks, so the loop vectorises.
        let (nx, ny, overlap) = (&self.unit_x[..n], &self.unit_y[..n], &self.overlap[..n]);
        let (elastic, normal_damping) = (&self.elastic[..n], &self.normal_damping[..n]);
        let (stiffness, tangential_damping) = (&self.tangential_stiffness[..n], &self.tangential_damping[..n]);
        let (ri, rj) = (&self.rows.ri[..n], &self.rows.rj[..n]);
        let (dvx, dvy, omega_i, omega_j) = (&self.dvx[..n], &self.dvy[..n], &self.omega_i[..n], &self.omega_j[..n]);
        let (force_x, force_y) = (&mut self.force_x[..n], &mut self.force_y[..n]);
        let (torque_i, torque_j) = (&mut self.torque_i[..n], &mut self.torque_j[..n]);
        let (normal, tangential, spring) =
            (&mut self.normal[..n], &mut self.tangential[..n], &mut self.rows.spring[..n]);
        for c in 0..n {
            let coefficients = Coefficients {
                normal_force: elastic[c],
                normal_damping: normal_damping[c],
                tangential_stiffness: stiffness[c],
                tangential_damping: tangential_damping[c],
            };
            let spin = [omega_i[c] * ri[c], omega_j[c] * rj[c]];
            let motion = relative_motion(overlap[c], [nx[c], ny[c]], [dvx[c], dvy[c]], spin);
            let force = kind.resolve(&coefficients, &motion, &mut spring[c]);
            // Torque `F_t r` on both disks.
            [force_x[c], force_y[c]] = force.on_first_body(nx[c], ny[c]);
            torque_i[c] = force.tangential * ri[c];
            torque_j[c] = force.tangential * rj[c];
            (normal[c], tangential[c]) = (force.normal, force.tangential);
        }
    }
}

//! The pile's stress: the Love–Weber average of the contact forces over a region (Pa, compression
//! positive, as soil mechanics writes it).
//!
//! `σ = −(1 / (A h)) Σ_c f_c ⊗ l_c` over the contacts that carry force, where `f_c` is the force on
//! the contact's first disk, `l_c` its branch vector (from the first disk's centre to the other
//! disk's centre, or to the contact point on a wall), `A` the region's area and `h` the disks'
//! thickness. Over a horizontal band only the part of each branch vector inside the band counts:
//! the band's mean of the force per width carried across each horizontal line in it (method of
//! planes), so that in a pile at rest the stress just above the floor, times the width and the
//! thickness, is the weight the floor carries. The tensor is symmetrised (`σ_xy` is the mean of
//! the two off-diagonal sums).

use super::contact_record::{Partner, PileContact};
use super::pile::{Pile, PileGeometry};
use super::record::Snapshot;

/// A 2D stress tensor (Pa, compression positive).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stress {
    /// Horizontal normal stress.
    pub xx: f64,
    /// Vertical normal stress.
    pub yy: f64,
    /// Shear stress (symmetrised).
    pub xy: f64,
}

impl Stress {
    /// Mean normal stress `(σ_xx + σ_yy) / 2`.
    pub fn pressure(&self) -> f64 {
        0.5 * (self.xx + self.yy)
    }

    /// Deviatoric stress `√(((σ_xx − σ_yy) / 2)² + σ_xy²)`: the radius of Mohr's circle, the largest
    /// shear stress on any plane.
    pub fn deviatoric(&self) -> f64 {
        (0.5 * (self.xx - self.yy)).hypot(self.xy)
    }
}

/// The stress over the horizontal band `[bottom, top)` of the box (see the module doc); NaN when the
/// band has no height or the box no width.
pub fn band_stress(geometry: &PileGeometry, contacts: &[PileContact], [bottom, top]: [f64; 2]) -> Stress {
    let area = geometry.width * (top - bottom) * geometry.thickness;
    if area.is_nan() || area <= 0.0 {
        return Stress { xx: f64::NAN, yy: f64::NAN, xy: f64::NAN };
    }
    let mut sum = [[0.0; 2]; 2];
    for contact in contacts.iter().filter(|c| c.normal_force > 0.0) {
        let (force, branch) = force_and_branch(geometry, contact);
        let share = share_inside(geometry.y[contact.disk], branch[1], [bottom, top]);
        if share > 0.0 {
            for (row, f) in sum.iter_mut().zip(force) {
                for (cell, l) in row.iter_mut().zip(branch) {
                    *cell -= share * f * l;
                }
            }
        }
    }
    Stress { xx: sum[0][0] / area, yy: sum[1][1] / area, xy: 0.5 * (sum[0][1] + sum[1][0]) / area }
}

/// The stress of a pile: its contacts' Love–Weber sum over the box width times its surface height
/// (every branch vector counts whole); NaN without a surface.
pub fn pile_stress(pile: &Pile) -> Stress {
    let (top, surface) = (pile.height(), pile.surface_height());
    let whole = band_stress(pile.geometry(), pile.carrying(), [0.0, top]);
    let scale = top / surface;
    Stress { xx: whole.xx * scale, yy: whole.yy * scale, xy: whole.xy * scale }
}

/// The stress in each band between consecutive `edges` (increasing heights, m).
pub fn stress_profile(geometry: &PileGeometry, contacts: &[PileContact], edges: &[f64]) -> Vec<Stress> {
    edges.windows(2).map(|band| band_stress(geometry, contacts, [band[0], band[1]])).collect()
}

/// Height of a profile's bands at most, in largest disk diameters: enough layers of grains for the
/// band average to be a stress.
pub const PROFILE_BAND_DIAMETERS: f64 = 2.0;

/// The stress of a pile per horizontal band, as columns (one entry per band, from the floor up): the
/// pile's height (its highest disk top) cut into equal bands of at most
/// [`PROFILE_BAND_DIAMETERS`] largest diameters; empty without disks.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StressProfile {
    /// Band bottom (m).
    pub bottom: Vec<f64>,
    /// Band top (m).
    pub top: Vec<f64>,
    /// The band's stress ([`band_stress`]).
    pub stress: Vec<Stress>,
    /// Normal stress on the side walls in the band (Pa): the side walls' normal forces on the disks
    /// touching them there over twice the band's height times the disks' thickness (the two walls'
    /// mean).
    pub wall_normal: Vec<f64>,
    /// Shear stress on the side walls in the band (Pa): the upward force the side walls' friction
    /// exerts on the disks there, over the same area (positive when the walls carry weight).
    pub wall_shear: Vec<f64>,
}

impl StressProfile {
    /// The profile of a stored state (its disks and contact network) in a box `width` wide, disks
    /// `thickness` thick.
    pub fn of_state(state: &Snapshot, width: f64, thickness: f64) -> Self {
        // The stress needs no weight.
        // The stress needs no weight, nor the sides: its branch vectors follow the contact normals.
        let geometry =
            PileGeometry { x: &state.x, y: &state.y, r: &state.r, weight: f64::NAN, width, thickness, periodic: false };
        Self::measure(&geometry, &state.contacts.pile_contacts(&state.r))
    }

    /// The profile of the disks of `geometry` with `contacts`.
    pub fn measure(geometry: &PileGeometry, contacts: &[PileContact]) -> Self {
        let edges = profile_edges(geometry);
        let mut profile = Self::default();
        for band in edges.windows(2) {
            let band = [band[0], band[1]];
            let [normal, shear] = wall_stress(geometry, contacts, band);
            profile.bottom.push(band[0]);
            profile.top.push(band[1]);
            profile.stress.push(band_stress(geometry, contacts, band));
            profile.wall_normal.push(normal);
            profile.wall_shear.push(shear);
        }
        profile
    }

    /// Number of bands.
    pub fn len(&self) -> usize {
        self.bottom.len()
    }

    /// Whether it has no band.
    pub fn is_empty(&self) -> bool {
        self.bottom.is_empty()
    }
}

/// Most bands of a profile: a pile whose disks flew far (a diverged run) gets wider bands, not
/// more of them.
const PROFILE_MAX_BANDS: f64 = 200.0;

/// The band edges of a pile's profile (see [`StressProfile`]); none without disks or with a disk
/// at no finite height.
fn profile_edges(geometry: &PileGeometry) -> Vec<f64> {
    let height = geometry.y.iter().zip(geometry.r).map(|(y, r)| y + r).fold(0.0, f64::max);
    let largest = geometry.r.iter().copied().fold(0.0, f64::max);
    if !(height > 0.0 && height.is_finite() && largest > 0.0 && largest.is_finite()) {
        return Vec::new();
    }
    let bands = (height / (PROFILE_BAND_DIAMETERS * 2.0 * largest)).ceil().clamp(1.0, PROFILE_MAX_BANDS) as usize;
    (0..=bands).map(|k| height * k as f64 / bands as f64).collect()
}

/// The side walls' normal and shear stress (Pa) over the band `[bottom, top)`: their contacts'
/// normal forces and upward friction forces on the disks whose contact point lies in the band, over
/// twice the band's area.
fn wall_stress(geometry: &PileGeometry, contacts: &[PileContact], [bottom, top]: [f64; 2]) -> [f64; 2] {
    let area = 2.0 * (top - bottom) * geometry.thickness;
    let side = contacts.iter().filter(|c| matches!(c.partner, Partner::Wall(1 | 2)) && c.normal_force > 0.0);
    let mut sum = [0.0; 2];
    for contact in side {
        let (force, branch) = force_and_branch(geometry, contact);
        if (bottom..top).contains(&(geometry.y[contact.disk] + branch[1])) {
            sum[0] += contact.normal_force;
            sum[1] += force[1];
        }
    }
    sum.map(|s| s / area)
}

/// The force on the contact's first disk and its branch vector (m).
fn force_and_branch(geometry: &PileGeometry, c: &PileContact) -> ([f64; 2], [f64; 2]) {
    let [nx, ny] = c.normal;
    let force = [-c.normal_force * nx - c.tangential_force * ny, -c.normal_force * ny + c.tangential_force * nx];
    let i = c.disk;
    let branch = match c.partner {
        Partner::Disk(j) => {
            // A branch against its normal joins the disk to the other's image across periodic
            // sides (between walls the two never disagree).
            let dx = geometry.x[j] - geometry.x[i];
            let dx = if dx * nx < 0.0 { dx - geometry.width.copysign(dx) } else { dx };
            [dx, geometry.y[j] - geometry.y[i]]
        }
        Partner::Wall(_) => {
            let reach = geometry.r[i] * (1.0 - c.overlap_ratio);
            [reach * nx, reach * ny]
        }
    };
    (force, branch)
}

/// The share of the vertical extent of a branch from height `start` rising by `rise` that lies in
/// `[bottom, top)`; a horizontal branch counts whole where it lies in the band.
fn share_inside(start: f64, rise: f64, [bottom, top]: [f64; 2]) -> f64 {
    if rise == 0.0 {
        return if (bottom..top).contains(&start) { 1.0 } else { 0.0 };
    }
    let (low, high) = (start.min(start + rise), start.max(start + rise));
    (high.min(top) - low.max(bottom)).max(0.0) / rise.abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two disks of radius 0.1 and weight 1 N stacked on the floor at x = 0.5 of a box 1 m wide, at
    /// rest: the upper one rests on the lower (1 N), the lower on the floor (2 N).
    fn stack() -> (PileGeometry<'static>, Vec<PileContact>) {
        let geometry = PileGeometry {
            x: &[0.5, 0.5],
            y: &[0.1, 0.3],
            r: &[0.1, 0.1],
            weight: 2.0,
            width: 1.0,
            thickness: 1.0,
            periodic: false,
        };
        let contact = |disk, partner, normal, normal_force| PileContact {
            disk,
            partner,
            normal,
            normal_force,
            tangential_force: 0.0,
            friction: 0.0,
            overlap_ratio: 0.0,
            history: (0.0, 0.0),
        };
        let contacts =
            vec![contact(0, Partner::Disk(1), [0.0, 1.0], 1.0), contact(0, Partner::Wall(0), [0.0, -1.0], 2.0)];
        (geometry, contacts)
    }

    #[test]
    fn the_stress_just_above_the_floor_carries_the_whole_weight() {
        let (geometry, contacts) = stack();
        let floor = band_stress(&geometry, &contacts, [0.0, 0.05]);
        assert!((floor.yy * geometry.width - 2.0).abs() < 1e-12, "{floor:?}");
        assert_eq!((floor.xx, floor.xy), (0.0, 0.0));
        // Between the centres only the upper disk's weight crosses.
        let between = band_stress(&geometry, &contacts, [0.15, 0.25]);
        assert!((between.yy - 1.0).abs() < 1e-12, "{between:?}");
        // Above the upper centre nothing does.
        assert_eq!(band_stress(&geometry, &contacts, [0.3, 0.4]).yy, 0.0);
    }

    #[test]
    fn the_whole_pile_averages_its_bands() {
        let (geometry, contacts) = stack();
        let whole = band_stress(&geometry, &contacts, [0.0, 0.4]);
        let bands = stress_profile(&geometry, &contacts, &[0.0, 0.1, 0.2, 0.3, 0.4]);
        let mean = bands.iter().map(|s| s.yy).sum::<f64>() / 4.0;
        assert!((whole.yy - mean).abs() < 1e-12, "{whole:?} against {bands:?}");
        // 2 N over 0.1 m and 1 N over 0.2 m, over the area 0.4 m².
        assert!((whole.yy - (2.0 * 0.1 + 1.0 * 0.2) / 0.4).abs() < 1e-12);
        assert_eq!(whole.pressure(), whole.yy / 2.0);
        assert_eq!(whole.deviatoric(), whole.yy / 2.0);
    }

    #[test]
    fn a_sheared_contact_gives_a_symmetric_shear_stress() {
        // One horizontal disk-disk contact with a tangential force: σ_xy from its tangential part.
        let geometry = PileGeometry {
            x: &[0.0, 0.2],
            y: &[0.1, 0.1],
            r: &[0.1, 0.1],
            weight: 0.0,
            width: 1.0,
            thickness: 2.0,
            periodic: false,
        };
        let c = PileContact {
            disk: 0,
            partner: Partner::Disk(1),
            normal: [1.0, 0.0],
            normal_force: 3.0,
            tangential_force: 1.0,
            friction: 0.5,
            overlap_ratio: 0.0,
            history: (0.0, 0.0),
        };
        let s = band_stress(&geometry, &[c], [0.0, 0.2]);
        // Force on disk 0: (−3, 1); branch (0.2, 0): −f ⊗ l = [[0.6, 0], [−0.2, 0]] over A h = 0.4 m².
        assert!((s.xx - 0.6 / 0.4).abs() < 1e-12 && s.yy == 0.0, "{s:?}");
        assert!((s.xy + 0.1 / 0.4).abs() < 1e-12, "{s:?}");
    }

    #[test]
    fn a_profile_cuts_the_pile_height_into_equal_bands_of_at_most_two_diameters() {
        // Five disks of radius 0.1 stacked: 1 m tall, so three bands of 1/3 m (two diameters: 0.4 m).
        let (x, y, r) = ([0.5; 5], [0.1, 0.3, 0.5, 0.7, 0.9], [0.1; 5]);
        let geometry = PileGeometry { x: &x, y: &y, r: &r, weight: 5.0, width: 1.0, thickness: 1.0, periodic: false };
        let contact = |disk, partner, normal_force| PileContact {
            disk,
            partner,
            normal: [0.0, if partner == Partner::Wall(0) { -1.0 } else { 1.0 }],
            normal_force,
            tangential_force: 0.0,
            friction: 0.0,
            overlap_ratio: 0.0,
            history: (0.0, 0.0),
        };
        let mut contacts: Vec<PileContact> = (0..4).map(|k| contact(k, Partner::Disk(k + 1), 4.0 - k as f64)).collect();
        contacts.push(contact(0, Partner::Wall(0), 5.0));
        let profile = StressProfile::measure(&geometry, &contacts);
        assert_eq!(profile.len(), 3);
        assert_eq!((profile.bottom[0], *profile.top.last().unwrap()), (0.0, 1.0));
        let edges = [0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0];
        assert_eq!(profile.stress, stress_profile(&geometry, &contacts, &edges));
        // Without side-wall contacts the walls carry nothing.
        assert_eq!((profile.wall_normal, profile.wall_shear), (vec![0.0; 3], vec![0.0; 3]));
    }

    #[test]
    fn the_side_walls_load_counts_in_the_band_of_its_contact_point() {
        // Two disks of radius 0.1, one above the other, each pressed against a side wall with 2 N;
        // the wall's friction holds the lower one up with 1 N.
        let (x, y, r) = ([0.1, 0.9], [0.1, 0.7], [0.1, 0.1]);
        let geometry = PileGeometry { x: &x, y: &y, r: &r, weight: 0.0, width: 1.0, thickness: 0.5, periodic: false };
        let wall = |disk, wall, nx: f64, tangential_force| PileContact {
            disk,
            partner: Partner::Wall(wall),
            normal: [nx, 0.0],
            normal_force: 2.0,
            tangential_force,
            friction: 0.5,
            overlap_ratio: 0.0,
            history: (0.0, 0.0),
        };
        // On the left wall (n = −x) an upward force on the disk is a negative tangential force.
        let contacts = [wall(0, 1, -1.0, -1.0), wall(1, 2, 1.0, 0.0)];
        let profile = StressProfile::measure(&geometry, &contacts);
        // 0.8 m tall: two bands of 0.4 m, each over an area 2 × 0.4 × 0.5 = 0.4 m².
        assert_eq!(profile.len(), 2);
        assert!((profile.bottom[1] - 0.4).abs() < 1e-12, "{profile:?}");
        assert!((profile.wall_normal[0] - 5.0).abs() < 1e-12 && (profile.wall_normal[1] - 5.0).abs() < 1e-12);
        assert!((profile.wall_shear[0] - 2.5).abs() < 1e-12 && profile.wall_shear[1] == 0.0, "{profile:?}");
    }

    #[test]
    fn a_state_without_disks_has_no_profile() {
        assert!(StressProfile::of_state(&Snapshot::default(), 1.0, 1.0).is_empty());
    }

    #[test]
    fn a_diverged_pile_gets_a_bounded_profile_or_none() {
        let far = |y: f64| {
            let geometry = PileGeometry {
                x: &[0.5, 0.5],
                y: &[0.1, y],
                r: &[0.1, 0.1],
                weight: 0.0,
                width: 1.0,
                thickness: 1.0,
                periodic: false,
            };
            StressProfile::measure(&geometry, &[]).len()
        };
        assert_eq!(far(1e300), PROFILE_MAX_BANDS as usize);
        assert_eq!(far(f64::INFINITY), 0);
        assert_eq!(far(0.3), 1);
    }
}

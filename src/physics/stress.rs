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

/// The force on the contact's first disk and its branch vector (m).
fn force_and_branch(geometry: &PileGeometry, c: &PileContact) -> ([f64; 2], [f64; 2]) {
    let [nx, ny] = c.normal;
    let force = [-c.normal_force * nx - c.tangential_force * ny, -c.normal_force * ny + c.tangential_force * nx];
    let i = c.disk;
    let branch = match c.partner {
        Partner::Disk(j) => [geometry.x[j] - geometry.x[i], geometry.y[j] - geometry.y[i]],
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
        let geometry =
            PileGeometry { x: &[0.5, 0.5], y: &[0.1, 0.3], r: &[0.1, 0.1], weight: 2.0, width: 1.0, thickness: 1.0 };
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
        let geometry =
            PileGeometry { x: &[0.0, 0.2], y: &[0.1, 0.1], r: &[0.1, 0.1], weight: 0.0, width: 1.0, thickness: 2.0 };
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
}

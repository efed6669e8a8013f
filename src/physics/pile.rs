//! Structure of a pile: the measures that say whether two piles are "the same pile"
//! (`docs/deposition.md`), from the disks and the list of their contacts at one time.
//!
//! Only contacts that carry force (`F_n > 0`) count. Definitions:
//! - interior packing fraction: disk area inside a window `2 d_max` away from the side walls and the
//!   floor, up to `2 d_max` below the pile's surface (its highest disk top), over the window's area;
//!   disks clipped to the window exactly;
//! - coordination number `Z = 2 C_dd / N` over disk–disk contacts; the mechanical one after removing
//!   rattlers, disks with fewer than 2 contacts (walls included), repeatedly until none is left;
//! - floor load ratio: the floor's normal forces over the disks' total weight (Janssen: below 1 when
//!   wall friction carries weight);
//! - fabric anisotropy `a = 2 (λ₁ − λ₂)` of `φ = (1/C) Σ n ⊗ n` over disk–disk contacts
//!   (Rothenburg & Bathurst 1989), with the major principal direction (rad from +x, in [0, π));
//! - sliding fraction: share of contacts with friction whose tangential force is at the Coulomb limit;
//! - mean overlap ratio: overlap over the smaller radius, averaged over contacts.

use serde::{Deserialize, Serialize};

/// What a contact touches besides its first disk.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Partner {
    /// Another disk (index).
    Disk(usize),
    /// A wall (index in the box's walls; 0 is the floor).
    Wall(usize),
}

/// One contact of a state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PileContact {
    /// The first disk.
    pub disk: usize,
    /// What it touches.
    pub partner: Partner,
    /// Unit normal from the disk towards its partner.
    pub normal: [f64; 2],
    /// Normal force (N), repulsive when positive.
    pub normal_force: f64,
    /// Tangential force (N).
    pub tangential_force: f64,
    /// Sliding friction coefficient of the contact.
    pub friction: f64,
    /// Overlap over the smaller radius.
    pub overlap_ratio: f64,
}

impl PileContact {
    fn carries_force(&self) -> bool {
        self.normal_force > 0.0
    }
    fn disks(&self) -> Option<(usize, usize)> {
        match self.partner {
            Partner::Disk(j) => Some((self.disk, j)),
            Partner::Wall(_) => None,
        }
    }
}

/// The disks of a pile and its box.
#[derive(Clone, Copy, Debug)]
pub struct PileGeometry<'a> {
    /// Centres x (m).
    pub x: &'a [f64],
    /// Centres y (m).
    pub y: &'a [f64],
    /// Radii (m).
    pub r: &'a [f64],
    /// Total weight of the disks (N).
    pub weight: f64,
    /// Box width (m).
    pub width: f64,
}

/// The pile measures of one state (NaN where undefined, e.g. no contacts).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PileMetrics {
    /// Area fraction of disks in the interior window.
    pub packing_fraction_interior: f64,
    /// `2 C_dd / N`.
    pub coordination_number: f64,
    /// `2 C_dd / N` without rattlers.
    pub mechanical_coordination_number: f64,
    /// Share of disks that are rattlers.
    pub rattler_fraction: f64,
    /// Floor normal forces over the total weight.
    pub floor_load_ratio: f64,
    /// `2 (λ₁ − λ₂)` of the contact-normal fabric tensor.
    pub fabric_anisotropy: f64,
    /// Major principal direction of the fabric tensor (rad from +x, in [0, π)).
    pub fabric_direction: f64,
    /// Share of frictional contacts at the Coulomb limit.
    pub sliding_fraction: f64,
    /// Mean overlap over the smaller radius.
    pub mean_overlap_ratio: f64,
}

impl Default for PileMetrics {
    fn default() -> Self {
        Self {
            packing_fraction_interior: f64::NAN,
            coordination_number: f64::NAN,
            mechanical_coordination_number: f64::NAN,
            rattler_fraction: f64::NAN,
            floor_load_ratio: f64::NAN,
            fabric_anisotropy: f64::NAN,
            fabric_direction: f64::NAN,
            sliding_fraction: f64::NAN,
            mean_overlap_ratio: f64::NAN,
        }
    }
}

/// Names of the metrics, in the order of [`PileMetrics::values`].
pub const PILE_METRIC_NAMES: [&str; 9] = [
    "packing_fraction_interior",
    "coordination_number",
    "mechanical_coordination_number",
    "rattler_fraction",
    "floor_load_ratio",
    "fabric_anisotropy",
    "fabric_direction",
    "sliding_fraction",
    "mean_overlap_ratio",
];

impl PileMetrics {
    /// Measures a pile from its disks and contacts.
    pub fn measure(pile: &PileGeometry, contacts: &[PileContact]) -> Self {
        let carrying: Vec<PileContact> = contacts.iter().filter(|c| c.carries_force()).copied().collect();
        let n = pile.x.len();
        let rattlers = rattlers(n, &carrying);
        let rattler_count = rattlers.iter().filter(|r| **r).count();
        let kept: Vec<PileContact> = carrying
            .iter()
            .filter(|c| !rattlers[c.disk] && c.disks().is_none_or(|(_, j)| !rattlers[j]))
            .copied()
            .collect();
        let (fabric_anisotropy, fabric_direction) = fabric(&carrying);
        let frictional: Vec<&PileContact> = carrying.iter().filter(|c| c.friction > 0.0).collect();
        let sliding =
            frictional.iter().filter(|c| c.tangential_force.abs() >= c.friction * c.normal_force * (1.0 - 1e-9));
        Self {
            packing_fraction_interior: interior_packing_fraction(pile),
            coordination_number: coordination(&carrying, n),
            mechanical_coordination_number: coordination(&kept, n - rattler_count),
            rattler_fraction: if n > 0 { rattler_count as f64 / n as f64 } else { f64::NAN },
            floor_load_ratio: floor_load(&carrying) / pile.weight,
            fabric_anisotropy,
            fabric_direction,
            sliding_fraction: ratio(sliding.count(), frictional.len()),
            mean_overlap_ratio: mean(carrying.iter().map(|c| c.overlap_ratio)),
        }
    }

    /// The metrics in the order of [`PILE_METRIC_NAMES`].
    pub fn values(&self) -> [f64; PILE_METRIC_NAMES.len()] {
        [
            self.packing_fraction_interior,
            self.coordination_number,
            self.mechanical_coordination_number,
            self.rattler_fraction,
            self.floor_load_ratio,
            self.fabric_anisotropy,
            self.fabric_direction,
            self.sliding_fraction,
            self.mean_overlap_ratio,
        ]
    }
}

fn ratio(count: usize, of: usize) -> f64 {
    if of > 0 { count as f64 / of as f64 } else { f64::NAN }
}

fn mean(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, count) = values.fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    if count > 0 { sum / count as f64 } else { f64::NAN }
}

/// `2 C_dd / n` over the disk–disk contacts of `contacts`; NaN without disks.
fn coordination(contacts: &[PileContact], n: usize) -> f64 {
    let pairs = contacts.iter().filter(|c| c.disks().is_some()).count();
    ratio(2 * pairs, n)
}

/// Sum of the floor's normal forces (N).
fn floor_load(contacts: &[PileContact]) -> f64 {
    contacts.iter().filter(|c| c.partner == Partner::Wall(0)).map(|c| c.normal_force).sum()
}

/// Which of `n` disks are rattlers: fewer than 2 contacts, after removing rattlers repeatedly.
pub fn rattlers(n: usize, contacts: &[PileContact]) -> Vec<bool> {
    let mut degree = vec![0usize; n];
    let mut partners: Vec<Vec<usize>> = vec![Vec::new(); n];
    for c in contacts {
        degree[c.disk] += 1;
        if let Some((i, j)) = c.disks() {
            degree[j] += 1;
            partners[i].push(j);
            partners[j].push(i);
        }
    }
    let mut rattler = vec![false; n];
    let mut pending: Vec<usize> = (0..n).filter(|&i| degree[i] < 2).collect();
    while let Some(i) = pending.pop() {
        if rattler[i] {
            continue;
        }
        rattler[i] = true;
        for &j in &partners[i] {
            degree[j] -= 1;
            if degree[j] < 2 && !rattler[j] {
                pending.push(j);
            }
        }
    }
    rattler
}

/// Anisotropy `2 (λ₁ − λ₂)` and major direction of the fabric tensor of the disk–disk contacts.
pub fn fabric(contacts: &[PileContact]) -> (f64, f64) {
    let (mut xx, mut xy, mut yy, mut count) = (0.0, 0.0, 0.0, 0usize);
    for c in contacts.iter().filter(|c| c.disks().is_some()) {
        let [nx, ny] = c.normal;
        (xx, xy, yy, count) = (xx + nx * nx, xy + nx * ny, yy + ny * ny, count + 1);
    }
    if count == 0 {
        return (f64::NAN, f64::NAN);
    }
    let (xx, xy, yy) = (xx / count as f64, xy / count as f64, yy / count as f64);
    // λ₁ − λ₂ = 2 √(((φxx − φyy)/2)² + φxy²); the major axis at ½ atan2(2 φxy, φxx − φyy).
    let half_difference = 0.5 * (xx - yy);
    let anisotropy = 4.0 * (half_difference * half_difference + xy * xy).sqrt();
    let direction = (0.5 * (2.0 * xy).atan2(xx - yy)).rem_euclid(std::f64::consts::PI);
    (anisotropy, direction)
}

/// Area fraction of the disks inside the interior window (see the module doc); NaN when the pile
/// is too shallow or the box too narrow for a window.
pub fn interior_packing_fraction(pile: &PileGeometry) -> f64 {
    let d_max = 2.0 * pile.r.iter().cloned().fold(0.0, f64::max);
    let surface = pile.y.iter().zip(pile.r).map(|(y, r)| y + r).fold(0.0, f64::max);
    let window = [2.0 * d_max, pile.width - 2.0 * d_max, 2.0 * d_max, surface - 2.0 * d_max];
    let area = (window[1] - window[0]) * (window[3] - window[2]);
    if !(window[1] > window[0] && window[3] > window[2]) {
        return f64::NAN;
    }
    let covered: f64 = (0..pile.x.len()).map(|i| disk_area_in_rectangle(pile.x[i], pile.y[i], pile.r[i], window)).sum();
    covered / area
}

/// Exact area of the disk of radius `r` at `(cx, cy)` inside the rectangle `[x0, x1, y0, y1]` (m²).
pub fn disk_area_in_rectangle(cx: f64, cy: f64, r: f64, [x0, x1, y0, y1]: [f64; 4]) -> f64 {
    if cx + r <= x0 || cx - r >= x1 || cy + r <= y0 || cy - r >= y1 {
        return 0.0;
    }
    let q = |a: f64, b: f64| quadrant_area(a - cx, b - cy, r);
    (q(x1, y1) - q(x0, y1) - q(x1, y0) + q(x0, y0)).max(0.0)
}

/// Area of the disk of radius `r` centred at the origin with `x ≤ a` and `y ≤ b` (m²):
/// `∫_{−r}^{a} len{y ≤ b, |y| ≤ h(x)} dx` with `h = √(r² − x²)`, in closed form.
fn quadrant_area(a: f64, b: f64, r: f64) -> f64 {
    let a = a.clamp(-r, r);
    if b <= -r {
        return 0.0;
    }
    let b = b.min(r);
    // ∫₀ˣ h = ½ (x h(x) + r² asin(x/r)).
    let g = |x: f64| 0.5 * (x * (r * r - x * x).max(0.0).sqrt() + r * r * (x / r).clamp(-1.0, 1.0).asin());
    let xb = (r * r - b * b).max(0.0).sqrt();
    // Over |x| < xb the strip is y ∈ [−h, b] (length b + h); beyond it, the whole chord (2h) when
    // b ≥ 0, nothing when b < 0.
    let outer = if b >= 0.0 { 2.0 } else { 0.0 };
    let pieces = [(-r, -xb, outer, 0.0), (-xb, xb, 1.0, b), (xb, r, outer, 0.0)];
    pieces
        .iter()
        .filter(|(lo, _, _, _)| a > *lo)
        .map(|&(lo, hi, chord, offset)| {
            let hi = hi.min(a);
            chord * (g(hi) - g(lo)) + offset * (hi - lo)
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn clipped_disk_areas_match_geometry() {
        let r = 1.0;
        let whole = disk_area_in_rectangle(0.0, 0.0, r, [-2.0, 2.0, -2.0, 2.0]);
        assert!((whole - PI).abs() < 1e-12);
        let half = disk_area_in_rectangle(0.0, 0.0, r, [0.0, 2.0, -2.0, 2.0]);
        assert!((half - PI / 2.0).abs() < 1e-12);
        let quarter = disk_area_in_rectangle(0.0, 0.0, r, [0.0, 2.0, 0.0, 2.0]);
        assert!((quarter - PI / 4.0).abs() < 1e-12);
        // Segment cut by x ≥ 0.5: r² acos(d/r) − d √(r² − d²).
        let segment = disk_area_in_rectangle(0.0, 0.0, r, [0.5, 2.0, -2.0, 2.0]);
        let expect = 0.5f64.acos() - 0.5 * 0.75f64.sqrt();
        assert!((segment - expect).abs() < 1e-12, "{segment} vs {expect}");
        // A strip −0.3 ≤ y ≤ 0.2, 0.1 ≤ x ≤ 0.7, against a fine midpoint sum.
        let strip = disk_area_in_rectangle(0.0, 0.0, r, [0.1, 0.7, -0.3, 0.2]);
        let m = 2000;
        let (mut sum, cell) = (0.0, 1.0 / (m as f64 * m as f64));
        for i in 0..m {
            for j in 0..m {
                let (x, y) = (0.1 + 0.6 * (i as f64 + 0.5) / m as f64, -0.3 + 0.5 * (j as f64 + 0.5) / m as f64);
                sum += f64::from(u8::from(x * x + y * y <= 1.0)) * 0.3 * cell;
            }
        }
        assert!((strip - sum).abs() < 1e-5, "{strip} vs {sum}");
    }

    fn pair(i: usize, j: usize, angle: f64) -> PileContact {
        PileContact {
            disk: i,
            partner: Partner::Disk(j),
            normal: [angle.cos(), angle.sin()],
            normal_force: 1.0,
            tangential_force: 0.0,
            friction: 0.5,
            overlap_ratio: 1e-3,
        }
    }

    fn wall(i: usize, wall: usize) -> PileContact {
        PileContact { partner: Partner::Wall(wall), normal: [0.0, -1.0], ..pair(i, i, 0.0) }
    }

    #[test]
    fn a_chain_of_disks_along_a_line_has_anisotropy_two() {
        let contacts: Vec<_> = (0..9).map(|k| pair(k, k + 1, 0.3)).collect();
        let (a, direction) = fabric(&contacts);
        assert!((a - 2.0).abs() < 1e-12, "{a}");
        assert!((direction - 0.3).abs() < 1e-12, "{direction}");
    }

    #[test]
    fn rattler_removal_cascades() {
        // Disk 0 sits on the floor and touches 1; 1 touches only 0 and 2; 2 touches 1 and the floor.
        // Disk 3 touches only 2. 3 is a rattler; removing it leaves 2 with two contacts (1, floor).
        // Disk 4 touches only 5, and 5 touches 4 and 6, 6 touches 5 only: 4 and 6 go, then 5 goes.
        let contacts = [
            wall(0, 0),
            pair(0, 1, 0.0),
            pair(1, 2, 0.0),
            wall(2, 0),
            pair(2, 3, 1.0),
            pair(4, 5, 0.0),
            pair(5, 6, 0.0),
        ];
        let r = rattlers(7, &contacts);
        assert_eq!(r, [false, false, false, true, true, true, true]);
        let metrics = PileMetrics::measure(
            &PileGeometry { x: &[0.0; 7], y: &[0.0; 7], r: &[0.1; 7], weight: 2.0, width: 1.0 },
            &contacts,
        );
        assert!((metrics.rattler_fraction - 4.0 / 7.0).abs() < 1e-12);
        assert!((metrics.coordination_number - 2.0 * 5.0 / 7.0).abs() < 1e-12);
        assert!((metrics.mechanical_coordination_number - 2.0 * 2.0 / 3.0).abs() < 1e-12);
        assert!((metrics.floor_load_ratio - 1.0).abs() < 1e-12, "two floor contacts of 1 N carry 2 N");
    }

    #[test]
    fn contacts_without_force_do_not_count() {
        let mut idle = pair(0, 1, 0.0);
        idle.normal_force = 0.0;
        let sliding = PileContact { tangential_force: 0.5, ..pair(1, 2, 0.0) };
        let metrics = PileMetrics::measure(
            &PileGeometry { x: &[0.0; 3], y: &[0.0; 3], r: &[0.1; 3], weight: 1.0, width: 1.0 },
            &[idle, sliding, pair(0, 2, 0.0)],
        );
        assert!((metrics.coordination_number - 4.0 / 3.0).abs() < 1e-12);
        assert!((metrics.sliding_fraction - 0.5).abs() < 1e-12);
    }
}

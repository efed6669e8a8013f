//! Structure of a pile: the measures that say whether two piles are "the same pile"
//! (`docs/deposition.md`), from the disks and the list of their contacts at one time.
//!
//! Only contacts that carry force (`F_n > 0`) count. The metrics, their names and units are declared
//! in [`super::quantity::PILE_METRICS`]; the definitions:
//! - pile height: the highest disk top; packing fraction: disk area over width times height;
//! - surface height: the mean height of the free surface over the box width: at each of many
//!   evenly spaced points across the width, the top of the highest disk above it (0 where no disk is
//!   above it), averaged; one grain on top of a pile of width `W` moves it by about `d² / W` where it
//!   moves the pile height by `d`;
//! - interior packing fraction: disk area inside a window `2 d_max` away from the side walls and the
//!   floor, up to `2 d_max` below the pile's surface (its highest disk top), over the window's area;
//!   disks clipped to the window exactly; with periodic sides the window spans the whole width (a
//!   disk across the boundary counts on both sides);
//! - coordination number `Z = 2 C_dd / N` over disk–disk contacts; the mechanical one after removing
//!   rattlers, disks with fewer than 2 contacts (walls included), repeatedly until none is left;
//! - floor load ratio: the floor's normal forces over the disks' total weight (Janssen: below 1 when
//!   wall friction carries weight); floor mean contact force: their mean (N);
//! - normal force width: population standard deviation over mean of the disk–disk normal forces
//!   (0 when every contact carries the same force; broad, exponential-tailed force networks near 1);
//! - fabric anisotropy `a = 2 (λ₁ − λ₂)` of `φ = (1/C) Σ n ⊗ n` over disk–disk contacts
//!   (Rothenburg & Bathurst 1989), with the major principal direction (rad from +x, in [0, π));
//! - sliding fraction: share of contacts with friction whose tangential force is at the Coulomb limit;
//! - mean overlap ratio: overlap over the smaller radius, averaged over contacts;
//! - stress (Pa, compression positive): the Love–Weber average of every contact's force times its
//!   branch vector over the area below the surface height (`super::stress`, which measures it); its components
//!   `σ_xx`, `σ_yy`, `σ_xy`, pressure `(σ_xx + σ_yy)/2` and deviatoric stress (Mohr's circle radius).

use serde::{Deserialize, Serialize};

use super::contact_record::{Partner, PileContact};

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
    /// Disk thickness (m): the depth over which the contact forces act, for stresses.
    pub thickness: f64,
    /// Whether the sides are periodic (`domain.periodic_x`): no side walls, a disk across the
    /// boundary counts on both sides.
    pub periodic: bool,
}

impl PileGeometry<'_> {
    /// The x positions (m) at which a disk centred at `x` counts: `x`, and across periodic sides
    /// also its images one width to either side.
    fn images(&self, x: f64) -> impl Iterator<Item = f64> + use<> {
        let shifts: &[f64] = if self.periodic { &[0.0, -1.0, 1.0] } else { &[0.0] };
        let width = self.width;
        shifts.iter().map(move |k| x + k * width)
    }
}

/// Number of pile metrics (the length of [`super::quantity::PILE_METRICS`], which checks it).
pub const PILE_METRIC_COUNT: usize = 19;

/// The pile metrics of one state, in the order of `quantity::PILE_METRICS` (NaN where undefined, e.g.
/// no contacts); measured and looked up by name in `quantity`, which declares them.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PileMetrics {
    pub(super) values: [f64; PILE_METRIC_COUNT],
}

impl Default for PileMetrics {
    fn default() -> Self {
        Self { values: [f64::NAN; PILE_METRIC_COUNT] }
    }
}

impl PileMetrics {
    /// The metrics in the order of `quantity::PILE_METRICS`.
    pub fn values(&self) -> &[f64; PILE_METRIC_COUNT] {
        &self.values
    }
}

/// A pile prepared for measuring: its disks, the contacts that carry force and its rattlers.
pub struct Pile<'a> {
    geometry: &'a PileGeometry<'a>,
    carrying: Vec<PileContact>,
    rattlers: Vec<bool>,
}

impl<'a> Pile<'a> {
    /// The pile of `geometry` with the contacts of `contacts` that carry force.
    pub fn new(geometry: &'a PileGeometry<'a>, contacts: &[PileContact]) -> Self {
        let carrying: Vec<PileContact> = contacts.iter().filter(|c| c.carries_force()).copied().collect();
        let rattlers = rattlers(geometry.x.len(), &carrying);
        Self { geometry, carrying, rattlers }
    }

    fn disk_count(&self) -> usize {
        self.geometry.x.len()
    }

    fn rattler_count(&self) -> usize {
        self.rattlers.iter().filter(|r| **r).count()
    }

    fn disk_pairs(&self) -> impl Iterator<Item = &PileContact> {
        self.carrying.iter().filter(|c| c.disks().is_some())
    }

    fn floor(&self) -> impl Iterator<Item = &PileContact> {
        self.carrying.iter().filter(|c| c.partner == Partner::Wall(0))
    }

    /// Packing fraction at which [`predicted_interior_window`] expects a settled pile: random 2D
    /// deposits settle at about 0.80-0.86.
    pub const PREDICTED_PACKING: f64 = 0.82;

    /// The depth (m) a pile of disks of radii `radii` is predicted to settle to across `width`, at
    /// [`PREDICTED_PACKING`], and the height (m) of its interior window: the window ends 2 largest
    /// diameters below the highest disk top, which stands about one largest diameter above that depth,
    /// and starts 2 above the floor ([`interior_packing_fraction`]). At or below 0 the window is
    /// predicted empty (the metric undefined); below one largest diameter it rests on a few disks, and
    /// seeds whose pile settles lower leave it empty.
    pub fn predicted_interior_window(radii: impl Iterator<Item = f64>, width: f64) -> (f64, f64) {
        let (area, largest) = radii.fold((0.0, 0.0_f64), |(a, l), r| (a + std::f64::consts::PI * r * r, l.max(r)));
        let depth = area / (width * PREDICTED_PACKING);
        (depth, depth - 6.0 * largest)
    }

    /// The highest disk top (m); 0 without disks.
    pub fn height(&self) -> f64 {
        surface(self.geometry)
    }

    /// The disks and the box.
    pub fn geometry(&self) -> &PileGeometry<'a> {
        self.geometry
    }

    /// The contacts that carry force.
    pub fn carrying(&self) -> &[PileContact] {
        &self.carrying
    }

    /// See [`surface_height`].
    pub fn surface_height(&self) -> f64 {
        surface_height(self.geometry)
    }

    /// Disk area over the box width times the pile height; NaN without height.
    pub fn packing_fraction(&self) -> f64 {
        let h = self.height();
        let area: f64 = self.geometry.r.iter().map(|r| std::f64::consts::PI * r * r).sum();
        if h > 0.0 { area / (self.geometry.width * h) } else { f64::NAN }
    }

    /// See [`interior_packing_fraction`].
    pub fn interior_packing_fraction(&self) -> f64 {
        interior_packing_fraction(self.geometry)
    }

    /// `2 C_dd / N`.
    pub fn coordination_number(&self) -> f64 {
        ratio(2 * self.disk_pairs().count(), self.disk_count())
    }

    /// `2 C_dd / N` without the rattlers and their contacts.
    pub fn mechanical_coordination_number(&self) -> f64 {
        let kept = self.disk_pairs().filter(|c| c.disks().is_some_and(|(i, j)| !self.rattlers[i] && !self.rattlers[j]));
        ratio(2 * kept.count(), self.disk_count() - self.rattler_count())
    }

    /// Share of disks that are rattlers.
    pub fn rattler_fraction(&self) -> f64 {
        ratio(self.rattler_count(), self.disk_count())
    }

    /// The floor's normal forces over the total weight.
    pub fn floor_load_ratio(&self) -> f64 {
        self.floor().map(|c| c.normal_force).sum::<f64>() / self.geometry.weight
    }

    /// Mean normal force of the floor's contacts (N).
    pub fn floor_mean_contact_force(&self) -> f64 {
        mean(self.floor().map(|c| c.normal_force))
    }

    /// See [`fabric`].
    pub fn fabric_anisotropy(&self) -> f64 {
        fabric(&self.carrying).0
    }

    /// See [`fabric`].
    pub fn fabric_direction(&self) -> f64 {
        fabric(&self.carrying).1
    }

    /// Population standard deviation over mean of the disk–disk normal forces.
    pub fn normal_force_width(&self) -> f64 {
        let forces = || self.disk_pairs().map(|c| c.normal_force);
        let average = mean(forces());
        mean(forces().map(|f| (f - average) * (f - average))).sqrt() / average
    }

    /// Share of the frictional contacts at the Coulomb limit.
    pub fn sliding_fraction(&self) -> f64 {
        let frictional = || self.carrying.iter().filter(|c| c.friction > 0.0);
        let sliding = frictional().filter(|c| c.is_sliding()).count();
        ratio(sliding, frictional().count())
    }

    /// Mean overlap over the smaller radius.
    pub fn mean_overlap_ratio(&self) -> f64 {
        mean(self.carrying.iter().map(|c| c.overlap_ratio))
    }
}

fn ratio(count: usize, of: usize) -> f64 {
    if of > 0 { count as f64 / of as f64 } else { f64::NAN }
}

fn mean(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, count) = values.fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    if count > 0 { sum / count as f64 } else { f64::NAN }
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
    let surface = surface(pile);
    let side = if pile.periodic { 0.0 } else { 2.0 * d_max };
    let window = [side, pile.width - side, 2.0 * d_max, surface - 2.0 * d_max];
    let area = (window[1] - window[0]) * (window[3] - window[2]);
    if !(window[1] > window[0] && window[3] > window[2]) {
        return f64::NAN;
    }
    let area_of =
        |i: usize| pile.images(pile.x[i]).map(move |x| disk_area_in_rectangle(x, pile.y[i], pile.r[i], window));
    let covered: f64 = (0..pile.x.len()).flat_map(area_of).sum();
    covered / area
}

/// Packing fraction at which [`predicted_interior_window`] expects a settled pile: random 2D
/// deposits settle at about 0.80-0.86.
pub const PREDICTED_PACKING: f64 = 0.82;

/// The depth (m) a pile of disks of radii `radii` is predicted to settle to across `width`, at
/// [`PREDICTED_PACKING`], and the height (m) of its interior window: the window ends 2 largest
/// diameters below the highest disk top, which stands about one largest diameter above that depth,
/// and starts 2 above the floor ([`interior_packing_fraction`]). At or below 0 the window is
/// predicted empty (the metric undefined); below one largest diameter it rests on a few disks, and
/// seeds whose pile settles lower leave it empty.
pub fn predicted_interior_window(radii: impl Iterator<Item = f64>, width: f64) -> (f64, f64) {
    let (area, largest) = radii.fold((0.0, 0.0_f64), |(a, l), r| (a + std::f64::consts::PI * r * r, l.max(r)));
    let depth = area / (width * PREDICTED_PACKING);
    (depth, depth - 6.0 * largest)
}

/// The highest disk top (m); 0 without disks.
fn surface(pile: &PileGeometry) -> f64 {
    pile.y.iter().zip(pile.r).map(|(y, r)| y + r).fold(0.0, f64::max)
}

/// Points across the width per mean disk radius at which [`surface_height`] finds the surface.
const SURFACE_POINTS_PER_RADIUS: f64 = 16.0;

/// Points across the width [`surface_height`] uses at most, whatever the disks' sizes.
const SURFACE_POINTS_MAX: f64 = 1.0e6;

/// Mean height of the free surface over the box width (m): the width is cut into equal intervals,
/// `SURFACE_POINTS_PER_RADIUS` per mean radius, and at each interval's midpoint `x` the surface is
/// the top of the highest disk above it, `y_i + √(r_i² − (x − x_i)²)`, or 0 where no disk is
/// above it; NaN without disks or width. Disks reaching past a side wall count where they are;
/// across periodic sides, on both sides.
pub fn surface_height(pile: &PileGeometry) -> f64 {
    let n = pile.r.len();
    if n == 0 || pile.width.is_nan() || pile.width <= 0.0 {
        return f64::NAN;
    }
    let mean_radius = pile.r.iter().sum::<f64>() / n as f64;
    let points = (SURFACE_POINTS_PER_RADIUS * pile.width / mean_radius).ceil().clamp(1.0, SURFACE_POINTS_MAX) as usize;
    let spacing = pile.width / points as f64;
    let mut top = vec![0.0_f64; points];
    let images = (0..n).flat_map(|i| pile.images(pile.x[i]).map(move |x| (x, pile.y[i], pile.r[i])));
    for (x, y, r) in images {
        let first = ((x - r) / spacing - 0.5).ceil().max(0.0) as usize;
        let last = ((x + r) / spacing - 0.5).floor().min(points as f64 - 1.0);
        if last < 0.0 {
            continue;
        }
        for (k, slot) in top.iter_mut().enumerate().take(last as usize + 1).skip(first) {
            let dx = (k as f64 + 0.5) * spacing - x;
            *slot = slot.max(y + (r * r - dx * dx).max(0.0).sqrt());
        }
    }
    top.iter().sum::<f64>() / points as f64
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
            history: (0.0, 0.0),
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
            &PileGeometry {
                x: &[0.0; 7],
                y: &[0.0; 7],
                r: &[0.1; 7],
                weight: 2.0,
                width: 1.0,
                thickness: 1.0,
                periodic: false,
            },
            &contacts,
        );
        assert!((metrics["rattler_fraction"] - 4.0 / 7.0).abs() < 1e-12);
        assert!((metrics["coordination_number"] - 2.0 * 5.0 / 7.0).abs() < 1e-12);
        assert!((metrics["mechanical_coordination_number"] - 2.0 * 2.0 / 3.0).abs() < 1e-12);
        assert!((metrics["floor_load_ratio"] - 1.0).abs() < 1e-12, "two floor contacts of 1 N carry 2 N");
    }

    #[test]
    fn contacts_without_force_do_not_count() {
        let mut idle = pair(0, 1, 0.0);
        idle.normal_force = 0.0;
        let sliding = PileContact { tangential_force: 0.5, ..pair(1, 2, 0.0) };
        let metrics = PileMetrics::measure(
            &PileGeometry {
                x: &[0.0; 3],
                y: &[0.0; 3],
                r: &[0.1; 3],
                weight: 1.0,
                width: 1.0,
                thickness: 1.0,
                periodic: false,
            },
            &[idle, sliding, pair(0, 2, 0.0)],
        );
        assert!((metrics["coordination_number"] - 4.0 / 3.0).abs() < 1e-12);
        assert!((metrics["sliding_fraction"] - 0.5).abs() < 1e-12);
    }

    #[test]
    fn normal_force_width_is_the_relative_spread_of_disk_forces() {
        // Disk-disk forces 1, 2, 3, 6 N (mean 3, population variance (4 + 1 + 0 + 9) / 4 = 3.5);
        // the floor's 40 N and a force-free contact do not count.
        let forces = [1.0, 2.0, 3.0, 6.0, 0.0];
        let mut contacts: Vec<PileContact> =
            forces.iter().enumerate().map(|(k, &f)| PileContact { normal_force: f, ..pair(k, k + 1, 0.0) }).collect();
        contacts.push(PileContact { normal_force: 40.0, ..wall(0, 0) });
        let geometry = PileGeometry {
            x: &[0.0; 6],
            y: &[0.0; 6],
            r: &[0.1; 6],
            weight: 1.0,
            width: 1.0,
            thickness: 1.0,
            periodic: false,
        };
        let metrics = PileMetrics::measure(&geometry, &contacts);
        let expect = 3.5f64.sqrt() / 3.0;
        assert!(
            (metrics["normal_force_width"] - expect).abs() < 1e-15,
            "{} vs {expect}",
            metrics["normal_force_width"]
        );
        let uniform = PileMetrics::measure(&geometry, &[pair(0, 1, 0.0), pair(1, 2, 1.0), pair(2, 3, 2.0)]);
        assert_eq!(uniform["normal_force_width"], 0.0);
        assert!(PileMetrics::measure(&geometry, &[]).get("normal_force_width").unwrap().is_nan(), "no contacts");
    }

    #[test]
    fn floor_mean_contact_force_averages_the_floor_contacts_only() {
        // Floor forces 1, 2 and 6 N (mean 3 N); a side wall's 10 N and a disk pair's 5 N do not count.
        let floor = |i: usize, f: f64| PileContact { normal_force: f, ..wall(i, 0) };
        let contacts = [
            floor(0, 1.0),
            floor(1, 2.0),
            floor(2, 6.0),
            PileContact { normal_force: 10.0, ..wall(3, 1) },
            PileContact { normal_force: 5.0, ..pair(0, 1, 0.0) },
        ];
        let geometry = PileGeometry {
            x: &[0.0; 4],
            y: &[0.0; 4],
            r: &[0.1; 4],
            weight: 9.0,
            width: 1.0,
            thickness: 1.0,
            periodic: false,
        };
        let metrics = PileMetrics::measure(&geometry, &contacts);
        assert_eq!(metrics["floor_mean_contact_force"], 3.0);
        assert_eq!(metrics["floor_load_ratio"], 1.0, "9 N on the floor carry 9 N");
    }

    #[test]
    fn height_and_packing_fraction_of_two_stacked_disks() {
        // Two disks of radius 0.1 stacked at x = 0.5 in a box 0.5 wide: top 0.4, area 2 π 0.01.
        let geometry = PileGeometry {
            x: &[0.5, 0.5],
            y: &[0.1, 0.3],
            r: &[0.1, 0.1],
            weight: 1.0,
            width: 0.5,
            thickness: 1.0,
            periodic: false,
        };
        let metrics = PileMetrics::measure(&geometry, &[]);
        assert!((metrics["pile_height"] - 0.4).abs() < 1e-15);
        assert!((metrics["packing_fraction"] - 2.0 * PI * 0.01 / (0.5 * 0.4)).abs() < 1e-15);
    }

    #[test]
    fn surface_height_of_a_flat_row_is_its_mean_top() {
        // A row of 10 touching disks of radius 0.05 on the floor of a box 1 m wide: the surface is a
        // row of half circles, mean height r + (π/4) r over the width.
        let x: Vec<f64> = (0..10).map(|i| 0.05 + 0.1 * i as f64).collect();
        let geometry = PileGeometry {
            x: &x,
            y: &[0.05; 10],
            r: &[0.05; 10],
            weight: 1.0,
            width: 1.0,
            thickness: 1.0,
            periodic: false,
        };
        let surface = PileMetrics::measure(&geometry, &[])["surface_height"];
        let exact = 0.05 + PI / 4.0 * 0.05;
        assert!((surface / exact - 1.0).abs() < 1e-3, "{surface} vs {exact}");
    }

    #[test]
    fn one_grain_on_top_moves_the_surface_height_by_its_share_of_the_width() {
        // 40 disks of radius 0.0125 side by side (width 1), then one more on top: the pile height
        // grows by a diameter, the surface height by about a diameter times its share of the width.
        let r = 0.0125;
        let mut x: Vec<f64> = (0..40).map(|i| r + 2.0 * r * i as f64).collect();
        let mut y = vec![r; 40];
        let flat = PileGeometry { x: &x, y: &y, r: &[r; 40], weight: 1.0, width: 1.0, thickness: 1.0, periodic: false };
        let before = PileMetrics::measure(&flat, &[]);
        x.push(2.0 * r * 20.0);
        y.push(r + 2.0 * r * (0.75_f64).sqrt());
        let grain =
            PileGeometry { x: &x, y: &y, r: &[r; 41], weight: 1.0, width: 1.0, thickness: 1.0, periodic: false };
        let after = PileMetrics::measure(&grain, &[]);
        let height = after["pile_height"] - before["pile_height"];
        let surface = after["surface_height"] - before["surface_height"];
        assert!((height - 2.0 * r * 0.75_f64.sqrt()).abs() < 1e-12, "{height}");
        assert!(surface > 0.0 && surface < 0.05 * height, "{surface} against {height}");
    }
}

//! Dropped placement: sequential deposition in 2D (Visscher & Bolsterli 1972). The disks, in an
//! order drawn from the seed, each at an x drawn from the seed, fall straight down (−y) onto the
//! pile and roll, keeping contact, down what they land on, until they rest on the floor or on two
//! supports (disks or a side wall) whose contact normals can hold their weight; a disk that rolls
//! level with its support falls on. The pile is at rest and every impact is skipped.
//!
//! Each disk is placed as if it were `GAP` of its radius larger, so that neighbours and walls start
//! about 1e-9 radii apart: nothing overlaps and contact forces start at zero. Only `+ − × ÷` and
//! square roots are used (no trigonometry), so the positions are the same on every platform. A
//! drop looks at the top few disks of three columns ([`Columns`]) and a roll at the disks near its
//! arc: O(1) per move and O(log N) per bisection, O(N log N) in all.

use super::columns::Columns;
use super::error::PlacementError;
use super::random::order_for_locality;
use crate::physics::config::SceneConfig;
use crate::physics::number::{short, significant};
use crate::physics::particles::InitialDisk;
use crate::physics::rng::Rng;

/// The gap each disk keeps to its neighbours and the walls, as a fraction of its radius.
const GAP: f64 = 1e-9;
/// A disk whose centre is less than this fraction of the contact distance above a neighbour's
/// (a contact normal this close to level) is not held by it: it falls past.
const LEVEL: f64 = 1e-6;
/// Moves (falls and rolls) one disk may take before the placement gives up on it.
const MOST_MOVES: usize = 10_000;

/// What ends a roll.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Stop {
    /// Level with the support: the disk falls on.
    Off,
    Floor,
    /// A side wall, with its normal's x (1 for the left wall, −1 for the right).
    Wall(f64),
    Disk(u32),
}

/// The disks placed so far, with their radii enlarged by `GAP`.
struct Pile {
    x: Vec<f64>,
    y: Vec<f64>,
    r: Vec<f64>,
    columns: Columns,
    width: f64,
    largest: f64,
}

/// A stable rest found for a disk of radius `r` dropped at `x`, or `None` after `MOST_MOVES`.
type Rest = Option<(f64, f64)>;

/// Dropped placement of disks with `radii` (see the module documentation); the disks are then
/// ordered for memory locality, like random placement's. Fails when the pile would pass
/// `domain.height`, saying how many disks fit.
pub fn dropped(scene: &SceneConfig, radii: &[f64], rng: &mut Rng) -> Result<Vec<InitialDisk>, PlacementError> {
    let (w, h) = (scene.domain.width, scene.domain.height);
    let largest = radii.iter().copied().fold(0.0, f64::max) * (1.0 + GAP);
    let mut pile = Pile {
        x: Vec::with_capacity(radii.len()),
        y: Vec::with_capacity(radii.len()),
        r: Vec::with_capacity(radii.len()),
        columns: Columns::new(w, 2.0 * largest, 4 * radii.len()),
        width: w,
        largest,
    };
    let mut order: Vec<usize> = (0..radii.len()).collect();
    rng.shuffle(&mut order);
    let mut disks = Vec::with_capacity(radii.len());
    for &k in &order {
        let (r, grown) = (radii[k], radii[k] * (1.0 + GAP));
        if 2.0 * grown > w {
            let why = format!("a disk of radius {} m does not fit across it with the placement's gap", short(r));
            return Err(too_high(scene, &disks, radii.len(), &why));
        }
        let Some((x, y)) = pile.land(rng.range(grown, w - grown), grown) else {
            let why = format!("the next disk found no rest in {MOST_MOVES} moves");
            return Err(too_high(scene, &disks, radii.len(), &why));
        };
        if y + r > h {
            let why = format!("the next disk would rest with its top at {} m", short(y + r));
            return Err(too_high(scene, &disks, radii.len(), &why));
        }
        pile.add(x, y, grown);
        disks.push(InitialDisk { x, y, r, ..Default::default() });
    }
    order_for_locality(&mut disks, w, h, 2.0 * largest);
    Ok(disks)
}

fn too_high(scene: &SceneConfig, placed: &[InitialDisk], count: usize, why: &str) -> PlacementError {
    let area: f64 = placed.iter().map(|d| std::f64::consts::PI * d.r * d.r).sum();
    PlacementError {
        key: "placement.kind".into(),
        reason: format!(
            "dropped placement fit only {} of {count} disks in the {} m wide box below domain.height = {} m: \
             {why} (the disks placed fill {} of the box's area); enlarge domain.height or domain.width, or lower \
             particles.count",
            placed.len(),
            significant(scene.domain.width, 12),
            significant(scene.domain.height, 12),
            short(area / (scene.domain.width * scene.domain.height)),
        ),
    }
}

/// Whether contact normals `a` and `b` (unit, pointing into the disk) can hold its weight: the
/// upward vertical is a combination of them with weights >= 0.
fn holds(a: [f64; 2], b: [f64; 2]) -> bool {
    let det = a[0] * b[1] - a[1] * b[0];
    det != 0.0 && -b[0] / det >= 0.0 && a[0] / det >= 0.0
}

impl Pile {
    fn add(&mut self, x: f64, y: f64, r: f64) {
        self.columns.insert(x, y, self.x.len() as u32);
        self.x.push(x);
        self.y.push(y);
        self.r.push(r);
    }

    /// The unit contact normal from disk `j` to a disk centred at `(x, y)`.
    fn normal(&self, j: u32, x: f64, y: f64) -> [f64; 2] {
        let (dx, dy) = (x - self.x[j as usize], y - self.y[j as usize]);
        let d = (dx * dx + dy * dy).sqrt();
        [dx / d, dy / d]
    }

    /// Moves a disk of radius `r` dropped at `x` from above the pile to its rest.
    fn land(&self, x: f64, r: f64) -> Rest {
        let (mut x, mut y) = (x, f64::INFINITY);
        let mut left = None;
        let mut rolling = None;
        for _ in 0..MOST_MOVES {
            let Some(s) = rolling else {
                (y, rolling) = self.fall(x, y, r, left);
                if rolling.is_none() {
                    return Some((x, y));
                }
                continue;
            };
            let stop;
            (x, y, stop) = self.roll(s, x, y, r);
            match stop {
                Stop::Floor => return Some((x, y)),
                Stop::Wall(nx) if holds(self.normal(s, x, y), [nx, 0.0]) => return Some((x, y)),
                Stop::Disk(k) if holds(self.normal(s, x, y), self.normal(k, x, y)) => return Some((x, y)),
                Stop::Disk(k) => rolling = Some(k),
                Stop::Off | Stop::Wall(_) => (left, rolling) = (Some(s), None),
            }
        }
        None
    }

    /// Where a disk of radius `r` at `(x, from)` falling straight down lands: its height and the
    /// disk it lands on (`None`: the floor). `left`, the support it just rolled off, is passed.
    fn fall(&self, x: f64, from: f64, r: f64, left: Option<u32>) -> (f64, Option<u32>) {
        let reach = r + self.largest;
        let mut best = (r, None);
        for column in self.columns.span(x - reach, x + reach) {
            for (yj, j) in self.columns.below(column, from) {
                if yj + reach <= best.0 {
                    break;
                }
                let (d, dx) = (r + self.r[j as usize], x - self.x[j as usize]);
                let rise2 = d * d - dx * dx;
                if Some(j) == left || rise2 <= (LEVEL * d) * (LEVEL * d) {
                    continue;
                }
                let top = (yj + rise2.sqrt()).min(from);
                if top > best.0 {
                    best = (top, Some(j));
                }
            }
        }
        best
    }

    /// Rolls a disk of radius `r` at `(x, y)`, touching disk `s`, down around `s` (away from its
    /// centre) until the first floor, wall or disk it meets, or until it is level with `s`: where
    /// it stops and what stopped it. The arc's points are ordered by height, highest first; one up
    /// to `LEVEL` of the arc's radius above the start (rounding) stops the disk where it is.
    fn roll(&self, s: u32, x: f64, y: f64, r: f64) -> (f64, f64, Stop) {
        let (xs, ys, big) = (self.x[s as usize], self.y[s as usize], r + self.r[s as usize]);
        if y <= ys {
            return (x, y, Stop::Off);
        }
        let side = if x >= xs { 1.0 } else { -1.0 };
        let mut first = (xs + side * big, ys, Stop::Off);
        let mut meet = |px: f64, py: f64, stop: Stop| {
            if side * (px - xs) >= 0.0 && py > first.1 && py <= y + LEVEL * big {
                first = if py >= y { (x, y, stop) } else { (px, py, stop) };
            }
        };
        let below = r - ys;
        if (0.0..=big).contains(&below) {
            meet(xs + side * (big * big - below * below).sqrt(), r, Stop::Floor);
        }
        let across = side * (if side > 0.0 { self.width - r } else { r } - xs);
        if (0.0..=big).contains(&across) {
            meet(xs + side * across, ys + (big * big - across * across).sqrt(), Stop::Wall(-side));
        }
        let reach = big + r + self.largest;
        for k in self.columns.within([xs - reach, xs + reach, ys - reach, y + reach]) {
            if k == s {
                continue;
            }
            let (ex, ey) = (self.x[k as usize] - xs, self.y[k as usize] - ys);
            let (l2, d) = (ex * ex + ey * ey, r + self.r[k as usize]);
            let l = l2.sqrt();
            let along = (big * big - d * d + l2) / (2.0 * l);
            let off2 = big * big - along * along;
            if off2 < 0.0 {
                continue;
            }
            let (ux, uy, off) = (ex / l, ey / l, off2.sqrt());
            for sign in [1.0, -1.0] {
                let (px, py) = (xs + along * ux - sign * off * uy, ys + along * uy + sign * off * ux);
                // The rolling direction at p, and whether it heads into disk k there.
                let (nx, ny) = ((px - xs) / big, (py - ys) / big);
                let (tx, ty) = (side * ny, -side * nx);
                if tx * (ex + xs - px) + ty * (ey + ys - py) > 0.0 {
                    meet(px, py, Stop::Disk(k));
                }
            }
        }
        first
    }
}

#[cfg(test)]
mod tests {
    use super::holds;

    #[test]
    fn two_normals_hold_a_disk_when_they_straddle_the_vertical() {
        let (s, c) = (0.6f64.sqrt(), 0.4f64.sqrt());
        assert!(holds([-c, s], [c, s]), "a pocket between two disks");
        assert!(holds([c, s], [-1.0, 0.0]), "a disk against the right wall");
        assert!(!holds([c, s], [1.0, 0.0]), "the wall on the wrong side");
        assert!(!holds([c, s], [0.8, 0.6]), "both supports on the left");
        assert!(!holds([1.0, 0.0], [-1.0, 0.0]), "squeezed level: no upward force");
    }
}

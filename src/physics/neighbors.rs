//! Who may touch whom: a Verlet neighbour list built by a cell grid (or all pairs, for tests),
//! plus the disks near walls, carrying each contact's tangential spring from one build to the next.
//!
//! The list holds every pair closer than `r_i + r_j + skin` and is rebuilt once any disk has moved
//! more than half the skin since the last build, so no contact is missed in between. Pairs are kept
//! sorted by `(i, j)`, which makes the result independent of the broad phase and lets a rebuild carry
//! tangential springs over by a linear merge: no hashing, no allocation once buffers have grown.

use super::config::BroadPhaseKind;
use super::material::{effective_mass, effective_radius};
use super::particles::Particles;
use super::walls::BoxWalls;

/// A pair `i < j` that may be in contact, with its tangential spring ξ (m) and its effective
/// radius and mass (computed once per build, not once per step).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NeighborPair {
    /// First disk (smaller index).
    pub i: u32,
    /// Second disk.
    pub j: u32,
    /// Accumulated tangential displacement ξ; zero while not in contact.
    pub spring: f64,
    /// Effective radius R* (m).
    pub r_star: f64,
    /// Effective mass m* (kg).
    pub m_star: f64,
}

impl NeighborPair {
    fn new(p: &Particles, i: usize, j: usize) -> Self {
        Self {
            i: i as u32,
            j: j as u32,
            spring: 0.0,
            r_star: effective_radius(p.r[i], p.r[j]),
            m_star: effective_mass(p.mass[i], p.mass[j]),
        }
    }
}

/// A disk that may touch a wall, with its tangential spring ξ (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallPair {
    /// The disk.
    pub i: u32,
    /// Index of the wall in [`BoxWalls::walls`].
    pub wall: u32,
    /// Accumulated tangential displacement ξ; zero while not in contact.
    pub spring: f64,
}

/// A list entry with a sort key and a tangential spring to carry over rebuilds.
trait Carried: Copy {
    fn key(&self) -> (u32, u32);
    fn spring_mut(&mut self) -> &mut f64;
}

impl Carried for NeighborPair {
    fn key(&self) -> (u32, u32) {
        (self.i, self.j)
    }
    fn spring_mut(&mut self) -> &mut f64 {
        &mut self.spring
    }
}

impl Carried for WallPair {
    fn key(&self) -> (u32, u32) {
        (self.i, self.wall)
    }
    fn spring_mut(&mut self) -> &mut f64 {
        &mut self.spring
    }
}

/// Verlet list with its build state.
#[derive(Clone, Debug)]
pub struct NeighborList {
    /// Candidate pairs, sorted by `(i, j)`.
    pub pairs: Vec<NeighborPair>,
    /// Candidate disk-wall contacts, sorted by `(i, wall)`.
    pub wall_pairs: Vec<WallPair>,
    fresh: Vec<NeighborPair>,
    fresh_walls: Vec<WallPair>,
    x_ref: Vec<f64>,
    y_ref: Vec<f64>,
    skin: f64,
    broad_phase: BroadPhaseKind,
    grid: CellGrid,
    /// Number of builds so far.
    pub builds: u64,
}

impl NeighborList {
    /// An empty list; call [`NeighborList::rebuild`] before use.
    pub fn new(broad_phase: BroadPhaseKind, skin: f64) -> Self {
        Self {
            pairs: Vec::new(),
            wall_pairs: Vec::new(),
            fresh: Vec::new(),
            fresh_walls: Vec::new(),
            x_ref: Vec::new(),
            y_ref: Vec::new(),
            skin,
            broad_phase,
            grid: CellGrid::default(),
            builds: 0,
        }
    }

    /// Whether some disk moved more than half the skin since the last build.
    pub fn needs_rebuild(&self, p: &Particles) -> bool {
        let limit = 0.25 * self.skin * self.skin;
        p.x.iter().zip(&p.y).zip(self.x_ref.iter().zip(&self.y_ref)).any(|((x, y), (xr, yr))| {
            let (dx, dy) = (x - xr, y - yr);
            // NaN positions count as moved, so a diverging state never keeps a stale list.
            (dx * dx + dy * dy).partial_cmp(&limit) != Some(std::cmp::Ordering::Less)
        })
    }

    /// Rebuilds the lists from the current positions, keeping springs of surviving pairs.
    pub fn rebuild(&mut self, p: &Particles, walls: &BoxWalls) {
        self.fresh.clear();
        match self.broad_phase {
            BroadPhaseKind::Grid => self.grid.collect(p, self.skin, &mut self.fresh),
            BroadPhaseKind::AllPairs => all_pairs(p, self.skin, &mut self.fresh),
        }
        carry_springs(&self.pairs, &mut self.fresh);
        std::mem::swap(&mut self.pairs, &mut self.fresh);
        self.fresh_walls.clear();
        for i in 0..p.len() {
            for (w, wall) in walls.walls.iter().enumerate() {
                // NaN positions are kept as candidates, so a diverging disk is still seen.
                let overlap = wall.overlap(p.x[i], p.y[i], p.r[i]);
                if overlap > -self.skin || overlap.is_nan() {
                    self.fresh_walls.push(WallPair { i: i as u32, wall: w as u32, spring: 0.0 });
                }
            }
        }
        carry_springs(&self.wall_pairs, &mut self.fresh_walls);
        std::mem::swap(&mut self.wall_pairs, &mut self.fresh_walls);
        self.x_ref.clone_from(&p.x);
        self.y_ref.clone_from(&p.y);
        self.builds += 1;
    }
}

#[inline]
fn within(p: &Particles, i: usize, j: usize, skin: f64) -> bool {
    let (dx, dy) = (p.x[j] - p.x[i], p.y[j] - p.y[i]);
    let reach = p.r[i] + p.r[j] + skin;
    dx * dx + dy * dy < reach * reach
}

fn all_pairs(p: &Particles, skin: f64, out: &mut Vec<NeighborPair>) {
    for i in 0..p.len() {
        for j in i + 1..p.len() {
            if within(p, i, j, skin) {
                out.push(NeighborPair::new(p, i, j));
            }
        }
    }
}

/// Copies springs from the old sorted list into the new sorted list where the entry survives.
fn carry_springs<T: Carried>(old: &[T], new: &mut [T]) {
    let mut k = 0;
    for entry in new.iter_mut() {
        while k < old.len() && old[k].key() < entry.key() {
            k += 1;
        }
        if k < old.len() && old[k].key() == entry.key() {
            let mut survivor = old[k];
            *entry.spring_mut() = *survivor.spring_mut();
        }
    }
}

/// Uniform cell grid sized to the current positions (a counting sort of disks into cells).
#[derive(Clone, Debug, Default)]
struct CellGrid {
    cell_of: Vec<u32>,
    start: Vec<u32>,
    members: Vec<u32>,
    fill: Vec<u32>,
    row: Vec<u32>,
}

impl CellGrid {
    fn collect(&mut self, p: &Particles, skin: f64, out: &mut Vec<NeighborPair>) {
        let n = p.len();
        if n == 0 {
            return;
        }
        let (xmin, xmax) = min_max(&p.x);
        let (ymin, ymax) = min_max(&p.y);
        // Cells at least as wide as the longest possible pair reach; at most ~2 cells per disk so a
        // disk that flew far away cannot blow the grid up (disks beyond are clamped to edge cells).
        let mut cell = 2.0 * p.max_radius() + skin;
        let max_cells = (2 * n + 16) as f64;
        let span = |lo: f64, hi: f64, c: f64| (((hi - lo) / c).floor() + 1.0).min(1e9);
        while span(xmin, xmax, cell) * span(ymin, ymax, cell) > max_cells {
            cell *= 1.5;
        }
        let cols = span(xmin, xmax, cell) as usize;
        let rows = span(ymin, ymax, cell) as usize;
        let cell_index = |x: f64, y: f64| {
            let c = (((x - xmin) / cell) as usize).min(cols - 1);
            let r = (((y - ymin) / cell) as usize).min(rows - 1);
            r * cols + c
        };
        self.cell_of.clear();
        self.cell_of.extend(p.x.iter().zip(&p.y).map(|(&x, &y)| cell_index(x, y) as u32));
        self.start.clear();
        self.start.resize(cols * rows + 1, 0);
        for &c in &self.cell_of {
            self.start[c as usize + 1] += 1;
        }
        for c in 0..cols * rows {
            self.start[c + 1] += self.start[c];
        }
        self.members.resize(n, 0);
        self.fill.clone_from(&self.start);
        for (k, &c) in self.cell_of.iter().enumerate() {
            self.members[self.fill[c as usize] as usize] = k as u32;
            self.fill[c as usize] += 1;
        }
        for i in 0..n {
            let c = self.cell_of[i] as usize;
            let (ci, ri) = (c % cols, c / cols);
            self.row.clear();
            for r in ri.saturating_sub(1)..=(ri + 1).min(rows - 1) {
                for cc in ci.saturating_sub(1)..=(ci + 1).min(cols - 1) {
                    let cell = r * cols + cc;
                    for &j in &self.members[self.start[cell] as usize..self.start[cell + 1] as usize] {
                        if j as usize > i && within(p, i, j as usize, skin) {
                            self.row.push(j);
                        }
                    }
                }
            }
            self.row.sort_unstable();
            out.extend(self.row.iter().map(|&j| NeighborPair::new(p, i, j as usize)));
        }
    }
}

fn min_max(v: &[f64]) -> (f64, f64) {
    let lo = v.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = v.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    if lo.is_finite() && hi.is_finite() { (lo, hi) } else { (0.0, 0.0) }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::config::SceneConfig;
    use crate::physics::placement;

    #[test]
    fn grid_finds_exactly_the_all_pairs_set() {
        let mut scene = SceneConfig::default();
        scene.particles.count = 200;
        scene.particles.radius_max = Some(0.015);
        let disks = placement::generate(&scene).unwrap();
        let p = Particles::new(&disks, 1000.0, 1.0);
        let walls = BoxWalls::new(&scene.domain);
        let mut grid = NeighborList::new(BroadPhaseKind::Grid, 0.006);
        let mut brute = NeighborList::new(BroadPhaseKind::AllPairs, 0.006);
        grid.rebuild(&p, &walls);
        brute.rebuild(&p, &walls);
        assert!(!grid.wall_pairs.is_empty());
        assert_eq!(grid.wall_pairs, brute.wall_pairs);
        assert!(!brute.pairs.is_empty());
        assert_eq!(grid.pairs, brute.pairs);
    }

    #[test]
    fn rebuild_keeps_springs_of_surviving_pairs() {
        let pair = |i, j, spring| NeighborPair { i, j, spring, r_star: 0.0, m_star: 0.0 };
        let old = [pair(0, 1, 1.0), pair(0, 3, 2.0), pair(2, 3, 3.0)];
        let mut new = [pair(0, 3, 0.0), pair(1, 2, 0.0), pair(2, 3, 0.0)];
        carry_springs(&old, &mut new);
        let springs: Vec<f64> = new.iter().map(|p| p.spring).collect();
        assert_eq!(springs, [2.0, 0.0, 3.0]);
    }
}

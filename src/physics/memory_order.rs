//! Renumbering the disks of a large scene so that neighbours stay close in memory.
//!
//! The contact stages read both disks of every candidate pair. When the two are far apart in the
//! arrays, those reads miss the caches. Placement numbers disks in strips ([`strips`]), which a
//! vertical deposition in a wide box keeps. A long fall in a tall box mixes the strips, though, and
//! a placement file may come in any order.
//! So before the first step, and at each neighbour-list build, the simulation counts the candidate
//! pairs whose disks are more than [`FAR_PLACES`] places apart. When their share passes
//! [`MemoryOrder::far_share`], in a scene of at least [`MemoryOrder::min_disks`] disks, it numbers
//! the disks afresh in strips at their current positions. Every per-disk array, the integrator's
//! history and the list's contact histories go through the same permutation; outputs (snapshots,
//! contacts, pile measures) are given in the scene's own numbering ([`Numbering`]).
//!
//! The decision reads only the list, which is the same on any number of threads, so results stay
//! the same bits whatever the thread count. A renumbering does change the order in which a disk's
//! contact forces (and the diagnostics' sums over disks) are added up: a run that renumbers
//! differs from one that does not in the last bits, as any change of summation order does.
//! `examples/memory_order.rs` measures what it gains.

use super::contact_record::{Partner, PileContact};

/// Two disks more than this many places apart count as far apart in memory: 512 disks of one
/// array fill 4 KiB, an eighth of a typical first-level data cache.
pub const FAR_PLACES: u32 = 512;

/// When the disks are numbered afresh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MemoryOrder {
    /// Scenes of fewer disks keep their numbering: their arrays fit in the second-level cache.
    pub min_disks: usize,
    /// The share of candidate pairs whose disks are far apart ([`FAR_PLACES`]) above which the
    /// disks are numbered afresh.
    pub far_share: f64,
}

impl MemoryOrder {
    /// Never renumber.
    pub const KEPT: Self = Self { min_disks: usize::MAX, far_share: f64::INFINITY };

    /// Renumber at every build, whatever the scene (a negative share: for tests).
    pub const EVERY_BUILD: Self = Self { min_disks: 0, far_share: -1.0 };

    /// Whether a scene of `disks` disks, `far` of whose `pairs` candidate pairs are far apart, is
    /// numbered afresh after `numbering`: past the limit, and by that much past the share the last
    /// renumbering left (where strips cannot do better, they are not redone at every build).
    pub fn due(&self, disks: usize, far: usize, pairs: usize, numbering: &Numbering) -> bool {
        let past = far as f64 > (self.far_share + numbering.far_share_left) * pairs as f64;
        disks >= self.min_disks && (past || self.far_share < 0.0)
    }
}

impl Default for MemoryOrder {
    /// At 20 000 disks the hot arrays (some 80 bytes a disk) outgrow a 1 MiB second-level cache;
    /// from 2 % far pairs on, renumbering a 100 000-disk pile pays (results/bench/performance.md).
    fn default() -> Self {
        Self { min_disks: 20_000, far_share: 0.02 }
    }
}

/// The order of the disks at `x`, `y` in strips `cell` wide (m) across the longer side of their
/// extent, each strip along the shorter side: the `k`-th disk of the new numbering is disk
/// `order[k]` of the old. Ties keep the old order.
pub fn strip_order(x: &[f64], y: &[f64], cell: f64) -> Vec<u32> {
    let extent = |v: &[f64]| {
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (lo, hi - lo)
    };
    let ((x0, width), (y0, height)) = (extent(x), extent(y));
    strips(x, y, width > height, [x0, y0], cell)
}

/// The order of the disks at `x`, `y` in strips `cell` wide (m) counted from `origin`: columns
/// (each from the bottom up) if `columns`, else rows (each from the left), as in [`strip_order`].
pub fn strips(x: &[f64], y: &[f64], columns: bool, origin: [f64; 2], cell: f64) -> Vec<u32> {
    let strip = |across: f64, origin: f64| ((across - origin) / cell) as u64;
    let key = |k: u32| {
        let k = k as usize;
        if columns { (strip(x[k], origin[0]), y[k]) } else { (strip(y[k], origin[1]), x[k]) }
    };
    let mut order: Vec<u32> = (0..x.len() as u32).collect();
    order.sort_by(|&a, &b| {
        let ((sa, la), (sb, lb)) = (key(a), key(b));
        sa.cmp(&sb).then(la.total_cmp(&lb))
    });
    order
}

/// Puts `column[order[k]]` at place `k` of `column`, through `scratch`.
pub fn gather<T: Copy>(column: &mut Vec<T>, order: &[u32], scratch: &mut Vec<T>) {
    scratch.clear();
    scratch.extend(order.iter().map(|&k| column[k as usize]));
    std::mem::swap(column, scratch);
}

/// For each place of `order` (as [`strip_order`] gives it), the new place of the disk there.
pub fn inverse(order: &[u32]) -> Vec<u32> {
    let mut new_of_old = vec![0; order.len()];
    for (new, &old) in order.iter().enumerate() {
        new_of_old[old as usize] = new as u32;
    }
    new_of_old
}

/// Which disk of the scene each place of the simulation's arrays holds.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Numbering {
    /// The scene's index of the disk at each place; empty while the numbering is the scene's.
    scene_of: Vec<u32>,
    /// The share of candidate pairs far apart right after the last renumbering (0 before any).
    far_share_left: f64,
    /// Renumberings so far.
    renumberings: u32,
}

impl Numbering {
    /// Whether the simulation's numbering is the scene's.
    pub fn is_scene_order(&self) -> bool {
        self.scene_of.is_empty()
    }

    /// How many times the disks were numbered afresh.
    pub fn renumberings(&self) -> u32 {
        self.renumberings
    }

    /// The scene's index of the disk at place `k`.
    pub fn scene_index(&self, k: usize) -> usize {
        self.scene_of.get(k).map_or(k, |&s| s as usize)
    }

    /// The numbering after a disk was added at the end of the arrays: the scene's next disk.
    pub fn add_disk(&mut self) {
        if !self.scene_of.is_empty() {
            self.scene_of.push(self.scene_of.len() as u32);
        }
    }

    /// The numbering after the disks were numbered afresh by `order` (see [`strip_order`]),
    /// which left `far_share_left` of the candidate pairs far apart.
    pub fn renumber(&mut self, order: &[u32], far_share_left: f64) {
        self.far_share_left = far_share_left;
        self.renumberings += 1;
        if self.scene_of.is_empty() {
            self.scene_of = order.to_vec();
        } else {
            let scene_of = order.iter().map(|&k| self.scene_of[k as usize]).collect();
            self.scene_of = scene_of;
        }
    }

    /// The place of each of the scene's disks (the order that puts the simulation's arrays back
    /// in the scene's numbering, for [`gather`]), or `None` while the numbering is the scene's.
    pub fn places(&self) -> Option<Vec<u32>> {
        (!self.is_scene_order()).then(|| inverse(&self.scene_of))
    }

    /// `contacts` (in the simulation's numbering, each pair's smaller place first) in the scene's
    /// numbering and order: each pair from its smaller scene index (the normal reversed where that
    /// is the other disk; its forces and history read the same from either side), pairs first by
    /// their disks, then disk-wall contacts by disk and wall.
    pub fn scene_contacts(&self, contacts: &mut [PileContact]) {
        if self.is_scene_order() {
            return;
        }
        for c in contacts.iter_mut() {
            c.disk = self.scene_index(c.disk);
            if let Partner::Disk(j) = c.partner {
                let j = self.scene_index(j);
                if j < c.disk {
                    (c.disk, c.partner, c.normal) = (j, Partner::Disk(c.disk), c.normal.map(|n| -n));
                } else {
                    c.partner = Partner::Disk(j);
                }
            }
        }
        contacts.sort_unstable_by_key(|c| match c.partner {
            Partner::Disk(j) => (0, c.disk, j),
            Partner::Wall(w) => (1, c.disk, w),
        });
    }
}

super::run_state::persist_fields!(Numbering { scene_of, far_share_left, renumberings });

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_run_across_the_longer_side_and_ties_keep_their_order() {
        // A wide extent: columns 1 wide from x = 0, each from the bottom up.
        let x = [2.5, 0.5, 0.2, 2.1, 0.5, 3.9];
        let y = [0.1, 0.9, 0.5, 0.0, 0.9, 0.3];
        assert_eq!(strip_order(&x, &y, 1.0), [2, 1, 4, 3, 0, 5]);
        // The same disks turned a quarter: rows, each from the left.
        assert_eq!(strip_order(&y, &x, 1.0), [2, 1, 4, 3, 0, 5]);
    }

    #[test]
    fn renumberings_compose_and_undo() {
        let mut numbering = Numbering::default();
        assert_eq!((numbering.scene_index(3), numbering.places()), (3, None));
        let first = [2, 0, 3, 1];
        numbering.renumber(&first, 0.0);
        let second = [3, 2, 1, 0];
        numbering.renumber(&second, 0.0);
        // Place k holds the disk the first order put at place second[k].
        let held: Vec<usize> = (0..4).map(|k| numbering.scene_index(k)).collect();
        assert_eq!((&held[..], numbering.renumberings()), (&[1, 3, 0, 2][..], 2));
        let places = numbering.places().unwrap();
        let mut column = held.clone();
        gather(&mut column, &places, &mut Vec::new());
        assert_eq!(column, [0, 1, 2, 3]);
        assert!((0..4).all(|s| numbering.scene_index(places[s] as usize) == s));
    }

    #[test]
    fn due_only_in_large_scenes_past_the_far_share_and_what_the_last_renumbering_left() {
        let policy = MemoryOrder { min_disks: 100, far_share: 0.1 };
        let mut numbering = Numbering::default();
        assert!(policy.due(100, 11, 100, &numbering));
        assert!(!policy.due(100, 10, 100, &numbering), "at the share, not past it");
        assert!(!policy.due(99, 50, 100, &numbering), "too few disks");
        assert!(!MemoryOrder::KEPT.due(usize::MAX, 1, 1, &numbering));
        assert!(MemoryOrder::EVERY_BUILD.due(1, 0, 0, &numbering));
        numbering.renumber(&[0, 1], 0.3);
        assert!(!policy.due(100, 40, 100, &numbering) && policy.due(100, 41, 100, &numbering));
    }

    #[test]
    fn contacts_come_back_in_the_scene_numbering_and_order() {
        let contact = |disk, partner, nx| PileContact {
            disk,
            partner,
            normal: [nx, 0.5],
            normal_force: disk as f64,
            tangential_force: 0.0,
            friction: 0.0,
            overlap_ratio: 0.0,
            history: (0.0, 0.0),
        };
        let mut numbering = Numbering::default();
        // Places 0, 1, 2 hold the scene's disks 2, 0, 1.
        numbering.renumber(&[2, 0, 1], 0.0);
        let mut contacts =
            [contact(0, Partner::Disk(1), 0.8), contact(1, Partner::Disk(2), 0.6), contact(0, Partner::Wall(3), 1.0)];
        numbering.scene_contacts(&mut contacts);
        let seen: Vec<_> = contacts.iter().map(|c| (c.disk, c.partner, c.normal, c.normal_force)).collect();
        assert_eq!(
            seen,
            [
                (0, Partner::Disk(1), [0.6, 0.5], 1.0),
                (0, Partner::Disk(2), [-0.8, -0.5], 0.0),
                (2, Partner::Wall(3), [1.0, 0.5], 0.0)
            ]
        );
    }
}

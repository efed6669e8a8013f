//! The overlaps of given disks (a placement file's) with each other and with the walls, found
//! through the cell grid, and what they mean for a run: an error beyond `limits.max_overlap_ratio`,
//! a warning beyond `limits.overlap_warning_ratio`.

use crate::physics::CellGrid;
use crate::physics::config::SceneConfig;
use crate::physics::number::short;
use crate::physics::particles::InitialDisk;

/// Overlaps of file disks with each other and with the walls, as fractions of the smaller radius:
/// the worst one and how many there are beyond the scene's error and warning limits.
pub struct Overlaps {
    /// Beyond `limits.max_overlap_ratio` (or a centre outside the box): (worst, count).
    errors: Option<(Overlap, usize)>,
    /// Beyond `limits.overlap_warning_ratio` but not an error: (worst, count).
    warnings: Option<(Overlap, usize)>,
    max_ratio: f64,
    warning_ratio: f64,
    /// The disk pairs examined when the check stopped early (heaped disks), if it did.
    stopped_after: Option<usize>,
}

/// One overlap between disks (0-based rows) or a disk and a wall.
#[derive(Clone, Debug)]
struct Overlap {
    ratio: f64,
    what: String,
}

impl Overlaps {
    /// The overlaps of `disks` in `scene`'s box, against its limits.
    pub fn find(scene: &SceneConfig, disks: &[InitialDisk]) -> Self {
        let limits = &scene.limits;
        let mut found = Self {
            errors: None,
            warnings: None,
            max_ratio: limits.max_overlap_ratio,
            warning_ratio: limits.overlap_warning_ratio,
            stopped_after: None,
        };
        for (i, disk) in disks.iter().enumerate() {
            if let Some(reason) = outside_box(scene, i, disk) {
                found.add(f64::INFINITY, || reason);
            } else {
                for (wall, depth) in wall_depths(scene, disk) {
                    found.add(depth / disk.r, || {
                        format!(
                            "disk {} (x = {}, y = {}, r = {}) crosses the {wall}",
                            i + 1,
                            short(disk.x),
                            short(disk.y),
                            short(disk.r)
                        )
                    });
                }
            }
        }
        let checked = touching_pairs(disks, |i, j| {
            let (a, b) = (&disks[i], &disks[j]);
            let depth = a.r + b.r - (a.x - b.x).hypot(a.y - b.y);
            found.add(depth / a.r.min(b.r), || {
                format!("disks {} and {} (rows {} and {} of the file) overlap", i + 1, j + 1, i + 1, j + 1)
            });
        });
        found.stopped_after = checked.err();
        found
    }

    /// Counts an overlap of `ratio` radii; `what` describes it (made only for a new worst one).
    fn add(&mut self, ratio: f64, what: impl FnOnce() -> String) {
        let slot = if ratio > self.max_ratio {
            &mut self.errors
        } else if ratio > self.warning_ratio {
            &mut self.warnings
        } else {
            return;
        };
        match slot {
            Some((worst, count)) => {
                *count += 1;
                if ratio > worst.ratio {
                    *worst = Overlap { ratio, what: what() };
                }
            }
            None => *slot = Some((Overlap { ratio, what: what() }, 1)),
        }
    }

    /// The worst overlap beyond `limits.max_overlap_ratio`, in words: the run would diverge at t = 0.
    pub fn error(&self) -> Option<String> {
        let (worst, count) = self.errors.as_ref()?;
        let what = if worst.ratio.is_finite() {
            format!(
                "{} by {} radii, beyond limits.max_overlap_ratio = {}: the run would end as diverged at t = 0",
                worst.what,
                short(worst.ratio),
                self.max_ratio
            )
        } else {
            worst.what.clone()
        };
        Some(format!("{what}{}", self.more(*count, "beyond the limit")))
    }

    /// The worst overlap beyond `limits.overlap_warning_ratio` that is no error, in words.
    pub fn warning(&self) -> Option<String> {
        let Some((worst, count)) = self.warnings.as_ref() else {
            let pairs = self.stopped_after.filter(|_| self.errors.is_none())?;
            return Some(format!(
                "the overlap check stopped after {pairs} disk pairs (disks of very different sizes crowd its grid): \
                 overlaps beyond them were not looked for"
            ));
        };
        Some(format!(
            "{} by {} radii, beyond limits.overlap_warning_ratio = {} (Hertz validity): they start pushed apart{}",
            worst.what,
            short(worst.ratio),
            self.warning_ratio,
            self.more(*count, "beyond it")
        ))
    }

    /// `; N overlaps WHERE in all` when there is more than one (`at least`, and why, when the
    /// check stopped early).
    fn more(&self, count: usize, place: &str) -> String {
        match self.stopped_after {
            Some(pairs) => format!(
                "; at least {count} overlaps {place} (the check stopped after {pairs} disk pairs: the disks are heaped)"
            ),
            None if count > 1 => format!("; {count} overlaps {place} in all"),
            None => String::new(),
        }
    }
}

/// A disk whose centre is outside the box, in words.
fn outside_box(scene: &SceneConfig, i: usize, k: &InitialDisk) -> Option<String> {
    let d = &scene.domain;
    let inside = k.x >= 0.0 && k.x <= d.width && k.y >= 0.0 && (!d.lid || k.y <= d.height);
    (!inside).then(|| {
        format!(
            "disk {} (x = {}, y = {}, r = {}) is not inside the box (domain.width = {} m{})",
            i + 1,
            k.x,
            k.y,
            k.r,
            d.width,
            if d.lid { format!(", lid at {} m", d.height) } else { String::new() }
        )
    })
}

/// How deep a disk (centre inside the box) reaches into each wall it crosses (m).
fn wall_depths(scene: &SceneConfig, k: &InitialDisk) -> Vec<(&'static str, f64)> {
    let d = &scene.domain;
    let lid = if d.lid { k.y + k.r - d.height } else { 0.0 };
    [("floor", k.r - k.y), ("left wall", k.r - k.x), ("right wall", k.x + k.r - d.width), ("lid", lid)]
        .into_iter()
        .filter(|(_, depth)| *depth > 0.0)
        .collect()
}

/// Disk pairs a placement check examines at most (per disk, plus a constant): disks that do not
/// overlap have a bounded number of neighbours, so only a placement of heaped disks (every pair
/// overlapping, e.g. 60 000 copies of one disk) reaches it; the check then stops, keeping time O(N).
const PAIRS_EXAMINED_PER_DISK: usize = 256;
/// See [`PAIRS_EXAMINED_PER_DISK`].
const PAIRS_EXAMINED_MIN: usize = 10_000_000;

/// Calls `touching(i, j)` for pairs of disks (indices, `i < j`) that touch or overlap, found through
/// the cell grid; returns `Err(examined)` when it stopped after examining that many pairs (see
/// [`PAIRS_EXAMINED_PER_DISK`]), else `Ok(())`.
fn touching_pairs(disks: &[InitialDisk], mut touching: impl FnMut(usize, usize)) -> Result<(), usize> {
    let (x, y): (Vec<f64>, Vec<f64>) = disks.iter().map(|d| (d.x, d.y)).unzip();
    let largest = disks.iter().map(|d| d.r).filter(|r| r.is_finite()).fold(0.0, f64::max);
    let mut grid = CellGrid::default();
    grid.build(&x, &y, 2.0 * largest);
    let budget = PAIRS_EXAMINED_PER_DISK.saturating_mul(disks.len()).max(PAIRS_EXAMINED_MIN);
    let mut examined = 0;
    for (i, a) in disks.iter().enumerate() {
        for j in grid.neighbours(i) {
            examined += 1;
            if examined > budget {
                return Err(budget);
            }
            let b = &disks[j];
            if (a.x - b.x).hypot(a.y - b.y) < a.r + b.r {
                touching(i, j);
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Disks of radius 1-3 mm at pseudo-random places in a 5 cm square (a small LCG, fixed seed).
    fn random_disks(n: usize) -> Vec<InitialDisk> {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..n)
            .map(|_| InitialDisk {
                x: 0.05 * next(),
                y: 0.05 * next(),
                r: 0.001 + 0.002 * next(),
                ..InitialDisk::default()
            })
            .collect()
    }

    #[test]
    fn touching_pairs_are_the_brute_force_pairs() {
        let disks = random_disks(400);
        let mut found = Vec::new();
        assert_eq!(touching_pairs(&disks, |i, j| found.push((i, j))), Ok(()));
        found.sort_unstable();
        let mut brute = Vec::new();
        for i in 0..disks.len() {
            for j in i + 1..disks.len() {
                let (a, b) = (&disks[i], &disks[j]);
                if (a.x - b.x).hypot(a.y - b.y) < a.r + b.r {
                    brute.push((i, j));
                }
            }
        }
        assert!(brute.len() > 100, "a test with overlaps: {}", brute.len());
        assert_eq!(found, brute);
    }

    #[test]
    fn heaped_disks_stop_the_pair_check_at_its_budget() {
        let disks = vec![InitialDisk { x: 0.1, y: 0.1, r: 0.005, ..InitialDisk::default() }; 20_000];
        let mut found = 0_usize;
        assert_eq!(
            touching_pairs(&disks, |_, _| found += 1),
            Err(PAIRS_EXAMINED_MIN.max(PAIRS_EXAMINED_PER_DISK * 20_000))
        );
        assert_eq!(found, PAIRS_EXAMINED_MIN.max(PAIRS_EXAMINED_PER_DISK * 20_000));
    }
}

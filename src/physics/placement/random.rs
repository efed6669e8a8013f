//! Seeded random sequential placement without overlaps, and the memory order of placed disks.

use super::error::PlacementError;
use crate::physics::config::SceneConfig;
use crate::physics::memory_order::strips;
use crate::physics::particles::InitialDisk;
use crate::physics::rng::Rng;

/// Uniform grid of buckets over the box, for overlap checks during placement.
struct Buckets {
    cell: f64,
    cols: usize,
    rows: usize,
    items: Vec<Vec<usize>>,
}

impl Buckets {
    fn new(width: f64, height: f64, cell: f64) -> Self {
        let cols = ((width / cell).ceil() as usize).clamp(1, 4096);
        let rows = ((height / cell).ceil() as usize).clamp(1, 4096);
        let cell = (width / cols as f64).max(height / rows as f64).max(cell);
        Self { cell, cols, rows, items: vec![Vec::new(); cols * rows] }
    }
    fn index(&self, x: f64, y: f64) -> (usize, usize) {
        let c = ((x / self.cell) as usize).min(self.cols - 1);
        let r = ((y / self.cell) as usize).min(self.rows - 1);
        (c, r)
    }
    fn free(&self, disks: &[InitialDisk], x: f64, y: f64, r: f64) -> bool {
        let (c, row) = self.index(x, y);
        for rr in row.saturating_sub(1)..=(row + 1).min(self.rows - 1) {
            for cc in c.saturating_sub(1)..=(c + 1).min(self.cols - 1) {
                for &k in &self.items[rr * self.cols + cc] {
                    let d = &disks[k];
                    let (dx, dy, rs) = (d.x - x, d.y - y, d.r + r);
                    if dx * dx + dy * dy < rs * rs {
                        return false;
                    }
                }
            }
        }
        true
    }
    fn insert(&mut self, x: f64, y: f64, k: usize) {
        let (c, r) = self.index(x, y);
        self.items[r * self.cols + c].push(k);
    }
}

/// Random sequential placement: each disk tries up to `max_attempts` uniform positions inside the
/// box (below `domain.height`) until it overlaps no earlier disk. The placed disks are then ordered
/// for memory locality (`order_for_locality`); the result depends only on the seed.
pub fn random(scene: &SceneConfig, radii: &[f64], rng: &mut Rng) -> Result<Vec<InitialDisk>, PlacementError> {
    let (w, h) = (scene.domain.width, scene.domain.height);
    let rmax = radii.iter().cloned().fold(0.0, f64::max);
    let mut buckets = Buckets::new(w, h, 2.0 * rmax);
    let mut disks: Vec<InitialDisk> = Vec::with_capacity(radii.len());
    for (k, &r) in radii.iter().enumerate() {
        if 2.0 * r > w || 2.0 * r > h {
            return Err(too_full(scene, radii, k, "a disk is larger than the box"));
        }
        let placed = (0..scene.placement.max_attempts).find_map(|_| {
            let x = rng.range(r, w - r);
            let y = rng.range(r, h - r);
            buckets.free(&disks, x, y, r).then_some((x, y))
        });
        let Some((x, y)) = placed else {
            return Err(too_full(scene, radii, k, "no free spot found"));
        };
        buckets.insert(x, y, k);
        disks.push(InitialDisk { x, y, r, ..Default::default() });
    }
    order_for_locality(&mut disks, w, h, buckets.cell);
    Ok(disks)
}

/// Orders disks in strips of one cell across the box's longer side, along the shorter side within a
/// strip, so that neighbours are close in memory. In a wide box the strips are columns, which a
/// vertical deposition keeps: the order stays good while the disks fall and settle (`cell`: the
/// strips' width, m; the simulation numbers large scenes afresh where it does not: `memory_order`).
pub fn order_for_locality(disks: &mut [InitialDisk], width: f64, height: f64, cell: f64) {
    let (x, y): (Vec<f64>, Vec<f64>) = disks.iter().map(|d| (d.x, d.y)).unzip();
    let placed = disks.to_vec();
    for (disk, k) in disks.iter_mut().zip(strips(&x, &y, width > height, [0.0, 0.0], cell)) {
        *disk = placed[k as usize];
    }
}

fn too_full(scene: &SceneConfig, radii: &[f64], placed: usize, why: &str) -> PlacementError {
    let count = radii.len();
    let area: f64 = radii.iter().map(|r| std::f64::consts::PI * r * r).sum();
    let box_area = scene.domain.width * scene.domain.height;
    PlacementError {
        key: "particles.count".into(),
        reason: format!(
            "random placement fit only {placed} of {count} disks in the {} m x {} m box ({why} after {} tries; \
             requested area fraction {:.2}, random placement jams near 0.5): lower the count, enlarge domain.height \
             or use placement.kind = \"lattice\"",
            scene.domain.width,
            scene.domain.height,
            scene.placement.max_attempts,
            area / box_area
        ),
    }
}

#[cfg(test)]
mod tests {
    use crate::physics::config::SceneConfig;
    use crate::physics::placement::{generate, worst_overlap};

    #[test]
    fn random_placement_is_seeded_and_overlap_free() {
        let scene = SceneConfig::default();
        let a = generate(&scene).unwrap();
        let b = generate(&scene).unwrap();
        assert_eq!(a, b);
        assert_eq!(a.len(), 300);
        assert_eq!(worst_overlap(&a), 0.0);
        let mut other = scene.clone();
        other.placement.seed += 1;
        assert_ne!(generate(&other).unwrap(), a);
    }

    #[test]
    fn overfull_box_says_how_many_fit() {
        let mut scene = SceneConfig::default();
        scene.particles.count = 2000;
        scene.placement.max_attempts = 200;
        let err = generate(&scene).unwrap_err();
        assert_eq!(err.key, "particles.count");
        assert!(err.reason.contains("of 2000 disks"), "{}", err.reason);
    }
}

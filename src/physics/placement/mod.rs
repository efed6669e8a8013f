//! Initial positions and radii: seeded random placement, lattices, dropped piles (sequential
//! deposition), and the lowered start of a random or lattice placement.

mod columns;
mod dropped;
mod error;
mod fill;
mod lattice;
mod lowered;
mod overlaps;
mod pour;
mod random;

pub use dropped::dropped;
pub use error::PlacementError;
pub use fill::Fill;
pub use lattice::lattice;
pub use overlaps::Overlaps;
pub use pour::reference as pour_reference;
pub use random::random;

use super::config::{PlacementKind, SceneConfig};
use super::particles::InitialDisk;
use super::rng::Rng;

/// Radii of all disks: equal, uniform in `[radius, radius_max]` (drawn first from `rng`), or listed.
pub fn radii(scene: &SceneConfig, rng: &mut Rng) -> Vec<f64> {
    let p = &scene.particles;
    match (&p.radii, p.radius_max, &p.size_distribution) {
        (Some(list), _, _) => list.clone(),
        (None, Some(rmax), _) => (0..p.count).map(|_| rng.range(p.radius, rmax)).collect(),
        (None, None, Some(distribution)) => distribution.sample(p.count, rng),
        (None, None, None) => vec![p.radius; p.count],
    }
}

/// Whether the disks a scene starts from vary with `placement.seed`: random and dropped placement
/// draw their positions from it; a lattice only its radii, when they differ from the next seed's
/// (a uniform range or a size distribution); a placement file never.
pub fn draws_from_seed(scene: &SceneConfig) -> bool {
    let drawn = |seed: u64| radii(scene, &mut Rng::new(seed));
    match scene.placement.kind {
        PlacementKind::Random | PlacementKind::Dropped | PlacementKind::Pour => true,
        PlacementKind::Lattice => drawn(scene.placement.seed) != drawn(scene.placement.seed.wrapping_add(1)),
        PlacementKind::File | PlacementKind::Lammps => false,
    }
}

/// Generated initial disks of a scene whose placement is `random`, `lattice` or `dropped`
/// (`random` and `lattice` lowered by `placement.lowered_by`: `lowered::lowered`); of a `pour`,
/// the disks its estimates see ([`pour::reference`]: the simulation pours them).
/// `file` placement is the caller's: it reads the states and passes them to the simulation.
pub fn generate(scene: &SceneConfig) -> Result<Vec<InitialDisk>, PlacementError> {
    let mut rng = Rng::new(scene.placement.seed);
    let radii = radii(scene, &mut rng);
    match scene.placement.kind {
        PlacementKind::Random => lowered::lowered(scene, |band| random(band, &radii, &mut rng)),
        PlacementKind::Lattice => lowered::lowered(scene, |band| lattice(band, &radii)),
        PlacementKind::Dropped => dropped(scene, &radii, &mut rng),
        PlacementKind::Pour => Ok(pour::reference(scene, &radii)),
        PlacementKind::File | PlacementKind::Lammps => Err(PlacementError {
            key: "placement.file".into(),
            reason: "file placement needs the initial states read from the file".into(),
        }),
    }
}

/// The largest overlap between two disks, as a fraction of the sum of their radii (0 when none
/// overlap), by all pairs: for the tests' small placements.
#[cfg(test)]
fn worst_overlap(d: &[InitialDisk]) -> f64 {
    let overlap = |a: &InitialDisk, b: &InitialDisk| (1.0 - (a.x - b.x).hypot(a.y - b.y) / (a.r + b.r)).max(0.0);
    let pairs = (0..d.len()).flat_map(|i| (i + 1..d.len()).map(move |j| (i, j)));
    pairs.map(|(i, j)| overlap(&d[i], &d[j])).fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_random_dropped_and_drawn_radii_vary_with_the_seed() {
        let of_kind = |kind| {
            let mut scene = SceneConfig::default();
            scene.placement.kind = kind;
            draws_from_seed(&scene)
        };
        let kinds = [PlacementKind::Random, PlacementKind::Dropped, PlacementKind::Lattice, PlacementKind::File];
        assert_eq!(kinds.map(of_kind), [true, true, false, false]);
        assert!(of_kind(PlacementKind::Pour), "a pour draws its spots");
        let mut scene = SceneConfig::default();
        scene.placement.kind = PlacementKind::Lattice;
        scene.particles.radius_max = Some(0.012);
        assert!(draws_from_seed(&scene), "a lattice of drawn radii");
        scene.particles.radius_max = Some(scene.particles.radius);
        assert!(!draws_from_seed(&scene), "a range of one radius draws the same radii");
    }
}

//! The lowered start: a placement made between `placement.lowered_by` and `domain.height`, moved
//! down by `lowered_by` and falling at `√(2 |g| lowered_by)`. That is exactly the state the same
//! disks reach after falling `lowered_by` from rest (they fall together, so none touches another
//! or the floor before then): the impacts are those of the higher pour, the free fall's time is not
//! simulated. `validate` asks for gravity straight down and room for the largest disk.

use super::error::PlacementError;
use crate::physics::config::SceneConfig;
use crate::physics::number::{exact, significant};
use crate::physics::particles::InitialDisk;

/// The disks `place` puts in the box below `domain.height − placement.lowered_by` (the band
/// above `lowered_by`, moved down), each falling at the speed of the height it skipped.
pub fn lowered(
    scene: &SceneConfig,
    place: impl FnOnce(&SceneConfig) -> Result<Vec<InitialDisk>, PlacementError>,
) -> Result<Vec<InitialDisk>, PlacementError> {
    let h = scene.placement.lowered_by;
    if h == 0.0 {
        return place(scene);
    }
    let mut band = scene.clone();
    band.domain.height -= h;
    let mut disks = place(&band).map_err(|mut e| {
        e.reason = format!(
            "{} (placement.lowered_by = {} m leaves the disks the box below {} m)",
            e.reason,
            exact(h),
            significant(band.domain.height, 12)
        );
        e
    })?;
    let speed = (2.0 * -scene.gravity[1] * h).sqrt();
    for disk in &mut disks {
        disk.vy = -speed;
    }
    Ok(disks)
}

#[cfg(test)]
mod tests {
    use crate::physics::config::SceneConfig;
    use crate::physics::placement::{generate, worst_overlap};

    #[test]
    fn lowered_disks_are_the_higher_placement_moved_down_and_falling() {
        let mut scene = SceneConfig::default();
        scene.particles.count = 200;
        let mut short = scene.clone();
        scene.placement.lowered_by = 0.2;
        short.domain.height = 0.6 - 0.2;
        let (low, band) = (generate(&scene).unwrap(), generate(&short).unwrap());
        assert_eq!(low.len(), 200);
        assert_eq!(worst_overlap(&low), 0.0);
        let speed = (2.0 * 9.81 * 0.2f64).sqrt();
        for (l, b) in low.iter().zip(&band) {
            assert_eq!((l.x, l.y, l.r, l.vx), (b.x, b.y, b.r, 0.0));
            assert!((l.vy + speed).abs() < 1e-12 * speed, "{}", l.vy);
        }
    }

    #[test]
    fn a_band_too_small_names_the_lowering() {
        let mut scene = SceneConfig::default();
        scene.placement.lowered_by = 0.5;
        scene.placement.max_attempts = 100;
        let err = generate(&scene).unwrap_err();
        assert!(err.reason.contains("of 300 disks"), "{}", err.reason);
        assert!(
            err.reason.contains("placement.lowered_by = 0.5 m leaves the disks the box below 0.1"),
            "{}",
            err.reason
        );
    }
}

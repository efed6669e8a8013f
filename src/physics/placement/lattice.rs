//! Rows of disks filled from the floor up, square or hexagonal.

use super::error::PlacementError;
use crate::physics::config::SceneConfig;
use crate::physics::particles::InitialDisk;

/// Rows of disks from the floor up, spaced by the largest diameter plus `lattice_gap` of it;
/// hexagonal rows are offset by half a spacing and packed closer vertically.
pub fn lattice(scene: &SceneConfig, radii: &[f64]) -> Result<Vec<InitialDisk>, PlacementError> {
    let (w, h) = (scene.domain.width, scene.domain.height);
    let rmax = radii.iter().cloned().fold(0.0, f64::max);
    let spacing = 2.0 * rmax * (1.0 + scene.placement.lattice_gap);
    let hex = scene.placement.lattice_hexagonal;
    let row_height = if hex { spacing * 3f64.sqrt() / 2.0 } else { spacing };
    let margin = rmax * (1.0 + scene.placement.lattice_gap);
    let mut disks = Vec::with_capacity(radii.len());
    let mut row = 0usize;
    while disks.len() < radii.len() {
        let y = margin + row as f64 * row_height;
        let shift = if hex && row % 2 == 1 { 0.5 * spacing } else { 0.0 };
        let per_row = ((w - 2.0 * margin - shift) / spacing).floor() as i64 + 1;
        if y + rmax > h || per_row < 1 {
            return Err(PlacementError {
                key: "particles.count".into(),
                reason: format!(
                    "the lattice fits only {} of {} disks in the {w} m x {h} m box: lower the count, \
                     enlarge the box or reduce placement.lattice_gap",
                    disks.len(),
                    radii.len()
                ),
            });
        }
        for col in 0..per_row as usize {
            if disks.len() == radii.len() {
                break;
            }
            let x = margin + shift + col as f64 * spacing;
            disks.push(InitialDisk { x, y, r: radii[disks.len()], ..Default::default() });
        }
        row += 1;
    }
    Ok(disks)
}

#[cfg(test)]
mod tests {
    use crate::physics::config::{PlacementKind, SceneConfig};
    use crate::physics::placement::{generate, worst_overlap};

    #[test]
    fn lattice_fills_rows_without_overlap() {
        let mut scene = SceneConfig::default();
        scene.placement.kind = PlacementKind::Lattice;
        scene.placement.lattice_hexagonal = true;
        let d = generate(&scene).unwrap();
        assert_eq!(d.len(), 300);
        assert_eq!(worst_overlap(&d), 0.0);
        assert!(d.iter().all(|p| p.x >= p.r && p.x <= 0.4 - p.r && p.y >= p.r));
    }
}

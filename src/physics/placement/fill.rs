//! How full a generated placement got: how high its disks reach, as a share of the box.

use crate::physics::config::SceneConfig;
use crate::physics::particles::InitialDisk;

/// How far up the box a placement's disks reach.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fill {
    /// Number of disks.
    pub count: usize,
    /// The highest disk top (m).
    pub top: f64,
    /// `top` over `domain.height`.
    pub height_fraction: f64,
    /// The disks' area over the box's area below `top` (0 without disks).
    pub area_fraction: f64,
}

impl Fill {
    /// The fill of `disks` in the box of `scene`.
    pub fn of(scene: &SceneConfig, disks: &[InitialDisk]) -> Self {
        let top = disks.iter().map(|d| d.y + d.r).fold(0.0, f64::max);
        let area: f64 = disks.iter().map(|d| std::f64::consts::PI * d.r * d.r).sum();
        let below = scene.domain.width * top;
        Self {
            count: disks.len(),
            top,
            height_fraction: top / scene.domain.height,
            area_fraction: if below > 0.0 { area / below } else { 0.0 },
        }
    }
}

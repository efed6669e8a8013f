//! The box: floor `y = 0`, side walls `x = 0` and `x = width`, optional lid `y = height`.
//!
//! A wall is a half-plane of infinite mass and radius. It is described by its outward unit normal `n`
//! (from a disk inside the box towards the wall) and the plane `n·x = offset`, so a disk of radius
//! `r` at `x` overlaps it by `r − (offset − n·x)`.

use super::config::DomainConfig;

/// One flat wall.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wall {
    /// Outward unit normal (from the box interior to the wall).
    pub normal: [f64; 2],
    /// Plane position: points on the wall satisfy `normal·x = offset`.
    pub offset: f64,
}

impl Wall {
    /// Overlap of a disk of radius `r` centred at `(x, y)` (m); positive when touching.
    #[inline]
    pub fn overlap(&self, x: f64, y: f64, r: f64) -> f64 {
        r - (self.offset - (self.normal[0] * x + self.normal[1] * y))
    }
}

/// The walls of a scene's box (3 or 4).
#[derive(Clone, Debug, PartialEq)]
pub struct BoxWalls {
    /// Floor, left, right, then lid if present.
    pub walls: Vec<Wall>,
    /// Box width (m).
    pub width: f64,
    /// Box height (m).
    pub height: f64,
}

impl BoxWalls {
    /// The box of a domain.
    pub fn new(domain: &DomainConfig) -> Self {
        let mut walls = vec![
            Wall { normal: [0.0, -1.0], offset: 0.0 },
            Wall { normal: [-1.0, 0.0], offset: 0.0 },
            Wall { normal: [1.0, 0.0], offset: domain.width },
        ];
        if domain.lid {
            walls.push(Wall { normal: [0.0, 1.0], offset: domain.height });
        }
        Self { walls, width: domain.width, height: domain.height }
    }

    /// The point of the box (shrunk by `r`) lowest in the potential of gravity `g`.
    pub fn lowest_point(&self, g: [f64; 2], r: f64) -> [f64; 2] {
        let x = if g[0] > 0.0 {
            self.width - r
        } else if g[0] < 0.0 {
            r
        } else {
            0.5 * self.width
        };
        let y = if g[1] > 0.0 { self.height - r } else { r };
        [x, y]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overlaps_of_each_wall() {
        let b = BoxWalls::new(&DomainConfig { width: 1.0, height: 2.0, lid: true });
        let (x, y, r) = (0.05, 1.97, 0.1);
        let o: Vec<f64> = b.walls.iter().map(|w| w.overlap(x, y, r)).collect();
        let expect = [0.1 - 1.97, 0.05, 0.1 - 0.95, 0.07];
        for (a, e) in o.iter().zip(expect) {
            assert!((a - e).abs() < 1e-12, "{o:?}");
        }
    }
}

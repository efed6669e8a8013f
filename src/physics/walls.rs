//! The box: floor `y = 0`, side walls `x = 0` and `x = width` or periodic sides, optional lid
//! `y = height`.
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
    /// Floor, left, right, then lid if present (the sides listed but never touched when periodic,
    /// so that a wall's index names the same wall either way).
    pub walls: Vec<Wall>,
    /// Box width (m).
    pub width: f64,
    /// Box height (m).
    pub height: f64,
    /// Whether the sides are periodic (`domain.periodic_x`).
    pub periodic: bool,
}

/// How the x separation of two disks is measured: directly between side walls, or to the nearest
/// image across periodic sides. Chosen once per step, outside the loops over pairs, so that the
/// walled loops are those of a box without the option.
pub trait Sides: Copy + Send + Sync {
    /// The x separation `dx = x_j − x_i` (m) as the contact sees it.
    fn dx(self, dx: f64) -> f64;
}

/// Side walls: the separation as it is.
#[derive(Clone, Copy, Debug)]
pub struct Walled;

impl Sides for Walled {
    #[inline(always)]
    fn dx(self, dx: f64) -> f64 {
        dx
    }
}

/// Periodic sides `width` apart (m): the separation to the nearest image.
#[derive(Clone, Copy, Debug)]
pub struct Periodic {
    width: f64,
    half: f64,
}

impl Periodic {
    /// Sides `width` apart (m).
    pub fn new(width: f64) -> Self {
        Self { width, half: 0.5 * width }
    }
}

impl Sides for Periodic {
    #[inline(always)]
    fn dx(self, dx: f64) -> f64 {
        if dx > self.half {
            dx - self.width
        } else if dx < -self.half {
            dx + self.width
        } else {
            dx
        }
    }
}

/// Puts every `x` (m) back into `[0, width)`, as periodic sides `width` apart do (NaN stays NaN):
/// one width over in a loop without branches (a step moves a disk less than a width), then, only
/// if some disk was farther out, the rest of the way.
pub fn wrap(x: &mut [f64], width: f64) {
    let mut out = false;
    for x in x.iter_mut() {
        let v = if *x < 0.0 { *x + width } else { *x };
        // Rounding can land a tiny negative x on `width` itself: taken on to 0.
        let v = if v >= width { v - width } else { v };
        out |= v < 0.0 || v >= width;
        *x = v;
    }
    if out {
        for x in x.iter_mut().filter(|x| **x < 0.0 || **x >= width) {
            let wrapped = *x - width * (*x / width).floor();
            *x = if wrapped < width { wrapped } else { 0.0 };
        }
    }
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
        Self { walls, width: domain.width, height: domain.height, periodic: domain.periodic_x }
    }

    /// The walls a disk can touch, with their indices: all but the sides when periodic.
    pub fn touchable(&self) -> impl Iterator<Item = (usize, &Wall)> {
        let periodic = self.periodic;
        self.walls.iter().enumerate().filter(move |(w, _)| !(periodic && matches!(w, 1 | 2)))
    }

    /// The period of the sides (m), if they are periodic.
    pub fn period(&self) -> Option<f64> {
        self.periodic.then_some(self.width)
    }

    /// The x separation `x_j − x_i` of two disks (m) as a contact sees it (see [`Sides`]).
    pub fn dx(&self, dx: f64) -> f64 {
        match self.period() {
            Some(width) => Periodic::new(width).dx(dx),
            None => dx,
        }
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
        let b = BoxWalls::new(&DomainConfig { width: 1.0, height: 2.0, lid: true, periodic_x: false });
        let (x, y, r) = (0.05, 1.97, 0.1);
        let o: Vec<f64> = b.walls.iter().map(|w| w.overlap(x, y, r)).collect();
        let expect = [0.1 - 1.97, 0.05, 0.1 - 0.95, 0.07];
        for (a, e) in o.iter().zip(expect) {
            assert!((a - e).abs() < 1e-12, "{o:?}");
        }
    }

    #[test]
    fn periodic_sides_are_not_touchable_and_measure_to_the_nearest_image() {
        let domain = DomainConfig { width: 1.0, height: 2.0, lid: true, periodic_x: true };
        let b = BoxWalls::new(&domain);
        assert_eq!(b.touchable().map(|(w, _)| w).collect::<Vec<_>>(), [0, 3]);
        assert_eq!(b.dx(0.9), 0.9 - 1.0);
        assert_eq!(b.dx(-0.9), -0.9 + 1.0);
        assert_eq!(b.dx(0.3), 0.3);
        let walled = BoxWalls::new(&DomainConfig { periodic_x: false, ..domain });
        assert_eq!(walled.touchable().count(), 4);
        assert_eq!(walled.dx(0.9), 0.9);
    }

    #[test]
    fn wrap_puts_positions_into_the_box() {
        let mut x = [-0.25, 1.25, 0.5, 1.0, -1e-18, f64::NAN, -2.25, 7.5];
        wrap(&mut x, 1.0);
        assert_eq!([x[0], x[1], x[2], x[3], x[4], x[6], x[7]], [0.75, 0.25, 0.5, 0.0, 0.0, 0.75, 0.5]);
        assert!(x[5].is_nan());
    }
}

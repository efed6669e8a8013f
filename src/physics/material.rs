//! Materials and the effective pair properties of a contact (paper eqs 1-5, Mindlin's G*).

use super::config::{MaterialConfig, SceneConfig};

/// Elastic constants of one material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Elastic {
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Poisson's ratio ν.
    pub poisson_ratio: f64,
    /// Shear modulus G = E / (2(1+ν)) (Pa), eq 2.
    pub shear_modulus: f64,
}

impl Elastic {
    /// From E and either ν or G (ν = 0.3 when neither is given).
    pub fn new(youngs_modulus: f64, poisson_ratio: Option<f64>, shear_modulus: Option<f64>) -> Self {
        let poisson_ratio = match (poisson_ratio, shear_modulus) {
            (Some(nu), _) => nu,
            (None, Some(g)) => youngs_modulus / (2.0 * g) - 1.0,
            (None, None) => 0.3,
        };
        let shear_modulus = shear_modulus.unwrap_or(youngs_modulus / (2.0 * (1.0 + poisson_ratio)));
        Self { youngs_modulus, poisson_ratio, shear_modulus }
    }
}

/// Effective Young's modulus, eq 1: 1/E* = (1-ν₁²)/E₁ + (1-ν₂²)/E₂.
pub fn effective_youngs_modulus(a: &Elastic, b: &Elastic) -> f64 {
    1.0 / ((1.0 - a.poisson_ratio.powi(2)) / a.youngs_modulus + (1.0 - b.poisson_ratio.powi(2)) / b.youngs_modulus)
}

/// Effective shear modulus (Mindlin): 1/G* = (2-ν₁)/G₁ + (2-ν₂)/G₂.
pub fn effective_shear_modulus(a: &Elastic, b: &Elastic) -> f64 {
    1.0 / ((2.0 - a.poisson_ratio) / a.shear_modulus + (2.0 - b.poisson_ratio) / b.shear_modulus)
}

/// The paper's damping factor β from a restitution coefficient e (EDEM's relation):
/// β = −ln e / √(ln²e + π²). Exact for a linear spring-dashpot, approximate for Hertz.
pub fn beta_from_restitution(restitution: f64) -> f64 {
    let l = restitution.ln();
    -l / (l * l + std::f64::consts::PI.powi(2)).sqrt()
}

/// Inverse of [`beta_from_restitution`]: e = exp(−πβ/√(1−β²)) for β < 1, else 0 (overdamped).
pub fn restitution_from_beta(beta: f64) -> f64 {
    if beta >= 1.0 { 0.0 } else { (-std::f64::consts::PI * beta / (1.0 - beta * beta).sqrt()).exp() }
}

/// Properties shared by every contact of one kind (disk-disk or disk-wall).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactMaterial {
    /// Effective Young's modulus E* (Pa).
    pub e_star: f64,
    /// Effective shear modulus G* (Pa).
    pub g_star: f64,
    /// Damping factor β.
    pub beta: f64,
    /// Sliding friction μ.
    pub friction: f64,
    /// Rolling-resistance coefficient: the moment is this times `F_n R` (the material's rolling
    /// friction μ0 through `contact.rolling`'s model).
    pub rolling_friction: f64,
}

/// The two contact materials of a scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Materials {
    /// Disk-disk contacts.
    pub particle: ContactMaterial,
    /// Disk-wall contacts.
    pub wall: ContactMaterial,
    /// Disk density (kg/m³).
    pub density: f64,
}

fn beta_of(beta: Option<f64>, restitution: Option<f64>) -> Option<f64> {
    beta.or(restitution.map(beta_from_restitution))
}

impl Materials {
    /// Builds both contact materials from a (validated) scene.
    pub fn from_scene(scene: &SceneConfig) -> Self {
        let m: &MaterialConfig = &scene.material;
        let w = &scene.wall_material;
        let disk = Elastic::new(m.youngs_modulus, m.poisson_ratio, m.shear_modulus);
        let wall_given_elastic = w.youngs_modulus.is_some() || w.poisson_ratio.is_some() || w.shear_modulus.is_some();
        let wall = if wall_given_elastic {
            let e = w.youngs_modulus.unwrap_or(disk.youngs_modulus);
            let (nu, g) = match (w.poisson_ratio, w.shear_modulus) {
                (None, None) => (Some(disk.poisson_ratio), None),
                other => other,
            };
            Elastic::new(e, nu, g)
        } else {
            disk
        };
        let beta = beta_of(m.beta, m.restitution).unwrap_or_else(|| beta_from_restitution(0.5));
        let particle = ContactMaterial {
            e_star: effective_youngs_modulus(&disk, &disk),
            g_star: effective_shear_modulus(&disk, &disk),
            beta,
            friction: m.friction,
            rolling_friction: scene.contact.rolling_coefficient(m.rolling_friction),
        };
        let wall = ContactMaterial {
            e_star: effective_youngs_modulus(&disk, &wall),
            g_star: effective_shear_modulus(&disk, &wall),
            beta: beta_of(w.beta, w.restitution).unwrap_or(beta),
            friction: w.friction.unwrap_or(m.friction),
            rolling_friction: scene.contact.rolling_coefficient(w.rolling_friction.unwrap_or(m.rolling_friction)),
        };
        Self { particle, wall, density: m.density }
    }

    /// Whether any contact can carry a tangential force or a rolling torque.
    pub fn has_friction(&self) -> bool {
        self.particle.friction > 0.0
            || self.wall.friction > 0.0
            || self.particle.rolling_friction > 0.0
            || self.wall.rolling_friction > 0.0
    }
}

/// Effective radius of a disk pair, eq 3 (a wall has infinite radius: pass `f64::INFINITY`).
#[inline]
pub fn effective_radius(r1: f64, r2: f64) -> f64 {
    if r2.is_infinite() { r1 } else { r1 * r2 / (r1 + r2) }
}

/// Effective mass of a pair, eq 5 (a wall has infinite mass: pass `f64::INFINITY`).
#[inline]
pub fn effective_mass(m1: f64, m2: f64) -> f64 {
    if m2.is_infinite() { m1 } else { m1 * m2 / (m1 + m2) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shear_modulus_gives_poisson_ratio_by_eq_2() {
        let e = Elastic::new(20000.0, None, Some(20000.0));
        assert!((e.poisson_ratio + 0.5).abs() < 1e-12);
        let e = Elastic::new(1e9, Some(0.25), None);
        assert!((e.shear_modulus - 4e8).abs() < 1e-3);
    }

    #[test]
    fn restitution_and_beta_are_inverse() {
        for e in [0.1, 0.3, 0.5, 0.9, 0.99] {
            let b = beta_from_restitution(e);
            assert!((restitution_from_beta(b) - e).abs() < 1e-12, "e={e}");
        }
        assert_eq!(beta_from_restitution(1.0), 0.0);
    }

    #[test]
    fn same_material_pair_halves_plane_strain_modulus() {
        let m = Elastic::new(1e9, Some(0.3), None);
        let es = effective_youngs_modulus(&m, &m);
        assert!((es - 1e9 / (2.0 * 0.91)).abs() < 1e-3);
    }
}

//! [`SceneConfig::validate`]: every impossible value, each named by its dotted key.

use std::collections::HashSet;

use super::{MaterialConfig, PlacementKind, PourConfig, SceneConfig, SizeDistribution, WallMaterialConfig};
use crate::physics::number::{exact, significant};

/// One invalid value: the dotted key path (as in a study file) and why it is wrong.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ConfigIssue {
    /// Dotted key path, e.g. `material.poisson_ratio`.
    pub key: String,
    /// What is wrong, in words.
    pub reason: String,
}

impl std::fmt::Display for ConfigIssue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.key, self.reason)
    }
}

/// Collects issues while validating.
struct Checker(Vec<ConfigIssue>);

impl Checker {
    fn fail(&mut self, key: &str, reason: impl Into<String>) {
        self.0.push(ConfigIssue { key: key.to_string(), reason: reason.into() });
    }
    fn positive(&mut self, key: &str, value: f64) {
        if !(value.is_finite() && value > 0.0) {
            self.fail(key, format!("must be a finite number > 0, got {}", exact(value)));
        }
    }
    fn non_negative(&mut self, key: &str, value: f64) {
        if !(value.is_finite() && value >= 0.0) {
            self.fail(key, format!("must be a finite number >= 0, got {}", exact(value)));
        }
    }
    fn finite(&mut self, key: &str, value: f64) {
        if !value.is_finite() {
            self.fail(key, format!("must be finite, got {}", exact(value)));
        }
    }
    fn poisson(&mut self, key: &str, nu: f64) {
        if !(nu > -1.0 && nu <= 0.5) {
            self.fail(key, format!("Poisson's ratio must lie in (-1, 0.5], got {}", exact(nu)));
        }
    }
    fn restitution(&mut self, key: &str, e: f64) {
        if !(e > 0.0 && e <= 1.0) {
            self.fail(key, format!("restitution must lie in (0, 1], got {}", exact(e)));
        }
    }
    fn exclusive(&mut self, a: &str, a_set: bool, b: &str, b_set: bool) {
        if a_set && b_set {
            self.fail(b, format!("give either {a} or {b}, not both"));
        }
    }
}

/// The keys the particle and the wall material share, as their checks see them: the section they
/// are under and each value given (a wall's missing value follows the particle material's).
struct SharedMaterialKeys {
    section: &'static str,
    youngs_modulus: Option<f64>,
    poisson_ratio: Option<f64>,
    shear_modulus: Option<f64>,
    beta: Option<f64>,
    restitution: Option<f64>,
    friction: Option<f64>,
    rolling_friction: Option<f64>,
}

impl SharedMaterialKeys {
    /// Checks each value given; a shear modulus gives ν with this section's Young's modulus, else
    /// with `youngs_modulus` (the particle material's).
    fn check(&self, c: &mut Checker, youngs_modulus: f64) {
        let key = |name: &str| format!("{}.{name}", self.section);
        if let Some(e) = self.youngs_modulus {
            c.positive(&key("youngs_modulus"), e);
        }
        let (poisson, shear) = (key("poisson_ratio"), key("shear_modulus"));
        c.exclusive(&poisson, self.poisson_ratio.is_some(), &shear, self.shear_modulus.is_some());
        if let Some(nu) = self.poisson_ratio {
            c.poisson(&poisson, nu);
        }
        if let Some(g) = self.shear_modulus {
            c.positive(&shear, g);
            c.poisson(&shear, self.youngs_modulus.unwrap_or(youngs_modulus) / (2.0 * g) - 1.0);
        }
        let (beta, restitution) = (key("beta"), key("restitution"));
        c.exclusive(&beta, self.beta.is_some(), &restitution, self.restitution.is_some());
        if let Some(b) = self.beta {
            c.non_negative(&beta, b);
        }
        if let Some(e) = self.restitution {
            c.restitution(&restitution, e);
        }
        if let Some(f) = self.friction {
            c.non_negative(&key("friction"), f);
        }
        if let Some(f) = self.rolling_friction {
            c.non_negative(&key("rolling_friction"), f);
        }
    }
}

impl MaterialConfig {
    fn shared_keys(&self) -> SharedMaterialKeys {
        SharedMaterialKeys {
            section: "material",
            youngs_modulus: Some(self.youngs_modulus),
            poisson_ratio: self.poisson_ratio,
            shear_modulus: self.shear_modulus,
            beta: self.beta,
            restitution: self.restitution,
            friction: Some(self.friction),
            rolling_friction: Some(self.rolling_friction),
        }
    }
}

impl WallMaterialConfig {
    fn shared_keys(&self) -> SharedMaterialKeys {
        SharedMaterialKeys {
            section: "wall_material",
            youngs_modulus: self.youngs_modulus,
            poisson_ratio: self.poisson_ratio,
            shear_modulus: self.shear_modulus,
            beta: self.beta,
            restitution: self.restitution,
            friction: self.friction,
            rolling_friction: self.rolling_friction,
        }
    }
}

impl SceneConfig {
    /// Checks every value; returns all problems at once, each naming its key path.
    pub fn validate(&self) -> Result<(), Vec<ConfigIssue>> {
        let mut c = Checker(Vec::new());
        self.check_geometry(&mut c);
        self.check_material(&mut c);
        self.check_time(&mut c);
        c.0.extend(stage_issues(self));
        if c.0.is_empty() { Ok(()) } else { Err(c.0) }
    }

    fn check_geometry(&self, c: &mut Checker) {
        let d = &self.domain;
        c.positive("domain.width", d.width);
        c.positive("domain.height", d.height);
        let p = &self.particles;
        if p.count == 0 && !self.placement.kind.reads_file() {
            c.fail("particles.count", "a scene needs at least one disk, got 0");
        }
        c.positive("particles.radius", p.radius);
        c.positive("particles.thickness", p.thickness);
        if let Some(rmax) = p.radius_max
            && !(rmax.is_finite() && rmax >= p.radius)
        {
            c.fail(
                "particles.radius_max",
                format!("must be >= particles.radius ({}), got {}", exact(p.radius), exact(rmax)),
            );
        }
        c.exclusive("particles.radius_max", p.radius_max.is_some(), "particles.radii", p.radii.is_some());
        let distribution = p.size_distribution.is_some();
        c.exclusive("particles.radius_max", p.radius_max.is_some(), "particles.size_distribution", distribution);
        c.exclusive("particles.radii", p.radii.is_some(), "particles.size_distribution", distribution);
        for issue in p.size_distribution.iter().flat_map(SizeDistribution::issues) {
            c.fail(&format!("particles.size_distribution.{}", issue.key), issue.reason);
        }
        if let Some(radii) = &p.radii {
            if radii.len() != p.count {
                c.fail("particles.radii", format!("has {} entries but particles.count is {}", radii.len(), p.count));
            }
            if let Some(bad) = radii.iter().find(|r| !(r.is_finite() && **r > 0.0)) {
                c.fail("particles.radii", format!("every radius must be > 0, found {}", exact(*bad)));
            }
        }
        let largest = self.largest_radius();
        if largest.is_finite() && 2.0 * largest > d.width {
            c.fail(
                "domain.width",
                format!("{} m is narrower than the largest disk diameter {} m", exact(d.width), exact(2.0 * largest)),
            );
        } else if d.periodic_x && largest.is_finite() && 4.0 * largest > d.width {
            c.fail(
                "domain.width",
                format!(
                    "{} m is narrower than two largest disk diameters ({} m): with domain.periodic_x a disk would touch another and its image",
                    exact(d.width),
                    exact(4.0 * largest)
                ),
            );
        }
        if self.placement.kind.reads_file() && self.placement.file.is_none() {
            c.fail("placement.file", "placement.kind = \"file\" or \"lammps\" needs placement.file (a file path)");
        }
        if !self.placement.kind.reads_file() && self.placement.contacts.is_some() {
            c.fail("placement.contacts", "a contact history needs its disks: set placement.kind = \"file\"");
        }
        c.non_negative("placement.lattice_gap", self.placement.lattice_gap);
        if self.placement.max_attempts == 0 {
            c.fail("placement.max_attempts", "must be at least 1");
        }
        self.check_lowering(c, largest);
        self.check_pour(c, largest);
        c.finite("gravity[0]", self.gravity[0]);
        c.finite("gravity[1]", self.gravity[1]);
        if d.periodic_x && self.gravity[0] != 0.0 {
            c.fail(
                "domain.periodic_x",
                format!(
                    "periodic sides need gravity straight down, got gravity[0] = {}: the energy balance counts gravity's work by position, which a disk wrapping around would jump",
                    exact(self.gravity[0])
                ),
            );
        }
        let n = &self.neighbors;
        c.positive("neighbors.skin_ratio", n.skin_ratio);
    }

    /// Dropped placement and a lowered start move disks along −y: both need gravity straight down.
    fn check_lowering(&self, c: &mut Checker, largest: f64) {
        let (p, g) = (&self.placement, self.gravity);
        let down = g[0] == 0.0 && g[1] < 0.0;
        let gravity = format!("gravity = [0, g] with g < 0, got [{}, {}]", exact(g[0]), exact(g[1]));
        if p.kind == PlacementKind::Dropped && !down {
            c.fail(
                "placement.kind",
                format!("dropped placement rests each disk on what lies below it: it needs {gravity}"),
            );
        }
        c.non_negative("placement.lowered_by", p.lowered_by);
        if !p.lowered_by.is_finite() || p.lowered_by <= 0.0 {
            return;
        }
        let room = self.domain.height - p.lowered_by;
        if !matches!(p.kind, PlacementKind::Random | PlacementKind::Lattice) {
            c.fail(
                "placement.lowered_by",
                "lowers a random or lattice placement: dropped disks start at rest on the pile, file disks with their own velocities",
            );
        } else if !down {
            c.fail("placement.lowered_by", format!("lowers the disks along gravity straight down: it needs {gravity}"));
        } else if largest.is_finite() && room < 2.0 * largest {
            c.fail(
                "placement.lowered_by",
                format!(
                    "{} m leaves {} m of domain.height = {} m for the disks, less than the largest diameter {} m",
                    exact(p.lowered_by),
                    significant(room, 6),
                    exact(self.domain.height),
                    exact(2.0 * largest)
                ),
            );
        }
    }

    /// A pour needs one rate and an inlet inside the box that holds its largest disk.
    fn check_pour(&self, c: &mut Checker, largest: f64) {
        let (pour, d) = (&self.placement.pour, &self.domain);
        if let Some(rate) = pour.rate {
            c.positive("placement.pour.rate", rate);
        }
        if let Some(rate) = pour.mass_rate {
            c.positive("placement.pour.mass_rate", rate);
        }
        c.exclusive("placement.pour.rate", pour.rate.is_some(), "placement.pour.mass_rate", pour.mass_rate.is_some());
        c.finite("placement.pour.velocity[0]", pour.velocity[0]);
        c.finite("placement.pour.velocity[1]", pour.velocity[1]);
        c.non_negative("placement.pour.velocity_spread", pour.velocity_spread);
        if self.placement.kind != PlacementKind::Pour {
            if *pour != PourConfig::default() {
                c.fail("placement.pour", "sets a pour: it needs placement.kind = \"pour\"");
            }
            return;
        }
        if pour.rate.is_none() && pour.mass_rate.is_none() {
            c.fail("placement.pour.rate", "a pour needs placement.pour.rate or placement.pour.mass_rate");
        }
        if !largest.is_finite() {
            return;
        }
        let [x0, x1, y0, y1] = pour.inlet(d.width, d.height, largest);
        let sides =
            [("x_min", x0, 0.0, x1), ("x_max", x1, x0, d.width), ("y_min", y0, 0.0, y1), ("y_max", y1, y0, d.height)];
        for (key, value, low, high) in sides {
            if !(value.is_finite() && value >= low && value <= high) {
                let range = format!("[{}, {}]", significant(low, 6), significant(high, 6));
                c.fail(
                    &format!("placement.pour.{key}"),
                    format!("must lie in {range} (the box and the inlet's other side), got {}", exact(value)),
                );
            }
        }
        let room = (x1 - x0).min(y1 - y0);
        if room.is_finite() && room < 2.0 * largest {
            c.fail(
                "placement.pour",
                format!(
                    "the inlet [{}, {}] x [{}, {}] m is narrower than the largest disk diameter {} m",
                    significant(x0, 6),
                    significant(x1, 6),
                    significant(y0, 6),
                    significant(y1, 6),
                    exact(2.0 * largest)
                ),
            );
        }
    }

    fn check_material(&self, c: &mut Checker) {
        let m = &self.material;
        c.positive("material.density", m.density);
        m.shared_keys().check(c, m.youngs_modulus);
        self.wall_material.shared_keys().check(c, m.youngs_modulus);
        for (key, reason) in self.contact.problems() {
            c.fail(&key, reason);
        }
    }

    fn check_time(&self, c: &mut Checker) {
        let i = &self.integrator;
        if let Some(dt) = i.time_step {
            c.positive("integrator.time_step", dt);
        }
        for (key, fraction) in [
            ("integrator.contact_time_fraction", i.contact_time_fraction),
            ("integrator.rayleigh_fraction", i.rayleigh_fraction),
        ] {
            if let Some(f) = fraction
                && !(f.is_finite() && f > 0.0 && f <= 1.0)
            {
                c.fail(key, format!("must lie in (0, 1], got {}", exact(f)));
            }
            c.exclusive("integrator.time_step", i.time_step.is_some(), key, fraction.is_some());
        }
        c.exclusive(
            "integrator.contact_time_fraction",
            i.contact_time_fraction.is_some(),
            "integrator.rayleigh_fraction",
            i.rayleigh_fraction.is_some(),
        );
        let d = &self.damping;
        if !(d.local.is_finite() && (0.0..1.0).contains(&d.local)) {
            c.fail("damping.local", format!("must lie in [0, 1), got {}", exact(d.local)));
        }
        c.non_negative("damping.viscous", d.viscous);
        let r = &self.run;
        c.positive("run.duration", r.duration);
        c.positive("run.sample_interval", r.sample_interval);
        if let Some(i) = r.frame_interval {
            c.positive("run.frame_interval", i);
        }
        if let Some(t) = r.frame_times.iter().find(|t| !(t.is_finite() && **t >= 0.0)) {
            c.fail("run.frame_times", format!("frame times must be >= 0, found {}", exact(*t)));
        }
        let dt = i.fixed_time_step().unwrap_or(f64::INFINITY);
        let steps = r.duration / dt;
        // (A step or duration refused above is not counted again.)
        if dt > 0.0 && r.duration.is_finite() && steps > 1e12 {
            c.fail("run.duration", format!("needs {steps:.3e} steps of integrator.time_step; at most 1e12"));
        }
        let s = &self.settle;
        c.positive("settle.ubf_threshold", s.ubf_threshold);
        c.non_negative("settle.hold_time", s.hold_time);
        if let Some(k) = s.kinetic_energy_threshold {
            c.positive("settle.kinetic_energy_threshold", k);
        }
        let l = &self.limits;
        c.positive("limits.max_overlap_ratio", l.max_overlap_ratio);
        c.positive("limits.overlap_warning_ratio", l.overlap_warning_ratio);
        c.positive("limits.energy_growth_ratio", l.energy_growth_ratio);
        c.positive("limits.energy_balance_tolerance", l.energy_balance_tolerance);
        c.positive("limits.contact_time_fraction", l.contact_time_fraction);
        c.positive("limits.damping_rate_fraction", l.damping_rate_fraction);
    }
}

/// Every problem of `scene`'s stages, each naming its key as a study file writes it
/// (`stages.NAME.damping.local`; `stages[K]` for a stage without a usable name).
fn stage_issues(scene: &SceneConfig) -> Vec<ConfigIssue> {
    let mut issues = Vec::new();
    let mut names = HashSet::new();
    for (k, stage) in scene.stages.iter().enumerate() {
        let bare =
            !stage.name.is_empty() && stage.name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
        let label = if bare { format!("stages.{}", stage.name) } else { format!("stages[{k}]") };
        let mut fail = |key: &str, reason: String| {
            let key = if key.is_empty() { label.clone() } else { format!("{label}.{key}") };
            issues.push(ConfigIssue { key, reason });
        };
        if !bare {
            fail("name", format!("a stage needs a name of letters, digits, _ or - (got {:?})", stage.name));
        } else if !names.insert(stage.name.as_str()) {
            fail("name", format!("two stages are named {:?}", stage.name));
        }
        for (key, reason) in stage.until.problems() {
            fail(&if key.is_empty() { "until".to_string() } else { format!("until.{key}") }, reason);
        }
        let set = stage.keys();
        for issue in scene.in_stage(stage).validate().err().unwrap_or_default() {
            // Too many steps of the stage's own time step: that step is the key at fault.
            let step = "integrator.time_step";
            let key = if issue.key == "run.duration" && set.contains(&step) { step } else { issue.key.as_str() };
            if set.contains(&key) {
                fail(key, issue.reason);
            }
        }
    }
    issues
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The issues of a scene given as TOML, each as text with `wall_material.` read as `material.`.
    fn issues(text: &str) -> Vec<String> {
        let scene: SceneConfig = toml::from_str(text).expect("a scene");
        let issues = scene.validate().err().unwrap_or_default();
        issues.iter().map(|i| i.to_string().replace("wall_material.", "material.")).collect()
    }

    #[test]
    fn the_particle_and_the_wall_material_refuse_the_same_values_alike() {
        let cases = [
            "youngs_modulus = -1",
            "poisson_ratio = 0.7",
            "shear_modulus = -5",
            "shear_modulus = 1e3\npoisson_ratio = 0.2",
            "beta = -1",
            "restitution = 2",
            "beta = 0.1\nrestitution = 0",
            "friction = nan",
            "rolling_friction = -1",
        ];
        for case in cases {
            let particle = issues(&format!("[material]\n{case}\n"));
            assert!(!particle.is_empty(), "{case}");
            assert_eq!(issues(&format!("[wall_material]\n{case}\n")), particle, "{case}");
        }
        assert_eq!(
            issues("[material]\nbeta = 0.1\nrestitution = 0\n"),
            [
                "material.restitution: give either material.beta or material.restitution, not both",
                "material.restitution: restitution must lie in (0, 1], got 0"
            ]
        );
    }
}

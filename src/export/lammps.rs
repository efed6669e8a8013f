//! LAMMPS: per state, a data file for `atom_style sphere` (`units si`, `dimension 2`) and an input
//! script that continues the pile in LAMMPS.
//!
//! The data file: one atom per disk with its diameter, a density giving the disk's mass, position
//! (z = 0), velocity and angular velocity; the box is the scene's (x from the left to the right wall,
//! or across the period of periodic sides, y from the floor to the lid or the pile's top) with a thin
//! z slab, as LAMMPS asks of 2D systems.
//! `atom_style sphere` has no rotation angle (LAMMPS integrates none for spheres), so the disks'
//! angles are not in the file.
//!
//! The input script (`<run>_<state>.in`, run as `lmp -in <run>_<state>.in [-var steps N]`): 2D,
//! `pair_style granular` with the run's law and material where LAMMPS has one (Hertz-Mindlin as
//! `hertz/material` + `mindlin`; any other law as a linear spring-dashpot at its loading stiffness),
//! the box walls as `fix wall/gran` (periodic sides as LAMMPS's periodic x boundary, `boundary p fm
//! p`), gravity, the run's time step, thermo output with the pile's height. Its header names everything of the run LAMMPS does not express and what stands in for it.

use std::f64::consts::PI;
use std::io::Write;
use std::path::Path;

use super::{Format, RunToExport, State, WriteError};
use crate::physics::SceneConfig;
use crate::physics::config::IntegratorKind;
use crate::physics::contact::{Coefficients, LawVisitor, NormalKind, PairProperties, RegisteredLaw};
use crate::physics::material::{ContactMaterial, Materials, effective_mass, restitution_from_beta};
use crate::physics::quantity;
use crate::physics::record::Snapshot;

/// The format's row of [`super::FORMATS`].
pub const FORMAT: Format = Format {
    name: "lammps",
    description: "LAMMPS: a data file for atom_style sphere (units si, dimension 2) and an input script that \
                  continues the pile (pair_style granular, walls, gravity, the run's time step)",
    write_run,
};

/// Steps the input script runs unless `-var steps N` says otherwise.
pub const DEFAULT_STEPS: u64 = 10_000;

/// Writes each state's `<run>_<label>.data` and `<run>_<label>.in` into `folder`.
fn write_run(folder: &Path, export: &RunToExport, states: &[State]) -> Result<(), WriteError> {
    let scene = &export.run.scene;
    let time_step = time_step(export);
    for state in states {
        let stem = format!("{}_{}", state.run, state.label);
        super::write_file(folder, &format!("{stem}.data"), |out| data_file(out, scene, state))?;
        let input = input_script(scene, state, time_step);
        super::write_file(folder, &format!("{stem}.in"), |out| out.write_all(input.as_bytes()))?;
    }
    Ok(())
}

/// The time step the run used (its `time_step` column), else the scene's resolved one.
fn time_step(export: &RunToExport) -> f64 {
    let stored = quantity::final_value_declarations()
        .position(|q| q.name == "time_step")
        .map(|k| export.row.final_values[k])
        .filter(|dt| dt.is_finite() && *dt > 0.0);
    stored.unwrap_or_else(|| crate::physics::scene_time_step(&export.run.scene, None).dt)
}

/// The top of the pile (m): the highest disk top, at least the box height.
fn box_top(scene: &SceneConfig, s: &Snapshot) -> f64 {
    s.y.iter().zip(&s.r).map(|(y, r)| y + r).fold(scene.domain.height, f64::max)
}

fn data_file(out: &mut dyn Write, scene: &SceneConfig, state: &State) -> std::io::Result<()> {
    let s = state.snapshot;
    let r_max = s.r.iter().copied().fold(0.0, f64::max);
    let thickness = scene.particles.thickness;
    writeln!(
        out,
        "LAMMPS data file (atom_style sphere, units si, dimension 2) from demsweep: run {} at t = {} s",
        state.run, s.time
    )?;
    writeln!(out, "\n{} atoms\n1 atom types\n", s.x.len())?;
    writeln!(out, "0 {} xlo xhi", scene.domain.width)?;
    writeln!(out, "0 {} ylo yhi", box_top(scene, s))?;
    writeln!(out, "{} {} zlo zhi", -r_max, r_max)?;
    // LAMMPS sets a sphere's mass as density·(4/3)πR³: the density below gives each disk its
    // demsweep mass ρ·πR²·h.
    writeln!(out, "\nAtoms # sphere\n")?;
    for i in 0..s.x.len() {
        let r = s.r[i];
        let density = scene.material.density * PI * r * r * thickness / (4.0 / 3.0 * PI * r * r * r);
        writeln!(out, "{} 1 {} {density} {} {} 0", i + 1, 2.0 * r, s.x[i], s.y[i])?;
    }
    writeln!(out, "\nVelocities\n")?;
    for i in 0..s.x.len() {
        writeln!(out, "{} {} {} 0 0 0 {}", i + 1, s.vx[i], s.vy[i], s.omega[i])?;
    }
    Ok(())
}

/// A typical disk of the state: mean radius and mean mass.
struct Typical {
    radius: f64,
    mass: f64,
}

impl Typical {
    fn of(scene: &SceneConfig, s: &Snapshot) -> Self {
        let n = s.r.len().max(1) as f64;
        let radius = s.r.iter().sum::<f64>() / n;
        let mass = s.r.iter().map(|r| scene.material.density * PI * r * r * scene.particles.thickness).sum::<f64>() / n;
        Self { radius, mass }
    }

    /// The pair properties of two typical disks (`wall`: a typical disk against a wall).
    fn pair(&self, material: &ContactMaterial, wall: bool) -> PairProperties {
        let (r_star, m_star) =
            if wall { (self.radius, self.mass) } else { (self.radius / 2.0, effective_mass(self.mass, self.mass)) };
        PairProperties { e_star: material.e_star, g_star: material.g_star, r_star, m_star, beta: material.beta }
    }
}

/// The law's coefficients when loaded to 1 % of R* for a pair, and that overlap.
struct Loading<'a>(&'a PairProperties);

impl LawVisitor for Loading<'_> {
    type Output = (Coefficients, f64);
    fn visit<L: RegisteredLaw>(self, law: &L) -> Self::Output {
        let overlap = 0.01 * self.0.r_star;
        (law.loading_coefficients(self.0, overlap), overlap)
    }
}

/// The `pair_coeff` / `fix wall/gran` model arguments of one kind of contact, and what they leave out.
fn granular_model(
    scene: &SceneConfig,
    material: &ContactMaterial,
    typical: &Typical,
    wall: bool,
    secant: Option<f64>,
    notes: &mut Vec<String>,
) -> String {
    let pair = typical.pair(material, wall);
    let (loading, overlap) = scene.contact.dispatch(Loading(&pair));
    let law = scene.contact.law_name();
    let what = if wall { "disk-wall" } else { "disk-disk" };
    let tangential_ratio = loading.tangential_damping / loading.normal_damping;
    if law == "hertz_mindlin" {
        // LAMMPS mixes a pair's material with itself, E_eff = E / (2 (1 − ν²)), and a wall's as
        // E_eff = E / (2 (1 − ν)): the E below gives the run's E*, the ν the run's G*/E* (LAMMPS's
        // Mindlin G_eff of that E and ν).
        let nu = poisson_for(material);
        let modulus = if wall { 2.0 * (1.0 - nu) } else { 2.0 * (1.0 - nu * nu) } * material.e_star;
        if wall {
            notes.push(format!(
                "disk-wall stiffness: LAMMPS 29 Sep 2021 mixes a wall's modulus as E / (2 (1 − ν)) (measured); the \
                 wall E = {modulus} Pa below gives the run's E* = {} Pa there. A LAMMPS that mixes it as E / (2 (1 − ν²)) \
                 makes the walls {}x stiffer",
                material.e_star,
                1.0 + nu
            ));
        }
        let restitution = restitution_from_beta(material.beta);
        notes.push(format!(
            "{what} damping: demsweep's 2√(5/6) β √(S_n m*) with β = {} is written as Tsuji's damping with the \
             restitution it gives, e = {restitution} (the same restitution, a slightly different law)",
            material.beta
        ));
        format!(
            "hertz/material {modulus} {restitution} {nu} tangential mindlin NULL {tangential_ratio} {} damping tsuji",
            material.friction
        )
    } else {
        let mut stiffness = loading.normal_force / overlap;
        if scene.contact.normal_kind() != NormalKind::Linear {
            // The state's own secant stiffness keeps the pile at rest as it is (a plastic law's
            // overlaps are larger than its loading stiffness would hold).
            let why = match secant {
                Some(k) => {
                    stiffness = k;
                    "the state's secant stiffness (its contacts' summed normal force over their summed overlap)"
                }
                None => "its loading stiffness (the state has no such contacts)",
            };
            notes.push(format!(
                "{what} contacts: LAMMPS has no `{law}` law; written as a linear spring-dashpot at {why}, \
                 {stiffness} N/m (its loading and unloading branches and the energy they dissipate are not expressed)"
            ));
        }
        notes.push(format!(
            "{what} damping: the dashpot {} N·s/m of a typical pair (mean radius, mean mass) is written as \
             LAMMPS's mass-proportional damping; pairs of other sizes are damped in proportion to their mass \
             instead of its square root",
            loading.normal_damping
        ));
        format!(
            "hooke {stiffness} {} tangential linear_history {} {tangential_ratio} {} damping mass_velocity",
            loading.normal_damping / pair.m_star,
            loading.tangential_stiffness,
            material.friction
        )
    }
}

/// The summed normal force over the summed overlap of the state's disk-disk (or disk-wall) contacts
/// (N/m); `None` without such contacts.
fn secant(s: &Snapshot, wall: bool) -> Option<f64> {
    let c = &s.contacts;
    let chosen = (0..c.len()).filter(|&k| (c.second[k] < 0) == wall && c.overlap[k] > 0.0);
    let (force, overlap) = chosen.fold((0.0, 0.0), |(f, d), k| (f + c.normal_force[k], d + c.overlap[k]));
    (overlap > 0.0 && force > 0.0).then(|| force / overlap)
}

/// The Poisson's ratio that gives LAMMPS's Mindlin G_eff = E_eff · 2(1 − ν²) / (4 (2 − ν)(1 + ν))
/// the run's G*/E*: solved by bisection on (−1, 0.5] (G*/E* falls as ν rises).
fn poisson_for(material: &ContactMaterial) -> f64 {
    let target = material.g_star / material.e_star;
    let ratio = |nu: f64| (1.0 - nu * nu) / (2.0 * (2.0 - nu) * (1.0 + nu));
    let (mut low, mut high) = (-0.999, 0.5);
    for _ in 0..100 {
        let mid = 0.5 * (low + high);
        if ratio(mid) > target { low = mid } else { high = mid }
    }
    0.5 * (low + high)
}

/// The input script of one state (see the module doc).
fn input_script(scene: &SceneConfig, state: &State, time_step: f64) -> String {
    let s = state.snapshot;
    let materials = Materials::from_scene(scene);
    let typical = Typical::of(scene, s);
    let mut notes = Vec::new();
    let pair = granular_model(scene, &materials.particle, &typical, false, secant(s, false), &mut notes);
    let wall = granular_model(scene, &materials.wall, &typical, true, secant(s, true), &mut notes);
    let r_max = s.r.iter().copied().fold(0.0, f64::max);
    let skin = scene.neighbors.skin_ratio * r_max;
    let [gx, gy] = scene.gravity;
    let g = gx.hypot(gy);
    let mut fixes = format!(
        "fix integrate all nve/sphere disc\nfix plane all enforce2d\n\
         fix floor all wall/gran granular {wall} yplane 0 {}\n",
        if scene.domain.lid { scene.domain.height.to_string() } else { "NULL".into() },
    );
    if !scene.domain.periodic_x {
        fixes.push_str(&format!("fix sides all wall/gran granular {wall} xplane 0 {}\n", scene.domain.width));
    }
    let x_boundary = if scene.domain.periodic_x { "p" } else { "f" };
    if g > 0.0 {
        fixes.push_str(&format!("fix weight all gravity {g} vector {} {} 0\n", gx / g, gy / g));
    }
    if scene.damping.viscous > 0.0 {
        let gamma = scene.damping.viscous * typical.mass;
        fixes.push_str(&format!("fix drag all viscous {gamma}\n"));
        notes.push(format!(
            "viscous damping {} 1/s (damping.viscous, mass-proportional) as LAMMPS's fix viscous {gamma} N·s/m, \
             the rate times the mean disk mass, and without its torque part",
            scene.damping.viscous
        ));
    }
    notes.extend(unexpressed(scene));
    notes.push(format!(
        "time: LAMMPS starts at step 0; the state is demsweep's at t = {} s, velocities and spins included, \
         without the contacts' history (tangential springs start from zero)",
        s.time
    ));
    let header: String = notes.iter().map(|n| format!("#   - {n}\n")).collect();
    let stem = format!("{}_{}", state.run, state.label);
    format!(
        "# LAMMPS input from demsweep: continues run {run} from its state `{label}` (t = {time} s).\n\
         #   lmp -in {stem}.in                    (runs {DEFAULT_STEPS} steps)\n\
         #   lmp -var steps 50000 -in {stem}.in   (or as many as you like)\n\
         # Written as the run had it: {law} contacts between disks of thickness {thickness} m (masses ρπR²h in the \
         data file), material and walls, gravity, 2D, time step {time_step} s.\n\
         # What LAMMPS cannot express as demsweep ran it, and what stands in for it:\n{header}\
         dimension 2\nunits si\natom_style sphere\nboundary {x_boundary} fm p\ncomm_modify vel yes\n\
         read_data {stem}.data\n\
         neighbor {skin} bin\nneigh_modify delay 0\n\
         pair_style granular\npair_coeff * * {pair}\n\
         {fixes}\
         timestep {time_step}\n\
         compute radius all property/atom radius\nvariable top atom y+c_radius\n\
         compute pile_height all reduce max v_top\n\
         thermo_style custom step time atoms ke c_pile_height\nthermo_modify norm no\nthermo 1000\n\
         variable steps index {DEFAULT_STEPS}\nrun ${{steps}}\n",
        run = state.run,
        label = state.label,
        time = s.time,
        law = scene.contact.law_name(),
        thickness = scene.particles.thickness,
    )
}

/// What of the scene has no counterpart in the script at all.
fn unexpressed(scene: &SceneConfig) -> Vec<String> {
    let mut notes = Vec::new();
    if scene.integrator.scheme == IntegratorKind::AdamsBashforthMoulton {
        notes.push(
            "the integrator: the run used the paper's Adams-Bashforth/Adams-Moulton scheme; LAMMPS integrates with \
             velocity Verlet (fix nve/sphere)"
                .to_string(),
        );
    }
    if scene.damping.local > 0.0 {
        notes.push(format!(
            "Cundall's local damping (damping.local = {}) has no LAMMPS fix: left out",
            scene.damping.local
        ));
    }
    let rolling =
        scene.material.rolling_friction > 0.0 || scene.wall_material.rolling_friction.is_some_and(|r| r > 0.0);
    if rolling {
        notes.push(
            "rolling friction (EDEM's constant directional torque μ0 F_n R) is not LAMMPS's rolling model: left out"
                .to_string(),
        );
    }
    if !scene.contact.allow_tension {
        notes.push("demsweep clamps the normal force at zero (no tension from damping); LAMMPS does not".to_string());
    }
    notes
}

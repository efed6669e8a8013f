//! LAMMPS data files for `atom_style sphere` (`units si`, `dimension 2`): one atom per disk with its
//! diameter, a density giving the disk's mass, position (z = 0), velocity and angular velocity; the
//! box is the scene's (x from the left to the right wall, y from the floor to the lid or the pile's
//! top) with a thin z slab, as LAMMPS asks of 2D systems. `atom_style sphere` has no rotation angle
//! (LAMMPS integrates none for spheres), so the disks' angles are not in the file.

use std::f64::consts::PI;
use std::io::Write;
use std::path::Path;

use super::State;
use crate::physics::SceneConfig;

/// Writes `<run>_<label>.data` into `folder`.
pub fn write(folder: &Path, scene: &SceneConfig, state: &State) -> Result<(), String> {
    let s = state.snapshot;
    let r_max = s.r.iter().copied().fold(0.0, f64::max);
    let top = s.y.iter().zip(&s.r).map(|(y, r)| y + r).fold(scene.domain.height, f64::max);
    let thickness = scene.particles.thickness;
    super::write_file(folder, &format!("{}_{}.data", state.run, state.label), |out: &mut dyn Write| {
        writeln!(
            out,
            "LAMMPS data file (atom_style sphere, units si, dimension 2) from demsweep: run {} at t = {} s",
            state.run, s.time
        )?;
        writeln!(out, "\n{} atoms\n1 atom types\n", s.x.len())?;
        writeln!(out, "0 {} xlo xhi", scene.domain.width)?;
        writeln!(out, "0 {top} ylo yhi")?;
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
    })
}

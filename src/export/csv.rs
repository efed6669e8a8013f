//! Placement CSV: one row per disk, `id,x,y,r,vx,vy,omega,contact_force` (SI units), the columns
//! `placement.kind = "file"` reads (it skips `id` and `contact_force`, which are there for the reader).

use std::io::Write;
use std::path::Path;

use super::State;

/// The header line.
pub const HEADER: &str = "id,x,y,r,vx,vy,omega,contact_force";

/// Writes `<run>_<label>.csv` into `folder`.
pub fn write(folder: &Path, state: &State) -> Result<(), String> {
    let s = state.snapshot;
    super::write_file(folder, &format!("{}_{}.csv", state.run, state.label), |out: &mut dyn Write| {
        writeln!(
            out,
            "# demsweep: run {} at t = {} s; m, m/s, rad/s, N (contact_force: sum of |F| on the disk)",
            state.run, s.time
        )?;
        writeln!(out, "{HEADER}")?;
        for i in 0..s.x.len() {
            writeln!(
                out,
                "{i},{},{},{},{},{},{},{}",
                s.x[i], s.y[i], s.r[i], s.vx[i], s.vy[i], s.omega[i], s.contact_force[i]
            )?;
        }
        Ok(())
    })
}

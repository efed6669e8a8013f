//! Placement CSV: one row per disk, `id,x,y,r,vx,vy,omega,angle,contact_force` (SI units), the
//! columns `placement.kind = "file"` reads (it skips `id` and `contact_force`, which are there for the
//! reader); and beside it the contacts' history, one row per contact,
//! `first,second,tangential_spring,law_state`, which `placement.contacts` reads.

use std::io::Write;
use std::path::Path;

use super::State;

/// The header line of the disks' file.
pub const HEADER: &str = "id,x,y,r,vx,vy,omega,angle,contact_force";

/// The header line of the contacts' file.
pub const CONTACTS_HEADER: &str = "first,second,tangential_spring,law_state";

/// Writes `<run>_<label>.csv` (the disks) and `<run>_<label>_contacts.csv` into `folder`.
pub fn write(folder: &Path, state: &State) -> Result<(), String> {
    let s = state.snapshot;
    super::write_file(folder, &format!("{}_{}.csv", state.run, state.label), |out: &mut dyn Write| {
        writeln!(
            out,
            "# demsweep: run {} at t = {} s; m, m/s, rad/s, rad, N (contact_force: sum of |F| on the disk)",
            state.run, s.time
        )?;
        writeln!(out, "{HEADER}")?;
        for i in 0..s.x.len() {
            let (x, y, r, vx, vy) = (s.x[i], s.y[i], s.r[i], s.vx[i], s.vy[i]);
            writeln!(out, "{i},{x},{y},{r},{vx},{vy},{},{},{}", s.omega[i], s.angle[i], s.contact_force[i])?;
        }
        Ok(())
    })?;
    let c = &s.contacts;
    super::write_file(folder, &format!("{}_{}_contacts.csv", state.run, state.label), |out: &mut dyn Write| {
        writeln!(
            out,
            "# demsweep: contacts of run {} at t = {} s; first, second: disk ids (second < 0: wall -1 floor, -2 left, \
             -3 right, -4 lid); tangential_spring: m; law_state: the contact law's state (hysteretic_linear: \
             largest overlap, m)",
            state.run, s.time
        )?;
        writeln!(out, "{CONTACTS_HEADER}")?;
        for k in 0..c.len() {
            writeln!(out, "{},{},{},{}", c.first[k], c.second[k], c.tangential_spring[k], c.law_state[k])?;
        }
        Ok(())
    })
}

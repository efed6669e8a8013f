//! ParaView files: VTK XML PolyData (ASCII, full precision) per state and a `.pvd` time collection
//! per run and part.
//!
//! - `<run>_<label>_disks.vtp`: one vertex per disk at its centre (z = 0); point data `id`, `radius`
//!   (m), `diameter` (m: the scale array of ParaView's 2D circle glyph, which is one unit across), `velocity` (m/s), `angular_velocity` (rad/s, along z), `angle` (rotation about z, rad,
//!   counter-clockwise), `contact_force` (sum of |F|, N).
//! - `<run>_<label>_contacts.vtp`: one line per contact, from the first disk's centre to the second's
//!   (or to the contact point on a wall); cell data `first`, `second` (wall `−1 − k`), `normal`,
//!   `normal_force`, `tangential_force` (N), `force` (the contact force on `first`, N), `overlap` (m),
//!   `contact_point` (m), `sliding` (0/1).
//! - `<run>_walls.vtp`: the box walls as lines (cell data `wall`: 0 floor, 1 left, 2 right, 3 lid).
//! - `<run>_disks.pvd`, `<run>_contacts.pvd`: the states in time order (ParaView's time steps).
//! - `paraview_pile.py`: a ready ParaView view of the folder's runs (`pvpython paraview_pile.py RUN_ID
//!   --state FILE.pvsm`): true-size disks coloured by contact force, force chains as tubes.

use std::io::Write;
use std::path::Path;

use super::{Format, RunToExport, State, WriteError};
use crate::physics::contact_network::ContactNetwork;
use crate::physics::record::Snapshot;

/// The format's row of [`super::FORMATS`].
pub const FORMAT: Format = Format {
    name: "vtk",
    description: "ParaView: VTK XML PolyData (.vtp) for disks, contacts and walls, .pvd time collections",
    write_run,
};

/// The ParaView script written beside the files (`scripts/paraview_pile.py`).
const PARAVIEW_SCRIPT: &str = include_str!("../../scripts/paraview_pile.py");

/// Writes the files of one run (see the module doc).
fn write_run(folder: &Path, export: &RunToExport, states: &[State]) -> Result<(), WriteError> {
    let run = export.run;
    let Some(first) = states.first() else { return Ok(()) };
    for state in states {
        let name = |part: &str| format!("{}_{}_{part}.vtp", state.run, state.label);
        super::write_file(folder, &name("disks"), |out| disks(out, state.snapshot))?;
        super::write_file(folder, &name("contacts"), |out| contacts(out, state.snapshot))?;
    }
    let top = states.iter().flat_map(|s| pile_top(s.snapshot)).fold(run.scene.domain.height, f64::max);
    super::write_file(folder, &format!("{}_walls.vtp", first.run), |out| {
        walls(out, run.scene.domain.width, top, run.scene.domain.lid)
    })?;
    for part in ["disks", "contacts"] {
        super::write_file(folder, &format!("{}_{part}.pvd", first.run), |out| collection(out, states, part))?;
    }
    super::write_file(folder, "paraview_pile.py", |out| out.write_all(PARAVIEW_SCRIPT.as_bytes()))
}

/// The top of each disk.
fn pile_top(s: &Snapshot) -> impl Iterator<Item = f64> + '_ {
    s.y.iter().zip(&s.r).map(|(y, r)| y + r)
}

/// A `.pvd` collection of one part of every state.
fn collection(out: &mut dyn Write, states: &[State], part: &str) -> std::io::Result<()> {
    writeln!(out, "<?xml version=\"1.0\"?>")?;
    writeln!(out, "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n<Collection>")?;
    for s in states {
        let file = format!("{}_{}_{part}.vtp", s.run, s.label);
        writeln!(out, "<DataSet timestep=\"{}\" part=\"0\" file=\"{file}\"/>", s.snapshot.time)?;
    }
    writeln!(out, "</Collection>\n</VTKFile>")
}

/// The opening of a PolyData file with one piece, its time (if any) as field data `TimeValue`.
fn open_piece(
    out: &mut dyn Write,
    time: Option<f64>,
    points: usize,
    verts: usize,
    lines: usize,
) -> std::io::Result<()> {
    writeln!(out, "<?xml version=\"1.0\"?>")?;
    writeln!(out, "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">")?;
    writeln!(out, "<PolyData>")?;
    if let Some(time) = time {
        writeln!(out, "<FieldData>")?;
        writeln!(
            out,
            "<DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">{time}</DataArray>"
        )?;
        writeln!(out, "</FieldData>")?;
    }
    writeln!(
        out,
        "<Piece NumberOfPoints=\"{points}\" NumberOfVerts=\"{verts}\" NumberOfLines=\"{lines}\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">"
    )
}

fn close_piece(out: &mut dyn Write) -> std::io::Result<()> {
    writeln!(out, "</Piece>\n</PolyData>\n</VTKFile>")
}

/// A `DataArray` of `components` values per tuple.
fn array<T: std::fmt::Display>(
    out: &mut dyn Write,
    kind: &str,
    name: &str,
    components: usize,
    values: impl Iterator<Item = T>,
) -> std::io::Result<()> {
    write!(out, "<DataArray type=\"{kind}\" Name=\"{name}\" NumberOfComponents=\"{components}\" format=\"ascii\">")?;
    for (k, v) in values.enumerate() {
        if k > 0 {
            out.write_all(b" ")?;
        }
        write!(out, "{v}")?;
    }
    writeln!(out, "</DataArray>")
}

/// Points in the z = 0 plane.
fn points(out: &mut dyn Write, xy: impl Iterator<Item = [f64; 2]>) -> std::io::Result<()> {
    writeln!(out, "<Points>")?;
    array(out, "Float64", "Points", 3, xy.flat_map(|[x, y]| [x, y, 0.0]))?;
    writeln!(out, "</Points>")
}

/// Cells (`Verts` or `Lines`) of `size` consecutive points each.
fn cells(out: &mut dyn Write, tag: &str, count: usize, size: usize) -> std::io::Result<()> {
    writeln!(out, "<{tag}>")?;
    array(out, "Int64", "connectivity", 1, 0..count * size)?;
    array(out, "Int64", "offsets", 1, (1..=count).map(|k| k * size))?;
    writeln!(out, "</{tag}>")
}

/// The disks of a state as vertices with their point data.
fn disks(out: &mut dyn Write, s: &Snapshot) -> std::io::Result<()> {
    let n = s.x.len();
    open_piece(out, Some(s.time), n, n, 0)?;
    writeln!(out, "<PointData Scalars=\"radius\" Vectors=\"velocity\">")?;
    array(out, "Int64", "id", 1, 0..n)?;
    array(out, "Float64", "radius", 1, s.r.iter())?;
    array(out, "Float64", "diameter", 1, s.r.iter().map(|r| 2.0 * r))?;
    array(out, "Float64", "velocity", 3, (0..n).flat_map(|i| [s.vx[i], s.vy[i], 0.0]))?;
    array(out, "Float64", "angular_velocity", 3, s.omega.iter().flat_map(|&w| [0.0, 0.0, w]))?;
    array(out, "Float64", "angle", 1, s.angle.iter())?;
    array(out, "Float64", "contact_force", 1, s.contact_force.iter())?;
    writeln!(out, "</PointData>")?;
    points(out, (0..n).map(|i| [s.x[i], s.y[i]]))?;
    cells(out, "Verts", n, 1)?;
    close_piece(out)
}

/// The contacts of a state as lines with their cell data.
fn contacts(out: &mut dyn Write, s: &Snapshot) -> std::io::Result<()> {
    let c: &ContactNetwork = &s.contacts;
    let n = c.len();
    open_piece(out, Some(s.time), 2 * n, 0, n)?;
    writeln!(out, "<CellData Scalars=\"normal_force\" Vectors=\"force\">")?;
    array(out, "Int64", "first", 1, c.first.iter())?;
    array(out, "Int64", "second", 1, c.second.iter())?;
    array(out, "Float64", "normal", 3, (0..n).flat_map(|k| [c.normal_x[k], c.normal_y[k], 0.0]))?;
    array(out, "Float64", "normal_force", 1, c.normal_force.iter())?;
    array(out, "Float64", "tangential_force", 1, c.tangential_force.iter())?;
    array(out, "Float64", "force", 3, (0..n).flat_map(|k| force_on_first(c, k)))?;
    array(out, "Float64", "overlap", 1, c.overlap.iter())?;
    array(out, "Float64", "contact_point", 3, (0..n).flat_map(|k| [c.point_x[k], c.point_y[k], 0.0]))?;
    array(out, "UInt8", "sliding", 1, c.sliding.iter().map(|&b| u8::from(b)))?;
    writeln!(out, "</CellData>")?;
    let ends = (0..n).flat_map(|k| {
        let i = c.first[k] as usize;
        let far = match usize::try_from(c.second[k]) {
            Ok(j) => [s.x[j], s.y[j]],
            Err(_) => [c.point_x[k], c.point_y[k]],
        };
        [[s.x[i], s.y[i]], far]
    });
    points(out, ends)?;
    cells(out, "Lines", n, 2)?;
    close_piece(out)
}

/// The contact force on the first body: `−F_n n + F_t t` with `t = (−n_y, n_x)`.
fn force_on_first(c: &ContactNetwork, k: usize) -> [f64; 3] {
    let [nx, ny] = [c.normal_x[k], c.normal_y[k]];
    let [fn_, ft] = [c.normal_force[k], c.tangential_force[k]];
    [-fn_ * nx - ft * ny, -fn_ * ny + ft * nx, 0.0]
}

/// The box walls as lines up to `top` (m).
fn walls(out: &mut dyn Write, width: f64, top: f64, lid: bool) -> std::io::Result<()> {
    let corners = [[0.0, 0.0], [width, 0.0], [0.0, top], [width, top]];
    let mut lines = vec![[0, 1], [0, 2], [1, 3]];
    if lid {
        lines.push([2, 3]);
    }
    open_piece(out, None, corners.len(), 0, lines.len())?;
    writeln!(out, "<CellData Scalars=\"wall\">")?;
    array(out, "Int64", "wall", 1, 0..lines.len())?;
    writeln!(out, "</CellData>")?;
    points(out, corners.into_iter())?;
    writeln!(out, "<Lines>")?;
    array(out, "Int64", "connectivity", 1, lines.iter().flatten())?;
    array(out, "Int64", "offsets", 1, (1..=lines.len()).map(|k| 2 * k))?;
    writeln!(out, "</Lines>")?;
    close_piece(out)
}

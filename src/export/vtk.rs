//! ParaView files: VTK XML PolyData (ASCII, full precision) per state and a `.pvd` time collection
//! per run and part.
//!
//! - `<run>_<label>_disks.vtp`: one vertex per disk at its centre (z = 0); point data `id`, `radius`
//!   (m), `diameter` (m: the scale array of ParaView's 2D circle glyph, which is one unit across), `velocity` (m/s), `angular_velocity` (rad/s, along z), `angle` (rotation about z, rad,
//!   counter-clockwise), `contact_force` (sum of |F|, N). With periodic sides
//!   (`domain.periodic_x`), after the disks the images of those reaching across a side, one width
//!   over, with their disk's data (`id` names it) and point data `image` (0 for a disk, 1 for an
//!   image), so that the pile shows whole at both sides.
//! - `<run>_<label>_contacts.vtp`: one line per contact, from the first disk's centre to the second's
//!   (to its image across periodic sides, or to the contact point on a wall); cell data `first`,
//!   `second` (wall `−1 − k`), `normal`, `normal_force`, `tangential_force` (N), `force` (the
//!   contact force on `first`, N), `overlap` (m), `contact_point` (m), `sliding` (0/1).
//! - `<run>_walls.vtp`: the box walls as lines (cell data `wall`: 0 floor, 1 left, 2 right, 3 lid;
//!   no sides when they are periodic).
//! - `<run>_disks.pvd`, `<run>_contacts.pvd`: the states in time order (ParaView's time steps).
//! - `paraview_pile.py`: a ready ParaView view of the folder's runs (`pvpython paraview_pile.py RUN_ID
//!   --state FILE.pvsm`): true-size disks coloured by contact force, force chains as tubes.

use std::io::Write;
use std::path::Path;

use super::{Format, RunToExport, State, WriteError};
use crate::physics::config::DomainConfig;
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
    let domain = &run.scene.domain;
    let period = domain.periodic_x.then_some(domain.width);
    for state in states {
        let name = |part: &str| format!("{}_{}_{part}.vtp", state.run, state.label);
        super::write_file(folder, &name("disks"), |out| disks(out, state.snapshot, period))?;
        super::write_file(folder, &name("contacts"), |out| contacts(out, state.snapshot, period))?;
    }
    let top = states.iter().flat_map(|s| pile_top(s.snapshot)).fold(domain.height, f64::max);
    super::write_file(folder, &format!("{}_walls.vtp", first.run), |out| walls(out, domain, top))?;
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

/// The vertices of the disks file: each disk's index and x shift (m), the disks (unshifted), then
/// across periodic sides `period` apart the images of the disks reaching past a side.
fn vertices(s: &Snapshot, period: Option<f64>) -> Vec<(usize, f64)> {
    let mut vertices: Vec<(usize, f64)> = (0..s.x.len()).map(|i| (i, 0.0)).collect();
    if let Some(width) = period {
        for i in 0..s.x.len() {
            if s.x[i] - s.r[i] < 0.0 {
                vertices.push((i, width));
            }
            if s.x[i] + s.r[i] > width {
                vertices.push((i, -width));
            }
        }
    }
    vertices
}

/// The disks of a state as vertices with their point data (and their images across periodic
/// sides `period` apart).
fn disks(out: &mut dyn Write, s: &Snapshot, period: Option<f64>) -> std::io::Result<()> {
    let v = vertices(s, period);
    let n = v.len();
    // A column the state lacks (no angles in an older file) stays empty, as before images.
    let each = |column: fn(&Snapshot) -> &[f64]| v.iter().filter_map(move |&(i, _)| column(s).get(i).copied());
    open_piece(out, Some(s.time), n, n, 0)?;
    writeln!(out, "<PointData Scalars=\"radius\" Vectors=\"velocity\">")?;
    array(out, "Int64", "id", 1, v.iter().map(|&(i, _)| i))?;
    array(out, "Float64", "radius", 1, each(|s| &s.r))?;
    array(out, "Float64", "diameter", 1, each(|s| &s.r).map(|r| 2.0 * r))?;
    array(out, "Float64", "velocity", 3, v.iter().flat_map(|&(i, _)| [s.vx[i], s.vy[i], 0.0]))?;
    array(out, "Float64", "angular_velocity", 3, v.iter().flat_map(|&(i, _)| [0.0, 0.0, s.omega[i]]))?;
    array(out, "Float64", "angle", 1, each(|s| &s.angle))?;
    array(out, "Float64", "contact_force", 1, each(|s| &s.contact_force))?;
    if period.is_some() {
        array(out, "UInt8", "image", 1, v.iter().map(|&(_, shift)| u8::from(shift != 0.0)))?;
    }
    writeln!(out, "</PointData>")?;
    points(out, v.iter().map(|&(i, shift)| [s.x[i] + shift, s.y[i]]))?;
    cells(out, "Verts", n, 1)?;
    close_piece(out)
}

/// The contacts of a state as lines with their cell data (across periodic sides `period` apart, to
/// the second disk's nearest image).
fn contacts(out: &mut dyn Write, s: &Snapshot, period: Option<f64>) -> std::io::Result<()> {
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
            Ok(j) => [s.x[j] + image_shift(s.x[j] - s.x[i], c.normal_x[k], period), s.y[j]],
            Err(_) => [c.point_x[k], c.point_y[k]],
        };
        [[s.x[i], s.y[i]], far]
    });
    points(out, ends)?;
    cells(out, "Lines", n, 2)?;
    close_piece(out)
}

/// The x shift (m) that takes the second disk of a contact, `dx` from the first along x and seen in
/// the direction `normal_x` from it, to its image across periodic sides `period` apart: a whole
/// width when `dx` points against the normal, else none.
fn image_shift(dx: f64, normal_x: f64, period: Option<f64>) -> f64 {
    match period {
        Some(width) if dx * normal_x < 0.0 => -width.copysign(dx),
        _ => 0.0,
    }
}

/// The contact force on the first body: `−F_n n + F_t t` with `t = (−n_y, n_x)`.
fn force_on_first(c: &ContactNetwork, k: usize) -> [f64; 3] {
    let [nx, ny] = [c.normal_x[k], c.normal_y[k]];
    let [fn_, ft] = [c.normal_force[k], c.tangential_force[k]];
    [-fn_ * nx - ft * ny, -fn_ * ny + ft * nx, 0.0]
}

/// The box walls of `domain` as lines up to `top` (m).
fn walls(out: &mut dyn Write, domain: &DomainConfig, top: f64) -> std::io::Result<()> {
    let width = domain.width;
    let corners = [[0.0, 0.0], [width, 0.0], [0.0, top], [width, top]];
    // Each wall's corners and index: floor, left, right, lid.
    let all = [([0, 1], 0), ([0, 2], 1), ([1, 3], 2), ([2, 3], 3)];
    let (lines, index): (Vec<[usize; 2]>, Vec<usize>) = all
        .into_iter()
        .filter(|(_, w)| match w {
            1 | 2 => !domain.periodic_x,
            3 => domain.lid,
            _ => true,
        })
        .unzip();
    open_piece(out, None, corners.len(), 0, lines.len())?;
    writeln!(out, "<CellData Scalars=\"wall\">")?;
    array(out, "Int64", "wall", 1, index.iter())?;
    writeln!(out, "</CellData>")?;
    points(out, corners.into_iter())?;
    writeln!(out, "<Lines>")?;
    array(out, "Int64", "connectivity", 1, lines.iter().flatten())?;
    array(out, "Int64", "offsets", 1, (1..=lines.len()).map(|k| 2 * k))?;
    writeln!(out, "</Lines>")?;
    close_piece(out)
}

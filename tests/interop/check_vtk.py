#!/usr/bin/env python3
"""Reads a `demsweep export --format vtk --frames` folder with VTK's own XML readers and compares it with
the results file read by h5py.

Usage: check_vtk.py EXPORT_DIR RESULTS.h5 RUN_GROUP RUN_ID

For the run: the .pvd collections list the frames then the final state, with their times; each disks
file has one point per disk, radius, diameter, velocity, angular velocity, angle and contact force equal to the stored
state; each contacts file has one line cell per stored contact with its normal and tangential force;
the walls file has the box's walls. The docs' ParaView recipe — ParaView's 2D Glyph (VTK's
vtkGlyphSource2D), Circle, scale array `diameter`, scale factor 1 — draws every disk at its true size
(its glyph spans 2R in x and y). Exits 1 listing every difference, 2 when vtk or h5py is missing.
"""
import sys
import xml.etree.ElementTree as ElementTree

try:
    import h5py
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkFiltersCore import vtkGlyph3D
    from vtkmodules.vtkFiltersSources import vtkGlyphSource2D
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
except ImportError as error:  # scripts/test.sh installs them; a missing reader must fail the test
    print(f"vtk and h5py are required: {error}", file=sys.stderr)
    sys.exit(2)


def read(path):
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    if reader.GetErrorCode() != 0 or reader.GetOutput().GetNumberOfPoints() == 0 and "disks" in path:
        raise RuntimeError(f"{path}: VTK could not read it")
    return reader.GetOutput()


def array(data, name, problems, where):
    found = data.GetArray(name)
    if found is None:
        problems.append(f"{where}: no array {name}")
        return None
    return vtk_to_numpy(found)


def same(found, expected, what, problems):
    if found is None:
        return
    if found.shape != np.shape(expected) or not np.array_equal(found, expected):
        problems.append(f"{what}: differs from the results file ({found.shape} vs {np.shape(expected)})")


def recipe_glyph_sizes(polydata):
    """Each disk's glyph as the docs' ParaView recipe makes it: (width, height) per disk."""
    circle = vtkGlyphSource2D()  # ParaView's "2D Glyph"
    circle.SetGlyphTypeToCircle()
    circle.FilledOn()
    circle.Update()
    per_glyph = circle.GetOutput().GetNumberOfPoints()
    polydata.GetPointData().SetActiveScalars("diameter")
    glyphs = vtkGlyph3D()
    glyphs.SetInputData(polydata)
    glyphs.SetSourceConnection(circle.GetOutputPort())
    glyphs.SetScaleModeToScaleByScalar()
    glyphs.OrientOff()
    glyphs.SetScaleFactor(1.0)
    glyphs.Update()
    points = vtk_to_numpy(glyphs.GetOutput().GetPoints().GetData()).reshape(-1, per_glyph, 3)
    return points.max(axis=1)[:, :2] - points.min(axis=1)[:, :2]


def collection(path):
    root = ElementTree.parse(path).getroot()
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]


def main(folder, h5_path, group_path, run_id):
    problems = []
    with h5py.File(h5_path, "r") as f:
        run = f[group_path]
        # The frames are arrays over time: row k of each (T, N) array, and the contacts of frame k.
        frames, states = run["frames"], []
        fields = ("x", "y", "vx", "vy", "omega", "angle", "r", "contact_force")
        for k, time in enumerate(frames["time"][()]):
            network = frames["contacts"][()]
            states.append((float(time), {name: frames[name][k] for name in fields}, network[network["frame"] == k]))
        states.append((float(run["final"].attrs["time"]), run["final"][()], run["final_contacts"][()]))
        disks = collection(f"{folder}/{run_id}_disks.pvd")
        contacts = collection(f"{folder}/{run_id}_contacts.pvd")
        times = [time for time, _, _ in states]
        if [t for t, _ in disks] != times or [t for t, _ in contacts] != times:
            problems.append(f"pvd times {[t for t, _ in disks]}, expected {times}")
        for (_, state, network), (_, disk_file), (_, contact_file) in zip(states, disks, contacts):
            polydata = read(f"{folder}/{disk_file}")
            if polydata.GetNumberOfPoints() != len(state["x"]) or polydata.GetNumberOfVerts() != len(state["x"]):
                problems.append(f"{disk_file}: {polydata.GetNumberOfPoints()} points, expected {len(state['x'])}")
                continue
            points = vtk_to_numpy(polydata.GetPoints().GetData())
            same(points[:, 0], state["x"], f"{disk_file} x", problems)
            same(points[:, 1], state["y"], f"{disk_file} y", problems)
            point_data = polydata.GetPointData()
            same(array(point_data, "radius", problems, disk_file), state["r"], f"{disk_file} radius", problems)
            diameter = array(point_data, "diameter", problems, disk_file)
            same(diameter, 2 * state["r"], f"{disk_file} diameter", problems)
            if diameter is not None:
                sizes = recipe_glyph_sizes(polydata)
                expected = np.stack([2 * state["r"], 2 * state["r"]], axis=1)
                if sizes.shape != expected.shape or not np.allclose(sizes, expected, rtol=1e-6, atol=0):
                    worst = np.max(np.abs(sizes / expected - 1)) if sizes.shape == expected.shape else "shape"
                    problems.append(f"{disk_file}: the recipe's glyphs are not the disks' size (worst {worst})")
            velocity = array(point_data, "velocity", problems, disk_file)
            if velocity is not None:
                same(velocity[:, :2], np.stack([state["vx"], state["vy"]], axis=1), f"{disk_file} velocity", problems)
            spin = array(point_data, "angular_velocity", problems, disk_file)
            if spin is not None:
                same(spin[:, 2], state["omega"], f"{disk_file} angular_velocity", problems)
            angle = array(point_data, "angle", problems, disk_file)
            same(angle, state["angle"], f"{disk_file} angle", problems)
            force = array(point_data, "contact_force", problems, disk_file)
            same(force, state["contact_force"], f"{disk_file} contact_force", problems)
            lines = read(f"{folder}/{contact_file}")
            if lines.GetNumberOfLines() != len(network):
                problems.append(f"{contact_file}: {lines.GetNumberOfLines()} lines, expected {len(network)} contacts")
                continue
            cell_data = lines.GetCellData()
            for name in ("normal_force", "tangential_force", "overlap", "first", "second"):
                same(array(cell_data, name, problems, contact_file), network[name], f"{contact_file} {name}", problems)
        walls = read(f"{folder}/{run_id}_walls.vtp")
        scene = run.attrs["scene.json"]
        scene = scene.decode() if isinstance(scene, bytes) else str(scene)
        expected_walls = 4 if '"lid":true' in scene else 3
        if walls.GetNumberOfLines() != expected_walls:
            problems.append(f"walls: {walls.GetNumberOfLines()} lines, expected {expected_walls}")
    for problem in problems:
        print(problem, file=sys.stderr)
    print(f"{folder}: {len(states)} states of {run_id} checked, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:5]))

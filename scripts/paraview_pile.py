"""A ready ParaView view of an exported pile (`demsweep export --format vtk`, which copies this file
into its output folder): disks as filled circles of their true size coloured by contact force, the
contact network as tubes whose radius and colour follow the normal force, the box's walls, and the
time slider over the frames (with `--frames`) and the final state.

    pvpython paraview_pile.py [RUN_ID] [--state FILE.pvsm] [--screenshot FILE.png]

run in the export folder (or give the folder as --folder DIR). RUN_ID defaults to the first run of
the folder. --state saves a ParaView state (`paraview --state=FILE.pvsm` opens it); --screenshot
renders the final state to a PNG (without a display: `xvfb-run pvpython ...`).

The disks are ParaView's 2D Glyph, type Circle (one unit across), scaled by the `diameter` array
with scale factor 1 — the recipe of the docs (docs/export.md).
"""
import argparse
import glob
import os
import sys

from paraview.simple import (CellDatatoPointData, ColorBy, GetActiveViewOrCreate, GetAnimationScene,
                             GetColorTransferFunction, GetScalarBar, Glyph, PVDReader, Render, ResetCamera, SaveScreenshot,
                             SaveState, Show, Tube, XMLPolyDataReader)


def arguments(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run", nargs="?", help="run id, e.g. r0007 (default: the first run in the folder)")
    parser.add_argument("--folder", default=os.path.dirname(os.path.abspath(__file__)), help="the export folder")
    parser.add_argument("--state", help="save a ParaView state file (.pvsm)")
    parser.add_argument("--screenshot", help="save a PNG of the final state")
    return parser.parse_args(argv)


def first_run(folder):
    found = sorted(glob.glob(os.path.join(folder, "*_disks.pvd")))
    if not found:
        sys.exit(f"{folder}: no *_disks.pvd: export a run with `demsweep export RESULTS.h5 --format vtk --out DIR`")
    return os.path.basename(found[0])[: -len("_disks.pvd")]


def main(argv):
    args = arguments(argv)
    folder = os.path.abspath(args.folder)
    run = args.run or first_run(folder)
    view = GetActiveViewOrCreate("RenderView")
    if hasattr(view, "UseColorPaletteForBackground"):
        view.UseColorPaletteForBackground = 0
    view.Background = [1, 1, 1]
    view.OrientationAxesVisibility = 0

    disks = PVDReader(registrationName=f"{run} disks", FileName=os.path.join(folder, f"{run}_disks.pvd"))
    disks.UpdatePipeline()
    smallest = disks.PointData["radius"].GetRange()[0]
    glyphs = Glyph(registrationName=f"{run} disks (true size)", Input=disks, GlyphType="2D Glyph")
    glyphs.GlyphType.GlyphType = "Circle"
    glyphs.GlyphType.Filled = 1
    glyphs.OrientationArray = ["POINTS", "No orientation array"]
    glyphs.ScaleArray = ["POINTS", "diameter"]
    glyphs.ScaleFactor = 1.0
    glyphs.GlyphMode = "All Points"
    shown = Show(glyphs, view)
    ColorBy(shown, ("POINTS", "contact_force"))
    shown.RescaleTransferFunctionToDataRange(True, False)
    shown.SetScalarBarVisibility(view, True)
    bar = GetScalarBar(GetColorTransferFunction("contact_force"), view)
    bar.Title, bar.ComponentTitle = "contact force", "(N)"
    bar.TitleColor = bar.LabelColor = [0, 0, 0]
    bar.WindowLocation = "Any Location"
    bar.Position, bar.ScalarBarLength = [0.76, 0.25], 0.5
    bar.RangeLabelFormat = "%.3g"

    contacts = PVDReader(registrationName=f"{run} contacts", FileName=os.path.join(folder, f"{run}_contacts.pvd"))
    on_points = CellDatatoPointData(registrationName=f"{run} contact forces", Input=contacts)
    tubes = Tube(registrationName=f"{run} force chains", Input=on_points)
    tubes.Scalars = ["POINTS", "normal_force"]
    tubes.VaryRadius = "By Scalar"
    tubes.Radius = 0.04 * smallest  # the weakest contact; the strongest 8 times as thick
    tubes.RadiusFactor = 8.0
    tubes.NumberofSides = 8
    chains = Show(tubes, view)
    ColorBy(chains, ("POINTS", "normal_force"))
    GetColorTransferFunction("normal_force").ApplyPreset("Grayscale", True)
    GetColorTransferFunction("normal_force").InvertTransferFunction()
    chains.RescaleTransferFunctionToDataRange(True, False)

    walls = XMLPolyDataReader(registrationName=f"{run} walls", FileName=[os.path.join(folder, f"{run}_walls.vtp")])
    box = Show(walls, view)
    ColorBy(box, None)
    box.AmbientColor = box.DiffuseColor = [0, 0, 0]
    box.LineWidth = 3.0

    scene = GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    scene.AnimationTime = scene.EndTime  # the final state; the time slider steps through the frames
    view.InteractionMode = "2D"
    view.CameraPosition = [0, 0, 1]
    view.CameraFocalPoint = [0, 0, 0]
    view.CameraViewUp = [0, 1, 0]
    ResetCamera(view)
    Render(view)
    if args.state:
        SaveState(args.state)
    if args.screenshot:
        SaveScreenshot(args.screenshot, view, ImageResolution=[1000, 800])


if __name__ == "__main__":
    main(sys.argv[1:])

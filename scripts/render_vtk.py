#!/usr/bin/env python3
"""Renders an exported pile (`demsweep export --format vtk`) off-screen with VTK, as ParaView would show
it: disks as circles of their radius coloured by contact force, contacts as lines, walls.

Usage: render_vtk.py EXPORT_DIR RUN_ID OUT.png
(Without a display: VTK_DEFAULT_OPENGL_WINDOW=vtkOSOpenGLRenderWindow, with Debian's libosmesa6.)
"""
import sys

from vtkmodules.vtkCommonCore import vtkLookupTable
from vtkmodules.vtkFiltersSources import vtkRegularPolygonSource
from vtkmodules.vtkFiltersCore import vtkGlyph3D
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
from vtkmodules.vtkRenderingCore import (vtkActor, vtkPolyDataMapper, vtkRenderer, vtkRenderWindow,
                                         vtkWindowToImageFilter)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (the rendering back end)


def read(path):
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    return reader


def main(folder, run, out):
    disks = read(f"{folder}/{run}_final_disks.vtp")
    disks.GetOutput().GetPointData().SetActiveScalars("radius")
    circle = vtkRegularPolygonSource()
    circle.SetNumberOfSides(24)
    circle.SetRadius(1.0)
    glyphs = vtkGlyph3D()
    glyphs.SetInputConnection(disks.GetOutputPort())
    glyphs.SetSourceConnection(circle.GetOutputPort())
    glyphs.SetScaleModeToScaleByScalar()
    glyphs.SetColorModeToColorByScalar()
    glyphs.SetScaleFactor(1.0)
    glyphs.Update()
    glyphs.GetOutput().GetPointData().SetActiveScalars("contact_force")
    disk_mapper = vtkPolyDataMapper()
    disk_mapper.SetInputConnection(glyphs.GetOutputPort())
    disk_mapper.SetScalarModeToUsePointFieldData()
    disk_mapper.SelectColorArray("contact_force")
    disk_mapper.SetScalarRange(disks.GetOutput().GetPointData().GetArray("contact_force").GetRange())
    table = vtkLookupTable()
    table.SetHueRange(0.667, 0.0)
    table.Build()
    disk_mapper.SetLookupTable(table)
    actors, readers = [vtkActor()], []
    actors[0].SetMapper(disk_mapper)
    for part, colour, width in (("final_contacts", (0.1, 0.1, 0.1), 2.0), ("walls", (0, 0, 0), 4.0)):
        name = f"{folder}/{run}_{part}.vtp"
        mapper = vtkPolyDataMapper()
        readers.append(read(name))  # kept alive: a mapper does not hold its reader
        mapper.SetInputConnection(readers[-1].GetOutputPort())
        mapper.ScalarVisibilityOff()
        actor = vtkActor()
        actor.SetMapper(mapper)
        actor.GetProperty().SetColor(*colour)
        actor.GetProperty().SetLineWidth(width)
        actors.append(actor)
    renderer = vtkRenderer()
    renderer.SetBackground(1, 1, 1)
    for actor in actors:
        renderer.AddActor(actor)
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(1000, 800)
    window.AddRenderer(renderer)
    renderer.ResetCamera()
    window.Render()
    image = vtkWindowToImageFilter()
    image.SetInput(window)
    image.Update()
    writer = vtkPNGWriter()
    writer.SetFileName(out)
    writer.SetInputConnection(image.GetOutputPort())
    writer.Write()


if __name__ == "__main__":
    main(*sys.argv[1:4])

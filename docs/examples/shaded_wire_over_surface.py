#!/usr/bin/env python3
"""WireFur from Python, in a plain VTK pipeline: a wire-frame cage drawn as shaded wire (the
paper's image 9b) and fur grown on a torus, composited by WireFur's A-buffer render pass over the
torus that VTK draws with OpenGL, written to a PNG.

    /usr/bin/python3 shaded_wire_over_surface.py OUT.png [WIDTH HEIGHT]

Needs the built package `wirefur` on PYTHONPATH (build/lib/python3/dist-packages) and an X
display (or xvfb-run). Debian's python3-vtk9 is /usr/bin/python3's."""
import sys

import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (the OpenGL implementations)
from vtkmodules.vtkCommonComputationalGeometry import vtkParametricEllipsoid, vtkParametricTorus
from vtkmodules.vtkFiltersExtraction import vtkExtractEdges
from vtkmodules.vtkFiltersSources import vtkParametricFunctionSource
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkRenderingCore import (vtkActor, vtkPolyDataMapper, vtkRenderer, vtkRenderWindow,
                                         vtkWindowToImageFilter)
from vtkmodules.vtkRenderingOpenGL2 import vtkRenderStepsPass

import wirefur


def build(width=480, height=360, fur=True):
    """The renderer, window and the objects of the scene (returned for inspection)."""
    torus = vtkParametricTorus()
    torus.SetRingRadius(1.0)
    torus.SetCrossSectionRadius(0.4)
    surface = vtkParametricFunctionSource()
    surface.SetParametricFunction(torus)
    surface.SetUResolution(64)
    surface.SetVResolution(32)
    surface_actor = vtkActor()
    surface_actor.SetMapper(vtkPolyDataMapper())
    surface_actor.GetMapper().SetInputConnection(surface.GetOutputPort())
    surface_actor.GetProperty().SetColor(0.6, 0.35, 0.2)
    surface_actor.GetProperty().SetSpecular(0.3)
    surface_actor.GetProperty().SetSpecularPower(20)

    # The cage: the edges of a coarse ellipsoid, drawn by the A-buffer as shaded wire.
    ellipsoid = vtkParametricEllipsoid()
    ellipsoid.SetXRadius(1.6)
    ellipsoid.SetYRadius(1.6)
    ellipsoid.SetZRadius(1.1)
    cage_source = vtkParametricFunctionSource()
    cage_source.SetParametricFunction(ellipsoid)
    cage_source.SetUResolution(16)
    cage_source.SetVResolution(8)
    edges = vtkExtractEdges()
    edges.SetInputConnection(cage_source.GetOutputPort())
    cage = vtkActor()
    cage.SetMapper(vtkPolyDataMapper())
    cage.GetMapper().SetInputConnection(edges.GetOutputPort())
    cage.GetProperty().SetColor(0.75, 0.75, 0.8)
    cage.GetProperty().SetSpecular(1.0)
    cage.GetProperty().SetSpecularPower(20)
    wirefur.vtkWireFurRenderPass.Mark(cage, True)
    cage.GetPropertyKeys().Set(wirefur.vtkWireFurRenderPass.WIREFUR_WIRE_THICKNESS(), 0.02)

    ren = vtkRenderer()
    ren.AddActor(surface_actor)
    ren.AddActor(cage)
    hairs = None
    if fur:
        # Fur grown on the exact torus (its derivatives), also drawn by the A-buffer.
        hairs = wirefur.vtkWireFurFurGenerator()
        hairs.SetParametricFunction(torus)
        hairs.SetGridU(120)
        hairs.SetGridV(50)
        hairs.SetLength(0.12)
        hairs.SetThickness(0.006)
        hairs.FlipNormalsOn()  # vtkParametricTorus has Su x Sv pointing into the tube
        hair_actor = vtkActor()
        hair_actor.SetMapper(vtkPolyDataMapper())
        hair_actor.GetMapper().SetInputConnection(hairs.GetOutputPort())
        hair_actor.GetProperty().SetColor(0.9, 0.75, 0.55)
        wirefur.vtkWireFurRenderPass.Mark(hair_actor, True)
        hair_actor.GetPropertyKeys().Set(wirefur.vtkWireFurRenderPass.WIREFUR_WIRE_THICKNESS(), 0.006)
        ren.AddActor(hair_actor)

    render_pass = wirefur.vtkWireFurRenderPass()
    render_pass.SetDelegatePass(vtkRenderStepsPass())
    ren.SetPass(render_pass)
    ren.SetBackground(0.0, 0.0, 0.0)
    ren.GetActiveCamera().SetPosition(0.0, -5.0, 3.5)
    ren.GetActiveCamera().SetFocalPoint(0.0, 0.0, 0.0)
    ren.GetActiveCamera().SetViewUp(0.0, 0.0, 1.0)
    ren.ResetCameraClippingRange()

    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(width, height)
    window.AddRenderer(ren)
    return window, ren, render_pass, hairs


def write_png(window, path):
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    grab.Update()
    writer = vtkPNGWriter()
    writer.SetFileName(path)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()
    return grab.GetOutput()


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    w, h = (int(sys.argv[2]), int(sys.argv[3])) if len(sys.argv) >= 4 else (480, 360)
    window, ren, render_pass, _ = build(w, h)
    window.Render()
    write_png(window, sys.argv[1])
    print("A-buffer: %d marked props, %.3f s, error estimate %.2e" %
          (render_pass.GetLastMarkedProps(), render_pass.GetLastRenderSeconds(), render_pass.GetLastErrorEstimate()))

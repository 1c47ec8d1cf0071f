#!/usr/bin/env python3
"""ctest: WireFur's Python package in VTK pipelines (issue 5). Runs the example
docs/examples/shaded_wire_over_surface.py and checks numbers against independent expectations:
the fur generator's hair count for a grid, the eye-space tangents of a circle, the map source's
image against its documented size, and the render pass compositing fur over the OpenGL surface.
Usage: /usr/bin/python3 python_pipeline.py OUT.png   (needs a display: ctest runs it under xvfb-run)"""
import importlib.util
import math
import os
import sys

import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkRenderingCore import vtkCamera

import wirefur

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLE = os.path.join(HERE, "..", "..", "docs", "examples", "shaded_wire_over_surface.py")
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


spec = importlib.util.spec_from_file_location("example", EXAMPLE)
example = importlib.util.module_from_spec(spec)
spec.loader.exec_module(example)

# 1. The map source: a Resolution x Resolution image of radiance.
maps = wirefur.vtkWireFurMapSource()
maps.SetResolution(48)
maps.Update()
dims = maps.GetOutput().GetDimensions()
check(dims[0] == 48 and dims[1] == 48, "map source is 48 x 48 (got %s)" % (dims,))
lo, hi = maps.GetOutput().GetPointData().GetArray("Radiance").GetRange(0)
check(0.0 <= lo < hi and math.isfinite(hi), "map radiance finite and not constant (%g .. %g)" % (lo, hi))

# 2. Eye-space tangents of a circle in the view plane: perpendicular to the radius.
if hasattr(wirefur, "vtkWireFurTangentShading"):
    n = 64
    pts = vtkPoints()
    for k in range(n + 1):
        a = 2 * math.pi * k / n
        pts.InsertNextPoint(math.cos(a), math.sin(a), 0.0)
    lines = vtkCellArray()
    lines.InsertNextCell(n + 1)
    for k in range(n + 1):
        lines.InsertCellPoint(k)
    circle = vtkPolyData()
    circle.SetPoints(pts)
    circle.SetLines(lines)
    cam = vtkCamera()
    cam.SetPosition(0, 0, 10)
    cam.SetFocalPoint(0, 0, 0)
    cam.SetViewUp(0, 1, 0)
    shading = wirefur.vtkWireFurTangentShading()
    shading.SetInputData(circle)
    shading.SetCamera(cam)
    shading.Update()
    t = shading.GetOutput().GetPointData().GetArray("EyeTangents")
    worst = 0.0
    for k in range(1, n):  # interior points: the averaged tangent of a regular polygon is exact
        a = 2 * math.pi * k / n
        tx, ty, tz = t.GetTuple3(k)
        worst = max(worst, abs(tx * math.cos(a) + ty * math.sin(a)), abs(math.hypot(tx, ty) - 1.0))
    check(worst < 1e-6, "circle tangents perpendicular to the radius and unit (worst %.1e)" % worst)

# 3. The fur generator on a torus: one hair per grid cell.
window, ren, render_pass, hairs = example.build(320, 240)
hairs.Update()
check(hairs.GetOutput().GetNumberOfLines() == 120 * 50,
      "fur grid 120 x 50 gives 6000 hairs (got %d)" % hairs.GetOutput().GetNumberOfLines())

# 4. The render pass: both marked props drawn by the A-buffer, and the fur visible over the
#    OpenGL surface (the image differs from the same scene without fur in many pixels).
window.Render()
with_fur = example.write_png(window, sys.argv[1] if len(sys.argv) > 1 else "python_pipeline.png")
check(render_pass.GetLastMarkedProps() == 2, "2 marked props drawn by the A-buffer (got %d)" % render_pass.GetLastMarkedProps())
check(math.isfinite(render_pass.GetLastErrorEstimate()), "error estimate reported (%g)" % render_pass.GetLastErrorEstimate())
window2, _, _, _ = example.build(320, 240, fur=False)
window2.Render()
import tempfile
without = example.write_png(window2, os.path.join(tempfile.gettempdir(), "wirefur_python_nofur.png"))
a = with_fur.GetPointData().GetScalars()
b = without.GetPointData().GetScalars()
differ = sum(1 for i in range(a.GetNumberOfTuples()) if max(abs(x - y) for x, y in zip(a.GetTuple(i), b.GetTuple(i))) > 8)
check(differ > 0.05 * a.GetNumberOfTuples(), "fur changes more than 5%% of the pixels (%d of %d)" % (differ, a.GetNumberOfTuples()))

# 5. Burnish -> mapper -> marked actor: brushed steel through the pass, not the plain actor's
#    plastic. The same plane with and without the filter, in the pass, under one light; the C++
#    test tests/vtk/burnish_pass_gltest.cpp compares the same pipeline with the command's render.
from vtkmodules.vtkFiltersSources import vtkPlaneSource
from vtkmodules.vtkFiltersCore import vtkTriangleFilter
from vtkmodules.vtkRenderingCore import vtkActor, vtkLight, vtkPolyDataMapper, vtkRenderer, vtkRenderWindow


def draw_plane(burnished):
    plane = vtkPlaneSource()
    plane.SetOrigin(-1.2, -0.8, 0.0)
    plane.SetPoint1(1.2, -0.8, 0.0)
    plane.SetPoint2(-1.2, 0.8, 0.0)
    plane.SetResolution(24, 16)
    tri = vtkTriangleFilter()
    tri.SetInputConnection(plane.GetOutputPort())
    last = tri
    if burnished:
        burnish = wirefur.vtkWireFurBurnish()
        burnish.SetInputConnection(tri.GetOutputPort())
        last = burnish
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(last.GetOutputPort())
    mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    prop = actor.GetProperty()
    prop.SetDiffuseColor(0.18, 0.18, 0.18)
    prop.SetSpecularColor(5.0, 5.0, 5.0)
    prop.SetSpecular(1.0)
    prop.SetSpecularPower(30.0)
    wirefur.vtkWireFurRenderPass.Mark(actor)
    ren = vtkRenderer()
    ren.AutomaticLightCreationOff()
    light = vtkLight()
    light.SetLightTypeToSceneLight()
    light.SetPosition(1, 1, 2)
    light.SetFocalPoint(0, 0, 0)
    light.SetPositional(False)
    ren.AddLight(light)
    ren.AddActor(actor)
    cam = ren.GetActiveCamera()
    cam.SetPosition(0, 0, 5)
    cam.SetFocalPoint(0, 0, 0)
    cam.SetViewUp(0, 1, 0)
    cam.SetViewAngle(30)
    ren.ResetCameraClippingRange()
    pass_ = wirefur.vtkWireFurRenderPass()
    ren.SetPass(pass_)
    win = vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetSize(200, 150)
    win.AddRenderer(ren)
    win.Render()
    return example.write_png(win, os.path.join(tempfile.gettempdir(), "wirefur_python_burnish_%d.png" % burnished))


brushed = draw_plane(True).GetPointData().GetScalars()
plastic = draw_plane(False).GetPointData().GetScalars()
n = brushed.GetNumberOfTuples()
mean_diff = sum(abs(x - y) for i in range(n) for x, y in zip(brushed.GetTuple(i), plastic.GetTuple(i))) / (3.0 * n)
check(mean_diff > 5.0, "the burnished actor differs from the plain one (mean %.1f of 255)" % mean_diff)

print("%d checks failed" % len(failures))
sys.exit(1 if failures else 0)

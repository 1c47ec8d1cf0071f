# The WireFur render view in pvbatch (docs/paraview.md): lines drawn through the A-buffer over
# ParaView's surfaces, hidden where a surface is nearer, antialiased, with the error estimate.
#
# Scene (parallel projection, looking down -z at a white plane z = 0 on a black background): a
# red line from (-0.8, 0, -0.5) to (0.8, 0, 0.5), which passes through the plane at x = 0. Checks,
# each against a geometric expectation:
#   - the left half of the line (x < 0, under the plane) is hidden: along the line's row the
#     pixels left of the centre are the plane's colour (within 2/255);
#   - the right half is drawn: those pixels are red (green well below the plane's);
#   - the edges are antialiased: across the line the green channel takes intermediate values;
#   - the view reports one actor drawn through the A-buffer, fragments, a shading error bound
#     below 1e-6 (closed path) and a coverage quantisation of 1/32 (8 x 4 mask);
#   - the annotation (the error estimate shown in the lower left corner) draws there, and not
#     with ShowErrorEstimate off;
#   - coloured by an array through a lookup table, the colour changes along the line;
#   - in the Wireframe representation (ambient-lit in ParaView) the line is still red.
# Usage (under Xvfb): pvbatch view_test.py PLUGIN.so OUT_DIR
import os
import sys
from paraview.simple import *
from vtkmodules.vtkIOImage import vtkPNGReader
from vtkmodules.util.numpy_support import vtk_to_numpy

plugin, out = sys.argv[1], sys.argv[2]
os.makedirs(out, exist_ok=True)
LoadPlugin(plugin, remote=False, ns=globals())
failures = []


def check(what, ok, detail=""):
    print(f"{what}: {'ok' if ok else 'FAILED'} {detail}")
    if not ok:
        failures.append(what)


W, H = 400, 300
view = CreateView("WireFurRenderView")
view.ViewSize = [W, H]
view.OrientationAxesVisibility = 0
view.Background = [0, 0, 0]
try:
    view.UseColorPaletteForBackground = 0
except AttributeError:
    pass

plane = Plane(Origin=[-1, -1, 0], Point1=[1, -1, 0], Point2=[-1, 1, 0])
pd = Show(plane, view)
pd.ColorArrayName = ["POINTS", ""]
pd.AmbientColor = pd.DiffuseColor = [1, 1, 1]
line = Line(Point1=[-0.8, -0.01, -0.5], Point2=[0.8, 0.01, 0.5], Resolution=8)  # (tilted by 4 px over its length)
ld = Show(line, view)
ld.ColorArrayName = ["POINTS", ""]
ld.AmbientColor = ld.DiffuseColor = [1, 0, 0]
ld.LineWidth = 5.0
Render(view)  # (the first render resets the camera: set it after)
view.CameraParallelProjection = 1
view.CameraPosition = [0, 0, 5]
view.CameraFocalPoint = [0, 0, 0]
view.CameraViewUp = [0, 1, 0]
view.CameraParallelScale = 0.75


def image(name):
    path = os.path.join(out, name)
    Render(view)
    SaveScreenshot(path, view, ImageResolution=[W, H], TransparentBackground=0)
    r = vtkPNGReader()
    r.SetFileName(path)
    r.Update()
    d = r.GetOutput()
    nx, ny, _ = d.GetDimensions()
    a = vtk_to_numpy(d.GetPointData().GetScalars()).reshape(ny, nx, -1)
    return a[::-1, :, :3].astype(int)  # row 0 at the top


img = image("wirefur_view.png")
px = view.SMProxy
px.UpdatePropertyInformation()
info = {n: px.GetProperty(n).GetElement(0) for n in ["MarkedActors", "Fragments", "ErrorEstimate", "CoverageError"]}
print(info)
check("one actor drawn through the A-buffer", info["MarkedActors"] == 1)
check("fragments", info["Fragments"] > 100)
check("shading error bound below 1e-6 (closed path)", 0 <= info["ErrorEstimate"] < 1e-6)
check("coverage quantisation 1/32", abs(info["CoverageError"] - 1 / 32) < 1e-12)

row = H // 2          # the line's row (y = 0 is the middle of the view)
plane_colour = img[row - 40, W // 2]
check("the plane is light", (plane_colour > 150).all(), str(plane_colour))
scale = W / 2 / (0.75 * W / H)   # pixels per world unit (parallel scale = half the height)
cx = W // 2


def along(x0, x1):
    """The pixels on the line's axis (y = 0.0125 x) for x in [x0, x1)."""
    cols = range(int(cx + x0 * scale), int(cx + x1 * scale))
    return img[[round(row - 0.0125 * (c - cx)) for c in cols], list(cols)][None]


left, right = along(-0.6, -0.2), along(0.2, 0.6)
check("the half under the plane is hidden", abs(left - plane_colour).max() <= 2, f"(largest difference {abs(left - plane_colour).max()})")
check("the half over the plane is drawn red", (right[:, :, 1] < plane_colour[1] - 100).all() and (right[:, :, 0] > right[:, :, 1] + 50).all(),
      f"(green {right[:, :, 1].min()}..{right[:, :, 1].max()}, red {right[:, :, 0].min()}..{right[:, :, 0].max()})")
# The edges sweep across the pixel grid along the tilted line: every column has partly covered
# pixels at its two edges (unless an edge falls on a pixel boundary).
columns = range(int(cx + 0.2 * scale), int(cx + 0.6 * scale))
between = sum(int(((img[row - 8:row + 9, c, 1] > 15) & (img[row - 8:row + 9, c, 1] < plane_colour[1] - 15)).sum()) for c in columns)
check("antialiased edges", between >= 1.5 * len(columns), f"({between} partly covered pixels in {len(columns)} columns; "
      f"one column: {list(map(int, img[row - 8:row + 9, int(cx + 0.3 * scale), 1]))})")

corner = img[H - 14:H - 4, 8:120]
check("the error estimate is shown", (corner != plane_colour).any(axis=2).sum() > 30)
view.ShowErrorEstimate = 0
off = image("wirefur_view_no_annotation.png")[H - 14:H - 4, 8:120]
check("and hidden with ShowErrorEstimate off", (off == plane_colour).all(axis=2).mean() > 0.99)

view.ShowErrorEstimate = 1

# Coloured by an array (ParaView interpolates scalars before mapping by default, which makes
# VTK's MapScalars return no colours): the visible half goes from the map's middle to its end.
withx = Calculator(Input=line, ResultArrayName="x", Function="coordsX")
Hide(line, view)
xd = Show(withx, view)
xd.LineWidth = 5.0
ColorBy(xd, ("POINTS", "x"))
lut = GetColorTransferFunction("x")
lut.ApplyPreset("Blue Orange (divergent)", True)
lut.RescaleTransferFunction(-0.8, 0.8)
coloured = image("wirefur_view_coloured.png")
img = coloured
near, far = along(0.25, 0.3)[0].mean(axis=0), along(0.7, 0.75)[0].mean(axis=0)
check("coloured by an array: the colour changes along the line", abs(near - far).max() > 40, f"(x = 0.27: {near.round()}, x = 0.72: {far.round()})")
# Wireframe representation (ParaView sets Ambient 1, Diffuse 0): not black.
xd.ColorArrayName = ["POINTS", ""]
xd.AmbientColor = xd.DiffuseColor = [1, 0, 0]
xd.Representation = "Wireframe"
img = image("wirefur_view_wireframe.png")
red = along(0.2, 0.6)[0][:, 0]
check("Wireframe representation: drawn red, not black", red.min() > 120, f"(red {red.min()}..{red.max()})")

print("FAILED: " + ", ".join(failures) if failures else "all view checks passed", flush=True)
# (os._exit: ParaView 5.11 can crash in its exit handlers after sys.exit with a view open.)
os._exit(1 if failures else 0)

# The WireFur plugin in pvbatch (docs/paraview.md): it loads, the CAD reader reads a STEP file
# (directly and through OpenDataFile's reader factory), every filter runs on a source, and each
# output is checked against what the same classes give in the system-VTK build's tests:
#   product.step: 35 faces, 72 edges of which 16 sharp (docs/cad.md);
#   fur on a plane: GridU x GridV = 7,000 hairs of Segments + 1 points;
#   scales on a plane: CellsU x CellsV scales; the map source: Resolution^2 texels;
#   silhouettes of product.step for a camera given as properties: exact (OpenCASCADE's faces),
#   within 1% of the model's size of the mesh path's curves (a different algorithm), moving with
#   the camera; edge visibility: some of the edges hidden by the faces, none without them.
# Usage: pvbatch plugin_test.py PLUGIN.so DATA_DIR
import sys
from paraview.simple import *
from paraview import servermanager as sm

plugin, data = sys.argv[1], sys.argv[2]
LoadPlugin(plugin, remote=False, ns=globals())
failures = []


def check(what, got, expected):
    print(f"{what}: {got} (expected {expected})")
    if got != expected:
        failures.append(what)


def fetch(proxy, port=0):
    return sm.Fetch(proxy, idx=port)


def info(proxy, name):  # an information property (the plugin's classes are not Python-wrapped)
    proxy.SMProxy.UpdatePropertyInformation()
    return proxy.SMProxy.GetProperty(name).GetElement(0)


step = f"{data}/cad/product.step"
reader = WireFurCADReader(FileName=step)
reader.UpdatePipeline()
faces, edges = fetch(reader, 0), fetch(reader, 1)
check("product.step faces (distinct FaceId)",
      len({int(faces.GetCellData().GetArray("FaceId").GetTuple1(i)) for i in range(faces.GetNumberOfCells())}), 35)
check("product.step edges", edges.GetNumberOfLines(), 72)
sharp = WireFurEdgeClasses(Input=OutputPort(reader, 1), Mode="Sharp")
sharp.UpdatePipeline()
check("sharp edges", fetch(sharp).GetNumberOfLines(), 16)
opened = OpenDataFile(step)
check("OpenDataFile's reader", opened.GetXMLName(), "WireFurCADReader")

plane = Plane(XResolution=20, YResolution=20)
fur = WireFurFurGenerator(Input=plane, Segments=4)
fur.UpdatePipeline()
hair = fetch(fur)
check("hairs", hair.GetNumberOfLines(), 100 * 70)
check("hair points", hair.GetNumberOfPoints(), 100 * 70 * 5)
shaded = WireFurTangentShading(Input=fur)
shaded.UpdatePipeline()
check("ShadedColor", fetch(shaded).GetPointData().GetArray("ShadedColor") is not None, True)
scales = WireFurScalesGenerator(Input=plane, CellsU=8, CellsV=6)
scales.UpdatePipeline()
check("scales", fetch(scales).GetNumberOfCells() > 0, True)
burnish = WireFurBurnish(Input=plane, GrooveCount=40)
burnish.UpdatePipeline()
# (From the data information: Fetch moves pieces through VTK's legacy writer, which drops the
# active tangents attribute, so a fetched piece from another rank has no grain.)
check("grain", "Tangents" in burnish.PointData.keys(), True)
check("grooves", "GrooveIntensity" in burnish.PointData.keys(), True)
table = WireFurMapSource(Resolution=64)
table.UpdatePipeline()
check("map texels", fetch(table).GetNumberOfPoints(), 64 * 64)

# The view-dependent filters, their camera given as properties (as a script copies them from a
# render view: docs/paraview.md), oblique from above the tray.
from vtkmodules.vtkCommonDataModel import vtkCellLocator, vtkGenericCell
from vtkmodules.vtkCommonCore import reference
b = faces.GetBounds()
centre = [(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2]
size = ((b[1] - b[0]) ** 2 + (b[3] - b[2]) ** 2 + (b[5] - b[4]) ** 2) ** 0.5
camera = dict(CameraPosition=[centre[0] + 1.1 * size, centre[1] - 1.4 * size, centre[2] + 1.0 * size],
              CameraFocalPoint=centre, CameraViewUp=[0, 0, 1], CameraViewAngle=30, ViewportSize=[800, 600])
exact = WireFurSilhouette(Input=reader, **camera)
exact.UpdatePipeline()
mesh = WireFurSilhouette(Input=reader, UseExactSurfaces=0, **camera)
mesh.UpdatePipeline()
ex, me = fetch(exact), fetch(mesh)
check("exact silhouette path", info(exact, "UsedExactSurfaces"), 1)
check("mesh silhouette path", info(mesh, "UsedExactSurfaces"), 0)
check("silhouette curves", ex.GetNumberOfLines() > 0 and me.GetNumberOfLines() > 0, True)
classes = ex.GetCellData().GetArray("EdgeClass")
check("silhouette EdgeClass 6", {int(classes.GetTuple1(i)) for i in range(ex.GetNumberOfCells())}, {6})
locator = vtkCellLocator()
locator.SetDataSet(me)
locator.BuildLocator()
closest, cell_id, sub_id, d2 = [0.0, 0.0, 0.0], reference(0), reference(0), reference(0.0)
far = 0.0
for i in range(ex.GetNumberOfPoints()):
    locator.FindClosestPoint(ex.GetPoint(i), closest, vtkGenericCell(), cell_id, sub_id, d2)
    far = max(far, d2.get() ** 0.5)
print(f"exact silhouette to the mesh path's: at most {far:.4g} ({far / size:.2e} of the model's size)")
check("exact and mesh silhouettes agree within 1% of the size", far < 0.01 * size, True)
locator = vtkCellLocator()
locator.SetDataSet(ex)
locator.BuildLocator()
back = 0.0
for i in range(me.GetNumberOfPoints()):
    locator.FindClosestPoint(me.GetPoint(i), closest, vtkGenericCell(), cell_id, sub_id, d2)
    back = max(back, d2.get() ** 0.5)
check("no mesh silhouette without an exact one within 2% of the size", back < 0.02 * size, True)
before = ex.GetNumberOfPoints()
exact.CameraPosition = [centre[0] - 1.6 * size, centre[1] + 0.4 * size, centre[2] + 0.8 * size]
exact.UpdatePipeline()
check("the silhouette moves with the camera", fetch(exact).GetNumberOfPoints() != before, True)
hidden = WireFurEdgeVisibility(Input=OutputPort(reader, 1), Surface=OutputPort(reader, 0), **camera)
hidden.UpdatePipeline()
seen = fetch(hidden).GetCellData().GetArray("Visible")
values = {int(seen.GetTuple1(i)) for i in range(seen.GetNumberOfTuples())}
check("edges seen and hidden", values, {0, 1})
seen_length, hidden_length = info(hidden, "VisibleLength"), info(hidden, "HiddenLength")
print(f"edge visibility: {seen_length:.4g} seen, {hidden_length:.4g} hidden")
bare = WireFurEdgeVisibility(Input=OutputPort(reader, 1), **camera)
bare.UpdatePipeline()
# A camera 3,000 units away (vtkCamera's own clipping range ends at 1,000): the range is fitted to
# the data, so the edges are in the view, as near.
far_camera = dict(camera, CameraPosition=[centre[0] + 3000, centre[1] - 1000, centre[2] + 1000], CameraViewAngle=1.5)
distant = WireFurEdgeVisibility(Input=OutputPort(reader, 1), **far_camera)
distant.UpdatePipeline()
check("a distant camera sees every edge", info(distant, "HiddenLength"), 0.0)
check("no surface: nothing hidden", info(bare, "HiddenLength"), 0.0)
check("no surface: the whole length seen",
      abs(info(bare, "VisibleLength") - seen_length - hidden_length) < 1e-9 * size, True)

if failures:
    print("FAILED:", ", ".join(failures))
    sys.exit(1)
print("plugin test passed")

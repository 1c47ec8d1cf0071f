# The WireFur plugin in pvbatch (docs/paraview.md): it loads, the CAD reader reads a STEP file
# (directly and through OpenDataFile's reader factory), every filter runs on a source, and each
# output is checked against what the same classes give in the system-VTK build's tests:
#   product.step: 35 faces, 72 edges of which 16 sharp (docs/cad.md);
#   fur on a plane: GridU x GridV = 7,000 hairs of Segments + 1 points;
#   scales on a plane: CellsU x CellsV scales; the map source: Resolution^2 texels.
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

if failures:
    print("FAILED:", ", ".join(failures))
    sys.exit(1)
print("plugin test passed")

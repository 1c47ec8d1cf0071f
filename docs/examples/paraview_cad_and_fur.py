# pvbatch example (docs/paraview.md): a CAD part's sharp edges over its faces, and fur on a plane,
# through the WireFur plugin, saved as a screenshot. From the repository root, after
# `bash scripts/paraview_plugin.sh`:
#   B=build-paraview
#   PYTHONPATH=$B/pvpython/usr/lib/python3/dist-packages xvfb-run -a pvbatch \
#     docs/examples/paraview_cad_and_fur.py [OUT.png]
# (Debian's ParaView renders through X: xvfb-run gives it one.) Under MPI, each rank runs the
# pipeline on its piece:
#   PYTHONPATH=... xvfb-run -a mpirun --allow-run-as-root -np 2 -x PYTHONPATH -x DISPLAY -x XAUTHORITY \
#     pvbatch docs/examples/paraview_cad_and_fur.py
import os
import sys
from paraview.simple import *

plugin = os.environ.get("WIREFUR_PLUGIN", "build-paraview/lib/paraview-5.11/plugins/WireFur/WireFur.so")
LoadPlugin(plugin, remote=False, ns=globals())
out = sys.argv[1] if len(sys.argv) > 1 else "paraview_cad_and_fur.png"

part = OpenDataFile("data/cad/product.step")          # the WireFur CAD reader: Faces, Edges
hard = WireFurEdgeClasses(Input=OutputPort(part, 1), Mode="Sharp")
view = CreateRenderView()
view.ViewSize = [800, 600]
faces = Show(OutputPort(part, 0), view)
faces.ColorArrayName = [None, ""]  # (not the file's colours)
faces.DiffuseColor = [0.75, 0.75, 0.78]
edges = Show(hard, view)
edges.ColorArrayName = [None, ""]
edges.DiffuseColor = [0.05, 0.05, 0.05]
edges.LineWidth = 2.0

# Fur on a plane beside the part, shaded as thin cylinders (ShadedColor, sRGB).
b = part.GetDataInformation().GetBounds()
size = max(b[1] - b[0], b[3] - b[2])
plane = Plane(Origin=[b[1] + 0.2 * size, b[2], b[4]], Point1=[b[1] + 0.8 * size, b[2], b[4]],
              Point2=[b[1] + 0.2 * size, b[3], b[4]], XResolution=10, YResolution=10)
fur = WireFurFurGenerator(Input=plane, GridU=150, GridV=150, Length=0.08 * size, Segments=4, Gravity=0.3)
shaded = WireFurTangentShading(Input=fur)
hair = Show(shaded, view)
ColorBy(hair, ("POINTS", "ShadedColor"))
hair.MapScalars = 0

view.OrientationAxesVisibility = 0
view.CameraPosition = [b[1], b[2] - 1.5 * size, b[5] + 1.2 * size]
view.CameraFocalPoint = [b[1], 0.5 * (b[2] + b[3]), b[4]]
view.CameraViewUp = [0, 0, 1]
ResetCamera(view)
GetActiveCamera().Dolly(1.4)
SaveScreenshot(out, view, ImageResolution=[800, 600])
print("wrote", out)

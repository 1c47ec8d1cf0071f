# Times of the WireFur render view on a dense fur, for docs/paraview.md's scaling model (a
# benchmark, not a test): a sphere (its pieces over the ranks), fur grown on each rank's piece
# (distributed growth), drawn through the A-buffer at 1024 x 768. Prints, per still frame, the
# wall time of Render() and the view's figures (the slowest rank's A-buffer band, the exchanges).
# Usage (under Xvfb): [mpirun -np N] pvbatch view_mpi_bench.py PLUGIN.so [GRID] [SEGMENTS] [FRAMES]
import sys
import time
import os
from paraview import servermanager
from paraview.simple import *

plugin = sys.argv[1]
grid = int(sys.argv[2]) if len(sys.argv) > 2 else 580
segments = int(sys.argv[3]) if len(sys.argv) > 3 else 3
frames = int(sys.argv[4]) if len(sys.argv) > 4 else 5
LoadPlugin(plugin, remote=False, ns=globals())
ranks = servermanager.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()
W, H = 1024, 768
view = CreateView("WireFurRenderView")
view.ViewSize = [W, H]
view.OrientationAxesVisibility = 0
view.ShowErrorEstimate = 0
ball = TextureMaptoSphere(Input=Sphere(Radius=1.0, ThetaResolution=96, PhiResolution=48))
Show(ball, view)
fur = WireFurFurGenerator(Input=ball, GridU=grid, GridV=grid, Length=0.12, Segments=segments, Gravity=0.3)
fd = Show(fur, view)
fd.ColorArrayName = ["POINTS", ""]
fd.LineWidth = 1.0
t = time.perf_counter()
Render(view)
first = time.perf_counter() - t
view.CameraPosition = [0, -4.2, 1.2]
view.CameraFocalPoint = [0, 0, 0]
view.CameraViewUp = [0, 0, 1]
cells = fur.GetDataInformation().GetNumberOfCells()
points = fur.GetDataInformation().GetNumberOfPoints()
walls, figures = [], []
px = view.SMProxy
for i in range(frames):
    view.CameraPosition = [0.01 * i, -4.2, 1.2]  # a new camera: a new frame, not a cached one
    t = time.perf_counter()
    Render(view)
    walls.append(time.perf_counter() - t)
    px.UpdatePropertyInformation()
    figures.append({n: px.GetProperty(n).GetElement(0) for n in
                    ["CoreSeconds", "PassSeconds", "GatherSeconds", "CompositeSeconds", "Fragments"]})
walls_sorted = sorted(walls)
median = walls_sorted[len(walls) // 2]
f = figures[walls.index(median)]
if servermanager.vtkProcessModule.GetProcessModule().GetPartitionId() == 0:
    print("ranks %d hairs %d segments %d first frame (growth, gather) %.2f s" % (ranks, cells, points - cells, first))
    print("median of %d frames: Render() %.3f s, pass %.3f s, A-buffer band %.3f s, gather %.4f s, composite %.4f s, fragments %d"
          % (frames, median, f["PassSeconds"], f["CoreSeconds"], f["GatherSeconds"], f["CompositeSeconds"], f["Fragments"]))
    print("all frames:", ["%.3f" % w for w in walls])
sys.stdout.flush()
os._exit(0)

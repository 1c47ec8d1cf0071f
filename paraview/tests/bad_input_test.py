# Bad input in ParaView (docs/paraview.md, "Bad input"), serially and under mpirun: what the
# wirefur command refuses with one line, the plugin reports as one error in ParaView's output on
# every rank concerned, with an empty output, and pvbatch (or pvserver) carries on; no rank waits
# for another that gave up (a hang would end the test at ctest's time limit).
# - CAD files that crash OpenCASCADE 7.6 in process (tests/apps/cad_regressions): read in the
#   reader's worker, each is one line "FILE: OpenCASCADE crashed ..." on the rank that reads;
#   a read past WorkerTimeout is stopped; a good file reads afterwards.
# - Growth on a redistributed mesh whose piece on the last rank has a NaN point, or has no
#   texture coordinates: an error on every rank (the piece's rank names the problem, the others
#   say another process's piece is unusable), no hairs anywhere.
# - Growth on a mesh that lies on rank 0 only (empty pieces elsewhere): the one-process hairs.
# - The WireFur view drawing lines with a NaN point on the last rank: the frame is made, with
#   the other lines in it.
# Errors are caught by observers on each rank's own objects (so ParaView does not print them);
# the test prints "all checks passed" on every rank that passed.
# Usage (under Xvfb): [mpirun -np N] pvbatch --symmetric bad_input_test.py PLUGIN.so SOURCE_DIR
# (--symmetric: every rank runs this script and checks its own errors.)
import os
import sys
from paraview import servermanager
from paraview.simple import *
from vtkmodules.vtkCommonCore import VTK_STRING
from vtkmodules.util.misc import calldata_type

plugin, source = sys.argv[1], sys.argv[2]
LoadPlugin(plugin, remote=False, ns=globals())
pm = servermanager.vtkProcessModule.GetProcessModule()
rank, ranks = pm.GetPartitionId(), pm.GetNumberOfLocalPartitions()
last = ranks - 1
failures = []


def check(what, ok, detail=""):
    print(f"rank {rank}: {what}: {'ok' if ok else 'FAILED'} {detail}", flush=True)
    if not ok:
        failures.append(what)


class Errors:
    """The error messages a proxy's local VTK object raises (caught, so ParaView prints none)."""

    def __init__(self, proxy):
        self.messages = []
        obj = proxy.GetClientSideObject()

        @calldata_type(VTK_STRING)
        def caught(_obj, _event, message):
            self.messages.append(str(message).strip().splitlines()[-1].strip())

        self.tag = obj.AddObserver("ErrorEvent", caught)


def cells(proxy, port=0):
    """Cells over all ranks (on rank 0, which gathers the data information; None elsewhere)."""
    return OutputPort(proxy, port).GetDataInformation().GetNumberOfCells() if rank == 0 else None


# --- CAD files that crash OpenCASCADE -----------------------------------------------------
regressions = os.path.join(source, "tests", "apps", "cad_regressions")
for name in ["step_segv_cartesianpoint.step", "iges_segv_face_nbloops.iges", "brep_segv_in_mesher.brep",
             "fcstd_segv_trimmed_curve.FCStd"]:
    path = os.path.join(regressions, name)
    reader = WireFurCADReader(FileName=path)
    errors = Errors(reader)
    reader.UpdatePipeline()
    if rank == 0:  # (a reader reads on rank 0; the other ranks' pieces are empty)
        m = errors.messages
        check(f"{name}: one line naming the file and the crash",
              len(m) == 1 and m[0].endswith("it is corrupt, or uses something OpenCASCADE 7.6 cannot read")
              and (path + ": OpenCASCADE crashed") in m[0], repr(m))
    else:
        check(f"{name}: nothing read on this rank", not errors.messages, repr(errors.messages))
    check(f"{name}: empty output", cells(reader) in (0, None))
    Delete(reader)

step = os.path.join(source, "data", "cad", "product.step")
slow = WireFurCADReader(FileName=step, LinearDeflection=1e-7, MaximumTriangles=10**12, WorkerTimeout=0.5)
errors = Errors(slow)
slow.UpdatePipeline()
if rank == 0:
    check("a read past WorkerTimeout is stopped",
          len(errors.messages) == 1 and errors.messages[0].endswith(
              step + ": reading and meshing did not finish within 0.5 s (OpenCASCADE may loop on a "
              "corrupt file; WorkerTimeout sets the limit)"), repr(errors.messages))
Delete(slow)
good = WireFurCADReader(FileName=step)
good.UpdatePipeline()
if rank == 0:
    check("a good file reads afterwards (1,564 triangles, 72 edges)", (cells(good), cells(good, 1)) == (1564, 72),
          str((cells(good), cells(good, 1))))

# --- Growth on bad pieces -----------------------------------------------------------------
surface = ExtractSurface(Input=RedistributeDataSet(Input=Plane(XResolution=20, YResolution=20)))
spoil = """
from vtkmodules.vtkParallelCore import vtkMultiProcessController
c = vtkMultiProcessController.GetGlobalController()
n = c.GetNumberOfProcesses() if c else 1
me = c.GetLocalProcessId() if c else 0
out = self.GetOutputDataObject(0)
out.DeepCopy(self.GetInputDataObject(0, 0))
if me == n - 1 and out.GetNumberOfPoints() > 0:
%s
"""
nan_point = ProgrammableFilter(Input=surface, OutputDataSetType="Same as Input",
                               Script=spoil % "    out.GetPoints().SetPoint(0, float('nan'), 0.0, 0.0)")
no_tcoords = ProgrammableFilter(Input=surface, OutputDataSetType="Same as Input",
                                Script=spoil % "    out.GetPointData().SetTCoords(None)\n"
                                               "    out.GetPointData().RemoveArray('TextureCoordinates')")
for label, bad, own in [("a NaN point", nan_point, "not finite"), ("no texture coordinates", no_tcoords, "texture coordinates")]:
    fur = WireFurFurGenerator(Input=bad, Segments=3)
    errors = Errors(fur)
    fur.UpdatePipeline()
    m = errors.messages
    expected = own if rank == last else "another process's piece is unusable"
    if ranks == 1:
        expected = own
    check(f"fur on a piece with {label}: one error on this rank", len(m) == 1 and expected in m[0], repr(m))
    check(f"fur on a piece with {label}: no hairs", cells(fur) in (0, None))
    Delete(fur)

plane = Plane(XResolution=20, YResolution=20)  # a source without pieces: all on rank 0
fur = WireFurFurGenerator(Input=plane, Segments=4)
errors = Errors(fur)
fur.UpdatePipeline()
check("fur on a mesh on rank 0 only: no error", not errors.messages, repr(errors.messages))
if rank == 0:
    check("fur on a mesh on rank 0 only: the one-process hairs (7,000)", cells(fur) == 7000, str(cells(fur)))

# --- The view, lines with a NaN point on one rank -----------------------------------------
# Of the grid's 840 edges, 2 meet point 0 (a corner): the frame is made, and the other lines are
# drawn (at least 95% of the fragments of the grid without its NaN point).
view = CreateView("WireFurRenderView")
view.ViewSize = [320, 240]
view.CameraPosition = [0, 0, 3]
view.CameraFocalPoint = [0, 0, 0]
view.CameraViewUp = [0, 1, 0]


def fragments(lines):
    shown = Show(lines, view)
    shown.ColorArrayName = ["POINTS", ""]
    shown.AmbientColor = shown.DiffuseColor = [1, 0.1, 0.05]
    Render(view)
    px = view.SMProxy
    px.UpdatePropertyInformation()
    Hide(lines, view)
    return px.GetProperty("Fragments").GetElement(0)


clean = fragments(ExtractEdges(Input=surface))
spoilt = fragments(ExtractEdges(Input=nan_point))
check("the view draws lines with a NaN point on one rank (the other lines drawn)",
      0.95 * clean <= spoilt <= clean and clean > 1000, f"{spoilt} of {clean} fragments")

# Every rank's verdict, gathered: rank 0 says "all checks passed" only when every rank got here
# and passed (ctest looks for that line and for "FAILED").
from vtkmodules.vtkParallelCore import vtkMultiProcessController
from vtkmodules.vtkCommonCore import vtkIntArray
controller = vtkMultiProcessController.GetGlobalController()
mine, total = vtkIntArray(), vtkIntArray()
mine.InsertNextValue(len(failures))
mine.InsertNextValue(1)
if controller and controller.GetNumberOfProcesses() > 1:
    controller.AllReduce(mine, total, 2)  # (vtkCommunicator::SUM_OP)
else:
    total.DeepCopy(mine)
if failures:
    print(f"rank {rank}: FAILED: {failures}", flush=True)
if rank == 0 and total.GetValue(0) == 0 and total.GetValue(1) == ranks:
    print(f"all checks passed on {ranks} rank(s)", flush=True)
os._exit(1 if failures else 0)

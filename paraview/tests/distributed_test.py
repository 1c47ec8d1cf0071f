# Fur and scales grown on a distributed surface (docs/paraview.md, "Distributed growth"): the union
# over the ranks is the one-process output, hair for hair and scale for scale, bit for bit.
#
# The surface: a 20 x 20 plane (texture coordinates), split by RedistributeDataSet (global cell
# ids) and turned back into polygons by ExtractSurface; fur three ways (the jittered grid; the
# regular grid, whose roots fall exactly on the triangles' shared edges in 3 rows of 70; the
# area-correct lattice) and scales. Each output, fetched to rank 0, is written canonically (ids
# and point coordinates as exact decimal strings, sorted by id) and compared with the same
# pipeline on the undivided plane (Plane -> fur, no redistribution) in this run, and, when a
# reference file from an earlier run is given, with it (ctest: the serial run writes it, the
# two-rank run compares with it). Under mpirun every rank must have grown some of it.
# Usage: pvbatch distributed_test.py PLUGIN.so OUT_JSON [REFERENCE_JSON]
import json
import sys
from paraview.simple import *
from paraview import servermanager as sm

plugin, out_path = sys.argv[1], sys.argv[2]
reference_path = sys.argv[3] if len(sys.argv) > 3 else None
LoadPlugin(plugin, remote=False, ns=globals())
ranks = sm.ActiveConnection.GetNumberOfDataPartitions()
failures = []


def check(what, ok, detail=""):
    print(f"{what}: {'ok' if ok else 'FAILED'} {detail}")
    if not ok:
        failures.append(what)


def canonical(proxy, key_array=None):
    """{id: [coordinates as repr strings]} for fur (by HairId), or {index: ...} for scales (sorted by their points)."""
    data = sm.Fetch(proxy)
    pts = data.GetPoints()
    out = {}
    if key_array:
        ids = data.GetCellData().GetArray(key_array)
        lines = data.GetLines()
        lines.InitTraversal()
        import vtk
        cell = vtk.vtkIdList()
        c = 0
        while lines.GetNextCell(cell):
            xyz = []
            for k in range(cell.GetNumberOfIds()):
                xyz += [repr(v) for v in pts.GetPoint(cell.GetId(k))]
            out[str(int(ids.GetTuple1(c)))] = xyz
            c += 1
    else:
        scales = []
        for s in range(data.GetNumberOfPoints() // 4):
            xyz = []
            for k in range(4):
                xyz += [repr(v) for v in pts.GetPoint(4 * s + k)]
            scales.append(xyz)
        scales.sort()
        out = {str(i): xyz for i, xyz in enumerate(scales)}
    return out


def ranks_with_cells(proxy):
    pids = ProcessIdScalars(Input=proxy)
    data = sm.Fetch(pids)
    arr = data.GetPointData().GetArray("ProcessId")
    return len({int(arr.GetTuple1(i)) for i in range(data.GetNumberOfPoints())}) if arr else 0


plane = Plane(XResolution=20, YResolution=20)
split = ExtractSurface(Input=RedistributeDataSet(Input=plane, GenerateGlobalCellIds=1))
variants = {
    "fur jittered grid": dict(Segments=3, Clumping=0.3),
    "fur regular grid (roots on shared edges)": dict(Segments=2, Jitter=0.0),
    "fur area-correct": dict(Placement="Area correct", Density=20000.0, CellsU=16, CellsV=12, Segments=2),
}
result = {}
for name, props in variants.items():
    distributed = WireFurFurGenerator(Input=split, **props)
    undivided = WireFurFurGenerator(Input=plane, **props)
    got, whole = canonical(distributed, "HairId"), canonical(undivided, "HairId")
    check(f"{name}: {len(got)} hairs on {ranks} rank(s) = the undivided plane's {len(whole)}", got == whole)
    if ranks > 1:
        n = ranks_with_cells(distributed)
        check(f"{name}: grown on every rank", n == ranks, f"({n} of {ranks})")
    result[name] = got
scales_d = WireFurScalesGenerator(Input=split, CellsU=12, CellsV=9)
scales_w = WireFurScalesGenerator(Input=plane, CellsU=12, CellsV=9)
got, whole = canonical(scales_d), canonical(scales_w)
check(f"scales: {len(got)} on {ranks} rank(s) = the undivided plane's {len(whole)}", got == whole)
if ranks > 1:
    n = ranks_with_cells(scales_d)
    check("scales: grown on every rank", n == ranks, f"({n} of {ranks})")
result["scales"] = got

with open(out_path, "w") as f:
    json.dump(result, f)
if reference_path:
    with open(reference_path) as f:
        reference = json.load(f)
    for name in result:
        same = reference.get(name) == result[name]
        check(f"{name}: the same as the reference run's", same,
              f"({len(result[name])} here, {len(reference.get(name, {}))} there)")

if failures:
    print("FAILED:", ", ".join(failures))
    sys.exit(1)
print("all distributed checks passed")

"""The CAD reader from Python (docs/cad.md): `import wirefur` does not load the CAD module (nor
OpenCASCADE); naming wirefur.vtkWireFurCADReader does. Reads data/cad/product.step (the tray made
by data/cad/make_samples.cpp: 35 faces, 72 edges, counted by OpenCASCADE when it was written) and
checks the counts and that every normal is a unit vector and every Su is orthogonal to it.

usage: python3 python_cad.py PRODUCT.step
"""
import math
import sys

import wirefur

assert "wirefur.WireFurCAD" not in sys.modules, "import wirefur loaded the CAD module"
Reader = wirefur.vtkWireFurCADReader
assert "wirefur.WireFurCAD" in sys.modules

r = Reader()
r.SetFileName(sys.argv[1])
r.Update()
assert r.GetErrorMessage() == "", r.GetErrorMessage()
assert r.GetNumberOfParts() == 1 and r.GetPartName(0) == "tray", (r.GetNumberOfParts(), r.GetPartName(0))
assert r.GetNumberOfFaces() == 35 and r.GetNumberOfMeshedFaces() == 35, r.GetNumberOfFaces()
assert r.GetNumberOfEdges() == 72, r.GetNumberOfEdges()
faces = r.GetOutput(0)
pd = faces.GetPointData()
n, su = pd.GetNormals(), pd.GetArray("Su")
worst_unit, worst_dot = 0.0, 0.0
for i in range(faces.GetNumberOfPoints()):
    a, t = n.GetTuple3(i), su.GetTuple3(i)
    worst_unit = max(worst_unit, abs(math.sqrt(sum(x * x for x in a)) - 1.0))
    lt = math.sqrt(sum(x * x for x in t))
    if lt > 0:
        worst_dot = max(worst_dot, abs(sum(x * y for x, y in zip(a, t))) / lt)
# float normals: 1e-6; Su is tangent to the surface, so orthogonal to the exact normal.
assert worst_unit < 1e-6, worst_unit
assert worst_dot < 1e-6, worst_dot

bad = Reader()
bad.SetFileName(sys.argv[1] + ".missing.step")
bad.GlobalWarningDisplayOff()
bad.Update()
assert bad.GetErrorMessage().endswith("no such file"), bad.GetErrorMessage()
print("python CAD reader: %d points, |n|-1 <= %.1e, |n.Su|/|Su| <= %.1e" % (faces.GetNumberOfPoints(), worst_unit, worst_dot))

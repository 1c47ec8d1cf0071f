#!/usr/bin/env python3
"""Writes torus_hair.vtk: straight hairs standing on a torus (major radius 1, minor 0.4, axis z),
as a legacy ASCII VTK polyline file with a grey intensity per point.

This stands in for the fur generator until it exists (paper section 4.2, image 15: "The hair
intensities were randomised slightly, as were the lengths"). Roots are uniform by area, each hair
leans along the normal with a random tilt, lengths 0.14 ... 0.22. Deterministic (fixed seed);
rerun with `python3 make_torus_hair.py > torus_hair.vtk`.
"""
import math
import random

N = 5000
R, r = 1.0, 0.4
rng = random.Random(1988)
points, greys = [], []
while len(points) < 2 * N:
    u, v = rng.uniform(0, 2 * math.pi), rng.uniform(0, 2 * math.pi)
    if rng.uniform(0, R + r) > R + r * math.cos(v):
        continue  # uniform by area
    n = (math.cos(v) * math.cos(u), math.cos(v) * math.sin(u), math.sin(v))
    root = (R * math.cos(u) + r * n[0], R * math.sin(u) + r * n[1], r * n[2])
    d = [n[k] + 0.45 * rng.uniform(-1, 1) for k in range(3)]
    dl = math.sqrt(sum(x * x for x in d))
    length = rng.uniform(0.14, 0.22)
    tip = tuple(root[k] + length * d[k] / dl for k in range(3))
    g = rng.uniform(0.75, 1.0)
    points += [root, tip]
    greys += [g, g]

print("# vtk DataFile Version 3.0")
print("torus hair: %d straight hairs, written by make_torus_hair.py" % N)
print("ASCII")
print("DATASET POLYDATA")
print("POINTS %d float" % len(points))
for p in points:
    print("%.4f %.4f %.4f" % p)
print("LINES %d %d" % (N, 3 * N))
for i in range(N):
    print("2 %d %d" % (2 * i, 2 * i + 1))
print("POINT_DATA %d" % len(points))
print("COLOR_SCALARS intensity 1")
for g in greys:
    print("%.2f" % g)

#!/usr/bin/env python3
"""Writes the scene files of the paper's creatures and the fir tree, whose many lofts are easier
to lay out in a loop than by hand: oscar.json and oscar_fur.json (image 18), spider.json (20),
dragon.json (21) and fir_tree.json (22). Deterministic: run it from this folder,
`python3 make_creatures.py`, and the committed files come out unchanged."""
import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def write(name, scene):
    with open(os.path.join(HERE, name), "w") as f:
        json.dump(scene, f, indent=1)
        f.write("\n")


def r3(p):
    return [round(c, 4) for c in p]


def loft(points, radii, resolution, up=(0, 0, 1)):
    """A loft of elliptical sections; radii are numbers or [a, b]."""
    sections = []
    for p, r in zip(points, radii):
        s = {"centre": r3(p)}
        if isinstance(r, (list, tuple)):
            s["radii"] = [round(r[0], 4), round(r[1], 4)]
        else:
            s["radius"] = round(r, 4)
        sections.append(s)
    return {"type": "loft", "sections": sections, "up": list(up), "resolution": list(resolution)}


STUDIO = {"preset": "studio", "count": 3}

# ---- Oscar (image 18): a lofted body and limbs; fur length proportional to |Su| ----------------
body = loft([(-1.55, 0, 0.95), (-1.35, 0, 0.95), (-0.8, 0, 1.0), (0.0, 0, 1.05), (0.65, 0, 1.1), (0.95, 0, 1.32),
             (1.25, 0, 1.52), (1.6, 0, 1.5), (1.78, 0, 1.44)],
            [0.0, [0.32, 0.3], [0.5, 0.46], [0.55, 0.5], [0.46, 0.42], [0.24, 0.24], [0.34, 0.32], [0.22, 0.2], 0.0],
            (48, 96))
legs = []
for k, (x, y) in enumerate([(0.55, 0.28), (0.55, -0.28), (-0.85, 0.3), (-0.85, -0.3)]):
    legs.append(loft([(x, y, 1.0), (x, y * 1.1, 0.75), (x + 0.05, y * 1.15, 0.4), (x + 0.05, y * 1.15, 0.12),
                      (x + 0.12, y * 1.15, 0.03), (x + 0.2, y * 1.15, 0.02)],
                     [0.2, 0.18, 0.13, 0.11, 0.1, 0.0], (24, 40), up=(0, 1, 0)))
tail = loft([(-1.4, 0, 1.0), (-1.7, 0, 1.1), (-1.95, 0, 1.35), (-2.05, 0, 1.6)], [0.12, 0.1, 0.07, 0.0], (16, 32))
ears = [loft([(1.3, y, 1.75), (1.28, y * 1.2, 1.9), (1.25, y * 1.25, 2.0)], [[0.08, 0.03], [0.06, 0.025], 0.0], (16, 12),
             up=(1, 0, 0)) for y in (0.16, -0.16)]
oscar_parts = [("body", body)] + [("leg %d" % (i + 1), l) for i, l in enumerate(legs)] + [("tail", tail)] + \
              [("ear %d" % (i + 1), e) for i, e in enumerate(ears)]
oscar_camera = {"direction": [0.45, -1.0, 0.35]}
oscar_materials = {
    "pelt": {"diffuse": [0.55, 0.38, 0.22], "specular": 0.9, "exponent": 15, "burnish": {"grain": "v"}},
    "skin": {"diffuse": [0.3, 0.2, 0.12], "specular": 0.1, "exponent": 10},
    "fur": {"diffuse": [0.8, 0.6, 0.4], "specular": 0.45, "exponent": 14}}
write("oscar.json", {
    "title": "Oscar, tangent shading only", "paper_image": "18a",
    "caption": "Paper image 18 (top): an animal modelled by lofting elliptical cross-sections along spline curves, one loft for the body and one for each limb, shaded only by its tangent vectors (the burnish model along v). It looks like a toy made from synthetic material.",
    "image": {"size": [640, 480]}, "camera": oscar_camera, "lights": STUDIO, "materials": oscar_materials,
    "objects": [{"name": n, "source": s, "surface": {"material": "pelt"}} for n, s in oscar_parts]})
oscar_fur = []
for n, s in oscar_parts:
    oscar_fur.append({"name": n, "source": s, "surface": {"material": "skin"}, "fur": {
        "placement": "area", "density": 3500, "orientation": [0.0, -0.75, 0.65], "unit_tangents": True,
        "length_mode": "su", "length_per_su": 0.07, "length_variation": 0.3, "intensity_variation": 0.3,
        "segments": 3, "gravity": 0.6, "root_colour": [0.5, 0.34, 0.2], "tip_colour": [0.95, 0.78, 0.55],
        "thickness": 0.006, "material": "fur", "seed": 18}})
write("oscar_fur.json", {
    "title": "Oscar, furry", "paper_image": "18b",
    "caption": "Paper image 18 (bottom): the same lofts with hairs added. As in the paper, each hair's length is proportional to |Su| (the local u tangent), so thick limbs grow longer fur; here the roots are area-correct (3,500 per unit area) and the hairs curve under gravity (3 segments), both beyond the paper. The fur hides the unblended joins of the limbs.",
    "image": {"size": [640, 480]}, "camera": oscar_camera, "lights": STUDIO, "materials": oscar_materials,
    "objects": oscar_fur})

# ---- Spider (image 20): ~15,000 triangles, ~37,000 fixed-length hairs, colour near the joints ----
spider = []
spider.append(("abdomen", loft([(-1.75, 0, 0.62), (-1.6, 0, 0.7), (-1.2, 0, 0.78), (-0.75, 0, 0.72), (-0.5, 0, 0.62),
                                (-0.42, 0, 0.6)], [0.0, [0.35, 0.3], [0.55, 0.48], [0.5, 0.44], [0.25, 0.22], 0.0], (40, 40)),
               (110, 130)))
spider.append(("cephalothorax", loft([(-0.45, 0, 0.58), (-0.35, 0, 0.6), (0.0, 0, 0.62), (0.35, 0, 0.58), (0.48, 0, 0.55)],
                                     [0.0, [0.25, 0.2], [0.36, 0.28], [0.22, 0.18], 0.0], (40, 40)), (80, 90)))
for k in range(8):
    side = 1 if k < 4 else -1
    i = k % 4
    a = math.radians(-55 + i * 38)  # splayed from front to back
    base = (0.25 - i * 0.17, side * 0.22, 0.6)
    d = (math.cos(a) * 0.2 if side > 0 else math.cos(a) * 0.2, side * math.sin(a + math.pi / 2) * 1.0, 0)
    reach = 1.3 - 0.1 * abs(i - 1.5)
    ux, uy = math.cos(math.radians(75 - i * 45)), side * math.sin(math.radians(75 - i * 45))
    ux, uy = -math.sin(math.radians(-60 + i * 40)), side * math.cos(math.radians(-60 + i * 40))
    pts = [base,
           (base[0] + ux * 0.25, base[1] + uy * 0.25, 0.78),
           (base[0] + ux * 0.55 * reach, base[1] + uy * 0.55 * reach, 1.05),
           (base[0] + ux * 0.95 * reach, base[1] + uy * 0.95 * reach, 0.6),
           (base[0] + ux * 1.2 * reach, base[1] + uy * 1.2 * reach, 0.15),
           (base[0] + ux * 1.3 * reach, base[1] + uy * 1.3 * reach, 0.0)]
    spider.append(("leg %d" % (k + 1), loft(pts, [0.07, 0.065, 0.055, 0.045, 0.035, 0.0], (12, 40)), (12, 170)))
spider_objects = []
for n, s, grid in spider:
    hairs = {"grid": grid, "orientation": [0.0, 0.45, 1.0], "unit_tangents": True, "length": 0.09,
             "length_variation": 0.0, "intensity_variation": 0.25, "root_colour": [0.35, 0.25, 0.15],
             "tip_colour": [0.6, 0.45, 0.3], "thickness": 0.006, "material": "hair", "seed": 20}
    if n.startswith("leg"):
        # Paler hairs around the knee and ankle joints (the paper's spider), rings of regions.
        hairs["regions"] = [{"centre": [s_, t], "radius": 0.07, "colour": [1.0, 0.92, 0.75], "falloff": 0.6}
                            for t in (0.4, 0.72) for s_ in (0.0, 0.25, 0.5, 0.75)]
    spider_objects.append({"name": n, "source": s, "surface": {"material": "chitin"}, "fur": hairs})
write("spider.json", {
    "title": "Spider", "paper_image": "20",
    "caption": "Paper image 20: a spider of lofted body parts and legs (13,824 triangles) with 37,820 hairs of fixed length (the paper: 15,456 and 36,737), their colour changed near the leg joints, all A-buffered as shaded cylinders.",
    "image": {"size": [800, 600]}, "camera": {"direction": [0.5, -1.0, 0.8]}, "lights": STUDIO,
    "materials": {"chitin": {"diffuse": [0.12, 0.08, 0.05], "specular": 0.5, "exponent": 30},
                  "hair": {"diffuse": [0.75, 0.6, 0.45], "specular": 0.5, "exponent": 14}},
    "objects": spider_objects})

# ---- Dragon (image 21): a sinuous lofted body, legs and head, all scaly --------------------------
spine = []
radii = []
for i in range(14):
    t = i / 13.0
    x = 2.4 - 5.2 * t
    spine.append((x, 0.8 * math.sin(2.2 * math.pi * t), 0.55 + 0.25 * math.sin(math.pi * t) - 0.2 * t))
    radii.append([0.0, 0.2, 0.3, 0.36, 0.38, 0.36, 0.33, 0.28, 0.24, 0.19, 0.14, 0.09, 0.05, 0.0][i])
dragon = [("body", loft(spine, [[r * 1.1, r] if r else 0.0 for r in radii], (48, 160)), (20, 70))]
head_base = spine[0]
dragon.append(("head", loft([(2.2, 0.0, 0.62), (2.45, 0.0, 0.75), (2.8, 0.0, 0.78), (3.1, 0.0, 0.7), (3.25, 0.0, 0.66)],
                            [[0.24, 0.2], [0.26, 0.22], [0.18, 0.14], [0.1, 0.08], 0.0], (32, 32)), (14, 10)))
for k, (i, side) in enumerate([(3, 1), (3, -1), (8, 1), (8, -1)]):
    p = spine[i]
    dragon.append(("leg %d" % (k + 1), loft([(p[0], p[1] + side * 0.2, p[2]), (p[0] + 0.1, p[1] + side * 0.55, p[2] - 0.05),
                                              (p[0] + 0.2, p[1] + side * 0.65, 0.15), (p[0] + 0.35, p[1] + side * 0.68, 0.02),
                                              (p[0] + 0.45, p[1] + side * 0.68, 0.0)],
                                             [0.14, 0.12, 0.09, 0.06, 0.0], (20, 32), up=(1, 0, 0)), (8, 10)))
dragon_objects = [{"name": n, "source": s, "surface": {"material": "belly"},
                   "scales": {"cells": list(cells), "size": 1.5, "lift": 0.18, "deflection": 0.7, "intensity_variation": 0.35,
                              "material": "scale", "seed": 21}} for n, s, cells in dragon]
write("dragon.json", {
    "title": "Dragon", "paper_image": "21",
    "caption": "Paper image 21: a dragon-like creature of lofts (a sinuous body along a spline, head and legs) covered in scales, two per parametric cell, each two triangles with outward-deflected normals and varied intensity.",
    "image": {"size": [800, 600]}, "camera": {"direction": [0.3, -0.7, 1.0]}, "lights": STUDIO,
    "materials": {"belly": {"diffuse": [0.15, 0.12, 0.05], "specular": 0.2, "exponent": 10},
                  "scale": {"diffuse": [0.25, 0.45, 0.18], "specular": 0.8, "exponent": 35}},
    "objects": dragon_objects})

# ---- Fir tree (image 22): branches as lofted cones in whorls, needles as wire segments ----------
tree = [{"name": "trunk", "source": {"type": "lathe", "profile": [[0.0, 0.0], [0.12, 0.0], [0.09, 1.5], [0.04, 3.5], [0.0, 4.2]],
                                     "interpolation": "linear", "resolution": [24, 24]}, "surface": {"material": "bark"}}]
whorls = 14
branch_count = 0
for w in range(whorls):
    h = 0.5 + 3.5 * w / whorls
    length = 1.6 * (1.0 - (h - 0.5) / 3.9) + 0.15
    for b in range(7):
        a = 2 * math.pi * b / 7 + 2.39996 * w  # successive whorls turned by the golden angle
        d = (math.cos(a), math.sin(a))
        droop = 0.25 * length
        pts = [(0.03 * d[0], 0.03 * d[1], h), (0.5 * length * d[0], 0.5 * length * d[1], h - 0.3 * droop),
               (length * d[0], length * d[1], h - droop)]
        branch_count += 1
        tree.append({"name": "branch %d.%d" % (w + 1, b + 1),
                     "source": loft(pts, [0.035, 0.02, 0.0], (8, 16), up=(0, 0, 1)),
                     "surface": {"material": "bark"},
                     "fur": {"grid": [6, max(12, int(120 * length))], "orientation": [0.0, 0.5, 1.0], "unit_tangents": True,
                             "length": 0.1, "length_variation": 0.2, "intensity_variation": 0.3,
                             "root_colour": [0.35, 0.5, 0.25], "tip_colour": [0.45, 0.65, 0.3], "thickness": 0.008,
                             "material": "needle", "seed": 22}})
write("fir_tree.json", {
    "title": "Fir tree", "paper_image": "22",
    "caption": "Paper image 22: a fir tree whose needles are wire segments grown on conical branch patches in whorls around the trunk, rendered by the A-buffer at the paper's 1024 x 768. The paper ray-cast its tree in 2 hours per frame; the render time is in the gallery's table.",
    "image": {"size": [1024, 768]}, "camera": {"direction": [0.0, -1.0, 0.25]}, "lights": STUDIO,
    "materials": {"bark": {"diffuse": [0.3, 0.2, 0.12], "specular": 0.1, "exponent": 10},
                  "needle": {"diffuse": [0.55, 0.75, 0.45], "specular": 0.6, "exponent": 20}},
    "background": None,
    "objects": tree} if False else {
    "title": "Fir tree", "paper_image": "22",
    "caption": "Paper image 22: a fir tree whose needles are wire segments grown on conical branch patches in whorls around the trunk, rendered by the A-buffer at the paper's 1024 x 768. The paper ray-cast its tree in 2 hours per frame; the render time is in the gallery's table.",
    "image": {"size": [1024, 768], "background": [0.55, 0.65, 0.8]}, "camera": {"direction": [0.0, -1.0, 0.25]}, "lights": STUDIO,
    "materials": {"bark": {"diffuse": [0.3, 0.2, 0.12], "specular": 0.1, "exponent": 10},
                  "needle": {"diffuse": [0.55, 0.75, 0.45], "specular": 0.6, "exponent": 20}},
    "objects": tree})

// Writes the seed corpus of the apps fuzz targets (tests/fuzz/run_fuzz.sh runs it):
//   make_app_seeds DIR
// DIR/mesh/*: each mesh / polyline file of fuzz_app_assets.h, prefixed with the byte that makes
// fuzz_mesh read it as its format; DIR/scene/*.json: scenes that name the asset files fuzz_scene
// writes into its folder (mesh files, tex.png, bump.png) and a CAD file, beside the committed
// scenes of data/scenes, which run_fuzz.sh copies in.
#include "fuzz_app_assets.h"

#include <vtkObject.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace fs = std::filesystem;

namespace {

const char* const kScenes[][2] = {
    {"files_wire_over_surface.json", R"({
  "title": "mesh files", "image": {"size": [64, 48], "mask": "4x4", "budget": 8},
  "materials": {"steel": {"diffuse": [0.5, 0.5, 0.52], "specular": 0.7, "exponent": 50}},
  "objects": [
    {"file": "mesh.vtp", "wire": {"from": "edges", "thickness": 1.5, "units": "pixels", "material": "steel"}},
    {"file": "lines.vtp", "surface": false, "wire": {"from": "lines", "thickness": 0.02}},
    {"file": "mesh.obj", "transform": {"translate": [2, 0, 0], "scale": 0.5}, "surface": {"material": "steel"}},
    {"file": "mesh.ply", "transform": {"rotate": {"axis": [0, 0, 1], "degrees": 30}}, "wire": {"style": "plain"}},
    {"file": "mesh.stl", "transform": {"translate": [0, 2, 0]}},
    {"file": "mesh_binary.vtk", "wire": {"from": "lines", "style": "depth-cued"}}
  ]
})"},
    {"textures.json", R"({
  "image": {"size": [64, 48], "view_grid": 2, "background": [0.1, 0.1, 0.2, 1]},
  "materials": {
    "tex": {"diffuse": 0.8, "texture": {"type": "image", "file": "tex.png", "wrap": [true, false]}},
    "bumpy": {"diffuse": 0.6, "bump": {"type": "image", "file": "bump.png", "scale": 0.05}},
    "noise": {"texture": {"type": "noise", "octaves": 3, "ramp": [[-1, [0, 0, 0]], [0, 0.5], [1, [1, 0.5, 0]]]},
              "bump": {"type": "noise", "frequency": 4, "scale": 0.01}},
    "chequer": {"texture": {"type": "chequer", "squares": [4, 2], "colours": [0.9, [0.1, 0.2, 0.3]]},
                "burnish": {"grain": "radial", "axis": {"point": [0, 0, 0], "direction": [0, 0, 1]},
                            "grooves": {"count": 50, "depth": 0.3, "seed": 3}}}
  },
  "objects": [
    {"source": {"type": "sphere", "radius": 1, "resolution": [24, 12]}, "surface": {"material": "tex"}},
    {"source": {"type": "torus", "major": 1, "minor": 0.3, "resolution": [24, 12]}, "surface": {"material": "bumpy"},
     "transform": {"translate": [3, 0, 0]}},
    {"source": {"type": "plane", "size": [2, 2], "resolution": [4, 4]}, "surface": {"material": "noise"},
     "transform": {"translate": [0, 3, 0]}},
    {"source": {"type": "lathe", "profile": [[0, 0], [1, 0], [1, 1], [0.5, 2]], "corners": [1], "resolution": [16, 8]},
     "surface": {"material": "chequer"}, "wire": {"from": "isolines", "lines": [4, 2]}}
  ]
})"},
    {"growth.json", R"({
  "image": {"size": [48, 32]},
  "camera": {"eye": [4, -4, 3], "target": [0, 0, 0], "up": [0, 0, 1], "fov": 30},
  "lights": {"ambient": 0.1, "directional": [{"direction": [1, -1, 1], "intensity": [1, 0.9, 0.8]}], "space": "world"},
  "materials": {"hair": {"diffuse": [0.4, 0.3, 0.2], "specular": 0.3, "exponent": 20}},
  "objects": [
    {"source": {"type": "torus", "major": 1, "minor": 0.4, "resolution": [16, 8]},
     "fur": {"placement": "area", "density": 200, "length": 0.2, "segments": 4, "gravity": 0.5, "curl": {"amplitude": 0.02, "frequency": 3},
             "clumping": 0.3, "clumps": [8, 4], "wind": {"direction": [1, 0, 0], "strength": 0.1, "time": 0.5},
             "density_map": {"octaves": 2, "range": [0.2, 1]}, "length_map": {"frequency": 2},
             "orientation": [0.2, 0.1, 1], "orientation_map": {"a": {"seed": 4}},
             "regions": [{"centre": [0.5, 0.5], "radius": 0.2, "colour": [1, 0, 0], "falloff": 0.5}],
             "thickness": 0.01, "material": "hair", "seed": 7, "opacity": 0.8}},
    {"source": {"type": "bspline", "points": [[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0.5], [1, 1, 1], [2, 1, 0.5], [0, 2, 0], [1, 2, 0], [2, 2, 0]],
                "count": [3, 3], "periodic": [false, false], "resolution": [8, 8]},
     "scales": {"cells": [6, 6], "size": 1.2, "lift": 0.3, "colour": [0.3, 0.6, 0.3], "seed": 2}},
    {"source": {"type": "loft", "sections": [{"centre": [0, 0, 0], "radius": 0.5}, {"centre": [0, 0, 1], "radii": [0.3, 0.6]},
                                             {"centre": [0, 0, 2], "radius": 0.2}],
                "up": [0, 1, 0], "resolution": [12, 6]},
     "fur": {"placement": "grid", "grid": [6, 6], "jitter": 0.5, "length_mode": "su", "length_per_su": 0.1, "segments": 2,
             "unit_tangents": true, "root_colour_map": {"type": "chequer"}}},
    {"source": {"type": "bezier", "points": [[0, 0, 0], [1, 0, 1], [2, 0, 1], [3, 0, 0], [0, 1, 1], [1, 1, 2], [2, 1, 2], [3, 1, 1],
                                              [0, 2, 1], [1, 2, 2], [2, 2, 2], [3, 2, 1], [0, 3, 0], [1, 3, 1], [2, 3, 1], [3, 3, 0]],
                "resolution": [6, 6]}, "surface": false, "wire": {"from": "isolines", "lines": [3, 3]}},
    {"source": {"type": "box", "size": [1, 1, 1]}, "wire": {"from": "edges", "colour": [1, 1, 0], "opacity": 0.5}}
  ]
})"},
    {"cad_file.json", R"({
  "objects": [{"file": "part.step", "cad": {"deflection": 0.01, "angular_deflection": 20, "isos": 2}, "wire": {"from": "edges"}}]
})"},
    {"orthographic.json", R"({
  "image": {"size": [32, 32], "mask": "8x8"},
  "camera": {"projection": "orthographic", "direction": [0, -1, 1], "fov": 20},
  "lights": {"preset": "studio", "count": 2},
  "materials": {"chrome": {"kind": "chrome", "reflectance": [0.9, 0.8, 0.7]}, "glass": {"opacity": 0.3, "diffuse": [0.2, 0.3, 0.9]}},
  "environment": "mountains",
  "objects": [{"source": {"type": "sphere"}, "surface": {"material": "chrome"}},
              {"source": {"type": "plane"}, "surface": {"material": "glass"}, "transform": {"translate": [0, 0, -1], "scale": [3, 3, 1]}}]
})"},
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR\n", argv[0]);
    return 2;
  }
  vtkObject::GlobalWarningDisplayOff();
  const fs::path dir = argv[1];
  std::error_code ec;
  fs::create_directories(dir / "mesh", ec);
  fs::create_directories(dir / "scene", ec);
  fs::create_directories(dir / "assets", ec);
  const std::vector<std::string> files = wffuzz::writeMeshFiles((dir / "assets").string());
  wffuzz::writeImages((dir / "assets").string());
  int n = 0;
  for (const std::string& name : files) {
    const std::string ext = fs::path(name).extension().string();
    const auto& exts = wffuzz::meshExtensions();
    size_t k = 0;
    while (k < exts.size() && exts[k] != ext) ++k;
    if (k == exts.size()) continue;
    std::ifstream in(dir / "assets" / name, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream out(dir / "mesh" / name, std::ios::binary);
    out.put(char(k));
    out << bytes;
    ++n;
  }
  for (const auto& s : kScenes) {
    std::ofstream(dir / "scene" / s[0], std::ios::binary) << s[1];
    ++n;
  }
  std::printf("make_app_seeds: %d seeds in %s\n", n, dir.c_str());
  return n > 0 ? 0 : 1;
}

// CAD tessellation in `wirefur accuracy`: data/cad/product.step drawn as brushed steel with exact
// shading at rising chordal deflection against the same at a much finer one (2e-5 of the model's
// size), so that the difference is the tessellation alone (facets at the silhouette; normals,
// (u, v) and tangents are exact at every vertex). Time is reading + meshing + rendering. The
// angular deflection is set loose (80 degrees) so that the linear deflection is the knob.
#include "accuracy_cad.h"

#include "cad_input.h"
#include "render_command.h"

#include <chrono>
#include <cstdio>
#include <filesystem>

namespace wfapp {

using json = nlohmann::ordered_json;

json cadTessellationStudy(bool quick, const Progress& progress, std::vector<std::pair<std::string, PlotSpec>>& plots) {
  const std::string path = std::string(WIREFUR_SOURCE_DIR) + "/data/cad/product.step";
  json out = json::array();
  if (!std::filesystem::exists(path)) return out;
  progress.say("CAD tessellation study: " + path);
  const int W = quick ? 200 : 400, H = quick ? 150 : 300;
  wf::RenderOptions o;
  o.width = W;
  o.height = H;
  o.shading = wf::ShadingPath::Exact;
  auto load = [&](double deflection) {
    CadOptions co;
    co.deflection = deflection;
    co.angularDegrees = 80.0;  // the linear deflection decides, not the angle
    SceneOverrides ov;
    ov.cad = co;
    SceneFile sf = sceneForCadFile(path, "burnished", ov);
    reframe(sf, W, H);
    return sf;
  };
  SceneFile ref;
  try {
    ref = load(2e-5);
  } catch (const std::runtime_error& e) {  // a build without CAD support
    std::printf("  skipped: %s\n", e.what());
    return out;
  }
  const wf::RenderResult fine = wf::render(ref.scene, o);
  PlotSpec spec{"CAD tessellation (product.step, brushed steel): error against time (labels: deflection / model size)",
                "read + mesh + render [ms]", "RGBA error vs deflection 2e-5", true, true, {}, {}};
  PlotSeries rms{"RMS", {}, {}, {}, "linespoints"}, mx{"max", {}, {}, {}, "linespoints dt 2"};
  for (double d : quick ? std::vector<double>{1e-2, 1e-3} : std::vector<double>{1e-2, 3e-3, 1e-3, 3e-4, 1e-4}) {
    const auto t0 = std::chrono::steady_clock::now();
    SceneFile sf = load(d);
    const double read = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    sf.scene.camera = ref.scene.camera;  // the same view for every deflection
    const wf::RenderResult r = wf::render(sf.scene, o);
    const ImageError e = imageError(r.image, fine.image);
    const double secs = read + r.stats.total;
    out.push_back({{"deflection_relative", d}, {"triangles", r.stats.triangles}, {"seconds", secs},
                   {"read_mesh_seconds", read}, {"rgba_rms", e.rms}, {"rgba_max", e.max}});
    char label[32];
    std::snprintf(label, sizeof label, "%.0e", d);
    rms.x.push_back(secs * 1e3);
    rms.y.push_back(std::max(e.rms, 1e-7));
    rms.labels.push_back(label);
    mx.x.push_back(secs * 1e3);
    mx.y.push_back(std::max(e.max, 1e-7));
    std::printf("  product.step deflection %-6s %7zu triangles: %7.1f ms (read + mesh %6.1f ms)  RGBA rms %.2e max %.2e\n", label,
                r.stats.triangles, secs * 1e3, read * 1e3, e.rms, e.max);
  }
  spec.series = {rms, mx};
  plots.emplace_back("cad_tessellation.png", spec);
  return out;
}

}  // namespace wfapp

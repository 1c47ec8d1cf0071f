// CAD tessellation in `wirefur accuracy`: data/cad/product.step drawn as brushed steel with exact
// shading at rising chordal deflection against the same at a much finer one (2e-5 of the model's
// size), so that the difference is the tessellation alone (facets at the silhouette; normals,
// (u, v) and tangents are exact at every vertex). Time is reading + meshing + rendering. The
// angular deflection is set loose (80 degrees) so that the linear deflection is the knob.
#include "accuracy_cad.h"
#include "cli.h"

#include "cad_input.h"
#include "render_command.h"

#include "surface/patches.h"
#include "surface/silhouette.h"

#include <chrono>
#include <cstdio>
#include <algorithm>
#include <filesystem>
#include <memory>

namespace wfapp {

using json = nlohmann::ordered_json;

json cadTessellationStudy(bool quick, const Progress& progress, std::vector<std::pair<std::string, PlotSpec>>& plots) {
  const std::string path = dataDir() + "/cad/product.step";
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

json silhouetteStudy(bool quick, const Progress& progress, std::vector<std::pair<std::string, PlotSpec>>& plots) {
  progress.say("silhouette study");
  wf::Camera c;
  c.eye = {2.4, -2.9, 1.6};
  c.target = glm::dvec3(0.0);
  c.up = {0, 0, 1};
  c.fovYDegrees = 35;
  c.nearPlane = 0.1;
  c.farPlane = 100;
  const wf::ViewTransform v = wf::ViewTransform::make(c, 1280, 960);
  const std::vector<std::pair<std::string, std::shared_ptr<const wf::Surface>>> surfaces{
      {"torus", std::make_shared<wf::TorusPatch>(1.0, 0.35)}, {"sphere", std::make_shared<wf::SpherePatch>(1.0)}};
  // Screen distance from p to the nearest chord of `lines`.
  auto distance = [&](const glm::dvec2& p, const std::vector<glm::dvec2>& pts, const wf::PolylineSet& lines) {
    double best = INFINITY;
    for (size_t i = 0; i < lines.polylineCount(); ++i)
      for (std::uint32_t k = lines.starts[i]; k + 1 < lines.starts[i + 1]; ++k) {
        const glm::dvec2 a = pts[k], b = pts[k + 1], d = b - a;
        const double l2 = glm::dot(d, d);
        const double t = l2 > 0 ? std::clamp(glm::dot(p - a, d) / l2, 0.0, 1.0) : 0.0;
        best = std::min(best, glm::length(p - (a + t * d)));
      }
    return best;
  };
  json out = json::array();
  PlotSpec spec{"Silhouette tracing: screen error of the chords against time (labels: tolerance, px)", "trace time per surface [ms]",
                "max distance from a 0.002 px tracing [px]", true, true, {}, {}};
  for (const auto& [name, surface] : surfaces) {
    wf::SilhouetteOptions fineOpt;
    fineOpt.tolerancePx = 0.002;
    fineOpt.grid = 256;
    fineOpt.maxDepth = 20;
    wf::PolylineSet fine;
    wf::SilhouetteStats fs;
    wf::traceSilhouette(*surface, nullptr, v, fineOpt, fine, fs);
    std::vector<glm::dvec2> finePts;
    for (const glm::dvec3& p : fine.points) finePts.push_back(v.project(v.toEye(p)));
    PlotSeries series{name, {}, {}, {}, "linespoints"};
    for (double tol : quick ? std::vector<double>{1.0, 0.1} : std::vector<double>{3.0, 1.0, 0.3, 0.1, 0.03, 0.01}) {
      wf::SilhouetteOptions o;
      o.tolerancePx = tol;
      wf::PolylineSet lines;
      wf::SilhouetteStats st;
      std::vector<double> times;
      for (int rep = 0; rep < (quick ? 1 : 5); ++rep) {
        lines = wf::PolylineSet{};
        st = wf::SilhouetteStats{};
        const auto t0 = std::chrono::steady_clock::now();
        wf::traceSilhouette(*surface, nullptr, v, o, lines, st);
        times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      }
      std::sort(times.begin(), times.end());
      const double secs = times[times.size() / 2];
      // Worst chord: its midpoint's distance from the fine curve (chords within 4 px of a cusp
      // of the fine curve left out: there two branches meet and the nearest one is not its own).
      double worst = 0.0;
      for (size_t i = 0; i < lines.polylineCount(); ++i)
        for (std::uint32_t k = lines.starts[i]; k + 1 < lines.starts[i + 1]; ++k) {
          const glm::dvec2 a = v.project(v.toEye(lines.points[k])), b = v.project(v.toEye(lines.points[k + 1]));
          worst = std::max(worst, distance(0.5 * (a + b), finePts, fine));
        }
      out.push_back({{"surface", name}, {"tolerance_px", tol}, {"points", st.points}, {"evaluations", st.evaluations},
                     {"seconds", secs}, {"max_error_px", worst}});
      char label[32];
      std::snprintf(label, sizeof label, "%g", tol);
      series.x.push_back(secs * 1e3);
      series.y.push_back(std::max(worst, 1e-6));
      series.labels.push_back(label);
      std::printf("  %-6s tolerance %-5s px: %5zu points, %6zu evaluations, %7.3f ms, max chord error %.3f px\n", name.c_str(),
                  label, st.points, st.evaluations, secs * 1e3, worst);
    }
    spec.series.push_back(series);
  }
  plots.emplace_back("silhouettes.png", spec);
  return out;
}

}  // namespace wfapp

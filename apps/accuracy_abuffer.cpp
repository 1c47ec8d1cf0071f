// The A-buffer part of `wirefur accuracy`: error against run time for the mask size and the
// fragment budget K, on a line-rich scene (hairs over a torus) and a triangle scene
// (interpenetrating, partly translucent surfaces and small triangles), each against the
// brute-force reference at 16x16 stratified samples per pixel. Both sides shade by the same
// tables, so the difference is the A-buffer's own: coverage, hiding and the budget tail. Then
// dense hair: round against flat wires, and stochastic simplification.
#include "accuracy_abuffer.h"

#include "render_command.h"
#include "scene_file.h"

#include "geometry/parametric_sources.h"
#include "render/renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

namespace wfapp {

namespace {

using json = nlohmann::ordered_json;

wf::Scene hairScene(int hairs, double thickness = 0.01) {
  wf::Scene s;
  s.lights = wf::LightRig::studioRig(3);
  s.lightsFollowCamera = true;
  s.background = glm::vec4(0.0f);
  wf::Material skin, fur;
  skin.phong = {glm::dvec3(0.35, 0.22, 0.12), glm::dvec3(0.1), 10};
  fur.phong = {glm::dvec3(0.62, 0.42, 0.22), glm::dvec3(0.35), 20};
  s.materials = {wf::Material{}, skin, fur};
  wf::ParametricSource torus;
  torus.type = wf::ParametricSource::Type::Torus;
  torus.major = 1.0;
  torus.minor = 0.4;
  s.surfaces.push_back({"torus", wf::tessellate(torus), 1});
  wf::SceneWire w;
  w.name = "hair";
  w.material = 2;
  w.thickness = thickness;
  w.restsOnSurface = false;  // hairs: the polyline is the axis
  w.aggregate = true;
  std::mt19937_64 rng(15);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const double pi2 = 2 * std::numbers::pi;
  while (int(w.lines.polylineCount()) < hairs) {
    const double u = pi2 * U(rng), v = pi2 * U(rng);
    if (U(rng) * 1.4 > 1.0 + 0.4 * std::cos(v)) continue;
    const glm::dvec3 n(std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v));
    const glm::dvec3 root = glm::dvec3(std::cos(u), std::sin(u), 0.0) + 0.4 * n;
    const glm::dvec3 d = glm::normalize(n + 0.45 * glm::dvec3(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5) * 2.0);
    w.lines.add({root, root + (0.14 + 0.08 * U(rng)) * d});
  }
  s.wires.push_back(std::move(w));
  s.camera = wf::frameSphere(glm::dvec3(0.0), 1.45, 4.0 / 3.0);
  return s;
}

wf::Scene triangleScene() {
  wf::Scene s;
  s.lights = wf::LightRig::studioRig(3);
  s.lightsFollowCamera = true;
  s.background = glm::vec4(0.0f);
  wf::Material a, b, glass;
  a.phong = {glm::dvec3(0.6, 0.3, 0.2), glm::dvec3(0.3), 30};
  b.phong = {glm::dvec3(0.2, 0.4, 0.6), glm::dvec3(0.3), 30};
  glass.phong = {glm::dvec3(0.5), glm::dvec3(0.5), 60};
  glass.opacity = 0.5f;
  s.materials = {wf::Material{}, a, b, glass};
  wf::ParametricSource torus;
  torus.type = wf::ParametricSource::Type::Torus;
  torus.major = 0.8;
  torus.minor = 0.3;
  s.surfaces.push_back({"torus", wf::tessellate(torus), 1});
  wf::TriangleMesh t2 = wf::tessellate(torus);
  wf::transformMesh(t2, glm::dmat4(glm::dvec4(1, 0, 0, 0), glm::dvec4(0, 0, 1, 0), glm::dvec4(0, -1, 0, 0),
                                   glm::dvec4(0.8, 0, 0, 1)));  // linked ring: interpenetrates
  s.surfaces.push_back({"ring", std::move(t2), 2});
  wf::ParametricSource ball;
  ball.type = wf::ParametricSource::Type::Sphere;
  ball.radius = 0.6;
  wf::TriangleMesh g = wf::tessellate(ball);
  wf::transformMesh(g, glm::dmat4(glm::dvec4(1, 0, 0, 0), glm::dvec4(0, 1, 0, 0), glm::dvec4(0, 0, 1, 0),
                                  glm::dvec4(-0.6, -0.4, 0.3, 1)));
  s.surfaces.push_back({"glass", std::move(g), 3});
  // Small random triangles: many partly covered pixels.
  wf::TriangleMesh confetti;
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> U(-1.4, 1.4), E(-0.06, 0.06);
  for (int i = 0; i < 3000; ++i) {
    const glm::dvec3 c(U(rng), U(rng), U(rng) * 0.6);
    const uint32_t base = uint32_t(confetti.positions.size());
    for (int k = 0; k < 3; ++k) confetti.positions.push_back(c + glm::dvec3(E(rng), E(rng), E(rng)));
    confetti.triangles.emplace_back(base, base + 1, base + 2);
  }
  s.surfaces.push_back({"confetti", std::move(confetti), 1});
  s.camera = wf::frameSphere(glm::dvec3(0.0), 1.6, 4.0 / 3.0);
  return s;
}


}  // namespace

double medianSeconds(int reps, const wf::Scene& s, const wf::RenderOptions& o, wf::RenderResult& last) {
  std::vector<double> t;
  for (int i = 0; i < reps; ++i) {
    last = wf::render(s, o);
    t.push_back(last.stats.total);
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

// The view-direction tables (render/view_tables.h): the map path against the exact path at the
// true view vector of every fragment, same A-buffer, so the difference is the shading alone:
// tables plus the view approximation. The shaded cage of image 9b, fields of view 30 and 60 degrees.
json viewGridStudy(bool quick, const Progress& progress, std::vector<std::pair<std::string, PlotSpec>>& plots) {
  progress.say("view-direction tables: map path against exact shading");
  json out = json::array();
  PlotSpec spec{"Shading tables for a grid of view directions: error against time (labels: grid n)",
                "render time incl. table builds [ms]", "RGBA error vs exact shading", true, true, {}, {2e-3}};
  const int W = quick ? 160 : 320, H = quick ? 120 : 240;
  for (double fov : {30.0, 60.0}) {
    // The gallery's shaded cage (image 9b, data/scenes/cage_shaded.json, compiled in), framed
    // at this field of view.
    wf::Scene s = defaultScene().scene;
    wf::Camera cam = wf::frameSphere(glm::dvec3(0.0), 1.45, double(W) / H);
    const double scale = std::tan(glm::radians(cam.fovYDegrees) / 2) / std::tan(glm::radians(fov) / 2);
    cam.eye = cam.target + (cam.eye - cam.target) * scale;
    cam.fovYDegrees = fov;
    cam.nearPlane = cam.farPlane = 0;
    s.camera = cam;
    wf::RenderOptions o;
    o.width = W;
    o.height = H;
    o.shading = wf::ShadingPath::Exact;
    const wf::RenderResult exact = wf::render(s, o);
    PlotSeries rms{"RMS, fov " + std::to_string(int(fov)) + " deg", {}, {}, {}, "linespoints"};
    PlotSeries mx{"max, fov " + std::to_string(int(fov)) + " deg", {}, {}, {}, "linespoints dt 2"};
    for (int n : {1, 2, 3, 5}) {
      o.shading = wf::ShadingPath::Maps;
      o.viewGrid = n;
      wf::RenderResult r;
      const double secs = medianSeconds(quick ? 1 : 3, s, o, r);
      const ImageError e = imageError(r.image, exact.image);
      out.push_back({{"fov_deg", fov}, {"view_grid", n}, {"seconds", secs}, {"maps_seconds", r.stats.maps},
                     {"rgba_rms", e.rms}, {"rgba_max", e.max}, {"estimate_max", r.stats.orthographicError},
                     {"maps_built", r.stats.pseudoReflectanceMaps}, {"spheres_built", r.stats.reflectanceSpheres}});
      rms.x.push_back(secs * 1e3);
      rms.y.push_back(std::max(e.rms, 1e-7));
      rms.labels.push_back(std::to_string(n));
      mx.x.push_back(secs * 1e3);
      mx.y.push_back(std::max(e.max, 1e-7));
      std::printf("  view grid %d, fov %2.0f: %7.2f ms (tables %6.2f ms)  RGBA rms %.2e max %.2e  (estimate %.2e)\n", n,
                  fov, secs * 1e3, r.stats.maps * 1e3, e.rms, e.max, r.stats.orthographicError);
    }
    std::printf("  exact shading, fov %2.0f: %7.2f ms\n", fov, exact.stats.total * 1e3);
    out.push_back({{"fov_deg", fov}, {"view_grid", "exact"}, {"seconds", exact.stats.total}, {"rgba_rms", 0.0}, {"rgba_max", 0.0}});
    spec.series.push_back({"exact shading, fov " + std::to_string(int(fov)) + " deg", {exact.stats.total * 1e3}, {1e-4}, {}, "points pt 7 ps 2"});
    spec.series.push_back(rms);
    spec.series.push_back(mx);
  }
  plots.emplace_back("view_grid.png", spec);
  return out;
}

// Dense hair (render/renderer.h: WireDepth, SimplifyOptions): thin hairs, many times denser than
// the pixels, against the brute-force reference of the full scene with round wires. Points: the
// A-buffer with round wires (the default), with the paper's flat polygons, and with stochastic
// simplification to 0.5 ... 4 pixels, error against time.
json denseHairStudy(bool quick, const Progress& progress, std::vector<std::pair<std::string, PlotSpec>>& plots) {
  progress.say("dense hair: round and flat wires, stochastic simplification, against the reference");
  const int W = quick ? 160 : 320, H = quick ? 120 : 240;
  const int hairs = quick ? 60000 : 100000;  // overlapping about 6 and 10 times over the torus
  const wf::Scene scene = hairScene(hairs, 0.003);  // about 0.2 pixel wide at 320x240
  wf::RenderOptions base;
  base.width = W;
  base.height = H;
  base.referenceSamples = quick ? 8 : 16;
  const wf::RenderResult ref = wf::renderReference(scene, base);
  json out;
  out["size"] = {W, H};
  out["hairs"] = hairs;
  out["reference_seconds"] = ref.stats.total;
  json points = json::array();
  PlotSpec spec{"Dense hair (" + std::to_string(hairs) + " hairs about 0.2 px wide, " + std::to_string(W) + "x" +
                    std::to_string(H) + "): error against time",
                "render time [ms]", "RGBA error vs reference (round wires)", true, true, {}, {}};
  PlotSeries simple{"stochastic simplification (labels: target width, px)", {}, {}, {}, "linespoints"};
  auto point = [&](const std::string& name, const wf::RenderOptions& o, PlotSeries* series, const std::string& label) {
    wf::RenderResult r;
    const double secs = medianSeconds(quick ? 1 : 3, scene, o, r);
    const ImageError e = imageError(r.image, ref.image);
    points.push_back({{"setting", name}, {"seconds", secs}, {"rgba_rms", e.rms}, {"rgba_max", e.max},
                      {"coverage_rms", e.coverageRms}, {"fragments", r.stats.abuffer.fragments},
                      {"hairs_drawn", o.simplify.enabled ? r.stats.simplifiedKept : size_t(hairs)}});
    std::printf("  dense hair %-22s %8.2f ms  RGBA rms %.2e max %.2e  coverage rms %.2e\n", name.c_str(), secs * 1e3, e.rms,
                e.max, e.coverageRms);
    if (series) {
      series->x.push_back(secs * 1e3);
      series->y.push_back(std::max(e.rms, 1e-7));
      series->labels.push_back(label);
    } else {
      spec.series.push_back({name, {secs * 1e3}, {std::max(e.rms, 1e-7)}, {}, "points pt 7 ps 2"});
    }
  };
  point("round wires (default)", base, &simple, "off");
  wf::RenderOptions flat = base;
  flat.wireDepth = wf::WireDepth::Flat;
  point("flat wires (the paper)", flat, nullptr, "");
  for (double target : {0.5, 1.0, 2.0, 4.0}) {
    wf::RenderOptions o = base;
    o.simplify.enabled = true;
    o.simplify.targetWidth = target;
    char label[16];
    std::snprintf(label, sizeof label, "%g", target);
    point(std::string("simplified to ") + label + " px", o, &simple, label);
  }
  spec.series.push_back(simple);
  out["sweep"] = points;
  plots.emplace_back("dense_hair.png", spec);
  return out;
}

json abufferStudy(bool quick, const Progress& progress, std::vector<std::pair<std::string, PlotSpec>>& plots) {
  json out;
  const int W = quick ? 160 : 320, H = quick ? 120 : 240;
  struct Case {
    std::string name;
    wf::Scene scene;
  };
  std::vector<Case> cases;
  cases.push_back({"lines", hairScene(quick ? 1500 : 6000)});
  cases.push_back({"triangles", triangleScene()});
  const std::vector<wf::MaskLayout> masks{{4, 4}, {8, 4}, {8, 8}};
  const std::vector<int> budgets = quick ? std::vector<int>{2, 8, 64} : std::vector<int>{1, 2, 4, 8, 16, 64};
  const int reps = quick ? 1 : 3;
  for (Case& c : cases) {
    progress.say("A-buffer study, " + c.name + " scene: reference at 16x16 samples");
    wf::RenderOptions base;
    base.width = W;
    base.height = H;
    base.referenceSamples = 16;
    const wf::RenderResult ref = wf::renderReference(c.scene, base);
    wf::RenderOptions other = base;
    other.referenceSeed = 2;
    const wf::RenderResult ref2 = wf::renderReference(c.scene, other);
    const ImageError noise = imageError(ref2.image, ref.image);
    json cj;
    cj["size"] = {W, H};
    cj["reference_seconds"] = ref.stats.total;
    // Two references with different jitter differ by sqrt(2) times the noise of one.
    cj["reference_noise_rms"] = noise.rms / std::sqrt(2.0);
    cj["reference_noise_coverage_rms"] = noise.coverageRms / std::sqrt(2.0);
    json points = json::array();
    PlotSpec spec{"A-buffer error against render time, " + c.name + " scene " + std::to_string(W) + "x" +
                      std::to_string(H) + " (labels: budget K)",
                  "render time [ms]", "RGBA error vs 16x16 reference", true, true, {}, {1.0 / 64}};
    for (const wf::MaskLayout& m : masks) {
      PlotSeries rms{"RMS, mask " + m.name(), {}, {}, {}, "linespoints"};
      PlotSeries mx{"max, mask " + m.name(), {}, {}, {}, "linespoints dt 2"};
      for (int k : budgets) {
        wf::RenderOptions o = base;
        o.mask = m;
        o.budget = k;
        wf::RenderResult r;
        const double secs = medianSeconds(reps, c.scene, o, r);
        const ImageError e = imageError(r.image, ref.image);
        points.push_back({{"mask", m.name()},
                          {"budget", k},
                          {"seconds", secs},
                          {"rgba_rms", e.rms},
                          {"rgba_max", e.max},
                          {"coverage_rms", e.coverageRms},
                          {"coverage_max", e.coverageMax},
                          {"fragments", r.stats.abuffer.fragments},
                          {"tail_fragments", r.stats.abuffer.tail},
                          {"pixels_over_budget", r.stats.abuffer.pixelsOverBudget},
                          {"max_fragments_per_pixel", r.stats.abuffer.maxFragmentsPerPixel}});
        rms.x.push_back(secs * 1e3);
        rms.y.push_back(std::max(e.rms, 1e-7));
        rms.labels.push_back(std::to_string(k));
        mx.x.push_back(secs * 1e3);
        mx.y.push_back(std::max(e.max, 1e-7));
        std::printf("  %-9s mask %s K %3d: %7.2f ms  RGBA rms %.2e max %.2e  coverage rms %.2e  tail %llu\n",
                    c.name.c_str(), m.name().c_str(), k, secs * 1e3, e.rms, e.max, e.coverageRms,
                    (unsigned long long)r.stats.abuffer.tail);
      }
      spec.series.push_back(rms);
      spec.series.push_back(mx);
    }
    // Occlusion culling's epsilon (mask 8x4, K 64): error bounded by epsilon against time.
    {
      PlotSeries eps{"RMS, occlusion epsilon (labels), 8x4, K 64", {}, {}, {}, "linespoints dt 4"};
      json ej = json::array();
      for (double e : {0.0, 1e-4, 1e-3, 1e-2}) {
        wf::RenderOptions o = base;
        o.occlusionEpsilon = e;
        wf::RenderResult r;
        const double secs = medianSeconds(reps, c.scene, o, r);
        const ImageError err = imageError(r.image, ref.image);
        ej.push_back({{"occlusion_epsilon", e}, {"seconds", secs}, {"rgba_rms", err.rms}, {"rgba_max", err.max},
                      {"fragments", r.stats.abuffer.fragments}, {"culled", r.stats.abuffer.culled}});
        eps.x.push_back(secs * 1e3);
        eps.y.push_back(std::max(err.rms, 1e-7));
        char label[16];
        std::snprintf(label, sizeof label, "%g", e);
        eps.labels.push_back(label);
        std::printf("  %-9s epsilon %-6g: %7.2f ms  RGBA rms %.2e max %.2e  fragments %llu\n", c.name.c_str(), e,
                    secs * 1e3, err.rms, err.max, (unsigned long long)r.stats.abuffer.fragments);
      }
      spec.series.push_back(eps);
      cj["occlusion_epsilon_sweep"] = ej;
    }
    spec.series.push_back({"reference noise (RMS)", {spec.series[0].x.front(), spec.series[0].x.back()},
                           {cj["reference_noise_rms"].get<double>(), cj["reference_noise_rms"].get<double>()}, {}, "lines dt 3"});
    std::printf("  %-9s reference %.2f s, its own noise RMS %.2e (coverage %.2e)\n", c.name.c_str(), ref.stats.total,
                cj["reference_noise_rms"].get<double>(), cj["reference_noise_coverage_rms"].get<double>());
    cj["sweep"] = points;
    out[c.name] = cj;
    plots.emplace_back("abuffer_" + c.name + ".png", spec);
  }
  out["view_grid"] = viewGridStudy(quick, progress, plots);
  out["dense_hair"] = denseHairStudy(quick, progress, plots);
  return out;
}

}  // namespace wfapp

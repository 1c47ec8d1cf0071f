// Textures and grooves in `wirefur accuracy`. The A-buffer shades a fragment once, so a pattern
// finer than a pixel must be filtered: it box-filters colour maps and grooves over the pixel's
// (u, v) footprint (render/surface_shading.cpp). The reference renderer point-samples the
// pattern at each of its n x n sub-samples and averages, which converges to the true pixel
// integral. Three scenes where the pattern is finer than a pixel over much of the image: a
// torus with a 128 x 64 chequer, a sphere turned with 400 grooves, a bump-mapped torus. For each:
// the A-buffer filtered and point-sampled (the baseline), and the reference at n = 2, 4, 8
// against the reference at n = 16, error against time on the same axes. Also the tessellation
// resolution of a smooth surface, against a much finer tessellation.
#include "accuracy_textures.h"

#include "accuracy_abuffer.h"

#include "render_command.h"

#include "geometry/parametric_sources.h"
#include "render/renderer.h"
#include "texture/grooves.h"
#include "texture/textures.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

namespace wfapp {

namespace {

using json = nlohmann::ordered_json;

wf::Scene baseScene() {
  wf::Scene s;
  s.lights = wf::LightRig::studioRig(3);
  s.lightsFollowCamera = true;
  s.background = glm::vec4(0.0f);
  return s;
}

wf::Scene chequerScene() {
  wf::Scene s = baseScene();
  wf::Material m;
  m.phong = {glm::dvec3(0.9), glm::dvec3(0.4), 30};
  m.colourMap = std::make_shared<wf::ChequerTexture>(128, 64, glm::vec3(0.9f, 0.85f, 0.2f), glm::vec3(0.1f, 0.15f, 0.6f));
  s.materials = {wf::Material{}, m};
  wf::ParametricSource torus;
  torus.type = wf::ParametricSource::Type::Torus;
  torus.minor = 0.42;
  torus.resolutionU = 96;
  torus.resolutionV = 48;
  s.surfaces.push_back({"torus", wf::tessellate(torus), 1});
  s.camera = wf::frameSphere(glm::dvec3(0.0), 1.45, 4.0 / 3.0, wf::Camera::Projection::Perspective, {0.0, -1.0, 0.5});
  return s;
}

wf::Scene grooveScene() {
  wf::Scene s = baseScene();
  wf::Material m;
  m.phong = {glm::dvec3(0.15), glm::dvec3(4.0), 30};
  m.burnish.grain = wf::Burnish::Grain::U;
  m.burnish.grooves = std::make_shared<wf::GrooveTexture>(400.0, 0.6, 6);
  s.materials = {wf::Material{}, m};
  wf::ParametricSource sphere;
  sphere.type = wf::ParametricSource::Type::Sphere;
  sphere.resolutionU = 96;
  sphere.resolutionV = 64;
  s.surfaces.push_back({"sphere", wf::tessellate(sphere), 1});
  s.camera = wf::frameSphere(glm::dvec3(0.0), 1.0, 4.0 / 3.0, wf::Camera::Projection::Perspective, {0.0, -1.0, 0.25});
  return s;
}

wf::Scene bumpScene() {
  wf::Scene s = chequerScene();
  wf::Material m;
  m.phong = {glm::dvec3(0.55, 0.5, 0.42), glm::dvec3(0.3), 20};
  wf::NoiseParams n;
  n.octaves = 6;
  n.frequency = 10;
  n.gain = 0.6;
  n.seed = 13;
  n.periodicU = n.periodicV = true;
  m.bumpMap = std::make_shared<wf::NoiseTexture>(n);
  m.bumpScale = 0.04;
  s.materials = {wf::Material{}, m};
  return s;
}

}  // namespace

// Tessellation resolution: the jug of images 2 and 8 (a smooth surface of revolution) rendered
// with exact shading at rising (u, v) resolution against the same at 768 x 512, so that the
// difference is the polygon approximation alone (silhouette facets, interpolated normals).
json tessellationStudy(bool quick, const Progress& progress, std::vector<std::pair<std::string, PlotSpec>>& plots) {
  progress.say("tessellation study: jug against 768 x 512");
  const int W = quick ? 160 : 320, H = quick ? 160 : 320;
  auto jug = [](int nu, int nv) {
    wf::Scene s = baseScene();
    wf::Material m;
    m.phong = {glm::dvec3(0.75, 0.3, 0.15), glm::dvec3(0.6), 40};
    s.materials = {wf::Material{}, m};
    wf::ParametricSource lathe;
    lathe.type = wf::ParametricSource::Type::Lathe;
    lathe.profile = {{0.0, -1.0}, {0.55, -1.0}, {0.62, -0.9}, {0.7, -0.6}, {0.72, -0.3}, {0.66, 0.0},
                     {0.5, 0.3},  {0.36, 0.55}, {0.32, 0.75}, {0.36, 0.9}, {0.42, 1.0}};
    lathe.resolutionU = nu;
    lathe.resolutionV = nv;
    s.surfaces.push_back({"jug", wf::tessellate(lathe), 1});
    s.camera = wf::frameSphere(glm::dvec3(0.0), 1.25, 1.0, wf::Camera::Projection::Perspective, {0.3, -1.0, 0.35});
    return s;
  };
  wf::RenderOptions o;
  o.width = W;
  o.height = H;
  o.shading = wf::ShadingPath::Exact;
  const wf::RenderResult fine = wf::render(jug(768, 512), o);
  json out = json::array();
  PlotSpec spec{"Tessellation of a smooth surface (jug): error against time, exact shading (labels: u x v)",
                "render time incl. tessellation [ms]", "RGBA error vs 768 x 512", true, true, {}, {}};
  PlotSeries rms{"RMS", {}, {}, {}, "linespoints"}, mx{"max", {}, {}, {}, "linespoints dt 2"};
  for (auto [nu, nv] : quick ? std::vector<std::pair<int, int>>{{24, 16}, {96, 64}}
                             : std::vector<std::pair<int, int>>{{12, 8}, {24, 16}, {48, 32}, {96, 64}, {192, 128}}) {
    const auto t0 = std::chrono::steady_clock::now();
    const wf::Scene s = jug(nu, nv);
    const double tess = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const wf::RenderResult r = wf::render(s, o);
    const ImageError e = imageError(r.image, fine.image);
    const double secs = tess + r.stats.total;
    out.push_back({{"resolution", {nu, nv}}, {"triangles", r.stats.triangles}, {"seconds", secs},
                   {"tessellation_seconds", tess}, {"rgba_rms", e.rms}, {"rgba_max", e.max}});
    const std::string label = std::to_string(nu) + "x" + std::to_string(nv);
    rms.x.push_back(secs * 1e3);
    rms.y.push_back(std::max(e.rms, 1e-7));
    rms.labels.push_back(label);
    mx.x.push_back(secs * 1e3);
    mx.y.push_back(std::max(e.max, 1e-7));
    std::printf("  jug %-8s %6zu triangles: %7.2f ms (tessellation %5.2f ms)  RGBA rms %.2e max %.2e\n", label.c_str(),
                r.stats.triangles, secs * 1e3, tess * 1e3, e.rms, e.max);
  }
  spec.series = {rms, mx};
  plots.emplace_back("tessellation.png", spec);
  return out;
}

json texturesStudy(bool quick, const Progress& progress, std::vector<std::pair<std::string, PlotSpec>>& plots) {
  json out;
  const int W = quick ? 160 : 320, H = quick ? 120 : 240;
  struct Case {
    std::string name;
    wf::Scene scene;
  };
  std::vector<Case> cases;
  cases.push_back({"chequer", chequerScene()});
  cases.push_back({"grooves", grooveScene()});
  cases.push_back({"bump", bumpScene()});
  PlotSpec spec{"Textures finer than a pixel: error against time, " + std::to_string(W) + "x" + std::to_string(H) +
                    " (labels: reference samples n x n)",
                "render time [ms]", "RGBA RMS vs 16x16 reference", true, true, {}, {}};
  for (Case& c : cases) {
    progress.say("textures study, " + c.name + ": reference at 16x16 samples");
    wf::RenderOptions base;
    base.width = W;
    base.height = H;
    base.referenceSamples = 16;
    const wf::RenderResult ref = wf::renderReference(c.scene, base);
    json cj;
    cj["reference_seconds"] = ref.stats.total;
    PlotSeries refSeries{"reference n x n, " + c.name, {}, {}, {}, "linespoints"};
    json refs = json::array();
    for (int n : quick ? std::vector<int>{2, 4} : std::vector<int>{2, 4, 8}) {
      wf::RenderOptions o = base;
      o.referenceSamples = n;
      o.referenceSeed = 7;
      const wf::RenderResult r = wf::renderReference(c.scene, o);
      const ImageError e = imageError(r.image, ref.image);
      refs.push_back({{"samples", n}, {"seconds", r.stats.total}, {"rgba_rms", e.rms}, {"rgba_max", e.max}});
      refSeries.x.push_back(r.stats.total * 1e3);
      refSeries.y.push_back(std::max(e.rms, 1e-7));
      refSeries.labels.push_back(std::to_string(n));
      std::printf("  %-8s reference %2dx%-2d: %8.2f ms  RGBA rms %.2e max %.2e\n", c.name.c_str(), n, n,
                  r.stats.total * 1e3, e.rms, e.max);
    }
    cj["reference"] = refs;
    for (bool filter : {true, false}) {
      wf::RenderOptions o = base;
      o.filterTextures = filter;
      wf::RenderResult r;
      const double secs = medianSeconds(quick ? 1 : 3, c.scene, o, r);
      const ImageError e = imageError(r.image, ref.image);
      const std::string key = filter ? "abuffer_filtered" : "abuffer_point_sampled";
      cj[key] = {{"seconds", secs}, {"rgba_rms", e.rms}, {"rgba_max", e.max}};
      spec.series.push_back({std::string(filter ? "A-buffer, box filter, " : "A-buffer, point sampled, ") + c.name,
                             {secs * 1e3}, {std::max(e.rms, 1e-7)}, {}, filter ? "points pt 7 ps 2" : "points pt 6 ps 2"});
      std::printf("  %-8s A-buffer %-13s: %8.2f ms  RGBA rms %.2e max %.2e\n", c.name.c_str(),
                  filter ? "box filter" : "point sampled", secs * 1e3, e.rms, e.max);
    }
    spec.series.push_back(refSeries);
    out[c.name] = cj;
  }
  plots.emplace_back("textures.png", spec);
  return out;
}

}  // namespace wfapp

#include "accuracy.h"

#include "cli.h"
#include "safe_files.h"
#include "plot.h"
#include "accuracy_abuffer.h"
#include "accuracy_cad.h"
#include "accuracy_shading.h"
#include "accuracy_textures.h"

#include "shading/cylinder_shading.h"
#include "shading/pseudo_reflectance_map.h"
#include "shading/reflectance_sphere.h"

#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <vector>

namespace wfapp {
namespace {

using json = nlohmann::ordered_json;
constexpr double kDeg = std::numbers::pi / 180.0;
const glm::dvec3 kView(0.0, 0.0, 1.0);

// Tangents further than `minDeg` from the view axis, uniform on the sphere, seeded.
std::vector<glm::dvec3> seededTangents(int count, double minDeg, double maxDeg, uint32_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), phi(0.0, 2.0 * std::numbers::pi);
  const double zmax = std::cos(minDeg * kDeg), zmin = std::cos(maxDeg * kDeg);
  std::vector<glm::dvec3> out;
  while (int(out.size()) < count) {
    const double z = u(rng), p = phi(rng);
    if (std::abs(z) > zmax || std::abs(z) < zmin) continue;
    const double r = std::sqrt(1.0 - z * z);
    out.emplace_back(r * std::cos(p), r * std::sin(p), z);
  }
  return out;
}

struct ShadingCase {
  int lights;
  double exponent;
  wf::LightRig rig;
  wf::PhongMaterial material;
  std::vector<glm::dvec3> exact;     // at the study tangents, V = +z
  std::vector<glm::dvec3> exactCap;  // at the near-axis tangents
};

struct ErrorStats {
  double maxLow = 0, rmsLow = 0;    // exponents <= 128
  double maxHigh = 0, rmsHigh = 0;  // exponent 1e4
  double maxCap = 0;                // within the end-on cap (all exponents <= 128)
  double build7ms = 0;              // build time of the 7-light, n = 100 case
  double buildMeanMs = 0;
};

using Indexing = wf::PseudoReflectanceMapOptions::Indexing;
const char* indexingName(Indexing i) { return i == Indexing::Paper ? "paper" : "warped"; }

struct SweepPoint {
  Indexing indexing;
  int resolution, samples;
  ErrorStats e;
};

struct Sweep {
  std::string label;
  std::vector<SweepPoint> points;
};

ErrorStats evaluateMap(std::vector<ShadingCase>& cases, const std::vector<glm::dvec3>& tangents,
                       const std::vector<glm::dvec3>& cap, Indexing indexing, int resolution, int samples) {
  ErrorStats s;
  double sumLow = 0, sumHigh = 0;
  size_t nLow = 0, nHigh = 0;
  for (ShadingCase& c : cases) {
    wf::PseudoReflectanceMap map;
    map.build(c.material, c.rig, {resolution, samples, indexing});
    s.buildMeanMs += map.lastBuildSeconds() * 1e3 / cases.size();
    if (c.lights == 7 && c.exponent == 100.0) s.build7ms = map.lastBuildSeconds() * 1e3;
    const bool low = c.exponent <= 128.0;
    for (size_t i = 0; i < tangents.size(); ++i) {
      const double e = channelError(glm::dvec3(map.lookup(tangents[i])), c.exact[i]);
      if (low) {
        s.maxLow = std::max(s.maxLow, e);
        sumLow += e * e;
        ++nLow;
      } else {
        s.maxHigh = std::max(s.maxHigh, e);
        sumHigh += e * e;
        ++nHigh;
      }
    }
    if (low)
      for (size_t i = 0; i < cap.size(); ++i)
        s.maxCap = std::max(s.maxCap, channelError(glm::dvec3(map.lookup(cap[i])), c.exactCap[i]));
  }
  s.rmsLow = nLow ? std::sqrt(sumLow / nLow) : 0.0;
  s.rmsHigh = nHigh ? std::sqrt(sumHigh / nHigh) : 0.0;
  return s;
}

json toJson(const SweepPoint& p) {
  return json{{"indexing", indexingName(p.indexing)},
              {"resolution", p.resolution},
              {"samples", p.samples},
              {"build_ms_7_lights_n100", p.e.build7ms},
              {"build_ms_mean", p.e.buildMeanMs},
              {"max_error_n_le_128", p.e.maxLow},
              {"rms_error_n_le_128", p.e.rmsLow},
              {"max_error_n_1e4", p.e.maxHigh},
              {"rms_error_n_1e4", p.e.rmsHigh},
              {"max_error_end_on_cap", p.e.maxCap}};
}

template <class F>
double medianNsPerItem(int repetitions, size_t items, const F& body) {
  std::vector<double> t;
  for (int r = 0; r < repetitions; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    body();
    t.push_back(secondsSince(t0) * 1e9 / double(items));
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

}  // namespace

int runAccuracy(const AccuracyOptions& opt) {
  const auto tStart = std::chrono::steady_clock::now();
  const Progress progress(opt.quiet);
  if (!opt.plotsDir.empty()) ensureDirectory(opt.plotsDir);
  if (!opt.jsonPath.empty()) {
    const auto parent = std::filesystem::path(opt.jsonPath).parent_path();
    if (!parent.empty()) ensureDirectory(parent.string());
  }

  // ---- the fixed, seeded study set ---------------------------------------------------------
  const double capDeg = 3.0;
  const int nTangents = opt.quick ? 300 : 2000;
  const std::vector<glm::dvec3> tangents = [&] {
    auto t = seededTangents(nTangents, 0.0, 90.0, 1988);
    // The places where maps are hardest: face-on (z = 0), the map switch |x| = |y|, the axes.
    for (glm::dvec3 s : {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(1, 1, 0), glm::dvec3(1, -1, 0),
                         glm::dvec3(1, 1, 1), glm::dvec3(-1, 1, 0.3), glm::dvec3(0.6, 0.8, 1e-9)})
      t.push_back(glm::normalize(s));
    return t;
  }();
  const std::vector<glm::dvec3> cap = seededTangents(opt.quick ? 50 : 300, 0.2, capDeg, 1989);
  const std::vector<int> rigSizes = {1, 3, 7};
  const std::vector<double> exponents = {1.0, 10.0, 100.0, 1e4};
  std::vector<ShadingCase> cases;
  for (int l : rigSizes)
    for (double n : exponents) {
      ShadingCase c{l, n, wf::LightRig::studioRig(l).canonical(), {}, {}, {}};
      c.material.diffuse = glm::dvec3(0.6);
      c.material.specular = glm::dvec3(0.4);
      c.material.exponent = n;
      cases.push_back(std::move(c));
    }
  progress.say("exact reference values for " + std::to_string(tangents.size()) + " tangents x " +
               std::to_string(cases.size()) + " light rigs");
  const auto tExact = std::chrono::steady_clock::now();
  for (ShadingCase& c : cases) {
    c.exact.resize(tangents.size());
    c.exactCap.resize(cap.size());
    tbb::parallel_for(size_t(0), tangents.size(), [&](size_t i) {
      c.exact[i] = wf::cylinderRadianceExact(tangents[i], kView, c.material, c.rig);
    });
    tbb::parallel_for(size_t(0), cap.size(), [&](size_t i) {
      c.exactCap[i] = wf::cylinderRadianceExact(cap[i], kView, c.material, c.rig);
    });
  }
  const double exactSeconds = secondsSince(tExact);

  // ---- sweeps ------------------------------------------------------------------------------
  // Resolution at the default sample count for both indexings, then samples at the default
  // resolution and indexing.
  const std::vector<int> resolutions = opt.quick ? std::vector<int>{32, 64, 128, 256}
                                                 : std::vector<int>{32, 64, 128, 256, 512, 1024};
  const std::vector<int> sampleCounts = opt.quick ? std::vector<int>{4, 16, 64}
                                                  : std::vector<int>{4, 8, 16, 32, 64, 128, 256, 512, 1024};
  const wf::PseudoReflectanceMapOptions defaults;
  std::vector<Sweep> resSweeps, sampleSweeps;
  for (Indexing ix : {Indexing::Warped, Indexing::Paper}) {
    Sweep sw{std::string(indexingName(ix)) + " indexing, " + std::to_string(defaults.samples) + " samples", {}};
    for (int r : resolutions) {
      progress.say(std::string(indexingName(ix)) + " map " + std::to_string(r) + "^2");
      sw.points.push_back({ix, r, defaults.samples, evaluateMap(cases, tangents, cap, ix, r, defaults.samples)});
    }
    resSweeps.push_back(sw);
  }
  {
    Sweep sw{"warped " + std::to_string(defaults.resolution) + "^2", {}};
    for (int sc : sampleCounts) {
      progress.say("warped map, " + std::to_string(sc) + " samples");
      sw.points.push_back({Indexing::Warped, defaults.resolution, sc,
                           evaluateMap(cases, tangents, cap, Indexing::Warped, defaults.resolution, sc)});
    }
    sampleSweeps.push_back(sw);
  }

  // ---- cost per fragment: lookup (per resolution: cache effects), exact, sampled -----------------
  const ShadingCase& ref = cases[2 * exponents.size() + 2];  // 7 lights, n = 100
  const std::vector<glm::dvec3> fragT = seededTangents(opt.quick ? 1 << 14 : 1 << 18, 0.0, 90.0, 7);
  std::vector<json> lookupCost;
  std::vector<double> lookupNs;
  for (int r : resolutions) {
    wf::PseudoReflectanceMap map;
    map.build(ref.material, ref.rig, {r, defaults.samples});
    float sink = 0.0f;
    const double ns = medianNsPerItem(5, fragT.size(), [&] {
      glm::vec3 acc(0.0f);
      for (const glm::dvec3& t : fragT) acc += map.lookup(t);
      sink += acc.x + acc.y + acc.z;
    });
    if (sink == -1.0f) std::puts("");  // keeps the loop alive
    lookupNs.push_back(ns);
    lookupCost.push_back({{"resolution", r}, {"lookup_ns_per_fragment", ns}, {"map_bytes", map.bytes()}});
  }
  const size_t nExactFrag = opt.quick ? 200 : 2000;
  json exactCost = json::array();
  double exactNs100 = 0;
  for (double n : exponents) {
    wf::PhongMaterial m = ref.material;
    m.exponent = n;
    double sink = 0;
    const double ns = medianNsPerItem(3, nExactFrag, [&] {
      for (size_t i = 0; i < nExactFrag; ++i) sink += wf::cylinderRadianceExact(fragT[i], kView, m, ref.rig).x;
    });
    if (sink == -1.0) std::puts("");
    if (n == 100.0) exactNs100 = ns;
    exactCost.push_back({{"exponent", n}, {"exact_ns_per_fragment", ns}});
  }
  // The paper's sampled mean evaluated per fragment instead of through a map: its cost, and
  // its error (the sampling error alone, no interpolation) on the study tangents.
  double sampledNs = 0, sampledMaxErr = 0;
  {
    const wf::CylinderSampler sampler(defaults.samples);
    double sink = 0;
    sampledNs = medianNsPerItem(3, nExactFrag, [&] {
      for (size_t i = 0; i < nExactFrag; ++i)
        sink += sampler.radiance(wf::cylinderFrame(fragT[i], kView), kView, ref.material, ref.rig,
                                 wf::CylinderSampler::lobeThreshold(ref.material.exponent)).x;
    });
    if (sink == -1.0) std::puts("");
    for (size_t i = 0; i < tangents.size(); ++i)
      sampledMaxErr = std::max(sampledMaxErr,
                               channelError(wf::cylinderRadianceSampled(tangents[i], kView, ref.material, ref.rig,
                                                                        defaults.samples), ref.exact[i]));
  }

  // ---- the orthographic assumption ---------------------------------------------------------------
  progress.say("orthographic assumption against the perspective-correct view direction");
  const std::vector<double> fovs = opt.quick ? std::vector<double>{30, 60, 90}
                                             : std::vector<double>{10, 20, 30, 40, 50, 60, 70, 80, 90};
  const std::vector<glm::dvec3> orthoT(tangents.begin(), tangents.begin() + std::min<size_t>(tangents.size(), opt.quick ? 60 : 300));
  const int grid = 5;  // fragments on a 5x5 grid over a square image, corners included
  json ortho = json::array();
  std::vector<PlotSeries> orthoSeries;
  wf::PseudoReflectanceMap defaultMap;
  for (double n : {10.0, 100.0}) {
    wf::PhongMaterial m = ref.material;
    m.exponent = n;
    defaultMap.build(m, ref.rig, defaults);
    PlotSeries smax{"max, n = " + std::to_string(int(n)), {}, {}, {}, "linespoints"};
    PlotSeries srms{"RMS, n = " + std::to_string(int(n)), {}, {}, {}, "linespoints"};
    std::vector<glm::dvec3> orthoExact(orthoT.size());
    tbb::parallel_for(size_t(0), orthoT.size(), [&](size_t i) {
      orthoExact[i] = wf::cylinderRadianceExact(orthoT[i], kView, m, ref.rig);
    });
    for (double fov : fovs) {
      const double t = std::tan(0.5 * fov * kDeg);
      std::vector<double> err(orthoT.size() * grid * grid), errMap(err.size());
      tbb::parallel_for(size_t(0), orthoT.size(), [&](size_t i) {
        for (int gy = 0; gy < grid; ++gy)
          for (int gx = 0; gx < grid; ++gx) {
            const double px = -1.0 + 2.0 * gx / (grid - 1), py = -1.0 + 2.0 * gy / (grid - 1);
            const glm::dvec3 vTrue = glm::normalize(glm::dvec3(-px * t, -py * t, 1.0));
            const glm::dvec3 persp = wf::cylinderRadianceExact(orthoT[i], vTrue, m, ref.rig);
            err[(i * grid + gy) * grid + gx] = channelError(persp, orthoExact[i]);
            errMap[(i * grid + gy) * grid + gx] = channelError(persp, glm::dvec3(defaultMap.lookup(orthoT[i])));
          }
      });
      double mx = 0, ss = 0, mxMap = 0, ssMap = 0;
      for (size_t k = 0; k < err.size(); ++k) {
        mx = std::max(mx, err[k]);
        ss += err[k] * err[k];
        mxMap = std::max(mxMap, errMap[k]);
        ssMap += errMap[k] * errMap[k];
      }
      const double rms = std::sqrt(ss / err.size()), rmsMap = std::sqrt(ssMap / err.size());
      smax.x.push_back(fov);
      smax.y.push_back(mx);
      srms.x.push_back(fov);
      srms.y.push_back(rms);
      ortho.push_back({{"fov_deg", fov}, {"exponent", n}, {"lights", 7},
                       {"max_error_orthographic", mx}, {"rms_error_orthographic", rms},
                       {"max_error_default_map_vs_perspective", mxMap},
                       {"rms_error_default_map_vs_perspective", rmsMap}});
    }
    orthoSeries.push_back(smax);
    orthoSeries.push_back(srms);
  }

  // ---- reflectance spheres (paper §2.1): resolution x indexing against direct Phong ---------------
  // Rigs of 1 and 3 lights, all in front (l.z > 0), so Phong is continuous over the hemisphere
  // and a max error means something; n = 10 and 100. Normals uniform over the disc (the screen
  // area of a sphere), seeded.
  progress.say("reflectance spheres");
  const std::vector<int> sphereRes = opt.quick ? std::vector<int>{64, 256} : std::vector<int>{64, 128, 256, 512, 1024};
  std::vector<glm::dvec3> discNormals;
  {
    std::mt19937_64 rng(2024);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    while (int(discNormals.size()) < (opt.quick ? 4000 : 40000)) {
      const double x = u(rng), y = u(rng);
      if (x * x + y * y < 1.0) discNormals.push_back(wf::ReflectanceSphere::normalAt(x, y));
    }
  }
  json spheres = json::array();
  std::vector<PlotSeries> sphereSeries;
  double sphereLookupNs = 0, phongNs = 0;
  for (auto ix : {wf::ReflectanceSphere::Indexing::Warped, wf::ReflectanceSphere::Indexing::Williams}) {
    const std::string ixName = ix == wf::ReflectanceSphere::Indexing::Warped ? "warped" : "williams";
    PlotSeries mx{"max, " + ixName, {}, {}, {}, "linespoints"}, rms{"RMS, " + ixName, {}, {}, {}, "linespoints dt 2"};
    for (int r : sphereRes) {
      double maxErr = 0, sumSq = 0, buildMs = 0;
      size_t count = 0;
      for (int lights : {1, 3})
        for (double n : {10.0, 100.0}) {
          wf::PhongMaterial m;
          m.exponent = n;
          const wf::LightRig rig = wf::LightRig::studioRig(lights).canonical();
          const auto t0 = std::chrono::steady_clock::now();
          const wf::ReflectanceSphere s = wf::ReflectanceSphere::phong(r, m, rig, ix);
          buildMs = std::max(buildMs, secondsSince(t0) * 1e3);
          for (const glm::dvec3& N : discNormals) {
            const double e = channelError(glm::dvec3(s.lookup(N)), wf::phongRadiance(N, kView, m, rig));
            maxErr = std::max(maxErr, e);
            sumSq += e * e;
            ++count;
          }
          if (r == 256 && lights == 3 && n == 100.0 && ix == wf::ReflectanceSphere::Indexing::Warped) {
            float sink = 0.0f;
            sphereLookupNs = medianNsPerItem(5, discNormals.size(), [&] {
              glm::vec3 acc(0.0f);
              for (const glm::dvec3& N : discNormals) acc += s.lookup(N);
              sink += acc.x;
            });
            double sinkD = 0.0;
            phongNs = medianNsPerItem(5, discNormals.size(), [&] {
              for (const glm::dvec3& N : discNormals) sinkD += wf::phongRadiance(N, kView, m, rig).x;
            });
            if (sink == -1.0f || sinkD == -1.0) std::puts("");
          }
        }
      const double rmsErr = std::sqrt(sumSq / double(count));
      mx.x.push_back(buildMs);
      mx.y.push_back(maxErr);
      mx.labels.push_back(std::to_string(r));
      rms.x.push_back(buildMs);
      rms.y.push_back(rmsErr);
      spheres.push_back({{"indexing", ixName}, {"resolution", r}, {"build_ms", buildMs},
                         {"max_error", maxErr}, {"rms_error", rmsErr}});
    }
    sphereSeries.push_back(mx);
    sphereSeries.push_back(rms);
  }

  // ---- report ------------------------------------------------------------------------------
  std::printf("Pseudo-reflectance map accuracy (error = max |map - exact| over RGB, linear radiance;\n");
  std::printf("%zu seeded tangents over the sphere x rigs of 1/3/7 lights x n = 1,10,100,1e4;\n", tangents.size());
  std::printf("'cap': %zu tangents 0.2 ... %.0f deg from the view axis)\n\n", cap.size(), capDeg);
  std::printf("%7s %6s %7s %10s %10s %11s %11s %11s %11s %11s\n", "index", "res", "samples", "build7 ms",
              "mean ms", "max n<=128", "rms n<=128", "max n=1e4", "rms n=1e4", "max cap");
  auto row = [](const SweepPoint& p) {
    std::printf("%7s %6d %7d %10.2f %10.2f %11.2e %11.2e %11.2e %11.2e %11.2e\n", indexingName(p.indexing),
                p.resolution, p.samples,
                p.e.build7ms, p.e.buildMeanMs, p.e.maxLow, p.e.rmsLow, p.e.maxHigh, p.e.rmsHigh, p.e.maxCap);
  };
  for (const auto& sw : resSweeps) for (const auto& p : sw.points) row(p);
  for (const auto& sw : sampleSweeps) for (const auto& p : sw.points) row(p);
  std::printf("\nCost per fragment (one thread, 7 lights, n = 100): exact path %.0f ns; the paper's mean of %d samples\n"
              "per fragment %.0f ns (max error %.2e)\n", exactNs100, defaults.samples, sampledNs, sampledMaxErr);
  for (size_t i = 0; i < resolutions.size(); ++i)
    std::printf("  map lookup %4dx%-4d %6.1f ns  (exact / lookup = %.0fx)\n", resolutions[i], resolutions[i],
                lookupNs[i], exactNs100 / lookupNs[i]);
  std::printf("\nReflectance sphere (Phong, 1 and 3 front lights, n = 10 and 100) against direct Phong, whole disc:\n");
  for (const auto& sp : spheres)
    std::printf("  %-8s %5d^2  build %7.2f ms  max %.2e  rms %.2e\n", sp["indexing"].get<std::string>().c_str(),
                sp["resolution"].get<int>(), sp["build_ms"].get<double>(), sp["max_error"].get<double>(),
                sp["rms_error"].get<double>());
  std::printf("  lookup %.1f ns per normal (warped 256^2), direct Phong (3 lights) %.1f ns\n", sphereLookupNs, phongNs);
  std::printf("\nOrthographic assumption (7 lights), error against the perspective-correct value:\n");
  for (const auto& o : ortho)
    if (o["fov_deg"] == 30.0 || o["fov_deg"] == 60.0 || o["fov_deg"] == 90.0)
      std::printf("  fov %3.0f deg n = %-4.0f max %.2e rms %.2e   (default map vs perspective: max %.2e rms %.2e)\n",
                  o["fov_deg"].get<double>(), o["exponent"].get<double>(),
                  o["max_error_orthographic"].get<double>(), o["rms_error_orthographic"].get<double>(),
                  o["max_error_default_map_vs_perspective"].get<double>(),
                  o["rms_error_default_map_vs_perspective"].get<double>());

  json doc;
  doc["study"] = {{"tangents", tangents.size()}, {"end_on_cap_deg", capDeg}, {"cap_tangents", cap.size()},
                  {"rigs_lights", rigSizes}, {"exponents", exponents}, {"seed", 1988},
                  {"error", "max over RGB of |value - exact|, linear radiance, lights summing to 0.95"},
                  {"exact_reference_seconds", exactSeconds}, {"quick", opt.quick}};
  json rs = json::array(), ss = json::array();
  for (const auto& sw : resSweeps) for (const auto& p : sw.points) rs.push_back(toJson(p));
  for (const auto& sw : sampleSweeps) for (const auto& p : sw.points) ss.push_back(toJson(p));
  doc["resolution_sweep"] = rs;
  doc["samples_sweep"] = ss;
  doc["lookup_cost"] = lookupCost;
  doc["exact_cost"] = exactCost;
  doc["sampled_per_fragment"] = {{"samples", defaults.samples}, {"ns", sampledNs}, {"max_error", sampledMaxErr}};
  doc["orthographic_assumption"] = ortho;
  doc["reflectance_sphere"] = {{"sweep", spheres}, {"lookup_ns", sphereLookupNs}, {"direct_phong_ns", phongNs}};

  std::printf("\nA-buffer (mask, budget K) against the brute-force reference (16x16 samples per pixel):\n");
  std::vector<std::pair<std::string, PlotSpec>> abufferPlots;
  doc["abuffer"] = abufferStudy(opt.quick, progress, abufferPlots);
  std::printf("\nTextures and grooves finer than a pixel: box filter against the reference's samples:\n");
  doc["textures"] = texturesStudy(opt.quick, progress, abufferPlots);
  std::printf("\nTessellation resolution of a smooth surface against 768 x 512 (exact shading):\n");
  doc["tessellation"] = tessellationStudy(opt.quick, progress, abufferPlots);
  std::printf("\nCAD tessellation (chordal deflection) against deflection 2e-5 of the model (exact shading):\n");
  doc["cad_tessellation"] = cadTessellationStudy(opt.quick, progress, abufferPlots);
  std::printf("\nSilhouette tracing tolerance against 0.002 px (a torus and a sphere, perspective, 1280 x 960):\n");
  doc["silhouettes"] = silhouetteStudy(opt.quick, progress, abufferPlots);
  std::printf("\nShading paths: the closed form (the default), the paper's maps and the exact path:\n");
  doc["shading_paths"] = shadingPathsStudy(opt.quick, progress, abufferPlots);

  if (!opt.plotsDir.empty()) {
    progress.say("plots into " + opt.plotsDir);
    const std::string dir = opt.plotsDir + "/";
    auto sweepSeries = [](PlotSpec& spec, const Sweep& sw, bool labelResolution) {
      PlotSeries mx{"max, n<=128, " + sw.label, {}, {}, {}, "linespoints"};
      PlotSeries cap{"max within 3 deg of the view axis, " + sw.label, {}, {}, {}, "linespoints dt 3"};
      PlotSeries rms{"RMS, n<=128, " + sw.label, {}, {}, {}, "linespoints dt 2"};
      for (const auto& p : sw.points) {
        mx.x.push_back(p.e.build7ms);
        mx.y.push_back(p.e.maxLow);
        mx.labels.push_back(std::to_string(labelResolution ? p.resolution : p.samples));
        cap.x.push_back(p.e.build7ms);
        cap.y.push_back(p.e.maxCap);
        rms.x.push_back(p.e.build7ms);
        rms.y.push_back(p.e.rmsLow);
      }
      spec.series.push_back(mx);
      spec.series.push_back(cap);
      spec.series.push_back(rms);
    };
    PlotSpec res{"Pseudo-reflectance map: error against build time, resolution sweep (labels: resolution)",
                 "build time, 7 lights, n = 100 [ms]", "error (linear radiance)", true, true, {}, {2e-3}};
    for (const Sweep& sw : resSweeps) sweepSeries(res, sw, true);
    plotPng(res, dir + "map_resolution.png");
    PlotSpec smp{"Pseudo-reflectance map: error against build time, samples sweep (labels: samples)",
                 "build time, 7 lights, n = 100 [ms]", "error (linear radiance)", true, true, {}, {2e-3}};
    for (const Sweep& sw : sampleSweeps) sweepSeries(smp, sw, false);
    plotPng(smp, dir + "map_samples.png");
    PlotSpec cost{"Error against shading time per fragment (7 lights, n = 100)", "time per fragment [ns]",
                  "max error (linear radiance)", true, true, {}, {2e-3}};
    PlotSeries lk{"warped map lookup (labels: resolution)", {}, {}, {}, "linespoints"};
    for (size_t i = 0; i < resolutions.size(); ++i) {
      lk.x.push_back(lookupNs[i]);
      lk.y.push_back(resSweeps[0].points[i].e.maxLow);
      lk.labels.push_back(std::to_string(resolutions[i]));
    }
    cost.series.push_back(lk);
    cost.series.push_back({"exact path (quadrature tol. 1e-10)", {exactNs100}, {1e-10}, {}, "points pt 7 ps 2"});
    cost.series.push_back({"the paper's mean of " + std::to_string(defaults.samples) + " samples, per fragment",
                           {sampledNs}, {sampledMaxErr}, {}, "points pt 5 ps 2"});
    plotPng(cost, dir + "cost_per_fragment.png");
    PlotSpec orth{"Orthographic assumption: error against field of view (7 lights)", "field of view [deg]",
                  "error vs perspective-correct (linear radiance)", false, true, orthoSeries, {2e-3}};
    plotPng(orth, dir + "orthographic.png");
    PlotSpec sph{"Reflectance sphere: error against build time (labels: resolution)", "build time [ms]",
                 "error vs direct Phong (linear radiance)", true, true, sphereSeries, {2e-3}};
    plotPng(sph, dir + "reflectance_sphere.png");
    for (const auto& [file, spec] : abufferPlots) plotPng(spec, dir + file);
  }
  if (!opt.jsonPath.empty()) {
    doc["seconds_total"] = secondsSince(tStart);
    writeOutputText(opt.jsonPath, doc.dump(2) + "\n");
  }
  std::printf("\naccuracy study took %.1f s\n", secondsSince(tStart));
  return 0;
}

}  // namespace wfapp

// Micro-benchmarks of the shading core: what a pseudo-reflectance map costs to build, what one
// lookup costs per fragment, and what the alternatives it replaces cost per fragment (the exact
// cylinder integral, the paper's sampled estimate, and, for the isotropic case, a reflectance
// sphere lookup against Phong evaluated directly).
//
// Every benchmark reports `items_per_second` and a counter `time_per_item` (wall time per texel
// for the builds, per fragment for the rest; the console prints it with its unit, e.g.
// "time_per_item=27.1ns", JSON/CSV hold it in seconds), so that e.g.
//   time_per_item(BM_ExactCylinder/n) / time_per_item(BM_MapLookup)
// is directly the cost of shading a fragment exactly relative to shading it by table lookup.
// All benchmarks use wall-clock time (UseRealTime): the map build is parallel (oneTBB), and the
// single-threaded ones are measured the same way so that their ratios are like for like.
//
// Run: bench_shading --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "shading/cylinder_lobe.h"
#include "shading/cylinder_shading.h"
#include "shading/light.h"
#include "shading/phong.h"
#include "shading/pseudo_reflectance_map.h"
#include "shading/reflectance_sphere.h"

#include <benchmark/benchmark.h>
#include <glm/glm.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

namespace {

constexpr std::uint64_t kSeed = 0x5EEDF00Dull;
constexpr size_t kLookupCount = size_t(1) << 16;  // fragments per iteration for cheap paths
constexpr size_t kExactCount = 1024;              // fragments per iteration for costly paths

// Unit vectors uniform on the sphere (or on the front hemisphere z >= 0), from a fixed seed.
// Uses its own Marsaglia-style rejection on uniform reals so that the set is the same on every
// standard library (std::normal_distribution is implementation-defined).
std::vector<glm::dvec3> randomUnitVectors(size_t count, bool frontHemisphere, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  auto uniform = [&rng] { return double(rng() >> 11) * 0x1.0p-53 * 2.0 - 1.0; };  // [-1, 1)
  std::vector<glm::dvec3> out;
  out.reserve(count);
  while (out.size() < count) {
    const glm::dvec3 p(uniform(), uniform(), uniform());
    const double len2 = glm::dot(p, p);
    if (len2 < 1e-6 || len2 > 1.0) continue;
    glm::dvec3 u = p / std::sqrt(len2);
    if (frontHemisphere) u.z = std::abs(u.z);
    out.push_back(u);
  }
  return out;
}

const std::vector<glm::dvec3>& tangents() {
  static const std::vector<glm::dvec3> t = randomUnitVectors(kLookupCount, false, kSeed);
  return t;
}

const std::vector<glm::dvec3>& normals() {
  static const std::vector<glm::dvec3> n = randomUnitVectors(kLookupCount, true, kSeed + 1);
  return n;
}

wf::PhongMaterial material(double exponent) {
  wf::PhongMaterial m;
  m.exponent = exponent;
  return m.sanitized();
}

const glm::dvec3 kView(0.0, 0.0, 1.0);  // the paper's orthographic view, as the maps assume

// items processed per iteration -> items_per_second, plus time_per_item, the inverse rate
// (items * iterations / t, inverted: seconds per item; the console shows it as ns, us, ...).
void reportPerItem(benchmark::State& state, double itemsPerIteration) {
  state.SetItemsProcessed(std::int64_t(double(state.iterations()) * itemsPerIteration));
  state.counters["time_per_item"] = benchmark::Counter(
      itemsPerIteration, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// ---------------------------------------------------------------------------------------------
using Indexing = wf::PseudoReflectanceMapOptions::Indexing;

wf::PseudoReflectanceMapOptions mapOptions(int resolution, int samples, Indexing indexing) {
  wf::PseudoReflectanceMapOptions o;
  o.resolution = resolution;
  o.samples = samples;
  o.indexing = indexing;
  return o;
}

// Map build. Args: resolution, samples, lights, exponent, indexing (0 = Warped, the default;
// 1 = Paper, the paper's (x, z) indexing).
void BM_MapBuild(benchmark::State& state) {
  const wf::PseudoReflectanceMapOptions opt =
      mapOptions(int(state.range(0)), int(state.range(1)), state.range(4) ? Indexing::Paper : Indexing::Warped);
  const wf::LightRig rig = wf::LightRig::studioRig(int(state.range(2)));
  const wf::PhongMaterial m = material(double(state.range(3)));
  wf::PseudoReflectanceMap map;
  size_t texels = 0;
  for (auto _ : state) {
    map.build(m, rig, opt);
    texels = map.texelsComputed();
    benchmark::DoNotOptimize(map.texels(wf::PseudoReflectanceMap::Plane::XZ).data());
    benchmark::ClobberMemory();
  }
  reportPerItem(state, double(texels));
  state.counters["texels"] = double(texels);
}

void MapBuildArgs(benchmark::internal::Benchmark* b) {
  b->ArgNames({"res", "samples", "lights", "n", "paper"});
  // Resolution sweep at 64 samples, 7 lights.
  for (int res : {64, 128, 256, 512})
    for (int n : {10, 100}) b->Args({res, 64, 7, n, 0});
  // Sample-count sweep at 256 x 256, 7 lights (64 is already above).
  for (int samples : {16, 256})
    for (int n : {10, 100}) b->Args({256, samples, 7, n, 0});
  // Light-count sweep at 256 x 256, 64 samples (7 is already above).
  for (int n : {10, 100}) b->Args({256, 64, 1, n, 0});
  // The paper's indexing at 256 x 256, 64 samples, 7 lights (builds only the texels it reads).
  for (int n : {10, 100}) b->Args({256, 64, 7, n, 1});
}
BENCHMARK(BM_MapBuild)->Apply(MapBuildArgs)->Unit(benchmark::kMillisecond)->UseRealTime();

// ---------------------------------------------------------------------------------------------
// Per-fragment shading of a cylinder with a random tangent.

// Args: exponent, indexing (0 = Warped, 1 = Paper).
void BM_MapLookup(benchmark::State& state) {
  wf::PseudoReflectanceMap map;
  map.build(material(double(state.range(0))), wf::LightRig::studioRig(7),
            mapOptions(256, 64, state.range(1) ? Indexing::Paper : Indexing::Warped));
  const std::vector<glm::dvec3>& ts = tangents();
  for (auto _ : state) {
    glm::vec3 acc(0.0f);
    for (const glm::dvec3& t : ts) acc += map.lookup(t);
    benchmark::DoNotOptimize(acc);
  }
  reportPerItem(state, double(ts.size()));
  state.SetLabel(state.range(1) ? "256x256 paper, 64 samples, 7 lights"
                                 : "256x256 warped, 64 samples, 7 lights");
}
BENCHMARK(BM_MapLookup)->ArgNames({"n", "paper"})->Args({100, 0})->Args({100, 1})->UseRealTime();

void BM_ExactCylinder(benchmark::State& state) {
  const wf::PhongMaterial m = material(double(state.range(0)));
  const wf::LightRig rig = wf::LightRig::studioRig(7).canonical();
  const std::vector<glm::dvec3>& ts = tangents();
  for (auto _ : state) {
    glm::dvec3 acc(0.0);
    for (size_t i = 0; i < kExactCount; ++i) acc += wf::cylinderRadianceExact(ts[i], kView, m, rig);
    benchmark::DoNotOptimize(acc);
  }
  reportPerItem(state, double(kExactCount));
  state.SetLabel("7 lights, relTol 1e-10");
}
BENCHMARK(BM_ExactCylinder)->ArgName("n")->Arg(10)->Arg(100)->Arg(10000)->Arg(100000)->UseRealTime();

// The closed form (shading/cylinder_lobe.h) at the same fragments: with the lobe table (the
// renderer's default path) and with the factor computed exactly (its exact path, which replaced
// the quadrature of BM_ExactCylinder).
void BM_ClosedCylinder(benchmark::State& state) {
  const wf::PhongMaterial m = material(double(state.range(0)));
  const wf::LightRig rig = wf::LightRig::studioRig(7).canonical();
  const std::vector<glm::dvec3>& ts = tangents();
  const bool table = state.range(1) != 0;
  const wf::CylinderLobeTable lobe(m.exponent);
  for (auto _ : state) {
    glm::dvec3 acc(0.0);
    for (size_t i = 0; i < kExactCount; ++i) acc += wf::cylinderRadianceClosed(ts[i], kView, m, rig, table ? &lobe : nullptr);
    benchmark::DoNotOptimize(acc);
  }
  reportPerItem(state, double(kExactCount));
  state.SetLabel(table ? "7 lights, lobe table" : "7 lights, exact factor");
}
BENCHMARK(BM_ClosedCylinder)->ArgNames({"n", "table"})->ArgsProduct({{10, 100, 10000, 100000}, {1, 0}})->UseRealTime();

// The paper's estimate per fragment through the public entry point (which builds its sample
// table on every call) ...
void BM_SampledCylinder(benchmark::State& state) {
  const wf::PhongMaterial m = material(double(state.range(0)));
  const wf::LightRig rig = wf::LightRig::studioRig(7).canonical();
  const std::vector<glm::dvec3>& ts = tangents();
  for (auto _ : state) {
    glm::dvec3 acc(0.0);
    for (size_t i = 0; i < kExactCount; ++i)
      acc += wf::cylinderRadianceSampled(ts[i], kView, m, rig, 64);
    benchmark::DoNotOptimize(acc);
  }
  reportPerItem(state, double(kExactCount));
  state.SetLabel("64 samples, 7 lights");
}
BENCHMARK(BM_SampledCylinder)->ArgName("n")->Arg(10)->Arg(100)->Arg(10000)->Arg(100000)->UseRealTime();

// ... and with the sample table and lobe threshold computed once, as a map build uses them.
void BM_SampledCylinderPrebuilt(benchmark::State& state) {
  const wf::PhongMaterial m = material(double(state.range(0)));
  const wf::LightRig rig = wf::LightRig::studioRig(7).canonical();
  const wf::CylinderSampler sampler(64);
  const double cut = wf::CylinderSampler::lobeThreshold(m.exponent);
  const std::vector<glm::dvec3>& ts = tangents();
  for (auto _ : state) {
    glm::dvec3 acc(0.0);
    for (size_t i = 0; i < kExactCount; ++i) {
      const wf::CylinderFrame fr = wf::cylinderFrame(ts[i], kView);
      if (!fr.endOn) acc += sampler.radiance(fr, kView, m, rig, cut);
    }
    benchmark::DoNotOptimize(acc);
  }
  reportPerItem(state, double(kExactCount));
  state.SetLabel("64 samples, 7 lights, CylinderSampler reused");
}
BENCHMARK(BM_SampledCylinderPrebuilt)->ArgName("n")->Arg(10)->Arg(100)->Arg(10000)->Arg(100000)->UseRealTime();

// ---------------------------------------------------------------------------------------------
// The isotropic case: a reflectance sphere lookup against Phong evaluated per normal.

void BM_ReflectanceSphereLookup(benchmark::State& state) {
  const wf::ReflectanceSphere sphere =
      wf::ReflectanceSphere::phong(256, material(double(state.range(0))), wf::LightRig::studioRig(7));
  const std::vector<glm::dvec3>& ns = normals();
  for (auto _ : state) {
    glm::vec3 acc(0.0f);
    for (const glm::dvec3& n : ns) acc += sphere.lookup(n);
    benchmark::DoNotOptimize(acc);
  }
  reportPerItem(state, double(ns.size()));
  state.SetLabel("256x256, 7 lights");
}
BENCHMARK(BM_ReflectanceSphereLookup)->ArgName("n")->Arg(100)->UseRealTime();

void BM_PhongDirect(benchmark::State& state) {
  const wf::PhongMaterial m = material(double(state.range(0)));
  const wf::LightRig rig = wf::LightRig::studioRig(7).canonical();
  const std::vector<glm::dvec3>& ns = normals();
  for (auto _ : state) {
    glm::dvec3 acc(0.0);
    for (const glm::dvec3& n : ns) acc += wf::phongRadiance(n, kView, m, rig);
    benchmark::DoNotOptimize(acc);
  }
  reportPerItem(state, double(ns.size()));
  state.SetLabel("7 lights");
}
BENCHMARK(BM_PhongDirect)->ArgName("n")->Arg(10)->Arg(100)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();

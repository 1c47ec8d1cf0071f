// Fur generation throughput (src/growth/fur.h): hairs generated per second, on all the threads
// oneTBB gives the process, wall-clock time (UseRealTime). The target for the paper's straight
// hairs on a grid is at least 10 million hairs per second on the 2-core CI machine.
//
// - BM_FurGridStraight: the paper's method, a 1000 x 1000 dithered grid, straight hairs.
// - BM_FurAreaCorrect: the same number of hairs (about 1M) placed per unit area (rejection by
//   |Su x Sv|, each root planned twice: counting and filling).
// - BM_FurGridCurved4: the grid with 4-segment hairs bent by gravity and wind and curled.
// - BM_NaiveGridStraight: the peer, the same hairs as a plain serial loop would make them
//   (std::mt19937 jitter, push_back per point, normal from Su x Sv): the ratio to
//   BM_FurGridStraight is what the generator's design buys.
// - BM_FurGridStraightTorusPatch: BM_FurGridStraight on the library's own TorusPatch.
//
// The surface is an analytic torus defined here (a virtual evaluate with four sines and cosines,
// like the patches of src/surface), so the numbers measure the generator, not a patch library.
// items_per_second = hairs; the counter `hairs` is the hairs per iteration.
//
// Run: bench_growth --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "growth/fur.h"
#include "surface/patches.h"
#include "surface/surface.h"

#include <benchmark/benchmark.h>
#include <glm/glm.hpp>

#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace {

constexpr double kPi = 3.14159265358979323846;

class BenchTorus final : public wf::Surface {
 public:
  BenchTorus(double major, double minor) : R_(major), r_(minor) {}
  wf::ParameterDomain domain() const override { return {0.0, 2 * kPi, 0.0, 2 * kPi, true, true}; }
  wf::SurfacePoint evaluate(double u, double v) const override {
    const double cu = std::cos(u), su = std::sin(u), cv = std::cos(v), sv = std::sin(v);
    const double w = R_ + r_ * cv;
    return {{w * cu, w * su, r_ * sv}, {-w * su, w * cu, 0.0}, {-r_ * sv * cu, -r_ * sv * su, r_ * cv}};
  }
  std::string describe() const override { return "bench torus"; }

 private:
  double R_, r_;
};

void report(benchmark::State& state, std::uint64_t hairs) {
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(hairs));
  state.counters["hairs"] = double(hairs);
}

// Grows `p` on `surface` once per iteration and reports hairs per second.
void grow(benchmark::State& state, const wf::Surface& surface, const wf::FurParams& p) {
  std::uint64_t hairs = 0;
  for (auto _ : state) {
    wf::Fur fur = wf::growFur(surface, p, 0);
    hairs = fur.counts.hairs;
    benchmark::DoNotOptimize(fur.hairs.points.data());
  }
  report(state, hairs);
}

wf::FurParams straightGrid() {
  wf::FurParams p;
  p.gridU = 1000;
  p.gridV = 1000;
  p.length = 0.05;
  return p;
}

void BM_FurGridStraight(benchmark::State& state) { grow(state, BenchTorus(1.0, 0.35), straightGrid()); }
BENCHMARK(BM_FurGridStraight)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_FurAreaCorrect(benchmark::State& state) {
  const BenchTorus torus(1.0, 0.35);
  wf::FurParams p;
  p.placement = wf::FurParams::Placement::AreaCorrect;
  p.density = 1.0e6 / (4 * kPi * kPi * 1.0 * 0.35);  // area of the torus 4 pi^2 R r: ~1M hairs
  p.cellsU = 128;
  p.cellsV = 64;
  p.length = 0.05;
  grow(state, torus, p);
}
BENCHMARK(BM_FurAreaCorrect)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_FurGridCurved4(benchmark::State& state) {
  wf::FurParams p = straightGrid();
  p.segments = 4;
  p.gravity = 0.8;
  p.curlAmplitude = 0.05;
  p.windStrength = 0.3;
  p.time = 0.25;
  grow(state, BenchTorus(1.0, 0.35), p);
}
BENCHMARK(BM_FurGridCurved4)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

void BM_NaiveGridStraight(benchmark::State& state) {
  const BenchTorus torus(1.0, 0.35);
  const int n = 1000;
  std::uint64_t hairs = 0;
  for (auto _ : state) {
    std::vector<glm::dvec3> points;
    std::vector<glm::vec3> colours;
    std::vector<std::uint32_t> starts{0};
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    const wf::ParameterDomain d = torus.domain();
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double u = d.u0 + (i + U(rng)) * d.du() / n, v = d.v0 + (j + U(rng)) * d.dv() / n;
        const wf::SurfacePoint sp = torus.evaluate(u, v);
        const glm::dvec3 N = glm::normalize(glm::cross(sp.Su, sp.Sv));
        const double len = 0.05 * (1.0 + 0.2 * (2.0 * U(rng) - 1.0));
        const float c = float(1.0 + 0.1 * (2.0 * U(rng) - 1.0));
        points.push_back(sp.P);
        points.push_back(sp.P + len * N);
        colours.push_back(glm::vec3(0.3f, 0.2f, 0.12f) * c);
        colours.push_back(glm::vec3(0.55f, 0.42f, 0.3f) * c);
        starts.push_back(std::uint32_t(points.size()));
      }
    hairs = starts.size() - 1;
    benchmark::DoNotOptimize(points.data());
  }
  report(state, hairs);
}
BENCHMARK(BM_NaiveGridStraight)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_FurGridStraightTorusPatch(benchmark::State& state) { grow(state, wf::TorusPatch(1.0, 0.35), straightGrid()); }
BENCHMARK(BM_FurGridStraightTorusPatch)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();

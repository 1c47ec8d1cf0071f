// Adaptive Gauss-Kronrod quadrature of smooth one-dimensional integrands: the reference values
// of the cylinder integrals (shading/cylinder_shading.cpp, shading/cylinder_lobe.cpp).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace wf::quadrature {

// Gauss-Kronrod (7, 15) nodes and weights.
inline constexpr std::array<double, 8> kXgk = {0.991455371120812639206854697526329,
                                        0.949107912342758524526189684047851,
                                        0.864864423359769072789712788640926,
                                        0.741531185599394439863864773280788,
                                        0.586087235467691130294144845693013,
                                        0.405845151377397166906606412076961,
                                        0.207784955007898467600689403773245,
                                        0.000000000000000000000000000000000};
inline constexpr std::array<double, 8> kWgk = {0.022935322010529224963732008058970,
                                        0.063092092629978553290700663189204,
                                        0.104790010322250183839876322541518,
                                        0.140653259715525918745189590510238,
                                        0.169004726639267902826583426598550,
                                        0.190350578064785409913256402421014,
                                        0.204432940075298892414161999234649,
                                        0.209482141084727828012999174891714};
inline constexpr std::array<double, 4> kWg = {0.129484966168869693270611432679082,
                                       0.279705391489276667901467771423780,
                                       0.381830050505118944950369775488975,
                                       0.417959183673469387755102040816327};

template <class F>
void gk15(const F& f, double lo, double hi, double& result, double& err) {
  const double c = 0.5 * (lo + hi), h = 0.5 * (hi - lo);
  const double fc = f(c);
  double rk = fc * kWgk[7], rg = fc * kWg[3];
  for (int j = 0; j < 7; ++j) {
    const double dx = h * kXgk[j];
    const double s = f(c - dx) + f(c + dx);
    rk += kWgk[j] * s;
    if (j % 2 == 1) rg += kWg[j / 2] * s;
  }
  result = rk * h;
  err = std::abs((rk - rg) * h);
}

// Globally adaptive quadrature (in the manner of QUADPACK's QAG): always split the segment with
// the largest error estimate, until the summed estimate meets max(absTol, relTol |total|) or
// kMaxSegments segments exist. The absolute floor and the budget bound the work even where
// rounding noise keeps the estimates from converging (a highlight that barely exists, where
// R.V is the difference of two nearly equal terms). Deterministic: no threads, fixed order.
inline constexpr size_t kMaxSegments = 1500;

template <class F>
double integrateAdaptive(const F& f, const std::vector<std::array<double, 2>>& pieces, double relTol,
                         double absTol) {
  struct Segment {
    double lo, hi, value, err;
  };
  auto lessErr = [](const Segment& a, const Segment& b) { return a.err < b.err; };
  std::vector<Segment> heap;
  heap.reserve(pieces.size() + 64);
  double total = 0.0, totalErr = 0.0;
  for (const auto& p : pieces) {
    Segment sg{p[0], p[1], 0.0, 0.0};
    gk15(f, sg.lo, sg.hi, sg.value, sg.err);
    total += sg.value;
    totalErr += sg.err;
    heap.push_back(sg);
    std::push_heap(heap.begin(), heap.end(), lessErr);
  }
  while (!heap.empty() && totalErr > std::max(absTol, relTol * std::abs(total)) && heap.size() < kMaxSegments) {
    std::pop_heap(heap.begin(), heap.end(), lessErr);
    Segment worst = heap.back();
    heap.pop_back();
    const double mid = 0.5 * (worst.lo + worst.hi);
    if (!(mid > worst.lo && mid < worst.hi) || worst.err == 0.0) {  // cannot be split further
      totalErr -= worst.err;
      worst.err = 0.0;
      heap.push_back(worst);
      std::push_heap(heap.begin(), heap.end(), lessErr);
      continue;
    }
    Segment a{worst.lo, mid, 0.0, 0.0}, b{mid, worst.hi, 0.0, 0.0};
    gk15(f, a.lo, a.hi, a.value, a.err);
    gk15(f, b.lo, b.hi, b.value, b.err);
    total += a.value + b.value - worst.value;
    totalErr += a.err + b.err - worst.err;
    for (const Segment& sg : {a, b}) {
      heap.push_back(sg);
      std::push_heap(heap.begin(), heap.end(), lessErr);
    }
  }
  std::sort(heap.begin(), heap.end(), [](const Segment& x, const Segment& y) { return x.lo < y.lo; });
  double sum = 0.0;  // summed afresh, left to right: no drift from the running updates
  for (const Segment& sg : heap) sum += sg.value;
  return sum;
}

}  // namespace wf::quadrature

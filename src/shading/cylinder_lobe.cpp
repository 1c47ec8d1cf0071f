#include "shading/cylinder_lobe.h"

#include "shading/quadrature.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

namespace wf {

namespace {

// Beyond n x^2 = 745, (1 - x^2)^n <= exp(-n x^2) is below the smallest double: nothing is left
// to integrate there.
constexpr double kTailExponent = 745.0;

// Integer exponents up to this use the recurrence in lobeFactorExact (cheaper than quadrature).
constexpr double kRecurrenceMax = 32.0;

// The lobe's profile (1 - x^2)^n for x in [0, 1]; 1 for n = 0 (the limit from inside, also at
// x = 1). Integer n up to 1024 by binary powering (as the Phong lobe); otherwise through
// log1p, since pow of the rounded 1 - x^2 near x = 0 would lose n ulp (1e-12 at n = 1e4).
double profile(double n, double x) {
  if (n == 0.0) return 1.0;
  if (n <= 1024.0 && n == std::floor(n)) return powInteger((1.0 - x) * (1.0 + x), unsigned(n));
  return std::exp(n * std::log1p(-x * x));
}

// Gauss-Legendre nodes and weights on [-1, 1], by Newton's iteration on the Legendre polynomial.
struct GaussLegendre {
  std::vector<double> x, w;
  explicit GaussLegendre(int n) : x(size_t(n)), w(size_t(n)) {
    const double pi = std::acos(-1.0);
    for (int i = 0; i < n; ++i) {
      double z = std::cos(pi * (i + 0.75) / (n + 0.5)), dp = 1.0;
      for (int it = 0; it < 100; ++it) {
        double p1 = 1.0, p2 = 0.0;
        for (int j = 1; j <= n; ++j) {
          const double p3 = p2;
          p2 = p1;
          p1 = ((2.0 * j - 1.0) * z * p2 - (j - 1.0) * p3) / j;
        }
        dp = n * (z * p1 - p2) / (z * z - 1.0);
        const double step = p1 / dp;
        z -= step;
        if (std::abs(step) < 1e-16) break;
      }
      x[size_t(i)] = z;
      w[size_t(i)] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
  }
  // int_a^b (1 - x^2)^n dx by this rule.
  double lobe(double n, double a, double b) const {
    const double c = 0.5 * (a + b), h = 0.5 * (b - a);
    double s = 0.0;
    for (size_t i = 0; i < x.size(); ++i) s += w[i] * profile(n, c + h * x[i]);
    return s * h;
  }
};

// F_n(x) for n > kRecurrenceMax by fixed Gauss-Legendre rules on the pieces [0, 3], [3, 6] and
// [6, 27.3] lobe widths (1 / sqrt(n)) of ~exp(-n x^2): 44 evaluations at most, relative error
// below 3e-15 against lobeIntegral (tests: CylinderLobe.FactorMatchesClosedForms).
double lobeIntegralFixed(double n, double x) {
  static const GaussLegendre g20(20), g12(12);
  const double sigma = 1.0 / std::sqrt(n);
  const double ends[3] = {3.0 * sigma, 6.0 * sigma, std::sqrt(kTailExponent) * sigma};
  const GaussLegendre* rules[3] = {&g20, &g12, &g12};
  double s = 0.0, a = 0.0;
  for (int k = 0; k < 3 && a < x; ++k) {
    const double b = std::min(x, ends[k]);
    if (b > a) s += rules[k]->lobe(n, a, b);
    a = b;
  }
  return s;
}

}  // namespace

double lobeIntegral(double n, double lo, double hi) {
  n = sanitizedExponent(n);
  lo = std::clamp(std::isnan(lo) ? 0.0 : lo, 0.0, 1.0);
  hi = std::clamp(std::isnan(hi) ? 0.0 : hi, 0.0, 1.0);
  if (!(hi > lo)) return 0.0;
  if (n == 0.0) return hi - lo;
  hi = std::min(hi, std::sqrt(kTailExponent / n));
  if (!(hi > lo)) return 0.0;
  auto f = [n](double x) { return profile(n, x); };
  // The integrand is ~exp(-n x^2): break at multiples of its width so that each piece is smooth
  // on its own scale.
  const double sigma = 1.0 / std::sqrt(2.0 * n);
  std::vector<std::array<double, 2>> pieces;
  double a = lo;
  for (double k : {1.0, 3.0, 8.0, 24.0}) {
    const double b = k * sigma;
    if (b <= a) continue;
    if (b >= hi) break;
    pieces.push_back({a, b});
    a = b;
  }
  pieces.push_back({a, hi});
  return quadrature::integrateAdaptive(f, pieces, 1e-13, 1e-300);
}

double lobeFactorExact(double n, double y) {
  if (!(y > 1e-150)) return 1.0;  // also NaN; G = 1 - n y^2 / 3 + ... is 1 there
  if (std::isinf(y)) return 0.0;
  n = sanitizedExponent(n);
  const double x = std::min(y, 1.0);
  if (n <= kRecurrenceMax && n == std::floor(n)) {
    // Integer exponents by the reduction formula F_k = (x (1 - x^2)^k + 2k F_(k-1)) / (2k + 1),
    // F_0 = x: every term is positive, so the recurrence is stable (relative error ~k ulp).
    const double d = 1.0 - x * x;
    double F = x, p = 1.0;
    for (int k = 1; k <= int(n); ++k) {
      p *= d;
      F = (x * p + 2.0 * k * F) / (2.0 * k + 1.0);
    }
    return F / y;
  }
  // Non-integer exponents up to 32: (1 - x^2)^n has a weak singularity at x = 1 that fixed rules
  // do not resolve; the adaptive quadrature does. Above, it is below 1e-300 of the value there.
  return (n > kRecurrenceMax ? lobeIntegralFixed(n, x) : lobeIntegral(n, 0.0, x)) / y;
}

// Below this exponent the table's nodes are graded towards y = 1 (see the constructor).
constexpr double kGradedBelow = 4.0;

double CylinderLobeTable::yAt(double tau) const {
  if (graded_) {
    const double r = (1.0 - tau) * (1.0 - tau);
    return 1.0 - r * r;
  }
  return tau / ((1.0 - tau) * scale_);
}

double CylinderLobeTable::tauOf(double y) const {
  if (graded_) return 1.0 - std::sqrt(std::sqrt(1.0 - y));
  const double z = y * scale_;
  return z / (1.0 + z);
}

CylinderLobeTable::CylinderLobeTable(double exponent, int nodes) {
  const auto t0 = std::chrono::steady_clock::now();
  n_ = sanitizedExponent(exponent);
  const int K = std::clamp(nodes, 4, 1 << 20);
  // Two node layouts. For n >= 4, uniform in tau = z / (1 + z), z = y sqrt(n + 1): the profile's
  // width 1/sqrt(n) is resolved at any exponent. Below 4 the profile is broad, but near y = 1,
  // F_n(1) - F_n(y) ~ (1 - y)^(n+1) is too rough for cubic Hermite when n is not an integer; the
  // nodes are graded there, y = 1 - (1 - tau)^4, which makes that term (1 - tau)^(4n + 4), smooth.
  graded_ = n_ < kGradedBelow;
  scale_ = std::sqrt(n_ + 1.0);
  tauMax_ = graded_ ? 1.0 : scale_ / (1.0 + scale_);
  const double step = tauMax_ / (K - 1);
  invStep_ = 1.0 / step;
  auto dyDtau = [&](double tau) {
    if (graded_) return 4.0 * (1.0 - tau) * (1.0 - tau) * (1.0 - tau);
    return 1.0 / (scale_ * (1.0 - tau) * (1.0 - tau));
  };
  // int (1 - x^2)^n dx between the points at tau = ta and tb. Graded: in tau itself, where with
  // q = (1 - tau)^4 = 1 - x the integrand (q (2 - q))^n 4 (1 - tau)^3 is smooth: one Gauss-Kronrod
  // panel. Otherwise the adaptive quadrature in x.
  auto piece = [&](double ta, double tb, double ya, double yb) {
    if (!graded_) return lobeIntegral(n_, ya, yb);
    auto f = [&](double tau) {
      const double r = 1.0 - tau, q = r * r * r * r;
      return (n_ == 0.0 ? 1.0 : phongLobe(q * (2.0 - q), n_)) * 4.0 * r * r * r;  // q (2 - q) = 1 - x^2
    };
    double value = 0.0, err = 0.0;
    quadrature::gk15(f, ta, tb, value, err);
    return value;
  };
  std::vector<double> ys(static_cast<size_t>(K)), Fs(static_cast<size_t>(K));
  value_.resize(size_t(K));
  slope_.resize(size_t(K));
  double F = 0.0, prevTau = 0.0;
  for (int i = 0; i < K; ++i) {
    const double tau = i == K - 1 ? tauMax_ : i * step;
    const double y = i == K - 1 ? 1.0 : yAt(tau);
    if (i > 0) F += piece(prevTau, tau, ys[size_t(i) - 1], y);
    prevTau = tau;
    ys[size_t(i)] = y, Fs[size_t(i)] = F;
    const double G = i == 0 ? 1.0 : F / y;
    const double dGdy = i == 0 ? 0.0 : (profile(n_, y) - G) / y;
    value_[size_t(i)] = G;
    slope_[size_t(i)] = dGdy * dyDtau(tau) * step;  // per node spacing
  }
  f1_ = F;
  // The interpolation error: the largest difference at seven points inside every interval,
  // plus 10% for a peak between them (the tests check it against a dense sampling).
  double worst = 0.0;
  for (int i = 0; i + 1 < K; ++i) {
    for (int k = 1; k < 8; ++k) {
      const double tau = (i + k / 8.0) * step, y = yAt(tau);
      const double exact = (Fs[size_t(i)] + piece(i * step, tau, ys[size_t(i)], y)) / y;
      worst = std::max(worst, std::abs(factor(y) - exact));
    }
  }
  error_ = 1.1 * worst;
  buildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double CylinderLobeTable::factor(double y) const {
  if (!(y > 0.0)) return 1.0;  // also NaN
  if (y >= 1.0) return f1_ / y;  // +Inf: 0
  const double x = tauOf(y) * invStep_;
  const int last = int(value_.size()) - 2;
  const int i = std::min(int(x), last);
  const double t = std::min(x - i, 1.0), s = 1.0 - t;
  const double h00 = (1.0 + 2.0 * t) * s * s, h10 = t * s * s, h01 = t * t * (3.0 - 2.0 * t), h11 = -t * t * s;
  return h00 * value_[size_t(i)] + h10 * slope_[size_t(i)] + h01 * value_[size_t(i) + 1] + h11 * slope_[size_t(i) + 1];
}

double lobeRadianceBound(const CylinderLobeTable& table, const PhongMaterial& m, const LightRig& rig) {
  double lightSum = 0.0;
  for (const DirectionalLight& l : rig.lights) lightSum += std::max({l.intensity.x, l.intensity.y, l.intensity.z});
  return table.measuredError() * lightSum * std::max({m.specular.x, m.specular.y, m.specular.z});
}

double cylinderSpecularClosedForm(double a, double b, double u, double w, double v, double exponent,
                                  const CylinderLobeTable* table) {
  if (!std::isfinite(a) || !std::isfinite(b) || !std::isfinite(u) || !std::isfinite(w) || !std::isfinite(v)) return 0.0;
  const double rho = std::sqrt(a * a + b * b);
  if (!(rho > 0.0)) return 0.0;  // light along the axis: no normal is lit
  const double P = rho * v, A = P - u * w;
  if (!(A > 0.0)) return 0.0;
  // cos^2(beta / 2) = (1 + a / rho) / 2, which cancels for beta near pi: there b^2 / (2 rho (rho - a)).
  const double c2 = std::clamp(a >= 0.0 ? 0.5 * (1.0 + a / rho) : b * b / (2.0 * rho * (rho - a)), 0.0, 1.0);
  const double y = std::sqrt(2.0 * c2 * P / A);  // 0 where P = 0: the limit c^2 A^n
  const double n = sanitizedExponent(exponent);
  if (table && table->exponent() != n) table = nullptr;  // a table of another exponent: exact
  return c2 * phongLobe(A, n) * (table ? table->factor(y) : lobeFactorExact(n, y));
}

}  // namespace wf

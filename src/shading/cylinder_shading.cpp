#include "shading/cylinder_shading.h"

#include "core/numeric.h"
#include "shading/cylinder_lobe.h"
#include "core/fast_atan2.h"
#include "shading/quadrature.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace wf {
namespace {

constexpr double kHalfPi = std::numbers::pi / 2;

// Below this sin(angle(T, V)) the cylinder counts as seen end-on. The end-on value is the mean
// of the limits; the largest jump to it is bounded by how fast the true value varies (see docs).
constexpr double kEndOnSin = 1e-9;

// A light within this sine of the cylinder axis lights no normal (N.l = rho cos(...) with rho
// below rounding noise). The true value jumps there (the specular limit of a grazing light from
// behind is not 0), so the decision is made at a fixed threshold, not by rounding noise.
constexpr double kAxisLightSin = 1e-12;

// Per light, everything the cylinder integral depends on.
struct LightTerms {
  double a, b, q;
};

// End-on cylinder: normals on the whole circle perpendicular to T (= V), uniform in angle.
// Diffuse mean: rho / pi. Specular: R.V = -l.V on the lit half (N.V = 0), so [rv > 0] (-q)^n / 2.
glm::dvec3 endOnRadiance(const glm::dvec3& T, const PhongMaterial& m, const LightRig& rig,
                         const glm::dvec3& V) {
  glm::dvec3 out = m.diffuse * rig.ambient;
  for (const DirectionalLight& l : rig.lights) {
    const double lt = glm::dot(l.direction, T);
    const double rho = std::sqrt(std::max(0.0, 1.0 - lt * lt));
    if (!(rho > kAxisLightSin)) continue;
    const double q = glm::dot(l.direction, V);
    out += l.intensity * (m.diffuse * (rho / kPi) + m.specular * (0.5 * phongLobe(-q, m.exponent)));
  }
  return out;
}

// A frame that is end-on: T along V, or T / V zero or non-finite. Undefined input shades as a
// cylinder seen end-on along the eye axis, a defined colour.
glm::dvec3 endOnFallback(const glm::dvec3& T, const glm::dvec3& V, const PhongMaterial& m,
                         const LightRig& rig) {
  const bool ok = finite3(T) && finite3(V) && glm::length(T) > 1e-300 && glm::length(V) > 1e-300;
  const glm::dvec3 vv = ok ? glm::normalize(V) : glm::dvec3(0, 0, 1);
  return endOnRadiance(vv, m, rig, vv);
}

// Intersect [lo, hi] with the union of the given intervals; append non-empty pieces.
void clipAppend(std::vector<std::array<double, 2>>& out, double lo, double hi, double a, double b) {
  const double l = std::max(lo, a), h = std::min(hi, b);
  if (h > l) out.push_back({l, h});
}

}  // namespace

CylinderFrame cylinderFrame(const glm::dvec3& T, const glm::dvec3& V) {
  CylinderFrame f;
  if (!finite3(T) || !finite3(V)) return f;
  const double lt = glm::length(T), lv = glm::length(V);
  if (!(lt > 1e-300) || !(lv > 1e-300) || !std::isfinite(lt) || !std::isfinite(lv)) return f;
  const glm::dvec3 t = T / lt, vv = V / lv;
  const double w = glm::dot(vv, t);
  const glm::dvec3 perp = vv - w * t;
  const double v = glm::length(perp);
  if (!(v > kEndOnSin)) return f;
  f.e1 = perp / v;
  f.e2 = glm::cross(t, f.e1);
  f.t = t;
  f.w = w;
  f.v = std::min(v, 1.0);
  f.endOn = false;
  return f;
}

double cylinderDiffuseClosedForm(double a, double b) {
  if (a == 0.0 && b == 0.0) return 0.0;
  const double beta = std::abs(fastAtan2(b, a));
  // For a light almost straight behind (a ~ -rho, b ~ 0) the two terms cancel to ~-1e-17.
  return std::max(0.0, 0.25 * (std::abs(b) + (kPi - beta) * a));
}

double cylinderSpecularQuadrature(double a, double b, double q, double v, double n,
                                  double relTol) {
  n = sanitizedExponent(n);
  const double rho = std::hypot(a, b);
  if (!(rho > kAxisLightSin) || !std::isfinite(rho) || !std::isfinite(q) || !std::isfinite(v))
    return 0.0;  // light along the axis: no normal is lit
  const double beta = std::atan2(b, a);
  const double P = rho * v;
  // R.V = P (cos(beta) + cos(2 theta - beta)) - q, N.l = rho cos(theta - beta), s = sin(theta).
  const double peakRV = P * (1.0 + std::cos(beta)) - q;
  if (!(peakRV > 0.0)) return 0.0;

  // Lit part of the visible half circle: one interval (|beta| <= pi).
  const double litLo = std::max(-kHalfPi, beta - kHalfPi), litHi = std::min(kHalfPi, beta + kHalfPi);
  // Where R.V > 0: cos(2 theta - beta) > c0, an interval of half width w0 about beta/2, period pi.
  std::vector<std::array<double, 2>> pieces;
  const double c0 = (P > 0.0) ? q / P - std::cos(beta) : (q < 0.0 ? -2.0 : 2.0);
  if (c0 < -1.0) {
    clipAppend(pieces, litLo, litHi, -kHalfPi, kHalfPi);
  } else if (c0 < 1.0) {
    const double w0 = 0.5 * std::acos(c0);
    for (int k = -1; k <= 1; ++k)
      clipAppend(pieces, litLo, litHi, 0.5 * beta - w0 + k * kPi, 0.5 * beta + w0 + k * kPi);
  }
  if (pieces.empty()) return 0.0;

  const double cb = std::cos(beta);
  auto f = [&](double theta) {
    const double rv = P * (cb + std::cos(2.0 * theta - beta)) - q;
    return phongLobe(rv, n) * std::cos(theta);
  };
  // Break points at the peak and at multiples of the lobe width sigma either side: the lobe is
  // ~ exp(-2 n P d^2 / rv*) in d = theta - beta/2, so sigma = sqrt(rv* / (4 n P)).
  std::vector<double> breaks;
  const double peak = 0.5 * beta;
  breaks.push_back(peak);
  if (n > 0.0 && P > 0.0) {
    const double sigma = std::sqrt(peakRV / (4.0 * n * P));
    for (double k : {1.0, 3.0, 8.0, 24.0, 64.0}) {
      breaks.push_back(peak - k * sigma);
      breaks.push_back(peak + k * sigma);
    }
  }
  std::sort(breaks.begin(), breaks.end());
  // The lobe mean is at most 1 and is scaled by ks L <= a few: 1e-15 absolute is far below
  // anything visible, and far above the noise floor that would otherwise stall the quadrature.
  std::vector<std::array<double, 2>> segments;
  for (const auto& pc : pieces) {
    double lo = pc[0];
    for (double br : breaks) {
      if (br <= lo || br >= pc[1]) continue;
      segments.push_back({lo, br});
      lo = br;
    }
    segments.push_back({lo, pc[1]});
  }
  const double total = quadrature::integrateAdaptive(f, segments, std::clamp(relTol, 1e-14, 1e-2), 1e-15);
  return 0.5 * total;
}

glm::dvec3 cylinderRadianceExact(const glm::dvec3& T, const glm::dvec3& V, const PhongMaterial& material,
                                 const LightRig& rig, double relTol) {
  const PhongMaterial m = material.sanitized();
  const CylinderFrame fr = cylinderFrame(T, V);
  if (fr.endOn) return endOnFallback(T, V, m, rig);
  const glm::dvec3 vv = glm::normalize(V);
  glm::dvec3 out = m.diffuse * rig.ambient;
  for (const DirectionalLight& l : rig.lights) {
    const double a = glm::dot(fr.e1, l.direction), b = glm::dot(fr.e2, l.direction);
    const double q = glm::dot(l.direction, vv);
    const double d = cylinderDiffuseClosedForm(a, b);
    const double s = cylinderSpecularQuadrature(a, b, q, fr.v, m.exponent, relTol);
    out += l.intensity * (m.diffuse * d + m.specular * s);
  }
  return out;
}

// Sum over samples k in [kl, kr) of the Phong lobe max(0, R.V)^n with
// R.V = 2 (c_k a + s_k b) c_k v - q. Written as whole-window passes (R.V for every sample, then
// binary powering applied to the whole window) so the compiler vectorises them; the final sum
// stays in order, so every build of the same map is bit-identical.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
double windowLobeSum(
    const double* s, const double* c, int kl, int kr, double a, double b, double v, double q, double n) {
  constexpr int kChunk = 256;
  double x[kChunk], r[kChunk];
  const bool integer = n >= 0.0 && n <= 1024.0 && n == std::floor(n);
  double sum = 0.0;
  for (int base = kl; base < kr; base += kChunk) {
    const int len = std::min(kChunk, kr - base);
    for (int i = 0; i < len; ++i) {
      const int k = base + i;
      const double rv = 2.0 * (c[k] * a + s[k] * b) * c[k] * v - q;
      x[i] = std::clamp(rv, 0.0, 1.0);
    }
    if (n == 0.0) {
      for (int i = 0; i < len; ++i) r[i] = x[i] > 0.0 ? 1.0 : 0.0;
    } else if (integer) {
      for (int i = 0; i < len; ++i) r[i] = 1.0;
      for (unsigned e = unsigned(n); e; e >>= 1) {
        if (e & 1u)
          for (int i = 0; i < len; ++i) r[i] *= x[i];
        for (int i = 0; i < len; ++i) x[i] *= x[i];
      }
    } else {
      for (int i = 0; i < len; ++i) r[i] = x[i] > 0.0 ? std::pow(x[i], n) : 0.0;
    }
    for (int i = 0; i < len; ++i) sum += r[i];
  }
  return sum;
}

CylinderSampler::CylinderSampler(int samples) : samples_(std::max(1, samples)) {
  const int m = samples_;
  s_.resize(m);
  c_.resize(m);
  prefixS_.assign(m + 1, 0.0);
  prefixC_.assign(m + 1, 0.0);
  for (int k = 0; k < m; ++k) {
    s_[k] = -1.0 + (2.0 * k + 1.0) / m;  // midpoints of m equal steps along the diameter
    c_[k] = std::sqrt(std::max(0.0, 1.0 - s_[k] * s_[k]));
    prefixS_[k + 1] = prefixS_[k] + s_[k];
    prefixC_[k + 1] = prefixC_[k] + c_[k];
  }
}

double CylinderSampler::lobeThreshold(double exponent, double lobeCut) {
  lobeCut = std::clamp(lobeCut, 1e-300, 1.0);
  return exponent > 0.0 ? std::pow(lobeCut, 1.0 / exponent) : 0.0;
}

glm::dvec3 CylinderSampler::radiance(const CylinderFrame& fr, const glm::dvec3& view,
                                     const PhongMaterial& m, const LightRig& rig,
                                     double cut) const {
  const int M = samples_;
  const double inv = 1.0 / M, n = m.exponent, halfM = 0.5 * M;
  // Samples k with s_k > x are those with k > (x + 1) M / 2 - 1/2: the first of them.
  auto firstAbove = [M, halfM](double x) {
    const double t = (x + 1.0) * halfM + 0.5;  // >= 0 for x >= -1
    return t <= 0.0 ? 0 : std::min(M, int(t));  // int() is floor() here: t >= 0
  };
  glm::dvec3 out = m.diffuse * rig.ambient;
  for (const DirectionalLight& l : rig.lights) {
    const double a = glm::dot(fr.e1, l.direction), b = glm::dot(fr.e2, l.direction);
    const double q = glm::dot(l.direction, view);
    const double rho = std::sqrt(a * a + b * b);
    if (!(rho > kAxisLightSin)) continue;  // light along the axis lights no normal
    // Lit run [k0, k1): theta in (beta - pi/2, beta + pi/2), i.e. s > -a/rho when b >= 0 and
    // s < a/rho when b < 0. A sample exactly on the boundary has N.l ~ 1e-16 either way.
    const double cb = a / rho;
    int k0 = 0, k1 = M;
    if (b >= 0.0) k0 = firstAbove(-cb);
    else k1 = firstAbove(cb);
    if (k0 >= k1) continue;
    const double dsum = a * (prefixC_[k1] - prefixC_[k0]) + b * (prefixS_[k1] - prefixS_[k0]);
    double ssum = 0.0;
    // R.V = P (cos(beta) + cos(2 theta - beta)) - q peaks at v (rho + a) - q (theta = beta / 2).
    if (fr.v * (rho + a) - q > cut) {
      // Window where R.V > cut: cos(2 theta - beta) > C, theta = beta/2 -+ w with cos(2w) = C.
      // Its ends in s = sin(theta) follow from half-angle identities, no trigonometric calls.
      const double P = rho * fr.v;
      const double ch = std::sqrt(std::max(0.0, 0.5 * (1.0 + cb)));                 // cos(beta/2)
      const double sh = std::copysign(std::sqrt(std::max(0.0, 0.5 * (1.0 - cb))), b);  // sin(beta/2)
      const double C = (cut + q) / P - cb;
      int kl = k0, kr = k1;
      if (C > -1.0) {
        const double cw = std::sqrt(std::max(0.0, 0.5 * (1.0 + C))), sw = std::sqrt(std::max(0.0, 0.5 * (1.0 - C)));
        const double sHi = (ch * cw - sh * sw < 0.0) ? 1.0 : sh * cw + ch * sw;    // past theta = pi/2: clamp
        const double sLo = (ch * cw + sh * sw < 0.0) ? -1.0 : sh * cw - ch * sw;   // before -pi/2: clamp
        kl = std::max(k0, firstAbove(sLo) - 1);
        kr = std::min(k1, firstAbove(sHi) + 1);
      }
      if (kl < kr) ssum = windowLobeSum(s_.data(), c_.data(), kl, kr, a, b, fr.v, q, n);
    }
    out += l.intensity * (m.diffuse * (dsum * inv) + m.specular * (ssum * inv));
  }
  return out;
}

glm::dvec3 cylinderRadianceSampled(const glm::dvec3& T, const glm::dvec3& V, const PhongMaterial& material,
                                   const LightRig& rig, int samples) {
  const PhongMaterial m = material.sanitized();
  const CylinderFrame fr = cylinderFrame(T, V);
  if (fr.endOn) return endOnFallback(T, V, m, rig);
  return CylinderSampler(samples).radiance(fr, glm::normalize(V), m, rig,
                                          CylinderSampler::lobeThreshold(m.exponent));
}


glm::dvec3 cylinderRadianceClosed(const glm::dvec3& T, const glm::dvec3& V, const PhongMaterial& material,
                                  const LightRig& rig, const CylinderLobeTable* table) {
  return cylinderRadianceClosedSanitized(T, V, material.sanitized(), rig, table);
}

glm::dvec3 cylinderRadianceClosedSanitized(const glm::dvec3& T, const glm::dvec3& V, const PhongMaterial& m,
                                           const LightRig& rig, const CylinderLobeTable* table) {
  const CylinderFrame fr = cylinderFrame(T, V);
  if (fr.endOn) return endOnFallback(T, V, m, rig);
  glm::dvec3 out = m.diffuse * rig.ambient;
  const bool specular = m.specular != glm::dvec3(0.0);  // not for the diffuse part of a split material
  for (const DirectionalLight& l : rig.lights) {
    const double a = glm::dot(fr.e1, l.direction), b = glm::dot(fr.e2, l.direction);
    if (!(a * a + b * b > kAxisLightSin * kAxisLightSin)) continue;  // light along the axis lights no normal
    const double spec =
        specular ? cylinderSpecularClosedForm(a, b, glm::dot(fr.t, l.direction), fr.w, fr.v, m.exponent, table) : 0.0;
    out += l.intensity * (m.diffuse * cylinderDiffuseClosedForm(a, b) + m.specular * spec);
  }
  return out;
}

}  // namespace wf

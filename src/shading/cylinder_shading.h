// Shading of a thin cylinder averaged across its visible width (paper §2.2, figure 1).
//
// A cylinder with unit axis T seen along the unit view vector V shows the normals
//   N(s) = sqrt(1 - s^2) e1 + s e2,  s in [-1, 1],
// e1 = the unit part of V perpendicular to T (the normal that faces the viewer most),
// e2 = T x e1; s is the position across the projected diameter, so equal steps in s are
// equal areas on screen. The cylinder radiance is the mean over s of the isotropic model:
//   C(T, V) = 1/2 * integral_{-1}^{1} I(N(s), V) ds.
// Three ways to compute it live here:
//   * cylinderRadianceSampled: the paper's own method, the mean of M samples equally spaced
//     along the diameter (midpoints). This is what fills a PseudoReflectanceMap.
//   * cylinderRadianceExact: the reference. Diffuse in closed form (the cylinder integral of
//     Lambert's law, cf. Mallo et al. 2005, "Illuminated Lines Revisited"), specular by adaptive
//     Gauss-Kronrod quadrature split at the highlight peak and at the exact ends of its support,
//     accurate for exponents up to 1e6.
//   * Both accept any V: V = (0,0,1) is the paper's orthographic assumption; the true direction
//     from a fragment to the eye gives the perspective-correct value.
// T and -T are the same cylinder and give the same value. When T is parallel to V (seen
// end-on) the limit depends on the direction of approach; we return the mean of those limits,
// which is the mean of the model over the whole circle of normals.
#pragma once

#include "shading/light.h"
#include "shading/phong.h"

#include <glm/glm.hpp>

#include <cmath>
#include <vector>

namespace wf {

/// The frame of a cylinder as seen from V (see the file comment).
struct CylinderFrame {
  glm::dvec3 e1{0.0}, e2{0.0};
  glm::dvec3 t{0.0};    ///< the unit axis T
  double w = 0.0;       ///< V.T for unit V and T = cos(angle between T and V)
  double v = 0.0;       ///< |V - (V.T)T| = sin(angle between T and V)
  bool endOn = true;    ///< T (nearly) parallel to V, or T / V undefined (zero, NaN, Inf)
};

/// Frame for any T, V (need not be unit). Degenerate input yields endOn = true.
CylinderFrame cylinderFrame(const glm::dvec3& T, const glm::dvec3& V);

/// The same for a unit, finite T and V = (0, 0, 1), without the checks and normalisations
/// (the map build's inner loop).
inline CylinderFrame cylinderFrameOrthographic(const glm::dvec3& unitT) {
  CylinderFrame f;
  const double v = std::sqrt(unitT.x * unitT.x + unitT.y * unitT.y);  // |V - (V.T) T|
  if (!(v > 1e-9)) return f;
  f.e1 = glm::dvec3(-unitT.z * unitT.x, -unitT.z * unitT.y, v * v) / v;
  f.e2 = glm::cross(unitT, f.e1);
  f.t = unitT;
  f.w = unitT.z;
  f.v = std::min(v, 1.0);
  f.endOn = false;
  return f;
}

/// Reference value of the cylinder-averaged Phong model. `relTol` is the relative tolerance of
/// the specular quadrature per light (the diffuse part is exact).
glm::dvec3 cylinderRadianceExact(const glm::dvec3& T, const glm::dvec3& V, const PhongMaterial& m,
                                 const LightRig& rig, double relTol = 1e-10);

/// The paper's estimate: mean of `samples` normals at the midpoints of equal steps along the
/// projected diameter (see CylinderSampler; specular samples below 1e-8 of the light are skipped).
glm::dvec3 cylinderRadianceSampled(const glm::dvec3& T, const glm::dvec3& V, const PhongMaterial& m,
                                   const LightRig& rig, int samples);

/// The paper's equal-spacing samples for one sample count M, precomputed so that the mean costs
/// O(1) per light for the diffuse part and O(samples inside the highlight) for the specular part:
/// the lit samples form one contiguous run in s (prefix sums of sqrt(1-s^2) and s give the
/// diffuse sum exactly), and R.V is unimodal in s, so the specular sum runs only over the
/// window where the lobe exceeds `lobeCut`, found in closed form (the error of leaving out the
/// rest is at most lobeCut * ks * L per light).
class CylinderSampler {
 public:
  explicit CylinderSampler(int samples);
  int samples() const { return samples_; }
  /// Same quantity as cylinderRadianceSampled; `frame` must not be end-on, `view` unit,
  /// material sanitised and rig canonical; `cut` = lobeThreshold(m.exponent).
  glm::dvec3 radiance(const CylinderFrame& frame, const glm::dvec3& view, const PhongMaterial& m,
                      const LightRig& rig, double cut) const;
  /// The R.V below which the lobe (R.V)^n is under `lobeCut` (0 for n = 0).
  static double lobeThreshold(double exponent, double lobeCut = 1e-8);

 private:
  int samples_;
  std::vector<double> s_, c_, prefixS_, prefixC_;
};

/// Closed form of 1/2 * int_{-1}^{1} max(0, sqrt(1-s^2) a + s b) ds (a = e1.l, b = e2.l):
/// (|b| + (pi - |beta|) a) / 4 with beta = atan2(b, a).
double cylinderDiffuseClosedForm(double a, double b);

/// 1/2 * int_{-1}^{1} [N.l > 0] max(0, R.V)^n ds for one light, by adaptive quadrature.
/// a = e1.l, b = e2.l, q = l.V, v = frame.v.
double cylinderSpecularQuadrature(double a, double b, double q, double v, double n,
                                  double relTol = 1e-10);

}  // namespace wf

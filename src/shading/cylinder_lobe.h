// The cylinder-averaged Phong model in closed form, at any view vector (perspective-exact).
//
// For one directional light l, a cylinder with unit axis T seen along unit V (notation of
// shading/cylinder_shading.h) depends on three numbers only: u = T.l, w = T.V and q = l.V.
// With rho = sqrt(1 - u^2), v = sqrt(1 - w^2), P = rho v and beta the angle between the parts of
// l and V across the axis (cos beta = (q - u w) / P):
//
//   diffuse   D = (rho |sin beta| + (pi - beta) rho cos beta) / 4          (Mallo et al. 2005)
//   specular  S = 1/2 int [N.l > 0] max(0, R.V)^n ds  =  c^2 A^n G_n(c sqrt(2P / A))
//
// where A = P - u w (the largest R.V over the cylinder, -cos of the sum of the angles of l and
// V to the axis), c = cos(beta / 2), and G_n(y) = F_n(min(y, 1)) / y, F_n(y) = int_0^y
// (1 - x^2)^n dx (an incomplete beta function). Derivation: along the cylinder's normals
// N(theta) = cos(theta) e1 + sin(theta) e2 (s = sin theta), R.V = P cos(2 theta - beta) - u w
// and N.l = rho cos(theta - beta); with psi = theta - beta/2 the visible, lit normals are
// |psi| < (pi - beta)/2, the lobe is even in psi, so the weight cos(theta) = cos(psi + beta/2)
// keeps only cos(psi) cos(beta/2); t = sin(psi) turns R.V into A - 2P t^2 and the integral into
// c int_0^c max(0, A - 2P t^2)^n dt. docs/shading.md has the steps.
//
// So the one non-elementary factor is G_n, a function of one variable per exponent, independent
// of the light, the camera and the frame. CylinderLobeTable tabulates it once per exponent
// (256 nodes, cubic Hermite in a warped coordinate, about 1 ms: error <= 4e-9 for exponents 0 ...
// 1e6); lobeFactorExact computes G_n to ~1e-15 for the exact path. Both are checked against the
// quadrature over theta (cylinderSpecularQuadrature) in the tests.
#pragma once

#include "shading/light.h"
#include "shading/phong.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <vector>

namespace wf {

/// F_n(y) = int_lo^hi (1 - x^2)^n dx for 0 <= lo <= hi <= 1, by adaptive Gauss-Kronrod quadrature
/// to a relative 1e-13 (exact for n = 0). n is sanitised as a Phong exponent.
double lobeIntegral(double n, double lo, double hi);

/// G_n(y) = F_n(min(y, 1)) / y, 1 at y = 0 (the mean of (1 - x^2)^n over [0, min(y, 1)] times
/// min(y, 1) / y), computed exactly: the recurrence for integer n <= 32, fixed Gauss-Legendre
/// rules above 32, lobeIntegral for the rest (relative error < 3e-15).
double lobeFactorExact(double n, double y);

/// G_n tabulated for one exponent: cubic Hermite on nodes uniform in tau = z / (1 + z),
/// z = y sqrt(n + 1), which resolves the lobe's width 1 / sqrt(n) at any exponent and holds the
/// whole of [0, 1] (exponents below 4: in tau with y = 1 - (1 - tau)^4, graded towards 1 where
/// F_n has a weak singularity); beyond y = 1, G_n(y) = F_n(1) / y exactly.
class CylinderLobeTable {
 public:
  explicit CylinderLobeTable(double exponent, int nodes = 256);
  double exponent() const { return n_; }
  int nodes() const { return int(value_.size()); }
  /// G_n(y) for y >= 0 (NaN and negative y: 1, the value at 0; +Inf: 0).
  double factor(double y) const;
  /// The interpolation error: 1.1 times the largest difference to the exact factor found at seven
  /// points inside every interval when the table was built.
  double measuredError() const { return error_; }
  double buildSeconds() const { return buildSeconds_; }
  size_t bytes() const { return (value_.size() + slope_.size()) * sizeof(double); }

 private:
  double yAt(double tau) const;   // the node coordinate's inverse
  double tauOf(double y) const;   // the node coordinate (see the constructor)
  double n_ = 0.0;
  bool graded_ = false;    // exponents below 4: nodes graded towards y = 1
  double scale_ = 1.0;     // sqrt(n + 1)
  double tauMax_ = 0.5;    // tau at y = 1
  double invStep_ = 1.0;   // 1 / node spacing in tau
  double f1_ = 1.0;        // F_n(1)
  std::vector<double> value_, slope_;  // G and dG/dtau at the nodes
  double error_ = 0.0;
  double buildSeconds_ = 0.0;
};

/// The bound on |closed - exact| of the cylinder radiance of `m` under `rig` with `table`: the
/// table's error enters once per light (c^2 A^n <= 1), scaled by the light and the specular
/// colour, largest components (the renderer's and the VTK filter's reported estimate).
double lobeRadianceBound(const CylinderLobeTable& table, const PhongMaterial& m, const LightRig& rig);

/// The specular factor S of one light (see the file comment), from the light in the cylinder's
/// frame (a = e1.l, b = e2.l, v = frame.v: accurate near the axis, where 1 - u^2 and 1 - w^2
/// are not) and u = T.l, w = T.V. `table` null, or built for another exponent: exact
/// (lobeFactorExact). The same quantity as cylinderSpecularQuadrature(a, b, l.V, v, exponent).
double cylinderSpecularClosedForm(double a, double b, double u, double w, double v, double exponent,
                                  const CylinderLobeTable* table);

/// The cylinder-averaged Phong radiance, as cylinderRadianceExact, in closed form: G_n from
/// `table` (built for m.exponent after sanitising) or, when it is null, computed exactly. Any T and
/// V (need not be unit); end-on and undefined input as cylinderRadianceExact.
glm::dvec3 cylinderRadianceClosed(const glm::dvec3& T, const glm::dvec3& V, const PhongMaterial& m,
                                  const LightRig& rig, const CylinderLobeTable* table = nullptr);
/// cylinderRadianceClosed for a material that is already PhongMaterial::sanitized (a prepared
/// scene's ShaderSlot::phong, and its parts): the same value, without re-sanitising per call.
glm::dvec3 cylinderRadianceClosedSanitized(const glm::dvec3& T, const glm::dvec3& V, const PhongMaterial& m,
                                           const LightRig& rig, const CylinderLobeTable* table = nullptr);

}  // namespace wf

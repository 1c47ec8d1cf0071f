// The isotropic Phong model (paper §2.1, image 1): the model every reflectance sphere and
// every pseudo-reflectance map in WireFur is built from.
#pragma once

#include "shading/light.h"

#include <glm/glm.hpp>

#include <string>

namespace wf {

struct PhongMaterial {
  glm::dvec3 diffuse{0.6};
  glm::dvec3 specular{0.4};
  double exponent = 20.0;  ///< Phong exponent n in (R.V)^n; 0 ... 1e6

  /// Finite, non-negative colours and an exponent in [0, 1e6] (NaN exponent -> 1).
  PhongMaterial sanitized() const;
  bool operator==(const PhongMaterial&) const = default;
  std::string toString() const;
};

/// Largest exponent any entry point accepts; larger values are clamped to it.
inline constexpr double kMaxPhongExponent = 1e6;

/// Phong radiance towards the viewer for unit normal N and unit view vector V (surface to eye):
///   kd * (ambient + sum_i L_i max(0, N.l_i)) + ks * sum_i L_i [N.l_i > 0] max(0, R_i.V)^n,
/// R_i = 2 (N.l_i) N - l_i. `rig` must be canonical (LightRig::canonical).
/// N and V need not be unit; a zero or non-finite N or V gives the ambient term alone.
glm::dvec3 phongRadiance(const glm::dvec3& N, const glm::dvec3& V, const PhongMaterial& m,
                         const LightRig& rig);
/// phongRadiance for a material that is already PhongMaterial::sanitized (a prepared scene's
/// ShaderSlot::phong, and its diffuse or specular part): the same value, without re-sanitising
/// per call (about 70 instructions of each fragment's shading).
glm::dvec3 phongRadianceSanitized(const glm::dvec3& N, const glm::dvec3& V, const PhongMaterial& m,
                                  const LightRig& rig);

/// The exponent every entry point uses: NaN -> 1, clamped to [0, kMaxPhongExponent].
double sanitizedExponent(double n);

/// x^e by binary powering: several times cheaper than pow() and exact to a few ulp (the Phong
/// lobe's integer exponents, and the cylinder lobe's profile, shading/cylinder_lobe.cpp).
inline double powInteger(double x, unsigned e) {
  double r = 1.0;
  for (; e; e >>= 1) {
    if (e & 1u) r *= x;
    x *= x;
  }
  return r;
}

/// max(0, x)^n with the convention that 0^0 is the indicator [x > 0]; defined for all x, n >= 0.
double phongLobe(double x, double n);

}  // namespace wf

#include "shading/phong.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace wf {

PhongMaterial PhongMaterial::sanitized() const {
  PhongMaterial m = *this;
  for (int i = 0; i < 3; ++i) {
    m.diffuse[i] = std::isfinite(diffuse[i]) ? std::max(0.0, diffuse[i]) : 0.0;
    m.specular[i] = std::isfinite(specular[i]) ? std::max(0.0, specular[i]) : 0.0;
  }
  m.exponent = sanitizedExponent(exponent);
  return m;
}

std::string PhongMaterial::toString() const {
  std::ostringstream s;
  s << "PhongMaterial{kd=(" << diffuse.x << "," << diffuse.y << "," << diffuse.z << ") ks=("
    << specular.x << "," << specular.y << "," << specular.z << ") n=" << exponent << "}";
  return s.str();
}

double sanitizedExponent(double n) {
  return std::isnan(n) ? 1.0 : std::clamp(n, 0.0, kMaxPhongExponent);
}

double phongLobe(double x, double n) {
  if (!(x > 0.0)) return 0.0;  // also NaN
  n = sanitizedExponent(n);
  x = std::min(x, 1.0);
  // Integer exponents up to 1024 (the common case, and the paper's) by binary powering:
  // several times cheaper than pow() and exact to a few ulp.
  if (n <= 1024.0 && n == std::floor(n)) return powInteger(x, unsigned(n));
  return std::pow(x, n);
}

glm::dvec3 phongRadiance(const glm::dvec3& N, const glm::dvec3& V, const PhongMaterial& material,
                         const LightRig& rig) {
  return phongRadianceSanitized(N, V, material.sanitized(), rig);
}

glm::dvec3 phongRadianceSanitized(const glm::dvec3& N, const glm::dvec3& V, const PhongMaterial& m,
                                  const LightRig& rig) {
  glm::dvec3 out = m.diffuse * rig.ambient;
  const double ln = glm::length(N), lv = glm::length(V);
  if (!(ln > 0.0) || !(lv > 0.0) || !std::isfinite(ln) || !std::isfinite(lv)) return out;
  const glm::dvec3 n = N / ln, v = V / lv;
  const double nv = glm::dot(n, v);
  for (const DirectionalLight& l : rig.lights) {
    const double nl = glm::dot(n, l.direction);
    if (!(nl > 0.0)) continue;
    const double rv = 2.0 * nl * nv - glm::dot(l.direction, v);
    out += l.intensity * (m.diffuse * nl + m.specular * phongLobe(rv, m.exponent));
  }
  return out;
}

}  // namespace wf

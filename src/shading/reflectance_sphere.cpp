#include "shading/reflectance_sphere.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace wf {

glm::dvec3 ReflectanceSphere::normalAt(double x, double y) {
  const double r2 = x * x + y * y;
  if (r2 > 1.0) {
    const double r = std::sqrt(r2);
    return {x / r, y / r, 0.0};
  }
  return {x, y, std::sqrt(1.0 - r2)};
}

ReflectanceSphere ReflectanceSphere::build(int resolution, const Shader& shader, int supersample) {
  ReflectanceSphere s;
  s.resolution_ = std::clamp(resolution, 8, 8192);
  supersample = std::clamp(supersample, 1, 16);
  const int n = s.resolution_;
  const double h = 2.0 / (n - 1);
  s.texels_.assign(size_t(n) * n, glm::vec3(0.0f));
  tbb::parallel_for(tbb::blocked_range<int>(0, n), [&](const tbb::blocked_range<int>& r) {
    for (int j = r.begin(); j != r.end(); ++j) {
      for (int i = 0; i < n; ++i) {
        const double x = -1.0 + i * h, y = -1.0 + j * h;
        glm::dvec3 sum(0.0);
        for (int b = 0; b < supersample; ++b)
          for (int a = 0; a < supersample; ++a) {
            const double ox = supersample == 1 ? 0.0 : ((a + 0.5) / supersample - 0.5) * h;
            const double oy = supersample == 1 ? 0.0 : ((b + 0.5) / supersample - 0.5) * h;
            sum += shader(normalAt(x + ox, y + oy));
          }
        s.texels_[size_t(j) * n + i] = glm::vec3(sum / double(supersample * supersample));
      }
    }
  });
  return s;
}

ReflectanceSphere ReflectanceSphere::phong(int resolution, const PhongMaterial& m,
                                           const LightRig& eyeLights) {
  const PhongMaterial mat = m.sanitized();
  const LightRig rig = eyeLights.canonical();
  const glm::dvec3 view(0.0, 0.0, 1.0);
  return build(resolution, [&](const glm::dvec3& n) { return phongRadiance(n, view, mat, rig); });
}

ReflectanceSphere ReflectanceSphere::chrome(int resolution, const EnvironmentMap& env,
                                            const glm::dvec3& reflectance, int supersample) {
  const glm::dvec3 view(0.0, 0.0, 1.0);
  return build(
      resolution,
      [&](const glm::dvec3& n) {
        const glm::dvec3 r = 2.0 * glm::dot(n, view) * n - view;  // mirror direction
        return reflectance * glm::dvec3(env.lookup(r));
      },
      supersample);
}

glm::vec3 ReflectanceSphere::lookupXY(double nx, double ny) const {
  if (texels_.empty()) return glm::vec3(0.0f);
  if (!std::isfinite(nx) || !std::isfinite(ny)) nx = ny = 0.0;
  const int n = resolution_;
  const double fx = std::clamp((nx + 1.0) * 0.5 * (n - 1), 0.0, double(n - 1));
  const double fy = std::clamp((ny + 1.0) * 0.5 * (n - 1), 0.0, double(n - 1));
  const int i = std::min(int(fx), n - 2), j = std::min(int(fy), n - 2);
  const float a = float(fx - i), b = float(fy - j);
  const glm::vec3* r0 = &texels_[size_t(j) * n + i];
  const glm::vec3* r1 = r0 + n;
  return (r0[0] * (1 - a) + r0[1] * a) * (1 - b) + (r1[0] * (1 - a) + r1[1] * a) * b;
}

glm::vec3 ReflectanceSphere::lookup(const glm::dvec3& normal) const {
  const double len = glm::length(normal);
  if (!(len > 1e-300) || !std::isfinite(len)) return lookupXY(0.0, 0.0);
  return lookupXY(normal.x / len, normal.y / len);
}

std::string ReflectanceSphere::toString() const {
  std::ostringstream s;
  s << "ReflectanceSphere{resolution=" << resolution_ << "}";
  return s.str();
}

}  // namespace wf

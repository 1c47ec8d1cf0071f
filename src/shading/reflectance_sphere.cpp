#include "shading/reflectance_sphere.h"

#include "core/limits.h"
#include "core/node_grid.h"

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

glm::dvec3 ReflectanceSphere::normalAtTable(double X, double Y) const {
  if (indexing_ == Indexing::Williams) return normalAt(X, Y);
  // Inverse of (X, Y) = (nx, ny) / (r + nz): rho' = sin t / (sin t + cos t), t the angle from the
  // view axis, so tan t = rho' / (1 - rho').
  const double rp = std::sqrt(X * X + Y * Y);
  if (rp >= 1.0) return {X / rp, Y / rp, 0.0};
  if (rp == 0.0) return {0.0, 0.0, 1.0};
  const double t = std::atan2(rp, 1.0 - rp);
  const double r = std::sin(t);
  return {X / rp * r, Y / rp * r, std::cos(t)};
}

ReflectanceSphere ReflectanceSphere::build(int resolution, const Shader& shader, int supersample,
                                           Indexing indexing) {
  ReflectanceSphere s;
  s.indexing_ = indexing;
  s.resolution_ = std::clamp(resolution, kMinSphereResolution, kMaxSphereResolution);
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
            sum += shader(s.normalAtTable(x + ox, y + oy));
          }
        s.texels_[size_t(j) * n + i] = glm::vec3(sum / double(supersample * supersample));
      }
    }
  });
  return s;
}

ReflectanceSphere ReflectanceSphere::phong(int resolution, const PhongMaterial& m,
                                           const LightRig& eyeLights, Indexing indexing) {
  const PhongMaterial mat = m.sanitized();
  const LightRig rig = eyeLights.canonical();
  const glm::dvec3 view(0.0, 0.0, 1.0);
  return build(
      resolution, [&](const glm::dvec3& n) { return phongRadiance(n, view, mat, rig); }, 1, indexing);
}

ReflectanceSphere ReflectanceSphere::chrome(int resolution, const EnvironmentMap& env,
                                            const glm::dvec3& reflectance, int supersample,
                                            Indexing indexing) {
  const glm::dvec3 view(0.0, 0.0, 1.0);
  return build(
      resolution,
      [&](const glm::dvec3& n) {
        const glm::dvec3 r = 2.0 * glm::dot(n, view) * n - view;  // mirror direction
        return reflectance * glm::dvec3(env.lookup(r));
      },
      supersample, indexing);
}

glm::vec3 ReflectanceSphere::lookupTable(double X, double Y) const {
  if (texels_.empty()) return glm::vec3(0.0f);
  if (!std::isfinite(X) || !std::isfinite(Y)) X = Y = 0.0;
  return bilinearNodeGrid(texels_.data(), resolution_, X, Y);
}

glm::vec3 ReflectanceSphere::lookupXY(double nx, double ny) const {
  if (!std::isfinite(nx) || !std::isfinite(ny)) nx = ny = 0.0;
  if (indexing_ == Indexing::Williams) return lookupTable(nx, ny);
  const double r2 = nx * nx + ny * ny;
  const double r = std::sqrt(r2);
  if (r2 >= 1.0) return lookupTable(nx / r, ny / r);  // on the rim: r + nz = 1
  const double d = r + std::sqrt(1.0 - r2);          // >= 1
  return lookupTable(nx / d, ny / d);
}

glm::vec3 ReflectanceSphere::lookup(const glm::dvec3& normal) const {
  const double len = glm::length(normal);
  if (!(len > 1e-300) || !std::isfinite(len)) return lookupTable(0.0, 0.0);
  const glm::dvec3 u = normal / len;
  if (indexing_ == Indexing::Williams) return lookupTable(u.x, u.y);
  const double r = std::sqrt(u.x * u.x + u.y * u.y);
  const double d = r + std::max(0.0, u.z);  // >= 1 for a front-facing unit normal, r for a back-facing
  if (!(d > 0.0)) return lookupTable(0.0, 0.0);
  return lookupTable(u.x / d, u.y / d);
}

std::string ReflectanceSphere::toString() const {
  std::ostringstream s;
  s << "ReflectanceSphere{indexing=" << (indexing_ == Indexing::Williams ? "williams" : "warped")
    << " resolution=" << resolution_ << "}";
  return s.str();
}

}  // namespace wf

#include "shading/pseudo_reflectance_map.h"

#include "core/limits.h"
#include "core/node_grid.h"
#include "shading/cylinder_shading.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <sstream>

namespace wf {
namespace {

double nodeCoord(int i, int n) { return -1.0 + 2.0 * i / (n - 1); }

using Indexing = PseudoReflectanceMapOptions::Indexing;
constexpr double kSqrt2 = 1.4142135623730951;
// Below this distance from the view axis a tangent is end-on (as in cylinderFrame).
constexpr double kAxisR = 1e-9;

// Paper indexing: u is x for the XZ map, y for the YZ map; the implicit component is the
// non-negative root. Outside the unit disc the point is moved to the rim (those texels only
// serve as bilinear neighbours near z = +-1).
glm::dvec3 paperTangent(PseudoReflectanceMap::Plane p, double u, double z) {
  double r2 = u * u + z * z;
  if (r2 > 1.0) {
    const double r = std::sqrt(r2);
    u /= r;
    z /= r;
    r2 = 1.0;
  }
  const double w = std::sqrt(std::max(0.0, 1.0 - r2));
  return p == PseudoReflectanceMap::Plane::XZ ? glm::dvec3(u, w, z) : glm::dvec3(w, u, z);
}

// Warped indexing (see the header). The edge rows zeta = +-1 stand for the view axis itself;
// they hold the limit along their azimuth, taken 1e-7 rad from the axis.
glm::dvec3 warpedTangent(PseudoReflectanceMap::Plane p, double a, double zeta) {
  const double m = 1.0 - std::abs(zeta);           // sqrt(1 - |z|)
  const double oneMinusZ = m * m;                  // 1 - |z|
  double r = std::sqrt(oneMinusZ * (2.0 - oneMinusZ));  // sqrt(1 - z^2), without cancellation
  r = std::max(r, 1e-7);
  const double z = std::copysign(std::sqrt(std::max(0.0, 1.0 - r * r)), zeta);
  const double c = std::clamp(a / kSqrt2, -1.0, 1.0);
  const double u = r * c, w = r * std::sqrt(std::max(0.0, 1.0 - c * c));
  return p == PseudoReflectanceMap::Plane::XZ ? glm::dvec3(u, w, z) : glm::dvec3(w, u, z);
}

}  // namespace

PseudoReflectanceMap::Plane PseudoReflectanceMap::planeFor(const glm::dvec3& T) {
  return std::abs(T.x) <= std::abs(T.y) ? Plane::XZ : Plane::YZ;
}

glm::dvec3 PseudoReflectanceMap::tangentAt(Plane plane, double u, double v) const {
  return options_.indexing == Indexing::Paper ? paperTangent(plane, u, v) : warpedTangent(plane, u, v);
}

bool PseudoReflectanceMap::texelNeeded(int i, int j) const {
  if (options_.indexing == Indexing::Warped) return true;  // the sector fills the whole map
  // A map is read where |u| <= |implicit component|, i.e. u^2 <= (1 - z^2) / 2. A texel is a
  // bilinear neighbour of any point within one texel spacing h of it.
  const int n = options_.resolution;
  const double h = 2.0 / (n - 1);
  const double u = std::max(0.0, std::abs(nodeCoord(i, n)) - h);
  const double z = std::max(0.0, std::abs(nodeCoord(j, n)) - h);
  return u * u <= 0.5 * (1.0 - z * z) + 1e-12;
}

void PseudoReflectanceMap::build(const PhongMaterial& material, const LightRig& eyeLights,
                                 const PseudoReflectanceMapOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  options_.resolution = std::clamp(options.resolution, kMinMapResolution, kMaxMapResolution);
  options_.samples = std::clamp(options.samples, 1, kMaxMapSamples);
  options_.indexing = options.indexing;
  material_ = material.sanitized();
  lights_ = eyeLights.canonical();
  const int n = options_.resolution;
  const glm::dvec3 view(0.0, 0.0, 1.0);
  std::atomic<size_t> computed{0};
  const CylinderSampler sampler(options_.samples);
  // The end-on value (the mean over approach directions, exact): the lookup of a tangent along
  // the view axis, and the texels that stand exactly for it.
  endOn_ = glm::vec3(cylinderRadianceSampled(view, view, material_, lights_, options_.samples));
  const double cut = CylinderSampler::lobeThreshold(material_.exponent);
  for (auto& m : maps_) m.assign(size_t(n) * size_t(n), glm::vec3(0.0f));
  // Rows of both maps in one parallel loop; each texel is written by exactly one task, so the
  // result does not depend on the thread count.
  tbb::parallel_for(tbb::blocked_range<int>(0, 2 * n), [&](const tbb::blocked_range<int>& r) {
    size_t local = 0;
    for (int row = r.begin(); row != r.end(); ++row) {
      const Plane p = row < n ? Plane::XZ : Plane::YZ;
      const int j = row % n;
      const double z = nodeCoord(j, n);
      for (int i = 0; i < n; ++i) {
        if (!texelNeeded(i, j)) continue;
        const CylinderFrame fr = cylinderFrameOrthographic(tangentAt(p, nodeCoord(i, n), z));
        maps_[int(p)][size_t(j) * n + i] =
            fr.endOn ? endOn_ : glm::vec3(sampler.radiance(fr, view, material_, lights_, cut));
        ++local;
      }
    }
    computed += local;
  });
  texelsComputed_ = computed.load();
  ++buildCount_;
  lastBuildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

bool PseudoReflectanceMap::update(const PhongMaterial& material, const LightRig& eyeLights,
                                  const PseudoReflectanceMapOptions& options) {
  PseudoReflectanceMapOptions o = options;
  o.resolution = std::clamp(o.resolution, kMinMapResolution, kMaxMapResolution);
  o.samples = std::clamp(o.samples, 1, kMaxMapSamples);
  if (!empty() && o == options_ && material.sanitized() == material_ &&
      eyeLights.canonical().nearlyEqual(lights_))
    return false;
  build(material, eyeLights, options);
  return true;
}

glm::vec3 PseudoReflectanceMap::lookupPlane(Plane plane, double u, double z) const {
  if (empty()) return glm::vec3(0.0f);
  if (!std::isfinite(u)) u = 0.0;
  if (!std::isfinite(z)) z = 0.0;
  return bilinearNodeGrid(maps_[int(plane)].data(), options_.resolution, u, z);
}

glm::vec3 PseudoReflectanceMap::lookup(const glm::dvec3& T) const {
  if (empty()) return glm::vec3(0.0f);
  const double len2 = glm::dot(T, T);
  if (!(len2 > 1e-300) || !std::isfinite(len2)) return endOn_;
  glm::dvec3 t = T / std::sqrt(len2);
  // T and -T are one cylinder: make the implicit component non-negative.
  const Plane plane = planeFor(t);
  if ((plane == Plane::XZ ? t.y : t.x) < 0.0) t = -t;
  const double u = plane == Plane::XZ ? t.x : t.y;
  // Seen end-on (as cylinderFrame decides it), whatever the indexing: the end-on value, not a
  // blend of the texels around the axis.
  const double r2 = t.x * t.x + t.y * t.y;
  if (!(r2 > kAxisR * kAxisR)) return endOn_;
  if (options_.indexing == Indexing::Paper) return lookupPlane(plane, u, t.z);
  const double r = std::sqrt(r2);
  const double oneMinusZ = r2 / (1.0 + std::abs(t.z));  // 1 - |z| without cancellation
  const double zeta = std::copysign(1.0 - std::sqrt(oneMinusZ), t.z);
  return lookupPlane(plane, kSqrt2 * u / r, zeta);
}

std::string PseudoReflectanceMap::toString() const {
  std::ostringstream s;
  s << "PseudoReflectanceMap{indexing=" << (options_.indexing == Indexing::Paper ? "paper" : "warped")
    << " resolution=" << options_.resolution << " samples=" << options_.samples
    << " builds=" << buildCount_ << " lastBuild=" << lastBuildSeconds_ * 1e3 << "ms texels="
    << texelsComputed_ << " " << material_.toString() << " lights=" << lights_.lights.size() << "}";
  return s.str();
}

}  // namespace wf

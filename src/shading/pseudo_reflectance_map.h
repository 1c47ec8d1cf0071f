// Pseudo-reflectance map (paper §2.2): the cylinder-averaged shading of the isotropic model,
// tabulated over the eye-space tangent so that a wire, a hair or a burnish groove is shaded by
// one table lookup.
//
// As in the paper the table is two maps, one indexed by (x, z) and one by (y, z) of the unit
// tangent; a tangent uses the map of whichever of |x|, |y| is smaller (ties: the (x, z) map), so
// the component left implicit is the larger one, recovered as sqrt(1 - ...) far from its
// singular point, and z ~ 0 (a wire face-on to the viewer) is sampled as densely as any z.
// T and -T are the same cylinder: the (x, z) map stores the tangents with y >= 0, the (y, z)
// map those with x >= 0. Each texel is filled by cylinderRadianceSampled with V = (0, 0, 1),
// the paper's orthographic assumption; lookups are bilinear between texel nodes at
// -1 + 2 i / (resolution - 1). Texels that no lookup can reach (outside each map's region plus
// one texel) are not computed. The map is RGB float.
//
// Indexing::Paper is the paper's (x, z) indexing. It samples z ~ 0 well but the view axis
// badly: near z = +-1 a step in z is a step of dz / sin(angle) in angle, so a 256^2 map has a
// z texel 8.6 degrees tall at 3 degrees from the axis, and there the cylinder's shading changes
// fastest (its limit at the axis depends on the direction of approach). Indexing::Warped keeps
// the two maps and the |x| <= |y| switch but indexes each by
//   a    = sqrt(2) * u / sqrt(x^2 + y^2)  (u = x or y: the azimuth within the map's 90° sector)
//   zeta = sign(z) (1 - sqrt(1 - |z|))    (grows linearly with the angle at the view axis)
// so texels are spread nearly evenly in angle, every texel is used, and the view axis becomes
// the edge rows zeta = +-1, holding the limit along each azimuth: the map is smooth there.
// It is the default; docs/shading.md shows both against the exact path.
#pragma once

#include "shading/light.h"
#include "shading/phong.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace wf {

struct PseudoReflectanceMapOptions {
  enum class Indexing { Paper, Warped };
  // Defaults chosen from `wirefur accuracy` (docs/shading.md): 128^2 warped with 64 samples is
  // the cheapest setting whose max error stays below 2e-3 for exponents <= 128 (7.7e-4).
  int resolution = 128;  ///< texel nodes per side of each map, 8 ... 4096
  int samples = 64;      ///< normals averaged across the cylinder, 1 ... 65536
  Indexing indexing = Indexing::Warped;
  bool operator==(const PseudoReflectanceMapOptions&) const = default;
};

class PseudoReflectanceMap {
 public:
  enum class Plane { XZ = 0, YZ = 1 };

  /// Builds both maps for a material under lights given in eye space (viewer on +z).
  void build(const PhongMaterial& material, const LightRig& eyeLights,
             const PseudoReflectanceMapOptions& options = {});

  /// Builds only when material, eye-space lights or options differ from the last build
  /// (the paper: the table must be recomputed when the camera moves relative to the lights).
  /// Returns true when it rebuilt.
  bool update(const PhongMaterial& material, const LightRig& eyeLights,
              const PseudoReflectanceMapOptions& options = {});

  bool empty() const { return maps_[0].empty(); }

  /// Radiance of a cylinder with eye-space axis T (any length, either sign). A zero or
  /// non-finite T shades as a cylinder seen end-on (see cylinder_shading.h).
  glm::vec3 lookup(const glm::dvec3& T) const;

  /// Which map a tangent uses.
  static Plane planeFor(const glm::dvec3& T);
  /// Bilinear lookup in one map at its texel coordinates (both in [-1, 1]): (x or y, z) for
  /// Indexing::Paper, (a, zeta) for Indexing::Warped.
  glm::vec3 lookupPlane(Plane plane, double u, double z) const;
  /// The unit tangent a map stands for at texel coordinates (u, v) (see lookupPlane).
  glm::dvec3 tangentAt(Plane plane, double u, double v) const;
  /// Whether lookups can reach texel (i, j) of a map: only those texels are built.
  bool texelNeeded(int i, int j) const;

  int resolution() const { return options_.resolution; }
  int samples() const { return options_.samples; }
  const PseudoReflectanceMapOptions& options() const { return options_; }
  const std::vector<glm::vec3>& texels(Plane p) const { return maps_[int(p)]; }
  glm::vec3 endOnValue() const { return endOn_; }
  int buildCount() const { return buildCount_; }
  double lastBuildSeconds() const { return lastBuildSeconds_; }
  size_t texelsComputed() const { return texelsComputed_; }
  size_t bytes() const { return (maps_[0].size() + maps_[1].size()) * sizeof(glm::vec3); }
  std::string toString() const;

 private:
  PseudoReflectanceMapOptions options_{};
  PhongMaterial material_{};
  LightRig lights_{};
  std::vector<glm::vec3> maps_[2];
  glm::vec3 endOn_{0.0f};
  int buildCount_ = 0;
  double lastBuildSeconds_ = 0.0;
  size_t texelsComputed_ = 0;
};

}  // namespace wf

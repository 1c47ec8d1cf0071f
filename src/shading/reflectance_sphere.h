// Reflectance sphere (Williams 1983; paper §2.1): a sphere rendered in orthographic projection
// holds the shading of every eye-space normal; (nx, ny) of a normal index it directly.
//
// Indexing::Williams is that table. Its texels are even in (nx, ny), so near the rim (the
// outline) one texel spans a large angle: nz = sqrt(1 - r^2) changes by sqrt(2 h) over the last
// texel h. Indexing::Warped (the default) indexes by (X, Y) = (nx, ny) / (r + nz), r = |(nx, ny)|:
// like Williams' at the centre (slope 1), but linear in the angle at the rim, at the price of one
// square root and one division per lookup. docs/shading.md has both against direct evaluation.
#pragma once

#include "shading/environment_map.h"
#include "shading/light.h"
#include "shading/phong.h"

#include <glm/glm.hpp>

#include <functional>
#include <string>
#include <vector>

namespace wf {

class ReflectanceSphere {
 public:
  enum class Indexing { Williams, Warped };

  /// Radiance for a unit eye-space normal (viewer on +z, orthographic).
  using Shader = std::function<glm::dvec3(const glm::dvec3& normal)>;

  /// Tabulates `shader` on resolution x resolution nodes over (nx, ny) in [-1, 1]^2. With
  /// supersample > 1 each node holds the mean over a supersample^2 grid across its texel
  /// (for shaders with detail finer than a texel, such as a reflected environment).
  static ReflectanceSphere build(int resolution, const Shader& shader, int supersample = 1,
                                 Indexing indexing = Indexing::Warped);

  /// Isotropic Phong under eye-space lights (paper image 1).
  static ReflectanceSphere phong(int resolution, const PhongMaterial& m, const LightRig& eyeLights,
                                 Indexing indexing = Indexing::Warped);

  /// Chrome ball: the environment seen by mirror reflection, scaled by `reflectance`
  /// (paper image 3).
  static ReflectanceSphere chrome(int resolution, const EnvironmentMap& env,
                                  const glm::dvec3& reflectance, int supersample = 4,
                                  Indexing indexing = Indexing::Warped);

  /// Williams' node (x, y): the normal (x, y, sqrt(1 - x^2 - y^2)), moved onto the rim when
  /// x^2 + y^2 > 1.
  static glm::dvec3 normalAt(double x, double y);
  /// The normal a table position (X, Y) in [-1, 1]^2 stands for under this sphere's indexing.
  glm::dvec3 normalAtTable(double X, double Y) const;

  /// Bilinear lookup by a normal (any length; back-facing normals read the rim); a zero or
  /// non-finite normal reads the centre (a normal facing the viewer).
  glm::vec3 lookup(const glm::dvec3& normal) const;
  /// Lookup by a front-facing unit normal's (nx, ny): nz = sqrt(1 - nx^2 - ny^2) (onto the rim
  /// when nx^2 + ny^2 > 1). Non-finite input reads the centre.
  glm::vec3 lookupXY(double nx, double ny) const;
  /// Bilinear lookup at table position (X, Y) in [-1, 1]^2.
  glm::vec3 lookupTable(double X, double Y) const;

  int resolution() const { return resolution_; }
  Indexing indexing() const { return indexing_; }
  const std::vector<glm::vec3>& texels() const { return texels_; }
  std::string toString() const;

 private:
  int resolution_ = 0;
  Indexing indexing_ = Indexing::Warped;
  std::vector<glm::vec3> texels_;
};

}  // namespace wf

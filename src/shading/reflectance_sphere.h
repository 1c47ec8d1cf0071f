// Reflectance sphere (Williams 1983; paper §2.1): a sphere rendered in orthographic projection
// holds the shading of every eye-space normal; (nx, ny) of a normal index it directly.
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
  /// Radiance for a unit eye-space normal (viewer on +z, orthographic).
  using Shader = std::function<glm::dvec3(const glm::dvec3& normal)>;

  /// Tabulates `shader` on resolution x resolution nodes over (nx, ny) in [-1, 1]^2. With
  /// supersample > 1 each node holds the mean over a supersample^2 grid across its texel
  /// (for shaders with detail finer than a texel, such as a reflected environment).
  static ReflectanceSphere build(int resolution, const Shader& shader, int supersample = 1);

  /// Isotropic Phong under eye-space lights (paper image 1).
  static ReflectanceSphere phong(int resolution, const PhongMaterial& m, const LightRig& eyeLights);

  /// Chrome ball: the environment seen by mirror reflection, scaled by `reflectance`
  /// (paper image 3).
  static ReflectanceSphere chrome(int resolution, const EnvironmentMap& env,
                                  const glm::dvec3& reflectance, int supersample = 4);

  /// The normal a node (x, y) stands for: (x, y, sqrt(1 - x^2 - y^2)), moved onto the rim when
  /// x^2 + y^2 > 1.
  static glm::dvec3 normalAt(double x, double y);

  /// Bilinear lookup by the normal's (nx, ny); a zero or non-finite normal reads the centre
  /// (a normal facing the viewer).
  glm::vec3 lookup(const glm::dvec3& normal) const;
  glm::vec3 lookupXY(double nx, double ny) const;

  int resolution() const { return resolution_; }
  const std::vector<glm::vec3>& texels() const { return texels_; }
  std::string toString() const;

 private:
  int resolution_ = 0;
  std::vector<glm::vec3> texels_;
};

}  // namespace wf

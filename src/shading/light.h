// Directional lights and ambient light, the lighting of every shading model in WireFur.
// Paper §2: the shading models take "a specified view direction and lighting environment";
// the paper's images use up to seven directional lights plus ambient.
#pragma once

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace wf {

/// A light at infinity. `direction` points from the surface towards the light.
struct DirectionalLight {
  glm::dvec3 direction{0.0, 0.0, 1.0};
  glm::dvec3 intensity{1.0};  ///< linear RGB radiance scale
};

/// Any number of directional lights plus an ambient term.
struct LightRig {
  glm::dvec3 ambient{0.0};
  std::vector<DirectionalLight> lights;

  /// The rig every shading routine assumes: unit, finite directions; finite, non-negative
  /// intensities; lights that are dark or have no direction left out (they add nothing).
  LightRig canonical() const;

  /// True when both rigs shade identically to within `tol` in every component
  /// (used to decide whether a map must be rebuilt).
  bool nearlyEqual(const LightRig& other, double tol = 1e-12) const;

  /// The same rig seen from a camera: directions mapped by `eyeFromWorld` (a rotation).
  LightRig transformed(const glm::dmat3& eyeFromWorld) const;

  std::string toString() const;

  /// Rigs used by the pictures, tests and the accuracy study (eye space, viewer on +z).
  /// Total intensity 1 split over `count` lights (1..7) placed around the viewer's hemisphere,
  /// plus a little ambient; `count` = 7 is the paper's seven-light set-up (image 16).
  static LightRig studioRig(int count);
};

}  // namespace wf

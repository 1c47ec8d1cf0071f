// An environment (light arriving from every direction) as a latitude-longitude image, and a
// procedural mountain scene so that the chrome ball of paper image 3 needs no download.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace wf {

/// Directions are eye space: x right, y up, the viewer looks along -z. Column 0 looks along -z
/// (straight ahead), longitude increases towards +x; row 0 is the zenith.
class EnvironmentMap {
 public:
  EnvironmentMap() = default;
  EnvironmentMap(int width, int height, std::vector<glm::vec3> texels);

  /// Bilinear radiance arriving from direction d (any length; zero / non-finite -> zenith).
  glm::vec3 lookup(const glm::dvec3& d) const;

  /// Sky with a sun, a ring of snow-capped mountains, a lake-blue band and a grassy plain;
  /// deterministic in `seed`. height = width / 2.
  static EnvironmentMap mountainScene(int width = 1024, uint32_t seed = 1988);
  /// Where mountainScene's sun stands (its disc has radiance (30, 28, 24), radius 1.8 degrees).
  static glm::dvec3 mountainSceneSunDirection();

  int width() const { return width_; }
  int height() const { return height_; }
  const std::vector<glm::vec3>& texels() const { return texels_; }

 private:
  int width_ = 0, height_ = 0;
  std::vector<glm::vec3> texels_;
};

}  // namespace wf

// Textures over a surface's (u, v) (paper §4.1): colour maps that multiply the shading, scalar
// fields (bump heights, fur density / length maps, groove intensities) and the parameters a
// filtered lookup needs.
//
// Every lookup takes the pixel's footprint in (u, v) (the screen derivatives of u and v), so a
// texture finer than a pixel is box-filtered over the pixel instead of point-sampled: a chequer
// of a thousand squares per pixel comes out as its mean, not as noise. A zero footprint is a
// point sample (the exact value the reference renderer averages over its sub-samples).
#pragma once

#include <glm/glm.hpp>

#include <memory>
#include <string>

namespace wf {

/// The pixel's extent in (u, v): how far (u, v) moves for one pixel step in x and in y.
struct UvFootprint {
  glm::dvec2 dx{0.0}, dy{0.0};
  /// Half-widths of the axis-aligned (u, v) box holding the pixel's parallelogram.
  glm::dvec2 halfBox() const { return 0.5 * (glm::abs(dx) + glm::abs(dy)); }
};

/// A colour over (u, v); multiplies the shaded radiance.
class ColourTexture {
 public:
  virtual ~ColourTexture() = default;
  /// Mean colour over the footprint's box around (u, v); finite for any input (NaN (u, v)
  /// gives the texture's mean colour).
  virtual glm::vec3 sample(const glm::dvec2& uv, const UvFootprint& footprint) const = 0;
  virtual std::string describe() const = 0;
};

/// A scalar over (u, v) with its gradient: bump heights (in world units per unit of the
/// surface's normal), density, length and orientation maps.
class ScalarTexture {
 public:
  virtual ~ScalarTexture() = default;
  virtual double value(const glm::dvec2& uv) const = 0;
  /// value() at n points into out[0 ... n-1] (the samples of one footprint): the same values; a
  /// texture may share work between the points.
  virtual void values(const glm::dvec2* uv, int n, double* out) const {
    for (int k = 0; k < n; ++k) out[k] = value(uv[k]);
  }
  /// (dh/du, dh/dv), finite.
  virtual glm::dvec2 gradient(const glm::dvec2& uv) const = 0;
  virtual std::string describe() const = 0;
};

}  // namespace wf

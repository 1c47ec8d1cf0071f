// The groove texture of burnished metal (paper §2.2, image 6): "The groove intensities were
// produced using an uncorrelated series of random numbers. Both the diffuse and specular
// components of the shading model were modulated by the groove texture so as to mimic the
// effect of self shadowing caused by uneven groove depth." The renderer multiplies both terms by
// `intensity`; this class is only the texture.
#pragma once

#include "texture/texture.h"

#include <cstdint>
#include <string>

namespace wf {

/// Grooves run across a groove coordinate c (u, v, or the radius of a turned record: the scene
/// picks it). Groove k covers [k / count, (k + 1) / count) and has the intensity
///
///     I_k = 1 - depth * xi_k,   xi_k = unitFromHash(hashWords(seed, k)) uniform in [0, 1),
///
/// independent between grooves (counter-based hash: no correlation, no state), so the mean
/// intensity is 1 - depth / 2 and I_k lies in (1 - depth, 1].
class GrooveTexture {
 public:
  /// count: grooves per unit of the groove coordinate (> 0; non-finite or <= 0 -> 1);
  /// depth: 0 ... 1 (clamped; NaN -> 0); seed: the series.
  GrooveTexture(double count, double depth, std::uint64_t seed = 1);

  /// Mean intensity over [c - w/2, c + w/2] (box filter), exact: the whole grooves inside plus
  /// the fractional ends. When more than kMaxExactGrooves whole grooves lie inside, the whole
  /// ones are replaced by their expected value 1 - depth/2 (the ends stay exact); the error is
  /// the deviation of M >= 64 i.i.d. intensities from their mean: standard deviation
  /// <= depth / sqrt(12 M) <= 0.036 depth, never more than depth / 2. w = 0 is the point value
  /// I_floor(c count). Non-finite c gives the mean; non-finite w an infinitely wide box (the mean).
  double intensity(double coordinate, double footprintWidth) const;
  /// The same with the footprint read from a pixel's (u, v) footprint along one axis (0: u,
  /// 1: v): the groove coordinate is that texture coordinate, the width twice the half-box.
  double intensity(const glm::dvec2& uv, const UvFootprint& footprint, int axis) const;
  /// Intensity of groove k.
  double grooveIntensity(std::int64_t k) const;
  /// Index of the groove holding coordinate c (finite c).
  std::int64_t grooveIndex(double coordinate) const;
  /// The expected intensity, 1 - depth / 2.
  double mean() const { return 1.0 - 0.5 * depth_; }
  double count() const { return count_; }
  double depth() const { return depth_; }
  std::uint64_t seed() const { return seed_; }
  std::string describe() const;

  static constexpr int kMaxExactGrooves = 64;

 private:
  double count_, depth_;
  std::uint64_t seed_;
};

}  // namespace wf

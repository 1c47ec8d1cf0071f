// The concrete textures of paper §4.1: the chequer of image 12, image maps, the fractal "rock"
// of images 13 and 14 (a scalar field: colour-mapped through a ramp for image 13, a bump height
// for image 14), heights read from an image, and constants.
//
// Conventions shared by all of them (docs/textures.md):
// - (u, v) are texture coordinates: one unit of u (or v) spans the image once, holds
//   `squaresU` chequer squares, one period of periodic noise. The scene decides how a surface's
//   parameters map to them.
// - Images: u = 0 is the left edge, v = 0 the BOTTOM edge (row height-1), v = 1 the top (row 0),
//   as in OpenGL and VTK texture coordinates; texel centres sit at half-integer texel coordinates.
// - Colour lookups are box-filtered over UvFootprint::halfBox(); a zero footprint is an exact
//   point sample. Every lookup is finite for any input: non-finite (u, v) gives the texture's
//   mean, a non-finite footprint is treated as an infinitely wide one (the mean along that axis).
#pragma once

#include "core/image.h"
#include "texture/texture.h"

#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

namespace wf {

/// A constant colour (the neutral texture).
class ConstantColour final : public ColourTexture {
 public:
  explicit ConstantColour(glm::vec3 colour) : colour_(colour) {}
  glm::vec3 sample(const glm::dvec2&, const UvFootprint&) const override { return colour_; }
  std::string describe() const override;

 private:
  glm::vec3 colour_;
};

/// Paper image 12: squaresU x squaresV squares per unit of (u, v), colourA on the square that
/// holds (0, 0) and on every square of even i + j, colourB on the others.
///
/// The box filter is exact: with s(x) = (-1)^floor(x) the chequer is A + (B - A)(1 - s(x)s(y))/2,
/// the box is a product of intervals, so its mean is separable; the mean of s over [a, b] is
/// (T(b) - T(a)) / (b - a) with the triangle wave T(x) = 1 - |x mod 2 - 1| (the antiderivative of
/// s). Intervals crossing at most one square edge are summed piecewise instead, which stays exact
/// for footprints far below a square (no cancellation).
class ChequerTexture final : public ColourTexture {
 public:
  ChequerTexture(int squaresU, int squaresV, glm::vec3 colourA, glm::vec3 colourB);
  glm::vec3 sample(const glm::dvec2& uv, const UvFootprint& footprint) const override;
  std::string describe() const override;
  /// Fraction of the box [uv - half, uv + half] covered by colour B (0 ... 1).
  double coverageB(const glm::dvec2& uv, const glm::dvec2& half) const;
  /// Mean of s(x) = (-1)^floor(x) over [x - h, x + h] (h >= 0; h = 0 is s(x)); in [-1, 1].
  static double meanSquareWave(double x, double h);

 private:
  int squaresU_, squaresV_;
  glm::vec3 colourA_, colourB_;
};

/// An image over (u, v) (pixels passed in by the apps layer, which reads the file). Each axis
/// wraps (periodic) or clamps (the edge texels extend outward).
///
/// The lookup is the box filter over the footprint of the piecewise-constant (nearest-texel)
/// image, with each half-width widened to at least half a texel: a one-texel box over a
/// piecewise-constant image is exactly bilinear interpolation, so a zero footprint is the
/// bilinear point sample (computed directly) and footprints grow continuously into the exact
/// area average (Crow 1984's summed-area table, in double precision, of texels minus their mean,
/// so a box of one texel in a 4096^2 image still keeps ~1e-9 relative accuracy).
class ImageTexture final : public ColourTexture {
 public:
  /// An empty image (0 x 0) reads as black.
  ImageTexture(ImageRGBA image, bool wrapU, bool wrapV);
  glm::vec3 sample(const glm::dvec2& uv, const UvFootprint& footprint) const override;
  std::string describe() const override;
  /// Bilinear point sample (the zero-footprint lookup).
  glm::vec3 bilinear(const glm::dvec2& uv) const;
  /// Exact mean of the piecewise-constant image over the texel-coordinate box
  /// [x0, x1] x [y0, y1] (x right, y DOWN from the top row; x0 < x1, y0 < y1) with this
  /// texture's wrap / clamp rule.
  glm::dvec3 boxMeanTexels(double x0, double x1, double y0, double y1) const;
  const glm::dvec3& mean() const { return mean_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  /// The integral of (texel - mean) over [0, x] x [0, y] (texel coordinates) of the image
  /// extended by the wrap / clamp rule.
  glm::dvec3 integral(double x, double y) const;
  glm::dvec3 sat(int i, int j) const { return sat_[size_t(j) * size_t(width_ + 1) + size_t(i)]; }

  int width_ = 0, height_ = 0;
  bool wrapU_, wrapV_;
  std::vector<glm::vec3> texels_;   ///< row-major, row 0 at the top
  std::vector<glm::dvec3> sat_;     ///< (height+1) x (width+1), of texel - mean
  glm::dvec3 mean_{0.0};
};

/// Fractal sum (fBm) of 2-D gradient noise (Perlin 1985 with the quintic fade of Perlin 2002),
/// with its analytic gradient: the rock of paper images 13 and 14.
struct NoiseParams {
  int octaves = 4;           ///< 1 ... 16
  double frequency = 8.0;    ///< lattice cells per unit of (u, v) for the first octave
  double lacunarity = 2.0;   ///< frequency ratio between octaves (rounded on a periodic axis)
  double gain = 0.5;         ///< amplitude ratio between octaves
  double amplitude = 1.0;    ///< the sum is normalised to about [-amplitude, amplitude]
  std::uint64_t seed = 1;
  bool periodicU = false;    ///< period periodU in u (a torus is periodic in both)
  bool periodicV = false;
  double periodU = 1.0, periodV = 1.0;
};

class NoiseTexture final : public ScalarTexture {
 public:
  /// Out-of-range parameters are clamped (octaves to [1, 16], non-finite values to defaults).
  explicit NoiseTexture(const NoiseParams& params);
  double value(const glm::dvec2& uv) const override;
  /// value() at n points, an octave at a time: points in the same lattice cell of an octave
  /// share its corners' gradients (the same values, formed once).
  void values(const glm::dvec2* uv, int n, double* out) const override;
  glm::dvec2 gradient(const glm::dvec2& uv) const override;
  /// Value and gradient in one pass.
  double evaluate(const glm::dvec2& uv, glm::dvec2* gradient) const;
  std::string describe() const override;
  const NoiseParams& params() const { return params_; }

 private:
  double foldU(double x) const;  ///< periodic axes fold into one period (keeps precision for large u)
  double foldV(double y) const;
  NoiseParams params_;
  std::vector<double> freqU_, freqV_, weight_;  ///< per octave (weights sum to amplitude)
  std::vector<std::int64_t> cellsU_, cellsV_;   ///< lattice period per octave (0: aperiodic)
  std::vector<std::uint64_t> octaveKey_;         ///< per octave: hashWords' chain of (seed, octave) (core/hash.h)
};

/// One stop of a colour ramp.
struct RampStop {
  double position = 0.0;
  glm::vec3 colour{0.0f};
};

/// A scalar texture seen through a colour ramp (paper image 13: the rock colour-mapped).
/// The scalar maps to t = (value - low) / (high - low), clamped to [0, 1], then piecewise
/// linearly through the stops (sorted by position; constant beyond the ends).
///
/// Footprint: the mean of samplesPerAxis^2 stratified samples (cell centres of a regular grid)
/// in the footprint's box, deterministic; a zero footprint is one exact sample. The ramp is not
/// linear, so averaging colours (not values) is what a box filter of the coloured field needs;
/// the error is that of a midpoint rule on the box.
class RampTexture final : public ColourTexture {
 public:
  RampTexture(std::shared_ptr<const ScalarTexture> scalar, std::vector<RampStop> stops,
              double low = -1.0, double high = 1.0, int samplesPerAxis = 3);
  glm::vec3 sample(const glm::dvec2& uv, const UvFootprint& footprint) const override;
  std::string describe() const override;
  glm::vec3 colourAt(double value) const;

 private:
  std::shared_ptr<const ScalarTexture> scalar_;
  std::vector<RampStop> stops_;
  double low_, high_;
  int samplesPerAxis_;
};

/// Heights from an image's luminance (Rec. 709, linear): h = offset + scale * Y, bilinear
/// (same texel layout and wrap / clamp rule as ImageTexture). The gradient is the exact
/// derivative of the bilinear interpolant (constant in u across a cell row, so it jumps at
/// texel-centre lines: use a finer image, or NoiseTexture, for smooth bumps).
class ImageHeight final : public ScalarTexture {
 public:
  ImageHeight(const ImageRGBA& image, bool wrapU, bool wrapV, double scale = 1.0,
              double offset = 0.0);
  double value(const glm::dvec2& uv) const override;
  glm::dvec2 gradient(const glm::dvec2& uv) const override;
  std::string describe() const override;

 private:
  /// Bilinear value and (d/du, d/dv).
  double evaluate(const glm::dvec2& uv, glm::dvec2* gradient) const;
  int width_ = 0, height_ = 0;
  bool wrapU_, wrapV_;
  double scale_, offset_, meanHeight_ = 0.0;
  std::vector<double> luminance_;
};

/// A constant scalar (zero gradient).
class ConstantScalar final : public ScalarTexture {
 public:
  explicit ConstantScalar(double value) : value_(std::isfinite(value) ? value : 0.0) {}
  double value(const glm::dvec2&) const override { return value_; }
  glm::dvec2 gradient(const glm::dvec2&) const override { return glm::dvec2(0.0); }
  std::string describe() const override;

 private:
  double value_;
};

}  // namespace wf

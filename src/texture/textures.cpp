#include "texture/textures.h"

#include "core/hash.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace wf {
namespace {

/// A non-finite or negative half-width counts as infinitely wide.
double sanitiseHalf(double h) { return (std::isfinite(h) && h >= 0.0) ? h : INFINITY; }

std::string vecString(const glm::vec3& c) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%g, %g, %g)", double(c.x), double(c.y), double(c.z));
  return buf;
}

/// (-1)^k for an integer-valued double k.
double squareSign(double k) { return std::fmod(std::fabs(k), 2.0) == 0.0 ? 1.0 : -1.0; }

/// The antiderivative of (-1)^floor(x): the triangle wave, 0 at even integers, 1 at odd ones.
double triangleWave(double x) {
  double r = std::fmod(x, 2.0);
  if (r < 0.0) r += 2.0;
  return 1.0 - std::fabs(r - 1.0);
}

/// Integer index of a lattice cell; coordinates beyond 2^52 (where every double is an integer)
/// are folded into a 2^32 range first so the conversion cannot overflow, and NaN or an infinity
/// (whose fmod is NaN, and converting NaN to an integer is undefined) is cell 0.
std::int64_t cellIndex(double floored) {
  if (!(std::fabs(floored) < 0x1.0p52)) floored = std::isfinite(floored) ? std::fmod(floored, 0x1.0p32) : 0.0;
  return std::int64_t(floored);
}

std::int64_t positiveMod(std::int64_t i, std::int64_t n) {
  const std::int64_t r = i % n;
  return r < 0 ? r + n : r;
}

// The four texels around (u, v) of a width x height image (v = 0 the bottom row, row 0 of the
// texels the top), wrapped or clamped per axis, and the bilinear weights (tx, ty) between them.
struct BilinearTaps {
  std::int64_t i0, i1, j0, j1;
  double tx, ty;
};

BilinearTaps bilinearTaps(const glm::dvec2& uv, std::int64_t width, std::int64_t height, bool wrapU, bool wrapV) {
  const double u = wrapU ? uv.x - std::floor(uv.x) : std::clamp(uv.x, -1.0, 2.0);
  const double v = wrapV ? uv.y - std::floor(uv.y) : std::clamp(uv.y, -1.0, 2.0);
  const double fx = u * double(width) - 0.5, fy = (1.0 - v) * double(height) - 0.5;
  const double ix = std::floor(fx), iy = std::floor(fy);
  auto column = [&](std::int64_t i) { return wrapU ? positiveMod(i, width) : std::clamp<std::int64_t>(i, 0, width - 1); };
  auto row = [&](std::int64_t j) { return wrapV ? positiveMod(j, height) : std::clamp<std::int64_t>(j, 0, height - 1); };
  return {column(std::int64_t(ix)), column(std::int64_t(ix) + 1), row(std::int64_t(iy)), row(std::int64_t(iy) + 1),
          fx - ix, fy - iy};
}

/// Brings the texel interval [a, b] of an axis of n texels into a range where the integral
/// stays accurate, without changing the mean over it (wrap: shift by whole periods; clamp:
/// beyond the edge the axis is constant). Spans beyond kMaxSpans periods are cut to that
/// (relative change of the mean <= 1 / kMaxSpans).
void normaliseInterval(double& a, double& b, int n, bool wrap) {
  constexpr double kMaxSpans = 1e6;
  const double N = double(n);
  if (wrap) {
    if (!(b - a < N * kMaxSpans)) {
      a = 0.0;
      b = N;
      return;
    }
    const double shift = std::floor(0.5 * (a + b) / N) * N;
    a -= shift;
    b -= shift;
    return;
  }
  if (a >= N) {  // wholly beyond the far edge: the last texel column / row
    a = N;
    b = N + 1.0;
  } else if (b <= 0.0) {
    a = -1.0;
    b = 0.0;
  } else {
    a = std::max(a, -N * kMaxSpans);
    b = std::min(b, N + N * kMaxSpans);
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------
std::string ConstantColour::describe() const { return "constant colour " + vecString(colour_); }

std::string ConstantScalar::describe() const {
  char buf[64];
  std::snprintf(buf, sizeof buf, "constant scalar %g", value_);
  return buf;
}

// ---------------------------------------------------------------------------------------------
ChequerTexture::ChequerTexture(int squaresU, int squaresV, glm::vec3 colourA, glm::vec3 colourB)
    : squaresU_(std::max(1, squaresU)), squaresV_(std::max(1, squaresV)),
      colourA_(colourA), colourB_(colourB) {}

double ChequerTexture::meanSquareWave(double x, double h) {
  if (!std::isfinite(x) || !std::isfinite(h)) return 0.0;
  h = std::fabs(h);
  const double a = x - h, b = x + h;
  const double fa = std::floor(a), fb = std::floor(b);
  if (fa == fb) return squareSign(fa);  // inside one square (includes h = 0)
  if (fb - fa == 1.0) {
    // One edge at fb: piecewise, exact however narrow the interval.
    return (squareSign(fa) * (fb - a) + squareSign(fb) * (b - fb)) / (b - a);
  }
  // Two or more edges: b - a > 1, so the antiderivative difference loses nothing.
  return std::clamp((triangleWave(b) - triangleWave(a)) / (b - a), -1.0, 1.0);
}

double ChequerTexture::coverageB(const glm::dvec2& uv, const glm::dvec2& half) const {
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return 0.5;
  const double hu = sanitiseHalf(half.x), hv = sanitiseHalf(half.y);
  const double su = meanSquareWave(uv.x * squaresU_, hu * squaresU_);
  const double sv = meanSquareWave(uv.y * squaresV_, hv * squaresV_);
  return std::clamp(0.5 * (1.0 - su * sv), 0.0, 1.0);
}

glm::vec3 ChequerTexture::sample(const glm::dvec2& uv, const UvFootprint& footprint) const {
  const double b = coverageB(uv, footprint.halfBox());
  return glm::vec3(glm::dvec3(colourA_) + b * (glm::dvec3(colourB_) - glm::dvec3(colourA_)));
}

std::string ChequerTexture::describe() const {
  return "chequer " + std::to_string(squaresU_) + "x" + std::to_string(squaresV_) + " " +
         vecString(colourA_) + " / " + vecString(colourB_);
}

// ---------------------------------------------------------------------------------------------
ImageTexture::ImageTexture(ImageRGBA image, bool wrapU, bool wrapV)
    : wrapU_(wrapU), wrapV_(wrapV) {
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() < size_t(image.width) * size_t(image.height))
    return;
  width_ = image.width;
  height_ = image.height;
  texels_.resize(size_t(width_) * size_t(height_));
  glm::dvec3 sum(0.0);
  for (size_t k = 0; k < texels_.size(); ++k) {
    glm::vec3 c(image.pixels[k]);
    for (int e = 0; e < 3; ++e)
      if (!std::isfinite(c[e])) c[e] = 0.0f;  // defined output for NaN / Inf texels
    texels_[k] = c;
    sum += glm::dvec3(c);
  }
  mean_ = sum / double(texels_.size());
  // Summed-area table of (texel - mean): sat(i, j) = sum over rows < j, columns < i.
  const size_t stride = size_t(width_) + 1;
  sat_.assign(stride * (size_t(height_) + 1), glm::dvec3(0.0));
  for (int j = 0; j < height_; ++j) {
    glm::dvec3 row(0.0);
    for (int i = 0; i < width_; ++i) {
      row += glm::dvec3(texels_[size_t(j) * size_t(width_) + size_t(i)]) - mean_;
      sat_[size_t(j + 1) * stride + size_t(i + 1)] = sat_[size_t(j) * stride + size_t(i + 1)] + row;
    }
  }
}

glm::dvec3 ImageTexture::integral(double x, double y) const {
  // Within a cell the integral of a piecewise-constant image is bilinear in (x, y), so the
  // bilinear interpolation of the table is exact; continuing the edge cells' bilinear form
  // beyond the image (unclamped local coordinates) is exactly the clamp-to-edge extension.
  auto bilinearSat = [&](double xx, double yy) {
    const int i = std::clamp(int(std::floor(std::clamp(xx, -1.0, double(width_)))), 0, width_ - 1);
    const int j = std::clamp(int(std::floor(std::clamp(yy, -1.0, double(height_)))), 0, height_ - 1);
    const double tx = xx - i, ty = yy - j;
    const glm::dvec3 s00 = sat(i, j), s10 = sat(i + 1, j), s01 = sat(i, j + 1),
                     s11 = sat(i + 1, j + 1);
    return s00 + tx * (s10 - s00) + ty * (s01 - s00) + tx * ty * (s11 - s10 - s01 + s00);
  };
  // Wrap: F(q n + r) = q F(n) + F(r), per axis.
  auto alongV = [&](double xx) {
    if (!wrapV_) return bilinearSat(xx, y);
    const double q = std::floor(y / height_), r = y - q * height_;
    return q * bilinearSat(xx, double(height_)) + bilinearSat(xx, r);
  };
  if (!wrapU_) return alongV(x);
  const double q = std::floor(x / width_), r = x - q * width_;
  return q * alongV(double(width_)) + alongV(r);
}

glm::dvec3 ImageTexture::boxMeanTexels(double x0, double x1, double y0, double y1) const {
  if (width_ == 0) return glm::dvec3(0.0);
  if (!(x1 > x0) || !(y1 > y0)) return mean_;
  normaliseInterval(x0, x1, width_, wrapU_);
  normaliseInterval(y0, y1, height_, wrapV_);
  const glm::dvec3 sum = integral(x1, y1) - integral(x0, y1) - integral(x1, y0) + integral(x0, y0);
  return mean_ + sum / ((x1 - x0) * (y1 - y0));
}

glm::vec3 ImageTexture::bilinear(const glm::dvec2& uv) const {
  if (width_ == 0) return glm::vec3(0.0f);
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return glm::vec3(mean_);
  const auto [i0, i1, j0, j1, tx, ty] = bilinearTaps(uv, width_, height_, wrapU_, wrapV_);
  auto at = [&](std::int64_t i, std::int64_t j) {
    return glm::dvec3(texels_[size_t(j) * size_t(width_) + size_t(i)]);
  };
  const glm::dvec3 top = at(i0, j0) + tx * (at(i1, j0) - at(i0, j0));
  const glm::dvec3 bottom = at(i0, j1) + tx * (at(i1, j1) - at(i0, j1));
  return glm::vec3(top + ty * (bottom - top));
}

glm::vec3 ImageTexture::sample(const glm::dvec2& uv, const UvFootprint& footprint) const {
  if (width_ == 0) return glm::vec3(0.0f);
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return glm::vec3(mean_);
  const glm::dvec2 half = footprint.halfBox();
  const double hx = sanitiseHalf(half.x) * width_, hy = sanitiseHalf(half.y) * height_;
  // Half a texel is the reconstruction filter: below it in both axes the box mean IS bilinear.
  if (hx <= 0.5 && hy <= 0.5) return bilinear(uv);
  // Fold a wrapped axis into one period first (shifts the box by whole periods: same mean).
  const double u = wrapU_ ? uv.x - std::floor(uv.x) : uv.x;
  const double v = wrapV_ ? uv.y - std::floor(uv.y) : uv.y;
  const double x = u * width_, y = (1.0 - v) * height_;
  const double ex = std::max(hx, 0.5), ey = std::max(hy, 0.5);
  if (std::isinf(ex) || std::isinf(ey)) {
    // An infinite footprint: the mean along that axis (wrap) or of the whole extension (clamp),
    // approximated by a box of kMaxSpans images (see normaliseInterval).
    const double bx = std::isinf(ex) ? 1e7 * width_ : ex, by = std::isinf(ey) ? 1e7 * height_ : ey;
    return glm::vec3(boxMeanTexels(x - bx, x + bx, y - by, y + by));
  }
  return glm::vec3(boxMeanTexels(x - ex, x + ex, y - ey, y + ey));
}

std::string ImageTexture::describe() const {
  return "image " + std::to_string(width_) + "x" + std::to_string(height_) +
         (wrapU_ ? " wrap-u" : " clamp-u") + (wrapV_ ? " wrap-v" : " clamp-v");
}

// ---------------------------------------------------------------------------------------------
namespace {

/// 16 unit gradient directions (Perlin's 2-D set generalised): the hash picks one per lattice
/// point, cheaper than a sine and cosine per corner.
struct GradientTable {
  glm::dvec2 g[16];
  GradientTable() {
    for (int k = 0; k < 16; ++k) {
      const double a = (k + 0.5) * std::numbers::pi / 8.0;
      g[k] = {std::cos(a), std::sin(a)};
    }
  }
};
const GradientTable& gradients() {
  static const GradientTable table;
  return table;
}

double fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }
double fadeDerivative(double t) { return 30.0 * t * t * (t * (t - 2.0) + 1.0); }

/// The lattice cell of an octave that holds a point: its floored corner and the gradients of
/// its four corners (what depends on the cell alone; points in the same cell share it).
struct NoiseCell {
  double fx0 = NAN, fy0 = NAN;  // NaN: no cell yet
  glm::dvec2 g00, g10, g01, g11;
};
void noiseCell(double fx0, double fy0, std::int64_t cellsX, std::int64_t cellsY, std::uint64_t octaveKey,
               NoiseCell& c) {
  std::int64_t i0 = cellIndex(fx0), j0 = cellIndex(fy0);
  std::int64_t i1 = i0 + 1, j1 = j0 + 1;
  // positiveMod(i0 + 1, n) from positiveMod(i0, n): one division per axis, not two.
  if (cellsX > 0) i0 = positiveMod(i0, cellsX), i1 = i0 + 1 == cellsX ? 0 : i0 + 1;
  if (cellsY > 0) j0 = positiveMod(j0, cellsY), j1 = j0 + 1 == cellsY ? 0 : j0 + 1;
  const GradientTable& table = gradients();
  const std::uint64_t h0 = hashAppend(octaveKey, std::uint64_t(i0)), h1 = hashAppend(octaveKey, std::uint64_t(i1));
  auto grad = [&](std::uint64_t column, std::int64_t j) { return table.g[hashAppend(column, std::uint64_t(j)) & 15u]; };
  c.fx0 = fx0, c.fy0 = fy0;
  c.g00 = grad(h0, j0), c.g10 = grad(h1, j0), c.g01 = grad(h0, j1), c.g11 = grad(h1, j1);
}

/// One octave of gradient noise at lattice coordinates (x, y), value in [-sqrt(2)/2, sqrt(2)/2],
/// with its analytic derivative in (x, y) when asked. Period (cellsX, cellsY) when non-zero.
/// A corner's gradient is hashWords(seed, octave, i, j), built from the octave's chain
/// `octaveKey` (core/hash.h, hashAppend): the prefix (seed, octave) is shared by every corner
/// and sample of the octave, (seed, octave, i) by the corners of one column. `cell` is the
/// cell of an earlier point, reused when this point lies in it (the same values, formed once).
template <bool WithDerivative>
double gradientNoise(double x, double y, std::int64_t cellsX, std::int64_t cellsY, std::uint64_t octaveKey,
                     NoiseCell& cell, glm::dvec2& d) {
  const double fx0 = std::floor(x), fy0 = std::floor(y);
  const double tx = x - fx0, ty = y - fy0;
  if (!(fx0 == cell.fx0 && fy0 == cell.fy0)) noiseCell(fx0, fy0, cellsX, cellsY, octaveKey, cell);
  const glm::dvec2 g00 = cell.g00, g10 = cell.g10, g01 = cell.g01, g11 = cell.g11;
  const double a = g00.x * tx + g00.y * ty;
  const double b = g10.x * (tx - 1.0) + g10.y * ty;
  const double c = g01.x * tx + g01.y * (ty - 1.0);
  const double e = g11.x * (tx - 1.0) + g11.y * (ty - 1.0);
  const double sx = fade(tx), sy = fade(ty);
  const double k = a - b - c + e;
  const double value = a + (b - a) * sx + (c - a) * sy + k * sx * sy;
  if constexpr (WithDerivative) {
    // d/dx of each corner term is its gradient's x component (and likewise y).
    const double dsx = fadeDerivative(tx), dsy = fadeDerivative(ty);
    const glm::dvec2 dk = g00 - g10 - g01 + g11;
    d.x = g00.x + (g10.x - g00.x) * sx + (b - a) * dsx + (g01.x - g00.x) * sy + dk.x * sx * sy +
          k * dsx * sy;
    d.y = g00.y + (g10.y - g00.y) * sx + (g01.y - g00.y) * sy + (c - a) * dsy + dk.y * sx * sy +
          k * sx * dsy;
  }
  return value;
}

}  // namespace

NoiseTexture::NoiseTexture(const NoiseParams& params) : params_(params) {
  NoiseParams& p = params_;
  const NoiseParams defaults;
  p.octaves = std::clamp(p.octaves, 1, 16);
  if (!std::isfinite(p.frequency) || p.frequency <= 0.0) p.frequency = defaults.frequency;
  if (!std::isfinite(p.lacunarity) || p.lacunarity <= 0.0) p.lacunarity = defaults.lacunarity;
  if (!std::isfinite(p.gain)) p.gain = defaults.gain;
  if (!std::isfinite(p.amplitude)) p.amplitude = defaults.amplitude;
  if (!std::isfinite(p.periodU) || p.periodU <= 0.0) p.periodU = 1.0;
  if (!std::isfinite(p.periodV) || p.periodV <= 0.0) p.periodV = 1.0;
  double total = 0.0, w = 1.0, f = p.frequency;
  for (int o = 0; o < p.octaves; ++o) {
    std::int64_t cu = 0, cv = 0;
    double fu = f, fv = f;
    if (p.periodicU) {
      cu = std::max<std::int64_t>(1, std::llround(std::min(f * p.periodU, 1e12)));
      fu = double(cu) / p.periodU;
    }
    if (p.periodicV) {
      cv = std::max<std::int64_t>(1, std::llround(std::min(f * p.periodV, 1e12)));
      fv = double(cv) / p.periodV;
    }
    freqU_.push_back(fu);
    freqV_.push_back(fv);
    cellsU_.push_back(cu);
    cellsV_.push_back(cv);
    weight_.push_back(w);
    octaveKey_.push_back(hashAppend(mix64(p.seed), std::uint64_t(o)));  // hashWords' chain after (seed, octave)
    total += std::fabs(w);
    w *= p.gain;
    f *= p.lacunarity;
  }
  // One octave spans [-sqrt(2)/2, sqrt(2)/2]; scale so the sum stays within +-amplitude.
  const double norm = total > 0.0 ? p.amplitude * std::numbers::sqrt2 / total : 0.0;
  for (double& x : weight_) x *= norm;
}

double NoiseTexture::evaluate(const glm::dvec2& uv, glm::dvec2* gradient) const {
  if (!gradient) {  // the value alone: no derivatives
    double value;
    values(&uv, 1, &value);
    return value;
  }
  *gradient = glm::dvec2(0.0);
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return 0.0;
  // Periodic axes fold into one period first (keeps precision for large u).
  const double u = foldU(uv.x), v = foldV(uv.y);
  double sum = 0.0;
  glm::dvec2 g(0.0);
  for (size_t o = 0; o < weight_.size(); ++o) {
    glm::dvec2 d;
    NoiseCell cell;
    const double n = gradientNoise<true>(u * freqU_[o], v * freqV_[o], cellsU_[o], cellsV_[o], octaveKey_[o], cell, d);
    sum += weight_[o] * n;
    g += weight_[o] * glm::dvec2(d.x * freqU_[o], d.y * freqV_[o]);
  }
  if (!std::isfinite(sum)) return 0.0;
  if (gradient && std::isfinite(g.x) && std::isfinite(g.y)) *gradient = g;
  return sum;
}

double NoiseTexture::value(const glm::dvec2& uv) const { return evaluate(uv, nullptr); }

double NoiseTexture::foldU(double x) const {
  return params_.periodicU ? x - std::floor(x / params_.periodU) * params_.periodU : x;
}
double NoiseTexture::foldV(double y) const {
  return params_.periodicV ? y - std::floor(y / params_.periodV) * params_.periodV : y;
}

void NoiseTexture::values(const glm::dvec2* uv, int n, double* out) const {
  // value() point by point, an octave at a time over all points, so that the points of one
  // footprint, which mostly share the coarse octaves' cells, form each cell's gradients once.
  // Each point's sum adds the same terms in the same order: the same values to the bit.
  constexpr int kBatch = 64;
  double u[kBatch], v[kBatch];
  for (int first = 0; first < n; first += kBatch) {
    const int m = std::min(kBatch, n - first);
    for (int p = 0; p < m; ++p) {
      const glm::dvec2& q = uv[first + p];
      const bool finite = std::isfinite(q.x) && std::isfinite(q.y);  // others: 0 below, as value() gives
      out[first + p] = 0.0;
      u[p] = finite ? foldU(q.x) : 0.5, v[p] = finite ? foldV(q.y) : 0.5;
    }
    glm::dvec2 unused;
    for (size_t o = 0; o < weight_.size(); ++o) {
      NoiseCell cell;
      for (int p = 0; p < m; ++p)
        out[first + p] +=
            weight_[o] * gradientNoise<false>(u[p] * freqU_[o], v[p] * freqV_[o], cellsU_[o], cellsV_[o], octaveKey_[o], cell, unused);
    }
    for (int p = 0; p < m; ++p) {
      const glm::dvec2& q = uv[first + p];
      if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(out[first + p])) out[first + p] = 0.0;
    }
  }
}

glm::dvec2 NoiseTexture::gradient(const glm::dvec2& uv) const {
  glm::dvec2 g;
  evaluate(uv, &g);
  return g;
}

std::string NoiseTexture::describe() const {
  char buf[192];
  std::snprintf(buf, sizeof buf,
                "noise octaves=%d frequency=%g lacunarity=%g gain=%g amplitude=%g seed=%llu%s%s",
                params_.octaves, params_.frequency, params_.lacunarity, params_.gain,
                params_.amplitude, static_cast<unsigned long long>(params_.seed),
                params_.periodicU ? " periodic-u" : "", params_.periodicV ? " periodic-v" : "");
  return buf;
}

// ---------------------------------------------------------------------------------------------
RampTexture::RampTexture(std::shared_ptr<const ScalarTexture> scalar, std::vector<RampStop> stops,
                         double low, double high, int samplesPerAxis)
    : scalar_(std::move(scalar)), stops_(std::move(stops)), low_(low), high_(high),
      samplesPerAxis_(std::clamp(samplesPerAxis, 1, 16)) {
  std::erase_if(stops_, [](const RampStop& s) { return !std::isfinite(s.position); });
  std::stable_sort(stops_.begin(), stops_.end(),
                   [](const RampStop& a, const RampStop& b) { return a.position < b.position; });
  if (stops_.empty()) stops_ = {{0.0, glm::vec3(0.0f)}, {1.0, glm::vec3(1.0f)}};
  if (!std::isfinite(low_) || !std::isfinite(high_) || low_ == high_) low_ = -1.0, high_ = 1.0;
}

glm::vec3 RampTexture::colourAt(double value) const {
  double t = std::isfinite(value) ? (value - low_) / (high_ - low_) : 0.5;
  t = std::clamp(t, 0.0, 1.0);
  if (t <= stops_.front().position) return stops_.front().colour;
  if (t >= stops_.back().position) return stops_.back().colour;
  const auto hi = std::upper_bound(stops_.begin(), stops_.end(), t,
                                   [](double x, const RampStop& s) { return x < s.position; });
  const auto lo = hi - 1;
  const double span = hi->position - lo->position;
  const double w = span > 0.0 ? (t - lo->position) / span : 1.0;
  return glm::vec3(glm::dvec3(lo->colour) + w * (glm::dvec3(hi->colour) - glm::dvec3(lo->colour)));
}

glm::vec3 RampTexture::sample(const glm::dvec2& uv, const UvFootprint& footprint) const {
  if (!scalar_) return colourAt(0.5 * (low_ + high_));
  glm::dvec2 half = footprint.halfBox();
  if (!std::isfinite(half.x) || !std::isfinite(half.y)) half = glm::dvec2(0.0);
  if (half.x == 0.0 && half.y == 0.0) return colourAt(scalar_->value(uv));
  const int n = samplesPerAxis_;
  std::array<glm::dvec2, 16 * 16> points;
  double value[16 * 16];
  for (int k = 0; k < n * n; ++k) {
    const int i = k % n, j = k / n;
    const glm::dvec2 offset(-1.0 + (2.0 * i + 1.0) / n, -1.0 + (2.0 * j + 1.0) / n);
    points[size_t(k)] = uv + offset * half;
  }
  // values() reads the n * n points set above (GCC cannot see that through the virtual call).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
  scalar_->values(points.data(), n * n, value);
#pragma GCC diagnostic pop
  glm::dvec3 sum(0.0);
  for (int k = 0; k < n * n; ++k) sum += glm::dvec3(colourAt(value[k]));
  return glm::vec3(sum / double(n * n));
}

std::string RampTexture::describe() const {
  return "ramp of " + std::to_string(stops_.size()) + " stops over [" + std::to_string(low_) +
         ", " + std::to_string(high_) + "] of " + (scalar_ ? scalar_->describe() : "nothing");
}

// ---------------------------------------------------------------------------------------------
ImageHeight::ImageHeight(const ImageRGBA& image, bool wrapU, bool wrapV, double scale,
                         double offset)
    : wrapU_(wrapU), wrapV_(wrapV), scale_(std::isfinite(scale) ? scale : 1.0),
      offset_(std::isfinite(offset) ? offset : 0.0) {
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() < size_t(image.width) * size_t(image.height))
    return;
  width_ = image.width;
  height_ = image.height;
  luminance_.resize(size_t(width_) * size_t(height_));
  double sum = 0.0;
  for (size_t k = 0; k < luminance_.size(); ++k) {
    const glm::vec4& p = image.pixels[k];
    double y = 0.2126 * p.x + 0.7152 * p.y + 0.0722 * p.z;
    if (!std::isfinite(y)) y = 0.0;
    luminance_[k] = y;
    sum += y;
  }
  meanHeight_ = sum / double(luminance_.size());
}

double ImageHeight::evaluate(const glm::dvec2& uv, glm::dvec2* gradient) const {
  if (gradient) *gradient = glm::dvec2(0.0);
  if (width_ == 0) return offset_;
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return offset_ + scale_ * meanHeight_;
  const auto [i0, i1, j0, j1, tx, ty] = bilinearTaps(uv, width_, height_, wrapU_, wrapV_);
  auto at = [&](std::int64_t i, std::int64_t j) {
    return luminance_[size_t(j) * size_t(width_) + size_t(i)];
  };
  const double h00 = at(i0, j0), h10 = at(i1, j0), h01 = at(i0, j1), h11 = at(i1, j1);
  const double top = h00 + tx * (h10 - h00), bottom = h01 + tx * (h11 - h01);
  const double h = top + ty * (bottom - top);
  if (gradient) {
    // d/dfx and d/dfy of the bilinear form; fx = u W - 1/2, fy = (1 - v) H - 1/2. In the clamped
    // margin the two corners coincide, so the derivative is 0 there, as the value is constant.
    const double dfx = (h10 - h00) + ty * (h11 - h01 - h10 + h00);
    const double dfy = bottom - top;
    *gradient = scale_ * glm::dvec2(dfx * width_, -dfy * height_);
  }
  return offset_ + scale_ * h;
}

double ImageHeight::value(const glm::dvec2& uv) const { return evaluate(uv, nullptr); }

glm::dvec2 ImageHeight::gradient(const glm::dvec2& uv) const {
  glm::dvec2 g;
  evaluate(uv, &g);
  return g;
}

std::string ImageHeight::describe() const {
  char buf[128];
  std::snprintf(buf, sizeof buf, "image height %dx%d scale=%g offset=%g", width_, height_, scale_,
                offset_);
  return buf;
}

}  // namespace wf

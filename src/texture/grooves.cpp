#include "texture/grooves.h"

#include "core/hash.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace wf {
namespace {

/// floor(x) as an index; beyond 2^52 (every double an integer there) folded into 2^32 first.
std::int64_t indexOf(double floored) {
  if (!(std::fabs(floored) < 0x1.0p52)) floored = std::fmod(floored, 0x1.0p32);
  return std::int64_t(floored);
}

}  // namespace

GrooveTexture::GrooveTexture(double count, double depth, std::uint64_t seed)
    : count_(std::isfinite(count) && count > 0.0 ? count : 1.0),
      depth_(std::isnan(depth) ? 0.0 : std::clamp(depth, 0.0, 1.0)), seed_(seed) {}

double GrooveTexture::grooveIntensity(std::int64_t k) const {
  return 1.0 - depth_ * unitFromHash(hashWords(seed_, std::uint64_t(k)));
}

std::int64_t GrooveTexture::grooveIndex(double coordinate) const {
  return indexOf(std::floor(coordinate * count_));
}

double GrooveTexture::intensity(double coordinate, double footprintWidth) const {
  const double x = coordinate * count_;  // in grooves
  if (!std::isfinite(x)) return mean();
  const double w = std::fabs(footprintWidth) * count_;
  if (!std::isfinite(w)) return mean();
  const double a = x - 0.5 * w, b = x + 0.5 * w;
  const double fa = std::floor(a), fb = std::floor(b);
  if (fa == fb || !(b > a)) return grooveIntensity(indexOf(std::floor(x)));
  const std::int64_t ka = indexOf(fa), kb = indexOf(fb);
  // Fractional ends: groove ka over [a, fa + 1), groove kb over [fb, b).
  double sum = grooveIntensity(ka) * (fa + 1.0 - a) + grooveIntensity(kb) * (b - fb);
  const double whole = fb - fa - 1.0;  // grooves ka+1 ... kb-1, wholly inside
  if (whole <= double(kMaxExactGrooves)) {
    for (std::int64_t k = ka + 1; k < kb; ++k) sum += grooveIntensity(k);
  } else {
    sum += whole * mean();
  }
  return std::clamp(sum / (b - a), 1.0 - depth_, 1.0);
}

double GrooveTexture::intensity(const glm::dvec2& uv, const UvFootprint& footprint,
                                int axis) const {
  const int a = axis == 1 ? 1 : 0;
  return intensity(uv[a], 2.0 * footprint.halfBox()[a]);
}

std::string GrooveTexture::describe() const {
  char buf[128];
  std::snprintf(buf, sizeof buf, "grooves count=%g depth=%g seed=%llu", count_, depth_,
                static_cast<unsigned long long>(seed_));
  return buf;
}

}  // namespace wf

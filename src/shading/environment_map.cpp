#include "shading/environment_map.h"

#include "core/numeric.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace wf {
namespace {

uint32_t hash32(uint32_t x) {  // integer finaliser (Murmur3 style mixing constants)
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

double lattice(uint32_t seed, int i, int period) {
  const uint32_t k = uint32_t(((i % period) + period) % period);
  return hash32(seed * 0x9e3779b9U ^ hash32(k)) / 4294967295.0;
}

// Periodic 1D value noise with smoothstep interpolation.
double noise1(uint32_t seed, double x, int period) {
  const double f = std::floor(x);
  const int i = int(f);
  double t = x - f;
  t = t * t * (3.0 - 2.0 * t);
  return lattice(seed, i, period) * (1.0 - t) + lattice(seed, i + 1, period) * t;
}

// Ridge height of the mountains at longitude phi in [0, 1).
double ridge(uint32_t seed, double phi) {
  double h = 0.0, amp = 0.5;
  int freq = 5;
  for (int o = 0; o < 6; ++o) {
    double nz = noise1(seed + uint32_t(o) * 101U, phi * freq, freq);
    nz = 1.0 - std::abs(2.0 * nz - 1.0);  // ridged
    h += amp * nz;
    amp *= 0.5;
    freq *= 2;
  }
  return h;  // about 0 ... 1
}

}  // namespace

EnvironmentMap::EnvironmentMap(int width, int height, std::vector<glm::vec3> texels)
    : width_(width), height_(height), texels_(std::move(texels)) {
  // An inconsistent image is an empty one (lookups give black), never an out-of-bounds read.
  if (width_ <= 0 || height_ <= 0 || texels_.size() != size_t(width_) * size_t(height_)) {
    width_ = height_ = 0;
    texels_.clear();
  }
}

glm::vec3 EnvironmentMap::lookup(const glm::dvec3& d) const {
  if (texels_.empty()) return glm::vec3(0.0f);
  double len = glm::length(d);
  glm::dvec3 u = (len > 1e-300 && std::isfinite(len)) ? d / len : glm::dvec3(0, 1, 0);
  const double lon = std::atan2(u.x, -u.z);  // -pi..pi, 0 straight ahead
  const double lat = std::asin(std::clamp(u.y, -1.0, 1.0));
  const double fx = (lon / (2.0 * kPi) + 0.5) * width_ - 0.5;
  const double fy = std::clamp((0.5 - lat / kPi) * height_ - 0.5, 0.0, double(height_ - 1));
  const int x0 = int(std::floor(fx)), y0 = std::max(0, std::min(int(fy), height_ - 2));
  const int y1 = std::min(y0 + 1, height_ - 1);  // a one-row image reads its only row
  const float a = float(fx - x0), b = height_ > 1 ? float(fy - y0) : 0.0f;
  auto at = [&](int x, int y) {
    x = ((x % width_) + width_) % width_;
    return texels_[size_t(y) * width_ + x];
  };
  return (at(x0, y0) * (1 - a) + at(x0 + 1, y0) * a) * (1 - b) +
         (at(x0, y1) * (1 - a) + at(x0 + 1, y1) * a) * b;
}

glm::dvec3 EnvironmentMap::mountainSceneSunDirection() {
  // Behind the viewer, 45 degrees up (above the highest ridge, 0.59 rad), so that a chrome ball
  // shows it.
  return glm::normalize(glm::dvec3(-0.45, 0.75, 0.60));
}

EnvironmentMap EnvironmentMap::mountainScene(int width, uint32_t seed) {
  width = std::max(16, width);
  const int height = width / 2;
  std::vector<glm::vec3> px(size_t(width) * height);
  const glm::dvec3 sunDir = mountainSceneSunDirection();
  for (int y = 0; y < height; ++y) {
    const double lat = (0.5 - (y + 0.5) / height) * kPi;  // +pi/2 at the top
    for (int x = 0; x < width; ++x) {
      const double phi = (x + 0.5) / width;  // 0..1
      const double lon = (phi - 0.5) * 2.0 * kPi;
      const glm::dvec3 dir(std::cos(lat) * std::sin(lon), std::sin(lat), -std::cos(lat) * std::cos(lon));
      glm::dvec3 c;
      const double mountainTop = 0.04 + 0.55 * ridge(seed, phi);  // radians above the horizon
      if (lat > mountainTop) {
        // Sky: pale at the horizon, deep blue at the zenith, plus a sun with a soft halo.
        const double t = std::pow(std::clamp(lat / (kPi / 2), 0.0, 1.0), 0.6);
        c = glm::mix(glm::dvec3(0.85, 0.90, 1.00), glm::dvec3(0.15, 0.35, 0.85), t);
        const double cs = glm::dot(dir, sunDir);
        if (cs > 0.9995) c = glm::dvec3(30.0, 28.0, 24.0);
        else c += glm::dvec3(1.0, 0.9, 0.7) * (0.6 * std::pow(std::max(0.0, cs), 64.0));
      } else if (lat > 0.0) {
        // Mountains: rock, with snow above a height that varies along the range.
        const double snowLine = 0.30 + 0.08 * noise1(seed + 7, phi * 40, 40);
        const double shade = 0.75 + 0.25 * noise1(seed + 13, phi * 160 + lat * 50, 160);
        c = lat > snowLine ? glm::dvec3(0.92, 0.94, 0.98) * shade
                           : glm::dvec3(0.33, 0.30, 0.28) * shade;
        if (lat < 0.02) c = glm::mix(glm::dvec3(0.10, 0.25, 0.12), c, lat / 0.02);
      } else {
        // Ground: a lake band near the horizon, then grass darkening towards the nadir.
        const double d = -lat / (kPi / 2);
        c = d < 0.06 ? glm::dvec3(0.20, 0.35, 0.55)
                     : glm::mix(glm::dvec3(0.20, 0.42, 0.15), glm::dvec3(0.05, 0.10, 0.04), std::sqrt(d));
      }
      px[size_t(y) * width + x] = glm::vec3(c);
    }
  }
  return EnvironmentMap(width, height, std::move(px));
}

}  // namespace wf

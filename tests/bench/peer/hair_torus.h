// The benchmark scene of issue 3: N hair-like straight segments standing on a torus, seen by a
// perspective camera. Shared by the WireFur A-buffer, its brute-force reference and the VTK peer
// (RenderLinesAsTubes) so that all three draw exactly the same segments from the same camera.
//
// Torus: centre at the origin, axis +z, major radius 1, minor radius 0.4. Roots are uniform by
// area (rejection on the minor angle with weight (R + r cos v) / (R + r)); each hair points
// along the surface normal tilted by up to ~25 degrees, length 0.06 ... 0.12.
// Camera: eye (0, -3.4, 2.2) looking at the origin, up +z, vertical field of view 38 degrees,
// near 0.5, far 8. Width of every segment: `kHairWidthPixels` screen pixels.
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

namespace wfbench {

struct HairSegment {
  glm::dvec3 p0, p1;
};

struct HairCamera {
  glm::dvec3 eye{0.0, -3.4, 2.2};
  glm::dvec3 target{0.0, 0.0, 0.0};
  glm::dvec3 up{0.0, 0.0, 1.0};
  double fovYDegrees = 38.0;
  double nearPlane = 0.5, farPlane = 8.0;
};

inline constexpr int kHairImageWidth = 1024;
inline constexpr int kHairImageHeight = 768;
inline constexpr double kHairWidthPixels = 1.5;

// SplitMix64: a tiny, fully specified generator so that every build draws the same hairs.
inline std::uint64_t splitMix64(std::uint64_t& s) {
  std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
inline double uniform01(std::uint64_t& s) { return double(splitMix64(s) >> 11) * 0x1.0p-53; }

inline std::vector<HairSegment> hairTorus(size_t count, std::uint64_t seed = 0x48A1Bull) {
  constexpr double kR = 1.0, kr = 0.4, kPi = 3.14159265358979323846;
  std::vector<HairSegment> out;
  out.reserve(count);
  std::uint64_t s = seed;
  while (out.size() < count) {
    const double u = 2 * kPi * uniform01(s), v = 2 * kPi * uniform01(s);
    if (uniform01(s) * (kR + kr) > kR + kr * std::cos(v)) continue;  // uniform by area
    const glm::dvec3 n(std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v));
    const glm::dvec3 root = glm::dvec3(kR * std::cos(u), kR * std::sin(u), 0.0) + kr * n;
    const glm::dvec3 jitter(uniform01(s) - 0.5, uniform01(s) - 0.5, uniform01(s) - 0.5);
    const glm::dvec3 dir = glm::normalize(n + 0.9 * jitter);
    const double length = 0.06 + 0.06 * uniform01(s);
    out.push_back({root, root + length * dir});
  }
  return out;
}

}  // namespace wfbench

// Bilinear interpolation on an n x n grid of nodes spanning [-1, 1]^2 (node i at -1 + 2i/(n-1)):
// the lookup of every table in the shading core (reflectance spheres, pseudo-reflectance maps).
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cstddef>

namespace wf {

/// `nodes` row-major (row j = second coordinate), n >= 2; u, v finite (clamped to [-1, 1]).
inline glm::vec3 bilinearNodeGrid(const glm::vec3* nodes, int n, double u, double v) {
  const double fu = std::clamp((u + 1.0) * 0.5 * (n - 1), 0.0, double(n - 1));
  const double fv = std::clamp((v + 1.0) * 0.5 * (n - 1), 0.0, double(n - 1));
  const int i = std::min(int(fu), n - 2), j = std::min(int(fv), n - 2);
  const float a = float(fu - i), b = float(fv - j);
  const glm::vec3* row0 = nodes + size_t(j) * n + i;
  const glm::vec3* row1 = row0 + n;
  return (row0[0] * (1.0f - a) + row0[1] * a) * (1.0f - b) + (row1[0] * (1.0f - a) + row1[1] * a) * b;
}

}  // namespace wf

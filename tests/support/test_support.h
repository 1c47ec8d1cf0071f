// Small helpers shared by the unit tests (header-only, tests only).
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace wf::test {

template <class V>
bool finite3(const V& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// Largest per-component |a - b|.
inline double maxAbsDiff(const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 d = glm::abs(a - b);
  return std::max({d.x, d.y, d.z});
}

/// A vector with every digit, for failure messages.
inline std::string str(const glm::dvec3& v) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "(%.17g, %.17g, %.17g)", v.x, v.y, v.z);
  return buf;
}

}  // namespace wf::test

// Finiteness checks, the largest component and the circle's constants that stages share, defined once: each file
// had its own copy in an anonymous namespace, which also kept files from sharing a translation
// unit (a unity build: CMAKE_UNITY_BUILD).
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace wf {

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

inline bool finite(double x) { return std::isfinite(x); }
inline bool finite(const glm::dvec2& p) { return std::isfinite(p.x) && std::isfinite(p.y); }
inline bool finite(const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }
/// finite(v) for a 3-vector, under the name most stages use.
inline bool finite3(const glm::dvec3& v) { return finite(v); }
/// v where finite, else zero.
inline glm::dvec3 finiteOrZero(const glm::dvec3& v) { return finite(v) ? v : glm::dvec3(0.0); }
/// The largest absolute component: a scale that cannot overflow as a length can.
inline double maxAbs(const glm::dvec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

}  // namespace wf

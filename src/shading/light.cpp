#include "shading/light.h"

#include "core/numeric.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace wf {
namespace {

glm::dvec3 clampIntensity(const glm::dvec3& c) {
  glm::dvec3 r;
  for (int i = 0; i < 3; ++i) r[i] = std::isfinite(c[i]) ? std::max(0.0, c[i]) : 0.0;
  return r;
}

}  // namespace

LightRig LightRig::canonical() const {
  LightRig out;
  out.ambient = clampIntensity(ambient);
  for (const DirectionalLight& l : lights) {
    if (!finite3(l.direction)) continue;
    const double len = glm::length(l.direction);
    if (!(len > 1e-300) || !std::isfinite(len)) continue;
    DirectionalLight c{l.direction / len, clampIntensity(l.intensity)};
    if (c.intensity.x + c.intensity.y + c.intensity.z <= 0.0) continue;  // dark light: skip
    out.lights.push_back(c);
  }
  return out;
}

bool LightRig::nearlyEqual(const LightRig& o, double tol) const {
  auto close = [tol](const glm::dvec3& a, const glm::dvec3& b) {
    return std::abs(a.x - b.x) <= tol && std::abs(a.y - b.y) <= tol && std::abs(a.z - b.z) <= tol;
  };
  if (lights.size() != o.lights.size() || !close(ambient, o.ambient)) return false;
  for (size_t i = 0; i < lights.size(); ++i)
    if (!close(lights[i].direction, o.lights[i].direction) ||
        !close(lights[i].intensity, o.lights[i].intensity))
      return false;
  return true;
}

LightRig LightRig::transformed(const glm::dmat3& eyeFromWorld) const {
  LightRig out = *this;
  for (DirectionalLight& l : out.lights) l.direction = eyeFromWorld * l.direction;
  return out;
}

std::string LightRig::toString() const {
  std::ostringstream s;
  s << "LightRig{ambient=(" << ambient.x << "," << ambient.y << "," << ambient.z << ")";
  for (const DirectionalLight& l : lights)
    s << " light{dir=(" << l.direction.x << "," << l.direction.y << "," << l.direction.z
      << ") I=(" << l.intensity.x << "," << l.intensity.y << "," << l.intensity.z << ")}";
  s << "}";
  return s.str();
}

LightRig LightRig::studioRig(int count) {
  count = std::clamp(count, 1, 7);
  // Key, fill, rim and four more around the viewer: all in front of or beside the subject,
  // one from behind (a rim light) so that "lights behind" are always exercised.
  static const glm::dvec3 dirs[7] = {{-0.45, 0.65, 0.62}, {0.75, 0.25, 0.61},
                                     {0.10, -0.80, 0.59}, {-0.30, 0.10, -0.95},
                                     {0.55, 0.75, 0.37},  {-0.85, -0.30, 0.43},
                                     {0.35, -0.35, 0.87}};
  static const glm::dvec3 tint[7] = {{1.00, 0.97, 0.92}, {0.85, 0.90, 1.00}, {1.00, 1.00, 1.00},
                                     {0.90, 0.95, 1.00}, {1.00, 0.90, 0.85}, {0.95, 1.00, 0.95},
                                     {1.00, 1.00, 0.90}};
  LightRig rig;
  rig.ambient = glm::dvec3(0.05);
  for (int i = 0; i < count; ++i)
    rig.lights.push_back({glm::normalize(dirs[i]), tint[i] * (0.95 / count)});
  return rig;
}

}  // namespace wf

// Bounds of a scene's geometry (what the camera frames and the near / far planes enclose).
#include "render/scene.h"

#include <algorithm>
#include <cmath>

namespace wf {

template <class F>
void Scene::forEachPoint(F&& f) const {
  for (const SceneSurface& s : surfaces)
    for (const glm::uvec3& t : s.mesh.triangles)
      for (int k = 0; k < 3; ++k)
        if (t[k] < s.mesh.positions.size()) f(s.mesh.positions[t[k]]);
  for (const SceneWire& w : wires)
    for (const glm::dvec3& p : w.lines.points) f(p);
}

bool Scene::bounds(glm::dvec3& lo, glm::dvec3& hi) const {
  lo = glm::dvec3(1e300);
  hi = glm::dvec3(-1e300);
  bool any = false;
  forEachPoint([&](const glm::dvec3& p) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return;
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
    any = true;
  });
  return any;
}

bool Scene::boundingSphere(glm::dvec3& centre, double& radius) const {
  glm::dvec3 lo, hi;
  if (!bounds(lo, hi)) return false;
  centre = 0.5 * lo + 0.5 * hi;
  double r2 = 0;
  forEachPoint([&](const glm::dvec3& p) {
    const glm::dvec3 d = p - centre;
    const double q = glm::dot(d, d);
    if (std::isfinite(q)) r2 = std::max(r2, q);
  });
  radius = std::sqrt(r2);
  return true;
}

}  // namespace wf

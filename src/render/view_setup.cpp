// Stage "camera" (render/pipeline.h): which camera a render uses and its near and far planes.
#include "render/pipeline.h"

#include <algorithm>
#include <cmath>

namespace wf {

Camera withDepthRange(Camera c, const Scene& scene) {
  if (c.nearPlane > 0 && c.farPlane > 0) return c;
  // Near and far from the bounding sphere, as tight as the scene allows.
  glm::dvec3 centre;
  double sphereRadius = 0;
  const bool hasBounds = scene.boundingSphere(centre, sphereRadius);
  const glm::dvec3 dir = glm::normalize(c.target - c.eye);
  double dmin = 1e-3, dmax = 1e3;
  if (hasBounds) {
    const double radius = std::max(sphereRadius, 1e-300);
    const double along = glm::dot(centre - c.eye, dir);
    dmax = along + radius * 1.01;
    dmin = std::max(along - radius * 1.01, dmax * 1e-6);
    if (!(dmax > 0)) dmax = 1.0, dmin = 1e-6;
  }
  if (c.nearPlane <= 0) c.nearPlane = dmin;
  if (c.farPlane <= 0) c.farPlane = std::max(dmax, c.nearPlane * 2);
  return c;
}

Camera chooseCamera(const Scene& scene, const RenderOptions& o, RenderStats& st) {
  glm::dvec3 centre;
  double sphereRadius = 0;
  const bool hasBounds = scene.boundingSphere(centre, sphereRadius);
  bool useScenes = scene.camera.has_value();
  if (useScenes) {
    const std::string problem = scene.camera->problem();
    if (!problem.empty()) {
      st.warnings.push_back("camera: " + problem + "; framed from the scene's bounds instead");
      useScenes = false;
    }
  }
  Camera c = useScenes ? *scene.camera
                       : (hasBounds ? frameSphere(centre, sphereRadius, double(o.width) / o.height)
                                    : Camera{});
  return withDepthRange(c, scene);
}

}  // namespace wf

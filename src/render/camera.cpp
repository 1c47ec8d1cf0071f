#include "render/camera.h"

#include "core/numeric.h"

#include <algorithm>
#include <cmath>

namespace wf {

std::string Camera::problem() const {
  if (!finite3(eye) || !finite3(target) || !finite3(up)) return "non-finite eye, target or up";
  const glm::dvec3 f = target - eye;
  if (!(glm::length(f) > 0)) return "eye and target coincide";
  if (!(glm::length(glm::cross(f, up)) > 1e-12 * glm::length(f) * glm::length(up)))
    return "up is parallel to the view direction (or zero)";
  if (projection == Projection::Perspective && !(fovYDegrees > 0 && fovYDegrees <= 179))
    return "fov must be in (0, 179] degrees";
  if (projection == Projection::Orthographic && !(orthoHeight > 0 && std::isfinite(orthoHeight)))
    return "orthographic height must be positive";
  if (!(nearPlane >= 0) || !(farPlane >= 0) || !std::isfinite(nearPlane) || !std::isfinite(farPlane))
    return "near and far must be finite and >= 0";
  if (nearPlane > 0 && farPlane > 0 && !(farPlane > nearPlane)) return "far must exceed near";
  return {};
}

Camera frameSphere(const glm::dvec3& centre, double radius, double aspect,
                   Camera::Projection projection, const glm::dvec3& direction, double fovYDegrees) {
  Camera c;
  c.projection = projection;
  if (!(radius > 0) || !std::isfinite(radius)) radius = std::max(1e-300, std::abs(centre.x) * 1e-9 + 1.0);
  const glm::dvec3 dir = glm::normalize(direction);
  c.target = centre;
  c.up = std::abs(dir.z) > 0.99 ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1);
  c.fovYDegrees = std::isfinite(fovYDegrees) ? std::clamp(fovYDegrees, 1e-3, 179.0) : 30.0;
  const double halfFov = glm::radians(c.fovYDegrees) / 2;
  const double fit = std::min(1.0, aspect);  // the smaller image side holds the sphere
  const double dist = radius / std::sin(std::atan(std::tan(halfFov) * fit)) * 1.08;
  c.eye = centre + dir * dist;
  c.orthoHeight = 2.16 * radius / fit;
  c.nearPlane = std::max(dist - 1.5 * radius, dist * 1e-4);
  c.farPlane = dist + 1.5 * radius;
  return c;
}

ViewTransform ViewTransform::make(const Camera& c, int width, int height) {
  ViewTransform v;
  v.width = width;
  v.height = height;
  const glm::dvec3 back = glm::normalize(c.eye - c.target);
  const glm::dvec3 right = glm::normalize(glm::cross(c.up, back));
  const glm::dvec3 up = glm::cross(back, right);
  v.eyeFromWorld = glm::transpose(glm::dmat3(right, up, back));
  v.eye = c.eye;
  v.perspective = c.projection == Camera::Projection::Perspective;
  v.cx = width / 2.0;
  v.cy = height / 2.0;
  v.focal = (height / 2.0) / std::tan(glm::radians(c.fovYDegrees) / 2);
  v.orthoScale = height / c.orthoHeight;
  v.nearPlane = c.nearPlane;
  v.farPlane = c.farPlane;
  return v;
}

double ViewTransform::maxRayAngle() const {
  if (!perspective) return 0.0;
  const double rx = std::max(cx, width - cx), ry = std::max(cy, height - cy);
  return std::atan(std::sqrt(rx * rx + ry * ry) / focal);
}

}  // namespace wf

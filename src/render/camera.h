// Cameras and the view transform every renderer in the core shares.
//
// Eye space: camera at the origin looking down -z, +y up (OpenGL's convention, and the one in
// which the pseudo-reflectance maps and reflectance spheres are built: viewer on +z). Screen
// space: x to the right and y down in pixels, pixel (i, j) covering [i, i+1] x [j, j+1].
// Depth is the view distance d = -z_eye > 0. For a perspective camera 1/d is linear in screen
// space, for an orthographic one d itself; ViewTransform::screenDepthKey gives that quantity.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

#include <string>

namespace wf {

struct Camera {
  enum class Projection { Perspective, Orthographic };
  Projection projection = Projection::Perspective;
  glm::dvec3 eye{0.0, 0.0, 5.0};
  glm::dvec3 target{0.0};
  glm::dvec3 up{0.0, 1.0, 0.0};
  double fovYDegrees = 30.0;  ///< perspective: vertical field of view, (0, 179]
  double orthoHeight = 2.0;   ///< orthographic: world height of the image
  double nearPlane = 0.0;     ///< 0: chosen from the scene's bounds
  double farPlane = 0.0;      ///< 0: chosen from the scene's bounds
  /// Empty when the camera can be used; otherwise what is wrong with it.
  std::string problem() const;
};

/// A camera that frames the sphere (centre, radius) seen from `direction` (from the target
/// towards the eye), the sphere filling the smaller image side. Works for any scale.
Camera frameSphere(const glm::dvec3& centre, double radius, double aspect,
                   Camera::Projection projection = Camera::Projection::Perspective,
                   const glm::dvec3& direction = glm::dvec3(0.55, -0.75, 0.45), double fovYDegrees = 30.0);

struct ViewTransform {
  glm::dmat3 eyeFromWorld{1.0};  ///< rows: right, up, back
  glm::dvec3 eye{0.0};
  bool perspective = true;
  double focal = 1.0;       ///< perspective: pixels per unit of x/d
  double orthoScale = 1.0;  ///< orthographic: pixels per world unit
  double cx = 0, cy = 0;    ///< image centre in pixels
  double nearPlane = 0.1, farPlane = 100.0;
  int width = 1, height = 1;

  static ViewTransform make(const Camera& camera, int width, int height);
  glm::dvec3 toEye(const glm::dvec3& world) const { return eyeFromWorld * (world - eye); }
  /// Screen position of an eye-space point in front of the camera (d > 0 for perspective).
  glm::dvec2 project(const glm::dvec3& p) const {
    if (perspective) {
      const double d = -p.z;
      return {cx + focal * p.x / d, cy - focal * p.y / d};
    }
    return {cx + orthoScale * p.x, cy - orthoScale * p.y};
  }
  /// project(p), and pixelsPerWorld at p's depth in `scale`: one division for both (wire set-up).
  /// The point may differ from project()'s in its last bit. As project(), for a point in front
  /// of the camera (d > 0 for perspective; else `scale` is not positive, or infinite).
  glm::dvec2 projectScaled(const glm::dvec3& p, double& scale) const {
    scale = perspective ? focal / -p.z : orthoScale;
    return {cx + scale * p.x, cy - scale * p.y};
  }
  /// The depth key (1/d or d), linear in screen space.
  double depthKey(double d) const { return perspective ? 1.0 / d : d; }
  /// Inverse of depthKey. Under perspective a key <= 0 (extrapolated beyond the vanishing
  /// line) is infinitely far, never in front of anything.
  double depthFromKey(double key) const { return perspective ? (key > 0.0 ? 1.0 / key : INFINITY) : key; }
  /// Eye-space point at screen (x, y) and view depth d.
  glm::dvec3 eyePoint(double x, double y, double d) const {
    if (perspective) return {(x - cx) / focal * d, -(y - cy) / focal * d, -d};
    return {(x - cx) / orthoScale, -(y - cy) / orthoScale, -d};
  }
  /// Unit vector from an eye-space point towards the viewer.
  glm::dvec3 viewVector(const glm::dvec3& p) const {
    return perspective ? viewVector(p, glm::length(p)) : glm::dvec3(0.0, 0.0, 1.0);
  }
  /// The same, given l = |p| (wire set-up has it already). One reciprocal for the three
  /// components (l is 0, or at least the square root of the smallest normal double: 1 / l is
  /// finite for every finite l > 0).
  glm::dvec3 viewVector(const glm::dvec3& p, double l) const {
    if (!perspective) return {0.0, 0.0, 1.0};
    return l > 0 ? p * (-1.0 / l) : glm::dvec3(0.0, 0.0, 1.0);
  }
  /// Pixels per world unit across the view at depth d (focal / d; orthographic: the scale).
  double pixelsPerWorld(double d) const { return perspective ? focal / d : orthoScale; }
  /// The largest angle (radians) between a view ray and the view axis in this image.
  double maxRayAngle() const;
  /// tan^2 of maxRayAngle() without its arc tangent (the image's farthest corner from the
  /// centre over the focal length, squared); 0 when orthographic.
  double maxRayTan2() const {
    if (!perspective) return 0.0;
    const double rx = std::max(cx, width - cx), ry = std::max(cy, height - cy);
    return (rx * rx + ry * ry) / (focal * focal);
  }
};

}  // namespace wf

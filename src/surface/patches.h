// Analytic parametric patches (docs/surfaces.md): every one answers S(u,v) and its exact first
// derivatives Su, Sv (no finite differences inside). u runs "around" (periodic where the shape
// closes), v "along"; N = Su x Sv points outward for the closed shapes.
//
// Each patch has a static `problem(...)` that checks the parameters it would be built from (empty
// string when they are usable) so that a scene loader can report bad input before building, and
// a member `problem()` for the parameters it holds. Evaluating a patch whose problem() is not
// empty is defined (finite where it can be) but meaningless.
#pragma once

#include "surface/surface.h"

#include <glm/glm.hpp>

#include <array>
#include <string>
#include <vector>

namespace wf {

/// Sphere about the origin: u in [0,1] around z (periodic), v in [0,1] from the south pole
/// (0,0,-r) to the north pole (0,0,r). Poles lie exactly on the axis (Su = 0 there).
/// S = r (sin(pi v) cos(2 pi u), sin(pi v) sin(2 pi u), -cos(pi v)).
class SpherePatch final : public Surface {
 public:
  explicit SpherePatch(double radius = 1.0) : radius_(radius) {}
  static std::string problem(double radius);
  std::string problem() const { return problem(radius_); }
  double radius() const { return radius_; }
  ParameterDomain domain() const override { return {0.0, 1.0, 0.0, 1.0, true, false}; }
  SurfacePoint evaluate(double u, double v) const override;
  std::string describe() const override;

 private:
  double radius_;
};

/// Torus about z: u in [0,1] around z, v in [0,1] around the tube (both periodic).
/// S = (R + r cos(2 pi v)) (cos(2 pi u), sin(2 pi u), 0) + r sin(2 pi v) z.
class TorusPatch final : public Surface {
 public:
  TorusPatch(double major = 1.0, double minor = 0.35) : major_(major), minor_(minor) {}
  static std::string problem(double major, double minor);
  std::string problem() const { return problem(major_, minor_); }
  ParameterDomain domain() const override { return {0.0, 1.0, 0.0, 1.0, true, true}; }
  SurfacePoint evaluate(double u, double v) const override;
  std::string describe() const override;

 private:
  double major_, minor_;
};

/// Rectangle in the z = 0 plane centred on the origin: S = ((u - 1/2) sx, (v - 1/2) sy, 0), N = +z.
class PlanePatch final : public Surface {
 public:
  PlanePatch(double sizeX = 2.0, double sizeY = 2.0) : sizeX_(sizeX), sizeY_(sizeY) {}
  static std::string problem(double sizeX, double sizeY);
  std::string problem() const { return problem(sizeX_, sizeY_); }
  ParameterDomain domain() const override { return {0.0, 1.0, 0.0, 1.0, false, false}; }
  SurfacePoint evaluate(double u, double v) const override;
  std::string describe() const override;

 private:
  double sizeX_, sizeY_;
};

/// How a revolution profile passes through its points.
enum class ProfileInterpolation {
  Smooth,  ///< centripetal Catmull-Rom (C1; see RevolutionPatch)
  Linear   ///< straight segments (the old lathe)
};

/// A profile curve (radius, height) revolved about z: u in [0,1] around (periodic), v in [0,1]
/// along the profile, first point to last, by (approximate) arc length.
///
/// The curve passes through every point. Smooth: centripetal Catmull-Rom tangents (Yuksel et al.
/// 2011: no cusps or loops inside a segment), each segment a cubic Bezier. Its radius never goes
/// below 0: the inner Bezier control radii are clamped to >= 0, so by the convex hull property
/// the curve cannot cross the axis. Corners: a point flagged in `corners`, a point repeated in
/// the input (the duplicates are merged) or, when cornerAngleDegrees < 180, a point where the
/// polyline turns by more than that angle; the curve's tangent is then one-sided there (each
/// side a parabola end condition). The ends of the profile use the same parabola end condition,
/// except an end on the axis (a pole): its tangent is made radial (perpendicular to the axis) so
/// the surface closes smoothly there instead of in a cone tip (flag it a corner for a cone tip).
/// Arc length: each segment's length table (16 nodes, 4-point Gauss-Legendre) is inverted by a
/// C1 cubic Hermite (slopes dt/ds = 1/|B'(t)|), so |Sv| is within a fraction of a percent of the
/// profile length and Sv stays analytic.
/// S = (r(v) cos(2 pi u), r(v) sin(2 pi u), z(v)); N is outward when the profile runs bottom to top.
class RevolutionPatch final : public Surface {
 public:
  explicit RevolutionPatch(std::vector<glm::dvec2> points, std::vector<bool> corners = {},
                           ProfileInterpolation interpolation = ProfileInterpolation::Smooth,
                           double cornerAngleDegrees = 180.0);
  static std::string problem(const std::vector<glm::dvec2>& points, const std::vector<bool>& corners = {});
  std::string problem() const { return problem(input_, inputCorners_); }
  ParameterDomain domain() const override { return {0.0, 1.0, 0.0, 1.0, true, false}; }
  SurfacePoint evaluate(double u, double v) const override;
  std::string describe() const override;
  /// The profile (radius, height) at v, and d/dv of it.
  glm::dvec2 profile(double v, glm::dvec2* derivative = nullptr) const;
  double profileLength() const { return length_; }
  /// The points as used (duplicates merged) and which of them are corners.
  const std::vector<glm::dvec2>& points() const { return points_; }
  const std::vector<bool>& corners() const { return corners_; }
  /// The v of every interior corner of the profile.
  std::vector<double> creasesV() const override;

 private:
  struct Interval {  // one arc-length table interval of one Bezier segment
    double s0, s1, t0, t1, g0, g1;  // arc length, segment parameter, dt/ds at both ends
    int segment;
  };
  std::vector<glm::dvec2> input_;
  std::vector<bool> inputCorners_;
  ProfileInterpolation interpolation_;
  std::vector<glm::dvec2> points_;
  std::vector<bool> corners_;
  std::vector<std::array<glm::dvec2, 4>> bezier_;  // per segment
  std::vector<Interval> table_;
  double length_ = 0.0;
};

/// One cross-section of a loft, placed at a spine control point.
struct LoftSection {
  glm::dvec3 centre{0.0};          ///< spine control point
  double a = 1.0, b = 1.0;         ///< radii along the section axes n1, n2 (0 closes the loft)
  std::vector<glm::dvec2> profile; ///< optional closed 2D polyline (x along n1, y along n2), scaled by (a, b)
};

/// A loft: cross-sections along a spine (paper §4: "Oscar was modelled by lofting between a series
/// of cross-sections spaced out along a spline curve"). u in [0,1] around the section (periodic),
/// v in [0,1] along the spine.
///
/// Spine C(v): clamped uniform cubic B-spline of the section centres (C2; passes through the first
/// and last; degree min(3, n-1) for fewer than 4 sections). a, b and the profile points are blended
/// along v with the same basis. Section frame: t = C'/|C'|, n1 = unit(up - (up.t) t), n2 = t x n1
/// (smooth and analytic in v). Fails where t is parallel to up; `up` = (0,0,0) (the default) picks
/// the coordinate axis (z, then y, then x) most perpendicular to the spine everywhere; problem()
/// reports a spine that comes within ~8 degrees of parallel to the chosen up.
/// Ellipse: S = C + a cos(2 pi u) n1 + b sin(2 pi u) n2. Profile: S = C + a q_x(u) n1 + b q_y(u) n2
/// with q the periodic uniform Catmull-Rom through the (blended) profile points, point k at
/// u = k / count. A section with a = b = 0 at an end closes the loft there (a pole).
class LoftPatch final : public Surface {
 public:
  explicit LoftPatch(std::vector<LoftSection> sections, glm::dvec3 up = glm::dvec3(0.0));
  static std::string problem(const std::vector<LoftSection>& sections, glm::dvec3 up = glm::dvec3(0.0));
  std::string problem() const { return problem(sections_, requestedUp_); }
  ParameterDomain domain() const override { return {0.0, 1.0, 0.0, 1.0, true, false}; }
  SurfacePoint evaluate(double u, double v) const override;
  std::string describe() const override;
  /// The spine point and the section frame at v.
  glm::dvec3 spine(double v) const;
  glm::dvec3 up() const { return up_; }

 private:
  std::vector<LoftSection> sections_;
  glm::dvec3 requestedUp_, up_;
  size_t profileCount_ = 0;  // 0: ellipses
};

/// Bicubic Bezier patch: control point (i, j) is controlPoints[4 j + i], i along u, j along v;
/// u, v in [0,1], S = sum B_i(u) B_j(v) P_ij (Bernstein).
class BezierPatch final : public Surface {
 public:
  explicit BezierPatch(const std::array<glm::dvec3, 16>& controlPoints) : points_(controlPoints) {}
  static std::string problem(const std::array<glm::dvec3, 16>& controlPoints);
  std::string problem() const { return problem(points_); }
  ParameterDomain domain() const override { return {0.0, 1.0, 0.0, 1.0, false, false}; }
  SurfacePoint evaluate(double u, double v) const override;
  std::string describe() const override;

 private:
  std::array<glm::dvec3, 16> points_;
};

/// Uniform cubic B-spline surface over a countU x countV control net (net[j countU + i], i along
/// u). Each direction is open-clamped (passes through the boundary control points; degree
/// min(3, count-1), count >= 2) or periodic (closed, C2; count >= 3 control points, the net wraps).
/// u, v in [0,1].
class BSplinePatch final : public Surface {
 public:
  BSplinePatch(std::vector<glm::dvec3> net, int countU, int countV, bool periodicU = false, bool periodicV = false);
  static std::string problem(const std::vector<glm::dvec3>& net, int countU, int countV, bool periodicU = false,
                             bool periodicV = false);
  std::string problem() const { return problem(net_, countU_, countV_, periodicU_, periodicV_); }
  ParameterDomain domain() const override { return {0.0, 1.0, 0.0, 1.0, periodicU_, periodicV_}; }
  SurfacePoint evaluate(double u, double v) const override;
  std::string describe() const override;

 private:
  std::vector<glm::dvec3> net_;
  int countU_, countV_;
  bool periodicU_, periodicV_;
};

}  // namespace wf

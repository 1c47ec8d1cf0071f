// The one surface concept of docs/design.md: a surface answers S(u,v) and its first derivatives
// Su = dS/du, Sv = dS/dv over a rectangular parameter domain, with N = Su x Sv / |Su x Sv|.
// Analytic patches (src/surface/patches.h), vtkParametricFunction and meshes with texture
// coordinates (vtk_filters) and OpenCASCADE faces (vtk_filters) are adapters to it; the
// tessellator, the burnish grain, the fur and the scale generators only ever see this class.
//
// Degenerate places are defined, never NaN: where Su x Sv vanishes (a pole of a sphere, the
// closed end of a loft, a cusp) `frame` returns the limit normal, taken from a regular point
// stepped towards the middle of the domain (see surface.cpp), and unit tangents taken from the
// same regular point when a derivative itself is zero.
#pragma once

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace wf {

/// The valid parameter rectangle [u0, u1] x [v0, v1] and its periodicity.
struct ParameterDomain {
  double u0 = 0.0, u1 = 1.0, v0 = 0.0, v1 = 1.0;
  bool periodicU = false, periodicV = false;
  double du() const { return u1 - u0; }
  double dv() const { return v1 - v0; }
  /// (s, t) in [0,1]^2 to (u, v) in the domain.
  glm::dvec2 fromUnit(double s, double t) const { return {u0 + s * du(), v0 + t * dv()}; }
  glm::dvec2 toUnit(double u, double v) const { return {(u - u0) / du(), (v - v0) / dv()}; }
  bool contains(double u, double v) const { return u >= u0 && u <= u1 && v >= v0 && v <= v1; }
};

/// A point of a surface with its first derivatives.
struct SurfacePoint {
  glm::dvec3 P{0.0}, Su{0.0}, Sv{0.0};
};

/// The same with the unit normal and unit tangents, all finite.
struct SurfaceFrame {
  glm::dvec3 P{0.0}, Su{0.0}, Sv{0.0};  ///< as evaluated (Su, Sv may be zero at a pole)
  glm::dvec3 N{0.0, 0.0, 1.0};          ///< unit Su x Sv, or its limit at a degenerate point
  glm::dvec3 Tu{1.0, 0.0, 0.0};         ///< unit Su, or its limit; orthogonal to N
  glm::dvec3 Tv{0.0, 1.0, 0.0};         ///< unit Sv, or its limit; orthogonal to N
  double areaElement = 0.0;             ///< |Su x Sv| (0 at a degenerate point)
  bool degenerate = false;              ///< true when N (or a tangent) is a limit
};

class Surface {
 public:
  virtual ~Surface() = default;
  virtual ParameterDomain domain() const = 0;
  /// S, Su, Sv at (u, v). (u, v) outside the domain is clamped (wrapped where periodic).
  virtual SurfacePoint evaluate(double u, double v) const = 0;
  /// A short description for messages ("sphere r=1").
  virtual std::string describe() const = 0;

  /// +1 when the surface's front (outward) normal is Su x Sv, -1 when it is -(Su x Sv): a
  /// mirrored placement (TransformedSurface with det < 0) keeps its parameterisation, so its
  /// hairs, scales and textures are the mirror image, and turns the normal round instead.
  virtual double normalSign() const { return 1.0; }
  /// Values of v strictly inside the domain where the surface is creased: S is continuous but
  /// its derivatives jump (a lathe profile's corner, a jug's base rim). Tessellation puts a
  /// doubled row of vertices there, each with its own side's normal, so the crease stays crisp.
  virtual std::vector<double> creasesV() const { return {}; }

  /// Position, derivatives, unit normal (times normalSign()) and tangents at (u, v), finite
  /// everywhere (see top).
  SurfaceFrame frame(double u, double v) const;
  /// Relative threshold under which |Su x Sv| counts as zero: |Su x Sv| <= eps |Su| |Sv|, or
  /// both derivatives below eps times the surface's scale.
  static constexpr double kDegenerateEpsilon = 1e-10;

 private:
  SurfaceFrame frameAlongSuSv(double u, double v) const;
};

}  // namespace wf

// Silhouettes (surface/silhouette.h) against the true ones in perspective: for a sphere, a
// cylinder and a torus, every drawn chord's midpoint is moved on screen, across the chord, to where
// the rays through it start to graze the surface (an implicit function's minimum along each ray,
// near the chord), and that distance is the error in pixels. Seams and poles give closed loops;
// non-finite surfaces give defined, counted output.
#include "surface/silhouette.h"

#include "surface/patches.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

namespace wf {
namespace {

class Cylinder final : public Surface {
 public:
  Cylinder(double r, double h) : r_(r), h_(h) {}
  ParameterDomain domain() const override { return {0.0, 2 * std::numbers::pi, -h_, h_, true, false}; }
  SurfacePoint evaluate(double u, double v) const override {
    return {{r_ * std::cos(u), r_ * std::sin(u), v}, {-r_ * std::sin(u), r_ * std::cos(u), 0.0}, {0.0, 0.0, 1.0}};
  }
  std::string describe() const override { return "cylinder"; }

 private:
  double r_, h_;
};

// NaN over half of the domain.
class HalfBroken final : public Surface {
 public:
  ParameterDomain domain() const override { return sphere_.domain(); }
  SurfacePoint evaluate(double u, double v) const override {
    if (u > 0.5 * (domain().u0 + domain().u1)) return {{NAN, NAN, NAN}, {NAN, 0, 0}, {0, NAN, 0}};
    return sphere_.evaluate(u, v);
  }
  std::string describe() const override { return "half broken"; }

 private:
  SpherePatch sphere_{1.0};
};

ViewTransform viewFrom(const glm::dvec3& eye, int w = 800, int h = 600, double fov = 35.0) {
  Camera c;
  c.eye = eye;
  c.target = glm::dvec3(0.0);
  c.up = std::abs(eye.x) + std::abs(eye.y) > 0 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
  c.fovYDegrees = fov;
  c.nearPlane = 0.1;
  c.farPlane = 100;
  return ViewTransform::make(c, w, h);
}

// Whether the ray through screen point q meets {f < 0} within [t0, t1] of its length (the
// minimum of f along it, sampled then narrowed by golden sections).
bool grazes(const ViewTransform& v, const glm::dvec2& q, double t0, double t1, const std::function<double(glm::dvec3)>& f) {
  const glm::dmat3 worldFromEye = glm::transpose(v.eyeFromWorld);
  const glm::dvec3 d = glm::normalize(worldFromEye * v.eyePoint(q.x, q.y, 1.0));
  auto at = [&](double t) { return f(v.eye + t * d); };
  const int n = 400;
  double best = INFINITY, bt = t0;
  for (int k = 0; k <= n; ++k) {
    const double t = t0 + (t1 - t0) * k / n, y = at(t);
    if (y < best) best = y, bt = t;
  }
  double a = std::max(t0, bt - (t1 - t0) / n), b = std::min(t1, bt + (t1 - t0) / n);
  const double gr = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int it = 0; it < 80; ++it) {
    const double c = b - gr * (b - a), e = a + gr * (b - a);
    if (at(c) < at(e)) b = e;
    else a = c;
  }
  return std::min(best, at(0.5 * (a + b))) < 0.0;
}

struct Measure {
  double worst = 0.0;
  int chords = 0, judged = 0;
};

// The largest screen distance of a chord's midpoint from the true silhouette (within 1.5 px
// across the chord, rays judged within `window` of the midpoint's distance). Chords within 4 px
// of a cusp of the drawn curve (where it doubles back on screen: two branches meet, and the
// crossing across the chord is not one position) are not judged.
Measure measure(const PolylineSet& lines, const ViewTransform& v, double window, const std::function<double(glm::dvec3)>& f) {
  Measure m;
  for (size_t i = 0; i < lines.polylineCount(); ++i) {
    std::vector<glm::dvec2> cusps;
    for (std::uint32_t k = lines.starts[i] + 1; k + 1 < lines.starts[i + 1]; ++k) {
      const glm::dvec2 p0 = v.project(v.toEye(lines.points[k - 1])), p1 = v.project(v.toEye(lines.points[k])),
                       p2 = v.project(v.toEye(lines.points[k + 1]));
      if (glm::dot(p1 - p0, p2 - p1) < 0.0) cusps.push_back(p1);
    }
    auto nearCusp = [&](const glm::dvec2& p) {
      for (const glm::dvec2& c : cusps)
        if (glm::length(p - c) < 4.0) return true;
      return false;
    };
    for (std::uint32_t k = lines.starts[i]; k + 1 < lines.starts[i + 1]; ++k) {
      const glm::dvec3 a = lines.points[k], b = lines.points[k + 1], mid = 0.5 * (a + b);
      const glm::dvec2 pa = v.project(v.toEye(a)), pb = v.project(v.toEye(b)), pm = v.project(v.toEye(mid));
      if (glm::length(pb - pa) < 1e-9) continue;
      ++m.chords;
      if (nearCusp(pa) || nearCusp(pb)) continue;
      const glm::dvec2 n = glm::normalize(glm::dvec2(pa.y - pb.y, pb.x - pa.x));
      const double t = glm::length(mid - v.eye);
      auto hit = [&](double s) { return grazes(v, pm + s * n, t - window, t + window, f); };
      // The silhouette crossing within [-1.5, 1.5] px: hit on one side, not on the other.
      const bool lo = hit(-1.5), hi = hit(1.5);
      if (lo == hi) continue;
      double x0 = -1.5, x1 = 1.5;
      for (int it = 0; it < 40; ++it) {
        const double xm = 0.5 * (x0 + x1);
        if (hit(xm) == lo) x0 = xm;
        else x1 = xm;
      }
      ++m.judged;
      m.worst = std::max(m.worst, std::abs(0.5 * (x0 + x1)));
    }
  }
  return m;
}

TEST(Silhouette, SphereInPerspectiveWithinAQuarterPixel) {
  const SpherePatch sphere(1.0);
  const ViewTransform v = viewFrom({2.2, -3.1, 1.4});
  PolylineSet lines;
  SilhouetteStats st;
  traceSilhouette(sphere, nullptr, v, SilhouetteOptions{}, lines, st);
  EXPECT_EQ(st.curves, 1u);  // one loop, across the seam
  ASSERT_GE(lines.points.size(), 20u);
  EXPECT_EQ(lines.points.front(), lines.points.back());
  const Measure m = measure(lines, v, 0.5, [](glm::dvec3 p) { return glm::dot(p, p) - 1.0; });
  EXPECT_GE(m.judged, m.chords - 2);
  EXPECT_GT(m.chords, 20);
  EXPECT_LT(m.worst, 0.25) << m.judged << " chords";
  std::printf("[ measured ] sphere: worst chord %.3f px over %d chords judged of %d\n", m.worst, m.judged, m.chords);
}

TEST(Silhouette, CylinderInPerspectiveWithinAQuarterPixel) {
  const Cylinder cyl(0.6, 1.5);
  const ViewTransform v = viewFrom({3.0, -2.0, 1.1});
  PolylineSet lines;
  SilhouetteStats st;
  traceSilhouette(cyl, nullptr, v, SilhouetteOptions{}, lines, st);
  EXPECT_EQ(st.curves, 2u);  // the two side lines
  const Measure m = measure(lines, v, 0.4, [](glm::dvec3 p) { return p.z * p.z > 1.5 * 1.5 ? 1.0 : p.x * p.x + p.y * p.y - 0.36; });
  EXPECT_GT(m.judged, 0);
  EXPECT_LT(m.worst, 0.25);
  std::printf("[ measured ] cylinder: worst chord %.3f px over %d chords judged of %d\n", m.worst, m.judged, m.chords);
}

TEST(Silhouette, TorusInPerspectiveWithinAQuarterPixel) {
  const TorusPatch torus(1.0, 0.35);
  const ViewTransform v = viewFrom({2.4, -2.9, 1.6});
  PolylineSet lines;
  SilhouetteStats st;
  traceSilhouette(torus, nullptr, v, SilhouetteOptions{}, lines, st);
  EXPECT_GE(st.curves, 2u);
  auto f = [](glm::dvec3 p) {
    const double q = std::sqrt(p.x * p.x + p.y * p.y) - 1.0;
    return q * q + p.z * p.z - 0.35 * 0.35;
  };
  const Measure m = measure(lines, v, 0.3, f);
  EXPECT_GT(m.judged, 40);
  EXPECT_LT(m.worst, 0.25) << m.judged << " of " << m.chords << " chords judged";
  std::printf("[ measured ] torus: worst chord %.3f px over %d chords judged of %d\n", m.worst, m.judged, m.chords);
  // Looser tolerance, fewer points, larger error: the option does what it says.
  PolylineSet coarse;
  SilhouetteOptions o;
  o.tolerancePx = 1.0;
  SilhouetteStats sc;
  traceSilhouette(torus, nullptr, v, o, coarse, sc);
  EXPECT_LT(coarse.points.size(), lines.points.size());
  EXPECT_LT(measure(coarse, v, 0.3, f).worst, 1.25);
}

// Looking down the pole: the sphere's silhouette is a circle of latitude crossing every seam
// column, and the torus's are two circles; each a closed loop.
TEST(Silhouette, SeamsAndPolesGiveClosedLoops) {
  const ViewTransform v = viewFrom({0.0, 0.0, 4.0});
  PolylineSet s, t;
  SilhouetteStats a, b;
  traceSilhouette(SpherePatch(1.0), nullptr, v, SilhouetteOptions{}, s, a);
  traceSilhouette(TorusPatch(1.0, 0.35), nullptr, v, SilhouetteOptions{}, t, b);
  EXPECT_EQ(a.curves, 1u);
  EXPECT_EQ(b.curves, 2u);
  for (const PolylineSet* p : {&s, &t})
    for (size_t i = 0; i < p->polylineCount(); ++i)
      EXPECT_EQ(p->points[p->starts[i]], p->points[p->starts[i + 1] - 1]);
  // On the sphere: every point where the cone from the eye touches it, z = 1 / 4.
  for (const glm::dvec3& p : s.points) EXPECT_NEAR(p.z, 0.25, 1e-9);
}

// Trimmed by the face: only where inside >= 0.5, ended at the border. The mask is read over the
// domain's unit square, as a CAD face's mask and fur read it (from a review: it was read at the
// raw (u, v), which a CAD face mask clamps to a corner of its square).
TEST(Silhouette, TrimmedToTheFace) {
  struct UpperHalf final : ScalarTexture {
    // v > 0.3 of the cylinder's [-1.5, 1.5]: t > 0.6
    double value(const glm::dvec2& st) const override { return st.y > 0.6 ? 1.0 : 0.0; }
    glm::dvec2 gradient(const glm::dvec2&) const override { return {0, 0}; }
    std::string describe() const override { return "v > 0.3"; }
  } inside;
  const Cylinder cyl(0.6, 1.5);
  const ViewTransform v = viewFrom({3.0, -2.0, 1.1});
  PolylineSet lines;
  SilhouetteStats st;
  traceSilhouette(cyl, &inside, v, SilhouetteOptions{}, lines, st);
  EXPECT_EQ(st.curves, 2u);
  double lo = INFINITY;
  for (const glm::dvec3& p : lines.points) lo = std::min(lo, p.z);
  EXPECT_NEAR(lo, 0.3, 1e-6);
}

TEST(Silhouette, NonFiniteSurfaceGivesDefinedCountedOutput) {
  const HalfBroken s;
  const ViewTransform v = viewFrom({2.2, -3.1, 1.4});
  PolylineSet lines;
  SilhouetteStats st;
  traceSilhouette(s, nullptr, v, SilhouetteOptions{}, lines, st);
  EXPECT_GT(st.nonFinite, 0u);
  for (const glm::dvec3& p : lines.points) EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
  // A plane has no silhouette, even edge-on.
  PolylineSet none;
  SilhouetteStats sn;
  traceSilhouette(PlanePatch(2, 2), nullptr, viewFrom({3.0, 0.0, 0.0}), SilhouetteOptions{}, none, sn);
  EXPECT_EQ(none.points.size(), 0u);
}

// From a review: SilhouetteOptions::maxPoints bounds a face, not each of its curves (an egg crate
// of 38 curves made 1,647 points at a bound of 64).
class EggCrate final : public Surface {
 public:
  ParameterDomain domain() const override { return {0.0, 1.0, 0.0, 1.0, false, false}; }
  SurfacePoint evaluate(double u, double v) const override {
    const double k = 2 * std::numbers::pi * 6, a = 0.05;
    return {{u - 0.5, v - 0.5, a * std::sin(k * u) * std::sin(k * v)},
            {1.0, 0.0, a * k * std::cos(k * u) * std::sin(k * v)},
            {0.0, 1.0, a * k * std::sin(k * u) * std::cos(k * v)}};
  }
  std::string describe() const override { return "egg crate"; }
};
TEST(Silhouette, MaxPointsBoundsAFace) {
  SilhouetteOptions o;
  o.maxPoints = 64;
  PolylineSet lines;
  SilhouetteStats st;
  traceSilhouette(EggCrate(), nullptr, viewFrom({2.5, -0.3, 0.35}), o, lines, st);
  EXPECT_LE(st.points, o.maxPoints + 2 * st.curves);
  EXPECT_EQ(st.cutShort, 1u);
}

// From a review: a plane through the eye at a slant has g = 0 but for rounding of either sign;
// it gave 70 curves of noise.
class ObliquePlane final : public Surface {
 public:
  glm::dvec3 e1 = glm::normalize(glm::dvec3(1.0, 0.3, 0.2)), e2 = glm::normalize(glm::dvec3(-0.2, 0.7, 0.9));
  ParameterDomain domain() const override { return {-1.0, 1.0, -1.0, 1.0, false, false}; }
  SurfacePoint evaluate(double u, double v) const override { return {u * e1 + v * e2, e1, e2}; }
  std::string describe() const override { return "oblique plane"; }
};
TEST(Silhouette, ObliquePlaneSeenEdgeOnHasNone) {
  const ObliquePlane pl;
  Camera c;
  c.eye = 3.1 * pl.e1 + 0.7 * pl.e2;  // in the plane
  c.target = glm::dvec3(0.0);
  c.up = glm::normalize(glm::cross(pl.e1, pl.e2));
  c.fovYDegrees = 35.0;
  c.nearPlane = 0.1;
  c.farPlane = 100;
  PolylineSet lines;
  SilhouetteStats st;
  traceSilhouette(pl, nullptr, ViewTransform::make(c, 800, 600), SilhouetteOptions{}, lines, st);
  EXPECT_EQ(lines.points.size(), 0u);
}

// A degenerate edge (a cone's apex, the corner of a CAD fillet blend): the normal's limit there
// depends on the direction, so g = N . V changes sign along the edge, and the trace can run
// along it, where every point is the apex. The true silhouette is the cone's two lines through
// the apex: every polyline drawn has length, no point repeats the one before it (a run of them
// drew a dot at each corner of product.step's tray), and each point is on one of the two lines.
class Cone final : public Surface {
 public:
  ParameterDomain domain() const override { return {0.0, 2 * std::numbers::pi, 0.0, 1.0, true, false}; }
  SurfacePoint evaluate(double u, double v) const override {
    return {{v * std::cos(u), v * std::sin(u), v}, {-v * std::sin(u), v * std::cos(u), 0.0}, {std::cos(u), std::sin(u), 1.0}};
  }
  std::string describe() const override { return "cone"; }
};
TEST(Silhouette, ADegenerateEdgeDrawsNoRunOfOnePoint) {
  const Cone cone;
  const glm::dvec3 eye(3.0, -2.0, 0.5);
  PolylineSet lines;
  SilhouetteStats st;
  traceSilhouette(cone, nullptr, viewFrom(eye), SilhouetteOptions{}, lines, st);
  ASSERT_GT(lines.polylineCount(), 0u);
  // The lines: the generators at u where the cone's normal (cos u, sin u, -1) is at right angles
  // to eye - P, i.e. eye . (cos u, sin u, -1) = 0.
  size_t repeats = 0, pointless = 0;
  double far = 0;
  for (size_t k = 0; k < lines.polylineCount(); ++k) {
    double length = 0;
    for (std::uint32_t i = lines.starts[k]; i < lines.starts[k + 1]; ++i) {
      const glm::dvec3 P = lines.points[i];
      if (i > lines.starts[k]) {
        const double step = glm::length(P - glm::dvec3(lines.points[i - 1]));
        repeats += step == 0.0;
        length += step;
      }
      // Distance from the nearer generator line through the apex.
      const double r = std::hypot(P.x, P.y);
      double best = r;  // (the apex itself)
      for (double sign : {-1.0, 1.0}) {
        // eye.x cos u + eye.y sin u = eye.z: u = atan2(eye.y, eye.x) +- acos(eye.z / |eye.xy|)
        const double u = std::atan2(eye.y, eye.x) + sign * std::acos(eye.z / std::hypot(eye.x, eye.y));
        const glm::dvec3 d = glm::normalize(glm::dvec3(std::cos(u), std::sin(u), 1.0));
        best = std::min(best, glm::length(P - glm::dot(P, d) * d));
      }
      far = std::max(far, best);
    }
    pointless += !(length > 0);
  }
  EXPECT_EQ(repeats, 0u);
  EXPECT_EQ(pointless, 0u);
  EXPECT_LT(far, 1e-3) << "a point off the cone's two silhouette lines";
}

}  // namespace
}  // namespace wf

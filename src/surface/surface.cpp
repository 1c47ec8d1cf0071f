// Surface::frame: the unit normal and tangents of a parametric surface, defined everywhere.
//
// The rule (docs/design.md, "One surface concept"; docs/surfaces.md):
//  1. (u, v) that is NaN or infinite is replaced by the domain's centre (per coordinate); finite
//     values outside the domain are clamped (wrapped where periodic) by the surface itself.
//  2. A point is regular when Su and Sv are finite and non-zero and the sine of the angle between
//     them exceeds kDegenerateEpsilon: |Su x Sv| > eps |Su| |Sv|. Then N = unit(Su x Sv), computed
//     from the unit derivatives so that it is the same for coordinates of 1e-6 and 1e6 (and far
//     beyond); Tu, Tv are Su, Sv projected off N and normalised.
//     A derivative counts as zero when |Su| du <= 1e-12 |Sv| dv (or the other way round): the
//     length a parameter step sweeps, compared with the other direction's, so it is scale-free.
//  3. At a degenerate point (a pole where Su = 0, the closed end of a loft, a cusp, a zero-area
//     cell) N is the LIMIT normal: the normal at a regular point stepped from (u, v) towards the
//     middle of the domain. The step is along v when Su vanishes (the row collapsed to a point:
//     the limit along the meridian is the one the neighbouring triangles see), along u when Sv
//     vanishes, and diagonally otherwise; its length starts at 1e-6 of the domain and grows by 4
//     up to 12 times (to about 1/4 of the domain). With two regular points at h and 2h the normal
//     is extrapolated, N = unit(2 N(h) - N(2h)), which removes the O(h) term (error O(h^2),
//     ~1e-12 on a sphere). A tangent whose derivative vanishes is taken from the same regular
//     point and projected off N.
//  4. If no regular point is found (a surface collapsed to a point or a curve), the frame is the
//     defined fallback: N = +z (or perpendicular to the one usable derivative), Tu and Tv completing
//     an orthonormal basis. Nothing is ever NaN: non-finite P, Su, Sv from evaluate are zeroed.
#include "surface/surface.h"

#include "core/numeric.h"

#include <algorithm>
#include <cmath>

namespace wf {

namespace {


// Length without overflow or underflow for any finite vector.
double safeLength(const glm::dvec3& v) {
  const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  if (!(m > 0) || !std::isfinite(m)) return 0.0;
  return m * glm::length(v / m);
}

// v / |v|, or zero when v is zero or not finite.
glm::dvec3 unitOrZero(const glm::dvec3& v) {
  const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  if (!(m > 0) || !std::isfinite(m)) return glm::dvec3(0.0);
  const glm::dvec3 w = v / m;
  return w / glm::length(w);
}

// Unit vector along t with its component along unit n removed; zero when t is (nearly) along n.
glm::dvec3 projectOff(const glm::dvec3& t, const glm::dvec3& n) {
  const glm::dvec3 ut = unitOrZero(t);
  const glm::dvec3 p = ut - n * glm::dot(n, ut);
  return glm::length(p) > 1e-8 ? glm::normalize(p) : glm::dvec3(0.0);
}

// Any unit vector perpendicular to unit n.
glm::dvec3 anyPerpendicular(const glm::dvec3& n) {
  const glm::dvec3 a = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  return glm::normalize(a - n * glm::dot(n, a));
}

struct Classified {
  glm::dvec3 uSu{0.0}, uSv{0.0}, N{0.0};
  bool zeroSu = true, zeroSv = true, regular = false;
  double area = 0.0;
};

Classified classify(const SurfacePoint& p, const ParameterDomain& d) {
  Classified c;
  const double lu = safeLength(p.Su) * std::abs(d.du()), lv = safeLength(p.Sv) * std::abs(d.dv());
  c.uSu = unitOrZero(p.Su);
  c.uSv = unitOrZero(p.Sv);
  c.zeroSu = !(lu > 0) || lu <= 1e-12 * lv;
  c.zeroSv = !(lv > 0) || lv <= 1e-12 * lu;
  if (c.zeroSu || c.zeroSv) return c;
  const glm::dvec3 cr = glm::cross(c.uSu, c.uSv);
  const double s = glm::length(cr);
  if (!(s > Surface::kDegenerateEpsilon)) return c;
  c.regular = true;
  c.N = cr / s;
  c.area = safeLength(p.Su) * safeLength(p.Sv) * s;
  if (!std::isfinite(c.area)) c.area = 0.0;
  return c;
}

double centreIfNotFinite(double x, double lo, double hi) { return std::isfinite(x) ? x : 0.5 * (lo + hi); }

}  // namespace

SurfaceFrame Surface::frame(double u, double v) const {
  SurfaceFrame f = frameAlongSuSv(u, v);
  if (normalSign() < 0) f.N = -f.N;  // Tu, Tv stay: they are orthogonal to either
  return f;
}

SurfaceFrame Surface::frameAlongSuSv(double u, double v) const {
  const ParameterDomain d = domain();
  u = centreIfNotFinite(u, d.u0, d.u1);
  v = centreIfNotFinite(v, d.v0, d.v1);
  if (!d.periodicU) u = std::clamp(u, std::min(d.u0, d.u1), std::max(d.u0, d.u1));
  if (!d.periodicV) v = std::clamp(v, std::min(d.v0, d.v1), std::max(d.v0, d.v1));

  SurfacePoint p = evaluate(u, v);
  SurfaceFrame f;
  f.P = finiteOrZero(p.P);
  f.Su = p.Su = finiteOrZero(p.Su);
  f.Sv = p.Sv = finiteOrZero(p.Sv);
  const Classified c = classify(p, d);
  if (c.regular) {
    f.N = c.N;
    f.Tu = projectOff(c.uSu, f.N);
    f.Tv = projectOff(c.uSv, f.N);
    f.areaElement = c.area;
    if (glm::length(f.Tu) > 0 && glm::length(f.Tv) > 0) return f;
    // Unreachable for a regular point up to rounding; fall through to a defined frame.
  }
  f.degenerate = true;
  f.areaElement = 0.0;

  // Step towards the middle: along v when the u-row collapsed, along u when the v-column did.
  const double uc = 0.5 * (d.u0 + d.u1), vc = 0.5 * (d.v0 + d.v1);
  double su = (uc - u) >= 0 ? 1.0 : -1.0, sv = (vc - v) >= 0 ? 1.0 : -1.0;
  if (c.zeroSu && !c.zeroSv) su = 0.0;
  else if (c.zeroSv && !c.zeroSu) sv = 0.0;
  // A periodic direction has no middle to step towards; a step along it only rotates the frame.
  if (d.periodicU && sv != 0.0) su = 0.0;
  if (d.periodicV && su != 0.0) sv = 0.0;
  if (su == 0.0 && sv == 0.0) su = sv = 1.0;

  auto at = [&](double h) {
    SurfacePoint q = evaluate(u + su * h * d.du(), v + sv * h * d.dv());
    q.Su = finiteOrZero(q.Su);
    q.Sv = finiteOrZero(q.Sv);
    return classify(q, d);
  };
  double h = 1e-6;
  for (int k = 0; k < 12; ++k, h *= 4.0) {
    const Classified a = at(h);
    if (!a.regular) continue;
    glm::dvec3 N = a.N;
    const Classified b = at(2.0 * h);
    if (b.regular) {
      const glm::dvec3 e = unitOrZero(2.0 * a.N - b.N);
      if (glm::dot(e, a.N) > 0.99) N = e;  // a smooth limit; otherwise keep the nearer normal
    }
    f.N = N;
    f.Tu = projectOff(c.zeroSu ? a.uSu : c.uSu, N);
    if (glm::length(f.Tu) == 0) f.Tu = projectOff(a.uSu, N);
    f.Tv = projectOff(c.zeroSv ? a.uSv : c.uSv, N);
    if (glm::length(f.Tv) == 0) f.Tv = projectOff(a.uSv, N);
    if (glm::length(f.Tu) == 0) f.Tu = anyPerpendicular(N);
    if (glm::length(f.Tv) == 0) f.Tv = glm::cross(N, f.Tu);
    return f;
  }
  // Nothing regular nearby: a defined orthonormal frame, keeping a usable derivative direction.
  const glm::dvec3 t = !c.zeroSu ? c.uSu : (!c.zeroSv ? c.uSv : glm::dvec3(0.0));
  if (glm::length(t) > 0) {
    f.N = std::abs(t.z) < 0.9 ? glm::normalize(glm::dvec3(0, 0, 1) - t * t.z) : anyPerpendicular(t);
  } else {
    f.N = glm::dvec3(0, 0, 1);
  }
  f.Tu = !c.zeroSu ? projectOff(c.uSu, f.N) : glm::dvec3(0.0);
  if (glm::length(f.Tu) == 0) f.Tu = anyPerpendicular(f.N);
  f.Tv = !c.zeroSv ? projectOff(c.uSv, f.N) : glm::dvec3(0.0);
  if (glm::length(f.Tv) == 0) f.Tv = glm::cross(f.N, f.Tu);
  return f;
}

}  // namespace wf

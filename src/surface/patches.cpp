// Analytic patches: S(u,v) with exact Su, Sv. See patches.h for each parameterisation and
// docs/surfaces.md for the overview.
#include "surface/patches.h"

#include "core/numeric.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>

namespace wf {

namespace {

bool positive(double x) { return x > 0 && std::isfinite(x); }

/// A parameter mapped into [lo, hi]: NaN / Inf to the centre, wrapped where periodic (hi itself
/// wraps to lo, so a periodic seam evaluates bit-identically on both sides), clamped otherwise.
double toDomain(double x, double lo, double hi, bool periodic) {
  if (!std::isfinite(x)) return 0.5 * (lo + hi);
  if (periodic) {
    double t = (x - lo) / (hi - lo);
    t -= std::floor(t);
    if (!(t < 1.0)) t = 0.0;
    return lo + t * (hi - lo);
  }
  return std::clamp(x, lo, hi);
}

// cos and sin of 2 pi u for u in [0,1), exact at the quarter turns (so the seam u = 0 and the
// axes are hit exactly).
void cosSin2Pi(double u, double& c, double& s) {
  if (u == 0.0) { c = 1.0; s = 0.0; return; }
  if (u == 0.25) { c = 0.0; s = 1.0; return; }
  if (u == 0.5) { c = -1.0; s = 0.0; return; }
  if (u == 0.75) { c = 0.0; s = -1.0; return; }
  c = std::cos(kTwoPi * u);
  s = std::sin(kTwoPi * u);
}

std::string fmt(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

// ---------------------------------------------------------------------------------------------
// B-spline basis with first and second derivatives (Piegl & Tiller, The NURBS Book, A2.3), for
// a uniform clamped knot vector, or the uniform periodic cubic.
struct Basis {
  int first = 0;    // index of the first control point (mod count when periodic)
  int size = 0;     // number of non-zero functions (degree + 1)
  double N[4]{}, d1[4]{}, d2[4]{};
};

class BSplineBasis {
 public:
  BSplineBasis(int count, bool periodic) : n_(count), periodic_(periodic) {
    p_ = periodic ? 3 : std::clamp(count - 1, 1, 3);
  }
  int count() const { return n_; }
  bool periodic() const { return periodic_; }

  // Basis at x in [0,1] (derivatives with respect to x).
  Basis at(double x) const {
    Basis b;
    b.size = p_ + 1;
    if (periodic_) {
      const double s = x * n_;
      int seg = std::clamp(int(std::floor(s)), 0, n_ - 1);
      const double t = s - seg, m = 1.0 - t, k = double(n_);
      b.first = seg - 1;  // control points seg-1 .. seg+2
      b.N[0] = m * m * m / 6.0;
      b.N[1] = (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0;
      b.N[2] = (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0;
      b.N[3] = t * t * t / 6.0;
      b.d1[0] = -0.5 * m * m * k;
      b.d1[1] = (1.5 * t * t - 2.0 * t) * k;
      b.d1[2] = (-1.5 * t * t + t + 0.5) * k;
      b.d1[3] = 0.5 * t * t * k;
      b.d2[0] = m * k * k;
      b.d2[1] = (3.0 * t - 2.0) * k * k;
      b.d2[2] = (-3.0 * t + 1.0) * k * k;
      b.d2[3] = t * k * k;
      return b;
    }
    // Knots U[k] = 0 (k <= p), k - p (p < k < n), n - p (k >= n); s = x (n - p).
    const int p = p_, n = n_;
    const double span = double(n - p);
    const double s = std::clamp(x, 0.0, 1.0) * span;
    const int i = std::min(p + int(std::floor(s)), n - 1);
    auto U = [&](int k) { return double(std::clamp(k - p, 0, n - p)); };
    double ndu[4][4], left[4], right[4];
    ndu[0][0] = 1.0;
    for (int j = 1; j <= p; ++j) {
      left[j] = s - U(i + 1 - j);
      right[j] = U(i + j) - s;
      double saved = 0.0;
      for (int r = 0; r < j; ++r) {
        ndu[j][r] = right[r + 1] + left[j - r];
        const double temp = ndu[r][j - 1] / ndu[j][r];
        ndu[r][j] = saved + right[r + 1] * temp;
        saved = left[j - r] * temp;
      }
      ndu[j][j] = saved;
    }
    double ders[3][4] = {};
    for (int j = 0; j <= p; ++j) ders[0][j] = ndu[j][p];
    const int nd = std::min(2, p);
    double a[2][4];
    for (int r = 0; r <= p; ++r) {
      int s1 = 0, s2 = 1;
      a[0][0] = 1.0;
      for (int k = 1; k <= nd; ++k) {
        double d = 0.0;
        const int rk = r - k, pk = p - k;
        if (r >= k) {
          a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
          d = a[s2][0] * ndu[rk][pk];
        }
        const int j1 = rk >= -1 ? 1 : -rk;
        const int j2 = (r - 1 <= pk) ? k - 1 : p - r;
        for (int j = j1; j <= j2; ++j) {
          a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
          d += a[s2][j] * ndu[rk + j][pk];
        }
        if (r <= pk) {
          a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
          d += a[s2][k] * ndu[r][pk];
        }
        ders[k][r] = d;
        std::swap(s1, s2);
      }
    }
    double f = p;
    for (int k = 1; k <= nd; ++k) {
      for (int j = 0; j <= p; ++j) ders[k][j] *= f;
      f *= (p - k);
    }
    b.first = i - p;
    for (int j = 0; j <= p; ++j) {
      b.N[j] = ders[0][j];
      b.d1[j] = ders[1][j] * span;
      b.d2[j] = ders[2][j] * span * span;
    }
    return b;
  }
  int index(const Basis& b, int k) const {
    const int i = b.first + k;
    return periodic_ ? ((i % n_) + n_) % n_ : i;
  }

 private:
  int n_, p_;
  bool periodic_;
};

SurfacePoint evaluateNet(const glm::dvec3* net, const BSplineBasis& bu, const BSplineBasis& bv, double u,
                         double v) {
  const Basis a = bu.at(u), b = bv.at(v);
  SurfacePoint sp;
  for (int l = 0; l < b.size; ++l) {
    const int j = bv.index(b, l);
    glm::dvec3 row(0.0), rowU(0.0);
    for (int k = 0; k < a.size; ++k) {
      const glm::dvec3& P = net[size_t(j) * size_t(bu.count()) + size_t(bu.index(a, k))];
      row += a.N[k] * P;
      rowU += a.d1[k] * P;
    }
    sp.P += b.N[l] * row;
    sp.Su += b.N[l] * rowU;
    sp.Sv += b.d1[l] * row;
  }
  return sp;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Sphere

std::string SpherePatch::problem(double radius) {
  return positive(radius) ? std::string() : "sphere radius must be positive and finite";
}

SurfacePoint SpherePatch::evaluate(double u, double v) const {
  u = toDomain(u, 0.0, 1.0, true);
  v = toDomain(v, 0.0, 1.0, false);
  double ca, sa;
  cosSin2Pi(u, ca, sa);
  // Exactly on the axis at the poles (sin(pi) is 1.2e-16, not 0): Su vanishes there exactly and
  // the pole's vertices coincide.
  const double th = kPi * v;
  const double st = (v <= 0.0 || v >= 1.0) ? 0.0 : (v == 0.5 ? 1.0 : std::sin(th));
  const double ct = v <= 0.0 ? 1.0 : (v >= 1.0 ? -1.0 : (v == 0.5 ? 0.0 : std::cos(th)));
  const double r = radius_;
  SurfacePoint sp;
  sp.P = r * glm::dvec3(st * ca, st * sa, -ct);
  sp.Su = (kTwoPi * r * st) * glm::dvec3(-sa, ca, 0.0);
  sp.Sv = (kPi * r) * glm::dvec3(ct * ca, ct * sa, st);
  return sp;
}

std::string SpherePatch::describe() const { return "sphere r=" + fmt(radius_); }

// ---------------------------------------------------------------------------------------------
// Torus

std::string TorusPatch::problem(double major, double minor) {
  return positive(major) && positive(minor) ? std::string() : "torus major and minor radii must be positive and finite";
}

SurfacePoint TorusPatch::evaluate(double u, double v) const {
  u = toDomain(u, 0.0, 1.0, true);
  v = toDomain(v, 0.0, 1.0, true);
  double ca, sa, cb, sb;
  cosSin2Pi(u, ca, sa);
  cosSin2Pi(v, cb, sb);
  const double ring = major_ + minor_ * cb;
  SurfacePoint sp;
  sp.P = glm::dvec3(ring * ca, ring * sa, minor_ * sb);
  sp.Su = (kTwoPi * ring) * glm::dvec3(-sa, ca, 0.0);
  sp.Sv = (kTwoPi * minor_) * glm::dvec3(-sb * ca, -sb * sa, cb);
  return sp;
}

std::string TorusPatch::describe() const { return "torus R=" + fmt(major_) + " r=" + fmt(minor_); }

// ---------------------------------------------------------------------------------------------
// Plane

std::string PlanePatch::problem(double sizeX, double sizeY) {
  return positive(sizeX) && positive(sizeY) ? std::string() : "plane size must be positive and finite";
}

SurfacePoint PlanePatch::evaluate(double u, double v) const {
  u = toDomain(u, 0.0, 1.0, false);
  v = toDomain(v, 0.0, 1.0, false);
  return {glm::dvec3((u - 0.5) * sizeX_, (v - 0.5) * sizeY_, 0.0), glm::dvec3(sizeX_, 0.0, 0.0),
          glm::dvec3(0.0, sizeY_, 0.0)};
}

std::string PlanePatch::describe() const { return "plane " + fmt(sizeX_) + " x " + fmt(sizeY_); }

// ---------------------------------------------------------------------------------------------
// Revolution

std::string RevolutionPatch::problem(const std::vector<glm::dvec2>& points, const std::vector<bool>& corners) {
  if (points.size() < 2) return "profile needs at least two [radius, height] points";
  if (!corners.empty() && corners.size() != points.size()) return "profile corner flags must be one per point";
  double length = 0.0, maxRadius = 0.0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (!finite(points[i]) || points[i].x < 0) return "profile points must be finite with radius >= 0";
    if (i > 0) length += glm::length(points[i] - points[i - 1]);
    maxRadius = std::max(maxRadius, points[i].x);
  }
  if (!(length > 0) || !std::isfinite(length) || !(maxRadius > 0))
    return "profile must have length and leave the axis somewhere";
  return {};
}

namespace {
// Cubic Bezier value and derivative in t.
glm::dvec2 bezier(const std::array<glm::dvec2, 4>& b, double t, glm::dvec2* d) {
  const double m = 1.0 - t;
  if (d) *d = 3.0 * (m * m * (b[1] - b[0]) + 2.0 * m * t * (b[2] - b[1]) + t * t * (b[3] - b[2]));
  return m * m * m * b[0] + 3.0 * m * m * t * b[1] + 3.0 * m * t * t * b[2] + t * t * t * b[3];
}
}  // namespace

RevolutionPatch::RevolutionPatch(std::vector<glm::dvec2> points, std::vector<bool> corners,
                                 ProfileInterpolation interpolation, double cornerAngleDegrees)
    : input_(std::move(points)), inputCorners_(std::move(corners)), interpolation_(interpolation) {
  if (!problem().empty()) {
    // Defined, if meaningless: a unit cylinder (problem() says what is wrong).
    points_ = {{1.0, 0.0}, {1.0, 1.0}};
    corners_ = {false, false};
  } else {
    // Merge repeated points (relative to the profile's size); a repeat makes a corner.
    double size = 0.0;
    for (const glm::dvec2& p : input_) size = std::max({size, std::abs(p.x), std::abs(p.y)});
    for (size_t i = 0; i < input_.size(); ++i) {
      const bool flagged = !inputCorners_.empty() && inputCorners_[i];
      if (!points_.empty() && glm::length(input_[i] - points_.back()) <= 1e-12 * size) {
        corners_.back() = true;
        continue;
      }
      points_.push_back(input_[i]);
      corners_.push_back(flagged);
    }
  }
  const size_t n = points_.size();
  corners_.front() = corners_.back() = false;  // an end has no sides to disagree
  if (cornerAngleDegrees < 180.0)
    for (size_t i = 1; i + 1 < n; ++i) {
      const glm::dvec2 a = glm::normalize(points_[i] - points_[i - 1]), b = glm::normalize(points_[i + 1] - points_[i]);
      const double angle = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)) * 180.0 / kPi;
      if (angle > cornerAngleDegrees) corners_[i] = true;
    }

  // Centripetal knot intervals and tangents (per knot unit) at the interior smooth points.
  std::vector<double> d(n - 1);
  for (size_t i = 0; i + 1 < n; ++i) d[i] = std::sqrt(glm::length(points_[i + 1] - points_[i]));
  const bool linear = interpolation_ == ProfileInterpolation::Linear;
  std::vector<glm::dvec2> m(n, glm::dvec2(0.0));
  std::vector<bool> smooth(n, false);
  for (size_t i = 1; i + 1 < n; ++i) {
    if (linear || corners_[i]) continue;
    smooth[i] = true;
    const glm::dvec2 &p0 = points_[i - 1], &p1 = points_[i], &p2 = points_[i + 1];
    m[i] = (p1 - p0) / d[i - 1] - (p2 - p0) / (d[i - 1] + d[i]) + (p2 - p1) / d[i];
  }
  // Per segment: one-sided tangents at ends and corners (parabola through the other side's
  // tangent, or the chord when both sides are one-sided); radial at a pole end.
  bezier_.resize(n - 1);
  for (size_t i = 0; i + 1 < n; ++i) {
    const glm::dvec2 chord = (points_[i + 1] - points_[i]) / d[i];
    glm::dvec2 m0 = m[i], m1 = m[i + 1];
    if (linear) {
      m0 = m1 = chord;
    } else {
      if (!smooth[i]) m0 = smooth[i + 1] ? 2.0 * chord - m1 : chord;
      if (!smooth[i + 1]) m1 = smooth[i] ? 2.0 * chord - m0 : chord;
      // A pole end (on the axis, not flagged a corner) leaves the axis radially.
      auto radial = [&](size_t k, glm::dvec2& t) {
        const bool flagged = !inputCorners_.empty() && (k == 0 ? inputCorners_.front() : inputCorners_.back());
        if (points_[k].x == 0.0 && !flagged && chord.x != 0.0)
          t = glm::dvec2(glm::length(chord) * (k == 0 ? 1.0 : -1.0), 0.0);
      };
      if (i == 0) radial(0, m0);
      if (i + 2 == n) radial(n - 1, m1);
    }
    std::array<glm::dvec2, 4> b{points_[i], points_[i] + m0 * (d[i] / 3.0), points_[i + 1] - m1 * (d[i] / 3.0),
                                points_[i + 1]};
    b[1].x = std::max(b[1].x, 0.0);  // convex hull: the radius stays >= 0
    b[2].x = std::max(b[2].x, 0.0);
    bezier_[i] = b;
  }

  // Arc-length tables: 16 intervals per segment, each integrated with 4-point Gauss-Legendre.
  constexpr int kNodes = 16;
  static const double gx[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
  static const double gw[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
  double s = 0.0;
  for (size_t seg = 0; seg < bezier_.size(); ++seg) {
    for (int k = 0; k < kNodes; ++k) {
      const double t0 = double(k) / kNodes, t1 = double(k + 1) / kNodes;
      double len = 0.0;
      for (int q = 0; q < 4; ++q) {
        glm::dvec2 dd;
        bezier(bezier_[seg], 0.5 * (t0 + t1) + 0.5 * (t1 - t0) * gx[q], &dd);
        len += 0.5 * (t1 - t0) * gw[q] * glm::length(dd);
      }
      if (!(len > 0)) continue;  // a degenerate piece: nothing to traverse
      glm::dvec2 d0, d1;
      bezier(bezier_[seg], t0, &d0);
      bezier(bezier_[seg], t1, &d1);
      const double secant = (t1 - t0) / len;
      // Slopes dt/ds, limited to 3 x the secant (Fritsch-Carlson) so that t(s) is monotone.
      auto slope = [&](const glm::dvec2& dd) {
        const double l = glm::length(dd);
        return l > 0 ? std::min(1.0 / l, 3.0 * secant) : 3.0 * secant;
      };
      table_.push_back({s, s + len, t0, t1, slope(d0), slope(d1), int(seg)});
      s += len;
    }
  }
  length_ = s;
}

glm::dvec2 RevolutionPatch::profile(double v, glm::dvec2* derivative) const {
  v = toDomain(v, 0.0, 1.0, false);
  if (table_.empty()) {
    if (derivative) *derivative = glm::dvec2(0.0);
    return points_.front();
  }
  const double s = v * length_;
  auto it = std::upper_bound(table_.begin(), table_.end(), s, [](double x, const Interval& I) { return x < I.s0; });
  const Interval& I = it == table_.begin() ? table_.front() : *(it - 1);
  const double h = I.s1 - I.s0;
  const double x = v >= 1.0 && &I == &table_.back() ? 1.0 : std::clamp((s - I.s0) / h, 0.0, 1.0);
  // Cubic Hermite t(s) on the interval.
  const double x2 = x * x, x3 = x2 * x;
  const double h00 = 2 * x3 - 3 * x2 + 1, h10 = x3 - 2 * x2 + x, h01 = -2 * x3 + 3 * x2, h11 = x3 - x2;
  const double e00 = 6 * x2 - 6 * x, e10 = 3 * x2 - 4 * x + 1, e01 = -6 * x2 + 6 * x, e11 = 3 * x2 - 2 * x;
  const double t = h00 * I.t0 + h10 * h * I.g0 + h01 * I.t1 + h11 * h * I.g1;
  const double dtds = (e00 * I.t0 + e01 * I.t1) / h + e10 * I.g0 + e11 * I.g1;
  glm::dvec2 db;
  const glm::dvec2 p = bezier(bezier_[size_t(I.segment)], t, &db);
  if (derivative) *derivative = db * (dtds * length_);
  return p;
}

std::vector<double> RevolutionPatch::creasesV() const {
  std::vector<double> out;
  if (!(length_ > 0)) return out;
  // Corner k (an interior point) is where segment k starts: its first arc-length interval.
  for (size_t i = 1; i < table_.size(); ++i) {
    const int k = table_[i].segment;
    if (k != table_[i - 1].segment && size_t(k) < corners_.size() && corners_[size_t(k)]) {
      const double v = table_[i].s0 / length_;
      if (v > 0.0 && v < 1.0) out.push_back(v);
    }
  }
  return out;
}

SurfacePoint RevolutionPatch::evaluate(double u, double v) const {
  u = toDomain(u, 0.0, 1.0, true);
  glm::dvec2 d;
  const glm::dvec2 q = profile(v, &d);
  double ca, sa;
  cosSin2Pi(u, ca, sa);
  SurfacePoint sp;
  sp.P = glm::dvec3(q.x * ca, q.x * sa, q.y);
  sp.Su = (kTwoPi * q.x) * glm::dvec3(-sa, ca, 0.0);
  sp.Sv = glm::dvec3(d.x * ca, d.x * sa, d.y);
  return sp;
}

std::string RevolutionPatch::describe() const {
  return std::string("revolution (") + (interpolation_ == ProfileInterpolation::Linear ? "linear" : "smooth") +
         " profile, " + std::to_string(points_.size()) + " points, length " + fmt(length_) + ")";
}

// ---------------------------------------------------------------------------------------------
// Loft

namespace {

struct SpineFrame {
  glm::dvec3 C{0.0}, dC{0.0}, n1{1, 0, 0}, n2{0, 1, 0}, dn1{0.0}, dn2{0.0};
  double a = 0, b = 0, da = 0, db = 0;
  bool ok = false;
};

SpineFrame spineFrame(const std::vector<LoftSection>& sections, const BSplineBasis& basis, const glm::dvec3& up,
                      double v) {
  const Basis B = basis.at(v);
  SpineFrame f;
  glm::dvec3 d2C(0.0);
  for (int k = 0; k < B.size; ++k) {
    const LoftSection& s = sections[size_t(basis.index(B, k))];
    f.C += B.N[k] * s.centre;
    f.dC += B.d1[k] * s.centre;
    d2C += B.d2[k] * s.centre;
    f.a += B.N[k] * s.a;
    f.da += B.d1[k] * s.a;
    f.b += B.N[k] * s.b;
    f.db += B.d1[k] * s.b;
  }
  const double speed = glm::length(f.dC);
  if (!(speed > 0) || !std::isfinite(speed)) return f;
  const glm::dvec3 t = f.dC / speed;
  const glm::dvec3 dt = (d2C - t * glm::dot(t, d2C)) / speed;  // derivative of a normalisation
  const glm::dvec3 w = up - t * glm::dot(up, t);
  const double wl = glm::length(w);
  if (!(wl > 1e-12)) return f;
  const glm::dvec3 dw = -glm::dot(up, dt) * t - glm::dot(up, t) * dt;
  f.n1 = w / wl;
  f.dn1 = (dw - f.n1 * glm::dot(f.n1, dw)) / wl;
  f.n2 = glm::cross(t, f.n1);
  f.dn2 = glm::cross(dt, f.n1) + glm::cross(t, f.dn1);
  f.ok = true;
  return f;
}

// Largest |t . up| along the spine (64 + 1 samples), 1 where the tangent is undefined.
double worstAlignment(const std::vector<LoftSection>& sections, const glm::dvec3& up) {
  const BSplineBasis basis(int(sections.size()), false);
  double worst = 0.0;
  for (int k = 0; k <= 64; ++k) {
    const Basis B = basis.at(k / 64.0);
    glm::dvec3 dC(0.0);
    for (int j = 0; j < B.size; ++j) dC += B.d1[j] * sections[size_t(basis.index(B, j))].centre;
    const double l = glm::length(dC);
    worst = std::max(worst, l > 0 && std::isfinite(l) ? std::abs(glm::dot(dC / l, up)) : 2.0);
  }
  return worst;  // 2: the spine's tangent vanishes somewhere
}

glm::dvec3 chooseUp(const std::vector<LoftSection>& sections, const glm::dvec3& requested) {
  if (glm::length(requested) > 0 && finite(requested)) return glm::normalize(requested);
  glm::dvec3 best(0, 0, 1);
  double bestScore = 2.0;
  for (const glm::dvec3& axis : {glm::dvec3(0, 0, 1), glm::dvec3(0, 1, 0), glm::dvec3(1, 0, 0)}) {
    const double s = worstAlignment(sections, axis);
    if (s < bestScore - 1e-9) bestScore = s, best = axis;
    if (s < 0.9) break;  // z (or y) is good enough: prefer it
  }
  return best;
}

// Periodic uniform Catmull-Rom through points q (u in [0,1), point k at k / count): value and d/du.
template <class Get>
glm::dvec2 catmullRom(size_t count, double u, Get q, glm::dvec2* du) {
  const double s = u * double(count);
  const long seg = std::clamp(long(std::floor(s)), 0L, long(count) - 1);
  const double t = s - double(seg);
  auto P = [&](long k) { return q(size_t(((k % long(count)) + long(count)) % long(count))); };
  const glm::dvec2 p0 = P(seg - 1), p1 = P(seg), p2 = P(seg + 1), p3 = P(seg + 2);
  const glm::dvec2 c1 = -p0 + p2, c2 = 2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3, c3 = -p0 + 3.0 * p1 - 3.0 * p2 + p3;
  if (du) *du = 0.5 * (c1 + 2.0 * t * c2 + 3.0 * t * t * c3) * double(count);
  return 0.5 * (2.0 * p1 + t * c1 + t * t * c2 + t * t * t * c3);
}

}  // namespace

LoftPatch::LoftPatch(std::vector<LoftSection> sections, glm::dvec3 up)
    : sections_(std::move(sections)), requestedUp_(up) {
  if (sections_.empty()) sections_.push_back({});
  if (sections_.size() == 1) sections_.push_back({sections_[0].centre + glm::dvec3(0, 0, 1), 1, 1, {}});
  profileCount_ = sections_.front().profile.size();
  for (const LoftSection& s : sections_)
    if (s.profile.size() != profileCount_ || (profileCount_ > 0 && profileCount_ < 3)) profileCount_ = 0;
  up_ = chooseUp(sections_, requestedUp_);
}

std::string LoftPatch::problem(const std::vector<LoftSection>& sections, glm::dvec3 up) {
  if (sections.size() < 2) return "loft needs at least two cross-sections";
  const size_t count = sections.front().profile.size();
  for (const LoftSection& s : sections) {
    if (!finite(s.centre)) return "loft section centres must be finite";
    if (!finite(s.a) || !finite(s.b) || s.a < 0 || s.b < 0) return "loft section radii must be finite and >= 0";
    if (s.profile.size() != count) return "loft section profiles must all have the same number of points";
    for (const glm::dvec2& p : s.profile)
      if (!finite(p)) return "loft section profile points must be finite";
  }
  if (count > 0 && count < 3) return "loft section profiles need at least three points";
  bool anyRadius = false;
  for (const LoftSection& s : sections) anyRadius = anyRadius || s.a > 0 || s.b > 0;
  if (!anyRadius) return "every loft section has radius 0: the loft would be a curve, not a surface";
  if (!finite(up)) return "loft up vector must be finite";
  // cos 8 degrees: closer to parallel than that and the section frame turns fast or flips.
  const double worst = worstAlignment(sections, chooseUp(sections, up));
  if (worst >= 2.0) return "loft spine has a zero-length tangent (repeated centres?)";
  if (worst > 0.99) return "loft spine runs (nearly) parallel to the up vector; choose another up";
  return {};
}

glm::dvec3 LoftPatch::spine(double v) const {
  return spineFrame(sections_, BSplineBasis(int(sections_.size()), false), up_, toDomain(v, 0.0, 1.0, false)).C;
}

SurfacePoint LoftPatch::evaluate(double u, double v) const {
  u = toDomain(u, 0.0, 1.0, true);
  v = toDomain(v, 0.0, 1.0, false);
  const BSplineBasis basis(int(sections_.size()), false);
  const SpineFrame f = spineFrame(sections_, basis, up_, v);
  // Section point (x, y) in the (n1, n2) plane and its derivatives.
  double x, y, xu, yu, xv, yv;
  if (profileCount_ == 0) {
    double c, s;
    cosSin2Pi(u, c, s);
    x = f.a * c, y = f.b * s;
    xu = -kTwoPi * f.a * s, yu = kTwoPi * f.b * c;
    xv = f.da * c, yv = f.db * s;
  } else {
    const Basis B = basis.at(v);
    auto blended = [&](size_t k) {
      glm::dvec2 q(0.0);
      for (int j = 0; j < B.size; ++j) q += B.N[j] * sections_[size_t(basis.index(B, j))].profile[k];
      return q;
    };
    auto blendedDv = [&](size_t k) {
      glm::dvec2 q(0.0);
      for (int j = 0; j < B.size; ++j) q += B.d1[j] * sections_[size_t(basis.index(B, j))].profile[k];
      return q;
    };
    glm::dvec2 qu;
    const glm::dvec2 q = catmullRom(profileCount_, u, blended, &qu);
    const glm::dvec2 qv = catmullRom(profileCount_, u, blendedDv, nullptr);
    x = f.a * q.x, y = f.b * q.y;
    xu = f.a * qu.x, yu = f.b * qu.y;
    xv = f.da * q.x + f.a * qv.x, yv = f.db * q.y + f.b * qv.y;
  }
  SurfacePoint sp;
  sp.P = f.C + x * f.n1 + y * f.n2;
  sp.Su = xu * f.n1 + yu * f.n2;
  sp.Sv = f.dC + xv * f.n1 + x * f.dn1 + yv * f.n2 + y * f.dn2;
  return sp;
}

std::string LoftPatch::describe() const {
  return "loft (" + std::to_string(sections_.size()) + " sections, " +
         (profileCount_ ? std::to_string(profileCount_) + "-point profiles" : std::string("ellipses")) + ")";
}

// ---------------------------------------------------------------------------------------------
// Bezier and B-spline patches

std::string BezierPatch::problem(const std::array<glm::dvec3, 16>& controlPoints) {
  for (const glm::dvec3& p : controlPoints)
    if (!finite(p)) return "Bezier control points must be finite";
  return {};
}

SurfacePoint BezierPatch::evaluate(double u, double v) const {
  // A clamped cubic B-spline over 4 control points is the Bezier curve (knots 0000 1111).
  static const BSplineBasis bernstein(4, false);
  return evaluateNet(points_.data(), bernstein, bernstein, toDomain(u, 0.0, 1.0, false), toDomain(v, 0.0, 1.0, false));
}

std::string BezierPatch::describe() const { return "bicubic Bezier patch"; }

BSplinePatch::BSplinePatch(std::vector<glm::dvec3> net, int countU, int countV, bool periodicU, bool periodicV)
    : net_(std::move(net)), countU_(countU), countV_(countV), periodicU_(periodicU), periodicV_(periodicV) {
  if (!problem().empty()) {  // defined, if meaningless: a flat 2 x 2 net
    net_ = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    countU_ = countV_ = 2;
    periodicU_ = periodicV_ = false;
  }
}

std::string BSplinePatch::problem(const std::vector<glm::dvec3>& net, int countU, int countV, bool periodicU,
                                  bool periodicV) {
  if (countU < (periodicU ? 3 : 2) || countV < (periodicV ? 3 : 2))
    return "B-spline net needs at least 2 control points per clamped direction and 3 per periodic one";
  if (net.size() != size_t(countU) * size_t(countV)) return "B-spline net must have countU x countV points";
  for (const glm::dvec3& p : net)
    if (!finite(p)) return "B-spline control points must be finite";
  return {};
}

SurfacePoint BSplinePatch::evaluate(double u, double v) const {
  const BSplineBasis bu(countU_, periodicU_), bv(countV_, periodicV_);
  return evaluateNet(net_.data(), bu, bv, toDomain(u, 0.0, 1.0, periodicU_), toDomain(v, 0.0, 1.0, periodicV_));
}

std::string BSplinePatch::describe() const {
  return "cubic B-spline patch " + std::to_string(countU_) + " x " + std::to_string(countV_) +
         (periodicU_ ? " periodic-u" : "") + (periodicV_ ? " periodic-v" : "");
}

}  // namespace wf

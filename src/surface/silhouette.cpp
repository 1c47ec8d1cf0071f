// Silhouette tracing (surface/silhouette.h): marching squares over the (u, v) domain, roots on
// the grid edges, chords split until within the screen tolerance, trimmed by the face.
#include "surface/silhouette.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace wf {

namespace {

class Tracer {
 public:
  Tracer(const Surface& s, const ScalarTexture* inside, const ViewTransform& view, const SilhouetteOptions& o,
         SilhouetteStats& st)
      : s_(s), inside_(inside), view_(view), o_(o), st_(st), dom_(s.domain()) {
    const glm::dmat3 worldFromEye = glm::transpose(view.eyeFromWorld);
    towardViewer_ = worldFromEye * glm::dvec3(0.0, 0.0, 1.0);
  }

  // The signed cosine between the normal and the way to the eye; NaN where not finite.
  // (u, v) beyond a periodic direction's domain (a curve unwrapped across the seam) is wrapped
  // here: not every surface wraps it itself (an OpenCASCADE face clamps).
  double g(const glm::dvec2& uvIn) const {
    ++st_.evaluations;
    const glm::dvec2 uv = wrap(uvIn);
    // N from the derivatives where they are regular (one evaluation); the frame's limit at poles.
    const SurfacePoint sp = s_.evaluate(uv.x, uv.y);
    if (!std::isfinite(sp.P.x) || !std::isfinite(sp.P.y) || !std::isfinite(sp.P.z)) return NAN;
    glm::dvec3 N = glm::cross(sp.Su, sp.Sv);
    const double nl = glm::length(N);
    if (nl > Surface::kDegenerateEpsilon * glm::length(sp.Su) * glm::length(sp.Sv) && std::isfinite(nl)) {
      N *= s_.normalSign() / nl;
    } else {
      ++st_.evaluations;
      N = s_.frame(uv.x, uv.y).N;  // (uv wrapped above)
    }
    double c;
    if (view_.perspective) {
      const glm::dvec3 d = view_.eye - sp.P;
      const double l = glm::length(d);
      c = l > 0 ? glm::dot(N, d) / l : 0.0;
    } else {
      c = glm::dot(N, towardViewer_);
    }
    return std::isfinite(c) ? c : NAN;
  }
  // g within kFlat of zero is rounding noise (a plane through the eye: g is zero there but for
  // rounding, of either sign): such values count as positive, so a face flat to the eye gives no
  // curves of noise.
  static constexpr double kFlat = 1e-12;
  static bool positive(double v) { return v >= -kFlat; }

  // A root of g on the segment a -> b where ga, gb differ in sign (Illinois).
  glm::dvec2 root(glm::dvec2 a, glm::dvec2 b, double ga, double gb) const {
    const double tol = 1e-13 * std::max(std::abs(dom_.du()) + std::abs(dom_.dv()), 1e-300);
    double side = 0;
    for (int it = 0; it < 60; ++it) {
      double t = ga / (ga - gb);
      if (!(t > 0.0 && t < 1.0)) t = 0.5;
      const glm::dvec2 m = a + t * (b - a);
      const double gm = g(m);
      if (!std::isfinite(gm)) return m;
      if (glm::length(b - a) <= tol || gm == 0.0) return m;
      if (positive(gm) == positive(ga)) {
        a = m, ga = gm;
        if (side == -1) gb *= 0.5;
        side = -1;
      } else {
        b = m, gb = gm;
        if (side == 1) ga *= 0.5;
        side = 1;
      }
    }
    return 0.5 * (a + b);
  }

  // Screen position of a world point; false behind the near plane.
  bool screen(const glm::dvec2& uvIn, glm::dvec2& p, glm::dvec3* world = nullptr) const {
    const glm::dvec2 uv = wrap(uvIn);
    const glm::dvec3 P = s_.evaluate(uv.x, uv.y).P;
    if (world) *world = P;
    const glm::dvec3 e = view_.toEye(P);
    if (view_.perspective && !(-e.z > view_.nearPlane * 0.5)) return false;
    p = view_.project(e);
    return std::isfinite(p.x) && std::isfinite(p.y);
  }

  // The curve again between a and b (both on it): halfway, along the chord's normal in the
  // unit parameter square; false where it is not found within half the chord's length.
  bool between(const glm::dvec2& a, const glm::dvec2& b, glm::dvec2& r) const {
    const glm::dvec2 scale(dom_.du(), dom_.dv());
    const glm::dvec2 ua = a / scale, ub = b / scale, m = 0.5 * (ua + ub), d = ub - ua;
    const double len = glm::length(d);
    if (!(len > 0)) return false;
    const glm::dvec2 n(-d.y / len, d.x / len);
    const double gm = g(m * scale);
    if (!std::isfinite(gm)) return false;
    if (gm == 0.0) {
      r = m * scale;
      return true;
    }
    for (double h = 0.0625 * len; h <= 0.5 * len; h *= 2.0)
      for (double sgn : {1.0, -1.0}) {
        const glm::dvec2 q = m + sgn * h * n;
        const glm::dvec2 uvq = q * scale;
        if (!periodicOk(uvq)) continue;
        const double gq = g(uvq);
        if (std::isfinite(gq) && positive(gq) != positive(gm)) {
          r = root(m * scale, uvq, gm, gq);
          return true;
        }
      }
    return false;
  }
  bool periodicOk(const glm::dvec2& uv) const {
    const double eu = 1e-9 * std::abs(dom_.du()), ev = 1e-9 * std::abs(dom_.dv());
    return (dom_.periodicU || (uv.x >= dom_.u0 - eu && uv.x <= dom_.u1 + eu)) &&
           (dom_.periodicV || (uv.y >= dom_.v0 - ev && uv.y <= dom_.v1 + ev));
  }

  // Splits a -> b (a already emitted) while the curve strays from the chord on screen.
  void refine(const glm::dvec2& a, const glm::dvec2& b, int depth, std::vector<glm::dvec2>& out) const {
    if (depth >= o_.maxDepth || done_ + out.size() >= o_.maxPoints) return;
    glm::dvec2 r;
    if (!between(a, b, r)) return;
    glm::dvec2 pa, pb, pr;
    if (!screen(a, pa) || !screen(b, pb) || !screen(r, pr)) return;
    const glm::dvec2 d = pb - pa;
    const double l2 = glm::dot(d, d);
    const double t = l2 > 0 ? std::clamp(glm::dot(pr - pa, d) / l2, 0.0, 1.0) : 0.0;
    if (glm::length(pr - (pa + t * d)) <= o_.tolerancePx) return;
    refine(a, r, depth + 1, out);
    out.push_back(r);
    refine(r, b, depth + 1, out);
  }

  void trace(PolylineSet& out) {
    ++st_.faces;
    const int nu = std::clamp(o_.grid, 4, 1024), nv = nu;
    const int cu = nu + 1, cv = nv + 1;
    auto node = [&](int i, int j) {
      return glm::dvec2(dom_.u0 + dom_.du() * i / nu, dom_.v0 + dom_.dv() * j / nv);
    };
    // Node values; a periodic direction's last column (row) is its first.
    std::vector<double> G(size_t(cu) * size_t(cv));
    for (int j = 0; j < cv; ++j)
      for (int i = 0; i < cu; ++i) {
        const int ii = dom_.periodicU && i == nu ? 0 : i, jj = dom_.periodicV && j == nv ? 0 : j;
        if (ii != i || jj != j) {
          G[size_t(j) * cu + i] = G[size_t(jj) * cu + ii];
          continue;
        }
        const double v = g(node(i, j));
        if (!std::isfinite(v)) ++st_.nonFinite;
        G[size_t(j) * cu + i] = v;
      }
    auto val = [&](int i, int j) { return G[size_t(j) * cu + i]; };
    // Edge ids on the canonical (wrapped) nodes: horizontal edges 2k, vertical 2k + 1.
    auto canon = [&](int i, int j) {
      if (dom_.periodicU && i == nu) i = 0;
      if (dom_.periodicV && j == nv) j = 0;
      return std::int64_t(j) * cu + i;
    };
    auto hEdge = [&](int i, int j) { return 2 * canon(i, j); };
    auto vEdge = [&](int i, int j) { return 2 * canon(i, j) + 1; };
    struct Crossing {
      glm::dvec2 uv;
      int links[2] = {-1, -1};
    };
    std::vector<Crossing> cross;
    std::unordered_map<std::int64_t, int> crossingOf;
    auto crossing = [&](std::int64_t id, int i0, int j0, int i1, int j1) -> int {
      auto it = crossingOf.find(id);
      if (it != crossingOf.end()) return it->second;
      const double a = val(i0, j0), b = val(i1, j1);
      Crossing c;
      c.uv = root(node(i0, j0), node(i1, j1), a, b);
      cross.push_back(c);
      crossingOf.emplace(id, int(cross.size()) - 1);
      return int(cross.size()) - 1;
    };
    auto link = [&](int a, int b) {
      for (int k = 0; k < 2; ++k)
        if (cross[size_t(a)].links[k] < 0) {
          cross[size_t(a)].links[k] = b;
          break;
        }
      for (int k = 0; k < 2; ++k)
        if (cross[size_t(b)].links[k] < 0) {
          cross[size_t(b)].links[k] = a;
          break;
        }
    };
    for (int j = 0; j < nv; ++j)
      for (int i = 0; i < nu; ++i) {
        const double c0 = val(i, j), c1 = val(i + 1, j), c2 = val(i + 1, j + 1), c3 = val(i, j + 1);
        if (!std::isfinite(c0) || !std::isfinite(c1) || !std::isfinite(c2) || !std::isfinite(c3)) continue;
        const bool s0 = positive(c0), s1 = positive(c1), s2 = positive(c2), s3 = positive(c3);
        int e[4], n = 0;  // crossings on bottom, right, top, left, in that order
        int ids[4] = {-1, -1, -1, -1};
        if (s0 != s1) ids[0] = crossing(hEdge(i, j), i, j, i + 1, j);
        if (s1 != s2) ids[1] = crossing(vEdge(i + 1, j), i + 1, j, i + 1, j + 1);
        if (s3 != s2) ids[2] = crossing(hEdge(i, j + 1), i, j + 1, i + 1, j + 1);
        if (s0 != s3) ids[3] = crossing(vEdge(i, j), i, j, i, j + 1);
        for (int k = 0; k < 4; ++k)
          if (ids[k] >= 0) e[n++] = k;
        if (n == 2) {
          link(ids[e[0]], ids[e[1]]);
        } else if (n == 4) {
          // A saddle: the centre's sign says which corners its region joins.
          const double cc = g(0.5 * (node(i, j) + node(i + 1, j + 1)));
          if (positive(cc) == s0) link(ids[0], ids[1]), link(ids[2], ids[3]);
          else link(ids[3], ids[0]), link(ids[1], ids[2]);
        }
      }
    // Chains: open ones from their ends first, then the loops.
    std::vector<char> used(cross.size(), 0);
    std::vector<glm::dvec2> chain, fine;
    auto walk = [&](int start) {
      chain.clear();
      int prev = -1, cur = start;
      while (cur >= 0 && !used[size_t(cur)]) {
        used[size_t(cur)] = 1;
        chain.push_back(cross[size_t(cur)].uv);
        const Crossing& c = cross[size_t(cur)];
        const int next = c.links[0] != prev ? c.links[0] : c.links[1];
        prev = cur;
        cur = next;
      }
      if (cur == start && chain.size() > 2) chain.push_back(chain.front());  // a loop closes
      emit(chain, fine, out);
    };
    for (size_t k = 0; k < cross.size(); ++k)
      if (!used[k] && (cross[k].links[0] < 0 || cross[k].links[1] < 0)) walk(int(k));
    for (size_t k = 0; k < cross.size(); ++k)
      if (!used[k]) walk(int(k));
  }

  // Refines a chain of roots, unwraps it across periodic seams, trims it and appends it.
  void emit(std::vector<glm::dvec2>& chain, std::vector<glm::dvec2>& fine, PolylineSet& out) {
    if (chain.size() < 2 || cut_) return;
    fine.clear();
    fine.push_back(chain[0]);
    for (size_t k = 1; k < chain.size(); ++k) {
      glm::dvec2 a = fine.back(), b = chain[k];
      // The shorter way round a periodic direction (both are the same points of the surface).
      if (dom_.periodicU && std::abs(b.x - a.x) > 0.5 * std::abs(dom_.du())) b.x += b.x > a.x ? -dom_.du() : dom_.du();
      if (dom_.periodicV && std::abs(b.y - a.y) > 0.5 * std::abs(dom_.dv())) b.y += b.y > a.y ? -dom_.dv() : dom_.dv();
      refine(a, b, 0, fine);
      fine.push_back(b);
      if (done_ + fine.size() >= o_.maxPoints) {
        if (!cut_) ++st_.cutShort;
        cut_ = true;
        break;
      }
    }
    done_ += fine.size();
    // Trim: runs where the face is, ended at the border found by bisection.
    std::vector<glm::dvec3> line;
    // The screen box of the line so far: a curve that fits inside the tolerance is no curve at
    // this resolution (a pole that is one only within the model's tolerance, 1e-7 to 1e-4
    // units, scatters its points by that much).
    glm::dvec2 boxLo(HUGE_VAL), boxHi(-HUGE_VAL);
    auto flush = [&] {
      const glm::dvec2 extent = boxHi - boxLo;
      if (line.size() >= 2 && std::isfinite(extent.x) && std::isfinite(extent.y) &&
          std::max(extent.x, extent.y) < o_.tolerancePx)
        line.clear();
      boxLo = glm::dvec2(HUGE_VAL);
      boxHi = glm::dvec2(-HUGE_VAL);
      if (line.size() >= 2) {
        out.add(line);
        ++st_.curves;
        st_.points += line.size();
      }
      line.clear();
    };
    // A point within 1e-6 px of the one before it on screen is left out: along a degenerate edge
    // (a pole: the corner of a CAD fillet blend) the root can run where every point is the pole,
    // up to rounding, and a curve left with one point is no curve (it drew a dot at each corner).
    glm::dvec2 lastScreen(NAN);
    auto push = [&](const glm::dvec2& uvIn) {  // a non-finite point splits the curve
      const glm::dvec2 uv = wrap(uvIn);
      const glm::dvec3 P = s_.evaluate(uv.x, uv.y).P;
      if (!(std::isfinite(P.x) && std::isfinite(P.y) && std::isfinite(P.z))) {
        flush();
        return;
      }
      glm::dvec2 q(NAN);
      const glm::dvec3 e = view_.toEye(P);
      if (!view_.perspective || -e.z > 0) q = view_.project(e);
      if (!line.empty() && glm::length(q - lastScreen) <= 1e-6) return;
      lastScreen = q;
      boxLo = glm::min(boxLo, q);  // (glm::min keeps the box: a point behind the eye, NaN, is left out)
      boxHi = glm::max(boxHi, q);
      line.push_back(P);
    };
    // The mask is over the unit square of the domain (as fur and scales read it: a CAD face's
    // FaceMask clamps (s, t) to [0, 1]^2)
    auto in = [&](const glm::dvec2& uv) {
      if (!inside_) return true;
      const glm::dvec2 w = wrap(uv);
      return inside_->value(dom_.toUnit(w.x, w.y)) >= 0.5;
    };
    bool prevIn = false;
    for (size_t k = 0; k < fine.size(); ++k) {
      const glm::dvec2 uv = fine[k];
      const bool here = in(uv);
      if (k > 0 && here != prevIn) {
        glm::dvec2 a = fine[k - 1], b = uv;  // a on prevIn's side
        for (int it = 0; it < 30; ++it) {
          const glm::dvec2 m = 0.5 * (a + b);
          if (in(m) == prevIn) a = m;
          else b = m;
        }
        push(prevIn ? a : b);
        if (prevIn) flush();
      }
      if (here) push(uv);
      prevIn = here;
    }
    flush();
  }
  glm::dvec2 wrap(glm::dvec2 uv) const {
    if (dom_.periodicU) uv.x = dom_.u0 + std::fmod(std::fmod(uv.x - dom_.u0, dom_.du()) + dom_.du(), dom_.du());
    if (dom_.periodicV) uv.y = dom_.v0 + std::fmod(std::fmod(uv.y - dom_.v0, dom_.dv()) + dom_.dv(), dom_.dv());
    return uv;
  }

 private:
  const Surface& s_;
  const ScalarTexture* inside_;
  const ViewTransform& view_;
  const SilhouetteOptions& o_;
  SilhouetteStats& st_;
  ParameterDomain dom_;
  glm::dvec3 towardViewer_{0.0, 0.0, 1.0};
  std::size_t done_ = 0;  // points of this face's chains so far (SilhouetteOptions::maxPoints is per face)
  bool cut_ = false;
};

}  // namespace

void traceSilhouette(const Surface& surface, const ScalarTexture* inside, const ViewTransform& view,
                     const SilhouetteOptions& options, PolylineSet& out, SilhouetteStats& stats) {
  const ParameterDomain d = surface.domain();
  if (!(std::isfinite(d.du()) && std::isfinite(d.dv()) && d.du() > 0 && d.dv() > 0)) {
    ++stats.faces;
    ++stats.nonFinite;
    return;
  }
  Tracer(surface, inside, view, options, stats).trace(out);
}

}  // namespace wf

// Stage "primitives" (render/pipeline.h), wire segments: the paper's wire polygons (§3) with
// mitred joints, end-on discs and optional round ends (see the top of render/pipeline.h).
#include "render/pipeline.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace wf {

namespace {

// Screen-space state of one wire segment during set-up.
struct SegScreen {
  bool valid = false, endOn = false;
  bool clipped0 = false, clipped1 = false;
  glm::dvec3 e0, e1;      // eye space, after clipping
  glm::dvec2 p0, p1;      // screen
  double d0 = 0, d1 = 0;  // depths
  double w0 = 0, w1 = 0;  // half widths, pixels
  glm::dvec2 dir{0}, nrm{0};
  double length = 0;
  glm::dvec3 tangent{0};  // eye-space unit direction (unclipped)
};

void addStadium(const SegScreen& s, ScreenPolygon& poly) {
  // Hull of two 16-gon discs with the discs' exact areas (circumradius scaled up).
  constexpr int kSides = 16;
  const double scale = std::sqrt(std::numbers::pi / (0.5 * kSides * std::sin(2 * std::numbers::pi / kSides)));
  std::vector<glm::dvec2> pts;
  for (int end = 0; end < 2; ++end) {
    const glm::dvec2 c = end ? s.p1 : s.p0;
    const double r = (end ? s.w1 : s.w0) * scale;
    for (int i = 0; i < kSides; ++i) {
      const double a = 2 * std::numbers::pi * i / kSides;
      pts.emplace_back(c.x + r * std::cos(a), c.y + r * std::sin(a));
    }
  }
  std::sort(pts.begin(), pts.end(), [](const glm::dvec2& a, const glm::dvec2& b) {
    return a.x < b.x || (a.x == b.x && a.y < b.y);
  });
  std::vector<glm::dvec2> hull(2 * pts.size());
  size_t k = 0;
  auto cross = [](const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
  };
  for (size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  for (size_t i = pts.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], pts[i - 1]) <= 0) --k;
    hull[k++] = pts[i - 1];
  }
  poly.count = 0;
  for (size_t i = 0; i + 1 < k; ++i) poly.add(hull[i].x, hull[i].y);
}

// A half disc of radius r about c, bulging along `out`, from c + r side to c - r side (both
// included), appended to `poly`. As few edges as keep every chord within 0.05 pixel of the
// circle (2 ... 8), the inner vertices a little outside the circle so that the half polygon has
// the half disc's exact area, pi r^2 / 2; the two end vertices stay on the wire's sides, so the
// cap meets the body without a step.
void addHalfDisc(const glm::dvec2& c, const glm::dvec2& out, const glm::dvec2& side, double r, ScreenPolygon& poly) {
  constexpr int kMaxSides = 8;
  // Fan about c: 2 triangles with one vertex at r and one at s r, n - 2 with both at s r, each
  // of angle t = pi / n: (n - 2) s^2 sin t + 2 s sin t = pi / 2 ... solved for s, per n.
  static const std::array<double, kMaxSides + 1> kScale = [] {
    std::array<double, kMaxSides + 1> k{};
    for (int n = 2; n <= kMaxSides; ++n) {
      const double sn = std::sin(std::numbers::pi / n), a = (n - 2) * sn, b = 2 * sn;
      k[size_t(n)] = a > 0 ? (-b + std::sqrt(b * b + 4 * a * std::numbers::pi)) / (2 * a) : std::numbers::pi / b;
    }
    return k;
  }();
  // Sagitta of a chord of angle t: r (1 - cos(t / 2)) <= 0.05 px.
  int n = 2;
  while (n < kMaxSides && r * (1 - std::cos(std::numbers::pi / (2 * n))) > 0.05) ++n;
  const double inner = r * kScale[size_t(n)];
  for (int i = 0; i <= n; ++i) {
    const double ang = std::numbers::pi * i / n;
    const double k = (i == 0 || i == n) ? r : inner;
    const glm::dvec2 p = c + k * (std::cos(ang) * side + std::sin(ang) * out);
    poly.add(p.x, p.y);
  }
}

}  // namespace

void setupPolylines(const PreparedScene& ps, const SceneWire& wire, std::uint16_t shader,
                    std::uint32_t tagBase, size_t begin, size_t end, ChunkOut& out) {
  const ViewTransform& view = ps.view;
  const PolylineSet& L = wire.lines;
  const ShaderSlot& slot = ps.shaders[shader];
  const bool hasColours = L.colours.size() == L.points.size();
  std::vector<SegScreen> segs;
  std::vector<size_t> ids;
  std::vector<glm::dvec2> offsets;
  std::vector<char> mitred;
  for (size_t li = begin; li < end; ++li) {
    const size_t a = L.starts[li], b = std::min<size_t>(L.starts[li + 1], L.points.size());
    // Repeated points make zero-length segments: drop them here, so that the segments on either
    // side still meet in a mitred joint.
    ids.clear();
    for (size_t k = a; k < b; ++k) {
      if (!ids.empty() && L.points[k] == L.points[ids.back()]) {
        ++out.zeroLength;
        continue;
      }
      ids.push_back(k);
    }
    if (ids.size() < 2) continue;
    const size_t nseg = ids.size() - 1;
    const bool closed = nseg > 1 && L.points[ids.front()] == L.points[ids.back()];
    segs.assign(nseg, SegScreen{});
    for (size_t j = 0; j < nseg; ++j) {
      SegScreen& s = segs[j];
      const glm::dvec3 &w0 = L.points[ids[j]], &w1 = L.points[ids[j + 1]];
      if (!finite3(w0) || !finite3(w1)) {
        ++out.rejected;
        continue;
      }
      glm::dvec3 e0 = view.toEye(w0), e1 = view.toEye(w1);
      if (!finite3(e0) || !finite3(e1) || e0 == e1) {
        ++out.zeroLength;
        continue;
      }
      ++out.segments;
      s.tangent = glm::normalize(e1 - e0);
      double d0 = -e0.z, d1 = -e1.z;
      const double nearP = view.nearPlane, farP = view.farPlane;
      if ((d0 < nearP && d1 < nearP) || (d0 > farP && d1 > farP)) {
        ++out.clipped;
        continue;
      }
      // Clip to [near, far] along the segment.
      auto clipEnd = [&](glm::dvec3& p, double& d, const glm::dvec3& q, double dq, bool& flag) {
        if (d < nearP) {
          p = p + (nearP - d) / (dq - d) * (q - p);
          d = nearP;
          flag = true;
        } else if (d > farP) {
          p = p + (farP - d) / (dq - d) * (q - p);
          d = farP;
          flag = true;
        }
      };
      const glm::dvec3 o0 = e0, o1 = e1;
      clipEnd(e0, d0, o1, d1, s.clipped0);
      clipEnd(e1, d1, o0, -o0.z, s.clipped1);
      s.e0 = e0;
      s.e1 = e1;
      s.d0 = d0;
      s.d1 = d1;
      s.p0 = view.project(e0);
      s.p1 = view.project(e1);
      const double halfT = 0.5 * wire.thickness;
      s.w0 = wire.thicknessInPixels ? halfT : halfT * view.pixelsPerWorld(d0);
      s.w1 = wire.thicknessInPixels ? halfT : halfT * view.pixelsPerWorld(d1);
      const glm::dvec2 dv = s.p1 - s.p0;
      s.length = glm::length(dv);
      if (!(std::isfinite(s.length)) || !(s.w0 > 0) || !(s.w1 > 0) || !std::isfinite(s.w0) ||
          !std::isfinite(s.w1)) {
        ++out.clipped;
        continue;
      }
      s.endOn = s.length < std::max(s.w0, s.w1);
      if (!s.endOn) {
        s.dir = dv / s.length;
        s.nrm = glm::dvec2(-s.dir.y, s.dir.x);
      }
      s.valid = true;
    }
    // Joint offsets: vertex j joins segment j-1 and j.
    offsets.assign(nseg + 1, glm::dvec2(0));
    mitred.assign(nseg + 1, 0);
    for (size_t j = 1; j < nseg; ++j) {
      const SegScreen &p = segs[j - 1], &q = segs[j];
      if (!p.valid || !q.valid || p.endOn || q.endOn || p.clipped1 || q.clipped0) continue;
      const glm::dvec2 m = p.nrm + q.nrm;
      const double ml = glm::length(m);
      if (!(ml > 1e-6)) continue;
      const glm::dvec2 mh = m / ml;
      const double c = glm::dot(mh, q.nrm);
      if (!(c > 1.0 / kMitreLimit)) continue;
      offsets[j] = mh * (q.w0 / c);
      mitred[j] = 1;
    }
    const std::uint32_t tag = tagBase + std::uint32_t(li);
    for (size_t j = 0; j < nseg; ++j) {
      const SegScreen& s = segs[j];
      if (!s.valid) continue;
      ScreenPolygon poly;
      if (s.endOn) {
        addStadium(s, poly);
        ++out.endOn;
      } else {
        glm::dvec2 o0 = mitred[j] ? offsets[j] : s.nrm * s.w0;
        glm::dvec2 o1 = mitred[j + 1] ? offsets[j + 1] : s.nrm * s.w1;
        // Round ends: a half disc at a free end of the polyline (not at a joint, not where the
        // near or far plane cut the segment).
        const bool cap0 = wire.roundEnds && j == 0 && !s.clipped0 && !closed;
        const bool cap1 = wire.roundEnds && j + 1 == nseg && !s.clipped1 && !closed;
        auto quad = [&](const glm::dvec2& u0, const glm::dvec2& u1) {
          // A free end is never mitred, so there u0 = nrm w0 and u1 = nrm w1: the caps run
          // between the same corners the square ends would have.
          poly.count = 0;
          if (cap0) addHalfDisc(s.p0, -s.dir, -s.nrm, s.w0, poly);  // from p0 - u0 round to p0 + u0
          else poly.add(s.p0.x + u0.x, s.p0.y + u0.y);
          if (cap1) {
            addHalfDisc(s.p1, s.dir, s.nrm, s.w1, poly);  // from p1 + u1 round to p1 - u1
          } else {
            poly.add(s.p1.x + u1.x, s.p1.y + u1.y);
            poly.add(s.p1.x - u1.x, s.p1.y - u1.y);
          }
          if (!cap0) poly.add(s.p0.x - u0.x, s.p0.y - u0.y);
        };
        quad(o0, o1);
        if (!isConvex(poly)) quad(s.nrm * s.w0, s.nrm * s.w1);  // a folding mitre: square ends
      }
      poly.removeDuplicates();
      Primitive prim;
      // The wire is drawn at its visible front, the cylinder's surface nearest the eye, one
      // radius in front of its axis: a wire lying on a surface (a CAD edge, a mesh's own edge)
      // then shows whole in front of it instead of tying with it pixel by pixel.
      const double f0 = std::max(view.nearPlane, s.d0 - s.w0 / view.pixelsPerWorld(s.d0));
      const double f1 = std::max(view.nearPlane, s.d1 - s.w1 / view.pixelsPerWorld(s.d1));
      const double k0 = view.depthKey(f0), k1 = view.depthKey(f1);
      if (s.length > 1e-12) {
        const glm::dvec2 u = (s.p1 - s.p0) / (s.length * s.length);
        prim.qa = (k1 - k0) * u.x;
        prim.qb = (k1 - k0) * u.y;
        prim.qc = k0 - prim.qa * s.p0.x - prim.qb * s.p0.y;
      } else {
        prim.qa = prim.qb = 0;
        prim.qc = view.perspective ? std::max(k0, k1) : std::min(k0, k1);
      }
      prim.zlo = float(std::min(f0, f1));
      prim.zhi = float(std::max(f0, f1));
      prim.tag = tag;
      prim.mayMerge = nseg > 1;  // a one-segment polyline (a straight hair) has nothing to merge with
      prim.opacity = safeOpacity(wire.opacity);
      prim.isSegment = true;
      prim.attribute = std::uint32_t(out.segs.size());
      SegmentAttributes sa;
      sa.p0 = s.e0;
      sa.p1 = s.e1;
      // Tangents at the ends: averaged with the neighbour at a joint, so a smooth curve of
      // straight segments shades smoothly, like one bent wire.
      auto jointTangent = [&](size_t jv, const glm::dvec3& own) {
        const SegScreen* other = nullptr;
        if (jv == j && j > 0) other = &segs[j - 1];
        if (jv == j + 1 && j + 1 < nseg) other = &segs[j + 1];
        if (!other || !other->valid) return own;
        const glm::dvec3 sum = own + other->tangent;
        const double l = glm::length(sum);
        return l > 1e-6 ? sum / l : own;
      };
      sa.t0 = jointTangent(j, s.tangent);
      sa.t1 = jointTangent(j + 1, s.tangent);
      sa.c0 = hasColours ? safeColour(L.colours[ids[j]]) : glm::vec3(1.0f);
      sa.c1 = hasColours ? safeColour(L.colours[ids[j + 1]]) : glm::vec3(1.0f);
      sa.r0 = float(s.w0 / view.pixelsPerWorld(s.d0));
      sa.r1 = float(s.w1 / view.pixelsPerWorld(s.d1));
      sa.shader = shader;
      if (sa.c0 == sa.c1) {
        if (slot.kind == ShaderSlot::Kind::WirePlain) {
          prim.constantColour = true;
          prim.colour = slot.colour * sa.c0;
        } else if (slot.kind == ShaderSlot::Kind::WireShaded && slot.wireTables && sa.t0 == sa.t1 &&
                   ps.grid->size() == 1) {
          prim.constantColour = true;  // one orthographic map: the tangent alone decides
          prim.colour = slot.wireTables->lookup(sa.t0, ps.view.cx, ps.view.cy) * sa.c0;
        }
      }
      if (!finishPolygon(poly, view, prim, out)) {
        ++out.clipped;
        continue;
      }
      out.segs.push_back(sa);
    }
  }
}

}  // namespace wf

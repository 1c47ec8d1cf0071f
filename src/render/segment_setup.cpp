// Stage "primitives" (render/pipeline.h), wire segments: the paper's wire polygons (§3) with
// mitred joints, end-on discs and optional round ends, stored as SegmentPrim (80 bytes),
// SegmentShading (24 bytes) and, when some wire needs them, SegmentColours (24 bytes); the
// polygon itself is made on demand (segmentPolygon), so that a million hairs do not hold twenty
// vertices each.
#include "render/pipeline.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace wf {

namespace {

// Screen-space state of one wire segment during set-up.
struct SegScreen {
  bool valid = false, endOn = false;
  /// Dropped for a reason that leaves its neighbours' ends free (a non-finite point, in the world
  /// or once in eye space; a width that rounds to nothing): they take round caps there. One the
  /// near or far plane took, or one of no length in eye space, leaves them cut or joined, not free.
  bool freesNeighbours = false;
  bool clipped0 = false, clipped1 = false;
  glm::dvec2 p0, p1;      // screen
  double d0 = 0, d1 = 0;  // depths
  double w0 = 0, w1 = 0;  // half widths, pixels
  glm::dvec3 e0{0}, e1{0};  // eye-space ends (after clipping)
  glm::dvec2 nrm{0};
  glm::dvec3 tangent{0};  // eye-space unit direction (unclipped)
  double k0 = 0, k1 = 0;  // pixels per world unit at the ends' depths
  double l0 = 0, l1 = 0;  // |e0|, |e1|: the ends' distances from the eye
  glm::dvec3 unitAxis{0};  // (e1 - e0) / |e1 - e0| after clipping (wireUnitAxis)
  double length = 0;       // |p1 - p0|, pixels
};

// Half discs of n = 2 ... kMaxCapSides edges: fan about the centre, 2 triangles with one vertex
// at r and one at s r, n - 2 with both at s r, each of angle pi / n: (n - 2) s^2 sin(pi / n) +
// 2 s sin(pi / n) = pi / 2 gives s, so that the half polygon has the half disc's exact area; the
// two end vertices stay on the wire's sides, so the cap meets the body without a step.
constexpr int kMaxCapSides = 8;
struct CapTable {
  double scale[kMaxCapSides + 1];
  double cosA[kMaxCapSides + 1][kMaxCapSides + 1], sinA[kMaxCapSides + 1][kMaxCapSides + 1];
  double sagittaFactor[kMaxCapSides + 1];  // 1 - cos(pi / (2 n))
};
const CapTable& capTable() {
  static const CapTable t = [] {
    CapTable c{};
    for (int n = 2; n <= kMaxCapSides; ++n) {
      const double sn = std::sin(std::numbers::pi / n), a = (n - 2) * sn, b = 2 * sn;
      c.scale[n] = a > 0 ? (-b + std::sqrt(b * b + 4 * a * std::numbers::pi)) / (2 * a) : std::numbers::pi / b;
      for (int i = 0; i <= n; ++i) {
        c.cosA[n][i] = std::cos(std::numbers::pi * i / n);
        c.sinA[n][i] = std::sin(std::numbers::pi * i / n);
      }
      c.sagittaFactor[n] = 1 - std::cos(std::numbers::pi / (2 * n));
    }
    return c;
  }();
  return t;
}

// A half disc of radius r about c, bulging along `out`, from c + o to c - o (o = r side, the
// corner offset the square end would have: both ends are the body's corners bit for bit),
// appended to `poly`: as few edges as keep every chord within 0.05 pixel of the circle (2 ... 8).
void addHalfDisc(const glm::dvec2& c, const glm::dvec2& out, const glm::dvec2& side, const glm::dvec2& o, double r,
                 ScreenPolygon& poly) {
  const CapTable& t = capTable();
  int n = 2;
  while (n < kMaxCapSides && r * t.sagittaFactor[n] > 0.05) ++n;
  const double inner = r * t.scale[n];
  poly.add(c.x + o.x, c.y + o.y);
  for (int i = 1; i < n; ++i)
    poly.add(c.x + inner * (t.cosA[n][i] * side.x + t.sinA[n][i] * out.x),
             c.y + inner * (t.cosA[n][i] * side.y + t.sinA[n][i] * out.y));
  poly.add(c.x - o.x, c.y - o.y);
}

// Hull of the two end discs (16-gons of the discs' exact areas), for a segment seen end-on.
void addStadium(const SegmentPrim& s, ScreenPolygon& poly) {
  constexpr int kSides = 16;
  static const double scale = std::sqrt(std::numbers::pi / (0.5 * kSides * std::sin(2 * std::numbers::pi / kSides)));
  glm::dvec2 pts[2 * kSides];
  for (int end = 0; end < 2; ++end) {
    const glm::dvec2 c = end ? s.p1 : s.p0;
    const double r = double(end ? s.w1 : s.w0) * scale;
    for (int i = 0; i < kSides; ++i) {
      const double a = 2 * std::numbers::pi * i / kSides;
      pts[end * kSides + i] = {c.x + r * std::cos(a), c.y + r * std::sin(a)};
    }
  }
  std::sort(pts, pts + 2 * kSides, [](const glm::dvec2& a, const glm::dvec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  glm::dvec2 hull[4 * kSides];
  int k = 0;
  auto cross = [](const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
  };
  for (int i = 0; i < 2 * kSides; ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  for (int i = 2 * kSides - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], pts[i - 1]) <= 0) --k;
    hull[k++] = pts[i - 1];
  }
  poly.count = 0;
  for (int i = 0; i + 1 < k; ++i) poly.add(hull[i].x, hull[i].y);
}

}  // namespace

SegmentTilt::SegmentTilt(const ViewTransform& v, const SegmentPrim& s, const SegmentFrame& fr) {
  if (!v.perspective) return;
  const double f2 = v.focal * v.focal;
  const double ox = fr.ax - v.cx, oy = fr.ay - v.cy;  // p0 from the image centre
  // X - c across the axis (constant along it) and along it at the two ends.
  double across, a0, a1;
  if (fr.length > 0) {
    across = ox * fr.nx + oy * fr.ny;
    a0 = (ox * fr.ux + oy * fr.uy) * fr.length;
    a1 = a0 + fr.length;
  } else {  // seen end-on: lat is the y offset, along the x offset, from p0
    across = oy;
    a0 = a1 = ox;
  }
  // Across: the plane through the eye and the axis has n_z = L / sqrt(f^2 + L^2) and |n_xy| =
  // f / sqrt(f^2 + L^2), L = (X - c) . n, and the half width is w = r f / (d |n_xy|), so the
  // chord's middle stands q r n_z = lat d L / (f^2 + L^2) nearer. Along (beyond an end, the end's
  // sphere): the same form with L = (X - c) . u at that end; only the ends' values matter there
  // (along is zero between them), so the coefficient runs linearly from one to the other.
  lateral = -across / (f2 + across * across);
  // The axis point the ray passes nearest is not the foot of the perpendicular from the screen
  // point: offsets across the wire run towards the vanishing point of n, which lies across the
  // axis line at -(f^2 + L^2) / L and along it at the image centre, so the ray through a point
  // lat across meets the axis's plane lat L A / (f^2 + L^2) pixels nearer the centre along the
  // axis (A = (X - c) . u). On a slanting wire the axis depth changes fast along it: there this
  // term is as large as the tilt itself.
  // In parameter units the slide is lat L A / ((f^2 + L^2) |p1 - p0|), which grows without
  // bound as the segment shortens on screen and would vanish at once where it turns end-on
  // (kSegmentEndOn: the hull of its end discs, no axis to slide along): it fades out with the
  // depth radius's ramp (segment_setup below), from full at two half widths of screen length to
  // none at one, so that a turning wire's depth changes continuously. In pixels it is then
  // at most w |A| / (2 f) where it is whole, and a parameter shift of at most |A| / (2 f).
  const double w = std::max(double(s.w0), double(s.w1));
  if (fr.length > 0 && !(s.flags & kSegmentEndOn)) {
    const double ramp = std::clamp(fr.length / w - 1.0, 0.0, 1.0);  // 1 when w = 0 (inf)
    shiftT = -ramp * across / (f2 + across * across);
    shift0 = shiftT * a0 / fr.length;
  }
  along0 = -a0 / (f2 + a0 * a0);
  alongT = -a1 / (f2 + a1 * a1) - along0;
  // |L| / (f^2 + L^2) <= 1 / (2 f): never more than a half width over f each (segmentTiltBound).
  // A wire as wide as the focal length (touching the eye) would tilt its depth to zero: the
  // first-order model is held to half the depth either way.
  const double raw = w * (std::abs(lateral) + std::max(std::abs(along0), std::abs(along0 + alongT)));
  if (raw > 0.5) {
    const double k = 0.5 / raw;
    lateral *= k, along0 *= k, alongT *= k;
  }
  bound = std::min(raw, 0.5) * (1.0 + 1e-6);
}

double SegmentTilt::shiftBound(const ViewTransform& v, const SegmentPrim& s, const SegmentFrame& fr) const {
  if (shiftT == 0.0) return 0.0;
  // The shift at axis parameter tc is shiftT A(tc) / |p1 - p0|, A(tc) = a0 + tc |p1 - p0|. Only
  // points inside the image take it, and where tc is strictly inside the segment |A(tc)| =
  // |(P - c) . u| <= R, R the image's farthest corner from its centre; beyond an end, |A(tc)| <=
  // R plus the point's distance from the axis: the polygon's reach for the samples it covers,
  // and up to two pixels more for the resolve's other evaluations (stand-in subpixels within
  // about 0.7 px of the outline, and a merged fragment's second segment taken at the first's
  // samples, up to sqrt 2 px beyond its own outline). An end far off screen (a wire cut by the
  // near plane: |a0| up to 1e5 pixels) would otherwise give a slide of hundreds of pixels and
  // undo the rasteriser's and the binner's culling.
  const double a0 = ((fr.ax - v.cx) * fr.ux + (fr.ay - v.cy) * fr.uy) * fr.length, a1 = a0 + fr.length;
  const double rx = std::max(std::abs(v.cx), std::abs(double(v.width) - v.cx));
  const double ry = std::max(std::abs(v.cy), std::abs(double(v.height) - v.cy));
  const double amax = std::min(std::max(std::abs(a0), std::abs(a1)), std::sqrt(rx * rx + ry * ry) + segmentReach(s) + 2.0);
  const double w = std::max(double(s.w0), double(s.w1));
  return w * std::abs(shiftT) * amax / fr.length * (1.0 + 1e-6);
}

double segmentTiltBound(const ViewTransform& v, const SegmentPrim& s) {
  return v.perspective ? std::min(0.5, std::max(double(s.w0), double(s.w1)) / v.focal) * (1.0 + 1e-6) : 0.0;
}

void segmentPolygon(const SegmentPrim& s, ScreenPolygon& poly) {
  poly.count = 0;
  if (s.flags & kSegmentEndOn) {
    addStadium(s, poly);
  } else {
    const glm::dvec2 o0(s.o0), o1(s.o1);
    const bool cap0 = s.flags & kSegmentCap0, cap1 = s.flags & kSegmentCap1;
    glm::dvec2 dir(0.0), nrm(0.0);
    if (cap0 || cap1) {
      const glm::dvec2 d = s.p1 - s.p0;
      const double l = glm::length(d);
      dir = d / l;
      nrm = {-dir.y, dir.x};
    }
    // A free end is never mitred, so there o0 = nrm w0 and o1 = nrm w1: the caps run between
    // the corners the square ends would have.
    if (cap0) addHalfDisc(s.p0, -dir, -nrm, -o0, s.w0, poly);  // from p0 - o0 round to p0 + o0
    else poly.add(s.p0.x + o0.x, s.p0.y + o0.y);
    if (cap1) {
      addHalfDisc(s.p1, dir, nrm, o1, s.w1, poly);  // from p1 + o1 round to p1 - o1
    } else {
      poly.add(s.p1.x + o1.x, s.p1.y + o1.y);
      poly.add(s.p1.x - o1.x, s.p1.y - o1.y);
    }
    if (!cap0) poly.add(s.p0.x - o0.x, s.p0.y - o0.y);
  }
  poly.removeDuplicates();
}

namespace {
bool hasPointColours(const PolylineSet& L) { return !L.points.empty() && L.colours.size() == L.points.size(); }
// A straight wire's shading through one orthographic map depends on its tangent alone: it is
// looked up once per segment at set-up and interpolated along it by colour (exactly: the
// tangent is the same at both ends).
bool preshadesByMap(const PreparedScene& ps, const ShaderSlot& slot) {
  return ps.path == ShadingPath::Maps && slot.kind == ShaderSlot::Kind::WireShaded && slot.wireTables &&
         ps.grid && ps.grid->size() == 1;
}
}  // namespace

// Without building the polygon where it is the quadrilateral p0 + o0, p1 + o1, p1 - o1, p0 - o0
// (no caps, not end-on) of four distinct consecutive corners: the same corners and the same
// turns in the same order, so the same answer. Otherwise the polygon itself.
bool segmentPolygonConvex(const SegmentPrim& s) {
  if (!(s.flags & (kSegmentCap0 | kSegmentCap1 | kSegmentEndOn))) {
    const glm::dvec2 o0(s.o0), o1(s.o1);
    const double x[4] = {s.p0.x + o0.x, s.p1.x + o1.x, s.p1.x - o1.x, s.p0.x - o0.x};
    const double y[4] = {s.p0.y + o0.y, s.p1.y + o1.y, s.p1.y - o1.y, s.p0.y - o0.y};
    bool distinct = true;
    for (int i = 0; i < 4; ++i) distinct = distinct && !(x[i] == x[(i + 1) & 3] && y[i] == y[(i + 1) & 3]);
    if (distinct) {
      int sign = 0;
      for (int i = 0; i < 4; ++i) {
        const int j = (i + 1) & 3, k = (i + 2) & 3;
        const int t = turnSign(x[i], y[i], x[j], y[j], x[k], y[k]);  // (isConvex's own)
        if (t == 0) continue;
        if (sign == 0) sign = t;
        else if (t != sign) return false;
      }
      return true;
    }
  }
  ScreenPolygon poly;
  segmentPolygon(s, poly);
  return isConvex(poly);
}

[[noreturn, gnu::cold, gnu::noinline]] static void noRoomForColours(const SceneWire& wire) {
  throw std::logic_error("setupPolylines: wire '" + wire.name + "' keeps colours and has no room for them");
}

bool wireKeepsColours(const PreparedScene& ps, const SceneWire& wire, std::uint32_t shader) {
  const ShaderSlot& slot = ps.shaders[shader];
  return hasPointColours(wire.lines) || slot.kind == ShaderSlot::Kind::WirePlain || preshadesByMap(ps, slot);
}

void setupPolylines(const PreparedScene& ps, const SceneWire& wire, std::uint32_t shader,
                    std::uint32_t tagBase, size_t begin, size_t end, SegmentSink& out, SetupCounts& counts,
                    const WireSimplification* simplification) {
  const ViewTransform& view = ps.view;
  const PolylineSet& L = wire.lines;
  const ShaderSlot& slot = ps.shaders[shader];
  const bool hasColours = hasPointColours(L);
  const bool preshadeMaps = preshadesByMap(ps, slot);
  // (prepareScene gives room for colours when any wire keeps them; a scene with no segment at all
  // has none to give, and needs none.)
  const bool keepsColours = wireKeepsColours(ps, wire, shader);
  const bool simplified = simplification && simplification->scale.size() == L.polylineCount();
  const double nearP = view.nearPlane, farP = view.farPlane;
  thread_local std::vector<SegScreen> segs;
  thread_local std::vector<size_t> ids;
  thread_local std::vector<glm::dvec2> offsets;
  thread_local std::vector<char> mitred;
  for (size_t li = begin; li < end; ++li) {
    // Stochastic simplification (simplify.cpp): left out, or widened.
    double widthScale = 1.0, contrast = 1.0;
    if (simplified) {
      widthScale = simplification->scale[li];
      if (!(widthScale > 0.0)) continue;
      contrast = std::sqrt(double(simplification->lambda[li]));
    }
    const double halfT = 0.5 * wire.thickness * widthScale;
    const size_t a = L.starts[li], b = std::min<size_t>(L.starts[li + 1], L.points.size());
    // Repeated points make zero-length segments: drop them here, so that the segments on either
    // side still meet in a mitred joint.
    ids.clear();
    for (size_t k = a; k < b; ++k) {
      if (!ids.empty() && L.points[k] == L.points[ids.back()]) {
        ++counts.zeroLength;
        continue;
      }
      ids.push_back(k);
    }
    if (ids.size() < 2) continue;
    const size_t nseg = ids.size() - 1;
    // Closed: a loop of three segments or more back to its first point (A, B, A goes out and
    // back: two free ends, both at A).
    const bool closed = nseg > 2 && L.points[ids.front()] == L.points[ids.back()];
    segs.assign(nseg, SegScreen{});
    for (size_t j = 0; j < nseg; ++j) {
      SegScreen& s = segs[j];
      const glm::dvec3 &w0 = L.points[ids[j]], &w1 = L.points[ids[j + 1]];
      if (!finite3(w0) || !finite3(w1)) {
        ++counts.rejected;
        s.freesNeighbours = true;
        continue;
      }
      glm::dvec3 e0 = view.toEye(w0), e1 = view.toEye(w1);
      if (!finite3(e0) || !finite3(e1) || e0 == e1) {
        ++counts.zeroLength;
        s.freesNeighbours = !finite3(e0) || !finite3(e1);  // overflowed in eye space: as a non-finite point
        continue;
      }
      ++counts.segments;
      s.tangent = glm::normalize(e1 - e0);
      double d0 = -e0.z, d1 = -e1.z;
      if ((d0 < nearP && d1 < nearP) || (d0 > farP && d1 > farP)) {
        ++counts.clipped;
        continue;
      }
      // Clip to [near, far] along the segment.
      auto clipEnd = [&](glm::dvec3& p, double& d, const glm::dvec3& q, double dq, bool& flag) {
        // (The cut point's z is set to the plane's: interpolated, it can miss it by the far
        // end's rounding, which projectScaled's scale would then carry into the width.)
        if (d < nearP) {
          p = p + (nearP - d) / (dq - d) * (q - p);
          d = nearP;
          p.z = -nearP;
          flag = true;
        } else if (d > farP) {
          p = p + (farP - d) / (dq - d) * (q - p);
          d = farP;
          p.z = -farP;
          flag = true;
        }
      };
      const glm::dvec3 o0 = e0, o1 = e1;
      clipEnd(e0, d0, o1, d1, s.clipped0);
      clipEnd(e1, d1, o0, -o0.z, s.clipped1);
      // Cut to a point: one end moved onto a plane the other end lies on (a straight segment off
      // the plane meets it in one point), nothing of it between the planes.
      if ((s.clipped0 || s.clipped1) && d0 == d1) {
        ++counts.clipped;
        continue;
      }
      s.d0 = d0;
      s.d1 = d1;
      // (What several of the quantities below share is formed once: the ends' scales and
      // distances, the unit axis.)
      s.p0 = view.projectScaled(e0, s.k0);
      s.p1 = view.projectScaled(e1, s.k1);
      s.l0 = glm::length(e0), s.l1 = glm::length(e1);
      s.unitAxis = wireUnitAxis(e1 - e0);
      // A width in pixels is the user's; a world thickness is the cylinder's outline in the
      // perspective image (wireWidthFactor: off the view axis it is wider than r f / d).
      const double widen = wire.thicknessInPixels ? 1.0 : wireWidthFactor(view, e0, e1, s.l0, s.l1);
      s.w0 = wire.thicknessInPixels ? halfT * ps.pixelScale : halfT * s.k0 * widen;
      s.w1 = wire.thicknessInPixels ? halfT * ps.pixelScale : halfT * s.k1 * widen;
      s.e0 = e0, s.e1 = e1;
      const glm::dvec2 dv = s.p1 - s.p0;
      s.length = glm::length(dv);
      // Widths are stored as floats: one that rounds to 0 or overflows draws nothing.
      if (!std::isfinite(s.length) || !(float(s.w0) > 0) || !(float(s.w1) > 0) || !std::isfinite(float(s.w0)) ||
          !std::isfinite(float(s.w1)) || !std::isfinite(float(s.d1)) || !std::isfinite(float(s.d0))) {
        ++counts.clipped;
        s.freesNeighbours = true;
        continue;
      }
      s.endOn = s.length < std::max(s.w0, s.w1);
      if (!s.endOn) s.nrm = glm::dvec2(-dv.y, dv.x) * (1.0 / s.length);
      s.valid = true;
    }
    // Joint offsets: vertex j joins segment j-1 and j; a closed loop's vertex 0 and vertex nseg
    // are one joint, of its last segment and its first, with the same offset in both.
    offsets.assign(nseg + 1, glm::dvec2(0));
    mitred.assign(nseg + 1, 0);
    auto mitre = [&](const SegScreen& p, const SegScreen& q, glm::dvec2& offset) {
      if (!p.valid || !q.valid || p.endOn || q.endOn || p.clipped1 || q.clipped0) return false;
      const glm::dvec2 m = p.nrm + q.nrm;
      const double ml = glm::length(m);
      if (!(ml > 1e-6)) return false;
      const glm::dvec2 mh = m / ml;
      const double c = glm::dot(mh, q.nrm);
      if (!(c > 1.0 / kMitreLimit)) return false;
      offset = mh * (q.w0 / c);
      return true;
    };
    for (size_t j = 1; j < nseg; ++j) mitred[j] = mitre(segs[j - 1], segs[j], offsets[j]);
    if (closed && mitre(segs[nseg - 1], segs[0], offsets[0])) {
      offsets[nseg] = offsets[0];
      mitred[0] = mitred[nseg] = 1;
    }
    // Dashed hidden lines: where the pattern stands at each segment's start, from the screen arc
    // length of the polyline before it: segments off screen count too, so the pattern does not
    // jump as they come into view; a segment cut by the near or far plane counts its part
    // between them, and one wholly beyond them or degenerate counts nothing. Around a closed
    // polyline whose seam shows (its first and last segments kept) the pattern is scaled to
    // the whole number of periods nearest its length (dashes and gaps longer or shorter on
    // screen, by at most a quarter from two periods up), so that the last dash runs on into the
    // first at the seam instead of a piece of one meeting a whole one.
    const double dashPeriod = slot.hidden.dash + slot.hidden.gap;
    double dashScale = 1.0;  // pixels of the pattern a pixel of the screen
    if (out.dashPattern && closed && dashPeriod > 0.0 && segs.front().valid && segs.back().valid) {
      double loop = 0.0;
      for (const SegScreen& s : segs)
        if (s.valid) loop += s.length;
      const double periods = std::round(loop / dashPeriod), scale = periods * dashPeriod / loop;
      if (periods >= 1.0 && std::isfinite(periods) && std::isfinite(scale) && scale > 0.0) dashScale = scale;
    }
    double arc = 0.0;
    const std::uint32_t tag = tagBase + std::uint32_t(li);
    size_t pieces = 0;
    for (const SegScreen& s : segs) pieces += s.valid;
    for (size_t j = 0; j < nseg; ++j) {
      const SegScreen& s = segs[j];
      if (!s.valid) continue;
      const double arcHere = arc;
      if (out.dashPattern) arc = std::fmod(arc + s.length * dashScale, dashPeriod);  // (finite: checked above)
      SegmentPrim sp;
      sp.p0 = s.p0;
      sp.p1 = s.p1;
      sp.w0 = float(s.w0);
      sp.w1 = float(s.w1);
      // The world radius at each end (a pixel thickness turned into world units at its depth),
      // and the axis: the polyline, or one radius nearer when the wire rests on a surface.
      const double r0 = wire.thicknessInPixels ? s.w0 / s.k0 : halfT;
      const double r1 = wire.thicknessInPixels ? s.w1 / s.k1 : halfT;
      // Depth across the wire: how far its round surface stands in front of the axis along
      // the view axis (wireDepthScale: more than a radius where the wire slants towards the
      // eye). Seen end-on, what shows is its end's sphere: one radius. (Near a free end that
      // faces the eye the ray meets the end before the slanting body, so there the model stands
      // up to (scale - 1) r too far forward; keeping one radius at such ends, ramped along the
      // segment, measured worse: torus70k 1.63e-3 -> 1.83e-3 RGBA RMS. docs/abuffer.md.)
      // The scale ramps to 1 as the segment nears end-on (screen length from two half widths
      // down to one), so that its depth does not jump by up to (kMaxWireDepthScale - 1) r as it
      // turns end-on while the camera moves.
      const double towardEndOn = s.endOn ? 0.0 : std::clamp(s.length / std::max(s.w0, s.w1) - 1.0, 0.0, 1.0);
      sp.r0 = float(r0 * (1.0 + (wireDepthScale(view, s.e0, s.l0, s.unitAxis) - 1.0) * towardEndOn));
      sp.r1 = float(r1 * (1.0 + (wireDepthScale(view, s.e1, s.l1, s.unitAxis) - 1.0) * towardEndOn));
      sp.d0 = float(wire.restsOnSurface ? std::max(nearP, s.d0 - r0) : s.d0);
      sp.d1 = float(wire.restsOnSurface ? std::max(nearP, s.d1 - r1) : s.d1);
      sp.tag = tag;
      sp.shader = shader;
      sp.flags = pieces > 1 ? kSegmentMayMerge : 0;  // one piece has nothing to merge with
      if (s.endOn) {
        sp.flags |= kSegmentEndOn;
        sp.o0 = sp.o1 = glm::vec2(0.0f);
      } else {
        // Round ends: a half disc at a free end of the polyline (not at a joint, not where the
        // near or far plane cut the segment). An end whose neighbour was dropped for a
        // non-finite point beyond it or a width that rounds to nothing is free too; one whose
        // neighbour a plane took lies on that plane or beyond it: a cut, square.
        const bool freeStart = closed ? segs[j > 0 ? j - 1 : nseg - 1].freesNeighbours : j == 0 || segs[j - 1].freesNeighbours;
        const bool freeEnd = closed ? segs[j + 1 < nseg ? j + 1 : 0].freesNeighbours : j + 1 == nseg || segs[j + 1].freesNeighbours;
        if (wire.roundEnds && freeStart && !s.clipped0) sp.flags |= kSegmentCap0;
        if (wire.roundEnds && freeEnd && !s.clipped1) sp.flags |= kSegmentCap1;
        sp.o0 = glm::vec2(mitred[j] ? offsets[j] : s.nrm * s.w0);
        sp.o1 = glm::vec2(mitred[j + 1] ? offsets[j + 1] : s.nrm * s.w1);
        if (mitred[j] || mitred[j + 1]) {
          // A mitre that folds the polygon falls back to square ends.
          if (!segmentPolygonConvex(sp)) {
            sp.o0 = glm::vec2(s.nrm * s.w0);
            sp.o1 = glm::vec2(s.nrm * s.w1);
          }
        }
      }
      // Nothing of it inside the image: dropped.
      const double reach = segmentReach(sp);
      if (std::max(s.p0.x, s.p1.x) + reach <= 0 || std::min(s.p0.x, s.p1.x) - reach >= view.width ||
          std::max(s.p0.y, s.p1.y) + reach <= 0 || std::min(s.p0.y, s.p1.y) - reach >= view.height) {
        ++counts.clipped;
        continue;
      }
      if (s.endOn) ++counts.endOn;  // (drawn as its disc: counted once it is kept)
      // Tangents at the ends: averaged with the neighbour at a joint, so a smooth curve of
      // straight segments shades smoothly, like one bent wire.
      auto jointTangent = [&](size_t jv, const glm::dvec3& own) {
        // An end a plane moved is a cut, not the joint (which lies beyond the plane, unseen):
        // its own tangent, as the mitre loop leaves it square.
        if ((jv == j && s.clipped0) || (jv == j + 1 && s.clipped1)) return own;
        const SegScreen* other = nullptr;
        if (jv == j) other = j > 0 ? &segs[j - 1] : closed ? &segs[nseg - 1] : nullptr;
        if (jv == j + 1) other = j + 1 < nseg ? &segs[j + 1] : closed ? &segs[0] : nullptr;
        if (!other || !other->valid) return own;
        const glm::dvec3 sum = own + other->tangent;
        const double l = glm::length(sum);
        return l > 1e-6 ? sum / l : own;
      };
      SegmentShading sh;
      const glm::dvec3 t0 = jointTangent(j, s.tangent), t1 = jointTangent(j + 1, s.tangent);
      sh.t0 = glm::vec3(t0);
      sh.t1 = glm::vec3(t1);
      SegmentColours cl;
      cl.c0 = hasColours ? safeColour(L.colours[ids[j]]) : glm::vec3(1.0f);
      cl.c1 = hasColours ? safeColour(L.colours[ids[j + 1]]) : glm::vec3(1.0f);
      if (contrast < 1.0 && hasColours && simplification->meanColour.size() == simplification->scale.size()) {
        const glm::vec3 mean = simplification->meanColour[li];
        cl.c0 = mean + (cl.c0 - mean) * float(contrast);
        cl.c1 = mean + (cl.c1 - mean) * float(contrast);
      }
      if (slot.kind == ShaderSlot::Kind::WirePlain) {
        cl.c0 *= slot.colour;
        cl.c1 *= slot.colour;
        sp.flags |= kSegmentPreshaded;
      } else if (preshadeMaps && t0 == t1) {
        const glm::vec3 radiance = slot.wireTables->lookup(t0, view.cx, view.cy);
        cl.c0 *= radiance;
        cl.c1 *= radiance;
        sp.flags |= kSegmentPreshaded;
      }
      out.prims[out.count] = sp;
      out.shading[out.count] = sh;
      if (out.colours) out.colours[out.count] = cl;
      else if (keepsColours) noRoomForColours(wire);
      if (out.dashPattern) out.dashPattern[out.count] = glm::vec2(float(arcHere), float(dashScale - 1.0));
      ++out.count;
    }
  }
  // The scratch grows to the longest polyline a thread has set up (about 250 bytes a point; ids
  // holds its points): past 4,096 points it is given back rather than kept for the process's life.
  if (ids.capacity() > 4096) {
    std::vector<SegScreen>().swap(segs);
    std::vector<size_t>().swap(ids);
    std::vector<glm::dvec2>().swap(offsets);
    std::vector<char>().swap(mitred);
  }
}

}  // namespace wf

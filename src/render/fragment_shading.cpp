// Shading of one fragment (render/pipeline.h): wires through the pseudo-reflectance map or the
// exact cylinder integral, plain and depth-cued wires; surfaces by interpolating their triangle
// (perspective-correct) and shadeSurfaceFragment (surface_shading.cpp).
#include "render/pipeline.h"
#include "render/rasterize.h"

#include "shading/cylinder_lobe.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <vector>

namespace wf {

glm::dvec3 chromeRadiance(const EnvironmentMap& env, const glm::dvec3& refl, const glm::dvec3& n,
                          const glm::dvec3& v) {
  const glm::dvec3 r = 2.0 * glm::dot(n, v) * n - v;
  return refl * glm::dvec3(env.lookup(r));
}

const EnvironmentMap& defaultEnvironment() {
  static const EnvironmentMap env = EnvironmentMap::mountainScene(512);
  return env;
}

namespace {
// Unclamped barycentrics of eye point P on the triangle's plane.
glm::dvec3 barycentricOf(const TriangleAttributes& ta, const glm::dvec3& P) {
  const glm::dvec3 v = P - ta.p0;
  const double d20 = glm::dot(v, ta.e1), d21 = glm::dot(v, ta.e2);
  const double b1 = (ta.d11 * d20 - ta.d01 * d21) * ta.invDen;
  const double b2 = (ta.d00 * d21 - ta.d01 * d20) * ta.invDen;
  return {1.0 - b1 - b2, b1, b2};
}

// World-space dP/du, dP/dv of a triangle from its positions and (u, v) (zero when the (u, v)
// are degenerate).
void triangleUvGradient(const TriangleMesh& mesh, const glm::uvec3& tri, glm::dvec3& du, glm::dvec3& dv) {
  const glm::dvec3 e1 = mesh.positions[tri.y] - mesh.positions[tri.x];
  const glm::dvec3 e2 = mesh.positions[tri.z] - mesh.positions[tri.x];
  const glm::dvec2 t1 = mesh.uvs[tri.y] - mesh.uvs[tri.x], t2 = mesh.uvs[tri.z] - mesh.uvs[tri.x];
  const double det = t1.x * t2.y - t2.x * t1.y;
  if (!(std::abs(det) > 0) || !std::isfinite(det)) {
    du = dv = glm::dvec3(0.0);
    return;
  }
  du = (e1 * t2.y - e2 * t1.y) / det;
  dv = (e2 * t1.x - e1 * t2.x) / det;
  if (!std::isfinite(glm::dot(du, du)) || !std::isfinite(glm::dot(dv, dv))) du = dv = glm::dvec3(0.0);
}

template <class V>
bool finiteVec(const V& v) {
  for (int k = 0; k < V::length(); ++k)
    if (!std::isfinite(double(v[k]))) return false;
  return true;
}

// b0 a + b1 b + b2 c over the vertices whose value is finite, weights renormalised (a vertex
// with a NaN attribute must not spoil the whole triangle: 0 x NaN is NaN); the plain mean of the
// finite ones where their weights vanish; false when no vertex is finite.
template <class V>
bool mixFinite(const V& a, const V& b, const V& c, double b0, double b1, double b2, V& out) {
  // The per-fragment path: one check of the mix (a NaN or Inf vertex makes it non-finite even
  // at weight 0, since 0 x NaN and 0 x Inf are NaN); the vertices are examined only then.
  out = b0 * a + b1 * b + b2 * c;
  if (finiteVec(out)) return true;
  const bool fa = finiteVec(a), fb = finiteVec(b), fc = finiteVec(c);
  if (!fa && !fb && !fc) return false;
  double w0 = fa ? b0 : 0.0, w1 = fb ? b1 : 0.0, w2 = fc ? b2 : 0.0;
  double ws = w0 + w1 + w2;
  if (!(ws > 0)) w0 = fa, w1 = fb, w2 = fc, ws = w0 + w1 + w2;
  out = (w0 / ws) * (fa ? a : V(0.0)) + (w1 / ws) * (fb ? b : V(0.0)) + (w2 / ws) * (fc ? c : V(0.0));
  return finiteVec(out);
}
}  // namespace

glm::dvec2 uvOnPlane(const PreparedScene& ps, const TriangleAttributes& ta, const glm::dvec3& P) {
  const TriangleMesh& mesh = ps.scene->surfaces[ta.surface].mesh;
  if (mesh.uvs.size() != mesh.positions.size()) return glm::dvec2(0.0);
  const glm::uvec3 tri = mesh.triangles[ta.triangle];
  const glm::dvec3 b = barycentricOf(ta, P);
  const glm::dvec2 uv = b.x * mesh.uvs[tri.x] + b.y * mesh.uvs[tri.y] + b.z * mesh.uvs[tri.z];
  // Not finite (a NaN uv, or beyond double range): an unbounded footprint, which the textures
  // read as their mean.
  return std::isfinite(uv.x) && std::isfinite(uv.y) ? uv : glm::dvec2(INFINITY);
}

SurfaceSample interpolateTriangle(const PreparedScene& ps, const TriangleAttributes& ta, const glm::dvec3& P,
                                  const glm::dvec3& V, bool tangentAndUv, bool derivatives) {
  // Barycentrics of the eye-space point P (on the triangle's plane under the fragment), clamped
  // into the triangle: perspective-correct by construction.
  const glm::dvec3 bu = barycentricOf(ta, P);
  double b0 = std::max(bu.x, 0.0), b1 = std::max(bu.y, 0.0), b2 = std::max(bu.z, 0.0);
  const double bs = b0 + b1 + b2;
  if (bs > 0 && std::isfinite(bs)) b0 /= bs, b1 /= bs, b2 /= bs;
  else b0 = 1, b1 = b2 = 0;
  const TriangleMesh& mesh = ps.scene->surfaces[ta.surface].mesh;
  const glm::uvec3 tri = mesh.triangles[ta.triangle];
  const size_t nv = mesh.positions.size();
  SurfaceSample out;
  out.barycentric = glm::dvec3(b0, b1, b2);
  auto mix3 = [&](const auto& a, const auto& b, const auto& c) { return b0 * a + b1 * b + b2 * c; };
  glm::dvec3 N = glm::cross(ta.e1, ta.e2);  // the face normal, unless the mesh has usable vertex normals
  if (glm::dvec3 n; mesh.normals.size() == nv &&
                    mixFinite(mesh.normals[tri.x], mesh.normals[tri.y], mesh.normals[tri.z], b0, b1, b2, n) &&
                    glm::dot(n, n) > 0)
    N = ps.view.eyeFromWorld * n;
  const double nl = glm::length(N);
  N = (nl > 0 && std::isfinite(nl)) ? N / nl : V;
  if (glm::dot(N, V) < 0) N = -N, out.flipped = true;  // two-sided: the side facing the viewer
  out.normal = N;
  if (tangentAndUv && mesh.tangents.size() == nv) {
    glm::dvec3 T(0.0);
    if (mixFinite(mesh.tangents[tri.x], mesh.tangents[tri.y], mesh.tangents[tri.z], b0, b1, b2, T)) T = ps.view.eyeFromWorld * T;
    const double tl = glm::length(T);
    out.tangent = (tl > 0 && std::isfinite(tl)) ? T / tl : glm::dvec3(0.0);
  }
  if (tangentAndUv && mesh.uvs.size() == nv && !mixFinite(mesh.uvs[tri.x], mesh.uvs[tri.y], mesh.uvs[tri.z], b0, b1, b2, out.uv))
    out.uv = glm::dvec2(0.0);
  if (derivatives) {
    // The mesh's own derivatives when all three vertices have finite ones; else the triangle's
    // (u, v) gradient; else its tangents for dS/du.
    glm::dvec3 du(0.0), dv(0.0);
    auto allFinite = [&](const std::vector<glm::dvec3>& a) {
      return a.size() == nv && finiteVec(a[tri.x]) && finiteVec(a[tri.y]) && finiteVec(a[tri.z]);
    };
    if (allFinite(mesh.derivU) && allFinite(mesh.derivV)) {
      du = mix3(mesh.derivU[tri.x], mesh.derivU[tri.y], mesh.derivU[tri.z]);
      dv = mix3(mesh.derivV[tri.x], mesh.derivV[tri.y], mesh.derivV[tri.z]);
    } else if (mesh.uvs.size() == nv) {
      triangleUvGradient(mesh, tri, du, dv);
    }
    if (glm::dot(du, du) == 0 && glm::dot(dv, dv) == 0 && mesh.tangents.size() == nv)
      mixFinite(mesh.tangents[tri.x], mesh.tangents[tri.y], mesh.tangents[tri.z], b0, b1, b2, du);
    out.derivU = finiteOrZero(ps.view.eyeFromWorld * du);
    out.derivV = finiteOrZero(ps.view.eyeFromWorld * dv);
  }
  if (mesh.colours.size() == nv)
    out.colour = safeColour(mesh.colours[tri.x] * float(b0) + mesh.colours[tri.y] * float(b1) + mesh.colours[tri.z] * float(b2));
  return out;
}

SurfaceSample interpolateSurface(const PreparedScene& ps, std::uint32_t i, double x, double y) {
  if (ps.isSegment(i)) return {};
  const TrianglePrim& t = ps.triangles[i];
  const double depth = ps.view.depthFromKey(t.depthKeyAt(x, y));
  const glm::dvec3 P = ps.view.eyePoint(x, y, depth);
  return interpolateTriangle(ps, ps.triangleAttributes[i], P, ps.view.viewVector(P), true);
}

glm::vec3 shadeFragment(const PreparedScene& ps, std::uint32_t i, double x, double y, double depth) {
  if (!ps.isSegment(i)) {
    const ViewTransform& view = ps.view;
    const glm::dvec3 P = view.eyePoint(x, y, depth);
    return shadeSurfaceFragment(ps, i, x, y, P, view.viewVector(P));
  }
  const SegmentPrim& sp = ps.segmentOf(i);
  const SegmentShading& sh = ps.segmentShading[i - ps.triangles.size()];
  // Where along the wire: the screen parameter of the point's projection onto the axis, made
  // perspective-correct (1/d is linear on screen), clamped to the segment.
  const SegmentFrame frame(sp);
  double s = std::clamp(frame.t(x, y), 0.0, 1.0);
  if (ps.view.perspective && sp.d0 != sp.d1) {
    const double a = (1.0 - s) / double(sp.d0), b = s / double(sp.d1);
    s = a + b > 0 ? b / (a + b) : s;
  }
  // (Without the colours every segment's are 1 at both ends, and mix(1, 1, s) = fl(fl(1 - s) + s)
  // is exactly 1: fl(1 - s) is within 2^-25 of 1 - s for s in [0, 1], so the sum is within 2^-25
  // of 1 and rounds to 1, a tie at 1 - 2^-25 to even, which is 1.)
  glm::vec3 c(1.0f);
  if (!ps.segmentColours.empty()) {
    const SegmentColours& cl = ps.segmentColours[i - ps.triangles.size()];
    c = glm::mix(cl.c0, cl.c1, float(s));
  }
  if (sp.flags & kSegmentPreshaded) return c;
  const ShaderSlot& slot = ps.shaders[sp.shader];
  switch (slot.kind) {
    case ShaderSlot::Kind::WirePlain:
      return slot.colour * c;
    case ShaderSlot::Kind::WireDepthCued: {
      // The paper's baseline (§3): lines dimmer as they recede, full at the nearest wire depth,
      // 10% at the farthest.
      const double range = ps.cueFar - ps.cueNear;
      const double t = range > 0 ? std::clamp((depth - ps.cueNear) / range, 0.0, 1.0) : 0.0;
      return slot.colour * c * float(1.0 - 0.9 * t);
    }
    default: {
      const glm::dvec3 T = glm::mix(glm::dvec3(sh.t0), glm::dvec3(sh.t1), s);
      if (ps.path == ShadingPath::Maps && slot.wireTables) return slot.wireTables->lookup(T, x, y) * c;
      // Closed and exact paths: the cylinder integral at this fragment's own view vector.
      const glm::dvec3 P = ps.view.eyePoint(x, y, depth);
      return glm::vec3(cylinderRadianceClosedSanitized(T, ps.view.viewVector(P), slot.phong, ps.eyeLights, slot.lobe.get())) * c;
    }
  }
}

// ---- the A-buffer's subpixel depths of a wire (PreparedFragmentSource) ------------------------

std::uint64_t PreparedFragmentSource::nextSerial() {
  static std::atomic<std::uint64_t> serial{0};
  return ++serial;
}

void PreparedFragmentSource::fillWireDepthBasis(std::uint32_t prim, WireDepthBasis& b) const {
  const ViewTransform& v = ps_.view;
  const SegmentPrim& s = ps_.segmentOf(prim);
  const SegmentFrame fr(s);
  SurfaceDepth& d = b.depth;
  d = SurfaceDepth{};
  d.perspective = v.perspective;
  d.nearPlane = float(v.nearPlane);
  d.kind = SurfaceDepth::Kind::Wire;
  d.round = ps_.wireDepth == WireDepth::Round;
  const SegmentEndKeys keys(v, s);
  const double k0 = d.round ? keys.axis(0.0) : keys.front(0.0);
  const double k1 = d.round ? keys.axis(1.0) : keys.front(1.0);
  d.k0 = float(k0), d.kx = float(k1 - k0);
  b.ax = fr.ax, b.ay = fr.ay;
  b.hasLength = fr.length > 0;
  if (b.hasLength) {
    b.ux = fr.ux, b.uy = fr.uy, b.nx = fr.nx, b.ny = fr.ny;
    d.tx = float(fr.ux), d.ty = float(fr.uy);
    d.lx = float(fr.nx), d.ly = float(fr.ny);
    d.length = float(fr.length);
    d.tmax = 1.0f;
  } else {  // seen exactly end-on: t is the x offset from its end point, held at 0
    d.tx = 1.0f, d.ty = 0.0f;
    d.lx = 0.0f, d.ly = 1.0f;
    d.length = 1.0f;
    d.tmax = 0.0f;
  }
  d.w0 = s.w0, d.dw = s.w1 - s.w0, d.r0 = s.r0, d.dr = s.r1 - s.r0;
  const SegmentTilt tilt(v, s, fr);
  d.tl = float(tilt.lateral), d.ta = float(tilt.along0), d.tt = float(tilt.alongT);
  d.s0 = float(tilt.shift0), d.st = float(tilt.shiftT);
  d.lo = 0.0f, d.hi = INFINITY;
  d.onSurface = ps_.shaderOf(prim).restsOnSurface;
  b.axis0 = keys.axis(0.0), b.axis1 = keys.axis(1.0);
  d.capsule = false;
  if (segmentUsesCapsule(ps_, prim)) {
    const WireCapsule c(v, s, segmentWidthInPixels(ps_, prim));
    if (c.valid) {
      d.capsule = true;
      b.endMargin = c.endMargin(s);
      b.length = fr.length;
      b.e0 = c.e0;
      d.cu0 = float(c.u.x), d.cu1 = float(c.u.y), d.cu2 = float(c.u.z);
      d.clen = float(c.length), d.cr0 = float(c.r0), d.cdr = float(c.r1 - c.r0);
      double k, rho0, h0, h1;
      d.cbody = c.coneBand(k, rho0, h0, h1);
      if (d.cbody) d.ck = float(k), d.crho0 = float(rho0), d.ch0 = float(h0), d.ch1 = float(h1);
    }
  }
}

void PreparedFragmentSource::capsuleRay(const WireDepthBasis& b, int x, int y, SurfaceDepth& d) const {
  const ViewTransform& v = ps_.view;
  const double tu = b.hasLength ? (x + 0.5 - b.ax) * b.ux + (y + 0.5 - b.ay) * b.uy : 0.0;
  // Along the body the model is the solid's depth within kCapsuleSlack radii: the solid only
  // near the ends (the pixel's samples lie within 0.71 pixels of its centre).
  if (!WireCapsule::nearEnd(tu, b.length, b.endMargin, WireCapsule::kPixelSpread)) {
    d.capsule = false;
    return;
  }
  const double t = std::clamp(tu, 0.0, 1.0);
  const double z = v.depthFromKey(b.axis0 + (b.axis1 - b.axis0) * t);
  if (!(z > 0.0) || !std::isfinite(z)) {
    d.capsule = false;  // (the model's depth then)
    return;
  }
  d.zref = float(z);
  if (v.perspective) {
    const double X = (x - v.cx) / v.focal, Y = -(y - v.cy) / v.focal;
    d.cw0 = float(X * z - b.e0.x), d.cw1 = float(Y * z - b.e0.y), d.cw2 = float(-z - b.e0.z);
    d.cwx = float(z / v.focal), d.cwy = float(-z / v.focal);
    d.cd0 = float(X), d.cd1 = float(Y), d.cd2 = -1.0f;
    d.cdx = float(1.0 / v.focal), d.cdy = float(-1.0 / v.focal);
  } else {
    d.cw0 = float((x - v.cx) / v.orthoScale - b.e0.x), d.cw1 = float(-(y - v.cy) / v.orthoScale - b.e0.y);
    d.cw2 = float(-z - b.e0.z);
    d.cwx = float(1.0 / v.orthoScale), d.cwy = float(-1.0 / v.orthoScale);
    d.cd0 = 0.0f, d.cd1 = 0.0f, d.cd2 = -1.0f, d.cdx = 0.0f, d.cdy = 0.0f;
  }
}

namespace {
constexpr std::size_t kBasisEntries = 2048;  // (a power of two: the index is a hash's top bits)
static_assert(std::has_single_bit(kBasisEntries));
}

std::size_t PreparedFragmentSource::cacheBytesPerThread() { return kBasisEntries * sizeof(WireDepthBasis); }

const PreparedFragmentSource::WireDepthBasis& PreparedFragmentSource::wireDepthBasis(std::uint32_t prim) const {
  // Direct-mapped, per thread (a resolving thread asks of the segments near the pixels it
  // resolves, and the same segment again in the next pixels), on the heap: 2048 entries of
  // sizeof(WireDepthBasis) (under 320 bytes with the solid's fields: 640 KiB a thread, made on
  // its first wire). A tile of dense fur asks of more segments than 256 entries held: on the
  // 700,000-hair torus 3.06M fills of 9.99M asks with 256, 1.86M with 1024, 0.71M (about one a
  // segment shown) with 2048. An entry holds the source's serial, so a later render never reads
  // an earlier render's segment of the same number. The reference returned is good until the
  // thread's next call (the callers copy what they need from it at once).
  static_assert(sizeof(WireDepthBasis) <= 320);
  thread_local std::vector<WireDepthBasis> cache;
  if (cache.empty()) cache.resize(kBasisEntries);
  WireDepthBasis& b = cache[std::uint32_t(prim * 2654435761u) >> (32 - std::countr_zero(kBasisEntries))];
  if (b.serial != serial_ || b.prim != prim) {
    fillWireDepthBasis(prim, b);
    b.serial = serial_;
    b.prim = prim;
  }
  return b;
}

}  // namespace wf

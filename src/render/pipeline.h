// The A-buffer's data path, one stage per file, in the order render() (renderer.cpp) calls them:
//
//   scene -> camera          view_setup.cpp      chooseCamera: the scene's camera, or one framing it
//         -> tables          shading_tables.cpp  prepareShaders: the shading tables the scene needs
//         -> simplification  simplify.cpp        planSimplification: which hairs of dense fur to draw
//                                                (RenderOptions::simplify; off by default)
//         -> primitives      prepare_scene.cpp   prepareScene: the stages above, then clipping and
//                            triangle_setup.cpp    projection of triangles and wire segments into
//                            segment_setup.cpp     convex screen polygons
//         -> bins            binning.cpp         countBins, binBands, binPrimitives: primitives into screen
//                                                tiles, a band of tile rows at a time
//         -> fragments       rasterize.h         rasterizePolygon: exact area, mask, depth per pixel
//         -> resolve         abuffer/abuffer.cpp TileABuffer: depth order, coverage, tails
//         -> image
//
// Shading of a fragment (fragment_shading.cpp, surface_shading.cpp) is deferred: the resolve
// asks for it (FragmentSource) only for fragments that show, merge or join a tail. The
// brute-force reference (reference_renderer.cpp) and the benchmarks' ray caster share every
// stage up to the bins. This header holds the data the stages hand each other.
//
// Wire segments follow the paper (§3): a polygon as thick as the wire, its narrow side across
// the screen direction of the segment and its long side joining the end points. Consecutive
// segments of a polyline share their joint edge (a mitre along the bisector), so the polygons
// abut exactly: no gap, no overlap, and the A-buffer merges the two pieces by their common tag.
// A mitre longer than kMitreLimit half-widths, or one that would fold a polygon, falls back to
// square ends. A segment whose screen length is less than its half width is seen (nearly) end-on and
// is drawn as the hull of its two end discs (16-gons of the discs' exact areas).
#pragma once

#include "abuffer/coverage_mask.h"
#include "abuffer/screen_polygon.h"
#include "core/hash.h"
#include "core/large_memory.h"  // allocateLarge, LargeAllocator
#include "core/numeric.h"
#include "core/timer.h"  // secondsSince, for the stages' timings
#include "render/renderer.h"
#include "shading/cylinder_lobe.h"
#include "shading/pseudo_reflectance_map.h"
#include "shading/reflectance_sphere.h"
#include "render/view_tables.h"

#include <glm/glm.hpp>
#include <tbb/task_arena.h>

#include <algorithm>
#include <type_traits>
#include <utility>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <new>
#include <optional>
#include <vector>

namespace wf {

inline constexpr double kMitreLimit = 4.0;

/// A vector whose resize() leaves trivially constructible elements uninitialised: the set-up
/// stage writes every element it keeps, and zeroing hundreds of megabytes first would cost as
/// much as the set-up itself (every first touch of a page is a fault). Large blocks come from
/// allocateLarge.
template <class T>
struct DefaultInitAllocator : LargeAllocator<T> {
  using value_type = T;
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  DefaultInitAllocator() = default;
  template <class U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};
template <class T>
using PodVector = std::vector<T, DefaultInitAllocator<T>>;

/// A triangle on screen: clipped to the near and far planes, a convex polygon of 3 to 5
/// vertices (PreparedScene::vertices) with a depth key plane. Its eye-space data for shading is
/// PreparedScene::triangleAttributes at the same index. Plain data (PodVector): no initialisers.
struct TrianglePrim {
  double qa, qb, qc;           ///< depth key = qa x + qb y + qc (1/d or d)
  float bbox[4];               ///< x0, y0, x1, y1 in pixels, clamped to the image
  float zlo, zhi;              ///< depth range of the polygon
  std::uint32_t firstVertex;   ///< into PreparedScene::vertices
  std::uint32_t tag;           ///< object id: pieces of one surface merge in the A-buffer
  std::uint16_t shader;        ///< into PreparedScene::shaders
  std::uint8_t vertexCount;
  bool mayMerge;               ///< false when the triangle is its surface's only piece
  double depthKeyAt(double x, double y) const { return qa * x + qb * y + qc; }
};

/// Eye-space data to interpolate over a triangle (perspective-correct by construction: the
/// barycentrics are those of the eye-space point under the fragment).
struct TriangleAttributes {
  glm::dvec3 p0, e1, e2;
  double d00, d01, d11, invDen;
  std::uint32_t surface, triangle;
};

/// A wire segment on screen, what the rasteriser reads (80 bytes; its polygon is made on demand,
/// segmentPolygon). The polygon (paper §3): corners p0 + o0, p1 + o1, p1 - o1, p0 - o0, where o
/// is the half width across the segment at a free end and the mitre at a joint (consecutive
/// segments store the same joint point and offset, so their polygons share the joint edge bit
/// for bit); half discs at round free ends; the hull of the two end discs when seen end-on.
/// Depth: the wire is the cylinder of radius r about the axis at view depths d0, d1 (after
/// near / far clipping). Plain data (PodVector): no initialisers.
struct SegmentPrim {
  glm::dvec2 p0, p1;           ///< screen end points of the axis
  glm::vec2 o0, o1;            ///< corner offsets at the two ends
  float w0, w1;                ///< half widths in pixels at the two ends
  float d0, d1;                ///< view depths of the axis at the two ends
  float r0, r1;                ///< depth radii at the two ends: the world radius times wireDepthScale, ramped to 1 towards end-on
  std::uint32_t tag;           ///< object id (the polyline): its pieces merge in the A-buffer
  std::uint32_t shader : 24;   ///< into PreparedScene::shaders (one per wire: up to kMaxShaders)
  std::uint32_t flags : 8;     ///< kSegment* bits
};
/// The most shader slots one render may have (a wire has its own; SegmentPrim::shader).
inline constexpr size_t kMaxShaders = size_t(1) << 24;
inline constexpr std::uint8_t kSegmentCap0 = 1;         ///< half disc at p0 (a round free end)
inline constexpr std::uint8_t kSegmentCap1 = 2;         ///< half disc at p1
inline constexpr std::uint8_t kSegmentEndOn = 4;        ///< shorter than its half width: the hull of its end discs
inline constexpr std::uint8_t kSegmentMayMerge = 8;     ///< its polyline has other pieces
inline constexpr std::uint8_t kSegmentPreshaded = 16;   ///< its colours hold the radiance at the ends

/// One of Liang and Barsky's four steps (below): the bound p t <= q narrows [ta, tb]; false
/// where it holds for no t (p = 0 and q < 0).
inline bool liangBarskyStep(double p, double q, double& ta, double& tb) {
  if (p == 0.0) return !(q < 0.0);
  const double r = q / p;
  if (p < 0.0) ta = std::max(ta, r);
  else tb = std::min(tb, r);
  return true;
}

/// The part [ta, tb] of the screen line p0 + t (p1 - p0), t in [0, 1], inside the rectangle
/// [rx0, rx1] x [ry0, ry1] (Liang and Barsky); false when none. The binning's clip of a hair to a
/// tile and the simplification's of a hair to the image (binning.cpp, simplify.cpp).
inline bool clipLineToRect(glm::dvec2 p0, glm::dvec2 p1, double rx0, double ry0, double rx1, double ry1, double& ta,
                           double& tb) {
  ta = 0.0;
  tb = 1.0;
  const double dx = p1.x - p0.x, dy = p1.y - p0.y;
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {p0.x - rx0, rx1 - p0.x, p0.y - ry0, ry1 - p0.y};
  for (int k = 0; k < 4; ++k)
    if (!liangBarskyStep(p[k], q[k], ta, tb)) return false;
  return ta <= tb;
}

// clipLineToRect's clip of a segment's axis to each tile of a block of tiles, each grown by g.
// Its four ratios (a division each) depend on the tile's column (the x bounds) or on its row (the
// y bounds) alone, so they are formed once per column and once per row and combined per tile in
// clipLineToRect's own order and comparisons: the same ta and tb to the bit, and the same
// refusals. (A tile's clip reads its column's two bounds and applies its row's two steps instead
// of forming four divisions; a long hair crosses a few columns and rows of a larger block.)
class TileClips {
 public:
  static constexpr int kMaxSpan = 64;  // columns or rows; wider blocks clip tile by tile
  /// False: the block is too wide to be held (clip each tile with clipLineToRect).
  bool init(const glm::dvec2& p0, const glm::dvec2& p1, int tile, double g, int tx0, int ty0, int tx1, int ty1) {
    if (tx1 - tx0 >= kMaxSpan || ty1 - ty0 >= kMaxSpan) return false;
    tx0_ = tx0, ty0_ = ty0;
    const double dx = p1.x - p0.x, dy = p1.y - p0.y;
    for (int tx = tx0; tx <= tx1; ++tx) {
      Column& c = col_[tx - tx0];
      c.ta = 0.0, c.tb = 1.0;
      const double rx0 = tx * tile - g, rx1 = (tx + 1) * tile + g;
      c.ok = liangBarskyStep(-dx, p0.x - rx0, c.ta, c.tb) && liangBarskyStep(dx, rx1 - p0.x, c.ta, c.tb);
    }
    for (int ty = ty0; ty <= ty1; ++ty) {
      Row& r = row_[ty - ty0];
      const double ry0 = ty * tile - g, ry1 = (ty + 1) * tile + g;
      r.p[0] = -dy, r.p[1] = dy;
      r.q[0] = p0.y - ry0, r.q[1] = ry1 - p0.y;
      for (int k = 0; k < 2; ++k) r.r[k] = r.p[k] == 0.0 ? 0.0 : r.q[k] / r.p[k];
    }
    return true;
  }
  /// clipLineToRect(p0, p1, the tile grown by g, ta, tb) for tile (tx, ty) of the block; where it
  /// refuses, ta and tb are left as they are here rather than as it leaves them.
  bool clip(int tx, int ty, double& ta, double& tb) const {
    const Column& c = col_[tx - tx0_];
    if (!c.ok) return false;
    ta = c.ta, tb = c.tb;
    const Row& r = row_[ty - ty0_];
    for (int k = 0; k < 2; ++k) {
      if (r.p[k] == 0.0) {
        if (r.q[k] < 0.0) return false;
        continue;
      }
      if (r.p[k] < 0.0) ta = std::max(ta, r.r[k]);
      else tb = std::min(tb, r.r[k]);
    }
    return ta <= tb;
  }

 private:
  struct Column {
    double ta, tb;  // after the x bounds
    bool ok;
  };
  struct Row {
    double p[2], q[2], r[2];  // the y bounds' steps
  };
  int tx0_ = 0, ty0_ = 0;
  Column col_[kMaxSpan];
  Row row_[kMaxSpan];
};

/// How far a segment's polygon reaches from its axis in pixels: mitres up to kMitreLimit half
/// widths, half discs up to pi / 2 half widths (their inner vertices sit outside the circle),
/// end-on discs a little over one. Every point the segment covers lies within it of the axis.
inline double segmentReach(const SegmentPrim& s) {
  // (float offsets squared in double cannot overflow: no need of hypot's care, or its cost)
  const double o0 = std::sqrt(double(s.o0.x) * s.o0.x + double(s.o0.y) * s.o0.y);
  const double o1 = std::sqrt(double(s.o1.x) * s.o1.x + double(s.o1.y) * s.o1.y);
  return std::max({o0, o1, 1.5708 * double(std::max(s.w0, s.w1))});
}

/// What shading a wire fragment needs, read only for fragments that survive to the resolve.
struct SegmentShading {
  glm::vec3 t0, t1;  ///< eye-space unit tangents at the two ends (averaged at joints)
};
/// A segment's colours at its ends: per-point colours; or, when kSegmentPreshaded, the radiance
/// there. Kept only when some wire of the scene needs them (wireKeepsColours); a segment's colour
/// is otherwise 1 at both ends, which interpolates to exactly 1.
struct SegmentColours {
  glm::vec3 c0, c1;
};

/// One way of shading: a surface material or a wire style, with the tables it reads.
struct ShaderSlot {
  enum class Kind { SurfacePhong, SurfaceChrome, SurfaceBurnished, WireShaded, WirePlain, WireDepthCued };
  Kind kind = Kind::SurfacePhong;
  PhongMaterial phong;
  glm::dvec3 chromeReflectance{0.9};
  glm::vec3 colour{1.0f};
  float opacity = 1.0f;          ///< the material's (surfaces) or the wire's opacity
  /// Shaded wire and burnished surfaces, map path (burnished: of the diffuse part when `split`).
  std::shared_ptr<WireTables> wireTables;
  /// Phong and chrome surfaces, map path (Phong: of the diffuse part when `split`).
  std::shared_ptr<SurfaceTables> surfaceTables;
  /// A colour map multiplies the diffuse part only: the tables above then hold the diffuse part
  /// and these the specular part (only then are they built).
  bool split = false;
  std::shared_ptr<WireTables> wireSpecular;
  std::shared_ptr<SurfaceTables> surfaceSpecular;
  /// Shaded wire and burnished surfaces, closed path: the lobe table of the material's exponent.
  std::shared_ptr<const CylinderLobeTable> lobe;
  /// Surfaces: the material (textures, bumps, grooves, grain) and what its fragments need.
  const Material* material = nullptr;
  bool needsUv = false;          ///< colour map, bump map, grooves along u or v, grain along u or v
  bool needsDerivatives = false; ///< bump map, grain along u or v
  /// Shading varies inside a pixel (textures, bumps, grooves): the reference renderer shades
  /// such primitives at every sample instead of once per pixel.
  bool variesInPixel = false;
  glm::dvec3 axisPoint{0.0}, axisDirection{0.0, 0.0, 1.0};  ///< radial / circular grain, eye space
  bool holdout = false;  ///< surfaces: hides, adds no colour (SceneSurface::holdout)
  HiddenLines hidden;    ///< wires: where surfaces hide them (SceneWire::hidden)
  bool restsOnSurface = false;  ///< wires: SceneWire::restsOnSurface (SurfaceDepth::onSurface)
  bool widthInPixels = false;   ///< wires: SceneWire::thicknessInPixels (the half widths are the user's, not widened: WireCapsule)
};

/// The weight of a dashed hidden line at arc length s (pixels from the pattern's start): the
/// share of [s - 0.5, s + 0.5] inside dashes of `dash` pixels separated by gaps of `gap`
/// (a one-pixel box filter along the wire, so a dash's ends are antialiased).
inline float dashCoverage(double s, double dash, double gap) {
  const double period = dash + gap;
  if (!(dash > 0.0) || !(period > 0.0) || !std::isfinite(s)) return 1.0f;
  auto on = [&](double x) {  // measure of dashes in [0, x]
    const double k = std::floor(x / period);
    return k * dash + std::min(x - k * period, dash);
  };
  return float(std::clamp(on(s + 0.5) - on(s - 0.5), 0.0, 1.0));
}

/// Everything the stages after set-up read. Primitives are numbered triangles first, then
/// segments: index i < triangles.size() is triangle i, otherwise segment i - triangles.size().
struct PreparedScene {
  const Scene* scene = nullptr;
  ViewTransform view;
  LightRig eyeLights;  ///< canonical, eye space
  ShadingPath path = ShadingPath::Closed;
  WireDepth wireDepth = WireDepth::Round;
  std::unique_ptr<ViewGrid> grid;  ///< view directions of the tables (held by pointer: tables refer to it)
  std::vector<ShaderSlot> shaders;
  PodVector<TrianglePrim> triangles;
  PodVector<TriangleAttributes> triangleAttributes;
  PodVector<glm::dvec2> vertices;  ///< the triangles' screen polygons
  PodVector<SegmentPrim> segments;
  PodVector<SegmentShading> segmentShading;
  /// Per segment, or empty when every segment's colour is 1 at both ends (wireKeepsColours):
  /// 24 bytes a segment that most dense scenes (one colour a wire, shaded) do without.
  PodVector<SegmentColours> segmentColours;
  /// Per segment, for dashed hidden lines (HiddenLines::Dashed; empty unless a wire draws them):
  /// x, where the dash pattern stands at p0 (pixels of the pattern); y, the pattern's pixels a
  /// screen pixel along the segment, less 1. Along an open polyline y is 0 (the pattern advances
  /// with the screen arc length); around a closed one the pattern is scaled to a whole number of
  /// periods, so that it runs on across the seam (segment_setup.cpp).
  PodVector<glm::vec2> dashPattern;
  bool anyXray = false;  ///< some wire draws its hidden parts (HiddenLines::drawn)
  /// Some wire rests on a surface (ShaderSlot::restsOnSurface): without one, and without an
  /// x-ray wire, a segment culled whole in a tile is passed over without reading its shader.
  bool anyResting = false;
  double cueNear = 0, cueFar = 1;  ///< depth range of the wires (depth cueing)
  /// Textures and grooves box-filtered over the pixel's footprint (the A-buffer), or point
  /// sampled (the reference renderer, which averages its sub-samples instead).
  bool filterTextures = true;
  double pixelScale = 1.0;  ///< RenderOptions::pixelScale: on widths given in pixels
  std::uint32_t primitiveCount() const { return std::uint32_t(triangles.size() + segments.size()); }
  bool isSegment(std::uint32_t i) const { return i >= triangles.size(); }
  const SegmentPrim& segmentOf(std::uint32_t i) const { return segments[i - triangles.size()]; }
  const ShaderSlot& shaderOf(std::uint32_t i) const {
    return shaders[isSegment(i) ? segmentOf(i).shader : triangles[i].shader];
  }
  float opacityOf(std::uint32_t i) const { return shaderOf(i).opacity; }
  /// The primitives' arrays (what a band of tile items is sized against: binBands).
  size_t primitiveBytes() const;
  /// Those and the shading tables.
  size_t bytes() const;
};

/// Whether segment primitive i takes its depth from the exact solid (WireCapsule): a hair (a
/// wire whose polyline is its axis, not one resting on a surface) in the round model.
inline bool segmentUsesCapsule(const PreparedScene& ps, std::uint32_t i) {
  return ps.wireDepth == WireDepth::Round && !ps.shaderOf(i).restsOnSurface;
}
/// ShaderSlot::widthInPixels of segment primitive i (WireCapsule's radius).
inline bool segmentWidthInPixels(const PreparedScene& ps, std::uint32_t i) { return ps.shaderOf(i).widthInPixels; }

// ---- a segment's geometry on screen ---------------------------------------------------------

/// The polygon of a segment (see SegmentPrim), in the order the rasteriser and the reference
/// share.
void segmentPolygon(const SegmentPrim& s, ScreenPolygon& poly);
/// isConvex(segmentPolygon(s)), as set-up asks it of every mitred segment (a mitre that folds the
/// polygon falls back to square ends).
bool segmentPolygonConvex(const SegmentPrim& s);

/// Where screen point (x, y) lies relative to a segment's axis: t along it (0 at p0, 1 at p1,
/// outside [0, 1] beyond the ends) and q, the distance from the nearest axis point in half
/// widths (1 at the outline). A segment of no screen length (seen exactly end-on) is its end
/// point: t is 0 everywhere and the distance is radial.
struct SegmentFrame {
  double ax, ay;    ///< p0
  double ux, uy;    ///< (p1 - p0) / |p1 - p0|^2: t = (P - p0) . u
  double nx, ny;    ///< unit normal of the axis
  double length;    ///< |p1 - p0| in pixels
  explicit SegmentFrame(const SegmentPrim& s) {
    ax = s.p0.x, ay = s.p0.y;
    const double dx = s.p1.x - s.p0.x, dy = s.p1.y - s.p0.y;
    const double l2 = dx * dx + dy * dy;
    length = std::sqrt(l2);
    ux = l2 > 0 ? dx / l2 : 0.0, uy = l2 > 0 ? dy / l2 : 0.0;
    nx = length > 0 ? -dy / length : 0.0, ny = length > 0 ? dx / length : 1.0;
  }
  double t(double x, double y) const { return (x - ax) * ux + (y - ay) * uy; }
  /// Squared distance in pixels from the nearest point of the axis.
  double distance2(double x, double y) const {
    if (!(length > 0)) return (x - ax) * (x - ax) + (y - ay) * (y - ay);
    const double tt = t(x, y), tc = std::clamp(tt, 0.0, 1.0);
    const double lateral = (x - ax) * nx + (y - ay) * ny, along = (tt - tc) * length;
    return lateral * lateral + along * along;
  }
};

/// The depth keys (1/d, or d when orthographic) of a segment's front (the axis one radius
/// nearer) and of its axis, at its ends and at axis parameter t in [0, 1]: both screen-linear in
/// t. Formed once per segment wherever its depth is asked more than once.
struct SegmentEndKeys {
  double front0, front1, axis0, axis1;
  SegmentEndKeys(const ViewTransform& v, const SegmentPrim& s)
      : front0(v.depthKey(std::max(v.nearPlane, double(s.d0) - double(s.r0)))),
        front1(v.depthKey(std::max(v.nearPlane, double(s.d1) - double(s.r1)))),
        axis0(v.depthKey(s.d0)), axis1(v.depthKey(s.d1)) {}
  double front(double t) const { return front0 + (front1 - front0) * t; }
  double axis(double t) const { return axis0 + (axis1 - axis0) * t; }
};
/// The perspective tilt of a wire's surface across it (docs/abuffer.md, "The wire's
/// footprint"). The ray through a screen point offset o (pixels) from the nearest point X of the
/// axis's image passes the axis at q = |o| / w radii (w the half width), and the middle of its
/// chord through the cylinder lies q r from the axis along the normal n of the plane through the
/// eye and the axis. That plane faces the eye only where it holds the view axis: elsewhere the
/// chord's middle stands q r n_z nearer than the axis point, which is lat d L / (f^2 + L^2)
/// (lat the signed offset across the axis, d the axis depth, f the focal length in pixels, L =
/// (X - c) . n the axis line's signed distance from the image centre c). So the side of a wire
/// towards the image centre lies farther and the other side nearer, by up to the radius times
/// n_z; zero when orthographic (every ray parallel). Beyond an end (its sphere) the same form
/// along the axis. The depth is the axis depth times factor(): 1 + lateral lat + (along0 + alongT
/// tc) along, the offset's components across and along the axis clamped to a half width each;
/// and the axis depth is taken a little along the axis (shift0, shiftT: see segment_setup.cpp).
/// Against rays cast at the exact cylinder the whole model is within 0.02 r across the wire
/// (WireFootprint.TiltedDepthIsWhereTheRayEntersTheCylinder; 0.82 r without the tilt), for
/// segments at least two half widths long on screen: below that the slide fades out, as the
/// depth radius's scale does, towards the end-on hull.
struct SegmentTilt {
  double lateral = 0, along0 = 0, alongT = 0;
  /// The axis point whose depth the chord's middle takes: parameter t + lat (shift0 + shiftT
  /// tc), clamped to [0, 1] (lat clamped to a half width; t unclamped, so that beyond an end,
  /// its sphere, the shift fades out within shiftBound() and every depth the model takes in a
  /// rectangle is the axis's in the rectangle grown by shiftBound() times the length)
  double shift0 = 0, shiftT = 0;
  double bound = 0;       ///< |factor - 1| <= bound over the whole segment (segmentTiltBound)
  SegmentTilt(const ViewTransform& v, const SegmentPrim& s, const SegmentFrame& fr);
  /// |the parameter's shift| <= shiftBound() at every point of the image within the polygon's
  /// reach plus two pixels of the axis (segment_setup.cpp says why that is where it is asked).
  /// Formed on demand: the rasteriser and the binner need it once per segment, the resolve's
  /// subpixel depths, which build a SegmentTilt per fragment, never.
  double shiftBound(const ViewTransform& v, const SegmentPrim& s, const SegmentFrame& fr) const;
  /// lat, along: the offset from the nearest axis point across and along the axis (pixels; for
  /// a segment of no screen length, y and x from its end point); w the half width there.
  double factor(double lat, double along, double tc, double w) const {
    const double l = std::clamp(lat, -w, w), a = std::clamp(along, -w, w);
    return 1.0 + lateral * l + (along0 + alongT * tc) * a;
  }
};
/// A bound on |SegmentTilt::factor - 1| for segment s: its largest half width over the focal
/// length (each of the two terms is at most w / (2 f)); 0 when orthographic.
double segmentTiltBound(const ViewTransform& v, const SegmentPrim& s);

// ---- a round wire seen in perspective (docs/abuffer.md, "The wire's footprint") -------------

/// The half width on screen of a round wire of radius r about the eye-space axis through e0 and
/// e1, over r * pixelsPerWorld(d) (the width of the same wire on the view axis, facing the eye):
/// 1 / |n_xy|, n the unit normal of the plane through the eye and the axis. The wire's outline
/// is where the two planes through the eye tangent to the cylinder meet the image; to first
/// order in r / distance both lie that factor wider than r f / d at every point of the axis, so
/// a wire off the view axis and across the radial direction is wider (1 / cos of the ray's
/// angle at the image's edge). 1 where the axis passes through the eye or the view is
/// orthographic (every ray parallel: r times the scale, exactly).
/// `l0`, `l1`: |e0|, |e1| (set-up forms them once for this and wireDepthScale).
inline double wireWidthFactor(const ViewTransform& v, const glm::dvec3& e0, const glm::dvec3& e1, double l0, double l1) {
  if (!v.perspective) return 1.0;
  const glm::dvec3 n = glm::cross(e0, e1);
  const double nl = glm::length(n);
  if (!(nl > 1e-12 * l0 * l1) || !std::isfinite(nl)) return 1.0;
  const double nz = n.z / nl;
  return 1.0 / std::sqrt(std::max(1e-4, 1.0 - nz * nz));  // at most 100: rays within 89.4 degrees of the axis
}
inline double wireWidthFactor(const ViewTransform& v, const glm::dvec3& e0, const glm::dvec3& e1) {
  return wireWidthFactor(v, e0, e1, glm::length(e0), glm::length(e1));
}

/// The most a wire's round surface is taken to stand in front of its axis, in radii along the
/// view axis (wireDepthScale's bound: axes within asin(0.2) = 11.5 degrees of the ray).
inline constexpr double kMaxWireDepthScale = 5.0;

/// How far the round surface of a wire stands in front of its axis along the view axis, per
/// world radius, at eye-space point e of an axis of direction `axis`: cos(theta) / sin(beta),
/// theta the ray's angle to the view axis and beta its angle to the wire's axis. The ray through
/// a point q half widths from the axis's image crosses the cylinder on a chord of 2 r sqrt(1 -
/// q^2) / sin(beta) whose middle is the axis point of the same screen parameter at the axis's
/// depth; its entry lies half the chord nearer along the ray, cos(theta) of that in view depth.
/// 1 for a wire across the view on the view axis (the paper's picture); bounded by
/// kMaxWireDepthScale towards end-on, where the end caps, not the body, are what is seen.
/// `unitAxis`: the axis over its length, or 0 where it has none (then 1); `le`: |e|. Set-up
/// forms the unit axis once per segment and each end's |e| once for this and wireWidthFactor.
inline double wireDepthScale(const ViewTransform& v, const glm::dvec3& e, double le, const glm::dvec3& unitAxis) {
  if (unitAxis == glm::dvec3(0.0)) return 1.0;
  const glm::dvec3 view = v.viewVector(e, le);
  const double sinBeta = glm::length(glm::cross(view, unitAxis));
  const double cosTheta = std::clamp(view.z, 0.0, 1.0);
  return cosTheta / std::max(sinBeta, 1.0 / kMaxWireDepthScale);
}
/// `axis` / |axis|, or 0 for an axis of no (or no finite) length: wireDepthScale's unit axis.
inline glm::dvec3 wireUnitAxis(const glm::dvec3& axis) {
  const double al = glm::length(axis);
  return al > 0 && std::isfinite(al) ? axis * (1.0 / al) : glm::dvec3(0.0);
}
inline double wireDepthScale(const ViewTransform& v, const glm::dvec3& e, const glm::dvec3& axis) {
  return wireDepthScale(v, e, glm::length(e), wireUnitAxis(axis));
}

/// Whether prepareScene keeps a dash pattern for every segment (PreparedScene::dashPattern): some
/// wire draws its hidden parts dashed.
inline bool keepsDashPatterns(const Scene& scene) {
  for (const SceneWire& w : scene.wires)
    if (w.hidden.mode == HiddenLines::Mode::Dashed) return true;
  return false;
}

/// A wire segment as a ray caster sees it: the balls about its eye-space axis of the radius its
/// half widths stand for (linear along it), that is a sphere about each end and the cone tangent
/// to both (a cylinder where the radii are equal; docs/abuffer.md, "The exact solid at the
/// ends"). The round model (segmentDepthAt) is within a few hundredths
/// of a radius of it along the body but not near the ends, where the end's sphere, not the
/// slanting body, is what a ray meets first (up to two radii farther than the model there).
/// Hairs (wires that do not rest on a surface) take their depth from this near their ends (or
/// along the whole segment: `everywhere`); a ray that misses it (the polygon's outline lies a
/// little outside the solid's) takes where it passes it nearest. `valid` is false where the
/// segment has no finite eye-space ends.
struct WireCapsule {
  glm::dvec3 e0{0.0}, u{0.0};  ///< eye-space p0; unit axis (0 for a segment of no length)
  double length = 0;           ///< |e1 - e0|, world
  double r0 = 0, r1 = 0;       ///< world radii at the ends (the half widths over pixelsPerWorld and wireWidthFactor)
  bool valid = false;
  bool everywhere = false;     ///< the model is not the body's depth here: the solid along the whole segment
  WireCapsule() = default;
  /// `widthInPixels`: the half widths are the user's pixels (ShaderSlot::widthInPixels), the
  /// radius they stand for w / pixelsPerWorld; otherwise set-up widened them by wireWidthFactor.
  WireCapsule(const ViewTransform& v, const SegmentPrim& s, bool widthInPixels = false) {
    if (!(s.d0 > 0.0f) || !(s.d1 > 0.0f) || !std::isfinite(s.d0) || !std::isfinite(s.d1)) return;
    e0 = v.eyePoint(s.p0.x, s.p0.y, s.d0);
    const glm::dvec3 e1 = v.eyePoint(s.p1.x, s.p1.y, s.d1);
    const double wf = widthInPixels ? 1.0 : wireWidthFactor(v, e0, e1);
    r0 = double(s.w0) / (v.pixelsPerWorld(s.d0) * wf);
    r1 = double(s.w1) / (v.pixelsPerWorld(s.d1) * wf);
    const glm::dvec3 axis = e1 - e0;
    length = glm::length(axis);
    u = length > 0 && std::isfinite(length) ? axis * (1.0 / length) : glm::dvec3(0.0);
    if (!(u != glm::dvec3(0.0))) length = 0, r1 = r0;  // its p0 end's sphere alone
    valid = std::isfinite(r0) && std::isfinite(r1) && std::isfinite(e0.x + e0.y + e0.z) && r0 >= 0 && r1 >= 0;
    // Where the model's depth radius is not the cylinder's own scale, the model differs from
    // the solid along the whole segment, and the solid is used everywhere: set-up draws an
    // end-on segment as its end discs, ramps the scale to 1 for one shorter than two half widths
    // on screen, and caps it at kMaxWireDepthScale (where it reaches the cap times the cosine
    // of the image's widest ray angle: a little more than where it is capped). A width given in
    // pixels is not widened by wireWidthFactor: off the view axis the model's outline then lies
    // inside the cylinder's.
    if (valid) {
      const double sl = glm::length(s.p1 - s.p0), wmax = std::max(double(s.w0), double(s.w1));
      const double cosMax = 1.0 / std::sqrt(1.0 + v.maxRayTan2());
      const double capped = kMaxWireDepthScale * cosMax * 0.999;
      everywhere = (s.flags & kSegmentEndOn) || !(length > 0) || !(sl >= 2.0 * wmax) ||
                   !(double(s.r0) < capped * r0) || !(double(s.r1) < capped * r1) ||
                   (widthInPixels && wireWidthFactor(v, e0, e1) > 1.001);
    }
  }
  /// The view depth where the ray through screen point (x, y) enters the solid (the ray's own
  /// parameter: its direction has z = -1); where it misses (`hit` false), where it passes the
  /// solid nearest (its outline's depth where it grazes it, so continuous across the outline:
  /// where it grazes the body's cone, or the nearer end's centre).
  double depthAt(const ViewTransform& v, double x, double y, bool* hit = nullptr) const {
    glm::dvec3 o, d;
    if (v.perspective) o = glm::dvec3(0.0), d = glm::dvec3((x - v.cx) / v.focal, -(y - v.cy) / v.focal, -1.0);
    else o = glm::dvec3((x - v.cx) / v.orthoScale, -(y - v.cy) / v.orthoScale, 0.0), d = glm::dvec3(0.0, 0.0, -1.0);
    const double dd = glm::dot(d, d);
    double best = INFINITY;
    auto sphere = [&](const glm::dvec3& w, double r) {  // w: the ray's origin less the centre
      const double b = glm::dot(d, w), disc = b * b - dd * (glm::dot(w, w) - r * r);
      if (disc >= 0.0) best = std::min(best, (-b - std::sqrt(disc)) / dd);
      return -b / dd;  // where it passes the centre nearest
    };
    const glm::dvec3 w = o - e0;
    const double near0 = sphere(w, r0);
    double nearest = near0;
    if (length > 0) {
      const double near1 = sphere(w - u * length, r1);
      const double du = glm::dot(d, u), wu = glm::dot(w, u);
      const glm::dvec3 dp = d - u * du, wp = w - u * wu;
      const double a = glm::dot(dp, dp), b = glm::dot(dp, wp);
      nearest = std::min(near0, near1);  // (along the axis, or no body: its nearer end)
      // The body: the cone tangent to both end spheres (a cylinder when r0 = r1), between the
      // circles where it touches them (coneBand). Its radius at axial position h is rho0 + k h;
      // the ray meets it where |wp + sigma dp| = rho0 + k (wu + sigma du), the quadratic
      // A sigma^2 + 2 B sigma + C = 0 (negative inside), whose root (-B - sqrt(B^2 - A C)) / A is
      // where the ray enters the cone's inside (the smaller root when A > 0, the larger when the
      // ray is steeper than the cone, A < 0); as C / (-B + sqrt(B^2 - A C)) where B < 0, the same
      // root without cancellation (and the linear one when A = 0). A ray that misses grazes it
      // nearest at the quadratic's vertex -B / A (A > 0: continuous with the entry at the
      // outline, where the root is double).
      double k, rho0, h0, h1;
      if (coneBand(k, rho0, h0, h1)) {
        const double rho = rho0 + k * wu;
        const double A = a - k * k * du * du, B = b - k * du * rho, C = glm::dot(wp, wp) - rho * rho;
        const double disc = B * B - A * C;
        if (disc >= 0.0 && (B < 0.0 || A != 0.0)) {
          const double q = std::sqrt(disc);
          const double sigma = B < 0.0 ? C / (-B + q) : (-B - q) / A, h = wu + sigma * du;
          if (h >= h0 && h <= h1) best = std::min(best, sigma);
        }
        if (A > 0.0) {
          const double sv = -B / A, hv = wu + sv * du;
          nearest = hv < h0 ? near0 : hv > h1 ? near1 : sv;
        }
      }
    }
    const bool in = best < INFINITY && best > 0.0;
    if (hit) *hit = in;
    return in ? best : nearest;
  }
  /// The largest world radius.
  double radius() const { return std::max(r0, r1); }
  /// The body of a solid of some length: the cone (the union of the balls of radius r0 + (r1 -
  /// r0) t about the axis points e0 + t length u, the ends' spheres and what lies between) has
  /// radius rho0 + k h at axial position h from e0 (k the tangent of its half angle, whose sine
  /// is (r1 - r0) / length; rho0 = r0 / its cosine) and touches the spheres on the circles at h0
  /// = -r0 sin and h1 = length - r1 sin. False where one sphere holds the other (no body).
  bool coneBand(double& k, double& rho0, double& h0, double& h1) const {
    if (!(length > 0)) return false;
    const double s = (r1 - r0) / length;
    if (!(std::abs(s) < 1.0)) return false;
    const double c = std::sqrt(1.0 - s * s);
    k = s / c, rho0 = r0 / c, h0 = -r0 * s, h1 = length - r1 * s;
    return true;
  }
  /// How far from either end (pixels along the axis) the solid may differ from the round model
  /// by more than kCapsuleSlack radii: the half width times the depth radius's scale over the
  /// world radius (where the end's sphere stands out of the slanting body; half of this measured
  /// on the fur benchmarks, docs/abuffer.md). Infinite where not finite.
  double endMargin(const SegmentPrim& s) const {
    if (everywhere) return INFINITY;
    const double sc0 = r0 > 0 ? double(s.r0) / r0 : 1.0, sc1 = r1 > 0 ? double(s.r1) / r1 : 1.0;
    const double m = std::max(double(s.w0) * std::max(1.0, sc0), double(s.w1) * std::max(1.0, sc1));
    return std::isfinite(m) ? m : INFINITY;
  }
  /// Whether the solid, not the model, gives the depth at axis parameter t (screen length
  /// `length` pixels) for a point up to `spread` pixels from it: near an end or beyond it.
  static bool nearEnd(double t, double length, double margin, double spread) {
    return nearP0(t, length, margin + spread) || nearP1(t, length, margin + spread);
  }
  /// Within `margin` pixels of p0 (or before it), of p1 (or beyond it), at axis parameter t.
  static bool nearP0(double t, double length, double margin) { return !(t * length >= margin); }
  static bool nearP1(double t, double length, double margin) { return !((1.0 - t) * length >= margin); }
  /// The spreads the solid's users take: the resolve decides per pixel at its centre, whose
  /// samples lie within kPixelSpread of it; the rasteriser's bounds, for any point of the axis
  /// parameters a rectangle spans, allow kRangeSpread (that and a pixel to spare).
  static constexpr double kPixelSpread = 0.71, kRangeSpread = 1.5;
};

/// How far, in world radii, the exact solid may lie outside the round model's depth range where
/// the model is used as its bound (the body, away from the ends: within 0.03 radii measured).
inline constexpr double kCapsuleSlack = 0.05;

/// How far (pixels) a point of a hair's solid of world radius at most `radius` may project from
/// the axis points within that radius of it, for points seen in the image (the bounds that hold
/// the solid: SegmentDepth::capsuleNearest, binning). The projection stretches a displacement at
/// depth z by at most f / z / cos(theta), theta the ray's angle to the view axis, at most the
/// image's widest (ViewTransform::maxRayAngle); the displacement's points lie no nearer than the
/// axis's nearest depth `dmin` less the radius. Orthographic: the radius times the scale.
/// Infinite where the solid may reach the eye (then the whole axis bounds it).
inline double capsuleReach(const ViewTransform& v, double radius, double dmin) {
  if (!v.perspective) return radius * v.orthoScale * 1.01 + 1e-9;
  const double dNear = dmin - radius;
  const double rho = radius * v.focal / dNear * std::sqrt(1.0 + v.maxRayTan2());
  return dNear > 0.0 && std::isfinite(rho) ? rho * 1.01 + 1e-9 : INFINITY;
}

/// The farthest a wire's surface may lie in front of its axis, either model (the depth radii)
/// or the exact solid (WireCapsule: its world radius, bounded from the half widths alone as
/// w d / f, since wireWidthFactor >= 1), for the bounds that cull it. `exact`: WireCapsule's
/// solid is the wire's depth (a hair in the round model, segmentUsesCapsule).
inline double wireNearRadius(const ViewTransform& v, const SegmentPrim& s, bool exact) {
  const double r = std::max(double(s.r0), double(s.r1));
  if (!exact) return r;
  const double w0 = double(s.w0) / v.pixelsPerWorld(s.d0), w1 = double(s.w1) / v.pixelsPerWorld(s.d1);
  const double rw = std::max(w0, w1) * (1.0 + kCapsuleSlack);
  return rw >= r ? rw : r;  // (NaN: the radii's own bound)
}

/// The nearest depth of a segment's visible surface (for either WireDepth): no nearer than its
/// nearest axis depth, less the tilt (SegmentTilt), less its largest radius.
inline float segmentZlo(const ViewTransform& v, const SegmentPrim& s, bool exact = false) {
  const double near = std::min(double(s.d0), double(s.d1)) * (1.0 - segmentTiltBound(v, s));
  return float(std::max(v.nearPlane, near - wireNearRadius(v, s, exact)));
}


/// View depth of a segment's surface at screen point (x, y): the round cylinder (its depth
/// across the wire, sqrt(1 - q^2) radii before the axis, tilted in perspective (SegmentTilt), and
/// a sphere at the ends), or the flat front of the paper's polygon (WireDepth::Flat). Never
/// nearer than the near plane. `k`, `tilt`: the segment's keys and tilt.
inline double segmentDepthAt(const ViewTransform& v, const SegmentPrim& s, const SegmentFrame& fr,
                             const SegmentEndKeys& k, const SegmentTilt& tilt, double x, double y, WireDepth model) {
  const double t = fr.t(x, y), tc = std::clamp(t, 0.0, 1.0);
  if (model == WireDepth::Flat) return std::max(v.nearPlane, v.depthFromKey(k.front(tc)));
  const double w = double(s.w0) + (double(s.w1) - double(s.w0)) * tc;
  double lat, along;  // as SurfaceDepth (abuffer.h) forms them
  if (fr.length > 0) lat = (x - fr.ax) * fr.nx + (y - fr.ay) * fr.ny, along = (t - tc) * fr.length;
  else lat = y - fr.ay, along = x - fr.ax;
  const double q2 = w > 0 ? std::min(1.0, (lat * lat + along * along) / (w * w)) : 1.0;
  const double r = double(s.r0) + (double(s.r1) - double(s.r0)) * tc;
  const double ts = std::clamp(t + std::clamp(lat, -w, w) * (tilt.shift0 + tilt.shiftT * tc), 0.0, fr.length > 0 ? 1.0 : 0.0);
  const double d = v.depthFromKey(k.axis(ts)) * tilt.factor(lat, along, tc, w);
  return std::max(v.nearPlane, d - r * std::sqrt(1.0 - q2));
}
inline double segmentDepthAt(const ViewTransform& v, const SegmentPrim& s, const SegmentFrame& fr, double x,
                             double y, WireDepth model) {
  return segmentDepthAt(v, s, fr, SegmentEndKeys(v, s), SegmentTilt(v, s, fr), x, y, model);
}

/// View depth of primitive i's surface at screen point (x, y) (the triangle's plane, clamped to
/// its depth range; a segment's surface, segmentDepthAt).
double primitiveDepthAt(const PreparedScene& ps, std::uint32_t i, double x, double y);

/// primitiveDepthAt with what depends on the primitive alone formed once (a segment's frame, end
/// keys and tilt: two divisions and a dozen products fewer per point), for the reference
/// renderer's many samples per primitive. The same arithmetic, so the same depths to the bit.
class PrimitiveDepth {
 public:
  PrimitiveDepth(const PreparedScene& ps, std::uint32_t i);
  double operator()(double x, double y) const {
    if (wire_) {
      if (wire_->capsule.valid) return std::max(view_->nearPlane, wire_->capsule.depthAt(*view_, x, y));
      return segmentDepthAt(*view_, *seg_, wire_->frame, wire_->keys, wire_->tilt, x, y, model_);
    }
    return std::clamp(view_->depthFromKey(tri_->depthKeyAt(x, y)), double(tri_->zlo), double(tri_->zhi));
  }

 private:
  struct Wire {
    SegmentFrame frame;
    SegmentEndKeys keys;
    SegmentTilt tilt;
    WireCapsule capsule;  ///< valid for a hair (segmentUsesCapsule)
  };
  const ViewTransform* view_;
  const SegmentPrim* seg_ = nullptr;
  const TrianglePrim* tri_ = nullptr;
  WireDepth model_;
  std::optional<Wire> wire_;
};

/// One pixel a primitive covers, as the fragment stage hands it to the A-buffer.
struct PixelCoverage {
  int x, y;
  double area;             ///< exact covered fraction
  MaskBits mask;
  double cx, cy;           ///< centroid of the covered part (where the fragment is shaded)
  int subpixel;            ///< sample index nearest the centroid (a stand-in when mask is 0)
  float zmin, zmax;        ///< view depth range of the primitive's surface over the pixel
  float zkey;              ///< its depth at the centroid (the order of the resolve)
};

/// The items of the tiles of tile rows [rowBegin, rowEnd) (the whole grid, or one band of it:
/// the renderer bins a dense scene a band at a time, so that its items are not all held at once).
struct TileBins {
  int tilesX = 0, tilesY = 0;
  int rowBegin = 0, rowEnd = 0;        ///< the tile rows binned
  std::vector<std::uint32_t> offsets;  ///< the band's k-th tile: items[offsets[k], offsets[k+1])
  /// Tile t's items (t numbered over the whole grid, in the rows binned): [begin, end).
  std::uint32_t begin(int t) const { return offsets[local(t)]; }
  std::uint32_t end(int t) const { return offsets[local(t) + 1]; }
  size_t local(int t) const {
    if (t < rowBegin * tilesX || t >= rowEnd * tilesX) outsideBand(t);
    return size_t(t) - size_t(rowBegin) * size_t(tilesX);
  }
  [[noreturn]] void outsideBand(int t) const;
  /// One primitive in one tile: what the tile needs to order and cull it without touching the
  /// primitive itself (most are culled whole on dense scenes, and primitives are scattered).
  /// 12 bytes: a dense scene has several per segment (a hair 40 pixels long crosses about five
  /// tiles of 32), and the items are the largest of the render's per-segment arrays.
  struct Item {
    float zlo;                     ///< nearest depth of the primitive inside the tile: the tile sorts its triangles, then its segments, by (zlo, index)
    std::uint32_t index;           ///< the primitive (PreparedScene's numbering)
    std::uint8_t x0, y0, x1, y1;   ///< pixel rectangle within the tile, inclusive (tiles are at most 256 wide)
    /// By zlo, then index; a NaN zlo after every number (a strict weak order even then: std::sort
    /// with an order NaN breaks may read outside the array). None reaches an item today.
    bool operator<(const Item& o) const {
      const bool nan = zlo != zlo, onan = o.zlo != o.zlo;
      if (nan || onan) return nan == onan ? index < o.index : onan;
      return zlo < o.zlo || (zlo == o.zlo && index < o.index);
    }
  };
  static constexpr int kMaxTileSize = 256;  ///< Item's corners are bytes
  static_assert(sizeof(Item) == 12);
  static_assert(kMaxTileSize - 1 <= std::numeric_limits<decltype(Item::x0)>::max());
  PodVector<Item> items;           ///< per tile, in primitive order
  size_t bytes() const { return offsets.capacity() * sizeof(std::uint32_t) + items.capacity() * sizeof(Item); }
};

/// Everything RenderOptions::problem() checks but the memory budget (render() and
/// renderReference() check that against their own estimate of the scene).
std::string optionsProblem(const RenderOptions& options);

/// Camera, lights, shading tables, screen primitives. Fills the setup / maps times, input
/// counts, warnings and error estimates of `stats`.
PreparedScene prepareScene(const Scene& scene, const RenderOptions& options, RenderStats& stats);
/// Sample s of the n x n stratified (jittered) samples of pixel (px, py): stratum (s mod n,
/// s div n), jittered by a hash of (seed, pixel, s), so the same for any thread count. The
/// brute-force reference and the ray-cast peer of the benchmarks sample pixels with it.
inline glm::dvec2 stratifiedSample(std::uint64_t seed, int px, int py, int s, int n) {
  const std::uint64_t h = mix64(seed * 0x100000001B3ull ^ mix64((std::uint64_t(px) << 32) ^ std::uint64_t(py)) ^
                                std::uint64_t(s));
  const double jx = double(h >> 40) * 0x1.0p-24, jy = double(h & 0xFFFFFF) * 0x1.0p-24;
  return {px + ((s % n) + jx) / n, py + ((s / n) + jy) / n};
}

/// Runs f on at most `threads` worker threads (0: all cores).
template <class F>
void inArena(int threads, F&& f) {
  if (threads > 0) {
    tbb::task_arena arena(threads);
    arena.execute(f);
  } else {
    f();
  }
}

/// Primitive i's screen polygon.
void screenPolygonOf(const PreparedScene& ps, std::uint32_t i, ScreenPolygon& poly);
/// Stage "bins", its counting pass: how many items each chunk of primitives gives each tile of
/// tile rows [rowBegin, rowEnd) (clamped to the grid). Tells the renderer how many items a band
/// of rows will hold before any is formed, and places them when it is filled.
struct BinCounts {
  int tileSize = 32, tilesX = 0, tilesY = 0, rowBegin = 0, rowEnd = 0;
  size_t chunks = 1, perChunk = 0;     ///< chunks of perChunk primitives, in primitive order
  std::vector<std::uint32_t> counts;   ///< chunk-major, then the rows' tiles in order
  /// Per block of kBlock primitives, the first and last tile rows its items reach (none: max,
  /// -1): a band's filling passes over blocks that reach none of its rows without reading them
  /// (primitives made in order, such as fur grown over a patch or a mesh's triangles, lie near
  /// their neighbours).
  static constexpr size_t kBlock = 256;
  std::vector<int> blockRows;
  std::uint64_t rowItems(int row) const;  ///< the items of tile row `row`
  size_t bytes() const { return counts.capacity() * sizeof(std::uint32_t) + blockRows.capacity() * sizeof(int); }
};
BinCounts countBins(const PreparedScene& ps, int tileSize, int rowBegin = 0,
                    int rowEnd = std::numeric_limits<int>::max());
/// Stage "bins": fills `bins` (reusing its memory) with the items of tile rows [rowBegin,
/// rowEnd) within those counted; each tile's items in primitive order, whatever the thread
/// count. Throws std::length_error when the items would exceed `memoryBudget` bytes (0:
/// unlimited) beside the primitives (checkBinsFit): many large primitives over small tiles
/// multiply. Adds the band's tiles, empty tiles and time to `stats`.
void binPrimitives(const PreparedScene& ps, const BinCounts& counts, int rowBegin, int rowEnd, RenderStats& stats,
                   size_t memoryBudget, TileBins& bins);
/// What is held while a band's items are: the primitives, the counts, the band's offsets and
/// `alsoHeld` (the renderer's image and tile buffers).
double binsHeldBeside(const PreparedScene& ps, const BinCounts& counts, double alsoHeld = 0.0);
/// Throws binPrimitives' std::length_error unless `items` items fit `memoryBudget` (0:
/// unlimited) beside binsHeldBeside.
void checkBinsFit(const PreparedScene& ps, const BinCounts& counts, std::uint64_t items, size_t memoryBudget,
                  double alsoHeld = 0.0);
/// The whole grid at once.
TileBins binPrimitives(const PreparedScene& ps, int tileSize, RenderStats& stats, size_t memoryBudget = 0);
/// The image and the tile buffers of every thread a render of `o` (renderReference's when
/// `reference`) holds whatever its primitives: estimateRenderBytes' first terms, and what
/// binBands leaves beside the items (renderer.cpp).
double renderImageAndTileBytes(const Scene& scene, const RenderOptions& o, bool reference);
/// A band of tile rows holds up to this many bytes of items, or a quarter of the primitives'
/// bytes where that is more (binBands).
inline constexpr size_t kOneBand = size_t(4) << 20;
/// The most bytes of tile items a band holds (binBands, and estimateRenderBytes with it): a
/// quarter of `primitiveBytes` or kOneBand, whichever is more, and no more than `room` (what a
/// memory budget leaves them; INFINITY without one) less the items array's own rounding.
inline double bandItemCap(double primitiveBytes, double room) {
  return std::min(std::max(primitiveBytes / 4.0, double(kOneBand)), room - largeArrayRounding(room));
}
/// Bands of the counted tile rows to bin and draw one after another, so that a dense scene's
/// items (several a hair: one per tile it crosses) are not all held at once beside its
/// primitives. A band holds at most a quarter of the primitives' bytes in items, or kOneBand
/// bytes where that is more (a scene whose items fit it is drawn as one band), or one tile row
/// where a row alone holds more; and no more than the memory budget leaves beside the
/// primitives, the counts, `alsoHeld` (the image and the tile buffers) and the items' own
/// rounding to pages (a row that does not fit is checkBinsFit's error, before any band is
/// drawn). `largest`: the most items a band holds. The image is the same for any bands: each
/// tile's items are the same, in the same order.
std::vector<std::pair<int, int>> binBands(const PreparedScene& ps, const BinCounts& c, size_t memoryBudget,
                                          double alsoHeld, std::uint64_t& largest);
/// Sorts one tile's items into TileBins::Item's order (zlo, then index) when they arrive in
/// primitive order, as binPrimitives leaves them: a stable radix sort on zlo (-0 taken as +0,
/// equal, as the comparison has them; NaN after every number), so that ties keep that order;
/// std::sort for short lists. Needs the items in increasing index (else ties may differ from the
/// comparison) and fewer than 2^32 of them (TileBins' offsets are 32-bit too). `scratch`: a
/// buffer the sort may use (the renderer keeps one per thread, as large as its largest tile's
/// items).
void sortTileItems(std::vector<TileBins::Item>& items, std::vector<TileBins::Item>& scratch);
/// The same for the n items from `items` on.
void sortTileItems(TileBins::Item* items, size_t n, std::vector<TileBins::Item>& scratch);
/// What a surface fragment interpolates (perspective-correct): eye-space unit normal (turned to
/// the viewer), eye-space unit tangent (zero when the mesh has none), (u, v), colour.
struct SurfaceSample {
  glm::dvec3 normal{0.0, 0.0, 1.0}, tangent{0.0};
  glm::dvec2 uv{0.0};
  glm::vec3 colour{1.0f};
  glm::dvec3 barycentric{1.0, 0.0, 0.0};
  /// Eye-space dS/du and dS/dv (on request): the mesh's per-vertex derivatives, else its
  /// tangents for dS/du, else the triangle's own (u, v) gradient; zero when there is none.
  glm::dvec3 derivU{0.0}, derivV{0.0};
  bool flipped = false;  ///< the normal was turned to face the viewer
};
/// `tangentAndUv` false leaves tangent and (u, v) at their defaults (cheaper per fragment);
/// `derivatives` fills derivU and derivV.
SurfaceSample interpolateTriangle(const PreparedScene& ps, const TriangleAttributes& ta, const glm::dvec3& eyePoint,
                                  const glm::dvec3& view, bool tangentAndUv, bool derivatives = false);
/// (u, v) of the triangle's plane at eye point P, extrapolated beyond the triangle (for pixel
/// footprints); zero when the mesh has no (u, v).
glm::dvec2 uvOnPlane(const PreparedScene& ps, const TriangleAttributes& ta, const glm::dvec3& P);
/// Mirror reflection of the environment (fixed to the viewer) for unit normal n, view vector v.
glm::dvec3 chromeRadiance(const EnvironmentMap& env, const glm::dvec3& reflectance, const glm::dvec3& n,
                          const glm::dvec3& v);
/// The procedural mountain scene chrome reflects when the scene names no environment.
const EnvironmentMap& defaultEnvironment();
/// Radiance of a surface fragment (Phong, chrome, burnished; textures, bumps, grooves).
glm::vec3 shadeSurfaceFragment(const PreparedScene& ps, std::uint32_t triangle, double x, double y,
                               const glm::dvec3& P, const glm::dvec3& V);
/// The same at screen point (x, y) of primitive i when a triangle (on its plane); default for
/// segments.
SurfaceSample interpolateSurface(const PreparedScene& ps, std::uint32_t i, double x, double y);
/// The scene's background as the renderers composite over it: a non-finite colour component
/// is 0 (as colours are, safeColour), alpha NaN is 0 and alpha is clamped to [0, 1].
inline glm::vec4 sanitizedBackground(const glm::vec4& bg) {
  glm::vec4 b;
  for (int c = 0; c < 3; ++c) b[c] = std::isfinite(bg[c]) ? bg[c] : 0.0f;
  b.w = std::isnan(bg.w) ? 0.0f : std::clamp(bg.w, 0.0f, 1.0f);
  return b;
}
/// Radiance of primitive i's fragment at screen point (x, y), view depth `depth`.
glm::vec3 shadeFragment(const PreparedScene& ps, std::uint32_t i, double x, double y, double depth);
/// Whether primitive i's shading varies inside a pixel (textures, bumps, grooves): the reference
/// renderer and the ray-cast peer shade such primitives at every sample.
inline bool shadingVariesInPixel(const PreparedScene& ps, std::uint32_t i) {
  return !ps.isSegment(i) && ps.shaderOf(i).variesInPixel;
}


// ---- helpers the stages share ------------------------------------------------------------

/// Colours and opacities from the scene: NaN / Inf / negative would reach the image.
inline glm::vec3 safeColour(const glm::vec3& c) {
  auto f = [](float v) { return std::isfinite(v) ? std::max(v, 0.0f) : 0.0f; };
  return {f(c.x), f(c.y), f(c.z)};
}
inline float safeOpacity(float a) { return std::isfinite(a) ? std::clamp(a, 0.0f, 1.0f) : 1.0f; }

/// Stage "camera": the scene's camera when usable (else one framing its bounds, with a warning),
/// near and far planes from the bounding sphere where the camera leaves them open.
Camera chooseCamera(const Scene& scene, const RenderOptions& options, RenderStats& stats);
/// Stage "tables": one shader slot per surface material and per wire, with the shading tables
/// (pseudo-reflectance maps, reflectance spheres) the map path needs, and only those; fills the
/// maps time, the table counts and the error estimates of the tables in `stats`.
void prepareShaders(PreparedScene& ps, const Scene& scene, const RenderOptions& options,
                    std::vector<int>& surfaceShader, std::vector<int>& wireShader, RenderStats& stats);


/// Stage "simplification" (simplify.cpp), before the primitives: for each polyline of each
/// aggregate wire, the factor its width is drawn at (0: left out) and its lambda (the fraction
/// of its neighbours drawn, which also sets how far its colours are pulled toward the local mean).
struct WireSimplification {
  std::vector<float> scale, lambda;  ///< per hair: width factor (0: left out), fraction drawn around it
  std::vector<glm::vec3> meanColour;  ///< per hair, when the wire has colours: the local mean
};
struct SimplificationPlan {
  std::vector<WireSimplification> wires;  ///< per scene wire (empty vectors: drawn as it is)
  size_t hairs = 0, kept = 0;
  double minLambda = 1.0;
};
SimplificationPlan planSimplification(const Scene& scene, const ViewTransform& view, const SimplifyOptions& options,
                                      double pixelScale = 1.0);

/// Counts of one set-up work item, added into RenderStats.
struct SetupCounts {
  size_t triangles = 0, segments = 0, rejected = 0, zeroLength = 0, clipped = 0, endOn = 0;
};
/// Where one work item of the primitives stage writes its triangles: from the start of these
/// arrays (room for every input triangle, up to 5 vertices each); firstVertex counts from
/// `vertices`, and prepareScene adds the item's final vertex offset when it joins the items.
struct TriangleSink {
  TrianglePrim* prims;
  TriangleAttributes* attributes;
  glm::dvec2* vertices;
  size_t count = 0, vertexCount = 0;
};
/// Where one work item writes its segments (room for every input segment).
struct SegmentSink {
  SegmentPrim* prims;
  SegmentShading* shading;
  SegmentColours* colours = nullptr;  ///< PreparedScene::segmentColours, when kept
  size_t count = 0;
  glm::vec2* dashPattern = nullptr;  ///< PreparedScene::dashPattern, when kept
};
/// Triangles [begin, end) of a surface: clipped to near / far, projected, depth plane, attributes.
void setupTriangles(const PreparedScene& ps, const SceneSurface& surf, std::uint32_t surfaceIndex,
                    std::uint16_t shader, std::uint32_t tag, size_t begin, size_t end, TriangleSink& out,
                    SetupCounts& counts);
/// True when wire `wire`, drawn by shader slot `shader` of `ps`, gives some segment a colour other
/// than 1 at an end: per-point colours, a plain wire's colour, or radiance looked up at set-up
/// (kSegmentPreshaded). PreparedScene::segmentColours is kept when any wire of the scene does.
bool wireKeepsColours(const PreparedScene& ps, const SceneWire& wire, std::uint32_t shader);
/// Polylines [begin, end) of a wire: the paper's wire polygons (see SegmentPrim). `out.colours`
/// must have room when wireKeepsColours says so and a segment is written (it is null where the
/// scene has no segment at all).
void setupPolylines(const PreparedScene& ps, const SceneWire& wire, std::uint32_t shader,
                    std::uint32_t tagBase, size_t begin, size_t end, SegmentSink& out, SetupCounts& counts,
                    const WireSimplification* simplification = nullptr);

}  // namespace wf

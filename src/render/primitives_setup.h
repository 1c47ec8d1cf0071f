// The stages before rasterisation, shared by the A-buffer renderer and its brute-force
// reference: camera and eye-space lights, the shading tables a scene needs (and only those),
// clipping and projection of triangles and wire segments into convex screen polygons, binning
// into tiles, and per-fragment shading.
//
// Wire segments follow the paper (§3): a polygon as thick as the wire, its narrow side across
// the screen direction of the segment and its long side joining the end points. Consecutive
// segments of a polyline share their joint edge (a mitre along the bisector), so the polygons
// abut exactly: no gap, no overlap, and the A-buffer merges the two pieces by their common tag.
// A mitre longer than kMitreLimit half-widths, or one that would fold a polygon, falls back to
// square ends. A segment whose screen length is less than its width is seen (nearly) end-on and
// is drawn as the hull of its two end discs (32-gons of the disc's exact area).
#pragma once

#include "abuffer/coverage_mask.h"
#include "abuffer/screen_polygon.h"
#include "core/hash.h"
#include "render/renderer.h"
#include "shading/pseudo_reflectance_map.h"
#include "shading/reflectance_sphere.h"
#include "render/view_tables.h"

#include <glm/glm.hpp>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

namespace wf {

inline constexpr double kMitreLimit = 4.0;

struct Primitive {
  std::uint32_t firstVertex = 0;
  std::uint16_t vertexCount = 0;
  bool isSegment = false;
  bool constantColour = false;  ///< `colour` holds the shading of every fragment
  bool mayMerge = true;         ///< false when the primitive is its object's only piece
  std::uint32_t tag = 0;
  std::uint32_t attribute = 0;  ///< index into triangles or segments of PreparedScene
  float opacity = 1.0f;
  float bbox[4] = {0, 0, 0, 0};  ///< x0, y0, x1, y1 in pixels, clamped to the image
  double qa = 0, qb = 0, qc = 0;  ///< depth key = qa x + qb y + qc (1/d or d)
  float zlo = 0, zhi = 0;         ///< depth range of the polygon
  glm::vec3 colour{0.0f};
  double depthKeyAt(double x, double y) const { return qa * x + qb * y + qc; }
};

/// Eye-space data to interpolate over a triangle (perspective-correct by construction: the
/// barycentrics are those of the eye-space point under the fragment).
struct TriangleAttributes {
  glm::dvec3 p0, e1, e2;
  double d00, d01, d11, invDen;
  std::uint32_t surface, triangle;
  std::uint16_t shader;
};

struct SegmentAttributes {
  glm::dvec3 p0, p1;  ///< eye space (after near / far clipping)
  glm::dvec3 t0, t1;  ///< eye-space unit tangents at the two ends (averaged at joints)
  glm::vec3 c0, c1;   ///< per-point colours
  /// Eye-space radius of the wire at the two ends (a pixel thickness turned into world units at
  /// each end's depth): the cylinder the polygon stands for, for ray-casting peers.
  float r0 = 0, r1 = 0;
  std::uint16_t shader;
};

/// One way of shading: a surface material or a wire style, with the tables it reads.
struct ShaderSlot {
  enum class Kind { SurfacePhong, SurfaceChrome, SurfaceBurnished, WireShaded, WirePlain, WireDepthCued };
  Kind kind = Kind::SurfacePhong;
  PhongMaterial phong;
  glm::dvec3 chromeReflectance{0.9};
  glm::vec3 colour{1.0f};
  /// Shaded wire and burnished surfaces, map path (burnished: of the diffuse part when `split`).
  std::shared_ptr<WireTables> wireTables;
  /// Phong and chrome surfaces, map path (Phong: of the diffuse part when `split`).
  std::shared_ptr<SurfaceTables> surfaceTables;
  /// A colour map multiplies the diffuse part only: the tables above then hold the diffuse part
  /// and these the specular part (only then are they built).
  bool split = false;
  std::shared_ptr<WireTables> wireSpecular;
  std::shared_ptr<SurfaceTables> surfaceSpecular;
  /// Surfaces: the material (textures, bumps, grooves, grain) and what its fragments need.
  const Material* material = nullptr;
  bool needsUv = false;          ///< colour map, bump map, grooves along u or v, grain along u or v
  bool needsDerivatives = false; ///< bump map, grain along u or v
  /// Shading varies inside a pixel (textures, bumps, grooves): the reference renderer shades
  /// such primitives at every sample instead of once per pixel.
  bool variesInPixel = false;
  glm::dvec3 axisPoint{0.0}, axisDirection{0.0, 0.0, 1.0};  ///< radial / circular grain, eye space
};

struct PreparedScene {
  const Scene* scene = nullptr;
  ViewTransform view;
  LightRig eyeLights;  ///< canonical, eye space
  ShadingPath path = ShadingPath::Maps;
  std::unique_ptr<ViewGrid> grid;  ///< view directions of the tables (held by pointer: tables refer to it)
  std::vector<ShaderSlot> shaders;
  std::vector<Primitive> primitives;
  std::vector<glm::dvec2> vertices;
  std::vector<TriangleAttributes> triangles;
  std::vector<SegmentAttributes> segments;
  double cueNear = 0, cueFar = 1;  ///< depth range of the wires (depth cueing)
  /// Textures and grooves box-filtered over the pixel's footprint (the A-buffer), or point
  /// sampled (the reference renderer, which averages its sub-samples instead).
  bool filterTextures = true;
  size_t bytes() const;
};

struct PixelCoverage {
  int x = 0, y = 0;
  double area = 0;         ///< exact covered fraction
  MaskBits mask = 0;
  double cx = 0, cy = 0;   ///< centroid of the covered part (where the fragment is shaded)
  double keyMin = 0, keyMax = 0;
  int subpixel = 0;        ///< sample index nearest the centroid
};

struct TileBins {
  int tilesX = 0, tilesY = 0;
  std::vector<std::uint32_t> offsets;  ///< tile t: items[offsets[t], offsets[t+1])
  /// One primitive in one tile: what the tile needs to order and cull it without touching the
  /// primitive itself (most are culled whole on dense scenes, and primitives are scattered).
  struct Item {
    float zlo;                     ///< nearest depth: the tile sorts by (zlo, index)
    std::uint32_t index;           ///< into PreparedScene::primitives
    std::uint32_t firstVertex;     ///< its vertices (for prefetching)
    std::int16_t x0, y0, x1, y1;   ///< pixel rectangle within the tile, inclusive
    bool operator<(const Item& o) const { return zlo < o.zlo || (zlo == o.zlo && index < o.index); }
  };
  std::vector<Item> items;         ///< per tile, in primitive order
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

/// The primitive's screen polygon.
ScreenPolygon screenPolygonOf(const PreparedScene& ps, const Primitive& prim);
TileBins binPrimitives(const PreparedScene& ps, int tileSize, RenderStats& stats);
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
glm::vec3 shadeSurfaceFragment(const PreparedScene& ps, const Primitive& prim, double x, double y,
                               const glm::dvec3& P, const glm::dvec3& V);
/// The same at screen point (x, y) of a triangle primitive (on its plane); default for segments.
SurfaceSample interpolateSurface(const PreparedScene& ps, const Primitive& prim, double x, double y);
/// The scene's background as the renderers composite over it: a non-finite colour component
/// is 0 (as colours are, safeColour), alpha NaN is 0 and alpha is clamped to [0, 1].
inline glm::vec4 sanitizedBackground(const glm::vec4& bg) {
  glm::vec4 b;
  for (int c = 0; c < 3; ++c) b[c] = std::isfinite(bg[c]) ? bg[c] : 0.0f;
  b.w = std::isnan(bg.w) ? 0.0f : std::clamp(bg.w, 0.0f, 1.0f);
  return b;
}
/// Radiance of a primitive's fragment at screen point (x, y), view depth `depth`.
glm::vec3 shadeFragment(const PreparedScene& ps, const Primitive& prim, double x, double y,
                        double depth);

}  // namespace wf

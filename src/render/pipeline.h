// The A-buffer's data path, one stage per file, in the order render() (renderer.cpp) calls them:
//
//   scene -> camera          view_setup.cpp      chooseCamera: the scene's camera, or one framing it
//         -> tables          shading_tables.cpp  prepareShaders: the shading tables the scene needs
//         -> primitives      prepare_scene.cpp   prepareScene: the stages above, then clipping and
//                            triangle_setup.cpp    projection of triangles and wire segments into
//                            segment_setup.cpp     convex screen polygons
//         -> bins            binning.cpp         binPrimitives: primitives into screen tiles
//         -> fragments       rasterize.h         rasterizePolygon: exact area, mask, depth per pixel
//         -> resolve         abuffer/abuffer.cpp TileABuffer: depth order, coverage, tails
//         -> image
//
// Shading of a fragment (fragment_shading.cpp, surface_shading.cpp) is called from the fragment
// stage. The brute-force reference (reference_renderer.cpp) and the benchmarks' ray caster share
// every stage up to the bins. This header holds the data the stages hand each other.
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
#include <chrono>
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


// ---- helpers the stages share ------------------------------------------------------------

inline double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
inline bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
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


/// What one work item of the primitives stage produces (a chunk of triangles or polylines);
/// prepareScene joins the chunks in a fixed order.
struct ChunkOut {
  std::vector<Primitive> prims;
  std::vector<glm::dvec2> verts;
  std::vector<TriangleAttributes> tris;
  std::vector<SegmentAttributes> segs;
  size_t triangles = 0, segments = 0, rejected = 0, zeroLength = 0, clipped = 0, endOn = 0;
};
/// Appends the screen polygon `poly` of `prim` to `out` with its bounding box; false (nothing
/// appended) when it covers no area inside the image.
bool finishPolygon(const ScreenPolygon& poly, const ViewTransform& view, Primitive& prim, ChunkOut& out);
/// Triangles [begin, end) of a surface: clipped to near / far, projected, depth plane, attributes.
void setupTriangles(const PreparedScene& ps, const SceneSurface& surf, std::uint32_t surfaceIndex,
                    std::uint16_t shader, std::uint32_t tag, float opacity, size_t begin, size_t end,
                    ChunkOut& out);
/// Polylines [begin, end) of a wire: the paper's wire polygons (see the top of this file).
void setupPolylines(const PreparedScene& ps, const SceneWire& wire, std::uint16_t shader,
                    std::uint32_t tagBase, size_t begin, size_t end, ChunkOut& out);

}  // namespace wf

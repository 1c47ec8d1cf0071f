// The A-buffer renderer (paper §3): triangles and thick line segments as antialiased fragments
// with exact coverage, resolved in depth order, shaded through the pseudo-reflectance map (wires)
// and reflectance spheres (surfaces), or exactly; plus the brute-force reference it is measured
// against. The data path, top to bottom:
//   render() -> prepareView (camera, eye-space lights) -> prepareShaders (only the maps the scene
//   needs) -> setupPrimitives (clip, project, wire quads with mitred joints) -> binPrimitives
//   (tiles) -> rasterizeTiles (fragments -> TileABuffer -> resolve) -> image + stats.
#pragma once

#include "abuffer/abuffer.h"
#include "abuffer/coverage_mask.h"
#include "core/image.h"
#include "render/scene.h"
#include "shading/pseudo_reflectance_map.h"

#include <cstdint>
#include <string>
#include <memory>
#include <vector>

namespace wf {

enum class ShadingPath {
  /// At the true view vector of every fragment (perspective-exact): Phong and chrome directly,
  /// wires, hairs and burnish grain by the cylinder integral in closed form with its one
  /// non-elementary factor read from a table per exponent (shading/cylinder_lobe.h; error ~1e-9).
  Closed,
  Maps,   ///< pseudo-reflectance maps and reflectance spheres (the paper; orthographic view)
  Exact,  ///< as Closed, with the factor computed exactly: the reference
};

/// The depth of a wire across its width (what decides, subpixel by subpixel, which of two
/// crossing hairs, or of a hair and the skin it grows from, is in front).
enum class WireDepth {
  Round,  ///< the cylinder's own surface: sqrt(1 - q^2) across the wire, spheres at the ends
  Flat,   ///< the paper's polygon: one plane at the wire's front, a depth radius (SegmentPrim::r0, r1) before its axis
};

/// Stochastic simplification of aggregate detail (Cook, Halstead, Planck and Ryu, "Stochastic
/// Simplification of Aggregate Detail", SIGGRAPH 2007) for wires marked SceneWire::aggregate
/// (fur): where hairs are thinner than `targetWidth` pixels and overlap each other at least
/// `minDepthComplexity` times (fully from twice that), a stable random fraction lambda =
/// max(width / targetWidth, 1/64) of them is
/// drawn (chosen by a hash of each hair's index, never its position), each widened by 1 /
/// lambda so that the expected coverage stays the same, its colours pulled toward the local
/// mean by sqrt(lambda) so that the pixels' variance stays the same, and faded across the cut
/// so that nothing pops as the camera moves. An approximation with no per-pixel bound:
/// `wirefur accuracy` measures its error against time; off (the default) is the exact path.
struct SimplifyOptions {
  bool enabled = false;
  double targetWidth = 2.0;         ///< pixels: thinner hairs are thinned out and widened to it
  double minDepthComplexity = 4.0;  ///< projected area of the hairs rooted in a region, per pixel of it, below which none is
  double fade = 0.25;               ///< width of the fade across the cut, relative to lambda
};

class ShadingCache;

/// The default RenderOptions::memoryBudget: half of the machine's physical memory (8 GiB where
/// it cannot be read). A render that needs more would push the machine into swap or the
/// out-of-memory killer (a crash); half leaves room for the caller, the PNG encoder and others.
size_t defaultMemoryBudget();

struct RenderOptions {
  int width = 640, height = 480;
  MaskLayout mask{8, 4};
  int budget = 64;          ///< fragments kept exactly per pixel (K); the rest blend into a tail
  /// Fragments behind subpixels whose transmittance is already <= this are skipped before
  /// rasterisation (error <= epsilon per pixel; 0: exact, only wholly hidden ones are skipped).
  /// Default 1e-4: below one 8-bit sRGB step even at black (sRGB's slope there is 12.92).
  double occlusionEpsilon = 1e-4;
  /// Deep shares (docs/abuffer.md, "Deep shares"): in a pixel that a surface's solid fragment
  /// covers, the fragments hidden anywhere share what the wholly visible ones leave of the pixel
  /// by the samples they own, instead of each weighing its exact area times the share of its
  /// own samples it owns. Dense fur over a body: its error against the truth falls by a fifth
  /// at 8x4 and a third at 8x8 (docs/benchmarks.md, "Deep shares, on by default"), and no
  /// picture of the gallery loses more than 0.4% against its own reference. On by default;
  /// off: the resolve's usual rule everywhere. Culling keeps its bound either way. (Each tile
  /// draws its surfaces before its wires, on or off.)
  bool deepShares = true;
  int tileSize = 32;
  int threads = 0;          ///< 0: all cores
  ShadingPath shading = ShadingPath::Closed;
  WireDepth wireDepth = WireDepth::Round;
  SimplifyOptions simplify{};
  PseudoReflectanceMapOptions map{};
  /// Tables for a viewGrid x viewGrid grid of view directions over the image, blended by screen
  /// position (1: the paper's single orthographic table; see render/view_tables.h). Default 1:
  /// the tables cost n^2 builds (about 4 ms each) and pay off on large images of many fragments;
  /// `wirefur accuracy` shows the curve.
  int viewGrid = 1;
  int sphereResolution = 256;
  /// Colour maps, bumps and grooves box-filtered over each pixel's (u, v) footprint (true), or
  /// point-sampled at the fragment's centroid (false: the unfiltered baseline of the accuracy
  /// study). The reference renderer always point-samples at every sub-sample.
  bool filterTextures = true;
  /// Pixels of this image per pixel of the picture it stands for: widths given in pixels
  /// (SceneWire::thicknessInPixels) are multiplied by it. A render at 1/F of the size that is
  /// scaled up afterwards (vtkWireFurRenderPass's image reduction) sets 1/F, so that a 3-pixel
  /// wire is still 3 pixels wide in the scaled-up picture. The simplification's target width and
  /// cells stay in pixels of this image (a reduced frame simplifies more, as hairs of world
  /// width do). 1e-6 ... 1e6; default 1.
  double pixelScale = 1.0;
  /// External opaque depth (optional, not owned): width * height view depths d = -z_eye, row 0
  /// at the top, +inf (or NaN) where nothing opaque lies. It stands for an opaque surface drawn
  /// elsewhere (OpenGL, by vtkWireFurRenderPass) that the image is composited over: a fragment
  /// counts only if its depth at the shading point (the centroid of its coverage, `zkey`) is
  /// nearer than the opaque depth at its pixel; otherwise it is dropped before shading. One
  /// depth per pixel, so the edge of that opaque surface across a fragment is not antialiased
  /// (the surface drawn elsewhere is not either). render() only; renderReference ignores it.
  const std::vector<float>* opaqueDepth = nullptr;
  /// Shading tables kept between frames (render/shading_cache.h): rebuilt only when material,
  /// eye-space lights, table options or view grid change. Null: built for every render.
  std::shared_ptr<ShadingCache> shadingCache;
  /// A band of rows: only the tiles that hold rows in [rowBegin, rowEnd) are rendered (the band
  /// of one process in a sort-first split of the image, vtkWireFurRenderPass under MPI); the
  /// band's pixels are those of the whole render bit for bit, and the rows of tiles wholly
  /// outside it are left transparent black. Set-up still sees the whole scene (so simplification
  /// decides as for the whole image); only the band's tiles are binned. 0, 0 (the default): all rows.
  /// render() only.
  int rowBegin = 0, rowEnd = 0;
  int referenceSamples = 16;  ///< brute-force reference: n x n stratified samples per pixel
  std::uint64_t referenceSeed = 1;
  /// Most bytes one render may hold at its peak (estimateRenderBytes: image, tile buffers of
  /// every thread, primitives and bins, shading tables), checked before anything large is
  /// allocated: problem() reports the scene-independent part, render() and renderReference()
  /// throw std::length_error with memoryProblem()'s line. Under it the tile items are binned in
  /// smaller bands of tile rows (binBands), down to one row. 0: unlimited.
  size_t memoryBudget = defaultMemoryBudget();
  /// Empty when usable; otherwise what is wrong.
  std::string problem() const;
};

struct RenderStats {
  // seconds
  double total = 0, setup = 0, maps = 0, binning = 0, raster = 0;
  size_t tablesReused = 0;  ///< shading tables taken from RenderOptions::shadingCache
  // what went in
  size_t triangles = 0, segments = 0;       ///< accepted input primitives
  size_t primitives = 0;                    ///< screen polygons after clipping
  size_t rejectedNonFinite = 0;             ///< primitives with NaN / Inf vertices, skipped
  size_t droppedZeroLength = 0;             ///< zero-length segments, dropped
  size_t clippedAway = 0;                   ///< wholly outside near / far / image, cut to a point on a plane, or a width that rounds to 0
  size_t endOnDiscs = 0;                    ///< segments drawn as their disc (seen end-on)
  size_t primitivesOccluded = 0;            ///< (primitive, tile) pairs skipped: tile hidden in front
  /// The fragment stage's work, for the per-stage costs of the benchmarks.
  struct RasterWork {
    std::uint64_t items = 0;         ///< (primitive, tile) pairs rasterised (not culled whole)
    std::uint64_t rows = 0;          ///< pixel rows of them visited
    std::uint64_t rowsCulled = 0;    ///< of those, skipped whole (hidden in front)
    std::uint64_t pixels = 0;        ///< pixels visited in the rows not culled
    std::uint64_t pixelsCulled = 0;  ///< of those, skipped before their area (hidden in front)
    std::uint64_t masksHidden = 0;   ///< skipped after their mask (its subpixels hidden in front)
    std::uint64_t emitted = 0;       ///< fragments handed to the A-buffer
    void add(const RasterWork& o) {
      items += o.items, rows += o.rows, rowsCulled += o.rowsCulled, pixels += o.pixels;
      pixelsCulled += o.pixelsCulled, masksHidden += o.masksHidden, emitted += o.emitted;
    }
  } work;
  // what the A-buffer did
  ABufferCounters abuffer;
  size_t tiles = 0, tilesEmpty = 0;  ///< tiles binned (a row band's only), those with no item
  size_t binBands = 0;  ///< bands of tile rows binned and drawn one after another (render, renderReference: their items not all held at once)
  int pseudoReflectanceMaps = 0, reflectanceSpheres = 0;  ///< built for this render
  int viewGrid = 1;                                       ///< nodes per side of the view-direction grid
  /// Primitives + bins (the largest band's items, the counts while any band is left to bin) +
  /// tile buffers and the threads' depth caches (as render() holds them over time).
  size_t peakBytes = 0;
  // error estimate (each an upper bound or a measurement, radiance units or coverage)
  double coverageQuantisation = 0;  ///< 1/N: one subpixel, where masks decide hiding
  double mapError = 0;              ///< max |map - exact| (orthographic) over a test set
  double sphereError = 0;           ///< max |sphere - Phong| over a test set
  /// Closed path: the lobe tables' measured error (CylinderLobeTable::measuredError) times the
  /// largest specular colour and the lights' summed intensity: a bound on |closed - exact|.
  double lobeError = 0;
  int lobeTables = 0;               ///< closed path: lobe tables built (one per exponent)
  double orthographicError = 0;     ///< tables with the view-direction approximation vs exact, where worst
  double budgetTailShare = 0;       ///< share of fragments blended into tails
  double occlusionEpsilon = 0;      ///< bound of the error of occlusion culling per pixel
  /// Stochastic simplification (RenderOptions::simplify): hairs of aggregate wires considered,
  /// drawn, and the smallest fraction drawn anywhere (1: nothing simplified).
  size_t simplifiedHairs = 0, simplifiedKept = 0;
  double simplifiedLambda = 1.0;
  std::vector<std::string> warnings;
};

struct RenderResult {
  ImageRGBA image;  ///< premultiplied linear RGBA over the scene's background
  RenderStats stats;
};

/// Bytes render() (renderReference() when `reference`) of `scene` is expected to hold at its
/// peak: the float RGBA image, one tile buffer per worker thread (fragment lists counted at
/// min(budget, 4) entries per pixel: deeper pixels add up to `budget` each), the primitives and
/// their attributes (each large array rounded to 2 MiB pages), the shading tables the scene's
/// materials need, and the tile items of a band of tile rows: a quarter of the primitives'
/// bytes or 4 MiB, whichever is more (binBands; no more than one item a primitive a tile, and
/// one tile row may hold more), or under options.memoryBudget what the budget leaves, at least
/// one item a primitive (the least a render needs: a budget below that is refused). Counted
/// from the input alone, before set-up.
size_t estimateRenderBytes(const Scene& scene, const RenderOptions& options, bool reference = false);
/// Empty when estimateRenderBytes fits options.memoryBudget (or the budget is 0); otherwise one
/// line: "image of WxH needs about X GiB, over the memory budget of Y GiB (...)".
std::string memoryProblem(const Scene& scene, const RenderOptions& options, bool reference = false);

/// The A-buffer render. Throws std::length_error (memoryProblem()) when over the memory budget.
RenderResult render(const Scene& scene, const RenderOptions& options);

// (releaseRenderMemory and renderMemoryHeld: core/large_memory.h, the blocks the renders free.)

/// Brute-force reference: options.referenceSamples^2 stratified point samples per pixel, each
/// taking the nearest opaque primitive and the translucent ones in front of it (sorted), shaded
/// by options.shading (Exact for a true reference). Same geometry as render(). Throws
/// std::length_error when over the memory budget, as render() does.
RenderResult renderReference(const Scene& scene, const RenderOptions& options);

}  // namespace wf

#include "render/renderer.h"

#include "render/shading_cache.h"

#include "abuffer/screen_polygon.h"
#include "core/limits.h"
#include "render/pipeline.h"
#include "render/rasterize.h"
#include "shading/cylinder_shading.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdio>
#include <set>
#include <stdexcept>

namespace wf {

size_t defaultMemoryBudget() {
  static const size_t budget = [] {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || page <= 0) return size_t(8) << 30;
    return size_t(pages) / 2 * size_t(page);
  }();
  return budget;
}

namespace {
std::string describeBytes(double b) {
  char buf[64];
  if (b >= 1024.0 * 1024 * 1024) std::snprintf(buf, sizeof buf, "%.3g GiB", b / (1024.0 * 1024 * 1024));
  else if (b >= 1024.0 * 1024) std::snprintf(buf, sizeof buf, "%.3g MiB", b / (1024.0 * 1024));
  else std::snprintf(buf, sizeof buf, "%.0f bytes", b);
  return buf;
}
}  // namespace

double renderImageAndTileBytes(const Scene& scene, const RenderOptions& o, bool reference) {
  const double w = std::max(o.width, 0), h = std::max(o.height, 0);
  double bytes = w * h * double(sizeof(glm::vec4));  // the image
  bytes += largeArrayRounding(bytes);                  // (on huge pages: core/large_memory.h)
  const int threads = o.threads > 0 ? o.threads : tbb::this_task_arena::max_concurrency();
  const int tile = std::clamp(o.tileSize, 1, 4096);
  const int tw = int(std::min<double>(tile, w)), th = int(std::min<double>(tile, h));
  double tileBytes =
      reference ? double(tw) * th * double(o.referenceSamples) * o.referenceSamples * (sizeof(float) + sizeof(std::int32_t))
                : double(TileABuffer::bytesFor(tw, th, o.mask, std::clamp(o.budget, 1, 4)));
  // Hidden lines drawn (dashed, ghost): the tile's x-ray fragments, at most kXrayPerPixel a pixel.
  bool xray = false;
  for (const SceneWire& wr : scene.wires) xray = xray || (wr.hidden.drawn() && wr.lines.points.size() >= 2);
  if (xray && !reference) {
    tileBytes += double(tw) * th * double(TileABuffer::xrayBytesPerPixel());
  }
  // A thread resolving wires keeps a cache of their depth bases (PreparedFragmentSource).
  bool wires = false;
  for (const SceneWire& wr : scene.wires) wires = wires || wr.lines.points.size() >= 2;
  if (wires && !reference) tileBytes += double(PreparedFragmentSource::cacheBytesPerThread());
  const double tiles = std::ceil(w / tile) * std::ceil(h / tile);
  return bytes + std::min<double>(threads, std::max(tiles, 1.0)) * tileBytes;
}
size_t estimateRenderBytes(const Scene& scene, const RenderOptions& o, bool reference) {
  // In double: a 16384^2 image with millions of primitives must not wrap.
  const double w = std::max(o.width, 0), h = std::max(o.height, 0);
  const int threads = o.threads > 0 ? o.threads : tbb::this_task_arena::max_concurrency();
  const int tile = std::clamp(o.tileSize, 1, 4096);
  const double tiles = std::ceil(w / tile) * std::ceil(h / tile);
  double bytes = renderImageAndTileBytes(scene, o, reference);
  // Primitives: room for every input triangle with 5 screen vertices (the most near / far
  // clipping leaves) and every input segment, and the per-chunk tile counts of the binning (the
  // bins' items last: what a budget leaves them).
  double triangles = 0, segments = 0;
  for (const SceneSurface& s : scene.surfaces) triangles += double(s.mesh.triangles.size());
  for (const SceneWire& wr : scene.wires)
    segments += std::max(0.0, double(wr.lines.points.size()) - double(wr.lines.polylineCount()));
  const double perTriangle = sizeof(TrianglePrim) + 5 * sizeof(glm::dvec2) + sizeof(TriangleAttributes);
  // (colours when kept; a dashed wire's patterns, PreparedScene::dashPattern, for every segment of a
  // scene with one: prepareScene keeps them for all or none)
  const double perSegment =
      sizeof(SegmentPrim) + sizeof(SegmentShading) + sizeof(SegmentColours) + (keepsDashPatterns(scene) ? sizeof(glm::vec2) : 0);
  // The binning's per-chunk tile counts (binning.cpp: up to 4 chunks a thread, 65,536 primitives each).
  const double chunks = std::clamp(std::ceil((triangles + segments) / 65536.0), 1.0, 4.0 * threads);
  const double primitiveBytes = triangles * perTriangle + segments * perSegment;
  // Each large array (allocateLarge: kLargeAllocation and more) is rounded up to whole 2 MiB pages.
  const auto rounded = largeArrayRounding;
  const double rounding = rounded(triangles * sizeof(TrianglePrim)) + rounded(triangles * sizeof(TriangleAttributes)) +
                          rounded(triangles * 5 * sizeof(glm::dvec2)) + rounded(segments * sizeof(SegmentPrim)) +
                          rounded(segments * sizeof(SegmentShading)) + rounded(segments * sizeof(SegmentColours)) +
                          (keepsDashPatterns(scene) ? rounded(segments * sizeof(glm::vec2)) : 0.0);
  // (and the counts' rows per block of primitives)
  bytes += primitiveBytes + rounding + (tiles + 1) * sizeof(std::uint32_t) * (1 + 2 * chunks) +
           std::ceil((triangles + segments) / double(BinCounts::kBlock)) * 2 * sizeof(int);
  // Shading tables (maps path): a pair of pseudo-reflectance maps per wire material, a
  // reflectance sphere per surface material, for every node of the view grid.
  if (o.shading == ShadingPath::Maps) {
    const double nodes = double(std::clamp(o.viewGrid, 1, 16)) * std::clamp(o.viewGrid, 1, 16);
    std::set<int> wireMaterials, surfaceMaterials;
    const int nm = std::max(1, int(scene.materials.size()));
    for (const SceneWire& wr : scene.wires)
      if (wr.style == WireStyle::Shaded) wireMaterials.insert(std::clamp(wr.material, 0, nm - 1));
    for (const SceneSurface& s : scene.surfaces) surfaceMaterials.insert(std::clamp(s.material, 0, nm - 1));
    const double map = 2.0 * double(o.map.resolution) * o.map.resolution * sizeof(glm::vec3);
    const double sphere = double(o.sphereResolution) * o.sphereResolution * sizeof(glm::vec3);
    bytes += nodes * (double(wireMaterials.size()) * map + 2.0 * double(surfaceMaterials.size()) * std::max(map, sphere));
  }
  // The items of a band of tile rows (binBands): at least one a primitive; a band holds up to a
  // quarter of the primitives' bytes, or kOneBand, of them (a hair crosses several tiles: about
  // five items a hair on the 700,000-hair torus; none more than one a tile), and under a memory
  // budget no more than it leaves: the least a render needs is then one item a primitive.
  const double oneEach = (triangles + segments) * sizeof(TileBins::Item);
  const double cap = bandItemCap(primitiveBytes, o.memoryBudget > 0 ? double(o.memoryBudget) - bytes : INFINITY);
  const double items = std::max(oneEach, std::min(cap, oneEach * tiles));
  bytes += items + rounded(items);
  return bytes >= 1.8e19 ? SIZE_MAX : size_t(bytes);
}

std::string memoryProblem(const Scene& scene, const RenderOptions& o, bool reference) {
  if (o.memoryBudget == 0) return {};
  const size_t need = estimateRenderBytes(scene, o, reference);
  if (need <= o.memoryBudget) return {};
  return "image of " + std::to_string(o.width) + "x" + std::to_string(o.height) + " needs about " +
         describeBytes(double(need)) + ", over the memory budget of " + describeBytes(double(o.memoryBudget)) +
         " (RenderOptions::memoryBudget / --memory-budget)";
}

std::string optionsProblem(const RenderOptions& o) {
  if (o.width < 1 || o.height < 1 || o.width > kMaxImageSide || o.height > kMaxImageSide)
    return "image size must be 1 ... " + std::to_string(kMaxImageSide) + " on each side";
  if (!o.mask.valid()) return "mask must be 4x4, 8x4 or 8x8";
  if (o.budget < 1 || o.budget > kMaxListBudget) return "budget must be 1 ... " + std::to_string(kMaxListBudget);
  if (!(o.occlusionEpsilon >= 0.0 && o.occlusionEpsilon <= 0.1)) return "occlusion epsilon must be 0 ... 0.1";
  if (o.tileSize < 8 || o.tileSize > TileBins::kMaxTileSize)
    return "tile size must be 8 ... " + std::to_string(TileBins::kMaxTileSize);
  if (o.threads < 0 || o.threads > kMaxThreads) return "threads must be 0 ... " + std::to_string(kMaxThreads);
  if (o.referenceSamples < 1 || o.referenceSamples > kMaxReferenceSamples)
    return "reference samples must be 1 ... " + std::to_string(kMaxReferenceSamples);
  if (o.map.resolution < kMinMapResolution || o.map.resolution > kMaxMapResolution)
    return "map resolution must be " + std::to_string(kMinMapResolution) + " ... " + std::to_string(kMaxMapResolution);
  if (o.map.samples < 1 || o.map.samples > kMaxMapSamples) return "map samples must be 1 ... " + std::to_string(kMaxMapSamples);
  if (o.sphereResolution < kMinSphereResolution || o.sphereResolution > kMaxSphereResolution)
    return "sphere resolution must be " + std::to_string(kMinSphereResolution) + " ... " + std::to_string(kMaxSphereResolution);
  if (o.viewGrid < 1 || o.viewGrid > kMaxViewGrid) return "view grid must be 1 ... " + std::to_string(kMaxViewGrid);
  if (!(o.pixelScale >= 1e-6 && o.pixelScale <= 1e6)) return "pixel scale must be 1e-6 ... 1e6";
  if (o.opaqueDepth && o.opaqueDepth->size() != size_t(o.width) * size_t(o.height))
    return "opaque depth must hold width x height values";
  if (!(o.rowBegin == 0 && o.rowEnd == 0) && !(0 <= o.rowBegin && o.rowBegin < o.rowEnd && o.rowEnd <= o.height))
    return "the band of rows must be 0 <= begin < end <= height (or 0, 0 for all rows)";
  return {};
}

std::string RenderOptions::problem() const {
  if (std::string m = optionsProblem(*this); !m.empty()) return m;
  return memoryProblem(Scene{}, *this);  // the image and tile buffers alone
}

namespace {

glm::vec4 overBackground(const glm::vec4& c, const glm::vec4& bg) {
  const float t = 1.0f - c.w;
  return glm::vec4(glm::vec3(c) + t * glm::vec3(bg) * bg.w, c.w + t * bg.w);
}

}  // namespace

RenderResult render(const Scene& scene, const RenderOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  RenderResult result;
  RenderStats& st = result.stats;
  // Options out of range (a 0-pixel image, a 5x5 mask, -1 threads) are refused here as well as
  // by the callers that check them first: nothing below is defined for them. Then the memory
  // the scene needs, before allocating.
  if (std::string m = optionsProblem(options); !m.empty()) throw std::invalid_argument("render options: " + m);
  if (std::string m = memoryProblem(scene, options); !m.empty()) throw std::length_error(m);
  result.image = ImageRGBA(options.width, options.height);
  const glm::vec4 background = sanitizedBackground(scene.background);  // NaN / Inf would reach every pixel
  inArena(options.threads, [&] {
    if (options.shadingCache) options.shadingCache->beginFrame();
    PreparedScene ps = prepareScene(scene, options, st);
    if (options.shadingCache) options.shadingCache->endFrame();  // tables in use are held by ps too
    // The tile rows drawn: all, or those holding the band's rows (another process draws the
    // rest: their items are not even formed).
    const bool band = options.rowEnd > options.rowBegin;
    const int rowLo = band ? options.rowBegin / options.tileSize : 0;
    const int rowHi = band ? (options.rowEnd + options.tileSize - 1) / options.tileSize : std::numeric_limits<int>::max();
    const auto tb = std::chrono::steady_clock::now();
    BinCounts binCounts = countBins(ps, options.tileSize, rowLo, rowHi);
    st.binning += secondsSince(tb);
    const size_t countBytes = binCounts.bytes();
    // A band's places while it is filled (binPrimitives: a 32-bit start per chunk and tile).
    const size_t placeBytes = binCounts.chunks * size_t(binCounts.tilesX) *
                              size_t(binCounts.rowEnd - binCounts.rowBegin) * sizeof(std::uint32_t);
    std::uint64_t largestBand = 0;
    const double alsoHeld = renderImageAndTileBytes(scene, options, false);
    const std::vector<std::pair<int, int>> bands =
        binBands(ps, binCounts, options.memoryBudget, alsoHeld, largestBand);
    st.binBands = bands.size();
    checkBinsFit(ps, binCounts, largestBand, options.memoryBudget, alsoHeld);  // before any band is drawn
    TileBins bins;
    bins.items.reserve(largestBand);  // once: every band's items fit it
    size_t binBytes = 0;
    const PreparedFragmentSource source(ps);
    const int tilesX = binCounts.tilesX;
    tbb::enumerable_thread_specific<TileABuffer> buffers(
        [&] { return TileABuffer(options.mask, options.budget, float(options.occlusionEpsilon), options.deepShares); });
    tbb::enumerable_thread_specific<ABufferCounters> counters;
    tbb::enumerable_thread_specific<size_t> occludedPrims(0);
    tbb::enumerable_thread_specific<RenderStats::RasterWork> work;
    for (const auto& [bandBegin, bandEnd] : bands) {
      binPrimitives(ps, binCounts, bandBegin, bandEnd, st, 0, bins);  // (checked above)
      binBytes = std::max(binBytes, bins.bytes());
      if (bandEnd == bands.back().second) binCounts = BinCounts{};  // the last band's: the counts are done with
      const auto tr = std::chrono::steady_clock::now();
      tbb::parallel_for(bandBegin * tilesX, bandEnd * tilesX, [&](int tile) {
        const int tx0 = (tile % tilesX) * options.tileSize, ty0 = (tile / tilesX) * options.tileSize;
        const int tx1 = std::min(options.width, tx0 + options.tileSize);
        const int ty1 = std::min(options.height, ty0 + options.tileSize);
        const uint32_t b0 = bins.begin(tile), b1 = bins.end(tile);
        if (b0 == b1) {
          for (int y = ty0; y < ty1; ++y)
            for (int x = tx0; x < tx1; ++x) result.image.at(x, y) = overBackground(glm::vec4(0), background);
          return;
        }
        TileABuffer& buf = buffers.local();
        buf.reset(tx1 - tx0, ty1 - ty0, tx0, ty0, &source);
        // The external opaque depth (RenderOptions::opaqueDepth): its farthest value over the
        // tile rejects whole primitives behind it, its per-pixel value single fragments.
        const float* opaque = options.opaqueDepth ? options.opaqueDepth->data() : nullptr;
        float opaqueTileMax = INFINITY;
        if (opaque) {
          opaqueTileMax = 0.0f;
          for (int y = ty0; y < ty1 && opaqueTileMax < INFINITY; ++y)
            for (int x = tx0; x < tx1; ++x) {
              const float d = opaque[size_t(y) * size_t(options.width) + size_t(x)];
              if (!(d <= opaqueTileMax)) opaqueTileMax = std::isnan(d) ? INFINITY : d;
            }
        }
        auto opaqueAt = [&](int x, int y) {
          const float d = opaque[size_t(y) * size_t(options.width) + size_t(x)];
          return std::isnan(d) ? INFINITY : d;
        };
        // The surfaces first, then the wires, each front to back by its nearest depth in this tile
        // (ties by primitive order: a strict order, so the same whatever the thread count), so
        // that the occlusion tests discard most of what lies behind before it is rasterised. The
        // surfaces first, so that only surfaces ever cull a surface: whether a pixel holds one
        // (deep shares' gate, TileABuffer::setSolid's Pixel::surface) then does not depend on
        // occlusionEpsilon.
        // (The items arrive in primitive order, triangles before segments: two ranges.)
        thread_local std::vector<TileBins::Item> order, sortScratch;
        order.assign(bins.items.begin() + b0, bins.items.begin() + b1);
        const std::uint32_t n = std::uint32_t(order.size());
        const std::uint32_t triangleCount = std::uint32_t(ps.triangles.size());
        const size_t surfaces = size_t(std::partition_point(order.begin(), order.end(), [&](const TileBins::Item& it) {
                                         return it.index < triangleCount;
                                       }) - order.begin());
        sortTileItems(order.data(), surfaces, sortScratch);
        sortTileItems(order.data() + surfaces, n - surfaces, sortScratch);
        RenderStats::RasterWork& wk = work.local();
        // Bands of rows culled whole count no fragments (like primitives culled whole per tile).
        auto cullBand = [&](int x0, int y0, int x1, int y1, double z) {
          return z >= buf.regionOcclusionDepth(x0 - tx0, y0 - ty0, x1 - tx0, y1 - ty0);
        };
        auto cullRow = [&](int y, int x0, int x1, double z) {
          if (!(z >= buf.rowOcclusionDepth(y - ty0, x0 - tx0, x1 - tx0))) return false;
          buf.countCulledRow(y - ty0, x0 - tx0, x1 - tx0);
          return true;
        };
        auto cullPixel = [&](int x, int y, double z) {
          if (!(z >= buf.occlusionDepth(x - tx0, y - ty0)) && !(opaque && z >= opaqueAt(x, y))) return false;
          buf.countCulled(x - tx0, y - ty0);
          return true;
        };
        auto hidden = [&](int x, int y, MaskBits mask, int subpixel, double z) {
          if (!buf.maskHidden(x - tx0, y - ty0, mask, subpixel, float(z))) return false;
          buf.countCulled(x - tx0, y - ty0);
          return true;
        };
        ScreenPolygon poly;
        // Whether an item culled whole still needs its wire's shader (below): only where some wire
        // rests on a surface or draws its hidden parts.
        const bool culledAsksShader = ps.anyResting || ps.anyXray;
        for (std::uint32_t oi = 0; oi < n; ++oi) {
          const TileBins::Item& item = order[oi];
          // Hierarchical occlusion first, from the bin item alone: is the primitive behind
          // everything over its rectangle in this tile?
          // (A wire that draws its hidden parts still gives its x-ray copy.)
          // (The external depth has no surface to judge an edge against at its axis: it culls all.)
          const bool behindExternal = item.zlo >= opaqueTileMax;
          bool occludedWhole = behindExternal || item.zlo >= buf.regionOcclusionDepth(item.x0, item.y0, item.x1, item.y1);
          if (occludedWhole && !behindExternal && item.index >= triangleCount && culledAsksShader) {
            // A wire resting on a surface is judged at its axis: culled whole only when its whole
            // axis lies in this tile's part of its rectangle (then what hides it there hides its
            // axis too; see cullAtAxis below). One that draws its hidden parts still gives its
            // x-ray copy. (Asked only where some wire does either, culledAsksShader: the shader is
            // read through the segment, a cache miss for each of the many items a dense scene
            // culls whole.)
            const ShaderSlot& ws = ps.shaderOf(item.index);
            if (ws.restsOnSurface) {
              const SegmentPrim& sg = ps.segments[item.index - triangleCount];
              const double bx0 = tx0 + item.x0, by0 = ty0 + item.y0, bx1 = tx0 + item.x1 + 1.0, by1 = ty0 + item.y1 + 1.0;
              auto in = [&](const glm::dvec2& q) { return q.x >= bx0 && q.x < bx1 && q.y >= by0 && q.y < by1; };
              occludedWhole = in(sg.p0) && in(sg.p1);
            }
            if (!occludedWhole) {
            } else if (ws.hidden.drawn()) {
              ++occludedPrims.local();
            } else {
              ++occludedPrims.local();
              continue;
            }
          } else if (occludedWhole) {
            ++occludedPrims.local();
            continue;
          }
          // Survivors are scattered through memory: fetch the next ones' data ahead.
          for (std::uint32_t ahead = oi + 1; ahead < std::min(n, oi + 4); ++ahead) {
            const std::uint32_t k = order[ahead].index;
            if (k >= triangleCount) __builtin_prefetch(&ps.segments[k - triangleCount]);
            else __builtin_prefetch(&ps.triangles[k]);
          }
          const std::uint32_t index = item.index;
          const ShaderSlot& slot = ps.shaderOf(index);
          const float opacity = slot.opacity;
          std::uint32_t tag;
          bool mayMerge;
          const bool segment = index >= triangleCount;
          if (!occludedWhole) ++wk.items;
          // The fragment of a pixel's coverage (also the x-ray copy's, below).
          auto fragmentOf = [&](const PixelCoverage& pc) {
            Fragment f;
            f.zmin = pc.zmin;
            f.zmax = pc.zmax;
            f.zkey = pc.zkey;
            f.area = float(pc.area);
            f.mask = pc.mask;
            f.opacity = opacity;
            f.tag = tag;
            f.mayMerge = mayMerge;
            f.occludesEarly = segment;
            f.prim = index;
            f.cx = Fragment::toPoint(pc.cx - pc.x);
            f.cy = Fragment::toPoint(pc.cy - pc.y);
            f.shaded = false;  // shaded only if it survives (PreparedFragmentSource)
            f.holdout = slot.holdout;
            f.onSurface = segment && slot.restsOnSurface;
            return f;
          };
          auto emit = [&](const PixelCoverage& pc) {
            if (opaque && !(pc.zkey < opaqueAt(pc.x, pc.y))) return;  // behind the external surface
            buf.insert(pc.x - tx0, pc.y - ty0, fragmentOf(pc), pc.subpixel);
          };
          const int rx0 = tx0 + item.x0, ry0 = ty0 + item.y0, rx1 = tx0 + item.x1, ry1 = ty0 + item.y1;
          screenPolygonOf(ps, index, poly);
          if (index >= triangleCount) {
            const SegmentPrim& s = ps.segments[index - triangleCount];
            tag = s.tag;
            mayMerge = s.flags & kSegmentMayMerge;
            const SegmentDepth depth(ps.view, s, ps.wireDepth, segmentUsesCapsule(ps, index), segmentWidthInPixels(ps, index));
            auto never = [](auto&&...) { return false; };
            // A wire resting on a surface is judged at its axis (Fragment::onSurface): a plane in
            // front over a pixel beside its axis may be behind it at the axis. So a pixel (a row) of
            // it is culled only where that pixel (row) and the pixels of the axis points nearest to
            // it are hidden in front of it, all in this tile; never a band at once (a tile only as
            // above).
            const SegmentFrame& fr = depth.frame;
            auto axisAt = [&](double x, double y) {
              const double t = fr.length > 0 ? std::clamp(fr.t(x, y), 0.0, 1.0) : 0.0;
              return glm::dvec2(s.p0.x + t * (s.p1.x - s.p0.x), s.p0.y + t * (s.p1.y - s.p0.y));
            };
            // Every pixel the axis passes from a to b hidden in front of z (sampled at half pixels).
            auto axisHidden = [&](const glm::dvec2& a, const glm::dvec2& b, double z) {
              const int steps = 1 + int(2.0 * std::max(std::abs(b.x - a.x), std::abs(b.y - a.y)));
              for (int k = 0; k <= steps; ++k) {
                const glm::dvec2 q = a + (b - a) * (double(k) / steps);
                const double qx = std::floor(q.x), qy = std::floor(q.y);
                if (!(qx >= tx0 && qx < tx1 && qy >= ty0 && qy < ty1)) return false;
                if (!(z >= buf.occlusionDepth(int(qx) - tx0, int(qy) - ty0))) return false;
              }
              return true;
            };
            auto cullAtAxis = [&](int x, int y, double z) {
              if (opaque && z >= opaqueAt(x, y)) {
                buf.countCulled(x - tx0, y - ty0);
                return true;
              }
              if (!(z >= buf.occlusionDepth(x - tx0, y - ty0))) return false;
              const glm::dvec2 a = axisAt(x + 0.5, y + 0.5);
              if (!axisHidden(a, a, z)) return false;
              buf.countCulled(x - tx0, y - ty0);
              return true;
            };
            auto cullRowAtAxis = [&](int y, int x0, int x1, double z) {
              if (!(z >= buf.rowOcclusionDepth(y - ty0, x0 - tx0, x1 - tx0))) return false;
              // t is linear along the row: the nearest axis points of its pixels lie between these
              if (!axisHidden(axisAt(x0 + 0.5, y + 0.5), axisAt(x1 + 0.5, y + 0.5), z)) return false;
              buf.countCulledRow(y - ty0, x0 - tx0, x1 - tx0);
              return true;
            };
            if (slot.restsOnSurface)
              rasterizePolygon(poly, depth, rx0, ry0, rx1, ry1, ty0, options.mask, wk, never, cullRowAtAxis, cullAtAxis, never,
                               emit);
            else if (!occludedWhole)
              rasterizePolygon(poly, depth, rx0, ry0, rx1, ry1, ty0, options.mask, wk, cullBand, cullRow, cullPixel, hidden,
                               emit);
            if (slot.hidden.drawn()) {
              // Its x-ray copy (hidden lines): every fragment, whatever hides it; the resolve
              // draws it where an opaque surface in front does (TileABuffer::insertXray).
              const bool dashed = slot.hidden.mode == HiddenLines::Mode::Dashed && !ps.dashPattern.empty();
              const glm::vec2 pattern = dashed ? ps.dashPattern[index - triangleCount] : glm::vec2(0.0f);
              const SegmentFrame& fr = depth.frame;
              RenderStats::RasterWork xw;
              auto emitXray = [&](const PixelCoverage& pc) {
                float factor = slot.hidden.ghost;
                if (dashed) {
                  const double t = fr.length > 0 ? std::clamp(fr.t(pc.cx, pc.cy), 0.0, 1.0) : 0.0;
                  const double along = t * fr.length;  // screen pixels from p0
                  factor = dashCoverage(pattern.x + along + along * double(pattern.y), slot.hidden.dash, slot.hidden.gap);
                }
                buf.insertXray(pc.x - tx0, pc.y - ty0, fragmentOf(pc), factor, pc.subpixel);
              };
              rasterizePolygon(poly, depth, rx0, ry0, rx1, ry1, ty0, options.mask, xw, never, never, never, never,
                               emitXray);
            }
          } else {
            const TrianglePrim& t = ps.triangles[index];
            tag = t.tag;
            mayMerge = t.mayMerge;
            rasterizePolygon(poly, TriangleDepth(ps.view, t), rx0, ry0, rx1, ry1, ty0, options.mask, wk,
                             cullBand, cullRow, cullPixel, hidden, emit);
          }
        }
        buf.resolveTile([&](int x, int y, const glm::vec4& c) { result.image.at(tx0 + x, ty0 + y) = overBackground(c, background); });
        buf.finish(counters.local());
      });
      st.raster += secondsSince(tr);
    }
    for (const ABufferCounters& c : counters) {
      const size_t peak = c.peakBytes;
      const std::uint64_t held = c.peakFragmentsHeld;
      ABufferCounters copy = c;
      copy.peakBytes = 0;
      copy.peakFragmentsHeld = 0;
      st.abuffer.add(copy);
      st.abuffer.peakBytes += peak;  // buffers of different threads live at the same time
      st.abuffer.peakFragmentsHeld += held;
    }
    for (size_t n : occludedPrims) st.primitivesOccluded += n;
    for (const RenderStats::RasterWork& w : work) st.work.add(w);
    // The counts are held through the rasterising of every band but the last; a band's places
    // only while it is filled, the depth caches of the threads that resolved wires from then on.
    size_t caches = 0;
    if (!ps.segments.empty()) caches = buffers.size() * PreparedFragmentSource::cacheBytesPerThread();
    const size_t held = bands.size() > 1 ? countBytes + std::max(placeBytes, st.abuffer.peakBytes + caches)
                                         : std::max(countBytes + placeBytes, st.abuffer.peakBytes + caches);
    st.peakBytes = ps.bytes() + binBytes + held;
  });
  st.coverageQuantisation = 1.0 / options.mask.samples();
  st.occlusionEpsilon = options.occlusionEpsilon;
  st.budgetTailShare = st.abuffer.fragments ? double(st.abuffer.tail) / double(st.abuffer.fragments) : 0.0;
  st.total = secondsSince(t0);
  return result;
}

}  // namespace wf

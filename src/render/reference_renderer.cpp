// Brute-force reference for the A-buffer: n x n stratified (jittered) point samples per pixel,
// each resolving its own visibility (nearest opaque primitive, translucent ones in front of it
// in depth order), box-filtered. Same screen geometry as render(), so the difference between the
// two is the A-buffer's own error: mask quantisation where primitives overlap, the budget tail,
// and per-fragment shading. Shading is per (pixel, primitive) at the mean of that primitive's
// visible samples in the pixel, by options.shading (Exact: the cylinder integral / Phong at the
// true view vector).
#include "abuffer/screen_polygon.h"
#include "render/pipeline.h"
#include "render/renderer.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace wf {

namespace {

struct Translucent {
  std::uint32_t sample;
  float depth;
  std::uint32_t order;  // arrival, for ties
  std::uint32_t prim;
};

struct TileSamples {
  std::vector<float> depth;
  std::vector<std::int32_t> prim;
  std::vector<Translucent> translucent;
};

struct Visible {
  std::uint32_t prim;
  double sx, sy, sd;
  int n;
  glm::vec3 colour;   ///< shaded colour (unused when `perSample`)
  bool perSample;     ///< shading varies inside the pixel: shaded at every sample
};

}  // namespace

RenderResult renderReference(const Scene& scene, const RenderOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  RenderResult result;
  RenderStats& st = result.stats;
  // As render(): options out of range, then the memory the scene needs, before allocating.
  if (std::string m = optionsProblem(options); !m.empty()) throw std::invalid_argument("render options: " + m);
  if (std::string m = memoryProblem(scene, options, true); !m.empty()) throw std::length_error(m);
  result.image = ImageRGBA(options.width, options.height);
  const int S = options.referenceSamples, S2 = S * S;
  auto body = [&] {
    PreparedScene ps = prepareScene(scene, options, st);
    // Textures, bumps and grooves are point-sampled at every sub-sample and averaged, instead of
    // the A-buffer's box filter over one pixel's footprint.
    ps.filterTextures = false;
    auto variesInPixel = [&](std::uint32_t p) { return shadingVariesInPixel(ps, p); };
    // Binned and drawn in bands of tile rows, as render() does (binBands): a dense scene's items
    // are not all held at once.
    const auto tb = std::chrono::steady_clock::now();
    const BinCounts counts = countBins(ps, options.tileSize);
    st.binning += std::chrono::duration<double>(std::chrono::steady_clock::now() - tb).count();
    const double alsoHeld = renderImageAndTileBytes(scene, options, true);  // (as the estimate counts them)
    std::uint64_t largestBand = 0;
    const std::vector<std::pair<int, int>> bands = binBands(ps, counts, options.memoryBudget, alsoHeld, largestBand);
    st.binBands = bands.size();
    checkBinsFit(ps, counts, largestBand, options.memoryBudget, alsoHeld);  // before any band is drawn
    TileBins bins;
    bins.items.reserve(largestBand);  // once: every band's items fit it
    size_t binBytes = 0;
    tbb::enumerable_thread_specific<TileSamples> store;
    double rasterSeconds = 0.0;
    for (const auto& [rowBegin, rowEnd] : bands) {
      binPrimitives(ps, counts, rowBegin, rowEnd, st, 0, bins);  // (checkBinsFit has passed every band)
      binBytes = std::max(binBytes, bins.bytes());
      const auto tr = std::chrono::steady_clock::now();
      const int firstTile = rowBegin * bins.tilesX;
      tbb::parallel_for(firstTile, rowEnd * bins.tilesX, [&](int tile) {
        const int ts = options.tileSize;
        const int tx0 = (tile % bins.tilesX) * ts, ty0 = (tile / bins.tilesX) * ts;
        const int tx1 = std::min(options.width, tx0 + ts), ty1 = std::min(options.height, ty0 + ts);
        const int tw = tx1 - tx0, th = ty1 - ty0;
        TileSamples& buf = store.local();
        buf.depth.assign(size_t(tw) * th * S2, INFINITY);
        buf.prim.assign(size_t(tw) * th * S2, -1);
        buf.translucent.clear();
        auto samplePos = [&](int px, int py, int s, double& x, double& y) {
          const glm::dvec2 q = stratifiedSample(options.referenceSeed, px, py, s, S);
          x = q.x;
          y = q.y;
        };
        std::uint32_t order = 0;
        const std::uint32_t b0 = bins.begin(tile), b1 = bins.end(tile);
        for (std::uint32_t b = b0; b < b1; ++b) {
          const std::uint32_t pi = bins.items[b].index;
          const float opacity = ps.opacityOf(pi);
          const PrimitiveDepth depthAt(ps, pi);
          ScreenPolygon poly;
          screenPolygonOf(ps, pi, poly);
          EdgeFunction edges[ScreenPolygon::kMaxVertices];
          const int ne = polygonEdges(poly, edges);
          if (ne < 3) continue;
          const int r0 = ty0 + bins.items[b].y0, r1 = ty0 + bins.items[b].y1;
          ScreenPolygon half, band;
          for (int row = r0; row <= r1; ++row) {
            clipAxis(poly, half, false, row, true);
            clipAxis(half, band, false, row + 1.0, false);
            if (band.count < 3) continue;
            double xmin = band.x[0], xmax = band.x[0];
            for (int i = 1; i < band.count; ++i) xmin = std::min(xmin, band.x[i]), xmax = std::max(xmax, band.x[i]);
            int c0, c1;
            pixelColumns(xmin, xmax, tx0, tx1, c0, c1);
            for (int col = c0; col <= c1; ++col) {
              const size_t base = (size_t(row - ty0) * tw + (col - tx0)) * S2;
              for (int s = 0; s < S2; ++s) {
                double x, y;
                samplePos(col, row, s, x, y);
                bool in = true;
                for (int e = 0; e < ne && in; ++e) in = edges[e](x, y) >= 0.0;
                if (!in) continue;
                const double d = depthAt(x, y);
                if (opacity >= 1.0f) {
                  if (float(d) < buf.depth[base + s]) {
                    buf.depth[base + s] = float(d);
                    buf.prim[base + s] = std::int32_t(pi);
                  }
                } else if (opacity > 0.0f) {
                  buf.translucent.push_back({std::uint32_t(base + s), float(d), order++, pi});
                }
              }
            }
          }
        }
        std::sort(buf.translucent.begin(), buf.translucent.end(), [](const Translucent& a, const Translucent& b) {
          return a.sample < b.sample || (a.sample == b.sample && (a.depth < b.depth || (a.depth == b.depth && a.order < b.order)));
        });
        size_t tcur = 0;
        std::vector<Visible> vis;
        for (int py = ty0; py < ty1; ++py)
          for (int px = tx0; px < tx1; ++px) {
            const size_t base = (size_t(py - ty0) * tw + (px - tx0)) * S2;
            const size_t tbegin = tcur;
            while (tcur < buf.translucent.size() && buf.translucent[tcur].sample < base + S2) ++tcur;
            vis.clear();
            auto find = [&](std::uint32_t p) -> Visible& {
              for (Visible& v : vis)
                if (v.prim == p) return v;
              vis.push_back({p, 0, 0, 0, 0, glm::vec3(0), variesInPixel(p)});
              return vis.back();
            };
            // Pass 1: which primitives are seen, and where (for shading).
            size_t tp = tbegin;
            for (int s = 0; s < S2; ++s) {
              double x, y;
              samplePos(px, py, s, x, y);
              const float zo = buf.depth[base + s];
              for (; tp < tcur && buf.translucent[tp].sample == base + s; ++tp)
                if (buf.translucent[tp].depth < zo) {
                  Visible& v = find(buf.translucent[tp].prim);
                  v.sx += x, v.sy += y, v.sd += buf.translucent[tp].depth, ++v.n;
                }
              if (buf.prim[base + s] >= 0) {
                Visible& v = find(std::uint32_t(buf.prim[base + s]));
                v.sx += x, v.sy += y, v.sd += zo, ++v.n;
              }
            }
            // Primitives whose shading varies inside the pixel are shaded at every sample in pass 2
            // (with that sample's own transmittance); the others once, at their mean position.
            for (Visible& v : vis)
              if (!v.perSample) v.colour = shadeFragment(ps, v.prim, v.sx / v.n, v.sy / v.n, v.sd / v.n);
            // Pass 2: composite every sample front to back.
            glm::vec3 rgb(0.0f);
            float alpha = 0;
            tp = tbegin;
            for (int s = 0; s < S2; ++s) {
              float T = 1.0f;
              glm::vec3 c(0.0f);
              const float zo = buf.depth[base + s];
              double x, y;
              samplePos(px, py, s, x, y);
              auto colourAt = [&](std::uint32_t p, float depth) {
                const Visible& v = find(p);
                return v.perSample ? shadeFragment(ps, p, x, y, depth) : v.colour;
              };
              for (; tp < tcur && buf.translucent[tp].sample == base + s; ++tp) {
                if (!(buf.translucent[tp].depth < zo)) continue;
                const float a = ps.opacityOf(buf.translucent[tp].prim);
                c += T * a * colourAt(buf.translucent[tp].prim, buf.translucent[tp].depth);
                T *= 1.0f - a;
              }
              if (buf.prim[base + s] >= 0) {
                c += T * colourAt(std::uint32_t(buf.prim[base + s]), zo);
                T = 0;
              }
              rgb += c;
              alpha += 1.0f - T;
            }
            const glm::vec4 px4(rgb / float(S2), alpha / float(S2));
            const glm::vec4 bg = sanitizedBackground(scene.background);
            result.image.at(px, py) = glm::vec4(glm::vec3(px4) + (1 - px4.w) * glm::vec3(bg) * bg.w,
                                                px4.w + (1 - px4.w) * bg.w);
          }
      });
      rasterSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - tr).count();
    }
    st.raster = rasterSeconds;
    st.peakBytes = ps.bytes() + counts.bytes() + binBytes + store.size() * size_t(options.tileSize) * options.tileSize * S2 * 8;
  };
  inArena(options.threads, body);
  st.coverageQuantisation = 0.5 / S;  // stratified sampling: about half a stratum per edge
  st.total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace wf

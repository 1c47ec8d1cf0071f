// Stage "bins" (render/pipeline.h): each primitive into the screen tiles its bounding box meets,
// with what a tile needs to order and cull it without touching the primitive.
#include "render/pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace wf {


TileBins binPrimitives(const PreparedScene& ps, int tileSize, RenderStats& st) {
  const auto t0 = std::chrono::steady_clock::now();
  TileBins bins;
  bins.tilesX = (ps.view.width + tileSize - 1) / tileSize;
  bins.tilesY = (ps.view.height + tileSize - 1) / tileSize;
  const size_t tiles = size_t(bins.tilesX) * size_t(bins.tilesY);
  bins.offsets.assign(tiles + 1, 0);
  auto range = [&](const Primitive& p, int& tx0, int& ty0, int& tx1, int& ty1) {
    tx0 = std::clamp(int(std::floor(p.bbox[0])) / tileSize, 0, bins.tilesX - 1);
    ty0 = std::clamp(int(std::floor(p.bbox[1])) / tileSize, 0, bins.tilesY - 1);
    tx1 = std::clamp((int(std::ceil(p.bbox[2])) - 1) / tileSize, 0, bins.tilesX - 1);
    ty1 = std::clamp((int(std::ceil(p.bbox[3])) - 1) / tileSize, 0, bins.tilesY - 1);
  };
  for (const Primitive& p : ps.primitives) {
    int a, b, c, d;
    range(p, a, b, c, d);
    for (int ty = b; ty <= d; ++ty)
      for (int tx = a; tx <= c; ++tx) ++bins.offsets[size_t(ty) * bins.tilesX + tx + 1];
  }
  for (size_t t = 0; t < tiles; ++t) bins.offsets[t + 1] += bins.offsets[t];
  bins.items.resize(bins.offsets[tiles]);
  std::vector<std::uint32_t> fill(bins.offsets.begin(), bins.offsets.end() - 1);
  for (size_t i = 0; i < ps.primitives.size(); ++i) {
    const Primitive& p = ps.primitives[i];
    int a, b, c, d;
    range(p, a, b, c, d);
    for (int ty = b; ty <= d; ++ty)
      for (int tx = a; tx <= c; ++tx) {
        const int ox = tx * tileSize, oy = ty * tileSize;
        const int w = std::min(tileSize, ps.view.width - ox), h = std::min(tileSize, ps.view.height - oy);
        TileBins::Item item;
        item.zlo = p.zlo;
        item.index = std::uint32_t(i);
        item.firstVertex = p.firstVertex;
        item.x0 = std::int16_t(std::clamp(int(p.bbox[0]) - ox, 0, w - 1));
        item.y0 = std::int16_t(std::clamp(int(p.bbox[1]) - oy, 0, h - 1));
        item.x1 = std::int16_t(std::clamp(int(p.bbox[2]) - ox, 0, w - 1));
        item.y1 = std::int16_t(std::clamp(int(p.bbox[3]) - oy, 0, h - 1));
        bins.items[fill[size_t(ty) * bins.tilesX + tx]++] = item;
      }
  }
  st.tiles = tiles;
  st.tilesEmpty = 0;
  for (size_t t = 0; t < tiles; ++t) st.tilesEmpty += bins.offsets[t] == bins.offsets[t + 1];
  st.binning = secondsSince(t0);
  return bins;
}

}  // namespace wf

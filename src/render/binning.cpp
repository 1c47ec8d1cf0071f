// Stage "bins" (render/pipeline.h): each primitive into the screen tiles it may cover, with what
// a tile needs to order and cull it without touching the primitive: its pixel rectangle inside
// the tile and its nearest depth inside the tile. A long hair crossing several tiles is near in
// one and far in another; ordering and culling it by its depth in each tile, not by its nearest
// point anywhere, lets each tile take it where it belongs in front-to-back order.
//
// In parallel and deterministic: chunks of primitives count their items per tile (countBins),
// the counts give every (chunk, tile) its place, and the chunks fill them (binPrimitives), so
// each tile's items are in primitive order whatever the thread count. The filling takes a band
// of tile rows at a time: the renderer bins and draws a dense scene's bands one after another
// (binBands; renderer.cpp and reference_renderer.cpp), so that its items are not all held at once.
#include "abuffer/coverage_mask.h"
#include "render/pipeline.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>

namespace wf {

namespace {

class Binner {
 public:
  // Tiles of tile rows [rowBegin, rowEnd) only (clamped to the grid).
  Binner(const PreparedScene& ps, int tileSize, int rowBegin, int rowEnd) : ps_(ps), view_(ps.view), tile_(tileSize) {
    tilesX_ = (view_.width + tileSize - 1) / tileSize;
    tilesY_ = (view_.height + tileSize - 1) / tileSize;
    rowLo_ = std::clamp(rowBegin, 0, tilesY_);
    rowHi_ = std::clamp(rowEnd, rowLo_, tilesY_);
  }
  int tilesX() const { return tilesX_; }
  int tilesY() const { return tilesY_; }

  // Calls f(tile, item) for every tile primitive i may cover.
  template <class F>
  void forEachItem(std::uint32_t i, F&& f) const {
    if (ps_.isSegment(i)) segmentItems<true>(i, ps_.segmentOf(i), f);
    else triangleItems(i, ps_.triangles[i], f);
  }
  // The same tiles, without forming the items (the counting pass: a segment's depths are not
  // needed to know which tiles it reaches).
  template <class F>
  void forEachTile(std::uint32_t i, F&& f) const {
    if (ps_.isSegment(i)) {
      segmentItems<false>(i, ps_.segmentOf(i), [&](int tile, const TileBins::Item&) { f(tile); });
      return;
    }
    const TrianglePrim& p = ps_.triangles[i];
    int tx0, ty0, tx1, ty1;
    if (!tileRange(p.bbox[0], p.bbox[1], p.bbox[2], p.bbox[3], tx0, ty0, tx1, ty1)) return;
    for (int ty = ty0; ty <= ty1; ++ty)
      for (int tx = tx0; tx <= tx1; ++tx) f(ty * tilesX_ + tx);
  }

 private:
  template <class F>
  void triangleItems(std::uint32_t i, const TrianglePrim& p, F& f) const {
    int tx0, ty0, tx1, ty1;
    if (!tileRange(p.bbox[0], p.bbox[1], p.bbox[2], p.bbox[3], tx0, ty0, tx1, ty1)) return;
    for (int ty = ty0; ty <= ty1; ++ty)
      for (int tx = tx0; tx <= tx1; ++tx) {
        TileBins::Item item = rectItem(i, tx, ty, p.bbox[0], p.bbox[1], p.bbox[2], p.bbox[3]);
        // Nearest depth of the plane over the item's rectangle: at the corner where the key is
        // largest (perspective, 1/d) or smallest (orthographic, d).
        const double xa = tx * tile_ + item.x0, xb = tx * tile_ + item.x1 + 1.0;
        const double ya = ty * tile_ + item.y0, yb = ty * tile_ + item.y1 + 1.0;
        const bool far = !view_.perspective;
        const double kx = (p.qa > 0) != far ? xb : xa, ky = (p.qb > 0) != far ? yb : ya;
        item.zlo = float(std::clamp(view_.depthFromKey(p.depthKeyAt(kx, ky)), double(p.zlo), double(p.zhi)));
        if (!(item.zlo >= p.zlo)) item.zlo = p.zlo;  // NaN
        f(ty * tilesX_ + tx, item);
      }
  }

  // kItems false: f(tile, an empty item) for the same tiles, with nothing of the items formed.
  template <bool kItems, class F>
  void segmentItems(std::uint32_t i, const SegmentPrim& s, F&& f) const {
    const double reach = segmentReach(s);
    const double bx0 = std::min(s.p0.x, s.p1.x) - reach, bx1 = std::max(s.p0.x, s.p1.x) + reach;
    const double by0 = std::min(s.p0.y, s.p1.y) - reach, by1 = std::max(s.p0.y, s.p1.y) + reach;
    int tx0, ty0, tx1, ty1;
    if (!tileRange(bx0, by0, bx1, by1, tx0, ty0, tx1, ty1)) return;
    // (Formed only to fill the items: two divisions, a square root and the tilt.)
    float zlo = 0.0f;
    double tilt = 0.0, slide = 0.0, nearRadius = 0.0, depthReach = reach;
    std::optional<SegmentEndKeys> keys;
    if constexpr (kItems) {
      const bool exact = segmentUsesCapsule(ps_, i);
      zlo = segmentZlo(view_, s, exact);
      nearRadius = wireNearRadius(view_, s, exact);
      // A hair's solid: a point of it seen in the tile lies within its radius of an axis point
      // projecting within capsuleReach of it (wider than the polygon's reach off the view axis).
      if (exact) depthReach = std::max(reach, capsuleReach(view_, nearRadius, std::min(double(s.d0), double(s.d1))));
      keys.emplace(view_, s);
      tilt = segmentTiltBound(view_, s);
      // The round model takes the axis depth up to `slide` along the axis from the pixel's foot.
      const SegmentFrame frame(s);
      slide = SegmentTilt(view_, s, frame).shiftBound(view_, s, frame);
    }
    // The axis inside each tile grown by the reach: only that part can cover the tile.
    TileClips clips;
    const bool held = clips.init(s.p0, s.p1, tile_, reach, tx0, ty0, tx1, ty1);
    // A hair's solid reaches from the axis grown by depthReach (below).
    TileClips depthClips;
    const bool depthHeld = kItems && depthReach > reach && depthReach < INFINITY && held &&
                           depthClips.init(s.p0, s.p1, tile_, depthReach, tx0, ty0, tx1, ty1);
    for (int ty = ty0; ty <= ty1; ++ty)
      for (int tx = tx0; tx <= tx1; ++tx) {
        double ta, tb;
        if (held ? !clips.clip(tx, ty, ta, tb)
                 : !clipLineToRect(s.p0, s.p1, tx * tile_ - reach, ty * tile_ - reach, (tx + 1) * tile_ + reach,
                                   (ty + 1) * tile_ + reach, ta, tb))
          continue;
        if constexpr (!kItems) {
          f(ty * tilesX_ + tx, TileBins::Item{});
          continue;
        }
        const double ax = s.p0.x + ta * (s.p1.x - s.p0.x), bx = s.p0.x + tb * (s.p1.x - s.p0.x);
        const double ay = s.p0.y + ta * (s.p1.y - s.p0.y), by = s.p0.y + tb * (s.p1.y - s.p0.y);
        TileBins::Item item = rectItem(i, tx, ty, std::min(ax, bx) - reach, std::min(ay, by) - reach,
                                       std::max(ax, bx) + reach, std::max(ay, by) + reach);
        // The axis depth is monotonic along the axis: its nearest is at one end of [ta, tb]; the
        // surface is at most the tilt and the largest radius nearer (either WireDepth, segmentZlo).
        // A hair's solid reaches from the axis grown by depthReach.
        if (depthReach > reach) {
          // (It holds the reach's clip, which succeeded: it refuses nothing the reach's took.)
          if (!(depthReach < INFINITY)) ta = 0.0, tb = 1.0;
          else if (!depthHeld || !depthClips.clip(tx, ty, ta, tb))
            clipLineToRect(s.p0, s.p1, tx * tile_ - depthReach, ty * tile_ - depthReach, (tx + 1) * tile_ + depthReach,
                           (ty + 1) * tile_ + depthReach, ta, tb);
        }
        const double sa = std::max(0.0, ta - slide), sb = std::min(1.0, tb + slide);
        const double k =
            view_.perspective ? std::max(keys->axis(sa), keys->axis(sb)) : std::min(keys->axis(sa), keys->axis(sb));
        const double z = view_.depthFromKey(k) * (1.0 - tilt) - nearRadius;
        item.zlo = z >= zlo ? float(z) : zlo;  // never nearer than the whole segment (nor NaN)
        f(ty * tilesX_ + tx, item);
      }
  }

  // Tiles overlapping the rectangle (clamped to the image); false when it misses the image.
  bool tileRange(double x0, double y0, double x1, double y1, int& tx0, int& ty0, int& tx1, int& ty1) const {
    x0 = std::max(x0, 0.0), y0 = std::max(y0, 0.0);
    x1 = std::min(x1, double(view_.width)), y1 = std::min(y1, double(view_.height));
    if (!(x1 > x0) || !(y1 > y0)) return false;
    // (floorToInt, ceilToInt: std::floor and std::ceil are calls on the x86-64 baseline, without
    // SSE4.1's rounding; the same integers for these bounded values.)
    tx0 = std::clamp(int(floorToInt(x0)) / tile_, 0, tilesX_ - 1);
    ty0 = std::clamp(int(floorToInt(y0)) / tile_, 0, tilesY_ - 1);
    tx1 = std::clamp((int(ceilToInt(x1)) - 1) / tile_, 0, tilesX_ - 1);
    ty1 = std::clamp((int(ceilToInt(y1)) - 1) / tile_, 0, tilesY_ - 1);
    ty0 = std::max(ty0, rowLo_), ty1 = std::min(ty1, rowHi_ - 1);  // the rows binned
    return ty0 <= ty1;
  }

  // The item of primitive i in tile (tx, ty) with the pixel rectangle of [x0, x1] x [y0, y1]
  // inside the tile.
  TileBins::Item rectItem(std::uint32_t i, int tx, int ty, double x0, double y0, double x1, double y1) const {
    const int ox = tx * tile_, oy = ty * tile_;
    const int w = std::min(tile_, view_.width - ox), h = std::min(tile_, view_.height - oy);
    auto cell = [](double v, int o, int n) {
      return std::uint8_t(std::clamp<double>(double(floorToInt(std::clamp(v, -1e9, 1e9))) - o, 0.0, double(n - 1)));
    };
    TileBins::Item item;
    item.index = i;
    item.x0 = cell(x0, ox, w);
    item.y0 = cell(y0, oy, h);
    // The last pixel a coverage up to x1 (exclusive) reaches.
    item.x1 = std::uint8_t(
        std::clamp<double>(double(ceilToInt(std::clamp(x1, -1e9, 1e9))) - 1 - ox, double(item.x0), double(w - 1)));
    item.y1 = std::uint8_t(
        std::clamp<double>(double(ceilToInt(std::clamp(y1, -1e9, 1e9))) - 1 - oy, double(item.y0), double(h - 1)));
    item.zlo = 0.0f;
    return item;
  }

  const PreparedScene& ps_;
  const ViewTransform& view_;
  int tile_;
  int tilesX_ = 1, tilesY_ = 1;
  int rowLo_ = 0, rowHi_ = 1;
};

// Calls f(b, begin, end) for the blocks of BinCounts::kBlock primitives of chunk k, in order
// ([begin, end): block b's primitives, whole: a chunk holds whole blocks).
template <class F>
void forEachBlock(const BinCounts& c, size_t k, std::uint32_t n, F&& f) {
  const std::uint32_t end = std::uint32_t(std::min<size_t>(n, (k + 1) * c.perChunk));
  for (std::uint32_t i = std::uint32_t(std::min<size_t>(n, k * c.perChunk)); i < end;) {
    const size_t b = i / BinCounts::kBlock;
    const std::uint32_t blockEnd = std::uint32_t(std::min<size_t>(end, (b + 1) * BinCounts::kBlock));
    f(b, i, blockEnd);
    i = blockEnd;
  }
}

}  // namespace

BinCounts countBins(const PreparedScene& ps, int tileSize, int rowBegin, int rowEnd) {
  if (tileSize < 1 || tileSize > TileBins::kMaxTileSize)  // (optionsProblem has said so already)
    throw std::invalid_argument("tile size " + std::to_string(tileSize) + " outside 1 ... " +
                                std::to_string(TileBins::kMaxTileSize));
  const Binner binner(ps, tileSize, rowBegin, rowEnd);
  BinCounts c;
  c.tileSize = tileSize;
  c.tilesX = binner.tilesX();
  c.tilesY = binner.tilesY();
  c.rowBegin = std::clamp(rowBegin, 0, c.tilesY);
  c.rowEnd = std::clamp(rowEnd, c.rowBegin, c.tilesY);
  const size_t tiles = size_t(c.tilesX) * size_t(c.rowEnd - c.rowBegin);
  const std::uint32_t n = ps.primitiveCount();
  // Chunks of primitives: enough to share out, few enough that their per-tile counts stay small.
  const size_t threads = size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
  // (Whole blocks a chunk: each block's rows are written by one.)
  c.chunks = std::clamp<size_t>((n + 65535) / 65536, 1, 4 * threads);
  c.perChunk = ((n + c.chunks - 1) / c.chunks + BinCounts::kBlock - 1) / BinCounts::kBlock * BinCounts::kBlock;
  c.counts.assign(c.chunks * tiles, 0);  // chunk-major
  c.blockRows.assign(2 * ((size_t(n) + BinCounts::kBlock - 1) / BinCounts::kBlock), 0);
  const size_t first = size_t(c.rowBegin) * size_t(c.tilesX);
  const int tilesX = c.tilesX;
  tbb::parallel_for(size_t(0), c.chunks, [&](size_t k) {
    std::uint32_t* cnt = c.counts.data() + k * tiles;  // (no tiles: nothing is counted)
    forEachBlock(c, k, n, [&](size_t b, std::uint32_t begin, std::uint32_t end) {
      int lo = std::numeric_limits<int>::max(), hi = -1;
      for (std::uint32_t i = begin; i < end; ++i)
        binner.forEachTile(i, [&](int tile) {
          ++cnt[size_t(tile) - first];
          const int row = tile / tilesX;
          lo = std::min(lo, row), hi = std::max(hi, row);
        });
      c.blockRows[2 * b] = lo, c.blockRows[2 * b + 1] = hi;
    });
  });
  return c;
}

void TileBins::outsideBand(int t) const {
  throw std::out_of_range("tile " + std::to_string(t) + " outside the tile rows binned, " + std::to_string(rowBegin) +
                          " ... " + std::to_string(rowEnd - 1));
}

double binsHeldBeside(const PreparedScene& ps, const BinCounts& c, double alsoHeld) {
  // The primitives, the counts, a band's offsets and places (at most all the counted rows'), and
  // what the caller holds besides.
  const double tiles = double(c.tilesX) * double(c.rowEnd - c.rowBegin);
  const double offsets = (tiles + 1.0) * sizeof(std::uint32_t) * (1.0 + double(c.chunks));
  return double(ps.bytes()) + double(c.bytes()) + offsets + alsoHeld;
}

void checkBinsFit(const PreparedScene& ps, const BinCounts& c, std::uint64_t items, size_t memoryBudget, double alsoHeld) {
  if (items > std::numeric_limits<std::uint32_t>::max()) throw std::length_error("more than 4 billion tile items");
  const double held = binsHeldBeside(ps, c, alsoHeld);
  const double itemBytes = double(items) * sizeof(TileBins::Item);
  const double need = itemBytes + largeArrayRounding(itemBytes);
  if (!memoryBudget || held + need <= double(memoryBudget)) return;
  auto mib = [](double b) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f MiB", b / double(1 << 20));
    return std::string(text);
  };
  const std::string budget = mib(double(memoryBudget)) + " (RenderOptions::memoryBudget / --memory-budget)";
  if (held > double(memoryBudget))  // (nothing of the items fits: what is held is over already)
    throw std::length_error("the primitives and what is held beside their tile items (" + mib(held) +
                            ") are over the memory budget of " + budget);
  throw std::length_error("a band of tile rows holds " + std::to_string(items) + " tile items (" + mib(need) +
                          (need > itemBytes ? " with their rounding to 2 MiB pages" : "") + ") beside " + mib(held) +
                          " already held, over the memory budget of " + budget);
}

std::vector<std::pair<int, int>> binBands(const PreparedScene& ps, const BinCounts& c, size_t memoryBudget,
                                          double alsoHeld, std::uint64_t& largest) {
  const double cap = bandItemCap(double(ps.primitiveBytes()),
                                 memoryBudget ? double(memoryBudget) - binsHeldBeside(ps, c, alsoHeld) : INFINITY);
  std::vector<std::pair<int, int>> bands;
  std::uint64_t items = 0;
  largest = 0;
  for (int row = c.rowBegin; row < c.rowEnd; ++row) {
    const std::uint64_t here = c.rowItems(row);
    if (!bands.empty() && bands.back().second == row && double(items + here) * sizeof(TileBins::Item) <= cap &&
        items + here <= std::numeric_limits<std::uint32_t>::max()) {
      bands.back().second = row + 1;
      items += here;
    } else {
      bands.emplace_back(row, row + 1);
      items = here;
    }
    largest = std::max(largest, items);
  }
  return bands;
}

std::uint64_t BinCounts::rowItems(int row) const {
  std::uint64_t sum = 0;
  if (row < rowBegin || row >= rowEnd) return 0;
  const size_t tiles = size_t(tilesX) * size_t(rowEnd - rowBegin);
  for (size_t k = 0; k < chunks; ++k)
    for (int tx = 0; tx < tilesX; ++tx) sum += counts[k * tiles + size_t(row - rowBegin) * size_t(tilesX) + size_t(tx)];
  return sum;
}

void binPrimitives(const PreparedScene& ps, const BinCounts& c, int rowBegin, int rowEnd, RenderStats& st,
                   size_t memoryBudget, TileBins& bins) {
  const auto t0 = std::chrono::steady_clock::now();
  rowBegin = std::clamp(rowBegin, c.rowBegin, c.rowEnd);
  rowEnd = std::clamp(rowEnd, rowBegin, c.rowEnd);
  const Binner binner(ps, c.tileSize, rowBegin, rowEnd);
  bins.tilesX = c.tilesX;
  bins.tilesY = c.tilesY;
  bins.rowBegin = rowBegin;
  bins.rowEnd = rowEnd;
  const size_t countedTiles = size_t(c.tilesX) * size_t(c.rowEnd - c.rowBegin);
  const size_t first = size_t(rowBegin) * size_t(c.tilesX);              // the band's first tile
  const size_t skip = size_t(rowBegin - c.rowBegin) * size_t(c.tilesX);   // its place in the counts
  const size_t tiles = size_t(c.tilesX) * size_t(rowEnd - rowBegin);
  const std::uint32_t n = ps.primitiveCount();
  // Offsets: tile-major, chunks in order within a tile.
  bins.offsets.assign(tiles + 1, 0);
  std::vector<std::uint32_t> start(c.chunks * tiles);
  std::uint64_t total = 0;
  for (size_t t = 0; t < tiles; ++t) {
    bins.offsets[t] = std::uint32_t(total);
    for (size_t k = 0; k < c.chunks; ++k) {
      start[k * tiles + t] = std::uint32_t(total);
      total += c.counts[k * countedTiles + skip + t];
    }
  }
  checkBinsFit(ps, c, total, memoryBudget);
  bins.offsets[tiles] = std::uint32_t(total);
  bins.items.resize(total);  // (within the capacity a previous band left: not moved)
  tbb::parallel_for(size_t(0), c.chunks, [&](size_t k) {
    std::uint32_t* fill = start.data() + k * tiles;
    forEachBlock(c, k, n, [&](size_t b, std::uint32_t begin, std::uint32_t end) {
      // A block none of whose primitives reaches these rows is passed over unread.
      if (c.blockRows[2 * b + 1] < rowBegin || c.blockRows[2 * b] >= rowEnd) return;
      for (std::uint32_t i = begin; i < end; ++i)
        binner.forEachItem(i, [&](int tile, const TileBins::Item& item) { bins.items[fill[size_t(tile) - first]++] = item; });
    });
  });
  st.tiles += tiles;
  for (size_t t = 0; t < tiles; ++t) st.tilesEmpty += bins.offsets[t] == bins.offsets[t + 1];
  st.binning += secondsSince(t0);
}

TileBins binPrimitives(const PreparedScene& ps, int tileSize, RenderStats& st, size_t memoryBudget) {
  const auto t0 = std::chrono::steady_clock::now();
  const BinCounts counts = countBins(ps, tileSize);
  st.binning += secondsSince(t0);
  TileBins bins;
  binPrimitives(ps, counts, 0, counts.tilesY, st, memoryBudget, bins);
  return bins;
}

void sortTileItems(std::vector<TileBins::Item>& items, std::vector<TileBins::Item>& scratch) {
  sortTileItems(items.data(), items.size(), scratch);
}

void sortTileItems(TileBins::Item* items, size_t n, std::vector<TileBins::Item>& scratch) {
  if (n < 64) {  // (a comparison sort wins on few)
    std::sort(items, items + n);
    return;
  }
  // The float's bits made unsigned-monotonic: negative ones reversed, positive ones above them;
  // -0 taken as +0 by its bits (not by adding 0, which flush-to-zero would make a subnormal's 0
  // too, where the comparison still orders it); a NaN after every number, as Item's order has it
  // (the items arrive in primitive order and the passes are stable: ties keep it).
  auto key = [](float z) {
    std::uint32_t u;
    std::memcpy(&u, &z, sizeof u);
    if (u == 0x80000000u) u = 0;
    if (z != z) return 0xFFFFFFFFu;
    return (u & 0x80000000u) ? ~u : (u | 0x80000000u);
  };
  std::uint32_t count[4][256] = {};
  for (const TileBins::Item& it : std::span<const TileBins::Item>(items, n)) {
    const std::uint32_t k = key(it.zlo);
    for (int b = 0; b < 4; ++b) ++count[b][(k >> (8 * b)) & 0xFFu];
  }
  scratch.resize(n);
  TileBins::Item* src = items;
  TileBins::Item* dst = scratch.data();
  const std::uint32_t first = key(items[0].zlo);
  for (int b = 0; b < 4; ++b) {
    if (count[b][(first >> (8 * b)) & 0xFFu] == n) continue;  // every key has this byte: nothing to move
    std::uint32_t at[256];
    std::uint32_t sum = 0;
    for (int d = 0; d < 256; ++d) at[d] = sum, sum += count[b][d];
    for (size_t i = 0; i < n; ++i) dst[at[(key(src[i].zlo) >> (8 * b)) & 0xFFu]++] = src[i];
    std::swap(src, dst);
  }
  if (src != items) std::copy(src, src + n, items);
}

}  // namespace wf

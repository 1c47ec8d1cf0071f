// Tests of the per-tile order (binning.cpp, sortTileItems) against the comparison it stands for,
// TileBins::Item::operator< (depth, then primitive), applied by std::sort; of binning in bands of
// tile rows against binning the whole grid; and of the per-block clip (TileClips, pipeline.h)
// against clipLineToRect tile by tile.
#include "abuffer/screen_polygon.h"
#include "render/pipeline.h"
#include "render/renderer.h"

#include "render_test_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

namespace wf {
namespace {

// Every band of tile rows, binned from the counts of the whole grid (or of rows counted alone),
// holds exactly the whole grid's items of its tiles, in the same order; the counts per row are
// the items the rows get. Triangles and segments, perspective (tilted hairs, whose tile depths
// reach their solid) and orthographic; primitives in shuffled order, so that the counts' blocks
// reach many rows.
TEST(BinBands, EveryBandHoldsTheWholeGridsItemsOfItsTiles) {
  for (bool perspective : {true, false}) {
    const int W = 200, H = 150;
    Scene s = test::baseScene(W, H);
    if (perspective) s.camera->projection = Camera::Projection::Perspective, s.camera->fovYDegrees = 120.0;
    s.surfaces.push_back(test::screenRect(20, 15, 180, 140, 40.0, W, H, glm::vec3(0.5f)));
    SceneWire w;
    w.restsOnSurface = false;
    w.thickness = 1.5;
    w.roundEnds = true;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < 3000; ++i) {
      const test::V2 a(u(rng) * W, u(rng) * H), b(a.x + (u(rng) - 0.5) * 90, a.y + (u(rng) - 0.5) * 90);
      w.lines.add({test::world(a, 20.0 + 10 * u(rng), W, H), test::world(b, 20.0 + 10 * u(rng), W, H)});
    }
    s.wires.push_back(w);
    RenderOptions o = test::smallOptions(W, H);
    o.tileSize = 8;
    RenderStats st;
    const PreparedScene ps = prepareScene(s, o, st);
    ASSERT_GT(ps.segments.size(), 1000u);
    const TileBins whole = binPrimitives(ps, o.tileSize, st);
    const BinCounts counts = countBins(ps, o.tileSize);
    std::uint64_t total = 0;
    for (int row = 0; row < counts.tilesY; ++row) {
      std::uint64_t inRow = 0;
      for (int t = row * whole.tilesX; t < (row + 1) * whole.tilesX; ++t) inRow += whole.end(t) - whole.begin(t);
      EXPECT_EQ(counts.rowItems(row), inRow) << row;
      total += inRow;
    }
    EXPECT_EQ(total, whole.items.size());
    auto same = [&](const TileBins& band, int t) {
      ASSERT_EQ(band.end(t) - band.begin(t), whole.end(t) - whole.begin(t)) << t;
      for (std::uint32_t k = 0; k < whole.end(t) - whole.begin(t); ++k) {
        const TileBins::Item &p = band.items[band.begin(t) + k], &q = whole.items[whole.begin(t) + k];
        ASSERT_TRUE(p.index == q.index && std::memcmp(&p.zlo, &q.zlo, sizeof(float)) == 0 && p.x0 == q.x0 &&
                    p.y0 == q.y0 && p.x1 == q.x1 && p.y1 == q.y1)
            << "tile " << t << " item " << k;
      }
    };
    // Bands of 1, 3 and 7 rows, one buffer reused; and rows 5 ... 11 counted alone.
    for (int rows : {1, 3, 7}) {
      TileBins band;
      for (int r0 = 0; r0 < counts.tilesY; r0 += rows) {
        binPrimitives(ps, counts, r0, r0 + rows, st, 0, band);
        for (int t = r0 * whole.tilesX; t < std::min(r0 + rows, counts.tilesY) * whole.tilesX; ++t) same(band, t);
      }
    }
    const BinCounts some = countBins(ps, o.tileSize, 5, 12);
    TileBins band;
    binPrimitives(ps, some, 0, 100, st, 0, band);
    EXPECT_EQ(band.rowBegin, 5);
    EXPECT_EQ(band.rowEnd, 12);
    for (int t = 5 * whole.tilesX; t < 12 * whole.tilesX; ++t) same(band, t);
    for (auto [r0, r1] : {std::pair{6, 8}, std::pair{8, 12}}) {  // bands inside rows counted from row 5
      binPrimitives(ps, some, r0, r1, st, 0, band);
      for (int t = r0 * whole.tilesX; t < r1 * whole.tilesX; ++t) same(band, t);
    }
  }
}

// Degenerate rows: a range empty, reversed or beyond the grid counts and bins nothing (and reads
// nothing out of range); a tile outside the rows binned is refused, not read.
TEST(BinBands, EmptyOrOutsideRowRangesBinNothing) {
  const int W = 64, H = 48;
  Scene s = test::baseScene(W, H);
  s.surfaces.push_back(test::screenRect(5, 5, 60, 40, 30.0, W, H, glm::vec3(0.5f)));
  RenderOptions o = test::smallOptions(W, H);
  o.tileSize = 8;
  RenderStats st;
  const PreparedScene ps = prepareScene(s, o, st);
  for (auto [r0, r1] : {std::pair{3, 3}, std::pair{4, 2}, std::pair{6, 100}, std::pair{-5, 0}, std::pair{1000, 2000}}) {
    const BinCounts c = countBins(ps, o.tileSize, r0, r1);
    EXPECT_TRUE(c.counts.empty()) << r0 << " ... " << r1;
    TileBins band;
    binPrimitives(ps, c, r0, r1, st, 0, band);
    EXPECT_TRUE(band.items.empty()) << r0 << " ... " << r1;
    EXPECT_EQ(band.rowBegin, band.rowEnd);
    EXPECT_THROW(band.begin(0), std::out_of_range);
  }
  const TileBins whole = binPrimitives(ps, o.tileSize, st);
  EXPECT_THROW(whole.begin(-1), std::out_of_range);
  EXPECT_THROW(whole.end(whole.tilesX * whole.tilesY), std::out_of_range);
  EXPECT_GT(whole.end(whole.tilesX * whole.tilesY - 1), 0u);
}

// Many chunks (a chunk a 65,536 primitives, at most 4 a thread: 4 at one thread, 5 at 3 and 7,
// so that the thread count changes the chunks) and blocks that reach few rows (short hairs made
// in screen order, as fur grown over a patch is), for 1, 3 and 7 threads: every band's tiles hold
// what a serial pass over the primitives in order gives them, item by item. The serial
// reference bins one primitive at a time (a scene of that primitive alone has one chunk), so it
// shares only the per-tile geometry with the code under test, not its counting, places, chunks
// or blocks.
TEST(BinBands, ManyChunksAndSkippedBlocksKeepEveryTilesItemsInOrder) {
  const int W = 256, H = 192;
  Scene s = test::baseScene(W, H);
  SceneWire w;
  w.restsOnSurface = false;
  w.thickness = 1.0;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int n = 300000;
  for (int i = 0; i < n; ++i) {
    // Row-major over the image: 256 consecutive hairs lie within about two rows of 8-pixel tiles.
    const double y = double(i) / n * H, x = std::fmod(i * 0.37, double(W));
    const test::V2 a(x, y), b(x + (u(rng) - 0.5) * 6, y + (u(rng) - 0.5) * 6);
    w.lines.add({test::world(a, 20.0 + u(rng), W, H), test::world(b, 20.0 + u(rng), W, H)});
  }
  s.wires.push_back(w);
  RenderOptions o = test::smallOptions(W, H);
  o.tileSize = 8;
  RenderStats st;
  const PreparedScene ps = prepareScene(s, o, st);
  ASSERT_GT(ps.segments.size(), size_t(280000));
  // The serial reference: per tile, the items in primitive order.
  const int tilesX = (W + 7) / 8, tilesY = (H + 7) / 8;
  std::vector<std::vector<TileBins::Item>> want(size_t(tilesX) * tilesY);
  {
    PreparedScene one;
    one.view = ps.view;
    one.wireDepth = ps.wireDepth;
    one.pixelScale = ps.pixelScale;
    one.shaders = ps.shaders;
    one.segments.resize(1);
    for (std::uint32_t i = 0; i < ps.segments.size(); ++i) {
      one.segments[0] = ps.segments[i];
      RenderStats s1;
      const TileBins b = binPrimitives(one, o.tileSize, s1);
      for (int t = 0; t < tilesX * tilesY; ++t)
        for (std::uint32_t k = b.begin(t); k < b.end(t); ++k) {
          TileBins::Item it = b.items[k];
          it.index = i;
          want[size_t(t)].push_back(it);
        }
    }
  }
  for (int threads : {1, 3, 7}) {
    inArena(threads, [&] {
      const BinCounts counts = countBins(ps, o.tileSize);
      EXPECT_EQ(counts.chunks, threads == 1 ? 4u : 5u) << threads;
      // A block lies in one chunk (its rows are written by one thread, from all its primitives).
      EXPECT_EQ(counts.perChunk % BinCounts::kBlock, 0u) << threads;
      // Most blocks reach at most three tile rows: the bands pass over the others unread.
      size_t narrow = 0, blocks = counts.blockRows.size() / 2;
      for (size_t b = 0; b < blocks; ++b) narrow += counts.blockRows[2 * b + 1] - counts.blockRows[2 * b] <= 2;
      EXPECT_GT(narrow, blocks * 9 / 10) << threads;
      for (int rows : {1, 5, tilesY}) {
        TileBins band;
        for (int r0 = 0; r0 < tilesY; r0 += rows) {
          binPrimitives(ps, counts, r0, r0 + rows, st, 0, band);
          for (int t = r0 * tilesX; t < std::min(r0 + rows, tilesY) * tilesX; ++t) {
            const std::vector<TileBins::Item>& v = want[size_t(t)];
            ASSERT_EQ(band.end(t) - band.begin(t), v.size()) << threads << " threads, tile " << t;
            for (size_t k = 0; k < v.size(); ++k) {
              const TileBins::Item& p = band.items[band.begin(t) + k];
              ASSERT_TRUE(p.index == v[k].index && std::memcmp(&p.zlo, &v[k].zlo, sizeof(float)) == 0 &&
                          p.x0 == v[k].x0 && p.y0 == v[k].y0 && p.x1 == v[k].x1 && p.y1 == v[k].y1)
                  << threads << " threads, " << rows << " rows a band, tile " << t << " item " << k;
            }
          }
        }
      }
    });
  }
}

// Every pixel a primitive covers lies in its item's rectangle in that pixel's tile, and its item's
// depth is no farther than the primitive's depth there (else a crack, or a visible fragment
// culled whole). The pixels it covers are found here by clipping its screen polygon to each
// pixel (a positive area), its depth at the covered part's centroid by primitiveDepthAt: neither
// from the binning. Random triangles (some cut by the near plane: up to five vertices) and
// wires 0.3 ... 20 pixels wide, round or square ended, resting on a surface or not, with sharp
// joints (mitres), end-on segments, and parts off the image; perspective and orthographic,
// tiles of 8 and 32 pixels.
TEST(BinBands, EveryCoveredPixelLiesInItsItemsRectangle) {
  const int W = 160, H = 120;
  long checked = 0, segmentPixels = 0, tileEdges = 0;
  for (bool perspective : {true, false})
    for (int tile : {8, 32}) {
      Scene s = test::baseScene(W, H);
      if (perspective) s.camera->projection = Camera::Projection::Perspective, s.camera->fovYDegrees = 70.0;
      std::mt19937 rng(perspective ? 11 : 12);
      std::uniform_real_distribution<double> u(0.0, 1.0);
      auto point = [&] { return test::V2(-30 + u(rng) * (W + 60), -30 + u(rng) * (H + 60)); };
      auto depth = [&] { return u(rng) < 0.1 ? 0.3 + u(rng) : 2.0 + 40.0 * u(rng); };  // some before the near plane (1)
      // The world point seen at pixel q at view depth d (the camera at z = 10 looking down -z).
      const double f = 0.5 * H / std::tan(0.5 * 70.0 * 3.14159265358979 / 180.0);
      auto at = [&](const test::V2& q, double d) {
        return perspective ? glm::dvec3((q.x - 0.5 * W) / f * d, (0.5 * H - q.y) / f * d, 10.0 - d) : test::world(q, d, W, H);
      };
      SceneSurface surf;
      for (int i = 0; i < 120; ++i) {
        const std::uint32_t b = std::uint32_t(surf.mesh.positions.size());
        const test::V2 c = point();
        const double size = u(rng) < 0.5 ? 3.0 + 10.0 * u(rng) : 20.0 + 80.0 * u(rng);
        for (int k = 0; k < 3; ++k) {
          const test::V2 q = k == 2 && u(rng) < 0.3 ? c + 0.01 * size * test::V2(u(rng), u(rng))  // slivers
                                                    : c + size * test::V2(u(rng) - 0.5, u(rng) - 0.5);
          surf.mesh.positions.push_back(at(q, depth()));
        }
        surf.mesh.triangles.push_back({b, b + 1, b + 2});
      }
      s.surfaces.push_back(surf);
      for (double width : {0.3, 1.5, 6.0, 20.0})
        for (bool round : {true, false}) {
          SceneWire w;
          w.thickness = width;
          w.thicknessInPixels = true;
          w.roundEnds = round;
          w.restsOnSurface = width > 5.0;
          for (int i = 0; i < 25; ++i) {
            std::vector<glm::dvec3> line;
            test::V2 q = point();
            const int points = 2 + int(u(rng) * 4);
            for (int k = 0; k < points; ++k) {
              line.push_back(at(q, depth()));
              // Sharp turns (mitres up to the limit), and now and then an end-on step (the same
              // screen point, deeper: exactly end-on when orthographic).
              const double a = u(rng) * 6.2832, len = 5.0 + 40.0 * u(rng);
              if (u(rng) < 0.1) line.push_back(at(q, depth()));
              q += len * test::V2(std::cos(a), std::sin(a));
            }
            w.lines.add(line);
          }
          s.wires.push_back(w);
        }
      RenderOptions o = test::smallOptions(W, H);
      o.tileSize = tile;
      RenderStats st;
      const PreparedScene ps = prepareScene(s, o, st);
      ASSERT_GT(ps.triangles.size(), 60u);
      ASSERT_GT(ps.segments.size(), 250u);
      const TileBins bins = binPrimitives(ps, tile, st);
      std::map<std::pair<std::uint32_t, int>, TileBins::Item> itemOf;  // (primitive, tile)
      for (int t = 0; t < bins.tilesX * bins.tilesY; ++t)
        for (std::uint32_t k = bins.begin(t); k < bins.end(t); ++k) itemOf[{bins.items[k].index, t}] = bins.items[k];
      const std::uint32_t triangles = std::uint32_t(ps.triangles.size());
      for (std::uint32_t i = 0; i < ps.primitiveCount(); ++i) {
        ScreenPolygon poly, cell;
        screenPolygonOf(ps, i, poly);
        if (poly.count < 3) continue;
        double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
        for (int k = 0; k < poly.count; ++k)
          x0 = std::min(x0, poly.x[k]), x1 = std::max(x1, poly.x[k]), y0 = std::min(y0, poly.y[k]), y1 = std::max(y1, poly.y[k]);
        for (int row = std::max(0, int(std::floor(y0))); row <= std::min(H - 1, int(std::floor(y1))); ++row)
          for (int col = std::max(0, int(std::floor(x0))); col <= std::min(W - 1, int(std::floor(x1))); ++col) {
            clipRect(poly, cell, col, row, col + 1.0, row + 1.0);
            if (cell.count < 3 || !(cell.area() > 1e-9)) continue;
            const int t = (row / tile) * bins.tilesX + col / tile;
            const auto found = itemOf.find({i, t});
            ASSERT_NE(found, itemOf.end()) << "primitive " << i << " pixel " << col << "," << row << " tile " << tile;
            const TileBins::Item& it = found->second;
            const int lx = col % tile, ly = row % tile;
            ASSERT_TRUE(lx >= it.x0 && lx <= it.x1 && ly >= it.y0 && ly <= it.y1)
                << "primitive " << i << " pixel " << col << "," << row << " outside [" << int(it.x0) << "," << int(it.x1) << "] x ["
                << int(it.y0) << "," << int(it.y1) << "], tile " << tile;
            double cx, cy;
            cell.centroid(cx, cy);
            const double z = primitiveDepthAt(ps, i, cx, cy);
            ASSERT_LE(double(it.zlo), z + 1e-6 * std::abs(z)) << "primitive " << i << " pixel " << col << "," << row;
            ++checked;
            segmentPixels += i >= triangles;
            tileEdges += lx == it.x0 || lx == it.x1 || ly == it.y0 || ly == it.y1;
          }
      }
    }
  std::printf("[ measured ] %ld covered pixels checked (%ld of segments, %ld on an edge of their item's rectangle)\n", checked,
              segmentPixels, tileEdges);
  EXPECT_GT(checked, 100000);
  EXPECT_GT(segmentPixels, 20000);
}

TEST(SortTileItems, SameOrderAsTheComparisonForAnyDepths) {
  std::mt19937 rng(5);
  // Depths that tie often, both zeros, negatives (orthographic views), infinities, subnormals.
  const float pool[] = {1.0f, 1.0f, 2.5f, 0.0f, -0.0f, -3.0f, -0.5f, INFINITY, -INFINITY, 1e-40f, -1e-40f, 3.4e38f, 7.0f};
  int moved = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const size_t n = size_t(rng() % 3000);
    std::vector<TileBins::Item> items(n);
    for (size_t i = 0; i < n; ++i) {
      TileBins::Item& it = items[i];
      it.zlo = rng() % 3 ? pool[rng() % 13] : std::ldexp(float(rng() % 100000) - 50000.0f, int(rng() % 40) - 20);
      it.index = std::uint32_t(i * 3 + rng() % 3);  // increasing: binPrimitives' primitive order
      it.x0 = std::uint8_t(i % 7);
    }
    std::vector<TileBins::Item> want = items, got = items, scratch;
    std::sort(want.begin(), want.end());
    sortTileItems(got, scratch);
    ASSERT_EQ(got.size(), want.size());
    for (size_t i = 0; i < n; ++i) {
      ASSERT_EQ(got[i].index, want[i].index) << "trial " << trial << " position " << i;
      ASSERT_EQ(got[i].x0, want[i].x0);
    }
    moved += n > 0 && !(got[0].index == items[0].index);
  }
  EXPECT_GT(moved, 100);  // the sort had work to do
}

// Depths that differ only in their lowest 0, 1, 2 or 3 bytes: the sort skips the passes whose
// byte every key shares, so it ends in either buffer (an odd number of passes: the scratch one,
// copied back). Includes a subnormal beside zero, which the key must not flush.
TEST(SortTileItems, SameOrderWhateverPassesRun) {
  std::mt19937 rng(9);
  for (int bytes = 0; bytes <= 3; ++bytes)
    for (int trial = 0; trial < 20; ++trial) {
      std::vector<TileBins::Item> items(64 + rng() % 500);
      const std::uint32_t base = trial % 2 ? 0x3F800000u : 0x00000000u;  // 1.0f, or +0 and the subnormals above it
      for (size_t i = 0; i < items.size(); ++i) {
        const std::uint32_t low = bytes == 0 ? 0u : std::uint32_t(rng()) & ((1u << (8 * bytes)) - 1u);
        const std::uint32_t bits = base + low;
        std::memcpy(&items[i].zlo, &bits, sizeof bits);
        items[i].index = std::uint32_t(i);
      }
      std::vector<TileBins::Item> want = items, got = items, scratch;
      std::sort(want.begin(), want.end());
      sortTileItems(got, scratch);
      for (size_t i = 0; i < items.size(); ++i)
        ASSERT_EQ(got[i].index, want[i].index) << bytes << " bytes, trial " << trial << ", position " << i;
    }
}

// NaN depths (none reaches an item today) sort after every number, ties and NaNs by index, on
// both paths (a comparison sort under 64 items, the radix sort from 64): the order written out
// here (the numbers by depth, then the NaNs in index order), not taken from std::sort, whose
// behaviour under an order NaN breaks is undefined.
TEST(SortTileItems, NaNDepthsSortLastInIndexOrder) {
  for (size_t n : {size_t(10), size_t(100)}) {
    std::vector<TileBins::Item> items(n);
    for (size_t i = 0; i < n; ++i) items[i].zlo = float(n - i), items[i].index = std::uint32_t(i);
    items[n / 2].zlo = NAN;
    items[n / 3].zlo = -NAN;
    items[1].zlo = items[2].zlo;  // a tie: index order
    std::vector<std::uint32_t> want;
    for (size_t i = n; i-- > 0;)
      if (!std::isnan(items[i].zlo) && i != 1) want.push_back(std::uint32_t(i));  // zlo = n - i rises as i falls
    want.insert(std::find(want.begin(), want.end(), 2u), 1u);  // 1 ties with 2 and comes first
    want.push_back(std::uint32_t(n / 3));
    want.push_back(std::uint32_t(n / 2));
    std::vector<TileBins::Item> got = items, scratch;
    sortTileItems(got, scratch);
    ASSERT_EQ(got.size(), n);
    for (size_t i = 0; i < n; ++i) EXPECT_EQ(got[i].index, want[i]) << n << " items, place " << i;
  }
}

// TileClips gives every tile of a block what clipLineToRect gives it, to the bit (ta and tb
// compared by their bits) and with the same refusals: random segments, axis-parallel ones (whose
// zero steps refuse whole columns or rows), ones lying on a column's or a row's line, diagonals
// through the tile corners (ta = tb: a clip that touches a corner only), points, segments far
// outside the block, NaN and infinite ends, and grows of 0, fractions and 1e6 pixels.
TEST(TileClips, EveryTileClipsAsClipLineToRectDoes) {
  std::mt19937 rng(20261207);
  std::uniform_real_distribution<double> u(-40.0, 200.0);
  auto bits = [](double v) {
    std::uint64_t b;
    std::memcpy(&b, &v, sizeof b);
    return b;
  };
  const double grows[] = {0.0, 0.37, 1.5, 31.9, 1e6};
  const int tiles[] = {1, 7, 32};
  int compared = 0, refused = 0, touching = 0;
  for (int trial = 0; trial < 6000; ++trial) {
    glm::dvec2 p0(u(rng), u(rng)), p1(u(rng), u(rng));
    switch (trial % 8) {
      case 1: p1.x = p0.x; break;                        // vertical
      case 2: p1.y = p0.y; break;                        // horizontal
      case 3: p1 = p0; break;                            // a point
      case 4: p1.x = std::round(p1.x), p0.x = p1.x; break;  // on a tile's line, for tile 1
      case 5: if (trial % 16 == 5) p1.x = std::nan(""); else p0.y = INFINITY; break;
      case 6: p1.y = std::round(p1.y), p0.y = p1.y; break;  // on a tile's row line, for tile 1
      case 7:  // a diagonal through lattice points: with tile 1 and no growth, it touches corners
        p0 = glm::dvec2(std::round(p0.x), std::round(p0.y));
        p1 = p0 + glm::dvec2(double(trial % 5 + 1), trial % 2 ? double(trial % 5 + 1) : -double(trial % 5 + 1));
        break;
      default: break;
    }
    const int tile = trial % 8 == 7 ? 1 : tiles[trial % 3];
    const double g = trial % 8 == 7 ? 0.0 : grows[(trial / 3) % 5];
    const int tx0 = int(std::floor(std::min(p0.x, 0.0) / tile)) + int(trial % 5) - 2;
    const int ty0 = int(std::floor(std::min(p0.y, 0.0) / tile)) + int(trial % 7) - 3;
    const int tx1 = tx0 + std::min(trial % 11, TileClips::kMaxSpan - 1), ty1 = ty0 + std::min(trial % 13, TileClips::kMaxSpan - 1);
    TileClips clips;
    ASSERT_TRUE(clips.init(p0, p1, tile, g, tx0, ty0, tx1, ty1));
    for (int ty = ty0; ty <= ty1; ++ty)
      for (int tx = tx0; tx <= tx1; ++tx) {
        double ta = -7.0, tb = -7.0, ra, rb;
        const bool got = clips.clip(tx, ty, ta, tb);
        const bool want = clipLineToRect(p0, p1, tx * tile - g, ty * tile - g, (tx + 1) * tile + g, (ty + 1) * tile + g, ra, rb);
        ASSERT_EQ(got, want) << "trial " << trial << " tile " << tx << ", " << ty;
        ++compared;
        if (!want) {
          ++refused;
          continue;
        }
        ASSERT_EQ(bits(ta), bits(ra)) << "trial " << trial << " tile " << tx << ", " << ty << ": " << ta << " against " << ra;
        ASSERT_EQ(bits(tb), bits(rb)) << "trial " << trial << " tile " << tx << ", " << ty << ": " << tb << " against " << rb;
        touching += ta == tb;
      }
  }
  EXPECT_GT(refused, compared / 10);  // both answers were exercised
  EXPECT_LT(refused, compared);
  EXPECT_GT(touching, 100);  // and clips that touch a corner only
  // Wider than it holds: refused, so that the caller clips tile by tile.
  TileClips wide;
  EXPECT_FALSE(wide.init({0, 0}, {1, 1}, 1, 0.0, 0, 0, TileClips::kMaxSpan, 0));
  EXPECT_FALSE(wide.init({0, 0}, {1, 1}, 1, 0.0, 0, 0, 0, TileClips::kMaxSpan));
}

}  // namespace
}  // namespace wf

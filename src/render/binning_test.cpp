// Tests of the per-tile order (binning.cpp, sortTileItems) against the comparison it stands for,
// TileBins::Item::operator< (depth, then primitive), applied by std::sort.
#include "render/pipeline.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

namespace wf {
namespace {

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

TEST(SortTileItems, NaNDepthsFallBackToTheComparison) {
  std::vector<TileBins::Item> items(100);
  for (size_t i = 0; i < items.size(); ++i) items[i].zlo = float(100 - i), items[i].index = std::uint32_t(i);
  items[50].zlo = NAN;
  std::vector<TileBins::Item> want = items, got = items, scratch;
  std::sort(want.begin(), want.end());
  sortTileItems(got, scratch);
  for (size_t i = 0; i < items.size(); ++i) EXPECT_EQ(got[i].index, want[i].index) << i;
}

}  // namespace
}  // namespace wf

// Tests of the tile A-buffer (abuffer.h) on one pixel or a few: what resolve() returns against
// the compositing written out by hand from abuffer.h's resolve rule,
//   w = opacity * area * mean_{s in M} T[s],  T[s] *= 1 - opacity * min(1, area * N / k),
// and what the counters say about merging, solid pixels, culling and the budget tail.
#include "abuffer/abuffer.h"

#include <gtest/gtest.h>

#include "abuffer_test_fragments.h"
#include "test_support.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

namespace wf {
namespace {

using namespace wf::test;

void expectRGBA(const glm::vec4& got, const glm::vec4& want, float tol, const char* what) {
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(got[i], want[i], tol) << what << " channel " << i;
}

TEST(TileABuffer, SingleFragmentAddsColourTimesAreaTimesOpacity) {
  TileABuffer buf(kL, 64);
  buf.reset(1, 1);
  // 4 samples in the mask but area 0.3: the exact area, not the mask, sets the contribution.
  const glm::vec3 c(1.0f, 0.5f, 0.25f);
  buf.insert(0, 0, frag(2.0f, 0.3f, 0.6f, c, 0xF, 1), 0);
  // Premultiplied colour * 0.3 * 0.6 = colour * 0.18, alpha 0.18 (float rounding only).
  expectRGBA(buf.resolve(0, 0), glm::vec4(c * 0.18f, 0.18f), 1e-7f, "single");
}

TEST(TileABuffer, EmptyMaskStillContributesItsExactArea) {
  // A sliver that hits no sample: area 0.01, mask 0 -> it gets a stand-in subpixel and adds
  // exactly its area (alpha 0.01), so thin lines fade instead of vanishing.
  TileABuffer buf(kL, 64);
  buf.reset(1, 1);
  buf.insert(0, 0, frag(1.0f, 0.01f, 1.0f, kGreen, 0, 1), 17);
  expectRGBA(buf.resolve(0, 0), glm::vec4(0, 0.01f, 0, 0.01f), 1e-8f, "sliver");
  // Many such slivers side by side (one object, disjoint stand-ins or not) sum their areas:
  // 10 pieces of 0.01 of different objects at different sample positions -> alpha 0.1 (each
  // dims only the share it covers of its stand-in subpixel, so they do not hide each other).
  TileABuffer b2(kL, 64);
  b2.reset(1, 1);
  for (int i = 0; i < 10; ++i) b2.insert(0, 0, frag(1.0f + i, 0.01f, 1.0f, kGreen, 0, 100 + i), 3 * i);
  EXPECT_NEAR(b2.resolve(0, 0).w, 0.1f, 1e-6f);
}

TEST(TileABuffer, NearerOpaqueFragmentWinsInEitherOrder) {
  for (int order = 0; order < 2; ++order) {
    TileABuffer buf(kL, 64);
    buf.reset(1, 1);
    const Fragment red = frag(1.0f, 1.0f, 1.0f, kRed, kFull, 1), green = frag(2.0f, 1.0f, 1.0f, kGreen, kFull, 2);
    if (order == 0) {
      buf.insert(0, 0, red, 0);
      buf.insert(0, 0, green, 0);
    } else {
      buf.insert(0, 0, green, 0);
      buf.insert(0, 0, red, 0);
    }
    // Full opaque red at z = 1 hides green at z = 2 wholly: exactly red, alpha 1.
    expectRGBA(buf.resolve(0, 0), glm::vec4(1, 0, 0, 1), 0.0f, order ? "green first" : "red first");
    ABufferCounters c;
    buf.finish(c);
    EXPECT_EQ(c.culled, 1u);  // the hidden one is dropped, whichever came first
    EXPECT_EQ(c.pixelsWithList, 0u);
    EXPECT_EQ(c.pixelsSolidOnly, 1u);
  }
}

TEST(TileABuffer, PartialMaskInFrontShowsHalfOfWhatIsBehind) {
  // Opaque red over the left half (16 of 32 samples, area 0.5) at z = 1, full green at z = 2:
  // red adds 0.5 and hides its samples; green adds area 1 * (16 / 32 samples unhidden) = 0.5.
  for (int order = 0; order < 2; ++order) {
    TileABuffer buf(kL, 64);
    buf.reset(1, 1);
    const Fragment red = frag(1.0f, 0.5f, 1.0f, kRed, kLeftHalf, 1), green = frag(2.0f, 1.0f, 1.0f, kGreen, kFull, 2);
    buf.insert(0, 0, order ? green : red, 0);
    buf.insert(0, 0, order ? red : green, 0);
    expectRGBA(buf.resolve(0, 0), glm::vec4(0.5f, 0.5f, 0, 1), 1e-7f, "half over full");
  }
}

TEST(TileABuffer, PiecesOfOneObjectMergeAndBecomeSolid) {
  // Same tag, disjoint masks (left / right halves), touching depths: one merged fragment with
  // area 1 and a full mask, which is opaque and so becomes the pixel's solid fragment.
  TileABuffer buf(kL, 64);
  buf.reset(1, 1);
  buf.insert(0, 0, frag(1.0f, 0.5f, 1.0f, kRed, kLeftHalf, 7), 0);
  buf.insert(0, 0, frag(1.0f, 0.5f, 1.0f, kBlue, kRightHalf, 7), 0);
  // Area-weighted mean colour (0.5 red + 0.5 blue), full coverage.
  expectRGBA(buf.resolve(0, 0), glm::vec4(0.5f, 0, 0.5f, 1), 1e-7f, "merged");
  ABufferCounters c;
  buf.finish(c);
  EXPECT_EQ(c.merged, 1u);
  EXPECT_EQ(c.pixelsWithList, 0u);  // solid: no list kept
  EXPECT_EQ(c.pixelsSolidOnly, 1u);
  EXPECT_EQ(c.fragments, 2u);
}

TEST(TileABuffer, DifferentObjectsDoNotMerge) {
  // Same geometry, different tags: two list entries, no merge; they still add up to alpha 1
  // because their masks are disjoint (each sees T = 1 on its own samples).
  TileABuffer buf(kL, 64);
  buf.reset(1, 1);
  buf.insert(0, 0, frag(1.0f, 0.5f, 1.0f, kRed, kLeftHalf, 7), 0);
  buf.insert(0, 0, frag(1.0f, 0.5f, 1.0f, kBlue, kRightHalf, 8), 0);
  expectRGBA(buf.resolve(0, 0), glm::vec4(0.5f, 0, 0.5f, 1), 1e-7f, "unmerged");
  ABufferCounters c;
  buf.finish(c);
  EXPECT_EQ(c.merged, 0u);
  EXPECT_EQ(c.pixelsWithList, 1u);
  EXPECT_EQ(c.pixelsSolidOnly, 0u);
  EXPECT_EQ(c.maxListLength, 2u);
}

TEST(TileABuffer, SameObjectDoesNotMergeAcrossADepthGapOrOverlappingMasks) {
  // Touching depth is required: same tag, disjoint masks, z = 1 and z = 5 -> two entries.
  {
    TileABuffer buf(kL, 64);
    buf.reset(1, 1);
    buf.insert(0, 0, frag(1.0f, 0.5f, 1.0f, kRed, kLeftHalf, 7), 0);
    buf.insert(0, 0, frag(5.0f, 0.5f, 1.0f, kBlue, kRightHalf, 7), 0);
    ABufferCounters c;
    buf.finish(c);
    EXPECT_EQ(c.merged, 0u);
  }
  // Overlapping masks (a fold of the same surface) are not merged either.
  {
    TileABuffer buf(kL, 64);
    buf.reset(1, 1);
    buf.insert(0, 0, frag(1.0f, 0.5f, 1.0f, kRed, kLeftHalf, 7), 0);
    buf.insert(0, 0, frag(1.0f, 0.5f, 1.0f, kBlue, kLeftHalf | 0x10, 7), 0);
    ABufferCounters c;
    buf.finish(c);
    EXPECT_EQ(c.merged, 0u);
  }
}

TEST(TileABuffer, SolidPixelKeepsNoListAndCullsWhatIsBehind) {
  TileABuffer buf(kL, 64);
  buf.reset(2, 1);
  buf.insert(0, 0, frag(1.0f, 1.0f, 1.0f, kRed, kFull, 1), 0);
  // Behind the solid red: a full one, a partial one and a translucent one: all culled.
  buf.insert(0, 0, frag(3.0f, 1.0f, 1.0f, kGreen, kFull, 2), 0);
  buf.insert(0, 0, frag(2.0f, 0.25f, 1.0f, kGreen, 0xFF, 3), 0);
  buf.insert(0, 0, frag(4.0f, 1.0f, 0.5f, kBlue, kFull, 4), 0);
  // The red is all that is seen; pixel (1, 0) received nothing and stays transparent.
  expectRGBA(buf.resolve(0, 0), glm::vec4(1, 0, 0, 1), 0.0f, "solid");
  expectRGBA(buf.resolve(1, 0), glm::vec4(0), 0.0f, "empty");
  // The occlusion depth is the solid's depth.
  EXPECT_EQ(buf.occlusionDepth(0, 0), 1.0f);
  EXPECT_EQ(buf.occlusionDepth(1, 0), INFINITY);
  ABufferCounters c;
  buf.finish(c);
  EXPECT_EQ(c.pixelsWithList, 0u);
  EXPECT_EQ(c.pixelsSolidOnly, 1u);
  EXPECT_EQ(c.culled, 3u);
  EXPECT_EQ(c.coveredPixels, 1u);
  EXPECT_EQ(c.fragments, 4u);
}

TEST(TileABuffer, TranslucentLayersCompositeFrontToBackInEitherOrder) {
  // Red (0.5) at z = 1 in front of blue (0.5) at z = 2: 0.5 red + (1 - 0.5) * 0.5 blue,
  // alpha 1 - 0.5 * 0.5 = 0.75, whatever the insertion order.
  for (int order = 0; order < 2; ++order) {
    TileABuffer buf(kL, 64);
    buf.reset(1, 1);
    const Fragment red = frag(1.0f, 1.0f, 0.5f, kRed, kFull, 1), blue = frag(2.0f, 1.0f, 0.5f, kBlue, kFull, 2);
    buf.insert(0, 0, order ? blue : red, 0);
    buf.insert(0, 0, order ? red : blue, 0);
    expectRGBA(buf.resolve(0, 0), glm::vec4(0.5f, 0, 0.25f, 0.75f), 1e-7f, order ? "blue first" : "red first");
  }
}

TEST(TileABuffer, BudgetKeepsTheNearestAndBlendsTheRestIntoTheTail) {
  // K = 4, ten full-coverage layers of opacity 0.1 at distinct depths, inserted in three
  // orders. Six go to the tail. Alpha: the list gives 1 - 0.9^4, the tail (1 - 0.9^6) behind
  // the list's 0.9^4: 1 - 0.9^10 in all (float rounding over ~20 operations: 1e-5).
  const float depths[10] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
  // The four nearest carry red = 1, 0.5, 0.25, 0.125 and nothing else; the six in the tail are
  // blue, so red and blue separate the exact part from the tail.
  auto colourOf = [](int i) { return i < 4 ? glm::vec3(std::ldexp(1.0f, -i), 0, 0) : kBlue; };
  std::vector<std::vector<int>> orders = {{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}, {9, 8, 7, 6, 5, 4, 3, 2, 1, 0}, {5, 0, 9, 3, 7, 1, 8, 2, 6, 4}};
  for (const auto& ord : orders) {
    TileABuffer buf(kL, 4);
    buf.reset(1, 1);
    for (int i : ord) buf.insert(0, 0, frag(depths[i], 1.0f, 0.1f, colourOf(i), kFull, 10 + i), 0);
    const glm::vec4 got = buf.resolve(0, 0);
    EXPECT_NEAR(got.w, 1.0 - std::pow(0.9, 10), 1e-5);
    // Exact part: layer i (i < 4) adds red_i * 0.1 * 0.9^i.
    double red = 0;
    for (int i = 0; i < 4; ++i) red += std::ldexp(1.0, -i) * 0.1 * std::pow(0.9, i);
    EXPECT_NEAR(got.x, red, 1e-6);
    EXPECT_NEAR(got.y, 0.0, 1e-7);
    // Tail: blue * (1 - 0.9^6), seen through the list's 0.9^4.
    EXPECT_NEAR(got.z, (1 - std::pow(0.9, 6)) * std::pow(0.9, 4), 1e-5);
    ABufferCounters c;
    buf.finish(c);
    EXPECT_EQ(c.tail, 6u);
    EXPECT_EQ(c.pixelsOverBudget, 1u);
    EXPECT_EQ(c.pixelsWithList, 1u);
    EXPECT_EQ(c.maxListLength, 4u);
    EXPECT_EQ(c.fragments, 10u);
  }
}

TEST(TileABuffer, BudgetKeepsTheNearestWhateverTheOrderAndTheTies) {
  // The same rule as above at the sizes where a full list remembers its farthest entries
  // (TileABuffer::FarCache: 8 of them, refilled by a scan): budgets 4, 32 and 64, 600
  // full-coverage layers of opacity 0.1, the budget's nearest red and the rest blue, inserted
  // front to back (no eviction), back to front (each layer evicts the farthest) and in five
  // random orders. Equal depths come in pairs among the red and in threes among the blue, so
  // evictions meet ties; which of equal layers stays is then a matter of arrival, but both are
  // the same colour. Expected, as above: red sum_{i<K} 0.1 * 0.9^i, blue (1 - 0.9^(600-K))
  // 0.9^K, alpha 1 - 0.9^600. A red layer wrongly evicted moves at least 0.1 * 0.9^63 = 1.3e-4
  // of red into the tail's blue; the tolerance, float rounding over ~1,200 operations, is 2e-5.
  const int M = 600;
  for (int K : {4, 32, 64}) {
    std::vector<float> depth(static_cast<size_t>(M));
    for (int i = 0; i < M; ++i) depth[size_t(i)] = i < K ? 1.0f + 0.01f * float(i / 2) : 2.0f + 0.01f * float((i - K) / 3);
    std::vector<std::vector<int>> orders(7, std::vector<int>(size_t(M)));
    std::iota(orders[0].begin(), orders[0].end(), 0);
    orders[1].assign(orders[0].rbegin(), orders[0].rend());
    std::mt19937 rng{std::uint32_t(K)};
    for (size_t o = 2; o < orders.size(); ++o) {
      orders[o] = orders[0];
      std::shuffle(orders[o].begin(), orders[o].end(), rng);
    }
    double red = 0;
    for (int i = 0; i < K; ++i) red += 0.1 * std::pow(0.9, i);
    const double blue = (1 - std::pow(0.9, M - K)) * std::pow(0.9, K);
    for (size_t o = 0; o < orders.size(); ++o) {
      TileABuffer buf(kL, K);
      buf.reset(1, 1);
      for (int i : orders[o])
        buf.insert(0, 0, frag(depth[size_t(i)], 1.0f, 0.1f, i < K ? kRed : kBlue, kFull, std::uint32_t(10 + i)), 0);
      const glm::vec4 got = buf.resolve(0, 0);
      EXPECT_NEAR(got.x, red, 2e-5) << "budget " << K << ", order " << o;
      EXPECT_NEAR(got.y, 0.0, 1e-7) << "budget " << K << ", order " << o;
      EXPECT_NEAR(got.z, blue, 2e-5) << "budget " << K << ", order " << o;
      EXPECT_NEAR(got.w, 1 - std::pow(0.9, M), 2e-5) << "budget " << K << ", order " << o;
      ABufferCounters c;
      buf.finish(c);
      EXPECT_EQ(c.tail, std::uint64_t(M - K));
    }
  }
}

TEST(TileABuffer, BudgetEvictsTheFarthestByTheListRuleAmongTies) {
  // Which of equal farthest entries a full list evicts is a rule (the farthest scanning from
  // the newest end of the list, of equal ones the last met), and the far cache must keep it:
  // 600 layers of random colours whose depths take 12 or 400 values, budgets 4, 32 and 64,
  // five random orders. The reference replays the rule on a plain array, then feeds a second
  // buffer the entries it kept (front to back: nothing evicted) and then what it sent to the
  // tail, in the order it went there: the same sums in the same order, so the same bits.
  const int M = 600;
  std::mt19937 rng{7};
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  for (int levels : {12, 400})
    for (int K : {4, 32, 64})
      for (int trial = 0; trial < 5; ++trial) {
        std::vector<Fragment> fs;
        for (int i = 0; i < M; ++i)
          fs.push_back(frag(1.0f + 0.01f * float(rng() % std::uint32_t(levels)), 1.0f, 0.1f, glm::vec3(U(rng), U(rng), U(rng)), kFull,
                            std::uint32_t(10 + i)));
        std::vector<int> list, tail;  // list: newest first, as the buffer links it
        for (int i = 0; i < M; ++i) {
          if (int(list.size()) < K) {
            list.insert(list.begin(), i);
            continue;
          }
          size_t far = 0;
          for (size_t j = 0; j < list.size(); ++j)
            if (fs[size_t(list[j])].zkey >= fs[size_t(list[far])].zkey) far = j;
          if (fs[size_t(i)].zkey >= fs[size_t(list[far])].zkey) {
            tail.push_back(i);
          } else {
            tail.push_back(list[far]);
            list[far] = i;
          }
        }
        TileABuffer buf(kL, K), ref(kL, K);
        buf.reset(1, 1);
        ref.reset(1, 1);
        for (const Fragment& f : fs) buf.insert(0, 0, f, 0);
        std::sort(list.begin(), list.end(), [&](int a, int b) {
          return fs[size_t(a)].zkey < fs[size_t(b)].zkey || (fs[size_t(a)].zkey == fs[size_t(b)].zkey && a < b);
        });
        for (int i : list) ref.insert(0, 0, fs[size_t(i)], 0);
        for (int i : tail) ref.insert(0, 0, fs[size_t(i)], 0);
        expectRGBA(buf.resolve(0, 0), ref.resolve(0, 0), 0.0f, "evictions by the rule");
      }
}

TEST(TileABuffer, AFullListDropsWhatIsHiddenBeforeItEvicts) {
  // Pruning (TileABuffer::pruneHidden), which skips its walk when no entry begins behind the
  // depth it prunes at: what the list holds wholly behind an occluder is dropped (counted as
  // culled) rather than evicted into a tail.
  {
    // (Objects of one piece each: they count for occlusion on arrival.)
    // Budget 6: four translucent layers at z = 10 ... 13, then two opaque halves at z = 5 that
    // hide every subpixel between them. The next fragment (z = 1) finds the list full and the
    // pixel hidden behind 5: the four are dropped, nothing goes to the tail.
    TileABuffer buf(kL, 6);
    buf.reset(1, 1);
    for (int i = 0; i < 4; ++i) buf.insert(0, 0, frag(10.0f + float(i), 1.0f, 0.5f, kBlue, kFull, std::uint32_t(1 + i), false), 0);
    buf.insert(0, 0, frag(5.0f, 0.5f, 1.0f, kGreen, kLeftHalf, 10, false), 0);
    buf.insert(0, 0, frag(5.0f, 0.5f, 1.0f, kGreen, kRightHalf, 11, false), 0);
    EXPECT_EQ(buf.occlusionDepth(0, 0), 5.0f);
    buf.insert(0, 0, frag(1.0f, 1.0f, 0.5f, kRed, kFull, 12, false), 0);
    // Red at half, then the green halves through the red's half: no blue.
    expectRGBA(buf.resolve(0, 0), glm::vec4(0.5f, 0.5f, 0.0f, 1.0f), 1e-6f, "pruned");
    ABufferCounters c;
    buf.finish(c);
    EXPECT_EQ(c.tail, 0u);
    EXPECT_EQ(c.culled, 4u);
  }
  {
    // Budget 2: two layers whose depth ranges begin near (z 1 ... 30 and 2 ... 28), then a flat
    // one at z = 10 that evicts the farther (keyed 15.5): it begins behind both. A solid
    // fragment at z = 5 then drops it from the list (it lies wholly behind) and keeps the other.
    TileABuffer buf(kL, 2);
    buf.reset(1, 1);
    Fragment a = frag(15.5f, 1.0f, 0.5f, kBlue, kFull, 1, false), b = frag(15.0f, 1.0f, 0.5f, kBlue, kFull, 2, false);
    a.zmin = 1.0f, a.zmax = 30.0f;
    b.zmin = 2.0f, b.zmax = 28.0f;
    buf.insert(0, 0, a, 0);
    buf.insert(0, 0, b, 0);
    buf.insert(0, 0, frag(10.0f, 1.0f, 0.5f, kRed, kFull, 3, false), 0);
    buf.insert(0, 0, frag(5.0f, 1.0f, 1.0f, kGreen, kFull, 4, false), 0);
    ABufferCounters c;
    buf.finish(c);
    EXPECT_EQ(c.tail, 1u);    // the evicted one
    EXPECT_EQ(c.culled, 1u);  // the flat one, dropped behind the solid
  }
  {
    // Two prunes, the second at a nearer depth than the first (its bound is the one the first
    // walk left: everything inserted since begins in front of the second depth). Budget 7: four
    // layers at z = 10 ... 13 and opaque halves at 5 (hidden behind 5), red at 1; yellow at 1.8
    // finds the list full: the four are dropped. Opaque halves at 2 then hide the pixel nearer,
    // and the next two (z = 1.5, 1.2) fill it again: the halves at 5, wholly behind 2, are
    // dropped; nothing is ever evicted.
    TileABuffer buf(kL, 7);
    buf.reset(1, 1);
    std::uint32_t tag = 1;
    for (int i = 0; i < 4; ++i) buf.insert(0, 0, frag(10.0f + float(i), 1.0f, 0.5f, kBlue, kFull, tag++, false), 0);
    buf.insert(0, 0, frag(5.0f, 0.5f, 1.0f, kGreen, kLeftHalf, tag++, false), 0);
    buf.insert(0, 0, frag(5.0f, 0.5f, 1.0f, kGreen, kRightHalf, tag++, false), 0);
    buf.insert(0, 0, frag(1.0f, 1.0f, 0.5f, kRed, kFull, tag++, false), 0);
    buf.insert(0, 0, frag(1.8f, 1.0f, 0.5f, kRed + kGreen, kFull, tag++, false), 0);
    buf.insert(0, 0, frag(2.0f, 0.5f, 1.0f, kRed + kBlue, kLeftHalf, tag++, false), 0);
    buf.insert(0, 0, frag(2.0f, 0.5f, 1.0f, kRed + kBlue, kRightHalf, tag++, false), 0);
    EXPECT_EQ(buf.occlusionDepth(0, 0), 2.0f);
    buf.insert(0, 0, frag(1.5f, 1.0f, 0.5f, kGreen, kFull, tag++, false), 0);
    buf.insert(0, 0, frag(1.2f, 1.0f, 0.5f, kGreen, kFull, tag++, false), 0);
    ABufferCounters c;
    buf.finish(c);
    EXPECT_EQ(c.tail, 0u);
    EXPECT_EQ(c.culled, 6u);
  }
}

TEST(TileABuffer, BudgetTailInFrontOfASolidFragmentStillShows) {
  // Regression test: against 523d985 resolve() composited the tail after *everything*,
  // including the solid fragment, so a tail of fragments lying in front of the solid was
  // hidden by it and vanished (blue 0, green 0.656 here) instead of being blended, e.g. hairs
  // beyond the budget over a skin surface. Fixed in cc8649c ("tail composites at its depth").
  // Every tail fragment here passed the "not behind the solid" test on insertion.
  //
  // K = 4; opaque full green at z = 20 (the solid); ten 0.1-opacity full layers at z = 1 ... 10:
  // red (the four nearest, kept exactly) and blue (the six in the tail). Front to back:
  // red adds 0.1 (1 + 0.9 + 0.9^2 + 0.9^3), the tail (1 - 0.9^6) * 0.9^4 blue, the solid
  // 0.9^10 green; alpha 1. The tail's compositing is exact here (all layers cover the pixel).
  for (int solidFirst = 0; solidFirst < 2; ++solidFirst) {
    TileABuffer buf(kL, 4);
    buf.reset(1, 1);
    if (solidFirst) buf.insert(0, 0, frag(20.0f, 1.0f, 1.0f, kGreen, kFull, 1), 0);
    for (int i = 9; i >= 0; --i) buf.insert(0, 0, frag(1.0f + i, 1.0f, 0.1f, i < 4 ? kRed : kBlue, kFull, 10 + i), 0);
    if (!solidFirst) buf.insert(0, 0, frag(20.0f, 1.0f, 1.0f, kGreen, kFull, 1), 0);
    const glm::vec4 got = buf.resolve(0, 0);
    double red = 0;
    for (int i = 0; i < 4; ++i) red += 0.1 * std::pow(0.9, i);
    EXPECT_NEAR(got.w, 1.0, 1e-6);
    EXPECT_NEAR(got.x, red, 1e-5) << "solid first: " << solidFirst;
    EXPECT_NEAR(got.z, (1 - std::pow(0.9, 6)) * std::pow(0.9, 4), 1e-5) << "tail lost behind the solid? solid first: " << solidFirst;
    EXPECT_NEAR(got.y, std::pow(0.9, 10), 1e-5) << "solid first: " << solidFirst;
    ABufferCounters c;
    buf.finish(c);
    EXPECT_EQ(c.tail, 6u);
  }
}

// Front-to-back composite of full-coverage layers in double: the exact answer.
glm::dvec4 exactComposite(std::vector<Fragment> fs) {
  std::stable_sort(fs.begin(), fs.end(), [](const Fragment& a, const Fragment& b) { return a.zkey < b.zkey; });
  double T = 1;
  glm::dvec3 rgb(0);
  for (const Fragment& f : fs) {
    const double a = double(f.opacity) * double(f.area);
    rgb += glm::dvec3(f.colour) * (a * T);
    T *= 1 - a;
  }
  return glm::dvec4(rgb, 1 - T);
}

std::vector<Fragment> randomLayers(int n, float maxOpacity, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  std::vector<Fragment> fs;
  for (int i = 0; i < n; ++i)
    fs.push_back(frag(1.0f + 1000.0f * U(rng), 1.0f, maxOpacity * U(rng), glm::vec3(U(rng), U(rng), U(rng)), kFull,
                      std::uint32_t(i + 1)));
  return fs;
}

TEST(TileABuffer, ThousandsOfLayersMatchTheExactComposite) {
  // 5000 full-coverage layers, budget 65535 (all kept exactly). Tolerance: every layer adds at
  // most ~4 float roundings (relative 2^-24 each) to the running transmittance and colour, and
  // T <= 1, so |error| <= 4 * n * 2^-24 = 1.2e-3 in the worst case.
  const int n = 5000;
  const double tol = 4.0 * n * std::ldexp(1.0, -24);
  // Small opacities (every layer matters: T(5000) ~ exp(-5)) and opacities in [0, 1].
  for (float maxOpacity : {0.002f, 1.0f}) {
    const std::vector<Fragment> fs = randomLayers(n, maxOpacity, 77);
    TileABuffer buf(kL, 65535);
    buf.reset(1, 1);
    for (const Fragment& f : fs) buf.insert(0, 0, f, 0);
    const glm::vec4 got = buf.resolve(0, 0);
    const glm::dvec4 want = exactComposite(fs);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(got[i], want[i], tol) << "max opacity " << maxOpacity << " channel " << i;
    ABufferCounters c;
    buf.finish(c);
    EXPECT_EQ(c.tail, 0u);
    EXPECT_EQ(c.maxListLength, 5000u);
    EXPECT_EQ(c.maxFragmentsPerPixel, 5000u);
  }
}

TEST(TileABuffer, ThousandsOfLayersUnderASmallBudgetStayFiniteAndBounded) {
  // 5000 random fragments (random masks, some empty, random areas and opacities) into budget
  // 8: finite, alpha in [0, 1], premultiplied colour in [0, alpha] (colours are in [0, 1]).
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  TileABuffer buf(kL, 8);
  buf.reset(1, 1);
  for (int i = 0; i < 5000; ++i) {
    Fragment f = frag(1.0f + 100.0f * U(rng), U(rng), U(rng), glm::vec3(U(rng), U(rng), U(rng)),
                      (MaskBits(rng()) & kFull) & (i % 3 == 0 ? 0 : kFull), std::uint32_t(i % 50));
    f.zmax = f.zmin + 0.01f * U(rng);
    f.zkey = 0.5f * (f.zmin + f.zmax);
    buf.insert(0, 0, f, int(rng() % 32));
  }
  const glm::vec4 got = buf.resolve(0, 0);
  EXPECT_TRUE(std::isfinite(got.x) && std::isfinite(got.y) && std::isfinite(got.z) && std::isfinite(got.w));
  EXPECT_GE(got.w, 0.0f);
  EXPECT_LE(got.w, 1.0f);
  for (int i = 0; i < 3; ++i) {
    EXPECT_GE(got[i], 0.0f);
    EXPECT_LE(got[i], got.w * (1 + 1e-5f));
  }
  ABufferCounters c;
  buf.finish(c);
  EXPECT_LE(c.maxListLength, 8u);
  EXPECT_GT(c.tail, 0u);

  // Full-coverage layers under budget 8: the tail is order-independent but its alpha is still
  // exact, 1 - prod(1 - a_i) (list: 1 - P_list; tail: (1 - P_tail) * P_list), float tolerance
  // as in the exact test above.
  const std::vector<Fragment> fs = randomLayers(5000, 0.002f, 78);
  TileABuffer small(kL, 8);
  small.reset(1, 1);
  for (const Fragment& f : fs) small.insert(0, 0, f, 0);
  EXPECT_NEAR(small.resolve(0, 0).w, exactComposite(fs).w, 4.0 * 5000 * std::ldexp(1.0, -24));
  ABufferCounters c2;
  small.finish(c2);
  EXPECT_EQ(c2.tail, 5000u - 8u);
}

TEST(TileABuffer, ResetClearsEverything) {
  // After reset the same buffer resolves a fresh single fragment exactly as a new one would.
  TileABuffer buf(kL, 4);
  buf.reset(3, 2);
  for (int i = 0; i < 20; ++i) buf.insert(1, 1, frag(1.0f + i, 1.0f, 0.3f, kRed, kFull, 1 + i), 0);
  buf.insert(2, 0, frag(1.0f, 1.0f, 1.0f, kGreen, kFull, 99), 0);
  ABufferCounters junk;
  buf.finish(junk);
  buf.reset(3, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) expectRGBA(buf.resolve(x, y), glm::vec4(0), 0.0f, "after reset");
  EXPECT_EQ(buf.occlusionDepth(2, 0), INFINITY);
  buf.insert(1, 1, frag(1.0f, 0.25f, 1.0f, kBlue, 0xFF, 1), 0);
  expectRGBA(buf.resolve(1, 1), glm::vec4(0, 0, 0.25f, 0.25f), 1e-7f, "fresh");
  ABufferCounters c;
  buf.finish(c);
  EXPECT_EQ(c.fragments, 1u);  // the counters of the previous tile went to `junk`
  EXPECT_EQ(c.tail, 0u);
}

// The occlusion bookkeeping (abuffer.h: per subpixel, the transmittance T that what lies in front
// leaves and the depth D behind which it all lies; settled once T <= epsilon) against the same
// rule written out here one subpixel at a time, for fragments alone in their pixel (no merges,
// solids or tails), in every layout, at epsilon 0 and 0.05: after every insertion, the pixel's
// occlusion depth and maskHidden's answer for random masks and depths. The buffer visits its
// subpixels four at a time (SSE2); masks reach every group of four, hides are exactly 1 or
// less, depths repeat, and some are +inf or NaN.
TEST(TileABuffer, OcclusionBookkeepingFollowsTheRuleSubpixelBySubpixel) {
  auto sameFloat = [](float a, float b) { return (std::isnan(a) && std::isnan(b)) || a == b; };
  int checks = 0, hiddenYes = 0;
  for (const MaskLayout L : {MaskLayout{4, 4}, MaskLayout{8, 4}, MaskLayout{8, 8}}) {
    for (const float eps : {0.0f, 0.05f}) {
      std::mt19937_64 rng(17);
      const int N = L.samples();
      auto randomMask = [&] {
        MaskBits m = 0;
        switch (rng() % 3) {
          case 0: m = rng() & L.full(); break;                        // about half the subpixels
          case 1: m = (rng() & rng() & rng()) & L.full(); break;      // a few
          default: m = MaskBits(0xF) << (4 * int(rng() % unsigned(N / 4)));  // one group of four
        }
        return m ? m : MaskBits(1) << (rng() % unsigned(N));
      };
      const float depths[] = {1.0f, 2.0f, 2.0f, 3.0f, 2.5f, INFINITY, NAN};
      for (int trial = 0; trial < 60; ++trial) {
        TileABuffer buf(L, 64, eps);
        buf.reset(1, 1);
        std::vector<float> D(size_t(N), 0.0f), T(size_t(N), 1.0f);
        bool tracked = false;
        int open = N;
        float occ = INFINITY;
        for (int step = 0; step < 40; ++step) {
          const MaskBits mask = randomMask();
          const int k = maskCount(mask);
          const float opacity = rng() % 2 ? 1.0f : 0.1f + 0.9f * float(rng() % 1000) / 1000.0f;
          // area k / N hides exactly `opacity`; the others less or (clamped) the same
          const float area = rng() % 2 ? float(k) / float(N) * 0.95f : 0.01f + 0.94f * float(rng() % 1000) / 1000.0f;
          const float z = depths[rng() % 7];
          Fragment f = frag(z, area, opacity, kRed, mask, 1, false);
          // The rule (abuffer.h; TileABuffer::occlude), subpixel by subpixel.
          const float hide = opacity * std::min(1.0f, area * float(N) / float(k));
          const bool culled = z >= occ;
          if (!culled && hide > 0.0f && !(tracked && open == 0 && (hide < 1.0f || !(z < occ)))) {
            tracked = true;
            bool changed = false;
            for (int s = 0; s < N; ++s) {
              if (!((mask >> s) & 1)) continue;
              const bool settled = T[size_t(s)] <= eps;
              if (hide >= 1.0f) {
                if (!settled) --open, D[size_t(s)] = z, changed = true;
                else if (z < D[size_t(s)]) D[size_t(s)] = z, changed = true;
                T[size_t(s)] = 0.0f;
              } else if (!settled) {
                T[size_t(s)] *= 1.0f - hide;
                D[size_t(s)] = std::max(D[size_t(s)], z);
                if (T[size_t(s)] <= eps) --open, changed = true;
              }
            }
            if (changed && open == 0) {
              float m = 0.0f;
              for (int s = 0; s < N; ++s) m = std::max(m, D[size_t(s)]);
              if (m < occ) occ = m;
            }
          }
          buf.insert(0, 0, f, 0);
          ASSERT_TRUE(sameFloat(buf.occlusionDepth(0, 0), occ))
              << L.name() << " eps " << eps << " trial " << trial << " step " << step << ": " << buf.occlusionDepth(0, 0)
              << " against " << occ;
          for (int q = 0; q < 4; ++q) {
            const MaskBits qm = randomMask();
            const float qz = depths[rng() % 7];
            bool want = tracked;
            for (int s = 0; s < N && want; ++s)
              if ((qm >> s) & 1) want = T[size_t(s)] <= eps && D[size_t(s)] <= qz;
            ASSERT_EQ(buf.maskHidden(0, 0, qm, 0, qz), want)
                << L.name() << " eps " << eps << " trial " << trial << " step " << step << " query mask " << std::hex << qm;
            ++checks;
            hiddenYes += want;
          }
        }
      }
    }
  }
  // The rule was exercised both ways, not only answered "no".
  EXPECT_GT(hiddenYes, checks / 20) << hiddenYes << " of " << checks;
  EXPECT_LT(hiddenYes, checks - checks / 20) << hiddenYes << " of " << checks;
}

// Deep shares (RenderOptions::deepShares): 7 thin opaque fragments, one sample column each
// (areas 0.06 ... 0.12, in front), over a blue full-pixel one that owns column 7's samples.
// The blue one covers the whole pixel and the 8 sampled fragments every sample, so the pixel
// is deep: the 7 in front keep their exact areas, and the blue one, hidden anywhere, gets the
// rest of the pixel, 1 - sum(areas), whatever share of samples it owns.
std::vector<Fragment> deepPixel(int columns, float area0 = 0.06f, float step = 0.01f) {
  std::vector<Fragment> fs;
  for (int c = 0; c < columns; ++c) {
    const glm::vec3 colour(0.1f * float(c + 1), 1.0f - 0.1f * float(c), 0.5f);
    fs.push_back(frag(1.0f + float(c), area0 + step * float(c), 1.0f, colour, MaskBits(0x01010101u) << c, 10u + std::uint32_t(c)));
  }
  fs.push_back(frag(20.0f, 1.0f, 1.0f, kBlue, kFull, 99));
  return fs;
}

glm::vec4 resolveOne(const std::vector<Fragment>& fs, bool deepShares) {
  TileABuffer buf(kL, 64, 0.0f, deepShares);
  buf.reset(1, 1);
  for (const Fragment& f : fs) buf.insert(0, 0, f, 0);
  return buf.resolve(0, 0);
}

TEST(TileABuffer, DeepSharesKeepTheFrontAreasAndGiveTheRestToWhatIsHidden) {
  // Areas 0.06 ... 0.12 (fewer than their 4 samples' 0.125): then abuffer.h's partial hides
  // give the same, 1 - sum(areas) to the blue one. Areas 0.126 ... 0.132 (more): each of the 7
  // hides its samples wholly, and the blue one would weigh its 4 samples' 0.125, 0.028 more
  // than the pixel has left: deep shares give it the 0.097 left.
  for (float area0 : {0.06f, 0.126f}) {
    const std::vector<Fragment> fs = deepPixel(7, area0, area0 < 0.1f ? 0.01f : 0.001f);
    glm::vec3 want(0.0f);
    double front = 0.0;
    for (int c = 0; c < 7; ++c) want += fs[size_t(c)].colour * fs[size_t(c)].area, front += fs[size_t(c)].area;
    want += kBlue * float(1.0 - front);
    expectRGBA(resolveOne(fs, true), glm::vec4(want, 1.0f), 2e-6f, area0 < 0.1f ? "thin" : "wider");
    const glm::vec4 off = resolveOne(fs, false);
    if (area0 < 0.1f) expectRGBA(off, glm::vec4(want, 1.0f), 2e-6f, "thin, deep shares off");
    else EXPECT_GT(std::abs(off.z - want.z), 0.005f);  // (normalised from alpha 1.028: blue 0.122, not 0.097)
  }
}

TEST(TileABuffer, DeepSharesShowTheSurfaceInTheGapsWhereNothingHiddenOwnsASample) {
  // All 8 columns taken by the thin ones (areas 0.06 ... 0.13, 0.76 in all): the blue surface
  // behind owns no sample, yet the gaps between them show it: 0.24 of the pixel. And so they
  // do with a wire's solid (white, area 1) between the thin ones and the surface, which takes
  // the surface's place as the pixel's solid: the gaps show the surface still (culling at
  // epsilon > 0 may leave the wire out, never the surface).
  std::vector<Fragment> fs = deepPixel(8);
  glm::vec3 want(0.0f);
  double front = 0.0;
  for (int c = 0; c < 8; ++c) want += fs[size_t(c)].colour * fs[size_t(c)].area, front += fs[size_t(c)].area;
  want += kBlue * float(1.0 - front);
  expectRGBA(resolveOne(fs, true), glm::vec4(want, 1.0f), 2e-6f, "gaps");
  Fragment wire = frag(15.0f, 1.0f, 1.0f, glm::vec3(1.0f), kFull, 98);
  wire.occludesEarly = true;
  fs.push_back(wire);
  expectRGBA(resolveOne(fs, true), glm::vec4(want, 1.0f), 2e-6f, "gaps behind a wire's solid");
}

TEST(TileABuffer, DeepSharesSplitTheRestBySamplesOwned) {
  // Over a grey surface that covers the whole pixel, eight fragments of area 0.2, fragment c over
  // sample columns c and c + 1 (mod 8), nearer the lower c, inserted back to front (nothing is
  // culled on arrival: under abuffer.h's rule each only dims its samples, by 0.2 * 32 / 8 =
  // 0.8; none of them occludes on arrival anyway, being pieces that may merge). Deep: fragment
  // 0 owns both its columns (its exact area, 0.2), fragments 1 ... 6 one
  // column each (4 samples), fragment 7 and the surface none: the 0.8 left goes to 1 ... 6 by
  // their samples, 0.8 / 6 each.
  std::vector<Fragment> fs{frag(30.0f, 1.0f, 1.0f, glm::vec3(0.5f), kFull, 19)};
  glm::vec3 want(0.0f);
  for (int c = 7; c >= 0; --c) {
    const MaskBits columns = (MaskBits(0x01010101u) << c) | (MaskBits(0x01010101u) << ((c + 1) % 8));
    const glm::vec3 colour(0.1f * float(c + 1), 0.05f * float(c), 1.0f - 0.1f * float(c));
    fs.push_back(frag(1.0f + float(c), 0.2f, 1.0f, colour, columns, 20u + std::uint32_t(c)));
    want += colour * (c == 0 ? 0.2f : c == 7 ? 0.0f : 0.8f / 6.0f);
  }
  expectRGBA(resolveOne(fs, true), glm::vec4(want, 1.0f), 2e-6f, "shares");
}

// Culling's bound in one pixel, fragment by fragment (review 65's case): a blue surface (whole,
// or 99.95% of the pixel: then no solid), three layers of thin opaque wire pieces in front that
// leave T = 0.008 at every sample, and behind them a wire covering the pixel or a translucent
// one. At epsilon 0.01 against 0 the pixel differs by at most 0.01 under either rule, though
// culling leaves the one behind out at 0.01 (a gate or a share that asked for it moved 0.2).
TEST(TileABuffer, CullingAtEpsilonMovesADeepPixelByAtMostEpsilon) {
  auto run = [](float eps, bool deep, float surfaceArea, bool wholeWire, std::uint64_t& culled) {
    auto piece = [](float z, float area, float opacity, glm::vec3 c, MaskBits m, std::uint32_t tag) {
      Fragment f = frag(z, area, opacity, c, m, tag, false);
      f.occludesEarly = true;  // a wire's
      return f;
    };
    TileABuffer b(kL, 64, eps, deep);
    b.reset(1, 1);
    b.insert(0, 0, frag(40.0f, surfaceArea, 1.0f, kBlue, kFull, 1), 0);  // the surface first
    std::uint32_t tag = 10;
    for (int layer = 0; layer < 3; ++layer)
      for (int c = 0; c < 8; ++c)
        b.insert(0, 0, piece(10.0f + float(layer) + 0.01f * float(c), 0.1f, 1.0f, glm::vec3(0.5f), MaskBits(0x01010101u) << c, tag++), 0);
    if (wholeWire) b.insert(0, 0, piece(25.0f, 0.9995f, 1.0f, glm::vec3(1.0f), kFull, tag++), 0);
    else b.insert(0, 0, piece(20.0f, 0.1f, 0.5f, kRed, MaskBits(0x01010101u), tag++), 0);
    const glm::vec4 r = b.resolve(0, 0);
    ABufferCounters c;
    b.finish(c);
    culled = c.culled;
    return r;
  };
  for (float surfaceArea : {1.0f, 0.9995f})
    for (bool wholeWire : {true, false})
      for (bool deep : {false, true}) {
        std::uint64_t culled0 = 0, culled1 = 0;
        const glm::vec4 a = run(0.0f, deep, surfaceArea, wholeWire, culled0), b = run(0.01f, deep, surfaceArea, wholeWire, culled1);
        EXPECT_GT(culled1, culled0) << surfaceArea << " " << wholeWire << " " << deep;  // culling did leave it out
        for (int i = 0; i < 4; ++i)
          EXPECT_LE(std::abs(a[i] - b[i]), 0.01f + 1e-6f) << "surface " << surfaceArea << (wholeWire ? ", whole wire" : ", translucent")
                                                            << (deep ? ", deep shares" : "") << ", channel " << i;
      }
}

TEST(TileABuffer, DeepSharesWeighSliversAndTranslucentLinesAsTheUsualRule) {
  // Over the grey surface, one thin fragment alone: a sliver that no sample saw (stand-in bit
  // only, area 0.02), opaque or at half opacity, or a translucent line over two sample columns
  // (area 0.15, opacity 0.5). Each weighs its area (times opacity) as by the usual rule, the
  // surface the rest: a hair's tip between the samples neither vanishes nor turns into a
  // sample's worth of the pixel.
  const Fragment surface = frag(30.0f, 1.0f, 1.0f, glm::vec3(0.5f), kFull, 19);
  Fragment sliver = frag(1.0f, 0.02f, 1.0f, glm::vec3(1.0f, 0.0f, 0.0f), MaskBits(1) << 9, 90);
  sliver.standInBits = sliver.mask;
  Fragment faint = sliver;
  faint.opacity = 0.5f;
  const Fragment line = frag(1.0f, 0.15f, 0.5f, glm::vec3(0.0f, 1.0f, 0.0f), MaskBits(0x03030303u), 91);
  for (const Fragment& thin : {sliver, faint, line}) {
    const std::vector<Fragment> fs{surface, thin};
    const glm::vec4 deep = resolveOne(fs, true), usual = resolveOne(fs, false);
    const float w = thin.opacity * thin.area;
    expectRGBA(deep, glm::vec4(thin.colour * w + glm::vec3(0.5f) * (1.0f - w), 1.0f), 2e-6f, "deep");
    expectRGBA(usual, deep, 2e-6f, "usual");
  }
}

TEST(TileABuffer, DeepSharesLeaveShallowAndUncoveredPixelsAsTheyWere) {
  // One thin fragment over the blue surface, or six: each visible at all its samples and
  // thinner than their share, so both rules give each its exact area and blue the rest.
  for (int columns : {1, 6}) {
    const std::vector<Fragment> shallow = deepPixel(columns);
    const glm::vec4 a = resolveOne(shallow, true), b = resolveOne(shallow, false);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(a[i], b[i], 1e-6f) << columns << " columns, channel " << i;
  }
  // Without the blue one column 7 shows the background: not every sample is covered, and no
  // surface covers the whole pixel, so the same pixel to the bit.
  std::vector<Fragment> open = deepPixel(7);
  open.pop_back();
  for (int c = 0; c < 3; ++c) open.push_back(frag(30.0f + float(c), 0.05f, 1.0f, kGreen, MaskBits(0x01010101u) << c, 50u + std::uint32_t(c)));
  const glm::vec4 c = resolveOne(open, true), d = resolveOne(open, false);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(c[i], d[i]) << "uncovered channel " << i;
}

TEST(TileABuffer, RefusesALayoutItCannotVisitFourSubpixelsAtATime) {
  EXPECT_THROW(TileABuffer(MaskLayout{4, 8}, 64), std::invalid_argument);
  EXPECT_THROW(TileABuffer(MaskLayout{3, 3}, 64), std::invalid_argument);
  EXPECT_NO_THROW(TileABuffer(MaskLayout{8, 8}, 64));
}

}  // namespace
}  // namespace wf

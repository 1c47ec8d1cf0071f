// Review tests of the tile A-buffer: the interplay of solid fragments, merging, the budget tail,
// pruning and occlusion tracking. Expected values follow abuffer.h's resolve rule
//   w = opacity * area * mean_{s in M} T[s],  T[s] *= 1 - opacity * min(1, area * N / k),
// written out here independently (resolveAll) over every fragment offered, with no culling.
#include "abuffer/abuffer.h"

#include <gtest/gtest.h>

#include "abuffer_test_fragments.h"
#include "test_support.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <random>
#include <vector>

namespace wf {
namespace {

using namespace wf::test;

// The resolve rule over all fragments (sorted by zkey, then arrival), in double, no culling,
// no budget, no merging: what the buffer must reproduce when culling is exact.
glm::dvec4 resolveAll(const std::vector<Fragment>& in, const MaskLayout& layout) {
  std::vector<std::pair<int, Fragment>> fs;
  for (size_t i = 0; i < in.size(); ++i) fs.push_back({int(i), in[i]});
  std::stable_sort(fs.begin(), fs.end(), [](const auto& a, const auto& b) { return a.second.zkey < b.second.zkey; });
  const int N = layout.samples();
  std::vector<double> T(size_t(N), 1.0);
  glm::dvec3 rgb(0);
  double alpha = 0;
  for (const auto& [i, f] : fs) {
    const int k = std::popcount(f.mask);
    if (k == 0 || !(f.area > 0)) continue;
    const double hide = double(f.opacity) * std::min(1.0, double(f.area) * N / k);
    double sumT = 0;
    for (int s = 0; s < N; ++s)
      if ((f.mask >> s) & 1) sumT += T[size_t(s)];
    for (int s = 0; s < N; ++s)
      if ((f.mask >> s) & 1) T[size_t(s)] *= 1 - hide;
    const double w = double(f.opacity) * f.area * sumT / k;
    rgb += glm::dvec3(f.colour) * w;
    alpha += w;
  }
  if (alpha > 1) rgb /= alpha, alpha = 1;
  return {rgb, alpha};
}

double maxAbs(const glm::vec4& a, const glm::dvec4& b) {
  double m = 0;
  for (int i = 0; i < 4; ++i) m = std::max(m, std::abs(double(a[i]) - b[i]));
  return m;
}

// ---- pruning at equal depth ------------------------------------------------------------------

TEST(TileABufferReview, BudgetPruneKeepsTheOccludersThemselves) {
  // Epsilon 0, K = 2. Two opaque one-piece fragments (hairs: mayMerge = false) at the same flat
  // depth 5 cover the left and right halves: the pixel is settled, occlusionDepth = 5. A third,
  // translucent fragment in front (z = 4, one sample, area 0.1, opacity 0.5) is over budget.
  // Expected (abuffer.h: "the nearest are kept exactly, farther ones are blended into one
  // tail"): the front one and one half are kept, the other half goes to the tail:
  //   front: 0.5 * 0.1 = 0.05 (T of its sample -> 0.5);
  //   kept half: 0.5 * mean T over its 16 samples (1 or 15.5/16)  ~ 0.48 ... 0.5;
  //   tail (the other half, weight 0.5, opacity 0.5, whole pixel): 0.5 * mean T (~0.25),
  // alpha ~ 0.784 ... 0.792 (without the budget it would be 1).
  // Bug: pushList (abuffer.cpp:361) prunes entries with zmin >= occlusionDepth before evicting;
  // the two halves that *make* that occlusion depth lie exactly at it (flat fragments:
  // orthographic views, pixel-width wires at one depth), so both are dropped and the pixel
  // keeps only the front fragment: alpha 0.05.
  TileABuffer buf(kL, 2, 0.0f);
  buf.reset(1, 1);
  buf.insert(0, 0, frag(5.0f, 0.5f, 1.0f, kRed, kLeftHalf, 1, false), 0);
  buf.insert(0, 0, frag(5.0f, 0.5f, 1.0f, kGreen, kRightHalf, 2, false), 0);
  ASSERT_EQ(buf.occlusionDepth(0, 0), 5.0f);
  buf.insert(0, 0, frag(4.0f, 0.1f, 0.5f, kBlue, 0x1, 3, false), 0);
  const glm::vec4 got = buf.resolve(0, 0);
  EXPECT_NEAR(got.z, 0.05f, 1e-6f);
  EXPECT_GE(got.w, 0.78f) << "the two opaque halves behind the front fragment vanished";
  EXPECT_GE(got.x + got.y, 0.73f);
}

TEST(TileABufferReview, BudgetPruneKeepsAnOccluderAtItsOwnDepthWithEpsilon) {
  // Epsilon 0.1, K = 1: one translucent full layer (opacity 0.95, z = 5, one piece) alone
  // settles the pixel (T = 0.05 <= 0.1), occlusionDepth = 5. A second, nearer fragment (z = 4,
  // full, opacity 0.5) is over budget: the farther one goes to the tail. Expected: 0.5 (front)
  // + 0.5 * 0.95 (tail behind it) = 0.975 alpha. Bug: the layer at z = 5 is pruned as "wholly
  // behind" its own occlusion depth: alpha 0.5, an error of 0.475 against the bound 0.1.
  TileABuffer buf(kL, 1, 0.1f);
  buf.reset(1, 1);
  buf.insert(0, 0, frag(5.0f, 1.0f, 0.95f, kRed, kFull, 1, false), 0);
  ASSERT_EQ(buf.occlusionDepth(0, 0), 5.0f);
  buf.insert(0, 0, frag(4.0f, 1.0f, 0.5f, kBlue, kFull, 2, false), 0);
  const glm::vec4 got = buf.resolve(0, 0);
  EXPECT_NEAR(got.z, 0.5f, 1e-6f);
  EXPECT_NEAR(got.x, 0.475f, 1e-5f);
  EXPECT_NEAR(got.w, 0.975f, 1e-5f);
}

// ---- tail and occlusion ----------------------------------------------------------------------

TEST(TileABufferReview, OcclusionCullingIsExactAtEpsilonZeroForOverBudgetPixels) {
  // Epsilon 0 ("culling is exact"), K = 1. A: opaque left half, key 2, range [1.5, 2] (a range,
  // so that the pruning bug above does not interfere); B: opaque right half at z = 1 (both
  // one-piece, so both count for occlusion: the pixel settles at depth 2).
  // B is nearer, so A goes to the tail. C: opaque, full, z = 3 (a surface behind both).
  // What the budget rule gives without culling: list {B}; tail {A, C}: weight 1.5,
  // transmittance (1 - 0.5) * (1 - 1) = 0 -> a whole-pixel layer of opacity 1 behind B: alpha
  // 0.5 + 1 * mean T (0.5) = 1. The pixel is wholly covered by opaque surfaces: alpha 1.
  // Bug: C is culled on arrival (its zmin 3 >= occlusionDepth 2), but A's hiding of the left
  // half was spread over the whole pixel by the tail (opacity 0.5): alpha 0.75, the background
  // shows through an opaque surface by 0.25.
  TileABuffer buf(kL, 1, 0.0f);
  buf.reset(1, 1);
  Fragment a = frag(2.0f, 0.5f, 1.0f, kRed, kLeftHalf, 1, false);
  a.zmin = 1.5f;
  buf.insert(0, 0, a, 0);
  buf.insert(0, 0, frag(1.0f, 0.5f, 1.0f, kGreen, kRightHalf, 2, false), 0);
  // Once a fragment went to the tail the per-subpixel occlusion no longer holds: the pixel stops
  // occluding (it has no solid fragment), so C is not culled.
  EXPECT_EQ(buf.occlusionDepth(0, 0), INFINITY);
  buf.insert(0, 0, frag(3.0f, 1.0f, 1.0f, kBlue, kFull, 3, false), 0);
  const glm::vec4 got = buf.resolve(0, 0);
  EXPECT_NEAR(got.y, 0.5f, 1e-6f);
  EXPECT_NEAR(got.w, 1.0f, 1e-5f) << "a pixel covered by opaque fragments shows the background";
}

// ---- wire pieces that occlude on arrival ---------------------------------------------------

TEST(TileABufferReview, WirePieceMergedLaterNeverHidesLessThanItWasCountedAt) {
  // Epsilon 0 ("culling is exact"). A wire's piece A (area 0.04 on one subpixel: hide
  // min(1, 0.04 * 32 / 1) = 1) counts for occlusion on arrival and settles subpixel 0. A hair
  // behind it on subpixel 0 (area 0.02, z = 3) is then culled as the rasteriser culls it
  // (maskHidden). The wire's next piece B (area 0.005, subpixel 1) merges into A: by area and
  // bits the merged fragment would hide 0.045 * 32 / 2 = 0.72 of what is behind, and the hair,
  // had it arrived after the merge, would add 0.02 * 0.28. Culling and resolve must agree
  // whatever the arrival order: the merged fragment keeps the hide it was counted at
  // (Fragment::hideFloor), and the pixel is A + B = 0.045 either way.
  auto run = [](bool hairLast) {
    TileABuffer buf(kL, 64, 0.0f);
    buf.reset(1, 1);
    Fragment a = frag(2.0f, 0.04f, 1.0f, kRed, 0x1, 1), b = frag(2.0f, 0.005f, 1.0f, kRed, 0x2, 1);
    a.occludesEarly = b.occludesEarly = true;
    const Fragment hair = frag(3.0f, 0.02f, 1.0f, kBlue, 0x1, 2, false);
    auto offer = [&](const Fragment& f) {
      if (!buf.maskHidden(0, 0, f.mask, 0, f.zmin)) buf.insert(0, 0, f, 0);
    };
    offer(a);
    if (!hairLast) offer(hair);
    offer(b);
    if (hairLast) offer(hair);
    return buf.resolve(0, 0);
  };
  const glm::vec4 first = run(false), last = run(true);
  EXPECT_NEAR(first.w, 0.045f, 1e-6f);
  EXPECT_NEAR(last.w, 0.045f, 1e-6f) << "the hair behind shows through a merge it was culled by";
  EXPECT_EQ(first.z, 0.0f);
  EXPECT_EQ(last.z, 0.0f);
}

// ---- solid / merge interplay ---------------------------------------------------------------------

TEST(TileABufferReview, MergedPiecesBecomeSolidInFrontOfAnExistingSolid) {
  // Solid green at z = 5, then two halves of one mesh (tag 7) at z = 3 merge into a whole
  // opaque fragment, nearer: it replaces the solid (the old one is wholly behind: culled).
  // Expected (0.5, 0, 0.5, 1), no list, occlusionDepth 3.
  TileABuffer buf(kL, 64);
  buf.reset(1, 1);
  buf.insert(0, 0, frag(5.0f, 1.0f, 1.0f, kGreen, kFull, 1), 0);
  buf.insert(0, 0, frag(3.0f, 0.5f, 1.0f, kRed, kLeftHalf, 7), 0);
  buf.insert(0, 0, frag(3.0f, 0.5f, 1.0f, kBlue, kRightHalf, 7), 0);
  const glm::vec4 got = buf.resolve(0, 0);
  EXPECT_NEAR(got.x, 0.5f, 1e-7f);
  EXPECT_NEAR(got.y, 0.0f, 1e-7f);
  EXPECT_NEAR(got.z, 0.5f, 1e-7f);
  EXPECT_NEAR(got.w, 1.0f, 1e-7f);
  EXPECT_EQ(buf.occlusionDepth(0, 0), 3.0f);
  ABufferCounters c;
  buf.finish(c);
  EXPECT_EQ(c.pixelsSolidOnly, 1u);
  EXPECT_EQ(c.merged, 1u);
}

TEST(TileABufferReview, MergedSolidBehindAnInterpenetratingSolidIsKept) {
  // Solid green spans z in [2, 6] (key 4); two halves of mesh 7 span [3, 5] (key 4.5) and merge
  // into a whole opaque fragment that is not nearer but not wholly behind either: it is kept
  // in the list and, by zkey, composited behind green: the pixel is green (0, 1, 0, 1).
  TileABuffer buf(kL, 64);
  buf.reset(1, 1);
  Fragment g = frag(4.0f, 1.0f, 1.0f, kGreen, kFull, 1);
  g.zmin = 2, g.zmax = 6;
  buf.insert(0, 0, g, 0);
  Fragment a = frag(4.5f, 0.5f, 1.0f, kRed, kLeftHalf, 7), b = frag(4.5f, 0.5f, 1.0f, kBlue, kRightHalf, 7);
  a.zmin = b.zmin = 3, a.zmax = b.zmax = 5;
  buf.insert(0, 0, a, 0);
  buf.insert(0, 0, b, 0);
  const glm::vec4 got = buf.resolve(0, 0);
  EXPECT_NEAR(got.y, 1.0f, 1e-7f);
  EXPECT_NEAR(got.w, 1.0f, 1e-7f);
  ABufferCounters c;
  buf.finish(c);
  EXPECT_EQ(c.merged, 1u);
  EXPECT_EQ(c.pixelsWithList, 1u);
}

TEST(TileABufferReview, MergedOpaquePiecesOfAnyAreaSplitBecomeSolid) {
  // Two opaque halves (complementary masks) whose float areas a and 1 - a sum to 1 up to
  // rounding: the merge's area-weighted opacity must stay exactly 1 (else the pixel never
  // becomes solid and never settles). Checked for 2000 splits.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  for (int i = 0; i < 2000; ++i) {
    const float a = U(rng), b = 1.0f - a;
    TileABuffer buf(kL, 64);
    buf.reset(1, 1);
    buf.insert(0, 0, frag(1.0f, a, 1.0f, kRed, kLeftHalf, 7), 0);
    buf.insert(0, 0, frag(1.0f, b, 1.0f, kRed, kRightHalf, 7), 0);
    ASSERT_EQ(buf.occlusionDepth(0, 0), 1.0f) << "split " << a;
  }
}

TEST(TileABufferReview, BudgetWithASolidBehindIsExact) {
  // Solid green at z = 10, then 3 full translucent layers (0.5) at z = 3, 1, 2 with K = 2:
  // one goes to the tail, which is exact for whole-pixel layers: 0.5 + 0.25 + 0.125 of the
  // layers, 0.125 green, alpha 1.
  TileABuffer buf(kL, 2);
  buf.reset(1, 1);
  buf.insert(0, 0, frag(10.0f, 1.0f, 1.0f, kGreen, kFull, 1), 0);
  buf.insert(0, 0, frag(3.0f, 1.0f, 0.5f, kBlue, kFull, 2), 0);
  buf.insert(0, 0, frag(1.0f, 1.0f, 0.5f, kRed, kFull, 3), 0);
  buf.insert(0, 0, frag(2.0f, 1.0f, 0.5f, kRed, kFull, 4), 0);
  const glm::vec4 got = buf.resolve(0, 0);
  EXPECT_NEAR(got.x, 0.75f, 1e-6f);
  EXPECT_NEAR(got.z, 0.125f, 1e-6f);
  EXPECT_NEAR(got.y, 0.125f, 1e-6f);
  EXPECT_NEAR(got.w, 1.0f, 1e-6f);
}

// ---- culling against the no-culling resolve ----------------------------------------------------

// Random one-piece fragments: masks of 1 ... N samples with areas consistent with them (between
// (k - 1) / N and (k + 1) / N), opacities 0.3 ... 1, some whole opaque ones (solids), distinct
// depths, optionally with depth ranges around their keys.
std::vector<Fragment> randomFragments(std::mt19937_64& rng, int n, bool ranges) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<Fragment> out;
  for (int i = 0; i < n; ++i) {
    Fragment f;
    const float z = float(1 + 100 * U(rng));
    f.zkey = z;
    f.zmin = ranges ? z - float(U(rng)) : z;
    f.zmax = ranges ? z + float(U(rng)) : z;
    f.tag = std::uint32_t(100 + i);
    f.mayMerge = false;
    f.colour = glm::vec3(float(U(rng)), float(U(rng)), float(U(rng)));
    if (U(rng) < 0.1) {
      f.mask = kFull, f.area = 1, f.opacity = 1;
    } else {
      MaskBits m = 0;
      const int k = 1 + int(U(rng) * 31);
      while (std::popcount(m) < k) m |= MaskBits(1) << int(U(rng) * 32);
      f.mask = m;
      f.area = float(std::clamp((k + 2 * U(rng) - 1) / 32.0, 0.005, 1.0));
      f.opacity = U(rng) < 0.5 ? 1.0f : float(0.3 + 0.7 * U(rng));
    }
    out.push_back(f);
  }
  return out;
}

TEST(TileABufferReview, EpsilonZeroCullingMatchesTheResolveOfEverything) {
  // With a budget that never overflows and no merging, culling at epsilon 0 drops only what is
  // wholly hidden: the pixel equals the resolve rule applied to every fragment (1e-5), and at
  // epsilon e it differs by at most e (doc: "What is skipped adds at most epsilon").
  std::mt19937_64 rng(17);
  for (int trial = 0; trial < 300; ++trial) {
    const bool ranges = trial % 2;
    const std::vector<Fragment> fs = randomFragments(rng, 4 + trial % 40, ranges);
    const glm::dvec4 want = resolveAll(fs, kL);
    for (float eps : {0.0f, 1e-3f, 1e-2f, 0.1f}) {
      TileABuffer buf(kL, 65535, eps);
      buf.reset(1, 1);
      for (const Fragment& f : fs) buf.insert(0, 0, f, 0);
      const double err = maxAbs(buf.resolve(0, 0), want);
      ASSERT_LE(err, eps + 1e-5) << "trial " << trial << " epsilon " << eps << " fragments " << fs.size();
    }
  }
}

TEST(TileABufferReview, ResetAfterHeavyUseKeepsMemoryBounded) {
  // 20 tiles' worth of 32 x 32 pixels with 100 translucent fragments each under K = 8: the
  // buffer's bytes stay at their first tile's peak (node storage bounded by pixels * K).
  TileABuffer buf(kL, 8);
  std::size_t first = 0;
  for (int t = 0; t < 20; ++t) {
    buf.reset(32, 32);
    for (int i = 0; i < 100; ++i)
      for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; x += 7) buf.insert(x, y, frag(float(1 + (i * 37 + t) % 100), 1.0f, 0.01f, kRed, kFull, std::uint32_t(10 + i), false), 0);
    if (t == 0) first = buf.bytes();
  }
  EXPECT_LE(buf.bytes(), first);
}

}  // namespace
}  // namespace wf

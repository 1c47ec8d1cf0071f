// The memory budget (issue 7: "an image of 16384x16384, refused with a clear message if over the
// memory budget"). A 16384^2 image is never allocated here: the refusals are checked to happen
// before any allocation (the process's peak resident memory does not grow by the image's 4 GiB).
#include "abuffer/abuffer.h"
#include "render/renderer.h"
#include "render/pipeline.h"

#include "render_test_scenes.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <regex>

#include <sys/resource.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <mutex>
#include <set>
#include <thread>
#include <vector>
#include <stdexcept>

namespace wf {
namespace {

constexpr size_t kGiB = size_t(1) << 30;

long peakRss() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return long(u.ru_maxrss) * 1024;
}

Scene tinyScene() {
  Scene s = test::baseScene(64, 64);
  s.surfaces.push_back(test::screenSurface({{{10, 10}, {50, 12}, {30, 55}}}, 5.0, 64, 64));
  return s;
}

// The estimate's image part is the closed form W x H x 16 bytes (float RGBA): at least 4 GiB
// for 16384^2, and the rest (tile buffers, primitives) small for a tiny scene (< 1%).
TEST(RobustMemory, EstimateOfA16384SquareImageIsItsFloatImage) {
  RenderOptions o;
  o.width = o.height = 16384;
  const double image = 16384.0 * 16384.0 * 16.0;
  const double est = double(estimateRenderBytes(tinyScene(), o));
  EXPECT_GE(est, image);
  EXPECT_LT(est, image * 1.01);
}

// Over the budget: problem() names the size, the estimate, the budget and where to change it, in
// one line; render() and renderReference() throw std::length_error with that line before they
// allocate the image (peak RSS grows by far less than the 4 GiB the image would take).
TEST(RobustMemory, A16384SquareImageOverTheBudgetIsRefusedBeforeAllocating) {
  RenderOptions o;
  o.width = o.height = 16384;
  o.memoryBudget = 2 * kGiB;
  const std::string p = o.problem();
  EXPECT_NE(p.find("16384x16384"), std::string::npos) << p;
  EXPECT_TRUE(std::regex_search(p, std::regex("needs about 4(\\.0[0-9])? GiB"))) << p;  // the image, and a little more
  EXPECT_NE(p.find("over the memory budget of 2 GiB"), std::string::npos) << p;
  EXPECT_NE(p.find("memoryBudget"), std::string::npos) << p;
  EXPECT_EQ(p.find('\n'), std::string::npos) << p;
  const long before = peakRss();
  for (bool reference : {false, true}) {
    try {
      const RenderResult r = reference ? renderReference(tinyScene(), o) : render(tinyScene(), o);
      ADD_FAILURE() << "rendered " << r.image.width << "x" << r.image.height << " over the budget";
    } catch (const std::length_error& e) {
      EXPECT_EQ(std::string(e.what()), memoryProblem(tinyScene(), o, reference));
      EXPECT_NE(std::string(e.what()).find("over the memory budget"), std::string::npos);
    }
  }
  EXPECT_LT(peakRss() - before, long(256) << 20);
  // Budget 0: unlimited; a budget that fits: no problem (nothing rendered).
  o.memoryBudget = 0;
  EXPECT_EQ(o.problem(), "");
  o.memoryBudget = 64 * kGiB;
  EXPECT_EQ(o.problem(), "");
}

// The scene's own share: with a budget between the empty scene's estimate and this scene's,
// problem() passes (it knows no scene) and render() refuses. The scene's share grows linearly
// with its primitives (closed form: n triangles cost the same per triangle, once the arrays are
// large enough to be rounded to whole pages and the items past a band's least).
TEST(RobustMemory, SceneSharePrimitivesCountInTheEstimate) {
  RenderOptions o;
  o.width = o.height = 64;
  Scene big = tinyScene();
  TriangleMesh& m = big.surfaces[0].mesh;
  const TriangleMesh one = m;
  for (int k = 0; k < 100000; ++k) m.triangles.push_back(one.triangles[0]);
  const size_t empty = estimateRenderBytes(Scene{}, o), full = estimateRenderBytes(big, o);
  ASSERT_GT(full, empty + 100000 * 100);  // at least 100 bytes per triangle
  Scene big2 = big;
  for (int k = 0; k < 100000; ++k) big2.surfaces[0].mesh.triangles.push_back(one.triangles[0]);
  Scene big3 = big2;
  for (int k = 0; k < 100000; ++k) big3.surfaces[0].mesh.triangles.push_back(one.triangles[0]);
  const size_t full2 = estimateRenderBytes(big2, o);
  const double perTriangle1 = double(full2 - full) / 100000, perTriangle2 = double(estimateRenderBytes(big3, o) - full2) / 100000;
  EXPECT_NEAR(perTriangle1, perTriangle2, 1.0);
  o.memoryBudget = (empty + full) / 2;
  EXPECT_EQ(o.problem(), "");
  EXPECT_THROW(render(big, o), std::length_error);
  EXPECT_NO_THROW(render(tinyScene(), o));
}

// A wire drawn with dashed hidden lines makes prepareScene keep a dash pattern (two floats) for every
// segment of the scene (PreparedScene::dashPattern): the estimate counts them, per segment of every
// wire (it did not before), and nothing for a scene without a dashed wire.
TEST(RobustMemory, DashPatternsCountInTheEstimate) {
  RenderOptions o;
  o.width = o.height = 64;
  o.threads = 1;  // one tile buffer
  o.tileSize = 32;  // of 32 x 32 pixels
  Scene plain = tinyScene();
  SceneWire edges, hairs;
  for (int k = 0; k < 5000; ++k) edges.lines.add({glm::dvec3(0.01 * k, 0.0, -5.0), glm::dvec3(0.01 * k, 1.0, -5.0)});
  for (int k = 0; k < 3000; ++k) hairs.lines.add({glm::dvec3(0.0, 0.01 * k, -5.0), glm::dvec3(1.0, 0.01 * k, -5.0)});
  plain.wires = {edges, hairs};
  // Ghosted and dashed hidden lines both keep the tile's x-ray fragments; dashes keep patterns too.
  Scene ghost = plain, dashed = plain;
  ghost.wires[0].hidden.mode = HiddenLines::Mode::Ghost;
  dashed.wires[0].hidden.mode = HiddenLines::Mode::Dashed;
  const size_t xray = size_t(32) * 32 * TileABuffer::xrayBytesPerPixel();
  EXPECT_EQ(estimateRenderBytes(ghost, o) - estimateRenderBytes(plain, o), xray);
  EXPECT_EQ(estimateRenderBytes(dashed, o) - estimateRenderBytes(ghost, o), 8000 * sizeof(glm::vec2));
}

// Within the budget a large image renders, and the estimate is honest: within a factor 2 of what
// the render reports it held (stats.peakBytes) plus its image (W x H x 16 bytes). 4096^2 of a
// tiny scene (256 MiB image), budget 1 GiB.
TEST(RobustMemory, A4096SquareImageWithinTheBudgetRendersAndTheEstimateIsWithin2x) {
  RenderOptions o;
  o.width = o.height = 4096;
  o.memoryBudget = kGiB;
  Scene s = tinyScene();
  s.camera->orthoHeight = 64;  // the triangle fills part of the image
  ASSERT_EQ(o.problem(), "");
  const RenderResult r = render(s, o);
  ASSERT_EQ(r.image.width, 4096);
  const double actual = double(r.stats.peakBytes) + 4096.0 * 4096.0 * 16.0;
  const double est = double(estimateRenderBytes(s, o));
  EXPECT_LT(est, 2 * actual);
  EXPECT_GT(est, actual / 2);
  EXPECT_GT(test::sumAlpha(r.image), 1e5);  // a real picture: the triangle covers ~0.25 of it
}

// The default budget: half of the physical memory (sysconf), documented in renderer.h.
TEST(RobustMemory, DefaultBudgetIsHalfThePhysicalMemory) {
  const double phys = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE));
  EXPECT_NEAR(double(RenderOptions{}.memoryBudget), phys / 2, double(sysconf(_SC_PAGE_SIZE)));
}

// The large arrays a render frees are kept for the next (core/large_memory.h, releaseRenderMemory):
// 60,000 segments need 4.8 MB of SegmentPrim (80 bytes each), over the 1 MiB of a large block.
// Held at most an eighth of the memory (1 GiB); a second frame reuses the blocks and draws the
// same image bit for bit; releaseRenderMemory empties the cache.
TEST(RobustMemory, LargeBlocksAreKeptBoundedReusedAndReleased) {
  constexpr int W = 256, H = 256;
  Scene s = test::baseScene(W, H);
  std::vector<std::vector<test::V2>> lines;
  for (int i = 0; i < 60000; ++i) {
    const double y = 8.0 + (i % 240), x = 8.0 + (i / 240) % 240;
    lines.push_back({{x, y}, {x + 3.0, y + 1.0}});
  }
  s.wires.push_back(test::plainWire(lines, 1.0, 5.0, W, H));
  const RenderOptions o = test::smallOptions(W, H);
  releaseRenderMemory();
  ASSERT_EQ(renderMemoryHeld(), 0u);
  const RenderResult a = render(s, o);
  const size_t held = renderMemoryHeld();
  const double phys = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE));
  EXPECT_GE(held, size_t(4) << 20);  // the segments' arrays, at least
  EXPECT_LE(double(held), std::min(phys / 8, double(kGiB)));
  const RenderResult b = render(s, o);
  EXPECT_EQ(renderMemoryHeld(), held);  // the same blocks, taken and given back
  EXPECT_EQ(test::maxDiff(a.image, b.image), 0.0);
  releaseRenderMemory();
  EXPECT_EQ(renderMemoryHeld(), 0u);
}

}  // namespace
}  // namespace wf

namespace wf {
namespace {

// Options out of range reach render() and renderReference() only from callers that skip
// RenderOptions::problem(): both refuse them with that line (std::invalid_argument) instead of
// running on, e.g. a 5x5 mask would index past the mask tables; a 0-pixel image, 0 tile size.
TEST(RobustOptions, RenderersRefuseOptionsOutOfRange) {
  const auto bad = [](auto&& edit) {
    RenderOptions o = test::smallOptions(64, 64);
    edit(o);
    return o;
  };
  const RenderOptions cases[] = {
      bad([](RenderOptions& o) { o.width = 0; }),       bad([](RenderOptions& o) { o.mask = {5, 5}; }),
      bad([](RenderOptions& o) { o.budget = 0; }),      bad([](RenderOptions& o) { o.tileSize = 0; }),
      bad([](RenderOptions& o) { o.threads = -1; }),    bad([](RenderOptions& o) { o.referenceSamples = 0; }),
      bad([](RenderOptions& o) { o.occlusionEpsilon = std::nan(""); }),
      bad([](RenderOptions& o) { o.tileSize = TileBins::kMaxTileSize + 1; }),  // bin items keep corners in bytes
  };
  for (const RenderOptions& o : cases) {
    ASSERT_FALSE(o.problem().empty());
    try {
      (void)render(tinyScene(), o);
      ADD_FAILURE() << "render() ran with: " << o.problem();
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(o.problem()), std::string::npos) << e.what();
    }
    EXPECT_THROW((void)renderReference(tinyScene(), o), std::invalid_argument) << o.problem();
  }
  EXPECT_NO_THROW((void)render(tinyScene(), test::smallOptions(64, 64)));
}

// A cached block serving a smaller request (more than half its size) is counted at its real
// size when it comes back: 16 MiB freed, 10 MiB asked (the same block), 10 MiB freed: 16 MiB held,
// not 10 (otherwise each reuse could shrink the count and the bound would hold only on paper).
// A request of half a block's size or less gets a fresh block.
TEST(RobustMemory, ACachedBlockIsCountedAtItsRealSize) {
  constexpr size_t MiB = size_t(1) << 20;
  releaseRenderMemory();
  void* a = allocateLarge(16 * MiB);
  freeLarge(a, 16 * MiB);
  ASSERT_EQ(renderMemoryHeld(), 16 * MiB);
  void* b = allocateLarge(10 * MiB);
  EXPECT_EQ(b, a);  // reused
  EXPECT_EQ(renderMemoryHeld(), 0u);
  freeLarge(b, 10 * MiB);
  EXPECT_EQ(renderMemoryHeld(), 16 * MiB);
  void* c = allocateLarge(8 * MiB);  // half: not this block
  EXPECT_NE(c, a);
  EXPECT_EQ(renderMemoryHeld(), 16 * MiB);
  freeLarge(c, 8 * MiB);
  EXPECT_EQ(renderMemoryHeld(), 24 * MiB);
  releaseRenderMemory();
  EXPECT_EQ(renderMemoryHeld(), 0u);
}

// Many threads taking and giving back large blocks of mixed sizes at once (as TBB's workers do
// in set-up and binning): every block handed out is distinct and writable for its whole size
// (AddressSanitizer checks the writes in CI's sanitizer pass), the cache never holds more than
// its bound, and after a release it holds nothing.
TEST(RobustMemory, LargeBlocksFromManyThreadsAtOnce) {
  constexpr size_t MiB = size_t(1) << 20;
  releaseRenderMemory();
  const double phys = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE));
  const size_t limit = size_t(std::min(phys / 8, double(kGiB)));
  std::atomic<bool> overBound{false}, badBlock{false}, shared{false};
  std::mutex liveMutex;
  std::set<void*> live;  // blocks handed out and not yet given back
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (int k = 0; k < 40; ++k) {
        const size_t bytes = (4 + size_t((t * 7 + k * 3) % 9)) * MiB + size_t(k) * 4096;
        auto* p = static_cast<unsigned char*>(allocateLarge(bytes));
        {
          std::lock_guard<std::mutex> lock(liveMutex);
          if (!live.insert(p).second) shared = true;
        }
        std::memset(p, t + 1, bytes);
        if (p[0] != t + 1 || p[bytes - 1] != t + 1) badBlock = true;
        if (renderMemoryHeld() > limit) overBound = true;
        {
          std::lock_guard<std::mutex> lock(liveMutex);
          live.erase(p);
        }
        freeLarge(p, bytes);
      }
    });
  for (std::thread& th : threads) th.join();
  EXPECT_FALSE(shared.load());
  EXPECT_FALSE(badBlock.load());
  EXPECT_FALSE(overBound.load());
  EXPECT_LE(renderMemoryHeld(), limit);
  releaseRenderMemory();
  EXPECT_EQ(renderMemoryHeld(), 0u);
}

}  // namespace
}  // namespace wf

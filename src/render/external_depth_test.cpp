// Tests of RenderOptions::opaqueDepth, the external opaque depth that vtkWireFurRenderPass fills
// from the OpenGL depth buffer: a fragment counts only if its depth at its shading point is
// nearer than the opaque depth at its pixel. Scenes of render_test_scenes.h (orthographic, one
// pixel per world unit, plain wires of colour 1 on a transparent background: alpha = coverage).
#include "render/renderer.h"

#include <gtest/gtest.h>

#include "render_test_scenes.h"

#include <cmath>
#include <limits>
#include <vector>

namespace wf {
namespace {

using namespace wf::test;

constexpr int W = 64, H = 48;

// A 3-pixel wide horizontal wire across the image at view depth 10.
Scene wireScene() {
  Scene s = baseScene(W, H);
  s.wires.push_back(plainWire({{V2(4.3, 23.6), V2(59.7, 23.6)}}, 3.0, 10.0, W, H));
  return s;
}

TEST(ExternalDepth, WireBehindAnOpaquePlaneDisappears) {
  const Scene s = wireScene();
  RenderOptions o = smallOptions(W, H);
  const RenderResult free = render(s, o);
  ASSERT_GT(sumAlpha(free.image), 100.0);  // 55 x 3 pixels of coverage without the plane
  const std::vector<float> plane(size_t(W) * H, 5.0f);  // opaque at depth 5, in front of the wire
  o.opaqueDepth = &plane;
  ASSERT_EQ(o.problem(), "");
  const RenderResult hidden = render(s, o);
  EXPECT_EQ(sumAlpha(hidden.image), 0.0);  // every fragment culled: exactly nothing left
  EXPECT_GT(hidden.stats.abuffer.culled + hidden.stats.primitivesOccluded, 0u);
}

TEST(ExternalDepth, WireInFrontOfAnOpaquePlaneStaysBitIdentical) {
  const Scene s = wireScene();
  RenderOptions o = smallOptions(W, H);
  const RenderResult free = render(s, o);
  const std::vector<float> plane(size_t(W) * H, 15.0f);  // behind the wire (depth 10)
  o.opaqueDepth = &plane;
  const RenderResult front = render(s, o);
  EXPECT_EQ(maxDiff(front.image, free.image), 0.0);
}

TEST(ExternalDepth, PerPixelDepthHidesOnlyWhereItIsNearer) {
  // Left half opaque at depth 5 (hides), right half empty (+inf) and NaN (treated as empty).
  const Scene s = wireScene();
  RenderOptions o = smallOptions(W, H);
  const RenderResult free = render(s, o);
  std::vector<float> depth(size_t(W) * H, std::numeric_limits<float>::infinity());
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      if (x < W / 2) depth[size_t(y) * W + x] = 5.0f;
      else if (x % 3 == 0) depth[size_t(y) * W + x] = std::numeric_limits<float>::quiet_NaN();
    }
  o.opaqueDepth = &depth;
  const RenderResult half = render(s, o);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const glm::vec4 p = half.image.at(x, y), q = free.image.at(x, y);
      if (x < W / 2) EXPECT_EQ(p.w, 0.0f) << x << "," << y;
      else EXPECT_EQ(p, q) << x << "," << y;
    }
}

TEST(ExternalDepth, WrongSizeIsAProblem) {
  RenderOptions o = smallOptions(W, H);
  const std::vector<float> depth(10, 1.0f);
  o.opaqueDepth = &depth;
  EXPECT_NE(o.problem(), "");
}

}  // namespace
}  // namespace wf

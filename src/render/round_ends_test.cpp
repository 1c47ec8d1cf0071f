// Round wire ends (SceneWire::roundEnds): a half disc at each free end of a polyline, the outline
// of a round cylinder with spherical caps (the ray-cast peer's round linear curves). Checked
// against exact areas and against a point-sampled stadium.
#include "render/renderer.h"

#include "render_test_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace wf {
namespace {

using namespace wf::test;

// Fraction of pixel (px, py) inside the stadium of segment p0-p1 of radius r (the set of points
// within r of the segment), by 64 x 64 point samples: the independent reference.
double stadiumCoverage(const V2& p0, const V2& p1, double r, int px, int py) {
  const V2 d = p1 - p0;
  const double dd = glm::dot(d, d);
  int in = 0;
  constexpr int n = 64;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const V2 q(px + (i + 0.5) / n, py + (j + 0.5) / n);
      const double t = std::clamp(glm::dot(q - p0, d) / dd, 0.0, 1.0);
      in += glm::length(q - (p0 + t * d)) <= r;
    }
  return double(in) / (n * n);
}

TEST(RoundEnds, SegmentCoversItsStadium) {
  // Area: w L + pi (w/2)^2 exactly (the caps' polygons are built with the half disc's area),
  // 1e-3 relative as the square-ended test. Per pixel within 0.06 of the true stadium: each cap
  // chord stays within 0.05 px of the circle, and the point-sampled reference adds < 0.01.
  const int W = 96, H = 96;
  const double L = 40;
  for (double width : {0.2, 1.5, 3.0, 9.0})
    for (double deg : {0.0, 27.0, 90.0, 211.0}) {
      const double a = deg * std::numbers::pi / 180;
      const V2 c(48.3, 47.6), d(std::cos(a), std::sin(a));
      const V2 p0 = c - 0.5 * L * d, p1 = c + 0.5 * L * d;
      Scene scene = baseScene(W, H);
      SceneWire w = plainWire({{p0, p1}}, width, 10.0, W, H);
      w.roundEnds = true;
      scene.wires.push_back(w);
      const RenderResult r = render(scene, smallOptions(W, H));
      const double want = width * L + std::numbers::pi * width * width / 4;
      EXPECT_NEAR(sumAlpha(r.image), want, 1e-3 * want) << "width " << width << " angle " << deg;
      double worst = 0;
      const V2 dd = p1 - p0;
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
          // Pixels whose centre is farther than r + 1 from the segment are outside: alpha 0.
          const V2 q(x + 0.5, y + 0.5);
          const double t = std::clamp(glm::dot(q - p0, dd) / glm::dot(dd, dd), 0.0, 1.0);
          const double ref = glm::length(q - (p0 + t * dd)) > width / 2 + 1 ? 0.0 : stadiumCoverage(p0, p1, width / 2, x, y);
          worst = std::max(worst, std::abs(double(r.image.at(x, y).w) - ref));
        }
      EXPECT_LE(worst, 0.06) << "width " << width << " angle " << deg;
    }
}

TEST(RoundEnds, OnlyTheFreeEndsOfAPolylineAreRound) {
  // A 60-degree bend: the mitred joint is unchanged (thickness (L1 + L2), see
  // Render.PolylineJointIsAMitreWithoutOverlap), and the two free ends add one disc, pi r^2.
  const int W = 128, H = 128;
  const double thickness = 6, r = thickness / 2, L1 = 40, L2 = 35;
  const double a1 = 0.3, a2 = a1 + std::numbers::pi / 3;
  const V2 d1(std::cos(a1), std::sin(a1)), d2(std::cos(a2), std::sin(a2));
  const V2 B(64.2, 63.7), A = B - L1 * d1, C = B + L2 * d2;
  Scene scene = baseScene(W, H);
  SceneWire w = plainWire({{A, B, C}}, thickness, 10.0, W, H);
  w.roundEnds = true;
  scene.wires.push_back(w);
  const RenderResult rr = render(scene, smallOptions(W, H));
  const double want = thickness * (L1 + L2) + std::numbers::pi * r * r;
  EXPECT_NEAR(sumAlpha(rr.image), want, 1e-3 * want);
  // Near the joint the round and the square wire are the same picture.
  scene.wires.back().roundEnds = false;
  const RenderResult rs = render(scene, smallOptions(W, H));
  for (int y = int(B.y) - 6; y <= int(B.y) + 6; ++y)
    for (int x = int(B.x) - 6; x <= int(B.x) + 6; ++x) EXPECT_EQ(rr.image.at(x, y).w, rs.image.at(x, y).w);
}

TEST(RoundEnds, AClosedLoopHasNoFreeEnd) {
  // A closed polyline (last point = first) has no free end: bit-identical to square ends.
  const int W = 96, H = 96;
  Scene scene = baseScene(W, H);
  SceneWire w = plainWire({{V2(20.5, 20.5), V2(70.5, 22.5), V2(60.5, 70.5), V2(20.5, 20.5)}}, 4.0, 10.0, W, H);
  w.roundEnds = true;
  scene.wires.push_back(w);
  const RenderResult round = render(scene, smallOptions(W, H));
  scene.wires.back().roundEnds = false;
  const RenderResult square = render(scene, smallOptions(W, H));
  for (size_t i = 0; i < round.image.pixels.size(); ++i) ASSERT_EQ(round.image.pixels[i], square.image.pixels[i]) << i;
}

TEST(RoundEnds, ReferenceRendererDrawsTheSameOutline) {
  // The brute-force reference uses the same screen polygons: 32 x 32 samples agree with the
  // A-buffer's exact areas within 1/32 + 1e-3 per pixel.
  const int W = 64, H = 64;
  Scene scene = baseScene(W, H);
  SceneWire w = plainWire({{V2(10.2, 30.7), V2(50.9, 36.1)}}, 5.0, 10.0, W, H);
  w.roundEnds = true;
  scene.wires.push_back(w);
  RenderOptions o = smallOptions(W, H);
  o.referenceSamples = 32;
  const RenderResult a = render(scene, o), ref = renderReference(scene, o);
  for (size_t i = 0; i < a.image.pixels.size(); ++i)
    ASSERT_NEAR(a.image.pixels[i].w, ref.image.pixels[i].w, 1.0 / 32 + 1e-3) << i;
}

}  // namespace
}  // namespace wf

// Tests of the reflectance sphere (Williams 1983, paper §2.1): the Phong sphere against direct
// Phong shading, the chrome ball against the environment it reflects, and degenerate lookups.
#include "shading/reflectance_sphere.h"

#include <gtest/gtest.h>

#include "test_support.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

namespace wf {
namespace {

using namespace wf::test;



TEST(ReflectanceSphere, NormalAt) {
  // Inside the disc: (x, y, sqrt(1 - x^2 - y^2)); outside: moved onto the rim (z = 0).
  const glm::dvec3 a = ReflectanceSphere::normalAt(0.6, 0.0);
  EXPECT_NEAR(a.z, 0.8, 1e-15);
  const glm::dvec3 b = ReflectanceSphere::normalAt(3.0, 4.0);
  EXPECT_NEAR(b.x, 0.6, 1e-15);
  EXPECT_NEAR(b.y, 0.8, 1e-15);
  EXPECT_EQ(b.z, 0.0);
  EXPECT_EQ(ReflectanceSphere::normalAt(0.0, 0.0), glm::dvec3(0, 0, 1));
}

// ---- 5. Phong sphere vs direct Phong --------------------------------------------------------

TEST(ReflectanceSphere, PhongLookupMatchesDirectPhongInsideRadius095) {
  // Bilinear interpolation on a 512^2 grid (spacing h = 2/511): where I is smooth the error is
  // ~h^2/8 times its second derivative across the disc, which grows towards the rim like 1/nz^3
  // (nz = 0.31 at r = 0.95) and with the exponent; plus float storage (~1e-7). Phong itself is
  // discontinuous where a light's terminator N.l = 0 crosses a texel and the lobe is not zero
  // there (R = -l, so R.V = -l.V > 0 for a light behind the subject, like the studio rig's rim
  // light): such probes are checked against the jump height ks L (-l.V)^n instead. Bounds:
  // measured (printed) with ~1.5x margin. docs/shading.md: up to 7e-2 at the rim itself
  // (r -> 1), hence r <= 0.95.
  const LightRig rig = LightRig::studioRig(7);
  const LightRig crig = rig.canonical();
  const int res = 512;
  const double h = 2.0 / (res - 1);
  // Measured: n=20 1.72e-4 (r < 0.5: 6.7e-5), n=80 1.72e-4 (r < 0.5: 9.8e-5).
  struct {
    double n, bound, innerBound;
  } cases[] = {{20.0, 2.6e-4, 1.5e-4}, {80.0, 2.6e-4, 1.5e-4}};
  for (const auto& c : cases) {
    PhongMaterial m;
    m.diffuse = glm::dvec3(0.6, 0.5, 0.4);
    m.specular = glm::dvec3(0.4, 0.5, 0.6);
    m.exponent = c.n;
    // Williams' (nx, ny) table: the cell arithmetic below is its layout.
    const ReflectanceSphere sphere = ReflectanceSphere::phong(res, m, rig, ReflectanceSphere::Indexing::Williams);
    ASSERT_EQ(sphere.resolution(), res);
    std::mt19937 rng(4242);
    std::uniform_real_distribution<double> U(-0.95, 0.95);
    double maxErr = 0.0, maxErrInner = 0.0, sum = 0.0, maxJumpErr = 0.0;
    int count = 0, nearTerminator = 0;
    while (count < 20000) {
      const double x = U(rng), y = U(rng);
      if (x * x + y * y > 0.95 * 0.95) continue;
      const glm::dvec3 N = ReflectanceSphere::normalAt(x, y);
      const double e = maxAbsDiff(glm::dvec3(sphere.lookup(N)), phongRadiance(N, {0, 0, 1}, m, crig));
      ++count;
      // The bilinear cell's four nodes; does any light's terminator pass between them?
      const int i = std::min(int((x + 1.0) / h), res - 2), j = std::min(int((y + 1.0) / h), res - 2);
      double jump = 0.0;
      for (const DirectionalLight& l : crig.lights) {
        int lit = 0;
        for (int dj = 0; dj < 2; ++dj)
          for (int di = 0; di < 2; ++di)
            lit += glm::dot(ReflectanceSphere::normalAt(-1 + (i + di) * h, -1 + (j + dj) * h), l.direction) > 0;
        if (lit != 0 && lit != 4) {
          const double q = l.direction.z;
          const glm::dvec3 dl = l.intensity * m.specular * (q < 0 ? std::pow(-q, c.n) : 0.0);
          jump += std::max({dl.x, dl.y, dl.z});
        }
      }
      if (jump > 0.0) {
        ++nearTerminator;
        EXPECT_LT(e, jump + c.bound) << x << "," << y;
        maxJumpErr = std::max(maxJumpErr, e);
        continue;
      }
      maxErr = std::max(maxErr, e);
      if (x * x + y * y < 0.5 * 0.5) maxErrInner = std::max(maxErrInner, e);
      sum += e;
    }
    std::printf("[ measured ] phong sphere 512^2 n=%g: max |lookup - phongRadiance| r<=0.95 %.4g "
                "(r<0.5: %.4g), mean %.3g; bound %.3g; %d probes in a texel crossed by a "
                "highlight's terminator: max %.4g\n",
                c.n, maxErr, maxErrInner, sum / (count - nearTerminator), c.bound, nearTerminator, maxJumpErr);
    EXPECT_LT(maxErr, c.bound);
    // Near the centre nz changes slowly: smaller error.
    EXPECT_LT(maxErrInner, c.innerBound);
  }
}

TEST(ReflectanceSphere, TexelsAreTheShaderAtTheirNodes) {
  // A node (i, j) holds shader(normalAtTable(-1 + i h, -1 + j h)) exactly (float rounding), and
  // for Williams' table normalAtTable is normalAt.
  PhongMaterial m;
  const LightRig rig = LightRig::studioRig(3).canonical();
  const int n = 65;
  const double h = 2.0 / (n - 1);
  for (auto ix : {ReflectanceSphere::Indexing::Williams, ReflectanceSphere::Indexing::Warped}) {
    const ReflectanceSphere s = ReflectanceSphere::phong(n, m, rig, ix);
    for (int j = 0; j < n; j += 4)
      for (int i = 0; i < n; i += 4) {
        const glm::dvec3 N = s.normalAtTable(-1 + i * h, -1 + j * h);
        if (ix == ReflectanceSphere::Indexing::Williams) {
          EXPECT_EQ(N, ReflectanceSphere::normalAt(-1 + i * h, -1 + j * h));
        }
        const glm::dvec3 want = phongRadiance(N, {0, 0, 1}, m, rig);
        EXPECT_LT(maxAbsDiff(glm::dvec3(s.texels()[size_t(j) * n + i]), want), 1e-6 * (1 + want.x));
      }
  }
}

TEST(ReflectanceSphere, WarpedTableInvertsItsLookup) {
  // normalAtTable and the lookup's (nx, ny) / (r + nz) are inverses: a normal built from a table
  // position maps back to it (checked through a linear shader, which bilinear lookup reproduces
  // exactly at nodes and to float rounding between them).
  const ReflectanceSphere s = ReflectanceSphere::build(
      33, [](const glm::dvec3& n) { return n; }, 1, ReflectanceSphere::Indexing::Warped);
  for (double X : {-0.9, -0.3, 0.0, 0.45, 0.99})
    for (double Y : {-0.6, 0.0, 0.1}) {
      if (X * X + Y * Y >= 1.0) continue;
      const glm::dvec3 N = s.normalAtTable(X, Y);
      EXPECT_NEAR(glm::length(N), 1.0, 1e-14);
      const double d = std::hypot(N.x, N.y) + N.z;
      EXPECT_NEAR(N.x / d, X, 1e-14);
      EXPECT_NEAR(N.y / d, Y, 1e-14);
    }
}

TEST(ReflectanceSphere, WarpedTableIsAccurateToTheRim) {
  // Front lights only (studioRig(3): every light has l.z > 0), so Phong is continuous over the
  // whole hemisphere and a max error means something. Williams' table loses the rim: there
  // nz = sqrt(1 - r^2) moves by sqrt(2 h) over the last texel h. The warped table is linear in
  // angle at the rim. Normals uniform over the disc r < 1 (screen area of a sphere), 40000 of
  // them, plus 2000 in the outer ring 0.99 < r < 1. Bounds: measured (printed) with margin.
  const LightRig rig = LightRig::studioRig(3).canonical();
  PhongMaterial m;
  m.exponent = 80.0;
  const int res = 512;
  double maxErr[2] = {0, 0};
  for (auto ix : {ReflectanceSphere::Indexing::Williams, ReflectanceSphere::Indexing::Warped}) {
    const ReflectanceSphere s = ReflectanceSphere::phong(res, m, rig, ix);
    std::mt19937 rng(77);
    std::uniform_real_distribution<double> U(-1.0, 1.0), Ring(0.99, 1.0), Phi(0.0, 6.283185307179586);
    double mx = 0.0;
    for (int k = 0; k < 42000; ++k) {
      double x, y;
      if (k < 40000) {
        do {
          x = U(rng);
          y = U(rng);
        } while (x * x + y * y >= 1.0);
      } else {
        const double r = Ring(rng), p = Phi(rng);
        x = r * std::cos(p);
        y = r * std::sin(p);
      }
      const glm::dvec3 N = ReflectanceSphere::normalAt(x, y);
      mx = std::max(mx, maxAbsDiff(glm::dvec3(s.lookup(N)), phongRadiance(N, {0, 0, 1}, m, rig)));
    }
    maxErr[ix == ReflectanceSphere::Indexing::Warped] = mx;
  }
  std::printf("[ measured ] Phong n=80 512^2, whole disc: Williams max %.3g, warped max %.3g\n", maxErr[0],
              maxErr[1]);
  EXPECT_LT(maxErr[1], 5e-4);  // measured 3.6e-4 (Williams: 6.5e-3)
  EXPECT_GT(maxErr[0], 5.0 * maxErr[1]);
}

TEST(ReflectanceSphere, LookupIgnoresNormalLength) {
  PhongMaterial m;
  const ReflectanceSphere s = ReflectanceSphere::phong(128, m, LightRig::studioRig(7));
  for (const glm::dvec3& N : {glm::dvec3(0.3, -0.2, 0.9), glm::dvec3(-0.7, 0.1, 0.2)}) {
    EXPECT_EQ(s.lookup(N), s.lookup(7.5 * N));
    const glm::dvec3 u = glm::normalize(N);
    EXPECT_EQ(s.lookup(u), s.lookupXY(u.x, u.y));
  }
}

// ---- chrome ball ----------------------------------------------------------------------------

TEST(ReflectanceSphere, ChromeCentreTexelReflectsStraightBack) {
  // The centre normal (0,0,1) mirrors V = (0,0,1) into R = (0,0,1) (behind the viewer).
  // Odd resolution 513: node 256 is exactly x = y = 0. With supersample 1 the texel is exactly
  // reflectance * env.lookup(R) (float products: 1e-6 relative).
  const EnvironmentMap env = EnvironmentMap::mountainScene(512);
  const glm::dvec3 refl(0.9, 0.8, 0.7);
  const ReflectanceSphere s = ReflectanceSphere::chrome(513, env, refl, 1);
  const glm::vec3 centre = s.texels()[size_t(256) * 513 + 256];
  const glm::dvec3 want = refl * glm::dvec3(env.lookup({0, 0, 1}));
  EXPECT_LT(maxAbsDiff(glm::dvec3(centre), want), 1e-6 * std::max(1.0, want.x));
  // And lookup of the facing normal reads exactly that node.
  EXPECT_EQ(s.lookup({0, 0, 1}), centre);
  EXPECT_EQ(s.lookupXY(0.0, 0.0), centre);

  // Off-centre node: normal N at node (300, 200) reflects V into R = 2 (N.V) N - V.
  const double h = 2.0 / 512;
  const glm::dvec3 N = s.normalAtTable(-1 + 300 * h, -1 + 200 * h);
  const glm::dvec3 R = 2.0 * N.z * N - glm::dvec3(0, 0, 1);
  const glm::dvec3 want2 = refl * glm::dvec3(env.lookup(R));
  EXPECT_LT(maxAbsDiff(glm::dvec3(s.texels()[size_t(200) * 513 + 300]), want2), 1e-6 * std::max(1.0, want2.x));
}

TEST(ReflectanceSphere, ChromeSupersampledCentreIsAMeanOfNearbyReflections) {
  // With the default 4x4 supersampling the centre texel is the mean of env values reflected by
  // normals within half a texel of the centre: it must lie within the range of env.lookup over
  // that patch (per channel; probed on a 9x9 grid, widened by 1e-6 for float rounding).
  const EnvironmentMap env = EnvironmentMap::mountainScene(1024);
  const ReflectanceSphere s = ReflectanceSphere::chrome(513, env, glm::dvec3(1.0));
  const glm::vec3 centre = s.texels()[size_t(256) * 513 + 256];
  const double h = 2.0 / 512;
  glm::dvec3 lo(1e30), hi(-1e30);
  for (int b = -4; b <= 4; ++b)
    for (int a = -4; a <= 4; ++a) {
      const glm::dvec3 N = ReflectanceSphere::normalAt(a * h / 8, b * h / 8);
      const glm::dvec3 e(env.lookup(2.0 * N.z * N - glm::dvec3(0, 0, 1)));
      lo = glm::min(lo, e);
      hi = glm::max(hi, e);
    }
  for (int k = 0; k < 3; ++k) {
    EXPECT_GE(centre[k], lo[k] - 1e-6) << k;
    EXPECT_LE(centre[k], hi[k] + 1e-6) << k;
  }
}

// ---- 6. extreme inputs ----------------------------------------------------------------------

TEST(ReflectanceSphereExtremes, DegenerateNormalsReadTheCentre) {
  const double nan = std::nan(""), inf = INFINITY;
  PhongMaterial m;
  const ReflectanceSphere s = ReflectanceSphere::phong(64, m, LightRig::studioRig(7));
  const glm::vec3 centre = s.lookupXY(0.0, 0.0);
  // Header: a zero or non-finite normal reads the centre (a normal facing the viewer).
  for (const glm::dvec3& N : {glm::dvec3(0.0), glm::dvec3(nan, 0, 1), glm::dvec3(0, inf, 0),
                              glm::dvec3(-inf, inf, nan), glm::dvec3(1e-310, 0, 0),
                              glm::dvec3(1e300, 1e300, 0)})
    EXPECT_EQ(s.lookup(N), centre);
  EXPECT_EQ(s.lookupXY(nan, 0.3), centre);
  EXPECT_EQ(s.lookupXY(0.2, inf), centre);
  // Any other input is finite and non-negative: rim, beyond the rim, facing away.
  for (const glm::dvec3& N : {glm::dvec3(1, 0, 0), glm::dvec3(-1, -1, 0), glm::dvec3(0, 0, -1),
                              glm::dvec3(1e-12, 1, 1e-12), glm::dvec3(0.3, 0.3, -0.9)}) {
    const glm::vec3 c = s.lookup(N);
    EXPECT_TRUE(finite3(c) && c.x >= 0 && c.y >= 0 && c.z >= 0);
  }
  for (double x : {-5.0, -1.0, 1.0, 5.0, 1e300})
    for (double y : {-1e300, -1.0, 0.0, 1.0}) {
      const glm::vec3 c = s.lookupXY(x, y);
      EXPECT_TRUE(finite3(c) && c.x >= 0 && c.y >= 0 && c.z >= 0) << x << "," << y;
    }
  // The exact corner of the table reads the corner texel.
  EXPECT_EQ(s.lookupTable(1.0, 1.0), s.texels().back());
  EXPECT_EQ(s.lookupTable(-1.0, -1.0), s.texels().front());
  // An unbuilt sphere reads 0.
  EXPECT_EQ(ReflectanceSphere().lookup({0, 0, 1}), glm::vec3(0.0f));
}

TEST(ReflectanceSphereExtremes, DegenerateMaterialsRigsAndSizes) {
  const double nan = std::nan(""), inf = INFINITY;
  LightRig rig = LightRig::studioRig(7);
  rig.lights.push_back({{0, 0, -1}, glm::dvec3(1.0)});   // behind
  rig.lights.push_back({{nan, 0, 1}, glm::dvec3(1.0)});  // dropped
  rig.lights.push_back({{0, 0, 0}, glm::dvec3(1.0)});    // dropped
  rig.lights.push_back({{1, 0, 0}, glm::dvec3(inf)});    // Inf intensity -> 0: dropped
  rig.ambient = glm::dvec3(nan, -1, 0.1);
  for (double n : {0.0, 1.0, 1e5, nan, -3.0, 1e9}) {
    PhongMaterial m;
    m.exponent = n;
    m.diffuse = glm::dvec3(0.5, inf, -1);
    const ReflectanceSphere s = ReflectanceSphere::phong(16, m, rig);
    for (const glm::vec3& t : s.texels()) ASSERT_TRUE(finite3(t) && t.x >= 0 && t.y >= 0 && t.z >= 0) << n;
    // Sanitised: NaN exponent behaves as 1, -3 as 0, 1e9 as 1e6 (identical texels).
    PhongMaterial clean = m.sanitized();
    EXPECT_EQ(s.texels(), ReflectanceSphere::phong(16, clean, rig).texels()) << n;
  }
  // Out-of-range sizes clamp: resolution 8 ... 8192, supersample 1 ... 16.
  EXPECT_EQ(ReflectanceSphere::phong(1, PhongMaterial{}, rig).resolution(), 8);
  EXPECT_EQ(ReflectanceSphere::phong(-100, PhongMaterial{}, rig).resolution(), 8);
  const ReflectanceSphere a = ReflectanceSphere::build(8, [](const glm::dvec3& n) { return n * n; }, 0);
  const ReflectanceSphere b = ReflectanceSphere::build(8, [](const glm::dvec3& n) { return n * n; }, 1);
  EXPECT_EQ(a.texels(), b.texels());
}

}  // namespace
}  // namespace wf

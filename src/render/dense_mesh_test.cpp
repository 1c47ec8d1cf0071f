// Meshes whose triangles are smaller than a coverage subpixel. Many pieces of one surface in a
// pixel each carry a stand-in subpixel when no sample falls inside them; the merged fragment
// must still hide all that lies behind the surface (the regression: stand-in bits counted as
// sampled made merged fragments overlap, stay apart, and let about 5% of a red plane behind a
// dense white one show through, RGBA RMS 0.052 against the reference).
#include "geometry/parametric_sources.h"
#include "render/renderer.h"

#include "render_test_scenes.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace wf {
namespace {

TEST(DenseMesh, SubSubpixelTrianglesHideWhatIsBehindThem) {
  const int W = 64, H = 48;
  Scene s = test::baseScene(W, H);
  Material white, red;
  white.phong = {glm::dvec3(1.0), glm::dvec3(0.0), 1};
  red.phong = {glm::dvec3(1.0, 0.0, 0.0), glm::dvec3(0.0), 1};
  s.materials = {Material{}, white, red};
  s.lights = LightRig{};
  s.lights.ambient = glm::dvec3(1.0);
  // A plane of many cells (2 to 24 triangles per pixel, cells of 0.2 to 0.5 pixel: near and
  // below a subpixel of the coarser masks) covering the image, in front of a red plane.
  for (auto [nu, nv] : {std::pair{150, 90}, {205, 107}, {260, 170}, {300, 200}}) {
    Scene sc = s;
    ParametricSource plane;
    plane.type = ParametricSource::Type::Plane;
    plane.size = glm::dvec3(W + 8.37, H + 8.71, 1);
    plane.resolutionU = nu;
    plane.resolutionV = nv;
    TriangleMesh front = tessellate(plane);
    transformMesh(front, glm::translate(glm::dmat4(1.0), glm::dvec3(0.13, 0.29, 1)));
    sc.surfaces.push_back({"front", front, 1});
    plane.resolutionU = 3;
    plane.resolutionV = 2;
    sc.surfaces.push_back({"back", tessellate(plane), 2});
    for (const MaskLayout& m : {MaskLayout{4, 4}, MaskLayout{8, 4}, MaskLayout{8, 8}}) {
      RenderOptions o = test::smallOptions(W, H);
      o.mask = m;
      const RenderResult r = render(sc, o);
      double worst = 0;
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
          const glm::vec4 p = r.image.at(x, y);
          worst = std::max({worst, std::abs(double(p.y) - 1.0), std::abs(double(p.z) - 1.0), std::abs(double(p.w) - 1.0)});
        }
      EXPECT_LT(worst, 1e-4) << nu << "x" << nv << " " << m.name();  // white, opaque: no red
      EXPECT_EQ(r.stats.abuffer.pixelsWithList, 0u) << nu << "x" << nv << " " << m.name();  // one solid fragment each
    }
  }
}

}  // namespace
}  // namespace wf

// Shading tables kept between frames (render/shading_cache.h): reused exactly when material,
// eye-space lights, options and view grid match, so a cached frame is the uncached frame bit for
// bit; rebuilt when the camera turns relative to lights fixed in the world (the paper's rule).
#include "geometry/parametric_sources.h"
#include "render/renderer.h"
#include "render/shading_cache.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

namespace wf {
namespace {

Scene cageScene(bool lightsFollowCamera) {
  Scene s;
  s.lights = lightsFollowCamera ? LightRig::studioRig(3)
                                : LightRig{glm::dvec3(0.05), {{glm::normalize(glm::dvec3(1, -1, 2)), glm::dvec3(0.9)}}};
  s.lightsFollowCamera = lightsFollowCamera;
  Material wire, skin;
  wire.phong = {glm::dvec3(0.3), glm::dvec3(1.2), 25};
  skin.phong = {glm::dvec3(0.6, 0.3, 0.2), glm::dvec3(0.4), 30};
  s.materials = {Material{}, wire, skin};
  ParametricSource torus;
  torus.type = ParametricSource::Type::Torus;
  s.surfaces.push_back({"torus", tessellate(torus), 2});
  ParametricSource cage;
  cage.type = ParametricSource::Type::Sphere;
  cage.radius = 1.4;
  SceneWire w;
  w.lines = isolines(cage, 12, 6);
  w.material = 1;
  w.thickness = 0.02;
  s.wires.push_back(w);
  return s;
}

Camera cameraAt(double azimuthDegrees) {
  const double a = glm::radians(azimuthDegrees);
  return frameSphere(glm::dvec3(0.0), 1.5, 4.0 / 3.0, Camera::Projection::Perspective,
                     glm::dvec3(std::cos(a), std::sin(a), 0.6));
}

bool sameImage(const ImageRGBA& a, const ImageRGBA& b) {
  return a.width == b.width && a.height == b.height && a.pixels == b.pixels;
}

RenderOptions options() {
  RenderOptions o;
  o.width = 96;
  o.height = 72;
  o.shading = ShadingPath::Maps;  // the cache holds the map path's tables
  return o;
}

TEST(ShadingCache, ASecondFrameReusesEveryTableAndIsBitIdentical) {
  Scene s = cageScene(true);
  s.camera = cameraAt(20);
  RenderOptions o = options();
  o.shadingCache = std::make_shared<ShadingCache>();
  const RenderResult first = render(s, o);
  EXPECT_GT(first.stats.pseudoReflectanceMaps + first.stats.reflectanceSpheres, 0);
  const RenderResult second = render(s, o);
  EXPECT_EQ(second.stats.pseudoReflectanceMaps, 0);
  EXPECT_EQ(second.stats.reflectanceSpheres, 0);
  EXPECT_EQ(second.stats.tablesReused, 2u);  // the wire's map, the torus's sphere
  EXPECT_TRUE(sameImage(first.image, second.image));
  EXPECT_EQ(o.shadingCache->size(), 2u);
}

TEST(ShadingCache, LightsFixedToTheCameraKeepTheTablesAsItTurns) {
  Scene s = cageScene(true);
  RenderOptions o = options();
  o.shadingCache = std::make_shared<ShadingCache>();
  s.camera = cameraAt(0);
  render(s, o);
  for (double az : {30.0, 75.0, 140.0}) {
    s.camera = cameraAt(az);
    const RenderResult cached = render(s, o);
    EXPECT_EQ(cached.stats.pseudoReflectanceMaps + cached.stats.reflectanceSpheres, 0) << az;
    RenderOptions plain = options();
    const RenderResult fresh = render(s, plain);
    EXPECT_GT(fresh.stats.pseudoReflectanceMaps, 0);
    EXPECT_TRUE(sameImage(cached.image, fresh.image)) << az;
  }
}

TEST(ShadingCache, LightsFixedInTheWorldRebuildWhenTheCameraTurns) {
  Scene s = cageScene(false);
  RenderOptions o = options();
  o.shadingCache = std::make_shared<ShadingCache>();
  s.camera = cameraAt(0);
  render(s, o);
  s.camera = cameraAt(0);
  EXPECT_EQ(render(s, o).stats.pseudoReflectanceMaps, 0);  // nothing moved
  s.camera = cameraAt(40);
  const RenderResult turned = render(s, o);
  EXPECT_EQ(turned.stats.pseudoReflectanceMaps, 1);
  EXPECT_EQ(turned.stats.reflectanceSpheres, 1);
  EXPECT_TRUE(sameImage(turned.image, render(s, options()).image));
  // A new material: its table is built, the stale ones are dropped at the frame's end.
  s.materials[1].phong.exponent = 60;
  EXPECT_EQ(render(s, o).stats.pseudoReflectanceMaps, 1);
  EXPECT_EQ(o.shadingCache->size(), 2u);
}

}  // namespace
}  // namespace wf

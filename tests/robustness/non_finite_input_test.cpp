// NaN and Inf in every input array of wf::Scene (issue 7): mesh positions, normals, tangents,
// dS/du, dS/dv, (u, v), colours; wire points, colours, thickness, opacity; light directions,
// intensities, ambient; material values; camera; background; burnish axis; the external opaque
// depth. Each bad value is either skipped and counted (stats.rejectedNonFinite, a warning) or
// replaced by the documented stand-in, and the expectation is the image rendered with that
// element left out or with the stand-in written explicitly: equal bit for bit (tolerance 0),
// and no NaN pixel anywhere.
#include "render/renderer.h"

#include "render_test_scenes.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <string>

namespace wf {
namespace {

const double kBad[] = {std::numeric_limits<double>::quiet_NaN(), INFINITY, -INFINITY};
const char* const kBadName[] = {"NaN", "+Inf", "-Inf"};

// A textured, burnished, lit scene that reads every array: surface 0 a Phong grid with normals,
// uvs and colours; surface 1 a burnished quad (grain along u: tangents, dS/du, dS/dv, uvs);
// wire 0 shaded with per-point colours; wire 1 plain, translucent.
Scene richScene() {
  Scene s;
  s.background = glm::vec4(0.05f, 0.05f, 0.08f, 1.0f);
  s.lights = LightRig::studioRig(3);
  s.lightsFollowCamera = true;
  Material steel;
  steel.name = "steel";
  steel.phong.diffuse = glm::dvec3(0.3);
  steel.phong.specular = glm::dvec3(0.6);
  steel.phong.exponent = 40;
  steel.burnish.grain = Burnish::Grain::U;
  s.materials = {Material{}, steel};
  SceneSurface grid;
  const int n = 8;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double u = double(i) / n, v = double(j) / n;
      grid.mesh.positions.push_back({2 * u - 1, 2 * v - 1, 0.2 * std::sin(3 * u + 2 * v) - 0.5});
      grid.mesh.normals.push_back(glm::normalize(glm::dvec3(-0.1 * std::cos(3 * u), -0.05, 1)));
      grid.mesh.uvs.push_back({u, v});
      grid.mesh.colours.push_back(glm::vec3(0.9f, 0.6f + 0.3f * float(u), 0.4f));
    }
  test::addGridTriangles(grid.mesh, n);
  s.surfaces.push_back(grid);
  SceneSurface quad;
  quad.material = 1;
  quad.mesh.positions = {{-0.9, 0.1, 0.1}, {-0.1, 0.1, 0.1}, {-0.1, 0.9, 0.2}, {-0.9, 0.9, 0.2}};
  quad.mesh.tangents = {{1, 0.2, 0}, {1, 0.3, 0}, {1, 0.1, 0}, {1, 0, 0}};
  quad.mesh.derivU = {{0.8, 0, 0}, {0.8, 0, 0}, {0.8, 0, 0.1}, {0.8, 0, 0.1}};
  quad.mesh.derivV = {{0, 0.8, 0.1}, {0, 0.8, 0.1}, {0, 0.8, 0.1}, {0, 0.8, 0.1}};
  quad.mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  quad.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  s.surfaces.push_back(quad);
  SceneWire shaded;
  shaded.thickness = 0.04;
  for (int k = 0; k < 6; ++k) {
    const double y = -0.8 + 0.3 * k;
    shaded.lines.add({{-0.8, y, 0.3}, {-0.2, y + 0.1, 0.4}, {0.3, y - 0.05, 0.45}, {0.8, y + 0.1, 0.35}});
    for (int p = 0; p < 4; ++p) shaded.lines.colours.push_back(glm::vec3(1.0f, 0.8f - 0.1f * p, 0.5f));
  }
  s.wires.push_back(shaded);
  SceneWire plain;
  plain.style = WireStyle::Plain;
  plain.thickness = 2.0;
  plain.thicknessInPixels = true;
  plain.opacity = 0.6f;
  plain.colour = glm::vec3(0.2f, 0.9f, 0.5f);
  plain.lines.add({{0.9, -0.9, 0.6}, {0.5, 0.9, 0.6}});
  s.wires.push_back(plain);
  Camera cam;
  cam.eye = {0.4, -2.5, 3.0};
  cam.target = {0, 0, 0};
  cam.up = {0, 0, 1};
  cam.fovYDegrees = 40;
  s.camera = cam;
  return s;
}

RenderOptions opts(ShadingPath path = ShadingPath::Maps) {
  RenderOptions o;
  o.width = 80;
  o.height = 60;
  o.shading = path;
  o.map.resolution = 64;
  o.sphereResolution = 64;
  return o;
}

// Renders `bad` and `want`; expects no NaN pixel in either and the two images equal.
void expectSameImage(const Scene& bad, const Scene& want, const std::string& what, ShadingPath path = ShadingPath::Maps,
                     size_t rejected = 0, double tolerance = 0.0) {
  const RenderResult a = render(bad, opts(path)), b = render(want, opts(path));
  ASSERT_TRUE(test::allFinite(a.image)) << what;
  EXPECT_GT(test::sumAlpha(b.image), 100.0) << what;  // a real picture
  int where = -1;
  EXPECT_LE(test::maxDiff(a.image, b.image, &where), tolerance) << what << " (pixel " << where << ")";
  EXPECT_EQ(a.stats.rejectedNonFinite, rejected) << what;
}

TEST(RobustNonFinite, MeshPositionsAreSkippedCountedAndWarned) {
  for (int k = 0; k < 3; ++k)
    for (int coord = 0; coord < 3; ++coord) {
      Scene want = richScene(), bad = richScene();
      // An extra triangle of its own vertices; one of them bad.
      TriangleMesh& m = bad.surfaces[0].mesh;
      const std::uint32_t b = std::uint32_t(m.positions.size());
      for (int v = 0; v < 3; ++v) {
        m.positions.push_back({0.1 * v, 0.3, 0.5});
        m.normals.push_back({0, 0, 1});
        m.uvs.push_back({0.5, 0.5});
        m.colours.push_back(glm::vec3(1));
        want.surfaces[0].mesh.positions.push_back(m.positions.back());
        want.surfaces[0].mesh.normals.push_back({0, 0, 1});
        want.surfaces[0].mesh.uvs.push_back({0.5, 0.5});
        want.surfaces[0].mesh.colours.push_back(glm::vec3(1));
      }
      m.positions[b + 1][coord] = kBad[k];
      m.triangles.push_back({b, b + 1, b + 2});
      const std::string what = std::string("position ") + kBadName[k] + " in coordinate " + std::to_string(coord);
      expectSameImage(bad, want, what, ShadingPath::Maps, 1);
      const RenderResult r = render(bad, opts());
      ASSERT_EQ(r.stats.warnings.size(), 1u) << what;
      EXPECT_NE(r.stats.warnings[0].find("non-finite"), std::string::npos) << r.stats.warnings[0];
    }
}

// Per-vertex attributes bad at every vertex of a surface: the documented stand-ins. Normals: the
// face normal (as with no normals); tangents: none (as with no tangents); dS/du, dS/dv: from the
// (u, v) gradient (as with none); colours: 0 (safeColour). Both shading paths.
TEST(RobustNonFinite, SurfaceAttributesFallBackToTheirStandIns) {
  for (ShadingPath path : {ShadingPath::Maps, ShadingPath::Exact})
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 bad3(kBad[k], 0.5, kBad[k]);
      const std::string tag = std::string(kBadName[k]) + (path == ShadingPath::Maps ? " maps" : " exact");
      {
        Scene bad = richScene(), want = richScene();
        for (glm::dvec3& n : bad.surfaces[0].mesh.normals) n = bad3;
        want.surfaces[0].mesh.normals.clear();
        expectSameImage(bad, want, "normals " + tag, path);
      }
      {
        Scene bad = richScene(), want = richScene();
        for (glm::dvec3& t : bad.surfaces[1].mesh.tangents) t = bad3;
        want.surfaces[1].mesh.tangents.clear();
        expectSameImage(bad, want, "tangents " + tag, path);
      }
      {
        Scene bad = richScene(), want = richScene();
        bad.surfaces[1].mesh.derivU[2] = bad3;
        bad.surfaces[1].mesh.derivV[0].y = kBad[k];
        want.surfaces[1].mesh.derivU.clear();
        want.surfaces[1].mesh.derivV.clear();
        expectSameImage(bad, want, "derivU / derivV " + tag, path);
      }
      {
        Scene bad = richScene(), want = richScene();
        for (size_t v = 0; v < bad.surfaces[0].mesh.colours.size(); v += 3) {
          bad.surfaces[0].mesh.colours[v] = glm::vec3(float(kBad[k]), 0.5f, 0.5f);
          want.surfaces[0].mesh.colours[v] = glm::vec3(0.0f, 0.5f, 0.5f);
        }
        // safeColour acts on the interpolated colour: a bad red at any vertex of a triangle makes
        // its red 0 (0 x NaN is NaN); so the stand-in is red 0 on every triangle that uses one,
        // written with the triangles on vertices of their own (in both scenes).
        Scene expected = want;
        TriangleMesh& m = expected.surfaces[0].mesh;
        TriangleMesh split;
        for (const glm::uvec3& t : m.triangles) {
          const bool dark = t.x % 3 == 0 || t.y % 3 == 0 || t.z % 3 == 0;
          const std::uint32_t b = std::uint32_t(split.positions.size());
          for (int c = 0; c < 3; ++c) {
            split.positions.push_back(m.positions[t[c]]);
            split.normals.push_back(m.normals[t[c]]);
            split.uvs.push_back(m.uvs[t[c]]);
            glm::vec3 col = m.colours[t[c]];
            if (dark) col.x = 0.0f;
            split.colours.push_back(col);
          }
          split.triangles.push_back({b, b + 1, b + 2});
        }
        Scene badSplit = bad;  // the bad scene with the same vertex splitting (same geometry order)
        TriangleMesh& bm = badSplit.surfaces[0].mesh;
        TriangleMesh bsplit;
        for (const glm::uvec3& t : bm.triangles) {
          const std::uint32_t b = std::uint32_t(bsplit.positions.size());
          for (int c = 0; c < 3; ++c) {
            bsplit.positions.push_back(bm.positions[t[c]]);
            bsplit.normals.push_back(bm.normals[t[c]]);
            bsplit.uvs.push_back(bm.uvs[t[c]]);
            bsplit.colours.push_back(bm.colours[t[c]]);
          }
          bsplit.triangles.push_back({b, b + 1, b + 2});
        }
        bm = bsplit;
        m = split;
        expectSameImage(badSplit, expected, "colours " + tag, path);
      }
      {
        // (u, v) bad everywhere on the burnished quad (grain along u, read through its
        // derivatives): finite and within the range of the clean picture's radiance.
        Scene bad = richScene();
        for (glm::dvec2& uv : bad.surfaces[1].mesh.uvs) uv = glm::dvec2(kBad[k], 0.5);
        const RenderResult r = render(bad, opts(path));
        ASSERT_TRUE(test::allFinite(r.image)) << "uvs " << tag;
      }
    }
}

// A bad point inside a polyline: the two segments touching it are skipped and counted, and the
// picture is that of the polyline split in two at that point (square ends, no joint there).
TEST(RobustNonFinite, WirePointsSplitThePolylineAndAreCounted) {
  for (int k = 0; k < 3; ++k) {
    Scene bad = richScene(), want = richScene();
    SceneWire& w = bad.wires[0];
    const std::uint32_t first = w.lines.starts[2];  // polyline 2: points first ... first + 3
    w.lines.points[first + 1].y = kBad[k];
    // Expected: polyline 2 as the segment-free point {p0} dropped and {p2, p3} kept.
    SceneWire& ww = want.wires[0];
    PolylineSet split;
    std::vector<glm::vec3> cols;
    for (size_t li = 0; li < ww.lines.polylineCount(); ++li) {
      const std::uint32_t a = ww.lines.starts[li], b = ww.lines.starts[li + 1];
      if (li == 2) {
        split.add({ww.lines.points[a + 2], ww.lines.points[a + 3]});
        cols.insert(cols.end(), {ww.lines.colours[a + 2], ww.lines.colours[a + 3]});
        continue;
      }
      split.add(std::vector<glm::dvec3>(ww.lines.points.begin() + a, ww.lines.points.begin() + b));
      cols.insert(cols.end(), ww.lines.colours.begin() + a, ww.lines.colours.begin() + b);
    }
    split.colours = cols;
    ww.lines = split;
    expectSameImage(bad, want, std::string("wire point ") + kBadName[k], ShadingPath::Maps, 2);
    expectSameImage(bad, want, std::string("wire point exact ") + kBadName[k], ShadingPath::Exact, 2);
  }
}

// Scalars and small arrays with their documented stand-ins: wire colours -> 0; wire thickness
// NaN / Inf / negative -> the wire draws nothing (counted as clipped); opacities -> 1; light
// direction or intensity -> the light is left out; ambient -> 0; material colours -> 0,
// exponent NaN -> 1; burnish axis -> the eye-space origin / +z.
TEST(RobustNonFinite, ScalarInputsTakeTheirDocumentedStandIns) {
  using Edit = std::function<void(Scene&, double)>;
  struct Case {
    const char* name;
    Edit bad, want;
  };
  const std::vector<Case> cases = {
      {"wire colour", [](Scene& s, double x) { s.wires[0].lines.colours[5] = glm::vec3(float(x), 0.3f, 0.3f); },
       [](Scene& s, double) { s.wires[0].lines.colours[5] = glm::vec3(0.0f, 0.3f, 0.3f); }},
      {"wire thickness", [](Scene& s, double x) { s.wires[1].thickness = x; },
       [](Scene& s, double) { s.wires.pop_back(); }},
      {"world wire thickness", [](Scene& s, double x) { s.wires[0].thickness = x; },
       [](Scene& s, double) { s.wires.erase(s.wires.begin()); }},
      {"wire opacity", [](Scene& s, double x) { s.wires[1].opacity = float(x); },
       [](Scene& s, double) { s.wires[1].opacity = 1.0f; }},
      {"material opacity", [](Scene& s, double x) { s.materials[0].opacity = float(x); },
       [](Scene& s, double) { s.materials[0].opacity = 1.0f; }},
      {"light direction", [](Scene& s, double x) { s.lights.lights[1].direction.z = x; },
       [](Scene& s, double) { s.lights.lights.erase(s.lights.lights.begin() + 1); }},
      {"light intensity", [](Scene& s, double x) { s.lights.lights[0].intensity = glm::dvec3(x); },
       [](Scene& s, double) { s.lights.lights.erase(s.lights.lights.begin()); }},
      {"ambient", [](Scene& s, double x) { s.lights.ambient = glm::dvec3(x); },
       [](Scene& s, double) { s.lights.ambient = glm::dvec3(0.0); }},
      {"diffuse", [](Scene& s, double x) { s.materials[0].phong.diffuse.y = x; },
       [](Scene& s, double) { s.materials[0].phong.diffuse.y = 0.0; }},
      {"specular", [](Scene& s, double x) { s.materials[1].phong.specular = glm::dvec3(x); },
       [](Scene& s, double) { s.materials[1].phong.specular = glm::dvec3(0.0); }},
      {"burnish axis", [](Scene& s, double x) {
         s.materials[1].burnish.grain = Burnish::Grain::Radial;
         s.materials[1].burnish.axisDirection = glm::dvec3(x, 0, 1);
       },
       [](Scene& s, double) {
         s.materials[1].burnish.grain = Burnish::Grain::Radial;
         // The stand-in is eye-space +z: the view axis, i.e. the direction towards the eye.
         const Camera& c = *s.camera;
         s.materials[1].burnish.axisDirection = glm::normalize(c.eye - c.target);
       }},
  };
  for (const Case& c : cases)
    for (int k = 0; k < 3; ++k) {
      Scene bad = richScene(), want = richScene();
      c.bad(bad, kBad[k]);
      c.want(want, kBad[k]);
      // The burnish axis stand-in is eye-space +z, written here in world space (rounding: 1e-5).
      const double tol = std::string(c.name) == "burnish axis" ? 1e-5 : 0.0;
      expectSameImage(bad, want, std::string(c.name) + " " + kBadName[k], ShadingPath::Maps, 0, tol);
    }
  // Negative thickness: drawn as nothing too.
  Scene neg = richScene(), none = richScene();
  neg.wires[1].thickness = -2.0;
  none.wires.pop_back();
  expectSameImage(neg, none, "negative thickness");
  // Exponent NaN: sanitised to 1 (phong.h).
  Scene nanExp = richScene(), one = richScene();
  nanExp.materials[1].phong.exponent = std::numeric_limits<double>::quiet_NaN();
  one.materials[1].phong.exponent = 1.0;
  expectSameImage(nanExp, one, "exponent NaN");
  expectSameImage(nanExp, one, "exponent NaN exact", ShadingPath::Exact);
}

// A bad camera (any field) is reported in a warning and replaced by the camera framed from the
// scene's bounds: the image equals the one rendered with no camera at all.
TEST(RobustNonFinite, BadCameraIsReplacedByTheFramedOne) {
  using Edit = std::function<void(Camera&, double)>;
  const std::vector<std::pair<const char*, Edit>> edits = {
      {"eye", [](Camera& c, double x) { c.eye.x = x; }},
      {"target", [](Camera& c, double x) { c.target.z = x; }},
      {"up", [](Camera& c, double x) { c.up.y = x; }},
      {"fov", [](Camera& c, double x) { c.fovYDegrees = x; }},
      {"near", [](Camera& c, double x) { c.nearPlane = x; }},
      {"far", [](Camera& c, double x) { c.farPlane = x; }},
      {"ortho height", [](Camera& c, double x) {
         c.projection = Camera::Projection::Orthographic;
         c.orthoHeight = x;
       }},
  };
  Scene framed = richScene();
  framed.camera.reset();
  for (const auto& [name, edit] : edits)
    for (int k = 0; k < 3; ++k) {
      Scene bad = richScene();
      edit(*bad.camera, kBad[k]);
      expectSameImage(bad, framed, std::string("camera ") + name + " " + kBadName[k]);
      const RenderResult r = render(bad, opts());
      ASSERT_FALSE(r.stats.warnings.empty());
      EXPECT_NE(r.stats.warnings[0].find("camera"), std::string::npos) << r.stats.warnings[0];
    }
}

// A bad background component is taken as 0 (as colours are), alpha clamped to [0, 1]: no NaN
// pixel, and the image equals the one with that component 0 (both renderers).
TEST(RobustNonFinite, BadBackgroundGivesNoNaNPixel) {
  for (int k = 0; k < 3; ++k)
    for (int c = 0; c < 4; ++c) {
      Scene bad = richScene(), want = richScene();
      bad.background[c] = float(kBad[k]);
      want.background[c] = c == 3 && kBad[k] > 0 ? 1.0f : 0.0f;
      if (c == 3 && std::isnan(kBad[k])) want.background[c] = 0.0f;
      expectSameImage(bad, want, std::string("background ") + std::to_string(c) + " " + kBadName[k]);
      RenderOptions o = opts();
      o.width = 16;
      o.height = 12;
      o.referenceSamples = 2;
      const RenderResult a = renderReference(bad, o), b = renderReference(want, o);
      ASSERT_TRUE(test::allFinite(a.image)) << "reference, background " << c << " " << kBadName[k];
      EXPECT_EQ(test::maxDiff(a.image, b.image), 0.0);
    }
}

// The external opaque depth: NaN and +Inf mean "nothing opaque here" (documented): the image
// equals the one without it; -Inf hides everything (every fragment is behind it): background.
TEST(RobustNonFinite, ExternalOpaqueDepthNaNAndInfAreDefined) {
  const Scene s = richScene();
  const RenderResult plain = render(s, opts());
  for (int k = 0; k < 2; ++k) {
    RenderOptions o = opts();
    const std::vector<float> depth(size_t(o.width) * o.height, float(kBad[k]));
    o.opaqueDepth = &depth;
    const RenderResult r = render(s, o);
    ASSERT_TRUE(test::allFinite(r.image));
    EXPECT_EQ(test::maxDiff(r.image, plain.image), 0.0) << kBadName[k];
  }
  RenderOptions o = opts();
  const std::vector<float> depth(size_t(o.width) * o.height, -INFINITY);
  o.opaqueDepth = &depth;
  const RenderResult r = render(s, o);
  for (const glm::vec4& p : r.image.pixels) ASSERT_EQ(p, s.background);
}

}  // namespace
}  // namespace wf

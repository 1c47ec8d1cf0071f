// Every style on every input kind (docs/scenes.md, "Styles"): a mesh with texture coordinates
// (OBJ), one without (STL), a file of polylines only (legacy VTK) and a scene file, in each of
// wire, wire-over-surface, burnished, fur and scales. Where the style means something the render
// succeeds with the preset's materials (from --stats: the materials the drawn geometry uses, the
// tables and growth it needed) and covers pixels; where it does not, one line and exit 2. CAD
// files: tests/apps/cad_cli_test.cpp.
#include "cli_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <set>
#include <sstream>
#include <string>

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

std::string q(const std::string& s) { return "'" + s + "'"; }

/// A 4 x 4 grid on the unit square at z = 0 with texture coordinates (u = x, v = y), bumped so
/// that it is not flat.
std::string objGrid() {
  std::ostringstream o;
  for (int j = 0; j <= 4; ++j)
    for (int i = 0; i <= 4; ++i) o << "v " << i / 4.0 << " " << j / 4.0 << " " << 0.1 * ((i + j) % 2) << "\n";
  for (int j = 0; j <= 4; ++j)
    for (int i = 0; i <= 4; ++i) o << "vt " << i / 4.0 << " " << j / 4.0 << "\n";
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      const int a = j * 5 + i + 1, b = a + 1, c = a + 6, d = a + 5;
      o << "f " << a << "/" << a << " " << b << "/" << b << " " << c << "/" << c << "\n";
      o << "f " << a << "/" << a << " " << c << "/" << c << " " << d << "/" << d << "\n";
    }
  return o.str();
}

/// A tetrahedron, ASCII STL (no texture coordinates).
std::string stlTetrahedron() {
  const double p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  std::ostringstream o;
  o << "solid t\n";
  for (const auto& t : f) {
    o << "facet normal 0 0 0\nouter loop\n";
    for (int k = 0; k < 3; ++k) o << "vertex " << p[t[k]][0] << " " << p[t[k]][1] << " " << p[t[k]][2] << "\n";
    o << "endloop\nendfacet\n";
  }
  o << "endsolid t\n";
  return o.str();
}

/// 50 wavy polylines of 6 points, legacy VTK.
std::string vtkPolylines() {
  std::ostringstream o;
  o << "# vtk DataFile Version 3.0\nhair\nASCII\nDATASET POLYDATA\nPOINTS 300 float\n";
  for (int h = 0; h < 50; ++h)
    for (int k = 0; k < 6; ++k) o << 0.02 * h << " " << 0.1 * k << " " << 0.03 * ((k + h) % 3) << "\n";
  o << "LINES 50 350\n";
  for (int h = 0; h < 50; ++h) {
    o << 6;
    for (int k = 0; k < 6; ++k) o << " " << h * 6 + k;
    o << "\n";
  }
  return o.str();
}

json renderStyled(const fs::path& d, const std::string& input, const std::string& style, wf::test::CliResult& r) {
  const fs::path png = d / (fs::path(input).stem().string() + "_" + style + ".png");
  const fs::path stats = d / (fs::path(input).stem().string() + "_" + style + ".json");
  r = wf::test::runWirefur("render " + q(input) + " -o " + q(png.string()) + " --style " + style + " --size 96x72 --stats " +
                           q(stats.string()));
  if (r.status != 0) {
    EXPECT_FALSE(fs::exists(png)) << input << " " << style;
    return json::object();
  }
  return json::parse(wf::test::readFile(stats));
}

std::set<std::string> materials(const json& s) {
  std::set<std::string> m;
  for (const json& n : s.value("materials", json::array())) m.insert(n.get<std::string>());
  return m;
}

TEST(StylesCli, EveryStyleOnEveryInputKind) {
  const fs::path d = wf::test::scratchDir("styles");
  const std::string obj = wf::test::writeFile(d, "grid.obj", objGrid());
  const std::string stl = wf::test::writeFile(d, "tetra.stl", stlTetrahedron());
  const std::string lines = wf::test::writeFile(d, "hair.vtk", vtkPolylines());
  for (const std::string& input : {obj, stl}) {
    SCOPED_TRACE(input);
    wf::test::CliResult r;
    json s = renderStyled(d, input, "wire", r);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(materials(s), std::set<std::string>({"wire"}));
    EXPECT_GT(s["segments"].get<double>(), 0);
    EXPECT_EQ(s["triangles"].get<double>(), 0);
    s = renderStyled(d, input, "wire-over-surface", r);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(materials(s), std::set<std::string>({"part", "wire"}));
    s = renderStyled(d, input, "burnished", r);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(materials(s), std::set<std::string>({"brushed steel"}));
    EXPECT_EQ(s["left_out"]["lobe_tables_built"].get<int>(), 1);  // grain is shaded as cylinders
    s = renderStyled(d, input, "fur", r);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(materials(s), std::set<std::string>({"fur skin", "fur"}));
    EXPECT_GT(s["generated"]["hairs"].get<double>(), 10000);  // about 60,000 on any surface
    s = renderStyled(d, input, "scales", r);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(materials(s), std::set<std::string>({"skin", "scale"}));
    EXPECT_GT(s["generated"]["scales"].get<double>(), 100);
    for (const char* style : {"wire", "wire-over-surface", "burnished", "fur", "scales"}) {
      const json t = renderStyled(d, input, style, r);
      EXPECT_GT(t["left_out"]["covered_pixels"].get<double>(), 200) << style;
    }
  }
  {
    wf::test::CliResult r;
    for (const char* style : {"wire", "wire-over-surface"}) {
      const json s = renderStyled(d, lines, style, r);
      ASSERT_EQ(r.status, 0) << r.err;
      EXPECT_EQ(materials(s), std::set<std::string>({"hair"})) << style;
      EXPECT_EQ(s["segments"].get<double>(), 250) << style;
    }
    for (const char* style : {"burnished", "fur", "scales"}) {
      renderStyled(d, lines, style, r);
      EXPECT_EQ(r.status, 2) << style;
      EXPECT_EQ(wf::test::lineCount(r.err), 1) << r.err;
      EXPECT_NE(r.err.find("needs polygons"), std::string::npos) << r.err;
    }
  }
  {
    wf::test::CliResult r;
    renderStyled(d, std::string(WIREFUR_SOURCE_DIR) + "/data/scenes/fur_torus.json", "fur", r);
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(wf::test::lineCount(r.err), 1) << r.err;
  }
}

}  // namespace

// --grooves-per-mm on a mesh without (u, v) (an STL): grooves along u or v would give the whole
// surface one groove's shade, so there are none, with one warning naming the file; the image is
// then the plain burnished one, bit for bit. Circular grooves need no (u, v) and are drawn.
TEST(StylesCli, GroovesNeedTextureCoordinates) {
  const fs::path d = wf::test::scratchDir("styles_grooves");
  const std::string stl = wf::test::writeFile(d, "tetra.stl", stlTetrahedron());
  auto render = [&](const std::string& extra, const std::string& name) {
    const fs::path png = d / (name + ".png"), stats = d / (name + ".json");
    const wf::test::CliResult r = wf::test::runWirefur("render " + q(stl) + " -o " + q(png.string()) +
                                                       " --style burnished --size 96x72 --stats " + q(stats.string()) + " " + extra);
    EXPECT_EQ(r.status, 0) << r.err;
    return std::make_pair(r, json::parse(wf::test::readFile(stats)));
  };
  const auto [plain, plainStats] = render("", "plain");
  const auto [grooved, groovedStats] = render("--grooves-per-mm 10", "grooved");
  EXPECT_EQ(wf::test::lineCount(grooved.err), 1) << grooved.err;
  EXPECT_NE(grooved.err.find("tetra.stl"), std::string::npos) << grooved.err;
  EXPECT_NE(grooved.err.find("no texture coordinates"), std::string::npos) << grooved.err;
  EXPECT_EQ(wf::test::lineCount(plain.err), 0) << plain.err;  // the style puts no grooves there
  EXPECT_EQ(wf::test::readFile(d / "plain.png"), wf::test::readFile(d / "grooved.png"));
  const auto [circular, circularStats] = render("--grain circular --grooves-per-mm 10", "circular");
  EXPECT_EQ(circular.err.find("no texture coordinates"), std::string::npos) << circular.err;
  EXPECT_NE(wf::test::readFile(d / "plain.png"), wf::test::readFile(d / "circular.png"));
}

// A scene file's grooved material shared by a plane (its (u, v) from the source) and an STL (none):
// the STL gets a copy of the material without grooves, with one warning naming it, and is drawn as
// with a plain material; the plane keeps its grooves.
TEST(StylesCli, SharedGroovedMaterialLeavesOutTheMeshWithoutTextureCoordinates) {
  const fs::path d = wf::test::scratchDir("styles_grooves_shared");
  const std::string stl = wf::test::writeFile(d, "tetra.stl", stlTetrahedron());
  auto scene = [&](const std::string& name, const std::string& grooves, bool plane, bool mesh) {
    std::string objects;
    if (plane) objects += R"({"name": "plate", "source": {"type": "plane", "size": [2, 2]}, "surface": {"material": "steel"}})";
    if (mesh) objects += std::string(plane ? ", " : "") + R"({"name": "tetra", "file": ")" + stl + R"(", "surface": {"material": "steel"}})";
    return wf::test::writeFile(d, name, R"({"image": {"size": [96, 72]}, "camera": {"eye": [0, -3, 3], "target": [0, 0, 0], "up": [0, 0, 1]},
      "materials": {"steel": {"burnish": {"grain": "u")" + grooves + R"(}}}, "objects": [)" + objects + "]}");
  };
  auto render = [&](const std::string& file, const std::string& name) {
    const wf::test::CliResult r = wf::test::runWirefur("render " + q(file) + " -o " + q((d / (name + ".png")).string()));
    EXPECT_EQ(r.status, 0) << r.err;
    return r;
  };
  const std::string grooves = R"(, "grooves": {"count": 40, "depth": 0.8})";
  const auto both = render(scene("both.json", grooves, true, true), "both");
  EXPECT_EQ(wf::test::lineCount(both.err), 1) << both.err;
  EXPECT_NE(both.err.find("/objects/1"), std::string::npos) << both.err;
  EXPECT_NE(both.err.find("no texture coordinates"), std::string::npos) << both.err;
  // The mesh alone, grooved or not: the same image. The plate alone: its grooves show.
  render(scene("mesh_grooved.json", grooves, false, true), "mesh_grooved");
  render(scene("mesh_plain.json", "", false, true), "mesh_plain");
  EXPECT_EQ(wf::test::readFile(d / "mesh_grooved.png"), wf::test::readFile(d / "mesh_plain.png"));
  render(scene("plate_grooved.json", grooves, true, false), "plate_grooved");
  render(scene("plate_plain.json", "", true, false), "plate_plain");
  EXPECT_NE(wf::test::readFile(d / "plate_grooved.png"), wf::test::readFile(d / "plate_plain.png"));
}

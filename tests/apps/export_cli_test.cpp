// `wirefur export`: the geometry a scene draws, written by VTK's writers and read back by
// `wirefur render` (its own VTK readers), with the same counts of hair segments and triangles.
#include "cli_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

using Result = wf::test::CliResult;
Result run(const std::string& args) { return wf::test::runWirefur(args); }
const std::string kScenes = std::string(WIREFUR_SOURCE_DIR) + "/data/scenes/";

fs::path dir() { return wf::test::scratchDir("wirefur-export"); }

json renderStats(const std::string& input, const std::string& extra) {
  const fs::path png = dir() / "r.png", stats = dir() / "r.json";
  const Result r = run("render '" + input + "' -o '" + png.string() + "' --size 64x48 --stats '" + stats.string() + "' " + extra);
  EXPECT_EQ(r.status, 0) << r.err;
  std::ifstream in(stats);
  return json::parse(in);
}

}  // namespace

// The furry torus (7,000 hairs over 3,200 triangles) exported to .vtp, .vtk and .obj and
// rendered back: the same segments and triangles as the scene itself.
TEST(ExportCli, FurAndSurfacesRoundTripThroughEveryLineFormat) {
  const json scene = renderStats(kScenes + "fur_torus.json", "");
  for (const std::string ext : {"vtp", "vtk", "obj"}) {
    const fs::path out = dir() / ("fur." + ext);
    const Result r = run("export '" + kScenes + "fur_torus.json' -o '" + out.string() + "'");
    ASSERT_EQ(r.status, 0) << ext << ": " << r.err;
    EXPECT_TRUE(r.err.empty()) << r.err;
    const json back = renderStats(out.string(), "--style wire-over-surface");
    EXPECT_EQ(back["segments"], scene["segments"]) << ext;
    EXPECT_EQ(back["triangles"], scene["triangles"]) << ext;
  }
}

// PLY holds no lines: the surfaces are written, one warning line says what was left out.
TEST(ExportCli, PlyKeepsTheSurfacesAndSaysTheHairsAreLeftOut) {
  const fs::path out = dir() / "fur.ply";
  const Result r = run("export '" + kScenes + "fur_torus.json' -o '" + out.string() + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(wf::test::lineCount(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("7000"), std::string::npos) << r.err;
  const json back = renderStats(out.string(), "--style wire-over-surface");
  EXPECT_EQ(back["triangles"].get<int>(), 3200);
}

// The same --time gives the same hairs; another time moves them (wind).
TEST(ExportCli, TimeMovesTheWindBlownHairs) {
  const std::string scene = (dir() / "wind.json").string();
  std::ofstream(scene) << R"({"objects": [{"source": {"type": "torus"}, "fur": {"grid": [12, 8], "segments": 3,
                              "wind": {"strength": 0.5, "frequency": 1}}}]})";
  auto exportAt = [&](const std::string& t, const std::string& name) {
    const fs::path out = dir() / name;
    const Result r = run("export '" + scene + "' -o '" + out.string() + "' --time " + t);
    EXPECT_EQ(r.status, 0) << r.err;
    std::ifstream in(out, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  EXPECT_EQ(exportAt("0.25", "a.vtk"), exportAt("0.25", "b.vtk"));
  EXPECT_NE(exportAt("0.25", "c.vtk"), exportAt("0.5", "d.vtk"));
}

// Bad input: one line naming the place, exit 2, nothing written.
TEST(ExportCli, BadInputIsOneLineAndWritesNothing) {
  const fs::path out = dir() / "bad.vtp";
  for (const std::string& args : {std::string("export '") + kScenes + "fur_torus.json' -o '" + (dir() / "x.stl").string() + "'",
                                  std::string("export -o '") + out.string() + "'",
                                  std::string("export '") + (dir() / "missing.json").string() + "' -o '" + out.string() + "'",
                                  std::string("export '") + kScenes + "fur_torus.json' -o '" + (dir() / "no/such/x.vtp").string() + "'",
                                  std::string("export '") + kScenes + "fur_torus.json' -o '" + out.string() + "' --time abc"}) {
    const Result r = run(args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.err;
    EXPECT_EQ(wf::test::lineCount(r.err), 1) << args << ": " << r.err;
    EXPECT_FALSE(fs::exists(out)) << args;
  }
}

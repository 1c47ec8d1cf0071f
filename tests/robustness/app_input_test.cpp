// NaN / Inf in input files read by the app's readers (.vtp .vtk .ply .obj, apps/mesh_io.cpp), and
// the command's memory budget (`wirefur render --memory-budget`). Expectations: a file with a
// non-finite coordinate renders with that element skipped and counted (stats.rejectedNonFinite)
// and the image equal to the same file without the bad triangle, or is refused with one line
// naming the file (exit status 2 for the command) -- never a crash or a NaN pixel. The budget: a
// 16384x16384 render over it exits 2 with one line and writes no PNG; 0 means unlimited.
#include "cli.h"
#include "mesh_io.h"
#include "reader_worker.h"
#include "render_command.h"
#include "scene_file.h"

#include "render/renderer.h"

#include "cli_support.h"
#include "render_test_scenes.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkPLYWriter.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataWriter.h>
#include <vtkXMLPolyDataWriter.h>

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

namespace wf {
namespace {

namespace fs = std::filesystem;

// A 6 x 6 grid of points (a gentle bump) in triangles; with `badValue` finite or not, one more
// triangle on the grid's boundary edge (0, 1) whose third point is (badValue, -0.3, 0):
// `withExtra` false leaves that triangle (and its point) out.
struct GridFile {
  std::vector<glm::dvec3> points;
  std::vector<glm::uvec3> triangles;
};

GridFile grid(bool withExtra, double badValue) {
  GridFile g;
  const int n = 6;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) g.points.push_back({i * 0.2, j * 0.2, 0.05 * std::sin(i + 0.7 * j)});
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const unsigned a = unsigned(j * n + i);
      g.triangles.push_back({a, a + 1, a + n + 1});
      g.triangles.push_back({a, a + n + 1, a + n});
    }
  if (withExtra) {
    g.points.push_back({badValue, -0.3, 0.0});
    g.triangles.push_back({1, 0, unsigned(g.points.size() - 1)});
  }
  return g;
}

vtkNew<vtkPolyData> toPolyData(const GridFile& g) {
  vtkNew<vtkPolyData> pd;
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  for (const glm::dvec3& p : g.points) pts->InsertNextPoint(p.x, p.y, p.z);
  vtkNew<vtkCellArray> polys;
  for (const glm::uvec3& t : g.triangles) {
    const vtkIdType ids[3] = {t.x, t.y, t.z};
    polys->InsertNextCell(3, ids);
  }
  pd->SetPoints(pts);
  pd->SetPolys(polys);
  return pd;
}

std::string writeAs(const GridFile& g, const fs::path& dir, const std::string& name) {
  const std::string path = (dir / name).string();
  const std::string ext = fs::path(name).extension().string();
  vtkNew<vtkPolyData> pd = toPolyData(g);
  if (ext == ".vtp") {
    vtkNew<vtkXMLPolyDataWriter> w;
    w->SetFileName(path.c_str());
    w->SetInputData(pd);
    w->SetDataModeToBinary();
    w->Write();
  } else if (ext == ".vtk") {
    vtkNew<vtkPolyDataWriter> w;
    w->SetFileName(path.c_str());
    w->SetInputData(pd);
    w->SetFileTypeToBinary();
    w->Write();
  } else if (ext == ".ply") {
    vtkNew<vtkPLYWriter> w;
    w->SetFileName(path.c_str());
    w->SetInputData(pd);
    w->SetFileTypeToBinary();
    w->Write();
  } else {  // .obj, by hand: "nan" / "inf" as C's printf writes them
    std::ofstream f(path);
    for (const glm::dvec3& p : g.points) f << "v " << p.x << " " << p.y << " " << p.z << "\n";
    for (const glm::uvec3& t : g.triangles) f << "f " << t.x + 1 << " " << t.y + 1 << " " << t.z + 1 << "\n";
  }
  return path;
}

RenderOptions fileOptions() {
  RenderOptions o;
  o.width = 96;
  o.height = 72;
  return o;
}

// For each reader and each bad value: read both files through the command's own loader
// (wire-over-surface: the part and its edges as wire), render, and compare. Accepted files:
// rejectedNonFinite counts the bad triangle and its two edges, no NaN pixel, and the picture
// equals the clean file's within 1e-6 (the framing uses only finite points, so the camera is the
// same). Refused files: a UsageError of one line naming the file.
TEST(RobustAppInput, MeshFilesWithNonFiniteCoordinatesAreSkippedOrRefused) {
  const fs::path dir = test::scratchDir("wirefur-robust-files");
  for (const char* ext : {".vtp", ".vtk", ".ply", ".obj"}) {
    const std::string clean = writeAs(grid(false, 0), dir, std::string("clean") + ext);
    const wfapp::SceneFile ref = wfapp::sceneForGeometryFile(clean, "wire-over-surface");
    const RenderResult want = render(ref.scene, fileOptions());
    ASSERT_GT(test::sumAlpha(want.image), 500.0) << ext;
    int k = 0;
    for (double bad : {std::numeric_limits<double>::quiet_NaN(), double(INFINITY), -double(INFINITY)}) {
      const std::string path = writeAs(grid(true, bad), dir, "bad" + std::to_string(k++) + ext);
      const std::string what = path + " (" + std::to_string(bad) + ")";
      wfapp::SceneFile sf;
      try {
        sf = wfapp::sceneForGeometryFile(path, "wire-over-surface");
      } catch (const wfapp::UsageError& e) {
        const std::string m = e.what();
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
        EXPECT_EQ(m.rfind(path, 0), 0u) << m;
        continue;
      }
      const RenderResult got = render(sf.scene, fileOptions());
      ASSERT_TRUE(test::allFinite(got.image)) << what;
      EXPECT_EQ(got.stats.rejectedNonFinite, 3u) << what;  // the triangle and its two new edges
      int where = -1;
      EXPECT_LE(test::maxDiff(got.image, want.image, &where), 1e-6) << what << " pixel " << where;
    }
  }
}

#ifdef WIREFUR_EXE
// The command on such a file: exit 0 with the bad elements counted in --stats
// (input.rejected_non_finite) and a PNG, or exit 2 with one line. Never a crash (exit 1 or a
// signal).
TEST(RobustAppInput, CommandOnAFileWithNaNCoordinatesExitsCleanly) {
  const fs::path dir = test::scratchDir("wirefur-robust-cli");
  const std::string path = writeAs(grid(true, std::numeric_limits<double>::quiet_NaN()), dir, "nan.vtp");
  const std::string png = (dir / "nan.png").string(), stats = (dir / "nan.json").string();
  const test::CliResult r = test::runWirefur("render '" + path + "' -o '" + png + "' --size 64x48 --stats '" + stats + "' --quiet");
  ASSERT_TRUE(r.status == 0 || r.status == 2) << r.status << ": " << r.err;
  if (r.status == 2) {
    EXPECT_EQ(test::lineCount(r.err), 1) << r.err;
    EXPECT_FALSE(fs::exists(png));
    return;
  }
  ASSERT_TRUE(fs::exists(png));
  const nlohmann::json j = nlohmann::json::parse(test::readFile(stats));
  EXPECT_EQ(j["input"]["rejected_non_finite"].get<int>(), 3);
}

// --memory-budget: 16384x16384 with 1G exits 2 with one line naming the budget, and writes no
// PNG; bad values exit 2 with one line; 0 is unlimited (a small render succeeds); a budget the
// image fits but the scene does not (the built-in scene's primitives) is refused too.
TEST(RobustAppInput, MemoryBudgetOptionRefusesOversizedRendersWithOneLine) {
  const fs::path dir = test::scratchDir("wirefur-robust-budget");
  const std::string png = (dir / "big.png").string();
  test::CliResult r = test::runWirefur("render -o '" + png + "' --size 16384x16384 --memory-budget 1G --quiet");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(test::lineCount(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("16384x16384"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("over the memory budget of 1 GiB"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--memory-budget"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(png));
  for (const char* bad : {"abc", "-1", "1.5X", "G", "", "1e400"}) {
    r = test::runWirefur("render -o '" + png + "' --size 8x8 --memory-budget '" + std::string(bad) + "' --quiet");
    EXPECT_EQ(r.status, 2) << bad << ": " << r.err;
    EXPECT_EQ(test::lineCount(r.err), 1) << r.err;
    EXPECT_FALSE(fs::exists(png));
  }
  const std::string small = (dir / "small.png").string();
  r = test::runWirefur("render -o '" + small + "' --size 16x12 --memory-budget 0 --quiet");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(small));
  // Between the image's share and the scene's: the command refuses after reading the scene.
  const wfapp::SceneFile builtIn = wfapp::defaultScene();
  RenderOptions o;
  o.width = 64;
  o.height = 48;
  const size_t imageOnly = estimateRenderBytes(Scene{}, o), withScene = estimateRenderBytes(builtIn.scene, o);
  ASSERT_GT(withScene, imageOnly + 2 * 64 * 48 * 3 + 4096);
  const size_t between = (imageOnly + withScene) / 2;
  const std::string mid = (dir / "mid.png").string();
  r = test::runWirefur("render -o '" + mid + "' --size 64x48 --memory-budget " + std::to_string(between) + " --quiet");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(test::lineCount(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("built-in scene"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(mid));
  r = test::runWirefur("render -o '" + mid + "' --size 64x48 --memory-budget 1G --quiet");
  EXPECT_EQ(r.status, 0) << r.err;
}
#endif

// The parser: bytes and binary suffixes, 0 unlimited; garbage refused naming the option.
TEST(RobustAppInput, ByteSizesParse) {
  EXPECT_EQ(wfapp::parseByteSize("--memory-budget", "0"), 0u);
  EXPECT_EQ(wfapp::parseByteSize("--memory-budget", "1500"), 1500u);
  EXPECT_EQ(wfapp::parseByteSize("--memory-budget", "512M"), size_t(512) << 20);
  EXPECT_EQ(wfapp::parseByteSize("--memory-budget", "2G"), size_t(2) << 30);
  EXPECT_EQ(wfapp::parseByteSize("--memory-budget", "1.5GiB"), size_t(3) << 29);
  EXPECT_EQ(wfapp::parseByteSize("--memory-budget", "64k"), size_t(64) << 10);
  for (const char* bad : {"", "x", "-5", "5X", "1e3", "nan", "M", ".5G", "99999999999999999999T"})
    EXPECT_THROW(wfapp::parseByteSize("--memory-budget", bad), wfapp::UsageError) << bad;
}

// A reader's result is served again (the gallery, wfapp::enableReaderCache) only for the same
// file as it is now: its key changes with the file's size, its modification time, the path, the
// reader and the reader's arguments, and there is none for a file that is not there.
TEST(RobustAppInput, ReaderResultKeyFollowsTheFileAndTheReader) {
  const fs::path dir = fs::temp_directory_path() / ("wirefur-reader-key-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path file = dir / "part.step";
  auto write = [&](const std::string& text) {
    std::ofstream f(file, std::ios::binary | std::ios::trunc);
    f << text;
  };
  write("ISO-10303-21;");
  wfapp::ReaderWorkerCall call;
  call.mode = "cad-worker";
  call.extra = {"0.1", "0"};
  const std::string k = wfapp::readerResultKey(file.string(), call);
  ASSERT_FALSE(k.empty());
  EXPECT_EQ(wfapp::readerResultKey(file.string(), call), k);  // the same file, the same key
  wfapp::ReaderWorkerCall other = call;
  other.extra[0] = "0.2";
  EXPECT_NE(wfapp::readerResultKey(file.string(), other), k);  // another deflection
  other = call;
  other.mode = "mesh-worker";
  EXPECT_NE(wfapp::readerResultKey(file.string(), other), k);  // another reader
  // The same file by another spelling of its path: another key (the result names the path).
  EXPECT_NE(wfapp::readerResultKey((dir / "." / "part.step").string(), call), k);
  // Another size.
  write("ISO-10303-21;\n");
  const std::string longer = wfapp::readerResultKey(file.string(), call);
  EXPECT_NE(longer, k);
  // The same size and contents, modified two seconds later (whole seconds: any file system's
  // clock tells them apart).
  fs::last_write_time(file, fs::last_write_time(file) + std::chrono::seconds(2));
  EXPECT_NE(wfapp::readerResultKey(file.string(), call), longer);
  fs::remove(file);
  EXPECT_TRUE(wfapp::readerResultKey(file.string(), call).empty());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace wf

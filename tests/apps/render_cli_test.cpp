// `wirefur render` as users and scripts call it (docs/cli.md): the stats keys of docs/design.md,
// one-line errors naming the file and the JSON pointer with exit status 2 and nothing written,
// determinism across thread counts, and the reference path.
#include "cli_support.h"
#include "core/sanitizers.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

using Result = wf::test::CliResult;
Result run(const std::string& args) { return wf::test::runWirefur(args); }

fs::path dir() { return wf::test::scratchDir("wirefur-render"); }
std::string write(const std::string& name, const std::string& text) { return wf::test::writeFile(dir(), name, text); }
std::string slurp(const fs::path& p) { return wf::test::readFile(p); }

int lines(const std::string& s) { return wf::test::lineCount(s); }

const std::string kScenes = std::string(WIREFUR_SOURCE_DIR) + "/data/scenes/";

}  // namespace

TEST(RenderCli, BuiltInSceneWritesPngAndTheContractsStatsKeys) {
  const fs::path png = dir() / "default.png", stats = dir() / "default.json";
  const Result r = run("render -o '" + png.string() + "' --size 160x120 --stats '" + stats.string() + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(png));
  const json s = json::parse(slurp(stats));
  // docs/design.md: seconds (total and per stage), segments, triangles, fragments,
  // max_fragments_per_pixel, peak_bytes, error_estimate.
  for (const char* k : {"seconds", "segments", "triangles", "fragments", "max_fragments_per_pixel", "peak_bytes", "error_estimate"})
    EXPECT_TRUE(s.contains(k)) << k;
  for (const char* k : {"total", "setup", "maps", "binning", "raster_resolve"}) EXPECT_TRUE(s["seconds"].contains(k)) << k;
  EXPECT_GT(s["segments"].get<int>(), 1000);   // the cage: 23 isolines of 96 segments
  EXPECT_GT(s["triangles"].get<int>(), 1000);  // the torus: 96 x 48 x 2
  // The default closed path: one material drawn as shaded wire, one lobe table; no maps, no
  // spheres; shading exact at every fragment's view vector but for the table's ~1e-9.
  EXPECT_EQ(s["options"]["shading"].get<std::string>(), "closed");
  EXPECT_EQ(s["left_out"]["lobe_tables_built"].get<int>(), 1);
  EXPECT_EQ(s["left_out"]["pseudo_reflectance_maps_built"].get<int>(), 0);
  EXPECT_EQ(s["left_out"]["reflectance_spheres_built"].get<int>(), 0);
  EXPECT_GT(s["error_estimate"]["shading_bound"].get<double>(), 0.0);
  EXPECT_LT(s["error_estimate"]["shading_bound"].get<double>(), 1e-7);
  EXPECT_DOUBLE_EQ(s["error_estimate"]["coverage_quantisation"].get<double>(), 1.0 / 32);  // 8x4 default
}

// Deep shares are on by default (the built-in cage over its torus: wires over a surface, so some
// pixels are deep) and --no-deep-shares turns them off: the stats say which and count the deep
// pixels, and the images differ; either flag with a value is refused with one line.
TEST(RenderCli, DeepSharesByDefaultAndOffOnRequest) {
  const fs::path on = dir() / "deep_on.json", off = dir() / "deep_off.json";
  ASSERT_EQ(run("render -o '" + (dir() / "deep_on.png").string() + "' --size 160x120 --stats '" + on.string() + "'").status, 0);
  ASSERT_EQ(run("render -o '" + (dir() / "deep_off.png").string() + "' --size 160x120 --no-deep-shares --stats '" + off.string() + "'").status, 0);
  const json a = json::parse(slurp(on)), b = json::parse(slurp(off));
  EXPECT_TRUE(a["options"]["deep_shares"].get<bool>());
  EXPECT_FALSE(b["options"]["deep_shares"].get<bool>());
  EXPECT_GT(a["left_out"]["pixels_deep"].get<std::uint64_t>(), 100u);
  EXPECT_EQ(b["left_out"]["pixels_deep"].get<std::uint64_t>(), 0u);
  EXPECT_NE(slurp(dir() / "deep_on.png"), slurp(dir() / "deep_off.png"));
  for (const char* flag : {"--no-deep-shares=yes", "--deep-shares=no"}) {
    const Result r = run("render -o '" + (dir() / "deep_bad.png").string() + "' " + flag);
    EXPECT_EQ(r.status, 2) << flag;
    EXPECT_EQ(r.err, "wirefur: option " + std::string(flag).substr(0, std::string(flag).find('=')) + " takes no value\n") << flag;
    EXPECT_FALSE(fs::exists(dir() / "deep_bad.png")) << flag;
  }
}

TEST(RenderCli, ViewGridBuildsOneMapPerNode) {
  const fs::path stats = dir() / "grid.json";
  const Result r = run("render -o '" + (dir() / "grid.png").string() + "' --size 160x120 --shading maps --view-grid 3 --stats '" +
                       stats.string() + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const json s = json::parse(slurp(stats));
  // 3 x 3 view directions: nine maps for the one wire material, nine spheres for the one surface.
  EXPECT_EQ(s["options"]["view_grid"].get<int>(), 3);
  EXPECT_EQ(s["left_out"]["pseudo_reflectance_maps_built"].get<int>(), 9);
  EXPECT_EQ(s["left_out"]["reflectance_spheres_built"].get<int>(), 9);
}

TEST(RenderCli, PlainWireSceneBuildsNoMap) {
  const fs::path stats = dir() / "plain.json";
  const Result r = run("render '" + kScenes + "cage_plain.json' -o '" + (dir() / "plain.png").string() +
                       "' --size 160x120 --stats '" + stats.string() + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const json s = json::parse(slurp(stats));
  // Plain wire needs no pseudo-reflectance map (it is not shaded as a cylinder).
  EXPECT_EQ(s["left_out"]["pseudo_reflectance_maps_built"].get<int>(), 0);
}

TEST(RenderCli, SameImageForAnyThreadCount) {
  const std::string scene = kScenes + "fur_torus.json";
  const fs::path a = dir() / "t1.png", b = dir() / "t2.png", c = dir() / "t16.png";
  ASSERT_EQ(run("render '" + scene + "' -o '" + a.string() + "' --size 240x180 --threads 1").status, 0);
  ASSERT_EQ(run("render '" + scene + "' -o '" + b.string() + "' --size 240x180 --threads 2").status, 0);
  ASSERT_EQ(run("render '" + scene + "' -o '" + c.string() + "' --size 240x180 --threads 16").status, 0);
  EXPECT_EQ(slurp(a), slurp(b));
  EXPECT_EQ(slurp(a), slurp(c));
}

TEST(RenderCli, MeasuredErrorAgainstTheReferenceIsSmall) {
  const fs::path stats = dir() / "measured.json";
  const Result r = run("render '" + kScenes + "cage_plain.json' -o '" + (dir() / "m.png").string() +
                       "' --size 120x90 --measure-error --samples 8 --stats '" + stats.string() + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const json s = json::parse(slurp(stats));
  const json& m = s["error_estimate"]["measured_against_reference"];
  // Plain wire and Phong surfaces, A-buffer vs 8x8 stratified reference: coverage error well
  // under the issue's 1/64 RMS target (exact areas; masks only decide hiding).
  EXPECT_LT(m["coverage_rms"].get<double>(), 1.0 / 64);
  EXPECT_GT(m["reference_seconds"].get<double>(), 0.0);
}

TEST(RenderCli, ReferenceRenderRuns) {
  const fs::path png = dir() / "ref.png";
  const Result r = run("render -o '" + png.string() + "' --size 64x48 --reference --samples 4");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(png));
}

// Bad input: one line naming the file and the place, exit status 2, and no output file.
TEST(RenderCli, BadScenesNameFileAndPointerAndWriteNothing) {
  struct Case {
    std::string name, text, expect;
  };
  const std::vector<Case> cases = {
      {"syntax.json", "{\n  \"objects\": [\n    {\"source\": }\n  ]\n}\n", "syntax.json:3:"},
      {"unknown.json", R"({"objects": [{"source": {"type": "torus", "radius": 1, "colour": 2}}]})", "/objects/0/source/colour"},
      {"badtype.json", R"({"objects": [{"source": {"type": "teapot"}}]})", "/objects/0/source/type"},
      {"range.json", R"({"image": {"size": [0, 10]}, "objects": [{"source": {"type": "sphere"}}]})", "/image/size/0"},
      {"mask.json", R"({"image": {"mask": "5x5"}, "objects": [{"source": {"type": "sphere"}}]})", "/image/mask"},
      {"material.json", R"({"objects": [{"source": {"type": "sphere"}, "surface": {"material": "gold"}}]})",
       "/objects/0/surface/material"},
      {"file.json", R"({"objects": [{"file": "no-such-file.vtp"}]})", "/objects/0/file"},
      {"empty.json", R"({"objects": []})", "/objects"},
      {"camera.json", R"({"camera": {"eye": [0,0,1], "target": [0,0,1]}, "objects": [{"source": {"type": "sphere"}}]})", "/camera"},
  };
  for (const Case& c : cases) {
    const std::string scene = write(c.name, c.text);
    const fs::path png = dir() / (c.name + ".png");
    const Result r = run("render '" + scene + "' -o '" + png.string() + "'");
    EXPECT_EQ(r.status, 2) << c.name << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1) << c.name << ": " << r.err;
    EXPECT_NE(r.err.find(c.name), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << "expected '" << c.expect << "' in: " << r.err;
    EXPECT_FALSE(fs::exists(png)) << c.name;
  }
}

TEST(RenderCli, BadOptionsAreExitTwo) {
  const fs::path png = dir() / "opt.png";
  for (const std::string& args : {std::string("render --mask 5x5 -o ") + png.string(), std::string("render --size 12 -o ") + png.string(),
                                  std::string("render"), std::string("render x.step -o ") + png.string(),
                                  std::string("render --style fluffy -o ") + png.string(),
                                  std::string("render --view-grid 0 -o ") + png.string()}) {
    const Result r = run(args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1) << args << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(png));
}

// --shading: closed (default), maps, exact; anything else is one line and exit 2. --view-grid
// belongs to the map path: with another one line of warning, the render still made.
TEST(RenderCli, ShadingPathsAndTheViewGridWarning) {
  const fs::path png = dir() / "paths.png", stats = dir() / "paths.json";
  for (const char* bad : {"--shading bogus", "--shading ''", "--shading MAPS", "--shading"}) {
    const Result r = run("render -o '" + png.string() + "' --size 64x48 " + bad);
    EXPECT_EQ(r.status, 2) << bad << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1) << bad << ": " << r.err;
    EXPECT_NE(r.err.find("--shading"), std::string::npos) << bad << ": " << r.err;
  }
  for (const std::string path : {"closed", "maps", "exact"}) {
    const Result r = run("render -o '" + png.string() + "' --size 64x48 --shading " + path + " --stats '" + stats.string() + "'");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_EQ(json::parse(slurp(stats))["options"]["shading"].get<std::string>(), path);
  }
  const Result warned = run("render -o '" + png.string() + "' --size 64x48 --view-grid 3");
  EXPECT_EQ(warned.status, 0) << warned.err;
  EXPECT_EQ(lines(warned.err), 1) << warned.err;
  EXPECT_NE(warned.err.find("view grid (3) belongs to --shading maps"), std::string::npos) << warned.err;
  const Result quiet = run("render -o '" + png.string() + "' --size 64x48 --shading maps --view-grid 3");
  EXPECT_EQ(quiet.status, 0) << quiet.err;
  EXPECT_EQ(quiet.err, "");
}

// --simplify and --wire-depth: out of range, not a number, NaN, Inf, empty: one line naming the
// option, exit 2, no PNG. In range: the stats say what was used, and how many hairs of how many
// were drawn (error_estimate.simplification).
// (fur_torus at 160 x 120 pixels is dense enough that some hairs are simplified: the smallest
// fraction is under 1, though with the fade every hair keeps some weight.)
TEST(RenderCli, SimplifyAndWireDepthOptions) {
  const fs::path png = dir() / "simplify.png";
  const std::string scene = "'" + kScenes + "fur_torus.json'";
  for (const char* badText : {"--simplify 0", "--simplify 0.05", "--simplify 65", "--simplify nan", "--simplify inf",
                                 "--simplify 1e400", "--simplify abc", "--simplify ''", "--simplify 2px", "--wire-depth square",
                                 "--wire-depth ''"}) {
    const std::string bad = badText;
    const Result r = run("render " + scene + " -o '" + png.string() + "' " + bad);
    EXPECT_EQ(r.status, 2) << bad << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1) << bad << ": " << r.err;
    EXPECT_NE(r.err.find(bad.substr(0, bad.find(' '))), std::string::npos) << bad << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(png));
  const fs::path stats = dir() / "simplify.json";
  const Result r = run("render " + scene + " -o '" + png.string() + "' --size 160x120 --simplify 2 --wire-depth flat --stats '" +
                       stats.string() + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const json j = json::parse(slurp(stats));
  EXPECT_EQ(j["options"]["wire_depth"], "flat");
  EXPECT_EQ(j["options"]["simplify"], 2.0);
  const json& e = j["error_estimate"]["simplification"];
  ASSERT_TRUE(e.is_object()) << j["error_estimate"].dump();
  EXPECT_EQ(e["hairs"], 7000);
  EXPECT_GT(e["drawn"].get<double>(), 0.0);
  EXPECT_LE(e["drawn"].get<double>(), 7000.0);
  EXPECT_GT(e["smallest_fraction"].get<double>(), 0.0);
  EXPECT_LT(e["smallest_fraction"].get<double>(), 1.0);
}

// --measure-error with --simplify: the simplification's own error, against its exact path (every
// hair drawn) rendered beside it. Both runs compare against the same reference, of every hair
// (review 56: it used to take --simplify too, so the simplified run measured against a simplified
// truth), and RMS over the same pixels is a norm: the three measured differences (simplified and
// full against the reference, simplified against full) satisfy the triangle inequality. Where
// nothing is simplified (a target width under every hair's) the exact path gives the same image
// to the bit: zero.
TEST(RenderCli, MeasureErrorGivesTheSimplificationsOwnError) {
  const std::string scene = "'" + kScenes + "fur_torus.json'";
  auto measured = [&](const std::string& name, const std::string& extra) {
    const fs::path stats = dir() / (name + ".json");
    const Result r = run("render " + scene + " -o '" + (dir() / (name + ".png")).string() +
                         "' --size 160x120 --measure-error --samples 4 " + extra + " --stats '" + stats.string() + "'");
    EXPECT_EQ(r.status, 0) << r.err;
    return json::parse(slurp(stats))["error_estimate"];
  };
  const json simplified = measured("simplified", "--simplify 3"), full = measured("full", ""),
             none = measured("none_simplified", "--simplify 0.1");
  ASSERT_TRUE(simplified["simplification"]["measured_against_full"].is_object()) << simplified.dump();
  EXPECT_FALSE(full.contains("simplification"));
  const double a = simplified["measured_against_reference"]["rgba_rms"].get<double>();
  const double b = full["measured_against_reference"]["rgba_rms"].get<double>();
  const double c = simplified["simplification"]["measured_against_full"]["rgba_rms"].get<double>();
  EXPECT_GT(c, 1e-4) << "fur_torus at 160x120 is dense enough that hairs are thinned out";
  EXPECT_LE(std::abs(a - b), c * (1 + 1e-9) + 1e-12);
  EXPECT_LE(c, (a + b) * (1 + 1e-9) + 1e-12);
  EXPECT_GT(simplified["simplification"]["measured_against_full"]["full_seconds"].get<double>(), 0.0);
  EXPECT_EQ(none["simplification"]["smallest_fraction"].get<double>(), 1.0);
  EXPECT_EQ(none["simplification"]["measured_against_full"]["rgba_rms"].get<double>(), 0.0);
  EXPECT_EQ(none["simplification"]["measured_against_full"]["coverage_max"].get<double>(), 0.0);
  // The reference is the same for every run (of every hair, by the exact path): the same error
  // for the full render with and without the (inert) simplification.
  EXPECT_EQ(none["measured_against_reference"]["rgba_rms"].get<double>(), b);
}

// NaN / Inf vertices (a binary STL, where they survive the reader): the bad triangles and the
// wire segments touching them are skipped with one warning line per object naming the file,
// and the rest renders.
TEST(RenderCli, NonFiniteVerticesAreSkippedWithAWarning) {
  std::string stl(80, '\0');
  auto u32 = [&](uint32_t v) { stl.append(reinterpret_cast<const char*>(&v), 4); };
  auto f32 = [&](float v) { stl.append(reinterpret_cast<const char*>(&v), 4); };
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const float tris[3][9] = {{0, 0, 0, 1, 0, 0, 0, 1, 0}, {nan, 0, 0, 1, 1, 0, 0, 1, 1}, {2, 0, 0, 3, inf, 0, 2, 1, 0}};
  u32(4);
  for (int t = 0; t < 4; ++t) {
    for (int k = 0; k < 3; ++k) f32(k == 2 ? 1.0f : 0.0f);  // facet normal
    for (int k = 0; k < 9; ++k) f32(t < 3 ? tris[t][k] : float(k % 3 == 0 ? 4 + k / 3 : (k % 3 == 1 ? (k / 3 == 1) : 0)));
    stl.append(2, '\0');
  }
  const std::string file = write("nan.stl", stl);
  const fs::path png = dir() / "nan.png", stats = dir() / "nan.json";
  const Result r = run("render '" + file + "' -o '" + png.string() + "' --size 64x64 --stats '" + stats.string() + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(png));
  EXPECT_EQ(lines(r.err), 2) << r.err;  // one for the surface, one for its wire-frame
  EXPECT_NE(r.err.find("non-finite"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("nan.stl"), std::string::npos) << r.err;
  const json s = json::parse(slurp(stats));
  EXPECT_EQ(s["triangles"].get<int>(), 2);  // the two finite triangles are drawn
  EXPECT_GE(s["input"]["rejected_non_finite"].get<int>(), 2);
}

// A text file the reader cannot parse is bad input: one line, exit 2, nothing written.
TEST(RenderCli, UnreadableMeshFileIsExitTwo) {
  const std::string vtk = write("broken.vtk",
                                "# vtk DataFile Version 3.0\nbroken\nASCII\nDATASET POLYDATA\nPOINTS 2 float\n"
                                "0 0 0\nnan 1 0\nLINES 1 3\n2 0 1\n");
  const fs::path png = dir() / "broken.png";
  const Result r = run("render '" + vtk + "' --style wire -o '" + png.string() + "'");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("broken.vtk"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(png));
}

// Malformed mesh files that once crashed VTK's filters or readers, or rendered silently: each is
// bad input now, one line, exit 2, nothing written (found by the apps review).
TEST(RenderCli, MalformedMeshFilesAreBadInputNotCrashes) {
  std::string stl(80, '\0');
  const uint32_t declared = 10;
  stl.append(reinterpret_cast<const char*>(&declared), 4);
  stl.append(2 * 50 + 3, '\0');  // two triangles and stray bytes, where ten were declared
  const std::vector<std::pair<std::string, std::string>> files = {
      {"oob.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n"},
      {"oob.vtk", "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 1 88\n"},
      {"short.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1\n"},
      {"trunc.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 1000000\nproperty float x\nend_header\n\x01\x02"},
      {"trunc.stl", stl},
  };
  for (const auto& [name, text] : files) {
    const std::string file = write(name, text);
    const fs::path png = dir() / (name + ".png");
    const Result r = run("render '" + file + "' -o '" + png.string() + "'");
    EXPECT_EQ(r.status, 2) << name << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1) << name << ": " << r.err;
    EXPECT_NE(r.err.find(name), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(png)) << name;
  }
}

TEST(RenderCli, UnwritableOutputsAndOutOfRangeNumbersAreBadInput) {
  fs::create_directories(dir() / "a-folder.png");
  const std::string scene = write("ok.json", R"({"objects": [{"source": {"type": "sphere"}}]})");
  for (const std::string& args : {"render '" + scene + "' -o '" + (dir() / "a-folder.png").string() + "'",
                                  "render '" + scene + "' -o '" + (dir() / "x.png").string() + "' --stats '" + dir().string() + "'",
                                  "render '" + write("huge.json", R"({"objects": [{"source": {"type": "sphere", "radius": 1e400}}]})") +
                                      "' -o '" + (dir() / "y.png").string() + "'"}) {
    const Result r = run(args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1) << r.err;
  }
  EXPECT_FALSE(fs::exists(dir() / "x.png"));
  EXPECT_FALSE(fs::exists(dir() / "y.png"));
}

// The memory estimate the command checks --memory-budget against (stats "memory") bounds the
// peak resident memory it then measures (getrusage), from 512^2 to 8192^2 and with the second
// and third images of --measure-error; and it is a bound, not a guess far above: within 1.5 x
// the peak plus 64 MiB.
TEST(RenderCli, MemoryEstimateBoundsThePeak) {
#if defined(WF_UNDER_ASAN)
  GTEST_SKIP() << "AddressSanitizer's shadow memory and quarantine are not the command's";
#endif
  struct Case {
    int size;
    std::string extra;
  };
  const Case cases[] = {{512, ""}, {1024, ""}, {2048, ""}, {4096, ""}, {8192, ""},
                        {1024, "--measure-error --samples 2"}, {1024, "--measure-error --samples 2 --simplify 3"},
                        {1024, "--reference --samples 2"}};
  const double machine = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE));
  for (const Case& c : cases) {
    // 8192^2 holds about 1.3 GiB: within the default budget (half the memory) from 4 GiB up.
    if (double(c.size) * c.size * 40.0 > 0.4 * machine) continue;
    const fs::path png = dir() / "memory.png", stats = dir() / "memory.json";
    const std::string size = std::to_string(c.size) + "x" + std::to_string(c.size);
    const Result r = run("render -o '" + png.string() + "' --size " + size + " " + c.extra + " --stats '" + stats.string() + "'");
    ASSERT_EQ(r.status, 0) << r.err;
    const json m = json::parse(slurp(stats))["memory"];
    const double estimate = m["estimate_bytes"].get<double>(), peak = m["peak_rss_bytes"].get<double>();
    EXPECT_GE(estimate, peak) << size << " " << c.extra;
    EXPECT_LE(estimate, 1.5 * peak + 64.0 * (1 << 20)) << size << " " << c.extra;
  }
}

// The same where the primitives and their tile items, not the fixed costs, are most of it: the
// furry torus with 240,000 thin hairs (about five tile items a hair), alone and with the three
// further renders of --measure-error --simplify made in turn (each one's memory given back
// before the next, so that the estimate is the largest stage, not their sum).
TEST(RenderCli, MemoryEstimateBoundsTheDenseFursPeak) {
#if defined(WF_UNDER_ASAN)
  GTEST_SKIP() << "AddressSanitizer's shadow memory and quarantine are not the command's";
#endif
  json scene = json::parse(slurp(kScenes + "fur_torus.json"));
  scene["objects"][0]["fur"]["grid"] = {600, 400};
  scene["objects"][0]["fur"]["thickness"] = 0.004;
  const std::string path = write("dense_fur.json", scene.dump());
  const fs::path png = dir() / "dense.png", stats = dir() / "dense.json";
  double plain = 0.0;
  for (const std::string extra : {"", "--measure-error --samples 2 --simplify 3"}) {
    const Result r = run("render '" + path + "' -o '" + png.string() + "' --size 1024x768 " + extra + " --stats '" +
                         stats.string() + "'");
    ASSERT_EQ(r.status, 0) << r.err;
    const json m = json::parse(slurp(stats))["memory"];
    const double estimate = m["estimate_bytes"].get<double>(), peak = m["peak_rss_bytes"].get<double>();
    EXPECT_GE(estimate, peak) << extra;
    EXPECT_LE(estimate, 1.5 * peak + 64.0 * (1 << 20)) << extra;
    if (extra.empty()) plain = estimate;
    // Three more renders, each with its image kept: less than twice the render alone (the sum
    // of the four renders' working memory, as the estimate once was, is over three times it).
    else EXPECT_LT(estimate, 2.0 * plain);
  }
  // A budget a little under that estimate: the render keeps to it (it is given what the command
  // leaves, and bins its tile items in bands to fit) rather than being refused, as it was when
  // each render was given the whole budget.
  const std::uint64_t budget = std::uint64_t(plain) - (std::uint64_t(3) << 20);
  const Result tight = run("render '" + path + "' -o '" + png.string() + "' --size 1024x768 --memory-budget " +
                           std::to_string(budget) + " --stats '" + stats.string() + "'");
  ASSERT_EQ(tight.status, 0) << tight.err;
  const json m = json::parse(slurp(stats))["memory"];
  EXPECT_LE(m["estimate_bytes"].get<double>(), double(budget));
  EXPECT_LE(m["peak_rss_bytes"].get<double>(), double(budget));
}

// The wirefur command as users and scripts call it: exit codes, one-line errors, the files it
// promises, and the numbers in its reports against what the shading core must reach.
#include "cli_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

using Result = wf::test::CliResult;
Result run(const std::string& args) { return wf::test::runWirefur(args); }
using wf::test::lineCount;

fs::path freshDir(const std::string& name) {
  const fs::path d = wf::test::processScratchRoot() / name;
  fs::remove_all(d);
  return d;
}

bool isPng(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  char sig[8] = {};
  f.read(sig, 8);
  return f && std::string(sig + 1, 3) == "PNG" && fs::file_size(p) > 1000;
}


}  // namespace

// Bad input: one line on stderr naming the problem, exit status 2, nothing written.
TEST(Cli, UnknownCommandAndOptionsExitTwoWithOneLine) {
  for (const char* args : {"frobnicate", "accuracy --bogus", "gallery --size abc", "gallery --size 0",
                           "gallery --size 99999999", "gallery -o", "accuracy --json"}) {
    const Result r = run(args);
    EXPECT_EQ(r.status, 2) << args;
    EXPECT_EQ(lineCount(r.err), 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find("wirefur:"), std::string::npos) << args;
  }
}

TEST(Cli, UnwritableOutputDirectoryIsBadInput) {
  const Result r = run("gallery -o /proc/wirefur-cannot-exist");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(lineCount(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("/proc/wirefur-cannot-exist"), std::string::npos);
}

TEST(Cli, HelpAndVersionSucceed) {
  EXPECT_EQ(run("--help").status, 0);
  EXPECT_EQ(run("--version").status, 0);
}

// The quick accuracy study: the JSON holds every knob's error and time, and the numbers are
// those the shading core promises (docs/shading.md).
TEST(Cli, AccuracyQuickWritesJsonAndPlotsWithExpectedErrors) {
  const fs::path dir = freshDir("accuracy");
  const Result r = run("accuracy --quick --quiet --json '" + (dir / "acc.json").string() + "' --plots '" +
                       (dir / "plots").string() + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* p : {"map_resolution.png", "map_samples.png", "cost_per_fragment.png", "orthographic.png"})
    EXPECT_TRUE(isPng(dir / "plots" / p)) << p;
  std::ifstream f(dir / "acc.json");
  const json doc = json::parse(f);
  double warped128 = -1, warped32 = -1, paperCap128 = -1, warpedCap128 = -1;
  for (const json& p : doc.at("resolution_sweep")) {
    EXPECT_GT(p.at("build_ms_7_lights_n100").get<double>(), 0.0);
    const std::string ix = p.at("indexing");
    const int res = p.at("resolution");
    if (ix == "warped" && res == 128) {
      warped128 = p.at("max_error_n_le_128");
      warpedCap128 = p.at("max_error_end_on_cap");
    }
    if (ix == "warped" && res == 32) warped32 = p.at("max_error_n_le_128");
    if (ix == "paper" && res == 128) paperCap128 = p.at("max_error_end_on_cap");
  }
  // The target: a warped 128^2 map with 64 samples stays within 2e-3 of the exact cylinder
  // average for exponents <= 128 (measured 7.7e-4), and resolution buys accuracy.
  EXPECT_GT(warped128, 0.0);
  EXPECT_LT(warped128, 2e-3);
  EXPECT_GT(warped32, warped128);
  // Why the warped indexing is the default: near the view axis the paper's (x, z) map is off
  // by ~0.2 at 128^2 while the warped map stays below 2e-3.
  EXPECT_GT(paperCap128, 0.05);
  EXPECT_LT(warpedCap128, 2e-3);
  // The lookup is much cheaper than the exact path (the issue asks for >= 50x).
  const double exactNs = doc.at("exact_cost")[2].at("exact_ns_per_fragment");
  for (const json& l : doc.at("lookup_cost")) EXPECT_GT(exactNs / l.at("lookup_ns_per_fragment").get<double>(), 50.0);
  // Reflectance spheres: at 256^2 the warped table beats Williams' (nx, ny) table (measured RMS
  // 1.0e-4 vs 2.6e-4, max 5.1e-3 vs 9.3e-3), and resolution buys accuracy.
  double warped256 = -1, williams256 = -1, warped64 = -1;
  for (const json& p : doc.at("reflectance_sphere").at("sweep")) {
    const std::string ix = p.at("indexing");
    const int res = p.at("resolution");
    if (res == 256) (ix == "warped" ? warped256 : williams256) = p.at("rms_error");
    if (res == 64 && ix == "warped") warped64 = p.at("rms_error");
  }
  EXPECT_GT(warped256, 0.0);
  EXPECT_LT(warped256, williams256);
  EXPECT_LT(warped256, warped64);
  EXPECT_TRUE(isPng(dir / "plots" / "reflectance_sphere.png"));
  // The orthographic assumption's error grows with the field of view.
  double prev = 0.0;
  for (const json& o : doc.at("orthographic_assumption"))
    if (o.at("exponent") == 10.0) {
      const double e = o.at("rms_error_orthographic");
      EXPECT_GT(e, prev) << "fov " << o.at("fov_deg");
      prev = e;
    }
  // The A-buffer study: both scenes, every mask; with K = 64 the RGBA error against the 16x16
  // reference is well under 1/64 (measured 2-4e-3), and a budget of K = 2 is clearly worse
  // (its tail blends what should be ordered). The reference's own noise is below what it measures.
  for (const char* scene : {"lines", "triangles"}) {
    const json& a = doc.at("abuffer").at(scene);
    double k64 = -1, k2 = -1;
    for (const json& p : a.at("sweep")) {
      if (p.at("mask") != "8x4") continue;
      if (p.at("budget") == 64) k64 = p.at("rgba_rms");
      if (p.at("budget") == 2) k2 = p.at("rgba_rms");
    }
    EXPECT_GT(k64, 0.0) << scene;
    EXPECT_LT(k64, 1.0 / 64) << scene;
    EXPECT_GT(k2, 1.5 * k64) << scene;
    EXPECT_LT(a.at("reference_noise_rms").get<double>(), k64) << scene;
    EXPECT_TRUE(isPng(dir / "plots" / (std::string("abuffer_") + scene + ".png"))) << scene;
  }
  fs::remove_all(dir);
}

TEST(Cli, GalleryWritesEveryPictureWithTimeAndError) {
  const fs::path dir = freshDir("gallery");
  // (Its summary line kept: stdout into a file by a shell of its own.)
  const fs::path out = dir.parent_path() / "gallery_stdout.txt";
  const Result r = wf::test::runCommand(std::string("sh -c \"'") + WIREFUR_EXE + "' gallery --quiet --size 64 -o '" +
                                        dir.string() + "' > '" + out.string() + "'\"");
  ASSERT_EQ(r.status, 0) << r.err;
  {
    // Four scenes draw data/cad/product.step, one with data/cad/mould.step: two reader
    // workers, and the part's result served again to the three others (wfapp::enableReaderCache).
    std::ifstream s(out);
    std::stringstream text;
    text << s.rdbuf();
    EXPECT_NE(text.str().find("2 reader workers, 3 results read again from memory"), std::string::npos) << text.str();
  }
  fs::remove(out);
  std::ifstream f(dir / "gallery.json");
  const json doc = json::parse(f);
  ASSERT_GE(doc.size(), 4u);
  std::ifstream h(dir / "index.html");
  std::stringstream html;
  html << h.rdbuf();
  int renders = 0;
  for (const json& e : doc) {
    const std::string file = e.at("file");
    EXPECT_TRUE(isPng(dir / file)) << file;
    EXPECT_NE(html.str().find(file), std::string::npos) << file;
    EXPECT_FALSE(e.at("error_estimate").get<std::string>().empty()) << file;
    EXPECT_GE(e.at("seconds").get<double>(), 0.0);
    // Every scene's render: shading within 2e-3 of exact per-fragment shading at each
    // fragment's own view vector (the default closed path: the lobe tables' ~1e-9).
    if (e.contains("stats")) {
      ++renders;
      EXPECT_EQ(e["stats"]["options"]["shading"], "closed") << file;
      EXPECT_LE(e["stats"]["error_estimate"]["shading_bound"].get<double>(), 2e-3) << file;
    }
  }
  EXPECT_GE(renders, 20);
  fs::remove_all(dir);
}

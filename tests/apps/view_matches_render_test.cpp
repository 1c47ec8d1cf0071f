// `wirefur view` draws what `wirefur render` draws (docs/vtk.md, "The viewer"): the viewer's first
// frame (the scene's own camera) against the command's image of the same scene and size, RGB RMS
// in linear light over the image above the viewer's two caption lines, on the scenes whose looks
// the viewer used to lose (burnish grain, chrome, a CAD part, fur, scales). The viewer runs under
// its own Xvfb (xvfb-run), offscreen.
#include "cli_support.h"

#include "image_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace fs = std::filesystem;

namespace {

const std::string kScenes = std::string(WIREFUR_SOURCE_DIR) + "/data/scenes/";

bool haveXvfbRun() { return std::system("command -v xvfb-run >/dev/null 2>&1") == 0; }

TEST(ViewMatchesRender, SameSceneSameImage) {
  if (!haveXvfbRun()) GTEST_SKIP() << "xvfb-run is not installed";
  const fs::path d = wf::test::processScratchRoot() / "view-matches-render";
  fs::create_directories(d);
  const int W = 400, H = 300, caption = 44;  // the caption's two lines of 14 px text, and margins
  for (const std::string scene : {"jug_burnished", "jug_chrome", "mould_cad", "fur_torus", "scaly_torus"}) {
    SCOPED_TRACE(scene);
    const std::string file = kScenes + scene + ".json", v = (d / (scene + "_view.png")).string(),
                      r = (d / (scene + "_render.png")).string();
    const std::string size = std::to_string(W) + "x" + std::to_string(H);
    const wf::test::CliResult vr = wf::test::runCommand(
        "xvfb-run -a -s '-screen 0 1024x768x24 -noreset' '" + std::string(WIREFUR_EXE) + "' view '" + file +
        "' --offscreen --frames 1 --png '" + v + "' --size " + size);
    ASSERT_EQ(vr.status, 0) << vr.err;
    const wf::test::CliResult rr = wf::test::runWirefur("render '" + file + "' -o '" + r + "' --size " + size + " --quiet");
    ASSERT_EQ(rr.status, 0) << rr.err;
    const wf::ImageRGBA a = wfapp::readPng(v), b = wfapp::readPng(r);
    ASSERT_EQ(a.width, W);
    ASSERT_EQ(b.width, W);
    ASSERT_EQ(a.height, H);
    double sum = 0.0, signal = 0.0;
    for (int y = 0; y < H - caption; ++y)
      for (int x = 0; x < W; ++x)
        for (int k = 0; k < 3; ++k) {
          const double e = double(a.at(x, y)[k]) - double(b.at(x, y)[k]);
          sum += e * e;
          signal += double(b.at(x, y)[k]);
        }
    const double rms = std::sqrt(sum / (3.0 * W * (H - caption)));
    EXPECT_LE(rms, 1e-2) << "viewer against render";
    EXPECT_GT(signal / (3.0 * W * (H - caption)), 0.01) << "the render drew something";
    std::printf("%s: view against render RMS %.3g\n", scene.c_str(), rms);
  }
}

}  // namespace

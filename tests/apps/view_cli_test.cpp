// `wirefur view` where no X display can be opened: one line saying so, exit status 1, never the
// abort VTK 9.1 ends in when its X window finds no display; bad input is still exit 2 first.
#include "cli_support.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

namespace {

const std::string kScenes = std::string(WIREFUR_SOURCE_DIR) + "/data/scenes/";

TEST(ViewCli, NoDisplayIsOneLineNotAnAbort) {
  const char* old = std::getenv("DISPLAY");
  const std::string saved = old ? old : "";
  setenv("DISPLAY", ":977", 1);  // no X server there
  const wf::test::CliResult r = wf::test::runWirefur("view '" + kScenes + "fur_torus.json' --offscreen --frames 1");
  const wf::test::CliResult bad = wf::test::runWirefur("view '" + kScenes + "no_such_scene.json' --offscreen --frames 1");
  if (old) setenv("DISPLAY", saved.c_str(), 1);
  else unsetenv("DISPLAY");
  EXPECT_EQ(r.status, 1) << r.err;  // not -1 (killed by SIGABRT)
  EXPECT_EQ(wf::test::lineCount(r.err), 1) << r.err;
  EXPECT_EQ(bad.status, 2) << bad.err;
  EXPECT_EQ(wf::test::lineCount(bad.err), 1) << bad.err;
}

}  // namespace

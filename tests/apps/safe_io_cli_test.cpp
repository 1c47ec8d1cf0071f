// What a shell can hand `wirefur render` besides good files (apps/safe_files.h, apps/reader_worker.h):
// FIFOs and devices as inputs, textures, mesh files and outputs; a reader that crashes in its
// worker; a command stopped while it writes; four commands writing one path at once; scenes that
// draw nothing. Each must end in one line and a defined state: exit 2 and no image, or one whole
// image, and nothing left behind.
#include "cli_support.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;
using wf::test::lineCount;
using wf::test::runWirefur;

namespace {

bool isFifo(const fs::path& p) {
  struct stat st;
  return lstat(p.c_str(), &st) == 0 && S_ISFIFO(st.st_mode);
}

// A PNG is whole when it starts with the signature and ends with the IEND chunk.
bool wholePng(const fs::path& p) {
  const std::string b = wf::test::readFile(p);
  static const std::string sig("\x89PNG\r\n\x1a\n", 8);
  static const std::string iend("IEND\xae\x42\x60\x82", 8);
  return b.size() > 64 && b.compare(0, 8, sig) == 0 && b.compare(b.size() - 8, 8, iend) == 0;
}

std::vector<std::string> leftovers(const fs::path& dir, const std::string& part) {
  std::vector<std::string> found;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().find(part) != std::string::npos) found.push_back(e.path().filename().string());
  return found;
}

}  // namespace

// A FIFO as the scene, as a mesh file a scene names, as a texture, and as the mesh given
// directly: refused at once (a read would block for ever), one line, exit 2, no image.
TEST(SafeIo, FifosAreRefusedAtOnce) {
  const fs::path dir = wf::test::scratchDir("wirefur-safe-fifo");
  ASSERT_EQ(mkfifo((dir / "pipe.json").c_str(), 0600), 0);
  ASSERT_EQ(mkfifo((dir / "pipe.obj").c_str(), 0600), 0);
  ASSERT_EQ(mkfifo((dir / "pipe.png").c_str(), 0600), 0);
  wf::test::writeFile(dir, "mesh.json", R"({"objects": [{"file": "pipe.obj"}]})");
  wf::test::writeFile(dir, "texture.json", R"({"materials": {"m": {"texture": {"type": "image", "file": "pipe.png"}}},
    "objects": [{"source": {"type": "sphere"}, "surface": {"material": "m"}}]})");
  const fs::path png = dir / "out.png";
  for (const char* input : {"pipe.json", "mesh.json", "texture.json", "pipe.obj"}) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto r = runWirefur("render '" + (dir / input).string() + "' -o '" + png.string() + "'");
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(r.status, 2) << input << ": " << r.err;
    EXPECT_EQ(lineCount(r.err), 1) << input << ": " << r.err;
    EXPECT_NE(r.err.find("is a FIFO, not a regular file"), std::string::npos) << input << ": " << r.err;
    EXPECT_LT(s, 10.0) << input;
    EXPECT_FALSE(fs::exists(png)) << input;
  }
  EXPECT_TRUE(leftovers(dir, ".tmp").empty());  // nor a temporary of the output
}

// A device behind an input's name (a link to /dev/zero would be read without end).
TEST(SafeIo, DevicesAreRefusedAsInputs) {
  const fs::path dir = wf::test::scratchDir("wirefur-safe-device-in");
  fs::create_symlink("/dev/zero", dir / "zero.obj");
  fs::create_symlink("/dev/urandom", dir / "random.json");
  for (const char* input : {"zero.obj", "random.json"}) {
    const auto r = runWirefur("render '" + (dir / input).string() + "' -o '" + (dir / "out.png").string() + "'");
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(lineCount(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("is a character device, not a regular file"), std::string::npos) << r.err;
  }
}

// Outputs that exist and are not regular files are not replaced: a FIFO as -o and as --stats,
// and a link to a character device. (Run as root, a rename onto the name replaced the device.)
TEST(SafeIo, OutputsThatAreNotRegularFilesAreLeftAlone) {
  const fs::path dir = wf::test::scratchDir("wirefur-safe-device-out");
  ASSERT_EQ(mkfifo((dir / "fifo.png").c_str(), 0600), 0);
  ASSERT_EQ(mkfifo((dir / "fifo.json").c_str(), 0600), 0);
  fs::create_symlink("/dev/null", dir / "null.png");
  const std::string ok = (dir / "ok.png").string();
  const std::pair<std::string, std::string> cases[] = {
      {"-o '" + (dir / "fifo.png").string() + "'", "fifo.png: is a FIFO, not a regular file: not replaced"},
      {"-o '" + ok + "' --stats '" + (dir / "fifo.json").string() + "'", "fifo.json: is a FIFO"},
      {"-o '" + (dir / "null.png").string() + "'", "null.png: is a character device, not a regular file: not replaced"},
  };
  for (const auto& [args, expect] : cases) {
    const auto r = runWirefur("render --size 32x24 " + args);
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(lineCount(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(expect), std::string::npos) << r.err;
  }
  EXPECT_TRUE(isFifo(dir / "fifo.png"));
  EXPECT_TRUE(isFifo(dir / "fifo.json"));
  EXPECT_TRUE(fs::is_symlink(dir / "null.png"));
  EXPECT_TRUE(fs::is_character_file(dir / "null.png"));
  EXPECT_FALSE(fs::exists(ok));  // both or neither
  EXPECT_TRUE(leftovers(dir, ".tmp").empty());
}

// VTK 9.1's legacy reader dies on a FIELD line with nothing after it (SIGSEGV in
// vtkPolyDataReader, found by fuzz_mesh): in the mesh worker that is one line and exit 2, with no
// image, given directly and named by a scene.
TEST(SafeIo, AReaderCrashInTheWorkerIsOneLine) {
  const fs::path dir = wf::test::scratchDir("wirefur-safe-crash");
  const std::string crash = std::string(WIREFUR_SOURCE_DIR) + "/tests/apps/mesh_regressions/vtk_field_without_name.vtk";
  wf::test::writeFile(dir, "scene.json", R"({"objects": [{"file": ")" + crash + R"("}]})");
  const fs::path png = dir / "out.png";
  for (const std::string& input : {crash, (dir / "scene.json").string()}) {
    const auto r = runWirefur("render '" + input + "' -o '" + png.string() + "'");
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(lineCount(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("vtk_field_without_name.vtk: VTK's reader crashed reading this file ("), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(png));
  }
}

// SIGTERM while the PNG is being written (its temporary exists): the command dies of the signal
// and leaves neither the image nor its temporary.
TEST(SafeIo, StoppedWhileWritingLeavesNothing) {
  const fs::path dir = wf::test::scratchDir("wirefur-safe-sigterm");
  const fs::path png = dir / "big.png";
  // 4096 x 4096: tens of milliseconds of encoding, polled every 0.2 ms.
  const pid_t pid = wf::test::spawnWirefur({"render", "--size", "4096x4096", "--threads", "1", "-o", png.string()});
  ASSERT_GT(pid, 0);
  wf::test::ProcessGuard guard{pid};
  bool seen = false;
  int status = 0;
  for (int i = 0; i < 600000 && !seen; ++i) {
    seen = !leftovers(dir, ".tmp").empty();
    if (!seen) {
      if (waitpid(pid, &status, WNOHANG) == pid) {  // finished before we saw it
        guard.pid = -1;
        break;
      }
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
  }
  ASSERT_TRUE(seen) << "the temporary output never appeared";
  kill(pid, SIGTERM);
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  guard.pid = -1;
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << status;
  EXPECT_FALSE(fs::exists(png));
  EXPECT_TRUE(leftovers(dir, ".tmp").empty());
}

// Four renders writing one path at once: every one exits 0 and the path holds one whole PNG (each
// writes its own temporary and renames it; the last rename wins).
TEST(SafeIo, ConcurrentRendersToOnePathLeaveOneWholeImage) {
  const fs::path dir = wf::test::scratchDir("wirefur-safe-concurrent");
  const fs::path png = dir / "same.png";
  for (int round = 0; round < 3; ++round) {
    wf::test::ProcessGuard guards[4];
    for (int i = 0; i < 4; ++i)
      guards[i].pid = wf::test::spawnWirefur({"render", "--size", i % 2 ? "640x480" : "320x240", "--threads", "1", "-o", png.string()});
    for (wf::test::ProcessGuard& g : guards) {
      int status = 0;
      ASSERT_EQ(waitpid(g.pid, &status, 0), g.pid);
      g.pid = -1;
      EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
    }
    EXPECT_TRUE(wholePng(png)) << "round " << round;
    EXPECT_TRUE(leftovers(dir, ".tmp").empty());
  }
}

// Scenes that draw nothing. Nothing could be drawn (a triangle of three equal points; vertices at
// 1e308, which no camera frames): exit 2, one line, no image. A camera of the scene's that looks
// away from it: a warning, and the background is written.
TEST(SafeIo, ARenderThatDrawsNothingSaysSo) {
  const fs::path dir = wf::test::scratchDir("wirefur-safe-empty");
  wf::test::writeFile(dir, "equal.obj", "v 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\n");
  wf::test::writeFile(dir, "huge.obj", "v 1e308 0 0\nv 0 1e308 0\nv 0 0 1e308\nf 1 2 3\n");
  const fs::path png = dir / "out.png";
  for (const std::string input : {"equal.obj", "huge.obj"}) {
    const auto r = runWirefur("render '" + (dir / input).string() + "' -o '" + png.string() + "'");
    EXPECT_EQ(r.status, 2) << input << ": " << r.err;
    EXPECT_EQ(lineCount(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(input + ": nothing could be drawn"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(png)) << input;
  }
  EXPECT_TRUE(leftovers(dir, ".tmp").empty());
  wf::test::writeFile(dir, "away.json", R"({"camera": {"eye": [0, 0, 5], "target": [0, 0, 10], "up": [0, 1, 0]},
    "objects": [{"source": {"type": "sphere"}}]})");
  const auto r = runWirefur("render '" + (dir / "away.json").string() + "' -o '" + png.string() + "'");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(lineCount(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("warning: " + (dir / "away.json").string() + ": nothing was drawn"), std::string::npos) << r.err;
  EXPECT_TRUE(wholePng(png));
}

// A .vtp whose array claims 2e9 components ran 150 s up to 15.7 GB before its exit 2, and one
// claiming -3 ended as "internal error" (exit 1): both are bad input, refused at once (exit 2,
// one line) once VTK's reader asks for what no array can hold. The worker's cap is set to 4 GB
// here, so that the test does not depend on the machine's memory (VTK's reader value-initialises
// a std::vector<double> of 2e9 entries, 16 GB, within a cap of 16 GiB).
TEST(SafeIo, AbsurdComponentCountsAreBadInputAtOnce) {
  const fs::path dir = wf::test::scratchDir("wirefur-safe-components");
  const fs::path vtp = dir / "scene.vtp";
  const auto e = runWirefur("export '" + std::string(WIREFUR_SOURCE_DIR) + "/data/scenes/cage_shaded.json' -o '" + vtp.string() + "' --quiet");
  ASSERT_EQ(e.status, 0) << e.err;
  const std::string bytes = wf::test::readFile(vtp);
  const std::string three = "NumberOfComponents=\"3\"";
  const size_t at = bytes.find(three);
  ASSERT_NE(at, std::string::npos);
  for (const std::string count : {"2000000000", "-3"}) {
    const std::string name = "components" + count + ".vtp";
    std::string changed = bytes;
    changed.replace(at, three.size(), "NumberOfComponents=\"" + count + "\"");
    wf::test::writeFile(dir, name, changed);
    const auto t0 = std::chrono::steady_clock::now();
    const auto r = wf::test::runCommand(std::string("WIREFUR_WORKER_MEMORY_CAP=4000000000 '") + WIREFUR_EXE +
                                        "' render '" + (dir / name).string() + "' -o '" + (dir / "out.png").string() + "'");
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(r.status, 2) << name << ": " << r.err;
    EXPECT_EQ(lineCount(r.err), 1) << r.err;
    // VTK's reader refuses the count, or asks for more than the worker's cap (under
    // AddressSanitizer too: its options carry the cap, src/core/worker_process.cpp).
    EXPECT_TRUE(r.err.find(name + ": the file's counts") != std::string::npos ||
                r.err.find(name + ": out of memory in the mesh worker") != std::string::npos)
        << r.err;
    EXPECT_LT(s, 20.0) << name;
    EXPECT_FALSE(fs::exists(dir / "out.png"));
  }
}

// Scene-file keys of the surface, texture, burnish and growth issue, through `wirefur render`.
//
// The contract (docs/design.md, docs/cli.md, docs/scenes.md): bad input gets ONE line on stderr naming
// the file, the JSON pointer and the problem, exit status 2, and nothing written (no PNG, no
// stats); never a crash, never a hang, never an enormous allocation, never a silent empty image;
// the same input gives the same image bit for bit for any --threads. Positive cases check the
// numbers the stats must show (segments per hair, triangles per scale, maps and spheres built).
#include "cli_support.h"
#include "core/sanitizers.h"
#include "core/timer.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

using Result = wf::test::CliResult;

const std::string kScenes = std::string(WIREFUR_SOURCE_DIR) + "/data/scenes/";

// Each test writes into its own folder, named after the test.
fs::path testDir() {
  const ::testing::TestInfo* t = ::testing::UnitTest::GetInstance()->current_test_info();
  return wf::test::scratchDir(std::string(t->test_suite_name()) + "." + t->name());
}

std::string write(const fs::path& d, const std::string& name, const std::string& bytes) { return wf::test::writeFile(d, name, bytes); }
std::string slurp(const fs::path& p) { return wf::test::readFile(p); }

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

Result run(const std::string& args) { return wf::test::runWirefur(args); }

// Runs wirefur with the address space capped (KiB) and a wall-clock limit, so that a scene that
// would allocate tens of GB or run for minutes fails the test instead of the machine. A run
// killed by `timeout` has status 124.
// Under AddressSanitizer (WIREFUR_SANITIZE builds every target with it) the shadow memory needs
// terabytes of address space, so only the time limit applies there.
#if defined(WF_UNDER_ASAN)
constexpr bool kCapAddressSpace = false;
#else
constexpr bool kCapAddressSpace = true;
#endif

Result runCapped(const std::string& args, long memKiB, int seconds) {
  const fs::path errFile = wf::test::processScratchRoot() / "capped-stderr.txt";
  const std::string cap = kCapAddressSpace ? "ulimit -v " + std::to_string(memKiB) + "; " : std::string();
  const std::string cmd = cap + "exec timeout " + std::to_string(seconds) +
                          " '" + WIREFUR_EXE + "' " + args + " >/dev/null 2>'" + errFile.string() + "'";
  const int raw = std::system(cmd.c_str());
  const std::string err = slurp(errFile);
  fs::remove(errFile);
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, err};
}

using wf::secondsSince;  // core/timer.h

// --- scene text -----------------------------------------------------------------------------------

// Scenes are written as text (not built with nlohmann) so that a case can hold what JSON allows but
// a double does not (1e400).
const std::string kImage = R"("image": {"size": [48, 36]})";
const std::string kTorus = R"({"type": "torus", "major": 1.0, "minor": 0.4, "resolution": [24, 12]})";

/// One torus drawn with material "m" = `material`.
std::string withMaterial(const std::string& material) {
  return "{" + kImage + R"(, "materials": {"m": )" + material +
         R"(}, "objects": [{"source": )" + kTorus + R"(, "surface": {"material": "m"}}]})";
}
/// One object with this source, drawn as a surface.
std::string withSource(const std::string& source) {
  return "{" + kImage + R"(, "objects": [{"source": )" + source + "}]}";
}
/// A torus object with extra keys (`, "fur": ...`); a material "fm" exists for fur / scales.
std::string withTorusKeys(const std::string& keys) {
  return "{" + kImage + R"(, "materials": {"fm": {"diffuse": 0.6}}, "objects": [{"source": )" + kTorus + keys +
         "}]}";
}

struct BadCase {
  std::string name;     ///< file name of the scene (unique in the test)
  std::string text;     ///< the scene
  std::string pointer;  ///< the JSON pointer (or place) the one line must name
};

// The contract for bad input, checked for one scene: exit 2, one line starting "wirefur: ", naming
// the scene file and `pointer`, quickly, and neither the PNG nor the stats written.
void expectRefused(const fs::path& d, const BadCase& c, double maxSeconds = 20.0, long memKiB = 6L << 20) {
  SCOPED_TRACE(c.name);
  const std::string scene = write(d, c.name, c.text);
  const fs::path png = d / (c.name + ".png"), stats = d / (c.name + ".stats.json");
  const auto t0 = std::chrono::steady_clock::now();
  const Result r = runCapped("render " + q(scene) + " -o " + q(png) + " --stats " + q(stats), memKiB, 60);
  const double seconds = secondsSince(t0);
  EXPECT_EQ(r.status, 2) << c.name << ": " << r.err;
  EXPECT_EQ(wf::test::lineCount(r.err), 1) << c.name << ": " << r.err;
  EXPECT_EQ(r.err.rfind("wirefur: ", 0), 0u) << c.name << ": " << r.err;
  EXPECT_NE(r.err.find(c.name), std::string::npos) << c.name << ": " << r.err;
  EXPECT_NE(r.err.find(c.pointer), std::string::npos) << c.name << ": expected '" << c.pointer << "' in: " << r.err;
  // An allocation failure reported as "bad input" is not a refusal: it means it tried.
  EXPECT_EQ(r.err.find("bad_alloc"), std::string::npos) << c.name << ": " << r.err;
  EXPECT_LT(seconds, maxSeconds) << c.name << ": refusing took " << seconds << " s";
  EXPECT_FALSE(fs::exists(png)) << c.name;
  EXPECT_FALSE(fs::exists(stats)) << c.name;
}

void expectAllRefused(const std::vector<BadCase>& cases) {
  const fs::path d = testDir();
  for (const BadCase& c : cases) expectRefused(d, c);
}

// Renders `scene` (a file path) and returns the parsed stats; fails the test on a non-zero exit.
json renderStats(const fs::path& d, const std::string& scene, const std::string& tag, const std::string& extra = "") {
  const fs::path png = d / (tag + ".png"), stats = d / (tag + ".stats.json");
  const Result r = run("render " + q(scene) + " -o " + q(png) + " --stats " + q(stats) + " " + extra);
  EXPECT_EQ(r.status, 0) << tag << ": " << r.err;
  EXPECT_TRUE(fs::exists(png)) << tag;
  if (r.status != 0 || !fs::exists(stats)) return json::object();
  return json::parse(slurp(stats));
}

// --- PNG files made by hand (CRC-32 and Adler-32 written here; deflate as stored blocks) -------------

std::uint32_t crc32(const std::string& bytes) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t n = 0; n < 256; ++n) {
      std::uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  std::uint32_t c = 0xFFFFFFFFu;
  for (unsigned char b : bytes) c = table[(c ^ b) & 0xFF] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

std::string be32(std::uint32_t v) {
  return {char(v >> 24), char((v >> 16) & 0xFF), char((v >> 8) & 0xFF), char(v & 0xFF)};
}

std::string chunk(const std::string& type, const std::string& data) {
  return be32(std::uint32_t(data.size())) + type + data + be32(crc32(type + data));
}

/// zlib stream of `raw` in stored (uncompressed) deflate blocks.
std::string zlibStored(const std::string& raw) {
  std::string z = {char(0x78), char(0x01)};
  size_t pos = 0;
  do {
    const size_t n = std::min<size_t>(65535, raw.size() - pos);
    const bool last = pos + n == raw.size();
    z += char(last ? 1 : 0);
    z += char(n & 0xFF), z += char(n >> 8), z += char(~n & 0xFF), z += char((~n >> 8) & 0xFF);
    z += raw.substr(pos, n);
    pos += n;
  } while (pos < raw.size());
  std::uint32_t a = 1, b = 0;
  for (unsigned char c : raw) a = (a + c) % 65521, b = (b + a) % 65521;
  return z + be32((b << 16) | a);
}

const std::string kPngSignature = "\x89PNG\r\n\x1a\n";

std::string ihdr(std::uint32_t w, std::uint32_t h, int depth, int colourType) {
  return chunk("IHDR", be32(w) + be32(h) + char(depth) + char(colourType) + std::string(3, '\0'));
}

/// A valid PNG: `raw` holds the filtered scanlines (filter byte 0 and the row's bytes).
std::string pngFile(std::uint32_t w, std::uint32_t h, int depth, int colourType, const std::string& raw) {
  return kPngSignature + ihdr(w, h, depth, colourType) + chunk("IDAT", zlibStored(raw)) + chunk("IEND", "");
}

/// A 4 x 4 8-bit RGB gradient.
std::string smallRgbPng() {
  std::string raw;
  for (int y = 0; y < 4; ++y) {
    raw += '\0';
    for (int x = 0; x < 4; ++x) raw += char(60 * x), raw += char(60 * y), raw += char(200);
  }
  return pngFile(4, 4, 8, 2, raw);
}

/// A 2 x 2 16-bit grey image.
std::string small16BitGreyPng() {
  std::string raw;
  for (int y = 0; y < 2; ++y) raw += '\0', raw += std::string("\x80\x00\xff\xff", 4);
  return pngFile(2, 2, 16, 0, raw);
}

/// An all-black 8-bit RGB PNG of w x h pixels, deflated with fixed Huffman codes as one literal 0
/// and then matches of 258 bytes at distance 1 (an 8192 x 8192 image is about 1.3 MB).
std::string blackPng(std::uint32_t w, std::uint32_t h) {
  const std::uint64_t n = std::uint64_t(h) * (1 + 3 * std::uint64_t(w));  // filter byte + RGB per row
  std::string z = {char(0x78), char(0x01)};
  std::uint32_t acc = 0;
  int used = 0;
  auto bit = [&](std::uint32_t b) {
    acc |= (b & 1u) << used;
    if (++used == 8) z += char(acc), acc = 0, used = 0;
  };
  auto huffman = [&](std::uint32_t code, int len) {  // Huffman codes go most significant bit first
    for (int i = len - 1; i >= 0; --i) bit(code >> i);
  };
  bit(1), bit(1), bit(0);  // BFINAL, BTYPE = 01 (fixed codes), least significant bit first
  std::uint64_t left = n;
  huffman(0x30, 8), --left;  // literal 0
  for (; left >= 258; left -= 258) huffman(0xC5, 8), huffman(0, 5);  // length 258 (code 285), distance 1
  for (; left > 0; --left) huffman(0x30, 8);
  huffman(0, 7);  // end of block
  if (used) z += char(acc);
  z += be32(std::uint32_t((n % 65521) << 16 | 1));  // Adler-32 of n zero bytes
  return kPngSignature + ihdr(w, h, 8, 2) + chunk("IDAT", z) + chunk("IEND", "");
}

}  // namespace

// ==================================================================================================
// Validation of every new key: one line, the right pointer, exit 2, nothing written.
// ==================================================================================================

TEST(SceneKeysCli, BurnishKeysAreValidated) {
  const std::string m = "/materials/m/burnish";
  expectAllRefused({
      {"b_not_object.json", withMaterial(R"({"burnish": 3})"), m},
      {"b_grain_word.json", withMaterial(R"({"burnish": {"grain": "w"}})"), m + "/grain"},
      {"b_grain_number.json", withMaterial(R"({"burnish": {"grain": 5}})"), m + "/grain"},
      {"b_unknown.json", withMaterial(R"({"burnish": {"grian": "u"}})"), m + "/grian"},
      {"b_grooves_unknown.json", withMaterial(R"({"burnish": {"grooves": {"cnt": 3}}})"), m + "/grooves/cnt"},
      {"b_grooves_not_object.json", withMaterial(R"({"burnish": {"grooves": [1, 2]}})"), m + "/grooves"},
      {"b_count_zero.json", withMaterial(R"({"burnish": {"grooves": {"count": 0}}})"), m + "/grooves/count"},
      {"b_count_negative.json", withMaterial(R"({"burnish": {"grooves": {"count": -5}}})"), m + "/grooves/count"},
      {"b_count_string.json", withMaterial(R"({"burnish": {"grooves": {"count": "90"}}})"), m + "/grooves/count"},
      {"b_count_huge.json", withMaterial(R"({"burnish": {"grooves": {"count": 1e10}}})"), m + "/grooves/count"},
      {"b_depth.json", withMaterial(R"({"burnish": {"grooves": {"depth": 1.5}}})"), m + "/grooves/depth"},
      {"b_seed_negative.json", withMaterial(R"({"burnish": {"grooves": {"seed": -1}}})"), m + "/grooves/seed"},
      {"b_seed_fraction.json", withMaterial(R"({"burnish": {"grooves": {"seed": 1.5}}})"), m + "/grooves/seed"},
      {"b_chrome.json", withMaterial(R"({"kind": "chrome", "burnish": {"grain": "u"}})"), m},
      {"b_axis_on_u.json", withMaterial(R"({"burnish": {"grain": "u", "axis": {"direction": [0, 0, 1]}}})"), m + "/axis"},
      {"b_axis_on_v.json", withMaterial(R"({"burnish": {"grain": "v", "axis": {"point": [0, 0, 0]}}})"), m + "/axis"},
      {"b_axis_default_grain.json", withMaterial(R"({"burnish": {"axis": {"point": [0, 0, 0]}}})"), m + "/axis"},
      {"b_axis_zero.json", withMaterial(R"({"burnish": {"grain": "circular", "axis": {"direction": [0, 0, 0]}}})"),
       m + "/axis/direction"},
      {"b_axis_short.json", withMaterial(R"({"burnish": {"grain": "radial", "axis": {"direction": [0, 1]}}})"),
       m + "/axis/direction"},
      {"b_axis_unknown.json", withMaterial(R"({"burnish": {"grain": "radial", "axis": {"centre": [0, 0, 0]}}})"),
       m + "/axis/centre"},
      {"b_axis_not_object.json", withMaterial(R"({"burnish": {"grain": "radial", "axis": [0, 0, 1]}})"), m + "/axis"},
  });
}

TEST(SceneKeysCli, TextureKeysAreValidated) {
  const std::string t = "/materials/m/texture";
  expectAllRefused({
      {"t_no_type.json", withMaterial(R"({"texture": {"squares": [2, 2]}})"), t},
      {"t_not_object.json", withMaterial(R"({"texture": "chequer"})"), t},
      {"t_type.json", withMaterial(R"({"texture": {"type": "marble"}})"), t + "/type"},
      {"t_unknown.json", withMaterial(R"({"texture": {"type": "chequer", "colors": [0, 1]}})"), t + "/colors"},
      {"t_squares_zero.json", withMaterial(R"({"texture": {"type": "chequer", "squares": [0, 4]}})"), t + "/squares/0"},
      {"t_squares_one.json", withMaterial(R"({"texture": {"type": "chequer", "squares": [4]}})"), t + "/squares"},
      {"t_squares_fraction.json", withMaterial(R"({"texture": {"type": "chequer", "squares": [4, 2.5]}})"),
       t + "/squares/1"},
      {"t_squares_huge.json", withMaterial(R"({"texture": {"type": "chequer", "squares": [4, 3000000]}})"),
       t + "/squares/1"},
      {"t_colours_one.json", withMaterial(R"({"texture": {"type": "chequer", "colours": [[1, 1, 1]]}})"), t + "/colours"},
      {"t_colour_negative.json", withMaterial(R"({"texture": {"type": "chequer", "colours": [[-1, 0, 0], 1]}})"),
       t + "/colours/0/0"},
      {"t_chequer_ramp.json", withMaterial(R"({"texture": {"type": "chequer", "ramp": [[0, 1], [1, 0]]}})"), t + "/ramp"},
      {"t_octaves_zero.json", withMaterial(R"({"texture": {"type": "noise", "octaves": 0}})"), t + "/octaves"},
      {"t_octaves_17.json", withMaterial(R"({"texture": {"type": "noise", "octaves": 17}})"), t + "/octaves"},
      {"t_frequency_zero.json", withMaterial(R"({"texture": {"type": "noise", "frequency": 0}})"), t + "/frequency"},
      {"t_frequency_huge.json", withMaterial(R"({"texture": {"type": "noise", "frequency": 1e300}})"), t + "/frequency"},
      {"t_lacunarity.json", withMaterial(R"({"texture": {"type": "noise", "lacunarity": 0.5}})"), t + "/lacunarity"},
      {"t_gain.json", withMaterial(R"({"texture": {"type": "noise", "gain": 2}})"), t + "/gain"},
      {"t_seed.json", withMaterial(R"({"texture": {"type": "noise", "seed": "one"}})"), t + "/seed"},
      {"t_periodic_one.json", withMaterial(R"({"texture": {"type": "noise", "periodic": [true]}})"), t + "/periodic"},
      {"t_periodic_number.json", withMaterial(R"({"texture": {"type": "noise", "periodic": [1, 0]}})"), t + "/periodic/0"},
      {"t_noise_file.json", withMaterial(R"({"texture": {"type": "noise", "file": "a.png"}})"), t + "/file"},
      {"t_noise_squares.json", withMaterial(R"({"texture": {"type": "noise", "squares": [2, 2]}})"), t + "/squares"},
      {"t_ramp_one_stop.json", withMaterial(R"({"texture": {"type": "noise", "ramp": [[0, 1]]}})"), t + "/ramp"},
      {"t_ramp_decreasing.json",
       withMaterial(R"({"texture": {"type": "noise", "ramp": [[0.5, 1], [0.2, 0], [0.9, 0.5]]}})"), t + "/ramp/1/0"},
      {"t_ramp_stop_short.json", withMaterial(R"({"texture": {"type": "noise", "ramp": [[0.5], [0.9, 1]]}})"),
       t + "/ramp/0"},
      {"t_ramp_colour.json", withMaterial(R"({"texture": {"type": "noise", "ramp": [[0, 1], [1, [1, 2]]]}})"),
       t + "/ramp/1/1"},
      {"t_ramp_not_list.json", withMaterial(R"({"texture": {"type": "noise", "ramp": {"0": 1}}})"), t + "/ramp"},
      {"t_image_octaves.json", withMaterial(R"({"texture": {"type": "image", "file": "x.png", "octaves": 2}})"),
       t + "/octaves"},
      {"t_image_no_file.json", withMaterial(R"({"texture": {"type": "image"}})"), t},
      {"t_image_file_number.json", withMaterial(R"({"texture": {"type": "image", "file": 7}})"), t + "/file"},
      {"t_image_wrap_word.json", withMaterial(R"({"texture": {"type": "image", "file": "x.png", "wrap": "yes"}})"),
       t + "/wrap"},
      {"t_image_wrap_one.json", withMaterial(R"({"texture": {"type": "image", "file": "x.png", "wrap": [true]}})"),
       t + "/wrap"},
  });
}

TEST(SceneKeysCli, BumpKeysAreValidated) {
  const std::string b = "/materials/m/bump";
  expectAllRefused({
      {"p_no_type.json", withMaterial(R"({"bump": {"scale": 0.1}})"), b},
      {"p_type.json", withMaterial(R"({"bump": {"type": "chequer"}})"), b + "/type"},
      {"p_scale_string.json", withMaterial(R"({"bump": {"type": "noise", "scale": "big"}})"), b + "/scale"},
      {"p_scale_huge.json", withMaterial(R"({"bump": {"type": "noise", "scale": 1e7}})"), b + "/scale"},
      {"p_unknown.json", withMaterial(R"({"bump": {"type": "noise", "amplitude": 1}})"), b + "/amplitude"},
      {"p_ramp.json", withMaterial(R"({"bump": {"type": "noise", "ramp": [[0, 0], [1, 1]]}})"), b + "/ramp"},
      {"p_octaves.json", withMaterial(R"({"bump": {"type": "noise", "octaves": 40}})"), b + "/octaves"},
      {"p_image_octaves.json", withMaterial(R"({"bump": {"type": "image", "file": "x.png", "octaves": 2}})"),
       b + "/octaves"},
      {"p_image_no_file.json", withMaterial(R"({"bump": {"type": "image", "scale": 0.1}})"), b},
      {"p_image_missing.json", withMaterial(R"({"bump": {"type": "image", "file": "nowhere.png"}})"), b + "/file"},
  });
}

TEST(SceneKeysCli, NewSourceKeysAreValidated) {
  const std::string s = "/objects/0/source";
  const std::string profile = R"("profile": [[0, 0], [1, 0], [1, 1]])";
  auto lathe = [&](const std::string& extra) { return withSource(R"({"type": "lathe", )" + profile + extra + "}"); };
  std::string fifteen, sixteen;
  for (int i = 0; i < 16; ++i) {
    const std::string p = "[" + std::to_string(i % 4) + ", " + std::to_string(i / 4) + ", " + std::to_string(i % 3) + "]";
    if (i < 15) fifteen += (i ? ", " : "") + p;
    sixteen += (i ? ", " : "") + p;
  }
  std::string eight;
  for (int i = 0; i < 8; ++i) eight += (i ? ", " : "") + ("[" + std::to_string(i % 3) + ", " + std::to_string(i / 3) + ", 0]");
  expectAllRefused({
      // lathe
      {"s_corner_index.json", lathe(R"(, "corners": [5])"), s + "/corners/0"},
      {"s_corner_negative.json", lathe(R"(, "corners": [-1])"), s + "/corners/0"},
      {"s_corner_word.json", lathe(R"(, "corners": ["base"])"), s + "/corners/0"},
      {"s_corners_not_list.json", lathe(R"(, "corners": 1)"), s + "/corners"},
      {"s_corners_no_profile.json", withSource(R"({"type": "lathe", "corners": [0]})"), s},
      {"s_interpolation.json", lathe(R"(, "interpolation": "cubic")"), s + "/interpolation"},
      {"s_corner_angle_big.json", lathe(R"(, "corner_angle": 200)"), s + "/corner_angle"},
      {"s_corner_angle_negative.json", lathe(R"(, "corner_angle": -1)"), s + "/corner_angle"},
      {"s_corner_angle_zero.json", lathe(R"(, "corner_angle": 0)"), s},
      {"s_profile_one_point.json", withSource(R"({"type": "lathe", "profile": [[1, 0]]})"), s},
      {"s_profile_on_axis.json", withSource(R"({"type": "lathe", "profile": [[0, 0], [0, 1]]})"), s},
      // keys of another type
      {"s_corners_on_sphere.json", withSource(R"({"type": "sphere", "corners": [0]})"), s + "/corners"},
      {"s_interpolation_on_torus.json", withSource(R"({"type": "torus", "interpolation": "linear"})"),
       s + "/interpolation"},
      {"s_corner_angle_on_loft.json",
       withSource(R"({"type": "loft", "corner_angle": 30, "sections": [{"centre": [0,0,0], "radius": 1}, {"centre": [1,0,0], "radius": 1}]})"),
       s + "/corner_angle"},
      {"s_sections_on_lathe.json", lathe(R"(, "sections": [])"), s + "/sections"},
      {"s_up_on_sphere.json", withSource(R"({"type": "sphere", "up": [0, 0, 1]})"), s + "/up"},
      {"s_points_on_loft.json",
       withSource(R"({"type": "loft", "points": [], "sections": [{"centre": [0,0,0], "radius": 1}, {"centre": [1,0,0], "radius": 1}]})"),
       s + "/points"},
      {"s_count_on_bezier.json", withSource(R"({"type": "bezier", "count": [4, 4], "points": [)" + sixteen + "]}"),
       s + "/count"},
      {"s_periodic_on_bezier.json",
       withSource(R"({"type": "bezier", "periodic": [false, false], "points": [)" + sixteen + "]}"), s + "/periodic"},
      {"s_profile_on_bspline.json", withSource(R"({"type": "bspline", )" + profile + "}"), s + "/profile"},
      // loft
      {"s_loft_one_section.json", withSource(R"({"type": "loft", "sections": [{"centre": [0, 0, 0], "radius": 1}]})"), s},
      {"s_loft_no_sections.json", withSource(R"({"type": "loft"})"), s},
      {"s_loft_sections_not_list.json", withSource(R"({"type": "loft", "sections": {"centre": [0, 0, 0]}})"),
       s + "/sections"},
      {"s_loft_no_centre.json",
       withSource(R"({"type": "loft", "sections": [{"radius": 1}, {"centre": [1, 0, 0], "radius": 1}]})"),
       s + "/sections/0"},
      {"s_loft_unknown.json",
       withSource(R"({"type": "loft", "sections": [{"centre": [0,0,0], "radious": 1}, {"centre": [1,0,0], "radius": 1}]})"),
       s + "/sections/0/radious"},
      {"s_loft_radii_one.json",
       withSource(R"({"type": "loft", "sections": [{"centre": [0,0,0], "radii": [1]}, {"centre": [1,0,0], "radius": 1}]})"),
       s + "/sections/0/radii"},
      {"s_loft_radius_negative.json",
       withSource(R"({"type": "loft", "sections": [{"centre": [0,0,0], "radius": -1}, {"centre": [1,0,0], "radius": 1}]})"),
       s + "/sections/0/radius"},
      {"s_loft_profile_counts.json",
       withSource(R"({"type": "loft", "sections": [{"centre": [0,0,0], "profile": [[1,0],[0,1],[-1,0]]}, {"centre": [1,0,0], "profile": [[1,0],[0,1],[-1,0],[0,-1]]}]})"),
       s},
      {"s_loft_profile_two.json",
       withSource(R"({"type": "loft", "sections": [{"centre": [0,0,0], "profile": [[1,0],[0,1]]}, {"centre": [1,0,0], "profile": [[1,0],[0,1]]}]})"),
       s},
      {"s_loft_repeated_centres.json",
       withSource(R"({"type": "loft", "sections": [{"centre": [0,0,0], "radius": 1}, {"centre": [0,0,0], "radius": 1}]})"), s},
      {"s_loft_up_zero_length.json",
       withSource(R"({"type": "loft", "up": [0, 1], "sections": [{"centre": [0,0,0], "radius": 1}, {"centre": [1,0,0], "radius": 1}]})"),
       s + "/up"},
      // bezier and bspline
      {"s_bezier_15.json", withSource(R"({"type": "bezier", "points": [)" + fifteen + "]}"), s},
      {"s_bezier_no_points.json", withSource(R"({"type": "bezier"})"), s},
      {"s_bezier_point_short.json",
       withSource(R"({"type": "bezier", "points": [[0, 0]], "resolution": [8, 8]})"), s + "/points/0"},
      {"s_bezier_points_not_list.json", withSource(R"({"type": "bezier", "points": 16})"), s + "/points"},
      {"s_bspline_mismatch.json", withSource(R"({"type": "bspline", "count": [3, 3], "points": [)" + eight + "]}"), s},
      {"s_bspline_no_count.json", withSource(R"({"type": "bspline", "points": [)" + eight + "]}"), s},
      {"s_bspline_count_zero.json", withSource(R"({"type": "bspline", "count": [0, 8], "points": [)" + eight + "]}"),
       s + "/count/0"},
      {"s_bspline_count_huge.json", withSource(R"({"type": "bspline", "count": [100000, 1], "points": [)" + eight + "]}"),
       s + "/count/0"},
      {"s_bspline_count_one.json", withSource(R"({"type": "bspline", "count": [4], "points": [)" + eight + "]}"),
       s + "/count"},
      {"s_bspline_periodic_few.json",
       withSource(R"({"type": "bspline", "count": [2, 4], "periodic": [true, false], "points": [)" + eight + "]}"), s},
      {"s_bspline_periodic_word.json",
       withSource(R"({"type": "bspline", "count": [4, 2], "periodic": ["yes", false], "points": [)" + eight + "]}"),
       s + "/periodic/0"},
      // resolution
      {"s_resolution_total.json", withSource(R"({"type": "sphere", "resolution": [4096, 4096]})"), s},
      {"s_resolution_axis.json", withSource(R"({"type": "sphere", "resolution": [5000, 10]})"), s + "/resolution/0"},
      {"s_resolution_small.json", withSource(R"({"type": "sphere", "resolution": [2, 2]})"), s},
  });
}

TEST(SceneKeysCli, FurKeysAreValidated) {
  const std::string f = "/objects/0/fur";
  auto fur = [&](const std::string& keys) { return withTorusKeys(R"(, "fur": )" + keys); };
  expectAllRefused({
      {"f_not_object.json", fur("true"), f},
      {"f_unknown.json", fur(R"({"lenght": 0.2})"), f + "/lenght"},
      {"f_curl_unknown.json", fur(R"({"curl": {"amp": 0.1}})"), f + "/curl/amp"},
      {"f_orientation_map_unknown.json", fur(R"({"orientation_map": {"d": {}}})"), f + "/orientation_map/d"},
      {"f_orientation_map_range.json", fur(R"({"orientation_map": {"a": {"range": [0, 1e400]}}})"), ""},
      {"f_root_colour_map_type.json", fur(R"({"root_colour_map": {"type": "marble"}})"), f + "/root_colour_map/type"},
      {"f_root_colour_map_missing.json", fur(R"({"root_colour_map": {"type": "image", "file": "nope.png"}})"),
       f + "/root_colour_map/file"},
      {"f_curl_not_object.json", fur(R"({"curl": 0.1})"), f + "/curl"},
      {"f_curl_negative.json", fur(R"({"curl": {"amplitude": -1}})"), f + "/curl/amplitude"},
      {"f_wind_unknown.json", fur(R"({"wind": {"speed": 2}})"), f + "/wind/speed"},
      {"f_wind_sway.json", fur(R"({"wind": {"sway": 2}})"), f + "/wind/sway"},
      {"f_wind_direction.json", fur(R"({"wind": {"direction": [1, 0]}})"), f + "/wind/direction"},
      {"f_regions_unknown.json", fur(R"({"regions": [{"centre": [0.5, 0.5], "size": 0.2}]})"), f + "/regions/0/size"},
      {"f_regions_not_list.json", fur(R"({"regions": {"centre": [0.5, 0.5]}})"), f + "/regions"},
      {"f_regions_falloff.json", fur(R"({"regions": [{"falloff": 3}]})"), f + "/regions/0/falloff"},
      {"f_regions_centre.json", fur(R"({"regions": [{"centre": [0.5]}]})"), f + "/regions/0/centre"},
      {"f_density_map_unknown.json", fur(R"({"placement": "area", "density": 10, "density_map": {"amplitude": 1}})"),
       f + "/density_map/amplitude"},
      {"f_length_map_range.json", fur(R"({"length_map": {"range": [0]}})"), f + "/length_map/range"},
      {"f_placement.json", fur(R"({"placement": "random"})"), f + "/placement"},
      {"f_grid_zero.json", fur(R"({"grid": [0, 5]})"), f + "/grid/0"},
      {"f_grid_one.json", fur(R"({"grid": [5]})"), f + "/grid"},
      {"f_grid_huge.json", fur(R"({"grid": [70000, 1]})"), f + "/grid/0"},
      {"f_grid_fraction.json", fur(R"({"grid": [10.5, 4]})"), f + "/grid/0"},
      {"f_jitter.json", fur(R"({"jitter": 2})"), f + "/jitter"},
      {"f_density_negative.json", fur(R"({"placement": "area", "density": -1})"), f + "/density"},
      {"f_segments_zero.json", fur(R"({"segments": 0})"), f + "/segments"},
      {"f_segments_65.json", fur(R"({"segments": 65})"), f + "/segments"},
      {"f_length_negative.json", fur(R"({"length": -1})"), f + "/length"},
      {"f_length_mode.json", fur(R"({"length_mode": "long"})"), f + "/length_mode"},
      {"f_length_variation.json", fur(R"({"length_variation": 1.5})"), f + "/length_variation"},
      {"f_length_variation_one.json", fur(R"({"length_variation": 1})"), f},
      {"f_clumping.json", fur(R"({"clumping": 1.5})"), f + "/clumping"},
      {"f_clumps.json", fur(R"({"clumps": [0, 3]})"), f + "/clumps/0"},
      {"f_gravity.json", fur(R"({"gravity": -1})"), f + "/gravity"},
      {"f_orientation.json", fur(R"({"orientation": [1, 2]})"), f + "/orientation"},
      {"f_unit_tangents.json", fur(R"({"unit_tangents": 1})"), f + "/unit_tangents"},
      {"f_thickness.json", fur(R"({"thickness": 0})"), f + "/thickness"},
      {"f_root_colour.json", fur(R"({"root_colour": [1, -1, 0]})"), f + "/root_colour/1"},
      {"f_material.json", fur(R"({"material": "mink"})"), f + "/material"},
      {"f_opacity.json", fur(R"({"opacity": 2})"), f + "/opacity"},
      {"f_ends.json", fur(R"({"ends": "pointy"})"), f + "/ends"},
      {"f_ends_type.json", fur(R"({"ends": true})"), f + "/ends"},
      {"f_seed.json", fur(R"({"seed": -3})"), f + "/seed"},
  });
}

TEST(SceneKeysCli, ScalesKeysAreValidated) {
  const std::string s = "/objects/0/scales";
  auto scales = [&](const std::string& keys) { return withTorusKeys(R"(, "scales": )" + keys); };
  expectAllRefused({
      {"c_not_object.json", scales("[6, 4]"), s},
      {"c_unknown.json", scales(R"({"cell": [6, 4]})"), s + "/cell"},
      {"c_cells_zero.json", scales(R"({"cells": [0, 4]})"), s + "/cells/0"},
      {"c_cells_one.json", scales(R"({"cells": [6]})"), s + "/cells"},
      {"c_cells_axis.json", scales(R"({"cells": [20000, 1]})"), s + "/cells/0"},
      {"c_size_zero.json", scales(R"({"size": 0})"), s},
      {"c_size_big.json", scales(R"({"size": 200})"), s + "/size"},
      {"c_lift_negative.json", scales(R"({"lift": -1})"), s},
      {"c_deflection.json", scales(R"({"deflection": -1})"), s + "/deflection"},
      {"c_shoulder.json", scales(R"({"shoulder": 1})"), s},
      {"c_colour.json", scales(R"({"colour": "green"})"), s + "/colour"},
      {"c_material.json", scales(R"({"material": "jade"})"), s + "/material"},
      {"c_seed.json", scales(R"({"seed": 0.5})"), s + "/seed"},
  });
}

// Fur and scales grow on a mesh file's triangles too (surface/mesh_surface.h: its texture
// coordinates, else an automatic flat layout); a box is several patches and still refuses them.
TEST(SceneKeysCli, FurAndScalesGrowOnMeshFilesNotOnABox) {
  const fs::path d = testDir();
  write(d, "quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n");
  write(d, "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  auto onFile = [](const std::string& file, const std::string& key, const std::string& value) {
    return "{" + kImage + R"(, "objects": [{"file": ")" + file + R"(", ")" + key + R"(": )" + value + "}]}";
  };
  for (const std::string file : {"quad.obj", "tri.obj"}) {
    SCOPED_TRACE(file);
    // 8 x 8 roots on the grid over the uv square: all on the quad, about half on the triangle's
    // layout (the triangle fills half of its bounding box in uv).
    const json fur = renderStats(d, write(d, "fur_" + file + ".json", onFile(file, "fur", R"({"grid": [8, 8], "length": 0.2, "length_mode": "fixed", "thickness": 0.01})")), "fur_" + file);
    const double hairs = fur.value("/generated/hairs"_json_pointer, 0.0);
    if (file == "quad.obj") EXPECT_EQ(hairs, 64.0);
    else EXPECT_NEAR(hairs, 32.0, 10.0);
    const json scales = renderStats(d, write(d, "scales_" + file + ".json", onFile(file, "scales", R"({"cells": [6, 6]})")), "scales_" + file);
    const double grown = scales.value("/generated/scales"_json_pointer, 0.0);
    // Two per cell on the quad; on the triangle (0,0) (1,0) (0,1), laid flat as it is, the
    // corners (i, j) / 6 with i + j <= 6 (26) and the centres with i + j <= 5 (21).
    if (file == "quad.obj") EXPECT_EQ(grown, 72.0);
    else EXPECT_EQ(grown, 47.0);
  }
  auto onBox = [](const std::string& key) {
    return "{" + kImage + R"(, "objects": [{"source": {"type": "box", "size": [1, 1, 1]}, ")" + key + R"(": {}}]})";
  };
  for (const BadCase& c : std::vector<BadCase>{{"fur_on_box.json", onBox("fur"), "/objects/0/"},
                                               {"scales_on_box.json", onBox("scales"), "/objects/0/"}})
    expectRefused(d, c);
}

TEST(SceneKeysCli, ViewGridIsValidated) {
  auto scene = [](const std::string& v) {
    return R"({"image": {"size": [48, 36], "view_grid": )" + v + R"(}, "objects": [{"source": {"type": "sphere"}}]})";
  };
  expectAllRefused({{"v_zero.json", scene("0"), "/image/view_grid"},
                    {"v_17.json", scene("17"), "/image/view_grid"},
                    {"v_fraction.json", scene("2.5"), "/image/view_grid"},
                    {"v_string.json", scene("\"3\""), "/image/view_grid"},
                    {"v_list.json", scene("[3, 3]"), "/image/view_grid"}});
}

// A number beyond double range inside the new keys: bad input, one line naming the file.
TEST(SceneKeysCli, NumbersBeyondDoubleRangeAreBadInput) {
  const fs::path d = testDir();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"o_grooves.json", withMaterial(R"({"burnish": {"grooves": {"count": 1e400}}})")},
      {"o_frequency.json", withMaterial(R"({"texture": {"type": "noise", "frequency": 1e400}})")},
      {"o_bump_scale.json", withMaterial(R"({"bump": {"type": "noise", "scale": -1e400}})")},
      {"o_density.json", withTorusKeys(R"(, "fur": {"placement": "area", "density": 1e400})")},
      {"o_lift.json", withTorusKeys(R"(, "scales": {"lift": 1e400})")},
      {"o_loft.json",
       withSource(R"({"type": "loft", "sections": [{"centre": [0,0,0], "radius": 1e400}, {"centre": [1,0,0], "radius": 1}]})")},
  };
  for (const auto& [name, text] : cases) {
    SCOPED_TRACE(name);
    const std::string scene = write(d, name, text);
    const fs::path png = d / (name + ".png");
    const Result r = run("render " + q(scene) + " -o " + q(png));
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(wf::test::lineCount(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(name), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(png));
  }
}

// The contract asks for the place of the problem; for a number beyond double range the one line
// should say where it is (line and column, as other JSON errors do).
TEST(SceneKeysCli, NumbersBeyondDoubleRangeNameTheirPlace) {
  const fs::path d = testDir();
  const std::string scene =
      write(d, "o_place.json", "{\n \"image\": {\"size\": [48, 36]},\n \"objects\": [{\"source\": {\"type\": \"sphere\", \"radius\": 1e400}}]\n}\n");
  const Result r = run("render " + q(scene) + " -o " + q(d / "o.png"));
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("o_place.json:3:"), std::string::npos) << "no line:column in: " << r.err;
}

// The loft's own checks: a spine parallel to up is named as such (not as repeated centres), and a
// loft of zero radius everywhere is a line, not a surface: refused before anything grows on it.
TEST(SceneKeysCli, DegenerateLoftsAreNamedForWhatTheyAre) {
  const fs::path d = testDir();
  expectRefused(d, {"l_parallel_up.json",
                    withSource(R"({"type": "loft", "up": [0, 0, 1], "sections": [{"centre": [0,0,0], "radius": 1}, {"centre": [0,0,1], "radius": 1}, {"centre": [0,0,2], "radius": 1}]})"),
                    "parallel"});
  const std::string zero =
      R"({"type": "loft", "sections": [{"centre": [0,0,0], "radius": 0}, {"centre": [1,0,0], "radius": 0}, {"centre": [2,0,0.5], "radius": 0}]})";
  expectRefused(d, {"l_zero_radii.json", withSource(zero), "/objects/0/source"});
  expectRefused(d, {"l_zero_radii_fur.json",
                    "{" + kImage + R"(, "objects": [{"source": )" + zero + R"(, "surface": false, "fur": {"grid": [5, 5]}}]})",
                    "/objects/0/source"});
}

// ==================================================================================================
// Sizes: refused quickly, before anything big is allocated. Each run has its address space capped
// at 6 GiB, so a scene that tries to allocate tens of GB fails the test, not the machine.
// ==================================================================================================

TEST(SceneKeysCli, HugeSizesAreRefusedQuickly) {
  const std::string f = "/objects/0/fur";
  expectAllRefused({
      {"h_grid.json", withTorusKeys(R"(, "fur": {"grid": [65536, 65536]})"), f},
      {"h_grid_segments.json", withTorusKeys(R"(, "fur": {"grid": [4096, 4096], "segments": 64})"), f},
      {"h_density.json", withTorusKeys(R"(, "fur": {"placement": "area", "density": 1e15})"), f},
      {"h_density_segments.json", withTorusKeys(R"(, "fur": {"placement": "area", "density": 1e7, "segments": 64})"), f},
      {"h_scales_cells.json", withTorusKeys(R"(, "scales": {"cells": [16384, 16384]})"), "/objects/0/scales"},
      {"h_resolution.json", withSource(R"({"type": "torus", "resolution": [4096, 4096]})"), "/objects/0/source"},
      {"h_resolution_lathe.json",
       withSource(R"({"type": "lathe", "profile": [[1, 0], [1, 1]], "resolution": [4096, 2048]})"), "/objects/0/source"},
  });
}

// 4096 x 4096 cells pass the per-axis and the 2^24 total check, but two scales per cell of 288 bytes
// of slots plus four vertices of 148 bytes each is about 30 GB: it must be refused, not attempted.
TEST(SceneKeysCli, ScalesCellsNeedingTensOfGigabytesAreRefused) {
  expectRefused(testDir(), {"h_scales_4096.json", withTorusKeys(R"(, "scales": {"cells": [4096, 4096]})"),
                            "/objects/0/scales"});
}

// The fur bound multiplies the density by the placed area, but a density map multiplies the
// density again (its range goes up to 1e6): the bound must include the map's maximum.
TEST(SceneKeysCli, DensityMapCannotBypassTheFurBound) {
  expectRefused(testDir(),
                {"h_density_map.json",
                 withTorusKeys(R"(, "fur": {"placement": "area", "density": 30, "density_map": {"range": [1e6, 1e6]}})"),
                 "/objects/0/fur"});
}

// The fur bound is per object (33.5M points, ~8 GB and ~1 min of rendering for one object
// measured): a scene repeating such an object must be refused as a whole, not grown object by
// object until memory runs out.
TEST(SceneKeysCli, FurBoundHoldsForTheWholeScene) {
  std::string objects;
  for (int i = 0; i < 6; ++i)
    objects += std::string(i ? ", " : "") +
               R"({"source": {"type": "torus", "minor": 0.4}, "surface": false, "fur": {"grid": [4096, 4096], "segments": 1, "length": 0.1}})";
  expectRefused(testDir(), {"h_many_furs.json", "{" + kImage + R"(, "objects": [)" + objects + "]}", "/objects/"}, 20.0,
                3L << 20);
}

// ==================================================================================================
// Image textures and bump images.
// ==================================================================================================

// A PNG this test makes with `wirefur render`, used as a colour texture and as a bump image, and
// PNGs written by hand (8-bit RGB, 16-bit grey): all render, the same for any thread count.
TEST(SceneKeysCli, ImageTexturesFromRenderedAndHandMadePngsRender) {
  const fs::path d = testDir();
  const fs::path made = d / "made.png";
  const Result m = run("render -o " + q(made) + " --size 24x18");
  ASSERT_EQ(m.status, 0) << m.err;
  write(d, "rgb.png", smallRgbPng());
  write(d, "grey16.png", small16BitGreyPng());
  fs::create_directories(d / "sub");
  fs::copy_file(made, d / "sub" / "nested.png");
  const std::string scene = write(
      d, "textured.json",
      "{" + kImage + R"(, "materials": {
         "a": {"texture": {"type": "image", "file": "made.png"}},
         "b": {"texture": {"type": "image", "file": "rgb.png", "wrap": [true, false]}, "bump": {"type": "image", "file": "made.png", "scale": 0.05}},
         "c": {"texture": {"type": "image", "file": "sub/nested.png", "wrap": false}, "bump": {"type": "image", "file": "grey16.png", "wrap": true}},
         "d": {"burnish": {"grain": "circular", "grooves": {"count": 40}}, "texture": {"type": "image", "file": ")" +
          (d / "grey16.png").string() + R"("}}},
       "objects": [
         {"source": {"type": "torus", "minor": 0.4}, "surface": {"material": "a"}, "transform": {"translate": [-1.5, 0, 0]}},
         {"source": {"type": "sphere", "radius": 0.6}, "surface": {"material": "b"}, "transform": {"translate": [1.5, 0, 0]}},
         {"source": {"type": "plane", "size": [1, 1]}, "surface": {"material": "c"}, "transform": {"translate": [0, 1.5, 0]}},
         {"source": {"type": "sphere", "radius": 0.5}, "surface": {"material": "d"}, "transform": {"translate": [0, -1.5, 0]}}]})");
  const fs::path a = d / "t1.png", b = d / "t3.png";
  const Result r1 = run("render " + q(scene) + " -o " + q(a) + " --threads 1");
  ASSERT_EQ(r1.status, 0) << r1.err;
  EXPECT_EQ(r1.err, "");
  const Result r3 = run("render " + q(scene) + " -o " + q(b) + " --threads 3");
  ASSERT_EQ(r3.status, 0) << r3.err;
  EXPECT_EQ(slurp(a), slurp(b));
}

// Files that are not usable PNGs: one line naming the scene, the pointer and the image file; exit
// 2; nothing written; never a crash (libpng errors must not escape as a signal or extra lines).
TEST(SceneKeysCli, BadImageFilesAreBadInputNotCrashes) {
  const fs::path d = testDir();
  ASSERT_EQ(run("render -o " + q(d / "valid.png") + " --size 24x18").status, 0);
  const std::string valid = slurp(d / "valid.png");
  const std::string good = smallRgbPng();
  std::string badCrc = good;
  badCrc[29] = char(badCrc[29] ^ 0xFF);  // the IHDR's CRC
  const std::string tinyData = zlibStored(std::string(64, '\0'));
  const std::vector<std::pair<std::string, std::string>> files = {
      {"empty.png", ""},
      {"text.png", "this is not an image\n"},
      {"half.png", valid.substr(0, valid.size() / 2)},
      {"header_only.png", kPngSignature + ihdr(4, 4, 8, 2).substr(0, 10)},
      {"bad_crc.png", badCrc},
      {"no_idat.png", kPngSignature + ihdr(4, 4, 8, 2) + chunk("IEND", "")},
      {"zero_width.png", kPngSignature + ihdr(0, 5, 8, 2) + chunk("IDAT", tinyData) + chunk("IEND", "")},
      {"bad_depth.png", kPngSignature + ihdr(4, 4, 7, 2) + chunk("IDAT", tinyData) + chunk("IEND", "")},
      {"huge.png", kPngSignature + ihdr(100000, 100000, 8, 2) + chunk("IDAT", tinyData) + chunk("IEND", "")},
      {"too_wide.png", kPngSignature + ihdr(0x7FFFFFFF, 1, 8, 2) + chunk("IDAT", tinyData) + chunk("IEND", "")},
      // Declares 8192 x 8192 (within the texture limit) but holds 64 bytes of pixels.
      {"short_data.png", kPngSignature + ihdr(8192, 8192, 8, 2) + chunk("IDAT", tinyData) + chunk("IEND", "")},
  };
  fs::create_directories(d / "folder.png");
  std::vector<std::string> names = {"missing.png", "folder.png"};
  for (const auto& [name, bytes] : files) {
    write(d, name, bytes);
    names.push_back(name);
  }
  for (const std::string& name : names)
    for (const std::string& key : {std::string("texture"), std::string("bump")}) {
      SCOPED_TRACE(key + " " + name);
      const std::string sceneName = key + "_" + name + ".json";
      const std::string scene = write(
          d, sceneName, withMaterial(R"({")" + key + R"(": {"type": "image", "file": ")" + name + R"("}})"));
      const fs::path png = d / (sceneName + ".png"), stats = d / (sceneName + ".stats.json");
      const Result r = runCapped("render " + q(scene) + " -o " + q(png) + " --stats " + q(stats), 6L << 20, 60);
      EXPECT_EQ(r.status, 2) << r.err;
      EXPECT_EQ(wf::test::lineCount(r.err), 1) << r.err;
      EXPECT_NE(r.err.find(sceneName), std::string::npos) << r.err;
      EXPECT_NE(r.err.find("/materials/m/" + key + "/file"), std::string::npos) << r.err;
      EXPECT_NE(r.err.find(name), std::string::npos) << r.err;
      EXPECT_FALSE(fs::exists(png));
      EXPECT_FALSE(fs::exists(stats));
    }
}

// A texture may have 2^26 pixels (apps/image_io.h); decoded it holds ~3.4 GB (measured), and each
// material naming the same file decodes it again, used or not: eight materials over one 190 KB PNG
// would take ~27 GB. Within a 6 GiB cap the scene must render (one decode, shared) or be refused
// as a whole with one line; not run out of memory.
TEST(SceneKeysCli, OneLargeImageNamedByManyMaterialsStaysBounded) {
  const fs::path d = testDir();
  write(d, "black.png", blackPng(8192, 8192));
  std::string materials;
  for (int i = 0; i < 8; ++i)
    materials += std::string(i ? ", " : "") + "\"m" + std::to_string(i) + R"(": {"texture": {"type": "image", "file": "black.png"}})";
  const std::string scene = write(d, "many_textures.json",
                                  "{" + kImage + R"(, "materials": {)" + materials +
                                      R"(}, "objects": [{"source": {"type": "torus"}, "surface": {"material": "m0"}}]})");
  const fs::path png = d / "many.png";
  const Result r = runCapped("render " + q(scene) + " -o " + q(png), 6L << 20, 120);
  EXPECT_TRUE(r.status == 0 || r.status == 2) << r.status << ": " << r.err;
  EXPECT_EQ(r.err.find("bad_alloc"), std::string::npos) << r.err;
  if (r.status == 2) {
    EXPECT_EQ(wf::test::lineCount(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("many_textures.json"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(png));
  }
}

// ==================================================================================================
// What the keys do, in numbers from --stats.
// ==================================================================================================

// Paper §4.2: one hair per cell of the (u, v) grid; straight hairs are one segment each, curved
// ones `segments` each. Fur over a wire-frame adds exactly its segments to the wire's.
TEST(SceneKeysCli, FurGridGivesOneHairPerCellAndSegmentsPerHair) {
  const fs::path d = testDir();
  const std::string fur = R"("fur": {"grid": [10, 7], "length": 0.3, "material": "fm")";
  const json straight = renderStats(d, write(d, "straight.json", withTorusKeys(R"(, "surface": false, )" + fur + "}")), "s");
  EXPECT_EQ(straight.value("segments", -1), 70);
  EXPECT_EQ(straight.value("triangles", -1), 0);
  const json curved =
      renderStats(d, write(d, "curved.json", withTorusKeys(R"(, "surface": false, )" + fur + R"(, "segments": 3})")), "c");
  EXPECT_EQ(curved.value("segments", -1), 210);
  const std::string wire = R"(, "wire": {"lines": [4, 3], "material": "fm"})";
  const json wireOnly = renderStats(d, write(d, "wire.json", withTorusKeys(R"(, "surface": false)" + wire)), "w");
  const json both =
      renderStats(d, write(d, "both.json", withTorusKeys(R"(, "surface": false)" + wire + ", " + fur + "}")), "b");
  ASSERT_GT(wireOnly.value("segments", -1), 0);
  EXPECT_EQ(both.value("segments", -1), wireOnly.value("segments", -1) + 70);
  // Fur over the surface: the torus's 24 x 12 x 2 triangles and the 70 hairs.
  const json furry = renderStats(d, write(d, "furry.json", withTorusKeys(", " + fur + "}")), "f");
  EXPECT_EQ(furry.value("segments", -1), 70);
  EXPECT_EQ(furry.value("triangles", -1), 24 * 12 * 2);
}

// Paper §4.2: two scales per cell, two triangles per scale: cells [6, 4] add 2 * 2 * 6 * 4 = 96.
TEST(SceneKeysCli, ScalesAddFourTrianglesPerCell) {
  const fs::path d = testDir();
  const json bare = renderStats(d, write(d, "bare.json", withTorusKeys("")), "bare");
  const json scaly = renderStats(
      d, write(d, "scaly.json", withTorusKeys(R"(, "scales": {"cells": [6, 4], "material": "fm"})")), "scaly");
  EXPECT_EQ(bare.value("triangles", -1), 24 * 12 * 2);
  EXPECT_EQ(scaly.value("triangles", -1) - bare.value("triangles", -1), 96);
  EXPECT_EQ(scaly.value("segments", -1), 0);
}

// docs/design.md "leave out what a scene does not need". The map path (--shading maps): a burnished
// surface is shaded through the pseudo-reflectance map (one per view-grid node), a plain Phong
// surface through a reflectance sphere, and a colour-textured one needs its tables in two parts
// (two reflectance spheres, not one). The closed path (the default): no maps and no spheres, one
// lobe table for the burnished surface's exponent, none for Phong.
TEST(SceneKeysCli, MapsAndSpheresAreBuiltOnlyWhereNeeded) {
  const fs::path d = testDir();
  const std::string plainScene = write(d, "plain.json", withMaterial(R"({"diffuse": 0.5})"));
  const json plain = renderStats(d, plainScene, "plain", "--shading maps");
  EXPECT_EQ(plain["left_out"].value("pseudo_reflectance_maps_built", -1), 0);
  EXPECT_EQ(plain["left_out"].value("reflectance_spheres_built", -1), 1);
  const json plainClosed = renderStats(d, plainScene, "plain_closed");
  EXPECT_EQ(plainClosed["options"].value("shading", ""), "closed");
  EXPECT_EQ(plainClosed["left_out"].value("reflectance_spheres_built", -1), 0);
  EXPECT_EQ(plainClosed["left_out"].value("lobe_tables_built", -1), 0);
  EXPECT_EQ(plainClosed["error_estimate"].value("shading_bound", -1.0), 0.0);  // Phong at every fragment: exact
  for (const std::string grain : {"u", "v", "radial", "circular"}) {
    SCOPED_TRACE(grain);
    const std::string scene = write(
        d, "burnish_" + grain + ".json",
        withMaterial(R"({"specular": 2, "burnish": {"grain": ")" + grain + R"(", "grooves": {"count": 30}}})"));
    const json b = renderStats(d, scene, "burnish_" + grain, "--shading maps");
    EXPECT_EQ(b["left_out"].value("pseudo_reflectance_maps_built", -1), 1);
    EXPECT_EQ(b["left_out"].value("reflectance_spheres_built", -1), 0);
    EXPECT_GT(b["error_estimate"].value("map_max", -1.0), 0.0);
    const json c = renderStats(d, scene, "burnish_closed_" + grain);
    EXPECT_EQ(c["left_out"].value("pseudo_reflectance_maps_built", -1), 0);
    EXPECT_EQ(c["left_out"].value("lobe_tables_built", -1), 1);
    EXPECT_GT(c["error_estimate"].value("lobe_max", -1.0), 0.0);
    EXPECT_LT(c["error_estimate"].value("shading_bound", 1.0), 1e-7);
  }
  const json chequer = renderStats(
      d, write(d, "chequer.json", withMaterial(R"({"texture": {"type": "chequer", "squares": [6, 3]}})")), "chequer",
      "--shading maps");
  EXPECT_EQ(chequer["left_out"].value("reflectance_spheres_built", -1), 2);
  EXPECT_EQ(chequer["left_out"].value("pseudo_reflectance_maps_built", -1), 0);
  const json noise = renderStats(
      d, write(d, "noise.json",
               withMaterial(R"({"texture": {"type": "noise", "ramp": [[-0.5, [0.2, 0.1, 0]], [0, 0.5], [0.5, [1, 1, 0.8]]]},
                                "bump": {"type": "noise", "scale": 0.02}})")),
      "noise", "--shading maps");
  EXPECT_EQ(noise["left_out"].value("reflectance_spheres_built", -1), 2);
}

// image.view_grid n: n x n tables on the map path, reported in the stats; --view-grid overrides it.
TEST(SceneKeysCli, ViewGridFromTheSceneIsUsedAndReported) {
  const fs::path d = testDir();
  const std::string scene = write(
      d, "grid.json", R"({"image": {"size": [48, 36], "view_grid": 3}, "objects": [{"source": {"type": "torus"}}]})");
  const json s = renderStats(d, scene, "grid3", "--shading maps");
  EXPECT_EQ(s["options"].value("view_grid", -1), 3);
  EXPECT_EQ(s["left_out"].value("reflectance_spheres_built", -1), 9);
  const json o = renderStats(d, scene, "grid2", "--shading maps --view-grid 2");
  EXPECT_EQ(o["options"].value("view_grid", -1), 2);
  EXPECT_EQ(o["left_out"].value("reflectance_spheres_built", -1), 4);
}

namespace {
// Every number under `j` is finite (nlohmann writes NaN and Inf as null).
void expectFiniteNumbers(const json& j, const std::string& where) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it)
      if (it.key() != "notes") expectFiniteNumbers(it.value(), where + "/" + it.key());
  } else if (j.is_array()) {
    for (size_t i = 0; i < j.size(); ++i) expectFiniteNumbers(j[i], where + "/" + std::to_string(i));
  } else {
    EXPECT_TRUE(j.is_number()) << where << " = " << j.dump();
    if (j.is_number()) {
      EXPECT_TRUE(std::isfinite(j.get<double>())) << where;
    }
  }
}
}  // namespace

// Every gallery scene renders at a small size: exit 0, a PNG, something drawn, finite estimates.
TEST(SceneKeysCli, EveryGallerySceneRendersSmallWithFiniteErrorEstimates) {
  const fs::path d = testDir();
  int scenes = 0;
  for (const auto& e : fs::directory_iterator(kScenes)) {
    if (e.path().extension() != ".json") continue;
    ++scenes;
    const std::string name = e.path().stem().string();
    SCOPED_TRACE(name);
    const fs::path png = d / (name + ".png"), stats = d / (name + ".json");
    const auto t0 = std::chrono::steady_clock::now();
    const Result r = runCapped("render " + q(e.path()) + " -o " + q(png) + " --size 64x48 --stats " + q(stats), 8L << 20, 120);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_TRUE(fs::exists(png));
    const json s = json::parse(slurp(stats));
    expectFiniteNumbers(s["error_estimate"], "error_estimate");
    EXPECT_GT(s.value("fragments", 0), 0) << "nothing drawn";
    EXPECT_GT(s.value("segments", 0) + s.value("triangles", 0), 0);
    std::cout << "  " << name << ": " << secondsSince(t0) << " s\n";
  }
  EXPECT_GE(scenes, 25);
}

// Area-correct, curved, clumped, windy fur with maps and colour regions: bit-identical PNGs for
// any thread count (counter-based randomness; docs/design.md "Deterministic").
TEST(SceneKeysCli, CurvedClumpedWindyFurIsTheSameForAnyThreadCount) {
  const fs::path d = testDir();
  const std::string scene = write(
      d, "windy.json",
      "{" + std::string(R"("image": {"size": [96, 72]}, "materials": {"fm": {"diffuse": [0.8, 0.6, 0.4], "specular": 0.5, "exponent": 14},
                         "skin": {"diffuse": 0.3, "burnish": {"grain": "v"}}},
       "objects": [{"source": {"type": "torus", "minor": 0.42, "resolution": [32, 16]}, "surface": {"material": "skin"},
         "fur": {"placement": "area", "density": 400, "density_map": {"octaves": 3, "frequency": 4, "range": [0.2, 1.5]},
                 "orientation": [0.3, 0.1, 1.0], "length": 0.25, "length_variation": 0.3,
                 "length_map": {"frequency": 3, "range": [0.6, 1.2]}, "segments": 5, "gravity": 0.4,
                 "curl": {"amplitude": 0.03, "frequency": 3}, "clumping": 0.6, "clumps": [24, 12],
                 "wind": {"direction": [1, 0.2, 0], "strength": 0.3, "sway": 0.5, "frequency": 2, "time": 0.7},
                 "root_colour": [0.4, 0.3, 0.2], "tip_colour": [0.9, 0.8, 0.6], "intensity_variation": 0.3,
                 "regions": [{"centre": [0.25, 0.5], "radius": 0.2, "colour": [0.2, 0.2, 0.2], "falloff": 0.5}],
                 "thickness": 0.01, "material": "fm", "seed": 7}}]})"));
  const fs::path a = d / "t1.png", b = d / "t2.png", c = d / "t7.png", sa = d / "t1.json";
  const Result r1 = run("render " + q(scene) + " -o " + q(a) + " --threads 1 --stats " + q(sa));
  ASSERT_EQ(r1.status, 0) << r1.err;
  ASSERT_EQ(run("render " + q(scene) + " -o " + q(b) + " --threads 2").status, 0);
  ASSERT_EQ(run("render " + q(scene) + " -o " + q(c) + " --threads 7").status, 0);
  const json s = json::parse(slurp(sa));
  // Several hundred hairs of five segments each (density 400 over an area of about 16.6).
  EXPECT_GT(s.value("segments", 0), 5 * 1000);
  EXPECT_EQ(s.value("segments", 0) % 5, 0);
  EXPECT_EQ(slurp(a), slurp(b));
  EXPECT_EQ(slurp(a), slurp(c));
}

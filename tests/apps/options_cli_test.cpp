// The command line as CLI11 parses it (apps/main.cpp, apps/cli_options.cpp; docs/cli.md): every
// command answers --help and -h on stdout with exit status 0 and names its options; an option
// several commands share is refused with the same one line, naming the option and the limits
// of core/limits.h, in every command that takes it; CLI11's own multi-line messages never show.
#include "cli_support.h"
#include "core/limits.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using wf::test::lineCount;

const std::string kSide = std::to_string(wf::kMaxImageSide);

// The options each command's help must name.
const std::map<std::string, std::vector<std::string>> kOptions = {
    {"gallery", {"--out", "--scenes", "--size", "--quiet"}},
    {"accuracy", {"--json", "--plots", "--quick", "--quiet"}},
    {"render", {"INPUT", "--out", "--size", "--style", "--mask", "--threads", "--stats", "--budget", "--no-deep-shares", "--shading",
                "--reference", "--samples", "--measure-error", "--view-grid", "--memory-budget", "--simplify",
                "--wire-depth", "--time", "--quiet", "--deflection", "--linear-deflection", "--angular-deflection",
                "--isos", "--read-timeout"}},
    {"export", {"INPUT", "--out", "--style", "--time", "--quiet", "--deflection", "--linear-deflection",
                "--angular-deflection", "--isos", "--read-timeout"}},
    {"view", {"INPUT", "--style", "--size", "--mask", "--threads", "--frames", "--interactive-reduction", "--offscreen", "--png", "--quiet",
              "--deflection", "--linear-deflection", "--angular-deflection", "--isos", "--read-timeout"}},
};

}  // namespace

TEST(OptionsCli, EveryCommandAnswersHelpWithItsOptions) {
  for (const auto& [command, options] : kOptions)
    for (const char* flag : {"--help", "-h"}) {
      const wf::test::CliOutput r = wf::test::runWirefurWithOutput(command + " " + flag);
      EXPECT_EQ(r.status, 0) << command << " " << flag << ": " << r.err;
      EXPECT_EQ(r.err, "") << command << " " << flag;
      EXPECT_NE(r.out.find("Usage: wirefur " + command), std::string::npos) << command << " " << flag << ":\n" << r.out;
      for (const std::string& option : options)
        EXPECT_NE(r.out.find(option), std::string::npos) << command << " " << flag << " does not name " << option << ":\n"
                                                         << r.out;
    }
  // The limits in the help are the core's.
  for (const char* command : {"render", "view"})
    EXPECT_NE(wf::test::runWirefurWithOutput(std::string(command) + " --help").out.find("each side 1 ... " + kSide),
              std::string::npos)
        << command;
}

TEST(OptionsCli, TopLevelHelpListsTheCommands) {
  for (const char* args : {"--help", "-h", "help"}) {
    const wf::test::CliOutput r = wf::test::runWirefurWithOutput(args);
    EXPECT_EQ(r.status, 0) << args;
    EXPECT_EQ(r.err, "") << args;
    for (const auto& [command, options] : kOptions) EXPECT_NE(r.out.find(command), std::string::npos) << args << ": " << command;
    EXPECT_NE(r.out.find("--version"), std::string::npos) << args;
  }
  const wf::test::CliOutput v = wf::test::runWirefurWithOutput("--version");
  EXPECT_EQ(v.status, 0);
  EXPECT_EQ(v.out.rfind("wirefur ", 0), 0u) << v.out;
}

// A bad value of a shared option: exit 2, one line starting "wirefur: ", naming the option and
// what it takes; the same line in every command that takes the option.
TEST(OptionsCli, ABadSharedOptionIsTheSameOneLineInEveryCommand) {
  struct Case {
    std::string args;                   ///< after the command
    std::vector<std::string> commands;  ///< those that take the option
    std::string expect;                 ///< the whole message after "wirefur: "
  };
  const std::vector<Case> cases = {
      {"--size 0x10", {"render", "view"}, "option --size: expected WxH, each side an integer in [1, " + kSide + "], got '0x10'"},
      {"--size 12", {"render", "view"}, "option --size: expected WxH, each side an integer in [1, " + kSide + "], got '12'"},
      {"--threads 0", {"render", "view"}, "option --threads: expected an integer in [1, 1024], got '0'"},
      {"--threads many", {"render", "view"}, "option --threads: expected an integer in [1, 1024], got 'many'"},
      {"--mask 5x5", {"render", "view"}, "option --mask: expected 4x4, 8x4 or 8x8, got '5x5'"},
      {"--style fluffy", {"render", "view", "export"}, "option --style: expected wire, wire-over-surface, burnished, fur or scales, got 'fluffy'"},
      {"--time nan", {"render", "export"}, "option --time: expected a number in [-1e9, 1e9], got 'nan'"},
      {"--time 2e9", {"render", "export"}, "option --time: expected a number in [-1e9, 1e9], got '2e9'"},
      {"--deflection 0", {"render", "export", "view"}, "option --deflection: expected a number in [1e-7, 0.5], got '0'"},
      {"--angular-deflection 90", {"render", "export", "view"},
       "option --angular-deflection: expected a number in [1, 85], got '90'"},
      {"--isos 1001", {"render", "export", "view"}, "option --isos: expected an integer in [0, 1000], got '1001'"},
      {"--cad-timeout 0", {"render", "export", "view"}, "option --cad-timeout: expected a number in [0.1, 1e6], got '0'"},
      {"--read-timeout 0", {"render", "export", "view"}, "option --read-timeout: expected a number in [0.1, 1e6], got '0'"},
      {"--quiet=no", {"gallery", "accuracy", "render", "export", "view"}, "option --quiet takes no value"},
      {"-o", {"gallery", "render", "export"}, "option -o needs a value"},
      {"--size", {"gallery", "render", "view"}, "option --size needs a value"},
  };
  for (const Case& c : cases)
    for (const std::string& command : c.commands) {
      const wf::test::CliOutput r = wf::test::runWirefurWithOutput(command + " " + c.args);
      EXPECT_EQ(r.status, 2) << command << " " << c.args << ": " << r.err;
      EXPECT_EQ(lineCount(r.err), 1) << command << " " << c.args << ": " << r.err;
      EXPECT_EQ(r.err, "wirefur: " + c.expect + "\n") << command << " " << c.args;
      EXPECT_EQ(r.out, "") << command << " " << c.args;
    }
  // gallery's --size is one number, with the same largest side.
  const wf::test::CliOutput g = wf::test::runWirefurWithOutput("gallery --size " + std::to_string(wf::kMaxImageSide + 1));
  EXPECT_EQ(g.status, 2);
  EXPECT_EQ(g.err, "wirefur: option --size: expected an integer in [16, " + kSide + "], got '" +
                       std::to_string(wf::kMaxImageSide + 1) + "'\n");
}

// Every --size accepts the same largest side: the parse takes it, and the first problem is the
// missing input (nothing is rendered).
TEST(OptionsCli, EverySizeAcceptsTheLargestSide) {
  const std::string out = (wf::test::scratchDir("largest-side") / "gallery").string();
  for (const std::string& args : {"render /nonexistent/in.json -o /nonexistent/out.png --size " + kSide + "x" + kSide,
                                  "view /nonexistent/in.json --size " + kSide + "x" + kSide,
                                  "gallery --scenes /nonexistent/scenes -o '" + out + "' --size " + kSide}) {
    const wf::test::CliOutput r = wf::test::runWirefurWithOutput(args);
    EXPECT_EQ(r.status, 2) << args;
    EXPECT_EQ(lineCount(r.err), 1) << args << ": " << r.err;
    EXPECT_EQ(r.err.find("--size"), std::string::npos) << args << ": " << r.err;
    EXPECT_NE(r.err.find("/nonexistent/"), std::string::npos) << args << ": " << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(out)) << "a gallery that cannot start makes no folder";
}

// Lines CLI11 alone would misread: "--stats=" took the next argument as the stats file (and
// wrote over it), "-o=x.png" wrote a file named "=x.png", '' was "no input", help lost to a bad
// value, and a second input after "--" went up to the top level.
TEST(OptionsCli, EmptyValuesDashesAndHelpFirst) {
  const fs::path d = wf::test::scratchDir("empty-values");
  const std::string scene = wf::test::writeFile(d, "keep.json", "{}");
  struct Case {
    std::string args, expect;
  };
  for (const Case& c : std::vector<Case>{
           {"render --stats= '" + scene + "' -o x.png", "option --stats needs a value"},
           {"render -o=x.png '" + scene + "'", "option -o: write -o VALUE, without '='"},
           {"render '' -o x.png", "INPUT is empty"},
           {"render '" + scene + "' -o x.png --stats ''", "option --stats: empty value"},
           {"view --png '' --frames 1", "option --png: empty value"},
           {"render a.json -- b.json", "render: more than one input ('a.json' and 'b.json')"},
           {"render a.json -- --version", "render: more than one input ('a.json' and '--version')"},
           {"render -- a.json b.json", "only one input may follow '--'"},
           {"view --style fur", "--style applies to a mesh or CAD input, not to the built-in scene"}}) {
    const wf::test::CliOutput r = wf::test::runWirefurWithOutput(c.args);
    EXPECT_EQ(r.status, 2) << c.args;
    EXPECT_EQ(r.err, "wirefur: " + c.expect + "\n") << c.args;
  }
  EXPECT_EQ(wf::test::readFile(scene), "{}") << "the scene file is untouched";
  for (const std::string args : {"render --help --threads 0", "render -h -o", "export --bogus --help"}) {
    const wf::test::CliOutput r = wf::test::runWirefurWithOutput(args);
    EXPECT_EQ(r.status, 0) << args << ": " << r.err;
    EXPECT_NE(r.out.find("Usage: wirefur"), std::string::npos) << args;
  }
}

// Unknown options, unknown commands and stray arguments: one line, exit 2, in every command.
TEST(OptionsCli, UnknownOptionsAndStrayArgumentsAreOneLine) {
  for (const auto& [command, options] : kOptions) {
    const wf::test::CliOutput r = wf::test::runWirefurWithOutput(command + " --bogus 3");
    EXPECT_EQ(r.status, 2) << command;
    EXPECT_EQ(r.err, "wirefur: " + command + ": unknown option '--bogus' (try wirefur " + command + " --help)\n") << command;
  }
  for (const auto& [args, expect] : std::vector<std::pair<std::string, std::string>>{
           {"", "no command (try wirefur --help)"},
           {"frobnicate", "unknown command 'frobnicate' (try wirefur --help)"},
           {"--bogus render", "unknown option '--bogus' (try wirefur --help)"},
           {"render a.json b.json", "render: more than one input ('a.json' and 'b.json')"},
           {"export a.json b.json", "export: more than one input ('a.json' and 'b.json')"},
           {"view a.json b.json", "view: more than one input ('a.json' and 'b.json')"},
           {"gallery stray", "gallery: unexpected argument 'stray'"},
           {"render --version", "render: unknown option '--version' (try wirefur render --help)"}}) {
    const wf::test::CliOutput r = wf::test::runWirefurWithOutput(args);
    EXPECT_EQ(r.status, 2) << args;
    EXPECT_EQ(r.err, "wirefur: " + expect + "\n") << args;
  }
}

// An option given twice takes the last value (as before CLI11); each one is still checked.
TEST(OptionsCli, ARepeatedOptionTakesTheLastValueAndChecksEach) {
  const wf::test::CliOutput bad = wf::test::runWirefurWithOutput("render --threads 0 --threads 2");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("got '0'"), std::string::npos) << bad.err;
  const std::filesystem::path dir = wf::test::scratchDir("options_cli");
  const std::string png = (dir / "last.png").string(), stats = (dir / "last.json").string();
  const wf::test::CliOutput r = wf::test::runWirefurWithOutput("render -o '" + png + "' --size 32x24 --size 64x48 --mask 4x4 "
                                                               "--mask 8x8 --threads 1 --threads 2 --stats '" + stats + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(wf::test::readFile(stats));
  EXPECT_EQ(j["options"]["size"], nlohmann::json::array({64, 48}));
  EXPECT_EQ(j["options"]["mask"], "8x8");
  EXPECT_EQ(j["options"]["threads"], 2);
}

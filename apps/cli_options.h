// The wirefur command line on CLI11 (docs/cli.md): the options several commands share, each
// declared once here with its name, meaning, limits and help text; the one range check every
// number of the command line goes through; and the parse that turns CLI11's errors into the
// contract's one line (UsageError: "wirefur: ...", exit status 2).
#pragma once

#include "scene_file.h"  // CadOptions

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace CLI {
class App;
class Option;
class Validator;
}  // namespace CLI

namespace wfapp {

// ---- the range check ---------------------------------------------------------------------

/// What is wrong with `text` as an integer (decimal digits after an optional '-') in [lo, hi]:
/// "expected an integer in [1, 16], got '0'"; empty when nothing is.
std::string integerProblem(const std::string& text, long long lo, long long hi);

/// What is wrong with `text` as a finite number in [lo, hi] (the whole text, as strtod reads it):
/// "expected a number in [0.1, 64], got 'abc'"; empty when nothing is.
std::string numberProblem(const std::string& text, double lo, double hi);

/// A check of an option's value (a function giving what is wrong, or nothing) as a CLI11
/// validator: every occurrence of the option is checked, and the error names the option.
CLI::Validator checkedBy(std::function<std::string(const std::string&)> problem);

/// The two checks as CLI11 validators: every occurrence of the option is checked, and the error
/// names the option ("option --view-grid: expected an integer in [1, 16], got '0'").
CLI::Validator integerIn(long long lo, long long hi);
CLI::Validator numberIn(double lo, double hi);

/// Exactly one of `names`: "expected closed, maps or exact, got 'x'".
CLI::Validator oneOf(std::vector<std::string> names);

/// An integer option in [lo, hi] into `target`, a number option in [lo, hi] into `target`
/// (the value is read by the same code that checked it). The range replaces "{range}" in the
/// description, or follows it in parentheses.
CLI::Option* addIntegerOption(CLI::App& app, const std::string& name, int& target, int lo, int hi,
                              const std::string& description, const std::string& typeName = "N");
CLI::Option* addNumberOption(CLI::App& app, const std::string& name, double& target, double lo, double hi,
                             const std::string& description, const std::string& typeName);

/// A flag (no value) into `target`.
CLI::Option* addFlag(CLI::App& app, const std::string& name, bool& target, const std::string& description);

// ---- the options several commands share --------------------------------------------------

/// The command's creation with the settings every command has: unknown arguments are left for
/// parseCommandLine to report in one line, and an option given twice takes its last value.
CLI::App* addCommand(CLI::App& wirefur, const std::string& name, const std::string& description);

/// INPUT (positional): a scene .json, a CAD file or a mesh / polyline file.
CLI::Option* addInputArgument(CLI::App& app, std::string& input, const std::string& description);
/// -o, --out PATH.
CLI::Option* addOutputOption(CLI::App& app, std::string& path, const std::string& typeName, const std::string& description);
/// --size WxH: each side 1 ... wf::kMaxImageSide.
CLI::Option* addSizeOption(CLI::App& app, int& width, int& height, const std::string& defaultText);
/// --style STYLE, one of `styles`.
CLI::Option* addStyleOption(CLI::App& app, std::string& style, const std::vector<std::string>& styles,
                            const std::string& description);
/// --mask 4x4|8x4|8x8.
/// Parses `--hidden`'s value: off, hide, dashed[=DASH,GAP] (pixels), ghost[=OPACITY]; the
/// problem, or empty.
std::string parseHidden(const std::string& text, wf::HiddenLines& hidden);
/// --hidden MODE (HiddenLines: how wire-frames draw where surfaces hide them).
CLI::Option* addHiddenOption(CLI::App& app, std::optional<wf::HiddenLines>& hidden);
/// --edges all|sharp|boundary, --seams on|off, --feature-angle DEG (render/edge_classes.h).
void addEdgeOptions(CLI::App& app, wf::EdgeOverrides& edges);
/// --grain u|v|longer|circular|radial, --grain-axis P,D, --grooves-per-mm N (scene/style_presets.h).
void addBurnishOptions(CLI::App& app, wf::BurnishOverrides& burnish);
/// --silhouettes on|off (the silhouettes of curved faces with the wire-frame).
CLI::Option* addSilhouettesOption(CLI::App& app, std::optional<bool>& silhouettes);
CLI::Option* addMaskOption(CLI::App& app, std::string& mask);
/// --threads N: 1 ... wf::kMaxThreads.
CLI::Option* addThreadsOption(CLI::App& app, int& threads);
/// --quiet.
CLI::Option* addQuietOption(CLI::App& app, bool& quiet);
/// --time T: every fur's wind time, |T| <= wf::kMaxWindTime.
CLI::Option* addTimeOption(CLI::App& app, std::optional<double>& time);
/// The CAD options: --deflection, --linear-deflection, --angular-deflection, --isos, --cad-timeout
/// (the limits of a scene's cad block, core/limits.h).
void addCadOptions(CLI::App& app, CadOptions& cad);

// ---- the parse ---------------------------------------------------------------------------

/// Parses `args` (those after the program's name) with `wirefur` and its commands. --help (-h)
/// and --version are answered on stdout and give false (the caller exits 0); true: a command
/// was chosen and its options are set. Anything wrong (an unknown command or option, a missing
/// value, a bad value, a second input) throws one UsageError line naming it; CLI11's own
/// messages never reach the terminal as they are.
bool parseCommandLine(CLI::App& wirefur, const std::vector<std::string>& args);

/// The command parseCommandLine chose, or nullptr.
const CLI::App* chosenCommand(const CLI::App& wirefur);

}  // namespace wfapp

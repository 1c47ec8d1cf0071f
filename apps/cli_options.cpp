#include "cli_options.h"

#include "cli.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <iostream>

namespace wfapp {

namespace {

std::optional<long long> readInteger(const std::string& text) {
  long long v = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, v);  // decimal, an optional '-', nothing else
  if (text.empty() || ec != std::errc() || ptr != end) return std::nullopt;
  return v;
}

std::optional<double> readNumber(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v)) return std::nullopt;
  return v;
}

// A limit as people write it: 0.5, 85, 1e-7, 1e9 (not %g's 1e-07, 1e+09).
std::string limitText(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  std::string s = b;
  const size_t e = s.find('e');
  if (e == std::string::npos) return s;
  std::string exponent = s.substr(e + 1);
  const bool negative = exponent[0] == '-';
  exponent.erase(0, exponent.find_first_not_of("+-0"));
  return s.substr(0, e + 1) + (negative ? "-" : "") + exponent;
}

std::string rangeText(double lo, double hi) { return limitText(lo) + " ... " + limitText(hi); }

// The help text with the range in place of "{range}" (or after it).
std::string withRange(const std::string& description, double lo, double hi) {
  const size_t at = description.find("{range}");
  if (at == std::string::npos) return description + " (" + rangeText(lo, hi) + ")";
  return description.substr(0, at) + rangeText(lo, hi) + description.substr(at + 7);
}

// One line from a CLI11 error: an option's error starts with its name.
std::string cliErrorLine(const std::string& what) {
  std::string s = what;
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return !s.empty() && s[0] == '-' ? "option " + s : s;
}

bool looksLikeOption(const std::string& a) { return a.size() > 1 && a[0] == '-'; }

}  // namespace

std::string integerProblem(const std::string& text, long long lo, long long hi) {
  const std::optional<long long> v = readInteger(text);
  if (v && *v >= lo && *v <= hi) return {};
  return "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got '" + text + "'";
}

std::string numberProblem(const std::string& text, double lo, double hi) {
  const std::optional<double> v = readNumber(text);
  if (v && *v >= lo && *v <= hi) return {};
  return "expected a number in [" + limitText(lo) + ", " + limitText(hi) + "], got '" + text + "'";
}

CLI::Validator checkedBy(std::function<std::string(const std::string&)> problem) {
  // No description: the option's help says what it takes.
  return CLI::Validator([problem = std::move(problem)](std::string& text) { return problem(text); }, "");
}

CLI::Validator integerIn(long long lo, long long hi) {
  return checkedBy([lo, hi](const std::string& text) { return integerProblem(text, lo, hi); });
}

CLI::Validator numberIn(double lo, double hi) {
  return checkedBy([lo, hi](const std::string& text) { return numberProblem(text, lo, hi); });
}

CLI::Validator oneOf(std::vector<std::string> names) {
  std::string list;
  for (size_t i = 0; i < names.size(); ++i) list += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  return checkedBy([names = std::move(names), list](const std::string& text) -> std::string {
    for (const std::string& n : names)
      if (text == n) return {};
    return "expected " + list + ", got '" + text + "'";
  });
}

CLI::Option* addIntegerOption(CLI::App& app, const std::string& name, int& target, int lo, int hi,
                              const std::string& description, const std::string& typeName) {
  return app
      .add_option_function<std::string>(
          name, [&target](const std::string& v) { target = int(*readInteger(v)); }, withRange(description, lo, hi))
      ->check(integerIn(lo, hi))
      ->type_name(typeName)
      ->trigger_on_parse();  // checked and set in the order given, as each one is read
}

CLI::Option* addNumberOption(CLI::App& app, const std::string& name, double& target, double lo, double hi,
                             const std::string& description, const std::string& typeName) {
  return app
      .add_option_function<std::string>(
          name, [&target](const std::string& v) { target = *readNumber(v); }, withRange(description, lo, hi))
      ->check(numberIn(lo, hi))
      ->type_name(typeName)
      ->trigger_on_parse();
}

CLI::App* addCommand(CLI::App& wirefur, const std::string& name, const std::string& description) {
  CLI::App* c = wirefur.add_subcommand(name, description);
  c->group("Commands");
  c->allow_extras();  // parseCommandLine reports what is left, in one line
  c->option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  return c;
}

CLI::Option* addInputArgument(CLI::App& app, std::string& input, const std::string& description) {
  return app.add_option("INPUT", input, description)->type_name("");
}

CLI::Option* addOutputOption(CLI::App& app, std::string& path, const std::string& typeName, const std::string& description) {
  return app.add_option("-o,--out", path, description)->type_name(typeName)->trigger_on_parse();
}

CLI::Option* addSizeOption(CLI::App& app, int& width, int& height, const std::string& defaultText) {
  const int most = wf::kMaxImageSide;
  auto problem = [most](const std::string& text) -> std::string {
    const size_t x = text.find('x');
    if (x != std::string::npos && integerProblem(text.substr(0, x), 1, most).empty() &&
        integerProblem(text.substr(x + 1), 1, most).empty())
      return {};
    return "expected WxH, each side an integer in [1, " + std::to_string(most) + "], got '" + text + "'";
  };
  return app
      .add_option_function<std::string>(
          "--size",
          [&width, &height](const std::string& v) {
            const size_t x = v.find('x');
            width = int(*readInteger(v.substr(0, x)));
            height = int(*readInteger(v.substr(x + 1)));
          },
          "image size in pixels, each side 1 ... " + std::to_string(most) + " (" + defaultText + ")")
      ->check(checkedBy(problem))
      ->type_name("WxH")
      ->trigger_on_parse();
}

CLI::Option* addStyleOption(CLI::App& app, std::string& style, const std::vector<std::string>& styles,
                            const std::string& description) {
  return app.add_option("--style", style, description)->check(oneOf(styles))->type_name("STYLE")->trigger_on_parse();
}

std::string parseHidden(const std::string& text, wf::HiddenLines& h) {
  const size_t eq = text.find('=');
  const std::string mode = text.substr(0, eq);
  const std::string expected = "expected off, hide, dashed[=DASH,GAP] or ghost[=OPACITY], got '" + text + "'";
  if (!wf::parseHiddenMode(mode, h.mode)) return expected;
  if (eq == std::string::npos) return {};
  const std::string value = text.substr(eq + 1);
  if (h.mode == wf::HiddenLines::Mode::Dashed) {
    const size_t comma = value.find(',');
    if (comma == std::string::npos) return "dashed=DASH,GAP: expected two lengths in pixels, got '" + value + "'";
    const std::string dash = value.substr(0, comma), gap = value.substr(comma + 1);
    if (std::string p = numberProblem(dash, 0.5, 1000); !p.empty()) return "dash length: " + p;
    if (std::string p = numberProblem(gap, 0.5, 1000); !p.empty()) return "gap length: " + p;
    h.dash = std::strtod(dash.c_str(), nullptr);
    h.gap = std::strtod(gap.c_str(), nullptr);
    return {};
  }
  if (h.mode == wf::HiddenLines::Mode::Ghost) {
    if (std::string p = numberProblem(value, 0.01, 1); !p.empty()) return "ghost opacity: " + p;
    h.ghost = float(std::strtod(value.c_str(), nullptr));
    return {};
  }
  return expected;
}

CLI::Option* addHiddenOption(CLI::App& app, std::optional<wf::HiddenLines>& hidden) {
  return app
      .add_option_function<std::string>(
          "--hidden",
          [&hidden](const std::string& v) {
            wf::HiddenLines h;
            parseHidden(v, h);
            hidden = h;
          },
          "edges behind surfaces: off (default: as today), hide (also in the wire style, against the "
          "part's faces), dashed[=DASH,GAP] (pixels, default 6,4), ghost[=OPACITY] (default 0.3)")
      ->check(checkedBy([](const std::string& v) {
        wf::HiddenLines h;
        return parseHidden(v, h);
      }))
      ->type_name("MODE")
      ->trigger_on_parse();
}

CLI::Option* addSilhouettesOption(CLI::App& app, std::optional<bool>& silhouettes) {
  return app
      .add_option_function<std::string>(
          "--silhouettes", [&silhouettes](const std::string& v) { silhouettes = v == "on"; },
          "the silhouettes of curved faces, traced from the exact surfaces for the view, drawn with the "
          "edges (default: on for the wire styles of CAD files; off otherwise)")
      ->check(oneOf({"on", "off"}))
      ->type_name("on|off")
      ->trigger_on_parse();
}

void addEdgeOptions(CLI::App& app, wf::EdgeOverrides& edges) {
  app.add_option_function<std::string>(
         "--edges",
         [&edges](const std::string& v) {
           wf::EdgeSelection::Mode m = wf::EdgeSelection::Mode::All;
           wf::parseEdgeMode(v, m);
           edges.mode = m;
         },
         "which edges the wire-frame draws: all (default), sharp (hard edges: where faces meet at more than "
         "the feature angle, and borders), boundary (borders of open shells)")
      ->check(oneOf({"all", "sharp", "boundary"}))
      ->type_name("all|sharp|boundary")
      ->trigger_on_parse();
  app.add_option_function<std::string>(
         "--seams", [&edges](const std::string& v) { edges.seams = v == "on"; },
         "seam edges (a face on both sides: a cylinder's seam) drawn too (default off)")
      ->check(oneOf({"on", "off"}))
      ->type_name("on|off")
      ->trigger_on_parse();
  app.add_option_function<std::string>(
         "--feature-angle", [&edges](const std::string& v) { edges.featureAngle = *readNumber(v); },
         withRange("degrees: faces whose normals differ by more along their edge meet at a sharp edge, else a "
                   "smooth one (default 10), {range}",
                   0.0, 180.0))
      ->check(numberIn(0.0, 180.0))
      ->type_name("DEG")
      ->trigger_on_parse();
}

namespace {
// "PX,PY,PZ,DX,DY,DZ": six finite numbers, the direction not zero.
std::string parseAxis(const std::string& v, glm::dvec3& point, glm::dvec3& direction) {
  double x[6];
  std::string rest = v;
  for (int i = 0; i < 6; ++i) {
    const size_t comma = rest.find(',');
    const std::string part = rest.substr(0, comma);
    const std::optional<double> n = readNumber(part);
    if (!n || !std::isfinite(*n) || (i < 5) == (comma == std::string::npos))
      return "expected PX,PY,PZ,DX,DY,DZ (a point of the axis and its direction), got '" + v + "'";
    x[i] = *n;
    rest = comma == std::string::npos ? std::string() : rest.substr(comma + 1);
  }
  point = {x[0], x[1], x[2]};
  direction = {x[3], x[4], x[5]};
  if (!(glm::length(direction) > 0) || !std::isfinite(glm::length(direction))) return "the axis direction must not be zero";
  return {};
}
}  // namespace

void addBurnishOptions(CLI::App& app, wf::BurnishOverrides& b) {
  app.add_option_function<std::string>(
         "--grain",
         [&b](const std::string& v) {
           using G = wf::BurnishOverrides::Grain;
           b.grain = v == "u" ? G::U : v == "v" ? G::V : v == "longer" ? G::Longer : v == "circular" ? G::Circular : G::Radial;
           if (b.axisPoint && *b.grain != G::Circular && *b.grain != G::Radial)
             throw CLI::ValidationError("--grain " + v, "--grain-axis needs --grain circular or radial");
         },
         "brushed steel's grain (burnished surfaces): along each face's u, v, or longer extent (default for CAD "
         "files), circular or radial about --grain-axis (turned parts)")
      ->check(oneOf({"u", "v", "longer", "circular", "radial"}))
      ->type_name("u|v|longer|circular|radial")
      ->trigger_on_parse();
  app.add_option_function<std::string>(
         "--grain-axis",
         [&b](const std::string& v) {
           glm::dvec3 p, d;
           parseAxis(v, p, d);
           b.axisPoint = p, b.axisDirection = d;
           using G = wf::BurnishOverrides::Grain;
           if (b.grain && *b.grain != G::Circular && *b.grain != G::Radial)
             throw CLI::ValidationError("--grain-axis", "needs --grain circular or radial");
         },
         "the axis of circular and radial grain: a point and a direction (default: through the part's bounding-box "
         "centre, along z)")
      ->check(checkedBy([](const std::string& v) {
        glm::dvec3 p, d;
        return parseAxis(v, p, d);
      }))
      ->type_name("PX,PY,PZ,DX,DY,DZ")
      ->trigger_on_parse();
  // An axis with no grain at all (the check above sees only a grain given before it). This takes
  // the subcommand's one parse-complete callback: a second check there must join this one.
  app.parse_complete_callback([&b] {
    if (b.axisPoint && !b.grain) throw CLI::ValidationError("--grain-axis", "needs --grain circular or radial");
  });
  app.add_option_function<std::string>(
         "--grooves-per-mm", [&b](const std::string& v) { b.groovesPerUnit = *readNumber(v); },
         withRange("visible grooves of brushed steel per millimetre (world unit) across the grain (default 10 for "
                   "the burnished style; 0: none), {range}",
                   0.0, 1e6))
      ->check(numberIn(0.0, 1e6))
      ->type_name("N")
      ->trigger_on_parse();
}

CLI::Option* addMaskOption(CLI::App& app, std::string& mask) {
  return app.add_option("--mask", mask, "coverage mask: subsamples per pixel (default: the scene's, else 8x4)")
      ->check(oneOf({"4x4", "8x4", "8x8"}))
      ->type_name("4x4|8x4|8x8")
      ->trigger_on_parse();
}

CLI::Option* addThreadsOption(CLI::App& app, int& threads) {
  return addIntegerOption(app, "--threads", threads, 1, wf::kMaxThreads,
                          "worker threads, {range} (default: all cores; the image is the same for any count)");
}

CLI::Option* addFlag(CLI::App& app, const std::string& name, bool& target, const std::string& description) {
  return app.add_flag(name, target, description)->disable_flag_override();  // --quiet, not --quiet=no
}

CLI::Option* addQuietOption(CLI::App& app, bool& quiet) {
  return addFlag(app, "--quiet", quiet, "no progress lines (shown only on a terminal, outside CI)");
}

CLI::Option* addTimeOption(CLI::App& app, std::optional<double>& time) {
  const double most = wf::kMaxWindTime;
  return app
      .add_option_function<std::string>(
          "--time", [&time](const std::string& v) { time = *readNumber(v); },
          "the time of every fur's wind (the scene's wind.time), " + rangeText(-most, most) +
              ": the same T gives the same hairs")
      ->check(numberIn(-most, most))
      ->type_name("T")
      ->trigger_on_parse();
}

void addCadOptions(CLI::App& app, CadOptions& cad) {
  const std::string group = "CAD options (.step .stp .iges .igs .brep .FCStd input)";
  // --deflection and --linear-deflection set the same value: the last one given wins.
  auto deflection = [&](const char* name, bool absolute, double lo, double hi, const std::string& help, const char* type) {
    app.add_option_function<std::string>(
           name,
           [&cad, absolute](const std::string& v) {
             cad.deflection = *readNumber(v);
             cad.absoluteDeflection = absolute;
           },
           withRange(help, lo, hi))
        ->check(numberIn(lo, hi))
        ->type_name(type)
        ->trigger_on_parse()
        ->group(group);
  };
  deflection("--deflection", false, wf::kMinCadDeflection, wf::kMaxCadDeflection,
             "chordal deflection as a fraction of the model's diagonal, {range} (default 0.001)", "D");
  deflection("--linear-deflection", true, wf::kMinCadLinearDeflection, wf::kMaxCadLinearDeflection,
             "the chordal deflection in world units instead, {range}", "L");
  addNumberOption(app, "--angular-deflection", cad.angularDegrees, wf::kMinCadAngularDegrees, wf::kMaxCadAngularDegrees,
                  "angular deflection in degrees, {range} (default about 20)", "DEG")
      ->group(group);
  addIntegerOption(app, "--isos", cad.isos, 0, wf::kMaxCadIsos, "u and v iso lines per face, {range} (default 0)")->group(group);
  // Only here: the worker's time limit is no scene key.
  addNumberOption(app, "--read-timeout", cad.timeoutSeconds, 0.1, 1e6,
                  "read CAD, mesh and polyline files in a worker process stopped after S seconds, {range} "
                  "(default 600)", "S")
      ->group(group);
  // Its older name, kept for scripts.
  addNumberOption(app, "--cad-timeout", cad.timeoutSeconds, 0.1, 1e6, "the same as --read-timeout (its older name)", "S")
      ->group(group);
}

bool parseCommandLine(CLI::App& wirefur, const std::vector<std::string>& args) {
  // Before CLI11 sees them (up to a "--"): help first, whatever else is on the line; an option
  // written "--stats=" or "-o=..." (CLI11 would take the next argument as the value of the
  // first, and write over it, and give the second a file named "=..."); at most one argument
  // after "--".
  const auto dashes = std::find(args.begin(), args.end(), std::string("--"));
  for (auto it = args.begin(); it != dashes; ++it) {
    const std::string& a = *it;
    if (a == "-h" || a == "--help") {
      std::vector<std::string> help;
      if (args.front() != a && !looksLikeOption(args.front())) help.push_back(args.front());  // the command
      help.push_back("--help");
      if (help.size() == args.size() && help == args) break;  // this very line: let CLI11 print it
      return parseCommandLine(wirefur, help);
    }
    if (a.size() > 1 && a[0] == '-' && a.back() == '=' && a.find('=') == a.size() - 1)
      throw UsageError("option " + a.substr(0, a.size() - 1) + " needs a value");
    if (a.size() > 2 && a[0] == '-' && a[1] != '-' && a[2] == '=')
      throw UsageError("option " + a.substr(0, 2) + ": write " + a.substr(0, 2) + " VALUE, without '='");
  }
  if (dashes != args.end() && args.end() - dashes > 2)
    throw UsageError("only one input may follow '--'");
  // The input after "--" (one that starts with '-') is set here, after CLI11 has parsed the
  // rest: CLI11 would hand it up to the top level once the command had its INPUT.
  const std::string afterDashes = dashes != args.end() && dashes + 1 != args.end() ? *(dashes + 1) : std::string();
  const bool hasAfterDashes = dashes != args.end() && dashes + 1 != args.end();
  std::vector<std::string> head(args.begin(), dashes);
  std::vector<std::string> reversed(head.rbegin(), head.rend());  // CLI11 reads from the back
  try {
    wirefur.parse(reversed);
  } catch (const CLI::CallForHelp&) {
    std::cout << wirefur.help();  // the chosen command's help, else the list of commands
    return false;
  } catch (const CLI::CallForAllHelp&) {
    std::cout << wirefur.help("", CLI::AppFormatMode::All);
    return false;
  } catch (const CLI::CallForVersion& e) {
    std::cout << e.what() << "\n";
    return false;
  } catch (const CLI::ArgumentMismatch& e) {
    const std::string what = e.what();
    // CLI11 takes an option's value whatever it looks like, so it runs out of values only at
    // the end of the line: the last argument is the option without one ("--x: 1 required N missing").
    const std::string& last = args.empty() ? std::string() : args.back();
    const size_t equals = last.find('=');
    if (looksLikeOption(last) && (equals == std::string::npos || equals + 1 == last.size()) && what.ends_with(" missing"))
      throw UsageError("option " + last.substr(0, equals) + " needs a value");
    // A flag given a value ("--quiet=no": "quiet was given a disallowed flag override").
    if (const size_t at = what.find(" was given a disallowed flag override"); at != std::string::npos) {
      const std::string name = what.substr(0, at);
      throw UsageError("option " + (name.starts_with("-") ? name : "--" + name) + " takes no value");
    }
    throw UsageError(cliErrorLine(what));
  } catch (const CLI::ParseError& e) {
    throw UsageError(cliErrorLine(e.what()));
  }
  const CLI::App* command = chosenCommand(wirefur);
  CLI::Option* input = command ? wirefur.get_subcommands().front()->get_option_no_throw("INPUT") : nullptr;
  if (hasAfterDashes) {
    if (!command) throw UsageError("no command (try wirefur --help)");
    if (!input) throw UsageError(command->get_name() + ": unexpected argument '" + afterDashes + "'");
    if (!input->results().empty())
      throw UsageError(command->get_name() + ": more than one input ('" + input->results().front() + "' and '" + afterDashes + "')");
    input->add_result(afterDashes);
    input->run_callback();
  }
  // What CLI11 left (every command allows extras, so that they are reported here in one line);
  // what a command passed up (after its INPUT) is the command's.
  for (const std::string& a : wirefur.remaining()) {
    if (a == "--") continue;
    if (command && input && !input->results().empty())
      throw UsageError(command->get_name() + ": more than one input ('" + input->results().front() + "' and '" + a + "')");
    throw UsageError((looksLikeOption(a) ? "unknown option '" : "unknown command '") + a + "' (try wirefur --help)");
  }
  if (!command) throw UsageError("no command (try wirefur --help)");
  // An empty value ('' for INPUT, -o, --stats, --png, --json ...) names nothing: refused, not
  // read as "no input" or "no file".
  for (const CLI::Option* opt : command->get_options())
    for (const std::string& r : opt->results())
      if (r.empty())
        throw UsageError(opt->get_name() == "INPUT" ? "INPUT is empty" : "option " + opt->get_name() + ": empty value");
  for (const std::string& a : command->remaining()) {
    if (a == "--") continue;
    const std::string& name = command->get_name();
    if (looksLikeOption(a)) throw UsageError(name + ": unknown option '" + a + "' (try wirefur " + name + " --help)");
    if (input && !input->results().empty())
      throw UsageError(name + ": more than one input ('" + input->results().front() + "' and '" + a + "')");
    throw UsageError(name + ": unexpected argument '" + a + "'");
  }
  return true;
}

const CLI::App* chosenCommand(const CLI::App& wirefur) {
  const std::vector<CLI::App*> chosen = wirefur.get_subcommands();
  return chosen.empty() ? nullptr : chosen.front();
}

}  // namespace wfapp

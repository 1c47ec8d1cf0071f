// wirefur: the command-line face of WireFur (see docs/cli.md for the contract).
#include "accuracy.h"
#include "cli.h"
#include "gallery.h"

#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

namespace {

constexpr const char* kUsage =
    "usage: wirefur <command> [options]\n"
    "  gallery  [-o DIR] [--size N] [--quiet]        render every picture into DIR (default out/) with index.html\n"
    "  accuracy [--json FILE] [--plots DIR] [--quick] [--quiet]\n"
    "                                               error against run time of every shading approximation\n"
    "  render, view, export                          not in this version yet (they need the A-buffer)\n"
    "  --help, --version\n";

std::string need(const std::vector<std::string>& a, size_t& i) {
  if (i + 1 >= a.size()) throw wfapp::UsageError("option " + a[i] + " needs a value");
  return a[++i];
}

int run(const std::vector<std::string>& a) {
  if (a.empty() || a[0] == "--help" || a[0] == "-h" || a[0] == "help") {
    std::cout << kUsage;
    return a.empty() ? 2 : 0;
  }
  if (a[0] == "--version") {
    std::cout << "wirefur 0.1.0\n";
    return 0;
  }
  const std::string cmd = a[0];
  if (cmd == "gallery") {
    wfapp::GalleryOptions o;
    for (size_t i = 1; i < a.size(); ++i) {
      if (a[i] == "-o" || a[i] == "--out") o.outDir = need(a, i);
      else if (a[i] == "--size") o.size = wfapp::parsePositiveInt("--size", need(a, i));
      else if (a[i] == "--quiet") o.quiet = true;
      else throw wfapp::UsageError("gallery: unknown option '" + a[i] + "'");
    }
    if (o.size < 16 || o.size > 8192) throw wfapp::UsageError("option --size: expected 16 ... 8192");
    return wfapp::runGallery(o);
  }
  if (cmd == "accuracy") {
    wfapp::AccuracyOptions o;
    for (size_t i = 1; i < a.size(); ++i) {
      if (a[i] == "--json") o.jsonPath = need(a, i);
      else if (a[i] == "--plots") o.plotsDir = need(a, i);
      else if (a[i] == "--quick") o.quick = true;
      else if (a[i] == "--quiet") o.quiet = true;
      else throw wfapp::UsageError("accuracy: unknown option '" + a[i] + "'");
    }
    return wfapp::runAccuracy(o);
  }
  if (cmd == "render" || cmd == "view" || cmd == "export") {
    std::cerr << "wirefur: '" << cmd << "' is not in this version yet (it needs the A-buffer renderer)\n";
    return 1;
  }
  throw wfapp::UsageError("unknown command '" + cmd + "' (try wirefur --help)");
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(std::vector<std::string>(argv + 1, argv + argc));
  } catch (const wfapp::UsageError& e) {
    std::cerr << "wirefur: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "wirefur: internal error: " << e.what() << "\n";
    return 1;
  }
}

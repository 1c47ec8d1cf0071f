// Scaling benchmark of issue 7: "time growing no faster than linearly in segments from 10,000 to
// 4,000,000 (fit the exponent and report it); peak memory bounded by the tile budget, not by the
// depth complexity (report bytes per fragment and per pixel)."
//
// Part 1, segments: N hairs of hair_torus.h (the peer benchmark's scene and camera) at 1920x1080,
// drawn as the paper's SHADED wire (a Phong material through the pseudo-reflectance map, two
// directional lights), so that the shading tables' build and lookups are in the time. Each N runs
// in its own forked child (ru_maxrss is its own); the time is the median of R renders, split into
// setup / maps / binning / raster from RenderStats. time = a N^b is fitted by least squares in
// log-log, over the whole range and over 100k ... 4M (small N are dominated by fixed costs: the
// tables, the image, the tiles).
//
// Part 2, depth complexity: a fixed number S of segments as S / D hairs of hair_torus.h, each
// drawn D times, copy i scaled about the eye by 1 + 0.05 i / D: every copy projects onto exactly
// the same pixels (the width is in pixels), one behind the other, so a pixel under a hair gets
// about D times the fragments. Two materials: opaque (default options) and translucent
// (opacity 0.3, occlusionEpsilon 0: nothing is culled, every list fills to the budget K and spills
// into its tail, the worst case for the A-buffer's memory). The tile buffers' peak bytes are
// reported against the bound threads x (fixed tile part + nextPow2(T^2 K) list entries +
// T^2 tails and solid fragments).
//
//   bench_scaling [--segments 10000,30000,...] [--size 1920x1080] [--repeats 5] [--threads T]
//                 [--depth-segments S] [--depth-stacks 1,10,100,1000,5000] [--no-depth]
//                 [--markdown FILE] [--json FILE] [--plots DIR] [--check] [--quiet]
//
// The full run (scripts/bench_scaling.sh):
//   build/bench_scaling --repeats 5 --markdown out/scaling.md --json out/scaling.json --plots out/scaling
// The CI smoke test runs it with --segments 10000,30000 --size 640x480 --repeats 1 --check, which
// fails (exit 3) when the fitted exponent is not finite, when fragments do not grow with N within
// tolerance, when the stacked scene does not reach its depth complexity, or when the tile buffers'
// peak bytes exceed the bound.
#include "bench_support.h"
#include "hair_torus.h"

#include "abuffer/abuffer.h"
#include "plot.h"
#include "render/pipeline.h"
#include "render/renderer.h"

#include <nlohmann/json.hpp>
#include <tbb/info.h>

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using json = nlohmann::ordered_json;

struct Args {
  std::vector<size_t> segments{10000, 30000, 100000, 300000, 1000000, 2000000, 4000000};
  int width = 1920, height = 1080;
  int repeats = 5;
  int threads = 0;
  size_t depthSegments = 200000;
  std::vector<size_t> depthStacks{1, 10, 100, 1000, 5000};
  bool depth = true;
  bool check = false;
  bool quiet = false;
  std::string markdownPath, jsonPath, plotDir;
};

constexpr size_t kFitFrom = 100000;  // the second fit: N >= this

using wfbench::median;

std::vector<size_t> parseList(const std::string& s) {
  std::vector<size_t> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ',')) {
    double v = 0;
    char suffix = 0;
    if (std::sscanf(item.c_str(), "%lf%c", &v, &suffix) < 1 || !(v >= 1)) throw std::invalid_argument(item);
    if (suffix == 'k' || suffix == 'K') v *= 1e3;
    if (suffix == 'm' || suffix == 'M') v *= 1e6;
    out.push_back(size_t(std::llround(v)));
  }
  if (out.empty()) throw std::invalid_argument(s);
  return out;
}

// The peer benchmark's camera; a brown Phong hair material and two lights, so that the shaded
// wire's table is built and looked up as in a real render.
wf::Scene hairScene(const std::vector<wfbench::HairSegment>& segs, float opacity) {
  wf::Scene scene;
  scene.camera = wfbench::camera();
  scene.background = glm::vec4(0, 0, 0, 1);
  scene.lights.ambient = glm::dvec3(0.05);
  scene.lights.lights.push_back({glm::normalize(glm::dvec3(1.0, -1.0, 2.0)), glm::dvec3(0.9)});
  scene.lights.lights.push_back({glm::normalize(glm::dvec3(-1.0, -0.5, 0.5)), glm::dvec3(0.3)});
  wf::Material hair;
  hair.name = "hair";
  hair.phong.diffuse = glm::dvec3(0.45, 0.30, 0.18);
  hair.phong.specular = glm::dvec3(0.3);
  hair.phong.exponent = 40.0;
  scene.materials = {hair};
  wf::SceneWire wire;
  wire.name = "hairs";
  wire.style = wf::WireStyle::Shaded;
  wire.material = 0;
  wire.thickness = wfbench::kHairWidthPixels;
  wire.thicknessInPixels = true;
  wire.opacity = opacity;
  // Hairs: the polyline is the cylinder's axis. (Left at the default, edges resting on a surface,
  // they were culled only where their axis is hidden, and the 4M-segment render had grown from
  // 28.5M to 303M fragments considered, 3.9 -> 8.9 s.)
  wire.restsOnSurface = false;
  wire.lines = wfbench::polylines(segs);
  scene.wires.push_back(std::move(wire));
  return scene;
}

// `hairs` hairs, each `stack` times, copy i scaled about the eye by 1 + 0.05 i / stack: the same
// screen footprint, one behind the other.
std::vector<wfbench::HairSegment> stackedHairs(size_t hairs, size_t stack) {
  const std::vector<wfbench::HairSegment> base = wfbench::hairTorus(hairs);
  const glm::dvec3 eye = wfbench::HairCamera{}.eye;
  std::vector<wfbench::HairSegment> out;
  out.reserve(hairs * stack);
  for (const auto& h : base)
    for (size_t i = 0; i < stack; ++i) {
      const double s = 1.0 + 0.05 * double(i) / double(stack);
      out.push_back({eye + (h.p0 - eye) * s, eye + (h.p1 - eye) * s});
    }
  return out;
}

int concurrency(int threads) { return threads > 0 ? threads : tbb::info::default_concurrency(); }

// The most the tile buffers can hold, from the code of TileABuffer (src/abuffer/abuffer.h): the
// fixed part of a tile (pixel records, occlusion, counts, the reserved subpixel depths) measured
// from an empty buffer, plus list entries (TileABuffer::listEntryBytes(), and a free-list index)
// for at most T^2 K live fragments (vectors grow by doubling: the capacity is the next power of
// two), plus one tail (24 bytes) and one solid Fragment per pixel; times the threads, each of
// which keeps its own buffer.
json tileBound(const wf::RenderOptions& opt) {
  wf::TileABuffer empty(opt.mask, opt.budget, float(opt.occlusionEpsilon));
  empty.reset(opt.tileSize, opt.tileSize);
  const size_t fixed = empty.bytes();
  const size_t P = size_t(opt.tileSize) * size_t(opt.tileSize);
  const size_t nodeBytes = wf::TileABuffer::listEntryBytes();
  const size_t tailBytes = 6 * sizeof(float);
  const size_t lists = std::bit_ceil(P * size_t(opt.budget)) * (nodeBytes + sizeof(std::int32_t));
  const size_t perPixel = std::bit_ceil(P) * (tailBytes + sizeof(wf::Fragment));
  const size_t perThread = fixed + lists + perPixel;
  json j;
  j["tile_size"] = opt.tileSize;
  j["budget"] = opt.budget;
  j["threads"] = concurrency(opt.threads);
  j["fixed_bytes_per_thread"] = fixed;
  j["list_bytes_per_thread"] = lists;
  j["tail_and_solid_bytes_per_thread"] = perPixel;
  j["bound_bytes"] = perThread * size_t(concurrency(opt.threads));
  j["fragment_bytes"] = sizeof(wf::Fragment);
  j["list_entry_bytes"] = nodeBytes;
  return j;
}

// Everything a render reports about time, fragments and memory.
void renderFigures(const wf::Scene& scene, const wf::RenderOptions& opt, int repeats, json& j) {
  std::vector<double> total, setup, maps, binning, raster;
  wf::RenderResult r;
  for (int i = 0; i < repeats; ++i) {
    r = wf::render(scene, opt);
    total.push_back(r.stats.total);
    setup.push_back(r.stats.setup);
    maps.push_back(r.stats.maps);
    binning.push_back(r.stats.binning);
    raster.push_back(r.stats.raster);
  }
  const wf::RenderStats& st = r.stats;
  const size_t pixels = size_t(opt.width) * size_t(opt.height);
  j["seconds"] = total;
  j["seconds_median"] = median(total);
  j["seconds_min"] = *std::min_element(total.begin(), total.end());
  j["seconds_max"] = *std::max_element(total.begin(), total.end());
  j["setup_median"] = median(setup);
  j["maps_median"] = median(maps);
  j["binning_median"] = median(binning);
  j["raster_median"] = median(raster);
  j["segments_accepted"] = st.segments;
  j["primitives"] = st.primitives;
  j["primitives_occluded"] = st.primitivesOccluded;
  j["fragments"] = st.abuffer.fragments;
  j["fragments_culled"] = st.abuffer.culled;
  j["tail"] = st.abuffer.tail;
  j["max_fragments_per_pixel"] = st.abuffer.maxFragmentsPerPixel;
  j["max_list_length"] = st.abuffer.maxListLength;
  j["pixels_with_list"] = st.abuffer.pixelsWithList;
  j["pixels_over_budget"] = st.abuffer.pixelsOverBudget;
  j["covered_pixels"] = st.abuffer.coveredPixels;
  j["peak_bytes"] = st.peakBytes;
  j["tile_buffer_peak_bytes"] = st.abuffer.peakBytes;
  j["peak_fragments_held"] = st.abuffer.peakFragmentsHeld;
  j["image_bytes"] = pixels * sizeof(glm::vec4);
  // The parts of peakBytes: prepare and bin once more, outside the timing, through the same code.
  wf::inArena(opt.threads, [&] {
    wf::RenderStats s2;
    const wf::PreparedScene ps = wf::prepareScene(scene, opt, s2);
    // (Counted, not binned: binning the whole grid at once would hold more than the render did,
    // and this process's peak RSS is reported.)
    const wf::BinCounts counts = wf::countBins(ps, opt.tileSize);
    std::uint64_t items = 0;
    for (int row = counts.rowBegin; row < counts.rowEnd; ++row) items += counts.rowItems(row);
    size_t tables = 0;
    for (const wf::ShaderSlot& s : ps.shaders) {
      if (s.wireTables) tables += s.wireTables->bytes();
      if (s.surfaceTables) tables += s.surfaceTables->bytes();
    }
    j["primitives_bytes"] = ps.segments.capacity() * sizeof(wf::SegmentPrim) + ps.triangles.capacity() * sizeof(wf::TrianglePrim);
    j["vertices_bytes"] = ps.vertices.capacity() * sizeof(glm::dvec2);
    j["attributes_bytes"] = ps.segmentShading.capacity() * sizeof(wf::SegmentShading) +
                            ps.segmentColours.capacity() * sizeof(wf::SegmentColours) +
                            ps.triangleAttributes.capacity() * sizeof(wf::TriangleAttributes);
    j["tables_bytes"] = tables;
    j["prepared_bytes"] = ps.bytes();
    // The render bins a band of tile rows at a time (docs/abuffer.md): what it held of them at
    // its peak is the rest of peakBytes.
    j["bins_bytes"] = st.peakBytes - std::min(st.peakBytes, ps.bytes() + st.abuffer.peakBytes);
    j["bin_items"] = items;  // over the whole grid
    j["bin_bands"] = st.binBands;
  });
  size_t input = 0;
  for (const wf::SceneWire& w : scene.wires)
    input += w.lines.points.capacity() * sizeof(glm::dvec3) + w.lines.starts.capacity() * sizeof(std::uint32_t);
  j["input_bytes"] = input;
}

struct Fit {
  double a = NAN, b = NAN, r2 = NAN;
  size_t points = 0;
};

// y = a x^b by least squares on (ln x, ln y).
Fit fitPower(const std::vector<double>& x, const std::vector<double>& y) {
  Fit f;
  std::vector<double> lx, ly;
  for (size_t i = 0; i < x.size(); ++i)
    if (x[i] > 0 && y[i] > 0) lx.push_back(std::log(x[i])), ly.push_back(std::log(y[i]));
  f.points = lx.size();
  if (lx.size() < 2) return f;
  double mx = 0, my = 0;
  for (size_t i = 0; i < lx.size(); ++i) mx += lx[i], my += ly[i];
  mx /= double(lx.size());
  my /= double(lx.size());
  double sxx = 0, sxy = 0, syy = 0;
  for (size_t i = 0; i < lx.size(); ++i) {
    sxx += (lx[i] - mx) * (lx[i] - mx);
    sxy += (lx[i] - mx) * (ly[i] - my);
    syy += (ly[i] - my) * (ly[i] - my);
  }
  if (!(sxx > 0)) return f;
  f.b = sxy / sxx;
  f.a = std::exp(my - f.b * mx);
  f.r2 = syy > 0 ? sxy * sxy / (sxx * syy) : 1.0;
  return f;
}

json fitJson(const Fit& f, const std::string& range) {
  json j;
  j["range"] = range;
  j["points"] = f.points;
  j["exponent_b"] = std::isfinite(f.b) ? json(f.b) : json(nullptr);
  j["coefficient_a"] = std::isfinite(f.a) ? json(f.a) : json(nullptr);
  j["r_squared"] = std::isfinite(f.r2) ? json(f.r2) : json(nullptr);
  j["target_b_at_most_1"] = std::isfinite(f.b) && f.b <= 1.0;
  return j;
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}
std::string mib(double bytes) { return fmt("%.1f", bytes / 1048576.0); }
std::string count(double v) {
  if (v >= 1e6) return fmt("%.2fM", v / 1e6);
  if (v >= 1e4) return fmt("%.0fk", v / 1e3);
  return fmt("%.0f", v);
}
double num(const json& j, const char* key) { return j.at(key).get<double>(); }

}  // namespace

int main(int argc, char** argv) {
  Args a;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string s = argv[i];
      auto next = [&]() -> std::string {
        if (i + 1 >= argc) throw std::invalid_argument(s + " needs a value");
        return argv[++i];
      };
      if (s == "--segments") a.segments = parseList(next());
      else if (s == "--size") {
        const std::string v = next();
        if (std::sscanf(v.c_str(), "%dx%d", &a.width, &a.height) != 2) throw std::invalid_argument("--size " + v);
      } else if (s == "--repeats") a.repeats = std::max(1, std::stoi(next()));
      else if (s == "--threads") a.threads = std::stoi(next());
      else if (s == "--depth-segments") a.depthSegments = parseList(next()).front();
      else if (s == "--depth-stacks") a.depthStacks = parseList(next());
      else if (s == "--no-depth") a.depth = false;
      else if (s == "--markdown") a.markdownPath = next();
      else if (s == "--json") a.jsonPath = next();
      else if (s == "--plots") a.plotDir = next();
      else if (s == "--check") a.check = true;
      else if (s == "--quiet") a.quiet = true;
      else throw std::invalid_argument("unknown option " + s);
    }
  } catch (const std::exception& e) {
    std::cerr << "bench_scaling: " << e.what() << "\n";
    return 2;
  }
  std::sort(a.segments.begin(), a.segments.end());
  wf::RenderOptions opt;
  opt.width = a.width;
  opt.height = a.height;
  opt.threads = a.threads;
  if (const std::string p = opt.problem(); !p.empty()) {
    std::cerr << "bench_scaling: " << p << "\n";
    return 2;
  }
  const size_t pixels = size_t(a.width) * size_t(a.height);
  const std::string tmp = (std::filesystem::temp_directory_path() / ("wirefur_scaling_" + std::to_string(getpid()))).string();
  auto say = [&](const std::string& s) {
    if (!a.quiet) std::cerr << s << std::flush;
  };

  json report;
  report["image"] = {{"width", a.width}, {"height", a.height}};
  report["style"] = "shaded wire (Phong hair material through the pseudo-reflectance map, 2 lights), 1.5 px wide, opaque";
  report["repeats"] = a.repeats;
  report["threads"] = concurrency(a.threads);
  report["options"] = {{"tile_size", opt.tileSize}, {"budget", opt.budget}, {"mask", opt.mask.name()},
                       {"occlusion_epsilon", opt.occlusionEpsilon}};
  const json bound = tileBound(opt);
  report["tile_buffer_bound"] = bound;

  // Part 1: time and memory against N.
  json rows = json::array();
  std::vector<double> ns, secs, mins, nsTail, secsTail, minsTail, frags;
  for (size_t n : a.segments) {
    say("bench_scaling: " + std::to_string(n) + " segments ... ");
    json j;
    const bool ok = wfbench::inChild("bench_scaling", tmp + "_n.json", j, [&](json& out) {
      const wf::Scene scene = hairScene(wfbench::hairTorus(n), 1.0f);
      renderFigures(scene, opt, a.repeats, out);
    });
    if (!ok) {
      std::cerr << "bench_scaling: the render of " << n << " segments failed\n";
      return 1;
    }
    {
      json front{{"segments", n}};
      front.update(j);
      j = std::move(front);
    }
    const double held = num(j, "peak_fragments_held");
    j["tile_bytes_per_fragment_held"] = held > 0 ? num(j, "tile_buffer_peak_bytes") / held : 0.0;
    j["peak_bytes_per_fragment"] = num(j, "fragments") > 0 ? num(j, "peak_bytes") / num(j, "fragments") : 0.0;
    j["peak_bytes_per_pixel"] = num(j, "peak_bytes") / double(pixels);
    j["tile_bytes_per_pixel"] = num(j, "tile_buffer_peak_bytes") / double(pixels);
    j["rss_bytes_per_pixel"] = num(j, "peak_rss_bytes") / double(pixels);
    j["ns_per_fragment"] = num(j, "fragments") > 0 ? 1e9 * num(j, "seconds_median") / num(j, "fragments") : 0.0;
    say(fmt("%.3f s\n", num(j, "seconds_median")));
    ns.push_back(double(n));
    secs.push_back(num(j, "seconds_median"));
    mins.push_back(num(j, "seconds_min"));
    frags.push_back(num(j, "fragments"));
    if (n >= kFitFrom) {
      nsTail.push_back(double(n));
      secsTail.push_back(num(j, "seconds_median"));
      minsTail.push_back(num(j, "seconds_min"));
    }
    rows.push_back(j);
  }
  report["segments"] = rows;
  const Fit fitAll = fitPower(ns, secs), fitTail = fitPower(nsTail, secsTail), fitFrag = fitPower(ns, frags);
  // The fastest of the R renders: less disturbed by other work on the machine than the median.
  const Fit fitMinAll = fitPower(ns, mins), fitMinTail = fitPower(nsTail, minsTail);
  const std::string rangeAll = count(ns.front()) + " ... " + count(ns.back());
  const std::string rangeTail = nsTail.empty() ? "(none)" : count(nsTail.front()) + " ... " + count(nsTail.back());
  report["fit_time_all"] = fitJson(fitAll, rangeAll);
  report["fit_time_from_100k"] = fitJson(fitTail, rangeTail);
  report["fit_time_min_all"] = fitJson(fitMinAll, rangeAll);
  report["fit_time_min_from_100k"] = fitJson(fitMinTail, rangeTail);
  report["fit_fragments_all"] = fitJson(fitFrag, rangeAll);

  // Part 2: depth complexity at a fixed segment count.
  json depthRows = json::array();
  if (a.depth) {
    for (const bool translucent : {false, true})
      for (size_t stack : a.depthStacks) {
        const size_t hairs = std::max<size_t>(1, a.depthSegments / stack);
        say("bench_scaling: depth " + std::string(translucent ? "translucent" : "opaque") + ", " +
            std::to_string(hairs) + " hairs x " + std::to_string(stack) + " ... ");
        wf::RenderOptions o = opt;
        if (translucent) o.occlusionEpsilon = 0.0;
        json j;
        const bool ok = wfbench::inChild("bench_scaling", tmp + "_d.json", j, [&](json& out) {
          const wf::Scene scene = hairScene(stackedHairs(hairs, stack), translucent ? 0.3f : 1.0f);
          renderFigures(scene, o, 1, out);
        });
        if (!ok) {
          std::cerr << "bench_scaling: the stacked render (" << stack << ") failed\n";
          return 1;
        }
        {
          json front{{"material", translucent ? "translucent 0.3, epsilon 0" : "opaque"}, {"stack", stack},
                     {"hairs", hairs}, {"segments", hairs * stack}};
          front.update(j);
          j = std::move(front);
        }
        const double held = num(j, "peak_fragments_held");
        j["tile_bytes_per_fragment_held"] = held > 0 ? num(j, "tile_buffer_peak_bytes") / held : 0.0;
        j["tile_bound_bytes"] = bound["bound_bytes"];
        j["within_bound"] = num(j, "tile_buffer_peak_bytes") <= bound["bound_bytes"].get<double>();
        say(fmt("max %.0f fragments/pixel, ", num(j, "max_fragments_per_pixel")) +
            mib(num(j, "tile_buffer_peak_bytes")) + " MiB tile buffers\n");
        depthRows.push_back(j);
      }
  }
  report["depth_complexity"] = depthRows;

  // Tables.
  std::ostringstream md;
  md << "# A-buffer scaling (issue 7)\n\n";
  md << "Hair torus (tests/bench/peer/hair_torus.h), " << a.width << "x" << a.height << ", "
     << report["style"].get<std::string>() << "; mask " << opt.mask.name() << ", budget K = " << opt.budget
     << ", tiles " << opt.tileSize << "x" << opt.tileSize << ", " << concurrency(a.threads) << " threads; median of "
     << a.repeats << " renders, each N in its own process.\n\n";
  md << "## Time\n\n| segments | median s | min s | max s | setup | maps | binning | raster | fragments | ns / fragment"
        " | max frags / px | pixels with list | tail |\n|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const json& j : rows)
    md << "| " << count(num(j, "segments")) << " | " << fmt("%.3f", num(j, "seconds_median")) << " | "
       << fmt("%.3f", num(j, "seconds_min")) << " | " << fmt("%.3f", num(j, "seconds_max")) << " | "
       << fmt("%.3f", num(j, "setup_median")) << " | " << fmt("%.3f", num(j, "maps_median")) << " | "
       << fmt("%.3f", num(j, "binning_median")) << " | " << fmt("%.3f", num(j, "raster_median")) << " | "
       << count(num(j, "fragments")) << " | " << fmt("%.1f", num(j, "ns_per_fragment")) << " | "
       << num(j, "max_fragments_per_pixel") << " | " << count(num(j, "pixels_with_list")) << " | "
       << count(num(j, "tail")) << " |\n";
  auto fitLine = [&](const char* what, const Fit& f, const std::string& range) {
    md << "| " << what << " | " << range << " | " << f.points << " | " << fmt("%.3f", f.b) << " | "
       << fmt("%.3g", f.a) << " | " << fmt("%.4f", f.r2) << " | "
       << (std::isfinite(f.b) ? (f.b <= 1.0 ? "yes" : "**no**") : "n/a") << " |\n";
  };
  md << "\n## Fitted exponent, y = a N^b (least squares in log-log)\n\n| quantity | range | points | b | a | R² | b <= 1 |\n"
        "|---|---|---:|---:|---:|---:|---|\n";
  fitLine("time (median)", fitAll, rangeAll);
  fitLine("time (median)", fitTail, rangeTail);
  fitLine("time (min)", fitMinAll, rangeAll);
  fitLine("time (min)", fitMinTail, rangeTail);
  fitLine("fragments", fitFrag, rangeAll);
  md << "\n## Memory\n\nMiB unless stated. peak = RenderStats::peakBytes = prepared scene (primitives + vertices + "
        "attributes + tables) + bins (counts and the largest band's items) + tile buffers; not in it: the input scene and the output image ("
     << mib(double(pixels * sizeof(glm::vec4))) << " MiB, 16 B/pixel). held = most fragments the tile buffers held at once "
        "(list entries + solid fragments, summed over threads). A fragment is "
     << sizeof(wf::Fragment) << " B, a list entry " << bound["list_entry_bytes"].get<size_t>() << " B.\n\n";
  md << "| segments | input | primitives | vertices | attributes | tables | bins | tile buffers | peak | RSS | held"
        " | tile B / held fragment | peak B / fragment | peak B / pixel | RSS B / pixel |\n"
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const json& j : rows)
    md << "| " << count(num(j, "segments")) << " | " << mib(num(j, "input_bytes")) << " | "
       << mib(num(j, "primitives_bytes")) << " | " << mib(num(j, "vertices_bytes")) << " | "
       << mib(num(j, "attributes_bytes")) << " | " << mib(num(j, "tables_bytes")) << " | " << mib(num(j, "bins_bytes"))
       << " | " << mib(num(j, "tile_buffer_peak_bytes")) << " | " << mib(num(j, "peak_bytes")) << " | "
       << mib(num(j, "peak_rss_bytes")) << " | " << count(num(j, "peak_fragments_held")) << " | "
       << fmt("%.1f", num(j, "tile_bytes_per_fragment_held")) << " | " << fmt("%.1f", num(j, "peak_bytes_per_fragment"))
       << " | " << fmt("%.1f", num(j, "peak_bytes_per_pixel")) << " | " << fmt("%.1f", num(j, "rss_bytes_per_pixel"))
       << " |\n";
  if (a.depth) {
    md << "\n## Depth complexity at " << count(double(a.depthSegments))
       << " segments\n\nS / D hairs, each drawn D times one behind the other on the same pixels. Bound on the tile "
          "buffers: "
       << bound["threads"].get<int>() << " threads x (" << mib(bound["fixed_bytes_per_thread"].get<double>())
       << " fixed + " << mib(bound["list_bytes_per_thread"].get<double>()) << " lists of T² K entries + "
       << mib(bound["tail_and_solid_bytes_per_thread"].get<double>()) << " tails and solids) = "
       << mib(bound["bound_bytes"].get<double>()) << " MiB.\n\n";
    md << "| material | D | hairs | max frags / px | max list | pixels over budget | tail | held | tile buffers MiB | "
          "within bound | tile B / held | peak MiB | RSS MiB | s |\n"
          "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|\n";
    for (const json& j : depthRows)
      md << "| " << j["material"].get<std::string>() << " | " << num(j, "stack") << " | " << count(num(j, "hairs"))
         << " | " << num(j, "max_fragments_per_pixel") << " | " << num(j, "max_list_length") << " | "
         << count(num(j, "pixels_over_budget")) << " | " << count(num(j, "tail")) << " | "
         << count(num(j, "peak_fragments_held")) << " | " << mib(num(j, "tile_buffer_peak_bytes")) << " | "
         << (j["within_bound"].get<bool>() ? "yes" : "**no**") << " | " << fmt("%.1f", num(j, "tile_bytes_per_fragment_held"))
         << " | " << mib(num(j, "peak_bytes")) << " | " << mib(num(j, "peak_rss_bytes")) << " | "
         << fmt("%.3f", num(j, "seconds_median")) << " |\n";
  }
  std::cout << md.str();
  if (!a.markdownPath.empty()) std::ofstream(a.markdownPath) << md.str();
  if (!a.jsonPath.empty()) std::ofstream(a.jsonPath) << report.dump(2) << "\n";

  // Plots.
  if (!a.plotDir.empty()) {
    try {
      std::filesystem::create_directories(a.plotDir);
      wfapp::PlotSpec t;
      t.title = "A-buffer render time against segments (" + std::to_string(a.width) + "x" + std::to_string(a.height) + ")";
      t.xlabel = "segments N";
      t.ylabel = "seconds (median)";
      t.logx = t.logy = true;
      wfapp::PlotSeries m{"measured (median of " + std::to_string(a.repeats) + ")", ns, secs, {}, "points pt 7 ps 1.5"};
      t.series.push_back(m);
      wfapp::PlotSeries fastest{"fastest of " + std::to_string(a.repeats), ns, mins, {}, "points pt 6 ps 1.5"};
      if (a.repeats > 1) t.series.push_back(fastest);
      const Fit& f = std::isfinite(fitTail.b) ? fitTail : fitAll;
      const std::string fitRange = std::isfinite(fitTail.b) ? rangeTail : rangeAll;
      wfapp::PlotSeries fl{"fit over " + fitRange + ": " + fmt("%.3g", f.a) + " N^" + fmt("%.3f", f.b), {}, {}, {}, "lines"};
      wfapp::PlotSeries one{"slope 1 (linear), through the fit at the middle", {}, {}, {}, "lines dt 2"};
      if (std::isfinite(fitAll.b) && fitTail.b != fitAll.b) {
        wfapp::PlotSeries fa{"fit over " + rangeAll + ": N^" + fmt("%.3f", fitAll.b), {}, {}, {}, "lines dt 3"};
        for (double n : ns) fa.x.push_back(n), fa.y.push_back(fitAll.a * std::pow(n, fitAll.b));
        t.series.push_back(fa);
      }
      if (std::isfinite(f.b)) {
        const double mid = std::sqrt(ns.front() * ns.back()), atMid = f.a * std::pow(mid, f.b);
        for (double n : ns) {
          if (&f == &fitAll || n >= double(kFitFrom)) fl.x.push_back(n), fl.y.push_back(f.a * std::pow(n, f.b));
          one.x.push_back(n), one.y.push_back(atMid * n / mid);
        }
        t.series.push_back(fl);
        t.series.push_back(one);
      }
      wfapp::plotPng(t, (std::filesystem::path(a.plotDir) / "time_vs_segments.png").string());

      wfapp::PlotSpec mem;
      mem.title = "Memory against segments (dashed: the tile buffers' bound)";
      mem.xlabel = "segments N";
      mem.ylabel = "bytes";
      mem.logx = mem.logy = true;
      const std::pair<const char*, const char*> parts[] = {{"RenderStats::peakBytes", "peak_bytes"},
                                                           {"tile buffers (A-buffer)", "tile_buffer_peak_bytes"},
                                                           {"bins", "bins_bytes"},
                                                           {"primitives + vertices + attributes", "prepared_bytes"},
                                                           {"peak RSS of the process", "peak_rss_bytes"}};
      for (const auto& [title, key] : parts) {
        wfapp::PlotSeries s{title, {}, {}, {}, "linespoints"};
        for (const json& j : rows) s.x.push_back(num(j, "segments")), s.y.push_back(num(j, key));
        mem.series.push_back(s);
      }
      mem.hlines.push_back(bound["bound_bytes"].get<double>());
      wfapp::plotPng(mem, (std::filesystem::path(a.plotDir) / "memory_vs_segments.png").string());

      if (!depthRows.empty()) {
        wfapp::PlotSpec d;
        d.title = "Tile-buffer peak memory against depth complexity (" + count(double(a.depthSegments)) +
                  " segments; dashed: the bound)";
        d.xlabel = "max fragments per pixel";
        d.ylabel = "bytes";
        d.logx = d.logy = true;
        for (const char* mat : {"opaque", "translucent 0.3, epsilon 0"}) {
          wfapp::PlotSeries tb{std::string("tile buffers, ") + mat, {}, {}, {}, "linespoints"};
          wfapp::PlotSeries pk{std::string("RenderStats::peakBytes, ") + mat, {}, {}, {}, "linespoints"};
          for (const json& j : depthRows)
            if (j["material"] == mat) {
              tb.x.push_back(num(j, "max_fragments_per_pixel")), tb.y.push_back(num(j, "tile_buffer_peak_bytes"));
              pk.x.push_back(num(j, "max_fragments_per_pixel")), pk.y.push_back(num(j, "peak_bytes"));
              tb.labels.push_back("D=" + std::to_string(j["stack"].get<size_t>()));
            }
          d.series.push_back(tb);
          d.series.push_back(pk);
        }
        d.hlines.push_back(bound["bound_bytes"].get<double>());
        wfapp::plotPng(d, (std::filesystem::path(a.plotDir) / "memory_vs_depth.png").string());
      }
    } catch (const std::exception& e) {
      std::cerr << "bench_scaling: plots: " << e.what() << "\n";
      return 1;
    }
  }

  // Checks (the smoke test).
  if (a.check) {
    std::vector<std::string> failures;
    if (!std::isfinite(fitAll.b)) failures.push_back("the fitted time exponent is not finite");
    // Fragments per segment stay the same whatever N (a hair's footprint does not depend on how
    // many there are); occlusion culling can only lower it for the denser scene. Tolerance: the
    // ratio of fragments within [0.75, 1.1] of the ratio of segments.
    for (size_t i = 1; i < rows.size(); ++i) {
      const double want = num(rows[i], "segments") / num(rows[i - 1], "segments");
      const double got = num(rows[i], "fragments") / std::max(1.0, num(rows[i - 1], "fragments"));
      if (!(got >= 0.75 * want && got <= 1.1 * want))
        failures.push_back("fragments grew " + fmt("%.3f", got) + "x for " + fmt("%.3f", want) + "x the segments");
    }
    for (const json& j : depthRows) {
      const double stack = num(j, "stack");
      if (!(num(j, "max_fragments_per_pixel") >= stack))
        failures.push_back("stack " + fmt("%.0f", stack) + ": max fragments per pixel " +
                           fmt("%.0f", num(j, "max_fragments_per_pixel")) + " below the stack");
      if (!j["within_bound"].get<bool>())
        failures.push_back("stack " + fmt("%.0f", stack) + ": tile buffers " + fmt("%.0f", num(j, "tile_buffer_peak_bytes")) +
                           " B over the bound " + fmt("%.0f", bound["bound_bytes"].get<double>()) + " B");
    }
    for (const std::string& f : failures) std::cerr << "bench_scaling: check failed: " << f << "\n";
    if (!failures.empty()) return 3;
    std::cerr << "bench_scaling: checks passed\n";
  }
  return 0;
}

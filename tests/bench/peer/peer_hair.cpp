// Peer benchmark of issue 3: N hair-like segments over a torus at 1024x768 (hair_torus.h),
// drawn by the WireFur A-buffer and by VTK 9.1's RenderLinesAsTubes (Mesa llvmpipe), both
// measured against WireFur's brute-force reference (16x16 stratified samples per pixel) for
// coverage. The A-buffer runs as it is (every hair) and with stochastic simplification to each
// width of --simplify (RenderOptions::simplify: a fraction of the hairs, widened). Every
// renderer runs in its own forked child so that its peak memory (ru_maxrss) is its own. Prints
// a table and, with --json, writes the figures.
//
//   peer_hair [--segments N] [--frames F] [--samples S] [--threads T] [--no-vtk] [--json FILE]
//             [--simplify 3,6] [--vtk-msaa 2,4,8] [--vtk-ssaa 2,4,8,12]
//
// VTK is also run with multisample antialiasing (--vtk-msaa) and supersampled (--vtk-ssaa: drawn
// at k times the size each way and averaged down, the way past the few samples MSAA offers): its
// error against time, so that the A-buffer is compared with it at equal coverage error as well as
// with its aliased default.
//
// Under CI it runs with a small N as a smoke test; the full comparison is
//   xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" build/peer_hair --json out/peer_hair.json
#include "bench_support.h"
#include "hair_torus.h"
#include "vtk_tubes.h"

#include "render/renderer.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using json = nlohmann::ordered_json;

struct Args {
  size_t segments = 300000;
  int frames = 5;
  int samples = 16;
  int threads = 0;
  bool vtk = true;
  std::string jsonPath;
  std::vector<double> simplify{3.0, 6.0};
  std::vector<int> vtkMsaa{2, 4, 8};  ///< --vtk-msaa: VTK's antialiased runs (MSAA samples asked), beside its aliased one
  std::vector<int> vtkSsaa{2, 4, 8, 12};  ///< --vtk-ssaa: VTK's supersampled runs (k x k pixels a pixel, aliased)
};

using wfbench::median;

wf::Scene hairScene(const std::vector<wfbench::HairSegment>& segs) {
  wf::Scene scene;
  scene.camera = wfbench::camera();
  scene.background = glm::vec4(0, 0, 0, 0);
  wf::SceneWire wire;
  wire.name = "hairs";
  wire.style = wf::WireStyle::Plain;  // white: the image's alpha is the coverage
  wire.thickness = wfbench::kHairWidthPixels;
  wire.thicknessInPixels = true;
  wire.lines = wfbench::polylines(segs);
  wire.restsOnSurface = false;  // hairs: the segment is the axis
  wire.aggregate = true;        // many similar strands: RenderOptions::simplify may thin them
  scene.wires.push_back(std::move(wire));
  return scene;
}

// Runs `work(json&, coverage&)` in a child process (wfbench::inChild); the coverage comes back
// through a file beside the JSON.
template <class F>
bool measure(const std::string& stem, json& out, std::vector<float>& coverage, size_t pixels, F&& work) {
  const std::string covPath = stem + ".cov";
  const bool ok = wfbench::inChild("peer_hair", stem + ".json", out, [&](json& j) {
    std::vector<float> cov;
    work(j, cov);
    std::ofstream(covPath, std::ios::binary)
        .write(reinterpret_cast<const char*>(cov.data()), std::streamsize(cov.size() * sizeof(float)));
  });
  coverage.assign(pixels, 0.0f);
  std::ifstream in(covPath, std::ios::binary);
  const bool read = ok && in.read(reinterpret_cast<char*>(coverage.data()), std::streamsize(pixels * sizeof(float)));
  std::remove(covPath.c_str());
  return read;
}

json coverageError(const std::vector<float>& a, const std::vector<float>& ref) {
  double sq = 0, sqCovered = 0, mx = 0, sumA = 0, sumR = 0;
  size_t covered = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const double d = double(a[i]) - double(ref[i]);
    sq += d * d;
    mx = std::max(mx, std::abs(d));
    sumA += a[i];
    sumR += ref[i];
    if (a[i] > 0 || ref[i] > 0) sqCovered += d * d, ++covered;
  }
  json j;
  j["rms_all_pixels"] = std::sqrt(sq / double(a.size()));
  j["rms_covered_pixels"] = covered ? std::sqrt(sqCovered / double(covered)) : 0.0;
  j["max"] = mx;
  j["total_coverage"] = sumA;
  j["total_coverage_reference"] = sumR;
  return j;
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  CLI::App app{"peer_hair: the A-buffer against VTK's RenderLinesAsTubes on hair over a torus (docs/benchmarks.md)"};
  bool noVtk = false;
  std::vector<std::string> simplify;
  app.add_option("--segments", a.segments, "hair segments")->check(CLI::Range(size_t(1), size_t(1) << 28));
  app.add_option("--frames", a.frames, "timed frames (the median is reported)")->check(CLI::Range(1, 1000));
  app.add_option("--samples", a.samples, "the reference's N x N samples per pixel")->check(CLI::Range(1, 64));
  app.add_option("--threads", a.threads, "worker threads (0: all cores)")->check(CLI::Range(0, 4096));
  app.add_flag("--no-vtk", noVtk, "leave out VTK's tubes");
  app.add_option("--json", a.jsonPath, "write the report here");
  app.add_option("--simplify", simplify, "stochastic simplification's densities to measure, or off")->delimiter(',');
  app.add_option("--vtk-msaa", a.vtkMsaa, "VTK's antialiased runs beside its aliased one: the multisamples to ask for in each, 2 ... 64 (--no-vtk: no VTK runs at all)")
      ->delimiter(',')
      ->check(CLI::Range(2, 64));
  app.add_option("--vtk-ssaa", a.vtkSsaa, "VTK's supersampled runs: k x k pixels averaged into each, k = 2 ... 16 (each drawn aliased at k times the size)")
      ->delimiter(',')
      ->check(CLI::Range(2, 16));
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "peer_hair: " << e.what() << "\n";
    return 2;
  }
  a.vtk = !noVtk;
  if (app.count("--simplify")) {
    a.simplify.clear();
    for (const std::string& v : simplify) {
      if (v.empty() || v == "off") continue;
      char* end = nullptr;
      const double d = std::strtod(v.c_str(), &end);
      if (end == v.c_str() || *end != '\0' || !(d > 0.0) || !std::isfinite(d)) {
        std::cerr << "peer_hair: --simplify: expected densities > 0 or off, got '" << v << "'\n";
        return 2;
      }
      a.simplify.push_back(d);
    }
  }
  const int W = wfbench::kHairImageWidth, H = wfbench::kHairImageHeight;
  const size_t pixels = size_t(W) * H;
  const std::string tmp = "/tmp/wirefur_peer_" + std::to_string(getpid());
  json report;
  report["segments"] = a.segments;
  report["width"] = W;
  report["height"] = H;
  report["line_width_pixels"] = wfbench::kHairWidthPixels;

  wf::RenderOptions opt;
  opt.width = W;
  opt.height = H;
  opt.threads = a.threads;
  opt.referenceSamples = a.samples;

  json ja, jr, jv;
  std::vector<float> ca, cr, cv;
  auto abuffer = [&](const wf::RenderOptions& o) {
    return [&, o](json& j, std::vector<float>& cov) {
      const wf::Scene scene = hairScene(wfbench::hairTorus(a.segments));
      std::vector<double> times;
      wf::RenderResult r;
      for (int f = 0; f < a.frames; ++f) {
        r = wf::render(scene, o);
        times.push_back(r.stats.total);
      }
      j["frame_seconds"] = times;
      j["median_seconds"] = median(times);
      j["fragments"] = r.stats.abuffer.fragments;
      j["fragments_emitted"] = r.stats.work.emitted;
      j["max_fragments_per_pixel"] = r.stats.abuffer.maxFragmentsPerPixel;
      j["pixels_with_list"] = r.stats.abuffer.pixelsWithList;
      const wf::RenderStats::RasterWork& w = r.stats.work;
      j["raster_work"] = {{"items", w.items},   {"rows", w.rows},
                          {"rows_culled", w.rowsCulled}, {"pixels", w.pixels},
                          {"pixels_culled", w.pixelsCulled}, {"masks_hidden", w.masksHidden},
                          {"emitted", w.emitted}};
      j["tail_fragments"] = r.stats.abuffer.tail;
      j["renderer_peak_bytes"] = r.stats.peakBytes;
      j["seconds_setup"] = r.stats.setup;
      j["seconds_raster_resolve"] = r.stats.raster;
      if (o.simplify.enabled) j["hairs_drawn"] = r.stats.simplifiedKept;
      cov.resize(pixels);
      for (size_t i = 0; i < pixels; ++i) cov[i] = r.image.pixels[i].w;
    };
  };
  const bool okA = measure(tmp + "_abuffer", ja, ca, pixels, abuffer(opt));
  std::vector<json> simplified(a.simplify.size());
  std::vector<std::vector<float>> cs(a.simplify.size());
  for (size_t k = 0; k < a.simplify.size(); ++k) {
    wf::RenderOptions o = opt;
    o.simplify.enabled = true;
    o.simplify.targetWidth = a.simplify[k];
    if (!measure(tmp + "_simplified", simplified[k], cs[k], pixels, abuffer(o))) cs[k].clear();
  }
  const bool okR = measure(tmp + "_reference", jr, cr, pixels, [&](json& j, std::vector<float>& cov) {
    const wf::Scene scene = hairScene(wfbench::hairTorus(a.segments));
    const wf::RenderResult r = wf::renderReference(scene, opt);
    j["seconds"] = r.stats.total;
    j["samples_per_pixel"] = a.samples * a.samples;
    cov.resize(pixels);
    for (size_t i = 0; i < pixels; ++i) cov[i] = r.image.pixels[i].w;
  });
  bool okV = false;
  auto vtkRun = [&](int multiSamples, int supersample = 1) {
    return [&, multiSamples, supersample](json& j, std::vector<float>& cov) {
      const auto segs = wfbench::hairTorus(a.segments);
      const wfbench::VtkTubesResult v = wfbench::renderVtkTubes(segs, wfbench::HairCamera{}, W, H, wfbench::kHairWidthPixels,
                                                                a.frames, multiSamples, supersample);
      j["multisamples_asked"] = v.multiSamplesAsked;
      j["multisamples"] = v.multiSamples;  // what VTK's framebuffer got (-1: unknown)
      if (supersample > 1) {
        j["supersample"] = supersample;
        j["readback_and_average_seconds"] = v.downsampleSeconds;  // (in each frame's time)
      }
      j["frame_seconds"] = v.frameSeconds;
      j["median_seconds"] = v.medianSeconds;
      j["setup_seconds"] = v.setupSeconds;
      j["renderer"] = v.renderer;
      cov = v.coverage;
    };
  };
  if (a.vtk) okV = measure(tmp + "_vtk", jv, cv, pixels, vtkRun(0));
  // The antialiased runs only where the aliased one ran (a failure there is the display's): each
  // setting's report and coverage (empty where it failed), `key` naming the setting in both.
  auto vtkRuns = [&](const std::vector<int>& settings, const std::string& key, bool supersampled,
                     std::vector<json>& reports, std::vector<std::vector<float>>& coverage) {
    reports.assign(okV ? settings.size() : 0, json());
    coverage.assign(reports.size(), {});
    for (size_t k = 0; k < reports.size(); ++k) {
      const int s = settings[k];
      if (measure(tmp + "_vtk_" + key, reports[k], coverage[k], pixels, supersampled ? vtkRun(0, s) : vtkRun(s))) continue;
      std::cerr << "peer_hair: VTK's run with " << key << " " << s << " failed\n";
      reports[k] = json{{key, s}, {"failed", true}};
      coverage[k].clear();
    }
  };
  std::vector<json> msaa, ssaa;
  std::vector<std::vector<float>> cm, cq;
  vtkRuns(a.vtkMsaa, "multisamples_asked", false, msaa, cm);
  vtkRuns(a.vtkSsaa, "supersample", true, ssaa, cq);

  if (!okA || !okR) {
    std::cerr << "peer_hair: the WireFur renders failed\n";
    return 1;
  }
  ja["coverage_error"] = coverageError(ca, cr);
  report["wirefur_abuffer"] = ja;
  json js = json::array();
  for (size_t k = 0; k < a.simplify.size(); ++k) {
    if (cs[k].empty()) continue;
    simplified[k]["target_width_pixels"] = a.simplify[k];
    simplified[k]["coverage_error"] = coverageError(cs[k], cr);
    if (okV) simplified[k]["speedup_vs_vtk"] = jv["median_seconds"].get<double>() / simplified[k]["median_seconds"].get<double>();
    js.push_back(simplified[k]);
  }
  report["wirefur_abuffer_simplified"] = js;
  report["reference"] = jr;
  if (okV) {
    jv["coverage_error"] = coverageError(cv, cr);
    report["vtk_render_lines_as_tubes"] = jv;
    report["speedup_vs_vtk"] = jv["median_seconds"].get<double>() / ja["median_seconds"].get<double>();
    // VTK's error against time: its aliased run and each antialiased one (a run whose
    // framebuffer got the same samples as an earlier one draws the same image: listed, not
    // counted again). At equal coverage error: VTK's time on the front of its runs that no
    // other run beats in both error and time, interpolated (log time against log RMS) between
    // the two whose errors bracket the A-buffer's.
    struct Point {
      double rms, seconds;
      int samples;         // the framebuffer's multisamples
      int supersample = 1;
    };
    std::vector<Point> curve{{jv["coverage_error"]["rms_all_pixels"].get<double>(), jv["median_seconds"].get<double>(),
                              jv["multisamples"].get<int>()}};
    json jm = json::array();
    for (size_t k = 0; k < msaa.size(); ++k) {
      if (!cm[k].empty()) {
        msaa[k]["coverage_error"] = coverageError(cm[k], cr);
        const int got = msaa[k]["multisamples"].get<int>();
        const bool again = got >= 0 && std::any_of(curve.begin(), curve.end(), [&](const Point& p) { return p.samples == got; });
        msaa[k]["in_curve"] = !again;
        if (!again)
          curve.push_back({msaa[k]["coverage_error"]["rms_all_pixels"].get<double>(), msaa[k]["median_seconds"].get<double>(), got});
      }
      jm.push_back(msaa[k]);
    }
    report["vtk_msaa"] = jm;
    json jq = json::array();
    for (size_t k = 0; k < ssaa.size(); ++k) {
      if (!cq[k].empty()) {
        ssaa[k]["coverage_error"] = coverageError(cq[k], cr);
        ssaa[k]["in_curve"] = true;
        curve.push_back({ssaa[k]["coverage_error"]["rms_all_pixels"].get<double>(), ssaa[k]["median_seconds"].get<double>(),
                         ssaa[k]["multisamples"].get<int>(), a.vtkSsaa[k]});
      }
      jq.push_back(ssaa[k]);
    }
    report["vtk_ssaa"] = jq;
    std::sort(curve.begin(), curve.end(), [](const Point& p, const Point& q) {
      return p.rms < q.rms || (p.rms == q.rms && p.seconds < q.seconds);
    });
    std::vector<Point> front;  // RMS rising, time falling
    for (const Point& p : curve)
      if (front.empty() || (p.rms > front.back().rms && p.seconds < front.back().seconds)) front.push_back(p);
    std::vector<std::pair<double, double>> fastFirst;  // (time, RMS), the fastest first (timeAtError)
    for (auto p = front.rbegin(); p != front.rend(); ++p) fastFirst.emplace_back(p->seconds, p->rms);
    const double rmsA = ja["coverage_error"]["rms_all_pixels"].get<double>();
    const double secondsA = ja["median_seconds"].get<double>();
    json eq;
    eq["abuffer_rms"] = rmsA;
    eq["vtk_runs_in_curve"] = curve.size();
    eq["vtk_best"] = {{"multisamples", front.front().samples},
                      {"supersample", front.front().supersample},
                      {"rms", front.front().rms},
                      {"seconds", front.front().seconds}};
    std::string how;
    const double t = wfbench::timeAtError(fastFirst, rmsA, how);
    if (how == "extrapolated" || how == "n/a") {  // below every run's error: no setting of VTK reaches it
      eq["status"] = "not reached: every VTK run has a larger coverage error";
      eq["vtk_seconds_at_abuffer_rms"] = nullptr;
      eq["speedup_vs_vtk_at_equal_rms"] = nullptr;
      eq["speedup_vs_vtk_best"] = front.front().seconds / secondsA;
    } else {
      eq["status"] = how;
      eq["vtk_seconds_at_abuffer_rms"] = t;
      eq["speedup_vs_vtk_at_equal_rms"] = t / secondsA;
    }
    report["vtk_at_equal_error"] = eq;
  } else if (a.vtk) {
    report["vtk_render_lines_as_tubes"] = "failed (no display? run under xvfb-run)";
  }
  std::cout << report.dump(2) << "\n";
  if (!a.jsonPath.empty()) std::ofstream(a.jsonPath) << report.dump(2) << "\n";
  const double rms = ja["coverage_error"]["rms_all_pixels"].get<double>();
  return rms <= 1.0 / 64 ? 0 : 3;
}

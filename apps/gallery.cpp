#include "gallery.h"

#include "cli.h"
#include "safe_files.h"
#include "image_io.h"
#include "reader_worker.h"
#include "render_command.h"
#include "scene_file.h"

#include "shading/cylinder_shading.h"
#include "shading/environment_map.h"
#include "shading/pseudo_reflectance_map.h"
#include "shading/reflectance_sphere.h"

#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <exception>
#include <optional>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <tuple>
#include <vector>

namespace wfapp {
namespace {

using json = nlohmann::ordered_json;

struct Entry {
  std::string file, title, caption;
  double seconds = 0;
  std::string error;  // the error estimate, in words and numbers
};

std::string sci(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1e", v);
  return b;
}

wf::ImageRGBA mapImage(const wf::PseudoReflectanceMap& map, wf::PseudoReflectanceMap::Plane p, int scale) {
  const int n = map.resolution();
  wf::ImageRGBA img(n * scale, n * scale);
  const auto& tex = map.texels(p);
  for (int y = 0; y < n * scale; ++y)
    for (int x = 0; x < n * scale; ++x) {
      const int i = x / scale, j = n - 1 - y / scale;  // z up
      img.at(x, y) = glm::vec4(tex[size_t(j) * n + i], 1.0f);
    }
  return img;
}

// Scene titles and captions are the user's text: escaped for HTML.
std::string escapeHtml(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

void writeIndex(const std::string& dir, const std::vector<Entry>& entries, double total) {
  std::ostringstream html;
  html << "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>WireFur gallery</title>\n"
          "<style>body{font-family:sans-serif;background:#222;color:#ddd;max-width:1100px;margin:auto}"
          "figure{display:inline-block;vertical-align:top;width:520px;margin:12px}"
          "img{max-width:512px;image-rendering:pixelated;border:1px solid #444}"
          "figcaption{font-size:13px}.m{color:#9c9;font-family:monospace}</style></head><body>\n"
          "<h1>WireFur gallery</h1>\n<p>Pictures after G. S. P. Miller, <i>From Wire-frames to Furry Animals</i> "
          "(Graphics Interface 1988). Each shows its run time and its error against the exact path.</p>\n";
  for (const Entry& e : entries)
    html << "<figure><img src=\"" << escapeHtml(e.file) << "\" alt=\"" << escapeHtml(e.title) << "\"><figcaption><b>" << escapeHtml(e.title)
         << "</b><br>" << escapeHtml(e.caption) << "<br><span class=\"m\">time " << sci(e.seconds) << " s; error: " << escapeHtml(e.error)
         << "</span></figcaption></figure>\n";
  html << "<p class=\"m\">total " << sci(total) << " s</p></body></html>\n";
  writeOutputText(dir + "/index.html", html.str());
}

}  // namespace

int runGallery(const GalleryOptions& options) {
  GalleryOptions opt = options;
  if (opt.scenesDir.empty()) opt.scenesDir = dataDir() + "/scenes";
  const auto tStart = std::chrono::steady_clock::now();
  const Progress progress(opt.quiet);
  enableReaderCache();  // four scenes draw data/cad/product.step: one worker reads it
  {
    std::error_code ec;  // bad input first: no output folder made for a run that cannot start
    if (!std::filesystem::is_directory(opt.scenesDir, ec)) throw UsageError(opt.scenesDir + ": no such scenes folder");
  }
  ensureDirectory(opt.outDir);
  const std::string dir = opt.outDir;
  std::vector<Entry> entries;
  const glm::dvec3 view(0.0, 0.0, 1.0);

  // Every scene in the scenes folder, in the order of the paper's images (then by name).
  std::vector<std::pair<std::string, SceneFile>> scenes;
  double loadSeconds = 0, renderSeconds = 0, writeSeconds = 0;
  // The pictures are written after the renders (whose times are shown), in parallel.
  // (Kept as the PNGs' 8-bit bytes: each render's float image goes back at once, and the next
  // render takes its block again instead of new pages from the kernel.)
  struct PendingPng {
    SrgbImage image;
    std::string path;
  };
  std::vector<PendingPng> pending;
  {
    std::error_code ec;
    if (!std::filesystem::is_directory(opt.scenesDir, ec))
      throw UsageError(opt.scenesDir + ": no such scenes folder");
    std::vector<std::string> files;
    for (const auto& e : std::filesystem::directory_iterator(opt.scenesDir))
      if (e.path().extension() == ".json") files.push_back(e.path().string());
    std::sort(files.begin(), files.end());  // the directory's order is the file system's
    // Read (and grow) every scene first, all checked before anything is drawn, in parallel: the
    // first problem in file order is the one reported.
    const auto tl = std::chrono::steady_clock::now();
    std::vector<std::optional<SceneFile>> loaded(files.size());
    std::vector<std::exception_ptr> failed(files.size());
    tbb::parallel_for(size_t(0), files.size(), [&](size_t i) {
      try {
        loaded[i] = loadSceneFile(files[i]);
      } catch (...) {
        failed[i] = std::current_exception();
      }
    });
    for (size_t i = 0; i < files.size(); ++i)
      if (failed[i]) std::rethrow_exception(failed[i]);
    for (size_t i = 0; i < files.size(); ++i) scenes.emplace_back(files[i], std::move(*loaded[i]));
    loadSeconds = secondsSince(tl);
    auto key = [](const SceneFile& sf) {
      return std::atof(sf.paperImage.c_str()) + (sf.paperImage.empty() ? 1e6 : 0.0);
    };
    std::sort(scenes.begin(), scenes.end(), [&](const auto& a, const auto& b) {
      return std::make_tuple(key(a.second), a.second.paperImage, a.first) <
             std::make_tuple(key(b.second), b.second.paperImage, b.first);
    });
  }
  json sceneStats = json::object();
  for (auto& [file, sf] : scenes) {
    const std::string stem = std::filesystem::path(file).stem().string();
    if (stem == "environment" || stem.rfind("prm_", 0) == 0 || stem == "index" || stem == "gallery")
      throw UsageError(file + ": this name is taken by the gallery's own pictures; rename the scene");
    progress.say("scene " + stem);
    wf::RenderOptions ro = renderOptionsFor(sf);
    if (opt.size > 0 && std::max(ro.width, ro.height) > opt.size) {
      const double f = double(opt.size) / std::max(ro.width, ro.height);
      ro.width = std::max(1, int(std::lround(ro.width * f)));
      ro.height = std::max(1, int(std::lround(ro.height * f)));
    }
    const auto tr = std::chrono::steady_clock::now();
    wf::RenderResult r = wf::render(sf.scene, ro);
    renderSeconds += secondsSince(tr);
    const auto tw = std::chrono::steady_clock::now();
    pending.push_back({toSrgb(r.image), dir + "/" + stem + ".png"});
    r.image = wf::ImageRGBA();
    writeSeconds += secondsSince(tw);
    json st = statsJson(r.stats, ro, false);
    st["seconds"]["generate"] = sf.generateSeconds;
    st["generated"] = {{"hairs", sf.hairsGrown}, {"scales", sf.scalesGrown}};
    sceneStats[stem] = st;
    const auto& e = st["error_estimate"];
    const std::string shading =
        ro.shading == wf::ShadingPath::Maps
            ? "shading by the paper's tables within " + sci(e["shading_bound"].get<double>()) + " (tables " +
                  sci(e["map_max"].get<double>() + e["sphere_max"].get<double>()) + ", orthographic view " +
                  sci(e["orthographic_max"].get<double>()) + "), " + std::to_string(r.stats.pseudoReflectanceMaps) +
                  " maps built"
        : e["shading_bound"].get<double>() == 0.0
            ? std::string("shading exact at every fragment's own view vector (no tables)")
            : "shading at every fragment's own view vector within " + sci(e["shading_bound"].get<double>()) +
                  " of exact (" + std::to_string(r.stats.lobeTables) +
                  (r.stats.lobeTables == 1 ? " lobe table built)" : " lobe tables built)");
    std::string err = "coverage exact per fragment (hiding by " + ro.mask.name() + " masks, 1/" +
                      std::to_string(ro.mask.samples()) + "); " + shading + "; " +
                      std::to_string(r.stats.abuffer.fragments) + " fragments";
    if (sf.hairsGrown + sf.scalesGrown > 0)
      err += "; grew " + std::to_string(sf.hairsGrown) + " hairs and " + std::to_string(sf.scalesGrown) + " scales in " +
             std::to_string(int(std::lround(sf.generateSeconds * 1e3))) + " ms (not in the render time)";
    std::string title = sf.title;
    if (!sf.paperImage.empty()) title = sf.paperImage + ". " + title;
    entries.push_back({stem + ".png", title, sf.caption, r.stats.total, err});
  }

  // The procedural environment the chrome scenes reflect.
  {
    const wf::EnvironmentMap env = wf::EnvironmentMap::mountainScene(1024);
    wf::ImageRGBA envImg(env.width() / 2, env.height() / 2);
    for (int y = 0; y < envImg.height; ++y)
      for (int x = 0; x < envImg.width; ++x) {
        glm::vec3 s(0.0f);
        for (int k = 0; k < 4; ++k) s += env.texels()[size_t(2 * y + k / 2) * env.width() + 2 * x + k % 2];
        envImg.at(x, y) = glm::vec4(s * 0.25f, 1.0f);
      }
    writePng(envImg, dir + "/environment.png");
    entries.push_back({"environment.png", "The environment (latitude-longitude)",
                       "The procedural scene the chrome scenes reflect (fixed to the viewer); centre column straight "
                       "ahead (-z), the viewer's back at the left and right edges.", 0.0, "exact (it is the definition)"});
  }

  // Image 1's plastic under seven lights: the material of the map pictures below.
  wf::PhongMaterial plastic;
  plastic.diffuse = glm::dvec3(0.55, 0.10, 0.06);
  plastic.specular = glm::dvec3(6.0);  // the paper's "very bright highlights" (§2.2)
  plastic.exponent = 80.0;
  const wf::LightRig rig = wf::LightRig::studioRig(7).canonical();

  // The two pseudo-reflectance maps of the same plastic under the same lights, with the
  // default (warped) indexing and with the paper's (x, z) / (y, z) indexing.
  using Indexing = wf::PseudoReflectanceMapOptions::Indexing;
  for (Indexing ix : {Indexing::Warped, Indexing::Paper}) {
    const bool warped = ix == Indexing::Warped;
    progress.say(std::string("pseudo-reflectance maps, ") + (warped ? "warped" : "paper") + " indexing");
    wf::PseudoReflectanceMapOptions mo;
    mo.indexing = ix;
    if (!warped) mo.resolution = 256;  // the paper's indexing needs it (and still falls short)
    wf::PseudoReflectanceMap map;
    map.build(plastic, rig, mo);
    // Error against the exact path over seeded tangents on the whole sphere.
    std::mt19937_64 rng(1988);
    std::normal_distribution<double> g;
    double mx = 0, sq = 0;
    const int count = 2000;
    for (int i = 0; i < count; ++i) {
      const glm::dvec3 t = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
      const glm::dvec3 e = glm::abs(glm::dvec3(map.lookup(t)) - wf::cylinderRadianceExact(t, view, plastic, rig));
      const double err = std::max({e.x, e.y, e.z});
      mx = std::max(mx, err);
      sq += err * err;
    }
    const std::string err = "map vs exact cylinder average over 2000 tangents: max " + sci(mx) + ", RMS " +
                            sci(std::sqrt(sq / count)) + "; " + std::to_string(map.texelsComputed()) + " texels";
    const std::string tag = warped ? "" : "_paper";
    const int scale = std::max(1, 512 / map.resolution());
    writePng(mapImage(map, wf::PseudoReflectanceMap::Plane::XZ, scale), dir + "/prm_xz" + tag + ".png");
    writePng(mapImage(map, wf::PseudoReflectanceMap::Plane::YZ, scale), dir + "/prm_yz" + tag + ".png");
    const std::string size = std::to_string(map.resolution()) + "x" + std::to_string(map.resolution());
    if (warped) {
      entries.push_back({"prm_xz.png", "Pseudo-reflectance map (x, z), default warped indexing",
                         "The plastic of image 1 averaged across cylinders (64 normals equally spaced along the "
                         "diameter), for tangents with |x| <= |y| (y >= 0 implicit). Across: sqrt(2) x / "
                         "sqrt(x^2+y^2), the azimuth; up: z, warped so rows are near-equal steps in angle; the top "
                         "and bottom rows are the view axis. " + size + ".",
                         map.lastBuildSeconds(), err});
      entries.push_back({"prm_yz.png", "Pseudo-reflectance map (y, z), default warped indexing",
                         "The second map: tangents with |y| < |x| (x >= 0 implicit), indexed by the azimuth from "
                         "y and the warped z. " + size + ".",
                         map.lastBuildSeconds(), err});
    } else {
      entries.push_back({"prm_xz_paper.png", "Pseudo-reflectance map (x, z), the paper's indexing",
                         "As in §2.2: across x, up z, y >= 0 implicit; the ellipse is where |x| <= |y| (black "
                         "texels are never read, so never computed). Near the top and bottom (the view axis) one "
                         "texel spans many degrees: the error there is why the warped indexing is the default. " + size + ".",
                         map.lastBuildSeconds(), err});
      entries.push_back({"prm_yz_paper.png", "Pseudo-reflectance map (y, z), the paper's indexing",
                         "The (y, z) map, used where |y| < |x|. " + size + ".", map.lastBuildSeconds(), err});
    }
  }

  {
    const auto tw = std::chrono::steady_clock::now();
    // Each picture is written to a temporary file and renamed (writePng); of several failures the
    // first in gallery order is reported.
    std::vector<std::exception_ptr> failed(pending.size());
    tbb::parallel_for(size_t(0), pending.size(), [&](size_t i) {
      try {
        writePng(pending[i].image, pending[i].path, 1);
      } catch (...) {
        failed[i] = std::current_exception();
      }
    });
    for (const std::exception_ptr& e : failed)
      if (e) std::rethrow_exception(e);
    writeSeconds += secondsSince(tw);
  }
  const double total = secondsSince(tStart);
  writeIndex(dir, entries, total);
  json doc = json::array();
  for (const Entry& e : entries) {
    json j = {{"file", e.file}, {"title", e.title}, {"seconds", e.seconds}, {"error_estimate", e.error}};
    const std::string stem = std::filesystem::path(e.file).stem().string();
    if (sceneStats.contains(stem)) j["stats"] = sceneStats[stem];
    doc.push_back(j);
  }
  writeOutputText(dir + "/gallery.json", doc.dump(2) + "\n");
  for (const Entry& e : entries)
    std::printf("%-24s %8.3f s  %s\n", e.file.c_str(), e.seconds, e.error.c_str());
  const ReaderRuns reads = readerRuns();
  std::printf("gallery: %zu pictures in %s/index.html, %.2f s (reading and growing %.2f s, rendering %.2f s, writing %.2f s; "
              "%llu reader workers, %llu results read again from memory)\n",
              entries.size(), dir.c_str(), total, loadSeconds, renderSeconds, writeSeconds,
              (unsigned long long)reads.workers, (unsigned long long)reads.reused);
  return 0;
}

}  // namespace wfapp

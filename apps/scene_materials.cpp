// The material keys of a scene beyond Phong and chrome: burnish (grain and grooves), colour
// textures and bump maps (docs/scenes.md, "Materials").
#include "scene_materials.h"

#include "image_io.h"

#include "texture/grooves.h"
#include "texture/textures.h"

#include <filesystem>
#include <memory>

namespace wfapp {

namespace {

std::string resolve(const std::string& folder, const std::string& file) {
  std::filesystem::path p(file);
  if (p.is_relative()) p = std::filesystem::path(folder) / p;
  return p.string();
}

wf::ImageRGBA readImageAt(const Reader& r, const std::string& file, const std::string& ptr, SceneBudget& budget) {
  try {
    wf::ImageRGBA img = readPng(file);
    budget.addTexels(r, ptr, double(img.width) * double(img.height));
    return img;
  } catch (const UsageError& e) {
    r.fail(ptr, e.what());
  }
}

// The key under which a decoded image texture is shared: the file as named and its wrapping.
std::string imageKey(const std::string& file, bool wu, bool wv) {
  std::error_code ec;
  const std::filesystem::path a = std::filesystem::absolute(file, ec);
  return (ec ? std::filesystem::path(file) : a).lexically_normal().string() + (wu ? "|wu" : "|cu") + (wv ? "|wv" : "|cv");
}

std::pair<bool, bool> readWrap(const Reader& r, const json& j, const std::string& ptr) {
  if (!j.contains("wrap")) return {true, true};
  const std::string wp = Reader::at(ptr, "wrap");
  if (j["wrap"].is_boolean()) return {j["wrap"].get<bool>(), j["wrap"].get<bool>()};
  if (!j["wrap"].is_array() || j["wrap"].size() != 2) r.fail(wp, "expected true, false or [wrap u, wrap v]");
  return {r.boolean(j["wrap"][0], Reader::at(wp, 0)), r.boolean(j["wrap"][1], Reader::at(wp, 1))};
}

const std::set<std::string> kNoiseKeys = {"octaves", "frequency", "lacunarity", "gain", "seed", "periodic"};

std::set<std::string> with(std::set<std::string> a, const std::set<std::string>& b) {
  a.insert(b.begin(), b.end());
  return a;
}

std::shared_ptr<const wf::ScalarTexture> readBump(const Reader& r, const json& j, const std::string& ptr,
                                                  const std::string& folder, SceneBudget& budget, double& scale) {
  if (!j.is_object() || !j.contains("type")) r.fail(ptr, "a bump map needs a type (noise, image)");
  const std::string type = r.choice(j["type"], Reader::at(ptr, "type"), {"noise", "image"});
  if (j.contains("scale")) scale = r.number(j["scale"], Reader::at(ptr, "scale"), -1e6, 1e6);
  if (type == "image") {
    r.keys(j, ptr, {"type", "file", "wrap", "scale"});
    if (!j.contains("file")) r.fail(ptr, "an image bump map needs a file");
    const auto [wu, wv] = readWrap(r, j, ptr);
    const std::string fp = Reader::at(ptr, "file"), file = resolve(folder, r.string(j["file"], fp));
    auto& cached = budget.heightImages[imageKey(file, wu, wv)];
    if (!cached) cached = std::make_shared<wf::ImageHeight>(readImageAt(r, file, fp, budget), wu, wv);
    return cached;
  }
  r.keys(j, ptr, with(kNoiseKeys, {"type", "scale"}));
  return std::make_shared<wf::NoiseTexture>(readNoiseParams(r, j, ptr));
}

void readBurnish(const Reader& r, const json& j, const std::string& ptr, wf::Material& mat) {
  r.keys(j, ptr, {"grain", "axis", "grooves"});
  if (mat.kind == wf::Material::Kind::Chrome) r.fail(ptr, "burnish applies to Phong materials, not chrome");
  const std::string g = j.contains("grain") ? r.choice(j["grain"], Reader::at(ptr, "grain"), {"u", "v", "longer", "radial", "circular"}) : "u";
  using Grain = wf::Burnish::Grain;
  mat.burnish.grain = g == "u" || g == "longer" ? Grain::U : g == "v" ? Grain::V : g == "radial" ? Grain::Radial : Grain::Circular;
  // "longer": each face's grain along its longer extent, in world lengths (surface/grain_layout.h).
  if (g == "longer") mat.burnish.layout = wf::GrainLayout::Longer;
  if (j.contains("axis")) {
    const std::string ap = Reader::at(ptr, "axis");
    if (mat.burnish.grain == Grain::U || mat.burnish.grain == Grain::V)
      r.fail(ap, "an axis belongs to radial or circular grain");
    r.keys(j["axis"], ap, {"point", "direction"});
    if (j["axis"].contains("point")) mat.burnish.axisPoint = r.vec3(j["axis"]["point"], Reader::at(ap, "point"));
    if (j["axis"].contains("direction")) {
      mat.burnish.axisDirection = r.vec3(j["axis"]["direction"], Reader::at(ap, "direction"));
      if (!(glm::length(mat.burnish.axisDirection) > 0)) r.fail(Reader::at(ap, "direction"), "direction must not be zero");
    }
  }
  if (j.contains("grooves")) {
    const std::string gp = Reader::at(ptr, "grooves");
    const json& gj = j["grooves"];
    r.keys(gj, gp, {"count", "per_mm", "depth", "seed"});
    if (gj.contains("count") && gj.contains("per_mm")) r.fail(gp, "give count (per unit of the texture coordinate) or per_mm, not both");
    double count = gj.contains("count") ? r.number(gj["count"], Reader::at(gp, "count"), 1e-9, 1e9) : 100.0;
    if (gj.contains("per_mm")) {
      // Per millimetre (world unit) across the grain: u and v made world lengths.
      if (mat.burnish.grain != Grain::U && mat.burnish.grain != Grain::V)
        r.fail(Reader::at(gp, "per_mm"), "per_mm belongs to grain u, v or longer (circular grooves are per unit of distance already)");
      count = r.number(gj["per_mm"], Reader::at(gp, "per_mm"), 1e-9, 1e9);
      if (mat.burnish.layout == wf::GrainLayout::Raw) mat.burnish.layout = wf::GrainLayout::U;
    }
    const double depth = gj.contains("depth") ? r.number(gj["depth"], Reader::at(gp, "depth"), 0.0, 1.0) : 0.5;
    const auto seed = std::uint64_t(gj.contains("seed") ? r.integer(gj["seed"], Reader::at(gp, "seed"), 0, 2147483647) : 1);
    mat.burnish.grooves = std::make_shared<wf::GrooveTexture>(count, depth, seed);
  }
}

}  // namespace

wf::NoiseParams readNoiseParams(const Reader& r, const json& j, const std::string& ptr) {
  wf::NoiseParams n;
  if (j.contains("octaves")) n.octaves = r.integer(j["octaves"], Reader::at(ptr, "octaves"), 1, 16);
  if (j.contains("frequency")) n.frequency = r.number(j["frequency"], Reader::at(ptr, "frequency"), 1e-6, 1e6);
  if (j.contains("lacunarity")) n.lacunarity = r.number(j["lacunarity"], Reader::at(ptr, "lacunarity"), 1.0, 16.0);
  if (j.contains("gain")) n.gain = r.number(j["gain"], Reader::at(ptr, "gain"), 0.0, 1.0);
  if (j.contains("seed")) n.seed = std::uint64_t(r.integer(j["seed"], Reader::at(ptr, "seed"), 0, 2147483647));
  if (j.contains("periodic")) {
    const std::string pp = Reader::at(ptr, "periodic");
    if (!j["periodic"].is_array() || j["periodic"].size() != 2) r.fail(pp, "expected [periodic in u, periodic in v]");
    n.periodicU = r.boolean(j["periodic"][0], Reader::at(pp, 0));
    n.periodicV = r.boolean(j["periodic"][1], Reader::at(pp, 1));
  }
  return n;
}

std::shared_ptr<const wf::ColourTexture> readColourTexture(const Reader& r, const json& j, const std::string& ptr,
                                                     const std::string& folder, SceneBudget& budget) {
  if (!j.is_object() || !j.contains("type")) r.fail(ptr, "a texture needs a type (chequer, image, noise)");
  const std::string type = r.choice(j["type"], Reader::at(ptr, "type"), {"chequer", "image", "noise"});
  if (type == "chequer") {
    r.keys(j, ptr, {"type", "squares", "colours"});
    int su = 8, sv = 8;
    if (j.contains("squares")) {
      const std::string sp = Reader::at(ptr, "squares");
      if (!j["squares"].is_array() || j["squares"].size() != 2) r.fail(sp, "expected [squares along u, along v]");
      su = r.integer(j["squares"][0], Reader::at(sp, 0), 1, 1 << 20);
      sv = r.integer(j["squares"][1], Reader::at(sp, 1), 1, 1 << 20);
    }
    glm::dvec3 a(0.9), b(0.1);
    if (j.contains("colours")) {
      const std::string cp = Reader::at(ptr, "colours");
      if (!j["colours"].is_array() || j["colours"].size() != 2) r.fail(cp, "expected [colour, colour]");
      a = r.colour(j["colours"][0], Reader::at(cp, 0));
      b = r.colour(j["colours"][1], Reader::at(cp, 1));
    }
    return std::make_shared<wf::ChequerTexture>(su, sv, glm::vec3(a), glm::vec3(b));
  }
  if (type == "image") {
    r.keys(j, ptr, {"type", "file", "wrap"});
    if (!j.contains("file")) r.fail(ptr, "an image texture needs a file");
    const auto [wu, wv] = readWrap(r, j, ptr);
    const std::string fp = Reader::at(ptr, "file"), file = resolve(folder, r.string(j["file"], fp));
    auto& cached = budget.colourImages[imageKey(file, wu, wv)];
    if (!cached) cached = std::make_shared<wf::ImageTexture>(readImageAt(r, file, fp, budget), wu, wv);
    return cached;
  }
  r.keys(j, ptr, with(kNoiseKeys, {"type", "ramp"}));
  auto noise = std::make_shared<wf::NoiseTexture>(readNoiseParams(r, j, ptr));
  std::vector<wf::RampStop> stops = {{-1.0, glm::vec3(0.1f)}, {1.0, glm::vec3(0.9f)}};
  if (j.contains("ramp")) {
    const std::string rp = Reader::at(ptr, "ramp");
    if (!j["ramp"].is_array() || j["ramp"].size() < 2) r.fail(rp, "expected at least two [value, colour] stops");
    stops.clear();
    for (size_t i = 0; i < j["ramp"].size(); ++i) {
      const json& st = j["ramp"][i];
      const std::string sp = Reader::at(rp, i);
      if (!st.is_array() || st.size() != 2) r.fail(sp, "expected [value, colour]");
      const double pos = r.number(st[0], Reader::at(sp, 0), -1e6, 1e6);
      if (!stops.empty() && pos < stops.back().position) r.fail(Reader::at(sp, 0), "ramp values must not decrease");
      stops.push_back({pos, glm::vec3(r.colour(st[1], Reader::at(sp, 1)))});
    }
  }
  // Stops are given at noise values; the ramp takes them at t = (value - low) / (high - low).
  const double lo = stops.front().position, hi = stops.back().position;
  const double span = hi > lo ? hi - lo : 1.0;
  for (wf::RampStop& st : stops) st.position = (st.position - lo) / span;
  return std::make_shared<wf::RampTexture>(noise, stops, lo, lo + span);
}

const std::set<std::string>& materialExtraKeys() {
  static const std::set<std::string> keys = {"burnish", "texture", "bump"};
  return keys;
}

void readMaterialExtras(const Reader& r, const json& m, const std::string& mp, const std::string& folder,
                        SceneBudget& budget, wf::Material& mat) {
  if (m.contains("burnish")) readBurnish(r, m["burnish"], Reader::at(mp, "burnish"), mat);
  if (m.contains("texture")) mat.colourMap = readColourTexture(r, m["texture"], Reader::at(mp, "texture"), folder, budget);
  if (m.contains("bump")) mat.bumpMap = readBump(r, m["bump"], Reader::at(mp, "bump"), folder, budget, mat.bumpScale);
}

}  // namespace wfapp

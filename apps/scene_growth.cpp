// The "fur" and "scales" keys of a scene object (docs/scenes.md, "Fur and scales"): what the
// paper grows on its patches (§4.2), grown on the object's placed surface.
#include "scene_growth.h"

#include "scene_materials.h"

#include "core/limits.h"
#include "growth/fur.h"
#include "growth/scales.h"
#include "texture/textures.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>

namespace wfapp {

namespace {

glm::dvec2 pair(const Reader& r, const json& j, const std::string& ptr, double lo, double hi) {
  if (!j.is_array() || j.size() != 2) r.fail(ptr, "expected [u, v]");
  return {r.number(j[0], Reader::at(ptr, 0), lo, hi), r.number(j[1], Reader::at(ptr, 1), lo, hi)};
}

std::pair<int, int> intPair(const Reader& r, const json& j, const std::string& ptr, int lo, int hi) {
  if (!j.is_array() || j.size() != 2) r.fail(ptr, "expected [u, v]");
  return {r.integer(j[0], Reader::at(ptr, 0), lo, hi), r.integer(j[1], Reader::at(ptr, 1), lo, hi)};
}

// A scalar map over (u, v) for fur: fractal noise mapped to [low, high].
class RangeMap final : public wf::ScalarTexture {
 public:
  RangeMap(std::shared_ptr<const wf::ScalarTexture> n, double lo, double hi) : n_(std::move(n)), lo_(lo), hi_(hi) {}
  double value(const glm::dvec2& uv) const override { return lo_ + (hi_ - lo_) * 0.5 * (1.0 + n_->value(uv)); }
  glm::dvec2 gradient(const glm::dvec2& uv) const override { return (hi_ - lo_) * 0.5 * n_->gradient(uv); }
  std::string describe() const override { return "noise map"; }

 private:
  std::shared_ptr<const wf::ScalarTexture> n_;
  double lo_, hi_;
};

std::shared_ptr<const wf::ScalarTexture> readScalarMap(const Reader& r, const json& j, const std::string& ptr) {
  r.keys(j, ptr, {"octaves", "frequency", "lacunarity", "gain", "seed", "periodic", "range"});
  const wf::NoiseParams n = readNoiseParams(r, j, ptr);
  glm::dvec2 range(0.0, 1.0);
  if (j.contains("range")) range = pair(r, j["range"], Reader::at(ptr, "range"), -1e6, 1e6);
  return std::make_shared<RangeMap>(std::make_shared<wf::NoiseTexture>(n), range.x, range.y);
}

wf::FurParams readFurParams(const Reader& r, const json& j, const std::string& ptr, const GrowthContext& ctx) {
  r.keys(j, ptr, {"placement", "grid", "jitter", "density", "density_map", "orientation", "orientation_map", "unit_tangents",
                  "length", "length_mode", "length_per_su", "length_variation", "length_map", "segments", "gravity",
                  "gravity_direction", "curl", "clumping", "clumps", "wind", "root_colour", "tip_colour",
                  "root_colour_map", "intensity_variation", "regions", "thickness", "material", "seed", "opacity", "ends"});
  wf::FurParams f;
  auto num = [&](const char* key, double lo, double hi, double& out) {
    if (j.contains(key)) out = r.number(j[key], Reader::at(ptr, key), lo, hi);
  };
  if (j.contains("placement"))
    f.placement = r.choice(j["placement"], Reader::at(ptr, "placement"), {"grid", "area"}) == "grid"
                      ? wf::FurParams::Placement::Grid
                      : wf::FurParams::Placement::AreaCorrect;
  if (j.contains("grid")) std::tie(f.gridU, f.gridV) = intPair(r, j["grid"], Reader::at(ptr, "grid"), 1, 1 << 16);
  num("jitter", 0, 1, f.jitter);
  num("density", 0, 1e15, f.density);
  if (j.contains("density_map")) f.densityMap = readScalarMap(r, j["density_map"], Reader::at(ptr, "density_map"));
  if (j.contains("orientation")) f.orientation = r.vec3(j["orientation"], Reader::at(ptr, "orientation"), 1e6);
  if (j.contains("orientation_map")) {
    // Maps replacing a, b or c of the orientation where given (a combing pattern over the patch).
    const std::string op = Reader::at(ptr, "orientation_map");
    const json& o = j["orientation_map"];
    r.keys(o, op, {"a", "b", "c"});
    if (o.contains("a")) f.orientationMapA = readScalarMap(r, o["a"], Reader::at(op, "a"));
    if (o.contains("b")) f.orientationMapB = readScalarMap(r, o["b"], Reader::at(op, "b"));
    if (o.contains("c")) f.orientationMapC = readScalarMap(r, o["c"], Reader::at(op, "c"));
  }
  if (j.contains("root_colour_map"))
    f.rootColourMap = readColourTexture(r, j["root_colour_map"], Reader::at(ptr, "root_colour_map"), ctx.folder, *ctx.budget);
  if (j.contains("unit_tangents")) f.unitTangents = r.boolean(j["unit_tangents"], Reader::at(ptr, "unit_tangents"));
  num("length", 0, 1e12, f.length);
  if (j.contains("length_mode")) {
    const std::string m = r.choice(j["length_mode"], Reader::at(ptr, "length_mode"), {"fixed", "su", "paper"});
    f.lengthMode = m == "fixed" ? wf::FurParams::LengthMode::Fixed
                   : m == "su"  ? wf::FurParams::LengthMode::ProportionalToSu
                                : wf::FurParams::LengthMode::Paper;
  }
  num("length_per_su", 0, 1e12, f.lengthPerSu);
  num("length_variation", 0, 1, f.lengthVariation);
  if (j.contains("length_map")) f.lengthMap = readScalarMap(r, j["length_map"], Reader::at(ptr, "length_map"));
  if (j.contains("segments")) f.segments = r.integer(j["segments"], Reader::at(ptr, "segments"), 1, 64);
  num("gravity", 0, 1e6, f.gravity);
  if (j.contains("gravity_direction")) f.gravityDirection = r.vec3(j["gravity_direction"], Reader::at(ptr, "gravity_direction"), 1e6);
  if (j.contains("curl")) {
    const std::string cp = Reader::at(ptr, "curl");
    r.keys(j["curl"], cp, {"amplitude", "frequency"});
    if (j["curl"].contains("amplitude")) f.curlAmplitude = r.number(j["curl"]["amplitude"], Reader::at(cp, "amplitude"), 0, 1e6);
    if (j["curl"].contains("frequency")) f.curlFrequency = r.number(j["curl"]["frequency"], Reader::at(cp, "frequency"), 0, 1e6);
  }
  num("clumping", 0, 1, f.clumping);
  if (j.contains("clumps")) std::tie(f.clumpCellsU, f.clumpCellsV) = intPair(r, j["clumps"], Reader::at(ptr, "clumps"), 1, 1 << 16);
  if (j.contains("wind")) {
    const std::string wp = Reader::at(ptr, "wind");
    const json& w = j["wind"];
    r.keys(w, wp, {"direction", "strength", "sway", "frequency", "time"});
    if (w.contains("direction")) f.windDirection = r.vec3(w["direction"], Reader::at(wp, "direction"), 1e6);
    if (w.contains("strength")) f.windStrength = r.number(w["strength"], Reader::at(wp, "strength"), 0, 1e6);
    if (w.contains("sway")) f.windSway = r.number(w["sway"], Reader::at(wp, "sway"), 0, 1);
    if (w.contains("frequency")) f.windFrequency = r.number(w["frequency"], Reader::at(wp, "frequency"), 0, 1e6);
    if (w.contains("time")) f.time = r.number(w["time"], Reader::at(wp, "time"), -wf::kMaxWindTime, wf::kMaxWindTime);
  }
  if (j.contains("root_colour")) f.rootColour = glm::vec3(r.colour(j["root_colour"], Reader::at(ptr, "root_colour")));
  if (j.contains("tip_colour")) f.tipColour = glm::vec3(r.colour(j["tip_colour"], Reader::at(ptr, "tip_colour")));
  num("intensity_variation", 0, 1, f.intensityVariation);
  if (j.contains("regions")) {
    const std::string rp = Reader::at(ptr, "regions");
    if (!j["regions"].is_array()) r.fail(rp, "expected a list of {centre, radius, colour, falloff}");
    for (size_t i = 0; i < j["regions"].size(); ++i) {
      const json& g = j["regions"][i];
      const std::string gp = Reader::at(rp, i);
      r.keys(g, gp, {"centre", "radius", "colour", "falloff"});
      wf::FurColourRegion reg;
      if (g.contains("centre")) reg.centre = pair(r, g["centre"], Reader::at(gp, "centre"), -1e6, 1e6);
      if (g.contains("radius")) reg.radius = r.number(g["radius"], Reader::at(gp, "radius"), 0, 1e6);
      if (g.contains("colour")) reg.colour = glm::vec3(r.colour(g["colour"], Reader::at(gp, "colour")));
      if (g.contains("falloff")) reg.falloff = r.number(g["falloff"], Reader::at(gp, "falloff"), 0, 1);
      f.colourRegions.push_back(reg);
    }
  }
  num("thickness", 1e-12, 1e12, f.thickness);
  if (j.contains("seed")) f.seed = std::uint64_t(r.integer(j["seed"], Reader::at(ptr, "seed"), 0, 2147483647));
  return f;
}

wf::ScaleParams readScaleParams(const Reader& r, const json& j, const std::string& ptr) {
  r.keys(j, ptr, {"cells", "cell_size", "size", "lift", "deflection", "intensity_variation", "shoulder", "colour", "seed", "material"});
  if (j.contains("cells") && j.contains("cell_size")) r.fail(ptr, "give cells or cell_size, not both");
  wf::ScaleParams s;
  if (j.contains("cells")) std::tie(s.cellsU, s.cellsV) = intPair(r, j["cells"], Reader::at(ptr, "cells"), 1, 1 << 14);
  auto num = [&](const char* key, double lo, double hi, double& out) {
    if (j.contains(key)) out = r.number(j[key], Reader::at(ptr, key), lo, hi);
  };
  num("size", 1e-9, 16, s.size);
  num("lift", 0, 16, s.lift);
  num("deflection", 0, 16, s.deflection);
  num("intensity_variation", 0, 1, s.intensityVariation);
  num("shoulder", 1e-9, 1 - 1e-9, s.shoulder);
  if (j.contains("colour")) s.colour = glm::vec3(r.colour(j["colour"], Reader::at(ptr, "colour")));
  if (j.contains("seed")) s.seed = std::uint64_t(r.integer(j["seed"], Reader::at(ptr, "seed"), 0, 2147483647));
  return s;
}

}  // namespace

void readGrowth(const Reader& r, const json& obj, const std::string& ptr, const GrowthContext& ctx, wf::ObjectDescription& object) {
  if (obj.contains("fur")) {
    const std::string fp = Reader::at(ptr, "fur");
    const json& j = obj["fur"];
    wf::FurDescription f;
    f.where = fp;
    f.params = readFurParams(r, j, fp, ctx);
    if (j.contains("material")) f.material = ctx.material(j["material"], Reader::at(fp, "material"));
    if (j.contains("opacity")) f.opacity = float(r.number(j["opacity"], Reader::at(fp, "opacity"), 0, 1));
    if (j.contains("ends")) f.roundEnds = r.choice(j["ends"], Reader::at(fp, "ends"), {"square", "round"}) == "round";
    object.fur = std::move(f);
  }
  if (obj.contains("scales")) {
    const std::string sp = Reader::at(ptr, "scales");
    const json& j = obj["scales"];
    wf::ScalesDescription s;
    s.where = sp;
    s.cellsWhere = Reader::at(sp, "cells");
    s.params = readScaleParams(r, j, sp);
    if (j.contains("cell_size")) s.cellSize = r.number(j["cell_size"], Reader::at(sp, "cell_size"), 1e-12, 1e12);
    if (j.contains("material")) s.material = ctx.material(j["material"], Reader::at(sp, "material"));
    object.scales = std::move(s);
  }
}

}  // namespace wfapp

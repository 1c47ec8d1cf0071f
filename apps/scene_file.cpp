#include "scene_file.h"

#include "cad_input.h"

#include "cli.h"
#include "safe_files.h"
#include "built_in_scene.h"
#include "mesh_io.h"
#include "scene_growth.h"
#include "scene_materials.h"
#include "scene_reader.h"

#include "geometry/parametric_sources.h"

#include <nlohmann/json.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace wfapp {

namespace {

using json = nlohmann::json;

std::string readText(const std::string& path) { return readInputFile(path, "the scene file"); }

json parse(const std::string& path, const std::string& text) {
  // Byte offset to "line:column" for the one-line message.
  auto place = [&](size_t byte) {
    size_t line = 1, col = 1;
    for (size_t i = 0; i + 1 < byte && i < text.size(); ++i) {
      if (text[i] == '\n') ++line, col = 1;
      else ++col;
    }
    return std::to_string(line) + ":" + std::to_string(col);
  };
  try {
    return json::parse(text, nullptr, true, /*ignore_comments=*/true);
  } catch (const json::parse_error& e) {
    std::string what = e.what();
    const size_t p = what.find("parse error");
    if (p != std::string::npos) what = what.substr(p);
    throw UsageError(path + ":" + place(e.byte) + ": invalid JSON: " + what);
  } catch (const json::exception& e) {
    // A number beyond double range ("number overflow parsing '1e400'"): still bad input. The
    // parser gives no offset; the token it quotes is found in the text instead.
    std::string what = e.what();
    const size_t p = what.find("] ");
    if (p != std::string::npos) what = what.substr(p + 2);
    const size_t q0 = what.find('\''), q1 = q0 == std::string::npos ? q0 : what.find('\'', q0 + 1);
    if (q1 != std::string::npos && q1 > q0 + 1) {
      const std::string token = what.substr(q0 + 1, q1 - q0 - 1);
      const size_t at = text.find(token);
      if (at != std::string::npos) throw UsageError(path + ":" + place(at + 1) + ": invalid JSON: " + what);
    }
    throw UsageError(path + ": invalid JSON: " + what);
  }
}

glm::dmat4 readTransform(const Reader& r, const json& j, const std::string& ptr) {
  r.keys(j, ptr, {"scale", "rotate", "translate"});
  glm::dmat4 M(1.0);
  if (j.contains("translate")) M = glm::translate(M, r.vec3(j["translate"], Reader::at(ptr, "translate")));
  if (j.contains("rotate")) {
    const json& rot = j["rotate"];
    const std::string rp = Reader::at(ptr, "rotate");
    auto one = [&](const json& x, const std::string& p) {
      r.keys(x, p, {"axis", "degrees"});
      if (!x.contains("axis") || !x.contains("degrees")) r.fail(p, "a rotation needs axis and degrees");
      const glm::dvec3 axis = r.vec3(x["axis"], Reader::at(p, "axis"));
      if (!(glm::length(axis) > 0)) r.fail(Reader::at(p, "axis"), "axis must not be zero");
      M = glm::rotate(M, glm::radians(r.number(x["degrees"], Reader::at(p, "degrees"), -1e6, 1e6)), glm::normalize(axis));
    };
    if (rot.is_array())
      for (size_t i = 0; i < rot.size(); ++i) one(rot[i], Reader::at(rp, i));
    else one(rot, rp);
  }
  if (j.contains("scale")) {
    const std::string sp = Reader::at(ptr, "scale");
    const glm::dvec3 s = j["scale"].is_number() ? glm::dvec3(r.number(j["scale"], sp, 1e-12, 1e12)) : r.vec3(j["scale"], sp);
    for (int k = 0; k < 3; ++k)  // mirroring allowed; sizes within the range the renderer is tested for
      if (!(std::abs(s[k]) >= 1e-12 && std::abs(s[k]) <= 1e12))
        r.fail(sp, "each scale factor must have a magnitude in [1e-12, 1e12]");
    M = glm::scale(M, s);
  }
  return M;
}

std::vector<glm::dvec3> readPoints(const Reader& r, const json& j, const std::string& ptr) {
  if (!j.is_array()) r.fail(ptr, "expected a list of [x, y, z] points");
  std::vector<glm::dvec3> pts;
  for (size_t i = 0; i < j.size(); ++i) pts.push_back(r.vec3(j[i], Reader::at(ptr, i)));
  return pts;
}

wf::ParametricSource readSource(const Reader& r, const json& j, const std::string& ptr) {
  r.keys(j, ptr, {"type", "radius", "major", "minor", "profile", "corners", "interpolation", "corner_angle", "size",
                  "sections", "up", "points", "count", "periodic", "resolution"});
  if (!j.contains("type")) r.fail(ptr, "a source needs a type");
  wf::ParametricSource s;
  const std::string type = r.choice(j["type"], Reader::at(ptr, "type"),
                                    {"sphere", "torus", "lathe", "plane", "box", "loft", "bezier", "bspline"});
  using T = wf::ParametricSource::Type;
  s.type = type == "sphere"   ? T::Sphere
           : type == "torus"  ? T::Torus
           : type == "lathe"  ? T::Lathe
           : type == "plane"  ? T::Plane
           : type == "loft"   ? T::Loft
           : type == "bezier" ? T::Bezier
           : type == "bspline" ? T::BSpline
                              : T::Box;
  // Keys that belong to other types are errors, not silently ignored.
  static const std::map<std::string, std::set<std::string>> owners = {
      {"radius", {"sphere"}}, {"major", {"torus"}}, {"minor", {"torus"}}, {"profile", {"lathe"}},
      {"corners", {"lathe"}}, {"interpolation", {"lathe"}}, {"corner_angle", {"lathe"}}, {"size", {"plane", "box"}},
      {"sections", {"loft"}}, {"up", {"loft"}}, {"points", {"bezier", "bspline"}}, {"count", {"bspline"}},
      {"periodic", {"bspline"}}};
  for (const auto& [key, types] : owners)
    if (j.contains(key) && !types.count(type)) r.fail(Reader::at(ptr, key), "does not belong to a " + type + " source");
  if (j.contains("radius")) s.radius = r.number(j["radius"], Reader::at(ptr, "radius"), 1e-12, 1e12);
  if (j.contains("major")) s.major = r.number(j["major"], Reader::at(ptr, "major"), 1e-12, 1e12);
  if (j.contains("minor")) s.minor = r.number(j["minor"], Reader::at(ptr, "minor"), 1e-12, 1e12);
  if (j.contains("size")) {
    const std::string sp = Reader::at(ptr, "size");
    if (j["size"].is_array() && j["size"].size() == 2)
      s.size = glm::dvec3(r.number(j["size"][0], Reader::at(sp, 0), 1e-12, 1e12), r.number(j["size"][1], Reader::at(sp, 1), 1e-12, 1e12), 1.0);
    else s.size = r.vec3(j["size"], sp);
  }
  if (j.contains("profile")) {
    const std::string pp = Reader::at(ptr, "profile");
    if (!j["profile"].is_array()) r.fail(pp, "expected [[radius, height], ...]");
    for (size_t i = 0; i < j["profile"].size(); ++i) {
      const json& p = j["profile"][i];
      const std::string ip = Reader::at(pp, i);
      if (!p.is_array() || p.size() != 2) r.fail(ip, "expected [radius, height]");
      s.profile.emplace_back(r.number(p[0], Reader::at(ip, 0), 0, 1e12), r.number(p[1], Reader::at(ip, 1), -1e12, 1e12));
    }
  }
  if (j.contains("corners")) {
    // Indices of profile points that are crisp corners (a jug's base rim).
    const std::string cp = Reader::at(ptr, "corners");
    if (!j["corners"].is_array()) r.fail(cp, "expected a list of profile point indices");
    s.profileCorners.assign(s.profile.size(), false);
    for (size_t i = 0; i < j["corners"].size(); ++i)
      s.profileCorners[size_t(r.integer(j["corners"][i], Reader::at(cp, i), 0, int(s.profile.size()) - 1))] = true;
  }
  if (j.contains("interpolation"))
    s.profileLinear = r.choice(j["interpolation"], Reader::at(ptr, "interpolation"), {"smooth", "linear"}) == "linear";
  if (j.contains("corner_angle")) s.profileCornerAngle = r.number(j["corner_angle"], Reader::at(ptr, "corner_angle"), 0, 180);
  if (j.contains("sections")) {
    const std::string sp = Reader::at(ptr, "sections");
    if (!j["sections"].is_array()) r.fail(sp, "expected a list of {centre, radii}");
    for (size_t i = 0; i < j["sections"].size(); ++i) {
      const json& q = j["sections"][i];
      const std::string qp = Reader::at(sp, i);
      r.keys(q, qp, {"centre", "radius", "radii", "profile"});
      if (!q.contains("centre")) r.fail(qp, "a section needs a centre");
      wf::LoftSection sec;
      sec.centre = r.vec3(q["centre"], Reader::at(qp, "centre"));
      if (q.contains("radius")) sec.a = sec.b = r.number(q["radius"], Reader::at(qp, "radius"), 0, 1e12);
      if (q.contains("radii")) {
        const std::string rp = Reader::at(qp, "radii");
        if (!q["radii"].is_array() || q["radii"].size() != 2) r.fail(rp, "expected [a, b]");
        sec.a = r.number(q["radii"][0], Reader::at(rp, 0), 0, 1e12);
        sec.b = r.number(q["radii"][1], Reader::at(rp, 1), 0, 1e12);
      }
      if (q.contains("profile")) {
        const std::string pp = Reader::at(qp, "profile");
        if (!q["profile"].is_array()) r.fail(pp, "expected [[x, y], ...]");
        for (size_t k = 0; k < q["profile"].size(); ++k) {
          const json& p = q["profile"][k];
          if (!p.is_array() || p.size() != 2) r.fail(Reader::at(pp, k), "expected [x, y]");
          sec.profile.emplace_back(r.number(p[0], Reader::at(Reader::at(pp, k), 0), -1e12, 1e12),
                                   r.number(p[1], Reader::at(Reader::at(pp, k), 1), -1e12, 1e12));
        }
      }
      s.sections.push_back(sec);
    }
  }
  if (j.contains("up")) s.up = r.vec3(j["up"], Reader::at(ptr, "up"));
  if (j.contains("points")) s.controlPoints = readPoints(r, j["points"], Reader::at(ptr, "points"));
  if (j.contains("count")) {
    const std::string cp = Reader::at(ptr, "count");
    if (!j["count"].is_array() || j["count"].size() != 2) r.fail(cp, "expected [control points along u, along v]");
    s.controlCountU = r.integer(j["count"][0], Reader::at(cp, 0), 1, 4096);
    s.controlCountV = r.integer(j["count"][1], Reader::at(cp, 1), 1, 4096);
  }
  if (j.contains("periodic")) {
    const std::string pp = Reader::at(ptr, "periodic");
    if (!j["periodic"].is_array() || j["periodic"].size() != 2) r.fail(pp, "expected [closed in u, closed in v]");
    s.periodicU = r.boolean(j["periodic"][0], Reader::at(pp, 0));
    s.periodicV = r.boolean(j["periodic"][1], Reader::at(pp, 1));
  }
  if (j.contains("resolution")) {
    const std::string rp = Reader::at(ptr, "resolution");
    if (!j["resolution"].is_array() || j["resolution"].size() != 2) r.fail(rp, "expected [u, v]");
    s.resolutionU = r.integer(j["resolution"][0], Reader::at(rp, 0), 1, 4096);
    s.resolutionV = r.integer(j["resolution"][1], Reader::at(rp, 1), 1, 4096);
  }
  const std::string problem = s.problem();
  if (!problem.empty()) r.fail(ptr, problem);
  return s;
}

void readLights(const Reader& r, const json& j, const std::string& ptr, wf::Scene& scene) {
  r.keys(j, ptr, {"preset", "count", "ambient", "directional", "space"});
  if (j.contains("count") && !j.contains("preset")) r.fail(Reader::at(ptr, "count"), "count belongs to a preset");
  if (j.contains("preset")) {
    r.choice(j["preset"], Reader::at(ptr, "preset"), {"studio"});
    const int count = j.contains("count") ? r.integer(j["count"], Reader::at(ptr, "count"), 1, 7) : 3;
    scene.lights = wf::LightRig::studioRig(count);
    scene.lightsFollowCamera = true;
  }
  if (j.contains("space"))
    scene.lightsFollowCamera = r.choice(j["space"], Reader::at(ptr, "space"), {"world", "eye"}) == "eye";
  if (j.contains("ambient")) scene.lights.ambient = r.colour(j["ambient"], Reader::at(ptr, "ambient"));
  if (j.contains("directional")) {
    const std::string dp = Reader::at(ptr, "directional");
    if (!j["directional"].is_array()) r.fail(dp, "expected a list of lights");
    for (size_t i = 0; i < j["directional"].size(); ++i) {
      const json& l = j["directional"][i];
      const std::string lp = Reader::at(dp, i);
      r.keys(l, lp, {"direction", "intensity"});
      if (!l.contains("direction")) r.fail(lp, "a light needs a direction (towards the light)");
      wf::DirectionalLight light;
      light.direction = r.vec3(l["direction"], Reader::at(lp, "direction"));
      if (!(glm::length(light.direction) > 0)) r.fail(Reader::at(lp, "direction"), "direction must not be zero");
      light.direction = glm::normalize(light.direction);
      if (l.contains("intensity")) light.intensity = r.colour(l["intensity"], Reader::at(lp, "intensity"));
      scene.lights.lights.push_back(light);
    }
  }
}

void readMaterials(const Reader& r, const json& j, const std::string& ptr, const std::string& folder,
                   SceneBudget& budget, wf::Scene& scene, std::map<std::string, int>& index) {
  if (!j.is_object()) r.fail(ptr, "expected an object of named materials");
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string mp = Reader::at(ptr, it.key());
    const json& m = it.value();
    std::set<std::string> keys = {"kind", "diffuse", "specular", "exponent", "opacity", "reflectance"};
    keys.insert(materialExtraKeys().begin(), materialExtraKeys().end());
    r.keys(m, mp, keys);
    wf::Material mat;
    mat.name = it.key();
    if (m.contains("kind"))
      mat.kind = r.choice(m["kind"], Reader::at(mp, "kind"), {"phong", "chrome"}) == "chrome" ? wf::Material::Kind::Chrome
                                                                                              : wf::Material::Kind::Phong;
    if (m.contains("diffuse")) mat.phong.diffuse = r.colour(m["diffuse"], Reader::at(mp, "diffuse"));
    if (m.contains("specular")) mat.phong.specular = r.colour(m["specular"], Reader::at(mp, "specular"));
    if (m.contains("exponent")) mat.phong.exponent = r.number(m["exponent"], Reader::at(mp, "exponent"), 0, wf::kMaxPhongExponent);
    if (m.contains("opacity")) mat.opacity = float(r.number(m["opacity"], Reader::at(mp, "opacity"), 0, 1));
    if (m.contains("reflectance")) mat.chromeReflectance = r.colour(m["reflectance"], Reader::at(mp, "reflectance"));
    readMaterialExtras(r, m, mp, folder, budget, mat);
    index[mat.name] = int(scene.materials.size());
    scene.materials.push_back(mat);
  }
}

int materialRef(const Reader& r, const json& j, const std::string& ptr, const std::map<std::string, int>& index) {
  const std::string name = r.string(j, ptr);
  auto it = index.find(name);
  if (it == index.end()) r.fail(ptr, "no material named '" + name + "' in /materials");
  return it->second;
}

wf::WireDescription readWire(const Reader& r, const json& j, const std::string& ptr, const std::map<std::string, int>& materials) {
  r.keys(j, ptr, {"from", "lines", "style", "material", "thickness", "units", "colour", "opacity", "ends", "hidden", "silhouettes",
                  "edges"});
  wf::WireDescription w;
  w.where = ptr;
  if (j.contains("from")) {
    const std::string from = r.choice(j["from"], Reader::at(ptr, "from"), {"isolines", "edges", "lines"});
    using F = wf::WireDescription::From;
    w.from = from == "isolines" ? F::Isolines : from == "edges" ? F::Edges : F::Lines;
  }
  if (j.contains("lines")) {
    const std::string lp = Reader::at(ptr, "lines");
    if (!j["lines"].is_array() || j["lines"].size() != 2) r.fail(lp, "expected [lines along u, lines along v]");
    w.linesU = r.integer(j["lines"][0], Reader::at(lp, 0), 0, 4096);
    w.linesV = r.integer(j["lines"][1], Reader::at(lp, 1), 0, 4096);
  }
  if (j.contains("style")) {
    const std::string s = r.choice(j["style"], Reader::at(ptr, "style"), {"shaded", "plain", "depth-cued"});
    w.wire.style = s == "shaded" ? wf::WireStyle::Shaded : s == "plain" ? wf::WireStyle::Plain : wf::WireStyle::DepthCued;
  }
  if (j.contains("material")) w.wire.material = materialRef(r, j["material"], Reader::at(ptr, "material"), materials);
  if (j.contains("thickness")) w.wire.thickness = r.number(j["thickness"], Reader::at(ptr, "thickness"), 1e-12, 1e12);
  if (j.contains("units")) w.wire.thicknessInPixels = r.choice(j["units"], Reader::at(ptr, "units"), {"world", "pixels"}) == "pixels";
  if (w.wire.thicknessInPixels && w.wire.thickness > 1000) r.fail(Reader::at(ptr, "thickness"), "at most 1000 pixels");
  if (j.contains("colour")) w.wire.colour = glm::vec3(r.colour(j["colour"], Reader::at(ptr, "colour")));
  if (j.contains("opacity")) w.wire.opacity = float(r.number(j["opacity"], Reader::at(ptr, "opacity"), 0, 1));
  if (j.contains("ends")) w.wire.roundEnds = r.choice(j["ends"], Reader::at(ptr, "ends"), {"square", "round"}) == "round";
  if (j.contains("silhouettes")) w.silhouettes = r.boolean(j["silhouettes"], Reader::at(ptr, "silhouettes"));
  if (j.contains("edges")) {
    // "sharp", or {"mode": "sharp", "feature_angle": 20, "seams": true}
    const std::string ep = Reader::at(ptr, "edges");
    const json& e = j["edges"];
    if (e.is_object()) r.keys(e, ep, {"mode", "feature_angle", "seams"});
    if (!e.is_object() || e.contains("mode")) {
      const std::string m = r.choice(e.is_object() ? e["mode"] : e, e.is_object() ? Reader::at(ep, "mode") : ep, {"all", "sharp", "boundary"});
      wf::parseEdgeMode(m, w.edges.mode);
    }
    if (e.is_object() && e.contains("feature_angle")) w.edges.featureAngle = r.number(e["feature_angle"], Reader::at(ep, "feature_angle"), 0, 180);
    if (e.is_object() && e.contains("seams")) w.edges.seams = r.boolean(e["seams"], Reader::at(ep, "seams"));
  }
  if (j.contains("hidden")) {
    // "dashed", or {"mode": "dashed", "dash": 6, "gap": 4} / {"mode": "ghost", "opacity": 0.3}
    const std::string hp = Reader::at(ptr, "hidden");
    const json& h = j["hidden"];
    const json& mode = h.is_object() && h.contains("mode") ? h["mode"] : h;
    if (h.is_object()) r.keys(h, hp, {"mode", "dash", "gap", "opacity"});
    const std::string m = r.choice(mode, h.is_object() ? Reader::at(hp, "mode") : hp, {"off", "dashed", "ghost", "hide"});
    wf::parseHiddenMode(m, w.wire.hidden.mode);
    if (h.is_object()) {
      // Keys of another mode are errors, as keys of another source type are.
      if (m == "dashed") r.keys(h, hp, {"mode", "dash", "gap"});
      else if (m == "ghost") r.keys(h, hp, {"mode", "opacity"});
      else r.keys(h, hp, {"mode"});
      if (h.contains("dash")) w.wire.hidden.dash = r.number(h["dash"], Reader::at(hp, "dash"), 0.5, 1000);
      if (h.contains("gap")) w.wire.hidden.gap = r.number(h["gap"], Reader::at(hp, "gap"), 0.5, 1000);
      if (h.contains("opacity")) w.wire.hidden.ghost = float(r.number(h["opacity"], Reader::at(hp, "opacity"), 0.01, 1));
    }
  }
  return w;
}

// One object of the scene file: its description, with its file's geometry read (the I/O this
// layer does); buildScene makes it.
wf::ObjectDescription readObject(const Reader& r, const json& j, const std::string& ptr, const std::string& folder,
                                 const std::map<std::string, int>& materials, const SceneOverrides& overrides,
                                 SceneBudget& budget, nlohmann::ordered_json& inputStats) {
  r.keys(j, ptr, {"name", "source", "file", "cad", "transform", "surface", "wire", "fur", "scales"});
  wf::ObjectDescription o;
  o.where = ptr;
  o.name = j.contains("name") ? r.string(j["name"], Reader::at(ptr, "name")) : ptr;
  o.sourceWhere = Reader::at(ptr, "source");
  o.fileWhere = Reader::at(ptr, "file");
  o.surfaceWhere = Reader::at(ptr, "surface");
  if (j.contains("source") == j.contains("file")) r.fail(ptr, "an object needs exactly one of source and file");
  if (j.contains("transform")) o.transform = readTransform(r, j["transform"], Reader::at(ptr, "transform"));
  const bool grows = j.contains("fur") || j.contains("scales");
  if (j.contains("source")) {
    o.source = readSource(r, j["source"], o.sourceWhere);
  } else {
    std::string f = r.string(j["file"], o.fileWhere);
    std::filesystem::path p(f);
    if (p.is_relative()) p = std::filesystem::path(folder) / p;
    std::shared_ptr<wf::GeometryData> g = std::make_shared<wf::GeometryData>();
    if (isCadFile(p.string())) {
      // A CAD file: faces with exact surface data, its edges as the object's lines.
      CadOptions co = overrides.cad;
      if (j.contains("cad")) {
        const json& c = j["cad"];
        const std::string cp = Reader::at(ptr, "cad");
        r.keys(c, cp, {"deflection", "linear_deflection", "angular_deflection", "isos"});
        if (c.contains("deflection") && c.contains("linear_deflection")) r.fail(cp, "give deflection (relative) or linear_deflection (world units), not both");
        if (c.contains("deflection")) co.deflection = r.number(c["deflection"], Reader::at(cp, "deflection"), wf::kMinCadDeflection, wf::kMaxCadDeflection), co.absoluteDeflection = false;
        if (c.contains("linear_deflection"))
          co.deflection = r.number(c["linear_deflection"], Reader::at(cp, "linear_deflection"), wf::kMinCadLinearDeflection, wf::kMaxCadLinearDeflection), co.absoluteDeflection = true;
        if (c.contains("angular_deflection")) co.angularDegrees = r.number(c["angular_deflection"], Reader::at(cp, "angular_deflection"), wf::kMinCadAngularDegrees, wf::kMaxCadAngularDegrees);
        if (c.contains("isos")) co.isos = int(r.number(c["isos"], Reader::at(cp, "isos"), 0, wf::kMaxCadIsos));
      }
      try {
        // The exact faces for growth, and for silhouettes (asked by the wire or --silhouettes on).
        const bool silhouettes = overrides.silhouettes.value_or(j.contains("wire") && j["wire"].is_object() &&
                                                                j["wire"].contains("silhouettes") && j["wire"]["silhouettes"] == true);
        CadGeometry c = readCad(p.string(), co, grows || silhouettes);
        if (!c.warning.empty()) warn(c.warning);
        // For --stats: the coarsest tessellation of the scene's CAD objects, in world units
        // after the object's transform (its largest scale).
        nlohmann::ordered_json info = c.info;
        const glm::dmat3 A(o.transform);
        const double scale = std::max({glm::length(A[0]), glm::length(A[1]), glm::length(A[2])});
        if (info.contains("linear_deflection") && info["linear_deflection"].is_number())
          info["linear_deflection"] = info["linear_deflection"].get<double>() * scale;
        if (inputStats.empty() || info.value("linear_deflection", 0.0) > inputStats.value("linear_deflection", 0.0))
          inputStats = std::move(info);
        g = cadGeometryData(std::move(c));
      } catch (const UsageError& e) {
        r.fail(o.fileWhere, e.what());
      }
    } else {
      if (j.contains("cad")) r.fail(Reader::at(ptr, "cad"), "only for CAD files (.step .stp .iges .igs .brep .FCStd)");
      try {
        LoadedGeometry lg = readGeometry(p.string(), overrides.cad.isolate, overrides.cad.timeoutSeconds);
        g->mesh = std::move(lg.mesh);
        g->lines = std::move(lg.lines);
      } catch (const UsageError& e) {
        r.fail(o.fileWhere, e.what());
      }
    }
    o.geometry = std::move(g);
  }
  // Surface: drawn unless "surface": false; a material by name, or the default.
  if (j.contains("surface")) {
    const json& s = j["surface"];
    if (s.is_boolean()) {
      o.drawSurface = s.get<bool>();
      o.surfaceExplicit = o.drawSurface;  // `true` on an object without polygons is an error
    } else {
      r.keys(s, o.surfaceWhere, {"material", "holdout", "colours"});
      if (s.contains("material")) o.surfaceMaterial = materialRef(r, s["material"], Reader::at(o.surfaceWhere, "material"), materials);
      // A hold-out: hides the wires behind it, draws nothing (hidden-line removal)
      if (s.contains("holdout")) o.surfaceHoldout = r.boolean(s["holdout"], Reader::at(o.surfaceWhere, "holdout"));
      // The file's colours multiply the material (default); false: the material alone (steel).
      if (s.contains("colours")) o.keepColours = r.boolean(s["colours"], Reader::at(o.surfaceWhere, "colours"));
    }
  }
  if (j.contains("wire")) o.wire = readWire(r, j["wire"], Reader::at(ptr, "wire"), materials);
  GrowthContext growth;
  growth.budget = &budget;
  growth.folder = folder;
  growth.material = [&](const json& m, const std::string& mp) { return materialRef(r, m, mp, materials); };
  readGrowth(r, j, ptr, growth, o);
  return o;
}

wf::CameraDescription readCamera(const Reader& r, const json& j, const std::string& ptr) {
  r.keys(j, ptr, {"projection", "eye", "target", "up", "fov", "height", "near", "far", "direction"});
  wf::CameraDescription cd;
  cd.where = ptr.empty() ? "/" : ptr;
  wf::Camera& c = cd.camera;
  if (j.contains("projection"))
    c.projection = r.choice(j["projection"], Reader::at(ptr, "projection"), {"perspective", "orthographic"}) == "orthographic"
                       ? wf::Camera::Projection::Orthographic
                       : wf::Camera::Projection::Perspective;
  if (j.contains("fov")) c.fovYDegrees = r.number(j["fov"], Reader::at(ptr, "fov"), 1e-3, 179);
  if (!j.contains("eye")) {
    // Framed from the objects' bounds, looking along `direction` (from the target to the eye);
    // refitted by reframe() when the image size changes.
    glm::dvec3 dir(0.55, -0.75, 0.45);
    if (j.contains("direction")) dir = r.vec3(j["direction"], Reader::at(ptr, "direction"));
    if (!(glm::length(dir) > 0)) r.fail(Reader::at(ptr, "direction"), "direction must not be zero");
    for (const char* k : {"target", "up", "height"})
      if (j.contains(k)) r.fail(Reader::at(ptr, k), "only with an eye (without one the camera frames the scene)");
    cd.framed = true;
    cd.frameDirection = dir;
  } else {
    if (j.contains("direction")) r.fail(Reader::at(ptr, "direction"), "only without an eye (it says where to frame from)");
    cd.framed = false;
    c.eye = r.vec3(j["eye"], Reader::at(ptr, "eye"));
    c.target = j.contains("target") ? r.vec3(j["target"], Reader::at(ptr, "target")) : glm::dvec3(0.0);
    c.up = j.contains("up") ? r.vec3(j["up"], Reader::at(ptr, "up")) : glm::dvec3(0, 0, 1);
  }
  if (j.contains("height")) c.orthoHeight = r.number(j["height"], Reader::at(ptr, "height"), 1e-12, 1e12);
  if (j.contains("near")) c.nearPlane = r.number(j["near"], Reader::at(ptr, "near"), 0, 1e15);
  if (j.contains("far")) c.farPlane = r.number(j["far"], Reader::at(ptr, "far"), 0, 1e15);
  return cd;
}

}  // namespace

static void build(SceneFile& sf, const wf::SceneDescription& d, const std::string& file) {
  wf::BuiltScene b;
  try {
    b = wf::buildScene(d);
  } catch (const wf::SceneError& e) {
    throw UsageError(file + ": " + (e.where.empty() ? std::string("/") : e.where) + ": " + e.what());
  }
  sf.scene = std::move(b.scene);
  sf.generateSeconds = b.generateSeconds;
  sf.hairsGrown = b.hairsGrown;
  sf.grainFaces = b.grainFaces, sf.grainAlongU = b.grainAlongU, sf.grainAlongV = b.grainAlongV;
  sf.scalesGrown = b.scalesGrown;
  sf.framed = b.framed;
  sf.camera = d.camera;
  sf.silhouettes = std::move(b.silhouettes);
  sf.silhouetteStats = b.silhouetteStats;
  sf.silhouetteSeconds = b.silhouetteSeconds;
}

SceneFile parseScene(const std::string& path, const std::string& text, const std::string& folder,
                     const SceneOverrides& overrides) {
  const Reader r{path};
  const json doc = parse(path, text);
  r.keys(doc, "", {"title", "caption", "paper_image", "image", "camera", "lights", "materials", "environment", "objects"});
  SceneFile sf;
  wf::SceneDescription d;
  d.maxPrimitives = SceneBudget::kMaxPrimitives;
  d.time = overrides.time;
  if (doc.contains("title")) sf.title = r.string(doc["title"], "/title");
  if (doc.contains("caption")) sf.caption = r.string(doc["caption"], "/caption");
  if (doc.contains("paper_image")) sf.paperImage = r.string(doc["paper_image"], "/paper_image");
  if (doc.contains("image")) {
    const json& im = doc["image"];
    r.keys(im, "/image", {"size", "mask", "budget", "background", "view_grid"});
    if (im.contains("size")) {
      if (!im["size"].is_array() || im["size"].size() != 2) r.fail("/image/size", "expected [width, height]");
      sf.width = r.integer(im["size"][0], "/image/size/0", 1, wf::kMaxImageSide);
      sf.height = r.integer(im["size"][1], "/image/size/1", 1, wf::kMaxImageSide);
    }
    if (im.contains("mask") && !wf::MaskLayout::parse(r.string(im["mask"], "/image/mask"), sf.mask))
      r.fail("/image/mask", "expected 4x4, 8x4 or 8x8");
    if (im.contains("budget")) sf.budget = r.integer(im["budget"], "/image/budget", 1, wf::kMaxListBudget);
    if (im.contains("view_grid")) sf.viewGrid = r.integer(im["view_grid"], "/image/view_grid", 1, wf::kMaxViewGrid);
    if (im.contains("background")) {
      const json& b = im["background"];
      if (b.is_array() && b.size() == 4) {
        const glm::dvec3 c = r.colour(json::array({b[0], b[1], b[2]}), "/image/background");
        d.background = glm::vec4(glm::vec3(c), float(r.number(b[3], "/image/background/3", 0, 1)));
      } else {
        d.background = glm::vec4(glm::vec3(r.colour(b, "/image/background")), 1.0f);
      }
    }
  }
  d.width = sf.width, d.height = sf.height;
  wf::Scene lit;  // the lights as the reader fills them
  if (doc.contains("lights")) readLights(r, doc["lights"], "/lights", lit);
  else lit.lights = wf::LightRig::studioRig(3), lit.lightsFollowCamera = true;
  d.lights = lit.lights;
  d.lightsFollowCamera = lit.lightsFollowCamera;
  if (doc.contains("environment")) r.choice(doc["environment"], "/environment", {"mountains"});
  std::map<std::string, int> materials{{"default", 0}};
  SceneBudget budget;
  if (doc.contains("materials")) readMaterials(r, doc["materials"], "/materials", folder, budget, lit, materials);
  d.materials = lit.materials;
  if (!doc.contains("objects") || !doc["objects"].is_array() || doc["objects"].empty())
    r.fail("/objects", "expected a non-empty list of objects");
  for (size_t i = 0; i < doc["objects"].size(); ++i)
    d.objects.push_back(readObject(r, doc["objects"][i], Reader::at("/objects", i), folder, materials, overrides, budget,
                                   sf.inputStats));
  d.camera = readCamera(r, doc.contains("camera") ? doc["camera"] : json::object(), "/camera");
  if (overrides.hidden) wf::applyHiddenLines(d, *overrides.hidden);
  if (overrides.silhouettes) wf::applySilhouettes(d, *overrides.silhouettes);
  wf::applyEdgeSelection(d, overrides.edges);
  for (const std::string& w : wf::applyBurnish(d, overrides.burnish)) warn(path + ": " + w);
  build(sf, d, path);
  if (sf.title.empty()) sf.title = std::filesystem::path(path).stem().string();
  return sf;
}

void reframe(SceneFile& sf, int width, int height) {
  if (!sf.framed) return;
  wf::BuiltScene b;
  b.scene = std::move(sf.scene);
  b.silhouettes = std::move(sf.silhouettes);
  wf::frameCamera(b, sf.camera, width, height);  // (traces the silhouettes again)
  sf.scene = std::move(b.scene);
  sf.silhouettes = std::move(b.silhouettes);
  sf.silhouetteStats = b.silhouetteStats;  // of this tracing, for the camera drawn
  sf.silhouetteSeconds = b.silhouetteSeconds;
}

SceneFile loadSceneFile(const std::string& path, const SceneOverrides& overrides) {
  const std::string folder = std::filesystem::path(path).parent_path().string();
  return parseScene(path, readText(path), folder.empty() ? "." : folder, overrides);
}

SceneFile defaultScene(const SceneOverrides& overrides) {
  // data/scenes/cage_shaded.json, compiled in (built_in_scene.h) so that the command works
  // without the source tree.
  return parseScene("built-in scene (data/scenes/cage_shaded.json)", kBuiltInSceneJson, ".", overrides);
}

void buildStyled(SceneFile& sf, const std::string& path, std::shared_ptr<const wf::GeometryData> geometry, wf::Style style,
                 const SceneOverrides& overrides) {
  sf.title = std::filesystem::path(path).stem().string();
  sf.caption = path + " as " + wf::styleName(style);
  wf::SceneDescription d;
  try {
    d = wf::describeStyled(std::move(geometry), style);
  } catch (const wf::SceneError& e) {
    throw UsageError(path + ": " + e.where + ": " + e.what());
  }
  if (overrides.hidden) wf::applyHiddenLines(d, *overrides.hidden);
  if (overrides.silhouettes) wf::applySilhouettes(d, *overrides.silhouettes);
  wf::applyEdgeSelection(d, overrides.edges);
  for (const std::string& w : wf::applyBurnish(d, overrides.burnish)) warn(path + ": " + w);
  d.width = sf.width, d.height = sf.height;
  d.maxPrimitives = SceneBudget::kMaxPrimitives;
  build(sf, d, path);
}

SceneFile sceneForGeometryFile(const std::string& path, const std::string& style, const SceneOverrides& overrides) {
  wf::Style s;
  if (!wf::parseStyle(style, s)) throw UsageError("--style " + style + ": expected " + wf::styleNames());
  LoadedGeometry lg = readGeometry(path, overrides.cad.isolate, overrides.cad.timeoutSeconds);
  auto g = std::make_shared<wf::GeometryData>();
  g->mesh = std::move(lg.mesh);
  g->lines = std::move(lg.lines);
  SceneFile sf;
  buildStyled(sf, path, std::move(g), s, overrides);
  return sf;
}

}  // namespace wfapp

#include "scene/style_presets.h"

#include "texture/grooves.h"

#include <cmath>
#include <limits>
#include <map>

namespace wf {

namespace {

constexpr const char* kNames[] = {"wire", "wire-over-surface", "burnished", "fur", "scales"};

// The presets' materials, one set for every input kind. Indices into the description's list.
enum PresetMaterial { kDefault, kPart, kWire, kSteel, kIso, kHair, kFur, kSkin, kScale, kFurSkin };

std::vector<Material> presetMaterials() {
  std::vector<Material> m(10);
  auto phong = [&](int i, const char* name, glm::dvec3 d, glm::dvec3 s, double n) {
    m[size_t(i)].name = name;
    m[size_t(i)].phong = {d, s, n};
  };
  // A part's own colours (CAD files) multiply its light grey.
  phong(kPart, "part", glm::dvec3(0.8), glm::dvec3(0.25), 30.0);
  // Copper wire: it stands out from grey parts, with the highlight that shows it round.
  phong(kWire, "wire", glm::dvec3(0.6, 0.3, 0.1), glm::dvec3(0.9), 40.0);
  phong(kSteel, "brushed steel", glm::dvec3(0.18), glm::dvec3(5.0), 30.0);
  m[kSteel].burnish.grain = Burnish::Grain::U;
  phong(kIso, "iso lines", glm::dvec3(0.3, 0.32, 0.36), glm::dvec3(0.9), 40.0);
  // Strands of a polyline file: dark blond hair with a clear highlight.
  phong(kHair, "hair", glm::dvec3(0.22, 0.15, 0.09), glm::dvec3(1.0), 20.0);
  phong(kFur, "fur", glm::dvec3(0.55, 0.42, 0.3), glm::dvec3(0.25), 12.0);
  phong(kSkin, "skin", glm::dvec3(0.1, 0.12, 0.08), glm::dvec3(0.1), 10.0);
  phong(kScale, "scale", glm::dvec3(0.35, 0.55, 0.25), glm::dvec3(0.6), 30.0);
  // Under fur, skin of the hairs' root colour: the gaps between hairs read as denser fur.
  phong(kFurSkin, "fur skin", glm::dvec3(0.2, 0.13, 0.08), glm::dvec3(0.05), 10.0);
  return m;
}

double meshArea(const TriangleMesh& m) {
  double area = 0.0;
  for (const glm::uvec3& t : m.triangles) {
    if (t.x >= m.positions.size() || t.y >= m.positions.size() || t.z >= m.positions.size()) continue;
    const double a = 0.5 * glm::length(glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]));
    if (std::isfinite(a)) area += a;
  }
  return area;
}

}  // namespace

bool parseStyle(const std::string& name, Style& style) {
  for (int i = 0; i < 5; ++i)
    if (name == kNames[i]) {
      style = Style(i);
      return true;
    }
  return false;
}

const char* styleName(Style style) { return kNames[int(style)]; }

const char* styleNames() { return "wire, wire-over-surface, burnished, fur or scales"; }

double modelSize(const GeometryData& g) {
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  auto add = [&](const glm::dvec3& p) {
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) lo = glm::min(lo, p), hi = glm::max(hi, p);
  };
  for (const glm::dvec3& p : g.mesh.positions) add(p);
  for (const glm::dvec3& p : g.lines.points) add(p);
  const double d = glm::length(hi - lo);
  return std::isfinite(d) && d > 0.0 ? d : 1.0;
}

SceneDescription describeStyled(std::shared_ptr<const GeometryData> geometry, Style style) {
  const GeometryData& g = *geometry;
  const bool polygons = !g.mesh.triangles.empty();
  const bool strands = !polygons && !g.cad && !g.lines.points.empty();  // a file of polylines only
  if (!polygons && style != Style::Wire && style != Style::WireOverSurface)
    throw SceneError(std::string("--style ") + styleName(style), "needs polygons (this file has only lines)");
  SceneDescription d;
  d.materials = presetMaterials();
  d.lights = LightRig::studioRig(3);
  d.lightsFollowCamera = true;
  const double size = modelSize(g);

  const std::string where = std::string("--style ") + styleName(style);
  d.camera.where = where;
  ObjectDescription o;
  o.name = g.cad ? "part" : "mesh";
  o.where = where;
  o.sourceWhere = o.fileWhere = o.surfaceWhere = where;
  o.geometry = geometry;
  o.splitParts = g.cad;
  o.surfaceMaterial = kPart;
  o.drawSurface = style != Style::Wire;
  if (style == Style::Burnished) {
    o.surfaceMaterial = kSteel;
    o.keepColours = false;  // steel: the file's colours would paint it
    // Brushed along each face's longer extent, with visible grooves at a physical density
    // (kDefaultGroovesPerUnit a millimetre for CAD files) where the surface has its (u, v).
    d.materials[kSteel].burnish.layout = GrainLayout::Longer;
    if (g.mesh.uvs.size() == g.mesh.positions.size())
      d.materials[kSteel].burnish.grooves = std::make_shared<GrooveTexture>(kDefaultGroovesPerUnit, kDefaultGrooveDepth, 1);
  }
  if (style == Style::Scales || style == Style::Fur) {
    o.surfaceMaterial = style == Style::Fur ? kFurSkin : kSkin;
    o.keepColours = false;  // the creature's own colours, not the part's
  }
  const bool lines = style == Style::Wire || style == Style::WireOverSurface;
  if (lines && (!g.cad || !g.lines.points.empty())) {
    WireDescription w;
    w.where = where;
    w.from = g.cad || !g.lines.points.empty() ? WireDescription::From::Lines : WireDescription::From::Edges;
    w.wire.material = kWire;
    w.wire.thickness = style == Style::Wire ? 1.5 : 2.0;
    w.wire.thicknessInPixels = true;
    w.silhouettes = g.cad;  // from the exact faces, when the reader gave them (GeometryData::faces)
    if (strands) {
      // Hair, fibres, streamlines: fine strands that grow out of nothing, drawn round.
      w.wire.material = kHair;
      w.wire.thickness = 1.0;
      w.wire.restsOnSurface = false;
      w.wire.aggregate = true;
      w.wire.roundEnds = true;
    }
    o.wire = w;
  }
  if (g.cad) {
    SceneWire iso;
    iso.material = kIso;
    iso.thickness = 0.9;
    iso.thicknessInPixels = true;
    o.isoLineWire = iso;
  }
  if (style == Style::Fur) {
    FurDescription f;
    f.where = where;
    f.material = kFur;
    FurParams& p = f.params;
    const double area = meshArea(g.mesh);
    p.placement = FurParams::Placement::AreaCorrect;
    p.density = area > 0 && std::isfinite(area) ? 60000.0 / area : 0.0;
    p.cellsU = p.cellsV = 32;
    p.lengthMode = FurParams::LengthMode::Fixed;
    p.length = 0.03 * size;
    p.lengthVariation = 0.3;
    p.unitTangents = true;
    p.orientation = glm::dvec3(0.25, 0.0, 1.0);
    p.segments = 3;
    p.gravity = 0.35;
    p.thickness = 0.0012 * size;
    p.rootColour = glm::vec3(0.28f, 0.18f, 0.1f);
    p.tipColour = glm::vec3(0.75f, 0.6f, 0.42f);
    p.seed = 7;
    o.fur = f;
  }
  if (style == Style::Scales) {
    ScalesDescription s;
    s.where = s.cellsWhere = where;
    s.material = kScale;
    s.cellSize = 0.025 * size;
    s.params.size = 1.4;
    s.params.lift = 0.3;
    s.params.deflection = 0.7;
    s.params.intensityVariation = 0.3;
    s.params.seed = 17;
    o.scales = s;
  }
  d.objects.push_back(std::move(o));
  return d;
}

void applyHiddenLines(SceneDescription& d, const HiddenLines& hidden) {
  for (ObjectDescription& o : d.objects) {
    if (!o.wire || o.wire->wire.aggregate) continue;
    o.wire->wire.hidden = hidden;
    const bool polygons = o.source || (o.geometry && !o.geometry->mesh.triangles.empty());
    if (hidden.mode != HiddenLines::Mode::Off && !o.drawSurface && polygons) {
      o.drawSurface = true;
      o.surfaceHoldout = true;
      o.keepColours = false;
    }
  }
}

void applySilhouettes(SceneDescription& d, bool on) {
  for (ObjectDescription& o : d.objects)
    if (o.wire && !o.wire->wire.aggregate) o.wire->silhouettes = on;
}

std::vector<std::string> applyBurnish(SceneDescription& d, const BurnishOverrides& b) {
  std::vector<std::string> warnings;
  for (ObjectDescription& o : d.objects) {
    if (!o.drawSurface || o.surfaceMaterial < 0 || std::size_t(o.surfaceMaterial) >= d.materials.size()) continue;
    Burnish& burnish = d.materials[std::size_t(o.surfaceMaterial)].burnish;
    if (!burnish.active()) continue;
    const std::optional<BurnishOverrides::Grain>& grain = b.grain;
    if (grain) {
      if (*grain == BurnishOverrides::Grain::Circular || *grain == BurnishOverrides::Grain::Radial) {
        burnish.grain = *grain == BurnishOverrides::Grain::Circular ? Burnish::Grain::Circular : Burnish::Grain::Radial;
        burnish.layout = GrainLayout::Raw;
        if (b.axisPoint) {
          burnish.axisPoint = *b.axisPoint;
          burnish.axisDirection = *b.axisDirection;
        } else {
          // The object's bounding-box centre (placed), along z.
          glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
          if (o.geometry)
            for (const glm::dvec3& p : o.geometry->mesh.positions) {
              const glm::dvec3 q(o.transform * glm::dvec4(p, 1.0));
              if (std::isfinite(q.x + q.y + q.z)) lo = glm::min(lo, q), hi = glm::max(hi, q);
            }
          burnish.axisPoint = lo.x <= hi.x ? 0.5 * (lo + hi) : glm::dvec3(o.transform[3]);
          burnish.axisDirection = glm::dvec3(0, 0, 1);
        }
      } else {
        burnish.grain = Burnish::Grain::U;
        burnish.layout = *grain == BurnishOverrides::Grain::U   ? GrainLayout::U
                         : *grain == BurnishOverrides::Grain::V ? GrainLayout::V
                                                                  : GrainLayout::Longer;
      }
    }
    if (b.groovesPerUnit) {
      const double depth = burnish.grooves ? burnish.grooves->depth() : kDefaultGrooveDepth;
      const std::uint64_t seed = burnish.grooves ? burnish.grooves->seed() : 1;
      burnish.grooves = *b.groovesPerUnit > 0 ? std::make_shared<GrooveTexture>(*b.groovesPerUnit, depth, seed) : nullptr;
      // Grooves per unit of length: u and v made world lengths where the grain runs along them.
      if (burnish.layout == GrainLayout::Raw && (burnish.grain == Burnish::Grain::U || burnish.grain == Burnish::Grain::V))
        burnish.layout = GrainLayout::U;
    }
  }
  // Grain along u or v: grooves run across (u, v), and a mesh without them would take one groove's
  // shade all over (circular and radial grooves need only the position). Such an object gets its
  // own copy of the material, without grooves (the material may be shared with objects that have
  // (u, v), and a scene file's material may carry grooves of its own).
  std::map<int, int> withoutGrooves;
  for (ObjectDescription& o : d.objects) {
    if (!o.drawSurface || !o.geometry || o.surfaceMaterial < 0 || std::size_t(o.surfaceMaterial) >= d.materials.size()) continue;
    const Burnish& burnish = d.materials[std::size_t(o.surfaceMaterial)].burnish;
    if (!burnish.active() || !burnish.grooves || o.geometry->mesh.uvs.size() == o.geometry->mesh.positions.size()) continue;
    if (burnish.grain != Burnish::Grain::U && burnish.grain != Burnish::Grain::V) continue;
    auto [it, added] = withoutGrooves.try_emplace(o.surfaceMaterial, int(d.materials.size()));
    if (added) {
      Material copy = d.materials[std::size_t(o.surfaceMaterial)];
      copy.burnish.grooves = nullptr;
      d.materials.push_back(std::move(copy));
    }
    o.surfaceMaterial = it->second;
    warnings.push_back(o.where + ": the mesh has no texture coordinates (u, v): its brushed steel has no grooves");
  }
  return warnings;
}

void applyEdgeSelection(SceneDescription& d, const EdgeOverrides& e) {
  for (ObjectDescription& o : d.objects) {
    if (!o.wire || o.wire->wire.aggregate) continue;
    if (e.mode) o.wire->edges.mode = *e.mode;
    if (e.seams) o.wire->edges.seams = *e.seams;
    if (e.featureAngle) o.wire->edges.featureAngle = *e.featureAngle;
  }
}

bool parseHiddenMode(const std::string& name, HiddenLines::Mode& mode) {
  using M = HiddenLines::Mode;
  if (name == "off") mode = M::Off;
  else if (name == "dashed") mode = M::Dashed;
  else if (name == "ghost") mode = M::Ghost;
  else if (name == "hide") mode = M::Hide;
  else return false;
  return true;
}

}  // namespace wf

// Stage "tables" (render/pipeline.h): a shader slot per surface material and per wire, the
// shading tables of the map path (built once per material and lights, or taken from the frame
// cache, render/shading_cache.h), and the error estimates of those tables against the exact path.
#include "render/pipeline.h"

#include "render/shading_cache.h"
#include "shading/cylinder_lobe.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>

namespace wf {

namespace {

// Unit vectors spread evenly over the sphere (Fibonacci lattice): the test set of the error
// estimates.
std::vector<glm::dvec3> fibonacciSphere(int n) {
  std::vector<glm::dvec3> out;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (i + 0.5) * 2.0 / n, r = std::sqrt(std::max(0.0, 1.0 - z * z));
    out.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
  }
  return out;
}

double maxComponentDiff(const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 d = glm::abs(a - b);
  return std::max({d.x, d.y, d.z});
}

}  // namespace

void prepareShaders(PreparedScene& ps, const Scene& scene, const RenderOptions& o,
                    std::vector<int>& surfaceShader, std::vector<int>& wireShader,
                    RenderStats& st) {
  const auto t0 = std::chrono::steady_clock::now();
  const bool maps = o.shading == ShadingPath::Maps;
  const bool closed = o.shading == ShadingPath::Closed;
  // Closed path: one lobe table per exponent, shared by every wire and burnished material that
  // has it (they are independent of colours, lights and view).
  std::map<double, std::shared_ptr<const CylinderLobeTable>> lobeOf;
  auto lobeTable = [&](const PhongMaterial& m) {
    auto& t = lobeOf[m.exponent];
    if (!t) {
      bool built = true;
      if (o.shadingCache) t = o.shadingCache->lobe(m.exponent, built);
      else t = std::make_shared<const CylinderLobeTable>(m.exponent);
      if (built) ++st.lobeTables;
      else ++st.tablesReused;
    }
    return t;
  };
  ps.grid = std::make_unique<ViewGrid>(ps.view, maps ? o.viewGrid : 1);  // the grid is the map path's
  const ViewGrid& grid = *ps.grid;
  // Tables from the cache of the last frame where they match (RenderOptions::shadingCache), else
  // built here; the counts say which.
  auto wireTables = [&](const PhongMaterial& m) {
    std::shared_ptr<WireTables> t;
    bool built = true;
    if (o.shadingCache) t = o.shadingCache->wire(grid, m, ps.eyeLights, o.map, built);
    else t = std::make_shared<WireTables>(grid, m, ps.eyeLights, o.map);
    if (built) st.pseudoReflectanceMaps += t->mapsBuilt();
    else ++st.tablesReused;
    return t;
  };
  auto phongTables = [&](const PhongMaterial& m) {
    std::shared_ptr<SurfaceTables> t;
    bool built = true;
    if (o.shadingCache) t = o.shadingCache->phong(grid, o.sphereResolution, m, ps.eyeLights, built);
    else t = std::make_shared<SurfaceTables>(SurfaceTables::phong(grid, o.sphereResolution, m, ps.eyeLights));
    if (built) st.reflectanceSpheres += t->spheresBuilt();
    else ++st.tablesReused;
    return t;
  };
  std::map<int, std::shared_ptr<WireTables>> wireTablesOf;
  // Every table built, with the model it tabulates, for the error estimates below.
  std::vector<std::pair<const WireTables*, PhongMaterial>> wireChecks;
  struct SurfaceCheck {
    const SurfaceTables* tables;
    PhongMaterial phong;
    bool chrome;
    glm::dvec3 reflectance;
  };
  std::vector<SurfaceCheck> surfaceChecks;
  std::map<int, int> surfaceSlotOf;
  auto material = [&](int i) -> const Material& {
    return scene.materials[size_t(std::clamp(i, 0, int(scene.materials.size()) - 1))];
  };
  // The environment is made only when a chrome material needs it.
  auto env = [&]() -> const EnvironmentMap& { return scene.environment ? *scene.environment : defaultEnvironment(); };
  int holdoutSlot = -1;  // hold-outs share one slot, which needs no tables: they are never shaded
  // A triangle holds its slot in 16 bits (TrianglePrim::shader): refused before a slot past that
  // is made (and its tables built).
  auto roomForSurfaceSlot = [&] {
    if (ps.shaders.size() > std::numeric_limits<std::uint16_t>::max())
      throw std::length_error("more than 65,536 surface shader slots (materials, and the hold-out) in one render");
  };
  for (const SceneSurface& s : scene.surfaces) {
    if (s.mesh.triangles.empty()) {
      surfaceShader.push_back(0);
      continue;
    }
    if (s.holdout) {
      if (holdoutSlot < 0) {
        roomForSurfaceSlot();
        ShaderSlot slot;
        slot.holdout = true;
        slot.opacity = 1.0f;
        slot.material = &material(s.material);
        ps.shaders.push_back(slot);
        holdoutSlot = int(ps.shaders.size()) - 1;
      }
      surfaceShader.push_back(holdoutSlot);
      continue;
    }
    const int mi = std::clamp(s.material, 0, int(scene.materials.size()) - 1);
    auto it = surfaceSlotOf.find(mi);
    if (it == surfaceSlotOf.end()) {
      roomForSurfaceSlot();
      ShaderSlot slot;
      const Material& m = material(mi);
      const bool chrome = m.kind == Material::Kind::Chrome;
      const bool burnished = !chrome && m.burnish.active();
      slot.kind = chrome ? ShaderSlot::Kind::SurfaceChrome
                         : burnished ? ShaderSlot::Kind::SurfaceBurnished : ShaderSlot::Kind::SurfacePhong;
      slot.phong = m.phong.sanitized();
      slot.chromeReflectance = m.chromeReflectance;
      slot.opacity = safeOpacity(m.opacity);
      slot.material = &m;
      const Burnish::Grain grain = burnished ? m.burnish.grain : Burnish::Grain::None;
      const bool grainUV = grain == Burnish::Grain::U || grain == Burnish::Grain::V;
      const bool grooves = burnished && m.burnish.grooves;
      slot.needsUv = bool(m.colourMap) || bool(m.bumpMap) || grainUV;
      slot.needsDerivatives = bool(m.bumpMap) || grainUV;
      slot.variesInPixel = bool(m.colourMap) || bool(m.bumpMap) || grooves;
      slot.split = !chrome && bool(m.colourMap);
      if (grain == Burnish::Grain::Radial || grain == Burnish::Grain::Circular) {
        slot.axisPoint = ps.view.toEye(m.burnish.axisPoint);
        glm::dvec3 a = ps.view.eyeFromWorld * m.burnish.axisDirection;
        const double al = glm::length(a);
        slot.axisDirection = (al > 0 && std::isfinite(al)) ? a / al : glm::dvec3(0.0, 0.0, 1.0);
        if (!finite3(slot.axisPoint)) slot.axisPoint = glm::dvec3(0.0);
      }
      PhongMaterial diffusePart = slot.phong, specularPart = slot.phong;
      diffusePart.specular = glm::dvec3(0.0);
      specularPart.diffuse = glm::dvec3(0.0);
      if (closed && burnished) slot.lobe = lobeTable(slot.phong);
      if (maps && burnished) {
        // The burnished surface's cylinders share the pseudo-reflectance map of wires of the
        // same material (unless split into parts by a colour map).
        if (slot.split) {
          slot.wireTables = wireTables(diffusePart);
          slot.wireSpecular = wireTables(specularPart);
          wireChecks.push_back({slot.wireTables.get(), diffusePart});
          wireChecks.push_back({slot.wireSpecular.get(), specularPart});
        } else {
          auto wt = wireTablesOf.find(mi);
          if (wt == wireTablesOf.end()) {
            auto tables = wireTables(slot.phong);
            wt = wireTablesOf.emplace(mi, tables).first;
            wireChecks.push_back({tables.get(), slot.phong});
          }
          slot.wireTables = wt->second;
        }
      } else if (maps) {
        if (chrome) {
          bool built = true;
          if (o.shadingCache)
            slot.surfaceTables = o.shadingCache->chrome(
                grid, o.sphereResolution,
                scene.environment ? scene.environment
                                  : std::shared_ptr<const EnvironmentMap>(&defaultEnvironment(), [](const EnvironmentMap*) {}),
                slot.chromeReflectance, built);
          else
            slot.surfaceTables = std::make_shared<SurfaceTables>(
                SurfaceTables::chrome(grid, o.sphereResolution, env(), slot.chromeReflectance));
          if (built) st.reflectanceSpheres += slot.surfaceTables->spheresBuilt();
          else ++st.tablesReused;
        } else {
          slot.surfaceTables = phongTables(slot.split ? diffusePart : slot.phong);
          if (slot.split) slot.surfaceSpecular = phongTables(specularPart);
        }
        surfaceChecks.push_back({slot.surfaceTables.get(), slot.split ? diffusePart : slot.phong, chrome, slot.chromeReflectance});
        if (slot.surfaceSpecular) surfaceChecks.push_back({slot.surfaceSpecular.get(), specularPart, false, glm::dvec3(0.0)});
      }
      ps.shaders.push_back(slot);
      it = surfaceSlotOf.emplace(mi, int(ps.shaders.size()) - 1).first;
    }
    surfaceShader.push_back(it->second);
  }
  if (scene.wires.size() + ps.shaders.size() > kMaxShaders)
    throw std::length_error("more than " + std::to_string(kMaxShaders) + " wires in one render");
  for (const SceneWire& w : scene.wires) {
    ShaderSlot slot;
    const int mi = std::clamp(w.material, 0, int(scene.materials.size()) - 1);
    slot.phong = material(mi).phong.sanitized();
    slot.colour = safeColour(w.colour);
    slot.opacity = safeOpacity(w.opacity);
    slot.hidden = w.hidden;
    slot.restsOnSurface = w.restsOnSurface;
    slot.widthInPixels = w.thicknessInPixels;
    HiddenLines& h = slot.hidden;  // out-of-range values fall back to the defaults
    if (!(h.dash >= 0.1 && h.dash <= 1e4)) h.dash = HiddenLines{}.dash;
    if (!(h.gap >= 0.0 && h.gap <= 1e4)) h.gap = HiddenLines{}.gap;
    if (!(h.ghost >= 0.0f && h.ghost <= 1.0f)) h.ghost = HiddenLines{}.ghost;
    if (slot.hidden.drawn() && w.lines.points.size() >= 2) ps.anyXray = true;
    if (slot.restsOnSurface && w.lines.points.size() >= 2) ps.anyResting = true;
    slot.kind = w.style == WireStyle::Shaded  ? ShaderSlot::Kind::WireShaded
                : w.style == WireStyle::Plain ? ShaderSlot::Kind::WirePlain
                                              : ShaderSlot::Kind::WireDepthCued;
    if (closed && slot.kind == ShaderSlot::Kind::WireShaded && w.lines.points.size() >= 2) slot.lobe = lobeTable(slot.phong);
    if (maps && slot.kind == ShaderSlot::Kind::WireShaded && w.lines.points.size() >= 2) {
      auto it = wireTablesOf.find(mi);
      if (it == wireTablesOf.end()) {
        auto tables = wireTables(slot.phong);
        it = wireTablesOf.emplace(mi, tables).first;
        wireChecks.push_back({tables.get(), slot.phong});
      }
      slot.wireTables = it->second;
    }
    ps.shaders.push_back(slot);
    wireShader.push_back(int(ps.shaders.size()) - 1);
  }
  st.maps = secondsSince(t0);
  st.viewGrid = grid.size();

  // Closed path: the only approximation is the lobe table's factor G (at most 1, times c^2 A^n
  // <= 1 per light), so |closed - exact| <= its measured error x ks x the lights' sum.
  if (closed)
    for (const ShaderSlot& slot : ps.shaders)
      if (slot.lobe) st.lobeError = std::max(st.lobeError, lobeRadianceBound(*slot.lobe, slot.phong, ps.eyeLights));

  // Error estimates against the exact path at the true view vector: the tables alone at a node
  // (where a table is exact in direction), and the tables with the view-direction approximation
  // (the orthographic assumption for one node, interpolation between nodes otherwise) where it is
  // worst: the image corner for one node, the centre of the corner cell of the grid otherwise.
  if (!maps) return;
  const int n = grid.size();
  // A node (where the tables are exact in direction), and where the view approximation is worst:
  // the image corner (beyond the outer nodes) or the point between the first four nodes.
  const double nodeX = 0.5 * ps.view.width / n, nodeY = 0.5 * ps.view.height / n;
  auto viewAt = [&](double x, double y) { return ps.view.viewVector(ps.view.eyePoint(x, y, 1.0)); };
  const glm::dvec3 vNode = viewAt(nodeX, nodeY);
  const double worstPoints[2][2] = {{0.0, 0.0}, {n > 1 ? 2 * nodeX : 0.0, n > 1 ? 2 * nodeY : 0.0}};
  const bool perspective = ps.view.perspective;
  const std::vector<glm::dvec3> dirs = fibonacciSphere(192);
  for (const auto& [tables, m] : wireChecks) {
    for (size_t i = 0; i < dirs.size(); ++i) {
      st.mapError = std::max(st.mapError, maxComponentDiff(glm::dvec3(tables->lookup(dirs[i], nodeX, nodeY)),
                                                           cylinderRadianceClosed(dirs[i], vNode, m, ps.eyeLights)));
      if (perspective && i % 3 == 0)
        for (const auto& w : worstPoints)
          st.orthographicError = std::max(
              st.orthographicError, maxComponentDiff(glm::dvec3(tables->lookup(dirs[i], w[0], w[1])),
                                                     cylinderRadianceClosed(dirs[i], viewAt(w[0], w[1]), m, ps.eyeLights)));
    }
  }
  for (const SurfaceCheck& check : surfaceChecks) {
    const SurfaceTables* tables = check.tables;
    const PhongMaterial& m = check.phong;
    auto exactAt = [&](const glm::dvec3& nrm, const glm::dvec3& v) {
      return check.chrome ? chromeRadiance(env(), check.reflectance, nrm, v) : phongRadiance(nrm, v, m, ps.eyeLights);
    };
    for (const glm::dvec3& d : dirs) {
      // Normals facing the viewer at the node (and at the worst point, for the second estimate).
      glm::dvec3 nrm = glm::dot(d, vNode) < 0 ? -d : d;
      st.sphereError = std::max(st.sphereError, maxComponentDiff(glm::dvec3(tables->lookup(nrm, nodeX, nodeY)), exactAt(nrm, vNode)));
      if (perspective && !check.chrome)
        for (const auto& w : worstPoints) {
          const glm::dvec3 v = viewAt(w[0], w[1]);
          nrm = glm::dot(d, v) < 0 ? -d : d;
          st.orthographicError = std::max(st.orthographicError,
                                          maxComponentDiff(glm::dvec3(tables->lookup(nrm, w[0], w[1])), exactAt(nrm, v)));
        }
    }
  }
}

}  // namespace wf

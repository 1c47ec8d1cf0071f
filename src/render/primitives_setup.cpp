#include "render/primitives_setup.h"

#include "abuffer/screen_polygon.h"
#include "render/shading_cache.h"
#include "shading/cylinder_shading.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <numbers>

namespace wf {

template <class F>
void Scene::forEachPoint(F&& f) const {
  for (const SceneSurface& s : surfaces)
    for (const glm::uvec3& t : s.mesh.triangles)
      for (int k = 0; k < 3; ++k)
        if (t[k] < s.mesh.positions.size()) f(s.mesh.positions[t[k]]);
  for (const SceneWire& w : wires)
    for (const glm::dvec3& p : w.lines.points) f(p);
}

bool Scene::bounds(glm::dvec3& lo, glm::dvec3& hi) const {
  lo = glm::dvec3(1e300);
  hi = glm::dvec3(-1e300);
  bool any = false;
  forEachPoint([&](const glm::dvec3& p) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return;
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
    any = true;
  });
  return any;
}

bool Scene::boundingSphere(glm::dvec3& centre, double& radius) const {
  glm::dvec3 lo, hi;
  if (!bounds(lo, hi)) return false;
  centre = 0.5 * lo + 0.5 * hi;
  double r2 = 0;
  forEachPoint([&](const glm::dvec3& p) {
    const glm::dvec3 d = p - centre;
    const double q = glm::dot(d, d);
    if (std::isfinite(q)) r2 = std::max(r2, q);
  });
  radius = std::sqrt(r2);
  return true;
}

ScreenPolygon screenPolygonOf(const PreparedScene& ps, const Primitive& prim) {
  ScreenPolygon poly;
  poly.count = prim.vertexCount;
  for (int i = 0; i < prim.vertexCount; ++i) {
    poly.x[i] = ps.vertices[prim.firstVertex + i].x;
    poly.y[i] = ps.vertices[prim.firstVertex + i].y;
  }
  return poly;
}

size_t PreparedScene::bytes() const {
  size_t b = primitives.capacity() * sizeof(Primitive) + vertices.capacity() * sizeof(glm::dvec2) +
             triangles.capacity() * sizeof(TriangleAttributes) +
             segments.capacity() * sizeof(SegmentAttributes);
  for (const ShaderSlot& s : shaders) {
    if (s.wireTables) b += s.wireTables->bytes();
    if (s.surfaceTables) b += s.surfaceTables->bytes();
  }
  return b;
}

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

bool finite3(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Colours and opacities from the scene: NaN / Inf / negative would reach the image.
glm::vec3 safeColour(const glm::vec3& c) {
  auto f = [](float v) { return std::isfinite(v) ? std::max(v, 0.0f) : 0.0f; };
  return {f(c.x), f(c.y), f(c.z)};
}
float safeOpacity(float a) { return std::isfinite(a) ? std::clamp(a, 0.0f, 1.0f) : 1.0f; }

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

glm::dvec3 chromeRadiance(const EnvironmentMap& env, const glm::dvec3& refl, const glm::dvec3& n,
                          const glm::dvec3& v) {
  const glm::dvec3 r = 2.0 * glm::dot(n, v) * n - v;
  return refl * glm::dvec3(env.lookup(r));
}

const EnvironmentMap& defaultEnvironment() {
  static const EnvironmentMap env = EnvironmentMap::mountainScene(512);
  return env;
}

namespace {

// ---- camera, lights, shaders -------------------------------------------------------------

Camera chooseCamera(const Scene& scene, const RenderOptions& o, RenderStats& st) {
  glm::dvec3 centre;
  double sphereRadius = 0;
  const bool hasBounds = scene.boundingSphere(centre, sphereRadius);
  bool useScenes = scene.camera.has_value();
  if (useScenes) {
    const std::string problem = scene.camera->problem();
    if (!problem.empty()) {
      st.warnings.push_back("camera: " + problem + "; framed from the scene's bounds instead");
      useScenes = false;
    }
  }
  Camera c = useScenes ? *scene.camera
                       : (hasBounds ? frameSphere(centre, sphereRadius, double(o.width) / o.height)
                                    : Camera{});
  if (c.nearPlane > 0 && c.farPlane > 0) return c;
  // Near and far from the bounding sphere, as tight as the scene allows.
  const glm::dvec3 dir = glm::normalize(c.target - c.eye);
  double dmin = 1e-3, dmax = 1e3;
  if (hasBounds) {
    const double radius = std::max(sphereRadius, 1e-300);
    const double along = glm::dot(centre - c.eye, dir);
    dmax = along + radius * 1.01;
    dmin = std::max(along - radius * 1.01, dmax * 1e-6);
    if (!(dmax > 0)) dmax = 1.0, dmin = 1e-6;
  }
  if (c.nearPlane <= 0) c.nearPlane = dmin;
  if (c.farPlane <= 0) c.farPlane = std::max(dmax, c.nearPlane * 2);
  return c;
}

void prepareShaders(PreparedScene& ps, const Scene& scene, const RenderOptions& o,
                    std::vector<int>& surfaceShader, std::vector<int>& wireShader,
                    RenderStats& st) {
  const auto t0 = Clock::now();
  const bool maps = o.shading == ShadingPath::Maps;
  ps.grid = std::make_unique<ViewGrid>(ps.view, o.viewGrid);
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
  for (const SceneSurface& s : scene.surfaces) {
    if (s.mesh.triangles.empty()) {
      surfaceShader.push_back(0);
      continue;
    }
    const int mi = std::clamp(s.material, 0, int(scene.materials.size()) - 1);
    auto it = surfaceSlotOf.find(mi);
    if (it == surfaceSlotOf.end()) {
      ShaderSlot slot;
      const Material& m = material(mi);
      const bool chrome = m.kind == Material::Kind::Chrome;
      const bool burnished = !chrome && m.burnish.active();
      slot.kind = chrome ? ShaderSlot::Kind::SurfaceChrome
                         : burnished ? ShaderSlot::Kind::SurfaceBurnished : ShaderSlot::Kind::SurfacePhong;
      slot.phong = m.phong.sanitized();
      slot.chromeReflectance = m.chromeReflectance;
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
  for (const SceneWire& w : scene.wires) {
    ShaderSlot slot;
    const int mi = std::clamp(w.material, 0, int(scene.materials.size()) - 1);
    slot.phong = material(mi).phong.sanitized();
    slot.colour = safeColour(w.colour);
    slot.kind = w.style == WireStyle::Shaded  ? ShaderSlot::Kind::WireShaded
                : w.style == WireStyle::Plain ? ShaderSlot::Kind::WirePlain
                                              : ShaderSlot::Kind::WireDepthCued;
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
                                                           cylinderRadianceExact(dirs[i], vNode, m, ps.eyeLights, 1e-8)));
      if (perspective && i % 3 == 0)
        for (const auto& w : worstPoints)
          st.orthographicError = std::max(
              st.orthographicError, maxComponentDiff(glm::dvec3(tables->lookup(dirs[i], w[0], w[1])),
                                                     cylinderRadianceExact(dirs[i], viewAt(w[0], w[1]), m, ps.eyeLights, 1e-8)));
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

// ---- geometry ----------------------------------------------------------------------------

struct ChunkOut {
  std::vector<Primitive> prims;
  std::vector<glm::dvec2> verts;
  std::vector<TriangleAttributes> tris;
  std::vector<SegmentAttributes> segs;
  size_t triangles = 0, segments = 0, rejected = 0, zeroLength = 0, clipped = 0, endOn = 0;
};

// Intersection of the segment a-b with the plane depth = plane, computed from the endpoints in
// a canonical order so that the two triangles sharing an edge get the very same point.
glm::dvec3 depthIntersection(glm::dvec3 a, glm::dvec3 b, double plane) {
  if (b.x < a.x || (b.x == a.x && (b.y < a.y || (b.y == a.y && b.z < a.z)))) std::swap(a, b);
  const double t = (plane - (-a.z)) / ((-b.z) - (-a.z));
  return a + t * (b - a);
}

// Keeps the part of a convex eye-space polygon with depth >= plane (keepFar) or <= plane.
int clipDepth(const glm::dvec3* in, int n, glm::dvec3* out, double plane, bool keepFar) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const glm::dvec3 &a = in[i], &b = in[(i + 1) % n];
    const bool ia = keepFar ? -a.z >= plane : -a.z <= plane;
    const bool ib = keepFar ? -b.z >= plane : -b.z <= plane;
    if (ia) out[m++] = a;
    if (ia != ib) out[m++] = depthIntersection(a, b, plane);
  }
  return m;
}

bool finishPolygon(const ScreenPolygon& poly, const ViewTransform& view, Primitive& prim,
                   ChunkOut& out) {
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (int i = 0; i < poly.count; ++i) {
    x0 = std::min(x0, poly.x[i]);
    x1 = std::max(x1, poly.x[i]);
    y0 = std::min(y0, poly.y[i]);
    y1 = std::max(y1, poly.y[i]);
  }
  x0 = std::max(x0, 0.0);
  y0 = std::max(y0, 0.0);
  x1 = std::min(x1, double(view.width));
  y1 = std::min(y1, double(view.height));
  if (!(x1 > x0) || !(y1 > y0) || poly.count < 3 || !(poly.area() > 0)) return false;
  // Rounded outwards: a box shrunk by float rounding would drop a row of thin coverage.
  auto down = [](double v) { float f = float(v); return double(f) > v ? std::nextafter(f, -INFINITY) : f; };
  auto up = [](double v) { float f = float(v); return double(f) < v ? std::nextafter(f, INFINITY) : f; };
  prim.bbox[0] = down(x0);
  prim.bbox[1] = down(y0);
  prim.bbox[2] = up(x1);
  prim.bbox[3] = up(y1);
  prim.firstVertex = std::uint32_t(out.verts.size());
  prim.vertexCount = std::uint16_t(poly.count);
  for (int i = 0; i < poly.count; ++i) out.verts.emplace_back(poly.x[i], poly.y[i]);
  out.prims.push_back(prim);
  return true;
}

void setupTriangles(const PreparedScene& ps, const SceneSurface& surf, std::uint32_t surfaceIndex,
                    std::uint16_t shader, std::uint32_t tag, float opacity, size_t begin, size_t end,
                    ChunkOut& out) {
  const ViewTransform& view = ps.view;
  const TriangleMesh& mesh = surf.mesh;
  for (size_t t = begin; t < end; ++t) {
    const glm::uvec3 tri = mesh.triangles[t];
    if (tri.x >= mesh.positions.size() || tri.y >= mesh.positions.size() ||
        tri.z >= mesh.positions.size()) {
      ++out.rejected;
      continue;
    }
    glm::dvec3 e[3];
    bool ok = true;
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3& w = mesh.positions[tri[k]];
      ok = ok && finite3(w);
      e[k] = view.toEye(w);
    }
    if (!ok || !finite3(e[0]) || !finite3(e[1]) || !finite3(e[2])) {
      ++out.rejected;
      continue;
    }
    ++out.triangles;
    glm::dvec3 a[8], b[8];
    int n = clipDepth(e, 3, a, view.nearPlane, true);
    n = clipDepth(a, n, b, view.farPlane, false);
    if (n < 3) {
      ++out.clipped;
      continue;
    }
    ScreenPolygon poly;
    float zlo = 1e30f, zhi = 0;
    for (int k = 0; k < n; ++k) {
      const glm::dvec2 p = view.project(b[k]);
      poly.add(p.x, p.y);
      zlo = std::min(zlo, float(-b[k].z));
      zhi = std::max(zhi, float(-b[k].z));
    }
    poly.removeDuplicates();
    // Depth key plane from the eye-space plane n.P = k of the triangle.
    const glm::dvec3 e1 = e[1] - e[0], e2 = e[2] - e[0];
    const glm::dvec3 nrm = glm::cross(e1, e2);
    const double k = glm::dot(nrm, e[0]);
    Primitive prim;
    // Seen edge-on (the plane through the eye, or perpendicular to the screen): no area. The
    // test is relative, so that it means the same at any scale (1e-100 ... 1e100).
    const double nrmLength = glm::length(nrm);
    if (view.perspective) {
      if (!(std::abs(k) > 1e-14 * nrmLength * glm::length(e[0]))) {
        ++out.clipped;
        continue;
      }
      const double f = view.focal;
      prim.qa = nrm.x / (f * k);
      prim.qb = -nrm.y / (f * k);
      prim.qc = (-nrm.x * view.cx / f + nrm.y * view.cy / f - nrm.z) / k;
    } else {
      if (!(std::abs(nrm.z) > 1e-14 * nrmLength)) {
        ++out.clipped;
        continue;
      }
      const double s = view.orthoScale;
      prim.qa = nrm.x / (s * nrm.z);
      prim.qb = -nrm.y / (s * nrm.z);
      prim.qc = (-nrm.x * view.cx / s + nrm.y * view.cy / s - k) / nrm.z;
    }
    prim.zlo = zlo;
    prim.zhi = zhi;
    prim.tag = tag;
    prim.opacity = opacity;
    prim.isSegment = false;
    prim.attribute = std::uint32_t(out.tris.size());
    if (!finishPolygon(poly, view, prim, out)) {
      ++out.clipped;
      continue;
    }
    TriangleAttributes ta;
    ta.p0 = e[0];
    ta.e1 = e1;
    ta.e2 = e2;
    ta.d00 = glm::dot(e1, e1);
    ta.d01 = glm::dot(e1, e2);
    ta.d11 = glm::dot(e2, e2);
    const double den = ta.d00 * ta.d11 - ta.d01 * ta.d01;
    ta.invDen = den > 0 ? 1.0 / den : 0.0;
    ta.surface = surfaceIndex;
    ta.triangle = std::uint32_t(t);
    ta.shader = shader;
    out.tris.push_back(ta);
  }
}

// Screen-space state of one wire segment during set-up.
struct SegScreen {
  bool valid = false, endOn = false;
  bool clipped0 = false, clipped1 = false;
  glm::dvec3 e0, e1;      // eye space, after clipping
  glm::dvec2 p0, p1;      // screen
  double d0 = 0, d1 = 0;  // depths
  double w0 = 0, w1 = 0;  // half widths, pixels
  glm::dvec2 dir{0}, nrm{0};
  double length = 0;
  glm::dvec3 tangent{0};  // eye-space unit direction (unclipped)
};

void addStadium(const SegScreen& s, ScreenPolygon& poly) {
  // Hull of two 16-gon discs with the discs' exact areas (circumradius scaled up).
  constexpr int kSides = 16;
  const double scale = std::sqrt(std::numbers::pi / (0.5 * kSides * std::sin(2 * std::numbers::pi / kSides)));
  std::vector<glm::dvec2> pts;
  for (int end = 0; end < 2; ++end) {
    const glm::dvec2 c = end ? s.p1 : s.p0;
    const double r = (end ? s.w1 : s.w0) * scale;
    for (int i = 0; i < kSides; ++i) {
      const double a = 2 * std::numbers::pi * i / kSides;
      pts.emplace_back(c.x + r * std::cos(a), c.y + r * std::sin(a));
    }
  }
  std::sort(pts.begin(), pts.end(), [](const glm::dvec2& a, const glm::dvec2& b) {
    return a.x < b.x || (a.x == b.x && a.y < b.y);
  });
  std::vector<glm::dvec2> hull(2 * pts.size());
  size_t k = 0;
  auto cross = [](const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
  };
  for (size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  for (size_t i = pts.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], pts[i - 1]) <= 0) --k;
    hull[k++] = pts[i - 1];
  }
  poly.count = 0;
  for (size_t i = 0; i + 1 < k; ++i) poly.add(hull[i].x, hull[i].y);
}

// A half disc of radius r about c, bulging along `out`, from c + r side to c - r side (both
// included), appended to `poly`. As few edges as keep every chord within 0.05 pixel of the
// circle (2 ... 8), the inner vertices a little outside the circle so that the half polygon has
// the half disc's exact area, pi r^2 / 2; the two end vertices stay on the wire's sides, so the
// cap meets the body without a step.
void addHalfDisc(const glm::dvec2& c, const glm::dvec2& out, const glm::dvec2& side, double r, ScreenPolygon& poly) {
  constexpr int kMaxSides = 8;
  // Fan about c: 2 triangles with one vertex at r and one at s r, n - 2 with both at s r, each
  // of angle t = pi / n: (n - 2) s^2 sin t + 2 s sin t = pi / 2 ... solved for s, per n.
  static const std::array<double, kMaxSides + 1> kScale = [] {
    std::array<double, kMaxSides + 1> k{};
    for (int n = 2; n <= kMaxSides; ++n) {
      const double sn = std::sin(std::numbers::pi / n), a = (n - 2) * sn, b = 2 * sn;
      k[size_t(n)] = a > 0 ? (-b + std::sqrt(b * b + 4 * a * std::numbers::pi)) / (2 * a) : std::numbers::pi / b;
    }
    return k;
  }();
  // Sagitta of a chord of angle t: r (1 - cos(t / 2)) <= 0.05 px.
  int n = 2;
  while (n < kMaxSides && r * (1 - std::cos(std::numbers::pi / (2 * n))) > 0.05) ++n;
  const double inner = r * kScale[size_t(n)];
  for (int i = 0; i <= n; ++i) {
    const double ang = std::numbers::pi * i / n;
    const double k = (i == 0 || i == n) ? r : inner;
    const glm::dvec2 p = c + k * (std::cos(ang) * side + std::sin(ang) * out);
    poly.add(p.x, p.y);
  }
}

void setupPolylines(const PreparedScene& ps, const SceneWire& wire, std::uint16_t shader,
                    std::uint32_t tagBase, size_t begin, size_t end, ChunkOut& out) {
  const ViewTransform& view = ps.view;
  const PolylineSet& L = wire.lines;
  const ShaderSlot& slot = ps.shaders[shader];
  const bool hasColours = L.colours.size() == L.points.size();
  std::vector<SegScreen> segs;
  std::vector<size_t> ids;
  std::vector<glm::dvec2> offsets;
  std::vector<char> mitred;
  for (size_t li = begin; li < end; ++li) {
    const size_t a = L.starts[li], b = std::min<size_t>(L.starts[li + 1], L.points.size());
    // Repeated points make zero-length segments: drop them here, so that the segments on either
    // side still meet in a mitred joint.
    ids.clear();
    for (size_t k = a; k < b; ++k) {
      if (!ids.empty() && L.points[k] == L.points[ids.back()]) {
        ++out.zeroLength;
        continue;
      }
      ids.push_back(k);
    }
    if (ids.size() < 2) continue;
    const size_t nseg = ids.size() - 1;
    const bool closed = nseg > 1 && L.points[ids.front()] == L.points[ids.back()];
    segs.assign(nseg, SegScreen{});
    for (size_t j = 0; j < nseg; ++j) {
      SegScreen& s = segs[j];
      const glm::dvec3 &w0 = L.points[ids[j]], &w1 = L.points[ids[j + 1]];
      if (!finite3(w0) || !finite3(w1)) {
        ++out.rejected;
        continue;
      }
      glm::dvec3 e0 = view.toEye(w0), e1 = view.toEye(w1);
      if (!finite3(e0) || !finite3(e1) || e0 == e1) {
        ++out.zeroLength;
        continue;
      }
      ++out.segments;
      s.tangent = glm::normalize(e1 - e0);
      double d0 = -e0.z, d1 = -e1.z;
      const double nearP = view.nearPlane, farP = view.farPlane;
      if ((d0 < nearP && d1 < nearP) || (d0 > farP && d1 > farP)) {
        ++out.clipped;
        continue;
      }
      // Clip to [near, far] along the segment.
      auto clipEnd = [&](glm::dvec3& p, double& d, const glm::dvec3& q, double dq, bool& flag) {
        if (d < nearP) {
          p = p + (nearP - d) / (dq - d) * (q - p);
          d = nearP;
          flag = true;
        } else if (d > farP) {
          p = p + (farP - d) / (dq - d) * (q - p);
          d = farP;
          flag = true;
        }
      };
      const glm::dvec3 o0 = e0, o1 = e1;
      clipEnd(e0, d0, o1, d1, s.clipped0);
      clipEnd(e1, d1, o0, -o0.z, s.clipped1);
      s.e0 = e0;
      s.e1 = e1;
      s.d0 = d0;
      s.d1 = d1;
      s.p0 = view.project(e0);
      s.p1 = view.project(e1);
      const double halfT = 0.5 * wire.thickness;
      s.w0 = wire.thicknessInPixels ? halfT : halfT * view.pixelsPerWorld(d0);
      s.w1 = wire.thicknessInPixels ? halfT : halfT * view.pixelsPerWorld(d1);
      const glm::dvec2 dv = s.p1 - s.p0;
      s.length = glm::length(dv);
      if (!(std::isfinite(s.length)) || !(s.w0 > 0) || !(s.w1 > 0) || !std::isfinite(s.w0) ||
          !std::isfinite(s.w1)) {
        ++out.clipped;
        continue;
      }
      s.endOn = s.length < std::max(s.w0, s.w1);
      if (!s.endOn) {
        s.dir = dv / s.length;
        s.nrm = glm::dvec2(-s.dir.y, s.dir.x);
      }
      s.valid = true;
    }
    // Joint offsets: vertex j joins segment j-1 and j.
    offsets.assign(nseg + 1, glm::dvec2(0));
    mitred.assign(nseg + 1, 0);
    for (size_t j = 1; j < nseg; ++j) {
      const SegScreen &p = segs[j - 1], &q = segs[j];
      if (!p.valid || !q.valid || p.endOn || q.endOn || p.clipped1 || q.clipped0) continue;
      const glm::dvec2 m = p.nrm + q.nrm;
      const double ml = glm::length(m);
      if (!(ml > 1e-6)) continue;
      const glm::dvec2 mh = m / ml;
      const double c = glm::dot(mh, q.nrm);
      if (!(c > 1.0 / kMitreLimit)) continue;
      offsets[j] = mh * (q.w0 / c);
      mitred[j] = 1;
    }
    const std::uint32_t tag = tagBase + std::uint32_t(li);
    for (size_t j = 0; j < nseg; ++j) {
      const SegScreen& s = segs[j];
      if (!s.valid) continue;
      ScreenPolygon poly;
      if (s.endOn) {
        addStadium(s, poly);
        ++out.endOn;
      } else {
        glm::dvec2 o0 = mitred[j] ? offsets[j] : s.nrm * s.w0;
        glm::dvec2 o1 = mitred[j + 1] ? offsets[j + 1] : s.nrm * s.w1;
        // Round ends: a half disc at a free end of the polyline (not at a joint, not where the
        // near or far plane cut the segment).
        const bool cap0 = wire.roundEnds && j == 0 && !s.clipped0 && !closed;
        const bool cap1 = wire.roundEnds && j + 1 == nseg && !s.clipped1 && !closed;
        auto quad = [&](const glm::dvec2& u0, const glm::dvec2& u1) {
          // A free end is never mitred, so there u0 = nrm w0 and u1 = nrm w1: the caps run
          // between the same corners the square ends would have.
          poly.count = 0;
          if (cap0) addHalfDisc(s.p0, -s.dir, -s.nrm, s.w0, poly);  // from p0 - u0 round to p0 + u0
          else poly.add(s.p0.x + u0.x, s.p0.y + u0.y);
          if (cap1) {
            addHalfDisc(s.p1, s.dir, s.nrm, s.w1, poly);  // from p1 + u1 round to p1 - u1
          } else {
            poly.add(s.p1.x + u1.x, s.p1.y + u1.y);
            poly.add(s.p1.x - u1.x, s.p1.y - u1.y);
          }
          if (!cap0) poly.add(s.p0.x - u0.x, s.p0.y - u0.y);
        };
        quad(o0, o1);
        if (!isConvex(poly)) quad(s.nrm * s.w0, s.nrm * s.w1);  // a folding mitre: square ends
      }
      poly.removeDuplicates();
      Primitive prim;
      // The wire is drawn at its visible front, the cylinder's surface nearest the eye, one
      // radius in front of its axis: a wire lying on a surface (a CAD edge, a mesh's own edge)
      // then shows whole in front of it instead of tying with it pixel by pixel.
      const double f0 = std::max(view.nearPlane, s.d0 - s.w0 / view.pixelsPerWorld(s.d0));
      const double f1 = std::max(view.nearPlane, s.d1 - s.w1 / view.pixelsPerWorld(s.d1));
      const double k0 = view.depthKey(f0), k1 = view.depthKey(f1);
      if (s.length > 1e-12) {
        const glm::dvec2 u = (s.p1 - s.p0) / (s.length * s.length);
        prim.qa = (k1 - k0) * u.x;
        prim.qb = (k1 - k0) * u.y;
        prim.qc = k0 - prim.qa * s.p0.x - prim.qb * s.p0.y;
      } else {
        prim.qa = prim.qb = 0;
        prim.qc = view.perspective ? std::max(k0, k1) : std::min(k0, k1);
      }
      prim.zlo = float(std::min(f0, f1));
      prim.zhi = float(std::max(f0, f1));
      prim.tag = tag;
      prim.mayMerge = nseg > 1;  // a one-segment polyline (a straight hair) has nothing to merge with
      prim.opacity = safeOpacity(wire.opacity);
      prim.isSegment = true;
      prim.attribute = std::uint32_t(out.segs.size());
      SegmentAttributes sa;
      sa.p0 = s.e0;
      sa.p1 = s.e1;
      // Tangents at the ends: averaged with the neighbour at a joint, so a smooth curve of
      // straight segments shades smoothly, like one bent wire.
      auto jointTangent = [&](size_t jv, const glm::dvec3& own) {
        const SegScreen* other = nullptr;
        if (jv == j && j > 0) other = &segs[j - 1];
        if (jv == j + 1 && j + 1 < nseg) other = &segs[j + 1];
        if (!other || !other->valid) return own;
        const glm::dvec3 sum = own + other->tangent;
        const double l = glm::length(sum);
        return l > 1e-6 ? sum / l : own;
      };
      sa.t0 = jointTangent(j, s.tangent);
      sa.t1 = jointTangent(j + 1, s.tangent);
      sa.c0 = hasColours ? safeColour(L.colours[ids[j]]) : glm::vec3(1.0f);
      sa.c1 = hasColours ? safeColour(L.colours[ids[j + 1]]) : glm::vec3(1.0f);
      sa.r0 = float(s.w0 / view.pixelsPerWorld(s.d0));
      sa.r1 = float(s.w1 / view.pixelsPerWorld(s.d1));
      sa.shader = shader;
      if (sa.c0 == sa.c1) {
        if (slot.kind == ShaderSlot::Kind::WirePlain) {
          prim.constantColour = true;
          prim.colour = slot.colour * sa.c0;
        } else if (slot.kind == ShaderSlot::Kind::WireShaded && slot.wireTables && sa.t0 == sa.t1 &&
                   ps.grid->size() == 1) {
          prim.constantColour = true;  // one orthographic map: the tangent alone decides
          prim.colour = slot.wireTables->lookup(sa.t0, ps.view.cx, ps.view.cy) * sa.c0;
        }
      }
      if (!finishPolygon(poly, view, prim, out)) {
        ++out.clipped;
        continue;
      }
      out.segs.push_back(sa);
    }
  }
}

}  // namespace

PreparedScene prepareScene(const Scene& scene, const RenderOptions& o, RenderStats& st) {
  const auto t0 = Clock::now();
  PreparedScene ps;
  ps.scene = &scene;
  ps.path = o.shading;
  ps.filterTextures = o.filterTextures;
  const Camera camera = chooseCamera(scene, o, st);
  ps.view = ViewTransform::make(camera, o.width, o.height);
  ps.eyeLights = scene.lightsFollowCamera ? scene.lights.canonical()
                                          : scene.lights.transformed(ps.view.eyeFromWorld).canonical();

  std::vector<int> surfaceShader, wireShader;
  const auto tm = Clock::now();
  prepareShaders(ps, scene, o, surfaceShader, wireShader, st);
  const double mapSeconds = secondsSince(tm);

  // Depth-cue range: the wires' depths.
  double cn = 1e300, cf = -1e300;
  for (const SceneWire& w : scene.wires)
    if (w.style == WireStyle::DepthCued)
      for (const glm::dvec3& p : w.lines.points) {
        const double d = -ps.view.toEye(p).z;
        if (std::isfinite(d)) cn = std::min(cn, d), cf = std::max(cf, d);
      }
  ps.cueNear = std::max(cn, ps.view.nearPlane);
  ps.cueFar = std::min(cf, ps.view.farPlane);

  // Work items in a fixed order: chunks of triangles, then chunks of polylines.
  struct Job {
    bool wire;
    std::uint32_t object;
    size_t begin, end;
  };
  std::vector<Job> jobs;
  constexpr size_t kTriChunk = 4096, kLineChunk = 2048;
  for (size_t s = 0; s < scene.surfaces.size(); ++s)
    for (size_t b = 0; b < scene.surfaces[s].mesh.triangles.size(); b += kTriChunk)
      jobs.push_back({false, std::uint32_t(s), b, std::min(b + kTriChunk, scene.surfaces[s].mesh.triangles.size())});
  std::vector<std::uint32_t> tagBase(scene.wires.size());
  std::uint32_t nextTag = std::uint32_t(scene.surfaces.size()) + 1;
  for (size_t w = 0; w < scene.wires.size(); ++w) {
    tagBase[w] = nextTag;
    const size_t n = scene.wires[w].lines.polylineCount();
    nextTag += std::uint32_t(n);
    for (size_t b = 0; b < n; b += kLineChunk) jobs.push_back({true, std::uint32_t(w), b, std::min(b + kLineChunk, n)});
  }
  std::vector<ChunkOut> chunks(jobs.size());
  tbb::parallel_for(size_t(0), jobs.size(), [&](size_t i) {
    const Job& j = jobs[i];
    if (j.wire) {
      setupPolylines(ps, scene.wires[j.object], std::uint16_t(wireShader[j.object]), tagBase[j.object],
                     j.begin, j.end, chunks[i]);
    } else {
      const SceneSurface& s = scene.surfaces[j.object];
      const Material& m = scene.materials[size_t(std::clamp(s.material, 0, int(scene.materials.size()) - 1))];
      setupTriangles(ps, s, j.object, std::uint16_t(surfaceShader[j.object]), j.object + 1,
                     safeOpacity(m.opacity), j.begin, j.end, chunks[i]);
    }
  });
  // Concatenate in job order (deterministic whatever the thread count).
  std::vector<size_t> rejectedPerObject(scene.surfaces.size() + scene.wires.size(), 0);
  size_t np = 0, nv = 0, nt = 0, ns = 0;
  for (const ChunkOut& c : chunks) np += c.prims.size(), nv += c.verts.size(), nt += c.tris.size(), ns += c.segs.size();
  ps.primitives.reserve(np);
  ps.vertices.reserve(nv);
  ps.triangles.reserve(nt);
  ps.segments.reserve(ns);
  for (size_t i = 0; i < chunks.size(); ++i) {
    ChunkOut& c = chunks[i];
    const std::uint32_t v0 = std::uint32_t(ps.vertices.size());
    const std::uint32_t a0 = std::uint32_t(jobs[i].wire ? ps.segments.size() : ps.triangles.size());
    for (Primitive p : c.prims) {
      p.firstVertex += v0;
      p.attribute += a0;
      ps.primitives.push_back(p);
    }
    ps.vertices.insert(ps.vertices.end(), c.verts.begin(), c.verts.end());
    ps.triangles.insert(ps.triangles.end(), c.tris.begin(), c.tris.end());
    ps.segments.insert(ps.segments.end(), c.segs.begin(), c.segs.end());
    st.triangles += c.triangles;
    st.segments += c.segments;
    st.rejectedNonFinite += c.rejected;
    st.droppedZeroLength += c.zeroLength;
    st.clippedAway += c.clipped;
    st.endOnDiscs += c.endOn;
    rejectedPerObject[jobs[i].wire ? scene.surfaces.size() + jobs[i].object : jobs[i].object] += c.rejected;
    c = ChunkOut{};
  }
  for (size_t i = 0; i < rejectedPerObject.size(); ++i) {
    if (!rejectedPerObject[i]) continue;
    const bool wire = i >= scene.surfaces.size();
    const std::string name = wire ? scene.wires[i - scene.surfaces.size()].name : scene.surfaces[i].name;
    st.warnings.push_back((wire ? "wire '" : "surface '") + name + "': " +
                          std::to_string(rejectedPerObject[i]) +
                          (wire ? " segments" : " triangles") +
                          " with non-finite (NaN/Inf) or missing vertices skipped");
  }
  st.primitives = ps.primitives.size();
  st.setup = secondsSince(t0) - mapSeconds;
  return ps;
}

TileBins binPrimitives(const PreparedScene& ps, int tileSize, RenderStats& st) {
  const auto t0 = Clock::now();
  TileBins bins;
  bins.tilesX = (ps.view.width + tileSize - 1) / tileSize;
  bins.tilesY = (ps.view.height + tileSize - 1) / tileSize;
  const size_t tiles = size_t(bins.tilesX) * size_t(bins.tilesY);
  bins.offsets.assign(tiles + 1, 0);
  auto range = [&](const Primitive& p, int& tx0, int& ty0, int& tx1, int& ty1) {
    tx0 = std::clamp(int(std::floor(p.bbox[0])) / tileSize, 0, bins.tilesX - 1);
    ty0 = std::clamp(int(std::floor(p.bbox[1])) / tileSize, 0, bins.tilesY - 1);
    tx1 = std::clamp((int(std::ceil(p.bbox[2])) - 1) / tileSize, 0, bins.tilesX - 1);
    ty1 = std::clamp((int(std::ceil(p.bbox[3])) - 1) / tileSize, 0, bins.tilesY - 1);
  };
  for (const Primitive& p : ps.primitives) {
    int a, b, c, d;
    range(p, a, b, c, d);
    for (int ty = b; ty <= d; ++ty)
      for (int tx = a; tx <= c; ++tx) ++bins.offsets[size_t(ty) * bins.tilesX + tx + 1];
  }
  for (size_t t = 0; t < tiles; ++t) bins.offsets[t + 1] += bins.offsets[t];
  bins.items.resize(bins.offsets[tiles]);
  std::vector<std::uint32_t> fill(bins.offsets.begin(), bins.offsets.end() - 1);
  for (size_t i = 0; i < ps.primitives.size(); ++i) {
    const Primitive& p = ps.primitives[i];
    int a, b, c, d;
    range(p, a, b, c, d);
    for (int ty = b; ty <= d; ++ty)
      for (int tx = a; tx <= c; ++tx) {
        const int ox = tx * tileSize, oy = ty * tileSize;
        const int w = std::min(tileSize, ps.view.width - ox), h = std::min(tileSize, ps.view.height - oy);
        TileBins::Item item;
        item.zlo = p.zlo;
        item.index = std::uint32_t(i);
        item.firstVertex = p.firstVertex;
        item.x0 = std::int16_t(std::clamp(int(p.bbox[0]) - ox, 0, w - 1));
        item.y0 = std::int16_t(std::clamp(int(p.bbox[1]) - oy, 0, h - 1));
        item.x1 = std::int16_t(std::clamp(int(p.bbox[2]) - ox, 0, w - 1));
        item.y1 = std::int16_t(std::clamp(int(p.bbox[3]) - oy, 0, h - 1));
        bins.items[fill[size_t(ty) * bins.tilesX + tx]++] = item;
      }
  }
  st.tiles = tiles;
  st.tilesEmpty = 0;
  for (size_t t = 0; t < tiles; ++t) st.tilesEmpty += bins.offsets[t] == bins.offsets[t + 1];
  st.binning = secondsSince(t0);
  return bins;
}

namespace {
// Unclamped barycentrics of eye point P on the triangle's plane.
glm::dvec3 barycentricOf(const TriangleAttributes& ta, const glm::dvec3& P) {
  const glm::dvec3 v = P - ta.p0;
  const double d20 = glm::dot(v, ta.e1), d21 = glm::dot(v, ta.e2);
  const double b1 = (ta.d11 * d20 - ta.d01 * d21) * ta.invDen;
  const double b2 = (ta.d00 * d21 - ta.d01 * d20) * ta.invDen;
  return {1.0 - b1 - b2, b1, b2};
}

// World-space dP/du, dP/dv of a triangle from its positions and (u, v) (zero when the (u, v)
// are degenerate).
void triangleUvGradient(const TriangleMesh& mesh, const glm::uvec3& tri, glm::dvec3& du, glm::dvec3& dv) {
  const glm::dvec3 e1 = mesh.positions[tri.y] - mesh.positions[tri.x];
  const glm::dvec3 e2 = mesh.positions[tri.z] - mesh.positions[tri.x];
  const glm::dvec2 t1 = mesh.uvs[tri.y] - mesh.uvs[tri.x], t2 = mesh.uvs[tri.z] - mesh.uvs[tri.x];
  const double det = t1.x * t2.y - t2.x * t1.y;
  if (!(std::abs(det) > 0) || !std::isfinite(det)) {
    du = dv = glm::dvec3(0.0);
    return;
  }
  du = (e1 * t2.y - e2 * t1.y) / det;
  dv = (e2 * t1.x - e1 * t2.x) / det;
  if (!std::isfinite(glm::dot(du, du)) || !std::isfinite(glm::dot(dv, dv))) du = dv = glm::dvec3(0.0);
}

glm::dvec3 finiteOrZero(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) ? v : glm::dvec3(0.0);
}

template <class V>
bool finiteVec(const V& v) {
  for (int k = 0; k < V::length(); ++k)
    if (!std::isfinite(double(v[k]))) return false;
  return true;
}

// b0 a + b1 b + b2 c over the vertices whose value is finite, weights renormalised (a vertex
// with a NaN attribute must not spoil the whole triangle: 0 x NaN is NaN); the plain mean of the
// finite ones where their weights vanish; false when no vertex is finite.
template <class V>
bool mixFinite(const V& a, const V& b, const V& c, double b0, double b1, double b2, V& out) {
  // The per-fragment path: one check of the mix (a NaN or Inf vertex makes it non-finite even
  // at weight 0, since 0 x NaN and 0 x Inf are NaN); the vertices are examined only then.
  out = b0 * a + b1 * b + b2 * c;
  if (finiteVec(out)) return true;
  const bool fa = finiteVec(a), fb = finiteVec(b), fc = finiteVec(c);
  if (!fa && !fb && !fc) return false;
  double w0 = fa ? b0 : 0.0, w1 = fb ? b1 : 0.0, w2 = fc ? b2 : 0.0;
  double ws = w0 + w1 + w2;
  if (!(ws > 0)) w0 = fa, w1 = fb, w2 = fc, ws = w0 + w1 + w2;
  out = (w0 / ws) * (fa ? a : V(0.0)) + (w1 / ws) * (fb ? b : V(0.0)) + (w2 / ws) * (fc ? c : V(0.0));
  return finiteVec(out);
}
}  // namespace

glm::dvec2 uvOnPlane(const PreparedScene& ps, const TriangleAttributes& ta, const glm::dvec3& P) {
  const TriangleMesh& mesh = ps.scene->surfaces[ta.surface].mesh;
  if (mesh.uvs.size() != mesh.positions.size()) return glm::dvec2(0.0);
  const glm::uvec3 tri = mesh.triangles[ta.triangle];
  const glm::dvec3 b = barycentricOf(ta, P);
  const glm::dvec2 uv = b.x * mesh.uvs[tri.x] + b.y * mesh.uvs[tri.y] + b.z * mesh.uvs[tri.z];
  // Not finite (a NaN uv, or beyond double range): an unbounded footprint, which the textures
  // read as their mean.
  return std::isfinite(uv.x) && std::isfinite(uv.y) ? uv : glm::dvec2(INFINITY);
}

SurfaceSample interpolateTriangle(const PreparedScene& ps, const TriangleAttributes& ta, const glm::dvec3& P,
                                  const glm::dvec3& V, bool tangentAndUv, bool derivatives) {
  // Barycentrics of the eye-space point P (on the triangle's plane under the fragment), clamped
  // into the triangle: perspective-correct by construction.
  const glm::dvec3 bu = barycentricOf(ta, P);
  double b0 = std::max(bu.x, 0.0), b1 = std::max(bu.y, 0.0), b2 = std::max(bu.z, 0.0);
  const double bs = b0 + b1 + b2;
  if (bs > 0 && std::isfinite(bs)) b0 /= bs, b1 /= bs, b2 /= bs;
  else b0 = 1, b1 = b2 = 0;
  const TriangleMesh& mesh = ps.scene->surfaces[ta.surface].mesh;
  const glm::uvec3 tri = mesh.triangles[ta.triangle];
  const size_t nv = mesh.positions.size();
  SurfaceSample out;
  out.barycentric = glm::dvec3(b0, b1, b2);
  auto mix3 = [&](const auto& a, const auto& b, const auto& c) { return b0 * a + b1 * b + b2 * c; };
  glm::dvec3 N = glm::cross(ta.e1, ta.e2);  // the face normal, unless the mesh has usable vertex normals
  if (glm::dvec3 n; mesh.normals.size() == nv &&
                    mixFinite(mesh.normals[tri.x], mesh.normals[tri.y], mesh.normals[tri.z], b0, b1, b2, n) &&
                    glm::dot(n, n) > 0)
    N = ps.view.eyeFromWorld * n;
  const double nl = glm::length(N);
  N = (nl > 0 && std::isfinite(nl)) ? N / nl : V;
  if (glm::dot(N, V) < 0) N = -N, out.flipped = true;  // two-sided: the side facing the viewer
  out.normal = N;
  if (tangentAndUv && mesh.tangents.size() == nv) {
    glm::dvec3 T(0.0);
    if (mixFinite(mesh.tangents[tri.x], mesh.tangents[tri.y], mesh.tangents[tri.z], b0, b1, b2, T)) T = ps.view.eyeFromWorld * T;
    const double tl = glm::length(T);
    out.tangent = (tl > 0 && std::isfinite(tl)) ? T / tl : glm::dvec3(0.0);
  }
  if (tangentAndUv && mesh.uvs.size() == nv && !mixFinite(mesh.uvs[tri.x], mesh.uvs[tri.y], mesh.uvs[tri.z], b0, b1, b2, out.uv))
    out.uv = glm::dvec2(0.0);
  if (derivatives) {
    // The mesh's own derivatives when all three vertices have finite ones; else the triangle's
    // (u, v) gradient; else its tangents for dS/du.
    glm::dvec3 du(0.0), dv(0.0);
    auto allFinite = [&](const std::vector<glm::dvec3>& a) {
      return a.size() == nv && finiteVec(a[tri.x]) && finiteVec(a[tri.y]) && finiteVec(a[tri.z]);
    };
    if (allFinite(mesh.derivU) && allFinite(mesh.derivV)) {
      du = mix3(mesh.derivU[tri.x], mesh.derivU[tri.y], mesh.derivU[tri.z]);
      dv = mix3(mesh.derivV[tri.x], mesh.derivV[tri.y], mesh.derivV[tri.z]);
    } else if (mesh.uvs.size() == nv) {
      triangleUvGradient(mesh, tri, du, dv);
    }
    if (glm::dot(du, du) == 0 && glm::dot(dv, dv) == 0 && mesh.tangents.size() == nv)
      mixFinite(mesh.tangents[tri.x], mesh.tangents[tri.y], mesh.tangents[tri.z], b0, b1, b2, du);
    out.derivU = finiteOrZero(ps.view.eyeFromWorld * du);
    out.derivV = finiteOrZero(ps.view.eyeFromWorld * dv);
  }
  if (mesh.colours.size() == nv)
    out.colour = safeColour(mesh.colours[tri.x] * float(b0) + mesh.colours[tri.y] * float(b1) + mesh.colours[tri.z] * float(b2));
  return out;
}

SurfaceSample interpolateSurface(const PreparedScene& ps, const Primitive& prim, double x, double y) {
  if (prim.isSegment) return {};
  const double depth = ps.view.depthFromKey(prim.depthKeyAt(x, y));
  const glm::dvec3 P = ps.view.eyePoint(x, y, depth);
  return interpolateTriangle(ps, ps.triangles[prim.attribute], P, ps.view.viewVector(P), true);
}

glm::vec3 shadeFragment(const PreparedScene& ps, const Primitive& prim, double x, double y,
                        double depth) {
  if (prim.constantColour) return prim.colour;
  const ViewTransform& view = ps.view;
  const glm::dvec3 P = view.eyePoint(x, y, depth);
  const glm::dvec3 V = view.viewVector(P);
  if (prim.isSegment) {
    const SegmentAttributes& sa = ps.segments[prim.attribute];
    const ShaderSlot& slot = ps.shaders[sa.shader];
    const glm::dvec3 d = sa.p1 - sa.p0;
    const double dd = glm::dot(d, d);
    const double s = dd > 0 ? std::clamp(glm::dot(P - sa.p0, d) / dd, 0.0, 1.0) : 0.0;
    const glm::vec3 c = glm::mix(sa.c0, sa.c1, float(s));
    switch (slot.kind) {
      case ShaderSlot::Kind::WirePlain:
        return slot.colour * c;
      case ShaderSlot::Kind::WireDepthCued: {
        // The paper's baseline (§3): lines dimmer as they recede, full at the nearest wire
        // depth, 10% at the farthest.
        const double range = ps.cueFar - ps.cueNear;
        const double t = range > 0 ? std::clamp((depth - ps.cueNear) / range, 0.0, 1.0) : 0.0;
        return slot.colour * c * float(1.0 - 0.9 * t);
      }
      default: {
        glm::dvec3 T = glm::mix(sa.t0, sa.t1, s);
        if (ps.path == ShadingPath::Maps && slot.wireTables) return slot.wireTables->lookup(T, x, y) * c;
        return glm::vec3(cylinderRadianceExact(T, V, slot.phong, ps.eyeLights, 1e-8)) * c;
      }
    }
  }
  return shadeSurfaceFragment(ps, prim, x, y, P, V);
}

}  // namespace wf

// buildScene (scene/scene_description.h): a description into the renderer's wf::Scene.
#include "scene/scene_description.h"
#include "surface/mesh_edges.h"

#include "core/timer.h"

#include "surface/mesh_surface.h"
#include "surface/transformed_surface.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <sstream>

namespace wf {

namespace {

/// Appends b's triangles and vertex arrays to a (an array present in one and not the other is
/// dropped: the scales of several faces all carry the same arrays).
void appendMesh(TriangleMesh& a, const TriangleMesh& b) {
  const std::uint32_t base = std::uint32_t(a.positions.size());
  const bool first = a.positions.empty();
  auto join = [&](auto& x, const auto& y) {
    if (first || x.size() == a.positions.size()) x.insert(x.end(), y.begin(), y.end());
  };
  join(a.normals, b.normals);
  join(a.tangents, b.tangents);
  join(a.derivU, b.derivU);
  join(a.derivV, b.derivV);
  join(a.uvs, b.uvs);
  join(a.colours, b.colours);
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  for (const glm::uvec3& t : b.triangles) a.triangles.push_back(t + glm::uvec3(base));
  const size_t n = a.positions.size();
  for (auto* v : {&a.normals, &a.tangents, &a.derivU, &a.derivV})
    if (v->size() != n) v->clear();
  if (a.uvs.size() != n) a.uvs.clear();
  if (a.colours.size() != n) a.colours.clear();
}

/// Cells of about `size` world units over a surface: its mean extent along u and along v (|Su| du
/// and |Sv| dv over a 9 x 9 grid of its valid points) divided by the size.
void cellsOfSize(const Surface& surface, double size, int& cellsU, int& cellsV) {
  const ParameterDomain dom = surface.domain();
  double lu = 0.0, lv = 0.0;
  int n = 0;
  for (int j = 0; j < 9; ++j)
    for (int i = 0; i < 9; ++i) {
      const glm::dvec2 uv = dom.fromUnit((i + 0.5) / 9.0, (j + 0.5) / 9.0);
      const SurfacePoint p = surface.evaluate(uv.x, uv.y);
      const double a = glm::length(p.Su) * std::abs(dom.du()), b = glm::length(p.Sv) * std::abs(dom.dv());
      if (!std::isfinite(p.P.x) || !std::isfinite(a) || !std::isfinite(b)) continue;
      lu += a, lv += b, ++n;
    }
  auto cells = [&](double length) { return n ? int(std::clamp(std::round(length / n / size), 1.0, 4096.0)) : 1; };
  cellsU = cells(lu);
  cellsV = cells(lv);
}

/// dS/du and dS/dv for burnish grain on a mesh that has none (a mesh file): from its texture
/// coordinates when it has them (each triangle's affine dP/du, dP/dv, area-weighted at the
/// vertices), else, and where those vanish, the up axis (+z, or +x where the normal is near z)
/// projected onto the tangent plane and N x that.
void fillGrainFrame(TriangleMesh& m) {
  if (m.derivU.size() == m.positions.size() && m.derivV.size() == m.positions.size()) return;
  std::vector<glm::dvec3> su(m.positions.size(), glm::dvec3(0.0)), sv(m.positions.size(), glm::dvec3(0.0));
  if (m.uvs.size() == m.positions.size())
    for (const glm::uvec3& t : m.triangles) {
      if (t.x >= m.positions.size() || t.y >= m.positions.size() || t.z >= m.positions.size()) continue;
      const glm::dvec2 d1 = m.uvs[t.y] - m.uvs[t.x], d2 = m.uvs[t.z] - m.uvs[t.x];
      const double det = d1.x * d2.y - d2.x * d1.y;
      if (!(std::abs(det) > 0.0)) continue;
      const glm::dvec3 e1 = m.positions[t.y] - m.positions[t.x], e2 = m.positions[t.z] - m.positions[t.x];
      // [Su Sv] = [e1 e2] [d1 d2]^-1, weighted by the triangle's area (|e1 x e2| / 2).
      const double area = glm::length(glm::cross(e1, e2));
      const glm::dvec3 a = (e1 * d2.y - e2 * d1.y) / det, b = (e2 * d1.x - e1 * d2.x) / det;
      const double la = glm::length(a), lb = glm::length(b);
      if (!(la > 0.0) || !(lb > 0.0) || !std::isfinite(la + lb + area)) continue;
      for (std::uint32_t v : {t.x, t.y, t.z}) su[v] += area * a / la, sv[v] += area * b / lb;
    }
  std::vector<glm::dvec3> normals = m.normals;
  if (normals.size() != m.positions.size()) {
    normals.assign(m.positions.size(), glm::dvec3(0.0));
    for (const glm::uvec3& t : m.triangles) {
      if (t.x >= m.positions.size() || t.y >= m.positions.size() || t.z >= m.positions.size()) continue;
      const glm::dvec3 c = glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
      if (!std::isfinite(c.x + c.y + c.z)) continue;
      normals[t.x] += c, normals[t.y] += c, normals[t.z] += c;
    }
  }
  m.derivU.resize(m.positions.size());
  m.derivV.resize(m.positions.size());
  for (size_t i = 0; i < m.positions.size(); ++i) {
    const double len = glm::length(normals[i]);
    const glm::dvec3 n = len > 0 && std::isfinite(len) ? normals[i] / len : glm::dvec3(0, 0, 1);
    const glm::dvec3 t = su[i] - glm::dot(su[i], n) * n;
    if (glm::length(t) > 1e-12 * glm::length(su[i]) && glm::length(t) > 0.0) {
      m.derivU[i] = glm::normalize(t);
      m.derivV[i] = glm::cross(n, m.derivU[i]);
      continue;
    }
    const glm::dvec3 up = std::abs(n.z) > 0.999 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 0, 1);
    m.derivU[i] = glm::normalize(up - glm::dot(up, n) * n);
    m.derivV[i] = glm::cross(n, m.derivU[i]);
  }
}

/// The scene's primitive count against the description's bound, checked before each is made.
struct Budget {
  double limit;
  double used = 0.0;
  void add(const std::string& where, double count, const std::string& what) {
    if (!(count >= 0.0) || !(used + count <= limit)) {
      std::ostringstream m;
      m.precision(3);
      m << what << " would make about " << (std::isfinite(count) ? count : 1e300) << " primitives, and the scene "
        << used << " before it: more than the " << limit
        << " one scene may make (lower the resolution, grid, density or segments)";
      throw SceneError(where, m.str());
    }
    used += count;
  }
  double left() const { return std::max(0.0, limit - used); }
};

/// A product of two maps over the unit square (a user's density map on a trimmed face).
class ProductMap final : public ScalarTexture {
 public:
  ProductMap(std::shared_ptr<const ScalarTexture> a, std::shared_ptr<const ScalarTexture> b) : a_(std::move(a)), b_(std::move(b)) {}
  double value(const glm::dvec2& st) const override { return a_->value(st) * b_->value(st); }
  glm::dvec2 gradient(const glm::dvec2& st) const override {
    return a_->gradient(st) * b_->value(st) + a_->value(st) * b_->gradient(st);
  }
  std::string describe() const override { return a_->describe() + " x " + b_->describe(); }

 private:
  std::shared_ptr<const ScalarTexture> a_, b_;
};

std::shared_ptr<const ScalarTexture> both(std::shared_ptr<const ScalarTexture> a, std::shared_ptr<const ScalarTexture> b) {
  if (!a) return b;
  if (!b) return a;
  return std::make_shared<ProductMap>(std::move(a), std::move(b));
}

/// A surface fur and scales grow on, with the identity its hairs take and where it is.
struct GrowthPatch {
  std::shared_ptr<const Surface> surface;
  std::shared_ptr<const ScalarTexture> inside;  ///< trimming (CAD faces), or null
  std::uint32_t id = 0;
};

/// The parts of a CAD model's tessellation, one mesh each (vertices renumbered).
std::vector<TriangleMesh> splitParts(const TriangleMesh& all, const std::vector<int>& trianglePart, size_t parts) {
  std::vector<TriangleMesh> meshes(parts);
  std::vector<std::vector<std::uint32_t>> remap(parts);
  for (size_t t = 0; t < all.triangles.size(); ++t) {
    const size_t p = std::min(parts - 1, size_t(std::max(0, t < trianglePart.size() ? trianglePart[t] : 0)));
    TriangleMesh& m = meshes[p];
    std::vector<std::uint32_t>& r = remap[p];
    if (r.empty()) r.assign(all.positions.size(), ~0u);
    glm::uvec3 tri;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = all.triangles[t][k];
      if (r[v] == ~0u) {
        r[v] = std::uint32_t(m.positions.size());
        m.positions.push_back(all.positions[v]);
        if (v < all.normals.size()) m.normals.push_back(all.normals[v]);
        if (v < all.tangents.size()) m.tangents.push_back(all.tangents[v]);
        if (v < all.derivU.size()) m.derivU.push_back(all.derivU[v]);
        if (v < all.derivV.size()) m.derivV.push_back(all.derivV[v]);
        if (v < all.uvs.size()) m.uvs.push_back(all.uvs[v]);
        if (v < all.colours.size()) m.colours.push_back(all.colours[v]);
      }
      tri[k] = r[v];
    }
    m.triangles.push_back(tri);
  }
  return meshes;
}

// A CAD model's lines as a wire: its B-rep edges that the selection keeps, each with its class,
// then whatever follows them in `lines` (iso lines drawn with the edges), of class IsoLine.
void selectEdges(const GeometryData& g, const PolylineSet& lines, const EdgeSelection& selection, SceneWire& w) {
  const std::size_t edges = g.lines.polylineCount();
  const bool classified = g.lineClasses.size() == edges && g.lineAngles.size() == edges;
  for (std::size_t k = 0; k < lines.polylineCount(); ++k) {
    const bool edge = k < edges && classified;
    if (edge && !selection.keeps(g.lineClasses[k], g.lineAngles[k])) continue;
    const EdgeClass c = !classified ? EdgeClass::Free  // (not stored: no classes at all)
                        : k >= edges ? EdgeClass::IsoLine
                        : g.lineClasses[k] == EdgeClass::Sharp || g.lineClasses[k] == EdgeClass::Smooth
                            ? EdgeSelection::byAngle(g.lineAngles[k], selection.featureAngle)
                            : g.lineClasses[k];
    if (w.lines.starts.empty()) w.lines.starts.push_back(0);
    w.lines.points.insert(w.lines.points.end(), lines.points.begin() + lines.starts[k], lines.points.begin() + lines.starts[k + 1]);
    w.lines.starts.push_back(std::uint32_t(w.lines.points.size()));
    if (classified) w.edgeClasses.push_back(c);
  }
}

void buildObject(const SceneDescription& d, const ObjectDescription& o, std::uint32_t index, Budget& budget, BuiltScene& out) {
  Scene& scene = out.scene;
  const bool isSource = o.source.has_value();
  if (isSource == bool(o.geometry)) throw SceneError(o.where, "an object needs exactly one of source and file");
  const bool isCad = !isSource && o.geometry->cad;
  const std::string& name = o.name.empty() ? o.where : o.name;
  const WireDescription::From wireFrom =
      !o.wire ? WireDescription::From::Default
              : o.wire->from != WireDescription::From::Default
                    ? o.wire->from
                    : isSource ? WireDescription::From::Isolines
                               : (o.geometry->lines.points.empty() && o.geometry->isoLines.points.empty()
                                      ? WireDescription::From::Edges
                                      : WireDescription::From::Lines);

  TriangleMesh mesh;
  PolylineSet fileLines;
  std::optional<SceneWire> isoWire;
  if (isSource) {
    // Tessellated only when something draws the polygons: a surface, or a wire of its edges
    // (fur and isolines work on the surface itself).
    if (o.drawSurface || (o.wire && wireFrom == WireDescription::From::Edges)) {
      budget.add(o.sourceWhere, 2.0 * o.source->resolutionU * o.source->resolutionV, "this tessellation");
      mesh = tessellate(*o.source);
    }
  } else {
    const GeometryData& g = *o.geometry;
    // The polygons are copied only where they are drawn, make the edges of a mesh's wire, or
    // are what fur and scales grow on (a CAD model grows on its exact faces).
    const bool drawn = o.drawSurface && !g.mesh.triangles.empty();
    if (isCad && drawn) budget.add(o.fileWhere, double(g.mesh.triangles.size()), "this CAD tessellation");
    if (drawn || (o.wire && wireFrom == WireDescription::From::Edges && !isCad) || ((o.fur || o.scales) && g.faces.empty()))
      mesh = g.mesh;
    if (!o.keepColours) mesh.colours.clear();
    // A CAD model's lines: its edges, then the iso lines asked for (unless drawn apart).
    fileLines = g.lines;
    if (o.isoLineWire && !g.isoLines.points.empty()) {
      SceneWire iso = *o.isoLineWire;
      iso.name = "iso lines";
      iso.lines = g.isoLines;
      budget.add(o.fileWhere, double(iso.lines.points.size() - iso.lines.polylineCount()), "these iso lines");
      transformPolylines(iso.lines, o.transform);
      isoWire = std::move(iso);
    }
    for (size_t k = 0; !o.isoLineWire && k < g.isoLines.polylineCount(); ++k)
      fileLines.add(std::vector<glm::dvec3>(g.isoLines.points.begin() + g.isoLines.starts[k],
                                            g.isoLines.points.begin() + g.isoLines.starts[k + 1]));
  }
  bool drawSurface = o.drawSurface && !mesh.triangles.empty();
  if (o.surfaceExplicit && o.drawSurface && mesh.triangles.empty())
    throw SceneError(o.surfaceWhere, "this object has no polygons to draw as a surface");

  if (o.wire) {
    const WireDescription& wd = *o.wire;
    const std::string fromWhere = wd.where + "/from";
    SceneWire w = wd.wire;
    // A wire's segments count against the budget as hair segments do. Edges are counted before
    // they are made (a closed mesh has 1.5 per triangle), the rest once made.
    bool counted = false;
    switch (wireFrom) {
      case WireDescription::From::Isolines:
        if (!isSource) throw SceneError(fromWhere, "isolines need a parametric source (use edges or lines for files)");
        w.lines = isolines(*o.source, wd.linesU, wd.linesV);
        break;
      case WireDescription::From::Edges:
        if (isCad) {
          if (fileLines.points.empty()) throw SceneError(fromWhere, "this CAD file has no edges");
          selectEdges(*o.geometry, fileLines, wd.edges, w);
        } else {
          if (mesh.triangles.empty()) throw SceneError(fromWhere, "this object has no polygons, so no edges");
          budget.add(wd.where, 1.5 * double(mesh.triangles.size()), "this wire's edges");
          counted = true;
          if (wd.edges.mode == EdgeSelection::Mode::All) {
            w.lines = meshEdges(mesh);
          } else {
            ClassifiedEdges e = classifyMeshEdges(mesh, wd.edges);
            w.lines = std::move(e.lines);
            w.edgeClasses = std::move(e.classes);
          }
        }
        break;
      default:
        if (fileLines.points.empty()) throw SceneError(fromWhere, "this object has no line cells");
        if (isCad) selectEdges(*o.geometry, fileLines, wd.edges, w);
        else w.lines = fileLines;
        break;
    }
    if (!counted) budget.add(wd.where, double(w.lines.points.size() - w.lines.polylineCount()), "this wire");
    transformPolylines(w.lines, o.transform);
    w.name = name;
    // Its silhouettes: one more wire like it, traced once the camera is known.
    SilhouetteSource sil;
    if (wd.silhouettes) {
      if (isSource) {
        if (std::shared_ptr<const Surface> base(makeSurface(*o.source)); base)
          sil.faces.push_back({std::make_shared<TransformedSurface>(base, o.transform), nullptr});
      } else {
        for (const FaceSurface& f : o.geometry->faces)
          if (f.surface) sil.faces.push_back({std::make_shared<TransformedSurface>(f.surface, o.transform), f.inside});
      }
    }
    SceneWire silWire;
    if (!sil.faces.empty()) {
      silWire = w;
      silWire.lines = PolylineSet{};
      silWire.name = name + " silhouettes";
    }
    scene.wires.push_back(std::move(w));
    if (!sil.faces.empty()) {
      sil.wire = scene.wires.size();
      sil.options = wd.silhouetteOptions;
      scene.wires.push_back(std::move(silWire));
      out.silhouettes.push_back(std::move(sil));
    }
  }

  // The polygons placed, once, for the surface and for growth on a mesh.
  const bool meshGrowth = (o.fur || o.scales) && !isSource && o.geometry->faces.empty();
  if (drawSurface || meshGrowth) transformMesh(mesh, o.transform);

  // Where fur and scales grow: the placed source, a CAD model's exact faces, or a mesh (its
  // texture coordinates, else an automatic layout: surface/mesh_surface.h).
  std::vector<GrowthPatch> patches;
  if (o.fur || o.scales) {
    const std::string where = o.fur ? o.fur->where : o.scales->where;
    if (isSource) {
      std::shared_ptr<const Surface> base(makeSurface(*o.source));
      if (!base) throw SceneError(o.sourceWhere, "a box is not one parametric patch: fur and scales need another source");
      patches.push_back({std::make_shared<TransformedSurface>(base, o.transform), nullptr, index});
    } else if (!o.geometry->faces.empty()) {
      // A face's identity: the top bit set, the object in the next 11 bits, the face in the low
      // 20, so that no face shares the random streams of another face or of a one-patch object
      // (whose identity is its index, below 2^31).
      if (index >= 2048) throw SceneError(where, "fur and scales grow on CAD faces of the first 2048 objects only");
      for (const FaceSurface& f : o.geometry->faces) {
        if (f.id < 0 || f.id >= (1 << 20)) throw SceneError(where, "face " + std::to_string(f.id) + ": fur and scales grow on the first 2^20 faces of a model only");
        patches.push_back({std::make_shared<TransformedSurface>(f.surface, o.transform), f.inside,
                           0x80000000u | (index << 20) | std::uint32_t(f.id)});
      }
    } else {
      if (mesh.triangles.empty()) throw SceneError(where, "fur and scales grow on a surface (this object has no polygons)");
      auto ms = std::make_shared<MeshSurface>(mesh);
      if (!ms->problem().empty()) throw SceneError(where, ms->problem());
      patches.push_back({ms, nullptr, index});
    }
  }

  if (drawSurface) {
    const Burnish::Grain grain = scene.materials[size_t(o.surfaceMaterial)].burnish.grain;
    if (grain == Burnish::Grain::U || grain == Burnish::Grain::V) fillGrainFrame(mesh);
    const GeometryData* g = isSource ? nullptr : o.geometry.get();
    const GrainLayout layout = scene.materials[size_t(o.surfaceMaterial)].burnish.layout;
    if (layout != GrainLayout::Raw && (grain == Burnish::Grain::U || grain == Burnish::Grain::V)) {
      // (A material of grain V is only scaled: both coordinates become world lengths.)
      const std::vector<int> none;
      const GrainLayoutStats st = layoutGrain(mesh, g ? g->triangleFace : none, grain == Burnish::Grain::U ? layout : GrainLayout::U);
      out.grainFaces += st.faces, out.grainAlongU += st.alongU, out.grainAlongV += st.alongV;
    }
    if (g && o.splitParts && g->partNames.size() > 1 && g->trianglePart.size() == mesh.triangles.size()) {
      std::vector<TriangleMesh> parts = splitParts(mesh, g->trianglePart, g->partNames.size());
      for (size_t p = 0; p < parts.size(); ++p)
        if (!parts[p].triangles.empty())
          scene.surfaces.push_back({g->partNames[p], std::move(parts[p]), o.surfaceMaterial, o.surfaceHoldout});
    } else {
      std::string surfaceName = name;
      if (g && o.splitParts && g->partNames.size() == 1) surfaceName = g->partNames[0];
      scene.surfaces.push_back({surfaceName, std::move(mesh), o.surfaceMaterial, o.surfaceHoldout});
    }
  }

  if (o.fur) {
    const FurDescription& fd = *o.fur;
    FurParams params = fd.params;
    if (d.time) params.time = *d.time;
    if (const std::string p = params.problem(); !p.empty()) throw SceneError(fd.where, p);
    const auto t0 = std::chrono::steady_clock::now();
    for (const GrowthPatch& patch : patches) {
      FurParams q = params;
      q.densityMap = both(params.densityMap, patch.inside);
      // The scene's remaining budget bounds this fur: the core counts the hairs' points exactly
      // before it allocates and refuses past the bound.
      q.maxPoints = std::floor(budget.left() / q.segments) * (q.segments + 1);
      Fur fur;
      try {
        fur = growFur(*patch.surface, q, patch.id);
      } catch (const std::exception& e) {
        throw SceneError(fd.where, e.what());
      }
      out.hairsGrown += fur.hairs.polylineCount();
      budget.add(fd.where, double(fur.hairs.polylineCount()) * q.segments, "this fur");
      if (fur.hairs.points.empty() && patches.size() > 1) continue;
      SceneWire w;
      w.name = patches.size() > 1 ? name + " fur of face " + std::to_string(patch.id & 0xFFFFFu) : name + " fur";
      w.lines = std::move(fur.hairs);
      w.thickness = params.thickness;
      w.style = WireStyle::Shaded;
      w.material = fd.material;
      w.opacity = fd.opacity;
      w.roundEnds = fd.roundEnds;
      w.restsOnSurface = false;  // a hair's polyline is its axis: it grows out of the skin
      w.aggregate = true;        // many similar strands: may be simplified (RenderOptions::simplify)
      scene.wires.push_back(std::move(w));
    }
    out.generateSeconds += secondsSince(t0);
  }
  if (o.scales) {
    const ScalesDescription& sd = *o.scales;
    if (const std::string p = sd.params.problem(); !p.empty()) throw SceneError(sd.where, p);
    const auto t0 = std::chrono::steady_clock::now();
    SceneSurface s;
    s.name = name + " scales";
    s.material = sd.material;
    for (const GrowthPatch& patch : patches) {
      ScaleParams q = sd.params;
      q.mask = patch.inside;
      if (sd.cellSize > 0.0) cellsOfSize(*patch.surface, sd.cellSize, q.cellsU, q.cellsV);
      // Two scales per cell, two triangles each, within the remaining budget (checked by the
      // core before it allocates, as for fur).
      q.maxTriangles = budget.left();
      TriangleMesh grown;
      try {
        grown = growScales(*patch.surface, q, patch.id);
      } catch (const std::exception& e) {
        throw SceneError(sd.cellsWhere, e.what());
      }
      budget.add(sd.cellsWhere, double(grown.triangles.size()), "these scales");
      out.scalesGrown += grown.triangles.size() / 2;
      appendMesh(s.mesh, grown);
    }
    out.generateSeconds += secondsSince(t0);
    scene.surfaces.push_back(std::move(s));
  }
  if (isoWire) scene.wires.push_back(std::move(*isoWire));
  if (!drawSurface && !o.wire && !o.fur && !o.scales && !isoWire)
    throw SceneError(o.where, "this object draws nothing (no polygons for a surface, no wire, fur or scales)");
}

}  // namespace

BuiltScene buildScene(const SceneDescription& d) {
  BuiltScene out;
  Scene& scene = out.scene;
  scene.materials = d.materials.empty() ? std::vector<Material>{Material{}} : d.materials;
  scene.lights = d.lights;
  scene.lightsFollowCamera = d.lightsFollowCamera;
  scene.background = d.background;
  scene.environment = d.environment;
  Budget budget{d.maxPrimitives};
  const int materials = int(scene.materials.size());
  for (size_t i = 0; i < d.objects.size(); ++i) {
    const ObjectDescription& o = d.objects[i];
    auto checkMaterial = [&](int m, const std::string& where) {
      if (m < 0 || m >= materials) throw SceneError(where, "no material " + std::to_string(m) + " (the scene has " + std::to_string(materials) + ")");
    };
    checkMaterial(o.surfaceMaterial, o.surfaceWhere.empty() ? o.where : o.surfaceWhere);
    if (o.wire) checkMaterial(o.wire->wire.material, o.wire->where);
    if (o.fur) checkMaterial(o.fur->material, o.fur->where);
    if (o.scales) checkMaterial(o.scales->material, o.scales->where);
    if (o.isoLineWire) checkMaterial(o.isoLineWire->material, o.where);
    buildObject(d, o, std::uint32_t(i), budget, out);
  }
  out.primitives = budget.used;
  out.framed = d.camera.framed;
  if (d.camera.framed) {
    frameCamera(out, d.camera, d.width, d.height);
  } else {
    scene.camera = d.camera.camera;
  }
  if (const std::string p = scene.camera->problem(); !p.empty()) throw SceneError(d.camera.where, p);
  if (!d.camera.framed && !out.silhouettes.empty())  // (framing traces them)
    out.silhouetteSeconds = traceSilhouettes(scene, out.silhouettes, *scene.camera, d.width, d.height, out.silhouetteStats);
  return out;
}

double traceSilhouettes(Scene& scene, const std::vector<SilhouetteSource>& sources, const Camera& camera, int width,
                        int height, SilhouetteStats& stats) {
  const auto t0 = std::chrono::steady_clock::now();
  if (sources.empty() || !camera.problem().empty()) return 0.0;
  const ViewTransform view = ViewTransform::make(camera, std::max(width, 1), std::max(height, 1));
  for (const SilhouetteSource& src : sources) {
    if (src.wire >= scene.wires.size()) continue;
    std::vector<PolylineSet> lines(src.faces.size());
    std::vector<SilhouetteStats> st(src.faces.size());
    tbb::parallel_for(size_t(0), src.faces.size(), [&](size_t i) {
      traceSilhouette(*src.faces[i].first, src.faces[i].second.get(), view, src.options, lines[i], st[i]);
    });
    PolylineSet& out = scene.wires[src.wire].lines;
    out = PolylineSet{};
    for (size_t i = 0; i < lines.size(); ++i) {
      stats.add(st[i]);
      for (size_t k = 0; k < lines[i].polylineCount(); ++k)
        out.add(std::vector<glm::dvec3>(lines[i].points.begin() + lines[i].starts[k], lines[i].points.begin() + lines[i].starts[k + 1]));
    }
    scene.wires[src.wire].edgeClasses.assign(out.polylineCount(), EdgeClass::Silhouette);
  }
  return secondsSince(t0);
}

void frameCamera(BuiltScene& built, const CameraDescription& cd, int width, int height) {
  if (!cd.framed) return;
  glm::dvec3 centre(0.0);
  double radius = 1.0;
  if (!built.scene.boundingSphere(centre, radius)) centre = glm::dvec3(0.0), radius = 1.0;
  Camera c = cd.camera;
  const Camera f = frameSphere(centre, radius, double(std::max(width, 1)) / std::max(height, 1), c.projection, cd.frameDirection, c.fovYDegrees);
  c.eye = f.eye;
  c.target = f.target;
  c.up = f.up;
  c.orthoHeight = f.orthoHeight;
  built.scene.camera = c;
  if (!built.silhouettes.empty())
    built.silhouetteSeconds += traceSilhouettes(built.scene, built.silhouettes, c, width, height, built.silhouetteStats);
}

}  // namespace wf

#include "wf_render_pass_scene.h"

#include <vtkFieldData.h>

#include "vtkWireFurRenderPass.h"

#include <vtkActor.h>
#include <vtkAbstractMapper.h>
#include <vtkAlgorithm.h>
#include <vtkAppendPolyData.h>
#include <vtkCompositeDataIterator.h>
#include <vtkCompositeDataSet.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkInformation.h>
#include <vtkLight.h>
#include <vtkLightCollection.h>
#include <vtkMapper.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkScalarsToColors.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>

#include "wf_vtk_surfaces.h"

#include "core/srgb.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace wfvtk {

namespace {

glm::dvec3 vec(const double v[3]) { return {v[0], v[1], v[2]}; }

// The mapper's input, brought up to date: a vtkPolyData, or a composite data set (ParaView's
// representations give their vtkCompositePolyDataMapper2 a vtkMultiBlockDataSet).
vtkDataObject* actorData(vtkActor* actor) {
  vtkMapper* mapper = actor->GetMapper();
  if (!mapper) return nullptr;
  if (vtkAlgorithm* producer = mapper->GetNumberOfInputConnections(0) > 0 ? mapper->GetInputAlgorithm() : nullptr)
    producer->Update();
  return mapper->GetInputDataObject(0, 0);
}

// The polygonal data to convert: the input itself, or a composite's vtkPolyData leaves appended
// into one (with the first leaf's field data, where the WireFur filters leave their flags).
vtkSmartPointer<vtkPolyData> actorInput(vtkActor* actor) {
  vtkDataObject* data = actorData(actor);
  if (auto* pd = vtkPolyData::SafeDownCast(data)) return pd;
  auto* composite = vtkCompositeDataSet::SafeDownCast(data);
  if (!composite) return nullptr;
  vtkNew<vtkAppendPolyData> append;
  vtkPolyData* first = nullptr;
  auto it = vtk::TakeSmartPointer(composite->NewIterator());
  for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem()) {
    auto* leaf = vtkPolyData::SafeDownCast(it->GetCurrentDataObject());
    if (!leaf || leaf->GetNumberOfPoints() == 0) continue;
    if (!first) first = leaf;
    append->AddInputData(leaf);
  }
  if (!first) return nullptr;
  append->Update();
  vtkSmartPointer<vtkPolyData> out = append->GetOutput();
  out->GetFieldData()->ShallowCopy(first->GetFieldData());
  return out;
}

// 8-bit sRGB -> linear, once.
const float* srgbTable() {
  static const auto table = [] {
    std::vector<float> t(256);
    for (int i = 0; i < 256; ++i) t[size_t(i)] = srgbToLinear(float(i) / 255.0f);
    return t;
  }();
  return table.data();
}

}  // namespace

float srgbToLinear(float v) { return wf::srgbToLinear(v); }

float linearToSrgb(float v) { return wf::linearToSrgb(v); }

vtkMTimeType actorSignature(vtkActor* actor) {
  vtkMTimeType t = actor->GetMTime();  // includes property, texture and user transform
  if (vtkInformation* keys = actor->GetPropertyKeys()) t = std::max(t, keys->GetMTime());
  if (vtkMapper* mapper = actor->GetMapper()) {
    t = std::max(t, mapper->GetMTime());
    if (vtkDataObject* d = actorData(actor)) t = std::max(t, d->GetMTime());
  }
  return t;
}

ActorPiece convertActor(vtkActor* actor) {
  ActorPiece piece;
  piece.actor = actor;
  piece.signature = actorSignature(actor);
  vtkProperty* prop = actor->GetProperty();
  wf::Material& m = piece.material;
  m.name = "actor";
  // vtkProperty colours are taken as linear Phong coefficients (the core's materials).
  double dc[3], sc[3];
  prop->GetDiffuseColor(dc);
  prop->GetSpecularColor(sc);
  m.phong.diffuse = vec(dc) * prop->GetDiffuse();
  // An actor lit only by its ambient term (ParaView's Wireframe and Points representations set
  // Ambient 1, Diffuse 0): its ambient colour as the diffuse one, rather than black.
  if (!(prop->GetDiffuse() > 0.0) && prop->GetAmbient() > 0.0) {
    double ac[3];
    prop->GetAmbientColor(ac);
    m.phong.diffuse = vec(ac) * prop->GetAmbient();
  }
  m.phong.specular = vec(sc) * prop->GetSpecular();
  m.phong.exponent = prop->GetSpecularPower();
  m.opacity = float(std::clamp(prop->GetOpacity(), 0.0, 1.0));

  const vtkSmartPointer<vtkPolyData> input = actorInput(actor);
  vtkPolyData* pd = input;
  if (!pd || pd->GetNumberOfPoints() == 0) return piece;
  // What the WireFur filters said of their output (field data): lines already shaded by
  // vtkWireFurTangentShading, a surface with burnish grain from vtkWireFurBurnish.
  vtkFieldData* fd = pd->GetFieldData();
  const bool preshaded = fd && fd->GetArray("WireFurShaded");
  const bool burnished = fd && fd->GetArray("WireFurGrain") && pd->GetPointData()->GetTangents() &&
                         pd->GetPointData()->GetTangents()->GetNumberOfComponents() == 3;
  // VTK's default property has no specular (Specular 0, SpecularPower 1): a wire or brushed
  // metal without a highlight reads as flat paint, so it gets the presets' (a property with any
  // specular keeps its own).
  const bool noSpecular = !(prop->GetSpecular() > 0.0);
  // A cell naming a point the data does not have (VTK's own mappers would read past the end):
  // the actor is left out, with a warning.
  if (const std::int64_t bad = wf::vtkio::firstCellWithMissingPoints(pd); bad >= 0) {
    vtkGenericWarningMacro(<< "vtkWireFurRenderPass: a marked actor's cell " << bad
                           << " names a point its data does not have; the actor is left out");
    return piece;
  }

  // The object: the data in object space, the actor's matrix as its transform (the builder
  // places positions, normals and grain directions).
  vtkNew<vtkMatrix4x4> matrix;
  actor->GetMatrix(matrix);
  glm::dmat4 M(1.0);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) M[c][r] = matrix->GetElement(r, c);
  wf::ObjectDescription& o = piece.object;
  o.name = "actor";
  o.where = "actor";
  o.transform = M;
  auto g = std::make_shared<wf::GeometryData>();
  const vtkIdType np = pd->GetNumberOfPoints();
  std::vector<glm::dvec3> points(static_cast<size_t>(np));
  for (vtkIdType i = 0; i < np; ++i) {
    double p[3];
    pd->GetPoint(i, p);
    points[size_t(i)] = vec(p);
  }
  // Mapped colours (direct 8-bit colours or through the lookup table). As in VTK's own
  // rendering they replace the diffuse colour (the diffuse coefficient still applies; the
  // specular colour stays): the core multiplies its shading by per-point colours, so the
  // material's diffuse colour becomes white. Cell colours go to the points of their cells (the
  // first cell using a point gives its colour: exact where cells share no points).
  std::vector<glm::vec3> colours;
  if (vtkMapper* mapper = actor->GetMapper(); mapper && mapper->GetScalarVisibility()) {
    int cellFlag = 0;
    // With InterpolateScalarsBeforeMapping on (ParaView's default) MapScalars makes texture
    // coordinates into a colour map, not colours: the scalars then go through the lookup table
    // here, as vtkMapper::MapScalars would with it off (range, colour mode; component -1: the
    // table's own vector mode).
    vtkSmartPointer<vtkUnsignedCharArray> own;
    vtkUnsignedCharArray* c = nullptr;
    if (mapper->GetInterpolateScalarsBeforeMapping()) {
      if (vtkDataArray* scalars = vtkAbstractMapper::GetScalars(pd, mapper->GetScalarMode(), mapper->GetArrayAccessMode(),
                                                                mapper->GetArrayId(), mapper->GetArrayName(), cellFlag)) {
        vtkScalarsToColors* lut = mapper->GetLookupTable();
        if (!mapper->GetUseLookupTableScalarRange()) lut->SetRange(mapper->GetScalarRange());
        own = vtk::TakeSmartPointer(lut->MapScalars(scalars, mapper->GetColorMode(), -1));
        c = own;
      }
    } else {
      c = mapper->MapScalars(pd, 1.0, cellFlag);
    }
    const float* lin = srgbTable();
    if (c && c->GetNumberOfComponents() >= 3) {
      const int nc = c->GetNumberOfComponents();
      const unsigned char* d = c->GetPointer(0);
      auto colourOf = [&](vtkIdType t) { return glm::vec3(lin[d[t * nc]], lin[d[t * nc + 1]], lin[d[t * nc + 2]]); };
      if (cellFlag == 0 && c->GetNumberOfTuples() == np) {
        colours.resize(size_t(np));
        for (vtkIdType i = 0; i < np; ++i) colours[size_t(i)] = colourOf(i);
      } else if (cellFlag == 1 && c->GetNumberOfTuples() == pd->GetNumberOfCells()) {
        colours.assign(size_t(np), glm::vec3(-1.0f));
        wf::vtkio::forEachCell(pd, [&](vtkIdType cell, vtkIdType n, const vtkIdType* ids) {
          for (vtkIdType k = 0; k < n; ++k)
            if (ids[k] >= 0 && ids[k] < np && colours[size_t(ids[k])].x < 0.0f) colours[size_t(ids[k])] = colourOf(cell);
          return true;
        });
        for (glm::vec3& col : colours)
          if (col.x < 0.0f) col = glm::vec3(1.0f);
      }
    }
    if (!colours.empty()) m.phong.diffuse = glm::dvec3(prop->GetDiffuse());
  }
  wf::Material& lineMaterial = piece.wireMaterial;
  lineMaterial = m;
  if (noSpecular) lineMaterial.phong.specular = glm::dvec3(0.5), lineMaterial.phong.exponent = 40.0;
  if (burnished) {
    m.burnish.grain = wf::Burnish::Grain::U;  // the grain is the tangent itself (derivU below)
    if (noSpecular) m.phong.specular = glm::dvec3(1.0), m.phong.exponent = 30.0;
  }

  // Lines and polylines -> the object's wire.
  vtkInformation* keys = actor->GetPropertyKeys();
  if (pd->GetNumberOfLines() > 0) {
    wf::WireDescription wd;
    wd.from = wf::WireDescription::From::Lines;
    wd.where = "actor/wire";
    wf::SceneWire& w = wd.wire;
    w.material = 1;
    w.opacity = m.opacity;
    w.colour = glm::vec3(vec(dc));
    const int style = keys && keys->Has(vtkWireFurRenderPass::WIREFUR_WIRE_STYLE())
                          ? keys->Get(vtkWireFurRenderPass::WIREFUR_WIRE_STYLE()) : 0;
    w.style = style == 1 ? wf::WireStyle::Plain : style == 2 ? wf::WireStyle::DepthCued : wf::WireStyle::Shaded;
    std::vector<glm::vec3> lineColours = colours;
    if (preshaded && style == 0) {
      // Shaded once already: drawn in its own radiance (the float array, not the 8-bit colour).
      w.style = wf::WireStyle::Plain;
      w.colour = glm::vec3(1.0f);
      if (auto* r = vtkDataArray::SafeDownCast(pd->GetPointData()->GetArray("ShadedRadiance"));
          r && r->GetNumberOfComponents() == 3 && r->GetNumberOfTuples() == np) {
        lineColours.resize(size_t(np));
        for (vtkIdType i = 0; i < np; ++i)
          lineColours[size_t(i)] = glm::vec3(float(r->GetComponent(i, 0)), float(r->GetComponent(i, 1)), float(r->GetComponent(i, 2)));
      }
    }
    if (keys && keys->Has(vtkWireFurRenderPass::WIREFUR_WIRE_THICKNESS())) {
      w.thickness = keys->Get(vtkWireFurRenderPass::WIREFUR_WIRE_THICKNESS());
      w.thicknessInPixels = false;
    } else {
      w.thickness = prop->GetLineWidth();
      w.thicknessInPixels = true;
    }
    const bool withColours = !lineColours.empty();
    wf::PolylineSet& lines = g->lines;
    vtkCellArray* cells = pd->GetLines();
    vtkNew<vtkIdList> ids;
    lines.points.reserve(size_t(cells->GetNumberOfConnectivityIds()));
    if (withColours) lines.colours.reserve(size_t(cells->GetNumberOfConnectivityIds()));
    std::vector<glm::dvec3> line;
    for (cells->InitTraversal(); cells->GetNextCell(ids);) {
      if (ids->GetNumberOfIds() < 2) continue;
      line.clear();
      for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) {
        const vtkIdType id = ids->GetId(k);
        line.push_back(points[size_t(id)]);
        if (withColours) lines.colours.push_back(lineColours[size_t(id)]);
      }
      lines.add(line);
    }
    if (lines.polylineCount() > 0) o.wire = std::move(wd);
  }

  // Polygons (fans) and strips -> the object's surface: one triangle mesh over all the points.
  o.drawSurface = false;
  if (pd->GetNumberOfPolys() > 0 || pd->GetNumberOfStrips() > 0) {
    wf::TriangleMesh& mesh = g->mesh;
    if (vtkDataArray* normals = pd->GetPointData()->GetNormals(); normals && normals->GetNumberOfComponents() == 3) {
      mesh.normals.resize(size_t(np));
      for (vtkIdType i = 0; i < np; ++i) {
        double n[3];
        normals->GetTuple(i, n);
        mesh.normals[size_t(i)] = vec(n);
      }
    }
    if (vtkDataArray* tc = pd->GetPointData()->GetTCoords(); tc && tc->GetNumberOfComponents() >= 2) {
      mesh.uvs.resize(size_t(np));
      for (vtkIdType i = 0; i < np; ++i) mesh.uvs[size_t(i)] = {tc->GetComponent(i, 0), tc->GetComponent(i, 1)};
    }
    mesh.colours = colours;
    auto add = [&](vtkIdType a, vtkIdType b, vtkIdType c) {
      mesh.triangles.push_back({std::uint32_t(a), std::uint32_t(b), std::uint32_t(c)});
    };
    vtkNew<vtkIdList> ids;
    vtkCellArray* polys = pd->GetPolys();
    for (polys->InitTraversal(); polys->GetNextCell(ids);)
      for (vtkIdType k = 1; k + 1 < ids->GetNumberOfIds(); ++k) add(ids->GetId(0), ids->GetId(k), ids->GetId(k + 1));
    vtkCellArray* strips = pd->GetStrips();
    for (strips->InitTraversal(); strips->GetNextCell(ids);)
      for (vtkIdType k = 0; k + 2 < ids->GetNumberOfIds(); ++k) {
        if (k % 2 == 0) add(ids->GetId(k), ids->GetId(k + 1), ids->GetId(k + 2));
        else add(ids->GetId(k + 1), ids->GetId(k), ids->GetId(k + 2));
      }
    if (burnished && !mesh.triangles.empty()) {
      // The grain as dS/du, which the core's grain U shades along, and N x grain (object space)
      // as dS/dv: the core uses a mesh's own derivatives only when it has both, and the builder
      // places both by the actor's linear part, as directions along the surface (under a
      // non-uniform scale dS/dv is then no longer exactly N x grain; only bump maps and grain V
      // read it, which an actor's surface has neither). Grooves dim diffuse and specular
      // together, as the core's groove texture does.
      vtkDataArray* t = pd->GetPointData()->GetTangents();
      std::vector<glm::dvec3> n = mesh.normals;
      if (n.size() != size_t(np)) {  // area-weighted face normals at the vertices
        n.assign(size_t(np), glm::dvec3(0.0));
        for (const glm::uvec3& f : mesh.triangles) {
          const glm::dvec3 c = glm::cross(points[f.y] - points[f.x], points[f.z] - points[f.x]);
          if (std::isfinite(c.x + c.y + c.z)) n[f.x] += c, n[f.y] += c, n[f.z] += c;
        }
      }
      mesh.derivU.resize(size_t(np));
      mesh.derivV.resize(size_t(np));
      for (vtkIdType i = 0; i < np; ++i) {
        double v[3];
        t->GetTuple(i, v);
        const glm::dvec3 T = vec(v);
        mesh.derivU[size_t(i)] = T;
        const glm::dvec3 B = glm::cross(n[size_t(i)], T);
        const double lb = glm::length(B);
        mesh.derivV[size_t(i)] = lb > 0.0 && std::isfinite(lb) ? B / lb : glm::dvec3(0.0);
      }
      if (auto* gi = vtkDataArray::SafeDownCast(pd->GetPointData()->GetArray("GrooveIntensity"));
          gi && gi->GetNumberOfComponents() == 1 && gi->GetNumberOfTuples() == np) {
        if (mesh.colours.empty()) mesh.colours.assign(size_t(np), glm::vec3(1.0f));
        for (vtkIdType i = 0; i < np; ++i) mesh.colours[size_t(i)] *= float(gi->GetComponent(i, 0));
      }
    }
    if (!mesh.triangles.empty()) {
      mesh.positions = std::move(points);
      o.drawSurface = true;
      o.surfaceMaterial = 0;
    }
  }
  if (o.drawSurface || o.wire) o.geometry = std::move(g);
  return piece;
}

wf::SceneDescription describeActors(const std::vector<ActorPiece>& pieces, std::vector<wf::Material> firstMaterials) {
  wf::SceneDescription d;
  d.materials = std::move(firstMaterials);
  d.maxPrimitives = INFINITY;  // VTK's data is already made: the render's memory estimate bounds it
  d.camera.framed = false;     // the pass sets the vtkCamera's every frame
  for (size_t k = 0; k < pieces.size(); ++k) {
    const ActorPiece& p = pieces[k];
    if (!p.object.geometry) continue;
    const int mi = int(d.materials.size());
    d.materials.push_back(p.material);
    d.materials.push_back(p.wireMaterial);
    wf::ObjectDescription o = p.object;
    if (o.name == "actor") o.name = o.where = "actor " + std::to_string(k);  // in the core's warnings
    if (o.wire) o.wire->where = o.where + "/wire";
    o.surfaceMaterial = mi;
    if (o.wire) o.wire->wire.material = mi + 1;
    d.objects.push_back(std::move(o));
  }
  if (d.materials.empty()) d.materials.emplace_back();
  return d;
}

wf::Scene assembleScene(const std::vector<ActorPiece>& pieces, const wf::Scene* core) {
  // The core scene's materials first, so that its surfaces' and wires' indices hold.
  const std::vector<wf::Material> first = core ? core->materials : std::vector<wf::Material>{};
  wf::Scene scene;
  try {
    scene = wf::buildScene(describeActors(pieces, first)).scene;
  } catch (const wf::SceneError&) {
    // An actor the builder cannot make is left out, with a warning; the others are drawn.
    std::vector<ActorPiece> kept;
    for (size_t k = 0; k < pieces.size(); ++k) {
      ActorPiece p = pieces[k];
      if (p.object.name == "actor") p.object.name = p.object.where = "actor " + std::to_string(k);
      try {
        wf::buildScene(describeActors({p}, first));
        kept.push_back(std::move(p));
      } catch (const wf::SceneError& e) {
        vtkGenericWarningMacro(<< "vtkWireFurRenderPass: marked " << e.where << " is left out: " << e.what());
      }
    }
    scene = wf::buildScene(describeActors(kept, first)).scene;
  }
  if (core) {
    scene.surfaces.insert(scene.surfaces.begin(), core->surfaces.begin(), core->surfaces.end());
    scene.wires.insert(scene.wires.begin(), core->wires.begin(), core->wires.end());
    scene.environment = core->environment;
  }
  scene.camera.reset();
  scene.background = glm::vec4(0.0f);  // premultiplied over nothing: composited afterwards
  return scene;
}

wf::Camera convertCamera(vtkCamera* camera, int width, int height) {
  wf::Camera c;
  double p[3], f[3], up[3], range[2];
  camera->GetPosition(p);
  camera->GetFocalPoint(f);
  camera->GetViewUp(up);
  camera->GetClippingRange(range);
  c.eye = vec(p);
  c.target = vec(f);
  c.up = vec(up);
  c.nearPlane = range[0];
  c.farPlane = range[1];
  if (camera->GetParallelProjection()) {
    c.projection = wf::Camera::Projection::Orthographic;
    c.orthoHeight = 2.0 * camera->GetParallelScale();
  } else {
    c.projection = wf::Camera::Projection::Perspective;
    double angle = camera->GetViewAngle();
    if (camera->GetUseHorizontalViewAngle()) {
      const double aspect = double(width) / double(std::max(1, height));
      angle = glm::degrees(2.0 * std::atan(std::tan(glm::radians(angle) / 2.0) / aspect));
    }
    c.fovYDegrees = angle;
  }
  return c;
}

vtkCamera* FilterView::active() const {
  if (camera) return camera;
  vtkRenderer* ren = renderer;
  return ren ? ren->GetActiveCamera() : nullptr;
}

void FilterView::size(const int fallback[2], int& width, int& height) const {
  width = fallback[0], height = fallback[1];
  if (vtkRenderer* ren = renderer) {
    const int* s = ren->GetSize();
    if (s && s[0] > 0 && s[1] > 0) width = s[0], height = s[1];
  }
  width = std::max(width, 1), height = std::max(height, 1);
}

vtkMTimeType FilterView::mtime(const int fallback[2]) {
  vtkCamera* c = active();
  int w, h;
  size(fallback, w, h);
  if (c != last_ || w != lastWidth_ || h != lastHeight_) {
    last_ = c, lastWidth_ = w, lastHeight_ = h;
    changed_.Modified();
  }
  return std::max<vtkMTimeType>(changed_.GetMTime(), c ? c->GetMTime() : 0);
}

wf::LightRig convertLights(vtkRenderer* renderer, vtkCamera* camera, const double ambient[3]) {
  wf::LightRig rig;
  rig.ambient = vec(ambient);
  double p[3], f[3];
  camera->GetPosition(p);
  camera->GetFocalPoint(f);
  const glm::dvec3 back = glm::normalize(vec(p) - vec(f));  // towards the viewer
  // Eye space -> world: VTK's camera-light frame has the camera at (0, 0, 1) looking at the
  // origin, +y up: the same axes as the core's eye space (viewer on +z).
  double upv[3];
  camera->GetViewUp(upv);
  const glm::dvec3 right = glm::normalize(glm::cross(vec(upv), back));
  const glm::dvec3 up = glm::cross(back, right);
  const glm::dmat3 worldFromEye(right, up, back);
  int lit = 0;
  vtkLightCollection* lights = renderer->GetLights();
  vtkCollectionSimpleIterator it;
  lights->InitTraversal(it);
  while (vtkLight* light = lights->GetNextLight(it)) {
    if (!light->GetSwitch()) continue;
    double c[3];
    light->GetDiffuseColor(c);
    wf::DirectionalLight d;
    d.intensity = vec(c) * light->GetIntensity();
    if (light->LightTypeIsHeadlight()) {
      d.direction = back;
    } else {
      double lp[3], lf[3];
      light->GetPosition(lp);
      light->GetFocalPoint(lf);
      glm::dvec3 dir = vec(lp) - vec(lf);
      if (light->LightTypeIsCameraLight()) {
        dir = worldFromEye * dir;
      } else {  // scene light: its own transform (if any) applied
        light->GetTransformedPosition(lp);
        light->GetTransformedFocalPoint(lf);
        dir = vec(lp) - vec(lf);
      }
      if (!(glm::length(dir) > 0)) continue;
      d.direction = glm::normalize(dir);
    }
    rig.lights.push_back(d);
    ++lit;
  }
  if (lit == 0 && lights->GetNumberOfItems() == 0) rig.lights.push_back({back, glm::dvec3(1.0)});
  return rig;
}

void viewDepthFromWindowDepth(const std::vector<float>& windowDepth, int width, int height,
                              vtkMatrix4x4* P, std::vector<float>& viewDepth) {
  viewDepth.assign(size_t(width) * size_t(height), std::numeric_limits<float>::infinity());
  const double p22 = P->GetElement(2, 2), p23 = P->GetElement(2, 3);
  const double p32 = P->GetElement(3, 2), p33 = P->GetElement(3, 3);
  for (int y = 0; y < height; ++y) {
    const float* src = windowDepth.data() + size_t(height - 1 - y) * size_t(width);
    float* dst = viewDepth.data() + size_t(y) * size_t(width);
    for (int x = 0; x < width; ++x) {
      const double zw = src[x];
      if (!(zw < 1.0)) continue;  // cleared: nothing opaque here
      // z_ndc = (p22 z + p23) / (p32 z + p33), solved for the eye-space z (negative in front).
      const double zn = 2.0 * zw - 1.0;
      const double den = zn * p32 - p22;
      const double z = den != 0.0 ? (p23 - zn * p33) / den : -std::numeric_limits<double>::infinity();
      const double d = -z;
      dst[x] = d > 0.0 && std::isfinite(d) ? float(d) : (d > 0.0 ? std::numeric_limits<float>::infinity() : 0.0f);
    }
  }
}

}  // namespace wfvtk

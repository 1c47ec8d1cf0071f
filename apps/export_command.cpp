#include "export_command.h"

#include "cli.h"
#include "safe_files.h"
#include "render_command.h"
#include "scene_file.h"

#include "scene/edge_visibility.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkOBJWriter.h>
#include <vtkPLYWriter.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataWriter.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLPolyDataWriter.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>

namespace wfapp {

namespace {

unsigned char toByte(float c) { return (unsigned char)std::lround(255.0f * std::clamp(std::isfinite(c) ? c : 0.0f, 0.0f, 1.0f)); }

glm::dvec3 unitOrZero(const glm::dvec3& v) {
  const double l = glm::length(v);
  return l > 0 && std::isfinite(l) ? v / l : glm::dvec3(0.0);
}

}  // namespace

vtkSmartPointer<vtkPolyData> sceneToPolyData(const wf::Scene& scene, const std::vector<std::vector<std::uint8_t>>* visible) {
  size_t nPoints = 0;
  for (const wf::SceneSurface& s : scene.surfaces)
    if (!s.holdout) nPoints += s.mesh.positions.size();
  for (const wf::SceneWire& w : scene.wires) nPoints += w.lines.points.size();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(vtkIdType(nPoints));
  vtkNew<vtkFloatArray> normals, tangents, tcoords;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(vtkIdType(nPoints));
  tangents->SetName("Tangents");
  tangents->SetNumberOfComponents(3);
  tangents->SetNumberOfTuples(vtkIdType(nPoints));
  tcoords->SetName("TCoords");
  tcoords->SetNumberOfComponents(2);
  tcoords->SetNumberOfTuples(vtkIdType(nPoints));
  // Raw surface derivatives dS/du and dS/dv (world units per parameter unit), where the surfaces
  // have them (parametric sources, CAD faces); zero elsewhere.
  bool anyDerivatives = false;
  for (const wf::SceneSurface& s : scene.surfaces) anyDerivatives = anyDerivatives || !s.mesh.derivU.empty();
  vtkNew<vtkDoubleArray> su, sv;
  if (anyDerivatives)
    for (auto [a, name] : {std::pair<vtkDoubleArray*, const char*>{su, "Su"}, {sv, "Sv"}}) {
      a->SetName(name);
      a->SetNumberOfComponents(3);
      a->SetNumberOfTuples(vtkIdType(nPoints));
      a->Fill(0.0);
    }
  vtkNew<vtkUnsignedCharArray> colours;
  colours->SetName("Colors");
  colours->SetNumberOfComponents(3);
  colours->SetNumberOfTuples(vtkIdType(nPoints));
  vtkNew<vtkCellArray> polys, lines;
  vtkNew<vtkIntArray> polyObject, lineObject, lineClass, lineVisible;
  vtkNew<vtkDoubleArray> polyThickness, lineThickness;
  vtkNew<vtkStringArray> names;
  names->SetName("ObjectNames");

  vtkIdType next = 0;
  int object = 0;
  auto setPoint = [&](vtkIdType id, const glm::dvec3& p, const glm::dvec3& n, const glm::dvec3& t, const glm::dvec2& uv,
                      const glm::vec3& c) {
    points->SetPoint(id, p.x, p.y, p.z);
    const float nf[3] = {float(n.x), float(n.y), float(n.z)}, tf[3] = {float(t.x), float(t.y), float(t.z)};
    const float uvf[2] = {float(uv.x), float(uv.y)};
    normals->SetTypedTuple(id, nf);
    tangents->SetTypedTuple(id, tf);
    tcoords->SetTypedTuple(id, uvf);
    const unsigned char cb[3] = {toByte(c.x), toByte(c.y), toByte(c.z)};
    colours->SetTypedTuple(id, cb);
  };
  for (const wf::SceneSurface& s : scene.surfaces) {
    if (s.holdout) continue;
    const wf::TriangleMesh& m = s.mesh;
    const size_t nv = m.positions.size();
    const vtkIdType base = next;
    for (size_t i = 0; i < nv; ++i) {
      const glm::dvec3 n = m.normals.size() == nv ? m.normals[i] : glm::dvec3(0.0);
      const glm::dvec3 t = m.derivU.size() == nv ? unitOrZero(m.derivU[i])
                                                 : (m.tangents.size() == nv ? m.tangents[i] : glm::dvec3(0.0));
      if (anyDerivatives && m.derivU.size() == nv && m.derivV.size() == nv) {
        su->SetTuple(next, &m.derivU[i].x);
        sv->SetTuple(next, &m.derivV[i].x);
      }
      setPoint(next++, m.positions[i], n, t, m.uvs.size() == nv ? m.uvs[i] : glm::dvec2(0.0),
               m.colours.size() == nv ? m.colours[i] : glm::vec3(1.0f));
    }
    for (const glm::uvec3& tri : m.triangles) {
      if (tri.x >= nv || tri.y >= nv || tri.z >= nv) continue;
      const vtkIdType ids[3] = {base + tri.x, base + tri.y, base + tri.z};
      polys->InsertNextCell(3, ids);
      polyObject->InsertNextValue(object);
      polyThickness->InsertNextValue(0.0);
    }
    names->InsertNextValue(s.name);
    ++object;
  }
  for (size_t wi = 0; wi < scene.wires.size(); ++wi) {
    const wf::SceneWire& w = scene.wires[wi];
    const wf::PolylineSet& L = w.lines;
    const bool classified = w.edgeClasses.size() == L.polylineCount();
    const std::vector<std::uint8_t>* vis =
        visible && wi < visible->size() && (*visible)[wi].size() == L.polylineCount() ? &(*visible)[wi] : nullptr;
    const vtkIdType base = next;
    const bool hasColours = L.colours.size() == L.points.size();
    for (size_t k = 0; k < L.points.size(); ++k) setPoint(next++, L.points[k], glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec2(0.0),
                                                           hasColours ? L.colours[k] : w.colour);
    for (size_t li = 0; li < L.polylineCount(); ++li) {
      const size_t a = L.starts[li], b = std::min<size_t>(L.starts[li + 1], L.points.size());
      if (b < a + 2) continue;
      lines->InsertNextCell(vtkIdType(b - a));
      for (size_t k = a; k < b; ++k) {
        lines->InsertCellPoint(base + vtkIdType(k));
        // The polyline's direction at each point (central where it can be).
        const glm::dvec3 t = unitOrZero(L.points[std::min(k + 1, b - 1)] - L.points[k > a ? k - 1 : a]);
        const float tf[3] = {float(t.x), float(t.y), float(t.z)};
        tangents->SetTypedTuple(base + vtkIdType(k), tf);
      }
      lineObject->InsertNextValue(object);
      lineThickness->InsertNextValue(w.thicknessInPixels ? 0.0 : w.thickness);
      lineClass->InsertNextValue(classified ? int(w.edgeClasses[li]) : -1);
      lineVisible->InsertNextValue(vis ? int((*vis)[li]) : -1);
    }
    names->InsertNextValue(w.name);
    ++object;
  }
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(points);
  pd->SetPolys(polys);
  pd->SetLines(lines);
  pd->GetPointData()->SetNormals(normals);
  pd->GetPointData()->SetTangents(tangents);
  pd->GetPointData()->SetTCoords(tcoords);
  pd->GetPointData()->SetScalars(colours);
  if (anyDerivatives) {
    pd->GetPointData()->AddArray(su);
    pd->GetPointData()->AddArray(sv);
  }
  // Cell data runs over vertices, lines, polygons, strips in that order: lines first.
  vtkNew<vtkIntArray> objectIds;
  objectIds->SetName("ObjectId");
  vtkNew<vtkDoubleArray> thickness;
  thickness->SetName("Thickness");
  vtkNew<vtkIntArray> edgeClass, visibleCells;
  edgeClass->SetName("EdgeClass");
  visibleCells->SetName("Visible");
  for (vtkIdType i = 0; i < lineObject->GetNumberOfTuples(); ++i) {
    objectIds->InsertNextValue(lineObject->GetValue(i));
    thickness->InsertNextValue(lineThickness->GetValue(i));
    edgeClass->InsertNextValue(lineClass->GetValue(i));
    visibleCells->InsertNextValue(lineVisible->GetValue(i));
  }
  for (vtkIdType i = 0; i < polyObject->GetNumberOfTuples(); ++i) {
    objectIds->InsertNextValue(polyObject->GetValue(i));
    thickness->InsertNextValue(polyThickness->GetValue(i));
    edgeClass->InsertNextValue(-1);
    visibleCells->InsertNextValue(-1);
  }
  pd->GetCellData()->AddArray(objectIds);
  pd->GetCellData()->AddArray(thickness);
  pd->GetCellData()->AddArray(edgeClass);
  if (visible) pd->GetCellData()->AddArray(visibleCells);
  pd->GetFieldData()->AddArray(names);
  return pd;
}

int runExport(const ExportOptions& o) {
  const std::string& input = o.input;
  const std::string& output = o.output;
  if (input.empty()) throw UsageError("export: no INPUT (a scene .json or a mesh / polyline file)");
  if (output.empty()) throw UsageError("export: no output (-o OUT.vtp|.vtk|.obj|.ply)");
  std::string ext = std::filesystem::path(output).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".vtp" && ext != ".vtk" && ext != ".obj" && ext != ".ply")
    throw UsageError(output + ": the output must be .vtp, .vtk, .obj or .ply");
  requireOutputPath(output);  // its folder exists; not a folder, device or FIFO (apps/safe_files.h)
  OutputFile::probe(output);  // the folder can be written: known now, not after the scene is built

  SceneOverrides overrides = o.overrides;
  // Visibility needs the faces even where the style draws none: as hold-outs (hidden-line
  // removal), which hide and are not written.
  if (o.visibility && !overrides.hidden) overrides.hidden = wf::HiddenLines{wf::HiddenLines::Mode::Hide};
  SceneFile sf = loadInput(input, o.style, overrides);
  if (o.width > 0) {
    sf.width = o.width, sf.height = o.height;
    reframe(sf, o.width, o.height);
  }
  std::vector<std::vector<std::uint8_t>> visible;
  if (o.visibility) {
    if (!sf.scene.camera) throw std::runtime_error(input + ": the scene has no camera for --visibility");
    const wf::OcclusionGrid grid(sf.scene, *sf.scene.camera, sf.width, sf.height);
    double silhouetteSlack = 0.0;
    glm::dvec3 centre;
    double radius = 0.0;
    if (sf.inputStats.contains("linear_deflection") && sf.scene.boundingSphere(centre, radius))
      silhouetteSlack = std::sqrt(2.0 * sf.inputStats["linear_deflection"].get<double>() * radius);
    wf::VisibilityStats stats;
    visible.resize(sf.scene.wires.size());
    for (size_t i = 0; i < sf.scene.wires.size(); ++i) {
      wf::SceneWire& w = sf.scene.wires[i];
      if (w.aggregate) continue;
      wf::VisibilityOptions vo;
      // Silhouettes lie on the exact surface, where the tessellation's chords can pass in front of
      // a grazing ray: hits within sqrt(2 deflection r) of such a point, or within the width of
      // the triangles there, do not count.
      if (!w.edgeClasses.empty() && w.edgeClasses.front() == wf::EdgeClass::Silhouette) vo.slack = silhouetteSlack, vo.localSlack = true;
      wf::VisibleLines v = wf::splitByVisibility(w.lines, grid, vo, stats);
      if (w.edgeClasses.size() == w.lines.polylineCount()) {
        std::vector<wf::EdgeClass> classes;
        for (std::uint32_t s : v.source) classes.push_back(w.edgeClasses[s]);
        w.edgeClasses = std::move(classes);
      } else {
        w.edgeClasses.clear();
      }
      w.lines = std::move(v.lines);
      visible[i] = std::move(v.visible);
    }
    if (!o.quiet)
      std::fprintf(stderr, "visibility: %.6g visible, %.6g hidden (world length), %zu splits, %zu samples\n",
                   stats.visibleLength, stats.hiddenLength, stats.splits, stats.samples);
  }
  const vtkSmartPointer<vtkPolyData> pd = sceneToPolyData(sf.scene, o.visibility ? &visible : nullptr);
  if (ext == ".ply" && pd->GetNumberOfLines() > 0)
    warn(output + ": PLY holds no lines: " + std::to_string(pd->GetNumberOfLines()) +
         " wire and hair polylines are left out (use .vtp, .vtk or .obj)");

  // Written under a unique temporary name beside the target and renamed: nothing half-written,
  // nothing left behind when stopped.
  OutputFile out(output);
  const std::string tmp = out.temporaryPath();
  int error = 0;
  if (ext == ".vtp") {
    vtkNew<vtkXMLPolyDataWriter> w;
    w->SetFileName(tmp.c_str());
    w->SetInputData(pd);
    w->SetDataModeToAppended();
    w->SetCompressorTypeToZLib();
    error = w->Write() == 1 ? 0 : 1;
  } else if (ext == ".vtk") {
    vtkNew<vtkPolyDataWriter> w;
    w->SetFileName(tmp.c_str());
    w->SetInputData(pd);
    w->SetFileTypeToBinary();
    error = w->Write() == 1 ? 0 : 1;
  } else if (ext == ".obj") {
    vtkNew<vtkOBJWriter> w;
    w->SetFileName(tmp.c_str());
    w->SetInputData(pd);
    error = w->Write() == 1 ? 0 : 1;
  } else {
    vtkNew<vtkPLYWriter> w;
    w->SetFileName(tmp.c_str());
    w->SetInputData(pd);
    w->SetFileTypeToBinary();
    w->SetArrayName("Colors");
    error = w->Write() == 1 ? 0 : 1;
  }
  if (error) throw OutputError(output + ": cannot write");
  out.commit();
  return 0;
}

}  // namespace wfapp

// The outputs of vtkWireFurCADReader as the core's types: the faces (port 0) as a TriangleMesh
// (positions, normals, Su and Sv as derivU and derivV, (u, v), the colours from sRGB bytes to
// linear, and the part of every triangle), the edges and iso lines (port 1) as polylines. Header-only (VTK and the core, no OpenCASCADE), shared by the wirefur
// command and the CAD benchmark. Throws std::runtime_error when the arrays are missing.
#pragma once

#include "core/srgb.h"
#include "render/scene.h"
#include "render/edge_classes.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <limits>
#include <stdexcept>
#include <vector>

namespace wfcad {

inline wf::TriangleMesh facesToMesh(vtkPolyData* faces, std::vector<int>* trianglePart = nullptr,
                                    std::vector<int>* triangleFace = nullptr) {
  wf::TriangleMesh m;
  const vtkIdType np = faces->GetNumberOfPoints();
  vtkDataArray* normals = faces->GetPointData()->GetNormals();
  vtkDataArray* su = faces->GetPointData()->GetArray("Su");
  vtkDataArray* sv = faces->GetPointData()->GetArray("Sv");
  vtkDataArray* uv = faces->GetPointData()->GetTCoords();
  vtkUnsignedCharArray* rgb = vtkUnsignedCharArray::SafeDownCast(faces->GetPointData()->GetArray("Colors"));
  if (np > 0 && (!normals || !su || !sv || !uv || !rgb || rgb->GetNumberOfComponents() != 3))
    throw std::runtime_error("the CAD reader's faces lack their point arrays");
  m.positions.resize(size_t(np));
  m.normals.resize(size_t(np));
  m.derivU.resize(size_t(np));
  m.derivV.resize(size_t(np));
  m.uvs.resize(size_t(np));
  m.colours.resize(size_t(np));
  for (vtkIdType i = 0; i < np; ++i) {
    double t[3];
    faces->GetPoint(i, t);
    m.positions[size_t(i)] = {t[0], t[1], t[2]};
    normals->GetTuple(i, t);
    m.normals[size_t(i)] = {t[0], t[1], t[2]};
    su->GetTuple(i, t);
    m.derivU[size_t(i)] = {t[0], t[1], t[2]};
    sv->GetTuple(i, t);
    m.derivV[size_t(i)] = {t[0], t[1], t[2]};
    uv->GetTuple(i, t);
    m.uvs[size_t(i)] = {t[0], t[1]};
    const unsigned char* c = rgb->GetPointer(3 * i);
    m.colours[size_t(i)] = {wf::srgbToLinear(float(c[0]) / 255.0f), wf::srgbToLinear(float(c[1]) / 255.0f),
                            wf::srgbToLinear(float(c[2]) / 255.0f)};
  }
  vtkDataArray* part = faces->GetCellData()->GetArray("PartId");
  vtkDataArray* face = faces->GetCellData()->GetArray("FaceId");
  vtkCellArray* polys = faces->GetPolys();
  vtkNew<vtkIdList> ids;
  m.triangles.reserve(size_t(polys->GetNumberOfCells()));
  vtkIdType cell = 0;
  for (polys->InitTraversal(); polys->GetNextCell(ids); ++cell)
    if (ids->GetNumberOfIds() == 3) {
      m.triangles.emplace_back(std::uint32_t(ids->GetId(0)), std::uint32_t(ids->GetId(1)), std::uint32_t(ids->GetId(2)));
      if (trianglePart) trianglePart->push_back(part ? int(part->GetTuple1(cell)) : 0);
      if (triangleFace) triangleFace->push_back(face ? int(face->GetTuple1(cell)) : 0);
    }
  return m;
}

/// The edges output of vtkWireFurCADReader (port 1) as polylines: the model's edges
/// (isoLines = false, cells of Kind 0) or its u and v iso lines (isoLines = true, Kind 1 and 2);
/// with `classes` and `angles`, each polyline's "EdgeClass" and "EdgeAngle" (render/edge_classes.h).
inline wf::PolylineSet edgesToPolylines(vtkPolyData* edges, bool isoLines, std::vector<wf::EdgeClass>* classes = nullptr,
                                        std::vector<float>* angles = nullptr) {
  wf::PolylineSet out;
  vtkDataArray* kind = edges->GetCellData()->GetArray("Kind");
  vtkDataArray* cls = edges->GetCellData()->GetArray("EdgeClass");
  vtkDataArray* ang = edges->GetCellData()->GetArray("EdgeAngle");
  vtkCellArray* lines = edges->GetLines();
  vtkNew<vtkIdList> ids;
  std::vector<glm::dvec3> line;
  vtkIdType cell = 0;
  for (lines->InitTraversal(); lines->GetNextCell(ids); ++cell) {
    if (((kind ? int(kind->GetTuple1(cell)) : 0) != 0) != isoLines) continue;
    line.clear();
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) {
      double q[3];
      edges->GetPoint(ids->GetId(k), q);
      line.emplace_back(q[0], q[1], q[2]);
    }
    out.add(line);
    if (classes) {
      const double c = cls ? cls->GetTuple1(cell) : 1.0;
      classes->push_back(c >= 0 && c <= 5 ? wf::EdgeClass(int(c)) : wf::EdgeClass::Sharp);
    }
    if (angles) angles->push_back(ang ? float(ang->GetTuple1(cell)) : std::numeric_limits<float>::quiet_NaN());
  }
  return out;
}

}  // namespace wfcad

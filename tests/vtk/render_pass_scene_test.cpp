// The render pass's conversion of marked actors (vtk_filters/wf_render_pass_scene.h) through the
// core's scene description and buildScene, without a window: where the actor's matrix puts
// points, normals and grain, how materials are numbered after a SetScene scene, and that an
// actor with nothing to draw adds nothing.
#include "wf_render_pass_scene.h"

#include "vtkWireFurRenderPass.h"

#include <vtkActor.h>
#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkIntArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>

#include <gtest/gtest.h>

#include <glm/glm.hpp>

namespace {

// One triangle in z = 0 with normals +z and tangents (1, 1, 0), marked as vtkWireFurBurnish
// output (field data WireFurGrain), and a line cell.
vtkSmartPointer<vtkPolyData> burnishedTriangle() {
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  pts->InsertNextPoint(0, 0, 0);
  pts->InsertNextPoint(1, 0, 0);
  pts->InsertNextPoint(0, 1, 0);
  pd->SetPoints(pts);
  vtkNew<vtkCellArray> polys, lines;
  const vtkIdType tri[3] = {0, 1, 2}, seg[2] = {0, 1};
  polys->InsertNextCell(3, tri);
  lines->InsertNextCell(2, seg);
  pd->SetPolys(polys);
  pd->SetLines(lines);
  vtkNew<vtkDoubleArray> n, t;
  n->SetNumberOfComponents(3);
  t->SetNumberOfComponents(3);
  t->SetName("Tangents");
  for (int i = 0; i < 3; ++i) {
    n->InsertNextTuple3(0, 0, 1);
    t->InsertNextTuple3(1, 1, 0);
  }
  pd->GetPointData()->SetNormals(n);
  pd->GetPointData()->SetTangents(t);
  vtkNew<vtkIntArray> grain;
  grain->SetName("WireFurGrain");
  grain->InsertNextValue(1);
  pd->GetFieldData()->AddArray(grain);
  return pd;
}

TEST(RenderPassScene, ActorMatrixPlacesPointsNormalsAndGrainThroughTheBuilder) {
  vtkSmartPointer<vtkPolyData> pd = burnishedTriangle();
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(pd);
  mapper->ScalarVisibilityOff();
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->SetScale(2.0, 1.0, 1.0);
  actor->SetPosition(10.0, 0.0, 0.0);

  // A SetScene scene with one material and one surface goes first.
  wf::Scene core;
  core.materials = {wf::Material{}};
  core.surfaces.push_back({"core", wf::TriangleMesh{}, 0});
  core.surfaces.back().mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  core.surfaces.back().mesh.triangles = {{0, 1, 2}};
  const wf::Scene s = wfvtk::assembleScene({wfvtk::convertActor(actor)}, &core);

  ASSERT_EQ(s.materials.size(), 3u);  // the core's, then the actor's surface and wire
  ASSERT_EQ(s.surfaces.size(), 2u);
  ASSERT_EQ(s.wires.size(), 1u);
  EXPECT_EQ(s.surfaces[0].name, "core");
  EXPECT_EQ(s.surfaces[1].material, 1);
  EXPECT_EQ(s.wires[0].material, 2);
  EXPECT_EQ(s.materials[1].burnish.grain, wf::Burnish::Grain::U);
  // VTK's default property has no specular: the presets' highlights (burnished 1 / 30, wire 0.5 / 40).
  EXPECT_EQ(s.materials[1].phong.specular, glm::dvec3(1.0));
  EXPECT_EQ(s.materials[2].phong.exponent, 40.0);

  // x' = 2 x + 10: exact in double.
  const wf::TriangleMesh& m = s.surfaces[1].mesh;
  ASSERT_EQ(m.positions.size(), 3u);
  EXPECT_EQ(m.positions[1], glm::dvec3(12, 0, 0));
  EXPECT_EQ(m.positions[2], glm::dvec3(10, 1, 0));
  EXPECT_EQ(s.wires[0].lines.points[1], glm::dvec3(12, 0, 0));
  // The normal by the cofactor (stays +z), the grain by the linear part: (1, 1, 0) -> (2, 1, 0).
  ASSERT_EQ(m.normals.size(), 3u);
  EXPECT_NEAR(glm::length(m.normals[0] - glm::dvec3(0, 0, 1)), 0.0, 1e-15);
  ASSERT_EQ(m.derivU.size(), 3u);
  EXPECT_NEAR(glm::length(m.derivU[0] - glm::dvec3(2, 1, 0)), 0.0, 1e-15);
  // dS/dv = A (N x T / |N x T|) = A (-1, 1, 0) / sqrt 2 = (-2, 1, 0) / sqrt 2, in the tangent plane.
  EXPECT_NEAR(glm::length(m.derivV[0] - glm::dvec3(-2, 1, 0) / std::sqrt(2.0)), 0.0, 1e-15);
  EXPECT_FALSE(s.camera.has_value());  // the pass sets the camera every frame
}

TEST(RenderPassScene, ActorWithNothingToDrawAddsNothing) {
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  pts->InsertNextPoint(0, 0, 0);
  pd->SetPoints(pts);
  vtkNew<vtkCellArray> verts;
  const vtkIdType v = 0;
  verts->InsertNextCell(1, &v);
  pd->SetVerts(verts);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(pd);
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  const wfvtk::ActorPiece piece = wfvtk::convertActor(actor);
  EXPECT_FALSE(piece.object.geometry);
  const wf::Scene s = wfvtk::assembleScene({piece});
  EXPECT_TRUE(s.surfaces.empty());
  EXPECT_TRUE(s.wires.empty());
  EXPECT_EQ(wfvtk::describeActors({piece}).objects.size(), 0u);
}

}  // namespace

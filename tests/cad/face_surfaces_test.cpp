// The exact faces handed out by the CAD module (wf_cad_plugin.h: wirefur_cad_face_surfaces) as
// the core's surface concept, and fur grown on them (the wirefur command's --style fur):
// a 40 x 30 plate, 5 thick, with a hole of radius 6 through it. The top face is a plane trimmed
// by the hole. Checked: the surface's S(u, v) is the face's plane and its normal points up; the
// trimming mask is 0 inside the hole and 1 on the face; hairs grown area-correct with the mask
// as density map root on the face only (no root inside the hole, none outside the plate), and
// their number matches density x the face's exact area (40 x 30 - pi 6^2).
#include "cad_fixtures.h"

#include "growth/fur.h"
#include "render/camera.h"
#include "surface/patches.h"
#include "surface/silhouette.h"
#include "wf_cad_plugin.h"

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <gp_Ax2.hxx>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <vector>

using namespace cadtest;

namespace {

constexpr double kPi = 3.14159265358979323846;

TopoDS_Shape plateWithHole() {
  const TopoDS_Shape plate = BRepPrimAPI_MakeBox(gp_Pnt(-20, -15, 0), 40, 30, 5).Shape();
  const TopoDS_Shape hole = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, -1), gp_Dir(0, 0, 1)), 6, 7).Shape();
  return BRepAlgoAPI_Cut(plate, hole).Shape();
}

}  // namespace

TEST(CadFaceSurfaces, TopFaceSurfaceMaskAndFur) {
  const Read r = readOk(writeBrep(plateWithHole(), "plate_hole.brep"));
  std::vector<WireFurCadFace> faces;
  ASSERT_EQ(wirefur_cad_face_surfaces(r.reader, &faces), r.reader->GetNumberOfMeshedFaces());
  ASSERT_EQ(faces.size(), 7u);  // 6 planes and the hole's cylinder
  // The top face: the one whose surface sits at z = 5 with its normal up.
  const WireFurCadFace* top = nullptr;
  for (const WireFurCadFace& f : faces) {
    const wf::ParameterDomain d = f.surface->domain();
    const wf::SurfaceFrame fr = f.surface->frame(0.5 * (d.u0 + d.u1), 0.5 * (d.v0 + d.v1));
    if (std::abs(fr.P.z - 5.0) < 1e-9 && fr.N.z > 0.999) top = &f;
  }
  ASSERT_NE(top, nullptr);
  const wf::ParameterDomain d = top->surface->domain();
  // S(u, v) on the plane z = 5 everywhere in the domain (1e-12), normal exactly +z.
  for (double s : {0.0, 0.3, 1.0})
    for (double t : {0.0, 0.7, 1.0}) {
      const glm::dvec2 uv = d.fromUnit(s, t);
      const wf::SurfaceFrame fr = top->surface->frame(uv.x, uv.y);
      EXPECT_NEAR(fr.P.z, 5.0, 1e-12);
      EXPECT_NEAR(fr.N.z, 1.0, 1e-12);
    }
  // The mask: find (s, t) of the hole's centre and of a point near a corner of the plate by
  // searching the domain for the (u, v) that lands there (a plane: S is affine in (u, v)).
  auto stOf = [&](double x, double y) {
    const wf::SurfacePoint o = top->surface->evaluate(d.u0, d.v0);
    const glm::dvec3 a = o.Su, b = o.Sv, q(x - o.P.x, y - o.P.y, 0.0);
    const double det = a.x * b.y - a.y * b.x;
    const double u = (q.x * b.y - q.y * b.x) / det, v = (a.x * q.y - a.y * q.x) / det;
    return d.toUnit(d.u0 + u, d.v0 + v);
  };
  EXPECT_EQ(top->inside->value(stOf(0, 0)), 0.0);     // the hole's centre
  EXPECT_EQ(top->inside->value(stOf(0, 5.9)), 0.0);   // just inside the hole's rim
  EXPECT_EQ(top->inside->value(stOf(0, 6.5)), 1.0);   // just outside it
  EXPECT_EQ(top->inside->value(stOf(19, 14)), 1.0);   // near a corner of the plate

  // Fur: area-correct, the mask as density map.
  wf::FurParams p;
  p.placement = wf::FurParams::Placement::AreaCorrect;
  p.density = 20.0;  // per unit area: about 21,700 hairs expected
  p.densityMap = top->inside;
  p.length = 1.0;
  p.lengthVariation = 0.0;
  const wf::Fur fur = wf::growFur(*top->surface, p, std::uint32_t(top->faceId));
  const double area = 40.0 * 30.0 - kPi * 36.0;
  const double expected = p.density * area;
  // Roots are placed by independent draws per cell: within 5 sigma of the expectation, plus
  // what cells cut by the rim may miss (their weight bound is sampled).
  EXPECT_NEAR(double(fur.hairs.polylineCount()), expected, 5 * std::sqrt(expected) + 0.01 * expected);
  size_t inHole = 0, offPlate = 0, notOnTop = 0, notUp = 0;
  for (size_t h = 0; h < fur.hairs.polylineCount(); ++h) {
    const glm::dvec3 root = fur.hairs.points[fur.hairs.starts[h]], tip = fur.hairs.points[fur.hairs.starts[h + 1] - 1];
    inHole += std::hypot(root.x, root.y) < 6.0 - 1e-9;
    offPlate += std::abs(root.x) > 20 + 1e-9 || std::abs(root.y) > 15 + 1e-9;
    notOnTop += std::abs(root.z - 5.0) > 1e-9;
    notUp += std::abs(tip.z - root.z - 1.0) > 1e-9;  // straight out along +z, length 1
  }
  EXPECT_EQ(inHole, 0u);
  EXPECT_EQ(offPlate, 0u);
  EXPECT_EQ(notOnTop, 0u);
  EXPECT_EQ(notUp, 0u);
}

// Silhouettes of OpenCASCADE's exact faces (surface/silhouette.h through wfcad::FaceSurface and
// its face mask), in perspective: a sphere, a cylinder and a torus made by OpenCASCADE. Every
// traced point lies on the true silhouette (N . (P - eye) = 0 with the analytic normal, to 1e-9
// of a cosine), and every drawn chord's midpoint lies within 0.25 px on screen of the same
// shape's silhouette traced on the analytic patch at 0.002 px (the cylinder's are straight).
// (An OpenCASCADE face clamps (u, v) beyond its periodic domain where the patches wrap it: the
// tracer's curves unwrapped across the seam then took points at the seam, 39 px off on the torus,
// until the tracer wrapped them itself.)
TEST(CadFaceSurfaces, SilhouettesOfExactFacesLieOnTheTrueSilhouette) {
  wf::Camera c;
  c.eye = {95.0, -130.0, 70.0};
  c.target = {0.0, 0.0, 0.0};
  c.up = {0, 0, 1};
  c.fovYDegrees = 30;
  c.nearPlane = 1;
  c.farPlane = 1000;
  const wf::ViewTransform v = wf::ViewTransform::make(c, 800, 600);
  struct Case {
    const char* name;
    TopoDS_Shape shape;
    std::function<glm::dvec3(const glm::dvec3&)> normal;  // analytic outward normal
    std::shared_ptr<wf::Surface> patch;                  // the same shape analytically (null: straight lines)
  };
  const double R = 30, r = 10;
  std::vector<Case> cases;
  cases.push_back({"sphere", BRepPrimAPI_MakeSphere(R).Shape(), [](const glm::dvec3& p) { return glm::normalize(p); },
                   std::make_shared<wf::SpherePatch>(R)});
  cases.push_back({"cylinder", BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, -20), gp_Dir(0, 0, 1)), R, 40).Shape(),
                   [](const glm::dvec3& p) { return glm::normalize(glm::dvec3(p.x, p.y, 0.0)); }, nullptr});
  cases.push_back({"torus", BRepPrimAPI_MakeTorus(R, r).Shape(),
                   [&](const glm::dvec3& p) {
                     const glm::dvec3 q = glm::normalize(glm::dvec3(p.x, p.y, 0.0)) * R;
                     return glm::normalize(p - q);
                   },
                   std::make_shared<wf::TorusPatch>(R, r)});
  for (const Case& k : cases) {
    const Read rd = readOk(writeBrep(k.shape, std::string("sil_") + k.name + ".brep"));
    std::vector<WireFurCadFace> faces;
    ASSERT_GT(wirefur_cad_face_surfaces(rd.reader, &faces), 0);
    wf::PolylineSet lines;
    wf::SilhouetteStats st;
    for (const WireFurCadFace& f : faces) wf::traceSilhouette(*f.surface, f.inside.get(), v, wf::SilhouetteOptions{}, lines, st);
    EXPECT_GT(st.curves, 0u) << k.name;
    EXPECT_EQ(st.nonFinite, 0u) << k.name;
    double worstCos = 0;
    for (const glm::dvec3& p : lines.points) {
      const glm::dvec3 n = k.normal(p);
      const double curved = std::abs(n.z) < 0.999 || k.patch;  // the cylinder's caps have none
      if (curved) worstCos = std::max(worstCos, std::abs(glm::dot(n, glm::normalize(v.eye - p))));
    }
    EXPECT_LT(worstCos, 1e-9) << k.name;
    if (!k.patch) continue;
    wf::SilhouetteOptions fine;
    fine.tolerancePx = 0.002;
    fine.grid = 256;
    fine.maxDepth = 20;
    wf::PolylineSet ref;
    wf::SilhouetteStats rs;
    wf::traceSilhouette(*k.patch, nullptr, v, fine, ref, rs);
    std::vector<glm::dvec2> rp;
    for (const glm::dvec3& p : ref.points) rp.push_back(v.project(v.toEye(p)));
    double worst = 0;
    for (size_t i = 0; i < lines.polylineCount(); ++i)
      for (std::uint32_t q = lines.starts[i]; q + 1 < lines.starts[i + 1]; ++q) {
        const glm::dvec2 m = 0.5 * (v.project(v.toEye(lines.points[q])) + v.project(v.toEye(lines.points[q + 1])));
        double best = INFINITY;
        for (size_t j = 0; j < ref.polylineCount(); ++j)
          for (std::uint32_t t = ref.starts[j]; t + 1 < ref.starts[j + 1]; ++t) {
            const glm::dvec2 a = rp[t], d = rp[t + 1] - rp[t];
            const double l2 = glm::dot(d, d);
            const double u = l2 > 0 ? std::clamp(glm::dot(m - a, d) / l2, 0.0, 1.0) : 0.0;
            best = std::min(best, glm::length(m - (a + u * d)));
          }
        worst = std::max(worst, best);
      }
    EXPECT_LT(worst, 0.25) << k.name;
    std::printf("[ measured ] OpenCASCADE %s: %zu curves, %zu points, worst chord %.3f px from the analytic silhouette\n", k.name,
                st.curves, st.points, worst);
  }
}

// FacesOnly (the wirefur command's second, in-process read): every face of the plate with a hole,
// with the FaceIds of a full update and the same surfaces (S at the domain's centre to 1e-12),
// nothing meshed and both outputs empty.
TEST(CadFaceSurfaces, FacesOnlyGivesTheSameFacesWithoutMeshing) {
  const std::string path = writeBrep(plateWithHole(), "plate_hole_faces_only.brep");
  const Read full = readOk(path);
  std::vector<WireFurCadFace> a, b;
  ASSERT_EQ(wirefur_cad_face_surfaces(full.reader, &a), 7);
  vtkNew<vtkWireFurCADReader> reader;
  reader->SetFileName(path.c_str());
  reader->FacesOnlyOn();
  reader->Update();
  EXPECT_EQ(reader->GetErrorMessage(), "");
  EXPECT_EQ(reader->GetOutput(0)->GetNumberOfCells(), 0);
  EXPECT_EQ(reader->GetOutput(1)->GetNumberOfCells(), 0);
  EXPECT_EQ(reader->GetNumberOfFaces(), 7);
  ASSERT_EQ(wirefur_cad_face_surfaces(reader, &b), 7);
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].faceId, b[i].faceId);
    const wf::ParameterDomain d = a[i].surface->domain();
    const double u = 0.5 * (d.u0 + d.u1), v = 0.5 * (d.v0 + d.v1);
    EXPECT_LT(glm::length(a[i].surface->frame(u, v).P - b[i].surface->frame(u, v).P), 1e-12);
  }
}

// vtkWireFurTangentShading: tangents of analytic curves, shading against the core's own map and
// exact cylinder integral, the map rebuilt only when the lights move relative to the camera, the
// lights of a vtkRenderer, NaN / Inf and empty input, and the sRGB colour array.
#include "vtkWireFurTangentShading.h"

#include "core/srgb.h"

#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkFloatArray.h"
#include "vtkLight.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include "core/srgb.h"
#include "shading/cylinder_shading.h"
#include "shading/light.h"
#include "shading/pseudo_reflectance_map.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

// Float storage of a unit vector: each component is rounded to within 2^-24 relative, so a
// component is within 2^-24 < 6e-8 of the double value; 2.5e-7 leaves room for the double
// arithmetic before it (about 1e-15).
constexpr double kFloatTol = 2.5e-7;

vtkSmartPointer<vtkPolyData> makePolyline(const std::vector<glm::dvec3>& pts, bool closed)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (const glm::dvec3& p : pts)
  {
    points->InsertNextPoint(p.x, p.y, p.z);
  }
  vtkNew<vtkCellArray> lines;
  lines->InsertNextCell(vtkIdType(pts.size() + (closed ? 1 : 0)));
  for (vtkIdType i = 0; i < vtkIdType(pts.size()); ++i)
  {
    lines->InsertCellPoint(i);
  }
  if (closed)
  {
    lines->InsertCellPoint(0);
  }
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(points);
  pd->SetLines(lines);
  return pd;
}

glm::dmat3 eyeFromWorld(vtkCamera* camera)
{
  vtkMatrix4x4* m = camera->GetViewTransformMatrix();
  glm::dmat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      r[j][i] = m->GetElement(i, j);
  return r;
}

glm::dvec3 tuple3(vtkDataArray* a, vtkIdType i)
{
  double t[3];
  a->GetTuple(i, t);
  return { t[0], t[1], t[2] };
}

double maxAbs(const glm::dvec3& d)
{
  return std::max({ std::abs(d.x), std::abs(d.y), std::abs(d.z) });
}

// A camera looking at the scene from an oblique direction (dyadic coordinates: moving it by a
// dyadic offset leaves its rotation bit for bit the same).
void obliqueCamera(vtkCamera* camera)
{
  camera->SetPosition(3.0, -4.0, 6.0);
  camera->SetFocalPoint(0.5, 0.25, -0.5);
  camera->SetViewUp(0.25, 1.0, 0.125);
  camera->OrthogonalizeViewUp();
}

// A helix: tangents of every direction relative to an oblique camera.
std::vector<glm::dvec3> helix(int n)
{
  std::vector<glm::dvec3> pts;
  for (int i = 0; i < n; ++i)
  {
    const double t = 0.37 * i;
    pts.emplace_back(std::cos(t), std::sin(t), 0.15 * t);
  }
  return pts;
}

// The filter's tangent rule, written out for an open polyline: the normalised sum of the unit
// incoming and outgoing directions, one-sided at the ends.
std::vector<glm::dvec3> averagedTangents(const std::vector<glm::dvec3>& p)
{
  std::vector<glm::dvec3> t(p.size());
  for (size_t i = 0; i < p.size(); ++i)
  {
    glm::dvec3 s(0.0);
    if (i > 0) s += glm::normalize(p[i] - p[i - 1]);
    if (i + 1 < p.size()) s += glm::normalize(p[i + 1] - p[i]);
    t[i] = glm::normalize(s);
  }
  return t;
}

wf::PhongMaterial filterMaterial(vtkWireFurTangentShading* f)
{
  wf::PhongMaterial m;
  m.diffuse = glm::dvec3(f->GetDiffuse()[0], f->GetDiffuse()[1], f->GetDiffuse()[2]);
  m.specular = glm::dvec3(f->GetSpecular()[0], f->GetSpecular()[1], f->GetSpecular()[2]);
  m.exponent = f->GetExponent();
  return m.sanitized();
}

class MessageCounter : public vtkCommand
{
public:
  static MessageCounter* New() { return new MessageCounter; }
  void Execute(vtkObject*, unsigned long event, void* data) override
  {
    (event == vtkCommand::WarningEvent ? warnings : errors)++;
    last = data ? static_cast<const char*>(data) : "";
  }
  int warnings = 0, errors = 0;
  std::string last;
};

void observe(vtkObject* o, MessageCounter* counter)
{
  o->AddObserver(vtkCommand::WarningEvent, counter);
  o->AddObserver(vtkCommand::ErrorEvent, counter);
}

} // namespace

// A regular N-gon inscribed in a circle in the view plane: at a vertex the sum of the two unit
// edge directions is, by symmetry, exactly the circle's tangent there (no chord error at the
// vertices), so the eye tangent must be (-sin a, cos a, 0) up to the float storage (kFloatTol).
// At the ends of the same polygon left open the tangent is one-sided: the chord direction, off
// the circle's tangent by half the angle step pi / N (the chord error), which is checked too.
TEST(VtkTangentShading, CircleInViewPlaneHasTheCircleTangent)
{
  vtkNew<vtkCamera> camera;
  obliqueCamera(camera);
  const glm::dmat3 r = eyeFromWorld(camera);
  const glm::dmat3 worldFromEye = glm::transpose(r);
  const glm::dvec3 right = worldFromEye[0], up = worldFromEye[1], centre(0.5, 0.25, -0.5);
  const int n = 24;
  const double radius = 2.0;
  std::vector<glm::dvec3> pts;
  for (int i = 0; i < n; ++i)
  {
    const double a = 2.0 * std::numbers::pi * i / n;
    pts.push_back(centre + radius * (std::cos(a) * right + std::sin(a) * up));
  }
  for (bool closed : { true, false })
  {
    vtkNew<vtkWireFurTangentShading> filter;
    filter->SetInputData(makePolyline(pts, closed));
    filter->SetCamera(camera);
    filter->Update();
    vtkPolyData* out = filter->GetOutput();
    auto* eyeT = vtkFloatArray::SafeDownCast(out->GetPointData()->GetArray("EyeTangents"));
    ASSERT_NE(eyeT, nullptr);
    vtkDataArray* worldT = out->GetPointData()->GetTangents();
    ASSERT_NE(worldT, nullptr);
    EXPECT_STREQ(worldT->GetName(), "Tangents");
    EXPECT_EQ(worldT->GetDataType(), VTK_FLOAT);
    for (int i = 0; i < n; ++i)
    {
      const double a = 2.0 * std::numbers::pi * i / n;
      const glm::dvec3 expectEye(-std::sin(a), std::cos(a), 0.0);
      const bool end = !closed && (i == 0 || i == n - 1);
      if (end)
      {
        // One-sided: the chord, pi / N from the tangent.
        const double angle = std::acos(std::clamp(glm::dot(tuple3(eyeT, i), expectEye), -1.0, 1.0));
        EXPECT_NEAR(angle, std::numbers::pi / n, 1e-6) << "open end " << i;
        continue;
      }
      EXPECT_LE(maxAbs(tuple3(eyeT, i) - expectEye), kFloatTol) << (closed ? "closed " : "open ") << i;
      EXPECT_LE(maxAbs(tuple3(worldT, i) - (-std::sin(a) * right + std::cos(a) * up)), kFloatTol) << i;
    }
    EXPECT_EQ(filter->GetDegeneratePoints(), 0);
  }
}

// A straight line along the view axis is seen end-on: eye tangent (0, 0, -1) (the line runs
// away from the viewer), shaded as the map's end-on value.
// The input's "Colors" (the fur generator's) replace the diffuse colour and multiply the
// radiance: a red-to-blue line with the copper default is the same line shaded with a grey
// diffuse of copper's largest component, times its colours (decoded from sRGB).
TEST(VtkTangentShading, InputColoursReplaceTheDiffuseColour)
{
  const std::vector<glm::dvec3> pts = { { -1, 0, 0 }, { 0, 0.3, 0.2 }, { 1, 0.1, -0.3 } };
  vtkSmartPointer<vtkPolyData> coloured = makePolyline(pts, false);
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetName("Colors");
  colors->SetNumberOfComponents(3);
  const unsigned char rgb[3][3] = { { 255, 0, 0 }, { 128, 128, 128 }, { 0, 0, 255 } };
  for (const auto& c : rgb)
    colors->InsertNextTypedTuple(c);
  coloured->GetPointData()->AddArray(colors);
  vtkNew<vtkWireFurTangentShading> a;
  a->SetInputData(coloured);
  a->Update();
  double d[3];
  a->GetDiffuse(d);
  vtkNew<vtkWireFurTangentShading> b;
  b->SetInputData(makePolyline(pts, false));
  const double grey = std::max({ d[0], d[1], d[2] });
  b->SetDiffuse(grey, grey, grey);
  b->Update();
  vtkDataArray* ra = a->GetOutput()->GetPointData()->GetArray("ShadedRadiance");
  vtkDataArray* rb = b->GetOutput()->GetPointData()->GetArray("ShadedRadiance");
  for (vtkIdType i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k)
    {
      const double c = wf::srgbToLinear(float(rgb[i][k]) / 255.0f);
      EXPECT_NEAR(ra->GetComponent(i, k), rb->GetComponent(i, k) * c, 1e-6) << i << " " << k;
    }
  EXPECT_GT(rb->GetComponent(1, 0), 0.01);  // lit
}

TEST(VtkTangentShading, LineAlongViewAxisIsEndOn)
{
  vtkNew<vtkCamera> camera;
  obliqueCamera(camera);
  double dop[3];
  camera->GetDirectionOfProjection(dop);
  const glm::dvec3 d(dop[0], dop[1], dop[2]), f(0.5, 0.25, -0.5);
  std::vector<glm::dvec3> pts;
  for (int i = 0; i < 5; ++i)
  {
    pts.push_back(f + (0.3 * i - 0.6) * d);
  }
  vtkNew<vtkWireFurTangentShading> filter;
  filter->SetInputData(makePolyline(pts, false));
  filter->SetCamera(camera);
  filter->Update();
  vtkPointData* pd = filter->GetOutput()->GetPointData();
  vtkDataArray* eyeT = pd->GetArray("EyeTangents");
  vtkDataArray* rad = pd->GetArray("ShadedRadiance");
  wf::PseudoReflectanceMap map;
  map.build(filterMaterial(filter), [] {
    wf::LightRig rig = wf::LightRig::studioRig(3);
    rig.ambient = glm::dvec3(0.05);
    return rig.canonical();
  }());
  for (int i = 0; i < 5; ++i)
  {
    // 3e-7: the direction of projection is stored in double but normalised by VTK separately.
    EXPECT_LE(maxAbs(tuple3(eyeT, i) - glm::dvec3(0.0, 0.0, -1.0)), 3e-7) << i;
    EXPECT_LE(maxAbs(tuple3(rad, i) - glm::dvec3(map.endOnValue())), 1e-6) << i;
  }
}

// ShadedRadiance is the core's PseudoReflectanceMap lookup at the eye tangent, for the same
// material, lights and options (1e-6: float storage of values below 2). Non-default material,
// light count, ambient and map options are passed through.
TEST(VtkTangentShading, RadianceIsTheCoresMapLookup)
{
  vtkNew<vtkCamera> camera;
  obliqueCamera(camera);
  const std::vector<glm::dvec3> pts = helix(60);
  vtkNew<vtkWireFurTangentShading> filter;
  filter->SetShadingToMaps();  // the map path
  filter->SetInputData(makePolyline(pts, false));
  filter->SetCamera(camera);
  filter->SetDiffuse(0.3, 0.5, 0.7);
  filter->SetSpecular(0.8, 0.9, 1.0);
  filter->SetExponent(50);
  filter->SetLightCount(5);
  filter->SetAmbient(0.1, 0.1, 0.1);
  filter->SetMapResolution(96);
  filter->SetMapSamples(48);
  filter->Update();
  EXPECT_EQ(filter->GetMapBuilds(), 1);

  wf::LightRig rig = wf::LightRig::studioRig(5);
  rig.ambient = glm::dvec3(0.1);
  wf::PseudoReflectanceMapOptions o;
  o.resolution = 96;
  o.samples = 48;
  wf::PseudoReflectanceMap map;
  map.build(filterMaterial(filter), rig.canonical(), o);

  const glm::dmat3 r = eyeFromWorld(camera);
  const std::vector<glm::dvec3> t = averagedTangents(pts);
  vtkPointData* pd = filter->GetOutput()->GetPointData();
  vtkDataArray* eyeT = pd->GetArray("EyeTangents");
  vtkDataArray* rad = pd->GetArray("ShadedRadiance");
  ASSERT_EQ(rad->GetDataType(), VTK_FLOAT);
  double worst = 0;
  for (size_t i = 0; i < pts.size(); ++i)
  {
    const glm::dvec3 te = glm::normalize(r * t[i]);
    EXPECT_LE(maxAbs(tuple3(eyeT, i) - te), kFloatTol) << i;
    worst = std::max(worst, maxAbs(tuple3(rad, i) - glm::dvec3(map.lookup(te))));
  }
  EXPECT_LE(worst, 1e-6);
}

// ExactShading, and the default closed path: each point is cylinderRadianceExact (the quadrature
// over the normals) at its own view vector (perspective: from the point to the eye; parallel
// projection: (0, 0, 1)), 1e-6; no map is built; the closed path's bound is its lobe table's.
TEST(VtkTangentShading, ExactShadingIsTheExactCylinderIntegral)
{
  for (int mode = 0; mode < 4; ++mode)
  {
    const bool parallel = mode & 1, closed = mode & 2;
    vtkNew<vtkCamera> camera;
    obliqueCamera(camera);
    camera->SetParallelProjection(parallel);
    const std::vector<glm::dvec3> pts = helix(40);
    vtkNew<vtkWireFurTangentShading> filter;
    filter->SetInputData(makePolyline(pts, false));
    filter->SetCamera(camera);
    filter->SetExponent(80);
    if (!closed)
    {
      filter->ExactShadingOn();
    }
    filter->Update();
    EXPECT_EQ(filter->GetMapBuilds(), 0);
    if (closed)
    {
      EXPECT_GT(filter->GetErrorEstimate(), 0.0);
      EXPECT_LT(filter->GetErrorEstimate(), 1e-8);
      EXPECT_LT(filter->GetMeasuredError(), 1e-6);
    }
    else
    {
      EXPECT_EQ(filter->GetErrorEstimate(), 0.0);
    }

    wf::LightRig rig = wf::LightRig::studioRig(3);
    rig.ambient = glm::dvec3(0.05);
    rig = rig.canonical();
    const glm::dmat3 r = eyeFromWorld(camera);
    double e[3];
    camera->GetPosition(e);
    const glm::dvec3 eye(e[0], e[1], e[2]);
    const std::vector<glm::dvec3> t = averagedTangents(pts);
    vtkDataArray* rad = filter->GetOutput()->GetPointData()->GetArray("ShadedRadiance");
    double worst = 0, perspectiveEffect = 0;
    for (size_t i = 0; i < pts.size(); ++i)
    {
      const glm::dvec3 te = glm::normalize(r * t[i]);
      const glm::dvec3 v = parallel ? glm::dvec3(0, 0, 1) : glm::normalize(-(r * (pts[i] - eye)));
      const glm::dvec3 expect = wf::cylinderRadianceExact(te, v, filterMaterial(filter), rig, 1e-10);
      worst = std::max(worst, maxAbs(tuple3(rad, i) - expect));
      perspectiveEffect = std::max(perspectiveEffect,
        maxAbs(expect - wf::cylinderRadianceExact(te, glm::dvec3(0, 0, 1), filterMaterial(filter), rig, 1e-10)));
    }
    EXPECT_LE(worst, 1e-6) << (parallel ? "parallel" : "perspective");
    // The perspective test is only a test if the true view vector matters for these points.
    if (!parallel)
    {
      EXPECT_GT(perspectiveEffect, 1e-3);
    }
  }
}

// The three paths on one filter: switching re-executes and gives each path's own output (closed
// and exact within 1e-6, the map visibly different under this perspective camera); going back to
// maps reuses the map; SetShadingToExact and ExactShadingOn agree; a new exponent changes the
// closed output as the exact path says.
TEST(VtkTangentShading, ShadingPathsSwitchOnOneFilter)
{
  vtkNew<vtkCamera> camera;
  obliqueCamera(camera);
  vtkNew<vtkWireFurTangentShading> filter;
  filter->SetInputData(makePolyline(helix(60), false));
  filter->SetCamera(camera);
  filter->SetExponent(50);
  auto radiance = [&] {
    filter->Update();
    vtkDataArray* rad = filter->GetOutput()->GetPointData()->GetArray("ShadedRadiance");
    std::vector<glm::dvec3> out;
    for (vtkIdType i = 0; i < rad->GetNumberOfTuples(); ++i)
      out.push_back(tuple3(rad, i));
    return out;
  };
  auto worst = [](const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b) {
    double w = 0.0;
    for (size_t i = 0; i < a.size(); ++i)
      w = std::max(w, maxAbs(a[i] - b[i]));
    return w;
  };
  const std::vector<glm::dvec3> closed = radiance();
  EXPECT_EQ(filter->GetMapBuilds(), 0);
  filter->SetShadingToExact();
  const std::vector<glm::dvec3> exact = radiance();
  EXPECT_EQ(filter->GetErrorEstimate(), 0.0);
  filter->SetShadingToMaps();
  const std::vector<glm::dvec3> maps = radiance();
  EXPECT_EQ(filter->GetMapBuilds(), 1);
  EXPECT_LE(worst(closed, exact), 1e-6);
  EXPECT_GT(worst(maps, exact), 1e-3);
  filter->SetShadingToClosed();
  EXPECT_LE(worst(radiance(), closed), 0.0);
  filter->SetShadingToMaps();
  EXPECT_LE(worst(radiance(), maps), 0.0);
  EXPECT_EQ(filter->GetMapBuilds(), 1);  // the same map
  filter->SetShadingToClosed();
  filter->ExactShadingOn();
  EXPECT_LE(worst(radiance(), exact), 0.0);
  filter->ExactShadingOff();
  filter->SetExponent(7.5);
  const std::vector<glm::dvec3> closed75 = radiance();
  filter->SetShadingToExact();
  EXPECT_LE(worst(closed75, radiance()), 1e-6);
  EXPECT_GT(worst(closed75, closed), 1e-3);
}

// The error estimate: positive, below the core's documented bound for the default map
// (2e-3, pseudo_reflectance_map.h), larger for a coarse map, and representative: on tangents
// other than its own test set the map's error stays within twice the estimate.
TEST(VtkTangentShading, ErrorEstimateMeasuresTheMap)
{
  vtkNew<vtkCamera> camera;
  obliqueCamera(camera);
  const std::vector<glm::dvec3> pts = helix(80);
  vtkNew<vtkWireFurTangentShading> filter;
  filter->SetShadingToMaps();  // the map path
  filter->SetInputData(makePolyline(pts, false));
  filter->SetCamera(camera);
  filter->Update();
  const double fine = filter->GetErrorEstimate();
  EXPECT_GT(fine, 0.0);
  EXPECT_LT(fine, 2e-3);
  EXPECT_GE(filter->GetMapSeconds(), 0.0);

  wf::LightRig rig = wf::LightRig::studioRig(3);
  rig.ambient = glm::dvec3(0.05);
  rig = rig.canonical();
  vtkDataArray* eyeT = filter->GetOutput()->GetPointData()->GetArray("EyeTangents");
  vtkDataArray* rad = filter->GetOutput()->GetPointData()->GetArray("ShadedRadiance");
  double observed = 0;
  for (vtkIdType i = 0; i < vtkIdType(pts.size()); ++i)
  {
    const glm::dvec3 expect =
      wf::cylinderRadianceExact(tuple3(eyeT, i), glm::dvec3(0, 0, 1), filterMaterial(filter), rig, 1e-10);
    observed = std::max(observed, maxAbs(tuple3(rad, i) - expect));
  }
  EXPECT_LE(observed, 2.0 * fine);

  // The exact path reports 0; back on the same map, the map's error again (no rebuild).
  filter->ExactShadingOn();
  filter->Update();
  EXPECT_EQ(filter->GetErrorEstimate(), 0.0);
  filter->ExactShadingOff();
  filter->Update();
  EXPECT_EQ(filter->GetMapBuilds(), 1);
  EXPECT_EQ(filter->GetErrorEstimate(), fine);

  filter->SetMapResolution(16);
  filter->Update();
  EXPECT_EQ(filter->GetMapBuilds(), 2);
  EXPECT_GT(filter->GetErrorEstimate(), fine);
}

// Scene lights are fixed in the world: the map is rebuilt when the camera rotates, not when it
// only moves (dyadic offsets keep the rotation bit for bit), and not when nothing changed. The
// light reaches the map as Intensity * DiffuseColor along R (position - focal point).
TEST(VtkTangentShading, SceneLightsRebuildTheMapOnlyWhenTheCameraRotates)
{
  vtkNew<vtkCamera> camera;
  obliqueCamera(camera);
  vtkNew<vtkRenderer> renderer;
  renderer->SetActiveCamera(camera);
  vtkNew<vtkLight> light;
  light->SetLightTypeToSceneLight();
  light->SetPosition(2.0, 3.0, 1.0);
  light->SetFocalPoint(0.0, 0.0, 0.0);
  light->SetIntensity(0.8);
  light->SetDiffuseColor(1.0, 0.9, 0.7);
  renderer->AddLight(light);
  vtkNew<vtkLight> off;
  off->SetLightTypeToSceneLight();
  off->SwitchOff();
  renderer->AddLight(off);

  const std::vector<glm::dvec3> pts = helix(30);
  vtkNew<vtkWireFurTangentShading> filter;
  filter->SetShadingToMaps();  // the map path
  filter->SetInputData(makePolyline(pts, false));
  filter->SetRenderer(renderer); // no SetCamera: the renderer's active camera
  filter->Update();
  EXPECT_EQ(filter->GetMapBuilds(), 1);

  auto checkAgainstCore = [&](const char* what) {
    const glm::dmat3 r = eyeFromWorld(camera);
    wf::LightRig rig;
    rig.ambient = glm::dvec3(0.05);
    rig.lights.push_back({ r * glm::dvec3(2.0, 3.0, 1.0), 0.8 * glm::dvec3(1.0, 0.9, 0.7) });
    wf::PseudoReflectanceMap map;
    map.build(filterMaterial(filter), rig.canonical());
    vtkDataArray* eyeT = filter->GetOutput()->GetPointData()->GetArray("EyeTangents");
    vtkDataArray* rad = filter->GetOutput()->GetPointData()->GetArray("ShadedRadiance");
    double worst = 0;
    for (vtkIdType i = 0; i < vtkIdType(pts.size()); ++i)
    {
      // Looked up at the stored (float) tangent: within 1e-5 of the filter's double one.
      worst = std::max(worst, maxAbs(tuple3(rad, i) - glm::dvec3(map.lookup(tuple3(eyeT, i)))));
    }
    EXPECT_LE(worst, 1e-5) << what;
  };
  checkAgainstCore("initial");

  const vtkMTimeType before = filter->GetOutput()->GetMTime();
  filter->Update(); // nothing changed: not even executed
  EXPECT_EQ(filter->GetOutput()->GetMTime(), before);

  double p[3], f[3];
  camera->GetPosition(p);
  camera->GetFocalPoint(f);
  camera->SetPosition(p[0] + 0.5, p[1] + 1.0, p[2] - 2.0);
  camera->SetFocalPoint(f[0] + 0.5, f[1] + 1.0, f[2] - 2.0);
  filter->Update();
  EXPECT_GT(filter->GetOutput()->GetMTime(), before); // executed again (the camera changed) ...
  EXPECT_EQ(filter->GetMapBuilds(), 1);               // ... but the lights did not move in eye space

  camera->Azimuth(25.0);
  filter->Update();
  EXPECT_EQ(filter->GetMapBuilds(), 2);
  checkAgainstCore("after azimuth");

  light->SetPosition(-1.0, 2.0, 2.0); // the light itself moves
  filter->Update();
  EXPECT_EQ(filter->GetMapBuilds(), 3);

  filter->SetExponent(40); // the material changes
  filter->Update();
  EXPECT_EQ(filter->GetMapBuilds(), 4);
}

// A headlight and a camera light move with the camera: rotating it never rebuilds the map. The
// headlight shines along eye +z, a camera light along its own position - focal point.
TEST(VtkTangentShading, LightsFixedToTheCameraNeverRebuildTheMap)
{
  for (int type : { VTK_LIGHT_TYPE_HEADLIGHT, VTK_LIGHT_TYPE_CAMERA_LIGHT })
  {
    vtkNew<vtkCamera> camera;
    obliqueCamera(camera);
    vtkNew<vtkRenderer> renderer;
    vtkNew<vtkLight> light;
    light->SetLightType(type);
    light->SetPosition(1.0, 1.0, 2.0); // used by the camera light only
    light->SetFocalPoint(0.0, 0.0, 0.0);
    light->SetIntensity(0.7);
    renderer->AddLight(light);
    const std::vector<glm::dvec3> pts = helix(30);
    vtkNew<vtkWireFurTangentShading> filter;
    filter->SetShadingToMaps();  // the map path
    filter->SetInputData(makePolyline(pts, false));
    filter->SetCamera(camera);
    filter->SetRenderer(renderer);
    filter->Update();
    camera->Azimuth(30.0);
    filter->Update();
    camera->Elevation(-20.0);
    camera->OrthogonalizeViewUp();
    camera->Roll(10.0);
    filter->Update();
    EXPECT_EQ(filter->GetMapBuilds(), 1) << type;

    wf::LightRig rig;
    rig.ambient = glm::dvec3(0.05);
    rig.lights.push_back({ type == VTK_LIGHT_TYPE_HEADLIGHT ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 1, 2), glm::dvec3(0.7) });
    wf::PseudoReflectanceMap map;
    map.build(filterMaterial(filter), rig.canonical());
    vtkDataArray* eyeT = filter->GetOutput()->GetPointData()->GetArray("EyeTangents");
    vtkDataArray* rad = filter->GetOutput()->GetPointData()->GetArray("ShadedRadiance");
    double worst = 0;
    for (vtkIdType i = 0; i < vtkIdType(pts.size()); ++i)
      worst = std::max(worst, maxAbs(tuple3(rad, i) - glm::dvec3(map.lookup(tuple3(eyeT, i)))));
    EXPECT_LE(worst, 1e-5) << type;
  }
}

// A renderer with no lights and AutomaticLightCreation on shades with the white headlight of
// intensity 1 VTK would create; with it off, ambient only (the diffuse colour times ambient).
TEST(VtkTangentShading, RendererWithoutLights)
{
  vtkNew<vtkCamera> camera;
  obliqueCamera(camera);
  vtkNew<vtkRenderer> renderer;
  const std::vector<glm::dvec3> pts = helix(20);
  vtkNew<vtkWireFurTangentShading> filter;
  filter->SetShadingToMaps();  // the map path
  filter->SetInputData(makePolyline(pts, false));
  filter->SetCamera(camera);
  filter->SetRenderer(renderer);
  filter->Update();
  wf::LightRig rig;
  rig.ambient = glm::dvec3(0.05);
  rig.lights.push_back({ glm::dvec3(0, 0, 1), glm::dvec3(1.0) });
  wf::PseudoReflectanceMap map;
  map.build(filterMaterial(filter), rig.canonical());
  vtkDataArray* eyeT = filter->GetOutput()->GetPointData()->GetArray("EyeTangents");
  vtkDataArray* rad = filter->GetOutput()->GetPointData()->GetArray("ShadedRadiance");
  for (vtkIdType i = 0; i < vtkIdType(pts.size()); ++i)
    EXPECT_LE(maxAbs(tuple3(rad, i) - glm::dvec3(map.lookup(tuple3(eyeT, i)))), 1e-5) << i;

  renderer->AutomaticLightCreationOff(); // the filter sees the renderer's modification
  filter->Update();
  rad = filter->GetOutput()->GetPointData()->GetArray("ShadedRadiance");
  for (vtkIdType i = 0; i < vtkIdType(pts.size()); ++i)
    EXPECT_LE(maxAbs(tuple3(rad, i) - 0.05 * glm::dvec3(0.55, 0.1, 0.06)), 1e-7) << i;
}

// NaN and Inf points: one warning with the count, tangent (0, 0, 0) and black there, no NaN
// anywhere; points whose segments do not touch them (0, 1, 8) are bit for bit as without them, their
// neighbours fall back to the one-sided tangent of the segment they have left.
TEST(VtkTangentShading, NonFinitePointsAreBlackAndReported)
{
  vtkNew<vtkCamera> camera;
  obliqueCamera(camera);
  std::vector<glm::dvec3> clean = helix(9);
  std::vector<glm::dvec3> dirty = clean;
  dirty[3].y = std::numeric_limits<double>::quiet_NaN();
  dirty[6].z = std::numeric_limits<double>::infinity();

  vtkNew<vtkWireFurTangentShading> ref;
  ref->SetInputData(makePolyline(clean, false));
  ref->SetCamera(camera);
  ref->Update();
  // By default bad input is an error and an empty output.
  {
    vtkNew<vtkWireFurTangentShading> strict;
    vtkNew<MessageCounter> errors;
    observe(strict, errors);
    strict->SetInputData(makePolyline(dirty, false));
    strict->SetCamera(camera);
    strict->Update();
    EXPECT_EQ(errors->errors, 1);
    EXPECT_NE(errors->last.find("2 point"), std::string::npos) << errors->last;
    EXPECT_NE(errors->last.find("point 3"), std::string::npos) << errors->last;
    EXPECT_EQ(strict->GetOutput()->GetNumberOfPoints(), 0);
  }
  // SkipNonFinitePoints: the rest is shaded.
  vtkNew<vtkWireFurTangentShading> filter;
  vtkNew<MessageCounter> messages;
  observe(filter, messages);
  filter->SkipNonFinitePointsOn();
  filter->SetInputData(makePolyline(dirty, false));
  filter->SetCamera(camera);
  filter->Update();
  EXPECT_EQ(messages->warnings, 1);
  EXPECT_EQ(messages->errors, 0);
  EXPECT_NE(messages->last.find("2 point"), std::string::npos) << messages->last;
  EXPECT_EQ(filter->GetNonFinitePoints(), 2);
  EXPECT_EQ(filter->GetDegeneratePoints(), 0); // point 7 between the Inf point and the end keeps one segment

  vtkPointData* a = ref->GetOutput()->GetPointData();
  vtkPointData* b = filter->GetOutput()->GetPointData();
  for (const char* name : { "Tangents", "EyeTangents", "ShadedRadiance", "ShadedColor" })
  {
    for (vtkIdType i = 0; i < 9; ++i)
    {
      const glm::dvec3 v = tuple3(b->GetArray(name), i);
      EXPECT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)) << name << i;
      if (i == 3 || i == 6)
      {
        EXPECT_EQ(v, glm::dvec3(0.0)) << name << i;
      }
      else if (i == 0 || i == 1 || i == 8)
      {
        EXPECT_EQ(v, tuple3(a->GetArray(name), i)) << name << i;
      }
    }
  }
  // One-sided neighbours: point 2 has only the segment from 1, point 4 only the one to 5.
  vtkDataArray* t = b->GetArray("Tangents");
  EXPECT_LE(maxAbs(tuple3(t, 2) - glm::normalize(clean[2] - clean[1])), kFloatTol);
  EXPECT_LE(maxAbs(tuple3(t, 4) - glm::normalize(clean[5] - clean[4])), kFloatTol);
  EXPECT_LE(maxAbs(tuple3(t, 5) - glm::normalize(clean[5] - clean[4])), kFloatTol); // 5: 4->5 only
  EXPECT_LE(maxAbs(tuple3(t, 7) - glm::normalize(clean[8] - clean[7])), kFloatTol);
}

// Zero-length segments are skipped (a repeated point takes the tangent of the points around it);
// a point with no segment at all gets (0, 0, 0), is counted, and shades as seen end-on.
TEST(VtkTangentShading, ZeroLengthSegmentsAndDegeneratePoints)
{
  vtkNew<vtkCamera> camera;
  obliqueCamera(camera);
  std::vector<glm::dvec3> pts = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 5, 5, 5 } };
  vtkSmartPointer<vtkPolyData> pd = makePolyline({ pts[0], pts[1], pts[2], pts[3] }, false);
  pd->GetPoints()->InsertNextPoint(5, 5, 5); // point 4: in a cell of its own, repeated
  vtkIdType lone[2] = { 4, 4 };
  pd->GetLines()->InsertNextCell(2, lone);
  vtkNew<vtkWireFurTangentShading> filter;
  filter->SetInputData(pd);
  filter->SetCamera(camera);
  filter->Update();
  vtkDataArray* t = filter->GetOutput()->GetPointData()->GetTangents();
  const glm::dvec3 corner = glm::normalize(glm::dvec3(1, 1, 0));
  EXPECT_LE(maxAbs(tuple3(t, 1) - corner), kFloatTol);
  EXPECT_LE(maxAbs(tuple3(t, 2) - corner), kFloatTol);
  EXPECT_LE(maxAbs(tuple3(t, 0) - glm::dvec3(1, 0, 0)), kFloatTol);
  EXPECT_EQ(tuple3(t, 4), glm::dvec3(0.0));
  EXPECT_EQ(filter->GetDegeneratePoints(), 1);
  wf::LightRig rig = wf::LightRig::studioRig(3);
  rig.ambient = glm::dvec3(0.05);
  wf::PseudoReflectanceMap map;
  map.build(filterMaterial(filter), rig.canonical());
  EXPECT_LE(maxAbs(tuple3(filter->GetOutput()->GetPointData()->GetArray("ShadedRadiance"), 4) -
              glm::dvec3(map.endOnValue())),
    1e-7);
}

// A closed polyline wraps around, also past a zero-length segment at its seam: a square
// A B C D A' with A' = A in position (another id) and the cell closed by repeating A's id. A'
// looks past the zero-length A' -> A to A -> B, so both A and A' get the corner's bisector.
TEST(VtkTangentShading, ClosedPolylineWrapsPastAZeroLengthSeam)
{
  const std::vector<glm::dvec3> square = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 0, 0 } };
  vtkNew<vtkWireFurTangentShading> filter;
  filter->SetInputData(makePolyline(square, true));
  filter->Update();
  vtkDataArray* t = filter->GetOutput()->GetPointData()->GetTangents();
  const glm::dvec3 corner = glm::normalize(glm::dvec3(1, -1, 0)); // (0,-1,0) + (1,0,0)
  EXPECT_LE(maxAbs(tuple3(t, 0) - corner), kFloatTol);
  EXPECT_LE(maxAbs(tuple3(t, 4) - corner), kFloatTol);
  EXPECT_LE(maxAbs(tuple3(t, 2) - glm::normalize(glm::dvec3(-1, 1, 0))), kFloatTol);
  EXPECT_EQ(filter->GetDegeneratePoints(), 0);
}

// Separate two-point line cells sharing their points (as edges extracted from a mesh), every
// other one reversed: each cell's tangent joins a point's sum with the sign of the first, so a
// vertex of the regular polygon still gets the circle's tangent up to sign (kFloatTol), not the
// difference of its edges. Without a camera the default vtkCamera is used: eye = world here.
TEST(VtkTangentShading, LineCellsSharingPointsAverageAsAxes)
{
  const int n = 16;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (int i = 0; i < n; ++i)
  {
    const double a = 2.0 * std::numbers::pi * i / n;
    points->InsertNextPoint(std::cos(a), std::sin(a), 0.0);
  }
  vtkNew<vtkCellArray> lines;
  for (vtkIdType i = 0; i < n; ++i)
  {
    vtkIdType ids[2] = { i, (i + 1) % n };
    if (i % 2)
      std::swap(ids[0], ids[1]);
    lines->InsertNextCell(2, ids);
  }
  vtkNew<vtkPolyData> pd;
  pd->SetPoints(points);
  pd->SetLines(lines);
  vtkNew<vtkWireFurTangentShading> filter;
  filter->SetInputData(pd);
  filter->Update();
  vtkDataArray* eyeT = filter->GetOutput()->GetPointData()->GetArray("EyeTangents");
  for (int i = 0; i < n; ++i)
  {
    const double a = 2.0 * std::numbers::pi * i / n;
    const glm::dvec3 expect(-std::sin(a), std::cos(a), 0.0), got = tuple3(eyeT, i);
    EXPECT_LE(std::min(maxAbs(got - expect), maxAbs(got + expect)), kFloatTol) << i;
  }
}

// Empty input: empty output with the four arrays, a warning (the whole data set; a piece of a
// parallel pipeline would be silent), no error, no map built. Cells that name points the input
// does not have (with or without points) are an error and an empty output.
TEST(VtkTangentShading, EmptyInputIsAnEmptyOutputWithTheArrays)
{
  vtkNew<vtkPolyData> empty;
  vtkNew<vtkWireFurTangentShading> filter;
  vtkNew<MessageCounter> messages;
  observe(filter, messages);
  filter->SetInputData(empty);
  filter->Update();
  EXPECT_EQ(messages->errors, 0) << messages->last;  // a rank's empty piece is not an error
  EXPECT_EQ(messages->warnings, 1) << messages->last; // the whole data set empty: a warning
  EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
  for (const char* name : { "Tangents", "EyeTangents", "ShadedRadiance", "ShadedColor" })
  {
    EXPECT_NE(filter->GetOutput()->GetPointData()->GetArray(name), nullptr) << name;
  }
  EXPECT_EQ(filter->GetMapBuilds(), 0);

  for (const int points : { 0, 4 })
  {
    vtkNew<vtkPolyData> dangling;
    vtkNew<vtkPoints> pts;
    for (int i = 0; i < points; ++i)
      pts->InsertNextPoint(i, 0, 0);
    vtkNew<vtkCellArray> lines;
    const vtkIdType ids[2] = { 0, 100000 };
    lines->InsertNextCell(2, ids);
    dangling->SetPoints(pts);
    dangling->SetLines(lines);
    filter->SetInputData(dangling);
    filter->Update();
    EXPECT_EQ(messages->errors, points == 0 ? 1 : 2) << messages->last;
    EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 0);
  }
}

// ShadedColor is ShadedRadiance clamped and sRGB-encoded, checked without re-implementing the
// encoder: each 8-bit value c must decode (inverse sRGB) to an interval [c - 1/2, c + 1/2] / 255
// containing the radiance; radiance <= 0 gives 0 and >= 1 gives 255. A bright ambient and specular
// make sure both the clamped and the in-range cases occur. The array is the active scalars and a
// plain vtkPolyDataMapper maps it to those colours unchanged (alpha 255).
TEST(VtkTangentShading, ShadedColorIsTheSrgbEncodingOfShadedRadiance)
{
  auto decode = [](double e) { return wf::srgbToLinear(e); }; // core/srgb.h, in double
  vtkNew<vtkCamera> camera;
  obliqueCamera(camera);
  const std::vector<glm::dvec3> pts = helix(200);
  vtkNew<vtkWireFurTangentShading> filter;
  filter->SetInputData(makePolyline(pts, false));
  filter->SetCamera(camera);
  filter->SetSpecular(6.0, 6.0, 6.0);
  filter->SetDiffuse(0.01, 0.2, 0.6);
  filter->SetExponent(200);
  filter->SetAmbient(2.0, 2.0, 2.0); // ambient alone: (0.02, 0.4, 1.2), blue clamped
  filter->Update();
  vtkPointData* pd = filter->GetOutput()->GetPointData();
  auto* colour = vtkUnsignedCharArray::SafeDownCast(pd->GetScalars());
  ASSERT_NE(colour, nullptr);
  EXPECT_STREQ(colour->GetName(), "ShadedColor");
  ASSERT_EQ(colour->GetNumberOfComponents(), 3);
  vtkDataArray* rad = pd->GetArray("ShadedRadiance");
  int clamped = 0, inRange = 0;
  for (vtkIdType i = 0; i < colour->GetNumberOfTuples(); ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      const double r = rad->GetComponent(i, k);
      const int c = colour->GetValue(3 * i + k);
      if (r <= 0.0)
        EXPECT_EQ(c, 0);
      else if (r >= 1.0)
      {
        EXPECT_EQ(c, 255);
        ++clamped;
      }
      else
      {
        EXPECT_GE(r, decode((c - 0.5) / 255.0)) << i << " " << k;
        EXPECT_LE(r, decode((c + 0.5) / 255.0)) << i << " " << k;
        ++inRange;
      }
    }
  }
  EXPECT_GT(clamped, 0);
  EXPECT_GT(inRange, 0);

  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(filter->GetOutputPort());
  mapper->Update();
  vtkUnsignedCharArray* rgba = mapper->MapScalars(1.0);
  ASSERT_NE(rgba, nullptr);
  ASSERT_EQ(rgba->GetNumberOfComponents(), 4);
  for (vtkIdType i = 0; i < colour->GetNumberOfTuples(); ++i)
  {
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(rgba->GetValue(4 * i + k), colour->GetValue(3 * i + k));
    EXPECT_EQ(rgba->GetValue(4 * i + 3), 255);
  }

  std::ostringstream printed;
  filter->Print(printed);
  EXPECT_NE(printed.str().find("MapResolution: 128"), std::string::npos);
}

// The measured error of an output includes the perspective the map leaves out: for a wide
// perspective camera it exceeds the map's own error at the view axis, it stays within a small
// factor of that error for a parallel camera, and it is 0 on the exact path.
TEST(VtkTangentShading, MeasuredErrorIncludesThePerspective)
{
  std::vector<glm::dvec3> pts;
  for (int k = 0; k <= 40; ++k)
    pts.push_back({ -4.0 + 0.2 * k, 2.5 * std::sin(0.7 * k), 0.3 * std::cos(1.3 * k) });
  vtkSmartPointer<vtkPolyData> line = makePolyline(pts, false);
  for (bool parallel : { false, true })
  {
    vtkNew<vtkCamera> camera;
    camera->SetPosition(0, 0, 6);
    camera->SetFocalPoint(0, 0, 0);
    camera->SetViewUp(0, 1, 0);
    camera->SetViewAngle(80);
    camera->SetParallelProjection(parallel);
    vtkNew<vtkWireFurTangentShading> filter;
    filter->SetShadingToMaps();  // the map path
    filter->SetInputData(line);
    filter->SetCamera(camera);
    filter->SetExponent(40);
    filter->Update();
    if (parallel)
      EXPECT_LE(filter->GetMeasuredError(), 3.0 * filter->GetErrorEstimate() + 1e-6);
    else
      EXPECT_GT(filter->GetMeasuredError(), 3.0 * filter->GetErrorEstimate());
    filter->ExactShadingOn();
    filter->Update();
    EXPECT_EQ(filter->GetMeasuredError(), 0.0);
  }
}


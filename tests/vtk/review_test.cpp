// Review tests of the VTK module's filters (no window) and of the core's ShadingCache. Each test
// states what it expects; the ones that fail on the reviewed code are listed in the review report.
#include "vtkWireFurBurnish.h"
#include "vtkWireFurFurGenerator.h"
#include "vtkWireFurScalesGenerator.h"
#include "vtkWireFurTangentShading.h"

#include "core/sanitizers.h"
#include "render/renderer.h"
#include "render/shading_cache.h"

#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkLight.h>
#include <vtkNew.h>
#include <vtkParametricFunctionSource.h>
#include <vtkParametricTorus.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkRenderer.h>
#include <vtkUnsignedCharArray.h>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <sys/resource.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace {

/// Collects the vtkErrorMacro messages of one object (and keeps them off stderr).
class ErrorCatcher : public vtkCommand
{
public:
  static ErrorCatcher* New() { return new ErrorCatcher; }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    ++count;
    last = data ? static_cast<const char*>(data) : "";
  }
  int count = 0;
  std::string last;
};

struct Watch
{
  vtkNew<ErrorCatcher> errors;
  vtkNew<ErrorCatcher> warnings;
  explicit Watch(vtkObject* o)
  {
    o->AddObserver(vtkCommand::ErrorEvent, errors);
    o->AddObserver(vtkCommand::WarningEvent, warnings);
  }
};

vtkSmartPointer<vtkPolyData> circle(int n, double r)
{
  vtkNew<vtkPoints> pts;
  vtkNew<vtkCellArray> lines;
  lines->InsertNextCell(n + 1);
  for (int i = 0; i < n; ++i)
  {
    const double a = 2.0 * M_PI * i / n;
    lines->InsertCellPoint(pts->InsertNextPoint(r * std::cos(a), r * std::sin(a), 0.0));
  }
  lines->InsertCellPoint(0);
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(pts);
  pd->SetLines(lines);
  return pd;
}

bool allFinite(vtkDataArray* a)
{
  if (!a)
    return true;
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
    for (int c = 0; c < a->GetNumberOfComponents(); ++c)
      if (!std::isfinite(a->GetComponent(i, c)))
        return false;
  return true;
}

bool samePoints(vtkPolyData* a, vtkPolyData* b)
{
  if (a->GetNumberOfPoints() != b->GetNumberOfPoints())
    return false;
  for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i)
  {
    double p[3], q[3];
    a->GetPoint(i, p);
    b->GetPoint(i, q);
    if (std::memcmp(p, q, sizeof p) != 0)
      return false;
  }
  return true;
}

// ---- vtkWireFurTangentShading ------------------------------------------------------------------

// docs/vtk.md: "The input's cells and arrays pass through (a shallow copy); the input's active
// scalars stay as an ordinary array." Expected: the input's active scalar array "Temperature" is
// still in the output's point data (not active any more).
TEST(ReviewTangentShading, InputActiveScalarsStayAsAnOrdinaryArray)
{
  vtkSmartPointer<vtkPolyData> pd = circle(16, 1.0);
  vtkNew<vtkFloatArray> temperature;
  temperature->SetName("Temperature");
  temperature->SetNumberOfTuples(16);
  for (int i = 0; i < 16; ++i)
    temperature->SetValue(i, float(i));
  pd->GetPointData()->SetScalars(temperature);
  vtkNew<vtkWireFurTangentShading> shade;
  shade->SetInputData(pd);
  shade->Update();
  vtkPolyData* out = shade->GetOutput();
  ASSERT_EQ(out->GetNumberOfPoints(), 16);
  EXPECT_NE(out->GetPointData()->GetArray("ShadedColor"), nullptr);
  EXPECT_NE(out->GetPointData()->GetArray("Temperature"), nullptr)
    << "the input's active scalars were dropped from the output";
}

// The filter's MTime includes the camera's: moving the camera re-executes the pipeline and, with a
// scene light fixed in the world, changes the shading.
TEST(ReviewTangentShading, MovingTheCameraReExecutes)
{
  vtkSmartPointer<vtkPolyData> pd = circle(32, 1.0);
  vtkNew<vtkRenderer> ren;
  ren->AutomaticLightCreationOff();
  vtkNew<vtkLight> light;
  light->SetLightTypeToSceneLight();
  light->SetPosition(3, 1, 2);
  light->SetFocalPoint(0, 0, 0);
  ren->AddLight(light);
  vtkNew<vtkCamera> cam;
  cam->SetPosition(0, 0, 5);
  vtkNew<vtkWireFurTangentShading> shade;
  shade->SetInputData(pd);
  shade->SetCamera(cam);
  shade->SetRenderer(ren);
  shade->Update();
  const vtkMTimeType t1 = shade->GetOutput()->GetMTime();
  vtkNew<vtkFloatArray> before;
  before->DeepCopy(shade->GetOutput()->GetPointData()->GetArray("ShadedRadiance"));
  shade->Update();
  EXPECT_EQ(shade->GetOutput()->GetMTime(), t1);  // nothing changed: no re-execution
  cam->SetPosition(4, 0, 3);
  shade->Update();
  EXPECT_GT(shade->GetOutput()->GetMTime(), t1);
  vtkDataArray* after = shade->GetOutput()->GetPointData()->GetArray("ShadedRadiance");
  double maxDiff = 0;
  for (vtkIdType i = 0; i < after->GetNumberOfTuples(); ++i)
    for (int c = 0; c < 3; ++c)
      maxDiff = std::max(maxDiff, std::abs(after->GetComponent(i, c) - before->GetComponent(i, c)));
  EXPECT_GT(maxDiff, 1e-3);
  // A light moved: re-executes too.
  const vtkMTimeType t2 = shade->GetOutput()->GetMTime();
  light->SetPosition(-3, 1, 2);
  shade->Update();
  EXPECT_GT(shade->GetOutput()->GetMTime(), t2);
}

// NaN material parameters: defined output, no NaN in any output array (DESIGN: "NaN / Inf in
// input ... Defined output, no NaN").
TEST(ReviewTangentShading, NaNMaterialGivesNoNaN)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int which = 0; which < 4; ++which)
  {
    vtkNew<vtkWireFurTangentShading> shade;
    Watch w(shade);
    shade->SetInputData(circle(16, 1.0));
    if (which == 0)
      shade->SetAmbient(nan, nan, nan);
    if (which == 1)
      shade->SetDiffuse(nan, 0.1, 0.1);
    if (which == 2)
      shade->SetExponent(nan);
    if (which == 3)
      shade->SetSpecular(std::numeric_limits<double>::infinity(), 1, 1);
    shade->Update();
    vtkPolyData* out = shade->GetOutput();
    EXPECT_TRUE(allFinite(out->GetPointData()->GetArray("ShadedRadiance")))
      << "case " << which << " (0 ambient NaN, 1 diffuse NaN, 2 exponent NaN, 3 specular Inf)";
  }
}

// ---- fur and scales generators ---------------------------------------------------------------

// Modifying the vtkParametricFunction (not the filter) regenerates the fur.
TEST(ReviewFur, ModifyingTheParametricFunctionRegenerates)
{
  vtkNew<vtkParametricTorus> torus;
  vtkNew<vtkWireFurFurGenerator> fur;
  fur->SetParametricFunction(torus);
  fur->SetGridU(20);
  fur->SetGridV(10);
  fur->Update();
  vtkNew<vtkPolyData> first;
  first->DeepCopy(fur->GetOutput());
  ASSERT_EQ(first->GetNumberOfLines(), 200);
  torus->SetRingRadius(3.0);
  fur->Update();
  double b[6];
  fur->GetOutput()->GetBounds(b);
  EXPECT_GT(b[1], 3.0) << "the fur still grows on the old torus";
  // The scales generator too.
  vtkNew<vtkWireFurScalesGenerator> scales;
  scales->SetParametricFunction(torus);
  scales->Update();
  scales->GetOutput()->GetBounds(b);
  EXPECT_GT(b[1], 3.0);
  torus->SetRingRadius(1.0);
  scales->Update();
  scales->GetOutput()->GetBounds(b);
  EXPECT_LT(b[1], 2.0);
}

// Deterministic: the same fur with one thread as with every thread, bit for bit (DESIGN).
TEST(ReviewFur, SameOutputWhateverTheThreadCount)
{
  auto grow = [](int threads) {
    std::unique_ptr<tbb::global_control> limit;
    if (threads > 0)
      limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, size_t(threads));
    vtkNew<vtkParametricTorus> torus;
    vtkNew<vtkWireFurFurGenerator> fur;
    fur->SetParametricFunction(torus);
    fur->SetPlacementToAreaCorrect();
    fur->SetDensity(3000);
    fur->SetSegments(4);
    fur->SetGravity(0.3);
    fur->SetClumping(0.5);
    fur->SetCurlAmplitude(0.02);
    fur->Update();
    auto out = vtkSmartPointer<vtkPolyData>::New();
    out->DeepCopy(fur->GetOutput());
    return out;
  };
  auto a = grow(1), b = grow(0), c = grow(0);
  ASSERT_GT(a->GetNumberOfPoints(), 10000);
  EXPECT_TRUE(samePoints(a, b));
  EXPECT_TRUE(samePoints(b, c));
}

TEST(ReviewFur, DegenerateParametersAreAnErrorAndAnEmptyOutput)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int which = 0; which < 6; ++which)
  {
    vtkNew<vtkParametricTorus> torus;
    vtkNew<vtkWireFurFurGenerator> fur;
    Watch w(fur);
    fur->SetParametricFunction(torus);
    fur->SetGridU(10);
    fur->SetGridV(10);
    switch (which)
    {
      case 0: fur->SetGridU(0); break;
      case 1: fur->SetPlacementToAreaCorrect(); fur->SetDensity(-5); break;
      case 2: fur->SetSegments(1000); break;
      case 3: fur->SetLength(nan); break;
      case 4: fur->SetGravityDirection(nan, 0, 0); break;
      case 5: fur->SetJitter(nan); break;
    }
    fur->Update();
    EXPECT_EQ(w.errors->count, 1) << "case " << which;
    EXPECT_EQ(fur->GetOutput()->GetNumberOfPoints(), 0) << "case " << which;
  }
}

// A NaN in the parametric function's own parameters: every root is NaN. Expected: an error (the
// docs: "a NaN or infinite point ... one vtkErrorMacro ... and an empty output") and no NaN point.
TEST(ReviewFur, NaNParametricFunctionIsAnError)
{
  vtkNew<vtkParametricTorus> torus;
  torus->SetRingRadius(std::numeric_limits<double>::quiet_NaN());
  vtkNew<vtkWireFurFurGenerator> fur;
  Watch w(fur);
  fur->SetParametricFunction(torus);
  fur->SetGridU(10);
  fur->SetGridV(10);
  fur->Update();
  vtkPolyData* out = fur->GetOutput();
  EXPECT_TRUE(allFinite(out->GetPoints() ? out->GetPoints()->GetData() : nullptr));
  EXPECT_EQ(out->GetNumberOfPoints(), 0);
  EXPECT_GE(w.errors->count, 1) << "all 100 roots were NaN and no error was reported";
}

// Huge but "valid" parameters: GridU 2^20 x GridV 1000 (10^9 roots, 2 * 10^9 points: ~72 GB of
// points and colours) passes FurParams::problem(). Expected: refused before allocating, with an
// error naming the size; run in a child limited to 3 GB of address space, the only acceptable
// error is one that does not come from a failed allocation.
void growHugeGridAndExit()
{
  rlimit lim{ 3ull << 30, 3ull << 30 };
  setrlimit(RLIMIT_AS, &lim);
  vtkNew<vtkParametricTorus> torus;
  vtkNew<vtkWireFurFurGenerator> fur;
  Watch w(fur);
  fur->SetParametricFunction(torus);
  fur->SetGridU(1 << 20);
  fur->SetGridV(1000);
  fur->Update();
  std::fprintf(stderr, "errors %d: %s\n", w.errors->count, w.errors->last.c_str());
  const bool refusedUpFront = w.errors->count == 1 && w.errors->last.find("bad_alloc") == std::string::npos &&
    fur->GetOutput()->GetNumberOfPoints() == 0;
  std::exit(refusedUpFront ? 0 : 3);
}

TEST(ReviewFur, HugeGridIsRefusedBeforeAllocating)
{
#if defined(WF_UNDER_ASAN)
  GTEST_SKIP() << "the child's address-space limit leaves AddressSanitizer no room for its shadow";
#endif
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(growHugeGridAndExit(), testing::ExitedWithCode(0), "");
}

// A mesh whose cells name points that do not exist (a corrupt file): an error and an empty
// output, never a crash. Fur (MeshSurface) and burnish (triangulate) both read uvs_[id] / P[id].
vtkSmartPointer<vtkPolyData> meshWithBadIds()
{
  vtkNew<vtkPoints> pts;
  pts->InsertNextPoint(0, 0, 0);
  pts->InsertNextPoint(1, 0, 0);
  pts->InsertNextPoint(0, 1, 0);
  vtkNew<vtkFloatArray> tc;
  tc->SetName("TCoords");
  tc->SetNumberOfComponents(2);
  tc->InsertNextTuple2(0, 0);
  tc->InsertNextTuple2(1, 0);
  tc->InsertNextTuple2(0, 1);
  vtkNew<vtkCellArray> polys;
  const vtkIdType good[3] = { 0, 1, 2 };
  const vtkIdType bad[3] = { 0, 1, 400000000 };
  polys->InsertNextCell(3, good);
  polys->InsertNextCell(3, bad);
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(pts);
  pd->SetPolys(polys);
  pd->GetPointData()->SetTCoords(tc);
  return pd;
}

void furOnBadMeshAndExit()
{
  vtkNew<vtkWireFurFurGenerator> fur;
  Watch w(fur);
  fur->SetInputData(meshWithBadIds());
  fur->SetGridU(4);
  fur->SetGridV(4);
  fur->Update();
  std::exit(w.errors->count >= 1 ? 0 : 3);
}

void burnishOnBadMeshAndExit()
{
  vtkNew<vtkWireFurBurnish> burnish;
  Watch w(burnish);
  burnish->SetInputData(meshWithBadIds());
  burnish->Update();
  std::exit(w.errors->count >= 1 ? 0 : 3);
}

TEST(ReviewFur, MeshWithOutOfRangeCellIdsDoesNotCrash)
{
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(furOnBadMeshAndExit(), testing::ExitedWithCode(0), "");
}

TEST(ReviewBurnish, MeshWithOutOfRangeCellIdsDoesNotCrash)
{
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(burnishOnBadMeshAndExit(), testing::ExitedWithCode(0), "");
}

// A pipeline: fur on a vtkParametricFunctionSource's mesh through SetInputConnection; the source
// changed upstream regenerates; Update twice without a change does not.
TEST(ReviewFur, MeshFromAnUpstreamSourceFollowsIt)
{
  vtkNew<vtkParametricTorus> torus;
  vtkNew<vtkParametricFunctionSource> source;
  source->SetParametricFunction(torus);
  source->GenerateTextureCoordinatesOn();
  source->SetUResolution(32);
  source->SetVResolution(16);
  vtkNew<vtkWireFurFurGenerator> fur;
  fur->SetInputConnection(source->GetOutputPort());
  fur->SetGridU(20);
  fur->SetGridV(10);
  fur->Update();
  const vtkIdType n1 = fur->GetOutput()->GetNumberOfLines();
  const vtkMTimeType t1 = fur->GetOutput()->GetMTime();
  EXPECT_GT(n1, 150);
  fur->Update();
  EXPECT_EQ(fur->GetOutput()->GetMTime(), t1);
  torus->SetRingRadius(3.0);
  source->Modified();
  fur->Update();
  double b[6];
  fur->GetOutput()->GetBounds(b);
  EXPECT_GT(b[1], 3.0);
}

// ---- the core's ShadingCache -----------------------------------------------------------------

// Chrome tables are keyed by the EnvironmentMap's address. Replace the scene's environment by
// another one (the old one freed: the allocator hands the same address back): expected the new
// environment's colour (blue), as an uncached render gives.
TEST(ReviewShadingCache, ChromeFollowsAReplacedEnvironment)
{
  wf::Scene s;
  wf::Camera c;
  c.projection = wf::Camera::Projection::Perspective;
  c.eye = { 0, 0, 5 };
  c.target = { 0, 0, 0 };
  c.up = { 0, 1, 0 };
  c.fovYDegrees = 30;
  c.nearPlane = 1;
  c.farPlane = 20;
  s.camera = c;
  s.lights.lights.push_back({ glm::dvec3(0, 0, 1), glm::dvec3(1.0) });
  s.materials[0].kind = wf::Material::Kind::Chrome;
  s.materials[0].chromeReflectance = glm::dvec3(1.0);
  wf::SceneSurface quad;
  quad.mesh.positions = { { -1, -1, 0 }, { 1, -1, 0 }, { 1, 1, 0 }, { -1, 1, 0 } };
  quad.mesh.triangles = { { 0, 1, 2 }, { 0, 2, 3 } };
  s.surfaces.push_back(quad);
  auto env = [](glm::vec3 colour) {
    return std::make_shared<const wf::EnvironmentMap>(8, 4, std::vector<glm::vec3>(32, colour));
  };
  s.environment = env({ 1, 0, 0 });
  wf::RenderOptions o;
  o.width = 64;
  o.height = 64;
  o.shadingCache = std::make_shared<wf::ShadingCache>();
  const wf::RenderResult red = wf::render(s, o);
  const void* oldAddress = s.environment.get();
  s.environment.reset();
  s.environment = env({ 0, 0, 1 });
  std::printf("environment address %s\n", s.environment.get() == oldAddress ? "reused" : "new");
  const wf::RenderResult cached = wf::render(s, o);
  wf::RenderOptions fresh = o;
  fresh.shadingCache = nullptr;
  const wf::RenderResult uncached = wf::render(s, fresh);
  const glm::vec4 r = red.image.at(32, 32), a = cached.image.at(32, 32), b = uncached.image.at(32, 32);
  std::printf("centre: first (%g %g %g), cached (%g %g %g), uncached (%g %g %g)\n", r.x, r.y, r.z, a.x, a.y, a.z,
              b.x, b.y, b.z);
  EXPECT_GT(b.z, 0.5f);
  EXPECT_NEAR(a.x, b.x, 1e-6);
  EXPECT_NEAR(a.z, b.z, 1e-6);
}

}  // namespace

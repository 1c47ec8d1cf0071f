// The fur and scale generators, the burnish filter and the surface adapters behind them
// (vtk_filters/wf_vtk_surfaces.h), on small inputs with analytic expectations. Every tolerance is
// stated with the reason for it.
#include "vtkWireFurBurnish.h"
#include "vtkWireFurFurGenerator.h"
#include "vtkWireFurScalesGenerator.h"
#include "wf_vtk_surfaces.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkCylinderSource.h"
#include "vtkDiskSource.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkMath.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkParametricFunctionSource.h"
#include "vtkParametricRandomHills.h"
#include "vtkParametricTorus.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkTypeUInt64Array.h"
#include "vtkUnsignedCharArray.h"

#include "texture/grooves.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>

namespace
{

constexpr double kPi = 3.14159265358979323846;

// Counts the error (and warning) events of a filter instead of printing them.
class EventCounter : public vtkCommand
{
public:
  static EventCounter* New() { return new EventCounter; }
  void Execute(vtkObject*, unsigned long event, void* data) override
  {
    if (event == vtkCommand::ErrorEvent)
    {
      ++this->Errors;
      this->Last = data ? static_cast<const char*>(data) : "";
    }
    else if (event == vtkCommand::WarningEvent)
    {
      ++this->Warnings;
    }
  }
  int Errors = 0, Warnings = 0;
  std::string Last;
};

// VTK's torus: x = (R + r cos v) sin u, y = (R + r cos v) cos u, z = r sin v (checked below against
// Evaluate); distance of p from it.
double torusDistance(const double p[3], double R, double r)
{
  const double rho = std::hypot(p[0], p[1]);
  return std::abs(std::hypot(rho - R, p[2]) - r);
}

// The same torus with its derivatives withheld (zeroed), under a class name the adapter does not
// know: it takes the mutex and the finite-difference path.
class TorusWithoutDerivatives : public vtkParametricTorus
{
public:
  static TorusWithoutDerivatives* New();
  vtkTypeMacro(TorusWithoutDerivatives, vtkParametricTorus);
  void Evaluate(double uvw[3], double Pt[3], double Duvw[9]) override
  {
    this->vtkParametricTorus::Evaluate(uvw, Pt, Duvw);
    std::fill(Duvw, Duvw + 9, 0.0);
  }
};
vtkStandardNewMacro(TorusWithoutDerivatives);

vtkSmartPointer<vtkPolyData> planeWithNaN()
{
  vtkNew<vtkPlaneSource> plane;
  plane->SetResolution(4, 4);
  plane->Update();
  auto copy = vtkSmartPointer<vtkPolyData>::New();
  copy->DeepCopy(plane->GetOutput());
  copy->GetPoints()->SetPoint(7, std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0);
  return copy;
}

template <class Filter>
vtkSmartPointer<EventCounter> observe(Filter* f)
{
  auto counter = vtkSmartPointer<EventCounter>::New();
  f->AddObserver(vtkCommand::ErrorEvent, counter);
  f->AddObserver(vtkCommand::WarningEvent, counter);
  return counter;
}

} // namespace

// --- surface adapters -----------------------------------------------------------------------------

// The adapter passes vtkParametricTorus's own derivatives through: exact to rounding (1e-12 on
// values of order 1), and the same as the closed form.
TEST(VtkSurfaces, ParametricTorusHasExactDerivatives)
{
  vtkNew<vtkParametricTorus> torus;
  torus->SetRingRadius(1.0);
  torus->SetCrossSectionRadius(0.5);
  wf::vtkio::ParametricFunctionSurface s(torus);
  ASSERT_TRUE(s.problem().empty()) << s.problem();
  EXPECT_TRUE(s.exactDerivatives());
  EXPECT_TRUE(s.concurrent());
  EXPECT_TRUE(s.domain().periodicU && s.domain().periodicV);
  EXPECT_NEAR(s.domain().u1, 2 * kPi, 1e-15);
  double worst = 0;
  for (double u : { 0.1, 1.3, 2.9, 4.4, 6.0 })
    for (double v : { 0.2, 1.7, 3.3, 5.1 })
    {
      const wf::SurfacePoint p = s.evaluate(u, v);
      const double rho = 1.0 + 0.5 * std::cos(v);
      const glm::dvec3 P(rho * std::sin(u), rho * std::cos(u), 0.5 * std::sin(v));
      const glm::dvec3 Su(rho * std::cos(u), -rho * std::sin(u), 0.0);
      const glm::dvec3 Sv(-0.5 * std::sin(v) * std::sin(u), -0.5 * std::sin(v) * std::cos(u), 0.5 * std::cos(v));
      worst = std::max({ worst, glm::length(p.P - P), glm::length(p.Su - Su), glm::length(p.Sv - Sv) });
    }
  EXPECT_LT(worst, 1e-12);
}

// A function without derivatives (and an unknown class: mutex path) gets central differences with
// h = 1e-5 of the domain: error ~ h^2 / 6 |S'''| ~ 1e-9 on this torus; tolerance 1e-7.
TEST(VtkSurfaces, FunctionWithoutDerivativesGetsCentralDifferences)
{
  vtkNew<TorusWithoutDerivatives> torus;
  wf::vtkio::ParametricFunctionSurface s(torus);
  ASSERT_TRUE(s.problem().empty()) << s.problem();
  EXPECT_FALSE(s.exactDerivatives());
  EXPECT_FALSE(s.concurrent());
  vtkNew<vtkParametricTorus> exact;
  wf::vtkio::ParametricFunctionSurface e(exact);
  double worst = 0;
  for (double u : { 0.0, 1.3, 2.9, 6.2 })
    for (double v : { 0.0, 1.7, 3.3, 6.28 })
    {
      const wf::SurfacePoint a = s.evaluate(u, v), b = e.evaluate(u, v);
      worst = std::max({ worst, glm::length(a.Su - b.Su), glm::length(a.Sv - b.Sv) });
    }
  std::cout << "finite-difference derivatives: largest error " << worst << "\n";
  EXPECT_LT(worst, 1e-7);
}

// vtkPlaneSource (double points, float texture coordinates) with axes a1 = Point1 - Origin and
// a2 = Point2 - Origin: S(u, v) = Origin + u a1 + v a2, so Su = a1, Sv = a2 on every triangle.
// Tolerance 1e-6 relative: the float texture coordinates (k / 3 rounded to 2^-24).
TEST(VtkSurfaces, MeshSurfaceOfPlaneSourceHasThePlanesAxes)
{
  vtkNew<vtkPlaneSource> plane;
  plane->SetOrigin(1, 2, 3);
  plane->SetPoint1(3, 3, 3);
  plane->SetPoint2(1, 2, 6);
  plane->SetResolution(3, 4);
  plane->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  plane->Update();
  wf::vtkio::MeshSurface s(plane->GetOutput());
  ASSERT_TRUE(s.problem().empty()) << s.problem();
  EXPECT_EQ(s.triangleCount(), 2u * 3 * 4);
  EXPECT_EQ(s.domain().u0, 0.0);
  EXPECT_EQ(s.domain().u1, 1.0);
  const glm::dvec3 origin(1, 2, 3), a1(2, 1, 0), a2(0, 0, 3);
  double worstDerivative = 0, worstPoint = 0;
  for (double u : { 0.0, 0.1, 0.37, 0.5, 0.9, 1.0 })
    for (double v : { 0.0, 0.25, 0.61, 0.99, 1.0 })
    {
      const wf::SurfacePoint p = s.evaluate(u, v);
      worstDerivative =
        std::max({ worstDerivative, glm::length(p.Su - a1) / glm::length(a1), glm::length(p.Sv - a2) / glm::length(a2) });
      worstPoint = std::max(worstPoint, glm::length(p.P - (origin + u * a1 + v * a2)));
    }
  std::cout << "plane mesh: largest relative derivative error " << worstDerivative << ", point error " << worstPoint
            << "\n";
  EXPECT_LT(worstDerivative, 1e-6);
  EXPECT_LT(worstPoint, 1e-6);
}

// Inside the uv bounding box but in no triangle: a NaN point (the generators skip the root).
TEST(VtkSurfaces, MeshSurfaceOutsideTheUvLayoutIsNaN)
{
  vtkNew<vtkPolyData> tri;
  vtkNew<vtkPoints> pts;
  pts->InsertNextPoint(0, 0, 0);
  pts->InsertNextPoint(2, 0, 0);
  pts->InsertNextPoint(0, 2, 1);
  tri->SetPoints(pts);
  vtkNew<vtkCellArray> polys;
  const vtkIdType ids[3] = { 0, 1, 2 };
  polys->InsertNextCell(3, ids);
  tri->SetPolys(polys);
  vtkNew<vtkFloatArray> tc;
  tc->SetNumberOfComponents(2);
  tc->InsertNextTuple2(0, 0);
  tc->InsertNextTuple2(1, 0);
  tc->InsertNextTuple2(0, 1);
  tri->GetPointData()->SetTCoords(tc);
  wf::vtkio::MeshSurface s(tri);
  ASSERT_TRUE(s.problem().empty()) << s.problem();
  EXPECT_TRUE(std::isnan(s.evaluate(0.9, 0.9).P.x));
  const wf::SurfacePoint in = s.evaluate(0.25, 0.5);
  EXPECT_NEAR(glm::length(in.P - glm::dvec3(0.5, 1.0, 0.5)), 0.0, 1e-15);
  EXPECT_NEAR(glm::length(in.Su - glm::dvec3(2, 0, 0)), 0.0, 1e-15);
  EXPECT_NEAR(glm::length(in.Sv - glm::dvec3(0, 2, 1)), 0.0, 1e-15);
}

// --- fur ------------------------------------------------------------------------------------------

// Grid placement: exactly GridU x GridV hairs on a torus (no degenerate root), Segments + 1 points
// each, ids the root indices j GridU + i in order.
TEST(VtkFurGenerator, GridGivesGridUTimesGridVHairs)
{
  vtkNew<vtkParametricTorus> torus;
  vtkNew<vtkWireFurFurGenerator> fur;
  fur->SetParametricFunction(torus);
  fur->SetGridU(20);
  fur->SetGridV(15);
  fur->SetSegments(4);
  fur->SetGravity(0.5);
  auto events = observe(fur.Get());
  fur->Update();
  EXPECT_EQ(events->Errors, 0) << events->Last;
  vtkPolyData* out = fur->GetOutput();
  ASSERT_EQ(out->GetNumberOfLines(), 20 * 15);
  EXPECT_EQ(out->GetNumberOfPoints(), 20 * 15 * 5);
  auto* ids = vtkTypeUInt64Array::SafeDownCast(out->GetCellData()->GetArray("HairId"));
  ASSERT_NE(ids, nullptr);
  for (vtkIdType h = 0; h < ids->GetNumberOfTuples(); ++h)
  {
    ASSERT_EQ(ids->GetValue(h), vtkTypeUInt64(h));
  }
  auto* colors = vtkUnsignedCharArray::SafeDownCast(out->GetPointData()->GetArray("Colors"));
  ASSERT_NE(colors, nullptr);
  EXPECT_EQ(colors->GetNumberOfComponents(), 3);
  EXPECT_EQ(out->GetPointData()->GetScalars(), colors);
  auto* thickness = vtkDoubleArray::SafeDownCast(out->GetFieldData()->GetArray("Thickness"));
  ASSERT_NE(thickness, nullptr);
  EXPECT_EQ(thickness->GetValue(0), 0.003);
}

// Area-correct placement: the hair count against density x the torus's area 4 pi^2 R r, within
// 4 standard deviations of a Poisson count (sqrt of the mean; the core's per-cell rounding
// floor(lambda + xi) varies less than that).
TEST(VtkFurGenerator, AreaCorrectCountMatchesDensityTimesArea)
{
  vtkNew<vtkParametricTorus> torus;
  torus->SetRingRadius(1.0);
  torus->SetCrossSectionRadius(0.5);
  vtkNew<vtkWireFurFurGenerator> fur;
  fur->SetParametricFunction(torus);
  fur->SetPlacementToAreaCorrect();
  fur->SetDensity(500.0);
  fur->Update();
  const double expected = 500.0 * 4.0 * kPi * kPi * 1.0 * 0.5;
  const double got = double(fur->GetOutput()->GetNumberOfLines());
  std::cout << "area-correct hairs " << got << " expected " << expected << " ("
            << (got - expected) / std::sqrt(expected) << " sigma)\n";
  EXPECT_NEAR(got, expected, 4.0 * std::sqrt(expected));
}

// Every root lies on the analytic torus: the adapter passes VTK's point through (double), so the
// distance is rounding only; tolerance 1e-9.
TEST(VtkFurGenerator, RootsLieOnTheTorus)
{
  vtkNew<vtkParametricTorus> torus;
  torus->SetRingRadius(2.0);
  torus->SetCrossSectionRadius(0.75);
  vtkNew<vtkWireFurFurGenerator> fur;
  fur->SetParametricFunction(torus);
  fur->SetGridU(40);
  fur->SetGridV(30);
  fur->SetSegments(3);
  fur->Update();
  vtkPolyData* out = fur->GetOutput();
  ASSERT_EQ(out->GetNumberOfLines(), 1200);
  double worst = 0;
  vtkCellArray* lines = out->GetLines();
  vtkIdType n;
  const vtkIdType* ids;
  for (lines->InitTraversal(); lines->GetNextCell(n, ids);)
  {
    double p[3];
    out->GetPoint(ids[0], p);
    worst = std::max(worst, torusDistance(p, 2.0, 0.75));
  }
  std::cout << "largest root distance from the torus " << worst << "\n";
  EXPECT_LT(worst, 1e-9);
}

// A parallel pipeline's pieces of a parametric surface (wf_vtk_pieces.h: bands across v, no
// communication): the three pieces' hairs together are the whole fur's, the same ids and the
// same points bit for bit, each hair in one piece; and likewise for the scales.
TEST(VtkFurGenerator, PiecesOfAParametricSurfaceMakeUpTheWholeFur)
{
  vtkNew<vtkParametricTorus> torus;
  torus->SetRingRadius(2.0);
  torus->SetCrossSectionRadius(0.75);
  auto hairs = [&](int piece, int pieces) {
    vtkNew<vtkWireFurFurGenerator> fur;
    fur->SetParametricFunction(torus);
    fur->SetGridU(40);
    fur->SetGridV(30);
    fur->SetSegments(3);
    fur->SetClumping(0.4);
    fur->UpdatePiece(piece, pieces, 0);
    vtkPolyData* out = fur->GetOutput();
    auto* ids = vtkTypeUInt64Array::SafeDownCast(out->GetCellData()->GetArray("HairId"));
    std::map<std::uint64_t, std::vector<double>> byId;
    vtkIdType n;
    const vtkIdType* pts;
    vtkIdType cell = 0;
    for (out->GetLines()->InitTraversal(); out->GetLines()->GetNextCell(n, pts); ++cell)
    {
      std::vector<double> xyz;
      for (vtkIdType k = 0; k < n; ++k)
      {
        double p[3];
        out->GetPoint(pts[k], p);
        xyz.insert(xyz.end(), p, p + 3);
      }
      byId[ids->GetValue(cell)] = xyz;
    }
    return byId;
  };
  const auto whole = hairs(0, 1);
  ASSERT_EQ(whole.size(), 1200u);
  std::map<std::uint64_t, std::vector<double>> joined;
  for (int piece = 0; piece < 3; ++piece)
  {
    const auto part = hairs(piece, 3);
    EXPECT_GT(part.size(), 300u) << "piece " << piece;
    for (const auto& [id, xyz] : part)
    {
      EXPECT_TRUE(joined.emplace(id, xyz).second) << "hair " << id << " in two pieces";
    }
  }
  EXPECT_TRUE(joined == whole);

  auto scales = [&](int piece, int pieces) {
    vtkNew<vtkWireFurScalesGenerator> gen;
    gen->SetParametricFunction(torus);
    gen->SetCellsU(20);
    gen->SetCellsV(10);
    gen->UpdatePiece(piece, pieces, 0);
    return vtkSmartPointer<vtkPolyData>(gen->GetOutput());
  };
  vtkSmartPointer<vtkPolyData> all = scales(0, 1);
  std::set<std::vector<double>> wholeScales, joinedScales;
  auto collect = [](vtkPolyData* m, std::set<std::vector<double>>& into) {
    for (vtkIdType s = 0; s < m->GetNumberOfPoints() / 4; ++s)
    {
      std::vector<double> key;
      for (int k = 0; k < 4; ++k)
      {
        double p[3];
        m->GetPoint(4 * s + k, p);
        key.insert(key.end(), p, p + 3);
      }
      into.insert(key);
    }
  };
  collect(all, wholeScales);
  vtkIdType parts = 0;
  for (int piece = 0; piece < 2; ++piece)
  {
    vtkSmartPointer<vtkPolyData> part = scales(piece, 2);
    parts += part->GetNumberOfPoints() / 4;
    collect(part, joinedScales);
  }
  EXPECT_EQ(parts, all->GetNumberOfPoints() / 4);
  EXPECT_EQ(wholeScales.size(), 400u);
  EXPECT_TRUE(joinedScales == wholeScales);
}

// vtkParametricTorus has Su x Sv pointing into the tube: its fur grows inward unless
// FlipNormals is on, and then every tip lies farther from the tube's centre circle than the root.
TEST(VtkFurGenerator, FlipNormalsGrowsTheTorusFurOutward)
{
  vtkNew<vtkParametricTorus> torus;
  torus->SetRingRadius(2.0);
  torus->SetCrossSectionRadius(0.75);
  for (bool flip : { false, true })
  {
    vtkNew<vtkWireFurFurGenerator> fur;
    fur->SetParametricFunction(torus);
    fur->SetGridU(24);
    fur->SetGridV(12);
    fur->SetLength(0.2);
    fur->SetFlipNormals(flip);
    fur->Update();
    vtkPolyData* out = fur->GetOutput();
    ASSERT_EQ(out->GetNumberOfLines(), 288);
    int outward = 0;
    vtkCellArray* lines = out->GetLines();
    vtkIdType n;
    const vtkIdType* ids;
    for (lines->InitTraversal(); lines->GetNextCell(n, ids);)
    {
      double r[3], t[3];
      out->GetPoint(ids[0], r);
      out->GetPoint(ids[n - 1], t);
      auto tube = [](const double* p) { return std::hypot(std::hypot(p[0], p[1]) - 2.0, p[2]); };
      outward += tube(t) > tube(r) ? 1 : 0;
    }
    EXPECT_EQ(outward, flip ? 288 : 0) << (flip ? "flipped" : "as VTK orients it");
  }
}

// Area-correct placement: doubling the density only adds hairs; every old id is still there with
// the same root (bit for bit).
TEST(VtkFurGenerator, HairIdsStableWhenDensityIncreases)
{
  vtkNew<vtkParametricTorus> torus;
  auto grow = [&](double density) {
    vtkNew<vtkWireFurFurGenerator> fur;
    fur->SetParametricFunction(torus);
    fur->SetPlacementToAreaCorrect();
    fur->SetCellsU(32);
    fur->SetCellsV(32);
    fur->SetDensity(density);
    fur->Update();
    std::map<vtkTypeUInt64, glm::dvec3> roots;
    vtkPolyData* out = fur->GetOutput();
    auto* hairIds = vtkTypeUInt64Array::SafeDownCast(out->GetCellData()->GetArray("HairId"));
    vtkCellArray* lines = out->GetLines();
    vtkIdType n, h = 0;
    const vtkIdType* ids;
    for (lines->InitTraversal(); lines->GetNextCell(n, ids); ++h)
    {
      double p[3];
      out->GetPoint(ids[0], p);
      roots[hairIds->GetValue(h)] = glm::dvec3(p[0], p[1], p[2]);
    }
    return roots;
  };
  const auto low = grow(200.0), high = grow(400.0);
  ASSERT_GT(low.size(), 1000u);
  EXPECT_GT(high.size(), low.size() + low.size() / 2);
  size_t missing = 0, moved = 0;
  for (const auto& [id, root] : low)
  {
    const auto it = high.find(id);
    if (it == high.end())
      ++missing;
    else if (it->second != root)
      ++moved;
  }
  EXPECT_EQ(missing, 0u);
  EXPECT_EQ(moved, 0u);
}

// A mesh with texture coordinates: the plane z = 0 over [-0.5, 0.5]^2 (normal +z): grid hairs all
// grow, roots on the plane (barycentric interpolation of z = 0 is exactly 0), tips above it.
TEST(VtkFurGenerator, GrowsOnAMeshWithTextureCoordinates)
{
  vtkNew<vtkPlaneSource> plane;
  plane->SetResolution(5, 5);
  vtkNew<vtkWireFurFurGenerator> fur;
  fur->SetInputConnection(plane->GetOutputPort());
  fur->SetGridU(10);
  fur->SetGridV(10);
  fur->Update();
  vtkPolyData* out = fur->GetOutput();
  ASSERT_EQ(out->GetNumberOfLines(), 100);
  vtkCellArray* lines = out->GetLines();
  vtkIdType n;
  const vtkIdType* ids;
  for (lines->InitTraversal(); lines->GetNextCell(n, ids);)
  {
    ASSERT_EQ(n, 2);
    double root[3], tip[3];
    out->GetPoint(ids[0], root);
    out->GetPoint(ids[1], tip);
    EXPECT_EQ(root[2], 0.0);
    EXPECT_NEAR(tip[2], 0.1, 0.1 * 0.2 + 1e-12); // Length 0.1 +- LengthVariation 0.2
  }
}

// Area-correct fur on a tessellated torus (vtkParametricFunctionSource, texture coordinates on):
// the count against density x the mesh's own area, within 4 Poisson standard deviations. The
// source joins its last column to its first (s = 1 to s = 0): those seam slivers cover the whole
// row in uv and must not capture the roots (before the rules: 39 % of the expected count, then 76 % with the joined corner still in).
TEST(VtkFurGenerator, AreaCorrectOnAJoinedParametricMeshMatchesItsArea)
{
  vtkNew<vtkParametricTorus> torus;
  vtkNew<vtkParametricFunctionSource> source;
  source->SetParametricFunction(torus);
  source->SetUResolution(64);
  source->SetVResolution(32);
  source->GenerateTextureCoordinatesOn();
  source->Update();
  vtkPolyData* mesh = source->GetOutput();
  double area = 0;
  for (const glm::uvec3& t : wf::vtkio::triangulate(mesh))
  {
    double a[3], b[3], c[3];
    mesh->GetPoint(t.x, a);
    mesh->GetPoint(t.y, b);
    mesh->GetPoint(t.z, c);
    const glm::dvec3 A(a[0], a[1], a[2]), B(b[0], b[1], b[2]), C(c[0], c[1], c[2]);
    area += 0.5 * glm::length(glm::cross(B - A, C - A));
  }
  vtkNew<vtkWireFurFurGenerator> fur;
  fur->SetInputConnection(source->GetOutputPort());
  fur->SetPlacementToAreaCorrect();
  fur->SetDensity(500.0);
  fur->Update();
  const double expected = 500.0 * area;
  const double got = double(fur->GetOutput()->GetNumberOfLines());
  std::cout << "area-correct hairs on the mesh " << got << " expected " << expected << " ("
            << (got - expected) / std::sqrt(expected) << " sigma)\n";
  EXPECT_NEAR(got, expected, 4.0 * std::sqrt(expected));
}

// A function whose Evaluate is not known to be thread-safe (RandomHills reads a vtkDoubleArray):
// evaluated under the mutex, the fur is the same on every run.
TEST(VtkSurfaces, UnsafeParametricFunctionIsSerialisedAndDeterministic)
{
  vtkNew<vtkParametricRandomHills> hills;
  wf::vtkio::ParametricFunctionSurface s(hills);
  EXPECT_FALSE(s.concurrent());
  auto grow = [&] {
    vtkNew<vtkWireFurFurGenerator> fur;
    fur->SetParametricFunction(hills);
    fur->SetGridU(60);
    fur->SetGridV(40);
    fur->Update();
    auto copy = vtkSmartPointer<vtkPolyData>::New();
    copy->DeepCopy(fur->GetOutput());
    return copy;
  };
  auto a = grow(), b = grow();
  ASSERT_EQ(a->GetNumberOfPoints(), 2 * 60 * 40);
  ASSERT_EQ(b->GetNumberOfPoints(), a->GetNumberOfPoints());
  for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i)
  {
    double p[3], q[3];
    a->GetPoint(i, p);
    b->GetPoint(i, q);
    ASSERT_TRUE(p[0] == q[0] && p[1] == q[1] && p[2] == q[2]) << "point " << i;
  }
}

// NaN points, no surface at all, an invalid parameter: one error each, empty output. An empty mesh
// (a rank's empty piece in a parallel pipeline) is an empty output and no error.
TEST(VtkFurGenerator, NaNAndEmptyInputGiveAnErrorAndAnEmptyOutput)
{
  vtkNew<vtkWireFurFurGenerator> fur;
  auto events = observe(fur.Get());
  fur->SetGridU(5);
  fur->SetGridV(5);
  fur->SetInputData(planeWithNaN());
  fur->Update();
  EXPECT_EQ(events->Errors, 1);
  EXPECT_NE(events->Last.find("not finite"), std::string::npos) << events->Last;
  EXPECT_EQ(fur->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_EQ(fur->GetOutput()->GetNumberOfCells(), 0);

  vtkNew<vtkPolyData> empty;  // a rank's empty piece: nothing grows, no error
  fur->SetInputData(empty);
  fur->Update();
  EXPECT_EQ(events->Errors, 1);
  EXPECT_EQ(fur->GetOutput()->GetNumberOfPoints(), 0);

  vtkNew<vtkWireFurFurGenerator> nothing;
  auto none = observe(nothing.Get());
  nothing->Update();
  EXPECT_EQ(none->Errors, 1);
  EXPECT_EQ(nothing->GetOutput()->GetNumberOfPoints(), 0);

  vtkNew<vtkParametricTorus> torus;
  nothing->SetParametricFunction(torus);
  nothing->SetJitter(std::numeric_limits<double>::quiet_NaN());
  nothing->Update();
  EXPECT_EQ(none->Errors, 2);
  EXPECT_NE(none->Last.find("jitter"), std::string::npos) << none->Last;
  EXPECT_EQ(nothing->GetOutput()->GetNumberOfPoints(), 0);
  nothing->SetJitter(1.0);
  nothing->SetGridU(4);
  nothing->SetGridV(4);
  nothing->Update();
  EXPECT_EQ(none->Errors, 2);
  EXPECT_EQ(nothing->GetOutput()->GetNumberOfLines(), 16);

  std::ostringstream print;
  nothing->Print(print);
  EXPECT_NE(print.str().find("GridU: 4"), std::string::npos);
}

// --- scales ---------------------------------------------------------------------------------------

// Two scales per cell, two triangles per scale: 4 CellsU CellsV triangles on a torus; each scale id
// 0 ... 2 CellsU CellsV - 1 on exactly two triangles.
// Cells asking for more than MaximumTriangles (4096 x 4096 cells: 67M triangles, tens of GB) are
// an error and an empty output, before anything is allocated.
TEST(VtkScalesGenerator, TooManyCellsAreAnErrorNotAnAllocation)
{
  vtkNew<vtkParametricTorus> torus;
  vtkNew<vtkWireFurScalesGenerator> scales;
  scales->SetParametricFunction(torus);
  scales->SetCellsU(4096);
  scales->SetCellsV(4096);
  auto events = observe(scales.Get());
  scales->Update();
  EXPECT_EQ(events->Errors, 1) << events->Last;
  EXPECT_EQ(scales->GetOutput()->GetNumberOfPolys(), 0);
}

TEST(VtkScalesGenerator, FourTrianglesPerCell)
{
  vtkNew<vtkParametricTorus> torus;
  vtkNew<vtkWireFurScalesGenerator> scales;
  scales->SetParametricFunction(torus);
  scales->SetCellsU(8);
  scales->SetCellsV(6);
  auto events = observe(scales.Get());
  scales->Update();
  EXPECT_EQ(events->Errors, 0) << events->Last;
  vtkPolyData* out = scales->GetOutput();
  ASSERT_EQ(out->GetNumberOfPolys(), 4 * 8 * 6);
  EXPECT_EQ(out->GetNumberOfPoints(), 4 * 2 * 8 * 6);
  ASSERT_NE(out->GetPointData()->GetNormals(), nullptr);
  ASSERT_NE(out->GetPointData()->GetTCoords(), nullptr);
  ASSERT_NE(vtkUnsignedCharArray::SafeDownCast(out->GetPointData()->GetArray("Colors")), nullptr);
  auto* ids = vtkTypeUInt64Array::SafeDownCast(out->GetCellData()->GetArray("ScaleId"));
  ASSERT_NE(ids, nullptr);
  std::map<vtkTypeUInt64, int> uses;
  for (vtkIdType t = 0; t < ids->GetNumberOfTuples(); ++t)
  {
    ++uses[ids->GetValue(t)];
  }
  ASSERT_EQ(uses.size(), size_t(2 * 8 * 6));
  EXPECT_EQ(uses.begin()->first, 0u);
  EXPECT_EQ(uses.rbegin()->first, vtkTypeUInt64(2 * 8 * 6 - 1));
  for (const auto& [id, count] : uses)
  {
    EXPECT_EQ(count, 2) << "scale " << id;
  }
}

TEST(VtkScalesGenerator, NaNAndEmptyInputGiveAnErrorAndAnEmptyOutput)
{
  vtkNew<vtkWireFurScalesGenerator> scales;
  auto events = observe(scales.Get());
  scales->SetInputData(planeWithNaN());
  scales->Update();
  EXPECT_EQ(events->Errors, 1);
  EXPECT_EQ(scales->GetOutput()->GetNumberOfPoints(), 0);
  vtkNew<vtkPolyData> empty;  // a rank's empty piece: nothing grows, no error
  scales->SetInputData(empty);
  scales->Update();
  EXPECT_EQ(events->Errors, 1);
  EXPECT_EQ(scales->GetOutput()->GetNumberOfCells(), 0);
  vtkNew<vtkPlaneSource> plane; // a good mesh afterwards works again
  scales->SetInputConnection(plane->GetOutputPort());
  scales->SetCellsU(3);
  scales->SetCellsV(2);
  scales->Update();
  EXPECT_EQ(events->Errors, 1) << events->Last;
  EXPECT_EQ(scales->GetOutput()->GetNumberOfPolys(), 4 * 3 * 2);
  scales->SetSize(0.0);
  scales->Update();
  EXPECT_EQ(events->Errors, 2);
  EXPECT_EQ(scales->GetOutput()->GetNumberOfPolys(), 0);
}

// --- burnish --------------------------------------------------------------------------------------

// vtkCylinderSource (axis y, no caps) writes t = 0 at y = +h/2 and t = 1 at y = -h/2, so grain V
// (along dS/dv) is -y everywhere. Tolerance 1e-6: float points and float tangents.
TEST(VtkBurnish, GrainVOfACylinderIsItsAxis)
{
  vtkNew<vtkCylinderSource> cylinder;
  cylinder->SetResolution(16);
  cylinder->SetHeight(2.0);
  cylinder->SetRadius(0.5);
  cylinder->CappingOff();
  vtkNew<vtkWireFurBurnish> burnish;
  burnish->SetInputConnection(cylinder->GetOutputPort());
  burnish->SetGrainToV();
  auto events = observe(burnish.Get());
  burnish->Update();
  EXPECT_EQ(events->Errors, 0) << events->Last;
  vtkPolyData* out = burnish->GetOutput();
  auto* t = vtkFloatArray::SafeDownCast(out->GetPointData()->GetTangents());
  ASSERT_NE(t, nullptr);
  EXPECT_STREQ(t->GetName(), "Tangents");
  ASSERT_EQ(t->GetNumberOfTuples(), out->GetNumberOfPoints());
  double worst = 0;
  for (vtkIdType i = 0; i < t->GetNumberOfTuples(); ++i)
  {
    double v[3];
    t->GetTuple(i, v);
    worst = std::max(worst, glm::length(glm::dvec3(v[0], v[1], v[2]) - glm::dvec3(0, -1, 0)));
  }
  std::cout << "cylinder grain V: largest |T - (0, -1, 0)| " << worst << "\n";
  EXPECT_LT(worst, 1e-6);
  EXPECT_EQ(out->GetNumberOfPolys(), 16); // a copy of the input
}

// Circular grain about the z axis on a disc in the plane z = 0 is tangent to the circles: its dot
// product with the radial direction is rounding only. In double (the grain function): < 1e-9; in
// the float "Tangents" array: < 1e-6 (float storage, 2^-24 relative per component).
TEST(VtkBurnish, CircularGrainOnADiscIsTangentToCircles)
{
  vtkNew<vtkDiskSource> disc;
  disc->SetInnerRadius(0.25);
  disc->SetOuterRadius(1.0);
  disc->SetRadialResolution(4);
  disc->SetCircumferentialResolution(32);
  disc->Update();
  vtkNew<vtkWireFurBurnish> burnish;
  burnish->SetInputConnection(disc->GetOutputPort());
  burnish->SetGrainToCircular();
  burnish->SetAxisPoint(0, 0, 0);
  burnish->SetAxisDirection(0, 0, 2); // normalised by the filter
  auto events = observe(burnish.Get());
  burnish->Update();
  EXPECT_EQ(events->Errors, 0) << events->Last;
  vtkPolyData* out = burnish->GetOutput();
  auto* t = vtkFloatArray::SafeDownCast(out->GetPointData()->GetTangents());
  ASSERT_NE(t, nullptr);
  double worstDouble = 0, worstFloat = 0, worstLength = 0;
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    double p[3], v[3];
    out->GetPoint(i, p);
    t->GetTuple(i, v);
    const glm::dvec3 P(p[0], p[1], p[2]);
    const glm::dvec3 radial = glm::normalize(glm::dvec3(p[0], p[1], 0.0));
    const glm::dvec3 T = wf::vtkio::grainTangent(wf::vtkio::Grain::Circular, P, glm::dvec3(0, 0, 1),
      glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0, 0, 1));
    worstDouble = std::max(worstDouble, std::abs(glm::dot(T, radial)));
    worstFloat = std::max(worstFloat, std::abs(glm::dot(glm::dvec3(v[0], v[1], v[2]), radial)));
    worstLength = std::max(worstLength, std::abs(glm::length(glm::dvec3(v[0], v[1], v[2])) - 1.0));
  }
  std::cout << "circular grain: |T . radial| double " << worstDouble << ", float " << worstFloat << "\n";
  EXPECT_LT(worstDouble, 1e-9);
  EXPECT_LT(worstFloat, 1e-6);
  EXPECT_LT(worstLength, 1e-6);

  // Radial grain is the radial direction itself.
  burnish->SetGrainToRadial();
  burnish->Update();
  t = vtkFloatArray::SafeDownCast(burnish->GetOutput()->GetPointData()->GetTangents());
  double worstRadial = 0;
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    double p[3], v[3];
    burnish->GetOutput()->GetPoint(i, p);
    t->GetTuple(i, v);
    const glm::dvec3 radial = glm::normalize(glm::dvec3(p[0], p[1], 0.0));
    worstRadial = std::max(worstRadial, glm::length(glm::dvec3(v[0], v[1], v[2]) - radial));
  }
  EXPECT_LT(worstRadial, 1e-6);
}

// Grooves: every intensity in [1 - depth, 1] (the core's I_k = 1 - depth xi_k, xi in [0, 1)), equal
// to the core's GrooveTexture at the groove coordinate u (grain V) to float rounding, and not all
// the same.
TEST(VtkBurnish, GrooveIntensityWithinDepth)
{
  vtkNew<vtkCylinderSource> cylinder;
  cylinder->SetResolution(64);
  cylinder->CappingOff();
  vtkNew<vtkWireFurBurnish> burnish;
  burnish->SetInputConnection(cylinder->GetOutputPort());
  burnish->SetGrainToV();
  burnish->SetGrooveCount(20.0);
  burnish->SetGrooveDepth(0.3);
  burnish->SetGrooveSeed(7);
  burnish->Update();
  vtkPolyData* out = burnish->GetOutput();
  auto* g = vtkFloatArray::SafeDownCast(out->GetPointData()->GetArray("GrooveIntensity"));
  ASSERT_NE(g, nullptr);
  vtkDataArray* tc = out->GetPointData()->GetTCoords();
  const wf::GrooveTexture texture(20.0, 0.3, 7);
  float lo = 2, hi = -1;
  double worst = 0;
  for (vtkIdType i = 0; i < g->GetNumberOfTuples(); ++i)
  {
    const float x = g->GetValue(i);
    lo = std::min(lo, x);
    hi = std::max(hi, x);
    worst = std::max(worst, std::abs(double(x) - texture.intensity(tc->GetComponent(i, 0), 0.0)));
  }
  EXPECT_GE(lo, 1.0f - 0.3f);
  EXPECT_LE(hi, 1.0f);
  EXPECT_GT(hi - lo, 0.05f);
  EXPECT_LT(worst, 1e-7);
  burnish->SetGrooveCount(0.0); // no grooves, no array
  burnish->Update();
  EXPECT_EQ(burnish->GetOutput()->GetPointData()->GetArray("GrooveIntensity"), nullptr);
}

// With the parametric function the grain is the function's own unit Su at
// (u, v) = (2 pi s, 2 pi t): (cos u, -sin u, 0) on VTK's torus. Tolerance 1e-6: float texture
// coordinates (u to 2pi 2^-24 ~ 4e-7) and float tangents.
TEST(VtkBurnish, ParametricTorusGrainUIsTheFunctionsSu)
{
  vtkNew<vtkParametricTorus> torus;
  vtkNew<vtkParametricFunctionSource> source;
  source->SetParametricFunction(torus);
  source->SetUResolution(24);
  source->SetVResolution(12);
  source->GenerateTextureCoordinatesOn();
  vtkNew<vtkWireFurBurnish> burnish;
  burnish->SetInputConnection(source->GetOutputPort());
  burnish->SetParametricFunction(torus);
  burnish->SetGrainToU();
  auto events = observe(burnish.Get());
  burnish->Update();
  EXPECT_EQ(events->Errors, 0) << events->Last;
  vtkPolyData* out = burnish->GetOutput();
  auto* t = vtkFloatArray::SafeDownCast(out->GetPointData()->GetTangents());
  ASSERT_NE(t, nullptr);
  vtkDataArray* tc = out->GetPointData()->GetTCoords();
  double worst = 0;
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    const double u = 2 * kPi * tc->GetComponent(i, 0);
    double v[3];
    t->GetTuple(i, v);
    worst = std::max(worst, glm::length(glm::dvec3(v[0], v[1], v[2]) - glm::dvec3(std::cos(u), -std::sin(u), 0.0)));
  }
  EXPECT_LT(worst, 1e-6);
}

// NaN points and unusable grain: an error and an empty output. An empty input is an empty output
// with the arrays and no error (a rank's empty piece).
TEST(VtkBurnish, NaNAndEmptyInputGiveAnErrorAndAnEmptyOutput)
{
  vtkNew<vtkWireFurBurnish> burnish;
  auto events = observe(burnish.Get());
  burnish->SetInputData(planeWithNaN());
  burnish->Update();
  EXPECT_EQ(events->Errors, 1);
  EXPECT_EQ(burnish->GetOutput()->GetNumberOfPoints(), 0);
  vtkNew<vtkPolyData> empty;  // a rank's empty piece: an empty output with the arrays, no error
  burnish->SetInputData(empty);
  burnish->Update();
  EXPECT_EQ(events->Errors, 1);
  EXPECT_EQ(burnish->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_NE(burnish->GetOutput()->GetPointData()->GetTangents(), nullptr);
  // Grain along u without texture coordinates, and a zero axis for circular grain.
  vtkNew<vtkDiskSource> disc;
  burnish->SetInputConnection(disc->GetOutputPort());
  burnish->Update();
  EXPECT_EQ(events->Errors, 2);
  EXPECT_EQ(burnish->GetOutput()->GetNumberOfPoints(), 0);
  burnish->SetGrainToCircular();
  burnish->SetAxisDirection(0, 0, 0);
  burnish->Update();
  EXPECT_EQ(events->Errors, 3);
  EXPECT_EQ(burnish->GetOutput()->GetNumberOfPoints(), 0);
  burnish->SetAxisDirection(0, 0, 1);
  burnish->Update();
  EXPECT_EQ(events->Errors, 3) << events->Last;
  EXPECT_GT(burnish->GetOutput()->GetNumberOfPoints(), 0);
}

namespace
{
// A w x h image of `components` doubles per pixel, value(i, j, c).
template <class F>
vtkSmartPointer<vtkImageData> mapImage(int w, int h, int components, F value, int type = VTK_DOUBLE)
{
  auto img = vtkSmartPointer<vtkImageData>::New();
  img->SetDimensions(w, h, 1);
  img->AllocateScalars(type, components);
  vtkDataArray* a = img->GetPointData()->GetScalars();
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      for (int c = 0; c < components; ++c)
        a->SetComponent(vtkIdType(j) * w + i, c, value(i, j, c));
  return img;
}

vtkSmartPointer<vtkPolyData> unitPlaneMesh()
{
  vtkNew<vtkPlaneSource> plane;  // (u, v) = its texture coordinates, [0, 1]^2 over the unit square
  plane->SetResolution(20, 20);
  plane->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(plane->GetOutput());
  return out;
}
}

// The core's maps and colour regions, given as VTK images and calls: a density map that is zero
// over the left half of (s, t) leaves no root there; a constant length map of 0.5 halves every
// hair; a red root colour map makes every root red; a colour region paints only the hairs whose
// roots lie inside it.
TEST(VtkFurGenerator, MapsAndColourRegionsFollowTheCore)
{
  vtkSmartPointer<vtkPolyData> plane = unitPlaneMesh();
  {
    vtkNew<vtkWireFurFurGenerator> fur;
    fur->SetInputData(plane);
    fur->SetPlacementToAreaCorrect();
    fur->SetDensity(4000);
    // 8 texels across s: 0 for the first four, 1 for the last four (texel centres at (i + 1/2) / 8).
    fur->SetDensityMap(mapImage(8, 1, 1, [](int i, int, int) { return i < 4 ? 0.0 : 1.0; }));
    fur->Update();
    vtkDataArray* uv = fur->GetOutput()->GetCellData()->GetArray("RootUV");
    ASSERT_NE(uv, nullptr);
    ASSERT_GT(uv->GetNumberOfTuples(), 1000);
    double smallest = 1.0;
    for (vtkIdType k = 0; k < uv->GetNumberOfTuples(); ++k)
      smallest = std::min(smallest, uv->GetComponent(k, 0));
    EXPECT_GE(smallest, 3.5 / 8.0);  // no root where the map is 0 (left of the last 0 texel centre)
  }
  {
    vtkNew<vtkWireFurFurGenerator> fur;
    fur->SetInputData(plane);
    fur->SetGridU(10);
    fur->SetGridV(10);
    fur->SetLength(0.2);
    fur->SetLengthVariation(0.0);
    fur->SetIntensityVariation(0.0);
    fur->SetLengthMap(mapImage(1, 1, 1, [](int, int, int) { return 0.5; }));
    fur->SetRootColorMap(mapImage(1, 1, 3, [](int, int, int c) { return c == 0 ? 255.0 : 0.0; }, VTK_UNSIGNED_CHAR));
    fur->AddColorRegion(0.5, 0.5, 0.2, 0.0, 1.0, 0.0, 0.0);
    EXPECT_EQ(fur->GetNumberOfColorRegions(), 1);
    fur->Update();
    vtkPolyData* out = fur->GetOutput();
    ASSERT_EQ(out->GetNumberOfLines(), 100);
    vtkDataArray* colours = out->GetPointData()->GetArray("Colors");
    vtkDataArray* uv = out->GetCellData()->GetArray("RootUV");
    vtkCellArray* lines = out->GetLines();
    vtkIdType n;
    const vtkIdType* ids;
    int cell = 0, inside = 0;
    for (lines->InitTraversal(); lines->GetNextCell(n, ids); ++cell)
    {
      double a[3], b[3];
      out->GetPoint(ids[0], a);
      out->GetPoint(ids[n - 1], b);
      EXPECT_NEAR(std::sqrt(vtkMath::Distance2BetweenPoints(a, b)), 0.1, 1e-9);  // 0.5 x 0.2
      const double ds = uv->GetComponent(cell, 0) - 0.5, dt = uv->GetComponent(cell, 1) - 0.5;
      const bool in = std::hypot(ds, dt) < 0.2 - 1e-9;
      inside += in;
      if (std::hypot(ds, dt) > 0.2 + 1e-9)
      {
        EXPECT_EQ(colours->GetComponent(ids[0], 0), 255.0);  // the red root colour map
        EXPECT_EQ(colours->GetComponent(ids[0], 1), 0.0);
      }
      else if (in)
      {
        EXPECT_EQ(colours->GetComponent(ids[0], 0), 0.0);  // the green region
        EXPECT_EQ(colours->GetComponent(ids[0], 1), 255.0);
      }
    }
    EXPECT_GT(inside, 5);
    // The maps take part in the modification time: a changed map regenerates.
    const vtkMTimeType before = fur->GetMTime();
    fur->GetLengthMap()->Modified();
    EXPECT_GT(fur->GetMTime(), before);
  }
}


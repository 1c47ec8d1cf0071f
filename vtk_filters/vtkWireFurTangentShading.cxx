#include "vtkWireFurTangentShading.h"

#include "wf_vtk_surfaces.h"

#include "core/srgb.h"

#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIntArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkRenderer.h"
#include "vtkUnsignedCharArray.h"

#include "core/srgb.h"
#include "shading/cylinder_shading.h"
#include "shading/light.h"
#include "shading/phong.h"
#include "shading/cylinder_lobe.h"
#include "shading/pseudo_reflectance_map.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <vector>

namespace {

bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Unit vector along d, scaled first so that tiny or huge coordinates neither underflow nor
// overflow. Zero (and non-finite) d gives zero.
glm::dvec3 unitOrZero(const glm::dvec3& d) {
  const double s = std::max({ std::abs(d.x), std::abs(d.y), std::abs(d.z) });
  if (!(s > 0.0) || !std::isfinite(s)) return glm::dvec3(0.0);
  const glm::dvec3 e = d / s;
  return e / std::sqrt(glm::dot(e, e));
}

// Unit vectors spread evenly over the sphere (Fibonacci lattice): the test set of the error
// estimate, as in the core's renderer.
std::vector<glm::dvec3> fibonacciSphere(int n) {
  std::vector<glm::dvec3> out;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (i + 0.5) * 2.0 / n, r = std::sqrt(std::max(0.0, 1.0 - z * z));
    out.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
  }
  return out;
}

// Parallel loop over [begin, end) in blocks, on oneTBB directly. vtkSMPTools (whose Debian
// backend is the same oneTBB) would be the VTK idiom, but VTK 9.1's vtkSMPTools.h does not compile
// as C++20 with GCC 12 (a template-id as constructor name, vtkSMPTools.h:106; CWG 2237).
template <typename Body>
void parallelFor(vtkIdType begin, vtkIdType end, const Body& body)
{
  tbb::parallel_for(tbb::blocked_range<vtkIdType>(begin, end, 256),
    [&](const tbb::blocked_range<vtkIdType>& r) { body(r.begin(), r.end()); });
}

// Segment state within a cell: usable, zero length (skipped: look past it), or touching a
// NaN / Inf point (the line is broken there).
enum class Segment : unsigned char { Usable, ZeroLength, Broken };

} // namespace

class vtkWireFurTangentShading::vtkInternals
{
public:
  wf::PseudoReflectanceMap Map;
  double MapError = 0.0; // measured at the map's last build
  std::shared_ptr<const wf::CylinderLobeTable> Lobe; // closed path: rebuilt when the exponent changes
};

vtkStandardNewMacro(vtkWireFurTangentShading);

vtkWireFurTangentShading::vtkWireFurTangentShading()
  : Internals(new vtkInternals)
{
}

vtkWireFurTangentShading::~vtkWireFurTangentShading()
{
  delete this->Internals;
}

void vtkWireFurTangentShading::SetCamera(vtkCamera* camera)
{
  if (this->Camera != camera)
  {
    this->Camera = camera;
    this->Modified();
  }
}

vtkCamera* vtkWireFurTangentShading::GetCamera()
{
  return this->Camera;
}

void vtkWireFurTangentShading::SetRenderer(vtkRenderer* renderer)
{
  if (this->Renderer != renderer)
  {
    this->Renderer = renderer;
    this->Modified();
  }
}

vtkRenderer* vtkWireFurTangentShading::GetRenderer()
{
  return this->Renderer;
}

int vtkWireFurTangentShading::GetMapBuilds()
{
  return this->Internals->Map.buildCount();
}

double vtkWireFurTangentShading::GetMapSeconds()
{
  return this->Internals->Map.lastBuildSeconds();
}

vtkMTimeType vtkWireFurTangentShading::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();
  if (this->Camera)
  {
    t = std::max(t, this->Camera->GetMTime());
  }
  if (vtkRenderer* ren = this->Renderer)
  {
    t = std::max(t, ren->GetMTime()); // e.g. AutomaticLightCreation
    if (!this->Camera && ren->IsActiveCameraCreated())
    {
      t = std::max(t, ren->GetActiveCamera()->GetMTime());
    }
    vtkLightCollection* lights = ren->GetLights();
    t = std::max(t, lights->GetMTime());
    vtkCollectionSimpleIterator it;
    lights->InitTraversal(it);
    while (vtkLight* light = lights->GetNextLight(it))
    {
      t = std::max(t, light->GetMTime());
    }
  }
  return t;
}

int vtkWireFurTangentShading::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  this->NonFinitePoints = 0;
  this->DegeneratePoints = 0;
  this->ErrorEstimate = 0.0; // set again below once the path is known; 0 for an early return
  this->MeasuredError = 0.0;
  // Bad input is an error and an empty output (the generators and the command line do the same),
  // unless SkipNonFinitePoints asks for the rest to be shaded.
  if (!input)
  {
    vtkErrorMacro("no input");
    output->Initialize();
    return 1;
  }
  // An empty input (a rank's empty piece in a parallel pipeline) is not an error: an empty output
  // with the four arrays (below), so that pieces append with their arrays; a warning when it is
  // the whole data set. Cells naming points the input does not have are an error.
  if (wf::vtkio::isEmpty(input) && wf::vtkio::wholeDataRequested(outputVector))
    vtkWarningMacro(<< wf::vtkio::wholeEmptyWarning);
  if (const std::int64_t missing = wf::vtkio::firstCellWithMissingPoints(input); missing >= 0)
  {
    vtkErrorMacro(<< "input cell " << missing << " names a point the input does not have");
    output->Initialize();
    return 1;
  }
  if (!this->SkipNonFinitePoints)
  {
    vtkIdType bad = 0, first = -1;
    for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
    {
      double p[3];
      input->GetPoint(i, p);
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      {
        bad += 1;
        first = first < 0 ? i : first;
      }
    }
    if (bad > 0)
    {
      vtkErrorMacro(<< bad << " point(s) with a NaN or Inf coordinate (the first is point " << first
                    << "): no output (SkipNonFinitePointsOn() shades the others)");
      this->NonFinitePoints = int(bad);
      output->Initialize();
      return 1;
    }
  }
  output->ShallowCopy(input);

  const vtkIdType n = input->GetNumberOfPoints();
  vtkNew<vtkFloatArray> worldTangents, eyeTangents, radiance;
  vtkNew<vtkUnsignedCharArray> colour;
  worldTangents->SetName("Tangents");
  eyeTangents->SetName("EyeTangents");
  radiance->SetName("ShadedRadiance");
  colour->SetName("ShadedColor");
  for (vtkDataArray* a : { static_cast<vtkDataArray*>(worldTangents), static_cast<vtkDataArray*>(eyeTangents),
         static_cast<vtkDataArray*>(radiance), static_cast<vtkDataArray*>(colour) })
  {
    a->SetNumberOfComponents(3);
    a->SetNumberOfTuples(n);
  }
  vtkPointData* pd = output->GetPointData();
  pd->AddArray(eyeTangents);
  pd->AddArray(radiance);
  // Added, then made active by name: SetScalars / SetTangents would remove the input's arrays
  // that held those roles (they stay as ordinary arrays).
  pd->AddArray(worldTangents);
  pd->AddArray(colour);
  pd->SetActiveTangents("Tangents");
  pd->SetActiveScalars("ShadedColor");
  // Says that these colours are shading already: vtkWireFurRenderPass draws such lines as they
  // are (plain wire in these colours) instead of shading them a second time.
  vtkNew<vtkIntArray> shaded;
  shaded->SetName("WireFurShaded");
  shaded->InsertNextValue(1);
  output->GetFieldData()->AddArray(shaded);
  if (n == 0)
  {
    return 1;
  }

  // ---- the eye space -------------------------------------------------------------------------
  vtkNew<vtkCamera> defaultCamera;
  vtkCamera* camera = this->Camera;
  if (!camera && this->Renderer)
  {
    camera = this->Renderer->GetActiveCamera();
  }
  if (!camera)
  {
    camera = defaultCamera;
  }
  vtkMatrix4x4* view = camera->GetViewTransformMatrix();
  glm::dmat3 eyeFromWorld(1.0); // glm is column-major: eyeFromWorld[column][row]
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
    {
      eyeFromWorld[c][r] = view->GetElement(r, c);
    }
  }
  double eyePosition[3];
  camera->GetPosition(eyePosition);
  const glm::dvec3 eye(eyePosition[0], eyePosition[1], eyePosition[2]);
  const bool perspective = !camera->GetParallelProjection();
  for (int c = 0; c < 3; ++c)
  {
    if (!finite3(eyeFromWorld[c]) || !(std::abs(glm::length(eyeFromWorld[c]) - 1.0) < 1e-6))
    {
      vtkErrorMacro("the camera's view transform is not a rotation (position = focal point, or a "
                    "zero view-up?): no tangents or shading computed");
      output->Initialize();
      return 1;  // an error and an empty output, like every other bad input
    }
  }

  // ---- lights in eye space -------------------------------------------------------------------
  wf::LightRig eyeLights;
  if (vtkRenderer* ren = this->Renderer)
  {
    vtkLightCollection* lights = ren->GetLights();
    vtkCollectionSimpleIterator it;
    lights->InitTraversal(it);
    int count = 0;
    while (vtkLight* light = lights->GetNextLight(it))
    {
      ++count;
      if (!light->GetSwitch())
      {
        continue;
      }
      glm::dvec3 towards(0.0, 0.0, 1.0); // a headlight
      if (light->LightTypeIsCameraLight())
      {
        double p[3], f[3];
        light->GetPosition(p);
        light->GetFocalPoint(f);
        towards = glm::dvec3(p[0] - f[0], p[1] - f[1], p[2] - f[2]);
      }
      else if (light->LightTypeIsSceneLight())
      {
        double p[3], f[3];
        light->GetTransformedPosition(p);
        light->GetTransformedFocalPoint(f);
        towards = eyeFromWorld * glm::dvec3(p[0] - f[0], p[1] - f[1], p[2] - f[2]);
      }
      double colourOfLight[3];
      light->GetDiffuseColor(colourOfLight);
      const glm::dvec3 intensity =
        light->GetIntensity() * glm::dvec3(colourOfLight[0], colourOfLight[1], colourOfLight[2]);
      eyeLights.lights.push_back({ towards, intensity });
    }
    if (count == 0 && ren->GetAutomaticLightCreation())
    {
      eyeLights.lights.push_back({ glm::dvec3(0.0, 0.0, 1.0), glm::dvec3(1.0) });
    }
  }
  else
  {
    eyeLights = wf::LightRig::studioRig(this->LightCount);
  }
  eyeLights.ambient = glm::dvec3(this->Ambient[0], this->Ambient[1], this->Ambient[2]);
  eyeLights = eyeLights.canonical();

  wf::PhongMaterial material;
  material.diffuse = glm::dvec3(this->Diffuse[0], this->Diffuse[1], this->Diffuse[2]);
  material.specular = glm::dvec3(this->Specular[0], this->Specular[1], this->Specular[2]);
  material.exponent = this->Exponent;
  material = material.sanitized();
  // The input's own colours (below) replace the diffuse colour, as point colours do in VTK's
  // mappers and in the core: the diffuse coefficient stays (its largest component).
  if (auto* in = vtkUnsignedCharArray::SafeDownCast(input->GetPointData()->GetArray("Colors"));
      in && in->GetNumberOfComponents() >= 3 && in->GetNumberOfTuples() == input->GetNumberOfPoints())
    material.diffuse = glm::dvec3(std::max({ material.diffuse.x, material.diffuse.y, material.diffuse.z }));

  // ---- the map (only when it is used, and only when something it depends on changed) --------
  wf::PseudoReflectanceMap& map = this->Internals->Map;
  const int path = this->ExactShading ? 2 : this->Shading; // 0 closed, 1 maps, 2 exact
  std::shared_ptr<const wf::CylinderLobeTable>& lobe = this->Internals->Lobe;
  if (path == 2)
  {
    this->ErrorEstimate = 0.0;
  }
  else if (path == 0)
  {
    if (!lobe || lobe->exponent() != material.exponent)
    {
      lobe = std::make_shared<const wf::CylinderLobeTable>(material.exponent);
    }
    this->ErrorEstimate = wf::lobeRadianceBound(*lobe, material, eyeLights);
  }
  else
  {
    wf::PseudoReflectanceMapOptions options;
    options.resolution = this->MapResolution;
    options.samples = this->MapSamples;
    if (map.update(material, eyeLights, options))
    {
      const std::vector<glm::dvec3> dirs = fibonacciSphere(192);
      std::vector<double> diff(dirs.size(), 0.0);
      parallelFor(0, vtkIdType(dirs.size()), [&](vtkIdType begin, vtkIdType end) {
        for (vtkIdType i = begin; i < end; ++i)
        {
          const glm::dvec3 d = glm::abs(glm::dvec3(map.lookup(dirs[i])) -
            wf::cylinderRadianceClosed(dirs[i], glm::dvec3(0.0, 0.0, 1.0), material, eyeLights));
          diff[i] = std::max({ d.x, d.y, d.z });
        }
      });
      this->Internals->MapError = *std::max_element(diff.begin(), diff.end());
    }
    this->ErrorEstimate = this->Internals->MapError;
  }

  // ---- world tangents (serial: points are shared between cells) ------------------------------
  std::vector<glm::dvec3> position(n);
  std::vector<unsigned char> finite(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    double p[3];
    input->GetPoint(i, p);
    position[i] = glm::dvec3(p[0], p[1], p[2]);
    finite[i] = finite3(position[i]);
    this->NonFinitePoints += !finite[i];
  }
  std::vector<glm::dvec3> sum(n, glm::dvec3(0.0)), fallback(n, glm::dvec3(0.0));
  std::vector<vtkIdType> owner(n, -1);
  std::vector<glm::dvec3> segDir;
  std::vector<Segment> segState;
  std::vector<int> incoming, outgoing;
  if (vtkCellArray* lines = input->GetLines())
  {
    auto cells = vtk::TakeSmartPointer(lines->NewIterator());
    vtkIdType cellIndex = 0;
    for (cells->GoToFirstCell(); !cells->IsDoneWithTraversal(); cells->GoToNextCell(), ++cellIndex)
    {
      vtkIdType npts;
      const vtkIdType* ids;
      cells->GetCurrentCell(npts, ids);
      bool valid = true;
      for (vtkIdType k = 0; k < npts; ++k)
      {
        valid = valid && ids[k] >= 0 && ids[k] < n;
      }
      if (!valid || npts < 2)
      {
        continue;
      }
      // A closed polyline repeats its first point id at the end: the m points wrap around.
      const bool closed = npts > 2 && ids[0] == ids[npts - 1];
      const int m = int(closed ? npts - 1 : npts);
      const int segments = closed ? m : m - 1;
      segDir.assign(segments, glm::dvec3(0.0));
      segState.assign(segments, Segment::Broken);
      for (int s = 0; s < segments; ++s)
      {
        const vtkIdType a = ids[s], b = ids[(s + 1) % m];
        if (!finite[a] || !finite[b])
        {
          continue;
        }
        segDir[s] = unitOrZero(position[b] - position[a]);
        segState[s] = segDir[s] == glm::dvec3(0.0) ? Segment::ZeroLength : Segment::Usable;
      }
      // incoming[k] / outgoing[k]: the nearest usable segment before / after point k, looking past
      // zero-length ones and stopping at broken ones (-1: none). Two laps settle a closed line.
      incoming.assign(m, -1);
      outgoing.assign(m, -1);
      const int laps = closed ? 2 : 1;
      for (int t = 1; t < laps * m; ++t)
      {
        const int k = t % m, s = (k + m - 1) % m; // segment s ends at point k
        if (!closed && k == 0)
        {
          continue;
        }
        incoming[k] = segState[s] == Segment::Usable ? s
          : segState[s] == Segment::ZeroLength       ? incoming[s]
                                                     : -1;
      }
      for (int t = laps * m - 2; t >= 0; --t)
      {
        const int k = t % m, s = k; // segment s starts at point k
        if (!closed && k == m - 1)
        {
          continue;
        }
        outgoing[k] = segState[s] == Segment::Usable ? s
          : segState[s] == Segment::ZeroLength       ? outgoing[(k + 1) % m]
                                                     : -1;
      }
      for (int k = 0; k < m; ++k)
      {
        const vtkIdType id = ids[k];
        if (!finite[id] || (incoming[k] < 0 && outgoing[k] < 0))
        {
          continue;
        }
        glm::dvec3 c(0.0);
        if (incoming[k] >= 0)
        {
          c += segDir[incoming[k]];
        }
        if (outgoing[k] >= 0)
        {
          c += segDir[outgoing[k]];
        }
        const glm::dvec3 one = segDir[incoming[k] >= 0 ? incoming[k] : outgoing[k]];
        if (owner[id] < 0)
        {
          owner[id] = cellIndex;
          fallback[id] = one;
        }
        else if (owner[id] != cellIndex)
        {
          // Another cell through this point: take its tangent with the sign of the first's.
          const glm::dvec3 ref = sum[id] != glm::dvec3(0.0) ? sum[id] : fallback[id];
          const glm::dvec3 mine = c != glm::dvec3(0.0) ? c : one;
          if (glm::dot(ref, mine) < 0.0)
          {
            c = -c;
          }
        }
        sum[id] += c;
      }
    }
  }

  // ---- per point: tangents and shading (independent: parallel, deterministic) ----------------
  // The input's own colours ("Colors", 8-bit sRGB: the fur generator's root-to-tip colours)
  // multiply the shading, as the core's vertex colours do: the material gives the light, the
  // strands keep their colour.
  std::vector<glm::dvec3> tint;
  if (auto* in = vtkUnsignedCharArray::SafeDownCast(input->GetPointData()->GetArray("Colors"));
      in && in->GetNumberOfComponents() >= 3 && in->GetNumberOfTuples() == n)
  {
    tint.resize(size_t(n));
    for (vtkIdType i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k)
        tint[size_t(i)][k] = wf::srgbToLinear(float(in->GetComponent(i, k)) / 255.0f);
  }
  std::vector<unsigned char> degenerate(n, 0);
  const wf::PhongMaterial& mat = material;
  const wf::CylinderLobeTable* table = path == 0 ? lobe.get() : nullptr;
  auto shade = [&](vtkIdType begin, vtkIdType end) {
    for (vtkIdType i = begin; i < end; ++i)
    {
      glm::dvec3 t(0.0), te(0.0), rad(0.0);
      if (finite[i])
      {
        t = unitOrZero(sum[i]);
        if (t == glm::dvec3(0.0))
        {
          t = fallback[i]; // a hairpin, or no segment at all (then zero)
        }
        degenerate[i] = t == glm::dvec3(0.0);
        te = unitOrZero(eyeFromWorld * t);
        if (path != 1)
        {
          const glm::dvec3 p = eyeFromWorld * (position[i] - eye);
          const glm::dvec3 v = perspective ? unitOrZero(-p) : glm::dvec3(0.0, 0.0, 1.0);
          rad = wf::cylinderRadianceClosed(
            te, v == glm::dvec3(0.0) ? glm::dvec3(0.0, 0.0, 1.0) : v, mat, eyeLights, table);
        }
        else
        {
          rad = glm::dvec3(map.lookup(te));
        }
        if (!tint.empty())
          rad *= tint[size_t(i)];
      }
      const float tw[3] = { float(t.x), float(t.y), float(t.z) };
      const float tv[3] = { float(te.x), float(te.y), float(te.z) };
      const float r[3] = { float(rad.x), float(rad.y), float(rad.z) };
      // The colour encodes the stored float radiance, so the two arrays agree exactly; encoded
      // in double, as this filter always has (in float about 4 in 10^6 codes would differ by one).
      const unsigned char c[3] = { wf::srgb8(double(r[0])), wf::srgb8(double(r[1])), wf::srgb8(double(r[2])) };
      worldTangents->SetTypedTuple(i, tw);
      eyeTangents->SetTypedTuple(i, tv);
      radiance->SetTypedTuple(i, r);
      colour->SetTypedTuple(i, c);
    }
  };
  // Chunks on this thread between parallel loops: progress and abort without touching the
  // pipeline from worker threads.
  const vtkIdType chunk = std::max<vtkIdType>(4096, n / 50);
  bool aborted = false;
  for (vtkIdType begin = 0; begin < n; begin += chunk)
  {
    this->UpdateProgress(double(begin) / double(n));
    if (this->GetAbortExecute())
    {
      aborted = true;
      break;
    }
    parallelFor(begin, std::min(n, begin + chunk), shade);
  }
  this->UpdateProgress(1.0);
  // The error of this very output: at up to 256 evenly spaced finite points, its radiance
  // against the exact cylinder model at that point's true view vector (for the map, that includes
  // the perspective it leaves out). 0 on the exact path, and after an abort (points not shaded).
  this->MeasuredError = 0.0;
  if (path != 2 && !aborted)
  {
    const vtkIdType step = std::max<vtkIdType>(1, n / 256);
    for (vtkIdType i = 0; i < n; i += step)
    {
      if (!finite[i])
      {
        continue;
      }
      double te[3], r[3];
      eyeTangents->GetTuple(i, te);
      radiance->GetTuple(i, r);
      const glm::dvec3 p = eyeFromWorld * (position[i] - eye);
      glm::dvec3 v = perspective ? unitOrZero(-p) : glm::dvec3(0.0, 0.0, 1.0);
      if (v == glm::dvec3(0.0))
      {
        v = glm::dvec3(0.0, 0.0, 1.0);
      }
      glm::dvec3 ex = wf::cylinderRadianceClosed(glm::dvec3(te[0], te[1], te[2]), v, mat, eyeLights);
      if (!tint.empty())
        ex *= tint[size_t(i)];
      const glm::dvec3 d = glm::abs(ex - glm::dvec3(r[0], r[1], r[2]));
      this->MeasuredError = std::max({ this->MeasuredError, d.x, d.y, d.z });
    }
  }
  for (vtkIdType i = 0; i < n; ++i)
  {
    this->DegeneratePoints += degenerate[i];
  }
  if (this->NonFinitePoints > 0)
  {
    vtkWarningMacro(<< this->NonFinitePoints
                    << " point(s) with a NaN or Inf coordinate: tangent (0, 0, 0), colour black");
  }
  return 1;
}

void vtkWireFurTangentShading::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Camera: " << static_cast<void*>(this->Camera.Get()) << "\n";
  os << indent << "Renderer: " << static_cast<void*>(this->Renderer.GetPointer()) << "\n";
  os << indent << "Diffuse: " << this->Diffuse[0] << " " << this->Diffuse[1] << " " << this->Diffuse[2] << "\n";
  os << indent << "Specular: " << this->Specular[0] << " " << this->Specular[1] << " " << this->Specular[2] << "\n";
  os << indent << "Exponent: " << this->Exponent << "\n";
  os << indent << "Ambient: " << this->Ambient[0] << " " << this->Ambient[1] << " " << this->Ambient[2] << "\n";
  os << indent << "LightCount: " << this->LightCount << "\n";
  const int path = this->ExactShading ? 2 : this->Shading;
  os << indent << "Shading: " << (this->Shading == 1 ? "maps" : this->Shading == 2 ? "exact" : "closed")
     << " (used: " << (path == 1 ? "maps" : path == 2 ? "exact" : "closed") << ")\n";
  os << indent << "ExactShading: " << (this->ExactShading ? "On" : "Off") << "\n";
  os << indent << "ExactTolerance: " << this->ExactTolerance << "\n";
  os << indent << "MapResolution: " << this->MapResolution << "\n";
  os << indent << "MapSamples: " << this->MapSamples << "\n";
  os << indent << "MapBuilds: " << this->Internals->Map.buildCount() << "\n";
  os << indent << "MapSeconds: " << this->Internals->Map.lastBuildSeconds() << "\n";
  os << indent << "ErrorEstimate: " << this->ErrorEstimate << "\n";
  os << indent << "NonFinitePoints: " << this->NonFinitePoints << "\n";
  os << indent << "SkipNonFinitePoints: " << this->SkipNonFinitePoints << "\n";
  os << indent << "MeasuredError: " << this->MeasuredError << "\n";
  os << indent << "DegeneratePoints: " << this->DegeneratePoints << "\n";
}

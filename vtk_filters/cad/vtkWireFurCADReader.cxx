#include "vtkWireFurCADReader.h"

#include "wf_cad_model.h"
#include "wf_cad_plugin.h"
#include "wf_cad_surface.h"
#include "wf_cad_worker.h"

#include "core/srgb.h"
#include "core/worker_process.h"
#include "render/edge_classes.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"
#include "vtkXMLPolyDataReader.h"

#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepLProp_SLProps.hxx>
#include <Geom2d_Curve.hxx>
#include <BRepBndLib.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <GCPnts_TangentialDeflection.hxx>
#include <Message_ProgressIndicator.hxx>
#include <Message_ProgressScope.hxx>
#include <Poly_Polygon3D.hxx>
#include <Precision.hxx>
#include <Poly_PolygonOnTriangulation.hxx>
#include <Poly_Triangulation.hxx>
#include <Prs3d_Drawer.hxx>
#include <Prs3d_IsoAspect.hxx>
#include <ShapeAnalysis_Surface.hxx>
#include <Standard_Failure.hxx>
#include <Standard_OutOfMemory.hxx>
#include <StdPrs_Isolines.hxx>
#include <TColgp_HSequenceOfPnt.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Vertex.hxx>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <dlfcn.h>
#include <sys/stat.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <limits>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>

vtkStandardNewMacro(vtkWireFurCADReader);

// The wirefur command loads this module only for CAD input (dlopen), and makes the reader here.
extern "C" WIREFURCAD_EXPORT vtkWireFurCADReader* wirefur_cad_new_reader()
{
  return vtkWireFurCADReader::New();
}

namespace
{

std::string lowerExtension(const std::string& path)
{
  std::string e = std::filesystem::path(path).extension().string();
  for (char& c : e)
    c = char(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

std::string failureText(const Standard_Failure& f)
{
  const char* m = f.GetMessageString();
  std::string s = (m && *m) ? m : f.DynamicType()->Name();
  for (char& ch : s)
    if (ch == '\n' || ch == '\r')
      ch = ' ';
  return s;
}

bool finite3(const gp_XYZ& p)
{
  return std::isfinite(p.X()) && std::isfinite(p.Y()) && std::isfinite(p.Z());
}

// One face's triangles with the exact surface data at its vertices.
struct FaceMesh
{
  int part = 0;
  int faceId = 0;  // in the file, across parts
  std::array<unsigned char, 3> colour{ 200, 200, 200 };
  std::vector<double> positions, su, sv, uv;  // 3, 3, 3, 2 per vertex
  std::vector<float> normals;                 // 3 per vertex
  std::vector<vtkIdType> triangles;           // 3 per triangle, face-local
  bool skipped = false;
  std::string problem;
};

struct FaceJob
{
  int part;
  int faceId;
  TopoDS_Face face;  // located
  std::optional<Quantity_Color> colour;
};

FaceMesh skippedFace(const FaceJob& job, const std::string& problem)
{
  FaceMesh m;
  m.part = job.part;
  m.faceId = job.faceId;
  m.skipped = true;
  m.problem = problem;
  return m;
}

std::array<unsigned char, 3> toSrgb8(const Quantity_Color& c)
{
  double r = 0, g = 0, b = 0;
  c.Values(r, g, b, Quantity_TOC_sRGB);
  auto q = [](double x) { return (unsigned char)std::lround(std::clamp(x, 0.0, 1.0) * 255.0); };
  return { q(r), q(g), q(b) };
}

void meshFace(const FaceJob& job, double modelSize, FaceMesh& out)
{
  out.part = job.part;
  out.faceId = job.faceId;
  if (job.colour)
    out.colour = toSrgb8(*job.colour);
  TopLoc_Location loc;
  const Handle(Poly_Triangulation)& tri = BRep_Tool::Triangulation(job.face, loc);
  if (tri.IsNull() || tri->NbTriangles() == 0 || tri->NbNodes() < 3)
  {
    out = skippedFace(job, "did not mesh");
    return;
  }
  const gp_Trsf trsf = loc.Transformation();
  const wfcad::FaceSurface surface(job.face);
  Handle(ShapeAnalysis_Surface) projector;
  const int n = tri->NbNodes();
  std::vector<char> degenerate;  // per node: Su x Sv vanishes there (the normal is a limit)
  degenerate.reserve(size_t(n));
  auto uvOf = [&](int node) { return gp_Pnt2d(out.uv[2 * size_t(node - 1)], out.uv[2 * size_t(node - 1) + 1]); };
  out.positions.reserve(3 * size_t(n));
  out.normals.reserve(3 * size_t(n));
  for (int i = 1; i <= n; ++i)
  {
    const gp_Pnt p = tri->Node(i).Transformed(trsf);
    if (!finite3(p.XYZ()))
    {
      out = skippedFace(job, "mesh node " + std::to_string(i) + " is not finite");
      return;
    }
    gp_Pnt2d uv;
    if (tri->HasUVNodes())
      uv = tri->UVNode(i);
    else
    {
      // BRep_Tool::Surface(face) is already placed by the face's location, like p.
      if (projector.IsNull())
        projector = new ShapeAnalysis_Surface(BRep_Tool::Surface(job.face));
      uv = projector->ValueOfUV(p, 1e-7);
    }
    const wf::SurfaceFrame f = surface.frame(uv.X(), uv.Y());
    degenerate.push_back(f.degenerate);
    out.positions.insert(out.positions.end(), { p.X(), p.Y(), p.Z() });
    out.normals.insert(out.normals.end(), { float(f.N.x), float(f.N.y), float(f.N.z) });
    out.su.insert(out.su.end(), { f.Su.x, f.Su.y, f.Su.z });
    out.sv.insert(out.sv.end(), { f.Sv.x, f.Sv.y, f.Sv.z });
    out.uv.insert(out.uv.end(), { uv.X(), uv.Y() });
  }
  // Counter-clockwise about the oriented normal: OpenCASCADE's triangles follow the surface's
  // own orientation, so a REVERSED face turns them, and a mirroring location turns them again.
  const bool flip = surface.normalSign() < 0.0;
  out.triangles.reserve(3 * size_t(tri->NbTriangles()));
  for (int t = 1; t <= tri->NbTriangles(); ++t)
  {
    int k[3] = { 0, 0, 0 };
    tri->Triangle(t).Get(k[0], k[1], k[2]);
    if (k[0] < 1 || k[1] < 1 || k[2] < 1 || k[0] > n || k[1] > n || k[2] > n || k[0] == k[1] || k[1] == k[2] ||
      k[0] == k[2])
      continue;
    if (flip)
      std::swap(k[1], k[2]);
    vtkIdType ids[3];
    for (int j = 0; j < 3; ++j)
    {
      ids[j] = vtkIdType(k[j] - 1);
      if (!degenerate[size_t(k[j] - 1)])
        continue;
      // A degenerate vertex (a cone's apex, a sphere's pole) has no normal of its own: the limit
      // differs along every meridian (the cone's). Each triangle gets its own copy, at the same
      // point but on the triangle's own meridian: the parameter along the collapsed edge moved
      // to the triangle's middle, where Surface::frame takes the limit along that meridian.
      const gp_Pnt2d a = uvOf(k[j]), b = uvOf(k[(j + 1) % 3]), c = uvOf(k[(j + 2) % 3]);
      const size_t src = size_t(k[j] - 1);
      const glm::dvec3 at(out.positions[3 * src], out.positions[3 * src + 1], out.positions[3 * src + 2]);
      const double tol = 1e-7 * std::max(1.0, glm::length(at)) + 1e-9 * modelSize;
      gp_Pnt2d m((b.X() + c.X()) / 2, a.Y());  // the collapsed edge runs along u (v fixed) ...
      if (glm::length(surface.evaluate(m.X(), m.Y()).P - at) > tol)
        m = gp_Pnt2d(a.X(), (b.Y() + c.Y()) / 2);  // ... or along v
      if (glm::length(surface.evaluate(m.X(), m.Y()).P - at) > tol)
        m = a;  // neither: keep the node's own limit
      const wf::SurfaceFrame f = surface.frame(m.X(), m.Y());
      ids[j] = vtkIdType(out.positions.size() / 3);
      out.positions.insert(out.positions.end(), { out.positions[3 * src], out.positions[3 * src + 1], out.positions[3 * src + 2] });
      out.normals.insert(out.normals.end(), { float(f.N.x), float(f.N.y), float(f.N.z) });
      out.su.insert(out.su.end(), { f.Su.x, f.Su.y, f.Su.z });
      out.sv.insert(out.sv.end(), { f.Sv.x, f.Sv.y, f.Sv.z });
      out.uv.insert(out.uv.end(), { m.X(), m.Y() });
    }
    out.triangles.insert(out.triangles.end(), { ids[0], ids[1], ids[2] });
  }
  // Drop the vertices no triangle uses (a degenerate node replaced by its copies), so every point
  // of the output belongs to a triangle of its face.
  const size_t nv = out.positions.size() / 3;
  std::vector<vtkIdType> remap(nv, -1);
  for (vtkIdType id : out.triangles)
    remap[size_t(id)] = 0;
  vtkIdType next = 0;
  for (size_t i = 0; i < nv; ++i)
  {
    if (remap[i] < 0)
      continue;
    const size_t to = size_t(next);
    remap[i] = next++;
    if (to == i)
      continue;
    for (int c = 0; c < 3; ++c)
    {
      out.positions[3 * to + c] = out.positions[3 * i + c];
      out.normals[3 * to + c] = out.normals[3 * i + c];
      out.su[3 * to + c] = out.su[3 * i + c];
      out.sv[3 * to + c] = out.sv[3 * i + c];
    }
    out.uv[2 * to] = out.uv[2 * i];
    out.uv[2 * to + 1] = out.uv[2 * i + 1];
  }
  out.positions.resize(3 * size_t(next));
  out.normals.resize(3 * size_t(next));
  out.su.resize(3 * size_t(next));
  out.sv.resize(3 * size_t(next));
  out.uv.resize(2 * size_t(next));
  for (vtkIdType& id : out.triangles)
    id = remap[size_t(id)];
}

// An edge as points: from a face's tessellation when the edge bounds one (the wire then lies on
// the surface's own boundary), else its 3-D polygon, else sampled to the deflection.
std::vector<gp_Pnt> edgePoints(const TopoDS_Edge& edge, const TopTools_ListOfShape* faces, double linear, double angular)
{
  std::vector<gp_Pnt> pts;
  if (faces)
    for (const TopoDS_Shape& f : *faces)
    {
      TopLoc_Location loc;
      const Handle(Poly_Triangulation)& tri = BRep_Tool::Triangulation(TopoDS::Face(f), loc);
      if (tri.IsNull())
        continue;
      const Handle(Poly_PolygonOnTriangulation) poly = BRep_Tool::PolygonOnTriangulation(edge, tri, loc);
      if (poly.IsNull())
        continue;
      const gp_Trsf t = loc.Transformation();
      for (int i = 1; i <= poly->NbNodes(); ++i)
      {
        const int k = poly->Node(i);
        if (k < 1 || k > tri->NbNodes())
          return {};
        pts.push_back(tri->Node(k).Transformed(t));
      }
      return pts;
    }
  TopLoc_Location loc;
  const Handle(Poly_Polygon3D)& p3 = BRep_Tool::Polygon3D(edge, loc);
  if (!p3.IsNull())
  {
    const gp_Trsf t = loc.Transformation();
    for (int i = 1; i <= p3->NbNodes(); ++i)
      pts.push_back(p3->Nodes().Value(i).Transformed(t));
    return pts;
  }
  const BRepAdaptor_Curve curve(edge);
  const GCPnts_TangentialDeflection sampler(curve, angular, linear, 2);
  for (int i = 1; i <= sampler.NbPoints(); ++i)
    pts.push_back(sampler.Value(i));
  return pts;
}

// The class of an edge from the faces on its sides (render/edge_classes.h), and for an edge
// between two faces the largest angle, in degrees, between their oriented normals at 9 points
// along it (0 along a fillet's tangent edge, 90 along a box's). Each normal comes from its face's
// own surface: at the edge's curve on that face, each curve over its own parameter range, where
// the edge is SameParameter; else at the 3-D point projected onto the surface. Two faces that run
// the edge the same way (an unsewn or unfixed shell) have one normal turned, as a consistently
// oriented shell would have it. Where no sample gives both normals (a degenerate surface) or
// OpenCASCADE fails, the angle is NaN and the edge counts as sharp, so it is drawn.
std::pair<wf::EdgeClass, double> classifyEdge(const TopoDS_Edge& edge, const TopTools_ListOfShape* faces, double featureAngle)
{
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<TopoDS_Face> distinct;
  if (faces)
    for (const TopoDS_Shape& f : *faces)
      if (std::none_of(distinct.begin(), distinct.end(), [&](const TopoDS_Face& g) { return g.IsSame(f); }))
        distinct.push_back(TopoDS::Face(f));
  if (distinct.empty())
    return { wf::EdgeClass::Free, nan };
  if (distinct.size() > 2)
    return { wf::EdgeClass::NonManifold, nan };
  try
  {
    if (distinct.size() == 1)
      return { BRep_Tool::IsClosed(edge, distinct[0]) ? wf::EdgeClass::Seam : wf::EdgeClass::Boundary, nan };
    // How each face runs the edge (its orientation as explored in the face, the face's own
    // orientation composed in).
    TopAbs_Orientation runs[2] = { TopAbs_EXTERNAL, TopAbs_EXTERNAL };
    for (int k = 0; k < 2; ++k)
      for (TopExp_Explorer x(distinct[size_t(k)], TopAbs_EDGE); x.More(); x.Next())
        if (x.Current().IsSame(edge))
        {
          runs[k] = x.Current().Orientation();
          break;
        }
    const bool sameWay = (runs[0] == TopAbs_FORWARD || runs[0] == TopAbs_REVERSED) && runs[0] == runs[1];
    const bool sameParameter = BRep_Tool::SameParameter(edge) && BRep_Tool::SameRange(edge);
    Standard_Real first[2] = { 0, 0 }, last[2] = { 0, 0 };
    Handle(Geom2d_Curve) c[2];
    for (int k = 0; k < 2; ++k)
      c[k] = BRep_Tool::CurveOnSurface(edge, distinct[size_t(k)], first[k], last[k]);
    const BRepAdaptor_Curve curve(edge);
    const BRepAdaptor_Surface s0(distinct[0]), s1(distinct[1]);
    const BRepAdaptor_Surface* s[2] = { &s0, &s1 };
    Handle(ShapeAnalysis_Surface) projector[2];
    double worst = -1.0;
    for (int i = 0; i <= 8; ++i)
    {
      const double f = 0.05 + 0.9 * i / 8.0;
      gp_Dir n[2];
      bool ok = true;
      for (int k = 0; k < 2 && ok; ++k)
      {
        gp_Pnt2d uv;
        if (sameParameter && !c[k].IsNull() && std::isfinite(first[k]) && std::isfinite(last[k]))
          uv = c[k]->Value(first[k] + (last[k] - first[k]) * f);
        else
        {
          const double t = curve.FirstParameter() + (curve.LastParameter() - curve.FirstParameter()) * f;
          if (projector[k].IsNull())
            projector[k] = new ShapeAnalysis_Surface(BRep_Tool::Surface(distinct[size_t(k)]));
          uv = projector[k]->ValueOfUV(curve.Value(t), Precision::Confusion());
        }
        BRepLProp_SLProps props(*s[k], uv.X(), uv.Y(), 1, Precision::Confusion());
        ok = props.IsNormalDefined();
        if (ok)
          n[k] = distinct[size_t(k)].Orientation() == TopAbs_REVERSED ? props.Normal().Reversed() : props.Normal();
      }
      if (ok)
        worst = std::max(worst, (sameWay ? n[0].Angle(n[1].Reversed()) : n[0].Angle(n[1])) * 180.0 / M_PI);
    }
    if (worst < 0.0)
      return { wf::EdgeClass::Sharp, nan };
    return { wf::EdgeSelection::byAngle(worst, featureAngle), worst };
  }
  catch (const Standard_Failure&)
  {
    return { wf::EdgeClass::Sharp, nan };
  }
}

// OpenCASCADE's progress of one meshing run, forwarded to the algorithm's progress events (the
// range [from, to] of the whole update), and VTK's abort flag back as a user break. OpenCASCADE
// calls Show under its own lock, from whichever thread advanced.
class MeshProgress : public Message_ProgressIndicator
{
public:
  MeshProgress(vtkAlgorithm* algorithm, double from, double to)
    : Algorithm(algorithm)
    , From(from)
    , To(to)
  {
  }
  Standard_Boolean UserBreak() override { return this->Algorithm->GetAbortExecute() != 0; }
  void Show(const Message_ProgressScope&, const Standard_Boolean force) override
  {
    const double p = this->From + (this->To - this->From) * std::clamp(this->GetPosition(), 0.0, 1.0);
    if (force || p >= this->Last + 0.01)
    {
      this->Last = p;
      this->Algorithm->UpdateProgress(p);
    }
  }

private:
  vtkAlgorithm* Algorithm;
  double From, To, Last = -1.0;
};

} // namespace

class vtkWireFurCADReader::vtkInternals
{
public:
  std::vector<std::string> partNames;
  int faces = 0, meshedFaces = 0, skippedFaces = 0, edges = 0;
  std::array<int, 7> edgesOfClass{};
  double appliedDeflection = 0.0, modelSize = 0.0, readSeconds = 0.0, meshSeconds = 0.0;
  std::string error, warning;
  // The meshed faces (located), their FaceId and part: for wirefur_cad_face_surfaces.
  std::vector<TopoDS_Face> faceShapes;
  std::vector<int> faceIds, faceParts;
  // Read by the worker: the faces it meshed (FaceId), whose exact surfaces are read here only
  // when asked for (wirefur_cad_face_surfaces), once.
  bool viaWorker = false, facesRead = false;
  std::vector<int> workerFaceIds;
  // The file the worker read, as it was then: the lazy read refuses a file changed since (its
  // faces would not be the ones meshed).
  std::string workerPath;
  std::string workerFileStamp;  // device, inode, size, modification and change times
  void clear() { *this = vtkInternals(); }
};

namespace
{
// What tells one version of a file from another: device, inode, size, modification time and
// change time (which no utime can set back); empty when it cannot be read.
std::string fileStamp(const std::string& path)
{
  struct stat st{};
  if (::stat(path.c_str(), &st) != 0)
    return std::string();
  return std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino) + ":" + std::to_string(st.st_size) + ":" +
    std::to_string(st.st_mtim.tv_sec) + "." + std::to_string(st.st_mtim.tv_nsec) + ":" +
    std::to_string(st.st_ctim.tv_sec) + "." + std::to_string(st.st_ctim.tv_nsec);
}
} // namespace

extern "C" WIREFURCAD_EXPORT int wirefur_cad_face_surfaces(vtkWireFurCADReader* reader, std::vector<WireFurCadFace>* faces)
{
  if (!reader || !faces)
    return 0;
  vtkWireFurCADReader::vtkInternals& in = *reader->GetInternals();
  faces->clear();
  // (Two filters may ask at once: the lazy read below writes the reader's lists.)
  static std::mutex lazyRead;
  const std::lock_guard<std::mutex> lock(lazyRead);
  if (in.viaWorker && !in.facesRead)
  {
    // The worker has read and meshed the file cleanly: its exact faces are read here, without
    // meshing, and those the worker meshed are kept (as wirefur_cad_face_surfaces promises) --
    // from the file the worker read, if it is unchanged since.
    in.facesRead = true;
    const std::string stamp = fileStamp(in.workerPath);
    if (stamp.empty() || stamp != in.workerFileStamp)
    {
      vtkWarningWithObjectMacro(reader, << in.workerPath
        << ": changed or gone since it was read: no exact faces (Modified() the reader to read it again)");
      return 0;
    }
    vtkNew<vtkWireFurCADReader> again;
    again->SetFileName(in.workerPath.c_str());
    again->FacesOnlyOn();
    again->SetNumberOfThreads(reader->GetNumberOfThreads());
    again->Update();
    const vtkWireFurCADReader::vtkInternals& a = *again->GetInternals();
    for (size_t i = 0; i < a.faceShapes.size(); ++i)
      if (std::binary_search(in.workerFaceIds.begin(), in.workerFaceIds.end(), a.faceIds[i]))
      {
        in.faceShapes.push_back(a.faceShapes[i]);
        in.faceIds.push_back(a.faceIds[i]);
        in.faceParts.push_back(a.faceParts[i]);
      }
  }
  for (size_t i = 0; i < in.faceShapes.size(); ++i)
  {
    try
    {
      WireFurCadFace f;
      auto surface = std::make_shared<wfcad::FaceSurface>(in.faceShapes[i]);
      f.inside = std::make_shared<wfcad::FaceMask>(in.faceShapes[i], surface->domain());
      f.surface = surface;
      f.faceId = in.faceIds[i];
      f.part = in.faceParts[i];
      faces->push_back(std::move(f));
    }
    catch (const Standard_Failure&)
    {
    }
  }
  return int(faces->size());
}

vtkWireFurCADReader::vtkWireFurCADReader()
  : Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(2);
}

vtkWireFurCADReader::~vtkWireFurCADReader()
{
  this->SetFileName(nullptr);
  delete this->Internals;
}

bool vtkWireFurCADReader::CanReadFile(const char* fileName)
{
  if (!fileName)
    return false;
  const std::string e = lowerExtension(fileName);
  return e == ".step" || e == ".stp" || e == ".iges" || e == ".igs" || e == ".brep" || e == ".fcstd";
}

int vtkWireFurCADReader::GetNumberOfParts() const { return int(this->Internals->partNames.size()); }
std::string vtkWireFurCADReader::GetPartName(int part) const
{
  return part >= 0 && part < this->GetNumberOfParts() ? this->Internals->partNames[size_t(part)] : std::string();
}
int vtkWireFurCADReader::GetNumberOfFaces() const { return this->Internals->faces; }
int vtkWireFurCADReader::GetNumberOfMeshedFaces() const { return this->Internals->meshedFaces; }
int vtkWireFurCADReader::GetNumberOfSkippedFaces() const { return this->Internals->skippedFaces; }
int vtkWireFurCADReader::GetNumberOfEdges() const { return this->Internals->edges; }
int vtkWireFurCADReader::GetNumberOfEdgesOfClass(int edgeClass) const
{
  return edgeClass >= 0 && edgeClass < 7 ? this->Internals->edgesOfClass[size_t(edgeClass)] : 0;
}
double vtkWireFurCADReader::GetAppliedLinearDeflection() const { return this->Internals->appliedDeflection; }
double vtkWireFurCADReader::GetModelSize() const { return this->Internals->modelSize; }
double vtkWireFurCADReader::GetReadSeconds() const { return this->Internals->readSeconds; }
double vtkWireFurCADReader::GetMeshSeconds() const { return this->Internals->meshSeconds; }
std::string vtkWireFurCADReader::GetErrorMessage() const { return this->Internals->error; }
std::string vtkWireFurCADReader::GetWarningMessage() const { return this->Internals->warning; }

int vtkWireFurCADReader::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInternals& in = *this->Internals;
  in.clear();
  vtkPolyData* facesOut = vtkPolyData::GetData(outputVector, 0);
  vtkPolyData* edgesOut = vtkPolyData::GetData(outputVector, 1);
  const std::string path = this->FileName ? this->FileName : "";
  // A failed read leaves both outputs empty and the pipeline going (1), as the module's filters
  // do: the one line is the message. (Returning 0 would make VTK's executive print the whole
  // request after it: a dozen more lines in ParaView's output window.)
  auto fail = [&](const std::string& message) {
    in.error = (path.empty() ? std::string("(no file name)") : path) + ": " + message;
    vtkErrorMacro(<< in.error);
    facesOut->Initialize();
    edgesOut->Initialize();
    return 1;
  };
  if (path.empty())
    return fail("no file name given");
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    return fail("no such file");
  if (!std::filesystem::is_regular_file(path, ec))
    return fail("not a regular file");
  if (std::filesystem::file_size(path, ec) == 0)
    return fail("empty file");
  const std::string ext = lowerExtension(path);
  if (this->ReadInWorker && !this->FacesOnly)
    return this->RequestDataInWorker(path, facesOut, edgesOut);
  const auto t0 = std::chrono::steady_clock::now();
  auto seconds = [](auto since) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
  };
  tbb::task_arena arena(this->NumberOfThreads > 0 ? this->NumberOfThreads : tbb::task_arena::automatic);

  wfcad::Model model;
  try
  {
    this->UpdateProgress(0.0);
    if (ext == ".step" || ext == ".stp")
      model = wfcad::readStepOrIges(path, false);
    else if (ext == ".iges" || ext == ".igs")
      model = wfcad::readStepOrIges(path, true);
    else if (ext == ".brep")
      model = wfcad::readBrep(path);
    else if (ext == ".fcstd")
      model = wfcad::readFreeCad(path);
    else
      return fail("unsupported extension '" + ext + "' (expected .step .stp .iges .igs .brep .FCStd)");
  }
  catch (const wfcad::CadError& e)
  {
    return fail(e.what());
  }
  catch (const Standard_Failure& f)
  {
    return fail("OpenCASCADE failed while reading: " + failureText(f));
  }
  catch (const std::bad_alloc&)
  {
    return fail("out of memory while reading");
  }
  in.readSeconds = seconds(t0);
  this->UpdateProgress(0.3);

  // Located parts, the model's size and the deflection.
  std::vector<TopoDS_Shape> located;
  Bnd_Box box;
  for (const wfcad::Part& p : model.parts)
  {
    // A mirroring placement (a mirrored instance) is a location with a negative scale, which
    // OpenCASCADE refuses by default: allowed here, the normals' sign takes care of it.
    located.push_back(p.shape.Moved(p.placement, Standard_False));
    in.partNames.push_back(p.name.empty() ? "part " + std::to_string(in.partNames.size() + 1) : p.name);
    try
    {
      BRepBndLib::Add(located.back(), box, Standard_False);
    }
    catch (const Standard_Failure&)
    {
    }
  }
  if (box.IsVoid())
    return fail("no geometry (the shapes have no faces, edges or vertices)");
  double x0, y0, z0, x1, y1, z1;
  box.Get(x0, y0, z0, x1, y1, z1);
  in.modelSize = std::sqrt((x1 - x0) * (x1 - x0) + (y1 - y0) * (y1 - y0) + (z1 - z0) * (z1 - z0));
  if (!std::isfinite(in.modelSize) || in.modelSize > 1e30)
    return fail("the model's bounds are not finite (an unbounded shape?)");
  if (in.modelSize <= 0.0)
    in.modelSize = 1.0;
  const double linear = this->RelativeDeflection ? this->LinearDeflection * in.modelSize : this->LinearDeflection;
  // OpenCASCADE's tolerances are absolute: its mesher fails below Precision::Confusion (1e-7),
  // which a model of a few micrometres at the relative default asks for. Such a model meshes at
  // 1e-7, with the angular deflection still bounding curved faces.
  in.appliedDeflection = std::max({ linear, in.modelSize * 1e-9, Precision::Confusion() });
  const double angular = this->AngularDeflection;

  // Mesh each distinct shape once (instances share their faces' triangulations), dropping any
  // triangulation the file carried so that the deflection asked for is the one used.
  const auto tm = std::chrono::steady_clock::now();
  if (!this->FacesOnly)
  {
    std::vector<TopoDS_Shape> distinct;
    for (const wfcad::Part& p : model.parts)
      if (std::none_of(distinct.begin(), distinct.end(), [&](const TopoDS_Shape& s) { return s.IsPartner(p.shape); }))
        distinct.push_back(p.shape);
    for (size_t i = 0; i < distinct.size(); ++i)
    {
      if (this->GetAbortExecute())
        return fail("aborted");
      try
      {
        BRepTools::Clean(distinct[i]);
        const double from = 0.3 + 0.3 * double(i) / double(distinct.size());
        Handle(MeshProgress) progress = new MeshProgress(this, from, from + 0.3 / double(distinct.size()));
        arena.execute([&] {
          IMeshTools_Parameters params;
          params.Deflection = in.appliedDeflection;
          params.Angle = angular;
          params.Relative = Standard_False;
          params.InParallel = this->NumberOfThreads != 1;
          BRepMesh_IncrementalMesh mesher(distinct[i], params, progress->Start());
        });
      }
      catch (const Standard_OutOfMemory&)
      {
        // Not a face to skip: the model would come out with holes that depend on the memory.
        return fail("out of memory while meshing");
      }
      catch (const std::bad_alloc&)
      {
        return fail("out of memory while meshing");
      }
      catch (const Standard_Failure&)
      {
        // Faces left without a triangulation are counted as skipped below.
      }
      this->UpdateProgress(0.3 + 0.3 * double(i + 1) / double(distinct.size()));
    }
  }

  // Faces, in file order.
  std::vector<FaceJob> jobs;
  for (size_t p = 0; p < model.parts.size(); ++p)
  {
    int k = 0;
    const wfcad::Part& part = model.parts[p];
    for (TopExp_Explorer e(part.shape, TopAbs_FACE); e.More(); e.Next(), ++k)
    {
      FaceJob j{ int(p), int(jobs.size()), TopoDS::Face(e.Current().Moved(part.placement, Standard_False)), part.colour };
      if (size_t(k) < part.faceColours.size() && part.faceColours[size_t(k)])
        j.colour = part.faceColours[size_t(k)];
      jobs.push_back(j);
    }
  }
  in.faces = int(jobs.size());
  if (this->FacesOnly)
  {
    // The exact faces alone (wirefur_cad_face_surfaces), every one: nothing meshed, no output.
    for (const FaceJob& j : jobs)
    {
      in.faceShapes.push_back(j.face);
      in.faceIds.push_back(j.faceId);
      in.faceParts.push_back(j.part);
    }
    in.meshSeconds = seconds(tm);
    this->UpdateProgress(1.0);
    return 1;
  }
  // The triangle budget, checked before any vertex data is made.
  {
    double total = 0;
    for (const FaceJob& j : jobs)
    {
      TopLoc_Location loc;
      const Handle(Poly_Triangulation)& t = BRep_Tool::Triangulation(j.face, loc);
      if (!t.IsNull())
        total += t->NbTriangles();
    }
    if (total > double(this->MaximumTriangles))
      return fail(std::to_string(std::llround(total)) + " triangles at deflection " + std::to_string(in.appliedDeflection) +
        ", over the limit of " + std::to_string(this->MaximumTriangles) + " (raise the deflection)");
  }
  std::vector<FaceMesh> meshes(jobs.size());
  arena.execute([&] {
    tbb::parallel_for(size_t(0), jobs.size(), [&](size_t i) {
      try
      {
        meshFace(jobs[i], in.modelSize, meshes[i]);
      }
      catch (const Standard_Failure& f)
      {
        meshes[i] = skippedFace(jobs[i], failureText(f));
      }
    });
  });
  this->UpdateProgress(0.8);

  // Faces output.
  {
    size_t nv = 0, nt = 0;
    for (const FaceMesh& m : meshes)
      nv += m.positions.size() / 3, nt += m.triangles.size() / 3;
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(vtkIdType(nv));
    auto makeD = [&](const char* name, int comps) {
      vtkNew<vtkDoubleArray> a;
      a->SetName(name);
      a->SetNumberOfComponents(comps);
      a->SetNumberOfTuples(vtkIdType(nv));
      return vtkSmartPointer<vtkDoubleArray>(a);
    };
    auto su = makeD("Su", 3), sv = makeD("Sv", 3), tc = makeD("TCoords", 2);
    vtkNew<vtkFloatArray> normals;
    normals->SetName("Normals");
    normals->SetNumberOfComponents(3);
    normals->SetNumberOfTuples(vtkIdType(nv));
    vtkNew<vtkUnsignedCharArray> colours;
    colours->SetName("Colors");
    colours->SetNumberOfComponents(3);
    colours->SetNumberOfTuples(vtkIdType(nv));
    vtkNew<vtkIntArray> faceIds, partIds;
    faceIds->SetName("FaceId");
    partIds->SetName("PartId");
    vtkNew<vtkCellArray> polys;
    polys->AllocateExact(vtkIdType(nt), vtkIdType(3 * nt));
    vtkIdType base = 0;
    std::string firstSkip;
    for (const FaceMesh& m : meshes)
    {
      if (m.skipped)
      {
        ++in.skippedFaces;
        if (firstSkip.empty())
          firstSkip = "face " + std::to_string(m.faceId) + " of part '" + in.partNames[size_t(m.part)] + "': " + m.problem;
        continue;
      }
      ++in.meshedFaces;
      in.faceShapes.push_back(jobs[size_t(m.faceId)].face);
      in.faceIds.push_back(m.faceId);
      in.faceParts.push_back(m.part);
      const vtkIdType n = vtkIdType(m.positions.size() / 3);
      for (vtkIdType i = 0; i < n; ++i)
      {
        points->SetPoint(base + i, &m.positions[size_t(3 * i)]);
        su->SetTypedTuple(base + i, &m.su[size_t(3 * i)]);
        sv->SetTypedTuple(base + i, &m.sv[size_t(3 * i)]);
        tc->SetTypedTuple(base + i, &m.uv[size_t(2 * i)]);
        normals->SetTypedTuple(base + i, &m.normals[size_t(3 * i)]);
        colours->SetTypedTuple(base + i, m.colour.data());
      }
      for (size_t t = 0; t < m.triangles.size(); t += 3)
      {
        const vtkIdType ids[3] = { base + m.triangles[t], base + m.triangles[t + 1], base + m.triangles[t + 2] };
        polys->InsertNextCell(3, ids);
        faceIds->InsertNextValue(m.faceId);
        partIds->InsertNextValue(m.part);
      }
      base += n;
    }
    facesOut->SetPoints(points);
    facesOut->SetPolys(polys);
    facesOut->GetPointData()->SetNormals(normals);
    facesOut->GetPointData()->SetTCoords(tc);
    facesOut->GetPointData()->SetTangents(su);
    facesOut->GetPointData()->AddArray(sv);
    facesOut->GetPointData()->SetScalars(colours);
    facesOut->GetCellData()->AddArray(faceIds);
    facesOut->GetCellData()->AddArray(partIds);
    if (in.skippedFaces > 0)
      in.warning = path + ": skipped " + std::to_string(in.skippedFaces) + " of " + std::to_string(in.faces) +
        " faces that failed to mesh (first: " + firstSkip + ")";
  }
  in.meshSeconds = seconds(tm);
  this->UpdateProgress(0.9);

  // Edges (and iso lines) output.
  {
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    vtkNew<vtkCellArray> lines;
    vtkNew<vtkIntArray> kind, edgeIds, partIds, edgeClasses;
    vtkNew<vtkFloatArray> edgeAngles;
    kind->SetName("Kind");
    edgeClasses->SetName("EdgeClass");
    edgeAngles->SetName("EdgeAngle");
    edgeIds->SetName("EdgeId");
    partIds->SetName("PartId");
    int edgeCounter = 0;
    auto addLine = [&](const std::vector<vtkIdType>& ids, int k, int id, int part, int cls = -1, double angle = std::numeric_limits<double>::quiet_NaN()) {
      if (ids.size() < 2)
        return;
      lines->InsertNextCell(vtkIdType(ids.size()), ids.data());
      kind->InsertNextValue(k);
      edgeClasses->InsertNextValue(cls);
      edgeAngles->InsertNextValue(float(angle));
      edgeIds->InsertNextValue(id);
      partIds->InsertNextValue(part);
    };
    for (size_t p = 0; p < located.size(); ++p)
    {
      TopTools_IndexedMapOfShape edgeMap, vertexMap;
      TopTools_IndexedDataMapOfShapeListOfShape edgeFaces;
      try
      {
        TopExp::MapShapes(located[p], TopAbs_EDGE, edgeMap);
        TopExp::MapShapes(located[p], TopAbs_VERTEX, vertexMap);
        TopExp::MapShapesAndAncestors(located[p], TopAbs_EDGE, TopAbs_FACE, edgeFaces);
      }
      catch (const Standard_Failure&)
      {
        continue;
      }
      std::vector<vtkIdType> vertexIds(size_t(vertexMap.Extent()) + 1, -1);
      auto vertexPoint = [&](const TopoDS_Vertex& v, const gp_Pnt& fallback) -> vtkIdType {
        const int k = v.IsNull() ? 0 : vertexMap.FindIndex(v);
        if (k > 0 && vertexIds[size_t(k)] >= 0)
          return vertexIds[size_t(k)];
        const vtkIdType id = points->InsertNextPoint(fallback.X(), fallback.Y(), fallback.Z());
        if (k > 0)
          vertexIds[size_t(k)] = id;
        return id;
      };
      for (int e = 1; e <= edgeMap.Extent(); ++e)
      {
        const TopoDS_Edge edge = TopoDS::Edge(edgeMap(e));
        const int id = edgeCounter++;
        try
        {
          if (BRep_Tool::Degenerated(edge))
            continue;
          const TopTools_ListOfShape* faces = edgeFaces.Seek(edge);
          std::vector<gp_Pnt> pts = edgePoints(edge, faces, in.appliedDeflection, angular);
          if (pts.size() < 2 || !std::all_of(pts.begin(), pts.end(), [](const gp_Pnt& q) { return finite3(q.XYZ()); }))
            continue;
          TopoDS_Vertex v1, v2;
          TopExp::Vertices(edge, v1, v2);  // v1 at the first parameter, where the polygon starts
          std::vector<vtkIdType> ids;
          ids.push_back(vertexPoint(v1, pts.front()));
          for (size_t i = 1; i + 1 < pts.size(); ++i)
            ids.push_back(points->InsertNextPoint(pts[i].X(), pts[i].Y(), pts[i].Z()));
          ids.push_back(vertexPoint(v2, pts.back()));
          const auto [cls, angle] = classifyEdge(edge, faces, this->FeatureAngle);
          addLine(ids, 0, id, int(p), int(cls), angle);
          ++in.edges;
          ++in.edgesOfClass[size_t(cls)];
        }
        catch (const Standard_Failure&)
        {
        }
      }
    }
    if (this->NumberOfUIsoLines > 0 || this->NumberOfVIsoLines > 0)
    {
      Handle(Prs3d_Drawer) drawer = new Prs3d_Drawer();
      drawer->SetUIsoAspect(new Prs3d_IsoAspect(Quantity_NOC_GRAY, Aspect_TOL_SOLID, 1.0, this->NumberOfUIsoLines));
      drawer->SetVIsoAspect(new Prs3d_IsoAspect(Quantity_NOC_GRAY, Aspect_TOL_SOLID, 1.0, this->NumberOfVIsoLines));
      drawer->SetIsoOnPlane(Standard_True);
      drawer->SetIsoOnTriangulation(Standard_False);
      std::vector<std::array<Prs3d_NListOfSequenceOfPnt, 2>> isos(jobs.size());
      arena.execute([&] {
        tbb::parallel_for(size_t(0), jobs.size(), [&](size_t i) {
          if (meshes[i].skipped)
            return;
          try
          {
            StdPrs_Isolines::AddOnSurface(jobs[i].face, drawer, in.appliedDeflection, isos[i][0], isos[i][1]);
          }
          catch (const Standard_Failure&)
          {
            isos[i][0].Clear();
            isos[i][1].Clear();
          }
        });
      });
      for (size_t i = 0; i < jobs.size(); ++i)
        for (int k = 0; k < 2; ++k)
          for (const Handle(TColgp_HSequenceOfPnt)& seq : isos[i][size_t(k)])
          {
            std::vector<vtkIdType> ids;
            for (int j = 1; j <= seq->Length(); ++j)
            {
              const gp_Pnt& q = seq->Value(j);
              if (finite3(q.XYZ()))
                ids.push_back(points->InsertNextPoint(q.X(), q.Y(), q.Z()));
            }
            addLine(ids, k + 1, jobs[i].faceId, jobs[i].part);
          }
    }
    edgesOut->SetPoints(points);
    edgesOut->SetLines(lines);
    edgesOut->GetCellData()->AddArray(kind);
    edgesOut->GetCellData()->AddArray(edgeIds);
    edgesOut->GetCellData()->AddArray(partIds);
    edgesOut->GetCellData()->AddArray(edgeClasses);
    edgesOut->GetCellData()->AddArray(edgeAngles);
  }

  vtkNew<vtkStringArray> names;
  names->SetName("PartNames");
  for (const std::string& n : in.partNames)
    names->InsertNextValue(n);
  facesOut->GetFieldData()->AddArray(names);
  edgesOut->GetFieldData()->AddArray(names);
  // The chord error of the tessellation, world units (vtkWireFurEdgeVisibility's silhouette slack).
  vtkNew<vtkDoubleArray> deflection;
  deflection->SetName("LinearDeflection");
  deflection->InsertNextValue(in.appliedDeflection);
  facesOut->GetFieldData()->AddArray(deflection);
  edgesOut->GetFieldData()->AddArray(deflection);
  if (in.meshedFaces == 0 && in.edges == 0)
  {
    facesOut->Initialize();
    edgesOut->Initialize();
    return fail(in.faces > 0 ? "none of the " + std::to_string(in.faces) + " faces could be meshed" +
          (in.warning.empty() ? std::string() : " (" + in.warning.substr(in.warning.find("first: ") + 7))
                             : std::string("no faces and no edges to draw"));
  }
  this->UpdateProgress(1.0);
  return 1;
}

namespace
{
void workerAnchor() {}

// This library's folder, found when it is loaded (a relative path from LD_LIBRARY_PATH would
// mean another folder once the host changes directory).
const std::filesystem::path gLibraryFolder = [] {
  Dl_info info{};
  if (!dladdr(reinterpret_cast<void*>(&workerAnchor), &info) || !info.dli_fname)
    return std::filesystem::path();
  std::error_code ec;
  const std::filesystem::path lib = std::filesystem::canonical(info.dli_fname, ec);
  return ec ? std::filesystem::path(info.dli_fname).parent_path() : lib.parent_path();
}();

double readProgress(const std::string& file)
{
  double p = 0;
  std::ifstream in(file, std::ios::binary);
  return in.read(reinterpret_cast<char*>(&p), sizeof p) && std::isfinite(p) ? std::clamp(p, 0.0, 1.0) : 0.0;
}
} // namespace

void vtkWireFurCADReader::SetWorkerTimeout(double seconds)
{
  if (std::isnan(seconds))
    return;
  seconds = std::clamp(seconds, 0.1, 1e6);
  if (seconds != this->WorkerTimeout)
  {
    this->WorkerTimeout = seconds;
    this->Modified();
  }
}

std::string vtkWireFurCADReader::GetWorkerExecutable()
{
  if (gLibraryFolder.empty())
    return std::string();
  std::error_code ec;
  const std::filesystem::path exe = gLibraryFolder / wfcad::kWorkerName;
  return std::filesystem::is_regular_file(exe, ec) && access(exe.c_str(), X_OK) == 0 ? exe.string() : std::string();
}

int vtkWireFurCADReader::RequestDataInWorker(const std::string& path, vtkPolyData* facesOut, vtkPolyData* edgesOut)
{
  vtkInternals& in = *this->Internals;
  auto fail = [&](const std::string& message) {  // (as RequestData's)
    in.error = path + ": " + message;
    vtkErrorMacro(<< in.error);
    return 1;
  };
  const std::string exe = GetWorkerExecutable();
  if (exe.empty())
    return fail(std::string("cannot read in a worker process: ") + wfcad::kWorkerName +
      " is not installed beside the WireFurCAD library (or turn ReadInWorker off)");
  const wf::TemporaryFolder folder("wirefur-cad-");
  if (folder.path().empty())
    return fail("cannot make a temporary folder for the CAD worker");
  // The file as it is now, for the exact faces read later (wirefur_cad_face_surfaces).
  std::error_code ec;
  in.workerPath = std::filesystem::absolute(path, ec).string();
  in.workerFileStamp = fileStamp(path);
  std::vector<std::string> args = { wfcad::kWorkerName, path, folder.path(), std::to_string(getpid()),
    wf::workerNumber(this->WorkerTimeout) };
  args.push_back(wf::workerNumber(this->LinearDeflection));
  args.push_back(this->RelativeDeflection ? "1" : "0");
  args.push_back(wf::workerNumber(this->AngularDeflection));
  args.push_back(std::to_string(this->NumberOfUIsoLines));
  args.push_back(std::to_string(this->NumberOfVIsoLines));
  args.push_back(std::to_string(this->MaximumTriangles));
  args.push_back(wf::workerNumber(this->FeatureAngle));
  args.push_back(std::to_string(this->NumberOfThreads));
  this->UpdateProgress(0.0);
  // While it runs: its progress (a double it rewrites in FOLDER/progress) every 50 ms, and an
  // abort request (AbortExecute) kills it.
  const std::string progressFile = folder.path() + "/" + wfcad::kWorkerProgressFile;
  auto lastLook = std::chrono::steady_clock::now();
  double shown = 0.0;
  wf::WorkerOptions run;
  run.timeoutSeconds = this->WorkerTimeout;
  run.stderrPath = folder.path() + "/stderr";
  run.poll = [&] {
    if (this->GetAbortExecute())
      return false;
    const auto now = std::chrono::steady_clock::now();
    if (now - lastLook > std::chrono::milliseconds(50))
    {
      lastLook = now;
      const double p = readProgress(progressFile);
      if (p > shown)
        this->UpdateProgress(shown = p);
    }
    return true;
  };
  const wf::WorkerExit e = wf::runWorker(exe, args, run);
  if (!e.started)
    return fail("cannot start the CAD worker " + exe + ": " + e.startError);
  if (e.timedOut || (e.signalled && e.signal == SIGALRM))  // (SIGALRM: the worker's own limit)
    return fail("reading and meshing did not finish within " + wf::workerNumber(this->WorkerTimeout) +
      " s (OpenCASCADE may loop on a corrupt file; WorkerTimeout sets the limit)");
  if (e.aborted)
    return fail("the read was aborted");
  if (e.signalled)
    return fail("OpenCASCADE crashed reading this file (" + wf::signalDescription(e.signal) +
      (e.signal == SIGKILL || e.signal == SIGABRT ? ", out of memory?" : "") +
      "): it is corrupt, or uses something OpenCASCADE 7.6 cannot read");
  // The worker writes its completion marker last, holding its exit status: without it there
  // is no whole result, whatever the status (unknown when the host reaps its children itself).
  int done = -1;
  {
    std::ifstream marker(folder.path() + "/" + wfcad::kWorkerDoneFile);
    if (!(marker >> done))
      done = -1;
  }
  const int status = e.statusUnknown ? done : e.status;
  const std::string words = wf::lastLineOf(run.stderrPath);
  if (status == wf::kWorkerExitOutOfMemory)
  {
    char cap[32];
    std::snprintf(cap, sizeof cap, "%.1f", wf::workerMemoryCap() / double(1 << 30));
    return fail(std::string("out of memory in the CAD worker (its cap is ") + cap +
      " GiB: half the memory this machine or its cgroup allows; turn ReadInWorker off to read without it)");
  }
  if (status == wf::kWorkerExitCannotRun || status == wf::kWorkerExitUsage || status == wf::kWorkerExitWriteFailed ||
    status == wf::kWorkerExitOrphaned)
    return fail("the CAD worker " + exe + " failed (status " + std::to_string(status) + ")" +
      (words.empty() ? std::string() : ": " + words));
  if ((status != 0 && status != 2) || done != status)
    return fail("OpenCASCADE crashed reading this file (the worker stopped with " +
      (status < 0 ? std::string("an unknown status") : "status " + std::to_string(status)) + " and no result" +
      (words.empty() ? std::string() : ": " + words) +
      "): it is corrupt, or uses something OpenCASCADE 7.6 cannot read");
  const std::string facesFile = folder.path() + "/faces.vtp", edgesFile = folder.path() + "/edges.vtp";
  vtkNew<vtkXMLPolyDataReader> faces, edges;
  faces->SetFileName(facesFile.c_str());
  edges->SetFileName(edgesFile.c_str());
  faces->Update();
  edges->Update();
  vtkFieldData* field = faces->GetOutput()->GetFieldData();
  vtkDoubleArray* figures = vtkDoubleArray::SafeDownCast(field->GetAbstractArray(wfcad::kWorkerFigures));
  vtkStringArray* messages = vtkStringArray::SafeDownCast(field->GetAbstractArray(wfcad::kWorkerMessages));
  if (faces->GetErrorCode() || edges->GetErrorCode() || !figures || !messages ||
    figures->GetNumberOfValues() != wfcad::kFigureCount || messages->GetNumberOfValues() != 2)
    return fail("the CAD worker's result is unreadable");
  // The figures, also for a failed read (as in process: "none of the N faces could be meshed"
  // leaves N faces, N skipped).
  in.warning = messages->GetValue(1);
  in.faces = int(figures->GetValue(wfcad::kFaces));
  in.meshedFaces = int(figures->GetValue(wfcad::kMeshedFaces));
  in.skippedFaces = int(figures->GetValue(wfcad::kSkippedFaces));
  in.edges = int(figures->GetValue(wfcad::kEdges));
  for (int c = 0; c < 7; ++c)
    in.edgesOfClass[size_t(c)] = int(figures->GetValue(wfcad::kEdgesOfClass0 + c));
  in.appliedDeflection = figures->GetValue(wfcad::kAppliedDeflection);
  in.modelSize = figures->GetValue(wfcad::kModelSize);
  in.readSeconds = figures->GetValue(wfcad::kReadSeconds);
  in.meshSeconds = figures->GetValue(wfcad::kMeshSeconds);
  if (status == 2 || !messages->GetValue(0).empty())
  {
    in.error = messages->GetValue(0).empty() ? path + ": the CAD worker failed" : messages->GetValue(0);
    vtkErrorMacro(<< in.error);
    return 1;
  }
  in.viaWorker = true;
  field->RemoveArray(wfcad::kWorkerFigures);
  field->RemoveArray(wfcad::kWorkerMessages);
  if (vtkStringArray* names = vtkStringArray::SafeDownCast(field->GetAbstractArray("PartNames")))
    for (vtkIdType i = 0; i < names->GetNumberOfValues(); ++i)
      in.partNames.push_back(names->GetValue(i));
  if (vtkDataArray* ids = faces->GetOutput()->GetCellData()->GetArray("FaceId"))
    for (vtkIdType i = 0; i < ids->GetNumberOfTuples(); ++i)
      in.workerFaceIds.push_back(int(ids->GetTuple1(i)));
  std::sort(in.workerFaceIds.begin(), in.workerFaceIds.end());
  in.workerFaceIds.erase(std::unique(in.workerFaceIds.begin(), in.workerFaceIds.end()), in.workerFaceIds.end());
  facesOut->ShallowCopy(faces->GetOutput());
  edgesOut->ShallowCopy(edges->GetOutput());
  this->UpdateProgress(1.0);
  return 1;
}

void vtkWireFurCADReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "LinearDeflection: " << this->LinearDeflection << "\n";
  os << indent << "RelativeDeflection: " << this->RelativeDeflection << "\n";
  os << indent << "AngularDeflection: " << this->AngularDeflection << "\n";
  os << indent << "NumberOfUIsoLines: " << this->NumberOfUIsoLines << "\n";
  os << indent << "NumberOfVIsoLines: " << this->NumberOfVIsoLines << "\n";
  os << indent << "MaximumTriangles: " << this->MaximumTriangles << "\n";
  os << indent << "FeatureAngle: " << this->FeatureAngle << "\n";
  os << indent << "FacesOnly: " << this->FacesOnly << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
  os << indent << "ReadInWorker: " << this->ReadInWorker << "\n";
  os << indent << "WorkerTimeout: " << this->WorkerTimeout << "\n";
}

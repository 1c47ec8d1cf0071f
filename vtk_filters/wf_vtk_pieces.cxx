#include "wf_vtk_pieces.h"

#include "wf_vtk_surfaces.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommunicator.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkCellType.h"
#include "vtkDoubleArray.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

namespace wf::vtkio {

namespace {

// One triangle of a piece: global cell id (-1 when none), rank, local cell id, sub-triangle, the
// corners' points and texture coordinates.
constexpr int kRecord = 19;

struct LocalPiece {
  std::vector<double> records;
  std::string problem;
  bool allGlobalIds = true;  // every triangle's cell has a global id (true when there are none)
  bool points = false;       // the piece has points
};

LocalPiece collect(vtkPolyData* mesh, int rank) {
  LocalPiece out;
  if (!mesh || isEmpty(mesh)) return out;
  out.points = mesh->GetNumberOfPoints() > 0;
  if (std::string why = inputProblem(mesh, ""); !why.empty()) {  // (" point 7 is not finite")
    out.problem = "input mesh:" + why;  // as one process says it (growthSurface)
    return out;
  }
  vtkDataArray* tc = textureCoordinates(mesh);
  vtkDataArray* gids = mesh->GetCellData()->GetGlobalIds();
  vtkUnsignedCharArray* ghosts = mesh->GetCellGhostArray();
  bool anyTriangle = false;
  auto add = [&](vtkIdType cell, int sub, vtkIdType a, vtkIdType b, vtkIdType c) {
    anyTriangle = true;
    if (!tc) return;
    const double gid = gids ? gids->GetComponent(cell, 0) : -1.0;
    if (!gids) out.allGlobalIds = false;
    double r[kRecord] = {gid, double(rank), double(cell), double(sub)};
    const vtkIdType corner[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
      mesh->GetPoint(corner[k], r + 4 + 3 * k);
      r[13 + 2 * k] = tc->GetComponent(corner[k], 0);
      r[14 + 2 * k] = tc->GetComponent(corner[k], 1);
    }
    out.records.insert(out.records.end(), r, r + kRecord);
  };
  // By cell id (VTK 9 numbers a polydata's cells in the order they were inserted, so the cell
  // data of mixed verts, lines and polygons is not in the arrays' order), triangulated as
  // triangulate() does: polygons fanned, strips split.
  vtkNew<vtkIdList> ids;
  for (vtkIdType cell = 0, n = mesh->GetNumberOfCells(); cell < n; ++cell) {
    const int type = mesh->GetCellType(cell);
    const bool polygon = type == VTK_TRIANGLE || type == VTK_QUAD || type == VTK_POLYGON;
    if (!polygon && type != VTK_TRIANGLE_STRIP) continue;
    if (ghosts && (ghosts->GetValue(cell) & vtkDataSetAttributes::DUPLICATECELL)) continue;
    mesh->GetCellPoints(cell, ids);
    const vtkIdType m = ids->GetNumberOfIds();
    if (polygon) {
      for (vtkIdType k = 1; k + 1 < m; ++k) add(cell, int(k - 1), ids->GetId(0), ids->GetId(k), ids->GetId(k + 1));
    } else {
      for (vtkIdType k = 0; k + 2 < m; ++k) {
        if (k % 2 == 0)
          add(cell, int(k), ids->GetId(k), ids->GetId(k + 1), ids->GetId(k + 2));
        else
          add(cell, int(k), ids->GetId(k + 1), ids->GetId(k), ids->GetId(k + 2));
      }
    }
  }
  if (anyTriangle && !tc)
    out.problem = "input mesh: the mesh has no texture coordinates (active TCoords, or a 2-component point array \"TCoords\")";
  return out;
}

}  // namespace

GrowthShare growthShare(vtkParametricFunction* function, vtkPolyData* mesh, bool flip,
                        vtkInformationVector* outputVector) {
  GrowthShare share;
  if (vtkInformation* info = outputVector ? outputVector->GetInformationObject(0) : nullptr) {
    if (info->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES()))
      share.pieces = std::max(1, info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES()));
    if (info->Has(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER()))
      share.piece = std::clamp(info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER()), 0, share.pieces - 1);
  }

  if (function) {
    share.surface = growthSurface(function, nullptr, share.problem, flip);
    if (share.surface && share.pieces > 1) {
      const ParameterDomain d = share.surface->domain();
      const int piece = share.piece, pieces = share.pieces;
      share.keep = [d, piece, pieces](const glm::dvec2& uv) {
        const double t = d.dv() != 0.0 ? (uv.y - d.v0) / d.dv() : 0.0;
        const double band = std::floor(std::clamp(t, 0.0, 1.0) * pieces);
        return std::min(int(band), pieces - 1) == piece;
      };
    }
    return share;
  }

  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  const bool distributed = share.pieces > 1 && controller && controller->GetNumberOfProcesses() == share.pieces &&
                           controller->GetLocalProcessId() == share.piece;
  if (!distributed) {
    share.surface = growthSurface(nullptr, mesh, share.problem, flip);
    return share;
  }

  // Gather (collective from here on: every process takes the same steps).
  const int rank = share.piece, size = share.pieces;
  LocalPiece local = collect(mesh, rank);
  int flags[3] = {local.problem.empty() ? 0 : 1, local.allGlobalIds ? 0 : 1, local.points ? 1 : 0}, any[3] = {0, 0, 0};
  if (!controller->AllReduce(flags, any, 3, vtkCommunicator::MAX_OP)) {
    share.problem = "input mesh: the processes could not exchange their pieces (MPI)";
    return share;
  }
  if (any[0]) {
    share.problem = !local.problem.empty() ? local.problem
                                           : "input mesh: another process's piece is unusable (that process names the problem)";
    return share;
  }
  const bool byGlobalId = any[1] == 0;
  vtkIdType count = vtkIdType(local.records.size());
  std::vector<vtkIdType> counts(size_t(size), 0), offsets(size_t(size), 0);
  if (!controller->AllGather(&count, counts.data(), 1)) {
    share.problem = "input mesh: the processes could not exchange their pieces (MPI)";
    return share;
  }
  for (int r = 1; r < size; ++r) offsets[size_t(r)] = offsets[size_t(r) - 1] + counts[size_t(r) - 1];
  const vtkIdType total = offsets.back() + counts.back();
  // MPI counts are ints: the gather takes at most 2^31 - 1 doubles (113 million triangles).
  if (total > vtkIdType(std::numeric_limits<int>::max())) {
    share.problem = "input mesh: " + std::to_string(total / kRecord) +
                    " triangles are too many to gather over MPI (at most 113,025,455)";
    return share;
  }
  std::vector<double> all(size_t(std::max<vtkIdType>(total, 1)));
  if (!controller->AllGatherV(local.records.data(), all.data(), count, counts.data(), offsets.data())) {
    share.problem = "input mesh: the processes could not exchange their pieces (MPI)";
    return share;
  }
  local.records = std::vector<double>();
  share.gathered = true;
  const size_t n = size_t(total / kRecord);
  if (n == 0) {
    // Nothing anywhere; points but no triangle (lines, vertices) is the whole mesh's problem.
    if (any[2]) share.problem = "input mesh: the mesh has no triangles";
    return share;
  }

  // Order: by global cell id, else piece by piece; then the triangles of a cell (the lookup does
  // not depend on it: surface/mesh_surface.h breaks exact ties by the triangles' corners). With
  // global ids, a triangle present in two pieces without a ghost mark (the same id, the same
  // corners) is kept once, the lower rank's; triangles that share an id but not their corners
  // (the faces of one volume cell after ExtractSurface) are all kept.
  auto rec = [&](size_t i) { return all.data() + i * kRecord; };
  auto sameTriangle = [&](size_t a, size_t b) { return std::equal(rec(a) + 4, rec(a) + kRecord, rec(b) + 4); };
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const double* x = rec(a);
    const double* y = rec(b);
    if (byGlobalId) {
      if (x[0] != y[0]) return x[0] < y[0];
      if (x[3] != y[3]) return x[3] < y[3];
      if (!sameTriangle(a, b)) return std::lexicographical_compare(x + 4, x + kRecord, y + 4, y + kRecord);
      return x[1] < y[1];
    }
    if (x[1] != y[1]) return x[1] < y[1];
    if (x[2] != y[2]) return x[2] < y[2];
    return x[3] < y[3];
  });
  if (byGlobalId) {
    order.erase(std::unique(order.begin(), order.end(),
                            [&](size_t a, size_t b) { return rec(a)[0] == rec(b)[0] && rec(a)[3] == rec(b)[3] && sameTriangle(a, b); }),
                order.end());
  }

  const vtkIdType triangles = vtkIdType(order.size());
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(3 * triangles);
  vtkNew<vtkDoubleArray> uvs;
  uvs->SetName("TCoords");
  uvs->SetNumberOfComponents(2);
  uvs->SetNumberOfTuples(3 * triangles);
  vtkNew<vtkCellArray> polys;
  auto owned = std::make_shared<std::vector<std::uint8_t>>(size_t(triangles), 0);
  for (vtkIdType t = 0; t < triangles; ++t) {
    const double* r = rec(order[size_t(t)]);
    (*owned)[size_t(t)] = int(r[1]) == rank ? 1 : 0;
    const vtkIdType ids[3] = {3 * t, 3 * t + 1, 3 * t + 2};
    for (int k = 0; k < 3; ++k) {
      points->SetPoint(ids[k], r + 4 + 3 * k);
      uvs->SetTypedTuple(ids[k], r + 13 + 2 * k);
    }
    polys->InsertNextCell(3, ids);
  }
  vtkNew<vtkPolyData> whole;
  whole->SetPoints(points);
  whole->SetPolys(polys);
  whole->GetPointData()->SetTCoords(uvs);

  auto surface = std::make_shared<MeshSurface>(whole.Get());
  if (!surface->problem().empty()) {
    share.problem = "input mesh: " + surface->problem();
    return share;
  }
  share.surface = flip ? std::shared_ptr<const Surface>(std::make_shared<FlippedSurface>(surface)) : surface;
  const ParameterDomain d = surface->domain();
  share.keep = [surface, owned, d](const glm::dvec2& uv) {
    std::size_t t = 0;
    glm::dvec3 b(0.0);
    if (!surface->locate(std::clamp(uv.x, d.u0, d.u1), std::clamp(uv.y, d.v0, d.v1), t, b)) return false;
    return (*owned)[surface->sourceTriangle(t)] != 0;
  };
  return share;
}

}  // namespace wf::vtkio

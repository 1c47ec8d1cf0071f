// Growth in a parallel pipeline (pvbatch or pvserver under mpirun, or any VTK pipeline asked for
// piece p of N): the surface one process grows fur or scales on, and its share of the roots, so
// that the union of the processes' outputs is the one-process output, hair for hair and scale
// for scale (the same ids, the same points, bit for bit).
//
// A mesh split over N processes (the global vtkMultiProcessController has N processes and this
// one is asked for piece p = its rank): every process gathers the whole mesh (collective: every
// process calls this, empty pieces too) as one triangle list, and grows on it the roots whose
// triangle is one of its own piece's. The list is ordered by global cell id (the input's
// vtkGlobalIds cell array, which ParaView's RedistributeDataSet writes) when every piece has
// them, else piece by piece; the lookup does not depend on the order (surface/mesh_surface.h
// breaks exact ties by the triangles' corners). Ghost cells (vtkGhostType DUPLICATECELL) are left
// to their owner, and a triangle two pieces hold unmarked (the same global id and corners) is
// kept once. Every root's (u, v) domain, lookup and tie between triangles are the whole mesh's,
// so a root on an edge between two pieces belongs to exactly one. It holds when the pieces put
// together are the one-process mesh's polygons with their corners in the same order (a quad
// started at another corner is split along the other diagonal). The cost: every process holds
// the whole surface while gathering (about 600 bytes a triangle at the peak) and judges every
// root (FurParams::rootFilter); it shapes and stores only its own.
//
// A parametric function (no piece to split): piece p keeps the roots whose unit coordinate t
// falls in [p/N, (p+1)/N): bands across v. No communication.
//
// N pieces without matching processes (one process streaming pieces): the piece is grown as a
// surface of its own (its own uv domain): the union is NOT the whole surface's fur.
#pragma once

#include "WireFurFiltersModule.h"  // export macro
#include "surface/surface.h"

#include <glm/glm.hpp>

#include <functional>
#include <memory>
#include <string>

class vtkInformationVector;
class vtkParametricFunction;
class vtkPolyData;

namespace wf::vtkio {

struct GrowthShare {
  std::shared_ptr<const Surface> surface;          ///< null: nothing to grow (an empty piece, or `problem`)
  std::function<bool(const glm::dvec2&)> keep;     ///< null: every root is this process's
  std::string problem;                             ///< one line when the input is unusable
  int piece = 0, pieces = 1;                       ///< as the pipeline asked
  bool gathered = false;                           ///< the mesh was gathered from every process
};

/// The surface and share for the request in `outputVector` (UPDATE_PIECE_NUMBER and
/// UPDATE_NUMBER_OF_PIECES): `function` when set, else `mesh` (texture coordinates needed);
/// front turned round when `flip`. A problem in any process's piece is a problem in every
/// process (the process with it names it), so that all of them stop together.
WIREFURFILTERS_EXPORT GrowthShare growthShare(vtkParametricFunction* function, vtkPolyData* mesh, bool flip,
                                              vtkInformationVector* outputVector);

}  // namespace wf::vtkio

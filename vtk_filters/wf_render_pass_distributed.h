// Private to vtkWireFurRenderPass: its distributed (sort-first) frame over MPI ranks, as
// docs/paraview.md describes it. Every function here is collective: every process of the
// controller calls it, in the same order, with the same image size.
//
// 1. gatherWires: every rank's marked lines, to every rank (the pieces in the same order).
// 2. compositeSurfaceBands: each rank owns a band of rows (bandOf); it receives every rank's
//    colour and depth of its band and keeps, per pixel, the nearest surface.
// 3. The rank renders its band of the A-buffer image (RenderOptions::rowBegin / rowEnd) over it.
// 4. gatherBands: the finished bands, to every rank: all ranks hold the same image and depth,
//    so that ParaView's depth compositing (IceT) picks identical pixels.
#pragma once

#include "WireFurFiltersModule.h"  // bandOf exported for the module's tests
#include "wf_render_pass_scene.h"

#include <vector>

class vtkMultiProcessController;

namespace wfvtk {

/// Rows [begin, end) of the image (row 0 at the top) that `rank` of `ranks` renders: whole rows
/// of the core's tiles (kBandRows, RenderOptions::tileSize's default), the same number each and
/// the first ranks one more, so that no tile is rasterised by two ranks (a band that cut a tile
/// would cost both ranks its whole work, and count its fragments twice). A rank may get no rows
/// (begin == end) when there are more ranks than rows of tiles.
constexpr int kBandRows = 32;
WIREFURFILTERS_EXPORT void bandOf(int rank, int ranks, int height, int& begin, int& end);

/// True when every rank passed the same `values` (an AllGather; false on a failed exchange).
bool sameOnEveryRank(vtkMultiProcessController* controller, const std::vector<double>& values);

/// The marked pieces with every rank's lines in rank order (piece i of every rank is the same
/// actor): one piece per actor and per way its lines are drawn (wire description, material,
/// per-point colours or none), so that ranks whose data differ (colours on some only) draw as
/// each would alone; usually one per actor. Surfaces of marked pieces are not gathered (dropped, counted in `droppedSurfaces`).
/// Throws std::runtime_error when an exchange fails.
std::vector<ActorPiece> gatherWires(vtkMultiProcessController* controller,
                                    const std::vector<ActorPiece>& local, int& droppedSurfaces);

/// Depth compositing of every rank's colour (RGBA8) and window depth, OpenGL rows (row 0 at
/// the bottom), w x h, for this rank's band: on return the band's rows of `colour` and `depth`
/// hold, per pixel, the nearest rank's (ties: the lower rank). Other rows are left as they were.
bool compositeSurfaceBands(vtkMultiProcessController* controller, int w, int h,
                           std::vector<unsigned char>& colour, std::vector<float>& depth);

/// Every rank's band of `colour` and `depth` (OpenGL rows) to every rank.
bool gatherBands(vtkMultiProcessController* controller, int w, int h,
                 std::vector<unsigned char>& colour, std::vector<float>& depth);

}  // namespace wfvtk

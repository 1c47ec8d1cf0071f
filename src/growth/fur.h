// Fur grown on a parametric surface (paper §4.2), and the paper's "future work" (§5) done:
// area-correct root placement, density / length / orientation / colour maps, curved hairs
// (gravity, curl), clumping, wind as a function of time, and colour regions.
//
// The paper's method: roots on an equally spaced (u, v) grid, "dithered" by zero to one grid
// increment; root H1 = S(u, v); tip H2 = H1 + a Su + b Sv + c N, the coefficients (a, b, c) being
// the hair's orientation relative to the surface. Because hairs are functions of (u, v) they
// "stick" to the patch: move or animate the surface and the hairs follow it.
//
// Everything random is a pure function of (seed, patch index, root identity) (core/hash.h), so
// the same hairs grow whatever the thread count, and in area-correct placement a higher density
// only ADDS hairs: every hair of a lower density is kept with the same id and the same points.
//
// Maps and colour regions are looked up at the patch's unit texture coordinates
// (s, t) = ((u - u0) / (u1 - u0), (v - v0) / (v1 - v0)) in [0, 1]^2: one map spans the patch once,
// whatever the parameter ranges (a sphere's [0, 2 pi] x [0, pi] included).
//
// Degenerate places give finite hairs or none, never NaN: at a pole or on a zero-area cell the
// normal is the surface's limit normal (Surface::frame); a root where the surface itself is not
// finite is skipped; a hair of zero length (a zero direction, a zero length map, a pole under
// length = k |Su|) is skipped. Both are counted in FurCounts.
#pragma once

#include "render/scene.h"
#include "surface/surface.h"
#include "texture/texture.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace wf {

/// Hairs whose root lies near `centre` take `colour` (the spider's leg joints, paper §4.2).
struct FurColourRegion {
  glm::dvec2 centre{0.5, 0.5};  ///< unit texture coordinates (s, t) of the patch (see top)
  double radius = 0.1;          ///< in (s, t); distance wraps across a periodic seam
  glm::vec3 colour{1.0f};       ///< replaces the hair's colour (root and tip) inside
  /// Fraction of the radius, at the rim, over which the region's colour fades out to the hair's own
  /// (smoothstep): 0 = hard edge, 1 = fades from the centre. Outside `radius` nothing changes.
  double falloff = 0.5;
};

struct FurParams {
  /// Grid: the paper's dithered (u, v) grid, gridU x gridV roots whatever the surface's area.
  /// AreaCorrect: `density` roots per unit of surface area, weighted by |Su x Sv|.
  enum class Placement { Grid, AreaCorrect };
  /// Paper: |H2 - H1| = |a Su + b Sv + c N| (the paper's formula taken literally).
  /// Fixed: `length` world units (the spider). ProportionalToSu: lengthPerSu * |Su| (Oscar).
  enum class LengthMode { Paper, Fixed, ProportionalToSu };

  std::uint64_t seed = 1;  ///< with the patch index and the root, all the randomness

  // --- Root placement -------------------------------------------------------------------------
  Placement placement = Placement::Grid;
  int gridU = 100, gridV = 70;  ///< Grid: roots per row and rows (7000: the furry torus of image 15)
  /// Grid: dither as a fraction of the grid increment. A root is at the cell centre moved by
  /// jitter * (xi - 1/2) increments, xi uniform in [0, 1): 1 = anywhere in its cell (the paper's
  /// "zero to one grid increment"), 0 = the regular brush.
  double jitter = 1.0;
  double density = 2.0e4;  ///< AreaCorrect: expected roots per unit area (world units^-2)
  /// AreaCorrect: the fixed lattice of parameter cells the roots are counted on. It does not depend
  /// on the density, so changing the density adds or removes hairs without moving the others.
  int cellsU = 64, cellsV = 64;
  /// AreaCorrect: multiplies `density` (negative or NaN counts as 0). Optional.
  std::shared_ptr<const ScalarTexture> densityMap;

  // --- Orientation: the hair's axis along a Su + b Sv + c N -------------------------------------
  glm::dvec3 orientation{0.0, 0.0, 1.0};  ///< (a, b, c); (0, 0, 1) = straight out along the normal
  /// Use the unit tangents Tu, Tv instead of Su, Sv (lean independent of the parametrisation speed).
  bool unitTangents = false;
  /// Optional maps that replace a, b or c where present (e.g. a combing direction painted over
  /// the patch).
  std::shared_ptr<const ScalarTexture> orientationMapA, orientationMapB, orientationMapC;

  // --- Length ---------------------------------------------------------------------------------
  LengthMode lengthMode = LengthMode::Fixed;
  double length = 0.1;           ///< Fixed: world units
  double lengthPerSu = 0.05;     ///< ProportionalToSu: k in length = k |Su|
  /// Random length variation: length * (1 + lengthVariation * (2 xi - 1)); in [0, 1).
  double lengthVariation = 0.2;
  std::shared_ptr<const ScalarTexture> lengthMap;  ///< optional, multiplies the length (< 0 -> 0)

  // --- Shape (straight when segments = 1 and gravity, curl and wind are 0) ---------------------
  int segments = 1;  ///< line segments per hair, 1 ... 64 (the paper's hairs are 1)
  /// Droop: the hair's direction at fraction s of its length is turned towards gravityDirection by
  /// axis + gravity * s * g (then normalised): growing along the hair; hair length is kept.
  double gravity = 0.0;
  glm::dvec3 gravityDirection{0.0, 0.0, -1.0};  ///< world; normalised (zero: no droop)
  /// Curl: a helix about the hair's axis, radius about curlAmplitude * length, curlFrequency turns
  /// per hair length, a random phase per hair.
  double curlAmplitude = 0.0;
  double curlFrequency = 2.0;

  // --- Clumping -------------------------------------------------------------------------------
  /// 0 ... 1: each hair's points are pulled towards the tip of its clump's centre hair by
  /// clumping * s^2 (s = fraction along the hair), so at 1 the tips of a clump meet.
  double clumping = 0.0;
  /// Clump centres: one hashed centre hair per cell of this coarser lattice over the patch; a hair
  /// belongs to the nearest centre (in cell units).
  int clumpCellsU = 16, clumpCellsV = 16;

  // --- Wind, a function of time (same `time`, same hairs: render an animation frame by frame) ---
  glm::dvec3 windDirection{1.0, 0.0, 0.0};  ///< world; normalised (zero: no wind)
  /// Bend at the tip relative to the hair's direction: the direction at fraction s is pushed by
  /// s * windStrength * ((1 - windSway) + windSway * sin(2 pi (windFrequency * time + phase))),
  /// phase hashed per hair. 0 = no wind (time then changes nothing).
  double windStrength = 0.0;
  double windSway = 0.5;       ///< 0 ... 1: the oscillating part of the push
  double windFrequency = 1.0;  ///< oscillations per unit of time
  double time = 0.0;

  // --- Colour (per point: root colour at the root blending to tip colour at the tip) -----------
  glm::vec3 rootColour{0.30f, 0.20f, 0.12f};
  glm::vec3 tipColour{0.55f, 0.42f, 0.30f};
  std::shared_ptr<const ColourTexture> rootColourMap;  ///< optional, replaces rootColour
  /// Random intensity variation: colours * (1 + intensityVariation * (2 xi - 1)); in [0, 1].
  double intensityVariation = 0.1;
  std::vector<FurColourRegion> colourRegions;  ///< applied in order

  /// Hair diameter in world units; passed through to Fur::thickness (SceneWire::thickness).
  double thickness = 0.003;

  /// The most points the hairs may have (roots x (segments + 1), counted exactly before anything
  /// is allocated): growFur throws std::length_error past it. Default and upper limit 2^32 - 1
  /// (PolylineSet's 32-bit starts); callers with a memory budget pass less.
  double maxPoints = 4294967295.0;

  /// A share of the roots: when set, a root grows only where this returns true for its (u, v)
  /// in the surface's domain (asked after placement, before the hair is shaped; from several
  /// threads); the others count as FurCounts::elsewhere. The processes of a distributed surface
  /// each keep the roots that fall in their own piece, so that the union of their fur is the
  /// one-process fur hair for hair (vtk_filters/wf_vtk_pieces.h). A grid root is judged by its
  /// (u, v) before the surface is evaluated; an area-correct root is placed first (its rejection
  /// sampling evaluates the surface), and placed again when it is kept. Only the kept roots are
  /// allocated; `maxPoints` is still checked against the whole surface's roots. Empty: every root.
  std::function<bool(const glm::dvec2& uv)> rootFilter;

  /// Empty when usable; otherwise one line naming the field and what is wrong (NaN / Inf, out of
  /// range).
  std::string problem() const;
  /// One line with the parameters that matter, for messages and debugging.
  std::string describe() const;
};

struct FurCounts {
  std::uint64_t rootsTried = 0;         ///< roots considered (grid points, or hairs the cells asked for)
  std::uint64_t hairs = 0;              ///< hairs made
  std::uint64_t skippedDegenerate = 0;  ///< the surface was not finite there (or no root found)
  std::uint64_t skippedZeroLength = 0;  ///< zero direction or zero length
  std::uint64_t skippedCapacity = 0;    ///< AreaCorrect: hairs over the per-cell id range (see Fur::ids)
  /// Roots FurParams::rootFilter left to other pieces (a grid root on no triangle of any piece
  /// too). With a filter the other counts are this piece's, but for capped roots, and
  /// area-correct roots with no place on the surface, which every piece counts.
  std::uint64_t elsewhere = 0;
};

struct Fur {
  /// One polyline per hair, segments + 1 points each (root first), a colour per point. Ordered by
  /// root identity (grid: row by row; area-correct: cell by cell, then k), never by thread timing.
  PolylineSet hairs;
  /// Per hair: a stable id, (patchIndex << 32) | root index; the root index is j * gridU + i for
  /// the grid and k * cellsU * cellsV + cell for hair k of a cell (so k < 2^32 / cells).
  std::vector<std::uint64_t> ids;
  std::vector<glm::dvec2> rootUvs;  ///< per hair: the root's (u, v) in the surface's domain
  double thickness = 0.0;           ///< FurParams::thickness
  FurCounts counts;
};

/// Grows fur on `surface` (only its Surface interface is used). `patchIndex` identifies the patch
/// among a creature's patches: it enters every hair's randomness and id. Parallel (oneTBB, in the
/// caller's task arena); the result is bit-identical for any thread count. Throws
/// std::invalid_argument with FurParams::problem() for invalid parameters (as growScales does), and
/// std::length_error when the hairs' points would exceed 2^32 (PolylineSet's 32-bit starts).
Fur growFur(const Surface& surface, const FurParams& params, std::uint32_t patchIndex = 0);

}  // namespace wf

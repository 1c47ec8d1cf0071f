// The A-buffer of one tile (Carpenter 1984, extended to line segments as in the paper §3):
// per-pixel lists of fragments with subpixel coverage masks, resolved front to back.
//
// A fragment carries its exact covered area (the primitive clipped to the pixel) as well as
// its mask. The mask decides what hides what; the area decides how much the fragment adds, so
// an isolated primitive contributes exactly its area, and a line thinner than a subpixel, which
// may hit no sample at all, still adds its true coverage and fades instead of aliasing. Such a
// fragment gets the one subpixel nearest its centroid as a stand-in mask.
//
// Resolve (box filter): fragments sorted by depth (zkey, then arrival); each subpixel s keeps
// the transmittance T[s] left by what lies in front. A fragment with mask M (k bits), area A
// and opacity alpha adds colour * alpha * A * mean_{s in M} T[s], then multiplies T[s] on M by
// 1 - alpha * min(1, A * N / k) (N samples per pixel): opaque polygons hide their subpixels as
// in Carpenter's A-buffer, sub-subpixel lines only dim them by the share they cover.
//
// Surfaces that interpenetrate inside a pixel (crossing hairs, a hair entering the skin) are
// ordered subpixel by subpixel, not by one depth per fragment: a fragment that hides its
// subpixels wholly owns each subpixel where its surface is the nearest of those (depths at the
// subpixel samples from the FragmentSource, asked only where two depth ranges overlap), and
// everything else at that subpixel counts only in front of the owner's surface there.
//
// Shading is deferred: a fragment may arrive unshaded (`shaded` false, with its primitive and
// shading point) and is shaded only if it survives to the resolve (or merges, or joins a tail).
//
// Leaving out what a pixel does not need: an opaque fragment that covers the whole pixel becomes
// the pixel's `solid` fragment, not a list entry; fragments wholly behind it are dropped at once
// and a pixel that has only a solid fragment keeps no list at all.
//
// Merging: a fragment with the same object tag as one already in the list, with a disjoint mask
// and a touching depth range, is one more piece of the same surface or polyline (abutting
// triangles, consecutive segments); the two become one fragment (masks or'ed, areas added), so
// the seam is neither a crack nor covered twice.
//
// Hidden lines (x-ray fragments): a wire drawn dashed or ghosted where surfaces hide it also
// gives copies of its fragments that no culling drops (insertXray). At the resolve, an x-ray
// fragment adds its colour, times its factor (the dash's coverage, or the ghost's opacity), on
// the subpixels where an opaque surface owns the subpixel and lies in front of the wire there:
// composited just in front of that surface, behind whatever lies in front of it.
//
// Budget (as in TressFX's k-buffer): a list holds at most `budget` fragments; the nearest are
// kept exactly, farther ones are blended into one order-independent tail per pixel, composited
// behind the list, and counted in the stats.
#pragma once

#include "abuffer/coverage_mask.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace wf {

struct Fragment {
  float zmin = 0, zmax = 0;  ///< view depth range of the primitive inside the pixel
  float zkey = 0;            ///< depth used for ordering (the primitive's depth at its centroid)
  float area = 0;            ///< exact covered fraction of the pixel, (0, 1]
  float opacity = 1;
  glm::vec3 colour{0.0f};    ///< radiance (not premultiplied)
  MaskBits mask = 0;         ///< subpixel samples covered
  /// Bits of `mask` that stand in for coverage no sample saw (a piece smaller than a subpixel
  /// gets its centroid's subpixel). A merge drops a stand-in bit once a sampled piece of the
  /// same object covers that subpixel, so that the merged mask converges to the sampled union and
  /// its bit count to the merged area (otherwise many tiny pieces leave the object's fragment
  /// more bits than area, hiding only part of what is behind it).
  MaskBits standInBits = 0;
  std::uint32_t tag = 0;     ///< object id: pieces with the same tag may merge
  std::uint32_t prim = kNoPrimitive;   ///< the primitive it comes from (the FragmentSource's numbering)
  /// A merged fragment's other primitive (a wire's next segment at a joint): its surface is the
  /// nearer of the two, subpixel by subpixel. The first piece of another kind keeps it unset.
  std::uint32_t prim2 = kNoPrimitive;
  /// Shading point inside the pixel, from its top left corner, in 1/65535 of a pixel.
  std::uint16_t cx = 32768, cy = 32768;
  bool mayMerge : 1 = true;  ///< false for an object of one piece (a one-segment hair): skips the merge search
  bool shaded : 1 = true;    ///< `colour` holds its radiance; false: the FragmentSource shades it when needed
  /// Counts for occlusion on arrival though it may still merge (pieces of a wire, which meet only
  /// at joints). Pieces of a surface count only once merged whole: tiny ones would otherwise
  /// hide their own siblings' stand-in subpixels and the surface would never close.
  bool occludesEarly : 1 = false;
  /// A hold-out (hidden-line removal): hides what lies behind it like any opaque surface and
  /// adds no colour of its own (what it covers shows the background).
  bool holdout : 1 = false;
  /// A piece of a wire resting on a surface (SurfaceDepth::onSurface): judged against surfaces at
  /// its axis, so no depth over this pixel alone may cull it (a plane in front over the pixel can
  /// be behind the line where its axis is).
  bool onSurface : 1 = false;
  /// The least hide (opacity times covered share of its subpixels) the resolve gives this
  /// fragment. A wire's piece counts for occlusion on arrival at its own hide; a later piece
  /// merged into it may lower the merged fragment's hide, and what was culled meanwhile behind
  /// the old one is gone. So the merged fragment keeps the hide it was counted at: culling and
  /// resolve agree, and epsilon = 0 stays exact.
  float hideFloor = 0.0f;
  static constexpr std::uint32_t kNoPrimitive = 0xFFFFFFFFu;
  /// The bits of `mask` that a sample saw (not stand-ins).
  MaskBits sampledMask() const { return mask & ~standInBits; }
  static std::uint16_t toPoint(double fraction) { return std::uint16_t(std::clamp(fraction, 0.0, 1.0) * 65535.0 + 0.5); }
  double pointX() const { return cx / 65535.0; }
  double pointY() const { return cy / 65535.0; }
};

/// The view depth of a fragment's surface across its pixel, as a function of the offset (sx, sy)
/// in [0, 1]^2 from the pixel's top left corner: a plane of the depth key (triangles; 1/d under
/// perspective, d when orthographic), or a round wire (render/pipeline.h, segmentDepthAt): its
/// axis key along t, its surface sqrt(1 - q^2) radii before the axis, q the distance from the
/// axis in half widths, the axis depth tilted across the wire in perspective (render/pipeline.h,
/// SegmentTilt). In float: plain data the resolve evaluates at the subpixels it needs.
struct SurfaceDepth {
  enum class Kind : std::uint8_t { Plane, Wire } kind = Kind::Plane;
  bool perspective = true;
  bool round = true;                 ///< wire: the round surface (false: the axis key alone)
  float nearPlane = 0, lo = 0, hi = INFINITY;  ///< the result is clamped to [max(near, lo), hi]
  float k0 = 0, kx = 0, ky = 0;      ///< plane: key = k0 + kx sx + ky sy; wire: key = k0 + kx tc
  float t0 = 0, tx = 0, ty = 0;      ///< wire: t along the axis (0 ... 1 between its ends)
  float l0 = 0, lx = 0, ly = 0;      ///< wire: lateral distance from the axis line (pixels)
  float length = 0;                  ///< wire: axis length (pixels), for the distance beyond its ends
  float tmax = 1;                    ///< wire: t is clamped to [0, tmax] (0: a point, seen end-on)
  float w0 = 1, dw = 0, r0 = 0, dr = 0;  ///< wire: half width (pixels) and depth radius (world: SegmentPrim::r0, r1) at t, linear
  /// wire: the axis depth times 1 + tl lat + (ta + tt tc) along, lat and along (the offset from
  /// the axis, pixels) clamped to [-w, w], taken at parameter t + lat (s0 + st tc) clamped to
  /// [0, tmax] (render/pipeline.h, SegmentTilt; all zero when orthographic)
  float tl = 0, ta = 0, tt = 0, s0 = 0, st = 0;
  /// wire: rests on a surface (a CAD edge on its faces, SceneWire::restsOnSurface). Against a
  /// plane it is judged at its axis, not at the subpixel: at subpixel s, the wire's depth at the
  /// axis point nearest s against the plane's depth there (axisPoint). A line drawn on a face
  /// seen at a grazing angle would otherwise be half hidden by that very face, whose depth
  /// changes by more than the wire's radius across the wire's width.
  bool onSurface = false;
  /// wire: its exact solid (render/pipeline.h, WireCapsule: a sphere at each end and the cone
  /// tangent to both), or where the ray through a sample passes it nearest when it misses. In the frame of
  /// the solid's p0 end, the ray through sample (sx, sy) passes (cw0 + cwx sx, cw1 + cwy sy,
  /// cw2) at view depth zref and runs (cd0 + cdx sx, cd1 + cdy sy, cd2) per unit of depth beyond
  /// it: every term of the size of the segment's world length, not of its distance from the eye,
  /// so that floats keep its depth to a small part of its radius.
  bool capsule = false;
  /// The resolve holds a wire's solid to its fragment's depth range [zmin, zmax], which culling
  /// trusted (render/rasterize.h, SegmentDepth bounds it there); the model already lies in it.
  void holdSolidTo(float zmin, float zmax) {
    if (kind == Kind::Wire && capsule) lo = zmin, hi = zmax;
  }
  float zref = 0;
  float cw0 = 0, cw1 = 0, cw2 = 0, cwx = 0, cwy = 0;
  float cd0 = 0, cd1 = 0, cd2 = -1, cdx = 0, cdy = 0;
  float cu0 = 0, cu1 = 0, cu2 = 0, clen = 0, cr0 = 0, cdr = 0;  ///< unit axis, length, radius at p0 and its change to p1 (world)
  /// The body, the cone tangent to both end spheres (WireCapsule::coneBand): radius crho0 + ck h
  /// at axial position h, between ch0 and ch1; none (cbody false) where one sphere holds the other.
  bool cbody = false;
  float ck = 0, crho0 = 0, ch0 = 0, ch1 = 0;
  /// plane: its depth at (sx, sy) extended beyond the primitive (no [lo, hi] clamp: the axis point
  /// an edge is judged at may lie outside this triangle, whose own depth range would then put it
  /// in front of a line lying on its plane), clamped to the near plane only.
  float planeDepthAt(float sx, float sy) const {
    const float key = k0 + kx * sx + ky * sy;
    const float d = perspective ? (key > 0.0f ? 1.0f / key : INFINITY) : key;
    return std::max(nearPlane, d);
  }
  /// The point of the axis nearest (sx, sy) (clamped to the ends), as the same pixel offsets.
  void axisPoint(float sx, float sy, float& ax, float& ay) const {
    const float t = t0 + tx * sx + ty * sy, tc = std::min(tmax, std::max(0.0f, t));
    const float lat = l0 + lx * sx + ly * sy, back = (tc - t) * length * length;
    ax = sx - lat * lx + back * tx;
    ay = sy - lat * ly + back * ty;
  }
  /// The depth at n samples (sx[k], sy[k]) into out[k] (a loop the compiler vectorises).
  void atSamples(const float* sx, const float* sy, int n, float* out) const;
  float at(float sx, float sy) const {
    if (capsule) {
      float d;
      atSamples(&sx, &sy, 1, &d);
      return d;
    }
    float key, cut = 0.0f, tilt = 1.0f;
    if (kind == Kind::Plane) {
      key = k0 + kx * sx + ky * sy;
    } else {
      const float t = t0 + tx * sx + ty * sy;
      const float tc = std::min(tmax, std::max(0.0f, t));
      key = k0 + kx * tc;
      if (round) {
        const float lat = l0 + lx * sx + ly * sy, along = (t - tc) * length, w = w0 + dw * tc;
        const float q2 = std::min(1.0f, (lat * lat + along * along) / (w * w));
        const float lc = std::min(w, std::max(-w, lat));
        cut = (r0 + dr * tc) * std::sqrt(1.0f - q2);
        tilt = 1.0f + tl * lc + (ta + tt * tc) * std::min(w, std::max(-w, along));
        key = k0 + kx * std::min(tmax, std::max(0.0f, t + lc * (s0 + st * tc)));
      }
    }
    const float d = (perspective ? (key > 0.0f ? 1.0f / key : INFINITY) : key) * tilt;
    return std::min(hi, std::max(std::max(nearPlane, lo), d - cut));
  }
};

/// What the A-buffer asks of the renderer about a fragment's primitive.
class FragmentSource {
 public:
  virtual ~FragmentSource() = default;
  /// The radiance of an unshaded fragment of pixel (x, y) (image coordinates).
  virtual glm::vec3 shade(const Fragment& f, int x, int y) const = 0;
  /// The depth of primitive `prim`'s surface across pixel (x, y); false when it has none (the
  /// fragment is flat, at its zkey).
  virtual bool surfaceDepth(std::uint32_t prim, int x, int y, SurfaceDepth& depth) const = 0;
  /// Whether primitive `prim` is a wire resting on a surface (SurfaceDepth::onSurface), asked
  /// before its depths are.
  virtual bool onSurface(std::uint32_t) const { return false; }
};

struct ABufferCounters {
  std::uint64_t fragments = 0;        ///< fragments offered to the buffer
  std::uint64_t merged = 0;           ///< merged into a fragment of the same object
  std::uint64_t culled = 0;           ///< dropped because wholly behind a solid fragment
  std::uint64_t tail = 0;             ///< blended into a pixel's tail (over budget)
  std::uint64_t pixelsWithList = 0;   ///< pixels that needed a fragment list
  std::uint64_t pixelsSolidOnly = 0;  ///< covered pixels resolved without a list
  std::uint64_t pixelsOverBudget = 0;
  std::uint64_t pixelsDeep = 0;       ///< pixels resolved with deep shares (RenderOptions::deepShares)
  std::uint64_t coveredPixels = 0;    ///< pixels that received any fragment
  std::uint32_t maxFragmentsPerPixel = 0;  ///< most fragments offered to one pixel
  std::uint32_t maxListLength = 0;         ///< longest list kept (budget-bounded)
  std::size_t peakBytes = 0;               ///< largest memory this buffer held
  /// Most fragments one buffer held at once over its tiles (an upper bound: the peak of live
  /// list entries plus the tile's solid fragments; tails are accumulators and not counted).
  /// The renderer sums it over threads, like peakBytes.
  std::uint64_t peakFragmentsHeld = 0;
  std::uint64_t xray = 0;        ///< x-ray fragments kept (hidden lines drawn dashed or ghosted)
  std::uint64_t xrayDropped = 0; ///< x-ray fragments over kXrayPerPixel in their pixel
  void add(const ABufferCounters& o);
};

class TileABuffer {
 public:
  /// `occlusionEpsilon`: a subpixel counts as hidden once the fragments in front leave at most
  /// this transmittance (0: only wholly hiding fragments count, and culling is exact).
  /// `deepShares`: deep pixels weigh their hidden fragments by the samples they own
  /// (resolveEntries; RenderOptions::deepShares).
  TileABuffer(const MaskLayout& layout, int budget, float occlusionEpsilon = 0.0f, bool deepShares = false);
  /// Empties the buffer for a tile of w x h pixels whose top left pixel is (x0, y0) of the image
  /// (keeps its memory). `source` shades deferred fragments and gives subpixel depths (null:
  /// every fragment arrives shaded and flat).
  void reset(int w, int h, int x0 = 0, int y0 = 0, const FragmentSource* source = nullptr);
  /// Adds a fragment to pixel (x, y) of the tile. `centroidSubpixel` is the sample index used as
  /// a stand-in when `f.mask` is empty.
  void insert(int x, int y, Fragment f, int centroidSubpixel);
  /// Adds an x-ray copy of a wire fragment to pixel (x, y): drawn with weight `factor` (0 ... 1)
  /// only where an opaque surface in front hides it (hidden lines; see above). Never culled.
  void insertXray(int x, int y, Fragment f, float factor, int centroidSubpixel);
  /// The most x-ray fragments a pixel keeps (later ones, mostly farther, are dropped and counted).
  static constexpr int kXrayPerPixel = 16;
  /// Depth behind which everything in pixel (x, y) is hidden: every subpixel is covered by an
  /// opaque fragment (one that hides its subpixels wholly) nearer than this; +inf until then.
  /// A fragment with zmin >= this depth cannot change the pixel, so the rasteriser may skip it
  /// before computing its coverage.
  float occlusionDepth(int x, int y) const { return occlusion_[size_t(y) * size_t(w_) + size_t(x)]; }
  /// The largest occlusionDepth over pixels x0 ... x1 of row y.
  float rowOcclusionDepth(int y, int x0, int x1) const {
    const float* o = &occlusion_[size_t(y) * size_t(w_)];
    float m = 0.0f;
    for (int x = x0; x <= x1; ++x) m = std::max(m, o[x]);
    return m;
  }
  /// The largest occlusionDepth over the pixels [x0, x1] x [y0, y1] (inclusive, tile
  /// coordinates), from 4x4-pixel blocks, so possibly over a slightly larger region: a primitive
  /// wholly behind it is hidden everywhere in the region (hierarchical occlusion culling).
  float regionOcclusionDepth(int x0, int y0, int x1, int y1) const {
    float m = 0.0f;
    for (int by = y0 >> 2; by <= (y1 >> 2); ++by)
      for (int bx = x0 >> 2; bx <= (x1 >> 2); ++bx) m = std::max(m, blockOcclusion_[size_t(by) * size_t(bw_) + size_t(bx)]);
    return m;
  }
  /// Whether the subpixels of `mask` (or the stand-in subpixel when the mask is empty) of pixel
  /// (x, y) are settled in front of depth z: a fragment there with nothing nearer than z would
  /// change the pixel by at most the occlusion epsilon. The caller then skips it (and counts it,
  /// countCulled).
  bool maskHidden(int x, int y, MaskBits mask, int standInSubpixel, float z) const;
  /// Counts a fragment skipped by the caller because of occlusionDepth().
  void countCulled(int x, int y) {
    ++offered_[size_t(y) * size_t(w_) + size_t(x)];
    ++local_.fragments;
    ++local_.culled;
  }
  /// Counts the fragments of pixels x0 ... x1 of row y skipped by the caller.
  void countCulledRow(int y, int x0, int x1) {
    std::uint32_t* o = &offered_[size_t(y) * size_t(w_)];
    for (int x = x0; x <= x1; ++x) ++o[x];
    local_.fragments += std::uint64_t(x1 - x0 + 1);
    local_.culled += std::uint64_t(x1 - x0 + 1);
  }
  /// Premultiplied linear RGBA of pixel (x, y) (alpha = coverage).
  glm::vec4 resolve(int x, int y) const;
  /// Every pixel's resolve, out(x, y, rgba) in row order: the same values as resolve(), with the
  /// lists gathered in one pass over the buffer's memory instead of pixel by pixel.
  template <class Out>
  void resolveTile(Out&& out) const {
    gatherLists();
    gatherXray();
    const bool xray = !xray_.empty();
    for (int y = 0; y < h_; ++y)
      for (int x = 0; x < w_; ++x) {
        const size_t i = size_t(y) * size_t(w_) + size_t(x);
        const XrayNode* const* xr = xray ? scratch_.xrayGathered.data() + scratch_.xrayStart[i] : nullptr;
        const int xn = xray ? int(scratch_.xrayStart[i + 1] - scratch_.xrayStart[i]) : 0;
        out(x, y, resolveEntries(i, scratch_.gathered.data() + scratch_.gatherStart[i], pixels_[i].length, xr, xn));
      }
  }
  /// Folds the per-pixel counts into counters (call after resolving the tile).
  void finish(ABufferCounters& counters);

  const MaskLayout& layout() const { return layout_; }
  std::size_t bytes() const;
  /// What bytes() comes to for a tile of w x h pixels whose lists hold `entriesPerPixel`
  /// fragments per pixel, every pixel with an occluder record (the renderer's memory estimate).
  static std::size_t bytesFor(int w, int h, const MaskLayout& layout, int entriesPerPixel);
  /// Bytes of one list entry (a fragment, its arrival, its link and its pixel).
  static std::size_t listEntryBytes();
  /// The most bytes x-ray fragments take per pixel (kXrayPerPixel of them, gathered), when a
  /// wire draws its hidden parts.
  static std::size_t xrayBytesPerPixel();

 private:
  struct Node {
    Fragment f;
    std::uint32_t seq;    ///< arrival order within the pixel, for a deterministic sort
    std::int32_t next;
    std::uint32_t pixel;  ///< tile pixel index, kFreeNode once freed
  };
  static constexpr std::uint32_t kFreeNode = 0xFFFFFFFFu;
  struct XrayNode {
    Fragment f;
    float factor;         ///< weight where hidden (dash coverage, ghost opacity)
    std::uint32_t seq;    ///< arrival order within the tile
    std::uint32_t pixel;  ///< tile pixel index
  };
  struct Tail {
    glm::vec3 premultiplied{0.0f};
    float weight = 0;             ///< sum of alpha * area (of what adds colour)
    float holdoutWeight = 0;      ///< the same of hold-outs (they hide, add no colour)
    float transmittance = 1;      ///< product of (1 - alpha * area)
    float zkeyMin = INFINITY;     ///< where the tail sorts among the kept fragments
  };
  struct Pixel {
    std::int32_t head = -1;
    std::uint16_t length = 0;
    std::uint8_t open = 64;       ///< subpixels not yet settled (see occlude)
    bool noOcclusion = false;     ///< has a tail: only the solid fragment occludes (see toTail)
    std::uint32_t seq = 0;
    std::int32_t tail = -1;       ///< index into tails_, or -1
    std::int32_t solid = -1;      ///< index into solids_ (kept out of Pixel: most have none), or -1
    /// The nearest surface's (not a wire's) solid fragment, in solids_: the solid itself, or kept
    /// behind a wire's that took its place (setSolid); -1: none (deep shares' gate).
    std::int32_t surface = -1;
    bool hasSolid() const { return solid >= 0; }
    bool hasTail() const { return tail >= 0; }
    std::int32_t depths = -1;     ///< this pixel's record (2N floats) in subpixelDepth_, once it has an occluder
    std::uint32_t solidSeq = 0;   ///< arrival of the solid fragment, for the resolve's order
    /// The list holds nothing wholly behind this depth (pruneHidden ran at it; every fragment
    /// inserted since lies in front of what hid then), so pruning at a depth not nearer is idle.
    float prunedAt = INFINITY;
    /// The list's farthest entry (largest zkey; of equal ones the earliest), or -1: not known,
    /// found by a scan when next needed. Kept through appends and through fragments sent to the
    /// tail, so that a full list costs O(1) per fragment that is not nearer than all it holds
    /// (thousands of coincident layers); after an eviction, taken from the far cache where it
    /// can tell (FarCache); forgotten when an entry is merged or pruned.
    std::int32_t far = -1;
    std::int32_t farCache = -1;   ///< index into farCache_ once a full list was scanned, or -1
    /// No list entry begins behind this depth (an upper bound, exact after each pruneHidden walk):
    /// pruning at a depth not nearer finds nothing to drop, and skips the walk.
    float zminBound = -INFINITY;
  };
  /// The entries next to the farthest of a full list, found by the scan that finds it, so that
  /// evicting the farthest need not scan the list again (pushList). Exact by construction: it
  /// holds the farthest `count` entries only while their keys are distinct and all larger than
  /// every other entry's (`rest`); a tie, a NaN or any other change to the list empties it, and
  /// the scan answers as before.
  static constexpr int kFarCache = 8;
  struct FarCache {
    std::int32_t node[kFarCache];
    float key[kFarCache];  ///< strictly decreasing
    std::int32_t count = 0;
    float rest = -INFINITY;  ///< no entry outside the cache is farther than this
  };
  /// The resolve's scratch space (one buffer per thread: no thread_local lookups per pixel).
  struct ResolveScratch {
    std::vector<const Node*> order;
    Node solidNode, tailNode;
    std::vector<MaskBits> owned;
    std::vector<float> hides, depths;
    std::vector<std::int8_t> depthState;
    std::vector<int> whole;                  ///< the fragments that hide their subpixels wholly
    std::vector<const Node*> gathered;      ///< every pixel's list, pixel after pixel (resolveTile)
    std::vector<std::uint32_t> gatherStart;  ///< pixel i's list begins at gathered[gatherStart[i]]
    std::vector<const XrayNode*> xrayGathered, xrayOrder;  ///< x-ray fragments by pixel (gatherXray), one pixel's sorted
    std::vector<std::uint32_t> xrayStart;    ///< pixel i's x-ray fragments: xrayGathered[xrayStart[i] ... xrayStart[i + 1])
    std::vector<float> xrayDepths;
    std::vector<std::uint32_t> xrayAt;
    std::vector<SurfaceDepth> models;  ///< two per fragment (resolveEntries' depthsOf)
    std::vector<int> partialOrder;
    std::uint64_t deepPixels = 0;  ///< pixels resolved with deep shares since finish()
  };
  mutable ResolveScratch scratch_;
  void gatherLists() const;
  void gatherXray() const;
  glm::vec4 resolveEntries(size_t pixelIndex, const Node* const* entries, int count, const XrayNode* const* xray = nullptr,
                           int xrayCount = 0) const;

  bool isSolid(const Fragment& f) const;
  void setSolid(Pixel& p, const Fragment& f);
  /// Where pushList put a fragment: in the list, straight into the tail (it was the farthest),
  /// or in the list with the farthest one evicted into the tail.
  enum class Placement { Listed, Tailed, Evicted };
  Placement pushList(Pixel& p, const Fragment& f);
  void toTail(Pixel& p, const Fragment& f, bool evicted);
  void occludeUniform(Pixel& p, size_t pixelIndex, const Fragment& f);
  void occlude(Pixel& p, size_t pixelIndex, const Fragment& f);
  void occlude(Pixel& p, size_t pixelIndex, MaskBits mask, float hide, float zmax);
  float hideOf(const Fragment& f) const;
  /// Stops counting occlusion in this pixel (what was counted no longer bounds the resolve): only
  /// its solid fragment hides from then on.
  void loseOcclusion(Pixel& p, size_t pixelIndex);
  void pruneHidden(Pixel& p, float depth);
  /// The farthest entry of p's list by a scan (largest zkey; of equal ones the earliest), filling
  /// its far cache on the way.
  std::int32_t scanFar(Pixel& p);
  /// After the farthest entry `slot` took a nearer fragment: the list's farthest from the far
  /// cache, or -1 where the cache cannot say (the next eviction scans).
  std::int32_t nextFar(Pixel& p, std::int32_t slot);
  void emptyFarCache(Pixel& p) {
    if (p.farCache >= 0) farCache_[size_t(p.farCache)].count = 0;
  }
  void forgetFar(Pixel& p) {
    p.far = -1;
    emptyFarCache(p);
  }
  void updateBlock(size_t pixelIndex);
  std::int32_t allocNode(const Node& node);  ///< a free slot (or a new one) holding `node`
  void freeNode(std::int32_t i);

  MaskLayout layout_;
  float sampleX_[64], sampleY_[64];  ///< subpixel sample positions in the pixel, by sample index
  int budget_;
  float epsilon_ = 0.0f;
  bool deepShares_ = false;
  int w_ = 0, h_ = 0;
  int x0_ = 0, y0_ = 0;
  const FragmentSource* source_ = nullptr;
  void shadeNow(Fragment& f, std::size_t pixelIndex) const;
  std::vector<Pixel> pixels_;
  std::vector<Node> nodes_;
  std::vector<std::int32_t> freeNodes_;
  std::vector<Tail> tails_;
  std::vector<float> occlusion_;      ///< per pixel: see occlusionDepth
  std::vector<std::uint32_t> offered_;  ///< per pixel: fragments offered (kept apart: the culling loops touch only these)
  std::vector<float> blockOcclusion_; ///< per 4x4 block: the largest occlusion_ in it
  int bw_ = 0;
  std::vector<float> subpixelDepth_;  ///< per pixel with occluders: N depths D then N transmittances T (see occlude)
  std::vector<Fragment> solids_;
  std::vector<FarCache> farCache_;    ///< per pixel whose full list was scanned (Pixel::farCache)
  std::vector<XrayNode> xray_;        ///< hidden-line copies (insertXray): empty unless a wire asks for them
  std::vector<std::uint8_t> xrayCount_;  ///< per pixel, once a wire asks for x-ray copies
  std::size_t peakBytes_ = 0;
  ABufferCounters local_;
};

}  // namespace wf

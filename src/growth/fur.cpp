// Fur generation (paper §4.2 and §5): roots, then hairs, then the polylines the renderer draws.
//
// Counts first, then one parallel fill (oneTBB) over fixed blocks of roots. The roots a block asks for
// are known before any surface evaluation (the grid's roots; on the area-correct lattice, each
// cell's n = floor(lambda + xi) from a cheap quadrature), so a prefix sum over the blocks gives each
// block its first slot and the output is sized exactly before it is filled. Each root is evaluated
// once. A root that grows no hair (surface not finite there, zero length) leaves its slot empty;
// when there are any, an in-order compaction closes the gaps and the spare capacity is returned, so
// the result is still exactly sized. (Counting by growing every hair twice, once to count and once to
// write, cost 40 % more on the 2-core CI machine for a case that almost never happens.)
// The output is ordered by root identity and bit-identical for any thread count: every random
// number is a hash of (seed, patch, root), never a stream, and every block writes only its slots.
#include "growth/fur.h"

#include "core/hash.h"
#include "core/numeric.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#ifdef __linux__
#include <sys/mman.h>
#endif

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace wf {

namespace {

// Hash streams: each kind of randomness draws from its own stream, so that e.g. enabling curl
// does not change where roots are or how long hairs are.
constexpr std::uint64_t kStreamPlacement = 0x706c6163656d656eull;
constexpr std::uint64_t kStreamHair = 0x6861697261747472ull;
constexpr std::uint64_t kStreamCellCount = 0x63656c6c636f756eull;
constexpr std::uint64_t kStreamClump = 0x636c756d70637472ull;

constexpr int kMaxSegments = 64;
constexpr int kMaxRejectionTries = 32;     // per area-correct root; see placeCellRoot
constexpr double kMaxWeightMargin = 1.25;  // the sampled maximum of |Su x Sv| over a cell, widened
constexpr std::size_t kRootsPerBlock = 2048;  // grid: roots per parallel work item
constexpr std::size_t kCellsPerBlock = 16;    // area-correct: cells per parallel work item

// Independent uniforms for one root of one stream: draw(k) is a hash of (seed, patch, stream, root,
// k) (core/hash.h), so any subset can be drawn in any order and adding a feature that draws never
// changes the other draws. One mix per draw; the stream base is hashed once per growFur.
class RootRandom {
 public:
  RootRandom(std::uint64_t streamBase, std::uint64_t root) : key_(mix64(streamBase + root * 0x9e3779b97f4a7c15ull)) {}
  double draw(std::uint64_t k) const { return unitFromHash(mix64(key_ ^ (k * 0xd1b54a32d192ed03ull))); }

 private:
  std::uint64_t key_;
};

glm::dvec3 normalizedOrZero(const glm::dvec3& v) {
  const double l = glm::length(v);
  return l > 0 && std::isfinite(l) ? v / l : glm::dvec3(0.0);
}

struct RootFrame {
  glm::dvec2 uv{0.0};  // the surface's (u, v)
  glm::dvec2 st{0.0};  // unit texture coordinates
  glm::dvec3 P{0.0}, Su{0.0}, Sv{0.0}, N{0.0, 0.0, 1.0};
  glm::dvec3 Tu{1.0, 0.0, 0.0}, Tv{0.0, 1.0, 0.0};  // filled when the generator needs them
};

struct HairPlan {
  RootFrame root;
  glm::dvec3 axis{0.0};  // unit
  double length = 0.0;
  RootRandom attributes{0, 0};  // draws: 0 length, 1 intensity, 2 wind phase, 3 curl phase
};

enum class Verdict { Grown, Degenerate, ZeroLength, Capacity, Elsewhere };

struct BlockTally {
  std::uint64_t roots = 0, hairs = 0, degenerate = 0, zeroLength = 0, capacity = 0, elsewhere = 0;
  void count(Verdict v) {
    ++roots;
    switch (v) {
      case Verdict::Grown: ++hairs; break;
      case Verdict::Degenerate: ++degenerate; break;
      case Verdict::ZeroLength: ++zeroLength; break;
      case Verdict::Capacity: ++capacity; break;
      case Verdict::Elsewhere: ++elsewhere; break;
    }
  }
};

struct Cell {
  double maxWeight = 0.0;   // an upper bound of |Su x Sv| * densityMap over the cell
  std::uint32_t count = 0;  // hairs grown in it (after the id-range cap)
  std::uint32_t capped = 0; // hairs asked for beyond the id range
};

struct ClumpCentre {
  glm::dvec2 st{0.0};
  glm::dvec3 tip{0.0};
  bool valid = false;
};

class FurGenerator {
 public:
  FurGenerator(const Surface& surface, const FurParams& params, std::uint32_t patchIndex)
      : surface_(surface), p_(params), domain_(surface.domain()), patch_(patchIndex),
        placementBase_(hashWords(params.seed, patchIndex, kStreamPlacement)),
        hairBase_(hashWords(params.seed, patchIndex, kStreamHair)),
        cellCountBase_(hashWords(params.seed, patchIndex, kStreamCellCount)),
        clumpBase_(hashWords(params.seed, patchIndex, kStreamClump)) {
    gravity_ = params.gravity * normalizedOrZero(params.gravityDirection);
    wind_ = normalizedOrZero(params.windDirection);
    windOn_ = params.windStrength != 0.0 && wind_ != glm::dvec3(0.0);
    curlOn_ = params.curlAmplitude != 0.0 && params.curlFrequency != 0.0;
    shaped_ = params.segments > 1 || gravity_ != glm::dvec3(0.0) || windOn_ || curlOn_;
    needTangents_ = params.unitTangents || curlOn_;
    segments_ = params.segments;
    windPhaseBase_ = params.windFrequency * params.time;
  }

  Fur grow();

 private:
  // --- roots ---
  bool rootFrame(const glm::dvec2& uv, const SurfacePoint& sp, RootFrame& f) const;
  Verdict placeGridRoot(std::uint32_t rootIndex, RootFrame& f) const;
  glm::dvec2 gridSt(std::uint32_t rootIndex) const;
  Verdict placeCellRoot(std::uint32_t cell, std::uint32_t rootIndex, RootFrame& f) const;
  double densityWeight(const glm::dvec2& st, const SurfacePoint& sp) const;
  void buildCells();
  // --- hairs ---
  Verdict plan(std::uint64_t hairKey, HairPlan& h) const;
  void shape(const HairPlan& h, glm::dvec3* points) const;
  void colours(const HairPlan& h, glm::vec3* out) const;
  void buildClumps();
  const ClumpCentre* nearestClump(const glm::dvec2& st) const;
  glm::dvec2 unitToUv(double s, double t) const { return domain_.fromUnit(s, t); }

  template <class Visit>
  BlockTally forEachRoot(std::size_t block, Visit&& visit, const std::vector<std::uint32_t>* only = nullptr) const;
  std::vector<std::uint32_t> rootsOfShare(std::size_t block, BlockTally& tally) const;
  std::size_t blockCount() const;
  std::uint64_t rootsAskedFor(std::size_t block) const;

  const Surface& surface_;
  const FurParams& p_;
  const ParameterDomain domain_;
  const std::uint32_t patch_;
  const std::uint64_t placementBase_, hairBase_, cellCountBase_, clumpBase_;
  glm::dvec3 gravity_{0.0}, wind_{0.0};
  bool windOn_ = false, curlOn_ = false, shaped_ = false, needTangents_ = false;
  int segments_ = 1;
  double windPhaseBase_ = 0.0;
  std::vector<Cell> cells_;
  std::uint32_t idRangePerCell_ = 0;
  std::vector<ClumpCentre> clumps_;
};

// --- roots -----------------------------------------------------------------------------------

// The root's frame from one evaluation. Regular points use Su x Sv directly (the hot path);
// degenerate or non-finite derivatives take Surface::frame's limit normal and tangents. A root
// where S itself is not finite has no hair (frame would replace it by a made-up point).
bool FurGenerator::rootFrame(const glm::dvec2& uv, const SurfacePoint& sp, RootFrame& f) const {
  if (!finite3(sp.P)) return false;
  f.uv = uv;
  const glm::dvec3 n = glm::cross(sp.Su, sp.Sv);
  const double n2 = glm::dot(n, n), su2 = glm::dot(sp.Su, sp.Su), sv2 = glm::dot(sp.Sv, sp.Sv);
  constexpr double eps2 = Surface::kDegenerateEpsilon * Surface::kDegenerateEpsilon;
  if (n2 > eps2 * su2 * sv2 && n2 > 0 && std::isfinite(n2)) {
    f.P = sp.P;
    f.Su = sp.Su;
    f.Sv = sp.Sv;
    f.N = n * (surface_.normalSign() / std::sqrt(n2));
    if (needTangents_) {
      f.Tu = sp.Su / std::sqrt(su2);
      f.Tv = sp.Sv / std::sqrt(sv2);
    }
    return true;
  }
  const SurfaceFrame fr = surface_.frame(uv.x, uv.y);
  if (!(finite3(fr.P) && finite3(fr.Su) && finite3(fr.Sv) && finite3(fr.N) && finite3(fr.Tu) &&
        finite3(fr.Tv)))
    return false;
  f.P = sp.P;  // as evaluated (frame may have moved a non-finite (u, v); ours are finite)
  f.Su = fr.Su;
  f.Sv = fr.Sv;
  f.N = fr.N;
  f.Tu = fr.Tu;
  f.Tv = fr.Tv;
  return true;
}

// Paper §4.2: the cell centre of an equally spaced grid, dithered by up to one increment.
glm::dvec2 FurGenerator::gridSt(std::uint32_t rootIndex) const {
  const std::uint32_t i = rootIndex % std::uint32_t(p_.gridU), j = rootIndex / std::uint32_t(p_.gridU);
  const RootRandom place(placementBase_, rootIndex);
  const double xu = place.draw(0), xv = place.draw(1);
  return {(i + 0.5 + p_.jitter * (xu - 0.5)) / p_.gridU, (j + 0.5 + p_.jitter * (xv - 0.5)) / p_.gridV};
}

Verdict FurGenerator::placeGridRoot(std::uint32_t rootIndex, RootFrame& f) const {
  f.st = gridSt(rootIndex);
  const glm::dvec2 uv = unitToUv(f.st.x, f.st.y);
  return rootFrame(uv, surface_.evaluate(uv.x, uv.y), f) ? Verdict::Grown : Verdict::Degenerate;
}

// |Su x Sv| times the density map: what root placement is proportional to. 0 where not finite.
double FurGenerator::densityWeight(const glm::dvec2& st, const SurfacePoint& sp) const {
  double w = glm::length(glm::cross(sp.Su, sp.Sv));
  if (p_.densityMap) {
    const double m = p_.densityMap->value(st);
    w *= m > 0 ? m : 0.0;
  }
  return std::isfinite(w) && finite3(sp.P) ? w : 0.0;
}

// Hair k of a cell: candidates hashed from (seed, patch, cell, k) only, accepted with probability
// weight / maxWeight (rejection sampling), so the position within the cell is area-correct and
// does not depend on the density. If every candidate is rejected (a cell whose weight bound is far
// too loose), the heaviest candidate is taken; if all weigh 0 there is no hair.
Verdict FurGenerator::placeCellRoot(std::uint32_t cell, std::uint32_t rootIndex, RootFrame& f) const {
  const std::uint32_t cu = cell % std::uint32_t(p_.cellsU), cv = cell / std::uint32_t(p_.cellsU);
  const double maxWeight = cells_[cell].maxWeight;
  const RootRandom place(placementBase_, rootIndex);
  SurfacePoint best;
  glm::dvec2 bestSt{0.0};
  double bestWeight = 0.0;
  for (int attempt = 0; attempt < kMaxRejectionTries; ++attempt) {
    const glm::dvec2 st{(cu + place.draw(3 * attempt)) / p_.cellsU, (cv + place.draw(3 * attempt + 1)) / p_.cellsV};
    const double accept = place.draw(3 * attempt + 2);
    const glm::dvec2 uv = unitToUv(st.x, st.y);
    const SurfacePoint sp = surface_.evaluate(uv.x, uv.y);
    const double w = densityWeight(st, sp);
    if (accept * maxWeight < w) {
      f.st = st;
      return rootFrame(uv, sp, f) ? Verdict::Grown : Verdict::Degenerate;
    }
    if (w > bestWeight) {
      bestWeight = w;
      best = sp;
      bestSt = st;
    }
  }
  if (!(bestWeight > 0)) return Verdict::Degenerate;
  f.st = bestSt;
  return rootFrame(unitToUv(bestSt.x, bestSt.y), best, f) ? Verdict::Grown : Verdict::Degenerate;
}

// The fixed lattice of cells: expected count lambda = density * integral of |Su x Sv| * map over the
// cell (3 x 3 Gauss-Legendre), n = floor(lambda + xi_cell) (expectation lambda, monotone in the
// density), and a bound of the weight for rejection sampling (max over a 4 x 4 grid of samples and
// the Gauss points, times a margin).
void FurGenerator::buildCells() {
  const std::size_t cellCount = std::size_t(p_.cellsU) * std::size_t(p_.cellsV);
  cells_.assign(cellCount, Cell{});
  idRangePerCell_ = std::uint32_t(std::min<std::uint64_t>((std::uint64_t(1) << 32) / cellCount,
                                                          std::numeric_limits<std::uint32_t>::max()));
  const double hs = 0.5 / p_.cellsU, ht = 0.5 / p_.cellsV;  // half a cell in (s, t)
  const double jacobian = domain_.du() * domain_.dv();       // d(u, v) / d(s, t)
  static constexpr std::array<double, 3> node{-0.7745966692414834, 0.0, 0.7745966692414834};
  static constexpr std::array<double, 3> weight{5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cellCount, 16), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t c = r.begin(); c != r.end(); ++c) {
      const double s0 = double(c % p_.cellsU) / p_.cellsU, t0 = double(c / p_.cellsU) / p_.cellsV;
      auto weightAt = [&](double s, double t) {
        const glm::dvec2 uv = unitToUv(s, t);
        return densityWeight({s, t}, surface_.evaluate(uv.x, uv.y));
      };
      double mass = 0.0, maxWeight = 0.0;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
          const double w = weightAt(s0 + hs * (1.0 + node[a]), t0 + ht * (1.0 + node[b]));
          mass += weight[a] * weight[b] * w;
          maxWeight = std::max(maxWeight, w);
        }
      mass *= hs * ht * std::abs(jacobian);
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b)
          maxWeight = std::max(maxWeight, weightAt(s0 + 2.0 * hs * a / 3.0, t0 + 2.0 * ht * b / 3.0));
      const double lambda = p_.density * mass;
      const double xi = RootRandom(cellCountBase_, c).draw(0);
      const double n = std::isfinite(lambda) && lambda > 0 ? std::floor(lambda + xi) : 0.0;
      Cell& cell = cells_[c];
      cell.maxWeight = kMaxWeightMargin * maxWeight;
      const double cap = double(idRangePerCell_);
      cell.count = std::uint32_t(std::min(n, cap));
      cell.capped = n > cap ? std::uint32_t(std::min(n - cap, 4294967295.0)) : 0u;
    }
  });
}

// --- hairs -----------------------------------------------------------------------------------

// Axis and length: the paper's H2 - H1 = a Su + b Sv + c N, its length fixed, proportional to |Su|
// or literal; maps and the random length variation on top. Zero length: no hair.
Verdict FurGenerator::plan(std::uint64_t hairKey, HairPlan& h) const {
  const RootFrame& root = h.root;
  glm::dvec3 abc = p_.orientation;
  if (p_.orientationMapA) abc.x = p_.orientationMapA->value(root.st);
  if (p_.orientationMapB) abc.y = p_.orientationMapB->value(root.st);
  if (p_.orientationMapC) abc.z = p_.orientationMapC->value(root.st);
  const glm::dvec3 dir = p_.unitTangents ? abc.x * root.Tu + abc.y * root.Tv + abc.z * root.N
                                         : abc.x * root.Su + abc.y * root.Sv + abc.z * root.N;
  const double dirLength = glm::length(dir);
  h.attributes = RootRandom(hairBase_, hairKey);
  const double xiLength = h.attributes.draw(0);
  if (!(dirLength > 0) || !std::isfinite(dirLength)) return Verdict::ZeroLength;
  h.axis = dir / dirLength;
  double length = 0.0;
  switch (p_.lengthMode) {
    case FurParams::LengthMode::Paper: length = dirLength; break;
    case FurParams::LengthMode::Fixed: length = p_.length; break;
    case FurParams::LengthMode::ProportionalToSu: length = p_.lengthPerSu * glm::length(root.Su); break;
  }
  if (p_.lengthMap) {
    const double m = p_.lengthMap->value(root.st);
    length *= m > 0 ? m : 0.0;
  }
  length *= 1.0 + p_.lengthVariation * (2.0 * xiLength - 1.0);
  // A hair too short to move its tip off the root in doubles is a zero-length hair.
  if (!(length > 0x1p-40 * maxAbs(root.P)) || !std::isfinite(length)) return Verdict::ZeroLength;
  h.length = length;
  return Verdict::Grown;
}

// The polyline: segments of equal length length / n whose directions are the axis bent by gravity
// and wind (growing along the hair) and twisted by the curl helix, evaluated at segment midpoints
// ("follow the leader": the hair keeps its length whatever the bending). Then clumping.
void FurGenerator::shape(const HairPlan& h, glm::dvec3* points) const {
  const int n = segments_;
  points[0] = h.root.P;
  if (!shaped_) {
    points[1] = h.root.P + h.length * h.axis;
  } else {
    const double step = h.length / n;
    glm::dvec3 bend = gravity_;
    if (windOn_) {
      const double phase = h.attributes.draw(2);
      const double push = p_.windStrength * ((1.0 - p_.windSway) +
                                             p_.windSway * std::sin(kTwoPi * (windPhaseBase_ + phase)));
      bend += push * wind_;
    }
    glm::dvec3 e1{0.0}, e2{0.0};
    if (curlOn_) {
      e1 = h.root.Tu - glm::dot(h.root.Tu, h.axis) * h.axis;
      if (glm::dot(e1, e1) < 1e-6) e1 = h.root.Tv - glm::dot(h.root.Tv, h.axis) * h.axis;
      e1 = normalizedOrZero(e1);
      e2 = glm::cross(h.axis, e1);
    }
    const double curlSlope = kTwoPi * p_.curlAmplitude * p_.curlFrequency;
    const double xiCurl = curlOn_ ? h.attributes.draw(3) : 0.0;
    glm::dvec3 previous = h.axis;
    for (int k = 1; k <= n; ++k) {
      const double s = (k - 0.5) / n;
      glm::dvec3 t = h.axis + s * bend;
      if (curlOn_) {
        const double theta = kTwoPi * (p_.curlFrequency * s + xiCurl);
        t += curlSlope * (std::cos(theta) * e2 - std::sin(theta) * e1);
      }
      const double tl = glm::length(t);
      if (tl > 1e-12 && std::isfinite(tl)) previous = t / tl;  // else keep the previous direction
      points[k] = points[k - 1] + step * previous;
    }
  }
  if (p_.clumping > 0) {
    const ClumpCentre* centre = nearestClump(h.root.st);
    if (centre && centre->valid) {
      const glm::dvec3 pull = centre->tip - points[n];
      for (int k = 1; k <= n; ++k) {
        const double s = double(k) / n;
        points[k] += (p_.clumping * s * s) * pull;
      }
      if (p_.clumping == 1.0) points[n] = centre->tip;  // exactly together
    }
  }
}

// Root colour (map or constant) to tip colour, colour regions, then the random intensity.
void FurGenerator::colours(const HairPlan& h, glm::vec3* out) const {
  const float intensity = float(1.0 + p_.intensityVariation * (2.0 * h.attributes.draw(1) - 1.0));
  glm::vec3 root = p_.rootColourMap ? p_.rootColourMap->sample(h.root.st, UvFootprint{}) : p_.rootColour;
  glm::vec3 tip = p_.tipColour;
  for (const FurColourRegion& region : p_.colourRegions) {
    glm::dvec2 d = h.root.st - region.centre;
    if (domain_.periodicU) d.x -= std::round(d.x);
    if (domain_.periodicV) d.y -= std::round(d.y);
    const double distance = glm::length(d);
    if (!(distance < region.radius)) continue;
    const double inner = region.radius * (1.0 - region.falloff);
    double w = 1.0;
    if (distance > inner) {
      const double x = (region.radius - distance) / (region.radius - inner);  // 1 at inner, 0 at rim
      w = x * x * (3.0 - 2.0 * x);
    }
    root = glm::mix(root, region.colour, float(w));
    tip = glm::mix(tip, region.colour, float(w));
  }
  if (!(std::isfinite(root.x) && std::isfinite(root.y) && std::isfinite(root.z))) root = p_.rootColour;
  const int n = segments_;
  for (int k = 0; k <= n; ++k) out[k] = intensity * glm::mix(root, tip, float(k) / float(n));
}

// One centre hair per clump cell, hashed within the cell and grown like any hair (no clumping):
// its tip is where the clump's hairs are pulled.
void FurGenerator::buildClumps() {
  const std::size_t count = std::size_t(p_.clumpCellsU) * std::size_t(p_.clumpCellsV);
  clumps_.assign(count, ClumpCentre{});
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 16), [&](const tbb::blocked_range<std::size_t>& r) {
    std::array<glm::dvec3, kMaxSegments + 1> points;
    for (std::size_t c = r.begin(); c != r.end(); ++c) {
      const RootRandom place(clumpBase_, c);
      ClumpCentre& centre = clumps_[c];
      centre.st = {(double(c % p_.clumpCellsU) + place.draw(0)) / p_.clumpCellsU,
                   (double(c / p_.clumpCellsU) + place.draw(1)) / p_.clumpCellsV};
      HairPlan h;
      h.root.st = centre.st;
      const glm::dvec2 uv = unitToUv(centre.st.x, centre.st.y);
      if (!rootFrame(uv, surface_.evaluate(uv.x, uv.y), h.root)) continue;
      // Its own attribute stream: key above every root index (< 2^32).
      if (plan((std::uint64_t(1) << 32) + c, h) != Verdict::Grown) continue;
      shape(h, points.data());
      centre.tip = points[segments_];
      centre.valid = true;
    }
  });
}

// The nearest centre (in clump-cell units) among the 3 x 3 cells around st, across periodic seams.
const ClumpCentre* FurGenerator::nearestClump(const glm::dvec2& st) const {
  const int nu = p_.clumpCellsU, nv = p_.clumpCellsV;
  const int cu = std::clamp(int(std::floor(st.x * nu)), 0, nu - 1);
  const int cv = std::clamp(int(std::floor(st.y * nv)), 0, nv - 1);
  const ClumpCentre* best = nullptr;
  double bestDistance = std::numeric_limits<double>::infinity();
  for (int dv = -1; dv <= 1; ++dv)
    for (int du = -1; du <= 1; ++du) {
      int iu = cu + du, iv = cv + dv;
      double shiftU = 0.0, shiftV = 0.0;
      if (iu < 0 || iu >= nu) {
        if (!domain_.periodicU) continue;
        shiftU = iu < 0 ? -1.0 : 1.0;
        iu = (iu + nu) % nu;
      }
      if (iv < 0 || iv >= nv) {
        if (!domain_.periodicV) continue;
        shiftV = iv < 0 ? -1.0 : 1.0;
        iv = (iv + nv) % nv;
      }
      const ClumpCentre& c = clumps_[std::size_t(iv) * nu + iu];
      const double x = (c.st.x + shiftU - st.x) * nu, y = (c.st.y + shiftV - st.y) * nv;
      const double d = x * x + y * y;
      if (d < bestDistance) {
        bestDistance = d;
        best = &c;
      }
    }
  return best;
}

// --- the two passes --------------------------------------------------------------------------

// reserve + resize: capacity is exactly n. Large arrays ask Linux for transparent huge pages before
// they are first touched: 2 MB page faults instead of 4 KB ones (on the CI machine the 4 KB faults
// of a million hairs' 100 MB cost as much as growing them). Only advice: without it, same result.
template <class T>
void resizeExactly(std::vector<T>& v, std::size_t n) {
  v.reserve(n);
#ifdef __linux__
  constexpr std::uintptr_t kPage = 4096;
  const std::size_t bytes = n * sizeof(T);
  if (bytes >= (std::size_t(8) << 20)) {
    const std::uintptr_t begin = (reinterpret_cast<std::uintptr_t>(v.data()) + kPage - 1) & ~(kPage - 1);
    const std::uintptr_t end = reinterpret_cast<std::uintptr_t>(v.data()) + bytes;
    if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
  }
#endif
  v.resize(n);
}

// Roots the block asks for: an upper bound of its hairs, exact unless roots are skipped.
std::uint64_t FurGenerator::rootsAskedFor(std::size_t block) const {
  if (p_.placement == FurParams::Placement::Grid) {
    const std::uint64_t roots = std::uint64_t(p_.gridU) * std::uint64_t(p_.gridV);
    return std::min<std::uint64_t>(roots, (block + 1) * kRootsPerBlock) - block * kRootsPerBlock;
  }
  std::uint64_t n = 0;
  const std::size_t end = std::min(cells_.size(), (block + 1) * kCellsPerBlock);
  for (std::size_t c = block * kCellsPerBlock; c < end; ++c) n += cells_[c].count;
  return n;
}

std::size_t FurGenerator::blockCount() const {
  if (p_.placement == FurParams::Placement::Grid) {
    const std::size_t roots = std::size_t(p_.gridU) * std::size_t(p_.gridV);
    return (roots + kRootsPerBlock - 1) / kRootsPerBlock;
  }
  return (cells_.size() + kCellsPerBlock - 1) / kCellsPerBlock;
}

// Calls visit(rootIndex, plan) for every hair that grows in the block, in root order; with
// `only` (a share's roots of the block, from rootsOfShare), for those roots alone.
template <class Visit>
BlockTally FurGenerator::forEachRoot(std::size_t block, Visit&& visit, const std::vector<std::uint32_t>* only) const {
  BlockTally tally;
  HairPlan h;
  RootFrame& root = h.root;
  auto grow = [&](std::uint32_t rootIndex, Verdict placed) {
    const Verdict v = placed == Verdict::Grown ? plan(rootIndex, h) : placed;
    tally.count(v);
    if (v == Verdict::Grown) visit(rootIndex, h);
  };
  const std::uint64_t cellCount = cells_.size();
  if (only) {
    for (std::uint32_t r : *only) {
      if (p_.placement == FurParams::Placement::Grid)
        grow(r, placeGridRoot(r, root));
      else
        grow(r, placeCellRoot(std::uint32_t(r % cellCount), r, root));
    }
    return tally;
  }
  if (p_.placement == FurParams::Placement::Grid) {
    const std::size_t roots = std::size_t(p_.gridU) * std::size_t(p_.gridV);
    const std::size_t end = std::min(roots, (block + 1) * kRootsPerBlock);
    for (std::size_t r = block * kRootsPerBlock; r < end; ++r) grow(std::uint32_t(r), placeGridRoot(std::uint32_t(r), root));
  } else {
    const std::size_t end = std::min(cells_.size(), (block + 1) * kCellsPerBlock);
    for (std::size_t c = block * kCellsPerBlock; c < end; ++c) {
      for (std::uint32_t k = 0; k < cells_[c].count; ++k) {
        const std::uint32_t rootIndex = std::uint32_t(k * cellCount + c);
        grow(rootIndex, placeCellRoot(std::uint32_t(c), rootIndex, root));
      }
      tally.roots += cells_[c].capped;
      tally.capacity += cells_[c].capped;
    }
  }
  return tally;
}

// The roots of the block that FurParams::rootFilter keeps, in root order; the others are counted
// in `tally` (elsewhere; area-correct roots with no place on the surface, degenerate; capped).
// A grid root is judged by its (u, v) alone, before the surface is evaluated; an area-correct
// root needs its placement (rejection sampling evaluates the surface), which its share repeats.
std::vector<std::uint32_t> FurGenerator::rootsOfShare(std::size_t block, BlockTally& tally) const {
  std::vector<std::uint32_t> kept;
  if (p_.placement == FurParams::Placement::Grid) {
    const std::size_t roots = std::size_t(p_.gridU) * std::size_t(p_.gridV);
    const std::size_t end = std::min(roots, (block + 1) * kRootsPerBlock);
    for (std::size_t r = block * kRootsPerBlock; r < end; ++r) {
      const glm::dvec2 st = gridSt(std::uint32_t(r));
      if (p_.rootFilter(unitToUv(st.x, st.y)))
        kept.push_back(std::uint32_t(r));
      else
        tally.count(Verdict::Elsewhere);
    }
    return kept;
  }
  RootFrame root;
  const std::size_t end = std::min(cells_.size(), (block + 1) * kCellsPerBlock);
  const std::uint64_t cellCount = cells_.size();
  for (std::size_t c = block * kCellsPerBlock; c < end; ++c) {
    for (std::uint32_t k = 0; k < cells_[c].count; ++k) {
      const std::uint32_t rootIndex = std::uint32_t(k * cellCount + c);
      const Verdict v = placeCellRoot(std::uint32_t(c), rootIndex, root);
      if (v != Verdict::Grown)
        tally.count(v);
      else if (p_.rootFilter(root.uv))
        kept.push_back(rootIndex);
      else
        tally.count(Verdict::Elsewhere);
    }
    tally.roots += cells_[c].capped;
    tally.capacity += cells_[c].capped;
  }
  return kept;
}

Fur FurGenerator::grow() {
  Fur fur;
  fur.thickness = p_.thickness;
  if (p_.placement == FurParams::Placement::AreaCorrect) buildCells();
  if (p_.clumping > 0) buildClumps();

  // Counts first: the roots each block asks for are known before any hair is grown (the grid's
  // roots; the cells' n = floor(lambda + xi)). Prefix sums give every block its first slot.
  // The limit is checked against the whole surface's roots, with or without a root filter, so
  // that every piece of a distributed surface fails or passes as the whole would.
  const std::size_t blocks = blockCount();
  std::vector<std::uint64_t> firstSlot(blocks + 1, 0);
  std::vector<std::uint64_t> asked(blocks, 0);
  std::uint64_t wholeSlots = 0;
  for (std::size_t b = 0; b < blocks; ++b) wholeSlots += asked[b] = rootsAskedFor(b);
  const std::uint64_t pointsPerHair = std::uint64_t(segments_) + 1;
  const double limit = std::min(p_.maxPoints, double(std::numeric_limits<std::uint32_t>::max()));
  if (double(wholeSlots) * double(pointsPerHair) > limit)
    throw std::length_error("fur on " + surface_.describe() + ": " + std::to_string(wholeSlots) + " hairs of " +
                            std::to_string(pointsPerHair) + " points would exceed the limit of " +
                            std::to_string((unsigned long long)limit) +
                            " points; lower the grid, density or segments (or split the patch)");
  // With a root filter (a distributed piece) only the share's roots get slots and are grown.
  std::vector<std::vector<std::uint32_t>> share;
  std::vector<BlockTally> shareTallies;
  if (p_.rootFilter) {
    share.resize(blocks);
    shareTallies.resize(blocks);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t b = r.begin(); b != r.end(); ++b) {
        share[b] = rootsOfShare(b, shareTallies[b]);
        asked[b] = share[b].size();
      }
    });
  }
  for (std::size_t b = 0; b < blocks; ++b) firstSlot[b + 1] = firstSlot[b] + asked[b];
  const std::uint64_t slots = firstSlot[blocks];
  // Sized exactly; the big arrays on two threads at once (value initialisation is serial per vector).
  tbb::parallel_invoke([&] { resizeExactly(fur.hairs.points, slots * pointsPerHair); },
                       [&] {
                         resizeExactly(fur.hairs.colours, slots * pointsPerHair);
                         resizeExactly(fur.ids, slots);
                         resizeExactly(fur.rootUvs, slots);
                       });

  // Fill: every block grows its roots in root order into its own slots. One evaluation per root.
  const std::uint64_t patchBits = std::uint64_t(patch_) << 32;
  std::vector<BlockTally> tallies(blocks);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t b = r.begin(); b != r.end(); ++b) {
      std::uint64_t hair = firstSlot[b];
      tallies[b] = forEachRoot(b, [&](std::uint32_t rootIndex, const HairPlan& h) {
        const std::uint64_t first = hair * pointsPerHair;
        shape(h, fur.hairs.points.data() + first);
        colours(h, fur.hairs.colours.data() + first);
        fur.ids[hair] = patchBits | rootIndex;
        fur.rootUvs[hair] = h.root.uv;
        ++hair;
      }, share.empty() ? nullptr : &share[b]);
      if (!shareTallies.empty()) {
        const BlockTally& o = shareTallies[b];
        BlockTally& t = tallies[b];
        t.roots += o.roots, t.degenerate += o.degenerate, t.capacity += o.capacity, t.elsewhere += o.elsewhere;
      }
    }
  });

  std::uint64_t hairs = 0;
  for (const BlockTally& t : tallies) {
    hairs += t.hairs;
    fur.counts.rootsTried += t.roots;
    fur.counts.skippedDegenerate += t.degenerate;
    fur.counts.skippedZeroLength += t.zeroLength;
    fur.counts.skippedCapacity += t.capacity;
    fur.counts.elsewhere += t.elsewhere;
  }
  fur.counts.hairs = hairs;

  // Roots skipped (degenerate, zero length) left their slots empty: close the gaps block by block in
  // root order (moving down, so in place), then give back the spare capacity. Rare: a surface that
  // is not finite somewhere, a zero length map, a pole under length = k |Su|.
  if (hairs < slots) {
    std::uint64_t to = 0;
    for (std::size_t b = 0; b < blocks; ++b) {
      const std::uint64_t from = firstSlot[b], n = tallies[b].hairs;
      if (from != to && n > 0) {
        std::copy(fur.hairs.points.begin() + from * pointsPerHair, fur.hairs.points.begin() + (from + n) * pointsPerHair,
                  fur.hairs.points.begin() + to * pointsPerHair);
        std::copy(fur.hairs.colours.begin() + from * pointsPerHair, fur.hairs.colours.begin() + (from + n) * pointsPerHair,
                  fur.hairs.colours.begin() + to * pointsPerHair);
        std::copy(fur.ids.begin() + from, fur.ids.begin() + from + n, fur.ids.begin() + to);
        std::copy(fur.rootUvs.begin() + from, fur.rootUvs.begin() + from + n, fur.rootUvs.begin() + to);
      }
      to += n;
    }
    fur.hairs.points.resize(hairs * pointsPerHair);
    fur.hairs.colours.resize(hairs * pointsPerHair);
    fur.ids.resize(hairs);
    fur.rootUvs.resize(hairs);
    fur.hairs.points.shrink_to_fit();
    fur.hairs.colours.shrink_to_fit();
    fur.ids.shrink_to_fit();
    fur.rootUvs.shrink_to_fit();
  }
  resizeExactly(fur.hairs.starts, hairs + 1);
  tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, hairs + 1, 1 << 16), [&](const tbb::blocked_range<std::uint64_t>& r) {
    for (std::uint64_t h = r.begin(); h != r.end(); ++h) fur.hairs.starts[h] = std::uint32_t(h * pointsPerHair);
  });
  return fur;
}

// --- validation ------------------------------------------------------------------------------

std::string fieldProblem(const char* field, const std::string& value, const char* rule) {
  return std::string("FurParams.") + field + " = " + value + ": " + rule;
}
std::string str(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", x);
  return buf;
}
std::string str(const glm::dvec3& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.9g, %.9g, %.9g)", v.x, v.y, v.z);
  return buf;
}
std::string str(const glm::vec3& v) { return str(glm::dvec3(v)); }

}  // namespace

std::string FurParams::problem() const {
  auto finite = [](double x) { return std::isfinite(x); };
  auto inRange = [](double x, double lo, double hi) { return x >= lo && x <= hi; };  // false for NaN
  auto finiteVec = [](const glm::dvec3& v) { return finite3(v); };
#define WF_FUR_CHECK(ok, field, value, rule) \
  if (!(ok)) return fieldProblem(field, str(value), rule)
  WF_FUR_CHECK(placement == Placement::Grid || placement == Placement::AreaCorrect, "placement",
               double(int(placement)), "must be Grid or AreaCorrect");
  WF_FUR_CHECK(gridU >= 1 && gridU <= 1 << 20, "gridU", double(gridU), "must be in [1, 2^20]");
  WF_FUR_CHECK(gridV >= 1 && gridV <= 1 << 20, "gridV", double(gridV), "must be in [1, 2^20]");
  WF_FUR_CHECK(double(gridU) * double(gridV) <= 4294967295.0, "gridU * gridV", double(gridU) * gridV,
               "must be below 2^32 (root ids are 32 bits per patch)");
  WF_FUR_CHECK(inRange(jitter, 0.0, 1.0), "jitter", jitter, "must be in [0, 1]");
  WF_FUR_CHECK(finite(density) && density >= 0, "density", density, "must be finite and >= 0");
  WF_FUR_CHECK(cellsU >= 1 && cellsU <= 1 << 12, "cellsU", double(cellsU), "must be in [1, 4096]");
  WF_FUR_CHECK(cellsV >= 1 && cellsV <= 1 << 12, "cellsV", double(cellsV), "must be in [1, 4096]");
  WF_FUR_CHECK(double(cellsU) * double(cellsV) <= double(1 << 22), "cellsU * cellsV", double(cellsU) * cellsV,
               "must be at most 2^22 (at least 1024 hair ids per cell)");
  WF_FUR_CHECK(finiteVec(orientation), "orientation", orientation, "must be finite");
  WF_FUR_CHECK(lengthMode == LengthMode::Paper || lengthMode == LengthMode::Fixed ||
                   lengthMode == LengthMode::ProportionalToSu,
               "lengthMode", double(int(lengthMode)), "must be Paper, Fixed or ProportionalToSu");
  WF_FUR_CHECK(finite(length) && length >= 0, "length", length, "must be finite and >= 0");
  WF_FUR_CHECK(finite(lengthPerSu) && lengthPerSu >= 0, "lengthPerSu", lengthPerSu, "must be finite and >= 0");
  WF_FUR_CHECK(lengthVariation >= 0 && lengthVariation < 1, "lengthVariation", lengthVariation, "must be in [0, 1)");
  WF_FUR_CHECK(segments >= 1 && segments <= kMaxSegments, "segments", double(segments), "must be in [1, 64]");
  WF_FUR_CHECK(finite(gravity), "gravity", gravity, "must be finite");
  WF_FUR_CHECK(finiteVec(gravityDirection), "gravityDirection", gravityDirection, "must be finite");
  WF_FUR_CHECK(finite(curlAmplitude) && curlAmplitude >= 0, "curlAmplitude", curlAmplitude, "must be finite and >= 0");
  WF_FUR_CHECK(finite(curlFrequency), "curlFrequency", curlFrequency, "must be finite");
  WF_FUR_CHECK(inRange(clumping, 0.0, 1.0), "clumping", clumping, "must be in [0, 1]");
  WF_FUR_CHECK(clumpCellsU >= 1 && clumpCellsU <= 4096, "clumpCellsU", double(clumpCellsU), "must be in [1, 4096]");
  WF_FUR_CHECK(clumpCellsV >= 1 && clumpCellsV <= 4096, "clumpCellsV", double(clumpCellsV), "must be in [1, 4096]");
  WF_FUR_CHECK(finiteVec(windDirection), "windDirection", windDirection, "must be finite");
  WF_FUR_CHECK(finite(windStrength), "windStrength", windStrength, "must be finite");
  WF_FUR_CHECK(inRange(windSway, 0.0, 1.0), "windSway", windSway, "must be in [0, 1]");
  WF_FUR_CHECK(finite(windFrequency), "windFrequency", windFrequency, "must be finite");
  WF_FUR_CHECK(finite(time), "time", time, "must be finite");
  WF_FUR_CHECK(finiteVec(glm::dvec3(rootColour)), "rootColour", rootColour, "must be finite");
  WF_FUR_CHECK(finiteVec(glm::dvec3(tipColour)), "tipColour", tipColour, "must be finite");
  WF_FUR_CHECK(inRange(intensityVariation, 0.0, 1.0), "intensityVariation", intensityVariation, "must be in [0, 1]");
  WF_FUR_CHECK(finite(thickness) && thickness >= 0, "thickness", thickness, "must be finite and >= 0");
  WF_FUR_CHECK(maxPoints >= 0, "maxPoints", maxPoints, "must be >= 0");
  for (std::size_t i = 0; i < colourRegions.size(); ++i) {
    const FurColourRegion& r = colourRegions[i];
    const std::string field = "colourRegions[" + std::to_string(i) + "]";
    if (!(std::isfinite(r.centre.x) && std::isfinite(r.centre.y)))
      return fieldProblem((field + ".centre").c_str(), str(glm::dvec3(r.centre, 0.0)), "must be finite");
    WF_FUR_CHECK(finite(r.radius) && r.radius >= 0, (field + ".radius").c_str(), r.radius, "must be finite and >= 0");
    WF_FUR_CHECK(inRange(r.falloff, 0.0, 1.0), (field + ".falloff").c_str(), r.falloff, "must be in [0, 1]");
    WF_FUR_CHECK(finiteVec(glm::dvec3(r.colour)), (field + ".colour").c_str(), r.colour, "must be finite");
  }
#undef WF_FUR_CHECK
  return {};
}

std::string FurParams::describe() const {
  std::ostringstream o;
  o << "fur " << (placement == Placement::Grid ? "grid " + std::to_string(gridU) + "x" + std::to_string(gridV) +
                                                     " jitter " + str(jitter)
                                               : "area-correct density " + str(density) + " cells " +
                                                     std::to_string(cellsU) + "x" + std::to_string(cellsV))
    << ", orientation " << str(orientation) << (unitTangents ? " (unit tangents)" : "") << ", length "
    << (lengthMode == LengthMode::Paper ? std::string("|aSu+bSv+cN|")
        : lengthMode == LengthMode::Fixed ? str(length)
                                          : str(lengthPerSu) + "|Su|")
    << " +-" << str(lengthVariation) << ", segments " << segments << ", gravity " << str(gravity) << ", curl "
    << str(curlAmplitude) << "@" << str(curlFrequency) << ", clumping " << str(clumping) << ", wind "
    << str(windStrength) << " at t=" << str(time) << ", thickness " << str(thickness) << ", seed " << seed;
  return o.str();
}

Fur growFur(const Surface& surface, const FurParams& params, std::uint32_t patchIndex) {
  if (std::string why = params.problem(); !why.empty()) throw std::invalid_argument(why);
  return FurGenerator(surface, params, patchIndex).grow();
}

}  // namespace wf

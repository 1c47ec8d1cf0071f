#include "abuffer/abuffer.h"

#include "core/limits.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace wf {

namespace {
// How many of a pixel's most recent fragments are checked for a merge: pieces of one object
// arrive one after another (consecutive segments, neighbouring triangles), so a short look-back
// finds them without making insertion O(list length).
constexpr int kMergeLookBack = 8;
// Solid means the whole pixel: the exact area may fall short of 1 by rounding only.
constexpr float kSolidArea = 1.0f - 1e-5f;

bool depthRangesTouch(const Fragment& a, const Fragment& b) {
  const float eps = 1e-5f * std::max(std::abs(a.zmax), std::abs(b.zmax)) + 1e-30f;
  return a.zmin <= b.zmax + eps && b.zmin <= a.zmax + eps;
}

void mergeInto(Fragment& g, const Fragment& f) {
  // The other piece's primitive, for the depth of the merged surface (the first other one).
  // Only for a wire's pieces: the pieces of a surface share its plane (or abut where they do not),
  // and another triangle's plane, extrapolated over this one's subpixels, is no depth of it.
  if (g.occludesEarly && g.prim2 == Fragment::kNoPrimitive && f.prim != g.prim) g.prim2 = f.prim;
  g.hideFloor = std::max(g.hideFloor, f.hideFloor);
  const float a = g.area + f.area;
  const float wg = a > 0 ? g.area / a : 0.5f, wf = 1.0f - wg;
  g.colour = g.colour * wg + f.colour * wf;
  g.opacity = g.opacity * wg + f.opacity * wf;
  g.zkey = g.zkey * wg + f.zkey * wf;
  g.zmin = std::min(g.zmin, f.zmin);
  g.zmax = std::max(g.zmax, f.zmax);
  g.area = std::min(1.0f, a);
  const MaskBits sampled = g.sampledMask() | f.sampledMask();
  g.standInBits = (g.standInBits | f.standInBits) & ~sampled;
  g.mask = sampled | g.standInBits;
}

#if defined(__SSE2__)
// The subpixel records (D, T: one float per sample, samples a multiple of 4 in every layout) four
// samples at a time: a nibble of the mask selects lanes through this table, so a fragment's
// occlusion costs a fixed few operations per four subpixels instead of a branch per set bit. The
// same float operations as the scalar loops, lane by lane (products, maxima, comparisons: no
// fused operations), so the same results to the bit.
struct NibbleLanes {
  alignas(16) std::uint32_t lanes[16][4];
  constexpr NibbleLanes() : lanes{} {
    for (int b = 0; b < 16; ++b)
      for (int i = 0; i < 4; ++i)
        if ((b >> i) & 1) lanes[b][i] = 0xFFFFFFFFu;
  }
};
constexpr NibbleLanes kNibbles{};
inline __m128 nibbleLanes(unsigned nibble) {
  return _mm_castsi128_ps(_mm_load_si128(reinterpret_cast<const __m128i*>(kNibbles.lanes[nibble])));
}
inline __m128 blendLanes(__m128 m, __m128 a, __m128 b) { return _mm_or_ps(_mm_and_ps(m, a), _mm_andnot_ps(m, b)); }
#endif
}  // namespace

void ABufferCounters::add(const ABufferCounters& o) {
  fragments += o.fragments;
  merged += o.merged;
  culled += o.culled;
  tail += o.tail;
  pixelsWithList += o.pixelsWithList;
  pixelsSolidOnly += o.pixelsSolidOnly;
  pixelsOverBudget += o.pixelsOverBudget;
  pixelsDeep += o.pixelsDeep;
  coveredPixels += o.coveredPixels;
  maxFragmentsPerPixel = std::max(maxFragmentsPerPixel, o.maxFragmentsPerPixel);
  maxListLength = std::max(maxListLength, o.maxListLength);
  peakBytes = std::max(peakBytes, o.peakBytes);
  peakFragmentsHeld = std::max(peakFragmentsHeld, o.peakFragmentsHeld);
  xray += o.xray;
  xrayDropped += o.xrayDropped;
}

namespace {
// (Inlined into each of atSamples' clones, below, so that each is compiled for its target.)
#if defined(__GNUC__)
#define WF_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define WF_ALWAYS_INLINE inline
#endif
// The depth of a SurfaceDepth at samples, one loop per case (no branch inside, so that it
// vectorises: the subpixel depths are the resolve's inner loop on dense hair).
template <bool Perspective>
inline float depthOfKey(float key) {
  if constexpr (Perspective) {
    const float d = 1.0f / key;
    return key > 0.0f ? d : INFINITY;
  } else {
    return key;
  }
}
template <bool Perspective>
WF_ALWAYS_INLINE void planeDepths(const SurfaceDepth& m, const float* sx, const float* sy, int n, float* out) {
  const float lo = std::max(m.nearPlane, m.lo), hi = m.hi, k0 = m.k0, kx = m.kx, ky = m.ky;
  for (int k = 0; k < n; ++k) out[k] = std::min(hi, std::max(lo, depthOfKey<Perspective>(k0 + kx * sx[k] + ky * sy[k])));
}
template <bool Perspective, bool Round>
WF_ALWAYS_INLINE void wireDepths(const SurfaceDepth& m, const float* sx, const float* sy, int n, float* out) {
  const float lo = std::max(m.nearPlane, m.lo), hi = m.hi;
  const float t0 = m.t0, tx = m.tx, ty = m.ty, l0 = m.l0, lx = m.lx, ly = m.ly, len = m.length;
  const float w0 = m.w0, dw = m.dw, r0 = m.r0, dr = m.dr, k0 = m.k0, kx = m.kx, tmax = m.tmax;
  const float tl = m.tl, ta = m.ta, tt = m.tt, s0 = m.s0, st = m.st;
  for (int k = 0; k < n; ++k) {
    const float t = t0 + tx * sx[k] + ty * sy[k];
    const float tc = std::min(tmax, std::max(0.0f, t));
    float d;
    if constexpr (Round) {
      const float lat = l0 + lx * sx[k] + ly * sy[k], along = (t - tc) * len, w = w0 + dw * tc;
      const float q2 = std::min(1.0f, (lat * lat + along * along) / (w * w));
      if constexpr (Perspective) {  // the tilt across the wire (SegmentTilt: zero when orthographic)
        const float lc = std::min(w, std::max(-w, lat));
        d = depthOfKey<Perspective>(k0 + kx * std::min(tmax, std::max(0.0f, t + lc * (s0 + st * tc))));
        d *= 1.0f + tl * lc + (ta + tt * tc) * std::min(w, std::max(-w, along));
      } else {
        d = depthOfKey<Perspective>(k0 + kx * tc);
      }
      d -= (r0 + dr * tc) * std::sqrt(1.0f - q2);
    } else {
      d = depthOfKey<Perspective>(k0 + kx * tc);
    }
    out[k] = std::min(hi, std::max(lo, d));
  }
}
// A wire's exact solid (SurfaceDepth::capsule) at the samples; where a sample's ray misses it,
// the depth where the ray passes it nearest (render/pipeline.h, WireCapsule::depthAt).
// Branch-free, so that it vectorises as the model does.
template <bool Perspective>
WF_ALWAYS_INLINE void capsuleDepths(const SurfaceDepth& m, const float* sx, const float* sy, int n, float* out) {
  const float lo = std::max(m.nearPlane, m.lo), hi = m.hi;
  const float u0 = m.cu0, u1 = m.cu1, u2 = m.cu2, len = m.clen, r0 = m.cr0, dr = m.cdr;
  // The body: the cone tangent to both spheres (SurfaceDepth::cbody, from WireCapsule::coneBand).
  const bool body = m.cbody;
  const float kc = m.ck, rho0 = m.crho0, h0 = m.ch0, h1 = m.ch1;
  for (int k = 0; k < n; ++k) {
    const float wx = m.cw0 + m.cwx * sx[k], wy = m.cw1 + m.cwy * sy[k], wz = m.cw2;
    const float dx = m.cd0 + m.cdx * sx[k], dy = m.cd1 + m.cdy * sy[k], dz = m.cd2;
    const float dd = dx * dx + dy * dy + dz * dz, idd = 1.0f / dd;
    // The spheres about the ends: |w + s d| = r, entered at -b / dd less the half chord, whose
    // square (r^2 - m^2) / dd is formed from m, the ray's distance from the centre where it passes
    // it nearest (not b^2 - dd (w^2 - r^2), which cancels at a graze: w is of the segment's length).
    const float b0 = dx * wx + dy * wy + dz * wz, near0 = -b0 * idd;
    const float m0x = wx + near0 * dx, m0y = wy + near0 * dy, m0z = wz + near0 * dz;
    const float disc0 = r0 * r0 - (m0x * m0x + m0y * m0y + m0z * m0z);
    const float e1x = wx - u0 * len, e1y = wy - u1 * len, e1z = wz - u2 * len, r1 = r0 + dr;
    const float b1 = dx * e1x + dy * e1y + dz * e1z, near1 = -b1 * idd;
    const float m1x = e1x + near1 * dx, m1y = e1y + near1 * dy, m1z = e1z + near1 * dz;
    const float disc1 = r1 * r1 - (m1x * m1x + m1y * m1y + m1z * m1z);
    float best = disc0 >= 0.0f ? near0 - std::sqrt(std::max(disc0, 0.0f) * idd) : INFINITY;
    best = disc1 >= 0.0f ? std::min(best, near1 - std::sqrt(std::max(disc1, 0.0f) * idd)) : best;
    // The body: where the ray enters the cone, |q + sigma p| = rho + kc du sigma (q, p: the
    // ray's origin and direction across the axis), A sigma^2 + 2 B sigma + C = 0: the root
    // (-B - sqrt(B^2 - A C)) / A, as C / (-B + sqrt(B^2 - A C)) where B < 0 (WireCapsule::depthAt).
    const float du = dx * u0 + dy * u1 + dz * u2, wu = wx * u0 + wy * u1 + wz * u2;
    const float px = dx - u0 * du, py = dy - u1 * du, pz = dz - u2 * du;
    const float qx = wx - u0 * wu, qy = wy - u1 * wu, qz = wz - u2 * wu;
    const float a = px * px + py * py + pz * pz, b = px * qx + py * qy + pz * qz;
    const float rho = rho0 + kc * wu;
    const float A = a - kc * kc * du * du, B = b - kc * du * rho, C = qx * qx + qy * qy + qz * qz - rho * rho;
    const float disc = B * B - A * C, root = std::sqrt(std::max(disc, 0.0f));
    const bool stable = B < 0.0f;
    const float num = stable ? C : -B - root, den = stable ? root - B : A;
    const float sig = den != 0.0f ? num / den : 0.0f, h = wu + sig * du;
    best = body && den != 0.0f && disc >= 0.0f && h >= h0 && h <= h1 ? std::min(best, sig) : best;
    // Missed: where it grazes the cone (the quadratic's vertex -B / A, A > 0) where that lies on
    // its band, else the nearer end's centre.
    const float sv = A > 0.0f ? -B / A : 0.0f, hv = wu + sv * du;
    const float nearest = !(body && A > 0.0f) ? std::min(near0, near1) : hv < h0 ? near0 : hv > h1 ? near1 : sv;
    const float s = best < INFINITY && m.zref + best > 0.0f ? best : nearest;  // (s from the depth zref)
    out[k] = std::min(hi, std::max(lo, m.zref + s));
  }
}
}  // namespace

// Built twice where the compiler can choose at load time (GCC on x86-64): for AVX2, eight
// samples per instruction, and for the baseline, four. Without fused multiply-adds: the avx2
// target does not enable FMA (GNU C++ would contract a * b + c where FMA is available: a build
// for a target with FMA in its baseline, -march=native or x86-64-v3, would change these floats,
// in both clones alike), so both give the same depths to the bit.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__SSE2__)
__attribute__((target_clones("avx2", "default")))
#endif
void SurfaceDepth::atSamples(const float* sx, const float* sy, int n, float* out) const {
  if (kind == Kind::Plane) {
    if (perspective) planeDepths<true>(*this, sx, sy, n, out);
    else planeDepths<false>(*this, sx, sy, n, out);
  } else if (round && capsule) {
    if (perspective) capsuleDepths<true>(*this, sx, sy, n, out);
    else capsuleDepths<false>(*this, sx, sy, n, out);
  } else if (round) {
    if (perspective) wireDepths<true, true>(*this, sx, sy, n, out);
    else wireDepths<false, true>(*this, sx, sy, n, out);
  } else {
    if (perspective) wireDepths<true, false>(*this, sx, sy, n, out);
    else wireDepths<false, false>(*this, sx, sy, n, out);
  }
}

TileABuffer::TileABuffer(const MaskLayout& layout, int budget, float occlusionEpsilon, bool deepShares)
    : layout_(layout), budget_(std::clamp(budget, 1, kMaxListBudget)),
      epsilon_(std::isfinite(occlusionEpsilon) ? std::clamp(occlusionEpsilon, 0.0f, 0.5f) : 0.0f), deepShares_(deepShares) {
  // 4x4, 8x4 or 8x8 only: the subpixel records are visited four samples at a time.
  if (!layout_.valid()) throw std::invalid_argument("TileABuffer: mask layout " + layout_.name() + " (4x4, 8x4 or 8x8)");
  for (int k = 0; k < layout_.samples(); ++k) {
    sampleX_[k] = float(layout_.sampleX(k % layout_.w));
    sampleY_[k] = float(layout_.sampleY(k / layout_.w));
  }
}

void TileABuffer::reset(int w, int h, int x0, int y0, const FragmentSource* source) {
  w_ = w;
  h_ = h;
  x0_ = x0;
  y0_ = y0;
  source_ = source;
  pixels_.assign(size_t(w) * size_t(h), Pixel{});
  scratch_.deepPixels = 0;
  nodes_.clear();
  freeNodes_.clear();
  tails_.clear();
  occlusion_.assign(size_t(w) * size_t(h), INFINITY);
  offered_.assign(size_t(w) * size_t(h), 0);
  bw_ = (w + 3) / 4;
  blockOcclusion_.assign(size_t(bw_) * size_t((h + 3) / 4), INFINITY);
  subpixelDepth_.clear();
  subpixelDepth_.reserve(2 * size_t(w) * size_t(h) * size_t(layout_.samples()));  // no regrowth while filling
  solids_.clear();
  farCache_.clear();
  xray_.clear();
  if (!xrayCount_.empty()) xrayCount_.assign(size_t(w) * size_t(h), 0);
}

std::size_t TileABuffer::bytesFor(int w, int h, const MaskLayout& layout, int entriesPerPixel) {
  const std::size_t n = std::size_t(std::max(w, 0)) * std::size_t(std::max(h, 0));
  const std::size_t blocks = std::size_t((std::max(w, 0) + 3) / 4) * std::size_t((std::max(h, 0) + 3) / 4);
  // Per pixel: its record, occlusion and offered counts, the subpixel depths and transmittances,
  // the list entries (nodes, free-list slots, the resolve's gathered pointers), a solid fragment
  // (and a surface's kept behind a wire's solid),
  // a tail and a far cache; vectors grow by doubling, so up to twice the entries are reserved at a peak.
  const std::size_t entries = std::size_t(std::max(entriesPerPixel, 0));
  return n * (sizeof(Pixel) + 3 * sizeof(float) + 2 * std::size_t(layout.samples()) * sizeof(float) +
              2 * entries * (sizeof(Node) + sizeof(std::int32_t) + sizeof(void*)) + 2 * sizeof(Fragment) + sizeof(Tail) +
              2 * sizeof(FarCache)) +
         blocks * sizeof(float);
}

std::size_t TileABuffer::listEntryBytes() { return sizeof(Node); }

std::size_t TileABuffer::xrayBytesPerPixel() {
  return std::size_t(kXrayPerPixel) * (sizeof(XrayNode) + 2 * sizeof(void*)) + 2 * sizeof(std::uint32_t) + 1;
}

std::size_t TileABuffer::bytes() const {
  return pixels_.capacity() * sizeof(Pixel) + nodes_.capacity() * sizeof(Node) +
         freeNodes_.capacity() * sizeof(std::int32_t) + tails_.capacity() * sizeof(Tail) +
         (subpixelDepth_.capacity() + occlusion_.capacity() + blockOcclusion_.capacity() + offered_.capacity()) * sizeof(float) +
         solids_.capacity() * sizeof(Fragment) + farCache_.capacity() * sizeof(FarCache) + xray_.capacity() * sizeof(XrayNode) + xrayCount_.capacity();
}

bool TileABuffer::isSolid(const Fragment& f) const {
  return f.opacity >= 1.0f && f.area >= kSolidArea && f.mask == layout_.full() && f.standInBits == 0;
}

void TileABuffer::shadeNow(Fragment& f, std::size_t pixelIndex) const {
  if (f.shaded) return;
  if (f.holdout) f.colour = glm::vec3(0.0f);
  else if (source_)
    f.colour = source_->shade(f, x0_ + int(pixelIndex % size_t(w_)), y0_ + int(pixelIndex / size_t(w_)));
  f.shaded = true;
}

bool TileABuffer::maskHidden(int x, int y, MaskBits mask, int standInSubpixel, float z) const {
  const size_t pixelIndex = size_t(y) * size_t(w_) + size_t(x);
  const Pixel& p = pixels_[pixelIndex];
  if (p.hasSolid() && z >= solids_[size_t(p.solid)].zmax) return true;
  if (p.depths < 0 || p.noOcclusion) return false;
  if (mask == 0) mask = MaskBits(1) << std::clamp(standInSubpixel, 0, layout_.samples() - 1);
  const int n = layout_.samples();
  const float* D = &subpixelDepth_[size_t(p.depths) * size_t(2 * n)];
  const float* T = D + n;
#if defined(__SSE2__)
  const __m128 eps = _mm_set1_ps(epsilon_), zv = _mm_set1_ps(z);
  for (int v = 0; v < n / 4; ++v) {
    const unsigned bits = unsigned(mask >> (4 * v)) & 0xFu;
    if (!bits) continue;
    const __m128 ok = _mm_and_ps(_mm_cmple_ps(_mm_loadu_ps(T + 4 * v), eps), _mm_cmple_ps(_mm_loadu_ps(D + 4 * v), zv));
    if ((unsigned(_mm_movemask_ps(ok)) & bits) != bits) return false;
  }
#else
  for (MaskBits m = mask; m; m &= m - 1) {
    const int s = std::countr_zero(m);
    if (!(T[s] <= epsilon_ && D[s] <= z)) return false;
  }
#endif
  return true;
}

std::int32_t TileABuffer::allocNode(const Node& node) {
  // (Written once, where it lands: a default node first and then the real one cost a second
  // 80-byte store per fragment, into memory that is often not yet in cache.)
  if (!freeNodes_.empty()) {
    const std::int32_t i = freeNodes_.back();
    freeNodes_.pop_back();
    nodes_[size_t(i)] = node;
    return i;
  }
  nodes_.push_back(node);  // capacities never shrink: finish() reads the peak
  return std::int32_t(nodes_.size() - 1);
}

void TileABuffer::freeNode(std::int32_t i) {
  nodes_[size_t(i)].pixel = kFreeNode;
  freeNodes_.push_back(i);
}

void TileABuffer::toTail(Pixel& p, const Fragment& in, bool evicted) {
  Fragment f = in;
  shadeNow(f, size_t(&p - pixels_.data()));
  if (p.tail < 0) {
    p.tail = std::int32_t(tails_.size());
    tails_.push_back(Tail{});
  }
  Tail& t = tails_[size_t(p.tail)];
  const float w = f.opacity * f.area;
  if (f.holdout) {
    t.holdoutWeight += w;
  } else {
    t.premultiplied += f.colour * w;
    t.weight += w;
  }
  t.transmittance *= std::max(0.0f, 1.0f - w);
  t.zkeyMin = std::min(t.zkeyMin, f.zkey);
  ++local_.tail;
  // The tail blends what it holds over the whole pixel. A fragment that goes there on arrival is
  // counted for occlusion that way by the caller (occludeUniform); one evicted from the list was
  // counted by its mask, which no longer holds: from then on only the solid fragment (never
  // evicted) occludes this pixel.
  if (evicted) loseOcclusion(p, size_t(&p - pixels_.data()));
}

void TileABuffer::occludeUniform(Pixel& p, size_t pixelIndex, const Fragment& f) {
  // A fragment blended into the tail dims every subpixel alike, by its opacity times its area.
  const float dim = f.opacity * f.area;
  const int n = layout_.samples();
  if (!(dim > 0.0f) || p.noOcclusion) return;
  if (p.open == 0 && p.depths >= 0) return;  // settled: a uniform layer does not bring it nearer
  if (p.depths < 0) {
    p.open = std::uint8_t(n);
    p.depths = std::int32_t(subpixelDepth_.size() / size_t(2 * n));
    subpixelDepth_.resize(subpixelDepth_.size() + size_t(n), 0.0f);   // D
    subpixelDepth_.resize(subpixelDepth_.size() + size_t(n), 1.0f);   // T
  }
  float* D = &subpixelDepth_[size_t(p.depths) * size_t(2 * n)];
  float* T = D + n;
  bool changed = false;
  for (int s = 0; s < n; ++s) {
    if (T[s] <= epsilon_) continue;
    T[s] *= std::max(0.0f, 1.0f - dim);
    D[s] = std::max(D[s], f.zmax);
    if (T[s] <= epsilon_) --p.open, changed = true;
  }
  if (!changed || p.open > 0) return;
  float occ = 0.0f;
  for (int s = 0; s < n; ++s) occ = std::max(occ, D[s]);
  if (!(occ < occlusion_[pixelIndex])) return;
  occlusion_[pixelIndex] = occ;
  updateBlock(pixelIndex);
}

void TileABuffer::updateBlock(size_t pixelIndex) {
  const int px = int(pixelIndex % size_t(w_)), py = int(pixelIndex / size_t(w_));
  const int bx = px >> 2, by = py >> 2;
  float bmax = 0.0f;
  for (int y = by * 4; y < std::min(h_, by * 4 + 4); ++y)
    for (int x = bx * 4; x < std::min(w_, bx * 4 + 4); ++x) bmax = std::max(bmax, occlusion_[size_t(y) * size_t(w_) + size_t(x)]);
  blockOcclusion_[size_t(by) * size_t(bw_) + size_t(bx)] = bmax;
}

float TileABuffer::hideOf(const Fragment& f) const {
  const int k = maskCount(f.mask);
  return k ? std::max(f.hideFloor, f.opacity * std::min(1.0f, f.area * float(layout_.samples()) / float(k))) : 0.0f;
}

void TileABuffer::loseOcclusion(Pixel& p, size_t pixelIndex) {
  if (p.noOcclusion) return;
  p.noOcclusion = true;
  p.prunedAt = INFINITY;  // what enters from now on may lie behind the old pruning depth
  occlusion_[pixelIndex] = p.hasSolid() ? solids_[size_t(p.solid)].zmax : INFINITY;
  updateBlock(pixelIndex);
}

void TileABuffer::occlude(Pixel& p, size_t pixelIndex, const Fragment& f) {
  // With deep shares a stand-in subpixel hides nothing in a deep pixel (resolveEntries): it
  // settles nothing here either, so that what culling leaves out is hidden under both rules.
  occlude(p, pixelIndex, deepShares_ ? f.sampledMask() : f.mask, hideOf(f), f.zmax);
}

void TileABuffer::occlude(Pixel& p, size_t pixelIndex, MaskBits mask, float hide, float zmax) {
  // Each subpixel tracks the transmittance T the fragments so far leave over it (the resolve's
  // own factors 1 - alpha * min(1, A N / k)) and the depth D behind which they all lie. Once
  // T <= epsilon the subpixel is settled: whatever lies behind D adds at most epsilon of its
  // colour there. With epsilon = 0 only fragments that hide wholly settle a subpixel and the skip
  // is exact; a fragment that alone hides a subpixel settles it at its own depth.
  const int n = layout_.samples();
  if (!(hide > 0.0f) || mask == 0 || p.noOcclusion) return;
  // A settled pixel changes only when a wholly hiding fragment comes nearer than its depth.
  if (p.open == 0 && p.depths >= 0 && (hide < 1.0f || !(zmax < occlusion_[pixelIndex]))) return;
  if (p.depths < 0) {
    p.open = std::uint8_t(n);
    p.depths = std::int32_t(subpixelDepth_.size() / size_t(2 * n));
    subpixelDepth_.resize(subpixelDepth_.size() + size_t(n), 0.0f);   // D
    subpixelDepth_.resize(subpixelDepth_.size() + size_t(n), 1.0f);   // T
  }
  float* D = &subpixelDepth_[size_t(p.depths) * size_t(2 * n)];
  float* T = D + n;
  bool changed = false;
#if defined(__SSE2__)
  // Four subpixels at a time (NibbleLanes): the loop below, lane by lane.
  const __m128 eps = _mm_set1_ps(epsilon_), z = _mm_set1_ps(zmax);
  MaskBits newlySettled = 0;  // the subpixels this fragment settles
  if (hide >= 1.0f) {
    for (int v = 0; v < n / 4; ++v) {
      const unsigned bits = unsigned(mask >> (4 * v)) & 0xFu;
      if (!bits) continue;
      const __m128 m = nibbleLanes(bits);
      const __m128 Tv = _mm_loadu_ps(T + 4 * v), Dv = _mm_loadu_ps(D + 4 * v);
      const __m128 settled = _mm_cmple_ps(Tv, eps);
      const __m128 fresh = _mm_andnot_ps(settled, m);                                   // settled now, at zmax
      const __m128 nearer = _mm_and_ps(_mm_and_ps(settled, m), _mm_cmplt_ps(z, Dv));   // settled, brought nearer
      const __m128 moved = _mm_or_ps(fresh, nearer);
      newlySettled |= MaskBits(unsigned(_mm_movemask_ps(fresh))) << (4 * v);
      if (_mm_movemask_ps(moved)) {
        changed = true;
        _mm_storeu_ps(D + 4 * v, blendLanes(moved, z, Dv));
      }
      _mm_storeu_ps(T + 4 * v, _mm_andnot_ps(m, Tv));
    }
  } else {
    const __m128 keep = _mm_set1_ps(1.0f - hide);
    for (int v = 0; v < n / 4; ++v) {
      const unsigned bits = unsigned(mask >> (4 * v)) & 0xFu;
      if (!bits) continue;
      const __m128 Tv = _mm_loadu_ps(T + 4 * v), Dv = _mm_loadu_ps(D + 4 * v);
      const __m128 open = _mm_andnot_ps(_mm_cmple_ps(Tv, eps), nibbleLanes(bits));
      if (!_mm_movemask_ps(open)) continue;
      const __m128 Tn = blendLanes(open, _mm_mul_ps(Tv, keep), Tv);
      _mm_storeu_ps(T + 4 * v, Tn);
      _mm_storeu_ps(D + 4 * v, blendLanes(open, _mm_max_ps(z, Dv), Dv));  // max(D, zmax), D where unordered, as std::max
      const int now = _mm_movemask_ps(_mm_and_ps(open, _mm_cmple_ps(Tn, eps)));
      if (now) newlySettled |= MaskBits(unsigned(now)) << (4 * v), changed = true;
    }
  }
  p.open = std::uint8_t(p.open - maskCount(newlySettled));
#else
  for (MaskBits m = mask; m; m &= m - 1) {
    const int s = std::countr_zero(m);
    const bool settled = T[s] <= epsilon_;
    if (hide >= 1.0f) {
      if (!settled) {
        --p.open;
        D[s] = zmax;
        changed = true;
      } else if (zmax < D[s]) {
        D[s] = zmax;
        changed = true;
      }
      T[s] = 0.0f;
    } else if (!settled) {
      T[s] *= 1.0f - hide;
      D[s] = std::max(D[s], zmax);
      if (T[s] <= epsilon_) --p.open, changed = true;
    }
  }
#endif
  if (!changed) return;
  if (p.open > 0) return;  // some subpixel is still uncovered: the pixel is not occluded yet
  float occ = 0.0f;
  for (int s = 0; s < n; ++s) occ = std::max(occ, D[s]);
  if (!(occ < occlusion_[pixelIndex])) return;
  occlusion_[pixelIndex] = occ;
  updateBlock(pixelIndex);
}

void TileABuffer::pruneHidden(Pixel& p, float depth) {
  // Drops the list entries that lie wholly behind `depth`. Strictly behind: an entry at exactly
  // that depth (a flat fragment, often the occluder itself) arrived earlier and sorts first.
  if (!(depth < p.prunedAt)) return;
  p.prunedAt = depth;
  if (!(p.zminBound > depth)) return;  // nothing lies wholly behind it
  float bound = -INFINITY;
  // (wires resting on a surface are kept within the depth span of the pixel's solid and of
  // themselves: see insert)
  const float slack = p.hasSolid() ? solids_[size_t(p.solid)].zmax - solids_[size_t(p.solid)].zmin : 0.0f;
  std::int32_t* link = &p.head;
  while (*link >= 0) {
    Node& n = nodes_[size_t(*link)];
    if (n.f.zmin > depth && !(n.f.onSurface && n.f.zmin < depth + 2.0f * (n.f.zmax - n.f.zmin) + slack)) {
      const std::int32_t dead = *link;
      *link = n.next;
      freeNode(dead);
      --p.length;
      forgetFar(p);
      ++local_.culled;
    } else {
      bound = std::max(bound, n.f.zmin);
      link = &n.next;
    }
  }
  p.zminBound = bound;
}

std::int32_t TileABuffer::scanFar(Pixel& p) {
  // The farthest by the plain scan's rule (of equal keys the last met, the earliest entry) and,
  // on the way, the kFarCache largest keys (equal ones in any order: cut off below) and the
  // largest of the others.
  std::int32_t far = -1;
  std::int32_t node[kFarCache];
  float key[kFarCache];
  int m = 0;
  float rest = -INFINITY;
  bool ordered = true;  // no NaN key
  for (std::int32_t i = p.head; i >= 0; i = nodes_[size_t(i)].next) {
    const float z = nodes_[size_t(i)].f.zkey;
    if (far < 0 || z >= nodes_[size_t(far)].f.zkey) far = i;
    ordered = ordered && z == z;
    if (m == kFarCache && !(z > key[kFarCache - 1])) {
      rest = std::max(rest, z);
      continue;
    }
    if (m == kFarCache) rest = std::max(rest, key[--m]);
    int j = m++;
    for (; j > 0 && key[j - 1] < z; --j) key[j] = key[j - 1], node[j] = node[j - 1];
    key[j] = z;
    node[j] = i;
  }
  // Cached: the longest run from the farthest with keys strictly decreasing and above all else.
  int keep = 0;
  if (ordered)
    while (keep < m && key[keep] > (keep + 1 < m ? key[keep + 1] : rest)) ++keep;
  if (p.farCache < 0 && keep > 0) {
    p.farCache = std::int32_t(farCache_.size());
    farCache_.push_back(FarCache{});
  }
  if (p.farCache >= 0) {
    FarCache& c = farCache_[size_t(p.farCache)];
    c.count = keep;
    c.rest = keep < m ? key[keep] : rest;
    std::copy(node, node + keep, c.node);
    std::copy(key, key + keep, c.key);
  }
  return far;
}

std::int32_t TileABuffer::nextFar(Pixel& p, std::int32_t slot) {
  if (p.farCache < 0) return -1;
  FarCache& c = farCache_[size_t(p.farCache)];
  if (c.count == 0 || c.node[0] != slot) return c.count = 0, -1;
  // The slot's key is nearer than it was: it leaves the head of the cache, and enters it again
  // where it lies above everything outside it.
  std::copy(c.node + 1, c.node + c.count, c.node);
  std::copy(c.key + 1, c.key + c.count, c.key);
  if (--c.count == 0) return -1;
  const float z = nodes_[size_t(slot)].f.zkey;
  if (!(z <= c.rest)) {
    if (z != z) return c.count = 0, -1;
    int j = c.count;
    for (; j > 0 && c.key[j - 1] < z; --j) c.key[j] = c.key[j - 1], c.node[j] = c.node[j - 1];
    if (j > 0 && c.key[j - 1] == z) return c.count = 0, -1;  // a tie: the list's order decides it
    c.key[j] = z;
    c.node[j] = slot;
    ++c.count;
  }
  return c.node[0];
}

TileABuffer::Placement TileABuffer::pushList(Pixel& p, const Fragment& f) {
  const float occ = occlusion_[size_t(&p - pixels_.data())];
  if (p.length >= budget_ && occ < INFINITY) pruneHidden(p, occ);
  if (p.length >= budget_) {
    // Keep the nearest `budget` exactly: the farthest of list + f goes to the tail.
    if (p.far < 0) p.far = scanFar(p);
    const std::int32_t far = p.far;
    if (f.zkey >= nodes_[size_t(far)].f.zkey) {
      toTail(p, f, false);
      return Placement::Tailed;
    }
    toTail(p, nodes_[size_t(far)].f, true);
    nodes_[size_t(far)].f = f;
    nodes_[size_t(far)].seq = p.seq++;
    p.zminBound = std::max(p.zminBound, f.zmin);
    p.far = nextFar(p, far);  // -1: found again by a scan when needed
    return Placement::Evicted;
  }
  const size_t pixelIndex = size_t(&p - pixels_.data());
  const std::int32_t n = allocNode(Node{f, p.seq++, p.head, std::uint32_t(pixelIndex)});
  // (Of equal keys the scan keeps the earliest entry: a new one replaces it only when farther.)
  if (p.length == 0) p.far = n;
  else if (p.far >= 0 && f.zkey > nodes_[size_t(p.far)].f.zkey) p.far = n;
  emptyFarCache(p);  // (rebuilt by the next scan)
  p.head = n;
  p.zminBound = std::max(p.zminBound, f.zmin);
  ++p.length;
  local_.maxListLength = std::max<std::uint32_t>(local_.maxListLength, p.length);
  return Placement::Listed;
}

void TileABuffer::setSolid(Pixel& p, const Fragment& f) {
  if (p.hasSolid()) {
    Fragment& cur = solids_[size_t(p.solid)];
    if (!(f.zkey < cur.zkey)) {
      if (f.zmin < cur.zmax) pushList(p, f);
      else ++local_.culled;
      return;
    }
    const Fragment old = cur;
    if (f.occludesEarly && p.solid == p.surface) {
      // A wire's solid in front of the surface's: the surface keeps its own entry (deep shares
      // show it in the gaps, resolveEntries).
      p.solid = std::int32_t(solids_.size());
      solids_.push_back(f);
    } else {
      solids_[size_t(p.solid)] = f;
    }
    p.solidSeq = p.seq++;
    if (old.zmin < f.zmax) pushList(p, old);  // interpenetrates the new solid: keep it
    else ++local_.culled;
  } else {
    p.solid = std::int32_t(solids_.size());
    solids_.push_back(f);
    p.solidSeq = p.seq++;
  }
  // The nearest surface's solid (deep shares' gate and gaps, resolveEntries). Only a nearer
  // solid surface ever replaces or culls it (the renderer draws surfaces before wires), whatever
  // occlusionEpsilon; a wire's in front of it does not.
  if (!f.occludesEarly) p.surface = p.solid;
  pruneHidden(p, solids_[size_t(p.solid)].zmax);  // entries wholly behind the new solid fragment
  // Everything behind the solid is hidden, at every subpixel. (A surface's solid does not enter
  // the subpixels' records (occlude): it arrives before the wires in front of it, and they must
  // still settle the pixel nearer than it, by their own hides.)
  const size_t pixelIndex = size_t(&p - pixels_.data());
  if (solids_[size_t(p.solid)].zmax < occlusion_[pixelIndex]) {
    occlusion_[pixelIndex] = solids_[size_t(p.solid)].zmax;
    updateBlock(pixelIndex);
  }
}

void TileABuffer::insert(int x, int y, Fragment f, int centroidSubpixel) {
  Pixel& p = pixels_[size_t(y) * size_t(w_) + size_t(x)];
  ++offered_[size_t(y) * size_t(w_) + size_t(x)];
  ++local_.fragments;
  if (!(f.area > 0.0f)) return;
  f.area = std::min(f.area, 1.0f);
  f.opacity = std::clamp(f.opacity, 0.0f, 1.0f);
  // A piece of a wire resting on a surface is judged at its axis and kept though behind what
  // hides this pixel, but only in the list (a tail, uniform over the pixel, would show it) and
  // only within the depth the pixel's solid spans and its own (farther, its axis is hidden too).
  const float occ = std::min(occlusion_[size_t(y) * size_t(w_) + size_t(x)], p.hasSolid() ? solids_[size_t(p.solid)].zmax : INFINITY);
  const bool behind = f.zmin >= occ;
  const float slack = (f.zmax - f.zmin) + (p.hasSolid() ? solids_[size_t(p.solid)].zmax - solids_[size_t(p.solid)].zmin : 0.0f);
  if (behind && (!f.onSurface || p.length >= budget_ || !(f.zmin < occ + slack))) {
    ++local_.culled;
    return;
  }
  const size_t pixelIndex = size_t(y) * size_t(w_) + size_t(x);
  if (f.mask == 0) {
    f.mask = MaskBits(1) << std::clamp(centroidSubpixel, 0, layout_.samples() - 1);
    f.standInBits = f.mask;
  }
  // Merge with a recent piece of the same object.
  std::int32_t* link = &p.head;
  for (int look = 0; f.mayMerge && *link >= 0 && look < kMergeLookBack; ++look) {
    Node& n = nodes_[size_t(*link)];
    // Pieces of one surface never share a sampled subpixel (shared edges split samples); two
    // layers of one object (a silhouette fold) do, and stay apart.
    if (n.f.tag == f.tag && (n.f.sampledMask() & f.sampledMask()) == 0 &&
        depthRangesTouch(n.f, f)) {
      shadeNow(n.f, pixelIndex);
      shadeNow(f, pixelIndex);
      const float hideBefore = hideOf(n.f);
      const MaskBits newlySampled = f.sampledMask();  // disjoint from n's sampled bits
      mergeInto(n.f, f);
      forgetFar(p);  // its depth may have moved
      ++local_.merged;
      // Occlusion counted the piece already here at its hide; the merged fragment never hides
      // less (Fragment::hideFloor), and the new piece's sampled subpixels count at its hide.
      if (n.f.occludesEarly) {
        n.f.hideFloor = std::max(n.f.hideFloor, hideBefore);
        occlude(p, pixelIndex, newlySampled, hideOf(n.f), n.f.zmax);
      }
      if (isSolid(n.f)) {
        const Fragment whole = n.f;
        const std::int32_t dead = *link;
        *link = n.next;
        freeNode(dead);
        --p.length;
        if (whole.occludesEarly) occlude(p, pixelIndex, whole);  // (a surface's: setSolid)
        setSolid(p, whole);
      }
      return;
    }
    link = &n.next;
  }
  const bool solid = isSolid(f);
  if (solid) {
    if (f.occludesEarly) occlude(p, pixelIndex, f);  // (a surface's: setSolid)
    setSolid(p, f);
    return;
  }
  // Occlusion counts what the resolve will do with this very fragment: a piece alone (or a wire's
  // piece, which is counted again if it merges, see above; its stand-in subpixels, which a merge
  // may drop, not at all), or in the tail as a uniform layer.
  const Placement where = pushList(p, f);
  if (where == Placement::Tailed) {
    if (!f.mayMerge || f.occludesEarly) occludeUniform(p, pixelIndex, f);
  } else if (!f.mayMerge) {
    occlude(p, pixelIndex, f);
  } else if (f.occludesEarly) {
    occlude(p, pixelIndex, f.sampledMask(), hideOf(f), f.zmax);
  }
}

void TileABuffer::insertXray(int x, int y, Fragment f, float factor, int centroidSubpixel) {
  if (!(f.area > 0.0f) || !(factor > 0.0f)) return;
  f.area = std::min(f.area, 1.0f);
  f.opacity = std::clamp(f.opacity, 0.0f, 1.0f);
  if (f.mask == 0) {
    f.mask = MaskBits(1) << std::clamp(centroidSubpixel, 0, layout_.samples() - 1);
    f.standInBits = f.mask;
  }
  const std::uint32_t pixel = std::uint32_t(size_t(y) * size_t(w_) + size_t(x));
  if (xrayCount_.size() != pixels_.size()) xrayCount_.assign(pixels_.size(), 0);
  if (xrayCount_[pixel] >= kXrayPerPixel) {
    ++local_.xrayDropped;
    return;
  }
  ++xrayCount_[pixel];
  xray_.push_back(XrayNode{f, std::min(factor, 1.0f), std::uint32_t(xray_.size()), pixel});
  ++local_.xray;
}

void TileABuffer::gatherXray() const {
  if (xray_.empty()) return;
  const size_t n = pixels_.size();
  std::vector<std::uint32_t>& start = scratch_.xrayStart;
  start.assign(n + 1, 0);
  for (const XrayNode& x : xray_) ++start[x.pixel + 1];
  for (size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  std::vector<const XrayNode*>& g = scratch_.xrayGathered;
  g.resize(xray_.size());
  std::vector<std::uint32_t>& at = scratch_.xrayAt;
  at.assign(start.begin(), start.end() - 1);
  for (const XrayNode& x : xray_) g[at[x.pixel]++] = &x;
}

glm::vec4 TileABuffer::resolve(int x, int y) const {
  const size_t pixelIndex = size_t(y) * size_t(w_) + size_t(x);
  std::vector<const Node*>& list = scratch_.gathered;
  list.clear();
  for (std::int32_t i = pixels_[pixelIndex].head; i >= 0; i = nodes_[size_t(i)].next) list.push_back(&nodes_[size_t(i)]);
  std::vector<const XrayNode*>& xr = scratch_.xrayGathered;
  xr.clear();
  for (const XrayNode& n : xray_)
    if (n.pixel == pixelIndex) xr.push_back(&n);
  return resolveEntries(pixelIndex, list.data(), int(list.size()), xr.data(), int(xr.size()));
}

void TileABuffer::gatherLists() const {
  // One pass over the nodes in memory order, counting sort by pixel: the resolve then reads
  // each pixel's fragments from independent addresses instead of down a chain of dependent ones.
  const size_t n = pixels_.size();
  std::vector<std::uint32_t>& start = scratch_.gatherStart;
  start.assign(n + 1, 0);
  for (const Node& node : nodes_)
    if (node.pixel != kFreeNode) ++start[node.pixel + 1];
  for (size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  std::vector<const Node*>& g = scratch_.gathered;
  g.resize(start[n]);
  for (const Node& node : nodes_)
    if (node.pixel != kFreeNode) g[start[node.pixel]++] = &node;
  for (size_t i = n; i > 0; --i) start[i] = start[i - 1];  // back to the beginnings
  start[0] = 0;
}

glm::vec4 TileABuffer::resolveEntries(size_t pixelIndex, const Node* const* entries, int count,
                                      const XrayNode* const* xray, int xrayCount) const {
  const Pixel& p = pixels_[pixelIndex];
  const int px = x0_ + int(pixelIndex % size_t(w_)), py = y0_ + int(pixelIndex / size_t(w_));
  auto colourOf = [&](const Fragment& f) {
    return f.shaded || !source_ ? f.colour : source_->shade(f, px, py);
  };
  // (x-ray fragments show only through an opaque surface: without one here, nothing to do)
  if (p.length == 0 && !p.hasTail() && (xrayCount == 0 || !p.hasSolid())) {
    if (p.hasSolid()) {
      const Fragment& f = solids_[size_t(p.solid)];
      return f.holdout ? glm::vec4(0.0f) : glm::vec4(colourOf(f), 1.0f);
    }
    return glm::vec4(0.0f);
  }
  // Gather, sort front to back (depth, then arrival: deterministic).
  std::vector<const Node*>& order = scratch_.order;
  Node& solidNode = scratch_.solidNode;
  Node& tailNode = scratch_.tailNode;
  order.assign(entries, entries + count);
  if (p.hasSolid()) {
    solidNode = Node{solids_[size_t(p.solid)], p.solidSeq, -1, 0};  // its arrival: ties sort by it
    order.push_back(&solidNode);
  }
  if (p.hasTail()) {
    // The tail composites as one whole-pixel layer, at the depth of its nearest member: behind
    // the kept fragments (they are the nearest), in front of a solid fragment it is not behind.
    const Tail& t = tails_[size_t(p.tail)];
    Fragment f;
    f.zkey = f.zmin = f.zmax = t.zkeyMin;
    f.area = 1.0f;
    // Its hold-outs' share of what it hides adds neither colour nor coverage (the background
    // shows there), though it hides what lies behind as the rest does.
    const float all = t.weight + t.holdoutWeight;
    f.opacity = (1.0f - t.transmittance) * (all > 0 ? t.weight / all : 0.0f);
    f.colour = t.weight > 0 ? t.premultiplied / t.weight : glm::vec3(0.0f);
    f.mask = layout_.full();
    tailNode = Node{f, 0xFFFFFFFEu, -1, 0};
    order.push_back(&tailNode);
  }
  // Front to back by zkey, ties by arrival (lists are short: insertion sort).
  for (size_t i = 1; i < order.size(); ++i) {
    const Node* v = order[i];
    size_t j = i;
    for (; j > 0 && (v->f.zkey < order[j - 1]->f.zkey || (v->f.zkey == order[j - 1]->f.zkey && v->seq < order[j - 1]->seq)); --j)
      order[j] = order[j - 1];
    order[j] = v;
  }
  const int N = layout_.samples();
  const int n = int(order.size());
  // A deep pixel (deepShares_): a surface's solid fragment covers it (Pixel::surface, perhaps
  // behind a nearer wire's solid): no gap between the samples can show the background. There
  // every sampled fragment hides its samples wholly, and what is hidden anywhere is
  // weighed by the samples it owns (below), not by its exact area times the share of its own
  // samples it owns: with many layers those shares are each noisy and their sum strays from the
  // pixel's full cover, which owned samples partition. None of this depends on what occlusion
  // culling leaves out (fragments hidden at all their samples; a surface's solid only by a
  // nearer one, since the renderer draws surfaces first), so culling keeps its bound
  // (docs/abuffer.md, "Deep shares").
  const bool deep = deepShares_ && p.surface >= 0;
  scratch_.deepPixels += deep;
  // Per fragment: its mask, how many subpixels, how much it hides each (1: wholly), and, for
  // those that hide wholly, the subpixels it owns (where it is the nearest of them).
  std::vector<MaskBits>& owned = scratch_.owned;
  std::vector<float>& hides = scratch_.hides;
  std::vector<float>& depths = scratch_.depths;
  std::vector<std::int8_t>& depthState = scratch_.depthState;  // 0: not evaluated, 1: per subpixel, 2: flat (zkey)
  owned.assign(size_t(n), 0);
  hides.resize(size_t(n));
  depthState.assign(size_t(n), 0);
  depths.resize(size_t(n) * size_t(N));
  bool anyPartial = false;
  std::vector<int>& whole = scratch_.whole;  // the fragments that hide wholly, front to back
  whole.clear();
  // Whether a fragment of that hide hides its subpixels wholly. Deep: an opaque fragment that
  // some sample saw does (its sampled subpixels); a translucent one, or one that no sample saw
  // (at its stand-in subpixel), is partial whatever its hide, and weighs as by the usual rule
  // (a hair's sliver between the samples, a thin translucent line: their areas, not samples).
  auto wholly = [&](const Fragment& f, float hide) { return deep ? f.opacity >= 1.0f && f.sampledMask() != 0 : hide >= 1.0f; };
  for (int i = 0; i < n; ++i) {
    const Fragment& f = order[size_t(i)]->f;
    const int k = maskCount(f.mask);
    hides[size_t(i)] = k ? std::max(f.hideFloor, f.opacity * std::min(1.0f, f.area * float(N) / float(k))) : 0.0f;
    if (wholly(f, hides[size_t(i)])) {
      owned[size_t(i)] = deep ? f.sampledMask() : f.mask;
      hides[size_t(i)] = 1.0f;
      whole.push_back(i);
    } else if (k) {
      anyPartial = true;
    }
  }
  // The depth of fragment i's surface at its subpixels, evaluated once, when two surfaces whose
  // depth ranges overlap share a subpixel (they interpenetrate in this pixel).
  // Its models are kept (two for a wire's merged pieces) for edges judged at their axis.
  std::vector<SurfaceDepth>& models = scratch_.models;
  if (models.size() < 2 * size_t(n)) models.resize(2 * size_t(n));  // (written before read: depthState)
  auto depthsOf = [&](int i) -> const float* {
    float* d = &depths[size_t(i) * size_t(N)];
    if (depthState[size_t(i)] == 0) {
      const Fragment& f = order[size_t(i)]->f;
      SurfaceDepth& model = models[2 * size_t(i)];
      if (source_ && f.prim != Fragment::kNoPrimitive && source_->surfaceDepth(f.prim, px, py, model)) {
        model.holdSolidTo(f.zmin, f.zmax);
        model.atSamples(sampleX_, sampleY_, N, d);
        SurfaceDepth& second = models[2 * size_t(i) + 1];
        second.kind = SurfaceDepth::Kind::Plane;  // none unless a wire's merged piece
        if (f.prim2 != Fragment::kNoPrimitive && source_->surfaceDepth(f.prim2, px, py, second)) {
          second.holdSolidTo(f.zmin, f.zmax);
          float d2[64];
          second.atSamples(sampleX_, sampleY_, N, d2);
          for (int s = 0; s < N; ++s) d[s] = std::min(d[s], d2[s]);
        }
        depthState[size_t(i)] = 1;
      } else {
        std::fill(d, d + N, f.zkey);
        depthState[size_t(i)] = 2;
      }
    }
    return d;
  };
  // The subpixels of `common` where fragment i lies in front of fragment j (i earlier in the
  // order, which decides ties). An edge resting on a surface against a plane: at its axis
  // (edgeFront).
  // The subpixels of `common` where an edge (w[0], and w[1] too when it is a merged piece's wire)
  // lies in front of plane p: each judged at the axis point nearest it, where the edge's front
  // faces the plane's depth (SurfaceDepth::onSurface).
  auto edgeFront = [&](const SurfaceDepth* w, const SurfaceDepth& p, MaskBits common) -> MaskBits {
    MaskBits front = 0;
    const int pieces = w[1].kind == SurfaceDepth::Kind::Wire ? 2 : 1;
    for (MaskBits m = common; m; m &= m - 1) {
      const int s = std::countr_zero(m);
      for (int k = 0; k < pieces; ++k) {
        float ax, ay;
        w[k].axisPoint(sampleX_[s], sampleY_[s], ax, ay);
        if (w[k].at(ax, ay) <= p.planeDepthAt(ax, ay)) {
          front |= MaskBits(1) << s;
          break;
        }
      }
    }
    return front;
  };
  auto isEdge = [&](int i) {
    return depthState[size_t(i)] == 1 && models[2 * size_t(i)].kind == SurfaceDepth::Kind::Wire && models[2 * size_t(i)].onSurface;
  };
  auto isPlane = [&](int i) { return depthState[size_t(i)] == 1 && models[2 * size_t(i)].kind == SurfaceDepth::Kind::Plane; };
  // Whether fragment w (a wire's piece resting on a surface) is judged against fragment p (a
  // surface's) at its axis: not when the wire lies wholly in front here (the axis rule agrees).
  // Depth ranges alone do not decide it: where the wire's axis lies outside this pixel, a plane
  // wholly in front over the pixel can be behind the line at its axis.
  auto axisJudged = [&](int w, int p) {
    const Fragment &fw = order[size_t(w)]->f, &fp = order[size_t(p)]->f;
    if (!fw.occludesEarly || fp.occludesEarly || !source_ || fw.zmax <= fp.zmin || !source_->onSurface(fw.prim)) return false;
    depthsOf(w);
    depthsOf(p);
    return isEdge(w) && isPlane(p);
  };
  // The subpixels of `common` where i's depth there is not behind j's (ties: the earlier, i).
  auto depthFront = [&](int i, int j, MaskBits common) -> MaskBits {
    const float *da = depthsOf(i), *db = depthsOf(j);
    MaskBits front = 0;
#if defined(__SSE2__)
    for (int v = 0; v < N / 4; ++v)  // four subpixels at a time (the same comparisons)
      if ((common >> (4 * v)) & 0xFu)
        front |= MaskBits(unsigned(_mm_movemask_ps(_mm_cmple_ps(_mm_loadu_ps(da + 4 * v), _mm_loadu_ps(db + 4 * v))))) << (4 * v);
    front &= common;
#else
    for (MaskBits m = common; m; m &= m - 1) {
      const int s = std::countr_zero(m);
      if (da[s] <= db[s]) front |= MaskBits(1) << s;
    }
#endif
    return front;
  };
  // An edge in front of a plane where its round surface is, subpixel by subpixel, or where its
  // axis is (edgeFront, asked only of the subpixels the first leaves to the plane: most edge
  // pixels need no axis at all).
  auto edgeWins = [&](int w, int p, MaskBits common, bool wFirst) -> MaskBits {
    const MaskBits own = wFirst ? depthFront(w, p, common) : common & ~depthFront(p, w, common);
    const MaskBits rest = common & ~own;
    return rest ? own | edgeFront(&models[2 * size_t(w)], models[2 * size_t(p)], rest) : own;
  };
  auto frontOf = [&](int i, int j, MaskBits common) -> MaskBits {
    const Fragment &a = order[size_t(i)]->f, &b = order[size_t(j)]->f;
    if (axisJudged(i, j)) return edgeWins(i, j, common, true);
    if (axisJudged(j, i)) return common & ~edgeWins(j, i, common, false);
    if (a.zmax <= b.zmin) return common;  // apart (touching: the order decides)
    if (a.zmin >= b.zmax) return 0;
    return depthFront(i, j, common);
  };
  // Ownership among the fragments that hide wholly: each pair sharing subpixels splits them.
  // (Only those have owned bits: the loops below visit them alone, in the same order.)
  const int nw = int(whole.size());
  for (int a = 0; a < nw; ++a) {
    const int i = whole[size_t(a)];
    for (int b = a + 1; b < nw; ++b) {
      const int j = whole[size_t(b)];
      const MaskBits common = owned[size_t(i)] & owned[size_t(j)];
      if (!common) continue;
      const MaskBits front = frontOf(i, j, common);
      owned[size_t(j)] &= ~front;
      owned[size_t(i)] &= ~(common & ~front);
    }
  }
  MaskBits ownedAny = 0;
  for (int i : whole) ownedAny |= owned[size_t(i)];
  // The axis rule is not transitive with the per-subpixel one (an edge judged at its axis, two
  // planes crossing within its width): a subpixel can lose to everyone. It goes back to the
  // nearest there.
  MaskBits covered = 0;
  for (int i : whole) covered |= order[size_t(i)]->f.mask;
  for (MaskBits lost = covered & ~ownedAny; lost; lost &= lost - 1) {
    const int s = std::countr_zero(lost);
    int best = -1;
    float bestDepth = INFINITY;
    for (int i : whole)
      if ((order[size_t(i)]->f.mask >> s) & 1) {
        const float d = depthsOf(i)[s];
        if (best < 0 || d < bestDepth) best = i, bestDepth = d;
      }
    owned[size_t(best)] |= MaskBits(1) << s;
    ownedAny |= MaskBits(1) << s;
  }
  alignas(32) float T[64];
  std::fill(T, T + N, 1.0f);
  glm::vec3 rgb(0.0f);
  float alpha = 0.0f;
  // What only dims its subpixels, front to back, where it lies in front of their owner.
  // (partialSeen: some of it lies in front of the owner at some sample. In a deep pixel only
  // that changes the owners' weights below: a translucent fragment hidden at all its samples,
  // which culling at epsilon may leave out, does not.)
  bool partialSeen = false;
  if (anyPartial) {
    // Front to back by zkey, but for an edge resting on a surface (SurfaceDepth::onSurface): it
    // moves in front of the partial planes before it that it lies in front of, judged at its
    // axis, at every subpixel they share (its own face seen at a grazing angle, whose part in
    // the pixel has the nearer centroid, would otherwise dim it by nearly its whole hide).
    std::vector<int>& po = scratch_.partialOrder;
    po.clear();
    for (int i = 0; i < n; ++i)
      if (order[size_t(i)]->f.mask != 0 && !wholly(order[size_t(i)]->f, hides[size_t(i)])) po.push_back(i);
    for (size_t a = 1; a < po.size(); ++a) {
      const int e = po[a];
      const Fragment& fe = order[size_t(e)]->f;
      if (!fe.occludesEarly || !source_ || !source_->onSurface(fe.prim)) continue;
      size_t b = a;
      for (; b > 0; --b) {
        const int q = po[b - 1];
        const Fragment& fq = order[size_t(q)]->f;
        const MaskBits common = fq.mask & fe.mask;
        if (common && (!axisJudged(e, q) || edgeWins(e, q, common, false) != common)) break;
        po[b] = q;
      }
      po[b] = e;
    }
    for (int i : po) {
      const Fragment& f = order[size_t(i)]->f;
      const float hide = hides[size_t(i)];
      MaskBits seen = f.mask;
      for (int b = 0; b < nw && (seen & ownedAny); ++b) {
        const int j = whole[size_t(b)];
        const MaskBits common = seen & owned[size_t(j)];
        if (!common) continue;
        const MaskBits front = j > i ? frontOf(i, j, common) : common & ~frontOf(j, i, common);
        seen &= ~(common & ~front);
      }
      partialSeen |= seen != 0;
      float sumT = 0;
      for (MaskBits m = seen; m; m &= m - 1) {
        const int s = std::countr_zero(m);
        sumT += T[s];
        T[s] *= 1.0f - hide;
      }
      if (!(sumT > 0.0f) || f.holdout) continue;
      const float w = f.opacity * f.area * (sumT / float(maskCount(f.mask)));
      rgb += colourOf(f) * w;
      alpha += w;
    }
  }
  // Hidden lines: each x-ray fragment (front to back), on the subpixels whose owner is an opaque
  // surface in front of the wire there, just in front of that surface.
  bool anyXray = false;
  if (xrayCount > 0 && nw > 0) {
    std::vector<const XrayNode*>& xo = scratch_.xrayOrder;
    xo.assign(xray, xray + xrayCount);
    for (size_t a = 1; a < xo.size(); ++a) {
      const XrayNode* v = xo[a];
      size_t b = a;
      for (; b > 0 && (v->f.zkey < xo[b - 1]->f.zkey || (v->f.zkey == xo[b - 1]->f.zkey && v->seq < xo[b - 1]->seq)); --b)
        xo[b] = xo[b - 1];
      xo[b] = v;
    }
    std::vector<float>& xd = scratch_.xrayDepths;
    xd.resize(size_t(N));
    for (const XrayNode* x : xo) {
      const Fragment& f = x->f;
      // Its subpixels owned by a surface in front of it, judged as its visible copy is
      // (frontOf: at its axis against planes when it rests on a surface; ties to the nearer zkey).
      MaskBits behind = 0;
      bool depthsDone = false, edge = false;
      const bool onSurface = source_ && f.prim != Fragment::kNoPrimitive && source_->onSurface(f.prim);
      SurfaceDepth xm[2];  // its model (an x-ray copy is one piece: xm[1] stays no wire)
      auto ownDepths = [&] {
        if (depthsDone) return;
        if (source_ && f.prim != Fragment::kNoPrimitive && source_->surfaceDepth(f.prim, px, py, xm[0])) {
          xm[0].holdSolidTo(f.zmin, f.zmax);
          xm[0].atSamples(sampleX_, sampleY_, N, xd.data());
          edge = xm[0].kind == SurfaceDepth::Kind::Wire && xm[0].onSurface;
        } else {
          std::fill(xd.begin(), xd.end(), f.zkey);
        }
        depthsDone = true;
      };
      for (int b = 0; b < nw; ++b) {
        const int j = whole[size_t(b)];
        const Fragment& o = order[size_t(j)]->f;
        const MaskBits common = f.mask & owned[size_t(j)] & ~behind;
        // Only surfaces hide lines: not a wire's piece, nor the tail (what it holds is unknown)
        if (!common || o.occludesEarly || o.prim == Fragment::kNoPrimitive) continue;
        if (onSurface && f.zmax > o.zmin) {
          ownDepths();
          depthsOf(j);
          if (edge && isPlane(j)) {  // as edgeWins: its round surface, else its axis
            const float* od = depthsOf(j);
            MaskBits rest = 0;
            for (MaskBits m = common; m; m &= m - 1) {
              const int s = std::countr_zero(m);
              if (od[s] < xd[size_t(s)] || (od[s] == xd[size_t(s)] && o.zkey <= f.zkey)) rest |= MaskBits(1) << s;
            }
            if (rest) behind |= rest & ~edgeFront(xm, models[2 * size_t(j)], rest);
            continue;
          }
        }
        if (o.zmax <= f.zmin) {
          behind |= common;
          continue;
        }
        if (o.zmin >= f.zmax) continue;
        ownDepths();
        const float* od = depthsOf(j);
        for (MaskBits m = common; m; m &= m - 1) {
          const int s = std::countr_zero(m);
          if (od[s] < xd[size_t(s)] || (od[s] == xd[size_t(s)] && o.zkey <= f.zkey)) behind |= MaskBits(1) << s;
        }
      }
      if (!behind) continue;
      const float hide = x->factor * hideOf(f);
      float sumT = 0;
      for (MaskBits m = behind; m; m &= m - 1) {
        const int s = std::countr_zero(m);
        sumT += T[s];
        T[s] *= 1.0f - hide;
      }
      anyXray = true;
      const float w = x->factor * f.opacity * f.area * (sumT / float(maskCount(f.mask)));
      rgb += colourOf(f) * w;
      alpha += w;
    }
  }
  // The owners, through what lies in front of them. In a deep pixel with nothing partial in it
  // and no x-ray fragment: those that own every sample they cover keep their exact areas, and
  // what is left of the pixel is shared among the others by the samples they own (a hair that
  // owns all its samples stays exact); where none of the others owns a sample, the gaps
  // between the visible ones show the surface (Pixel::surface: whatever else lay behind them,
  // culling may have left out). Otherwise (a tail or a translucent fragment in front of some
  // owner, an x-ray fragment): every owner by its samples, through what lies in front.
  if (deep && !partialSeen && !anyXray) {
    float exact = 0.0f, shares = 0.0f;
    for (int i : whole) {
      const Fragment& f = order[size_t(i)]->f;
      if (owned[size_t(i)] == f.sampledMask()) exact += f.area;
      else shares += float(maskCount(owned[size_t(i)]));
    }
    const float rest = std::max(0.0f, 1.0f - exact);
    if (!(shares > 0.0f) && rest > 0.0f) {
      const Fragment& gaps = solids_[size_t(p.surface)];
      if (!gaps.holdout) rgb += colourOf(gaps) * rest, alpha += rest;
    }
    for (int i : whole) {
      const Fragment& f = order[size_t(i)]->f;
      const MaskBits mine = owned[size_t(i)];
      if (f.holdout) continue;
      float w;
      if (mine == f.sampledMask()) w = f.area;  // (never 0: a whole fragment was sampled)
      else if (shares > 0.0f) w = rest * float(maskCount(mine)) / shares;
      else w = 0.0f;  // (the gaps: above)
      if (!(w > 0.0f)) continue;
      rgb += colourOf(f) * w;
      alpha += w;
    }
  } else {
    for (int i : whole) {
      const MaskBits mine = owned[size_t(i)];
      if (!mine) continue;
      const Fragment& f = order[size_t(i)]->f;
      if (f.holdout) continue;
      float sumT;
      if (anyPartial || anyXray) {
        sumT = 0;
        for (MaskBits m = mine; m; m &= m - 1) sumT += T[std::countr_zero(m)];
      } else {
        sumT = float(maskCount(mine));
      }
      if (!(sumT > 0.0f)) continue;
      const float w = deep ? f.opacity * sumT / float(N) : f.opacity * f.area * (sumT / float(maskCount(f.mask)));
      rgb += colourOf(f) * w;
      alpha += w;
    }
  }
  // Quantised masks can let true areas overlap where masks do not: never more than full cover.
  if (alpha > 1.0f) {
    rgb /= alpha;
    alpha = 1.0f;
  }
  return glm::vec4(rgb, alpha);
}

void TileABuffer::finish(ABufferCounters& counters) {
  for (size_t i = 0; i < pixels_.size(); ++i) {
    const Pixel& p = pixels_[i];
    if (offered_[i] == 0) continue;
    ++local_.coveredPixels;
    local_.maxFragmentsPerPixel = std::max(local_.maxFragmentsPerPixel, offered_[i]);
    if (p.length > 0 || p.hasTail()) ++local_.pixelsWithList;
    else if (p.hasSolid()) ++local_.pixelsSolidOnly;
    if (p.hasTail()) ++local_.pixelsOverBudget;
  }
  local_.peakBytes = std::max(peakBytes_, bytes());
  // Nodes are reused from the free list before the list grows, so its size is this tile's peak
  // of live entries; solid fragments are never freed (replaced in place, or a surface's kept
  // behind a wire's: setSolid).
  local_.peakFragmentsHeld = std::uint64_t(nodes_.size() + solids_.size());
  local_.pixelsDeep = scratch_.deepPixels;
  scratch_.deepPixels = 0;
  counters.add(local_);
  local_ = ABufferCounters{};
}

}  // namespace wf

#include "abuffer/abuffer.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace wf {

namespace {
// How many of a pixel's most recent fragments are checked for a merge: pieces of one object
// arrive one after another (consecutive segments, neighbouring triangles), so a short look-back
// finds them without making insertion O(list length).
constexpr int kMergeLookBack = 8;
// The eight bits of a byte as eight 0/1 floats (the resolve's mask expansion).
struct ByteLanes {
  float v[256][8];
  constexpr ByteLanes() : v{} {
    for (int b = 0; b < 256; ++b)
      for (int i = 0; i < 8; ++i) v[b][i] = float((b >> i) & 1);
  }
};
constexpr ByteLanes kByteLaneTable{};
const auto& kByteLanes = kByteLaneTable.v;
// Solid means the whole pixel: the exact area may fall short of 1 by rounding only.
constexpr float kSolidArea = 1.0f - 1e-5f;

bool depthRangesTouch(const Fragment& a, const Fragment& b) {
  const float eps = 1e-5f * std::max(std::abs(a.zmax), std::abs(b.zmax)) + 1e-30f;
  return a.zmin <= b.zmax + eps && b.zmin <= a.zmax + eps;
}

void mergeInto(Fragment& g, const Fragment& f) {
  const float a = g.area + f.area;
  const float wg = a > 0 ? g.area / a : 0.5f, wf = 1.0f - wg;
  g.colour = g.colour * wg + f.colour * wf;
  g.opacity = g.opacity * wg + f.opacity * wf;
  g.zkey = g.zkey * wg + f.zkey * wf;
  g.zmin = std::min(g.zmin, f.zmin);
  g.zmax = std::max(g.zmax, f.zmax);
  g.area = std::min(1.0f, a);
  const MaskBits sampled = (g.mask & ~g.standInBits) | (f.mask & ~f.standInBits);
  g.standInBits = (g.standInBits | f.standInBits) & ~sampled;
  g.mask = sampled | g.standInBits;
}
}  // namespace

void ABufferCounters::add(const ABufferCounters& o) {
  fragments += o.fragments;
  merged += o.merged;
  culled += o.culled;
  tail += o.tail;
  pixelsWithList += o.pixelsWithList;
  pixelsSolidOnly += o.pixelsSolidOnly;
  pixelsOverBudget += o.pixelsOverBudget;
  coveredPixels += o.coveredPixels;
  maxFragmentsPerPixel = std::max(maxFragmentsPerPixel, o.maxFragmentsPerPixel);
  maxListLength = std::max(maxListLength, o.maxListLength);
  peakBytes = std::max(peakBytes, o.peakBytes);
  peakFragmentsHeld = std::max(peakFragmentsHeld, o.peakFragmentsHeld);
}

TileABuffer::TileABuffer(const MaskLayout& layout, int budget, float occlusionEpsilon)
    : layout_(layout), budget_(std::clamp(budget, 1, 65535)),
      epsilon_(std::isfinite(occlusionEpsilon) ? std::clamp(occlusionEpsilon, 0.0f, 0.5f) : 0.0f) {}

void TileABuffer::reset(int w, int h) {
  w_ = w;
  h_ = h;
  pixels_.assign(size_t(w) * size_t(h), Pixel{});
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
}

std::size_t TileABuffer::bytesFor(int w, int h, const MaskLayout& layout, int entriesPerPixel) {
  const std::size_t n = std::size_t(std::max(w, 0)) * std::size_t(std::max(h, 0));
  const std::size_t blocks = std::size_t((std::max(w, 0) + 3) / 4) * std::size_t((std::max(h, 0) + 3) / 4);
  return n * (sizeof(Pixel) + 2 * sizeof(float) + 2 * std::size_t(layout.samples()) * sizeof(float) +
              std::size_t(std::max(entriesPerPixel, 0)) * sizeof(Node)) +
         blocks * sizeof(float);
}

std::size_t TileABuffer::bytes() const {
  return pixels_.capacity() * sizeof(Pixel) + nodes_.capacity() * sizeof(Node) +
         freeNodes_.capacity() * sizeof(std::int32_t) + tails_.capacity() * sizeof(Tail) +
         (subpixelDepth_.capacity() + occlusion_.capacity() + blockOcclusion_.capacity() + offered_.capacity()) * sizeof(float) +
         solids_.capacity() * sizeof(Fragment);
}

bool TileABuffer::isSolid(const Fragment& f) const {
  return f.opacity >= 1.0f && f.area >= kSolidArea && f.mask == layout_.full() && f.standInBits == 0;
}

std::int32_t TileABuffer::allocNode() {
  if (!freeNodes_.empty()) {
    const std::int32_t i = freeNodes_.back();
    freeNodes_.pop_back();
    return i;
  }
  nodes_.push_back(Node{});  // capacities never shrink: finish() reads the peak
  return std::int32_t(nodes_.size() - 1);
}

void TileABuffer::toTail(Pixel& p, const Fragment& f) {
  if (p.tail < 0) {
    p.tail = std::int32_t(tails_.size());
    tails_.push_back(Tail{});
  }
  Tail& t = tails_[size_t(p.tail)];
  const float w = f.opacity * f.area;
  t.premultiplied += f.colour * w;
  t.weight += w;
  t.transmittance *= std::max(0.0f, 1.0f - w);
  t.zkeyMin = std::min(t.zkeyMin, f.zkey);
  ++local_.tail;
  // The tail blends what it holds over the whole pixel, so the per-subpixel occlusion built from
  // fragments that may now sit in it no longer holds: from here on only the solid fragment (never
  // evicted) occludes this pixel.
  if (!p.noOcclusion) {
    p.noOcclusion = true;
    const size_t pixelIndex = size_t(&p - pixels_.data());
    occlusion_[pixelIndex] = p.hasSolid() ? solids_[size_t(p.solid)].zmax : INFINITY;
    updateBlock(pixelIndex);
  }
}

void TileABuffer::updateBlock(size_t pixelIndex) {
  const int px = int(pixelIndex % size_t(w_)), py = int(pixelIndex / size_t(w_));
  const int bx = px >> 2, by = py >> 2;
  float bmax = 0.0f;
  for (int y = by * 4; y < std::min(h_, by * 4 + 4); ++y)
    for (int x = bx * 4; x < std::min(w_, bx * 4 + 4); ++x) bmax = std::max(bmax, occlusion_[size_t(y) * size_t(w_) + size_t(x)]);
  blockOcclusion_[size_t(by) * size_t(bw_) + size_t(bx)] = bmax;
}

void TileABuffer::occlude(Pixel& p, size_t pixelIndex, const Fragment& f) {
  // Each subpixel tracks the transmittance T the fragments so far leave over it (the resolve's
  // own factors 1 - alpha * min(1, A N / k)) and the depth D behind which they all lie. Once
  // T <= epsilon the subpixel is settled: whatever lies behind D adds at most epsilon of its
  // colour there. With epsilon = 0 only fragments that hide wholly settle a subpixel and the skip
  // is exact; a fragment that alone hides a subpixel settles it at its own depth.
  const int k = maskCount(f.mask);
  const int n = layout_.samples();
  const float hide = f.opacity * std::min(1.0f, f.area * float(n) / float(std::max(k, 1)));
  if (!(hide > 0.0f) || k == 0 || p.noOcclusion) return;
  // A settled pixel changes only when a wholly hiding fragment comes nearer than its depth.
  if (p.open == 0 && p.depths >= 0 && (hide < 1.0f || !(f.zmax < occlusion_[pixelIndex]))) return;
  if (p.depths < 0) {
    p.open = std::uint8_t(n);
    p.depths = std::int32_t(subpixelDepth_.size() / size_t(2 * n));
    subpixelDepth_.resize(subpixelDepth_.size() + size_t(n), 0.0f);   // D
    subpixelDepth_.resize(subpixelDepth_.size() + size_t(n), 1.0f);   // T
  }
  float* D = &subpixelDepth_[size_t(p.depths) * size_t(2 * n)];
  float* T = D + n;
  bool changed = false;
  for (MaskBits m = f.mask; m; m &= m - 1) {
    const int s = std::countr_zero(m);
    const bool settled = T[s] <= epsilon_;
    if (hide >= 1.0f) {
      if (!settled) {
        --p.open;
        D[s] = f.zmax;
        changed = true;
      } else if (f.zmax < D[s]) {
        D[s] = f.zmax;
        changed = true;
      }
      T[s] = 0.0f;
    } else if (!settled) {
      T[s] *= 1.0f - hide;
      D[s] = std::max(D[s], f.zmax);
      if (T[s] <= epsilon_) --p.open, changed = true;
    }
  }
  if (!changed) return;
  const float* z = D;
  if (p.open > 0) return;  // some subpixel is still uncovered: the pixel is not occluded yet
  float occ = 0.0f;
  for (int s = 0; s < n; ++s) occ = std::max(occ, z[s]);
  if (!(occ < occlusion_[pixelIndex])) return;
  occlusion_[pixelIndex] = occ;
  updateBlock(pixelIndex);
}

void TileABuffer::pruneHidden(Pixel& p, float depth) {
  // Drops the list entries that lie wholly behind `depth`. Strictly behind: an entry at exactly
  // that depth (a flat fragment, often the occluder itself) arrived earlier and sorts first.
  std::int32_t* link = &p.head;
  while (*link >= 0) {
    Node& n = nodes_[size_t(*link)];
    if (n.f.zmin > depth) {
      const std::int32_t dead = *link;
      *link = n.next;
      freeNodes_.push_back(dead);
      --p.length;
      ++local_.culled;
    } else {
      link = &n.next;
    }
  }
}

void TileABuffer::pushList(Pixel& p, const Fragment& f) {
  const float occ = occlusion_[size_t(&p - pixels_.data())];
  if (p.length >= budget_ && occ < INFINITY) pruneHidden(p, occ);
  if (p.length >= budget_) {
    // Keep the nearest `budget` exactly: the farthest of list + f goes to the tail.
    std::int32_t far = -1;
    for (std::int32_t i = p.head; i >= 0; i = nodes_[size_t(i)].next)
      if (far < 0 || nodes_[size_t(i)].f.zkey >= nodes_[size_t(far)].f.zkey) far = i;
    if (f.zkey >= nodes_[size_t(far)].f.zkey) {
      toTail(p, f);
      return;
    }
    toTail(p, nodes_[size_t(far)].f);
    nodes_[size_t(far)].f = f;
    nodes_[size_t(far)].seq = p.seq++;
    return;
  }
  const std::int32_t n = allocNode();
  nodes_[size_t(n)] = Node{f, p.seq++, p.head};
  p.head = n;
  ++p.length;
  local_.maxListLength = std::max<std::uint32_t>(local_.maxListLength, p.length);
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
    cur = f;
    p.solidSeq = p.seq++;
    if (old.zmin < f.zmax) pushList(p, old);  // interpenetrates the new solid: keep it
    else ++local_.culled;
  } else {
    p.solid = std::int32_t(solids_.size());
    solids_.push_back(f);
    p.solidSeq = p.seq++;
  }
  pruneHidden(p, solids_[size_t(p.solid)].zmax);  // entries wholly behind the new solid fragment
  if (p.noOcclusion) {
    const size_t pixelIndex = size_t(&p - pixels_.data());
    occlusion_[pixelIndex] = std::min(occlusion_[pixelIndex], solids_[size_t(p.solid)].zmax);
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
  if (f.zmin >= occlusion_[size_t(y) * size_t(w_) + size_t(x)] || (p.hasSolid() && f.zmin >= solids_[size_t(p.solid)].zmax)) {
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
    if (n.f.tag == f.tag && ((n.f.mask & ~n.f.standInBits) & (f.mask & ~f.standInBits)) == 0 &&
        depthRangesTouch(n.f, f)) {
      mergeInto(n.f, f);
      ++local_.merged;
      if (isSolid(n.f)) {
        const Fragment whole = n.f;
        const std::int32_t dead = *link;
        *link = n.next;
        freeNodes_.push_back(dead);
        --p.length;
        occlude(p, pixelIndex, whole);
        setSolid(p, whole);
      }
      return;
    }
    link = &n.next;
  }
  // Occlusion counts what the resolve will do with this very fragment: a piece that may still
  // merge with another (and change its hiding) counts only once it covers the whole pixel.
  const bool solid = isSolid(f);
  if (solid || !f.mayMerge) occlude(p, pixelIndex, f);
  if (solid) setSolid(p, f);
  else pushList(p, f);
}

glm::vec4 TileABuffer::resolve(int x, int y) const {
  const Pixel& p = pixels_[size_t(y) * size_t(w_) + size_t(x)];
  if (p.length == 0 && !p.hasTail()) {
    if (p.hasSolid()) return glm::vec4(solids_[size_t(p.solid)].colour, 1.0f);
    return glm::vec4(0.0f);
  }
  // Gather, sort front to back (depth, then arrival: deterministic).
  thread_local std::vector<const Node*> order;
  thread_local Node solidNode, tailNode;
  order.clear();
  for (std::int32_t i = p.head; i >= 0; i = nodes_[size_t(i)].next) order.push_back(&nodes_[size_t(i)]);
  if (p.hasSolid()) {
    solidNode = Node{solids_[size_t(p.solid)], p.solidSeq, -1};  // its arrival: ties sort by it
    order.push_back(&solidNode);
  }
  if (p.hasTail()) {
    // The tail composites as one whole-pixel layer, at the depth of its nearest member: behind
    // the kept fragments (they are the nearest), in front of a solid fragment it is not behind.
    const Tail& t = tails_[size_t(p.tail)];
    Fragment f;
    f.zkey = f.zmin = f.zmax = t.zkeyMin;
    f.area = 1.0f;
    f.opacity = 1.0f - t.transmittance;
    f.colour = t.weight > 0 ? t.premultiplied / t.weight : glm::vec3(0.0f);
    f.mask = layout_.full();
    tailNode = Node{f, 0xFFFFFFFEu, -1};
    order.push_back(&tailNode);
  }
  std::sort(order.begin(), order.end(), [](const Node* a, const Node* b) {
    return a->f.zkey < b->f.zkey || (a->f.zkey == b->f.zkey && a->seq < b->seq);
  });
  const int N = layout_.samples();
  // Per-subpixel transmittance. Masks with few bits walk their bits; fuller ones update all N
  // lanes branch-free (vectorised), the mask expanded to 0/1 lanes a byte at a time.
  alignas(32) float T[64];
  std::fill(T, T + N, 1.0f);
  glm::vec3 rgb(0.0f);
  float alpha = 0.0f;
  for (const Node* n : order) {
    const Fragment& f = n->f;
    const int k = maskCount(f.mask);
    if (k == 0) continue;
    const float hide = f.opacity * std::min(1.0f, f.area * float(N) / float(k));
    float sumT = 0;
    if (k <= 8) {
      for (MaskBits m = f.mask; m; m &= m - 1) sumT += T[std::countr_zero(m)];
      for (MaskBits m = f.mask; m; m &= m - 1) T[std::countr_zero(m)] *= 1.0f - hide;
    } else {
      alignas(32) float in[64];
      for (int b = 0; b < N; b += 8) std::memcpy(in + b, kByteLanes[(f.mask >> b) & 0xFF], sizeof(float) * 8);
      for (int s = 0; s < N; ++s) sumT += T[s] * in[s];
      for (int s = 0; s < N; ++s) T[s] *= 1.0f - hide * in[s];
    }
    const float w = f.opacity * f.area * (sumT / float(k));
    rgb += f.colour * w;
    alpha += w;
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
  // of live entries; solid fragments are only replaced in place, never freed.
  local_.peakFragmentsHeld = std::uint64_t(nodes_.size() + solids_.size());
  counters.add(local_);
  local_ = ABufferCounters{};
}

}  // namespace wf

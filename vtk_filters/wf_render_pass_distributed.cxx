#include "wf_render_pass_distributed.h"

#include <vtkMultiProcessController.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>

namespace wfvtk {

void bandOf(int rank, int ranks, int height, int& begin, int& end) {
  const int units = (height + kBandRows - 1) / kBandRows;
  const int base = units / ranks, extra = units % ranks;
  const int first = rank * base + std::min(rank, extra);
  begin = std::min(height, first * kBandRows);
  end = std::min(height, (first + base + (rank < extra ? 1 : 0)) * kBandRows);
}

bool sameOnEveryRank(vtkMultiProcessController* controller, const std::vector<double>& values) {
  const int n = controller->GetNumberOfProcesses();
  std::vector<double> all(values.size() * static_cast<size_t>(n));
  if (!controller->AllGather(values.data(), all.data(), vtkIdType(values.size()))) return false;
  for (int r = 1; r < n; ++r)
    if (!std::equal(values.begin(), values.end(), all.begin() + std::ptrdiff_t(values.size()) * r)) return false;
  return true;
}

namespace {

// A piece's packet (doubles, exact: points are doubles, colours floats, starts < 2^53):
// header, then the points (3 a point), the colours (3 a point, or none), the polyline starts.
// Header: has lines, points, colours, starts, the wire's style, thickness, thickness in pixels,
// colour (3), opacity, the wire material's diffuse (3), specular (3), exponent, opacity, the
// transform (16, column major).
constexpr size_t kHeader = 4 + 3 + 3 + 1 + 3 + 3 + 1 + 1 + 16;

void pack(const ActorPiece& p, std::vector<double>& out) {
  const size_t at = out.size();
  out.resize(at + kHeader, 0.0);
  double* h = out.data() + at;
  const wf::GeometryData* g = p.object.geometry.get();
  if (!p.object.wire || !g || g->lines.polylineCount() == 0) return;  // h[0] = 0: no lines
  const wf::PolylineSet& l = g->lines;
  const wf::SceneWire& w = p.object.wire->wire;
  const wf::Material& m = p.wireMaterial;
  size_t k = 0;
  h[k++] = 1.0;
  h[k++] = double(l.points.size());
  h[k++] = double(l.colours.size());
  h[k++] = double(l.starts.size());
  h[k++] = double(int(w.style));
  h[k++] = w.thickness;
  h[k++] = w.thicknessInPixels ? 1.0 : 0.0;
  for (int c = 0; c < 3; ++c) h[k++] = w.colour[c];
  h[k++] = w.opacity;
  for (int c = 0; c < 3; ++c) h[k++] = m.phong.diffuse[c];
  for (int c = 0; c < 3; ++c) h[k++] = m.phong.specular[c];
  h[k++] = m.phong.exponent;
  h[k++] = m.opacity;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) h[k++] = p.object.transform[c][r];
  for (const glm::dvec3& q : l.points) out.insert(out.end(), {q.x, q.y, q.z});
  for (const glm::vec3& q : l.colours) out.insert(out.end(), {double(q.x), double(q.y), double(q.z)});
  for (std::uint32_t s : l.starts) out.push_back(double(s));
}

}  // namespace

std::vector<ActorPiece> gatherWires(vtkMultiProcessController* controller,
                                    const std::vector<ActorPiece>& local, int& droppedSurfaces) {
  const int ranks = controller->GetNumberOfProcesses();
  droppedSurfaces = 0;
  std::vector<double> mine;
  for (const ActorPiece& p : local) {
    pack(p, mine);
    if (p.object.geometry && !p.object.geometry->mesh.positions.empty()) ++droppedSurfaces;
  }
  const vtkIdType length = vtkIdType(mine.size());
  std::vector<vtkIdType> lengths(static_cast<size_t>(ranks)), offsets(static_cast<size_t>(ranks));
  if (!controller->AllGather(&length, lengths.data(), 1)) throw std::runtime_error("exchange of the lines' sizes failed");
  vtkIdType total = 0;
  for (int r = 0; r < ranks; ++r) offsets[size_t(r)] = total, total += lengths[size_t(r)];
  // MPI's counts and displacements are ints (vtkMPICommunicator narrows them): every rank sees
  // the same lengths, so every rank stops here together.
  if (total > vtkIdType(std::numeric_limits<int>::max()))
    throw std::runtime_error("the marked lines of all ranks (" + std::to_string(total / 3) +
                             " points) are too many to gather over MPI (at most 2^31 - 1 doubles)");
  std::vector<double> all(static_cast<size_t>(total));
  if (!controller->AllGatherV(mine.data(), all.data(), length, lengths.data(), offsets.data()))
    throw std::runtime_error("exchange of the lines failed");

  // Per marked actor, the ranks' lines, grouped by what they are drawn with (the header after
  // the counts, and whether they carry per-point colours): one piece per group, in the order of
  // the group's first rank. The actor's property is the same on every rank, so there is one
  // group but where ranks differ in their data (per-point colours on some ranks only: a partial
  // array), and each rank's lines are then drawn as that rank alone would draw them.
  std::vector<ActorPiece> out;
  std::vector<size_t> cursor(static_cast<size_t>(ranks));
  for (int r = 0; r < ranks; ++r) cursor[size_t(r)] = size_t(offsets[size_t(r)]);
  for (size_t i = 0; i < local.size(); ++i) {
    struct Group {
      std::vector<double> key;  // has colours, then the header after the counts
      ActorPiece piece;
      std::shared_ptr<wf::GeometryData> geometry;
    };
    std::vector<Group> groups;
    for (int r = 0; r < ranks; ++r) {
      size_t& at = cursor[size_t(r)];
      const size_t end = size_t(offsets[size_t(r)] + lengths[size_t(r)]);
      if (at + kHeader > end) throw std::runtime_error("a rank's lines are truncated");
      const double* h = all.data() + at;
      at += kHeader;
      if (h[0] != 1.0) continue;
      const double np = h[1], nc = h[2], ns = h[3];
      // (Counts are whole numbers below 2^53 that fit what this rank received.)
      if (!(np >= 0 && nc >= 0 && ns >= 2) || np != std::floor(np) || nc != std::floor(nc) || ns != std::floor(ns) ||
          3 * np + 3 * nc + ns > double(end - at) || (nc != 0 && nc != np))
        throw std::runtime_error("a rank's lines are malformed");
      std::vector<double> key(h + 4, h + kHeader);
      key.insert(key.begin(), nc > 0 ? 1.0 : 0.0);
      auto g = std::find_if(groups.begin(), groups.end(), [&](const Group& x) { return x.key == key; });
      if (g == groups.end()) {
        groups.push_back(Group{std::move(key), ActorPiece{}, std::make_shared<wf::GeometryData>()});
        g = groups.end() - 1;
        ActorPiece& p = g->piece;
        p.actor = local[i].actor;
        p.signature = local[i].signature;
        p.material = local[i].material;
        wf::WireDescription wd;
        wd.from = wf::WireDescription::From::Lines;
        wd.where = "actor/wire";
        wf::SceneWire& w = wd.wire;
        size_t k = 4;
        w.material = 1;
        w.style = wf::WireStyle(int(h[k++]));
        w.thickness = h[k++];
        w.thicknessInPixels = h[k++] != 0.0;
        for (int c = 0; c < 3; ++c) w.colour[c] = float(h[k++]);
        w.opacity = float(h[k++]);
        p.wireMaterial = local[i].wireMaterial;
        for (int c = 0; c < 3; ++c) p.wireMaterial.phong.diffuse[c] = h[k++];
        for (int c = 0; c < 3; ++c) p.wireMaterial.phong.specular[c] = h[k++];
        p.wireMaterial.phong.exponent = h[k++];
        p.wireMaterial.opacity = float(h[k++]);
        for (int c = 0; c < 4; ++c)
          for (int q = 0; q < 4; ++q) p.object.transform[c][q] = h[k++];
        p.object.name = "actor";
        p.object.where = "actor";
        p.object.drawSurface = false;
        p.object.wire = std::move(wd);
      }
      wf::PolylineSet& lines = g->geometry->lines;
      // The core numbers points with 32 bits.
      if (double(lines.points.size()) + np > double(std::numeric_limits<std::uint32_t>::max()))
        throw std::runtime_error("more than 2^32 - 1 points in one marked actor's lines");
      const double* d = all.data() + at;
      const std::uint32_t base = std::uint32_t(lines.points.size());
      for (size_t j = 0; j < size_t(np); ++j) lines.points.emplace_back(d[3 * j], d[3 * j + 1], d[3 * j + 2]);
      d += 3 * size_t(np);
      for (size_t j = 0; j < size_t(nc); ++j) lines.colours.emplace_back(float(d[3 * j]), float(d[3 * j + 1]), float(d[3 * j + 2]));
      d += 3 * size_t(nc);
      if (lines.starts.empty()) lines.starts.push_back(0);
      for (size_t j = 1; j < size_t(ns); ++j) lines.starts.push_back(base + std::uint32_t(d[j]));
      at += 3 * size_t(np) + 3 * size_t(nc) + size_t(ns);
    }
    for (Group& g : groups) {
      g.piece.object.geometry = std::move(g.geometry);
      out.push_back(std::move(g.piece));
    }
  }
  return out;
}

bool compositeSurfaceBands(vtkMultiProcessController* controller, int w, int h,
                           std::vector<unsigned char>& colour, std::vector<float>& depth) {
  const int ranks = controller->GetNumberOfProcesses(), me = controller->GetLocalProcessId();
  std::vector<unsigned char> colours;
  std::vector<float> depths;
  bool ok = true;  // a failed exchange does not leave the loop: every band's Gathers are taken
  for (int b = 0; b < ranks; ++b) {
    int r0, r1;
    bandOf(b, ranks, h, r0, r1);
    const size_t first = size_t(h - r1) * size_t(w), count = size_t(r1 - r0) * size_t(w);  // OpenGL rows
    if (b == me) colours.resize(4 * count * size_t(ranks)), depths.resize(count * size_t(ranks));
    const bool c = controller->Gather(colour.data() + 4 * first, b == me ? colours.data() : nullptr, vtkIdType(4 * count), b);
    const bool d = controller->Gather(depth.data() + first, b == me ? depths.data() : nullptr, vtkIdType(count), b);
    if (!c || !d) ok = false;
    if (b != me || !c || !d) continue;
    for (size_t i = 0; i < count; ++i) {
      int best = 0;
      for (int r = 1; r < ranks; ++r)
        if (depths[size_t(r) * count + i] < depths[size_t(best) * count + i]) best = r;
      depth[first + i] = depths[size_t(best) * count + i];
      std::memcpy(colour.data() + 4 * (first + i), colours.data() + 4 * (size_t(best) * count + i), 4);
    }
  }
  return ok;
}

bool gatherBands(vtkMultiProcessController* controller, int w, int h,
                 std::vector<unsigned char>& colour, std::vector<float>& depth) {
  const int ranks = controller->GetNumberOfProcesses(), me = controller->GetLocalProcessId();
  const size_t nr = static_cast<size_t>(ranks);
  std::vector<vtkIdType> lengths(nr), offsets(nr), lengths4(nr), offsets4(nr);
  for (int b = 0; b < ranks; ++b) {
    int r0, r1;
    bandOf(b, ranks, h, r0, r1);
    offsets[size_t(b)] = vtkIdType(h - r1) * w, lengths[size_t(b)] = vtkIdType(r1 - r0) * w;
    offsets4[size_t(b)] = 4 * offsets[size_t(b)], lengths4[size_t(b)] = 4 * lengths[size_t(b)];
  }
  // Sent from a copy: MPI forbids the send buffer overlapping the receive buffer.
  const size_t m = size_t(me);
  std::vector<unsigned char> c(colour.begin() + offsets4[m], colour.begin() + offsets4[m] + lengths4[m]);
  std::vector<float> d(depth.begin() + offsets[m], depth.begin() + offsets[m] + lengths[m]);
  return controller->AllGatherV(c.data(), colour.data(), lengths4[m], lengths4.data(), offsets4.data()) &&
         controller->AllGatherV(d.data(), depth.data(), lengths[m], lengths.data(), offsets.data());
}

}  // namespace wfvtk

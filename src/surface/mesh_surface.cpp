#include "surface/mesh_surface.h"

#include "core/numeric.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>

namespace wf {

MeshSurface::MeshSurface(std::vector<glm::dvec3> positions, std::vector<glm::dvec2> uvs,
                         const std::vector<glm::uvec3>& triangles, int gridCells)
    : positions_(std::move(positions)), uvs_(std::move(uvs)) {
  if (uvs_.size() != positions_.size()) {
    problem_ = "the mesh has no texture coordinate for every point";
    return;
  }
  build(triangles, gridCells, false);
}

MeshSurface::MeshSurface(const TriangleMesh& mesh, int gridCells) {
  if (!mesh.uvs.empty() && mesh.uvs.size() == mesh.positions.size()) {
    positions_ = mesh.positions;
    uvs_ = mesh.uvs;
    // The mesh's own layout, unless it leaves a tenth of the surface out (mirrored halves,
    // overlapping charts: a character's mirrored side would grow nothing) or overlaps itself
    // too much to look up: then the automatic layout.
    if (build(mesh.triangles, gridCells, true) && keptArea_ >= 0.9 * totalArea_) return;
    *this = MeshSurface();
  }
  automatic_ = true;
  layOut(mesh);
  if (!problem_.empty()) return;
  std::vector<glm::uvec3> own(positions_.size() / 3);
  for (size_t k = 0; k < own.size(); ++k) own[k] = glm::uvec3(3 * k, 3 * k + 1, 3 * k + 2);
  build(own, gridCells, true);
}

void MeshSurface::layOut(const TriangleMesh& mesh) {
  // Each triangle in its own frame: u along the up axis projected onto its plane, v = N x u, in
  // world units; then its bounding box placed on shelves of a strip about as wide as the layout
  // is tall (tallest first, then triangle order: deterministic).
  struct Flat {
    glm::dvec2 q[3];
    glm::dvec2 size;
  };
  std::vector<Flat> flat;
  std::vector<std::uint32_t> source;  // triangle index of each laid-out triangle
  double area = 0.0;
  for (size_t k = 0; k < mesh.triangles.size(); ++k) {
    const glm::uvec3 t = mesh.triangles[k];
    if (t.x >= mesh.positions.size() || t.y >= mesh.positions.size() || t.z >= mesh.positions.size()) {
      problem_ = "triangle " + std::to_string(k) + " names a point the mesh does not have";
      return;
    }
    const glm::dvec3 p0 = mesh.positions[t.x], p1 = mesh.positions[t.y], p2 = mesh.positions[t.z];
    if (!finite(p0) || !finite(p1) || !finite(p2)) continue;
    const glm::dvec3 c = glm::cross(p1 - p0, p2 - p0);
    const double len = glm::length(c);
    if (!(len > 0.0) || !std::isfinite(len)) continue;
    const glm::dvec3 n = c / len;
    glm::dvec3 up(0.0, 0.0, 1.0);
    if (std::abs(n.z) > 0.999) up = glm::dvec3(1.0, 0.0, 0.0);
    const glm::dvec3 tu = glm::normalize(up - glm::dot(up, n) * n), tv = glm::cross(n, tu);
    Flat f;
    glm::dvec2 lo(0.0), hi(0.0);
    const glm::dvec3 p[3] = {p0, p1, p2};
    for (int i = 0; i < 3; ++i) {
      f.q[i] = {glm::dot(p[i] - p0, tu), glm::dot(p[i] - p0, tv)};
      lo = glm::min(lo, f.q[i]);
      hi = glm::max(hi, f.q[i]);
    }
    for (int i = 0; i < 3; ++i) f.q[i] -= lo;
    f.size = hi - lo;
    area += f.size.x * f.size.y;
    flat.push_back(f);
    source.push_back(std::uint32_t(k));
  }
  if (flat.empty()) {
    problem_ = "the mesh has no triangle with a non-zero area";
    return;
  }
  std::vector<std::uint32_t> order(flat.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return flat[a].size.y > flat[b].size.y; });
  double widest = 0.0;
  for (const Flat& f : flat) widest = std::max(widest, f.size.x);
  const double stripWidth = std::max(widest, std::sqrt(area));
  // A gap of a thousandth of the strip between triangles, so that no two share an edge in uv.
  const double gap = 1e-3 * stripWidth;
  double x = 0.0, y = 0.0, shelf = 0.0;
  positions_.resize(3 * flat.size());
  uvs_.resize(3 * flat.size());
  for (size_t i = 0; i < order.size(); ++i) {
    const Flat& f = flat[order[i]];
    if (x > 0.0 && x + f.size.x > stripWidth) x = 0.0, y += shelf + gap, shelf = 0.0;
    const glm::uvec3 t = mesh.triangles[source[order[i]]];
    const std::uint32_t v[3] = {t.x, t.y, t.z};
    for (int k = 0; k < 3; ++k) {
      positions_[3 * i + k] = mesh.positions[v[k]];
      uvs_[3 * i + k] = f.q[k] + glm::dvec2(x, y);
    }
    x += f.size.x + gap;
    shelf = std::max(shelf, f.size.y);
  }
}

bool MeshSurface::build(const std::vector<glm::uvec3>& all, int gridCells, bool skipNonFinite) {
  const size_t np = positions_.size();
  if (np == 0 || all.empty()) {
    problem_ = "the mesh has no triangles";
    return false;
  }
  if (np > size_t(std::numeric_limits<std::uint32_t>::max())) {
    problem_ = "the mesh has more than 2^32 points";
    return false;
  }
  auto usable = [&](size_t i) { return finite(positions_[i]) && std::isfinite(uvs_[i].x) && std::isfinite(uvs_[i].y); };
  if (!skipNonFinite)
    for (size_t i = 0; i < np; ++i) {
      if (!finite(positions_[i])) {
        problem_ = "point " + std::to_string(i) + " is not finite";
        return false;
      }
      if (!(std::isfinite(uvs_[i].x) && std::isfinite(uvs_[i].y))) {
        problem_ = "texture coordinate " + std::to_string(i) + " is not finite";
        return false;
      }
    }
  // Bounds of the points the triangles use (an unused far point says nothing of their size).
  glm::dvec3 blo(std::numeric_limits<double>::infinity()), bhi(-std::numeric_limits<double>::infinity());
  for (size_t k = 0; k < all.size(); ++k) {
    const glm::uvec3& t = all[k];
    if (t.x >= np || t.y >= np || t.z >= np) {
      problem_ = "triangle " + std::to_string(k) + " names a point the mesh does not have";
      return false;
    }
    for (std::uint32_t v : {t.x, t.y, t.z})
      if (usable(v)) blo = glm::min(blo, positions_[v]), bhi = glm::max(bhi, positions_[v]);
  }
  // Zero area in space is measured against the whole mesh (its bounding box), not the triangle's
  // own edges: the joined corner of a closed layout is three copies of one point, all its edges
  // rounding noise, and yet it spans half the uv square. 1e-12 L^2 is above the area of a triangle
  // made of float-rounded copies of one point ((1e-7 L)^2) and far below any real triangle.
  const double diagonal2 = blo.x <= bhi.x ? glm::dot(bhi - blo, bhi - blo) : 0.0;
  std::vector<double> dets(all.size(), 0.0);
  std::vector<double> positive, negative;
  totalArea_ = 0.0;
  for (size_t k = 0; k < all.size(); ++k) {
    const glm::uvec3& t = all[k];
    if (!usable(t.x) || !usable(t.y) || !usable(t.z)) continue;  // (only when skipping)
    const glm::dvec2 d1 = uvs_[t.y] - uvs_[t.x], d2 = uvs_[t.z] - uvs_[t.x];
    const double det = d1.x * d2.y - d2.x * d1.y;
    const double scale = std::max({std::abs(d1.x), std::abs(d1.y), std::abs(d2.x), std::abs(d2.y)});
    const glm::dvec3 e1 = positions_[t.y] - positions_[t.x], e2 = positions_[t.z] - positions_[t.x];
    const double area2 = glm::length(glm::cross(e1, e2));
    if (std::isfinite(area2)) totalArea_ += 0.5 * area2;
    const double edge2 = std::max(glm::dot(e1, e1), glm::dot(e2, e2));
    if (!(std::abs(det) > 1e-14 * scale * scale) || !(area2 > 1e-12 * std::max(edge2, diagonal2))) continue;
    dets[k] = det;
    (det > 0 ? positive : negative).push_back(std::abs(det));
  }
  // Summed in sorted order, so that the same triangles in another order (a distributed mesh
  // gathered from its pieces, vtk_filters/wf_vtk_pieces.h) make the same choice; a tie within
  // rounding (a closed slab's top and bottom mapped alike, whose quads may be split along either
  // diagonal) goes to the positive winding.
  auto sorted = [](std::vector<double>& v) {
    std::sort(v.begin(), v.end());
    double sum = 0.0;
    for (double a : v) sum += a;
    return sum;
  };
  const double positiveArea = sorted(positive), negativeArea = sorted(negative);
  const double winding = positiveArea >= negativeArea * (1.0 - 1e-9) ? 1.0 : -1.0;
  glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  keptArea_ = 0.0;
  for (size_t k = 0; k < all.size(); ++k) {
    if (!(dets[k] * winding > 0)) continue;
    const glm::uvec3& t = all[k];
    Triangle tri;
    tri.v[0] = t.x, tri.v[1] = t.y, tri.v[2] = t.z;
    tri.source = std::uint32_t(k);
    const glm::dvec2 a = uvs_[t.x], b = uvs_[t.y], c = uvs_[t.z];
    const glm::dvec2 d1 = b - a, d2 = c - a;
    const double det = dets[k];
    const glm::dvec3 e1 = positions_[t.y] - positions_[t.x], e2 = positions_[t.z] - positions_[t.x];
    keptArea_ += 0.5 * glm::length(glm::cross(e1, e2));
    // [e1 e2] = [Su Sv] [d1 d2]  =>  [Su Sv] = [e1 e2] [d1 d2]^-1
    tri.Su = (e1 * d2.y - e2 * d1.y) / det;
    tri.Sv = (e2 * d1.x - e1 * d2.x) / det;
    // (b1, b2) with uv - a = b1 d1 + b2 d2.
    tri.toBary = glm::inverse(glm::dmat2(d1, d2));
    tri.lo = glm::min(a, glm::min(b, c));
    tri.hi = glm::max(a, glm::max(b, c));
    lo = glm::min(lo, tri.lo);
    hi = glm::max(hi, tri.hi);
    triangles_.push_back(tri);
  }
  if (triangles_.empty()) {
    problem_ = "the mesh has no triangle with a non-zero area in texture space";
    return false;
  }
  if (triangles_.size() > std::numeric_limits<std::uint32_t>::max()) {
    problem_ = "the mesh has more than 2^32 triangles";
    return false;
  }
  domain_.u0 = lo.x, domain_.u1 = hi.x, domain_.v0 = lo.y, domain_.v1 = hi.y;
  // Uniform grid: about one cell per triangle (or gridCells), shaped like the uv bounding box.
  const double target = gridCells > 0 ? double(gridCells) : double(triangles_.size());
  const double aspect = domain_.du() / domain_.dv();
  nx_ = std::clamp(int(std::lround(std::sqrt(target * aspect))), 1, 4096);
  ny_ = std::clamp(int(std::lround(std::sqrt(target / aspect))), 1, 4096);
  auto cellRange = [&](const Triangle& t, int& i0, int& i1, int& j0, int& j1) {
    auto ix = [&](double u) { return std::clamp(int(std::floor((u - domain_.u0) / domain_.du() * nx_)), 0, nx_ - 1); };
    auto iy = [&](double v) { return std::clamp(int(std::floor((v - domain_.v0) / domain_.dv() * ny_)), 0, ny_ - 1); };
    i0 = ix(t.lo.x), i1 = ix(t.hi.x), j0 = iy(t.lo.y), j1 = iy(t.hi.y);
  };
  // The lookup's size, counted before it is made: a layout that overlaps itself (every face on the
  // whole texture) puts each triangle in many cells, up to N^2 entries in all.
  std::size_t entries = 0;
  for (const Triangle& t : triangles_) {
    int i0, i1, j0, j1;
    cellRange(t, i0, i1, j0, j1);
    entries += std::size_t(i1 - i0 + 1) * std::size_t(j1 - j0 + 1);
  }
  const std::size_t cap = 16 * triangles_.size() + 4096;
  if (entries > cap) {
    problem_ = "the texture coordinates overlap themselves too much to look up (" + std::to_string(entries) +
               " grid entries for " + std::to_string(triangles_.size()) + " triangles)";
    triangles_.clear();
    return false;
  }
  cellStart_.assign(size_t(nx_) * size_t(ny_) + 1, 0);
  for (const Triangle& t : triangles_) {
    int i0, i1, j0, j1;
    cellRange(t, i0, i1, j0, j1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) ++cellStart_[size_t(j) * nx_ + i + 1];
  }
  for (size_t c = 1; c < cellStart_.size(); ++c) cellStart_[c] += cellStart_[c - 1];
  cellTriangles_.resize(cellStart_.back());
  std::vector<std::uint32_t> fill(cellStart_.begin(), cellStart_.end() - 1);
  for (std::uint32_t k = 0; k < triangles_.size(); ++k) {
    int i0, i1, j0, j1;
    cellRange(triangles_[k], i0, i1, j0, j1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) cellTriangles_[fill[size_t(j) * nx_ + i]++] = k;
  }
  return true;
}

bool MeshSurface::locate(double u, double v, std::size_t& triangle, glm::dvec3& barycentric) const {
  if (!problem_.empty() || !std::isfinite(u) || !std::isfinite(v)) return false;
  const int i = std::clamp(int(std::floor((u - domain_.u0) / domain_.du() * nx_)), 0, nx_ - 1);
  const int j = std::clamp(int(std::floor((v - domain_.v0) / domain_.dv() * ny_)), 0, ny_ - 1);
  const size_t c = size_t(j) * nx_ + i;
  // Inside with a relative tolerance, so that a point on a shared edge is found by one of its two
  // triangles despite rounding; the most interior candidate wins. An exact tie (triangles that
  // overlap in uv: two-sided or repeated charts) goes to the triangle with the smaller corners
  // (positions, then uvs, corners sorted), never to the one listed first: the choice does not
  // depend on the order of the triangles, which differs between a whole mesh and the same mesh
  // gathered from the pieces of a distributed one (vtk_filters/wf_vtk_pieces.h).
  constexpr double kInside = -1e-9;
  double best = -std::numeric_limits<double>::infinity();
  auto corners = [&](const Triangle& t) {
    std::array<std::array<double, 5>, 3> q;
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3& p = positions_[t.v[k]];
      const glm::dvec2& w = uvs_[t.v[k]];
      q[size_t(k)] = {p.x, p.y, p.z, w.x, w.y};
    }
    std::sort(q.begin(), q.end());
    return q;
  };
  for (std::uint32_t k = cellStart_[c]; k < cellStart_[c + 1]; ++k) {
    const Triangle& t = triangles_[cellTriangles_[k]];
    const glm::dvec2 b = t.toBary * (glm::dvec2(u, v) - uvs_[t.v[0]]);
    const double b0 = 1.0 - b.x - b.y;
    const double m = std::min({b0, b.x, b.y});
    if (m > best || (m == best && corners(t) < corners(triangles_[triangle]))) {
      best = m;
      triangle = cellTriangles_[k];
      barycentric = {b0, b.x, b.y};
    }
  }
  return best >= kInside;
}

SurfacePoint MeshSurface::evaluate(double u, double v) const {
  SurfacePoint sp;
  u = std::clamp(u, domain_.u0, domain_.u1);
  v = std::clamp(v, domain_.v0, domain_.v1);
  std::size_t k = 0;
  glm::dvec3 b(0.0);
  if (!locate(u, v, k, b)) {
    sp.P = glm::dvec3(std::numeric_limits<double>::quiet_NaN());
    return sp;
  }
  const Triangle& t = triangles_[k];
  sp.P = b.x * positions_[t.v[0]] + b.y * positions_[t.v[1]] + b.z * positions_[t.v[2]];
  sp.Su = t.Su;
  sp.Sv = t.Sv;
  return sp;
}

std::string MeshSurface::describe() const {
  std::ostringstream o;
  o << "mesh of " << triangles_.size() << (automatic_ ? " triangles laid out flat" : " uv triangles") << " over ["
    << domain_.u0 << ", " << domain_.u1 << "] x [" << domain_.v0 << ", " << domain_.v1 << "]";
  return o.str();
}

}  // namespace wf

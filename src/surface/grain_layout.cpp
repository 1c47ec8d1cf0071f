#include "surface/grain_layout.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace wf {

GrainLayoutStats layoutGrain(TriangleMesh& m, const std::vector<int>& triangleFace, GrainLayout layout) {
  GrainLayoutStats st;
  const std::size_t nv = m.positions.size();
  if (m.uvs.size() != nv || m.derivU.size() != nv || m.derivV.size() != nv) return st;
  const bool oneFace = triangleFace.size() != m.triangles.size();
  // Each face's vertices, first come (a vertex belongs to the first face that uses it).
  std::vector<int> owner(nv, -1);
  std::map<int, std::vector<std::uint32_t>> faces;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const int f = oneFace ? 0 : triangleFace[t];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = m.triangles[t][k];
      if (v >= nv || owner[v] >= 0) continue;
      owner[v] = f;
      faces[f].push_back(v);
    }
  }
  // Each face's area-weighted means of |dS/du| and |dS/dv| (a quadrature of their integrals over
  // the face: the same for any meshing of a plane or a cylinder, converging as h^2 elsewhere).
  std::map<int, glm::dvec3> sums;  // (area |Su|, area |Sv|, area)
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const glm::uvec3 tri = m.triangles[t];
    if (tri.x >= nv || tri.y >= nv || tri.z >= nv) continue;
    const double area = 0.5 * glm::length(glm::cross(m.positions[tri.y] - m.positions[tri.x], m.positions[tri.z] - m.positions[tri.x]));
    double a = 0, b = 0;
    for (int k = 0; k < 3; ++k) a += glm::length(m.derivU[tri[k]]) / 3, b += glm::length(m.derivV[tri[k]]) / 3;
    if (!std::isfinite(area + a + b) || !(area > 0)) continue;
    sums[oneFace ? 0 : triangleFace[t]] += glm::dvec3(area * a, area * b, area);
  }
  for (auto& [face, verts] : faces) {
    glm::dvec2 lo(INFINITY), hi(-INFINITY);
    std::size_t n = 0;
    for (std::uint32_t v : verts) {
      if (!std::isfinite(m.uvs[v].x + m.uvs[v].y)) continue;
      ++n;
      lo = glm::min(lo, m.uvs[v]), hi = glm::max(hi, m.uvs[v]);
    }
    const glm::dvec3 sum = sums[face];
    if (!(sum.z > 0)) n = 0;
    double lu = n ? sum.x / sum.z : 0.0, lv = n ? sum.y / sum.z : 0.0;
    if (n == 0) continue;
    const bool alongV = layout == GrainLayout::V ||
                        (layout == GrainLayout::Longer && (hi.y - lo.y) * lv > (hi.x - lo.x) * lu);
    ++st.faces;
    ++(alongV ? st.alongV : st.alongU);
    if (alongV) std::swap(lu, lv);
    const double scaleU = lu > 0 && std::isfinite(lu) ? lu : 1.0, scaleV = lv > 0 && std::isfinite(lv) ? lv : 1.0;
    for (std::uint32_t v : verts) {
      if (alongV) {
        std::swap(m.uvs[v].x, m.uvs[v].y);
        std::swap(m.derivU[v], m.derivV[v]);
      }
      m.uvs[v] *= glm::dvec2(scaleU, scaleV);
      m.derivU[v] /= scaleU;
      m.derivV[v] /= scaleV;
    }
  }
  return st;
}

}  // namespace wf

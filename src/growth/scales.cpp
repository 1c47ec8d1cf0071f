#include "growth/scales.h"

#include "core/hash.h"
#include "core/numeric.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace wf {
namespace {

/// One scale before compaction: its four vertices (root, right, tip, left) and what they share.
struct ScaleSlot {
  glm::dvec3 position[4];
  glm::dvec3 normal[4];
  glm::dvec3 Su{0.0}, Sv{0.0}, Tu{0.0};
  glm::dvec2 uv{0.0};
  float intensity = 1.0f;
  bool valid = false;
};

constexpr int kMaxCellsPerAxis = 16384;
constexpr long long kMaxCells = 1LL << 24;

/// The scale rooted at (u, v); invalid when the root is degenerate or the kite has no extent.
ScaleSlot growScale(const Surface& surface, const ScaleParams& p, double u, double v,
                    double cellDu, double cellDv, std::uint64_t patch, std::uint64_t index) {
  ScaleSlot s;
  const SurfaceFrame f = surface.frame(u, v);
  if (f.degenerate || !finite3(f.P)) return s;
  const double length = p.size * glm::length(f.Su) * std::fabs(cellDu);
  const double width = p.size * glm::length(f.Sv) * std::fabs(cellDv);
  if (!(length > 0.0) || !(width > 0.0) || !std::isfinite(length) || !std::isfinite(width)) return s;

  const glm::dvec3 axis = length * f.Tu + p.lift * length * f.N;  // root to tip
  const glm::dvec3 side = 0.5 * width * f.Tv;
  const glm::dvec3 shoulder = f.P + p.shoulder * axis;
  s.position[0] = f.P;
  s.position[1] = shoulder - side;
  s.position[2] = f.P + axis;
  s.position[3] = shoulder + side;

  // The kite's plane normal (facing +N), and the outward directions in its plane: along the
  // axis for root and tip, across it for the sides (Tv made perpendicular to the axis).
  const glm::dvec3 a = glm::normalize(axis);
  glm::dvec3 across = f.Tv - glm::dot(f.Tv, a) * a;
  glm::dvec3 plane = glm::cross(a, across);
  if (!(glm::length(across) > 1e-12) || !(glm::length(plane) > 1e-12)) return s;
  across = glm::normalize(across);
  plane = glm::normalize(plane);
  if (glm::dot(plane, f.N) < 0.0) plane = -plane;
  const glm::dvec3 outward[4] = {-a, -across, a, across};
  for (int k = 0; k < 4; ++k) s.normal[k] = glm::normalize(plane + p.deflection * outward[k]);

  HashRandom random(p.seed, patch, index);
  s.intensity = float(std::max(0.0, 1.0 + p.intensityVariation * (2.0 * random.next() - 1.0)));
  s.Su = f.Su;
  s.Sv = f.Sv;
  s.Tu = f.Tu;
  s.uv = {u, v};
  for (int k = 0; k < 4; ++k)
    if (!finite3(s.position[k]) || !finite3(s.normal[k])) return s;
  s.valid = true;
  return s;
}

}  // namespace

std::string ScaleParams::problem() const {
  std::ostringstream out;
  auto inRange = [](double x, double lo, double hi) { return std::isfinite(x) && x >= lo && x <= hi; };
  if (cellsU < 1 || cellsU > kMaxCellsPerAxis)
    out << "cellsU must be in [1, " << kMaxCellsPerAxis << "] (got " << cellsU << ")";
  else if (cellsV < 1 || cellsV > kMaxCellsPerAxis)
    out << "cellsV must be in [1, " << kMaxCellsPerAxis << "] (got " << cellsV << ")";
  else if ((long long)cellsU * cellsV > kMaxCells)
    out << "cellsU * cellsV must be at most " << kMaxCells << " (got " << (long long)cellsU * cellsV
        << ")";
  else if (!inRange(size, 0.0, 16.0) || size == 0.0)
    out << "size must be in (0, 16] (got " << size << ")";
  else if (!inRange(lift, 0.0, 16.0))
    out << "lift must be in [0, 16] (got " << lift << ")";
  else if (!inRange(deflection, 0.0, 16.0))
    out << "deflection must be in [0, 16] (got " << deflection << ")";
  else if (!(maxTriangles >= 0.0))
    out << "maxTriangles must be >= 0 (got " << maxTriangles << ")";
  else if (!inRange(intensityVariation, 0.0, 1.0))
    out << "intensityVariation must be in [0, 1] (got " << intensityVariation << ")";
  else if (!inRange(shoulder, 0.0, 1.0) || shoulder == 0.0 || shoulder == 1.0)
    out << "shoulder must be in (0, 1) (got " << shoulder << ")";
  else if (!inRange(colour.x, 0.0, 1e30) || !inRange(colour.y, 0.0, 1e30) ||
           !inRange(colour.z, 0.0, 1e30))
    out << "colour must be finite and non-negative (got " << colour.x << ", " << colour.y << ", "
        << colour.z << ")";
  return out.str();
}

TriangleMesh growScales(const Surface& surface, const ScaleParams& params,
                        std::uint32_t patchIndex) {
  if (const std::string why = params.problem(); !why.empty()) throw std::invalid_argument(why);
  const ParameterDomain d = surface.domain();
  const int nu = params.cellsU, nv = params.cellsV;
  const double cellDu = d.du() / nu, cellDv = d.dv() / nv;
  if (4.0 * double(nu) * double(nv) > params.maxTriangles)
    throw std::length_error("scales on " + surface.describe() + ": " + std::to_string(4LL * nu * nv) +
                            " triangles would exceed the limit of " +
                            std::to_string((long long)params.maxTriangles) + "; lower the cells");

  // Fixed slots: cell c = j nu + i holds scales 2c (corner) and 2c + 1 (centre), so every
  // thread writes its own slots and the result does not depend on the schedule.
  std::vector<ScaleSlot> slots(size_t(nu) * size_t(nv) * 2);
  tbb::parallel_for(tbb::blocked_range<int>(0, nv), [&](const tbb::blocked_range<int>& rows) {
    for (int j = rows.begin(); j != rows.end(); ++j)
      for (int i = 0; i < nu; ++i) {
        const size_t c = size_t(j) * size_t(nu) + size_t(i);
        const glm::dvec2 cornerSt(double(i) / nu, double(j) / nv), centreSt((i + 0.5) / nu, (j + 0.5) / nv);
        const glm::dvec2 corner = d.fromUnit(cornerSt.x, cornerSt.y);
        const glm::dvec2 centre = d.fromUnit(centreSt.x, centreSt.y);
        auto inside = [&](const glm::dvec2& st, const glm::dvec2& uv) {
          return (!params.mask || params.mask->value(st) >= 0.5) && (!params.rootFilter || params.rootFilter(uv));
        };
        if (inside(cornerSt, corner))
          slots[2 * c] = growScale(surface, params, corner.x, corner.y, cellDu, cellDv, patchIndex, 2 * c);
        if (inside(centreSt, centre))
          slots[2 * c + 1] = growScale(surface, params, centre.x, centre.y, cellDu, cellDv, patchIndex, 2 * c + 1);
      }
  });

  size_t valid = 0;
  for (const ScaleSlot& s : slots) valid += s.valid ? 1 : 0;
  TriangleMesh mesh;
  mesh.positions.reserve(4 * valid);
  mesh.normals.reserve(4 * valid);
  mesh.tangents.reserve(4 * valid);
  mesh.derivU.reserve(4 * valid);
  mesh.derivV.reserve(4 * valid);
  mesh.uvs.reserve(4 * valid);
  mesh.colours.reserve(4 * valid);
  mesh.triangles.reserve(2 * valid);
  const bool flip = surface.normalSign() < 0;
  for (const ScaleSlot& s : slots) {
    if (!s.valid) continue;
    const auto base = std::uint32_t(mesh.positions.size());
    const glm::vec3 colour = params.colour * s.intensity;
    for (int k = 0; k < 4; ++k) {
      mesh.positions.push_back(s.position[k]);
      mesh.normals.push_back(s.normal[k]);
      mesh.tangents.push_back(s.Tu);
      mesh.derivU.push_back(s.Su);
      mesh.derivV.push_back(s.Sv);
      mesh.uvs.push_back(s.uv);
      mesh.colours.push_back(colour);
    }
    if (flip) {  // a mirrored placement: wound about its front normal, -(Su x Sv)
      mesh.triangles.push_back({base, base + 2, base + 1});
      mesh.triangles.push_back({base, base + 3, base + 2});
    } else {
      mesh.triangles.push_back({base, base + 1, base + 2});
      mesh.triangles.push_back({base, base + 2, base + 3});
    }
  }
  return mesh;
}

}  // namespace wf

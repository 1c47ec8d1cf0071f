#include "render/view_tables.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace wf {

namespace {

// The rotation taking unit vector v to +z about the axis v x z (identity when v is +z).
glm::dmat3 rotationToZ(const glm::dvec3& v) {
  const glm::dvec3 z(0.0, 0.0, 1.0);
  const glm::dvec3 axis = glm::cross(v, z);
  const double s = glm::length(axis), c = glm::dot(v, z);
  if (!(s > 1e-15)) return glm::dmat3(1.0);
  const glm::dvec3 k = axis / s;
  const glm::dmat3 K(glm::dvec3(0, k.z, -k.y), glm::dvec3(-k.z, 0, k.x), glm::dvec3(k.y, -k.x, 0));  // columns
  return glm::dmat3(1.0) + s * K + (1.0 - c) * (K * K);
}

}  // namespace

ViewGrid::ViewGrid(const ViewTransform& view, int n)
    : n_(view.perspective ? std::clamp(n, 1, 16) : 1), width_(view.width), height_(view.height) {
  frames_.resize(size_t(n_) * size_t(n_));
  for (int j = 0; j < n_; ++j)
    for (int i = 0; i < n_; ++i) {
      // Nodes at the centres of an n x n partition of the image (n = 1: the image centre).
      const double x = width_ * (i + 0.5) / n_, y = height_ * (j + 0.5) / n_;
      frames_[size_t(j) * size_t(n_) + size_t(i)] = rotationToZ(view.viewVector(view.eyePoint(x, y, 1.0)));
    }
}

void ViewGrid::corners(double x, double y, int node[4], double weight[4]) const {
  if (n_ == 1) {
    node[0] = node[1] = node[2] = node[3] = 0;
    weight[0] = 1.0;
    weight[1] = weight[2] = weight[3] = 0.0;
    return;
  }
  auto axis = [&](double p, double extent, int& i0, double& t) {
    // Bilinear between cell centres; beyond the outer centres the nearest table holds.
    const double u = std::isfinite(p) ? std::clamp(p / extent * n_ - 0.5, 0.0, double(n_ - 1)) : 0.0;
    i0 = std::min(int(u), n_ - 2);
    t = u - i0;
  };
  int i0, j0;
  double tx, ty;
  axis(x, width_, i0, tx);
  axis(y, height_, j0, ty);
  node[0] = j0 * n_ + i0;
  node[1] = node[0] + 1;
  node[2] = node[0] + n_;
  node[3] = node[2] + 1;
  weight[0] = (1 - tx) * (1 - ty);
  weight[1] = tx * (1 - ty);
  weight[2] = (1 - tx) * ty;
  weight[3] = tx * ty;
}

WireTables::WireTables(const ViewGrid& grid, const PhongMaterial& m, const LightRig& eyeLights,
                       const PseudoReflectanceMapOptions& options)
    : grid_(&grid), maps_(size_t(grid.nodes())) {
  // Each map is itself built in parallel; the nodes one after another keep that simple.
  for (int k = 0; k < grid.nodes(); ++k)
    maps_[size_t(k)].build(m, eyeLights.transformed(grid.frameFromEye(k)).canonical(), options);
}

glm::vec3 WireTables::lookup(const glm::dvec3& T, double x, double y) const {
  int node[4];
  double w[4];
  grid_->corners(x, y, node, w);
  glm::vec3 sum(0.0f);
  for (int c = 0; c < 4; ++c)
    if (w[c] > 0.0) sum += float(w[c]) * maps_[size_t(node[c])].lookup(grid_->frameFromEye(node[c]) * T);
  return sum;
}

size_t WireTables::bytes() const {
  size_t b = 0;
  for (const PseudoReflectanceMap& m : maps_) b += m.bytes();
  return b;
}

SurfaceTables SurfaceTables::phong(const ViewGrid& grid, int resolution, const PhongMaterial& m,
                                   const LightRig& eyeLights) {
  SurfaceTables t;
  t.grid_ = &grid;
  for (int k = 0; k < grid.nodes(); ++k)
    t.spheres_.push_back(ReflectanceSphere::phong(resolution, m, eyeLights.transformed(grid.frameFromEye(k)).canonical()));
  return t;
}

SurfaceTables SurfaceTables::chrome(const ViewGrid& grid, int resolution, const EnvironmentMap& env,
                                    const glm::dvec3& reflectance) {
  SurfaceTables t;
  t.grid_ = &grid;
  for (int k = 0; k < grid.nodes(); ++k) {
    const glm::dmat3 eyeFromFrame = glm::transpose(grid.frameFromEye(k));
    t.spheres_.push_back(ReflectanceSphere::build(
        resolution,
        [&](const glm::dvec3& n) {
          const glm::dvec3 r = 2.0 * n.z * n - glm::dvec3(0.0, 0.0, 1.0);  // mirror of the node's view
          return reflectance * glm::dvec3(env.lookup(eyeFromFrame * r));
        },
        4));
  }
  return t;
}

glm::vec3 SurfaceTables::lookup(const glm::dvec3& N, double x, double y) const {
  int node[4];
  double w[4];
  grid_->corners(x, y, node, w);
  glm::vec3 sum(0.0f);
  for (int c = 0; c < 4; ++c)
    if (w[c] > 0.0) sum += float(w[c]) * spheres_[size_t(node[c])].lookup(grid_->frameFromEye(node[c]) * N);
  return sum;
}

size_t SurfaceTables::bytes() const {
  size_t b = 0;
  for (const ReflectanceSphere& s : spheres_) b += s.texels().size() * sizeof(glm::vec3);
  return b;
}

}  // namespace wf

// Shading tables for a grid of view directions: beyond the paper's orthographic assumption.
//
// A pseudo-reflectance map or reflectance sphere is built for one view direction (the paper: the
// view axis, V = +z). Under a perspective camera the true view vector turns by up to half the
// field of view across the image, and the shading with it (0.27 in radiance at the corners of a
// 30-degree image of specular wire). Here the image carries an n x n grid of nodes; each node has
// its own table, built in the frame where that node's view vector is +z (the lights rotated with
// it), and a fragment blends the four tables around it bilinearly by screen position, looking each
// up with its tangent (or normal) rotated into that node's frame. n = 1 is the paper's single
// orthographic table; the error against the exact path at the true view vector falls with n
// (`wirefur accuracy`, docs/abuffer.md), for n^2 times the build cost and four lookups.
#pragma once

#include "render/camera.h"
#include "shading/environment_map.h"
#include "shading/light.h"
#include "shading/phong.h"
#include "shading/pseudo_reflectance_map.h"
#include "shading/reflectance_sphere.h"

#include <glm/glm.hpp>

#include <vector>

namespace wf {

class ViewGrid {
 public:
  /// n x n nodes over the image of `view` (n = 1: one node, the view axis). An orthographic view
  /// has one view direction, so it always gets n = 1.
  ViewGrid(const ViewTransform& view, int n);
  int size() const { return n_; }
  int nodes() const { return n_ * n_; }
  /// Rotation taking eye-space vectors into node k's frame (its view vector to +z).
  const glm::dmat3& frameFromEye(int k) const { return frames_[size_t(k)]; }
  /// The same nodes and frames (tables built for one serve the other bit for bit). One node
  /// (the view axis) does not depend on the image size: the same grid for a reduced frame.
  bool sameAs(const ViewGrid& o) const {
    return n_ == o.n_ && (n_ == 1 || (width_ == o.width_ && height_ == o.height_)) && frames_ == o.frames_;
  }
  /// The four nodes around screen point (x, y) and their bilinear weights (some may be 0).
  void corners(double x, double y, int node[4], double weight[4]) const;

 private:
  int n_ = 1;
  double width_ = 1, height_ = 1;
  std::vector<glm::dmat3> frames_;
};

/// Pseudo-reflectance maps of one material for every node of a grid.
class WireTables {
 public:
  WireTables(const ViewGrid& grid, const PhongMaterial& m, const LightRig& eyeLights,
             const PseudoReflectanceMapOptions& options);
  /// Radiance of a wire with eye-space tangent T seen at screen point (x, y).
  glm::vec3 lookup(const glm::dvec3& T, double x, double y) const;
  int mapsBuilt() const { return int(maps_.size()); }
  size_t bytes() const;

 private:
  const ViewGrid* grid_;
  std::vector<PseudoReflectanceMap> maps_;
};

/// Reflectance spheres of one surface material (Phong or chrome) for every node of a grid.
class SurfaceTables {
 public:
  static SurfaceTables phong(const ViewGrid& grid, int resolution, const PhongMaterial& m,
                             const LightRig& eyeLights);
  /// Chrome: the environment (fixed to the viewer, eye space) seen by mirror reflection.
  static SurfaceTables chrome(const ViewGrid& grid, int resolution, const EnvironmentMap& env,
                              const glm::dvec3& reflectance);
  /// Radiance of a surface with eye-space unit normal N (facing the viewer) at screen (x, y).
  glm::vec3 lookup(const glm::dvec3& N, double x, double y) const;
  int spheresBuilt() const { return int(spheres_.size()); }
  size_t bytes() const;

 private:
  const ViewGrid* grid_ = nullptr;
  std::vector<ReflectanceSphere> spheres_;
};

}  // namespace wf

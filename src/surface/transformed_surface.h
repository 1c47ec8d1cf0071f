// A surface under an affine map x -> A x + t: S' = A S + t, Su' = A Su, Sv' = A Sv. Fur and
// scales grow on the placed surface (normals, lengths and densities in world units, correct
// under non-uniform scale and mirroring), not on the model and then moved. Coordinates pass
// through A as given: a singular A gives a degenerate surface, which frame() handles.
#pragma once

#include "surface/surface.h"

#include <glm/glm.hpp>

#include <memory>
#include <string>

namespace wf {

class TransformedSurface final : public Surface {
 public:
  TransformedSurface(std::shared_ptr<const Surface> base, const glm::dmat4& M)
      : base_(std::move(base)), A_(M), t_(M[3]), mirror_(glm::determinant(A_) < 0) {}
  ParameterDomain domain() const override { return base_->domain(); }
  /// A mirror (det A < 0) keeps (u, v) and turns the front normal round (normalSign), so that
  /// fur leaning along Su, scales pointing along Su and textures come out as the mirror image.
  SurfacePoint evaluate(double u, double v) const override {
    const SurfacePoint p = base_->evaluate(u, v);
    return {A_ * p.P + t_, A_ * p.Su, A_ * p.Sv};
  }
  double normalSign() const override { return mirror_ ? -base_->normalSign() : base_->normalSign(); }
  std::vector<double> creasesV() const override { return base_->creasesV(); }
  std::string describe() const override { return base_->describe() + " (placed)"; }
  const Surface& base() const { return *base_; }

 private:
  std::shared_ptr<const Surface> base_;
  glm::dmat3 A_;
  glm::dvec3 t_;
  bool mirror_;
};

}  // namespace wf

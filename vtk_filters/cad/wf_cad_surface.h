// An OpenCASCADE face as the core's one surface concept (src/surface/surface.h): S, Su and Sv
// from the face's own surface (BRepAdaptor_Surface, the face's location included) over the face's
// (u, v) bounds, and the normal sign of the face: REVERSED xor a mirroring location. Private to
// the WireFur::CAD module.
#pragma once

#include "surface/surface.h"
#include "texture/texture.h"

#include <BRepTopAdaptor_FClass2d.hxx>

#include <BRepAdaptor_Surface.hxx>
#include <TopoDS_Face.hxx>

#include <tbb/enumerable_thread_specific.h>

#include <memory>

namespace wfcad {

class FaceSurface final : public wf::Surface {
 public:
  explicit FaceSurface(const TopoDS_Face& face);
  wf::ParameterDomain domain() const override { return domain_; }
  /// Clamped to the face's (u, v) bounds. Each thread evaluates through an adaptor of its own
  /// (made on its first call): OpenCASCADE's B-spline evaluation keeps a cache in the adaptor, so
  /// one adaptor must not serve two threads at once.
  wf::SurfacePoint evaluate(double u, double v) const override;
  std::string describe() const override;
  double normalSign() const override { return sign_; }

 private:
  TopoDS_Face face_;
  BRepAdaptor_Surface adaptor_;  // for the constructor's questions and describe()
  wf::ParameterDomain domain_;
  double sign_ = 1.0;
  mutable tbb::enumerable_thread_specific<std::unique_ptr<BRepAdaptor_Surface>> perThread_;
};

/// A face's trimming as a texture over its unit (s, t) square (the FaceSurface's domain): 1 where
/// (u, v) is on the face (inside its wires, or on them), 0 where trimmed away. A classifier per
/// thread, like FaceSurface's adaptors. Its gradient is 0 (a mask, not a height).
class FaceMask final : public wf::ScalarTexture {
 public:
  FaceMask(const TopoDS_Face& face, const wf::ParameterDomain& domain);
  double value(const glm::dvec2& st) const override;
  glm::dvec2 gradient(const glm::dvec2&) const override { return glm::dvec2(0.0); }
  std::string describe() const override { return "CAD face trimming mask"; }

 private:
  TopoDS_Face face_;
  double tolerance_;
  wf::ParameterDomain domain_;
  mutable tbb::enumerable_thread_specific<std::unique_ptr<BRepTopAdaptor_FClass2d>> perThread_;
};

}  // namespace wfcad

#include "wf_cad_surface.h"

#include <BRepTools.hxx>
#include <GeomAbs_SurfaceType.hxx>
#include <TopAbs_Orientation.hxx>
#include <gp_Pnt.hxx>
#include <gp_Pnt2d.hxx>
#include <gp_Vec.hxx>

#include <algorithm>
#include <cmath>

namespace wfcad {

namespace {
glm::dvec3 toGlm(const gp_XYZ& p) { return {p.X(), p.Y(), p.Z()}; }
}  // namespace

FaceSurface::FaceSurface(const TopoDS_Face& face) : face_(face), adaptor_(face, Standard_False) {
  double u0 = 0, u1 = 1, v0 = 0, v1 = 1;
  BRepTools::UVBounds(face, u0, u1, v0, v1);
  if (!(std::isfinite(u0) && std::isfinite(u1) && u1 >= u0)) u0 = adaptor_.FirstUParameter(), u1 = adaptor_.LastUParameter();
  if (!(std::isfinite(v0) && std::isfinite(v1) && v1 >= v0)) v0 = adaptor_.FirstVParameter(), v1 = adaptor_.LastVParameter();
  // An unbounded face (no trimming) keeps a finite window.
  auto finiteOr = [](double x, double fallback) { return std::isfinite(x) && std::abs(x) < 1e100 ? x : fallback; };
  domain_.u0 = finiteOr(u0, -1e6), domain_.u1 = finiteOr(u1, 1e6);
  domain_.v0 = finiteOr(v0, -1e6), domain_.v1 = finiteOr(v1, 1e6);
  const double eps = 1e-9;
  domain_.periodicU = adaptor_.IsUPeriodic() && std::abs(domain_.du() - adaptor_.UPeriod()) <= eps * adaptor_.UPeriod();
  domain_.periodicV = adaptor_.IsVPeriodic() && std::abs(domain_.dv() - adaptor_.VPeriod()) <= eps * adaptor_.VPeriod();
  const bool reversed = face.Orientation() == TopAbs_REVERSED;
  const bool mirrored = face.Location().Transformation().IsNegative();
  sign_ = (reversed != mirrored) ? -1.0 : 1.0;
}

wf::SurfacePoint FaceSurface::evaluate(double u, double v) const {
  wf::SurfacePoint s;
  if (!std::isfinite(u) || !std::isfinite(v)) {
    s.P = s.Su = s.Sv = glm::dvec3(std::nan(""));
    return s;
  }
  u = std::clamp(u, domain_.u0, domain_.u1);
  v = std::clamp(v, domain_.v0, domain_.v1);
  std::unique_ptr<BRepAdaptor_Surface>& mine = perThread_.local();
  if (!mine) mine = std::make_unique<BRepAdaptor_Surface>(face_, Standard_False);
  gp_Pnt p;
  gp_Vec du, dv;
  mine->D1(u, v, p, du, dv);
  s.P = toGlm(p.XYZ());
  s.Su = toGlm(du.XYZ());
  s.Sv = toGlm(dv.XYZ());
  return s;
}

std::string FaceSurface::describe() const {
  static const char* names[] = {"plane", "cylinder", "cone", "sphere", "torus", "Bezier surface", "B-spline surface",
                                "surface of revolution", "surface of extrusion", "offset surface", "other surface"};
  const int t = int(adaptor_.GetType());
  return std::string("CAD face (") + (t >= 0 && t <= 10 ? names[t] : "surface") + ")";
}

FaceMask::FaceMask(const TopoDS_Face& face, const wf::ParameterDomain& domain)
    : face_(face), tolerance_(1e-9 * std::max({1.0, std::abs(domain.du()), std::abs(domain.dv())})), domain_(domain) {}

double FaceMask::value(const glm::dvec2& st) const {
  if (!std::isfinite(st.x) || !std::isfinite(st.y)) return 0.0;
  const glm::dvec2 uv = domain_.fromUnit(std::clamp(st.x, 0.0, 1.0), std::clamp(st.y, 0.0, 1.0));
  std::unique_ptr<BRepTopAdaptor_FClass2d>& mine = perThread_.local();
  if (!mine) mine = std::make_unique<BRepTopAdaptor_FClass2d>(face_, tolerance_);
  const TopAbs_State s = mine->Perform(gp_Pnt2d(uv.x, uv.y));
  return s == TopAbs_IN || s == TopAbs_ON ? 1.0 : 0.0;
}

}  // namespace wfcad

// Shading of surface fragments: Phong and chrome through reflectance spheres (or exactly),
// burnished metal through the pseudo-reflectance map by the eye-space grain tangent (paper §2.2),
// with colour maps, bump maps and groove textures over (u, v) (paper §4.1).
//
// Radiance = g (t D + S) c, where D and S are the diffuse (with ambient) and specular parts of the
// model, t the colour map, g the groove intensity (the paper modulates both parts by it) and c
// the mesh's vertex colour. Without a colour map D + S comes from one table lookup; with one the
// material's tables are built in two parts (ShaderSlot::split). Chrome has no diffuse part: the
// colour map and the grooves multiply the reflection.
//
// Pixel footprints: the A-buffer shades a fragment once, so a texture or groove pattern finer
// than a pixel is box-filtered over the (u, v) (or groove-coordinate) footprint of one pixel,
// found by moving the eye point one pixel in x and in y on the triangle's plane. The reference
// renderer point-samples instead and averages its sub-samples.
#include "render/pipeline.h"

#include "core/fast_atan2.h"
#include "core/numeric.h"

#include "shading/cylinder_lobe.h"
#include "texture/bump.h"
#include "texture/grooves.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace wf {

namespace {

glm::dvec3 perpendicularByCross(const glm::dvec3& n) {
  const glm::dvec3 a = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  return glm::normalize(glm::cross(n, a));
}

// Unit tangent t made orthogonal to unit N; a perpendicular of N when t is (nearly) along it or
// not finite.
glm::dvec3 tangentOff(const glm::dvec3& t, const glm::dvec3& N) {
  const glm::dvec3 p = t - glm::dot(t, N) * N;
  const double l = glm::length(p);
  return (l > 1e-12 && std::isfinite(l)) ? p / l : perpendicularByCross(N);
}

// The radial offset of eye point P from the grain axis (eye space).
glm::dvec3 radialOffset(const ShaderSlot& slot, const glm::dvec3& P) {
  const glm::dvec3 d = P - slot.axisPoint;
  return d - glm::dot(d, slot.axisDirection) * slot.axisDirection;
}

// Turn about the grain axis, in [0, 1).
double turnAbout(const ShaderSlot& slot, const glm::dvec3& P) {
  const glm::dvec3 r = radialOffset(slot, P);
  const glm::dvec3 e1 = perpendicularByCross(slot.axisDirection);
  const glm::dvec3 e2 = glm::cross(slot.axisDirection, e1);
  const double a = fastAtan2(glm::dot(r, e2), glm::dot(r, e1)) / kTwoPi;
  return a < 0 ? a + 1.0 : a;
}

// The groove coordinate (see Burnish::grooves) at eye point P with surface (u, v).
double grooveCoordinate(const ShaderSlot& slot, Burnish::Grain grain, const glm::dvec3& P, const glm::dvec2& uv) {
  switch (grain) {
    case Burnish::Grain::U: return uv.y;
    case Burnish::Grain::V: return uv.x;
    case Burnish::Grain::Radial: return turnAbout(slot, P);
    case Burnish::Grain::Circular: return glm::length(radialOffset(slot, P));
    case Burnish::Grain::None: break;
  }
  return 0.0;
}

struct Footprint {
  bool valid = false;      ///< Px, Py hold the neighbours
  bool unbounded = false;  ///< the plane reaches the horizon within a pixel: filter to the mean
  glm::dvec3 Px{0.0}, Py{0.0};  ///< eye points one pixel away in x and in y on the plane
};

// The eye points one pixel to the right and one down on the primitive's plane (one to the left
// or up where that one is beyond the horizon: the box filter only needs the distances).
Footprint footprintOf(const PreparedScene& ps, const TrianglePrim& prim, double x, double y) {
  Footprint f;
  auto neighbour = [&](double dx, double dy, glm::dvec3& out) {
    for (double sgn : {1.0, -1.0}) {
      const double d = ps.view.depthFromKey(prim.depthKeyAt(x + sgn * dx, y + sgn * dy));
      if (std::isfinite(d)) {
        out = ps.view.eyePoint(x + sgn * dx, y + sgn * dy, d);
        if (std::isfinite(out.x + out.y + out.z)) return true;
      }
    }
    return false;
  };
  if (neighbour(1.0, 0.0, f.Px) && neighbour(0.0, 1.0, f.Py)) f.valid = true;
  else f.unbounded = true;
  return f;
}

// The exact path's diffuse and specular parts: `model` of the whole material into D (S = 0), or,
// when a colour map splits the material, of its diffuse and its specular part.
template <class Model>
void exactParts(const ShaderSlot& slot, Model&& model, glm::dvec3& D, glm::dvec3& S) {
  if (!slot.split) {
    D = model(slot.phong);
    return;
  }
  PhongMaterial d = slot.phong, s = slot.phong;
  d.specular = glm::dvec3(0.0);
  s.diffuse = glm::dvec3(0.0);
  D = model(d);
  S = model(s);
}

// A texture's box filter covers the axis-aligned box around the pixel's (u, v) parallelogram,
// which over-blurs a long, oblique footprint (a surface seen at a grazing angle). The footprint
// is cut into up to kMaxTextureTaps pieces along its longer side, each box-filtered, and the
// pieces averaged (anisotropic filtering). `wirefur accuracy` (textures) measures the effect.
constexpr int kMaxTextureTaps = 4;

glm::dvec3 anisotropicSample(const ColourTexture& tex, const glm::dvec2& uv, const UvFootprint& f) {
  const double lx = glm::length(f.dx), ly = glm::length(f.dy);
  const bool xMajor = lx >= ly;
  const double major = xMajor ? lx : ly, minor = xMajor ? ly : lx;
  int n = 1;
  if (major > 0 && std::isfinite(major))
    n = minor > 0 ? int(std::clamp(std::ceil(major / minor), 1.0, double(kMaxTextureTaps))) : kMaxTextureTaps;
  if (n == 1) return glm::dvec3(tex.sample(uv, f));
  UvFootprint piece = f;
  glm::dvec2& along = xMajor ? piece.dx : piece.dy;
  along /= double(n);
  glm::dvec3 sum(0.0);
  for (int i = 0; i < n; ++i) sum += glm::dvec3(tex.sample(uv + (i + 0.5 - 0.5 * n) * along, piece));
  return sum / double(n);
}

}  // namespace

glm::vec3 shadeSurfaceFragment(const PreparedScene& ps, std::uint32_t triangle, double x, double y,
                               const glm::dvec3& P, const glm::dvec3& V) {
  const TrianglePrim& prim = ps.triangles[triangle];
  const TriangleAttributes& ta = ps.triangleAttributes[triangle];
  const ShaderSlot& slot = ps.shaders[prim.shader];
  const SurfaceSample sample = interpolateTriangle(ps, ta, P, V, slot.needsUv, slot.needsDerivatives);
  glm::dvec3 N = sample.normal;
  const glm::vec3 c = sample.colour;
  const bool maps = ps.path == ShadingPath::Maps;
  const Material* mat = slot.material;
  if (!mat || (!slot.variesInPixel && slot.kind != ShaderSlot::Kind::SurfaceBurnished)) {
    // Untextured, isotropic: one lookup by the normal.
    if (maps && slot.surfaceTables) return slot.surfaceTables->lookup(N, x, y) * c;
    if (slot.kind == ShaderSlot::Kind::SurfaceChrome) {
      const EnvironmentMap& env = ps.scene->environment ? *ps.scene->environment : defaultEnvironment();
      return glm::vec3(chromeRadiance(env, slot.chromeReflectance, N, V)) * c;
    }
    return glm::vec3(phongRadianceSanitized(N, V, slot.phong, ps.eyeLights)) * c;
  }

  // The pixel's footprint, only when a filtered lookup needs it.
  const Burnish::Grain grain = mat->burnish.grain;
  const bool grooves = mat->burnish.grooves && grain != Burnish::Grain::None;
  Footprint fp;
  if (ps.filterTextures && (mat->colourMap || grooves)) fp = footprintOf(ps, prim, x, y);
  glm::dvec2 uvx = sample.uv, uvy = sample.uv;
  if (fp.valid && slot.needsUv) uvx = uvOnPlane(ps, ta, fp.Px), uvy = uvOnPlane(ps, ta, fp.Py);

  // Bump map (Blinn): perturb the normal by the height's gradient; the outline stays smooth.
  // The height displaces along the surface's own front normal, whichever side is seen: bump the
  // unflipped normal and turn the result to the viewer after.
  if (mat->bumpMap) {
    const glm::dvec2 g = mat->bumpMap->gradient(sample.uv);
    const double side = sample.flipped ? -1.0 : 1.0;
    glm::dvec3 Nb = side * bumpNormal(side * N, sample.derivU, sample.derivV, g, mat->bumpScale);
    // A bumped normal never faces away from the viewer (it would look up the far hemisphere).
    const double nv = glm::dot(Nb, V);
    if (nv < 1e-3) Nb = glm::normalize(Nb + (1e-3 - nv) * V);
    if (std::isfinite(Nb.x + Nb.y + Nb.z)) N = Nb;
  }

  // Groove intensity, box-filtered over the footprint in the groove coordinate.
  double g = 1.0;
  if (grooves) {
    const double c0 = grooveCoordinate(slot, grain, P, sample.uv);
    double width = 0.0;
    if (fp.valid) {
      double cx = grooveCoordinate(slot, grain, fp.Px, uvx) - c0;
      double cy = grooveCoordinate(slot, grain, fp.Py, uvy) - c0;
      if (grain == Burnish::Grain::Radial) {  // the turn wraps at 1
        cx -= std::round(cx);
        cy -= std::round(cy);
      }
      width = std::abs(cx) + std::abs(cy);
      if (!std::isfinite(width)) width = INFINITY;
    } else if (fp.unbounded) {
      width = INFINITY;  // the groove texture's mean
    }
    g = mat->burnish.grooves->intensity(c0, width);
  }

  // Colour map, box-filtered over the (u, v) footprint.
  glm::dvec3 t(1.0);
  if (mat->colourMap) {
    UvFootprint f;
    if (fp.valid) f.dx = uvx - sample.uv, f.dy = uvy - sample.uv;
    if (fp.unbounded || !std::isfinite(f.dx.x + f.dx.y + f.dy.x + f.dy.y)) f.dx = f.dy = glm::dvec2(INFINITY);
    t = anisotropicSample(*mat->colourMap, sample.uv, f);
  }

  glm::dvec3 D(0.0), S(0.0);
  if (slot.kind == ShaderSlot::Kind::SurfaceBurnished) {
    // The grain tangent, in the surface's tangent plane.
    glm::dvec3 T(0.0);
    switch (grain) {
      case Burnish::Grain::U: T = sample.derivU; break;
      case Burnish::Grain::V: T = sample.derivV; break;
      case Burnish::Grain::Radial: T = radialOffset(slot, P); break;
      case Burnish::Grain::Circular: T = glm::cross(slot.axisDirection, radialOffset(slot, P)); break;
      case Burnish::Grain::None: break;
    }
    T = tangentOff(T, N);
    if (maps && slot.wireTables) {
      D = glm::dvec3(slot.wireTables->lookup(T, x, y));
      if (slot.split && slot.wireSpecular) S = glm::dvec3(slot.wireSpecular->lookup(T, x, y));
    } else {
      exactParts(slot, [&](const PhongMaterial& m) { return cylinderRadianceClosedSanitized(T, V, m, ps.eyeLights, slot.lobe.get()); }, D, S);
    }
  } else if (slot.kind == ShaderSlot::Kind::SurfaceChrome) {
    if (maps && slot.surfaceTables) {
      D = glm::dvec3(slot.surfaceTables->lookup(N, x, y));
    } else {
      const EnvironmentMap& env = ps.scene->environment ? *ps.scene->environment : defaultEnvironment();
      D = chromeRadiance(env, slot.chromeReflectance, N, V);
    }
  } else {
    if (maps && slot.surfaceTables) {
      D = glm::dvec3(slot.surfaceTables->lookup(N, x, y));
      if (slot.split && slot.surfaceSpecular) S = glm::dvec3(slot.surfaceSpecular->lookup(N, x, y));
    } else {
      exactParts(slot, [&](const PhongMaterial& m) { return phongRadianceSanitized(N, V, m, ps.eyeLights); }, D, S);
    }
  }
  const glm::dvec3 L = g * (t * D + S);
  return glm::vec3(L) * c;
}

}  // namespace wf

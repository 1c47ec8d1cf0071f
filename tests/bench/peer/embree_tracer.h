// The ray-cast peer of issue 7: Embree 3 (Debian's libembree-dev) casting primary rays through the
// same screen set-up as the A-buffer (prepareScene: the same camera, clipping and eye-space
// geometry), triangles as Embree triangles and every wire segment as a round linear curve of
// the segment's own radius (RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE: a cone between two spheres,
// the true cylinder the A-buffer's polygon stands for). n x n stratified (jittered) rays per
// pixel, box-filtered. Each primitive seen in a pixel is shaded once, at the mean of its hits
// there, by the same shading code as the A-buffer (shadeFragment: the pseudo-reflectance map or
// the exact cylinder integral, by RenderOptions::shading); primitives whose shading varies inside
// a pixel (textures, grooves, bumps) are shaded at every hit. This is how the brute-force reference
// (renderReference) shades too, so the ray caster differs from it only in how it finds what a
// sample sees: the true cylinder instead of the screen polygon.
//
// Opaque primitives only: a translucent one is drawn opaque and counted in `translucent`.
// Embree is a benchmark reference here and never part of the product (docs/benchmarks.md).
#pragma once

#include "core/image.h"
#include "render/renderer.h"
#include "render/scene.h"

#include <cstddef>
#include <cstdint>

namespace wfbench {

struct EmbreeOptions {
  int samples = 2;             ///< n: n x n stratified rays per pixel
  std::uint64_t seed = 1;      ///< jitter of the strata
  bool coverageOnly = false;   ///< no shading: white where hit (the coverage is the alpha)
  bool curvesOnly = false;     ///< leave the triangles out (the wires alone)
};

struct EmbreeResult {
  wf::ImageRGBA image;         ///< premultiplied linear RGBA over the scene's background
  double secondsPrepare = 0;   ///< prepareScene: camera, lights, shading tables, eye-space geometry
  double secondsBuild = 0;     ///< Embree geometry and BVH
  double secondsTrace = 0;     ///< rays, shading, compositing
  double secondsTotal = 0;
  std::size_t triangles = 0, curves = 0, rays = 0, translucent = 0;
  std::size_t embreeBytes = 0; ///< peak bytes Embree allocated (its memory monitor)
};

/// Renders `scene` with options.width x options.height, options.threads, options.shading (and the
/// map options for the map path).
EmbreeResult renderEmbree(const wf::Scene& scene, const wf::RenderOptions& options, const EmbreeOptions& eo);

}  // namespace wfbench

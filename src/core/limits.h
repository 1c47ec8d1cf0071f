// Limits that several places check (the renderer, the table builders, scene files, the command
// line): one named constant each, so that every entry point accepts the same values.
// Header only, no dependencies. The VTK modules' public headers (vtkWireFurRenderPass.h,
// vtkWireFurCADReader.h) cannot include the core and repeat the budget, thread and iso-line
// limits in their clamp macros.
#pragma once

namespace wf {

/// Largest image side in pixels: RenderOptions::width / height (render/renderer.cpp), a scene's
/// image.size (apps/scene_file.cpp) and every command's --size.
inline constexpr int kMaxImageSide = 16384;

/// Largest fragment-list budget K (fragments kept exactly per pixel): RenderOptions::budget, the
/// tile A-buffer (abuffer/abuffer.cpp), a scene's image.budget and --budget.
inline constexpr int kMaxListBudget = 65535;

/// View-direction tables per side: RenderOptions::viewGrid, image.view_grid and --view-grid.
inline constexpr int kMaxViewGrid = 16;

/// Worker threads: RenderOptions::threads (0 there: all cores) and --threads.
inline constexpr int kMaxThreads = 1024;

/// Brute-force reference samples per pixel side: RenderOptions::referenceSamples and --samples.
inline constexpr int kMaxReferenceSamples = 64;

/// Reflectance-sphere nodes per side (RenderOptions::sphereResolution, ReflectanceSphere).
inline constexpr int kMinSphereResolution = 8;
inline constexpr int kMaxSphereResolution = 8192;

/// Pseudo-reflectance map texels per side and normals per texel (RenderOptions::map,
/// PseudoReflectanceMap).
inline constexpr int kMinMapResolution = 8;
inline constexpr int kMaxMapResolution = 4096;
inline constexpr int kMaxMapSamples = 65536;

/// Largest |time| of a fur's wind: a scene's wind.time and --time.
inline constexpr double kMaxWindTime = 1e9;

/// CAD tessellation (a scene's cad block and the CAD options of the command line): the chordal
/// deflection relative to the model's diagonal, the same in world units, the angular deflection
/// in degrees, and u and v iso lines per face.
inline constexpr double kMinCadDeflection = 1e-7;
inline constexpr double kMaxCadDeflection = 0.5;
inline constexpr double kMinCadLinearDeflection = 1e-12;
inline constexpr double kMaxCadLinearDeflection = 1e30;
inline constexpr double kMinCadAngularDegrees = 1.0;
inline constexpr double kMaxCadAngularDegrees = 85.0;
inline constexpr int kMaxCadIsos = 1000;

}  // namespace wf

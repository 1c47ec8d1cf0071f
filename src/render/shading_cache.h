// Shading tables kept from one frame to the next: the lobe tables of the closed path (one per
// exponent, render/renderer.h) as long as frames use them, and the map path's tables as follows.
// The pseudo-reflectance maps and reflectance
// spheres depend on the material, the lights in eye space, the table options and the view grid
// (render/view_tables.h), not on the geometry: when a viewer or a render pass draws frame after
// frame and none of those changed (a camera turning with lights fixed to it, or a still camera),
// the tables are taken from here instead of being rebuilt. The paper's own rule (§2.2): the map
// must be recomputed when the camera moves relative to the lights, and only then.
//
// Give the same cache to successive render() calls through RenderOptions::shadingCache. Tables
// not used by a frame are dropped at its end, so the cache holds one frame's tables. Safe to share
// between threads (a mutex), but a cache serves one sequence of frames best.
#pragma once

#include "render/view_tables.h"
#include "shading/cylinder_lobe.h"

#include <memory>
#include <mutex>
#include <vector>

namespace wf {

class ShadingCache {
 public:
  /// Tables for `grid` (compared by value; the cache keeps its own copy, which the tables use),
  /// built only when no table of the last frame matches. `built` says which happened.
  std::shared_ptr<WireTables> wire(const ViewGrid& grid, const PhongMaterial& m, const LightRig& eyeLights,
                                   const PseudoReflectanceMapOptions& options, bool& built);
  std::shared_ptr<SurfaceTables> phong(const ViewGrid& grid, int resolution, const PhongMaterial& m,
                                       const LightRig& eyeLights, bool& built);
  /// The cache holds `env` (so its address, the key, cannot be reused by another map).
  std::shared_ptr<SurfaceTables> chrome(const ViewGrid& grid, int resolution, std::shared_ptr<const EnvironmentMap> env,
                                        const glm::dvec3& reflectance, bool& built);
  /// The closed path's lobe table of an exponent (independent of lights and view: kept for as
  /// long as frames use it).
  std::shared_ptr<const CylinderLobeTable> lobe(double exponent, bool& built);
  /// A frame starts: every table counts as unused until asked for.
  void beginFrame();
  /// A frame ends: tables it did not ask for are dropped.
  void endFrame();
  size_t size() const;

 private:
  enum class Kind { Wire, Phong, Chrome };
  struct Entry {
    Kind kind;
    std::shared_ptr<const ViewGrid> grid;
    PhongMaterial material;
    LightRig lights;
    PseudoReflectanceMapOptions map;
    int resolution = 0;
    std::shared_ptr<const EnvironmentMap> environment;
    glm::dvec3 reflectance{0.0};
    std::shared_ptr<WireTables> wire;
    std::shared_ptr<SurfaceTables> surface;
    bool used = true;
  };
  Entry* find(Kind kind, const ViewGrid& grid, const PhongMaterial& m, const LightRig& lights,
              const PseudoReflectanceMapOptions& map, int resolution, const EnvironmentMap* env,
              const glm::dvec3& reflectance);
  std::shared_ptr<const ViewGrid> gridCopy(const ViewGrid& grid);
  mutable std::mutex mutex_;
  std::vector<Entry> entries_;
  struct LobeEntry {
    std::shared_ptr<const CylinderLobeTable> table;
    bool used = true;
  };
  std::vector<LobeEntry> lobes_;
};

}  // namespace wf

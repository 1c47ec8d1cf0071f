#include "render/shading_cache.h"

#include <algorithm>

namespace wf {

ShadingCache::Entry* ShadingCache::find(Kind kind, const ViewGrid& grid, const PhongMaterial& m, const LightRig& lights,
                                        const PseudoReflectanceMapOptions& map, int resolution,
                                        const EnvironmentMap* env, const glm::dvec3& reflectance) {
  for (Entry& e : entries_) {
    if (e.kind != kind || !e.grid->sameAs(grid)) continue;
    if (kind == Kind::Chrome) {
      if (e.environment.get() == env && e.reflectance == reflectance && e.resolution == resolution) return &e;
      continue;
    }
    if (!(e.material == m) || !e.lights.nearlyEqual(lights, 0.0)) continue;
    if (kind == Kind::Wire ? e.map == map : e.resolution == resolution) return &e;
  }
  return nullptr;
}

std::shared_ptr<const ViewGrid> ShadingCache::gridCopy(const ViewGrid& grid) {
  for (const Entry& e : entries_)
    if (e.grid->sameAs(grid)) return e.grid;
  return std::make_shared<const ViewGrid>(grid);
}

std::shared_ptr<WireTables> ShadingCache::wire(const ViewGrid& grid, const PhongMaterial& m, const LightRig& eyeLights,
                                               const PseudoReflectanceMapOptions& options, bool& built) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (Entry* e = find(Kind::Wire, grid, m, eyeLights, options, 0, nullptr, glm::dvec3(0.0))) {
    e->used = true;
    built = false;
    return e->wire;
  }
  Entry e{Kind::Wire, gridCopy(grid), m, eyeLights, options, 0, nullptr, glm::dvec3(0.0), nullptr, nullptr};
  e.wire = std::make_shared<WireTables>(*e.grid, m, eyeLights, options);
  entries_.push_back(e);
  built = true;
  return e.wire;
}

std::shared_ptr<SurfaceTables> ShadingCache::phong(const ViewGrid& grid, int resolution, const PhongMaterial& m,
                                                   const LightRig& eyeLights, bool& built) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (Entry* e = find(Kind::Phong, grid, m, eyeLights, {}, resolution, nullptr, glm::dvec3(0.0))) {
    e->used = true;
    built = false;
    return e->surface;
  }
  Entry e{Kind::Phong, gridCopy(grid), m, eyeLights, {}, resolution, nullptr, glm::dvec3(0.0), nullptr, nullptr};
  e.surface = std::make_shared<SurfaceTables>(SurfaceTables::phong(*e.grid, resolution, m, eyeLights));
  entries_.push_back(e);
  built = true;
  return e.surface;
}

std::shared_ptr<SurfaceTables> ShadingCache::chrome(const ViewGrid& grid, int resolution,
                                                    std::shared_ptr<const EnvironmentMap> env,
                                                    const glm::dvec3& reflectance, bool& built) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (Entry* e = find(Kind::Chrome, grid, {}, {}, {}, resolution, env.get(), reflectance)) {
    e->used = true;
    built = false;
    return e->surface;
  }
  Entry e{Kind::Chrome, gridCopy(grid), {}, {}, {}, resolution, env, reflectance, nullptr, nullptr};
  e.surface = std::make_shared<SurfaceTables>(SurfaceTables::chrome(*e.grid, resolution, *env, reflectance));
  entries_.push_back(e);
  built = true;
  return e.surface;
}

std::shared_ptr<const CylinderLobeTable> ShadingCache::lobe(double exponent, bool& built) {
  const double n = sanitizedExponent(exponent);
  std::lock_guard<std::mutex> lock(mutex_);
  for (LobeEntry& e : lobes_)
    if (e.table->exponent() == n) {
      e.used = true;
      built = false;
      return e.table;
    }
  lobes_.push_back({std::make_shared<const CylinderLobeTable>(n), true});
  built = true;
  return lobes_.back().table;
}

void ShadingCache::beginFrame() {
  std::lock_guard<std::mutex> lock(mutex_);
  for (Entry& e : entries_) e.used = false;
  for (LobeEntry& e : lobes_) e.used = false;
}

void ShadingCache::endFrame() {
  std::lock_guard<std::mutex> lock(mutex_);
  entries_.erase(std::remove_if(entries_.begin(), entries_.end(), [](const Entry& e) { return !e.used; }), entries_.end());
  lobes_.erase(std::remove_if(lobes_.begin(), lobes_.end(), [](const LobeEntry& e) { return !e.used; }), lobes_.end());
}

size_t ShadingCache::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return entries_.size() + lobes_.size();
}

}  // namespace wf

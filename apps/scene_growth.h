// Scene-file object keys "fur" and "scales": grown on the object's placed parametric surface.
#pragma once

#include "scene_reader.h"

#include "render/scene.h"
#include "surface/surface.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace wfapp {

struct GrowthContext {
  std::shared_ptr<const wf::Surface> surface;  ///< placed (world space); null for file objects
  std::uint32_t patch = 0;                     ///< the object's index: part of every hair's identity
  std::string name;
  std::optional<double> time;                  ///< overrides every fur's wind time (`--time`)
  SceneBudget* budget = nullptr;               ///< the scene's budget (required)
  std::string folder = ".";                    ///< where the scene's relative file names start
  /// Resolves a material name at a JSON pointer (fails the read when unknown).
  std::function<int(const json&, const std::string&)> material;
};

/// Reads `fur` and `scales` of object `obj` at `ptr` (if present) and adds the hairs (shaded
/// wires) and scales (a surface) to the scene.
void readGrowth(const Reader& r, const json& obj, const std::string& ptr, const GrowthContext& ctx, wf::Scene& scene);

}  // namespace wfapp

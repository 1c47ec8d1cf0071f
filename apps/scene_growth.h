// Scene-file object keys "fur" and "scales": what grows on the object's placed surface.
#pragma once

#include "scene_reader.h"

#include "scene/scene_description.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace wfapp {

struct GrowthContext {
  SceneBudget* budget = nullptr;               ///< the scene's budget of texels (required)
  std::string folder = ".";                    ///< where the scene's relative file names start
  /// Resolves a material name at a JSON pointer (fails the read when unknown).
  std::function<int(const json&, const std::string&)> material;
};

/// Reads `fur` and `scales` of object `obj` at `ptr` (if present) into the object's description;
/// buildScene (scene/scene_description.h) grows them.
void readGrowth(const Reader& r, const json& obj, const std::string& ptr, const GrowthContext& ctx, wf::ObjectDescription& object);

}  // namespace wfapp

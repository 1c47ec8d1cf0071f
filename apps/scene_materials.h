// Scene-file material keys beyond Phong and chrome: "burnish", "texture", "bump".
#pragma once

#include "scene_reader.h"

#include "render/scene.h"
#include "texture/textures.h"

#include <set>
#include <string>

namespace wfapp {

/// Fractal noise parameters (octaves, frequency, lacunarity, gain, seed, periodic) of object `j`
/// at `ptr`, for textures, bumps and fur maps; the caller checks which keys `j` may have.
wf::NoiseParams readNoiseParams(const Reader& r, const json& j, const std::string& ptr);

/// A colour texture (chequer, image, noise with a ramp: docs/scenes.md) at `ptr`; image files
/// relative to `folder`, decoded once per scene and counted in `budget`.
std::shared_ptr<const wf::ColourTexture> readColourTexture(const Reader& r, const json& j, const std::string& ptr,
                                                           const std::string& folder, SceneBudget& budget);

/// The keys readMaterialExtras reads.
const std::set<std::string>& materialExtraKeys();

/// Reads burnish (grain, axis, grooves), texture (chequer, image, noise with a colour ramp) and
/// bump (noise, image) of material `m` at JSON pointer `mp`; files relative to `folder`.
void readMaterialExtras(const Reader& r, const json& m, const std::string& mp, const std::string& folder,
                        SceneBudget& budget, wf::Material& mat);

}  // namespace wfapp

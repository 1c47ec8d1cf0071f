// Reading scene documents: values out of the JSON, each failure one line naming the file and the
// JSON pointer of the value. Shared by the scene loader's parts (scene_file.cpp: camera, lights,
// objects; scene_materials.cpp: materials, textures, burnish; scene_growth.cpp: fur, scales).
#pragma once

#include "cli.h"

#include "texture/texture.h"

#include <nlohmann/json.hpp>

#include <glm/glm.hpp>

#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>

namespace wfapp {

using json = nlohmann::json;

// Reads values out of the document, naming the JSON pointer of anything wrong.
struct Reader {
  std::string file;

  [[noreturn]] void fail(const std::string& ptr, const std::string& what) const {
    throw UsageError(file + ": " + (ptr.empty() ? std::string("/") : ptr) + ": " + what);
  }
  static std::string at(const std::string& ptr, const std::string& key) {
    std::string k;
    for (char c : key) k += c == '~' ? "~0" : (c == '/' ? "~1" : std::string(1, c));
    return ptr + "/" + k;
  }
  static std::string at(const std::string& ptr, size_t i) { return ptr + "/" + std::to_string(i); }

  void keys(const json& j, const std::string& ptr, const std::set<std::string>& allowed) const {
    if (!j.is_object()) fail(ptr, "expected an object");
    for (auto it = j.begin(); it != j.end(); ++it)
      if (!allowed.count(it.key())) {
        std::string list;
        for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
        fail(at(ptr, it.key()), "unknown key (expected one of: " + list + ")");
      }
  }
  double number(const json& j, const std::string& ptr, double lo, double hi) const {
    if (!j.is_number()) fail(ptr, "expected a number");
    const double v = j.get<double>();
    if (!std::isfinite(v) || v < lo || v > hi) {
      std::ostringstream s;
      s << "expected a number in [" << lo << ", " << hi << "], got " << j.dump();
      fail(ptr, s.str());
    }
    return v;
  }
  int integer(const json& j, const std::string& ptr, int lo, int hi) const {
    if (!j.is_number_integer()) fail(ptr, "expected an integer");
    const long long v = j.get<long long>();
    if (v < lo || v > hi) fail(ptr, "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return int(v);
  }
  std::string string(const json& j, const std::string& ptr) const {
    if (!j.is_string()) fail(ptr, "expected a string");
    return j.get<std::string>();
  }
  std::string choice(const json& j, const std::string& ptr, const std::set<std::string>& options) const {
    const std::string s = string(j, ptr);
    if (!options.count(s)) {
      std::string list;
      for (const std::string& o : options) list += (list.empty() ? "" : ", ") + o;
      fail(ptr, "'" + s + "' is not one of: " + list);
    }
    return s;
  }
  glm::dvec3 vec3(const json& j, const std::string& ptr, double bound = 1e12) const {
    if (!j.is_array() || j.size() != 3) fail(ptr, "expected [x, y, z]");
    return {number(j[0], at(ptr, 0), -bound, bound), number(j[1], at(ptr, 1), -bound, bound),
            number(j[2], at(ptr, 2), -bound, bound)};
  }
  /// A colour: [r, g, b] or one grey value, linear, >= 0.
  glm::dvec3 colour(const json& j, const std::string& ptr) const {
    if (j.is_number()) return glm::dvec3(number(j, ptr, 0, 1e6));
    if (!j.is_array() || j.size() != 3) fail(ptr, "expected a colour [r, g, b] or a number");
    return {number(j[0], at(ptr, 0), 0, 1e6), number(j[1], at(ptr, 1), 0, 1e6), number(j[2], at(ptr, 2), 0, 1e6)};
  }
  bool boolean(const json& j, const std::string& ptr) const {
    if (!j.is_boolean()) fail(ptr, "expected true or false");
    return j.get<bool>();
  }
};

// The most primitives one scene may make (SceneBudget::kMaxPrimitives). The fuzz targets
// (tests/fuzz) build with a smaller bound, so that a scene at the bound loads within libFuzzer's
// time and memory limits; nothing else sets it.
#ifndef WIREFUR_SCENE_MAX_PRIMITIVES
#define WIREFUR_SCENE_MAX_PRIMITIVES 8388608.0
#endif

/// What one scene may read: decoded texture texels (the primitives it makes are counted by the
/// core's buildScene against SceneDescription::maxPrimitives, set to kMaxPrimitives); and the
/// textures already decoded, shared by every material that names the same file.
struct SceneBudget {
  /// About 4 GB of renderer memory.
  static constexpr double kMaxPrimitives = WIREFUR_SCENE_MAX_PRIMITIVES;
  static constexpr double kMaxTexels = 33554432.0;     ///< about 1.2 GB of texture tables
  double texels = 0.0;
  std::map<std::string, std::shared_ptr<const wf::ColourTexture>> colourImages;
  std::map<std::string, std::shared_ptr<const wf::ScalarTexture>> heightImages;

  /// Counts a decoded image's texels; fails the read past the budget.
  void addTexels(const Reader& r, const std::string& ptr, double count) {
    if (!(texels + count <= kMaxTexels))
      r.fail(ptr, "the scene's images would hold more than " + std::to_string((long long)kMaxTexels) +
                      " texels in all (use smaller images)");
    texels += count;
  }
};

}  // namespace wfapp

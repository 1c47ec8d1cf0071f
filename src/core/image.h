// Linear-light float RGBA image: what every renderer in the core produces. Encoding to sRGB and
// writing files belongs to the apps layer.
#pragma once

#include "core/large_memory.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <vector>

namespace wf {

struct ImageRGBA {
  int width = 0, height = 0;
  /// Row-major, row 0 at the top. (On huge pages from kLargeAllocation, as a render's arrays: a large
  /// image's first writes cost a fault per 2 MiB, not per 4 KiB; core/large_memory.h.)
  std::vector<glm::vec4, LargeAllocator<glm::vec4>> pixels;

  ImageRGBA() = default;
  ImageRGBA(int w, int h) : width(w), height(h), pixels(size_t(w) * size_t(h), glm::vec4(0.0f)) {}
  glm::vec4& at(int x, int y) { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
  const glm::vec4& at(int x, int y) const { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
};

}  // namespace wf

// Fragments for the tile A-buffer's tests: Carpenter's 8x4 layout, its whole and half masks,
// and a flat fragment with a given depth, area, opacity, colour, mask and tag.
#pragma once

#include "abuffer/abuffer.h"

#include <glm/glm.hpp>

#include <cstdint>

namespace wf::test {

inline const MaskLayout kL{8, 4};                      // Carpenter's 8x4: 32 samples
inline constexpr MaskBits kFull = 0xFFFFFFFFull;       // all 32 samples
inline constexpr MaskBits kLeftHalf = 0x0F0F0F0Full;   // columns 0-3 of every row
inline constexpr MaskBits kRightHalf = 0xF0F0F0F0ull;  // columns 4-7 of every row
inline const glm::vec3 kRed(1, 0, 0), kGreen(0, 1, 0), kBlue(0, 0, 1);

inline Fragment frag(float z, float area, float opacity, glm::vec3 colour, MaskBits mask, std::uint32_t tag,
                     bool mayMerge = true) {
  Fragment f;
  f.zmin = f.zmax = f.zkey = z;
  f.area = area;
  f.opacity = opacity;
  f.colour = colour;
  f.mask = mask;
  f.tag = tag;
  f.mayMerge = mayMerge;
  return f;
}

}  // namespace wf::test

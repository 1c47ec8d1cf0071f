// Counter-based random numbers: a value is a pure function of (seed, stream, index...), so
// generated geometry is the same whatever the thread count or the order of generation, and
// adding elements (more hairs) never moves the others. SplitMix64's finaliser (Steele, Lea and
// Flood 2014) mixes the words.
#pragma once

#include <cstdint>

namespace wf {

constexpr std::uint64_t mix64(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// One more word into a hash chain: hashWords is hashAppend(hashAppend(hashAppend(mix64(a), b),
/// c), d), so that a caller hashing many tuples with a common prefix (seed, octave, column) can
/// keep the prefix's chain and append only what differs, with the same values.
constexpr std::uint64_t hashAppend(std::uint64_t chain, std::uint64_t word) { return mix64(chain ^ word); }

/// A 64-bit hash of up to four words.
constexpr std::uint64_t hashWords(std::uint64_t a, std::uint64_t b = 0, std::uint64_t c = 0,
                                  std::uint64_t d = 0) {
  return hashAppend(hashAppend(hashAppend(mix64(a), b), c), d);
}

/// Uniform in [0, 1) from a hash (53 bits).
constexpr double unitFromHash(std::uint64_t h) { return double(h >> 11) * 0x1.0p-53; }

/// A small per-element random stream: element identity in, independent uniforms out
/// (`next()` k times gives the k-th draw, the same whatever else was drawn elsewhere).
class HashRandom {
 public:
  constexpr HashRandom(std::uint64_t seed, std::uint64_t stream, std::uint64_t index)
      : key_(hashWords(seed, stream, index)) {}
  constexpr double next() { return unitFromHash(mix64(key_ + 0x632be59bd9b4e019ULL * ++count_)); }
  /// Uniform in [lo, hi).
  constexpr double uniform(double lo, double hi) { return lo + (hi - lo) * next(); }

 private:
  std::uint64_t key_;
  std::uint64_t count_ = 0;
};

}  // namespace wf

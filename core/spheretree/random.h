#pragma once
// A deterministic uniform double in [0, 1) from a 64-bit state (splitmix64): the
// same sequence on every standard library, so trees and metrics are reproducible.

#include <cstdint>

namespace sulcus::detail {

inline double Uniform(std::uint64_t& state) {
  state += 0x9E3779B97F4A7C15ull;
  std::uint64_t z = state;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

}  // namespace sulcus::detail

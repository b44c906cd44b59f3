#pragma once
// PCG32 (O'Neill 2014): small, fast, and seeded per pixel so images do not depend on threads.
#include <cstdint>

namespace bouguer {

class Rng {
 public:
  Rng(std::uint64_t seed, std::uint64_t stream) {
    inc_ = (stream << 1u) | 1u;
    next_u32();
    state_ += seed;
    next_u32();
  }
  std::uint32_t next_u32() {
    const std::uint64_t old = state_;
    state_ = old * 6364136223846793005ULL + inc_;
    const auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
    const auto rot = static_cast<std::uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
  }
  // Uniform in [0, 1).
  double next_double() { return (next_u32() >> 8) * (1.0 / 16777216.0); }

 private:
  std::uint64_t state_ = 0, inc_ = 0;
};

}  // namespace bouguer

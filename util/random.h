// Random numbers. Pcg32 is a small sequential generator (O'Neill's PCG-XSH-RR); hash-based
// `uniform_float(key...)` gives a value that depends only on its arguments, so a path's samples
// are the same whatever thread or wavefront computes them.
#pragma once

#include <cstdint>

namespace dacrt {

class Pcg32 {
 public:
  explicit Pcg32(uint64_t seed = 0x853c49e6748fea9bULL, uint64_t stream = 0xda3e39cb94b95bdbULL) {
    inc_ = (stream << 1u) | 1u;
    state_ = 0;
    next();
    state_ += seed;
    next();
  }
  uint32_t next() {
    uint64_t old = state_;
    state_ = old * 6364136223846793005ULL + inc_;
    uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((-rot) & 31));
  }
  // Uniform in [0, bound) without modulo bias (Lemire's method).
  uint32_t below(uint32_t bound) {
    uint64_t m = uint64_t(next()) * bound;
    uint32_t low = uint32_t(m);
    if (low < bound) {
      uint32_t threshold = -bound % bound;
      while (low < threshold) {
        m = uint64_t(next()) * bound;
        low = uint32_t(m);
      }
    }
    return uint32_t(m >> 32);
  }
  float uniform() { return float(next() >> 8) * 0x1p-24f; }  // [0, 1)

 private:
  uint64_t state_, inc_;
};

// SplitMix64's finaliser: a strong 64-bit mix.
constexpr uint64_t mix64(uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

constexpr uint64_t hash(uint64_t a, uint64_t b) {
  return mix64(a ^ mix64(b + 0x9e3779b97f4a7c15ULL));
}
template <typename... Rest>
constexpr uint64_t hash(uint64_t a, uint64_t b, Rest... rest) {
  return hash(hash(a, b), uint64_t(rest)...);
}

// A float in [0, 1) that depends only on the key.
template <typename... Key>
constexpr float uniform_float(Key... key) {
  return float(hash(uint64_t(key)...) >> 40) * 0x1p-24f;
}

}  // namespace dacrt

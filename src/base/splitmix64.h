// splitmix64 (Steele, Lea, Flood 2014): a tiny PRNG whose output is fixed by its definition, so
// what is drawn from it (the atrium, automatic lights) is the same on every compiler and standard
// library (no std:: distributions).
#pragma once
#include <cstdint>

namespace hb {

struct SplitMix64 {
  uint64_t state;
  uint64_t next() {
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }  // [0, 1), 53 exact bits
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
};

}  // namespace hb

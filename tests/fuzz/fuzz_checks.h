// What both fuzz targets check of what they produce beyond "no crash": a promise of the header
// that does not hold aborts, so that libFuzzer records the input as a finding.
#pragma once
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <glm/glm.hpp>

// FUZZ_CHECK(cond): abort naming the condition when it is false. FUZZ_TARGET_NAME names the
// target in the message ("fuzz_gltf: ... breaks: <cond>").
#define FUZZ_CHECK(cond)                                                            \
  do {                                                                              \
    if (!(cond)) {                                                                  \
      std::fprintf(stderr, "%s: the result breaks: %s\n", FUZZ_TARGET_NAME, #cond); \
      std::abort();                                                                 \
    }                                                                               \
  } while (0)

namespace hb::fuzz {

inline bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool finite(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

}  // namespace hb::fuzz

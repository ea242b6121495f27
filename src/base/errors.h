// Error kinds and the exit codes they map to (docs/usage.md "Exit codes": 0 ok, 1 regression, 2 bad input,
// 3 device or runtime failure).
#pragma once
#include <stdexcept>
#include <string>

namespace hb {

constexpr int kExitOk = 0;
constexpr int kExitRegression = 1;
constexpr int kExitBadInput = 2;
constexpr int kExitDeviceFailure = 3;

// Something the user can fix: a missing file, a malformed field, an unknown name. The message is
// one line that names the file/field/value and what would fix it.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The device or the runtime failed (a Vulkan call, device lost, out of memory).
struct DeviceError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Internal invariant; stays on in release builds.
#define HB_ASSERT(cond)                                                                                     \
  do {                                                                                                      \
    if (!(cond))                                                                                            \
      throw std::logic_error(std::string("internal invariant failed: ") + #cond + " at " + __FILE__ + ":" + \
                             std::to_string(__LINE__));                                                     \
  } while (0)

}  // namespace hb

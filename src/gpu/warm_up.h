// A steady device before measuring (docs/usage.md "A steady device"): a GPU that has idled runs its
// first seconds of work at other clocks than the rest, so `peaks` and `sweep` first run rounds of a
// fixed load until successive rounds agree, bounded in time, and record how it went.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gpu/vk_context.h"

namespace hb {

struct WarmUpPolicy {
  double tolerance = 0.02;  // the last `window` rounds within this of their median: settled
  uint32_t window = 5;
  uint32_t minRounds = 10;   // at least this many rounds, settled or not
  double maxSeconds = 15.0;  // then stop, settled or not
};

struct WarmUp {
  bool ran = false;      // false: skipped (a CPU device has no clocks to warm)
  std::string skipped;   // why, where skipped
  bool settled = false;  // the last window agreed within the tolerance
  uint32_t rounds = 0;
  double seconds = 0;      // wall time the rounds took
  double spread = 0;       // (max − min) / median of the last window
  std::vector<double> ms;  // each round's time
  WarmUpPolicy policy;
};

// Runs `roundMs` (one round of the load; its time in ms) until the last policy.window rounds agree
// within policy.tolerance of their median and at least policy.minRounds ran, or until
// policy.maxSeconds of `nowSeconds` passed. Deterministic given its inputs.
WarmUp warmUntilSteady(const std::function<double()>& roundMs, const WarmUpPolicy& policy,
                       const std::function<double()>& nowSeconds);

// Rounds of fp32 FMA and a buffer read (about 0.05 s a round on an H200), timed by GPU timestamps,
// until steady. Its buffers and pipelines are made once, so that a measurement can warm the device
// again right before it is timed: a GPU that idled while the CPU worked (a BVH build, ray sets made
// on the CPU) drops its clocks within a second. A CPU device is skipped.
class DeviceWarmer {
 public:
  explicit DeviceWarmer(const VulkanContext& ctx);
  ~DeviceWarmer();
  WarmUp warm(const WarmUpPolicy& policy = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};
// Before a timed measurement: the last 3 rounds within 2 %, at least 3 rounds, at most 5 s.
inline constexpr WarmUpPolicy kRewarmPolicy{0.02, 3, 3, 5.0};

// The whole warm-up, once (DeviceWarmer(ctx).warm(policy)).
WarmUp warmDevice(const VulkanContext& ctx, const WarmUpPolicy& policy = {});

// {"ran", "settled", "rounds", "seconds", "spread", "tolerance", "window", "max_seconds", "ms"}, or
// {"ran": false, "skipped": why}.
nlohmann::json toJson(const WarmUp& w);
// The line a run whose device never settled carries in its warnings (empty when it settled or
// was skipped).
std::string warmUpWarning(const WarmUp& w);

}  // namespace hb

// Continuing an interrupted sweep (`sweep --resume`): what it keeps of the earlier results.json,
// and the whole command line that continues a sweep, which an interrupted sweep prints.
#pragma once
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "app/sweep.h"
#include "gpu/vk_context.h"

namespace hb {

struct ResumedResults {
  nlohmann::json context;                      // the earlier context, null when the file has none
  std::map<std::string, nlohmann::json> kept;  // by variant name: the runs the sweep does not run again
};

// Reads the earlier results in resultsPath (which exists). `config` is the config as it runs now
// (toJson of configForDevice's), `shard` the part it runs (context.shard, null without --shard).
// Keeps runs of status "ok", and "timeout" or "crashed" unless retryFailed ("error" runs again).
// Throws InputError, one line naming the file, when it is not JSON or was written by another config
// (the first field that differs and both values), device or part.
ResumedResults readResumable(const std::string& resultsPath, const nlohmann::json& config, const DeviceInfo& device,
                             const nlohmann::json& shard, bool retryFailed);

// The command that continues this sweep in outDir, ready to paste into a shell: the program as it
// was started, `sweep`, the config, then --resume (with --retry-failed when asked), --out and every
// option that shapes the results (--device, --frames, --warmup, --no-images, --scene, --size, --set,
// --variant-timeout, --shard). severalDevices: this device is one of a sweep on several; with --out
// given, the command resumes all of them (the same --device and --out), else this device's folder.
std::string resumeCommand(const SweepOptions& options, const DeviceInfo& device, const std::string& outDir,
                          bool severalDevices, bool retryFailed);

}  // namespace hb

// Continuing an interrupted sweep (`sweep --resume`): what it keeps of the earlier results.json,
// and the whole command line that continues a sweep, which an interrupted sweep prints.
#pragma once
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/sweep.h"
#include "gpu/vk_context.h"

namespace hb {

struct ResumedResults {
  nlohmann::json context;                      // the earlier context, null when the file has none
  std::map<std::string, nlohmann::json> kept;  // by variant name: the runs the sweep does not run again
  std::vector<std::string> warnings;           // the inputs at other paths, their content the same
};

// Reads the earlier results in resultsPath (which exists). `inputs` is what this sweep's context
// will say of its inputs (run_context.h inputsContext of configForDevice's config, with
// scene.sha256), `shard` the part it runs (context.shard, null without --shard). Keeps runs of
// status "ok", and "timeout" or "crashed" unless retryFailed ("error" runs again). Throws
// InputError, one line naming the file, when it is not JSON or was written by another config (the
// first field that differs and both values; file paths aside), scene content (both sha256s),
// device or part; inputs at other paths with the same content (a moved checkout) are a warning.
ResumedResults readResumable(const std::string& resultsPath, const nlohmann::json& inputs, const DeviceInfo& device,
                             const nlohmann::json& shard, bool retryFailed);

// Appends the options that shape a sweep's runs and that another sweep of the same runs must be
// given (a worker, or the command that resumes it): --frames, --warmup, --no-images, --scene,
// --size and every --set, each only where the user gave it.
void appendRunOptions(std::vector<std::string>& args, const SweepOptions& options);

// The command that continues this sweep in outDir, ready to paste into a shell: the program as it
// was started, `sweep`, the config, then --resume (with --retry-failed when asked), --out and every
// option that shapes the results (--device, --frames, --warmup, --no-images, --scene, --size, --set,
// --variant-timeout, --shard). severalDevices: this device is one of a sweep on several; with --out
// given, the command resumes all of them (the same --device and --out), else this device's folder.
std::string resumeCommand(const SweepOptions& options, const DeviceInfo& device, const std::string& outDir,
                          bool severalDevices, bool retryFailed);

}  // namespace hb

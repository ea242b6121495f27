// One device's part of `hybridbench sweep` (sweep.h): every variant of a config on one device,
// written to one output folder after each variant.
#pragma once
#include <string>
#include <vector>

#include "app/sweep.h"
#include "app/sweep_console.h"
#include "config/config.h"
#include "gpu/vk_context.h"

namespace hb {

// Sweeps `config` (with options' frame overrides, lowered for a CPU device) on `device` into
// outDir (created), resuming from its results.json with options.resume. `concurrent`: the other
// devices sweeping at the same time; `sharing`: those of them on this same device (both named in
// the results' context). Returns the process exit status: 130 when interrupted.
int sweepOneDevice(const SweepOptions& options, Config config, const DeviceInfo& device, const std::string& outDir,
                   const Console& console, const std::vector<std::string>& concurrent,
                   const std::vector<std::string>& sharing = {});

// The worker process's side (sweep_worker.h): runs the variants options.workerVariants names on
// `device` and sends the results context, each variant's steps and its run to options.workerFd.
int runSweepWorker(const SweepOptions& options, Config config, const DeviceInfo& device, const std::string& outDir);

// The config as it runs on `device`: options' frame counts, then lowered for a CPU device.
Config configForDevice(Config config, const SweepOptions& options, const DeviceInfo& device);

// sweep --dry-run: the variants with their effective parameters (each one's difference from the
// defaults), the frame count and a time estimate from a few frames of the first variant; renders
// nothing else and writes nothing.
void printDryRun(const SweepOptions& options, Config config, const DeviceInfo& device, const std::string& outDir);

// SIGINT and SIGTERM from now on only set the flag that sweepInterrupted() reads: the sweeps stop
// after their current frame and keep what they finished.
void catchSweepInterrupts();
bool sweepInterrupted();

}  // namespace hb

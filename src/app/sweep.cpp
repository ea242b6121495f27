#include "app/sweep.h"

#include <chrono>
#include <cstdio>
#include <ctime>
#include <exception>
#include <filesystem>
#include <sstream>
#include <thread>

#include "app/commands.h"
#include "app/out_dir.h"
#include "app/scene_setup.h"
#include "app/sweep_console.h"
#include "app/sweep_device.h"
#include "app/sweep_results.h"
#include "app/sweep_shard.h"
#include "base/errors.h"
#include "base/version.h"
#include "config/config_overrides.h"
#include "gpu/vk_context.h"

namespace hb {

namespace fs = std::filesystem;

int cmdSweep(const SweepOptions& options) {
  if (options.resume && options.out.empty())
    throw InputError("sweep --resume needs --out DIR: the directory of the interrupted sweep");
  if (options.resume && options.force)
    throw InputError(
        "sweep: --resume and --force contradict each other (--resume continues the results in --out, "
        "--force moves them aside); give one");
  if (options.retryFailed && !options.resume)
    throw InputError("sweep --retry-failed runs again what an earlier sweep left; it needs --resume --out DIR");
  if (options.frames == 0) throw InputError("--frames 0: a sweep needs at least 1 measured frame");
  if (!options.shard.empty()) (void)parseShard(options.shard);  // a bad K/N before anything else
  ConfigOverrides overrides;
  overrides.scene = options.scene;
  overrides.sets = options.sets;
  if (!options.size.empty()) {
    uint32_t w = 0, h = 0;
    parseSize(options.size, w, h, "--size");
    overrides.resolution = std::array<uint32_t, 2>{w, h};
  }
  Config config = loadConfigWith(options.config, overrides);
  std::vector<DeviceInfo> devices = enumerateDevices();
  // "all", a comma-separated list ("0,1"; a device may be named twice: two sweeps on one GPU at
  // once), or one index or name substring.
  std::vector<DeviceInfo> chosen;
  if (options.device == "all") {
    chosen = devices;
  } else if (options.device.find(',') != std::string::npos) {
    if (options.device.front() == ',' || options.device.back() == ',')
      throw InputError("--device " + options.device + ": an empty item; write e.g. --device 0,1");
    std::stringstream list(options.device);
    for (std::string item; std::getline(list, item, ',');) {
      if (item.empty()) throw InputError("--device " + options.device + ": an empty item; write e.g. --device 0,1");
      chosen.push_back(devices[resolveDevice(devices, item)]);
    }
  } else {
    chosen.push_back(devices[resolveDevice(devices, options.device)]);
  }
  if (chosen.empty()) throw DeviceError("no Vulkan device found; install a driver (lavapipe: mesa-vulkan-drivers)");
  if (!options.shard.empty() && chosen.size() > 1)
    throw InputError("--shard " + options.shard + " with --device " + options.device +
                     ": a part runs on one device; start one sweep per part and device (docs/fleet.md)");
  catchSweepInterrupts();
  if (options.workerFd >= 0) {  // this process is one device's worker (sweep_worker.h)
    if (chosen.size() != 1 || options.out.empty())
      throw InputError("--worker-fd is internal to sweep: it needs one --device and --out");
    return runSweepWorker(options, config, chosen[0], options.out);
  }

  // One folder per device: DIR/<position>-<device> when several (two identical GPUs differ in
  // position only), else DIR, or out/<config>-<device>-<time>-<git> without --out.
  std::time_t now = std::time(nullptr);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", std::gmtime(&now));
  std::vector<std::string> dirs, names;
  for (size_t k = 0; k < chosen.size(); ++k) {
    const std::string tag = chosen.size() > 1 ? std::to_string(k) + "-" + slug(chosen[k].name) : slug(chosen[k].name);
    names.push_back(std::to_string(k) + ": " + chosen[k].name);  // position, then name (a device may repeat)
    if (options.out.empty())
      dirs.push_back("out/" + config.name + "-" + tag + "-" + stamp + "-" + gitRevision());
    else
      dirs.push_back(chosen.size() > 1 ? (fs::path(options.out) / tag).string() : options.out);
  }
  // A glTF scene is loaded once here, before anything is printed, created or moved aside: a scene
  // that is refused costs one line and nothing else (built-in scenes are made by code).
  if (!config.sceneIsBuiltin() && !config.sceneIsHardCase()) {
    SceneCache probe;
    (void)probe.get(config, config.defaults);
  }
  // Earlier results in a folder are never lost without a word: refused unless --resume or --force
  // says what to do with them (every folder checked before any is touched).
  for (const std::string& dir : dirs)
    prepareOutDir(dir, "results.json", options.resume || options.force ? Existing::Resume : Existing::Refuse, "sweep",
                  true);
  if (options.dryRun) {
    for (size_t k = 0; k < chosen.size(); ++k) printDryRun(options, config, chosen[k], dirs[k]);
    return kExitOk;
  }
  if (options.force)
    for (const std::string& dir : dirs) {
      const std::string aside = prepareOutDir(dir, "results.json", Existing::Replace, "sweep", true);
      if (!aside.empty()) std::printf("--force: moved the earlier results in %s to %s/\n", dir.c_str(), aside.c_str());
    }
  if (chosen.size() == 1) return sweepOneDevice(options, config, chosen[0], dirs[0], Console(), {});

  // Several devices: one thread (own Vulkan instance, device and queue) per device, all at once.
  // The host's cores are shared by their analysis frames; GPU timestamps are each device's own,
  // unless a device is named twice: then its sweeps share it and each one's times include the
  // other's work (measured on an H200: an A/A compare of the two says "slower"/"faster" by up to
  // 1.9x per pass), so the results say so and only the counts compare.
  std::vector<std::vector<std::string>> sharing(chosen.size());
  for (size_t k = 0; k < chosen.size(); ++k)
    for (size_t o = 0; o < chosen.size(); ++o)
      if (o != k && chosen[o].index == chosen[k].index) sharing[k].push_back(names[o]);
  for (size_t k = 0; k < chosen.size(); ++k) {
    bool first = true;  // one warning per device, at its first position
    for (size_t o = 0; o < k; ++o) first &= chosen[o].index != chosen[k].index;
    if (!sharing[k].empty() && first)
      std::fprintf(stderr,
                   "warning: device %u (%s) is named more than once: its sweeps share it, so their times include "
                   "each other's work; compare their counts, not their times\n",
                   chosen[k].index, chosen[k].name.c_str());
  }
  std::printf("sweep on %zu devices concurrently (one thread and queue per device): ", chosen.size());
  for (size_t k = 0; k < chosen.size(); ++k)
    std::printf("%s%s -> %s", k ? "; " : "", names[k].c_str(), dirs[k].c_str());
  std::printf("\n");
  std::fflush(stdout);
  const auto start = std::chrono::steady_clock::now();
  std::vector<int> rcs(chosen.size(), kExitOk);
  std::vector<std::exception_ptr> errors(chosen.size());
  std::vector<double> seconds(chosen.size(), 0.0);
  std::vector<std::thread> threads;
  for (size_t k = 0; k < chosen.size(); ++k)
    threads.emplace_back([&, k] {
      std::vector<std::string> others;
      for (size_t o = 0; o < chosen.size(); ++o)
        if (o != k) others.push_back(names[o]);
      try {
        rcs[k] =
            sweepOneDevice(options, config, chosen[k], dirs[k], Console("[" + names[k] + "] "), others, sharing[k]);
      } catch (...) {
        errors[k] = std::current_exception();
      }
      seconds[k] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    });
  for (std::thread& t : threads) t.join();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  int rc = kExitOk;
  for (size_t k = 0; k < chosen.size(); ++k) {
    if (errors[k]) {  // as main() reports one device's: one line, exit 2 for bad input, 3 otherwise
      try {
        std::rethrow_exception(errors[k]);
      } catch (const InputError& e) {
        std::fprintf(stderr, "hybridbench: [%s] %s\n", names[k].c_str(), e.what());
        rcs[k] = kExitBadInput;
      } catch (const std::exception& e) {
        std::fprintf(stderr, "hybridbench: [%s] device failure: %s\n", names[k].c_str(), e.what());
        rcs[k] = kExitDeviceFailure;
      }
    }
    std::printf("[%s] finished after %.1f s -> %s\n", names[k].c_str(), seconds[k], dirs[k].c_str());
    if (rcs[k] != kExitOk && rc == kExitOk) rc = rcs[k];
  }
  std::printf("sweep on %zu devices: %.1f s wall time in all\n", chosen.size(), wall);
  return sweepInterrupted() ? 130 : rc;
}

}  // namespace hb

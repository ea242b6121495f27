// `hybridbench sweep`: runs every variant of a config on one device — warm-up frames, measured
// frames (GPU timestamps per pass and per frame, nothing else in them), then one analysis frame
// (not timed) for ray accounting, culling statistics, accuracy and images. Each finished variant
// is written at once (temporary file + rename) to results.json, results.csv and tables.md, so an
// interrupted sweep loses nothing and `--resume` skips what is done. The variants run in a child
// process with a watchdog (sweep_worker.h): a hung or crashed variant is recorded as "timeout" or
// "crashed" and the sweep goes on.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/sweep_results.h"  // resultsCsv, writeFileAtomic
#include "config/config.h"

namespace hb {

struct SweepOptions {
  std::string config;   // empty: the embedded default (configs/thesis.json)
  std::string device;   // index, name substring, or "all"
  std::string out;      // empty: out/<config>-<device>-<time>-<git>
  bool resume = false;  // continue the sweep whose results are in `out`
  bool force = false;   // `out` holds results: move them aside (out/previous-<time>/) and start afresh
  int frames = -1;      // override measured frames (-1: config's)
  int warmup = -1;      // override warm-up frames
  bool images = true;   // write per-variant images
  // Changes to the config (config_overrides.h): --scene, --size, --set key=value (every variant).
  std::string scene, size;
  std::vector<std::string> sets;
  bool dryRun = false;  // print the variants, their parameters and an estimate; run nothing
  // The watchdog (sweep_worker.h): a variant that runs longer than this many seconds is ended
  // (0: the default, kVariantTimeoutFloorS or kFrameLimitS a frame, whichever is longer).
  double variantTimeout = 0;
  bool retryFailed = false;  // with --resume: run again the variants that timed out or crashed
  // "K/N": run only the K-th of N parts of the variants (sweep_shard.h); empty: all of them.
  std::string shard;
  // Hidden: this process is a sweep's worker (sweep_worker.h): it runs the variants numbered in
  // workerVariants ("0,3,4", positions in the config's order) and sends them to workerFd.
  int workerFd = -1;
  std::string workerVariants;
};

// The watchdog's default limit a variant: the longer of a floor and a limit per frame.
constexpr double kVariantTimeoutFloorS = 600.0;
constexpr double kFrameLimitS = 2.0;
// SIGTERM first (the child stops after its frame); SIGKILL when it has not ended after this.
constexpr double kWorkerGraceS = 10.0;

int cmdSweep(const SweepOptions& options);

}  // namespace hb

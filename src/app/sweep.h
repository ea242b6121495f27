// `hybridbench sweep`: runs every variant of a config on one device — warm-up frames, measured
// frames (GPU timestamps per pass and per frame, nothing else in them), then one analysis frame
// (not timed) for ray accounting, culling statistics, accuracy and images. Each finished variant
// is written at once (temporary file + rename) to results.json, results.csv and tables.md, so an
// interrupted sweep loses nothing and `--resume` skips what is done.
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
};

int cmdSweep(const SweepOptions& options);

}  // namespace hb

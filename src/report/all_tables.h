// tables.md: the tables of what a results file's runs study — the thesis's Tables 5.1/5.2 where
// some run is one of their rows (the thesis's frame: direct light and shadows, 10 lights), the
// primary-visibility and anti-aliasing tables, each effect's own table (plan/effect.h
// EffectDef::table, in effect order), the many-lights table — as `sweep` prints and writes it and
// `tables` prints it. A file that no table has rows for gets the per-variant table instead. Last,
// whatever the study, the resources built on the CPU for each run's frame.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace hb {

// Throws InputError when `results` is not a results file.
std::string allTablesMarkdown(const nlohmann::json& results);
// Every run: its status, its frame time (median and CV) and its top-level passes' medians.
std::string variantTableMarkdown(const nlohmann::json& results);
// "Built once a frame": a row per run and keyed resource that records a build (frame_resources
// entries with build_ms: the BVH, the TLAS, an LDM set): who built it, the build's CPU wall clock,
// the bytes built and the bytes the frame reads, and the passes sharing it. Empty when no run
// records one (files written before frame_resources carried builds).
std::string builtResourcesTableMarkdown(const nlohmann::json& results);

}  // namespace hb

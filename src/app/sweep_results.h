// The files a sweep writes into its output folder, each rewritten whole (temporary file, then
// rename) after every variant, so that an interrupted sweep loses nothing.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace hb {

// results.json, results.csv, tables.md, accuracy.md and accuracy.svg of `results` (results.json's
// schema) in dir. Precondition: dir exists.
void writeSweepOutputs(const std::string& dir, const nlohmann::json& results);

// results.csv: one row per run and pass (and "frame"), flattened parameters.
std::string resultsCsv(const nlohmann::json& results);

// Writes text to path atomically (temporary beside it, then rename).
void writeFileAtomic(const std::string& path, const std::string& text);

// A folder name for a variant or device: its letters and digits in lower case, every other run of
// characters one '-'; "run" when nothing is left.
std::string slug(const std::string& s);

}  // namespace hb

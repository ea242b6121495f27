// The files a sweep writes into its output folder, each rewritten whole (temporary file, then
// rename) after every variant, so that an interrupted sweep loses nothing.
#pragma once
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "report/html_report.h"

namespace hb {

// results.json, results.csv, tables.md, accuracy.md, accuracy.svg, roofline.md, roofline.svg and
// report.html (report/html_report.h) of `results` (results.json's schema) in dir. Precondition: dir
// exists.
void writeSweepOutputs(const std::string& dir, const nlohmann::json& results);

// The images a sweep wrote for each run of `results` into resultsDir/<slug(name)>/ (*.png, or their
// *.webp previews, which win where both are), as the page at reportDir refers to them (paths
// relative to reportDir), the colour image first, then by name; a run whose folder holds none has
// no entry. Labels are the file names without extension, '_' as ' '.
std::map<std::string, std::vector<ReportImage>> variantImages(const std::string& resultsDir,
                                                              const std::string& reportDir,
                                                              const nlohmann::json& results);

// results.csv: one row per run and pass (and "frame"), flattened parameters.
std::string resultsCsv(const nlohmann::json& results);

// Writes text to path atomically (temporary beside it, then rename).
void writeFileAtomic(const std::string& path, const std::string& text);

// A folder name for a variant or device: its letters and digits in lower case, every other run of
// characters one '-'; "run" when nothing is left.
std::string slug(const std::string& s);

}  // namespace hb

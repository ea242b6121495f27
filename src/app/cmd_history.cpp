// `hybridbench history PATH... [--threshold PCT] [--alpha A] [--min-segment N] [--json F] [--html F]
// [--gate]`: the runs of many results files as series over time and the changes in them
// (report/history.h).
#include <cstdio>
#include <filesystem>
#include <iostream>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/sweep_results.h"
#include "base/errors.h"
#include "base/input_file.h"
#include "report/history.h"
#include "report/history_html.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

const char* kHistoryHint = "pass results files written by 'hybridbench sweep', or folders that hold them";

HistoryInput readHistoryInput(const std::string& path) {
  const std::string text = readInputText(path, kHistoryHint);
  try {
    return {path, nlohmann::json::parse(text)};
  } catch (const nlohmann::json::exception& e) {  // parse_error, and out_of_range for 1e999
    throw InputError(path + ": not valid JSON (" + std::string(e.what()) + "); " + kHistoryHint);
  }
}

// An output file the user named: its folder must exist and it must not be a folder, checked before
// the files are read so that a typo costs no time.
void requireOutputFile(const std::string& path, const char* flag) {
  if (path.empty()) return;
  std::error_code ec;
  if (fs::is_directory(path, ec))
    throw InputError(std::string(flag) + " " + path + " is a folder; name the file to write");
  const fs::path dir = fs::path(path).has_parent_path() ? fs::path(path).parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec))
    throw InputError(std::string(flag) + " " + path + ": the folder " + dir.string() +
                     " does not exist; create it or write elsewhere");
}

}  // namespace

int cmdHistory(const HistoryCommand& command) {
  requireOutputFile(command.json, "--json");
  requireOutputFile(command.html, "--html");
  std::vector<HistoryInput> inputs;
  for (const std::string& path : findResultsFiles(command.paths)) inputs.push_back(readHistoryInput(path));
  const HistoryReport report = buildHistory(inputs, command.options);
  std::cout << formatHistory(report);
  if (!command.json.empty()) writeFileAtomic(command.json, toJson(report).dump(2) + "\n");
  if (!command.html.empty()) writeFileAtomic(command.html, historyHtml(report, command.allSeries));
  return command.gate && report.regression ? kExitRegression : kExitOk;
}

}  // namespace hb

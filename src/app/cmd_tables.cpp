#include <cstdio>
#include <fstream>
#include <iostream>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "base/errors.h"
#include "report/accuracy_report.h"
#include "report/all_tables.h"
#include "report/compare.h"
#include "report/results_json.h"
#include "report/tables.h"

namespace hb {

static nlohmann::json readResults(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw InputError(path + ": cannot open; pass a results.json written by 'hybridbench sweep'");
  try {
    return nlohmann::json::parse(f);
  } catch (const nlohmann::json::exception& e) {  // parse_error, and out_of_range for 1e999
    throw InputError(path + ": not valid JSON (" + std::string(e.what()) +
                     "); pass a results.json written by 'hybridbench sweep'");
  }
}

int cmdTables(const std::vector<std::string>& resultsPaths, const std::string& format) {
  HB_ASSERT(!resultsPaths.empty());
  nlohmann::json results = readResults(resultsPaths[0]);
  for (size_t i = 1; i < resultsPaths.size(); ++i) {
    const nlohmann::json more = readResults(resultsPaths[i]);
    const auto deviceName = [](const nlohmann::json& r) {
      const nlohmann::json& d = results::at(results::at(r, "context"), "device");
      return results::at(d, "name").is_string() ? results::at(d, "name").get<std::string>() : std::string("?");
    };
    if (deviceName(more) != deviceName(results))
      throw InputError(resultsPaths[i] + ": measured on \"" + deviceName(more) + "\", " + resultsPaths[0] + " on \"" +
                       deviceName(results) +
                       "\"; tables read several files only from one kind of device (use "
                       "'hybridbench compare' across devices)");
    results::requireResultsFile(more);
    for (const nlohmann::json& run : more["runs"]) results["runs"].push_back(run);
  }
  if (format == "csv") {
    std::cout << thesisTablesCsv(results);
  } else if (format == "svg") {
    std::cout << accuracyReportSvg(results);
  } else {
    // As sweep writes them: tables.md, then accuracy.md.
    std::cout << allTablesMarkdown(results);
    std::cout << "\n" << accuracyReportMarkdown(results);
  }
  return kExitOk;
}

int cmdCompare(const std::string& a, const std::string& b, const CompareOptions& options, const std::string& format) {
  CompareReport report = compareResults(readResults(a), readResults(b), options);
  if (format == "json")
    std::cout << toJson(report).dump(2) << "\n";
  else if (format == "junit")
    std::cout << formatCompareJunit(report);
  else
    std::cout << formatCompare(report);
  return report.regression ? kExitRegression : kExitOk;
}

}  // namespace hb

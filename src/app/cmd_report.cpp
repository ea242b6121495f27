// `hybridbench report RESULTS.json [--compare BASE.json] --out report.html`: the page a sweep writes
// (report/html_report.h), for any results file, optionally compared against a base.
#include <filesystem>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/sweep_results.h"
#include "base/errors.h"
#include "base/input_file.h"
#include "report/html_report.h"
#include "report/noise_model.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

nlohmann::json readReportResults(const std::string& path) {
  const char* hint = "pass a results.json written by 'hybridbench sweep'";
  const std::string text = readInputText(path, hint);
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // parse_error, and out_of_range for 1e999
    throw InputError(path + ": not valid JSON (" + std::string(e.what()) + "); " + hint);
  }
}

}  // namespace

int cmdReport(const ReportOptions& options) {
  const fs::path out(options.out);
  std::error_code ec;
  if (fs::is_directory(out, ec))
    throw InputError("--out " + options.out + " is a folder; name the page to write, e.g. --out " +
                     (out / "report.html").string());
  const fs::path outDir = out.has_parent_path() ? out.parent_path() : fs::path(".");
  if (!fs::is_directory(outDir, ec))
    throw InputError("--out " + options.out + ": the folder " + outDir.string() +
                     " does not exist; create it or write the page elsewhere");

  const nlohmann::json results = readReportResults(options.results);
  nlohmann::json base;
  HtmlReportInput page;
  page.results = &results;
  page.source = options.results;
  if (!options.compare.empty()) {
    base = readReportResults(options.compare);
    page.base = &base;
    page.baseSource = options.compare;
    page.compareOptions = options.compareOptions;
  }
  NoiseModel noise;
  if (!options.noise.empty()) {
    if (options.compare.empty()) throw InputError("report: --noise needs --compare BASE.json; the noise is compare's");
    noise = readNoiseFile(options.noise);
    page.compareOptions.noise = &noise;
  }
  // The images of a sweep lie beside its results.json, one folder per variant.
  const fs::path resultsDir =
      fs::path(options.results).has_parent_path() ? fs::path(options.results).parent_path() : fs::path(".");
  page.images = variantImages(resultsDir.string(), outDir.string(), results);
  const std::string text = htmlReport(page);  // throws InputError before anything is written
  writeFileAtomic(options.out, text);
  return kExitOk;
}

}  // namespace hb

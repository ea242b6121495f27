#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/sweep_results.h"
#include "base/errors.h"
#include "base/input_file.h"
#include "base/text_format.h"
#include "report/accuracy_report.h"
#include "report/all_tables.h"
#include "report/compare.h"
#include "report/noise_model.h"
#include "report/results_json.h"
#include "report/roofline.h"
#include "report/tables.h"

namespace hb {

static const char* kResultsHint = "pass a results.json written by 'hybridbench sweep'";

static nlohmann::json readResults(const std::string& path) {
  const std::string text = readInputText(path, kResultsHint);
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // parse_error, and out_of_range for 1e999
    throw InputError(path + ": not valid JSON (" + std::string(e.what()) + "); " + kResultsHint);
  }
}

static int renderTables(const nlohmann::json& results, const std::vector<std::string>& resultsPaths,
                        const std::string& format, const std::vector<std::string>& ceilingPaths,
                        const std::function<std::string(const nlohmann::json&)>& deviceName);

int cmdTables(const std::vector<std::string>& resultsPaths, const std::string& format, bool allowDuplicates,
              const std::vector<std::string>& ceilingPaths) {
  HB_ASSERT(!resultsPaths.empty());
  if (!ceilingPaths.empty() && format != "roofline")
    throw InputError("--ceiling " + ceilingPaths[0] + " rates the roofline table's passes; add --format roofline");
  std::vector<nlohmann::json> files;
  for (const std::string& path : resultsPaths) {
    files.push_back(readResults(path));
    results::requireResultsFile(files.back(), path);
  }
  nlohmann::json results = files[0];
  const auto deviceName = [](const nlohmann::json& r) {
    const nlohmann::json& d = results::at(results::at(r, "context"), "device");
    return results::at(d, "name").is_string() ? results::at(d, "name").get<std::string>() : std::string("?");
  };
  for (size_t i = 1; i < files.size(); ++i) {
    if (deviceName(files[i]) != deviceName(results))
      throw InputError(resultsPaths[i] + ": measured on \"" + deviceName(files[i]) + "\", " + resultsPaths[0] +
                       " on \"" + deviceName(results) +
                       "\"; tables read several files only from one kind of device (use "
                       "'hybridbench compare' across devices)");
  }
  // Several files: one study's runs, one after another. A variant in two files would be read twice
  // (the tables take a variant's first run), so it is refused unless asked for; then every row is
  // named with its file.
  std::map<std::string, std::string> fileOf;  // variant -> first file holding it
  bool duplicates = false;
  for (size_t i = 0; i < files.size(); ++i)
    for (const nlohmann::json& run : files[i]["runs"]) {
      const std::string name = run.value("name", std::string());
      const auto [it, fresh] = fileOf.emplace(name, resultsPaths[i]);
      if (fresh) continue;
      if (!allowDuplicates)
        throw InputError(resultsPaths[i] + ": variant \"" + name + "\" is also in " + it->second +
                         "; tables would read only the first; pass each file alone, or --allow-duplicates to list "
                         "both with their files named");
      duplicates = true;
    }
  for (size_t i = 1; i < files.size(); ++i)
    for (const nlohmann::json& run : files[i]["runs"]) results["runs"].push_back(run);
  if (duplicates) {  // every run named with its file: "name [path]"
    size_t at = 0;
    for (size_t i = 0; i < files.size(); ++i)
      for (size_t k = 0; k < files[i]["runs"].size(); ++k, ++at) {
        nlohmann::json& run = results["runs"][at];
        run["name"] = run.value("name", std::string()) + " [" + resultsPaths[i] + "]";
      }
  }
  // A field of the right name but the wrong type (a roofline entry's `loads` that is not an array of
  // objects, a time that is a string) is the file's fault, not the tool's: one line, exit 2. Each
  // table is made whole before it is written, so nothing is half printed.
  try {
    return renderTables(results, resultsPaths, format, ceilingPaths, deviceName);
  } catch (const nlohmann::json::exception& e) {  // type_error, out_of_range, invalid_iterator
    std::string named;
    for (const std::string& path : resultsPaths) named += (named.empty() ? "" : ", ") + path;
    for (const std::string& path : ceilingPaths) named += ", --ceiling " + path;
    throw InputError(named + ": a field has the wrong type or is missing (" + std::string(e.what()) + "); " +
                     kResultsHint);
  }
}

static int renderTables(const nlohmann::json& results, const std::vector<std::string>& resultsPaths,
                        const std::string& format, const std::vector<std::string>& ceilingPaths,
                        const std::function<std::string(const nlohmann::json&)>& deviceName) {
  if (format == "csv") {
    std::cout << thesisTablesCsv(results);
  } else if (format == "svg") {
    std::cout << accuracyReportSvg(results);
  } else if (format == "accuracy") {
    std::cout << accuracyReportMarkdown(results);
  } else if (format == "roofline") {
    if (ceilingPaths.empty()) {
      std::cout << rooflineMarkdown(results);
    } else {
      // Every file's rates together: the highest for each (pass, unit, primary, aa).
      MeasuredCeilings ceilings;
      for (const std::string& path : ceilingPaths) {
        const nlohmann::json ceiling = readResults(path);
        results::requireResultsFile(ceiling, path);
        if (deviceName(ceiling) != deviceName(results))
          throw InputError("--ceiling " + path + ": measured on \"" + deviceName(ceiling) + "\", " + resultsPaths[0] +
                           " on \"" + deviceName(results) +
                           "\"; a ceiling rates passes only on the device that measured it (sweep "
                           "configs/ceilings*.json there)");
        const MeasuredCeilings one = measuredCeilings(ceiling, path);
        if (one.rates.empty())
          throw InputError("--ceiling " + path +
                           ": no run measured a rate without a device peak (a loop's steps); sweep "
                           "configs/ceilings*.json with this build and pass its results.json");
        ceilings.file += (ceilings.file.empty() ? "" : ", ") + path;
        for (const auto& [key, rate] : one.rates)
          if (rate.perSecond > ceilings.rates[key].perSecond) ceilings.rates[key] = rate;
      }
      if (ceilingMatches(results, ceilings) == 0)
        throw InputError("--ceiling " + ceilings.file + ": no pass of " + resultsPaths[0] +
                         " ran with the pass, primary and aa of a ceiling run; sweep configs/ceilings*.json with "
                         "the same primary and aa (--set primary=... --set aa=...)");
      std::cout << rooflineMarkdown(results, &ceilings);
    }
  } else if (format == "roofline-svg") {
    std::cout << rooflineSvg(results);
  } else if (format == "built") {
    const std::string table = builtResourcesTableMarkdown(results);
    if (table.empty())
      throw InputError(resultsPaths[0] +
                       ": no run records a resource built for the frame (frame_resources with "
                       "build_ms; files of older builds have none): use --format md");
    std::cout << table;
  } else {
    // As sweep writes them: tables.md, then accuracy.md (the roofline: --format roofline).
    std::cout << allTablesMarkdown(results);
    std::cout << "\n" << accuracyReportMarkdown(results);
  }
  // The Markdown says it in its text; a CSV or SVG cannot, so the console does.
  if (format != "md")
    for (const std::string& caveat : results::timingCaveats(results))
      std::fprintf(stderr, "caveat: %s\n", caveat.c_str());
  return kExitOk;
}

NoiseModel readNoiseFile(const std::string& path) {
  const std::string hint = "pass a noise file written by 'hybridbench noise A.json B.json ... --out FILE'";
  const std::string text = readInputText(path, hint);
  try {
    return noiseModelFromJson(nlohmann::json::parse(text), path);
  } catch (const nlohmann::json::exception& e) {  // parse_error; out_of_range for 1e999; a mistyped field
    throw InputError(path + ": not a valid noise file (" + std::string(e.what()) + "); " + hint);
  }
}

int cmdCompare(const std::string& a, const std::string& b, CompareOptions options, const std::string& format,
               const std::string& noise) {
  NoiseModel model;
  if (!noise.empty()) {
    model = readNoiseFile(noise);
    options.noise = &model;
  }
  const nlohmann::json ja = readResults(a), jb = readResults(b);
  results::requireResultsFile(ja, a);
  results::requireResultsFile(jb, b);
  CompareReport report = compareResults(ja, jb, options);
  // JSON and JUnit go to a file or another tool: the warnings are in them, and on stderr for the
  // log (the Markdown prints them itself).
  if (format != "md")
    for (const std::string& w : report.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  if (format == "json")
    std::cout << toJson(report).dump(2) << "\n";
  else if (format == "junit")
    std::cout << formatCompareJunit(report);
  else
    std::cout << formatCompare(report);
  return report.regression ? kExitRegression : kExitOk;
}

int cmdNoise(const NoiseOptions& options) {
  if (options.pairs.size() % 2 != 0)
    throw InputError(format("noise: %zu results files is not a list of pairs; give A/A pairs A1 B1 [A2 B2 ...]",
                            options.pairs.size()));
  if (options.trials == 0) throw InputError("noise: --trials 0 leaves nothing to measure; give e.g. 100");
  if (!(options.plantedPct > 0)) throw InputError("noise: --planted must be a slowdown in % > 0, e.g. 5");
  if (!(options.thresholdPct >= 0)) throw InputError("noise: --threshold must be a percentage >= 0, e.g. 5");
  if (!options.out.empty()) {
    const std::filesystem::path out(options.out);
    std::error_code ec;
    if (std::filesystem::is_directory(out, ec))
      throw InputError("noise: --out " + options.out + " is a folder; name the file to write, e.g. --out " +
                       (out / "noise.json").string());
    const std::filesystem::path dir = out.has_parent_path() ? out.parent_path() : std::filesystem::path(".");
    if (!std::filesystem::is_directory(dir, ec))
      throw InputError("noise: --out " + options.out + ": the folder " + dir.string() +
                       " does not exist; create it or write the file elsewhere");
  }
  std::vector<AaPair> pairs;
  for (size_t i = 0; i < options.pairs.size(); i += 2) {
    AaPair p{readResults(options.pairs[i]), readResults(options.pairs[i + 1]), options.pairs[i], options.pairs[i + 1]};
    results::requireResultsFile(p.a, p.nameA);
    results::requireResultsFile(p.b, p.nameB);
    pairs.push_back(std::move(p));
  }
  const NoiseModel model = buildNoiseModel(pairs);
  if (!options.out.empty()) writeFileAtomic(options.out, toJson(model).dump(2) + "\n");
  if (options.noCheck) {
    std::cout << formatNoise(model, NoiseCheck{options.plantedPct, options.thresholdPct});
    return kExitOk;
  }
  std::fprintf(stderr, "noise: %zu pairs; false alarms, then %zu detection trials a row ...\n", pairs.size(),
               options.trials);
  std::cout << formatNoise(model,
                           checkNoiseModel(pairs, model, options.plantedPct, options.thresholdPct, options.trials));
  return kExitOk;
}

}  // namespace hb

// `hybridbench merge DIR... --out DIR` (docs/fleet.md): the shards of one sweep (`sweep --shard
// K/N` on the machines of a fleet) as one results folder, as if one machine had swept them all.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <system_error>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/out_dir.h"
#include "app/sweep_results.h"
#include "base/errors.h"
#include "base/input_file.h"
#include "base/text_format.h"
#include "report/results_identity.h"
#include "report/results_json.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

struct MergePart {
  fs::path dir;
  nlohmann::json results;
};

// A field of the context as text for a message: a string as it is, anything else as JSON.
std::string mergeShown(const nlohmann::json& j) {
  if (j.is_string()) return "\"" + j.get<std::string>() + "\"";
  const std::string s = j.dump();
  return s.size() > 80 ? s.substr(0, 77) + "..." : s;
}

const nlohmann::json& mergeField(const nlohmann::json& results, std::initializer_list<const char*> path) {
  const nlohmann::json* j = &results;
  for (const char* key : path) j = &results::at(*j, key);
  return *j;
}

// Copies a variant's image folder, as hard links where the file system allows (images are never
// rewritten), else as copies.
void copyVariantImages(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  if (!fs::is_directory(from, ec)) return;
  fs::create_directories(to);
  const auto options = fs::copy_options::recursive | fs::copy_options::overwrite_existing;
  fs::copy(from, to, options | fs::copy_options::create_hard_links, ec);
  if (ec) fs::copy(from, to, options);  // another file system: plain copies
}

}  // namespace

int cmdMerge(const std::vector<std::string>& dirs, const std::string& out, bool force) {
  HB_ASSERT(!dirs.empty());
  const std::string hint = "name the folders that `sweep --shard K/N --out DIR` wrote";
  std::vector<MergePart> shards;
  for (const std::string& d : dirs) {
    fs::path dir = d;
    std::error_code ec;
    if (fs::is_regular_file(dir, ec) && (dir.filename() == "results.json" || dir.filename() == "results.json.gz"))
      dir = dir.parent_path();
    // A committed part keeps its results gzipped (docs/results-format.md "Committed results").
    const fs::path path = !fs::exists(dir / "results.json", ec) && fs::exists(dir / "results.json.gz", ec)
                              ? dir / "results.json.gz"
                              : dir / "results.json";
    const std::string text = readInputText(path, hint);
    nlohmann::json r = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
    if (r.is_discarded()) throw InputError(path.string() + ": not valid JSON; " + hint);
    results::requireResultsFile(r, path.string());
    if (!r.contains("context") || !r["context"].is_object())
      throw InputError(path.string() + ": no context block; " + hint);
    shards.push_back({dir, std::move(r)});
  }
  for (size_t i = 0; i < shards.size(); ++i)
    for (size_t k = 0; k < i; ++k)
      if (fs::weakly_canonical(shards[i].dir) == fs::weakly_canonical(shards[k].dir))
        throw InputError("merge: " + shards[i].dir.string() + " is named twice; name each shard's folder once");

  // One sweep's shards: the same config, scene, revision and device name (devices differ only with
  // --force: then each run records its own). The config is compared with its file paths aside
  // (results_identity.h): machines of a fleet hold the same scene at their own paths, and its
  // content is the scene hash.
  const MergePart& first = shards[0];
  struct MergeCheck {
    const char* what;
    std::initializer_list<const char*> path;
    bool forceable;
  };
  const std::vector<MergeCheck> checks = {{"config", {"context", "config"}, false},
                                          {"scene hash", {"context", "scene", "sha256"}, false},
                                          {"revision", {"context", "tool", "git"}, false},
                                          {"device name", {"context", "device", "name"}, true}};
  bool mixedDevices = false;
  for (const MergeCheck& c : checks) {
    const bool config = std::string(c.what) == "config";
    const nlohmann::json a =
        config ? results::configIdentity(mergeField(first.results, c.path)) : mergeField(first.results, c.path);
    if (a.is_null()) throw InputError((first.dir / "results.json").string() + ": no context " + c.what + "; " + hint);
    for (size_t i = 1; i < shards.size(); ++i) {
      const nlohmann::json b = config ? results::configIdentity(mergeField(shards[i].results, c.path))
                                      : mergeField(shards[i].results, c.path);
      if (a == b) continue;
      if (c.forceable && force) {
        mixedDevices = true;
        continue;
      }
      std::string values =
          mergeShown(a) + " in " + first.dir.string() + ", " + mergeShown(b) + " in " + shards[i].dir.string();
      if (a.is_object() && b.is_object()) {  // a config: where the two first differ
        const nlohmann::json patch = nlohmann::json::diff(a, b);
        values = "at " + patch[0].value("path", std::string("/")) + ": " + first.dir.string() + " and " +
                 shards[i].dir.string() + " differ";
      }
      throw InputError(
          "merge: the " + std::string(c.what) + " differs (" + values + "); merge only the parts of one sweep" +
          (c.forceable ? " (--force merges parts from devices of different names, recording each run's)" : ""));
    }
  }

  for (size_t i = 1; i < shards.size(); ++i) {
    const nlohmann::json& contextA = first.results["context"];
    const nlohmann::json& contextB = shards[i].results["context"];
    const std::string content =
        results::contentDifference(contextA, contextB, first.dir.string(), shards[i].dir.string());
    if (!content.empty()) throw InputError("merge: " + content + "; merge only the parts of one sweep");
    const std::vector<results::MovedInput> moved = results::movedInputs(contextA, contextB);
    if (!moved.empty())
      std::fprintf(
          stderr, "warning: merge: %s\n",
          results::describeMovedInputs(moved, contextA, true, first.dir.string(), shards[i].dir.string()).c_str());
  }

  // Every variant of the config exactly once.
  const nlohmann::json& variants = mergeField(first.results, {"context", "config", "variants"});
  if (!variants.is_array())
    throw InputError((first.dir / "results.json").string() + ": context.config has no variants; " + hint);
  std::map<std::string, size_t> position;
  for (size_t k = 0; k < variants.size(); ++k) position[variants[k].value("name", std::string())] = k;
  std::vector<nlohmann::json> slots(variants.size());
  std::vector<const MergePart*> from(variants.size(), nullptr);
  for (const MergePart& s : shards)
    for (const nlohmann::json& run : s.results["runs"]) {
      const std::string name = run.value("name", std::string());
      const auto it = position.find(name);
      if (it == position.end())
        throw InputError("merge: " + (s.dir / "results.json").string() + " holds run \"" + name +
                         "\", which is no variant of its config; " + hint);
      if (from[it->second])
        throw InputError("merge: variant \"" + name + "\" is in both " + from[it->second]->dir.string() + " and " +
                         s.dir.string() + "; merge each part once (two sweeps of one part: keep one)");
      slots[it->second] = run;
      from[it->second] = &s;
    }
  std::vector<std::string> missing;
  for (size_t k = 0; k < variants.size(); ++k)
    if (!from[k]) missing.push_back("\"" + variants[k].value("name", std::string()) + "\"");
  if (!missing.empty()) {
    // The parts absent, where the shards say how many there are.
    std::set<size_t> seen;
    size_t count = 0;
    for (const MergePart& s : shards) {
      const nlohmann::json& sh = mergeField(s.results, {"context", "shard"});
      if (sh.is_object()) {
        seen.insert(sh.value("index", size_t(0)));
        count = sh.value("count", size_t(0));
      }
    }
    std::string parts;
    for (size_t k = 0; k < count; ++k)
      if (!seen.count(k)) parts += (parts.empty() ? "" : ", ") + format("%zu/%zu", k, count);
    throw InputError("merge: " + countOf(missing.size(), "variant") + " of the config in no folder given (" +
                     missing[0] + (missing.size() > 1 ? ", ..." : "") + ")" +
                     (parts.empty() ? "" : "; missing part(s) " + parts) +
                     "; sweep the missing part(s) (sweep --shard K/N) and merge every part's folder");
  }

  // The merged context: the first part's, without its shard, and where every part came from.
  nlohmann::json merged = first.results;
  nlohmann::json& context = merged["context"];
  context.erase("shard");
  context["merged_from"] = nlohmann::json::array();
  for (const MergePart& s : shards) {
    const nlohmann::json& c = s.results["context"];
    nlohmann::json entry = {{"dir", s.dir.string()},
                            {"runs", s.results["runs"].size()},
                            {"device", mergeField(c, {"device", "name"})},
                            {"host", mergeField(c, {"host", "hostname"})},
                            {"date", mergeField(c, {"host", "date"})}};
    if (const nlohmann::json paths = results::inputPaths(c); !paths.empty()) entry["paths"] = paths;
    if (c.contains("shard"))
      entry["shard"] = {{"index", c["shard"].value("index", 0)}, {"count", c["shard"].value("count", 0)}};
    context["merged_from"].push_back(entry);
  }
  merged["runs"] = nlohmann::json::array();
  std::set<std::string> devices;
  for (size_t k = 0; k < slots.size(); ++k) {
    nlohmann::json run = slots[k];
    const nlohmann::json& device = mergeField(from[k]->results, {"context", "device"});
    devices.insert(device.value("name", std::string("?")));
    if (mixedDevices) run["device"] = {{"name", device.value("name", "")}, {"uuid", device.value("uuid", "")}};
    merged["runs"].push_back(run);
  }
  if (mixedDevices) {
    context["mixed_devices"] = devices;
    std::string list;
    for (const std::string& d : devices) list += (list.empty() ? "" : ", ") + d;
    std::fprintf(stderr,
                 "warning: merge --force: the parts ran on different devices (%s); each run records its own "
                 "(runs[].device), and times compare only between runs of one device\n",
                 list.c_str());
  }

  // Every input has been read and checked: only now is --out touched. An --out holding results
  // is refused (or with --force moved aside, as sweep does), never overwritten.
  const fs::path outDir = out;
  std::error_code ec;
  if (fs::exists(outDir / "results.json", ec) && force)
    for (const MergePart& s : shards) {
      const fs::path a = fs::weakly_canonical(s.dir), o = fs::weakly_canonical(outDir);
      if (std::mismatch(o.begin(), o.end(), a.begin(), a.end()).first == o.end())
        throw InputError("merge --out " + out + ": holds " + s.dir.string() +
                         ", which --force would move aside with the earlier results; merge into another folder");
    }
  const std::string aside =
      prepareOutDir(outDir, "results.json", force ? Existing::Replace : Existing::Refuse, "merge", /*resumable=*/false);
  if (!aside.empty()) std::printf("--force: moved the earlier results in %s to %s/\n", out.c_str(), aside.c_str());
  fs::create_directories(outDir);
  for (size_t k = 0; k < slots.size(); ++k) {
    const std::string folder = slug(slots[k].value("name", std::string()));
    if (fs::weakly_canonical(from[k]->dir) != fs::weakly_canonical(outDir))
      copyVariantImages(from[k]->dir / folder, outDir / folder);
  }
  writeSweepOutputs(outDir.string(), merged);
  std::printf(
      "merged %s from %s into %s: report.html (open it), results.json, results.csv, tables.md, accuracy.md, "
      "accuracy.svg, roofline.md, roofline.svg and each variant's images\n",
      countOf(slots.size(), "run").c_str(), countOf(shards.size(), "folder").c_str(), out.c_str());
  return kExitOk;
}

}  // namespace hb

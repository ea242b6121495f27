#include "app/out_dir.h"

#include <ctime>
#include <fstream>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/errors.h"
#include "base/input_file.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

// What the marker holds, for the message: "results.json, 12 runs".
std::string describeMarker(const fs::path& marker) {
  std::ifstream f(marker);
  const nlohmann::json j = nlohmann::json::parse(f, nullptr, /*allow_exceptions=*/false);
  if (j.is_object() && j.contains("runs") && j["runs"].is_array())
    return marker.filename().string() + " with " + std::to_string(j["runs"].size()) + " run(s)";
  return marker.filename().string();
}

}  // namespace

std::string prepareOutDir(const fs::path& dir, const std::string& marker, Existing existing, const std::string& command,
                          bool resumable) {
  requireOutputFolder(dir, command + " --out");
  std::error_code ec;
  if (!fs::exists(dir / marker, ec) || existing == Existing::Resume) return {};
  if (existing == Existing::Refuse)
    throw InputError(command + " --out " + dir.string() + ": the folder already holds results (" +
                     describeMarker(dir / marker) + "); " + (resumable ? "continue them with --resume, " : "") +
                     "replace them with --force (the old files move to " + (dir / "previous-<time>").string() +
                     "/), or give a fresh folder");
  std::time_t now = std::time(nullptr);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", std::gmtime(&now));
  fs::path aside = dir / (std::string("previous-") + stamp);
  for (int k = 2; fs::exists(aside, ec); ++k)
    aside = dir / (std::string("previous-") + stamp + "-" + std::to_string(k));
  std::vector<fs::path> entries;
  for (const fs::directory_entry& e : fs::directory_iterator(dir))
    if (e.path().filename().string().rfind("previous-", 0) != 0) entries.push_back(e.path());
  fs::create_directories(aside);
  for (const fs::path& p : entries) fs::rename(p, aside / p.filename());
  return aside.string();
}

}  // namespace hb

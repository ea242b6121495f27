#include "app/sweep_resume.h"

#include <fstream>
#include <optional>
#include <sstream>
#include <vector>

#include "base/errors.h"
#include "base/json_diff.h"
#include "base/text_format.h"
#include "report/results_identity.h"

namespace hb {

using json = nlohmann::json;

namespace {

// The program as the shell started it (argv[0]: "build/hybridbench", "hybridbench", ...): the
// command is run from the same folder. "hybridbench" where /proc cannot say.
std::string programName() {
  std::ifstream f("/proc/self/cmdline", std::ios::binary);
  std::string first;
  std::getline(f, first, '\0');
  return first.empty() ? "hybridbench" : first;
}

// One word for a POSIX shell: as it is when it holds only characters no shell treats specially,
// else in single quotes (a single quote inside as '\'').
std::string shellWord(const std::string& s) {
  const std::string plain = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-+=.,/:@%";
  if (!s.empty() && s.find_first_not_of(plain) == std::string::npos) return s;
  std::string quoted = "'";
  for (char c : s) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

std::string shardText(const json& shard) {
  return shard.is_object() ? format("--shard %zu/%zu", shard.value("index", size_t(0)), shard.value("count", size_t(0)))
                           : std::string("no --shard");
}

}  // namespace

ResumedResults readResumable(const std::string& resultsPath, const json& inputs, const DeviceInfo& device,
                             const json& shard, bool retryFailed) {
  std::ifstream f(resultsPath);
  json old;
  try {
    old = json::parse(f);
  } catch (const std::exception& e) {
    throw InputError(resultsPath + ": cannot resume, not valid JSON (" + e.what() +
                     "); remove it or use another --out");
  }
  const json& oc = old.value("context", json::object());
  const char* advice = "; resume with the options the interrupted sweep ran with, or use another --out";
  if (const auto d = firstDifference(results::configIdentity(oc.value("config", json())),
                                     results::configIdentity(inputs.value("config", json())), "config"))
    throw InputError(resultsPath +
                     ": --resume needs the config the interrupted sweep ran (frame counts included), and " +
                     describeDifference(*d, "interrupted sweep", "this one") + advice);
  if (const std::string content = results::contentDifference(oc, inputs, "the interrupted sweep", "this one");
      !content.empty())
    throw InputError(resultsPath + ": --resume needs the scene the interrupted sweep ran, and " + content + advice);
  const json oldDevice = oc.value("device", json::object());
  if (oldDevice.value("uuid", "") != device.uuid)
    throw InputError(resultsPath + ": --resume needs the device of the interrupted sweep, " +
                     oldDevice.value("name", std::string("unknown")) + " (UUID " + oldDevice.value("uuid", "") +
                     "); this one is " + device.name + " (UUID " + device.uuid + ")" + advice);
  const std::string was = shardText(oc.value("shard", json())), now = shardText(shard);
  if (was != now)
    throw InputError(resultsPath + ": --resume needs the same part as the interrupted sweep, which ran with " + was +
                     " (this one: " + now + "); use another --out");
  ResumedResults r;
  if (const std::vector<results::MovedInput> moved = results::movedInputs(oc, inputs); !moved.empty())
    r.warnings.push_back("--resume: " + results::describeMovedInputs(moved, oc, true, "interrupted sweep", "this one"));
  if (old.contains("context")) r.context = old["context"];
  for (const json& run : old.value("runs", json::array())) {
    const std::string status = run.value("status", "");
    // ok: done. timeout and crashed: kept unless --retry-failed. error: run again.
    if (status == "ok" || ((status == "timeout" || status == "crashed") && !retryFailed))
      r.kept[run.value("name", "")] = run;
  }
  return r;
}

void appendRunOptions(std::vector<std::string>& a, const SweepOptions& options) {
  if (options.frames > 0) a.insert(a.end(), {"--frames", std::to_string(options.frames)});
  if (options.warmup >= 0) a.insert(a.end(), {"--warmup", std::to_string(options.warmup)});
  if (!options.images) a.push_back("--no-images");
  if (!options.scene.empty()) a.insert(a.end(), {"--scene", options.scene});
  if (!options.size.empty()) a.insert(a.end(), {"--size", options.size});
  for (const std::string& set : options.sets) a.insert(a.end(), {"--set", set});
}

std::string resumeCommand(const SweepOptions& options, const DeviceInfo& device, const std::string& outDir,
                          bool severalDevices, bool retryFailed) {
  std::vector<std::string> a = {programName(), "sweep"};
  if (!options.config.empty()) a.push_back(options.config);
  a.push_back("--resume");
  if (retryFailed) a.push_back("--retry-failed");
  // Several devices with --out: the same --device and --out resume every device's folder. Without
  // --out each device has its own out/... folder, resumed one at a time.
  const bool whole = severalDevices && !options.out.empty();
  a.insert(a.end(), {"--out", whole ? options.out : outDir});
  if (whole)
    a.insert(a.end(), {"--device", options.device});
  else if (severalDevices)
    a.insert(a.end(), {"--device", std::to_string(device.index)});
  else if (!options.device.empty())
    a.insert(a.end(), {"--device", options.device});
  appendRunOptions(a, options);
  if (options.variantTimeout > 0) a.insert(a.end(), {"--variant-timeout", format("%g", options.variantTimeout)});
  if (!options.shard.empty()) a.insert(a.end(), {"--shard", options.shard});
  std::string command;
  for (const std::string& word : a) command += (command.empty() ? "" : " ") + shellWord(word);
  return command;
}

}  // namespace hb

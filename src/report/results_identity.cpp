#include "report/results_identity.h"

#include <algorithm>
#include <cctype>
#include <utility>

#include "base/text_format.h"
#include "report/results_json.h"

namespace hb::results {

using nlohmann::json;

namespace {

constexpr const char* kAFile = "(a file)";

// A glTF path rather than a built-in scene's name ("atrium", "grazing", ...): config.cpp resolves
// a .gltf/.glb to an absolute path, and a built-in's name never has an extension.
bool isScenePath(const json& scene) {
  if (!scene.is_string()) return false;
  const std::string s = asciiLower(scene.get<std::string>());
  auto endsWith = [&](const std::string& tail) {
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
  };
  return endsWith(".gltf") || endsWith(".glb");
}

std::string textOf(const json& v) { return v.is_string() ? v.get<std::string>() : std::string(); }

}  // namespace

json configIdentity(json config) {
  if (!config.is_object()) return config;
  if (config.contains("scene") && isScenePath(config["scene"])) config["scene"] = kAFile;
  if (config.contains("environment") && config["environment"].is_object() && config["environment"].contains("image"))
    config["environment"]["image"] = kAFile;
  return config;
}

json inputPaths(const json& context) {
  json paths = json::object();
  const json& config = at(context, "config");
  const std::pair<const char*, std::string> recorded[] = {
      {"config", textOf(at(context, "config_file"))},
      {"scene", isScenePath(at(config, "scene")) ? textOf(at(config, "scene")) : std::string()},
      {"environment", textOf(at(at(config, "environment"), "image"))}};
  for (const auto& [key, path] : recorded)
    if (!path.empty()) paths[key] = path;
  return paths;
}

std::vector<MovedInput> movedInputs(const json& contextA, const json& contextB) {
  const json a = inputPaths(contextA), b = inputPaths(contextB);
  std::vector<MovedInput> moved;
  for (const char* key : {"config", "scene", "environment"})
    if (a.contains(key) && b.contains(key) && a[key] != b[key]) moved.push_back({key, a[key], b[key]});
  return moved;
}

std::string describeMovedInputs(const std::vector<MovedInput>& moved, const json& contextA, bool sameContent,
                                const std::string& labelA, const std::string& labelB) {
  std::string sha = textOf(at(at(contextA, "scene"), "sha256"));
  if (sha.size() > 12) sha = sha.substr(0, 12) + "...";
  std::string line = "the inputs lie at other paths";
  if (sameContent) line += ", their content the same" + (sha.empty() ? std::string() : " (scene sha256 " + sha + ")");
  line += ": ";
  for (size_t i = 0; i < moved.size(); ++i)
    line += (i ? "; " : "") + moved[i].what + " (" + labelA + ": \"" + moved[i].a + "\", " + labelB + ": \"" +
            moved[i].b + "\")";
  return line;
}

std::string contentDifference(const json& contextA, const json& contextB, const std::string& labelA,
                              const std::string& labelB) {
  const json& sceneA = at(contextA, "scene");
  const json& sceneB = at(contextB, "scene");
  const std::pair<const char*, const char*> hashes[] = {{"sha256", "the scenes"},
                                                        {"environment_sha256", "the environment images"}};
  for (const auto& [key, what] : hashes) {
    const json &a = at(sceneA, key), &b = at(sceneB, key);
    // The scene's hash must be on both sides; an environment's only where both record one (files
    // written before it was recorded, or sweeps without an image).
    if (a == b || (std::string(key) != "sha256" && (a.is_null() || b.is_null()))) continue;
    auto shown = [](const json& v) { return v.is_string() ? v.get<std::string>() : std::string("(none)"); };
    return std::string(what) + " differ in content: context.scene." + key + " is " + shown(a) + " in " + labelA +
           " and " + shown(b) + " in " + labelB;
  }
  return "";
}

std::string tracerOfRun(const json& run) { return textOf(at(at(run, "backend_choice"), "ran")); }

std::string throttleWarningOf(const json& measured) { return textOf(at(at(measured, "telemetry"), "warning")); }

std::string tracedBy(const json& results) {
  std::vector<std::pair<std::string, std::vector<std::string>>> byTracer;  // in first-seen order
  for (const json& run : at(results, "runs")) {
    const std::string tracer = tracerOfRun(run);
    if (tracer.empty()) continue;
    auto it = std::find_if(byTracer.begin(), byTracer.end(), [&](const auto& t) { return t.first == tracer; });
    if (it == byTracer.end()) it = byTracer.insert(byTracer.end(), {tracer, {}});
    it->second.push_back(textOf(at(run, "name")));
  }
  if (byTracer.empty()) {
    const std::string device = textOf(at(at(at(results, "context"), "device"), "rt_backend"));
    return device.empty() ? device : device + " (the device's; the runs record no backend_choice)";
  }
  if (byTracer.size() == 1) return byTracer[0].first;
  std::string line;
  for (const auto& [tracer, runs] : byTracer) {
    std::string names;
    for (const std::string& n : runs) names += (names.empty() ? "" : ", ") + n;
    line += (line.empty() ? "" : ", ") + tracer + " (" + std::to_string(runs.size()) +
            (runs.size() == 1 ? " run: " : " runs: ") + names + ")";
  }
  return line;
}

}  // namespace hb::results

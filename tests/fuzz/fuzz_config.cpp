// libFuzzer target for the config parser: any bytes as a config file's text, parsed as loadConfig
// parses a file (json_reader::parseText, then parseConfig). InputError is the parser's answer to
// bad input, not a finding. A finding is anything else: another exception escaping, a crash, a
// sanitizer report, a leak, a timeout, or a config that breaks what config.h promises: finite
// lights and camera, runs that are non-empty with unique names, parseConfig(toJson(c)) expanding
// to the same runs, and lowerForCpuDevice keeping their names.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <glm/glm.hpp>
#include <set>
#include <string>
#include <vector>

#include "base/errors.h"
#include "base/json_reader.h"
#include "config/config.h"

#define FUZZ_TARGET_NAME "fuzz_config"
#include "fuzz_checks.h"

namespace {

// Its directory does not exist: a relative "scene" path resolves into it and is never read.
constexpr const char* kSource = "/nonexistent-hybridbench-fuzz-dir/fuzz.json";

using hb::fuzz::finite;

bool sameRuns(const std::vector<hb::Variant>& a, const std::vector<hb::Variant>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].name != b[i].name || !(a[i].params == b[i].params)) return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  hb::Config config;
  try {
    config = hb::parseConfig(hb::json_reader::parseText(text, kSource), kSource);
  } catch (const hb::InputError&) {
    return 0;
  }
  // What the renderer takes from the config as it is: finite lights and camera.
  for (const hb::Light& l : config.lights.value_or(std::vector<hb::Light>{})) {
    FUZZ_CHECK(finite(l.position) && finite(l.direction) && finite(l.color));
    FUZZ_CHECK(std::isfinite(l.intensity) && std::isfinite(l.range));
  }
  if (config.camera.explicitPose) FUZZ_CHECK(finite(hb::cameraFromSpec(config.camera).view));

  const std::vector<hb::Variant> runs = hb::expandVariants(config);
  FUZZ_CHECK(!runs.empty());
  std::set<std::string> names;
  for (const hb::Variant& run : runs) FUZZ_CHECK(names.insert(run.name).second);

  // The results file's effective config must read back as the same sweep; an InputError here
  // escapes and is a finding too.
  FUZZ_CHECK(sameRuns(hb::expandVariants(hb::parseConfig(hb::toJson(config), kSource)), runs));

  const std::vector<hb::Variant> lowered = hb::expandVariants(hb::lowerForCpuDevice(config));
  FUZZ_CHECK(lowered.size() == runs.size());
  for (size_t i = 0; i < runs.size(); ++i) FUZZ_CHECK(lowered[i].name == runs[i].name);
  return 0;
}

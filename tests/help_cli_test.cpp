// `hybridbench help params|effects`: the built binary's tables against the code they are printed
// from. The lists the tables must cover are read from the parser's own answers (an unknown key
// lists the keys it accepts), not written out here, so a parameter or effect added to the code
// without reaching the help fails a test.
#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "base/errors.h"
#include "config/config.h"
#include "plan/effects.h"
#include "tool_process.h"

namespace {

using namespace hb::testing;

// The keys listed in an InputError's "(allowed: a, b, c)".
std::vector<std::string> allowedKeysOf(const std::string& message) {
  const std::string marker = "(allowed: ";
  const size_t at = message.find(marker);
  if (at == std::string::npos) return {};
  const size_t end = message.find(')', at);
  std::stringstream list(message.substr(at + marker.size(), end - at - marker.size()));
  std::vector<std::string> keys;
  for (std::string k; std::getline(list, k, ',');) keys.push_back(k[0] == ' ' ? k.substr(1) : k);
  return keys;
}

// A key nothing accepts and no did-you-mean matches, so the error lists every accepted key.
const char* const kUnknownKey = "~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~";

// Every parameter key the config parser accepts in a params object ("defaults", a variant's params).
std::vector<std::string> parserParamKeys() {
  const nlohmann::ordered_json doc = {{"name", "x"}, {"defaults", {{kUnknownKey, 0}}}};
  try {
    hb::parseConfig(doc, "x.json");
  } catch (const hb::InputError& e) {
    return allowedKeysOf(e.what());
  }
  return {};
}

// Every effect key the config parser accepts in "effects".
std::vector<std::string> parserEffectKeys() {
  const nlohmann::ordered_json doc = {{"name", "x"}, {"effects", {{kUnknownKey, true}}}};
  try {
    hb::parseConfig(doc, "x.json");
  } catch (const hb::InputError& e) {
    return allowedKeysOf(e.what());
  }
  return {};
}

bool setIsAccepted(const std::string& keyEqualsValue) {
  hb::VariantParams p;
  try {
    hb::applySetOverride(p, keyEqualsValue);
  } catch (const hb::InputError&) {
    return false;
  }
  return true;
}

class HelpCli : public ToolTest {
 protected:
  nlohmann::json runJson(const std::string& topic) {
    const RunResult r = run({"help", topic, "--format", "json"});
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return nlohmann::json::parse(r.out, nullptr, /*allow_exceptions=*/false);
  }
};

TEST_F(HelpCli, TheParserListsItsKeys) {
  // The derivation the other tests rely on: without it they would check nothing.
  const std::vector<std::string> params = parserParamKeys();
  EXPECT_GE(params.size(), 10u);
  EXPECT_NE(std::find(params.begin(), params.end(), "tile_size"), params.end());
  const std::vector<std::string> effects = parserEffectKeys();
  EXPECT_EQ(effects.size(), hb::allEffects().size());
}

TEST_F(HelpCli, EveryParameterTheParserAcceptsIsARowOfHelpParams) {
  for (const char* format : {"md", "text"}) {
    const RunResult r = run({"help", "params", "--format", format});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    for (const std::string& key : parserParamKeys()) {
      const std::string row = std::string(format) == "md" ? "\n| " + key + " |" : "\n" + key + "\n";
      EXPECT_NE(("\n" + r.out).find(row), std::string::npos) << format << ": no row for " << key << "\n" << r.out;
    }
  }
}

TEST_F(HelpCli, MarkdownIsOneTableAndTheSameOnEveryRun) {
  const RunResult a = run({"help", "params", "--format", "md"});
  const RunResult b = run({"help", "params", "--format", "md"});
  ASSERT_EQ(a.exitCode, 0) << a.err;
  EXPECT_EQ(a.out, b.out);
  std::stringstream lines(a.out);
  size_t n = 0;
  for (std::string line; std::getline(lines, line); ++n) {
    EXPECT_EQ(line.front(), '|') << line;
    EXPECT_EQ(line.back(), '|') << line;
  }
  EXPECT_EQ(n, parserParamKeys().size() + 2);  // header, separator, a row per parameter
}

// What help says a parameter takes, the parser takes: its default, each choice, both ends of its
// range; and it refuses a value just outside.
TEST_F(HelpCli, ParamsJsonDescribesWhatTheParserAccepts) {
  const nlohmann::json j = runJson("params");
  ASSERT_TRUE(j.contains("params")) << j.dump();
  std::vector<std::string> names;
  for (const auto& p : j["params"]) {
    const std::string key = p["name"];
    names.push_back(key);
    SCOPED_TRACE(key);
    EXPECT_FALSE(p.value("description", "").empty());
    EXPECT_FALSE(p.value("allowed", "").empty());
    if (p.contains("default")) {
      EXPECT_TRUE(setIsAccepted(key + "=" + p["default"].dump()));
    }
    if (p.contains("choices")) {
      for (const auto& c : p["choices"]) EXPECT_TRUE(setIsAccepted(key + "=" + c.dump())) << c;
      EXPECT_FALSE(setIsAccepted(key + "=" + (p["type"] == "string" ? "\"no-such-choice\"" : "7")));
    }
    if (p.contains("min") && p["type"] != "[integer, integer]") {
      const double lo = p["min"], hi = p["max"];
      const bool integer = p["type"] == "integer";
      auto text = [&](double v) { return integer ? std::to_string(int64_t(v)) : nlohmann::json(v).dump(); };
      // max_lights_per_tile's ends are multiples of 32 and depth_slices' 0 and 32 are allowed.
      EXPECT_TRUE(setIsAccepted(key + "=" + text(lo)));
      EXPECT_TRUE(setIsAccepted(key + "=" + text(hi)));
      EXPECT_FALSE(setIsAccepted(key + "=" + text(integer ? hi + 1 : hi * 2)));
    }
  }
  std::vector<std::string> expected = parserParamKeys();
  EXPECT_EQ(names, expected);  // every parameter, in schema order
}

TEST_F(HelpCli, EveryEffectIsARowOfHelpEffectsWithItsPasses) {
  const RunResult r = run({"help", "effects", "--format", "md"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::vector<std::string> keys = parserEffectKeys();
  ASSERT_FALSE(keys.empty());
  for (const std::string& key : keys) {
    const hb::EffectDef* e = hb::findEffect(key);
    ASSERT_NE(e, nullptr) << key;
    const size_t row = ("\n" + r.out).find("\n| " + key + " | " + e->defaultValue.dump() + " |");
    ASSERT_NE(row, std::string::npos) << "no row for " << key << "\n" << r.out;
    const std::string line = r.out.substr(row, r.out.find('\n', row) - row);
    for (const char* pass : e->passes) EXPECT_NE(line.find(pass), std::string::npos) << key << ": " << pass;
  }
  const nlohmann::json j = runJson("effects");
  ASSERT_EQ(j["effects"].size(), keys.size()) << j.dump();
  for (const auto& e : j["effects"]) {
    if (e["name"] != "ambient_occlusion") continue;
    const std::string settings = e["settings"].dump();
    EXPECT_NE(settings.find("\"method\""), std::string::npos) << settings;
    EXPECT_NE(settings.find("1..2048"), std::string::npos) << settings;  // directions' range
  }
}

TEST_F(HelpCli, UnknownTopicOrFormatIsOneLineAndExitTwo) {
  expectRefused({"help", "colours"}, {"colours", "params", "effects"});
  expectRefused({"help", "params", "--format", "xml"}, {"xml", "md", "json"});
  expectRefused({"help"}, {"params", "effects"});
}

// --help says what the tool is now: a benchmark of hybrid rendering, with each of its parts (every
// effect the binary has, by name) and what it does with them; not the thesis's renderer alone.
TEST_F(HelpCli, HelpSaysTheToolBenchmarksHybridRenderingAndNamesEveryEffect) {
  const RunResult r = run({"--help"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::string about = r.out.substr(0, r.out.find('\n'));
  for (const char* part : {"hybrid rendering", "Forward+", "3D rasterization", "layered depth maps", "sweeps",
                           "GPU pass", "rays", "accuracy", "compares"})
    EXPECT_NE(about.find(part), std::string::npos) << "--help's first line does not say \"" << part << "\": " << about;
  for (const hb::EffectDef* e : hb::allEffects()) {
    std::string words = e->name;
    std::replace(words.begin(), words.end(), '_', ' ');
    EXPECT_NE(about.find(words), std::string::npos) << "--help does not name the effect " << e->name << ": " << about;
  }
}

TEST_F(HelpCli, TextAndJsonFormatsExitZero) {
  for (const char* topic : {"params", "effects"})
    for (const char* format : {"text", "json"}) {
      const RunResult r = run({"help", topic, "--format", format});
      EXPECT_EQ(r.exitCode, 0) << topic << " " << format << ": " << r.err;
      EXPECT_FALSE(r.out.empty());
    }
}

}  // namespace

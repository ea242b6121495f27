#include "plan/effects.h"

#include <gtest/gtest.h>

#include "base/input_error_of.h"
#include "effects/ambient_occlusion/ao_effect.h"
#include "effects/indirect/indirect_effect.h"

#include <charconv>
#include <string>

namespace hb {
namespace {

Scene sceneWithLights(std::vector<Light> lights) {
  Scene s;
  s.name = "test";
  s.lights = std::move(lights);
  return s;
}

Light pointLight(bool castShadows = true) {
  Light l;
  l.type = LightType::Point;
  l.range = 5.0f;
  l.castShadows = castShadows;
  return l;
}

const EffectState& stateOf(const FramePlan& plan, const std::string& name) {
  for (const EffectState& e : plan.effects)
    if (e.name == name) return e;
  throw std::runtime_error("no effect " + name);
}

TEST(Effects, DefaultsCallForShadowsAndTheFrameHasEveryPassInFrameOrder) {
  const FramePlan plan = planFrame(sceneWithLights({pointLight()}), {});
  EXPECT_EQ(plan.passes, (std::vector<std::string>{"depth_prepass", "light_culling", "shadows", "shading"}));
  // Ambient occlusion, indirect and environment light are off unless called for: their passes are
  // listed with that reason.
  const std::string off = "effects.ambient_occlusion is off (default)", offInd = "effects.indirect is off (default)",
                    offEnv = "effects.environment_light is off (default)";
  EXPECT_EQ(plan.skipped, (std::vector<std::pair<std::string, std::string>>{{"ldm_build", off},
                                                                            {"ambient_occlusion", off},
                                                                            {"indirect_ldm_build", offInd},
                                                                            {"photon_trace", offInd},
                                                                            {"photon_splat", offInd},
                                                                            {"indirect_gather", offInd},
                                                                            {"environment_ldm_build", offEnv},
                                                                            {"environment_light", offEnv}}));
  EXPECT_FALSE(plan.needs(FrameResource::LayeredDepthMaps));
  EXPECT_TRUE(plan.needs(FrameResource::AccelerationStructures));
  const EffectState& s = stateOf(plan, "shadows");
  EXPECT_EQ(s.source, EffectSource::Default);
  EXPECT_TRUE(s.runs);
}

TEST(Effects, PrecedenceIsDefaultThenSceneThenConfigThenSet) {
  Scene scene = sceneWithLights({pointLight()});
  scene.effects = {{"shadows", false}};
  scene.effectsOrigin = "scene.gltf";
  FramePlan plan = planFrame(scene, {});
  EXPECT_FALSE(plan.runs("shadows"));
  EXPECT_EQ(stateOf(plan, "shadows").source, EffectSource::Scene);
  EXPECT_FALSE(plan.needs(FrameResource::AccelerationStructures));  // nothing allocated for an effect that is off
  EXPECT_FALSE(plan.hasPass("shadows"));
  // shadows, then AO's 2, the indirect light's 4 and the environment light's 2 passes (off by default)
  ASSERT_EQ(plan.skipped.size(), 9u);
  EXPECT_EQ(plan.skipped[0].first, "shadows");
  EXPECT_EQ(plan.skipped[0].second, "effects.shadows is off (scene: scene.gltf)");

  EffectsRequest request;
  request.add(EffectSource::Config, "c.json", {{"shadows", true}});
  plan = planFrame(scene, request);
  EXPECT_TRUE(plan.runs("shadows"));
  EXPECT_EQ(stateOf(plan, "shadows").source, EffectSource::Config);
  EXPECT_EQ(stateOf(plan, "shadows").origin, "c.json");

  request.layers.push_back(parseEffectSet("shadows=false"));
  plan = planFrame(scene, request);
  EXPECT_FALSE(plan.runs("shadows"));
  EXPECT_EQ(stateOf(plan, "shadows").source, EffectSource::Set);
  EXPECT_EQ(stateOf(plan, "shadows").origin, "--set shadows=false");
}

// Ambient occlusion (effects/ambient_occlusion/ao_effect.h): it needs an ambient term; the method decides
// what the frame builds: LDMs for "ldm" (no acceleration structures if nothing else needs them),
// the ray tracer for "raytraced" and "reference" (no maps; ldm_build listed as unused).
TEST(Effects, AmbientOcclusionNeedsAnAmbientTermAndBuildsOnlyWhatItsMethodUses) {
  Scene scene = sceneWithLights({pointLight()});
  EffectsRequest request;
  request.add(EffectSource::Config, "c.json", {{"shadows", false}, {"ambient_occlusion", true}});
  FramePlan plan = planFrame(scene, request);
  EXPECT_FALSE(plan.runs("ambient_occlusion"));
  EXPECT_EQ(stateOf(plan, "ambient_occlusion").skippedBecause,
            "the scene has no ambient term (add extras.ambient to the glTF scene or \"ambient\" to the config)");
  EXPECT_FALSE(plan.needs(FrameResource::LayeredDepthMaps));

  scene.ambient = Ambient{{1, 1, 1}, 0.5f};
  plan = planFrame(scene, request);
  EXPECT_TRUE(plan.runs("ambient_occlusion"));
  EXPECT_EQ(plan.passes,
            (std::vector<std::string>{"depth_prepass", "light_culling", "ldm_build", "ambient_occlusion", "shading"}));
  EXPECT_TRUE(plan.needs(FrameResource::LayeredDepthMaps));
  EXPECT_FALSE(plan.needs(FrameResource::AccelerationStructures));

  request.layers.push_back(parseEffectSet(R"(ambient_occlusion={"method": "raytraced", "directions": 128})"));
  plan = planFrame(scene, request);
  EXPECT_EQ(plan.passes, (std::vector<std::string>{"depth_prepass", "light_culling", "ambient_occlusion", "shading"}));
  EXPECT_FALSE(plan.needs(FrameResource::LayeredDepthMaps));
  EXPECT_TRUE(plan.needs(FrameResource::AccelerationStructures));
  EXPECT_EQ(aoSettingsOf(stateOf(plan, "ambient_occlusion").value).directions, 128u);

  scene.ambient->intensity = 0.0f;
  EXPECT_EQ(stateOf(planFrame(scene, request), "ambient_occlusion").skippedBecause,
            "the scene's ambient intensity is 0");
}

TEST(Effects, AmbientOcclusionSettingsAreCheckedWithWhereAndHowToFix) {
  EXPECT_EQ(
      inputErrorOf([] { parseEffectSet(R"(ambient_occlusion={"method": "hbao2"})"); }),
      R"(--set ambient_occlusion={"method": "hbao2"}: effects.ambient_occlusion.method: "hbao2" is not one of "ldm", "raytraced", "reference", "hbao", "gtao")");
  EXPECT_NE(inputErrorOf([] { parseEffectSet(R"(ambient_occlusion={"directions": 0})"); }).find("directions"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] { parseEffectSet(R"(ambient_occlusion={"samples": 1000})"); }).find("is not a square"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] { parseEffectSet("ambient_occlusion=12"); }).find("expected true, false or an object"),
            std::string::npos);
  const AoSettings d = aoSettingsOf(true);
  EXPECT_EQ(d.method, AoMethod::Ldm);
  EXPECT_EQ(d.directions, 64u);
  EXPECT_FALSE(d.dMax.has_value());
}

TEST(Effects, ACalledForEffectThatCannotActIsSkippedWithItsReason) {
  struct Case {
    std::vector<Light> lights;
    const char* why;
    bool lightCulling;
  };
  Light sun;
  sun.type = LightType::Directional;
  for (const Case& c : {Case{{}, "the scene has no lights", false},
                        Case{{pointLight(false), pointLight(false)}, "no light casts shadows", true},
                        Case{{sun}, "every light is directional: not supported by the tiled shadow pass yet", false}}) {
    SCOPED_TRACE(c.why);
    const FramePlan plan = planFrame(sceneWithLights(c.lights), {});
    const EffectState& s = stateOf(plan, "shadows");
    EXPECT_TRUE(s.calledFor);
    EXPECT_FALSE(s.runs);
    EXPECT_EQ(s.skippedBecause, c.why);
    EXPECT_FALSE(plan.hasPass("shadows"));
    EXPECT_FALSE(plan.needs(FrameResource::AccelerationStructures));
    EXPECT_EQ(plan.hasPass("light_culling"), c.lightCulling);
    EXPECT_TRUE(plan.hasPass("depth_prepass"));
    EXPECT_TRUE(plan.hasPass("shading"));
    const nlohmann::json j = plan.effectsJson();
    EXPECT_EQ(j["shadows"]["skipped_because"], c.why);
    EXPECT_EQ(j["shadows"]["runs"], false);
  }
}

TEST(Effects, AnUnknownEffectOrABadValueIsOneLineNamingSourceAndKeyPath) {
  const json_reader::Where where{"scene.gltf", "scenes[0].extras.effects"};
  EXPECT_EQ(inputErrorOf([&] {
              validateEffects(nlohmann::json{{"shadow", true}}, where);
            }),
            "scene.gltf: scenes[0].extras.effects: unknown key \"shadow\" (did you mean \"shadows\"?)");
  const std::string bad = inputErrorOf([&] { validateEffects(nlohmann::json{{"shadows", {{"x", 1}}}}, where); });
  EXPECT_EQ(bad.rfind("scene.gltf: scenes[0].extras.effects.shadows: ", 0), 0u) << bad;
  EXPECT_EQ(bad.find('\n'), std::string::npos) << bad;
  EXPECT_NE(inputErrorOf([&] { validateEffects(nlohmann::json::array(), where); }).find("scenes[0].extras.effects"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] { parseEffectSet("effects.bloom=true"); }).find("--set effects.bloom=true"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] { parseEffectSet("shadows=maybe"); }).find("--set shadows=maybe: effects.shadows"),
            std::string::npos);
}

TEST(Effects, SetNamesAnEffectByItsNameOrUnderEffects) {
  EXPECT_TRUE(isEffectSet("shadows=false"));
  EXPECT_TRUE(isEffectSet("effects.shadows=true"));
  EXPECT_TRUE(isEffectSet("effects.bloom=true"));  // and fails in parseEffectSet, naming it
  EXPECT_FALSE(isEffectSet("tile_size=8"));
  EXPECT_EQ(parseEffectSet("effects.shadows=true").object, (nlohmann::json{{"shadows", true}}));
}

// The schema `help effects` prints (EffectDef::settings) and the validator that reads the values
// are one: each setting's default is what the effect uses when the setting is left out, each
// choice and both ends of each range are accepted, and one step beyond each end or an unknown
// choice is refused.
bool accepts(const EffectDef& e, const std::string& setting, const nlohmann::ordered_json& value) {
  try {
    e.validate(nlohmann::ordered_json{{setting, value}}, {"test", "effects"});
    return true;
  } catch (const InputError&) {
    return false;
  }
}

TEST(Effects, EachSettingOfTheSchemaIsWhatTheValidatorAcceptsWithItsDefault) {
  size_t checked = 0;
  for (const EffectDef* e : allEffects()) {
    // The settings an effect uses when its value is `true`, as its results write them.
    nlohmann::json defaults;
    if (std::string(e->name) == "ambient_occlusion") defaults = aoSettingsOf(true).toJson();
    if (std::string(e->name) == "indirect") defaults = indirectSettingsOf(true).toJson();
    for (const EffectSetting& s : e->settings) {
      const nlohmann::ordered_json def = nlohmann::ordered_json::parse(s.defaultValue);
      EXPECT_TRUE(def.is_null() || accepts(*e, s.name, def))
          << e->name << "." << s.name << " default " << s.defaultValue;
      if (defaults.contains(s.name)) {
        EXPECT_EQ(nlohmann::json(def), defaults[s.name]) << e->name << "." << s.name;
      }
      const std::string a = s.accepts;
      if (const size_t dots = a.find(".."); dots != std::string::npos && a.find(' ') == std::string::npos) {
        int64_t lo = 0, hi = 0;
        std::from_chars(a.data(), a.data() + dots, lo);
        std::from_chars(a.data() + dots + 2, a.data() + a.size(), hi);
        EXPECT_TRUE(accepts(*e, s.name, lo) && accepts(*e, s.name, hi)) << e->name << "." << s.name << " " << a;
        EXPECT_FALSE(accepts(*e, s.name, lo - 1)) << e->name << "." << s.name << " " << a;
        EXPECT_FALSE(accepts(*e, s.name, hi + 1)) << e->name << "." << s.name << " " << a;
        ++checked;
      } else if (a.find(" | ") != std::string::npos) {
        for (size_t at = 0; at <= a.size();) {
          const size_t bar = a.find(" | ", at);
          const std::string choice = a.substr(at, bar == std::string::npos ? std::string::npos : bar - at);
          int64_t number = 0;  // a choice of numbers ("32 | 64") is given as numbers
          const auto [end, ec] = std::from_chars(choice.data(), choice.data() + choice.size(), number);
          if (ec == std::errc() && end == choice.data() + choice.size()) {
            EXPECT_TRUE(accepts(*e, s.name, number)) << e->name << "." << s.name << " " << choice;
            // The next number is refused unless it is a choice itself ("1 | 2 | 4 | 8").
            const std::string next = std::to_string(number + 1);
            const bool listed = (" | " + a + " | ").find(" | " + next + " | ") != std::string::npos;
            EXPECT_EQ(accepts(*e, s.name, number + 1), listed) << e->name << "." << s.name << " " << choice << " + 1";
          } else {
            EXPECT_TRUE(accepts(*e, s.name, choice)) << e->name << "." << s.name << " " << choice;
          }
          at = bar == std::string::npos ? a.size() + 1 : bar + 3;
        }
        EXPECT_FALSE(accepts(*e, s.name, "no-such-choice")) << e->name << "." << s.name;
        ++checked;
      }
    }
    EXPECT_FALSE(accepts(*e, "no_such_setting", 1)) << e->name;
  }
  EXPECT_GE(checked, 10u);  // ranges and choices of ambient occlusion and indirect light
}

// docs/usage.md "Precedence": a key a layer leaves out keeps the value of the layer below.
TEST(EffectLayers, AnObjectAddsItsKeysTrueKeepsTheSettingsBelowAndFalseDropsThem) {
  const nlohmann::json below = {{"method", "ldm"}, {"directions", 128}};
  EXPECT_EQ(layerEffectValue(below, {{"bounces", 2}}),
            (nlohmann::json{{"method", "ldm"}, {"directions", 128}, {"bounces", 2}}));
  EXPECT_EQ(layerEffectValue(below, {{"directions", 32}}), (nlohmann::json{{"method", "ldm"}, {"directions", 32}}));
  EXPECT_EQ(layerEffectValue(below, true), below);
  EXPECT_EQ(layerEffectValue(below, false), false);
  EXPECT_EQ(layerEffectValue(false, {{"bounces", 2}}), (nlohmann::json{{"bounces", 2}}));
  EXPECT_EQ(layerEffectValue(false, true), true);
  EXPECT_EQ(layerEffectValue(nlohmann::json(), {{"bounces", 2}}), (nlohmann::json{{"bounces", 2}}));
}

TEST(EffectLayers, ThePlanMergesSceneConfigAndSetAndNamesWhereEachSettingCameFrom) {
  Scene scene = sceneWithLights({pointLight()});
  scene.effects = {{"indirect", {{"method", "ldm"}, {"directions", 128}}}};
  scene.effectsOrigin = "box.gltf";
  EffectsRequest request;
  request.add(EffectSource::Config, "c.json", {{"indirect", {{"photons", 4}}}});
  request.layers.push_back(parseEffectSet(R"(effects.indirect={"bounces":2,"ldm_list":"sbuffer"})"));
  const FramePlan plan = planFrame(scene, request);
  const EffectState& s = stateOf(plan, "indirect");
  EXPECT_EQ(s.value,
            (nlohmann::json{
                {"method", "ldm"}, {"directions", 128}, {"photons", 4}, {"bounces", 2}, {"ldm_list", "sbuffer"}}));
  EXPECT_EQ(s.settingOrigins.at("directions"), "box.gltf");
  EXPECT_EQ(s.settingOrigins.at("photons"), "c.json");
  EXPECT_EQ(s.settingOrigins.at("bounces"), R"(--set effects.indirect={"bounces":2,"ldm_list":"sbuffer"})");
  EXPECT_TRUE(s.notes.empty());
  EXPECT_EQ(s.source, EffectSource::Set);
}

TEST(EffectLayers, BouncesWithLdmTakeSbufferWhereNoLayerChoseAListAndRefuseAnotherChoice) {
  Scene scene = sceneWithLights({pointLight()});
  EffectsRequest request;
  request.layers.push_back(parseEffectSet(R"(effects.indirect={"bounces":2})"));
  const FramePlan plan = planFrame(scene, request);
  const EffectState& s = stateOf(plan, "indirect");
  EXPECT_EQ(s.value["ldm_list"], "sbuffer");
  EXPECT_EQ(s.settingOrigins.at("ldm_list"), "chosen by the tool");
  ASSERT_EQ(s.notes.size(), 1u);
  EXPECT_EQ(s.notes[0].rfind("effects.indirect.ldm_list: \"sbuffer\", chosen by the tool: 2 bounces", 0), 0u)
      << s.notes[0];

  // One bounce, or the ray tracer: nothing to choose.
  for (const char* set :
       {R"(effects.indirect={"bounces":1})", R"(effects.indirect={"bounces":3,"method":"raytraced"})"}) {
    EffectsRequest r;
    r.layers.push_back(parseEffectSet(set));
    const FramePlan plan1 = planFrame(scene, r);
    const EffectState& e = stateOf(plan1, "indirect");
    EXPECT_FALSE(e.value.contains("ldm_list")) << set;
    EXPECT_TRUE(e.notes.empty()) << set;
  }

  // A list chosen in a lower layer is still a choice: refused, naming that layer.
  scene.effects = {{"indirect", {{"ldm_list", "cas"}}}};
  scene.effectsOrigin = "box.gltf";
  const std::string err = inputErrorOf([&] { planFrame(scene, request); });
  EXPECT_EQ(err,
            "effects.indirect.bounces: 2 bounces with method ldm need ldm_list \"sbuffer\" (its lists hold the "
            "triangle ids a photon bounces off), but ldm_list is \"cas\" (box.gltf); set \"ldm_list\": \"sbuffer\", "
            "or \"bounces\": 1");
}

}  // namespace
}  // namespace hb

#include "effects/effects.h"

#include <gtest/gtest.h>

#include "base/input_error_of.h"
#include "effects/ambient_occlusion/ao_effect.h"

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
  // Ambient occlusion and indirect light are off unless called for: their passes are listed with that reason.
  const std::string off = "effects.ambient_occlusion is off (default)", offInd = "effects.indirect is off (default)";
  EXPECT_EQ(plan.skipped, (std::vector<std::pair<std::string, std::string>>{{"ldm_build", off},
                                                                            {"ambient_occlusion", off},
                                                                            {"indirect_ldm_build", offInd},
                                                                            {"photon_trace", offInd},
                                                                            {"photon_splat", offInd},
                                                                            {"indirect_gather", offInd}}));
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
  ASSERT_EQ(plan.skipped.size(), 7u);  // shadows, then AO's 2 and the indirect light's 4 passes (off by default)
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
      R"(--set ambient_occlusion={"method": "hbao2"}: effects.ambient_occlusion.method: "hbao2" is not one of "ldm", "raytraced", "reference", "hbao")");
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

}  // namespace
}  // namespace hb

// The frame's keyed resources on the real device (frame/frame_pass.h FrameResources::build): the
// driver's acceleration structures, our BVH and each LDM set are built once a frame for their key,
// whichever and however many passes trace through them, and raybench takes the frame's BVH (built
// for it, once, where the frame traces with the driver's). Sharing changes no result: the effects
// that share one LDM set compute, bit for bit, what each computes in a frame of its own.
// The builds are counted where they happen (AccelerationStructures::buildCount,
// traceBvhBuildCount, ldmSetBuildCount), not by the cache: a part that built its own would count.
#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "effects/ambient_occlusion/ao_part.h"
#include "effects/environment_light/env_part.h"
#include "effects/indirect/indirect_part.h"
#include "effects/shadows/shadows_part.h"
#include "frame/passes/ldm_build.h"
#include "frame/renderer.h"
#include "gpu/accel.h"
#include "gpu/trace_bvh.h"
#include "gpu_fixture.h"
#include "indirect_test_scenes.h"
#include "scene/environment.h"

namespace hb {
namespace {

// The builds of each kind since the process started.
struct BuildCounts {
  uint64_t accel = AccelerationStructures::buildCount();
  uint64_t bvh = traceBvhBuildCount();
  uint64_t ldm = ldmSetBuildCount();
};

// The closed diffuse box with a block (indirect_test_scenes.h), an ambient term (ambient occlusion)
// and a uniform environment (the environment light): every effect acts on it.
Scene everyEffectBox() {
  Scene s = indirect_testing::diffuseBox("every-effect-box", true);
  s.ambient = Ambient{{1, 1, 1}, 1.0f};
  nlohmann::ordered_json uniform = {{"color", {0.5, 1.0, 2.0}}, {"intensity", 0.7}};
  s.environment = readEnvironment(uniform, json_reader::Where{"test", "environment"}, {});
  return s;
}

// LDM settings every LDM effect accepts; directions 16 unless given.
nlohmann::json ldmSettings(uint32_t directions = 16) {
  return {{"method", "ldm"},
          {"directions", directions},
          {"ldm_resolution", 64},
          {"ldm_build", "hardware"},
          {"ldm_list", "max64"}};
}

nlohmann::json indirectLdm(uint32_t directions = 16) {
  nlohmann::json v = ldmSettings(directions);
  v["photons"] = 4;
  return v;
}

RenderSettings frameOf(const nlohmann::json& effects, const char* backend = "auto") {
  RenderSettings rs = testing::settingsWithEffects(48, 32, effects);
  rs.backend = testing::backendNamed(backend);
  return rs;
}

// Shadows with the three LDM effects: ambient occlusion and the environment light with the same
// LDM settings, indirect light with `indirect`'s.
RenderSettings withLdmEffects(const nlohmann::json& indirect) {
  return frameOf({{"shadows", true},
                  {"ambient_occlusion", ldmSettings()},
                  {"environment_light", ldmSettings()},
                  {"indirect", indirect}});
}

bool skipped(const Renderer& r, const std::string& pass) {
  for (const auto& [p, why] : r.passesSkipped())
    if (p == pass) return true;
  return false;
}

std::string skipReason(const Renderer& r, const std::string& pass) {
  for (const auto& [p, why] : r.passesSkipped())
    if (p == pass) return why;
  return "";
}

bool ran(const Renderer& r, const std::string& pass) {
  return std::find(r.passesRun().begin(), r.passesRun().end(), pass) != r.passesRun().end();
}

bool usedBy(const nlohmann::json& resources, const std::string& resource, const std::string& user) {
  if (!resources.contains(resource) || !resources[resource].contains("users")) return false;
  const nlohmann::json& users = resources[resource]["users"];
  return std::find(users.begin(), users.end(), user) != users.end();
}

class FrameResourcesGpuTest : public testing::GpuTest {};

// Shadows, ambient occlusion and the environment light traced by ray, and indirect light's
// photons, through our BVH (backend=compute): one BVH and one set of acceleration structures for
// the four, which frame_resources lists with their key, build time and every pass that reads them.
TEST_F(FrameResourcesGpuTest, EveryTracingPassSharesOneBvhAndOneAccelerationStructure) {
  const Scene scene = everyEffectBox();
  const nlohmann::json raytraced = {{"method", "raytraced"}, {"directions", 8}};
  const BuildCounts before;
  Renderer r(*ctx, scene,
             frameOf({{"shadows", true},
                      {"ambient_occlusion", raytraced},
                      {"environment_light", raytraced},
                      {"indirect", {{"method", "raytraced"}, {"directions", 8}, {"photons", 4}}}},
                     "compute"));
  r.renderFrame(true);
  const BuildCounts after;
  EXPECT_EQ(after.accel - before.accel, 1u);
  EXPECT_EQ(after.bvh - before.bvh, 1u);
  EXPECT_EQ(after.ldm - before.ldm, 0u);

  const nlohmann::json res = r.resources().toJson();
  ASSERT_TRUE(res.contains("trace_bvh")) << res.dump(1);
  EXPECT_EQ(res["trace_bvh"]["key"], traceBvhKey(r.settings().bvhWidth));
  EXPECT_EQ(res["trace_bvh"]["built_bytes"], r.traceBvh()->bytes);
  EXPECT_GE(res["trace_bvh"]["build_ms"].get<double>(), 0.0);
  EXPECT_EQ(res["trace_bvh"]["build_clock"], "cpu");
  for (const char* pass : {"shadows", "ambient_occlusion", "environment_light", "photon_trace"})
    EXPECT_TRUE(usedBy(res, "trace_bvh", pass)) << pass << ": " << res["trace_bvh"].dump();
  EXPECT_EQ(res["tlas"]["key"], accelerationStructuresKey());
  EXPECT_EQ(res["tlas"]["bytes"], r.accel()->bytes());

  // raybench through compute takes the frame's BVH: no build.
  ShadowsPart* shadows = shadowsOf(r);
  ASSERT_NE(shadows, nullptr);
  shadows->rayBench(r.timer(), 1, RtBackend::Compute);
  EXPECT_EQ(traceBvhBuildCount() - before.bvh, 1u);
  EXPECT_TRUE(usedBy(r.resources().toJson(), "trace_bvh", "raybench"));
}

// A frame that traces with the driver's: raybench through compute builds our BVH once, keyed, and
// a second bench through it builds nothing more.
TEST_F(FrameResourcesGpuTest, RaybenchBuildsOurBvhOnceWhereTheFrameTracesWithTheDrivers) {
  const Scene scene = everyEffectBox();
  Renderer r(*ctx, scene, frameOf({{"shadows", true}}));
  ASSERT_NE(r.settings().backend, RtBackend::Compute);
  EXPECT_EQ(r.traceBvh(), nullptr);
  r.renderFrame(true);
  ShadowsPart* shadows = shadowsOf(r);
  ASSERT_NE(shadows, nullptr);
  const uint64_t before = traceBvhBuildCount();
  shadows->rayBench(r.timer(), 1);
  EXPECT_FALSE(r.resources().toJson().contains("trace_bvh"));
  shadows->rayBench(r.timer(), 1, RtBackend::Compute);
  shadows->rayBench(r.timer(), 1, RtBackend::Compute);
  EXPECT_EQ(traceBvhBuildCount() - before, 1u);
  const nlohmann::json res = r.resources().toJson();
  ASSERT_TRUE(res.contains("trace_bvh")) << res.dump(1);
  EXPECT_EQ(res["trace_bvh"]["built_by"], "raybench");
  EXPECT_EQ(res["trace_bvh"]["users"], nlohmann::json::array({"raybench"}));
}

// Shadows, ambient occlusion, the environment light and indirect light, the three LDM effects with
// the same directions, resolution, build and list: one LDM set, drawn by the first effect's build
// pass; the others' build passes are skipped naming it, their passes read its lists, and each
// effect's output is bit for bit the one it computes in a frame of its own (its own set).
TEST_F(FrameResourcesGpuTest, EffectsWithTheSameLdmKeyShareOneSetAndComputeWhatTheyComputeAlone) {
  const Scene scene = everyEffectBox();
  const BuildCounts before;
  Renderer r(*ctx, scene, withLdmEffects(indirectLdm()));
  EXPECT_EQ(ldmSetBuildCount() - before.ldm, 1u);
  EXPECT_EQ(AccelerationStructures::buildCount() - before.accel, 1u);
  r.renderFrame(true);
  EXPECT_TRUE(ran(r, "ldm_build"));
  for (const char* pass : {"environment_ldm_build", "indirect_ldm_build"}) {
    EXPECT_FALSE(ran(r, pass)) << pass;
    ASSERT_TRUE(skipped(r, pass)) << pass;
    EXPECT_NE(skipReason(r, pass).find("ldm_build builds its LDM set (ambient_occlusion.ldm"), std::string::npos)
        << skipReason(r, pass);
  }
  for (const char* pass : {"ambient_occlusion", "environment_light", "photon_trace", "photon_splat"})
    EXPECT_TRUE(ran(r, pass)) << pass;
  const AoPass* ao = aoPassOf(r);
  const AoPass* env = environmentPassOf(r);
  const IndirectPass* indirect = indirectPassOf(r);
  ASSERT_TRUE(ao && env && indirect);
  ASSERT_NE(ao->ldm(), nullptr);
  EXPECT_EQ(env->ldm(), ao->ldm());
  EXPECT_EQ(indirect->ldm(), ao->ldm());
  const nlohmann::json res = r.resources().toJson();
  ASSERT_TRUE(res.contains("ambient_occlusion.ldm")) << res.dump(1);
  EXPECT_FALSE(res.contains("environment_light.ldm"));
  EXPECT_FALSE(res.contains("indirect.ldm"));
  const nlohmann::json& set = res["ambient_occlusion.ldm"];
  EXPECT_EQ(set["built_by"], "ldm_build");
  EXPECT_EQ(set["built_bytes"], ao->ldm()->memoryBytes());
  EXPECT_NE(set["key"].get<std::string>().find("ldmDirections(16), 64 x 64"), std::string::npos) << set["key"];
  for (const char* pass : {"ambient_occlusion", "environment_light", "photon_trace"})
    EXPECT_TRUE(usedBy(res, "ambient_occlusion.ldm", pass)) << pass << ": " << set.dump();

  // Each effect alone: its own set, and the same output.
  auto alone = [&](const char* effect, const nlohmann::json& value) {
    nlohmann::json effects = {
        {"shadows", true}, {"ambient_occlusion", false}, {"environment_light", false}, {"indirect", false}};
    effects[effect] = value;
    const uint64_t ldmBefore = ldmSetBuildCount();
    auto own = std::make_unique<Renderer>(*ctx, scene, frameOf(effects));
    EXPECT_EQ(ldmSetBuildCount() - ldmBefore, 1u) << effect;
    own->renderFrame(true);
    return own;
  };
  EXPECT_EQ(aoPassOf(*alone("ambient_occlusion", ldmSettings()))->readAo(), ao->readAo());
  EXPECT_EQ(environmentPassOf(*alone("environment_light", ldmSettings()))->readAo(), env->readAo());
  EXPECT_EQ(indirectPassOf(*alone("indirect", indirectLdm()))->readIrradiance(), indirect->readIrradiance());
}

// A key that differs in one thing (indirect's directions) is its own set, built and drawn by its own
// pass; the two that agree still share.
TEST_F(FrameResourcesGpuTest, ASetWhoseKeyDiffersIsBuiltByItsOwnPass) {
  const Scene scene = everyEffectBox();
  const BuildCounts before;
  Renderer r(*ctx, scene, withLdmEffects(indirectLdm(8)));
  EXPECT_EQ(ldmSetBuildCount() - before.ldm, 2u);
  r.renderFrame(true);
  EXPECT_TRUE(ran(r, "ldm_build"));
  EXPECT_TRUE(ran(r, "indirect_ldm_build"));
  EXPECT_TRUE(skipped(r, "environment_ldm_build"));
  EXPECT_NE(indirectPassOf(r)->ldm(), aoPassOf(r)->ldm());
  const nlohmann::json res = r.resources().toJson();
  EXPECT_TRUE(usedBy(res, "indirect.ldm", "photon_trace")) << res.dump(1);
  EXPECT_FALSE(usedBy(res, "ambient_occlusion.ldm", "photon_trace"));
}

}  // namespace
}  // namespace hb

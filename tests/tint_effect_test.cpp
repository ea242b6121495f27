// A test-only effect, defined entirely in this file and its shader (tests/shaders/tint.comp.glsl):
// "tint" adds light to shading — red in proportion to each pixel's tile light-list length. It runs
// before shading, writes its per-pixel term and declares it (FrameResources::addShadingTerm), and
// shading adds it: shading names no effect (docs/frame.md "Shading terms"). Registered from the
// test (registerEffect, registerSpirv), it runs in the frame of the real `render`, `sweep` and
// `tables` commands and appears under its own key in render.json and results.json and as its own
// table — with no edit to any file under src/ (docs/contributing.md "Adding an effect or a pass").
// That is the proof that an effect that adds light needs one folder, not thirty files.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "analysis/effect_report.h"
#include "app/commands.h"
#include "app/sweep.h"
#include "frame/frame_builder.h"
#include "frame/renderer.h"
#include "gpu/descriptor_binder.h"
#include "gpu/vk_pipeline.h"
#include "gpu_fixture.h"
#include "plan/effects.h"
#include "report/results_json.h"
#include "scene/atrium.h"
#include "tint_comp.h"  // generated from tests/shaders/tint.comp.glsl (CMakeLists.txt)

namespace hb {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr const char* kTintPass = "tint";
constexpr const char* kTintTerm = "tint.term";
// Red added per light of the pixel's list: small enough that the atrium's ten lights keep the
// image in range, large enough that one light is many RGBA16F steps above 1 (step 2^-10 there).
constexpr float kRedPerLight = 0.0625f;

struct TintPush {
  uint32_t width, height, tileSize, tilesX;
};

// The effect's GPU state and its one pass: each pixel's list length into its term, declared to
// shading as red per light, added as is.
class TintPart : public FramePart {
 public:
  explicit TintPart(FrameBuilder& f)
      : grid_(f.resources.requireBuffer(res::kListGrid)),
        term_(f.ctx, VkDeviceSize(f.settings.width) * f.settings.height * sizeof(float),
              VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, MemClass::Other),
        pipeline_(f.ctx) {
    const uint32_t tileSize = f.settings.tileSize;
    push_ = {f.settings.width, f.settings.height, tileSize, (f.settings.width + tileSize - 1) / tileSize};
    DescriptorBinder binder(kTintPass);  // tint.comp's bindings, by name
    binder.provide("Term", term_);
    binder.provide("Grid", grid_);
    pipeline_.createCompute(binder, "tint.comp", sizeof(TintPush));
    binder.checkEveryNameRead();
    f.resources.publish(kTintTerm, term_, "f32 per pixel: the tile's list length",
                        std::to_string(f.settings.width) + " x " + std::to_string(f.settings.height));
    f.resources.addShadingTerm(
        {kTintTerm, ShadingTerm::Storage::FloatPerPixel, {kRedPerLight, 0.0f, 0.0f}, ShadingTerm::Weight::AsIs, 0.0f});

    FramePass pass;
    pass.name = kTintPass;
    pass.reads = {res::kListGrid};
    pass.writes = {kTintTerm};  // the frame makes it visible to shading, which reads it (a declared term)
    pass.record = [this](VkCommandBuffer cmd, const PassFrame&) {
      VkDescriptorSet set = pipeline_.set();
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.handle());
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.layout(), 0, 1, &set, 0, nullptr);
      vkCmdPushConstants(cmd, pipeline_.layout(), VK_SHADER_STAGE_ALL, 0, sizeof push_, &push_);
      vkCmdDispatch(cmd, (push_.width + 7) / 8, (push_.height + 7) / 8, 1);
    };
    passes_.push_back(std::move(pass));
  }

 private:
  const Buffer& grid_;
  Buffer term_;
  Pipeline pipeline_;
  TintPush push_{};
};

// render.json / results.json "tint": the red per light, the longest list and the pixels tinted.
void reportTint(EffectReport& r) {
  const CullingReadback& c = r.culling;
  const RenderSettings& s = r.renderer.settings();
  uint64_t tinted = 0;
  uint32_t longest = 0;
  for (uint32_t y = 0; y < s.height && !c.count.empty(); ++y)
    for (uint32_t x = 0; x < s.width; ++x) {
      const uint32_t n = c.count[(y / s.tileSize) * c.tilesX + x / s.tileSize];
      tinted += n > 0;
      longest = std::max(longest, n);
    }
  r.run[kTintPass] = {{"red_per_light", kRedPerLight}, {"longest_list", longest}, {"pixels_tinted", tinted}};
  r.summary.push_back("tint: " + std::to_string(tinted) + " pixels tinted, longest list " + std::to_string(longest));
}

std::string tintTable(const json& results) {
  std::string rows;
  for (const json& run : results["runs"])
    if (run.contains(kTintPass))
      rows += "| " + run.value("name", std::string("?")) + " | " + run[kTintPass]["longest_list"].dump() + " | " +
              run[kTintPass]["pixels_tinted"].dump() + " |\n";
  if (rows.empty()) return "";
  return "## Tint (a test-only effect)\n\n| Run | Longest list | Pixels tinted |\n|---|---:|---:|\n" + rows;
}

const EffectDef& tintEffect() {
  static const EffectDef def{
      .name = kTintPass,
      .summary = "test only: red added to shading in proportion to each pixel's light-list length",
      .defaultValue = false,
      .validate = [](const nlohmann::ordered_json& value,
                     const json_reader::Where& where) { json_reader::readBool(value, where); },
      .needs = {FrameResource::Depth, FrameResource::LightLists},
      .passes = {kTintPass},
      .cannotAct = [](const Scene& scene, const json&) -> std::string {
        return scene.lights.empty() ? "the scene has no lights" : "";
      },
      .phase = FramePhase::BeforeShading,
      .build = [](FrameBuilder& f) -> std::unique_ptr<FramePart> { return std::make_unique<TintPart>(f); },
      .report = reportTint,
      .table = tintTable,
  };
  return def;
}

class TintEffectTest : public testing::GpuTest {
 protected:
  void SetUp() override {
    testing::GpuTest::SetUp();
    static const bool spirv = (registerSpirv("tint.comp", kSpirv_tint_comp, sizeof kSpirv_tint_comp), true);
    (void)spirv;
    registerEffect(tintEffect());
    dir = fs::temp_directory_path() / ("hb-tint-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  void TearDown() override {
    unregisterEffect(tintEffect());
    fs::remove_all(dir);
    testing::GpuTest::TearDown();
  }
  fs::path dir;
};

TEST_F(TintEffectTest, RunsBeforeShadingWhichAddsItsTermExactly) {
  const Scene scene = makeAtrium({});
  RenderSettings rs = testing::settingsWithEffects(96, 54, {{"shadows", false}, {"tint", true}});
  rs.tileSize = 8;
  RenderSettings plain = testing::settingsWithEffects(96, 54, {{"shadows", false}});  // without the effect
  plain.tileSize = 8;
  for (bool visbuffer : {false, true}) {
    if (visbuffer) {  // the other shading pass, in compute
      rs.primary = plain.primary = testing::primaryNamed("3dr");
      rs.shading = plain.shading = ShadingMethod::Visbuffer;
    }
    Renderer r(*ctx, scene, rs);
    ASSERT_EQ(r.passesRun().size(), 0u);
    r.renderFrame(true);
    const std::vector<std::string>& run = r.passesRun();
    const auto at = [&](const char* pass) { return std::find(run.begin(), run.end(), pass) - run.begin(); };
    ASSERT_LT(at(kTintPass), at(kShadingPass)) << "a term is written before shading adds it";
    ASSERT_NE(r.part<TintPart>(kTintPass), nullptr);
    Renderer without(*ctx, scene, plain);
    without.renderFrame(true);
    ASSERT_EQ(std::find(without.passesRun().begin(), without.passesRun().end(), kTintPass), without.passesRun().end());

    const std::vector<float> shaded = without.readColor();
    const std::vector<float> tinted = r.readColor();
    const CullingReadback lists = r.readCulling();
    const std::vector<float> normals = r.readRefNormals();  // w = 1 where a surface was shaded
    ASSERT_EQ(shaded.size(), tinted.size());
    ASSERT_EQ(normals.size(), tinted.size());
    uint64_t checked = 0, reddened = 0;
    for (uint32_t y = 0; y < rs.height; ++y)
      for (uint32_t x = 0; x < rs.width; ++x) {
        const size_t i = size_t(y) * rs.width + x;
        // Shading adds its terms to the surfaces it shades; the sky stays as it was cleared.
        const uint32_t n =
            normals[4 * i + 3] == 1.0f ? lists.count[(y / rs.tileSize) * lists.tilesX + x / rs.tileSize] : 0u;
        // Shading adds scale · value = (kRedPerLight·n, 0, 0) to the same fp32 colour c (the term is
        // exact: a power of two times a small integer), and each frame stores its colour RGBA16F,
        // rounded to nearest or towards zero (Vulkan allows either on a float-to-half store): within
        // one half-float step of c and of c + term. For a value in [2^e, 2^(e+1)) that step is
        // 2^(e−10) (10 mantissa bits), below 2^-14 it is 2^-24: the two images differ in red by the
        // term to within the step at the larger of the two values plus the step at the smaller.
        const float expected = shaded[4 * i] + kRedPerLight * float(n);
        const auto step = [](float v) {
          return std::ldexp(1.0f, std::ilogb(std::max(std::abs(v), std::ldexp(1.0f, -14))) - 10);
        };
        EXPECT_NEAR(tinted[4 * i], expected, step(expected) + step(shaded[4 * i]))
            << "pixel " << x << "," << y << " list " << n << (visbuffer ? " (visbuffer)" : "");
        // Green and blue get 0·n: c + 0 = c, bit for bit.
        for (int c = 1; c < 4; ++c) EXPECT_EQ(tinted[4 * i + c], shaded[4 * i + c]) << "only red changes";
        reddened += n > 0;
        ++checked;
      }
    EXPECT_GT(reddened, checked / 2) << "most of the atrium's shaded pixels lie in a tile with a light";
  }
}

TEST_F(TintEffectTest, RenderSweepAndTablesCarryItWithNoEditToTheTool) {
  // render: the effect by --set, its key in render.json, its pass run.
  RenderOptions ro;
  ro.size = "96x54";
  ro.sets = {"tint=true", "shadows=false", "tile_size=8"};
  ro.out = (dir / "render").string();
  ASSERT_EQ(cmdRender(ro), 0);
  std::ifstream rf(dir / "render" / "render.json");
  const json render = json::parse(rf);
  ASSERT_TRUE(render.contains("tint")) << render.dump(1).substr(0, 2000);
  EXPECT_GT(render["tint"]["pixels_tinted"].get<uint64_t>(), 0u);
  const auto passesRun = render["passes_run"].get<std::vector<std::string>>();
  EXPECT_LT(std::find(passesRun.begin(), passesRun.end(), kTintPass) - passesRun.begin(),
            std::find(passesRun.begin(), passesRun.end(), kShadingPass) - passesRun.begin());
  EXPECT_TRUE(render["effects"]["tint"]["runs"].get<bool>());

  // sweep: the config calls for it; each run carries its key and its pass time.
  const fs::path config = dir / "tint.json";
  std::ofstream(config) << json{{"name", "tint"},
                                {"scene", "atrium"},
                                {"resolution", {96, 54}},
                                {"effects", {{"shadows", false}, {"tint", true}}},
                                {"frames", {{"warmup", 1}, {"measured", 2}}},
                                {"variants", {{{"name", "tinted"}, {"params", {{"tile_size", 8}}}}}}}
                               .dump();
  SweepOptions so;
  so.config = config.string();
  so.out = (dir / "sweep").string();
  so.images = false;
  ASSERT_EQ(cmdSweep(so), 0);
  std::ifstream sf(dir / "sweep" / "results.json");
  const json results = json::parse(sf);
  ASSERT_EQ(results["runs"].size(), 1u);
  EXPECT_TRUE(results["runs"][0].contains("tint"));
  EXPECT_TRUE(results["runs"][0]["passes"].contains(kTintPass));

  // tables: its table hook prints.
  ::testing::internal::CaptureStdout();
  const int rc = cmdTables({(dir / "sweep" / "results.json").string()}, "md");
  const std::string out = ::testing::internal::GetCapturedStdout();
  EXPECT_EQ(rc, 0);
  EXPECT_NE(out.find("## Tint (a test-only effect)"), std::string::npos) << out.substr(0, 3000);
  EXPECT_NE(out.find("| tinted | "), std::string::npos);
}

}  // namespace
}  // namespace hb

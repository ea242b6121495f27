// The frame's own rays as ray files (analysis/frame_rays.h, `render --rays-out`): the shadow rays
// of a frame after culling and the rays of its ray-traced AO, rebuilt from the analysis frame, are
// the rays the frame traced: traced again by every backend (gpu/peaks.h traceRayFile) they give the
// frame's own visibility bits and AO values, ray for ray.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>

#include "analysis/frame_rays.h"
#include "analysis/ray_accounting.h"
#include "effects/ambient_occlusion/ao_part.h"
#include "effects/ambient_occlusion/ao_pass.h"
#include "effects/shadows/shadows_part.h"
#include "gltf/gltf_io.h"
#include "gpu/gpu_lights.h"
#include "gpu/peaks.h"
#include "gpu_fixture.h"
#include "reference/eq_partition.h"
#include "scene/atrium.h"
#include "tool_process.h"

namespace hb {
namespace {

class FrameRaysGpuTest : public hb::testing::GpuTest {};

constexpr uint32_t kDirections = 16;

RayFile anyHitFile(const Scene& scene, const std::string& kind, std::vector<RayRecord> rays) {
  RayFile f;
  f.info.count = rays.size();
  f.info.kind = kind;
  f.info.query = "any";
  f.info.sceneName = scene.name;
  f.info.sceneSha256 = sceneSha256(scene);
  f.info.grid = {64, uint32_t((rays.size() + 63) / 64)};
  f.rays = std::move(rays);
  return f;
}

TEST_F(FrameRaysGpuTest, TheFramesShadowAndAoRaysTracedAgainGiveTheFramesOwnAnswers) {
  AtriumParams ap;
  ap.lightCount = 24;
  const Scene scene = makeAtrium(ap);
  RenderSettings rs = testing::settingsWithEffects(
      96, 54, {{"shadows", true}, {"ambient_occlusion", {{"method", "raytraced"}, {"directions", kDirections}}}});
  rs.backend = RtBackend::Compute;
  rs.tileSize = 16;
  rs.rangeTest = true;
  Renderer r(*ctx, scene, rs);
  r.renderFrame(true);
  const ShadowsPart* shadows = shadowsOf(r);
  AoPass* ao = aoPassOf(r);
  ASSERT_TRUE(shadows && ao);
  const ShadowReadback sh = shadows->readShadows();
  const CullingReadback culling = r.readCulling();
  const glm::vec4 cameraPos = r.frameConstants().cameraPos;
  const size_t pixels = size_t(rs.width) * rs.height;

  // Shadow rays: as many as the pass counted, and each pixel's traced again finds visible exactly
  // the lights the pass found visible among those it traced. Both are the same float rays through
  // watertight tests (ours, the driver's), so no tie is allowed.
  const FrameRays shadowRays =
      frameShadowRays(sh, culling, packLights(scene.lights), cameraPos, rs.width, rs.height, rs.tileSize);
  uint64_t counted = 0;
  for (size_t i = 0; i < pixels; ++i) counted += unpackAccount(&sh.accounting[4 * i]).traced;
  ASSERT_GT(counted, 0u);
  EXPECT_EQ(shadowRays.rays.size(), counted);
  std::vector<uint32_t> frameVisible(pixels, 0);
  uint64_t visibleRays = 0;
  for (size_t i = 0; i < pixels; ++i)
    for (uint32_t j = 0; j < sh.words; ++j) {
      const uint32_t k = unpackAccount(&sh.accounting[4 * i]).listed;
      if (j > 0 && 32 * j >= k) break;  // words past the walk's last hold nothing of this frame
      frameVisible[i] += std::popcount(sh.visibility[j * pixels + i] & sh.traced[j * pixels + i]);
    }
  for (uint32_t v : frameVisible) visibleRays += v;
  // Not vacuous: some rays are blocked, some are not.
  EXPECT_GT(visibleRays, 0u);
  EXPECT_LT(visibleRays, counted);
  const RayFileTrace shadowTrace = traceRayFile(*ctx, scene, anyHitFile(scene, "frame-shadow", shadowRays.rays));
  ASSERT_FALSE(shadowTrace.figures.empty());
  for (const Peak& p : shadowTrace.figures) {
    SCOPED_TRACE(p.backend);
    const RayFileHits& h = shadowTrace.hits.at(p.backend);
    std::vector<uint32_t> again(pixels, 0);
    for (size_t k = 0; k < shadowRays.rays.size(); ++k) again[shadowRays.pixel[k]] += h.missed[k];
    size_t unlike = 0;
    for (size_t i = 0; i < pixels; ++i) unlike += again[i] != frameVisible[i];
    EXPECT_EQ(unlike, 0u);
  }

  // AO rays: per pixel with a value, every direction with n·v != 0, and the value from the rays
  // traced again is the pass's: AO = (2/N) Σ |n·v_i| V_i. The visibilities are the same (as above),
  // so the two differ only by float rounding of the sum: N terms of at most 1, each addition off by
  // at most u = 2^-24 of a partial sum <= N, so |Δ| <= (2/N)·N·N·u = 2·N·u.
  std::vector<glm::vec3> dirs;
  for (const glm::dvec3& d : ldmDirections(kDirections)) dirs.emplace_back(d);
  const float dMax = ao->settings().ao.dMax ? float(*ao->settings().ao.dMax) : 0.0f;
  const FrameRays aoRays = frameAoRays(sh, dirs, cameraPos, dMax, rs.width, rs.height);
  const std::vector<float> frameAo = ao->readAo();
  ASSERT_EQ(frameAo.size(), pixels);
  std::vector<uint32_t> perPixel(pixels, 0);
  for (uint32_t p : aoRays.pixel) perPixel[p]++;
  size_t withValue = 0, withRays = 0;
  for (size_t i = 0; i < pixels; ++i) {
    withValue += frameAo[i] >= 0.0f;
    withRays += perPixel[i] > 0;
    EXPECT_LE(perPixel[i], kDirections);
  }
  ASSERT_GT(withValue, 0u);
  EXPECT_EQ(withRays, withValue);
  const RayFileTrace aoTrace = traceRayFile(*ctx, scene, anyHitFile(scene, "frame-ao", aoRays.rays));
  const double bound = 2.0 * kDirections * std::ldexp(1.0, -24);
  for (const Peak& p : aoTrace.figures) {
    SCOPED_TRACE(p.backend);
    const RayFileHits& h = aoTrace.hits.at(p.backend);
    std::vector<float> sum(pixels, 0.0f);
    for (size_t k = 0; k < aoRays.rays.size(); ++k)
      if (h.missed[k]) sum[aoRays.pixel[k]] += aoRays.weight[k];
    double worst = 0;
    size_t occludedSome = 0;
    for (size_t i = 0; i < pixels; ++i) {
      if (!(frameAo[i] >= 0.0f)) continue;
      const float again = 2.0f * sum[i] / float(kDirections);
      worst = std::max(worst, double(std::abs(again - frameAo[i])));
      occludedSome += frameAo[i] < 0.99f;
    }
    EXPECT_LE(worst, bound);
    EXPECT_GT(occludedSome, 0u);  // not vacuous: the atrium occludes
  }
}

class FrameRaysCli : public hb::testing::ToolTest {};

TEST_F(FrameRaysCli, RenderWritesTheFramesRaysAndRaybenchTracesThemOnTheSameGeometry) {
  using namespace hb::testing;
  // 8 lights: a scene whose sha256 is not the built-in atrium's, whose geometry is.
  const RunResult render = run({"render", "--size", "64x36", "--set", "light_count=8", "--set",
                                R"(ambient_occlusion={"method": "raytraced", "directions": 8})", "--out",
                                (dir / "frame").string(), "--rays-out", (dir / "rays").string()});
  ASSERT_EQ(render.exitCode, 0) << render.err;
  for (const char* kind : {"frame-shadow", "frame-ao"}) {
    SCOPED_TRACE(kind);
    const json info = readJson(dir / "rays" / (std::string(kind) + ".json"));
    EXPECT_EQ(info["query"], "any");
    EXPECT_EQ(info["kind"], kind);
    EXPECT_GT(info["count"].get<uint64_t>(), 0u);
    const RunResult bench = run({"raybench", (dir / "rays" / (std::string(kind) + ".bin")).string(), "--json",
                                 (dir / (std::string(kind) + ".bench.json")).string()});
    ASSERT_EQ(bench.exitCode, 0) << bench.err;
    for (const json& b : readJson(dir / (std::string(kind) + ".bench.json"))["backends"])
      EXPECT_EQ(b["unlike_cpu"], 0) << b["backend"];
  }
  // The shadow file holds the rays the frame's accounting counted.
  EXPECT_EQ(readJson(dir / "rays" / "frame-shadow.json")["count"],
            readJson(dir / "frame" / "render.json")["rays"]["traced"]);
  // A frame without shadows has no rays to give: one line, exit 2, nothing written.
  const RunResult none = run({"render", "--size", "64x36", "--set", "shadows=false", "--out", (dir / "none").string(),
                              "--rays-out", (dir / "none-rays").string()});
  EXPECT_EQ(none.exitCode, 2);
  EXPECT_NE(none.err.find("--rays-out"), std::string::npos) << none.err;
  EXPECT_EQ(std::count(none.err.begin(), none.err.end(), '\n'), 1) << none.err;
  EXPECT_FALSE(fs::exists(dir / "none-rays"));
}

}  // namespace
}  // namespace hb

// The shadow pass on the real device, shared by the shadow tests (shadows_gpu_test.cpp: the
// backends against each other and the CPU; shadow_reconstruction_gpu_test.cpp: normals and world
// positions; shadow_hard_cases_gpu_test.cpp): a frame rendered with one backend, read back, and
// checked against the CPU's double-precision shadow rays.
#pragma once
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "analysis/ray_analysis.h"
#include "base/numbers.h"
#include "effects/shadows/shadows_part.h"
#include "frame/renderer.h"
#include "gpu/gpu_lights.h"
#include "gpu/trace_bvh.h"
#include "gpu_fixture.h"
#include "scene/hard_cases.h"
#include "shadow_frame.h"
#include "shared/gpu_types.h"

namespace hb::shadowtest {

constexpr uint32_t kWidth = 320, kHeight = 180;
constexpr NormalCulling kNormalModes[] = {NormalCulling::Off, NormalCulling::Naive, NormalCulling::Improved};

struct ShadowFrame : hb::testing::ShadowedFrame {
  ReconstructionCamera<double> cam;
  size_t pixels() const { return depth.size(); }
};

inline ShadowFrame render(const VulkanContext& ctx, const Scene& scene, NormalCulling normals,
                          const std::string& backend, uint32_t tileSize = 16, bool scaledTMin = false,
                          uint32_t bvhWidth = 2) {
  RenderSettings s{.width = kWidth,
                   .height = kHeight,
                   .tileSize = tileSize,
                   .backend = hb::testing::backendNamed(backend),
                   .bvhWidth = bvhWidth,
                   .normals = normals};
  s.tMin = scaledTMin ? ShadowTMin::Scaled : ShadowTMin::Constant;
  Renderer r(ctx, scene, s);
  EXPECT_EQ(toString(shadowsOf(r)->shadowPass().settings().backend), backend);
  r.renderFrame(true);
  ShadowFrame f{{s, r.readDepth(), r.readCulling(), shadowsOf(r)->readShadows(), r.view(), r.proj()}, {}};
  f.cam = reconstructionCamera<double>(glm::dmat4(f.view), glm::dmat4(f.proj), s.width, s.height);
  return f;
}

inline const Scene& sceneNamed(const std::string& name) {
  static std::map<std::string, Scene> cache;
  auto it = cache.find(name);
  if (it == cache.end()) it = cache.emplace(name, makeBuiltinScene(name)).first;
  return it->second;
}

inline RayAccounting account(const ShadowFrame& f, const Scene& scene) {
  return accountRays(f.shadows, f.culling, f.depth, f.settings.width, f.settings.height, f.settings.tileSize,
                     uint32_t(scene.lights.size()));
}

inline ShadowComparison compare(const ShadowFrame& f, const Scene& scene, const Bvh& bvh) {
  // The camera position and t_min scale exactly as the renderer uploads them.
  const glm::vec4 cameraPos =
      makeFrameConstants(f.view, f.proj, f.settings.width, f.settings.height, f.settings.tileSize, 0,
                         f.settings.tMin == ShadowTMin::Scaled ? gpu::kShadowTMinPerMetre : 0.0f)
          .cameraPos;
  return compareShadows(scene, bvh, f.shadows, f.culling, f.settings.width, f.settings.height, f.settings.tileSize,
                        f.settings.rangeTest, cameraPos);
}

// Sky pixels carry nothing; everything else is finite and has w = 1.
inline void expectCleanImages(const ShadowFrame& f, const std::string& what) {
  size_t bad = 0;
  for (size_t i = 0; i < f.pixels(); ++i) {
    const float* n = &f.shadows.normals[4 * i];
    const float* p = &f.shadows.positions[4 * i];
    bool ok = true;
    for (int k = 0; k < 4; ++k) ok = ok && std::isfinite(n[k]) && std::isfinite(p[k]);
    if (!(f.depth[i] > 0.0f))
      ok = ok && f.shadows.visibility[i] == 0u && f.shadows.accounting[4 * i] == 0u &&
           f.shadows.accounting[4 * i + 1] == 0u && f.shadows.accounting[4 * i + 2] == 0u && p[3] == 0.0f &&
           n[0] == 0.0f && n[1] == 0.0f && n[2] == 0.0f;
    else
      ok = ok && p[3] == 1.0f;
    bad += !ok;
  }
  EXPECT_EQ(bad, 0u) << what << ": pixels with NaN/Inf, a sky pixel with a mask/normal/position, or w != 1";
}

}  // namespace hb::shadowtest

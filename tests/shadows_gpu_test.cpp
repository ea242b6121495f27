// Exploratory: measure numbers.
#include <cmath>
#include <cstdio>
#include <map>

#include <gtest/gtest.h>

#include "atrium.h"
#include "gpu_fixture.h"
#include "hard_cases.h"
#include "ray_analysis.h"
#include "renderer.h"
#include "shared/gpu_types.h"

namespace hb {
namespace {

struct Frame {
  std::vector<float> depth;
  CullingReadback culling;
  ShadowReadback shadows;
  ReconstructionCamera<double> cam;
};

Frame render(const VulkanContext& ctx, const Scene& scene, const RenderSettings& s) {
  Renderer r(ctx, scene, s);
  r.renderFrame(true);
  Frame f{r.readDepth(), r.readCulling(), r.readShadows(), {}};
  f.cam = reconstructionCamera<double>(glm::dmat4(r.view()), glm::dmat4(r.proj()), s.width, s.height);
  return f;
}

const Scene& sceneNamed(const std::string& name) {
  static std::map<std::string, Scene> cache;
  auto it = cache.find(name);
  if (it == cache.end()) it = cache.emplace(name, makeBuiltinScene(name)).first;
  return it->second;
}

class ShadowExplore : public testing::GpuTest {};

TEST_F(ShadowExplore, Numbers) {
  for (const std::string& name : builtinSceneNames()) {
    const Scene& scene = sceneNamed(name);
    Bvh bvh = buildBvh(scene);
    TriangleBvh tbvh = buildTriangleBvh(scene);
    for (uint32_t normals : {gpu::kNormalsOff, gpu::kNormalsNaive, gpu::kNormalsImproved}) {
      RenderSettings s;
      s.width = 320;
      s.height = 180;
      s.tileSize = 16;
      s.normals = normals;
      s.backend = "rayquery";
      Frame a = render(*ctx, scene, s);
      s.backend = "pipeline";
      Frame b = render(*ctx, scene, s);
      size_t visDiff = 0, accDiff = 0, nDiff = 0, pDiff = 0;
      for (size_t i = 0; i < a.depth.size(); ++i) {
        visDiff += a.shadows.visibility[i] != b.shadows.visibility[i];
        accDiff += a.shadows.accounting[i] != b.shadows.accounting[i];
        for (int k = 0; k < 4; ++k) {
          nDiff += a.shadows.normals[4 * i + k] != b.shadows.normals[4 * i + k];
          pDiff += a.shadows.positions[4 * i + k] != b.shadows.positions[4 * i + k];
        }
      }
      RayAccounting acc = accountRays(a.shadows, a.culling, a.depth, s.width, s.height, s.tileSize,
                                      uint32_t(scene.lights.size()));
      ReferenceSurface ref = referenceSurface(tbvh, a.depth, a.cam);
      OracleRays o = oracleRays(scene, ref);
      NormalAccuracy na = normalAccuracy(a.shadows.normals, ref);
      PositionAccuracy pa = positionAccuracy(a.shadows.positions, a.depth, a.cam);
      ShadowComparison c = compareShadows(scene, bvh, a.shadows, a.culling, s.width, s.height, s.tileSize, false);
      glm::dvec3 eye(a.cam.viewInv[3]);
      std::printf(
          "%-14s n=%u diff vis %zu acc %zu nrm %zu pos %zu | rays cand %lu tile %lu ovf %lu nrm %lu traced %lu adds %d "
          "oracle %lu eff %.3f unmatched %lu | ang mean %.4f p95 %.4f max %.2f img %.5f noRec %lu | pos max %.3g "
          "(%.2f x 8eps) mean %.3g plain %.3g |eye| %.1f | cmp pairs %lu rays %lu mism %lu tie %lu end %lu graz %lu "
          "unexpl %lu\n",
          name.c_str(), normals, visDiff, accDiff, nDiff, pDiff, acc.candidates, acc.culledByTile, acc.droppedByOverflow,
          acc.culledByNormal, acc.traced, acc.addsUp(), o.total, rayEfficiency(o.total, acc.traced), ref.unmatched,
          na.meanAngleDeg, na.p95AngleDeg, na.maxAngleDeg, na.meanImageDifference, na.withoutReconstruction,
          pa.maxRelative, pa.maxRelative / (8.0 / 16777216.0), pa.meanRelative, pa.maxRelativePlain, glm::length(eye),
          c.pairs, c.rays, c.mismatches, c.nearTie, c.endpoint, c.grazing, c.unexplained());
    }
  }
}

}  // namespace
}  // namespace hb

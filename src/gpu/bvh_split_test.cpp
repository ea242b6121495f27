// Issue #51, tried and dropped: splitting the references of large triangles before the tracer's
// SAH build (gpu/bvh_split.h). Prints, for each priority and budget, the tree's SAH cost and depth
// and the 4-wide traversal's work a ray (trace_work.h, the CPU replay raybench prints) on the
// exported ray sets of the atrium. Runs where HB_SPLIT_RAYS names the folder of
// `hybridbench rays export --scene atrium --size 1920x1080`; skipped otherwise.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "gpu/bvh_reinsert.h"
#include "gpu/bvh_split.h"
#include "gpu/trace_bvh.h"
#include "gpu/trace_work.h"
#include "reference/ray_file.h"
#include "scene/atrium.h"

namespace hb {
namespace {

TEST(TraceBvhSplitStudy, TheWorkARayAtEachBudget) {
  const char* dir = std::getenv("HB_SPLIT_RAYS");
  if (!dir) GTEST_SKIP() << "HB_SPLIT_RAYS names no ray folder";
  const std::vector<glm::vec3> v = makeAtrium().worldTriangles();
  std::vector<RayFile> files;
  for (const char* k : {"camera", "ao", "shadow"}) files.push_back(readRayFile(std::string(dir) + "/" + k + ".bin"));
  std::printf(
      "| priority | budget | references | splits | SAH cost | depth | set | nodes | boxes | triangles | pushes | bytes "
      "|\n");
  std::printf("|---|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|\n");
  for (bool excess : {false, true}) {
    for (double b : {0.0, 0.002, 0.01, 0.03, 0.1, 0.3}) {
      if (excess && b == 0.0) continue;
      BvhBuildOptions o = kTraceBvhBuild;
      o.splitBudget = b;
      o.splitExcessOnly = excess;
      TriangleSplitStats st;
      (void)splitTriangleReferences(v, b, excess, &st);
      const PrimaryBvh t = buildPrimaryBvh(v, o);
      const TraceBvhLayout l = layoutTraceBvh(v, 4, o);
      for (const RayFile& f : files) {
        const TraceWork w = traceWork(l, f.rays, false);
        std::printf("| %s | %.3f | %zu | %llu | %.2f | %u | %s | %.2f | %.2f | %.2f | %.2f | %.0f |\n",
                    excess ? "area less the triangle's" : "box area", b, t.order.size(), (unsigned long long)st.splits,
                    bvhSahCost(t), t.depth, f.info.kind.c_str(), w.perRay(w.nodes), w.perRay(w.boxes),
                    w.perRay(w.triangles), w.perRay(w.pushes), w.perRay(w.bytes()));
      }
    }
  }
}

}  // namespace
}  // namespace hb

namespace hb {
namespace {

// The boxes of a triangle's references hold all of it: points on a 9 x 9 barycentric grid of
// every split triangle of the atrium (vertices and edges included), each inside one of its boxes.
TEST(TraceBvhSplit, ATrianglesReferencesHoldIt) {
  const std::vector<glm::vec3> v = makeAtrium().worldTriangles();
  TriangleSplitStats st;
  const std::vector<TriangleReference> refs = splitTriangleReferences(v, 0.1, false, &st);
  EXPECT_EQ(refs.size(), v.size() / 3 + st.splits);
  std::vector<std::vector<uint32_t>> of(v.size() / 3);
  for (uint32_t i = 0; i < refs.size(); ++i) of[refs[i].triangle].push_back(i);
  size_t split = 0;
  for (size_t t = 0; t < of.size(); ++t) {
    if (of[t].size() < 2) continue;
    ++split;
    for (int i = 0; i <= 8; ++i)
      for (int j = 0; i + j <= 8; ++j) {
        const double a = i / 8.0, b = j / 8.0;
        const glm::dvec3 p =
            (1.0 - a - b) * glm::dvec3(v[3 * t]) + a * glm::dvec3(v[3 * t + 1]) + b * glm::dvec3(v[3 * t + 2]);
        bool held = false;
        for (uint32_t r : of[t]) {
          const TriangleReference& x = refs[r];
          held = held ||
                 (p.x >= x.lo.x && p.y >= x.lo.y && p.z >= x.lo.z && p.x <= x.hi.x && p.y <= x.hi.y && p.z <= x.hi.z);
        }
        EXPECT_TRUE(held) << "triangle " << t << " point " << i << "," << j;
      }
  }
  EXPECT_GT(split, 0u);
}

}  // namespace
}  // namespace hb

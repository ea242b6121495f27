// Layered depth maps on the real device (frame/passes/ldm_build.h): the lists the hardware build
// writes hold every surface crossing of each pixel's line, sorted, against depths known exactly,
// for both builds (the raster hardware's and the compute rasterizer's) and the three list builders
// (max64's atomicMax insertion, the paper's compare-and-swap, sbuffer's count-scan-fill-sort).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "frame/passes/ldm_build.h"
#include "gpu_fixture.h"
#include "reference/eq_partition.h"
#include "scene/atrium.h"
#include "scene/mesh_builder.h"

namespace hb {
namespace {

gpu::LdmMap mapOf(glm::dvec3 dir, glm::dvec3 right, glm::dvec3 up, glm::dvec3 centre, double radius) {
  return {glm::vec4(glm::vec3(dir), 0.0f), glm::vec4(glm::vec3(right), 0.0f), glm::vec4(glm::vec3(up), 0.0f),
          glm::vec4(glm::vec3(centre), float(radius))};
}

Scene boxScene(glm::dvec3 lo, glm::dvec3 hi) {
  Scene s;
  s.name = "box";
  s.materials.push_back({});
  MeshBuilder mb("box");
  addBox(mb, 0, lo, hi);
  mb.appendTo(s);
  return s;
}

class LdmGpuTest : public testing::GpuTest {};

// "hardware, max64": a build method and list layout as a trace line names them.
std::string buildAndListName(LdmBuildMethod method, LdmList list) {
  return std::string(method == LdmBuildMethod::Hardware ? "hardware" : "3dr") + (list == LdmList::Max64 ? ", max64"
                                                                                 : list == LdmList::Cas ? ", cas"
                                                                                                        : ", sbuffer");
}

// A box [-1, 1] x [-0.5, 0.5] x [-0.25, 0.75] in a sphere of radius 2 at the origin, seen along
// each axis both ways and along a diagonal. Along an axis, a pixel whose line passes inside the
// box's cross-section (by more than the rasterizer's rounding of the edge, 1e-3 px here) holds
// exactly two entries, the box's two faces across it, at z = ±half + offset + radius; one outside
// holds none. Depths are interpolated from three float vertex depths: within a few u of 2·radius.
TEST_F(LdmGpuTest, ABoxSeenAlongEachAxisHasItsTwoFacesInEveryPixelInsideAndNothingOutside) {
  const glm::dvec3 lo(-1, -0.5, -0.25), hi(1, 0.5, 0.75);
  const Scene scene = boxScene(lo, hi);
  GpuScene gpuScene(*ctx, scene);
  for (const LdmBuildMethod method : {LdmBuildMethod::Hardware, LdmBuildMethod::Raster3d})
    for (const LdmList list : {LdmList::Max64, LdmList::Cas, LdmList::Sbuffer}) {
      SCOPED_TRACE(buildAndListName(method, list));
      const double radius = 2.0;
      const uint32_t R = 64;
      // dir, right, up (right × up = −dir: a right-handed view looking along dir).
      const glm::dvec3 X(1, 0, 0), Y(0, 1, 0), Z(0, 0, 1);
      const std::vector<std::array<glm::dvec3, 3>> frames = {{-Z, X, Y}, {Z, -X, Y},  {-X, -Z, Y},
                                                             {X, Z, Y},  {-Y, X, -Z}, {Y, X, Z}};
      std::vector<gpu::LdmMap> maps;
      for (const auto& f : frames) maps.push_back(mapOf(f[0], f[1], f[2], glm::dvec3(0), radius));
      LdmBuild build(*ctx, gpuScene, scene, maps, R, 8 * R * R, method, list);
      ctx->submitAndWait([&](VkCommandBuffer cmd) { build.record(cmd); });
      const std::vector<std::vector<float>> lists = build.readLists();
      const LdmCounters counters = build.readCounters();
      EXPECT_EQ(counters.overflow, 0u);
      EXPECT_EQ(counters.unfinished, 0u);
      const double u = 5.9604644775390625e-8, depthBound = 8.0 * u * 2.0 * radius;
      size_t inside = 0, wrong = 0, worstEntries = 0;
      uint64_t entries = 0;
      for (size_t m = 0; m < frames.size(); ++m) {
        const auto& [dir, right, up] = frames[m];
        for (uint32_t j = 0; j < R; ++j)
          for (uint32_t i = 0; i < R; ++i) {
            const std::vector<float>& depths = lists[(m * R + j) * R + i];
            entries += depths.size();
            const glm::dvec3 p =
                (2.0 * (i + 0.5) / R - 1.0) * radius * right + (1.0 - 2.0 * (j + 0.5) / R) * radius * up;
            // The pixel line's distance inside the box's cross-section (negative outside).
            double margin = 1e9;
            for (int a = 0; a < 3; ++a) {
              if (std::abs(dir[a]) > 0.5) continue;
              margin = std::min({margin, p[a] - lo[a], hi[a] - p[a]});
            }
            const double pixel = 2.0 * radius / R;
            if (std::abs(margin) < 1e-3 * pixel) continue;  // on the outline: either way
            if (margin < 0) {
              wrong += !depths.empty();
              continue;
            }
            ++inside;
            int axis = 0;
            for (int a = 0; a < 3; ++a)
              if (std::abs(dir[a]) > 0.5) axis = a;
            const double s = dir[axis];
            // z = (q − c)·dir + r for the two faces q[axis] = lo, hi.
            double z0 = s * lo[axis] + radius, z1 = s * hi[axis] + radius;
            if (z0 > z1) std::swap(z0, z1);
            const bool ok =
                depths.size() == 2 && std::abs(depths[0] - z0) <= depthBound && std::abs(depths[1] - z1) <= depthBound;
            wrong += !ok;
            worstEntries = std::max(worstEntries, depths.size());
          }
      }
      std::printf(
          "box LDMs (%s, %s), 6 axis maps of %ux%u: %zu pixels inside, %zu wrong, %llu entries, %llu nodes "
          "allocated\n",
          method == LdmBuildMethod::Hardware ? "hardware" : "3dr",
          list == LdmList::Max64 ? "max64"
          : list == LdmList::Cas ? "cas"
                                 : "sbuffer",
          R, R, inside, wrong, (unsigned long long)entries, (unsigned long long)counters.allocated);
      // Pixels are 1/16 m and the box's faces lie on pixel edges: the cross-sections (2 x 1, 1 x 1 and
      // 2 x 1 m² of the 4 x 4 m² map) hold exactly 512, 256 and 512 pixel centres, each seen both ways.
      EXPECT_EQ(inside, 2u * (512u + 256u + 512u));
      EXPECT_EQ(wrong, 0u);
      EXPECT_EQ(entries, counters.allocated);  // every fragment is in exactly one list
    }
}

// The fill rule at shared vertices (as 3DR's fill-rule tests): a grid of 24 x 24 quads, alternate
// diagonals, every vertex on a pixel centre of the map, seen head-on. Every centre strictly inside
// the grid lies in exactly one triangle's closed region or on shared edges and vertices, so each
// list must hold exactly one entry (0 holes, 0 double covers); the 3dr build decides edge values
// within their rounding bound in double, the hardware by Vulkan's rasterization rules. Centres on
// the grid's outline belong to no neighbour and may go either way: they are left out. (Measured: the
// 3dr build's float evaluation alone also gives 0 and 0 here, since the vertices' pixel coordinates
// are small and their products exact; the fallback decides 6,912 edge values and changes none.)
TEST_F(LdmGpuTest, AGridWithVerticesOnPixelCentresIsCoveredExactlyOncePerPixel) {
  const uint32_t R = 64, n = 24;
  const double radius = 2.0;
  const int first = 20;  // the grid's corner pixel; it spans pixels first .. first + n
  Scene scene;
  scene.name = "grid";
  scene.materials.push_back({});
  MeshBuilder mb("grid");
  auto at = [&](int i, int j) {  // the centre of map pixel (i, j): x right, y up (j down)
    return glm::dvec3((2.0 * (i + 0.5) / R - 1.0) * radius, (1.0 - 2.0 * (j + 0.5) / R) * radius, 0.0);
  };
  for (int j = 0; j < int(n); ++j)
    for (int i = 0; i < int(n); ++i) {
      const glm::dvec3 a = at(first + i, first + j), b = at(first + i + 1, first + j),
                       c = at(first + i + 1, first + j + 1), d = at(first + i, first + j + 1);
      auto v = [&](glm::dvec3 p) { return mb.vertex(0, Vertex{glm::vec3(p), glm::vec3(0, 0, 1), glm::vec2(0)}); };
      if ((i + j) % 2 == 0) {
        mb.triangle(0, v(a), v(b), v(c));
        mb.triangle(0, v(a), v(c), v(d));
      } else {
        mb.triangle(0, v(a), v(b), v(d));
        mb.triangle(0, v(b), v(c), v(d));
      }
    }
  mb.appendTo(scene);
  GpuScene gpuScene(*ctx, scene);
  const std::vector<gpu::LdmMap> maps = {mapOf({0, 0, -1}, {1, 0, 0}, {0, 1, 0}, glm::dvec3(0), radius)};
  for (const LdmBuildMethod method : {LdmBuildMethod::Hardware, LdmBuildMethod::Raster3d}) {
    SCOPED_TRACE(method == LdmBuildMethod::Hardware ? "hardware" : "3dr");
    LdmBuild build(*ctx, gpuScene, scene, maps, R, 4 * R * R, method);
    ctx->submitAndWait([&](VkCommandBuffer cmd) { build.record(cmd); });
    const std::vector<std::vector<float>> lists = build.readLists();
    size_t inside = 0, holes = 0, doubles = 0, outside = 0;
    for (int j = 0; j < int(R); ++j)
      for (int i = 0; i < int(R); ++i) {
        const size_t count = lists[size_t(j) * R + i].size();
        const bool in = i > first && i < first + int(n) && j > first && j < first + int(n);
        const bool out = i < first || i > first + int(n) || j < first || j > first + int(n);
        inside += in;
        holes += in && count == 0;
        doubles += in && count > 1;
        outside += out && count != 0;
      }
    std::printf(
        "grid on pixel centres (%s): %zu pixels inside, %zu holes, %zu double covers, %zu outside, fp64 edges %llu\n",
        method == LdmBuildMethod::Hardware ? "hardware" : "3dr", inside, holes, doubles, outside,
        (unsigned long long)build.readCounters().fp64Edges);
    EXPECT_EQ(inside, size_t((n - 1) * (n - 1)));
    EXPECT_EQ(holes, 0u);
    EXPECT_EQ(doubles, 0u);
    EXPECT_EQ(outside, 0u);
  }
}

// Lists are sorted, and a pool too small for the fragments is counted, never silent: the lists
// then hold exactly the nodes the pool had.
TEST_F(LdmGpuTest, AFullNodePoolIsCountedAndTheListsHoldWhatItHad) {
  const Scene scene = boxScene(glm::dvec3(-1), glm::dvec3(1));
  GpuScene gpuScene(*ctx, scene);
  for (const LdmBuildMethod method : {LdmBuildMethod::Hardware, LdmBuildMethod::Raster3d})
    for (const LdmList list : {LdmList::Max64, LdmList::Cas, LdmList::Sbuffer}) {
      SCOPED_TRACE(buildAndListName(method, list));
      const uint32_t R = 32, capacity = 500;
      std::vector<gpu::LdmMap> maps = {mapOf({0, 0, -1}, {1, 0, 0}, {0, 1, 0}, glm::dvec3(0), 2.0),
                                       mapOf({0.6, 0, -0.8}, {0.8, 0, 0.6}, {0, 1, 0}, glm::dvec3(0), 2.0)};
      LdmBuild build(*ctx, gpuScene, scene, maps, R, capacity, method, list);
      ctx->submitAndWait([&](VkCommandBuffer cmd) { build.record(cmd); });
      const std::vector<std::vector<float>> lists = build.readLists();
      const LdmCounters counters = build.readCounters();
      uint64_t entries = 0;
      for (const auto& l : lists) {
        entries += l.size();
        EXPECT_TRUE(std::is_sorted(l.begin(), l.end()));
      }
      EXPECT_GT(counters.allocated, uint64_t(capacity));
      EXPECT_EQ(counters.overflow, counters.allocated - capacity);
      EXPECT_EQ(entries, uint64_t(capacity));
      EXPECT_EQ(counters.unfinished, 0u);
    }
}

// The 3dr build's balance (ldm_build_3dr.comp.glsl): a pair rasterized by its own thread, a pair
// split into listed 64-pixel chunks, and a pair whose chunks did not fit the list all give a pixel the
// same fragment, bit for bit: both modes compute the view with the same `precise` expressions.
// sbuffer's words (offsets, then each range's depths and triangle ids sorted by (depth, id)) do not
// depend on arrival order, so they must be equal word for word whatever goes through the chunks: no
// chunks at all, every pair through chunks, the default split, a list of 7 entries that overflows
// in the middle of a pair, and chunks of 64 pixels instead of 512. On the atrium, whose triangles range from no pixel
// centre to thousands in a 128² map. max64's lists must hold the same depths.
TEST_F(LdmGpuTest, The3drBuildGivesTheSameListsWhicheverPairsGoThroughChunks) {
  const Scene scene = makeAtrium(AtriumParams{});
  GpuScene gpuScene(*ctx, scene);
  const uint32_t R = 128;
  const std::vector<gpu::LdmMap> maps = ldmMaps(scene, ldmDirections(8), R);
  const uint64_t pixels = uint64_t(maps.size()) * R * R, capacity = 4 * pixels;
  struct Case {
    const char* name;
    LdmBuildTuning tuning;
  };
  const Case cases[] = {{"no chunks", {.smallBox = ~0u}},
                        {"every pair through chunks", {.smallBox = 0}},
                        {"the default split", {}},
                        {"a list of 7 chunks", {.chunkCapacity = 7}},
                        {"chunks of 64 pixels", {.chunkPixels = 64}}};
  for (const LdmList list : {LdmList::Sbuffer, LdmList::Max64}) {
    std::vector<uint32_t> first;
    std::vector<std::vector<float>> firstLists;
    for (const Case& c : cases) {
      SCOPED_TRACE(std::string(list == LdmList::Sbuffer ? "sbuffer, " : "max64, ") + c.name);
      LdmBuild build(*ctx, gpuScene, scene, maps, R, uint32_t(capacity), LdmBuildMethod::Raster3d, list, c.tuning);
      ctx->submitAndWait([&](VkCommandBuffer cmd) { build.record(cmd); });
      const LdmCounters counters = build.readCounters();
      std::printf("atrium 8 maps of 128², 3dr %s, %s: %llu fragments, %llu chunks, %llu pairs past the list\n",
                  list == LdmList::Sbuffer ? "sbuffer" : "max64", c.name, (unsigned long long)counters.allocated,
                  (unsigned long long)counters.chunks, (unsigned long long)counters.chunkOverflow);
      EXPECT_EQ(counters.overflow, 0u);
      if (c.tuning.smallBox == ~0u) {
        EXPECT_EQ(counters.chunks, 0u);
      } else {
        EXPECT_GT(counters.chunks, 0u);
      }
      if (c.tuning.chunkCapacity == 7) {
        EXPECT_GT(counters.chunkOverflow, 0u);
      } else {
        EXPECT_EQ(counters.chunkOverflow, 0u);
      }
      if (list == LdmList::Max64) {
        std::vector<std::vector<float>> lists = build.readLists();
        if (firstLists.empty()) {
          firstLists = std::move(lists);
        } else {
          EXPECT_TRUE(lists == firstLists);
        }
        continue;
      }
      const std::vector<uint8_t> bytes = readbackBuffer(*ctx, build.links());
      const uint32_t* w = reinterpret_cast<const uint32_t*>(bytes.data());
      const uint32_t total = w[pixels];
      ASSERT_EQ(total, counters.allocated);
      std::vector<uint32_t> words(w, w + pixels + 1);                                                   // the offsets
      words.insert(words.end(), w + 2 * pixels + 1, w + 2 * pixels + 1 + total);                        // the depths
      words.insert(words.end(), w + 2 * pixels + 1 + capacity, w + 2 * pixels + 1 + capacity + total);  // the ids
      if (first.empty()) {
        first = std::move(words);
      } else {
        size_t differ = 0;
        for (size_t k = 0; k < std::min(words.size(), first.size()); ++k) differ += words[k] != first[k];
        EXPECT_EQ(words.size(), first.size());
        EXPECT_EQ(differ, 0u);
      }
    }
  }
}

}  // namespace
}  // namespace hb

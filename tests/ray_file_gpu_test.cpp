// Ray files end to end (reference/ray_file.h, ray_sets.h; gpu/peaks.h traceRayFile; `rays export`
// and `raybench`): the camera, AO and shadow sets of a scene, traced by every backend the device
// has, hit what the CPU's double-precision BVH hits, ray for ray.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <set>
#include <string>

#include "base/text_format.h"
#include "gltf/gltf_io.h"
#include "gpu/peaks.h"
#include "gpu/trace_bvh.h"
#include "gpu/trace_work.h"
#include "gpu_fixture.h"
#include "reference/ray_sets.h"
#include "scene/atrium.h"
#include "scene/hard_cases.h"
#include "tool_process.h"

namespace hb {
namespace {

class RayFileGpuTest : public hb::testing::GpuTest {};

RayFile fileOf(const Scene& scene, const std::string& kind, std::vector<RayRecord> rays, uint32_t gridWidth,
               const std::string& query = "closest") {
  RayFile f;
  f.info.count = rays.size();
  f.info.kind = kind;
  f.info.query = query;
  f.info.sceneName = scene.name;
  f.info.sceneSha256 = sceneSha256(scene);
  f.info.grid = {gridWidth, uint32_t((rays.size() + gridWidth - 1) / gridWidth)};
  f.rays = std::move(rays);
  return f;
}

// The CPU's double-precision hits of a file's rays and the GPU's trace of it by every backend;
// not vacuous: the rays both hit and miss.
RayFileTrace traceBeside(const VulkanContext& ctx, const Scene& scene, const Bvh& bvh, const RayFile& file,
                         RayHits& cpu) {
  cpu = traceOnCpu(bvh, file.rays, file.info.query == "any");
  EXPECT_GT(cpu.hits(), 0u);
  EXPECT_LT(cpu.hits(), file.rays.size());
  RayFileTrace trace = traceRayFile(ctx, scene, file);
  EXPECT_FALSE(trace.figures.empty());
  return trace;
}
// Rays a backend hits where the CPU misses, or misses where it hits.
size_t unlikeCpu(const RayFileHits& h, const RayHits& cpu) {
  size_t unlike = 0;
  for (size_t i = 0; i < h.missed.size(); ++i) unlike += (h.missed[i] == 0) != (cpu.t[i] >= 0.0);
  return unlike;
}

TEST_F(RayFileGpuTest, EveryBackendHitsWhatTheCpuHitsOnTheCameraAoAndShadowSets) {
  const Scene scene = makeAtrium(AtriumParams{});
  const RayView view = rayViewOf(scene.cameras.front(), 64, 36);
  const Bvh bvh = buildBvh(scene);
  const std::vector<RayRecord> camera = cameraRays(view);
  const RayHits cameraHits = traceOnCpu(bvh, camera);
  const SecondaryParams params;
  std::vector<RayFile> files = {fileOf(scene, "camera", camera, view.width),
                                fileOf(scene, "ao", aoRays(bvh, camera, cameraHits, params), view.width),
                                fileOf(scene, "shadow", shadowRays(bvh, camera, cameraHits, params), view.width)};
  files.push_back(fileOf(scene, "ao, any hit", files[1].rays, view.width, "any"));
  for (const RayFile& file : files) {
    SCOPED_TRACE(file.info.kind);
    const bool any = file.info.query == "any";
    RayHits cpu;
    const RayFileTrace trace = traceBeside(*ctx, scene, bvh, file, cpu);
    for (const Peak& p : trace.figures) {
      SCOPED_TRACE(p.backend);
      const RayFileHits& h = trace.hits.at(p.backend);
      ASSERT_EQ(h.missed.size(), file.rays.size());
      if (p.backend.find("-loads") != std::string::npos) {
        // The loads ceiling traces nothing: each ray walks the CPU replay's fetches and writes the
        // replay's flag, so its flags are the replay's, ray for ray (every ray visited).
        std::vector<uint8_t> replayMissed;
        traceWork(layoutTraceBvh(scene.worldTriangles(), 4), file.rays, any, nullptr, &replayMissed);
        size_t differ = 0;
        for (size_t i = 0; i < file.rays.size(); ++i) differ += h.missed[i] != replayMissed[i];
        EXPECT_EQ(differ, 0u);
        EXPECT_GT(p.perSecond, 0.0);
        continue;
      }
      // Watertight tracers, ours and the driver's, on the same float rays: a ray the exact test
      // hits is hit by every backend, one it misses by none (a silhouette edge is hit by both of
      // its triangles or neither, whichever side the ray passes).
      EXPECT_EQ(unlikeCpu(h, cpu), 0u);
      EXPECT_EQ(size_t(p.missed), file.rays.size() - cpu.hits());
      if (any || h.t.empty() || p.backend.rfind("compute", 0) != 0) continue;
      // Our BVH's t: the watertight test's ratio of float sums, a few u (2^-24) of t away from the
      // double one for rays that do not graze their triangle; the same 1e-6 as the primary ray
      // cast's depth (raster3d_continuum_gpu_test.cpp), here for every ray.
      double worst = 0;
      for (size_t i = 0; i < file.rays.size(); ++i)
        if (cpu.t[i] > 0.0 && h.missed[i] == 0) worst = std::max(worst, std::abs(h.t[i] - cpu.t[i]) / cpu.t[i]);
      EXPECT_LE(worst, 1e-6);
    }
  }
}

// Rays aimed at the edges of the cube 10 km from the origin ("far-origin"), where a float's spacing
// is ~1 mm. The any-hit traversal's slab test is one fma a plane with o·inv rounded once
// (compute_occluded.glsl.inc slabRay): an absolute error of up to u·|o_a| (6e-4 m here) in where a
// plane lies, while these rays pass their edge within the rounding of their direction (~1e-7 m).
// A ray that meets the box's entry and exit planes on different axes at nearly the same t is lost
// unless each plane's constant is widened toward its side; every backend must hit what the CPU's
// double-precision BVH hits, ray for ray, for any and closest hits (without the widening, δ = 0, the
// any-hit rays lost 433 of 4,096). The driver's traversal is printed, not held to it.
TEST_F(RayFileGpuTest, RaysThroughTheEdgesOfABoxFarFromTheOriginAreTracedAsTheCpuTracesThem) {
  const Scene scene = makeFarOrigin();
  const Bvh bvh = buildBvh(scene);
  const glm::dvec3 c(kFarOriginOffset, 1.0, 0.0);  // the cube's centre (makeCube: [-0.5, 0.5] about it)
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<RayRecord> rays;
  for (int i = 0; i < 4096; ++i) {
    // A point on one of the 12 edges: two coordinates at ±0.5, the third anywhere along it.
    const int axis = i % 3;
    glm::dvec3 q;
    q[axis] = unit(rng) - 0.5;
    q[(axis + 1) % 3] = (i / 3) % 2 ? 0.5 : -0.5;
    q[(axis + 2) % 3] = (i / 6) % 2 ? 0.5 : -0.5;
    // From 1.5 to 3 m away, on the edge's outer side (both of its faces seen from outside or grazed).
    glm::dvec3 away(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5);
    away[(axis + 1) % 3] = std::abs(away[(axis + 1) % 3]) * (q[(axis + 1) % 3] > 0 ? 1 : -1);
    away[(axis + 2) % 3] = std::abs(away[(axis + 2) % 3]) * (q[(axis + 2) % 3] > 0 ? 1 : -1);
    const double distance = 1.5 + 1.5 * unit(rng);
    const glm::dvec3 target = c + q, origin = target + glm::normalize(away) * distance;
    const glm::dvec3 dir = glm::normalize(target - origin);
    RayRecord r;
    for (int a = 0; a < 3; ++a) {
      r.origin[a] = float(origin[a]);
      r.dir[a] = float(dir[a]);
    }
    // Ending 5 cm past the edge: a ray that passes it meets nothing else (the ground is 0.5 m below).
    r.tMin = 0.0f;
    r.tMax = float(distance + 0.05);
    rays.push_back(r);
  }
  for (const char* query : {"any", "closest"}) {
    SCOPED_TRACE(query);
    const RayFile file = fileOf(scene, "edges", rays, 64, query);
    RayHits cpu;
    const RayFileTrace trace = traceBeside(*ctx, scene, bvh, file, cpu);  // rays on both sides of the edges
    for (const Peak& p : trace.figures) {
      SCOPED_TRACE(p.backend);
      const RayFileHits& h = trace.hits.at(p.backend);
      ASSERT_EQ(h.missed.size(), file.rays.size());
      const size_t unlike = unlikeCpu(h, cpu);
      std::printf("edges of the far cube, %s hit: %s differs from the CPU on %zu of %zu rays\n", query,
                  p.backend.c_str(), unlike, file.rays.size());
      // Ours only: lavapipe's own traversal loses 18 of these rays (its boxes are not widened so).
      if (p.backend.rfind("compute", 0) == 0 && p.backend.find("-loads") == std::string::npos) {
        EXPECT_EQ(unlike, 0u);
      }
    }
  }
}

class RaysCli : public hb::testing::ToolTest {};

// A glTF made outside this repository without a camera (scenes/external, OpenSCAD's MCAD gears): the
// export frames it as render's camera=auto does, says so, and records that camera; the rays hit the
// gears and every backend traces them as the CPU's double-precision BVH does.
TEST_F(RaysCli, ACameraLessGltfIsFramedAutomaticallyAndEveryBackendTracesItsRaysAsTheCpu) {
  using namespace hb::testing;
  const std::string gears = std::string(HYBRIDBENCH_SOURCE_DIR) + "/scenes/external/mcad-gears.glb";
  const RunResult exported =
      run({"rays", "export", "--scene", gears, "--size", "32x18", "--out", (dir / "r").string()});
  ASSERT_EQ(exported.exitCode, 0) << exported.err;
  EXPECT_NE(exported.out.find("has no camera; framed it automatically"), std::string::npos) << exported.out;
  const json info = readJson(dir / "r" / "camera.json");
  EXPECT_TRUE(info.contains("camera") && info["camera"].is_object()) << info.dump();
  const RunResult bench =
      run({"raybench", (dir / "r" / "camera.bin").string(), "--scene", gears, "--json", (dir / "b.json").string()});
  ASSERT_EQ(bench.exitCode, 0) << bench.err;
  const json figures = readJson(dir / "b.json");
  ASSERT_FALSE(figures["backends"].empty());
  for (const json& b : figures["backends"]) {
    EXPECT_EQ(b["unlike_cpu"], 0) << b["backend"];
    EXPECT_LT(b["missed"].get<double>(), info["count"].get<double>()) << "the camera sees the gears";
  }
}

TEST_F(RaysCli, ExportedFilesTraceWithEveryBackendAndAnotherScenesFileIsRefused) {
  using namespace hb::testing;
  const RunResult exported =
      run({"rays", "export", "--scene", "atrium", "--size", "32x18", "--out", (dir / "r").string()});
  ASSERT_EQ(exported.exitCode, 0) << exported.err;
  for (const char* kind : {"camera", "ao", "shadow"}) {
    EXPECT_TRUE(fs::is_regular_file(dir / "r" / (std::string(kind) + ".bin"))) << kind;
    EXPECT_EQ(readJson(dir / "r" / (std::string(kind) + ".json"))["scene"]["name"], "atrium");
  }
  const RunResult bench = run({"raybench", (dir / "r" / "shadow.bin").string(), "--json", (dir / "b.json").string()});
  ASSERT_EQ(bench.exitCode, 0) << bench.err;
  const json figures = readJson(dir / "b.json");
  ASSERT_FALSE(figures["backends"].empty());
  for (const json& b : figures["backends"]) EXPECT_EQ(b["unlike_cpu"], 0) << b["backend"];
  // What the driver compiled each kernel into: a table where the device offers the statistics (and
  // the compute backends carry them), one line saying so where it does not (lavapipe).
  const RunResult devices = run({"devices", "--json"});
  ASSERT_EQ(devices.exitCode, 0) << devices.err;
  const bool statistics = json::parse(devices.out)["devices"][0]["pipeline_statistics"].get<bool>();
  EXPECT_NE(bench.out.find(statistics ? "| backend | executable | statistics |" : "gives no pipeline statistics"),
            std::string::npos)
      << bench.out;
  for (const json& b : figures["backends"]) {
    if (b["backend"].get<std::string>().rfind("compute", 0) == 0) {
      EXPECT_EQ(b["compiled"].is_array(), statistics) << b.dump();
    }
  }
  // The traversal's work a ray, for each width: every shadow ray starts inside the scene's box, so
  // each fetches the root at least; a wide tree is shallower, so it fetches fewer nodes.
  ASSERT_EQ(figures["traversal_work"].size(), 3u) << figures.dump();
  for (const json& w : figures["traversal_work"]) EXPECT_GE(w["nodes_per_ray"].get<double>(), 1.0) << w.dump();
  EXPECT_LT(figures["traversal_work"][2]["nodes_per_ray"].get<double>(),
            figures["traversal_work"][0]["nodes_per_ray"].get<double>());
  EXPECT_NE(bench.out.find("| compute-w8 |"), std::string::npos) << bench.out;
  // rays table: a row for the file, its figure as the JSON has it; a file that is not one, one line.
  const RunResult table = run({"rays", "table", (dir / "b.json").string()});
  ASSERT_EQ(table.exitCode, 0) << table.err;
  EXPECT_NE(table.out.find("| b.json | shadow | closest | " + std::to_string(figures["file"]["count"].get<uint64_t>())),
            std::string::npos)
      << table.out;
  // and each loads ceiling's share, as raybench's JSON has it.
  for (const json& c : figures["loads_ceiling"])
    EXPECT_NE(table.out.find(format("| b.json | compute-w4 | %s |", c["ceiling"].get<std::string>().c_str())),
              std::string::npos)
        << table.out;
  EXPECT_EQ(figures["loads_ceiling"].size(), 2u) << figures.dump();
  const RunResult work = run({"rays", "table", (dir / "b.json").string(), "--work"});
  ASSERT_EQ(work.exitCode, 0) << work.err;
  EXPECT_NE(work.out.find(
                format("| b.json | compute-w8 | %.2f |", figures["traversal_work"][2]["nodes_per_ray"].get<double>())),
            std::string::npos)
      << work.out;
  // --compiled: the driver's statistics as columns where the files carry them, one line where none does.
  const RunResult compiled = run({"rays", "table", (dir / "b.json").string(), "--compiled"});
  ASSERT_EQ(compiled.exitCode, 0) << compiled.err;
  EXPECT_NE(compiled.out.find(statistics ? "| file | backend |" : "No file carries the driver's pipeline statistics"),
            std::string::npos)
      << compiled.out;
  const RunResult notOne = run({"rays", "table", (dir / "r" / "shadow.bin").string()});
  EXPECT_EQ(notOne.exitCode, 2);
  EXPECT_NE(notOne.err.find("not a raybench --json file"), std::string::npos) << notOne.err;
  EXPECT_EQ(std::count(notOne.err.begin(), notOne.err.end(), '\n'), 1) << notOne.err;
  // --hits-out: a record a ray for every backend and the CPU; our BVH names the CPU's triangle on
  // every hit (or ties it at a shared edge), at barycentrics inside it.
  const RunResult withHits = run({"raybench", (dir / "r" / "camera.bin").string(), "--json", (dir / "c.json").string(),
                                  "--hits-out", (dir / "hits").string()});
  ASSERT_EQ(withHits.exitCode, 0) << withHits.err;
  const json camera = readJson(dir / "c.json");
  const uint64_t count = camera["file"]["count"].get<uint64_t>();
  const uint64_t cpuHits = camera["cpu_reference"]["hits"].get<uint64_t>();
  ASSERT_GT(cpuHits, 0u);
  ASSERT_FALSE(camera["triangles_against_cpu"].empty());
  // Every backend but the ray-tracing pipeline (it runs no hit shader) and the loads ceiling (no
  // tracer) names its triangle: ours at each width and, where the device offers it (lavapipe does),
  // ray query. The ceiling's line says how close the 4-wide traversal runs to it.
  ASSERT_EQ(camera["loads_ceiling"].size(), 2u) << camera.dump();  // as the nodes are, and at half their bytes
  for (const json& c : camera["loads_ceiling"]) EXPECT_GT(c["fraction_of_ceiling"].get<double>(), 0.0) << c.dump();
  std::set<std::string> named, naming;
  for (const json& t : camera["triangles_against_cpu"]) named.insert(t["backend"].get<std::string>());
  for (const json& b : camera["backends"])
    if (b["backend"] != "pipeline" && b["backend"].get<std::string>().find("-loads") == std::string::npos)
      naming.insert(b["backend"].get<std::string>());
  EXPECT_EQ(named, naming);
  for (const json& t : camera["triangles_against_cpu"]) {
    EXPECT_EQ(t["same"].get<uint64_t>() + t["tie"].get<uint64_t>(), cpuHits) << t.dump();
    EXPECT_EQ(t["other"], 0) << t.dump();
  }
  const json described = readJson(dir / "hits" / "hits.json");
  for (const auto& [backend, name] : described["files"].items()) {
    const fs::path path = dir / "hits" / name.get<std::string>().substr(0, name.get<std::string>().find(' '));
    EXPECT_EQ(fs::file_size(path), 16 * count) << backend;
  }
  const std::string ours = readFile(dir / "hits" / "compute-w8.hits.bin"),
                    cpuFile = readFile(dir / "hits" / "cpu.hits.bin");
  ASSERT_EQ(ours.size(), 16 * count);
  size_t inside = 0;
  for (size_t i = 0; i < count; ++i) {
    uint32_t id, cpuId;
    float u, v;
    std::memcpy(&id, ours.data() + 16 * i + 4, 4);
    std::memcpy(&cpuId, cpuFile.data() + 16 * i + 4, 4);
    std::memcpy(&u, ours.data() + 16 * i + 8, 4);
    std::memcpy(&v, ours.data() + 16 * i + 12, 4);
    if (id == ~0u) continue;
    // Inside the triangle, to the rounding of the double barycentrics (a few 1e-16; 1e-6 is far).
    inside += u >= -1e-6f && v >= -1e-6f && u + v <= 1.0f + 1e-6f;
    EXPECT_TRUE(id == cpuId || cpuId == ~0u) << "ray " << i;
  }
  EXPECT_EQ(inside, cpuHits);
  const RunResult intoFile =
      run({"raybench", (dir / "r" / "camera.bin").string(), "--hits-out", (dir / "r" / "camera.json").string()});
  EXPECT_EQ(intoFile.exitCode, 2);
  EXPECT_NE(intoFile.err.find("--hits-out"), std::string::npos) << intoFile.err;
  EXPECT_EQ(std::count(intoFile.err.begin(), intoFile.err.end(), '\n'), 1) << intoFile.err;
  // The same file against another scene: one line, exit 2.
  const RunResult other = run({"raybench", (dir / "r" / "shadow.bin").string(), "--scene", "plane"});
  EXPECT_EQ(other.exitCode, 2);
  EXPECT_NE(other.err.find("its rays are of a scene with geometry sha256"), std::string::npos) << other.err;
  EXPECT_EQ(std::count(other.err.begin(), other.err.end(), '\n'), 1) << other.err;
}

}  // namespace
}  // namespace hb

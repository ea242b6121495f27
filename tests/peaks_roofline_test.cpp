// `hybridbench peaks` and the roofline every timed pass carries (docs/usage.md "peaks",
// docs/results-format.md "roofline"), end to end through the built tool on the device present
// (lavapipe in CI, where the figures are the host's: small but real).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tool_process.h"

namespace {

using namespace hb::testing;

class Peaks : public ToolTest {
 protected:
  void SetUp() override {
    ToolTest::SetUp();
    // A cache of this test's own: what `peaks` writes and a sweep then reads.
    setenv("HYBRIDBENCH_PEAKS_CACHE", (dir / "cache").c_str(), 1);
  }
  void TearDown() override {
    unsetenv("HYBRIDBENCH_PEAKS_CACHE");
    ToolTest::TearDown();
  }
};

// Every figure the microbenchmarks measure on any device (atomic_min_u64 where the device has
// 64-bit buffer atomics, as lavapipe and the NVIDIA GPUs do).
const std::vector<std::string> kFigures = {
    "memory_read", "memory_write",     "memory_copy", "atomic_add_distinct", "atomic_add_contended",
    "fma_fp32",    "raster_triangles", "raster_fill", "atomic_min_u64",      "dispatch_empty"};
// On the scene, through every backend lavapipe has: the ray-tracing pipeline (unsuffixed, as the
// NVIDIA GPUs have it too), ray query, our BVH in compute at every width, and at widths 4 and 8
// with persistent threads (lavapipe has compute subgroup ballots).
const std::vector<std::string> kRayFigures = {"rays_camera",
                                              "rays_random_closest",
                                              "rays_random_occlusion",
                                              "rays_ao",
                                              "rays_camera_rayquery",
                                              "rays_random_closest_rayquery",
                                              "rays_random_occlusion_rayquery",
                                              "rays_ao_rayquery",
                                              "rays_camera_compute",
                                              "rays_random_closest_compute",
                                              "rays_random_occlusion_compute",
                                              "rays_ao_compute",
                                              "rays_camera_compute_w4",
                                              "rays_random_closest_compute_w4",
                                              "rays_random_occlusion_compute_w4",
                                              "rays_ao_compute_w4",
                                              "rays_camera_compute_w8",
                                              "rays_random_closest_compute_w8",
                                              "rays_random_occlusion_compute_w8",
                                              "rays_ao_compute_w8",
                                              "rays_camera_compute_w4_persistent",
                                              "rays_random_closest_compute_w4_persistent",
                                              "rays_random_occlusion_compute_w4_persistent",
                                              "rays_ao_compute_w4_persistent",
                                              "rays_camera_compute_w8_persistent",
                                              "rays_random_closest_compute_w8_persistent",
                                              "rays_random_occlusion_compute_w8_persistent",
                                              "rays_ao_compute_w8_persistent"};

// Which ray figures a peaks record holds: none (the cache), the driver's pipeline (a sweep or render
// on a CPU device, gpu/peaks.h addRayPeaks) or every backend's (`peaks`).
enum class RayFigures { None, Driver, Every };
const std::vector<std::string> kDriverRayFigures = {"rays_camera", "rays_random_closest", "rays_random_occlusion"};

// A measurement's telemetry (gpu/telemetry.h toJson): both readings, the verdict and its reasons;
// or, where NVML cannot be used, available false and the reason alone.
void expectTelemetryShape(const json& t) {
  ASSERT_TRUE(t.is_object()) << t.dump();
  ASSERT_TRUE(t["available"].is_boolean()) << t.dump();
  if (t["available"] == false) {
    EXPECT_NE(t.value("reason", ""), "") << t.dump();
    EXPECT_FALSE(t.contains("before")) << t.dump();
    return;
  }
  for (const char* side : {"before", "after"})
    for (const char* key : {"sm_clock_mhz", "memory_clock_mhz", "power_w", "temperature_c", "clock_reasons"})
      EXPECT_TRUE(t[side].contains(key)) << side << "." << key;
  EXPECT_TRUE(t["throttled"].is_boolean() || t["throttled"].is_null()) << t.dump();
  EXPECT_TRUE(t["throttle_reasons"].is_array()) << t.dump();
  EXPECT_EQ(t.contains("warning"), t["throttled"] == true) << t.dump();
}

void expectPeaksShape(const json& p, RayFigures which) {
  const bool rays = which == RayFigures::Every;
  EXPECT_EQ(p.value("version", 0), 2);
  for (const char* key : {"device", "uuid", "driver", "timing"})
    EXPECT_TRUE(p.contains(key) && p[key].is_string() && !p[key].get<std::string>().empty()) << key;
  ASSERT_TRUE(p.contains("figures") && p["figures"].is_object());
  std::set<std::string> keys;
  for (const auto& [key, f] : p["figures"].items()) {
    SCOPED_TRACE(key);
    keys.insert(key);
    EXPECT_FALSE(f.value("unit", "").empty());
    EXPECT_FALSE(f.value("description", "").empty());
    // Every figure positive and finite, and its rate the work over the median time.
    const double perS = f.value("per_s", 0.0), work = f.value("work", 0.0);
    EXPECT_TRUE(std::isfinite(perS) && perS > 0) << perS;
    EXPECT_GT(work, 0);
    ASSERT_TRUE(f.contains("ms") && f["ms"].is_object());
    const double median = f["ms"].value("median", 0.0);
    EXPECT_GT(median, 0);
    EXPECT_LE(f["ms"].value("min", 0.0), median);
    EXPECT_GE(f["ms"].value("max", 0.0), median);
    EXPECT_GE(f["ms"]["samples"].size(), 3u);
    EXPECT_NEAR(perS, work / (median * 1e-3), 1e-9 * perS);
  }
  for (const std::string& k : kFigures) EXPECT_TRUE(keys.count(k)) << "no figure " << k;
  for (const std::string& k : kRayFigures) {
    const bool expected =
        rays || (which == RayFigures::Driver &&
                 std::find(kDriverRayFigures.begin(), kDriverRayFigures.end(), k) != kDriverRayFigures.end());
    EXPECT_EQ(keys.count(k), expected ? 1u : 0u) << k;
  }
  if (!rays) return;
  // The same rays through each backend: every backend misses the same number of them (our
  // watertight test and the driver's could part only on a ray through an edge or vertex, which
  // random and pixel-centre rays meet with probability 0).
  for (const char* mode : {"rays_camera", "rays_random_closest", "rays_random_occlusion", "rays_ao"}) {
    SCOPED_TRACE(mode);
    const double missed = p["figures"][mode].value("missed", -1.0);
    EXPECT_GE(missed, 0);
    EXPECT_LT(missed, p["figures"][mode].value("work", 0.0));
    for (const char* backend :
         {"_rayquery", "_compute", "_compute_w4", "_compute_w8", "_compute_w4_persistent", "_compute_w8_persistent"})
      EXPECT_EQ(p["figures"][std::string(mode) + backend].value("missed", -2.0), missed) << backend;
  }
  EXPECT_EQ(p["figures"]["rays_random_closest"]["missed"], p["figures"]["rays_random_occlusion"]["missed"]);
  // The public tracers' three sets (addPublicRayPeaks): every backend misses the same rays; the
  // camera set is the built-in camera rays made on the CPU, so it misses as many; the AO and shadow
  // sets hold a ray per camera hit.
  for (const char* set : {"rays_public_camera", "rays_public_ao", "rays_public_shadow"}) {
    SCOPED_TRACE(set);
    ASSERT_TRUE(p["figures"].contains(set));
    const double missed = p["figures"][set].value("missed", -1.0);
    for (const char* backend :
         {"_rayquery", "_compute", "_compute_w4", "_compute_w8", "_compute_w4_persistent", "_compute_w8_persistent"})
      EXPECT_EQ(p["figures"][std::string(set) + backend].value("missed", -2.0), missed) << backend;
  }
  EXPECT_EQ(p["figures"]["rays_public_camera"]["missed"], p["figures"]["rays_camera"]["missed"]);
  const double cameraHits =
      p["figures"]["rays_public_camera"].value("work", 0.0) - p["figures"]["rays_public_camera"].value("missed", 0.0);
  EXPECT_EQ(p["figures"]["rays_public_ao"].value("work", 0.0), cameraHits);
  EXPECT_EQ(p["figures"]["rays_public_shadow"].value("work", 0.0), cameraHits);
}

TEST_F(Peaks, JsonHasEveryFigurePositiveAndTheTableTheSame) {
  const RunResult r = run({"peaks", "--json"});
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_EQ(r.err.find("validation"), std::string::npos) << r.err;
  const json p = json::parse(r.out, nullptr, false);
  ASSERT_FALSE(p.is_discarded()) << r.out;
  expectPeaksShape(p, RayFigures::Every);
  expectTelemetryShape(p["telemetry"]);
  // The cache holds what was printed but the scene's ray rates and the telemetry of this run.
  std::vector<fs::path> cached;
  for (const auto& e : fs::directory_iterator(dir / "cache")) cached.push_back(e.path());
  ASSERT_EQ(cached.size(), 1u);
  const json cache = json::parse(readFile(cached[0]));
  expectPeaksShape(cache, RayFigures::None);
  json deviceOnly = p;
  deviceOnly.erase("telemetry");
  for (const std::string& k : kRayFigures) deviceOnly["figures"].erase(k);
  std::vector<std::string> publicSets;  // the public tracers' sets are the scene's too
  for (const auto& [key, f] : deviceOnly["figures"].items())
    if (key.rfind("rays_public_", 0) == 0) publicSets.push_back(key);
  size_t backends = 0;  // the backends the built-in camera rays went through
  for (const auto& [key, f] : p["figures"].items())
    backends += key == "rays_camera" || key.rfind("rays_camera_", 0) == 0;
  EXPECT_EQ(publicSets.size(), 3 * backends);
  for (const std::string& k : publicSets) deviceOnly["figures"].erase(k);
  EXPECT_EQ(cache, deviceOnly);

  const RunResult table = run({"peaks"});
  ASSERT_EQ(table.exitCode, 0) << table.err;
  for (const std::string& k : kFigures) EXPECT_NE(table.out.find("| " + k + " |"), std::string::npos) << k;
  for (const std::string& k : kRayFigures) EXPECT_NE(table.out.find("| " + k + " |"), std::string::npos) << k;
}

TEST_F(Peaks, BadDeviceIsOneLineExit2) {
  const RunResult r = run({"peaks", "--device", "99"});
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("--device 99"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// Every timed entry (pass and sub-pass) of every variant has a roofline entry whose figures are
// consistent: achieved = work / ms, fraction = achieved / peak, bound the highest fraction of
// its loads. The fixture runs one variant of each kind of pass the four measured sweeps have
// (thesis, 3d-rasterization, layered-depth-maps, many-lights).
TEST_F(Peaks, EveryTimedPassOfEveryKindHasARoofline) {
  const fs::path config = fs::path(HYBRIDBENCH_SOURCE_DIR) / "tests/fixtures/roofline-every-pass.json";
  const fs::path out = dir / "out";
  const RunResult r = run({"sweep", config.string(), "--out", out.string(), "--no-images"});
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const json results = json::parse(readFile(out / "results.json"));
  const json& peaks = results["context"]["device"]["peaks"];
  expectPeaksShape(peaks, RayFigures::Driver);  // lavapipe: a CPU device's sweep measures the driver's only
  // The warm-up before the first variant (gpu/warm_up.h): a GPU's rounds and whether it settled, a
  // CPU device's reason to skip it; the peaks carry the one they were measured after.
  const json& warm = results["context"]["device"]["warm_up"];
  ASSERT_TRUE(warm.is_object()) << results["context"]["device"].dump();
  if (results["context"]["device"].value("type", "") == "cpu") {
    EXPECT_EQ(warm["ran"], false);
    EXPECT_NE(warm.value("skipped", ""), "");
  } else {
    EXPECT_GE(warm["rounds"].get<int>(), 10);
    EXPECT_TRUE(warm["settled"].is_boolean());
  }
  EXPECT_TRUE(peaks.contains("warm_up")) << peaks.dump().substr(0, 300);
  // NVML's telemetry (gpu/telemetry.h): the device's once, and each variant's before and after its
  // measured frames; on a device without it (lavapipe here) one field says why, and nothing fails.
  const json& telemetry = results["context"]["device"]["telemetry"];
  ASSERT_TRUE(telemetry.is_object()) << results["context"]["device"].dump().substr(0, 300);
  if (telemetry["available"] == true)
    EXPECT_TRUE(telemetry.contains("max_sm_clock_mhz")) << telemetry.dump();
  else
    EXPECT_NE(telemetry.value("reason", ""), "") << telemetry.dump();
  for (const json& run : results["runs"]) {
    SCOPED_TRACE(run.value("name", ""));
    expectTelemetryShape(run["telemetry"]);
    EXPECT_EQ(run["telemetry"]["available"], telemetry["available"]);
  }
  std::set<std::string> entriesSeen;
  for (const json& run : results["runs"]) {
    SCOPED_TRACE(run.value("name", ""));
    ASSERT_EQ(run.value("status", ""), "ok") << run.dump();
    ASSERT_TRUE(run.contains("roofline"));
    for (const auto& [entry, t] : run["passes"].items()) {
      SCOPED_TRACE(entry);
      entriesSeen.insert(entry);
      ASSERT_TRUE(run["roofline"].contains(entry)) << "no roofline for a timed pass";
      const json& rl = run["roofline"][entry];
      for (const char* key : {"bound", "unit", "source"}) EXPECT_TRUE(rl[key].is_string()) << key;
      EXPECT_EQ(rl["ms"].get<double>(), t["median"].get<double>());
      EXPECT_GE(rl["work"].get<double>(), 0);
      ASSERT_FALSE(rl["loads"].empty());
      double best = -1;
      for (const json& load : rl["loads"]) {
        const double achieved = load["achieved_per_s"].get<double>();
        if (rl["ms"].get<double>() > 0) {
          EXPECT_NEAR(achieved, load["work"].get<double>() / (rl["ms"].get<double>() * 1e-3), 1e-9 * achieved);
        }
        if (load["fraction"].is_number()) {
          EXPECT_NEAR(load["fraction"].get<double>(), achieved / load["peak_per_s"].get<double>(),
                      1e-12 * load["fraction"].get<double>());
          best = std::max(best, load["fraction"].get<double>());
        }
        const std::string source = load["source"].get<std::string>();
        EXPECT_TRUE(source.rfind("counted: ", 0) == 0 || source.rfind("derived: ", 0) == 0) << source;
      }
      if (best >= 0) {
        EXPECT_EQ(rl["fraction"].get<double>(), best);
      }
    }
    // The work the analysis counted is the work the roofline divides: rays traced by the shadow pass.
    if (run["roofline"].contains("shadows")) {
      EXPECT_EQ(run["roofline"]["shadows"]["work"].get<double>(), run["rays"]["traced"].get<double>());
    }
  }
  // Timing-shaped checks, which hold on any device (lavapipe's timestamps do not bracket compute
  // work, so its times say nothing of speed, but they are still stamps of one clock): every timed
  // pass has a nonzero duration in each measured frame; the sub-passes of a pass ("raster3d.scan"
  // of "raster3d") sum to no more than it, and the passes to no more than their frame. Each
  // duration is a difference of two stamps quantised to timestamp_period_ns, so it is off by less
  // than one tick: a sum of k durations against one other is off by less than k + 1 ticks.
  const double tickMs = results["context"]["device"]["timestamp_period_ns"].get<double>() * 1e-6;
  const size_t frames = results["context"]["frames"]["measured"].get<size_t>();
  for (const json& run : results["runs"]) {
    SCOPED_TRACE(run.value("name", ""));
    const json& passes = run["passes"];
    for (const auto& [entry, t] : passes.items()) {
      ASSERT_EQ(t["samples"].size(), frames) << entry;
      for (const json& ms : t["samples"]) EXPECT_GT(ms.get<double>(), 0.0) << entry;
    }
    for (size_t f = 0; f < frames; ++f) {
      std::map<std::string, std::pair<double, size_t>> subSums;  // pass -> (sum of its sub-passes, count)
      double passSum = 0;
      size_t passCount = 0;
      for (const auto& [entry, t] : passes.items()) {
        const double ms = t["samples"][f].get<double>();
        const size_t dot = entry.find('.');
        if (dot == std::string::npos) {
          passSum += ms;
          ++passCount;
        } else {
          auto& [sum, count] = subSums[entry.substr(0, dot)];
          sum += ms;
          ++count;
        }
      }
      for (const auto& [pass, sc] : subSums) {
        ASSERT_TRUE(passes.contains(pass)) << "sub-passes of an untimed pass " << pass;
        EXPECT_LE(sc.first, passes[pass]["samples"][f].get<double>() + double(sc.second + 1) * tickMs)
            << pass << " frame " << f;
      }
      EXPECT_LE(passSum, run["frame_ms"]["samples"][f].get<double>() + double(passCount + 1) * tickMs) << "frame " << f;
    }
  }
  // Each kind of pass and sub-pass ran at least once.
  for (const char* e : {"depth_prepass",
                        "light_culling",
                        "shadows",
                        "shading",
                        "raster3d",
                        "raster3d.triangles",
                        "raster3d.count",
                        "raster3d.scan",
                        "raster3d.fill",
                        "raster3d.tiles",
                        "raster3d.resolve",
                        "raster3d.depth_copy",
                        "raycast",
                        "raycast.resolve",
                        "raycast.depth_copy",
                        "ldm_build",
                        "ambient_occlusion",
                        "indirect_ldm_build",
                        "photon_trace",
                        "photon_splat",
                        "ldm_build.insert",
                        "indirect_ldm_build.count",
                        "indirect_ldm_build.scan",
                        "indirect_ldm_build.fill",
                        "indirect_ldm_build.sort"})
    EXPECT_TRUE(entriesSeen.count(e)) << e;
  // The roofline table and plot are written beside the results, and the accuracy report names
  // the fraction of the limit.
  const std::string md = readFile(out / "roofline.md");
  EXPECT_NE(md.find("| Variant | Pass | ms | x empty | Bound |"), std::string::npos) << md;
  EXPECT_NE(readFile(out / "roofline.svg").find("<circle"), std::string::npos);
  EXPECT_NE(readFile(out / "accuracy.md").find("Fraction of the limit"), std::string::npos);
  const RunResult tables = run({"tables", (out / "results.json").string(), "--format", "roofline"});
  ASSERT_EQ(tables.exitCode, 0) << tables.err;
  EXPECT_EQ(tables.out, md);
}

// A pass faster than the device's peak for its bound ran on another path than the peak's kernel:
// the peak is not that pass's, and `render` says so beside the percentage. The peaks cache of this
// test's own, written by a first render, is then scaled down a billionfold (peaks of a much slower
// device), so the second render's passes bound by those figures are over their peaks.
TEST_F(Peaks, RenderSaysAPassOverItsPeakIsNotOnItsOwnPeak) {
  const std::vector<std::string> args = {"render", "--scene", "cube", "--size", "32x24", "--out"};
  auto withOut = [&](const char* out) {
    std::vector<std::string> a = args;
    a.push_back((dir / out).string());
    return a;
  };
  const RunResult first = run(withOut("first"));
  ASSERT_EQ(first.exitCode, 0) << first.out << first.err;
  size_t scaled = 0;
  for (const auto& entry : fs::directory_iterator(dir / "cache")) {
    json cache = json::parse(readFile(entry.path()));
    for (auto& [key, figure] : cache["figures"].items()) figure["per_s"] = figure["per_s"].get<double>() * 1e-9;
    hb::testing::writeFile(entry.path(), cache.dump());
    ++scaled;
  }
  ASSERT_EQ(scaled, 1u) << "the first render should have written one peaks cache";
  const RunResult r = run(withOut("second"));
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const json roofline = json::parse(readFile(dir / "second" / "render.json"))["roofline"];
  size_t over = 0;
  for (const auto& [pass, rl] : roofline.items()) {
    SCOPED_TRACE(pass);
    const size_t at = r.out.find("roofline " + pass + " ");
    ASSERT_NE(at, std::string::npos) << r.out;
    const std::string line = r.out.substr(at, r.out.find('\n', at) - at);
    const bool isOver = rl["fraction"].is_number() && rl["fraction"].get<double>() > 1;
    over += isOver;
    EXPECT_EQ(isOver, line.find("over 100 %: not this pass's peak") != std::string::npos) << line;
  }
  EXPECT_GT(over, 0u) << r.out;
}

}  // namespace

// End-to-end tests of the command line: they run the built hybridbench (HYBRIDBENCH_BINARY) as a
// child process and check its exit code, stdout and stderr. They hold the CLI to docs/usage.md's
// contract: exit codes 0 ok / 2 bad input / 3 device failure; bad input is ONE stderr line that
// names the thing that is wrong; a failed run loses nothing already in its output directory.
// Each test is fast: scene export/info, devices, and render only at 64x36 on the "plane" scene.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "tool_process.h"

namespace {

using namespace hb::testing;

class Cli : public ToolTest {};

// Standard base64 (RFC 4648), for a glTF buffer in a data URI.
std::string base64(const std::vector<uint8_t>& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string s;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    uint32_t v = uint32_t(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= uint32_t(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) v |= bytes[i + 2];
    s += kAlphabet[(v >> 18) & 63];
    s += kAlphabet[(v >> 12) & 63];
    s += i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=';
    s += i + 2 < bytes.size() ? kAlphabet[v & 63] : '=';
  }
  return s;
}

// A one-triangle glTF whose index buffer holds {0, 1, thirdIndex}; only 3 vertices exist, so
// thirdIndex >= 3 is out of range. Positions: float (0,0,0) (1,0,0) (0,1,0); indices uint16.
std::string triangleGltf(uint16_t thirdIndex) {
  std::vector<uint8_t> bytes;
  auto putFloat = [&](float f) {
    uint8_t b[4];
    std::memcpy(b, &f, 4);  // the test machines are little-endian, as glTF buffers are
    bytes.insert(bytes.end(), b, b + 4);
  };
  for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) putFloat(f);
  for (uint16_t i : {uint16_t(0), uint16_t(1), thirdIndex}) {
    bytes.push_back(uint8_t(i & 0xff));
    bytes.push_back(uint8_t(i >> 8));
  }
  bytes.resize(44, 0);  // pad to a multiple of 4
  nlohmann::json doc = {
      {"asset", {{"version", "2.0"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
      {"buffers", {{{"byteLength", bytes.size()}, {"uri", "data:application/octet-stream;base64," + base64(bytes)}}}},
      {"bufferViews",
       {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 36}},
        {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 6}}}},
      {"accessors",
       {trianglePositionsAccessor(), {{"bufferView", 1}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}}}}};
  return doc.dump(1);
}

const std::vector<std::string> kTinyRender = {"--scene", "plane", "--size", "64x36"};

std::vector<std::string> renderArgs(std::vector<std::string> extra, const fs::path& out) {
  std::vector<std::string> a{"render"};
  a.insert(a.end(), kTinyRender.begin(), kTinyRender.end());
  a.insert(a.end(), extra.begin(), extra.end());
  a.push_back("--out");
  a.push_back(out.string());
  return a;
}

TEST_F(Cli, HelpExitsZeroAndListsTheSubcommands) {
  const RunResult r = run({"--help"});
  EXPECT_EQ(r.exitCode, 0) << r.err;
  for (const char* sub : {"devices", "render", "scene"}) EXPECT_NE(r.out.find(sub), std::string::npos) << sub;
}

TEST_F(Cli, DevicesJsonListsADeviceWithBothRayTracingBackends) {
  const RunResult r = run({"devices", "--json"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out, nullptr, /*allow_exceptions=*/false);
  ASSERT_FALSE(j.is_discarded()) << "stdout is not JSON: " << r.out;
  ASSERT_TRUE(j.contains("devices") && j["devices"].is_array()) << r.out;
  // lavapipe (CI) exposes both ray queries and the ray-tracing pipeline; so do desktop RT GPUs.
  bool found = false;
  for (const auto& d : j["devices"]) found |= d.value("ray_query", false) && d.value("ray_tracing_pipeline", false);
  EXPECT_TRUE(found) << "no device with ray_query and ray_tracing_pipeline: " << r.out;
}

TEST_F(Cli, ExportedAtriumHasSponzaScaleTrianglesAndTenLights) {
  const fs::path gltf = dir / "atrium.gltf";
  const RunResult ex = run({"scene", "export", "atrium", gltf.string()});
  ASSERT_EQ(ex.exitCode, 0) << ex.err;
  ASSERT_TRUE(fs::exists(gltf));
  const RunResult info = run({"scene", "info", gltf.string(), "--json"});
  ASSERT_EQ(info.exitCode, 0) << info.err;
  const nlohmann::json j = nlohmann::json::parse(info.out, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << info.out;
  // atrium.h: ~262k triangles at triangleScale 1 (Sponza: 262,267); the window is Sponza ±25 %.
  const uint64_t triangles = j.value("triangles", uint64_t(0));
  EXPECT_GE(triangles, 200000u);
  EXPECT_LE(triangles, 330000u);
  EXPECT_EQ(j["lights"].value("total", -1), 10);
}

TEST_F(Cli, UnknownSceneNameIsOneLineNamingIt) {
  expectRefused({"scene", "info", "nosuchscene"}, {"nosuchscene", "atrium"});
  expectRefused({"render", "--scene", "nosuchscene", "--size", "64x36", "--out", (dir / "out").string()},
                {"nosuchscene"});
}

TEST_F(Cli, MissingGltfIsOneLineNamingTheFile) {
  const std::string path = (dir / "missing.gltf").string();
  expectRefused({"scene", "info", path}, {path});
}

TEST_F(Cli, MalformedGltfIsOneLineNamingTheFile) {
  const fs::path path = dir / "malformed.gltf";
  writeFile(path, "{ \"asset\": { \"version\": \"2.0\" }, \"meshes\": [ { \n");  // truncated JSON
  expectRefused({"scene", "info", path.string()}, {path.string()});
}

TEST_F(Cli, WellFormedTriangleGltfLoads) {
  // The control for the next test: the same file with an in-range index is accepted.
  const fs::path path = dir / "triangle.gltf";
  writeFile(path, triangleGltf(2));
  const RunResult r = run({"scene", "info", path.string(), "--json"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out).value("triangles", 0), 1);
}

TEST_F(Cli, GltfWithIndexOutOfRangeIsOneLineNamingTheFileAndField) {
  const fs::path path = dir / "bad-index.gltf";
  writeFile(path, triangleGltf(7));
  expectRefused({"scene", "info", path.string()}, {path.string(), "indices", "7"});
}

TEST_F(Cli, UnknownDeviceIndexIsOneLineNamingIt) {
  expectRefused(renderArgs({"--device", "99"}, dir / "out"), {"--device", "99"});
}

TEST_F(Cli, UnknownDeviceNameIsOneLineNamingIt) {
  expectRefused(renderArgs({"--device", "nosuchgpu"}, dir / "out"), {"--device", "nosuchgpu"});
}

TEST_F(Cli, ZeroOrNonNumericSizeIsOneLineNamingIt) {
  const std::string out = (dir / "out").string();
  expectRefused({"render", "--scene", "plane", "--size", "0x5", "--out", out}, {"--size", "0x5"});
  expectRefused({"render", "--scene", "plane", "--size", "abc", "--out", out}, {"--size", "abc"});
}

TEST_F(Cli, InvalidTileSizeIsOneLineNamingTheKeyAndValue) {
  expectRefused(renderArgs({"--set", "tile_size=12"}, dir / "out"), {"tile_size", "12"});
}

TEST_F(Cli, UnknownSetKeyIsOneLineNamingIt) {
  expectRefused(renderArgs({"--set", "nosuchkey=1"}, dir / "out"), {"nosuchkey"});
}

// A results file with a number beyond a double (JSON's out_of_range, not a parse_error) is bad
// input, not an internal error.
TEST_F(Cli, ResultsFileWithANumberBeyondADoubleIsOneLineNamingIt) {
  const fs::path path = dir / "results.json";
  writeFile(path, R"({"schema_version": 1, "runs": [], "x": 1e999})");
  expectRefused({"tables", path.string()}, {path.string(), "1e999"});
}

TEST_F(Cli, ConfigWithUnknownKeyIsOneLineNamingFileAndKey) {
  const fs::path config = dir / "bad-config.json";
  writeFile(config, R"({"name": "bad", "frames": {"warmup": 1, "measured": 1}, "nosuchfield": 3})");
  std::vector<std::string> args{"render", config.string()};
  args.insert(args.end(), kTinyRender.begin(), kTinyRender.end());
  args.insert(args.end(), {"--out", (dir / "out").string()});
  expectRefused(args, {config.string(), "nosuchfield"});
}

TEST_F(Cli, RenderWithoutOutIsOneLineNamingTheFlag) {
  std::vector<std::string> args{"render"};
  args.insert(args.end(), kTinyRender.begin(), kTinyRender.end());
  expectRefused(args, {"--out"});
}

// Disabled until main.cpp fixes it: "--set" is a CLI11 vector option and takes every following
// positional, so "render --set tile_size=16 CONFIG" parses CONFIG as a second --set and fails
// (exit 2, "--set CONFIG: expected key=value"). Fix: ->allow_extra_args(false) on the option.
TEST_F(Cli, SetTakesOneValueSoAConfigMayFollowIt) {
  const fs::path config = dir / "tiny.json";
  writeFile(config, R"({"name": "tiny", "scene": "atrium", "resolution": [64, 36]})");
  const RunResult r =
      run({"render", "--scene", "plane", "--set", "tile_size=16", config.string(), "--out", (dir / "out").string()});
  EXPECT_EQ(r.exitCode, 0) << r.err;
}

// A device that does not finish a submission in HYBRIDBENCH_GPU_TIMEOUT_S stops the run with one
// line and exit 3 instead of waiting forever (a hung GPU); 1 ns is shorter than any submission
// (lavapipe executes on another thread, so the wait returns VK_TIMEOUT before the work is done).
TEST_F(Cli, GpuThatDoesNotFinishInTimeStopsTheRunWithOneLineAndExit3) {
  ::setenv("HYBRIDBENCH_GPU_TIMEOUT_S", "1e-9", 1);
  const RunResult r = run(renderArgs({}, dir / "out"));
  ::setenv("HYBRIDBENCH_GPU_TIMEOUT_S", "soon", 1);
  const RunResult bad = run(renderArgs({}, dir / "out2"));
  ::unsetenv("HYBRIDBENCH_GPU_TIMEOUT_S");
  EXPECT_EQ(r.exitCode, 3) << r.err;
  EXPECT_NE(r.err.find("the GPU did not finish"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("HYBRIDBENCH_GPU_TIMEOUT_S"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(bad.exitCode, 2) << bad.err;
  EXPECT_EQ(bad.err, "hybridbench: HYBRIDBENCH_GPU_TIMEOUT_S=soon: expected a number of seconds > 0, e.g. 60\n");
  EXPECT_FALSE(fs::exists(dir / "out2"));
}

TEST_F(Cli, FailedRenderLosesNothingAlreadyWritten) {
  const fs::path out = dir / "out";
  fs::create_directories(out);
  const std::string earlier = "results of an earlier run\n";
  writeFile(out / "earlier.json", earlier);
  for (const auto& bad : std::vector<std::vector<std::string>>{{"--set", "tile_size=12"}, {"--device", "99"}}) {
    EXPECT_EQ(run(renderArgs(bad, out)).exitCode, 2);
    ASSERT_TRUE(fs::exists(out / "earlier.json")) << bad[0];
    EXPECT_EQ(readFile(out / "earlier.json"), earlier) << bad[0];
  }
}

TEST_F(Cli, TinyRenderWritesItsReportAndKeepsOtherFiles) {
  const fs::path out = dir / "out";
  fs::create_directories(out);
  writeFile(out / "earlier.json", "keep\n");
  const RunResult r = run(renderArgs({}, out));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(readFile(out / "earlier.json"), "keep\n");
  for (const char* f : {"render.json", "depth.png", "color.png"}) EXPECT_TRUE(fs::exists(out / f)) << f;
  const nlohmann::json j = nlohmann::json::parse(readFile(out / "render.json"), nullptr, false);
  ASSERT_FALSE(j.is_discarded());
  EXPECT_TRUE(j.contains("passes_run"));
  EXPECT_TRUE(j["timing_ms"].contains("frame"));
  EXPECT_EQ(j["params"]["resolution"], nlohmann::json::array({64, 36}));
}

}  // namespace

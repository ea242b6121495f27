// Ray files (ray_file.h): what is written reads back byte for byte, and every way a file can be
// wrong is one line naming the file and what to do.
#include "reference/ray_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>

#include "base/errors.h"

namespace hb {
namespace {

namespace fs = std::filesystem;

struct RayFileDir : ::testing::Test {
  fs::path dir = fs::temp_directory_path() / ("hb-ray-file-" + std::to_string(::getpid()));
  std::string bin = (dir / "rays.bin").string();
  void SetUp() override {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }

  static RayFileInfo info(size_t count) {
    RayFileInfo i;
    i.count = count;
    i.kind = "test";
    i.sceneName = "plane";
    i.sceneSha256 = "ab12";
    i.grid = {2, uint32_t((count + 1) / 2)};
    return i;
  }
  static std::vector<RayRecord> rays(size_t count) {
    std::vector<RayRecord> r(count);
    for (size_t k = 0; k < count; ++k) r[k] = {{float(k), 1.5f, -2.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, 100.0f + float(k)};
    return r;
  }
  // The one-line error reading the file gives.
  std::string errorOfRead() {
    try {
      readRayFile(bin);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  void editJson(const std::function<void(nlohmann::json&)>& edit) {
    nlohmann::json j = nlohmann::json::parse(std::ifstream(rayFileJsonPath(bin)));
    edit(j);
    std::ofstream(rayFileJsonPath(bin)) << j.dump();
  }
};

TEST_F(RayFileDir, WhatIsWrittenReadsBackByteForByte) {
  writeRayFile(bin, info(5), rays(5));
  EXPECT_EQ(fs::file_size(bin), 5u * 32u);
  const RayFile f = readRayFile(bin);
  ASSERT_EQ(f.rays.size(), 5u);
  EXPECT_EQ(std::memcmp(f.rays.data(), rays(5).data(), 5 * sizeof(RayRecord)), 0);
  EXPECT_EQ(f.info.count, 5u);
  EXPECT_EQ(f.info.query, "closest");
  EXPECT_EQ(f.info.sceneSha256, "ab12");
  EXPECT_EQ(f.info.grid, (std::array<uint32_t, 2>{2, 3}));
  // The record is little-endian float32s in the documented order: origin, tmin, direction, tmax.
  std::ifstream in(bin, std::ios::binary);
  float words[8];
  in.seekg(32);
  in.read(reinterpret_cast<char*>(words), sizeof words);
  EXPECT_EQ(std::vector<float>(words, words + 8), (std::vector<float>{1, 1.5f, -2, 0, 0, 0, -1, 101}));
}

TEST_F(RayFileDir, EveryBadFileIsOneLineNamingIt) {
  writeRayFile(bin, info(4), rays(4));
  const auto expectError = [&](const std::string& part) {
    const std::string e = errorOfRead();
    EXPECT_NE(e.find(part), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    EXPECT_NE(e.find(dir.string()), std::string::npos) << e;
  };
  editJson([](nlohmann::json& j) { j["version"] = 2; });
  expectError("ray file version 2, this build reads version 1");
  editJson([](nlohmann::json& j) {
    j["version"] = 1;
    j["query"] = "first";
  });
  expectError("query \"first\" is not closest or any");
  editJson([](nlohmann::json& j) {
    j["query"] = "any";
    j["grid"] = {1, 3};
  });
  expectError("holds fewer than its 4 rays");
  editJson([](nlohmann::json& j) {
    j["grid"] = {2, 3};
    j["count"] = 5;
  });
  expectError("128 bytes, but");
  editJson([](nlohmann::json& j) { j["count"] = 4; });
  EXPECT_EQ(errorOfRead(), "");  // back to a good file: the checks above each found their fault
  std::vector<RayRecord> bad = rays(4);
  bad[2].dir[1] = std::nanf("");
  writeRayFile(bin, info(4), bad);
  expectError("ray 2 has a non-finite origin or direction");
  bad = rays(4);
  bad[3].tMin = 1000.0f;
  writeRayFile(bin, info(4), bad);
  expectError("ray 3 has");
  fs::remove(rayFileJsonPath(bin));
  expectError("no such file; a ray file is NAME.bin with NAME.json beside it");
}

}  // namespace
}  // namespace hb

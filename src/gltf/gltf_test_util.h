// Helpers shared by the glTF tests (gltf_io_test.cpp, gltf_accessors_test.cpp,
// gltf_export_test.cpp): per-test temporary directories, a builder for hand-written (also
// malformed) glTF files, and the check that loadGltf fails with a one-line InputError.
#pragma once
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "base/errors.h"
#include "gltf/gltf_io.h"

namespace hb::gltf_test {

namespace fs = std::filesystem;
using nlohmann::json;

inline constexpr int kFloat = 5126, kU8 = 5121, kU16 = 5123, kU32 = 5125;

// A fresh directory per test, removed when the test ends: tests may run in parallel (ctest -j)
// and must not share files.
struct TestDir {
  fs::path path;
  TestDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path = fs::temp_directory_path() /
           ("hb_gltf_io_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" + std::to_string(getpid()));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TestDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  fs::path operator/(const std::string& name) const { return path / name; }
};

// Builds a glTF document and its one binary buffer by hand, so that tests can write exactly the
// (also malformed) files they need.
struct GltfBuilder {
  json doc = {{"asset", {{"version", "2.0"}}}};
  std::vector<uint8_t> bin;

  template <typename T>
  int view(const std::vector<T>& data) {
    while (bin.size() % 4) bin.push_back(0);
    size_t offset = bin.size();
    bin.resize(offset + data.size() * sizeof(T));
    std::memcpy(bin.data() + offset, data.data(), data.size() * sizeof(T));
    doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", data.size() * sizeof(T)}});
    return static_cast<int>(doc["bufferViews"].size() - 1);
  }
  int accessor(int view, int componentType, const char* type, size_t count) {
    doc["accessors"].push_back(
        {{"bufferView", view}, {"componentType", componentType}, {"type", type}, {"count", count}});
    return static_cast<int>(doc["accessors"].size() - 1);
  }
  int floats(const std::vector<float>& v, const char* type, int components) {
    return accessor(view(v), kFloat, type, v.size() / static_cast<size_t>(components));
  }
  // A unit quad in the z = 0 plane facing +z, indices as u16, with normals and texcoords unless
  // told otherwise. Returns the mesh index.
  int quad(bool withNormals = true, int material = -1) {
    json prim = {{"attributes", {{"POSITION", floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, "VEC3", 3)}}}};
    if (withNormals) prim["attributes"]["NORMAL"] = floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3", 3);
    prim["attributes"]["TEXCOORD_0"] = floats({0, 0, 1, 0, 1, 1, 0, 1}, "VEC2", 2);
    prim["indices"] = accessor(view(std::vector<uint16_t>{0, 1, 2, 0, 2, 3}), kU16, "SCALAR", 6);
    if (material >= 0) prim["material"] = material;
    doc["meshes"].push_back({{"name", "quad"}, {"primitives", json::array({prim})}});
    return static_cast<int>(doc["meshes"].size() - 1);
  }
  int node(json n) {
    doc["nodes"].push_back(std::move(n));
    return static_cast<int>(doc["nodes"].size() - 1);
  }
  int light(json l) {
    json& lights = doc["extensions"]["KHR_lights_punctual"]["lights"];
    lights.push_back(std::move(l));
    doc["extensionsUsed"] = {"KHR_lights_punctual"};
    return static_cast<int>(lights.size() - 1);
  }
  void scene(std::vector<int> roots) {
    doc["scenes"] = json::array({{{"nodes", roots}}});
    doc["scene"] = 0;
  }

  // .gltf with the buffer in a .bin beside it.
  fs::path writeGltf(const fs::path& path) {
    json d = doc;
    if (!bin.empty()) {
      fs::path binPath = path;
      binPath.replace_extension(".bin");
      std::ofstream(binPath, std::ios::binary)
          .write(reinterpret_cast<const char*>(bin.data()), static_cast<std::streamsize>(bin.size()));
      d["buffers"] = json::array({{{"uri", binPath.filename().string()}, {"byteLength", bin.size()}}});
    }
    std::ofstream(path) << d.dump(1);
    return path;
  }
  // .glb: 12-byte header, JSON chunk padded with spaces, BIN chunk padded with zeros (glTF 2.0
  // §4.4).
  fs::path writeGlb(const fs::path& path) {
    json d = doc;
    d["buffers"] = json::array({{{"byteLength", bin.size()}}});
    std::string text = d.dump();
    while (text.size() % 4) text += ' ';
    std::vector<uint8_t> body = bin;
    while (body.size() % 4) body.push_back(0);
    auto u32 = [](std::ofstream& out, uint32_t v) { out.write(reinterpret_cast<const char*>(&v), 4); };
    std::ofstream out(path, std::ios::binary);
    out.write("glTF", 4);
    u32(out, 2);
    u32(out, static_cast<uint32_t>(12 + 8 + text.size() + 8 + body.size()));
    u32(out, static_cast<uint32_t>(text.size()));
    u32(out, 0x4E4F534Au);  // "JSON"
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    u32(out, static_cast<uint32_t>(body.size()));
    u32(out, 0x004E4942u);  // "BIN\0"
    out.write(reinterpret_cast<const char*>(body.data()), static_cast<std::streamsize>(body.size()));
    return path;
  }
};

// The quad at the origin and a point light one node away: the file most tests start from.
inline GltfBuilder quadWithLight(json light) {
  GltfBuilder b;
  b.doc["materials"] = {{{"name", "red"},
                         {"pbrMetallicRoughness",
                          {{"baseColorFactor", {1, 0, 0, 1}}, {"metallicFactor", 0.25}, {"roughnessFactor", 0.5}}},
                         {"doubleSided", true}}};
  int mesh = b.quad(true, 0);
  int l = b.light(std::move(light));
  b.scene({b.node({{"mesh", mesh}}),
           b.node({{"translation", {1, 2, 3}}, {"extensions", {{"KHR_lights_punctual", {{"light", l}}}}}})});
  return b;
}

// Expects loadGltf(path) to throw an InputError whose one-line message names the file and
// contains every string in `parts`.
inline void expectInputError(const fs::path& path, std::vector<std::string> parts) {
  try {
    loadGltf(path.string());
    ADD_FAILURE() << "no InputError for " << path;
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    for (const std::string& part : parts)
      EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
  }
}

// A one-quad scene (GltfBuilder::quad, one node) broken by `edit` before it is written to `file`
// in `dir`: loading it must fail as expectInputError says.
template <class Dir, class Edit>
void expectBrokenQuad(const Dir& dir, const char* file, Edit edit, std::vector<std::string> parts) {
  GltfBuilder b;
  b.quad();
  edit(b.doc);
  b.scene({b.node({{"mesh", 0}})});
  expectInputError(b.writeGltf(dir / file), std::move(parts));
}

}  // namespace hb::gltf_test

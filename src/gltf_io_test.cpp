#include "gltf_io.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>

#include "errors.h"
#include "sha256.h"

namespace hb {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kFloat = 5126, kU8 = 5121, kU16 = 5123, kU32 = 5125;

// A fresh directory per test, removed when the test ends: tests may run in parallel (ctest -j)
// and must not share files.
struct TestDir {
  fs::path path;
  TestDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path = fs::temp_directory_path() / ("hb_gltf_io_" + std::string(info->test_suite_name()) + "_" +
                                        info->name() + "_" + std::to_string(getpid()));
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
    doc["bufferViews"].push_back(
        {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", data.size() * sizeof(T)}});
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
    json prim = {
        {"attributes", {{"POSITION", floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, "VEC3", 3)}}}};
    if (withNormals)
      prim["attributes"]["NORMAL"] = floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3", 3);
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
          .write(reinterpret_cast<const char*>(bin.data()),
                 static_cast<std::streamsize>(bin.size()));
      d["buffers"] =
          json::array({{{"uri", binPath.filename().string()}, {"byteLength", bin.size()}}});
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
    auto u32 = [](std::ofstream& out, uint32_t v) {
      out.write(reinterpret_cast<const char*>(&v), 4);
    };
    std::ofstream out(path, std::ios::binary);
    out.write("glTF", 4);
    u32(out, 2);
    u32(out, static_cast<uint32_t>(12 + 8 + text.size() + 8 + body.size()));
    u32(out, static_cast<uint32_t>(text.size()));
    u32(out, 0x4E4F534Au);  // "JSON"
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    u32(out, static_cast<uint32_t>(body.size()));
    u32(out, 0x004E4942u);  // "BIN\0"
    out.write(reinterpret_cast<const char*>(body.data()),
              static_cast<std::streamsize>(body.size()));
    return path;
  }
};

// The quad at the origin and a point light one node away: the file most tests start from.
GltfBuilder quadWithLight(json light) {
  GltfBuilder b;
  b.doc["materials"] = {
      {{"name", "red"},
       {"pbrMetallicRoughness",
        {{"baseColorFactor", {1, 0, 0, 1}}, {"metallicFactor", 0.25}, {"roughnessFactor", 0.5}}},
       {"doubleSided", true}}};
  int mesh = b.quad(true, 0);
  int l = b.light(std::move(light));
  b.scene({b.node({{"mesh", mesh}}),
           b.node({{"translation", {1, 2, 3}},
                   {"extensions", {{"KHR_lights_punctual", {{"light", l}}}}}})});
  return b;
}

// Expects loadGltf(path) to throw an InputError whose one-line message names the file and
// contains every string in `parts`.
void expectInputError(const fs::path& path, std::vector<std::string> parts) {
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

TEST(GltfLoad, ReadsAQuadWithAPointLight) {
  TestDir dir;
  GltfBuilder b = quadWithLight(
      {{"type", "point"}, {"intensity", 20}, {"range", 5}, {"color", {1, 0.5, 0.25}}});
  Scene s = loadGltf(b.writeGltf(dir / "quad.gltf").string());
  ASSERT_EQ(s.vertices.size(), 4u);
  EXPECT_EQ(s.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(s.vertices[2].position, glm::vec3(1, 1, 0));
  EXPECT_EQ(s.vertices[2].normal, glm::vec3(0, 0, 1));
  EXPECT_EQ(s.vertices[2].uv, glm::vec2(1, 1));
  ASSERT_EQ(s.meshes.size(), 1u);
  ASSERT_EQ(s.meshes[0].primitives.size(), 1u);
  EXPECT_EQ(s.meshes[0].primitives[0].indexCount, 6u);
  ASSERT_EQ(s.instances.size(), 1u);
  EXPECT_EQ(s.instances[0].transform, glm::mat4(1.0f));
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].baseColorFactor, glm::vec4(1, 0, 0, 1));
  EXPECT_EQ(s.materials[0].metallicFactor, 0.25f);
  EXPECT_EQ(s.materials[0].roughnessFactor, 0.5f);
  EXPECT_TRUE(s.materials[0].doubleSided);
  ASSERT_EQ(s.lights.size(), 1u);
  const Light& l = s.lights[0];
  EXPECT_EQ(l.type, LightType::Point);
  EXPECT_EQ(l.position, glm::vec3(1, 2, 3));
  EXPECT_EQ(l.direction, glm::vec3(0, 0, -1));
  EXPECT_EQ(l.color, glm::vec3(1, 0.5f, 0.25f));
  EXPECT_EQ(l.intensity, 20.0f);
  EXPECT_EQ(l.range, 5.0f);
  EXPECT_FALSE(l.rangeFromEq41);
  EXPECT_TRUE(l.castShadows);
  EXPECT_EQ(s.triangleCount(), 2u);
}

TEST(GltfLoad, LightWithoutRangeGetsThesisEq41) {
  TestDir dir;
  GltfBuilder b = quadWithLight({{"type", "spot"},
                                 {"intensity", 100},
                                 {"spot", {{"innerConeAngle", 0.1}, {"outerConeAngle", 0.5}}},
                                 {"extras", {{"castShadows", false}}}});
  Scene s = loadGltf(b.writeGltf(dir / "spot.gltf").string());
  ASSERT_EQ(s.lights.size(), 1u);
  // Eq. 4.1: D = 50 sqrt(0.02 I) = sqrt(50 I) = sqrt(5000) for I = 100.
  EXPECT_EQ(s.lights[0].range, static_cast<float>(std::sqrt(5000.0)));
  EXPECT_TRUE(s.lights[0].rangeFromEq41);
  EXPECT_GT(s.lights[0].range, 0.0f);
  EXPECT_FALSE(s.lights[0].castShadows);
  EXPECT_EQ(s.lights[0].innerConeAngle, 0.1f);
  EXPECT_EQ(s.lights[0].outerConeAngle, 0.5f);
}

TEST(GltfLoad, DirectionalLightHasRangeZeroAndPointsAlongNodeMinusZ) {
  TestDir dir;
  GltfBuilder b;
  int l = b.light({{"type", "directional"}, {"intensity", 3}});
  // Rotation of -90 degrees about X (quaternion x = -sin 45°, w = cos 45°) turns -Z into -Y.
  const double h = std::sqrt(0.5);
  b.scene({b.node(
      {{"rotation", {-h, 0, 0, h}}, {"extensions", {{"KHR_lights_punctual", {{"light", l}}}}}})});
  Scene s = loadGltf(b.writeGltf(dir / "sun.gltf").string());
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].type, LightType::Directional);
  EXPECT_EQ(s.lights[0].range, 0.0f);
  EXPECT_FALSE(s.lights[0].rangeFromEq41);
  // The quaternion components are sqrt(1/2) rounded to double; R's entries 1 - 2x^2 and 2xw are
  // off by a few double ulps (< 1e-15), far inside float rounding: 2^-24 per component.
  EXPECT_NEAR(s.lights[0].direction.x, 0.0f, 0x1p-24f);
  EXPECT_NEAR(s.lights[0].direction.y, -1.0f, 0x1p-24f);
  EXPECT_NEAR(s.lights[0].direction.z, 0.0f, 0x1p-24f);
}

TEST(GltfLoad, ComposesTrsAndMatrixNodeTransforms) {
  TestDir dir;
  GltfBuilder b;
  int mesh = b.quad();
  // Parent: T(10,0,0) * R(90° about Y) * S(2); child: a matrix translating by (0,0,1).
  const double h = std::sqrt(0.5);
  int child =
      b.node({{"mesh", mesh}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1}}});
  int parent = b.node({{"translation", {10, 0, 0}},
                       {"rotation", {0, h, 0, h}},
                       {"scale", {2, 2, 2}},
                       {"children", {child}}});
  b.scene({parent});
  Scene s = loadGltf(b.writeGltf(dir / "tree.gltf").string());
  ASSERT_EQ(s.instances.size(), 1u);
  // Child (1,0,0) -> translate (1,0,1) -> scale (2,0,2) -> rotate about Y by 90° (x' = z,
  // z' = -x) (2,0,-2) -> translate (12,0,-2). Error: the composed matrix is computed in double
  // (~1e-15) and rounded to float (2^-24 relative per entry); the float product M·p adds at most
  // 4 roundings of terms bounded by sum|M_ij p_j| <= 2 + 2 + 10 + 1 = 15, so |err| <= 5·2^-24·15.
  const float tol = 5.0f * 0x1p-24f * 15.0f;
  glm::vec4 p = s.instances[0].transform * glm::vec4(1, 0, 0, 1);
  EXPECT_NEAR(p.x, 12.0f, tol);
  EXPECT_NEAR(p.y, 0.0f, tol);
  EXPECT_NEAR(p.z, -2.0f, tol);
  EXPECT_NEAR(p.w, 1.0f, tol);
}

TEST(GltfLoad, WithoutScenesLoadsEveryRootNode) {
  TestDir dir;
  GltfBuilder b;
  int mesh = b.quad();
  int child = b.node({{"mesh", mesh}, {"translation", {0, 5, 0}}});
  b.node({{"mesh", mesh}, {"children", {child}}});
  b.node({{"mesh", mesh}, {"translation", {7, 0, 0}}});
  Scene s = loadGltf(b.writeGltf(dir / "noscene.gltf").string());
  ASSERT_EQ(s.instances.size(), 3u);  // two roots and the child, not the child twice
  EXPECT_EQ(s.triangleCount(), 6u);
}

TEST(GltfLoad, ComputesNormalsAndSequentialIndicesWhenMissing) {
  TestDir dir;
  GltfBuilder b;
  // Two triangles of a quad facing +z, no NORMAL and no indices.
  json prim = {{"attributes",
                {{"POSITION",
                  b.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0, 1, 1, 0, 0, 1, 0}, "VEC3", 3)}}}};
  b.doc["meshes"] = json::array({{{"primitives", json::array({prim})}}});
  b.scene({b.node({{"mesh", 0}})});
  Scene s = loadGltf(b.writeGltf(dir / "bare.gltf").string());
  EXPECT_EQ(s.indices, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5}));
  for (const Vertex& v : s.vertices) EXPECT_EQ(v.normal, glm::vec3(0, 0, 1));
  for (const Vertex& v : s.vertices) EXPECT_EQ(v.uv, glm::vec2(0, 0));
  ASSERT_EQ(s.materials.size(), 1u);  // the "default" material the primitive falls back to
  EXPECT_EQ(s.meshes[0].primitives[0].material, 0u);
}

TEST(GltfLoad, ReadsU8AndU32Indices) {
  TestDir dir;
  GltfBuilder b;
  int pos = b.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, "VEC3", 3);
  int i8 = b.accessor(b.view(std::vector<uint8_t>{0, 1, 2}), kU8, "SCALAR", 3);
  int i32 = b.accessor(b.view(std::vector<uint32_t>{0, 2, 3}), kU32, "SCALAR", 3);
  b.doc["meshes"] = json::array({{{"primitives",
                                   {{{"attributes", {{"POSITION", pos}}}, {"indices", i8}},
                                    {{"attributes", {{"POSITION", pos}}}, {"indices", i32}}}}}});
  b.scene({b.node({{"mesh", 0}})});
  Scene s = loadGltf(b.writeGltf(dir / "idx.gltf").string());
  EXPECT_EQ(s.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(s.meshes[0].primitives[1].vertexOffset, 4u);
}

TEST(GltfLoad, GlbGivesTheSameSceneAsGltf) {
  TestDir dir;
  GltfBuilder b = quadWithLight({{"type", "point"}, {"intensity", 8}});
  Scene a = loadGltf(b.writeGltf(dir / "quad.gltf").string());
  Scene g = loadGltf(b.writeGlb(dir / "quad.glb").string());
  EXPECT_EQ(sceneSha256(a), sceneSha256(g));
  EXPECT_EQ(g.vertices.size(), 4u);
  EXPECT_EQ(g.lights.size(), 1u);
}

TEST(GltfLoad, SkipsNonTriangleModesAndCountsThem) {
  TestDir dir;
  GltfBuilder b;
  b.quad();
  json lines = b.doc["meshes"][0]["primitives"][0];
  lines["mode"] = 1;  // LINES
  b.doc["meshes"][0]["primitives"].push_back(lines);
  b.scene({b.node({{"mesh", 0}})});
  GltfLoadWarnings warnings;
  Scene s = loadGltf(b.writeGltf(dir / "lines.gltf").string(), &warnings);
  EXPECT_EQ(warnings.skippedPrimitives, 1u);
  ASSERT_EQ(warnings.messages.size(), 1u);
  EXPECT_NE(warnings.messages[0].find("meshes[0].primitives[1]"), std::string::npos);
  EXPECT_EQ(s.meshes[0].primitives.size(), 1u);
}

TEST(GltfLoad, ReadsAPerspectiveCameraAsTheInverseOfItsNode) {
  TestDir dir;
  GltfBuilder b;
  b.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.05}}}}};
  b.scene({b.node({{"camera", 0}, {"translation", {0, 1, 4}}})});
  Scene s = loadGltf(b.writeGltf(dir / "cam.gltf").string());
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_EQ(s.cameras[0].yfov, 0.8f);
  EXPECT_EQ(s.cameras[0].znear, 0.05f);
  EXPECT_EQ(s.cameras[0].zfar, 1000.0f);  // missing zfar
  // Inverting a pure translation in double is exact: -t.
  EXPECT_EQ(s.cameras[0].view * glm::vec4(0, 1, 4, 1), glm::vec4(0, 0, 0, 1));
}

// ---- bad input
// -----------------------------------------------------------------------------------

TEST(GltfLoadErrors, MissingFileNamesThePath) {
  TestDir dir;
  expectInputError(dir / "nope.gltf", {"not found"});
}

TEST(GltfLoadErrors, MalformedJsonIsAnInputError) {
  TestDir dir;
  std::ofstream(dir / "bad.gltf") << "{ \"asset\": { \"version\": \"2.0\" }, ";
  expectInputError(dir / "bad.gltf", {"glTF"});
}

TEST(GltfLoadErrors, JsonThatIsNotGltfIsAnInputError) {
  TestDir dir;
  std::ofstream(dir / "other.gltf") << "{\"hello\": [1, 2, 3]}";
  expectInputError(dir / "other.gltf", {"glTF"});
  std::ofstream(dir / "old.gltf") << "{\"asset\": {\"version\": \"1.0\"}}";
  expectInputError(dir / "old.gltf", {"asset.version"});
}

TEST(GltfLoadErrors, AccessorPastItsBufferViewNamesTheAttribute) {
  TestDir dir;
  GltfBuilder b;
  b.quad();
  b.doc["accessors"][0]["count"] = 5;  // POSITION: 5 * 12 bytes > the 48-byte bufferView
  b.scene({b.node({{"mesh", 0}})});
  expectInputError(b.writeGltf(dir / "short.gltf"),
                   {"meshes[0].primitives[0].attributes.POSITION", "accessors[0]", "60"});
}

TEST(GltfLoadErrors, AccessorByteOffsetPastItsBufferViewNamesTheIndices) {
  TestDir dir;
  GltfBuilder b;
  b.quad();
  b.doc["accessors"][3]["byteOffset"] = 2;  // indices: 2 + 6 * 2 = 14 > 12 bytes
  b.scene({b.node({{"mesh", 0}})});
  expectInputError(b.writeGltf(dir / "offset.gltf"), {"meshes[0].primitives[0].indices"});
}

TEST(GltfLoadErrors, StridedAccessorPastItsBufferViewIsCaught) {
  TestDir dir;
  GltfBuilder b;
  b.quad();
  b.doc["bufferViews"][0]["byteStride"] = 16;  // 16 * 3 + 12 = 60 > 48
  b.scene({b.node({{"mesh", 0}})});
  expectInputError(b.writeGltf(dir / "stride.gltf"), {"attributes.POSITION", "stride 16"});
}

TEST(GltfLoadErrors, BufferViewPastItsBufferIsCaught) {
  TestDir dir;
  GltfBuilder b;
  b.quad();
  b.doc["bufferViews"][0]["byteLength"] = 4096;  // the whole buffer is far shorter
  b.doc["accessors"][0]["count"] = 300;
  b.scene({b.node({{"mesh", 0}})});
  expectInputError(b.writeGltf(dir / "view.gltf"), {"bufferViews[0]"});
}

TEST(GltfLoadErrors, IndexPastTheVertexCountNamesTheIndices) {
  TestDir dir;
  GltfBuilder b;
  int pos = b.floats({0, 0, 0, 1, 0, 0, 1, 1, 0}, "VEC3", 3);
  int idx = b.accessor(b.view(std::vector<uint16_t>{0, 1, 7}), kU16, "SCALAR", 3);
  b.doc["meshes"] =
      json::array({{{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"indices", idx}}}}}});
  b.scene({b.node({{"mesh", 0}})});
  expectInputError(b.writeGltf(dir / "index.gltf"),
                   {"meshes[0].primitives[0].indices", "7", "3 vertices"});
}

TEST(GltfLoadErrors, NonFinitePositionsNameThePositionAttribute) {
  TestDir dir;
  for (float bad : {std::nanf(""), INFINITY}) {
    GltfBuilder b;
    b.floats({0, 0, 0, 1, 0, 0, 1, bad, 0}, "VEC3", 3);
    b.doc["meshes"] = json::array({{{"primitives", {{{"attributes", {{"POSITION", 0}}}}}}}});
    b.scene({b.node({{"mesh", 0}})});
    expectInputError(b.writeGltf(dir / "nan.gltf"),
                     {"meshes[0].primitives[0].attributes.POSITION", "vertex 2", "not finite"});
  }
}

TEST(GltfLoadErrors, ZeroOrNegativeLightRangeNamesTheLight) {
  TestDir dir;
  for (double range : {0.0, -2.0}) {
    GltfBuilder b = quadWithLight({{"type", "point"}, {"intensity", 5}, {"range", range}});
    expectInputError(b.writeGltf(dir / "range.gltf"),
                     {"KHR_lights_punctual.lights[0].range", "> 0"});
  }
}

TEST(GltfLoadErrors, UnsupportedComponentTypeNamesTheAccessor) {
  TestDir dir;
  GltfBuilder b;
  b.quad();
  b.doc["accessors"][3]["componentType"] = kFloat;  // float indices
  b.doc["accessors"][3]["count"] = 3;
  b.scene({b.node({{"mesh", 0}})});
  expectInputError(b.writeGltf(dir / "floatidx.gltf"),
                   {"meshes[0].primitives[0].indices", "componentType 5126"});

  GltfBuilder c;
  c.quad();
  c.doc["accessors"][0]["componentType"] = kU16;  // quantized positions (KHR_mesh_quantization)
  c.scene({c.node({{"mesh", 0}})});
  expectInputError(c.writeGltf(dir / "u16pos.gltf"),
                   {"attributes.POSITION", "componentType 5123", "FLOAT"});
}

TEST(GltfLoadErrors, NodeCycleIsAnInputErrorNotAStackOverflow) {
  TestDir dir;
  GltfBuilder b;
  b.quad();
  b.node({{"mesh", 0}, {"children", {1}}});
  b.node({{"children", {0}}});
  b.scene({0});
  expectInputError(b.writeGltf(dir / "cycle.gltf"), {"children", "cycle"});
}

TEST(GltfLoadErrors, OutOfRangeReferencesNameTheirField) {
  TestDir dir;
  GltfBuilder b;
  b.quad(true, 3);  // material 3 of none
  b.scene({b.node({{"mesh", 0}})});
  expectInputError(b.writeGltf(dir / "mat.gltf"), {"meshes[0].primitives[0].material", "index 3"});

  GltfBuilder c;
  c.quad();
  c.scene({c.node({{"mesh", 4}})});
  expectInputError(c.writeGltf(dir / "mesh.gltf"), {"nodes[0].mesh"});
}

TEST(GltfLoadErrors, ImageBufferViewPastItsBufferIsCaughtBeforeDecoding) {
  TestDir dir;
  GltfBuilder b;
  b.quad(true, 0);
  int view = b.view(std::vector<uint8_t>(16, 0x89));
  b.doc["bufferViews"][view]["byteLength"] = 1 << 20;  // 1 MiB of a ~200-byte buffer
  b.doc["images"] = {{{"bufferView", view}, {"mimeType", "image/png"}}};
  b.doc["textures"] = {{{"source", 0}}};
  b.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  b.scene({b.node({{"mesh", 0}})});
  expectInputError(b.writeGltf(dir / "image.gltf"), {"images[0].bufferView"});
}

TEST(GltfLoadErrors, TruncatedGlbIsAnInputError) {
  TestDir dir;
  GltfBuilder b = quadWithLight({{"type", "point"}, {"intensity", 8}});
  fs::path glb = b.writeGlb(dir / "quad.glb");
  fs::resize_file(glb, fs::file_size(glb) - 40);
  expectInputError(glb, {"glb"});
}

TEST(GltfLoadErrors, MissingImageFileNamesTheImage) {
  TestDir dir;
  GltfBuilder b;
  b.quad(true, 0);
  b.doc["images"] = {{{"uri", "gone.png"}}};
  b.doc["textures"] = {{{"source", 0}}};
  b.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  b.scene({b.node({{"mesh", 0}})});
  expectInputError(b.writeGltf(dir / "noimage.gltf"), {"gone.png"});
}

// ---- export ------------------------------------------------------------------------------------

// Two meshes (one with two primitives), three instances, two textures, three materials, a spot,
// a point light with an eq. 4.1 range, a directional light without shadows and a look-at camera,
// laid out mesh by mesh as loadGltf lays scenes out.
Scene handBuiltScene() {
  Scene s;
  s.name = "handbuilt";
  auto addQuad = [&](float z, uint32_t material) {
    Primitive p;
    p.firstIndex = static_cast<uint32_t>(s.indices.size());
    p.vertexOffset = static_cast<uint32_t>(s.vertices.size());
    p.vertexCount = 4;
    p.indexCount = 6;
    p.material = material;
    const glm::vec3 n =
        glm::normalize(glm::vec3(0.1f, 0.2f, 1.0f));  // deliberately not axis-aligned
    for (int i = 0; i < 4; ++i)
      s.vertices.push_back(
          {glm::vec3(0.3f * (i & 1), 0.7f * (i >> 1), z), n, glm::vec2(0.1f * i, 1.0f / 3.0f * i)});
    for (uint32_t i : {0u, 1u, 3u, 0u, 3u, 2u}) s.indices.push_back(i);
    return p;
  };
  s.meshes.push_back({"two-prims", {addQuad(0.0f, 0), addQuad(0.5f, 1)}});
  s.meshes.push_back({"one-prim", {addQuad(-1.25f, 2)}});
  s.instances.push_back({0, glm::mat4(1.0f)});
  s.instances.push_back({1, glm::translate(glm::mat4(1.0f), glm::vec3(3.1f, -2.0f, 0.7f))});
  s.instances.push_back({1, glm::rotate(glm::mat4(1.0f), 0.3f, glm::vec3(0, 1, 0)) *
                                glm::scale(glm::mat4(1.0f), glm::vec3(1.5f))});

  Texture tex;
  tex.name = "checker";
  tex.width = 4;
  tex.height = 3;
  tex.srgb = true;
  for (uint32_t i = 0; i < 12; ++i)
    tex.rgba.insert(tex.rgba.end(),
                    {uint8_t(i * 20), uint8_t(255 - i * 7), uint8_t(i * i), uint8_t(200 + i)});
  s.textures.push_back(tex);
  Texture mr = tex;
  mr.name = "metal-rough";
  mr.srgb = false;
  mr.width = 3;
  mr.height = 4;
  s.textures.push_back(mr);

  Material a;
  a.name = "textured";
  a.baseColorFactor = glm::vec4(0.9f, 0.8f, 0.7f, 1.0f);
  a.metallicFactor = 0.1f;
  a.roughnessFactor = 0.65f;
  a.baseColorTexture = 0;
  a.metallicRoughnessTexture = 1;
  Material b;
  b.name = "plain";
  b.baseColorFactor = glm::vec4(0.2f, 0.3f, 1.0f / 3.0f, 0.5f);
  b.doubleSided = true;
  Material c;
  c.name = "defaults";
  s.materials = {a, b, c};

  Light spot;
  spot.name = "spot";
  spot.type = LightType::Spot;
  spot.position = glm::vec3(1.5f, 4.25f, -0.3f);
  spot.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
  spot.color = glm::vec3(1.0f, 0.9f, 0.7f);
  spot.intensity = 40.0f;
  spot.range = 12.5f;
  spot.innerConeAngle = 0.2f;
  spot.outerConeAngle = 0.6f;
  Light point;
  point.name = "point";
  point.position = glm::vec3(-2.0f, 1.0f, 0.1f);
  point.intensity = 7.0f;
  point.range = static_cast<float>(rangeFromIntensity(7.0));
  point.rangeFromEq41 = true;
  Light sun;
  sun.name = "sun";
  sun.type = LightType::Directional;
  sun.direction = glm::normalize(glm::vec3(-0.2f, -1.0f, -0.1f));
  sun.intensity = 2.0f;
  sun.range = 0.0f;
  sun.castShadows = false;
  s.lights = {spot, point, sun};

  Camera cam;
  cam.name = "main";
  cam.view =
      glm::lookAt(glm::vec3(6.0f, 2.5f, 7.0f), glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(0, 1, 0));
  cam.yfov = 0.9f;
  cam.znear = 0.05f;
  cam.zfar = 250.0f;
  s.cameras = {cam};
  return s;
}

void expectSameScene(const Scene& a, const Scene& b) {
  EXPECT_EQ(a.name, b.name);
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  EXPECT_EQ(0,
            std::memcmp(a.vertices.data(), b.vertices.data(), a.vertices.size() * sizeof(Vertex)));
  EXPECT_EQ(a.indices, b.indices);
  ASSERT_EQ(a.meshes.size(), b.meshes.size());
  for (size_t m = 0; m < a.meshes.size(); ++m) {
    EXPECT_EQ(a.meshes[m].name, b.meshes[m].name);
    ASSERT_EQ(a.meshes[m].primitives.size(), b.meshes[m].primitives.size());
    for (size_t p = 0; p < a.meshes[m].primitives.size(); ++p) {
      const Primitive &x = a.meshes[m].primitives[p], &y = b.meshes[m].primitives[p];
      EXPECT_EQ(x.firstIndex, y.firstIndex);
      EXPECT_EQ(x.indexCount, y.indexCount);
      EXPECT_EQ(x.vertexOffset, y.vertexOffset);
      EXPECT_EQ(x.vertexCount, y.vertexCount);
      EXPECT_EQ(x.material, y.material);
    }
  }
  ASSERT_EQ(a.instances.size(), b.instances.size());
  for (size_t i = 0; i < a.instances.size(); ++i) {
    EXPECT_EQ(a.instances[i].mesh, b.instances[i].mesh);
    EXPECT_EQ(a.instances[i].transform,
              b.instances[i].transform);  // float -> JSON double -> float is exact
  }
  ASSERT_EQ(a.materials.size(), b.materials.size());
  for (size_t i = 0; i < a.materials.size(); ++i) {
    const Material &x = a.materials[i], &y = b.materials[i];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.baseColorFactor, y.baseColorFactor);
    EXPECT_EQ(x.metallicFactor, y.metallicFactor);
    EXPECT_EQ(x.roughnessFactor, y.roughnessFactor);
    EXPECT_EQ(x.baseColorTexture, y.baseColorTexture);
    EXPECT_EQ(x.metallicRoughnessTexture, y.metallicRoughnessTexture);
    EXPECT_EQ(x.doubleSided, y.doubleSided);
  }
  ASSERT_EQ(a.textures.size(), b.textures.size());
  for (size_t i = 0; i < a.textures.size(); ++i) {
    EXPECT_EQ(a.textures[i].name, b.textures[i].name);
    EXPECT_EQ(a.textures[i].width, b.textures[i].width);
    EXPECT_EQ(a.textures[i].height, b.textures[i].height);
    EXPECT_EQ(a.textures[i].srgb, b.textures[i].srgb);
    EXPECT_EQ(a.textures[i].rgba, b.textures[i].rgba);  // PNG is lossless
  }
  ASSERT_EQ(a.lights.size(), b.lights.size());
  for (size_t i = 0; i < a.lights.size(); ++i) {
    const Light &x = a.lights[i], &y = b.lights[i];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.type, y.type);
    EXPECT_EQ(x.position, y.position);  // the node's translation column, exact
    // The loader normalises the exported -Z column (= the float direction d) in double. A float
    // normalize leaves | |d| - 1 | <= 3·2^-24, so dividing by |d| moves each component (|c| <= 1)
    // by at most 3·2^-24, and rounding back to float adds at most 2^-25: below 2^-22.
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(x.direction[k], y.direction[k], 0x1p-22f) << "light " << i;
    EXPECT_EQ(x.color, y.color);
    EXPECT_EQ(x.intensity, y.intensity);
    EXPECT_EQ(x.range, y.range);
    EXPECT_EQ(x.rangeFromEq41, y.rangeFromEq41);
    EXPECT_EQ(x.innerConeAngle, y.innerConeAngle);
    EXPECT_EQ(x.outerConeAngle, y.outerConeAngle);
    EXPECT_EQ(x.castShadows, y.castShadows);
  }
  ASSERT_EQ(a.cameras.size(), b.cameras.size());
  for (size_t i = 0; i < a.cameras.size(); ++i) {
    const Camera &x = a.cameras[i], &y = b.cameras[i];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.yfov, y.yfov);
    EXPECT_EQ(x.znear, y.znear);
    EXPECT_EQ(x.zfar, y.zfar);
    // view -> inverse (double, exported) -> inverse (double, loaded) -> float. Two 4x4 inverses
    // of a rigid transform with |t| <= T have error <= c·n·2^-53·kappa·||V|| with kappa <=
    // (1 + T)^2, ||V|| <= 1 + T; with c·n = 64 and T = 10 (|eye| = 9.5) that is 64·2^-53·1331 ~
    // 1e-11, far below a float ulp, so an entry comes back as the same float or, where it is 0,
    // as a number within that bound; the test allows 1 float ulp of the entry plus 1e-11.
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) {
        const float e = x.view[c][r];
        const float ulp = std::nextafter(std::abs(e), INFINITY) - std::abs(e);
        EXPECT_NEAR(e, y.view[c][r], ulp + 1e-11) << "view[" << c << "][" << r << "]";
      }
  }
}

TEST(GltfExport, GltfRoundTripGivesTheSameScene) {
  TestDir dir;
  const Scene original = handBuiltScene();
  exportGltf(original, (dir / "scene.gltf").string());
  // The .gltf is self-contained: one data-URI buffer, no side files.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path), fs::directory_iterator()), 1);
  GltfLoadWarnings warnings;
  const Scene loaded = loadGltf((dir / "scene.gltf").string(), &warnings);
  EXPECT_TRUE(warnings.messages.empty());
  expectSameScene(original, loaded);
}

TEST(GltfExport, GlbRoundTripGivesTheSameScene) {
  TestDir dir;
  const Scene original = handBuiltScene();
  exportGltf(original, (dir / "scene.GLB").string());
  std::ifstream in(dir / "scene.GLB", std::ios::binary);
  char magic[4] = {};
  in.read(magic, 4);
  EXPECT_EQ(std::string(magic, 4), "glTF");
  expectSameScene(original, loadGltf((dir / "scene.GLB").string()));
}

TEST(GltfExport, WritesRangesAndDeclaresTheLightsExtension) {
  TestDir dir;
  exportGltf(handBuiltScene(), (dir / "scene.gltf").string());
  json doc = json::parse(std::ifstream(dir / "scene.gltf"));
  EXPECT_NE(
      std::find(doc["extensionsUsed"].begin(), doc["extensionsUsed"].end(), "KHR_lights_punctual"),
      doc["extensionsUsed"].end());
  const json& lights = doc["extensions"]["KHR_lights_punctual"]["lights"];
  ASSERT_EQ(lights.size(), 3u);
  EXPECT_EQ(lights[0]["range"].get<float>(), 12.5f);
  EXPECT_EQ(lights[1]["range"].get<float>(), static_cast<float>(rangeFromIntensity(7.0)));
  EXPECT_EQ(doc["asset"]["version"], "2.0");
  EXPECT_EQ(
      doc["buffers"][0]["uri"].get<std::string>().rfind("data:application/octet-stream;base64,", 0),
      0u);
}

TEST(GltfExport, UnwritablePathIsAnInputError) {
  TestDir dir;
  EXPECT_THROW(exportGltf(handBuiltScene(), (dir / "missing" / "x.gltf").string()), InputError);
}

// ---- info and hash
// -------------------------------------------------------------------------------

TEST(SceneInfo, CountsAndBoundsOfTheQuad) {
  TestDir dir;
  Scene s = loadGltf(
      quadWithLight({{"type", "point"}, {"intensity", 50}}).writeGltf(dir / "q.gltf").string());
  json j = sceneInfoJson(s);
  EXPECT_EQ(j["triangles"], 2);
  EXPECT_EQ(j["vertices"], 4);
  EXPECT_EQ(j["meshes"], 1);
  EXPECT_EQ(j["instances"], 1);
  EXPECT_EQ(j["materials"], 1);
  EXPECT_EQ(j["lights"]["point"], 1);
  EXPECT_EQ(j["lights"]["ranges_from_eq41"], 1);
  EXPECT_EQ(j["lights"]["range_max"].get<float>(), 50.0f);  // sqrt(50 * 50)
  EXPECT_EQ(j["bounds"]["size_m"], json({1.0, 1.0, 0.0}));
  const std::string text = sceneInfoText(s);
  EXPECT_NE(text.find("triangles  2"), std::string::npos) << text;
  EXPECT_NE(text.find("eq. 4.1"), std::string::npos) << text;
}

TEST(SceneHash, IsDeterministicAndSeesEveryChange) {
  const Scene s = handBuiltScene();
  const std::string h = sceneSha256(s);
  EXPECT_EQ(h.size(), 64u);
  EXPECT_EQ(h, sceneSha256(handBuiltScene()));
  Scene renamed = s;
  renamed.name = "other";
  EXPECT_EQ(h, sceneSha256(renamed));  // names do not render
  Scene moved = s;
  moved.vertices[5].position.x = std::nextafter(moved.vertices[5].position.x, 1.0f);
  EXPECT_NE(h, sceneSha256(moved));
  Scene dimmer = s;
  dimmer.lights[1].intensity *= 0.5f;
  EXPECT_NE(h, sceneSha256(dimmer));
  Scene shadowless = s;
  shadowless.lights[0].castShadows = false;
  EXPECT_NE(h, sceneSha256(shadowless));
  Scene zoomed = s;
  zoomed.cameras[0].yfov = 0.5f;
  EXPECT_NE(h, sceneSha256(zoomed));
}

TEST(SceneHash, MatchesTheFips180ExampleForAbc) {
  EXPECT_EQ(sha256Hex("abc", 3),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

}  // namespace
}  // namespace hb

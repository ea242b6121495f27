// loadGltf on accessors and mesh primitives: component types, byte ranges of accessors and
// bufferViews, index ranges, non-finite positions, computed normals and indices, skipped modes.
#include <gtest/gtest.h>

#include <cmath>

#include "gltf/gltf_io.h"
#include "gltf/gltf_test_util.h"

namespace hb::gltf_test {
namespace {

TEST(GltfLoad, ComputesNormalsAndSequentialIndicesWhenMissing) {
  TestDir dir;
  GltfBuilder b;
  // Two triangles of a quad facing +z, no NORMAL and no indices.
  json prim = {
      {"attributes", {{"POSITION", b.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0, 1, 1, 0, 0, 1, 0}, "VEC3", 3)}}}};
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

TEST(GltfLoadErrors, AccessorPastItsBufferViewNamesTheAttribute) {
  TestDir dir;
  expectBrokenQuad(dir, "short.gltf",
                   [](json& doc) {
                     doc["accessors"][0]["count"] = 5;  // POSITION: 5 * 12 bytes > the 48-byte bufferView
                   },
                   {"meshes[0].primitives[0].attributes.POSITION", "accessors[0]", "60"});
}

TEST(GltfLoadErrors, AccessorByteOffsetPastItsBufferViewNamesTheIndices) {
  TestDir dir;
  expectBrokenQuad(dir, "offset.gltf",
                   [](json& doc) {
                     doc["accessors"][3]["byteOffset"] = 2;  // indices: 2 + 6 * 2 = 14 > 12 bytes
                   },
                   {"meshes[0].primitives[0].indices"});
}

TEST(GltfLoadErrors, StridedAccessorPastItsBufferViewIsCaught) {
  TestDir dir;
  expectBrokenQuad(dir, "stride.gltf",
                   [](json& doc) {
                     doc["bufferViews"][0]["byteStride"] = 16;  // 16 * 3 + 12 = 60 > 48
                   },
                   {"attributes.POSITION", "stride 16"});
}

TEST(GltfLoadErrors, BufferViewPastItsBufferIsCaught) {
  TestDir dir;
  expectBrokenQuad(dir, "view.gltf",
                   [](json& doc) {
                     doc["bufferViews"][0]["byteLength"] = 4096;  // the whole buffer is far shorter
                     doc["accessors"][0]["count"] = 300;
                   },
                   {"bufferViews[0]"});
}

TEST(GltfLoadErrors, IndexPastTheVertexCountNamesTheIndices) {
  TestDir dir;
  GltfBuilder b;
  int pos = b.floats({0, 0, 0, 1, 0, 0, 1, 1, 0}, "VEC3", 3);
  int idx = b.accessor(b.view(std::vector<uint16_t>{0, 1, 7}), kU16, "SCALAR", 3);
  b.doc["meshes"] = json::array({{{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"indices", idx}}}}}});
  b.scene({b.node({{"mesh", 0}})});
  expectInputError(b.writeGltf(dir / "index.gltf"), {"meshes[0].primitives[0].indices", "7", "3 vertices"});
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

TEST(GltfLoadErrors, UnsupportedComponentTypeNamesTheAccessor) {
  TestDir dir;
  expectBrokenQuad(dir, "floatidx.gltf",
                   [](json& doc) {
                     doc["accessors"][3]["componentType"] = kFloat;  // float indices
                     doc["accessors"][3]["count"] = 3;
                   },
                   {"meshes[0].primitives[0].indices", "componentType 5126"});

  expectBrokenQuad(dir, "u32pos.gltf",
                   [](json& doc) {
                     doc["accessors"][0]["componentType"] = kU32;  // 32-bit integers are not positions even quantized
                   },
                   {"attributes.POSITION", "componentType 5125", "FLOAT"});
}

// KHR_mesh_quantization as gltfpack writes it: unnormalized integer positions scaled back by the
// node, normalized signed-byte normals, normalized u16 texture coordinates whose range
// KHR_texture_transform scales back.
TEST(GltfQuantized, IntegerAttributesReadAsTheExtensionDefinesThem) {
  TestDir dir;
  GltfBuilder b;
  const int pos = b.accessor(b.view(std::vector<int16_t>{0, 0, 0, 1000, 0, 0, 1000, -1000, 0}), 5122, "VEC3", 3);
  // (0, 127, 0) is +Y; (-128, 0, 0) clamps to -1 (glTF 2.0 §3.11: max(c / 127, -1)); the third
  // is not unit (quantized): it loads normalised. Byte VEC3 elements are 4-byte aligned (stride 4).
  const int view = b.view(std::vector<int8_t>{0, 127, 0, 0, -128, 0, 0, 0, 90, 90, 0, 0});
  b.doc["bufferViews"][static_cast<size_t>(view)]["byteStride"] = 4;
  const int nrm = b.accessor(view, 5120, "VEC3", 3);
  b.doc["accessors"][static_cast<size_t>(nrm)]["normalized"] = true;
  const int uv = b.accessor(b.view(std::vector<uint16_t>{0, 0, 65535, 0, 65535, 65535}), kU16, "VEC2", 3);
  b.doc["accessors"][static_cast<size_t>(uv)]["normalized"] = true;
  b.doc["meshes"] = {
      {{"primitives", {{{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}, {"TEXCOORD_0", uv}}}, {"material", 0}}}}}};
  b.doc["materials"] = {
      {{"pbrMetallicRoughness",
        {{"baseColorTexture",
          {{"index", 0},
           {"extensions", {{"KHR_texture_transform", {{"offset", {0.25, 0.5}}, {"scale", {2.0, 4.0}}}}}}}}}}}};
  b.doc["images"] = {{{"uri",
                       "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8Dw"
                       "HwAFBQIAX8jx0gAAAABJRU5ErkJggg=="}}};
  b.doc["textures"] = {{{"source", 0}}};
  b.doc["extensionsUsed"] = {"KHR_mesh_quantization", "KHR_texture_transform"};
  b.doc["extensionsRequired"] = {"KHR_mesh_quantization"};
  b.scene({b.node({{"mesh", 0}, {"scale", {0.001, 0.001, 0.001}}})});
  GltfLoadWarnings warnings;
  const Scene s = loadGltf(b.writeGltf(dir / "quantized.gltf").string(), &warnings);
  EXPECT_TRUE(warnings.messages.empty()) << warnings.messages[0];
  ASSERT_EQ(s.vertices.size(), 3u);
  EXPECT_EQ(s.vertices[1].position, glm::vec3(1000, 0, 0));  // the node's scale brings it to 1 m
  EXPECT_EQ(s.vertices[2].position, glm::vec3(1000, -1000, 0));
  EXPECT_EQ(s.vertices[0].normal, glm::vec3(0, 1, 0));
  EXPECT_EQ(s.vertices[1].normal, glm::vec3(-1, 0, 0));
  EXPECT_NEAR(glm::length(s.vertices[2].normal), 1.0f, 1e-6f);
  // uv' = offset + scale * uv: (0, 0) → (0.25, 0.5); (1, 1) → (2.25, 4.5).
  EXPECT_EQ(s.vertices[0].uv, glm::vec2(0.25f, 0.5f));
  EXPECT_EQ(s.vertices[2].uv, glm::vec2(2.25f, 4.5f));
  ASSERT_EQ(s.instances.size(), 1u);
  EXPECT_FLOAT_EQ(s.instances[0].transform[0][0], 0.001f);
}

}  // namespace
}  // namespace hb::gltf_test

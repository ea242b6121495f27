// loadGltf on whole files: the node graph and its transforms, lights, cameras, materials and
// images, .gltf vs .glb, and files that are missing, malformed or refer past their arrays.
#include "gltf/gltf_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "gltf/gltf_test_util.h"

namespace hb::gltf_test {
namespace {

TEST(GltfLoad, ReadsAQuadWithAPointLight) {
  TestDir dir;
  GltfBuilder b = quadWithLight({{"type", "point"}, {"intensity", 20}, {"range", 5}, {"color", {1, 0.5, 0.25}}});
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
  b.scene({b.node({{"rotation", {-h, 0, 0, h}}, {"extensions", {{"KHR_lights_punctual", {{"light", l}}}}}}),
           b.node({{"mesh", b.quad()}})});
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
  int child = b.node({{"mesh", mesh}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1}}});
  int parent =
      b.node({{"translation", {10, 0, 0}}, {"rotation", {0, h, 0, h}}, {"scale", {2, 2, 2}}, {"children", {child}}});
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

TEST(GltfLoad, GlbGivesTheSameSceneAsGltf) {
  TestDir dir;
  GltfBuilder b = quadWithLight({{"type", "point"}, {"intensity", 8}});
  Scene a = loadGltf(b.writeGltf(dir / "quad.gltf").string());
  Scene g = loadGltf(b.writeGlb(dir / "quad.glb").string());
  EXPECT_EQ(sceneSha256(a), sceneSha256(g));
  EXPECT_EQ(g.vertices.size(), 4u);
  EXPECT_EQ(g.lights.size(), 1u);
}

TEST(GltfLoad, ReadsAPerspectiveCameraAsTheInverseOfItsNode) {
  TestDir dir;
  GltfBuilder b;
  b.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.05}}}}};
  // A quad too: a scene with nothing to draw is refused (gltf_io.h).
  b.scene({b.node({{"camera", 0}, {"translation", {0, 1, 4}}}), b.node({{"mesh", b.quad()}})});
  Scene s = loadGltf(b.writeGltf(dir / "cam.gltf").string());
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_EQ(s.cameras[0].yfov, 0.8f);
  EXPECT_EQ(s.cameras[0].znear, 0.05f);
  EXPECT_EQ(s.cameras[0].zfar, 1000.0f);  // missing zfar
  // Inverting a pure translation in double is exact: -t.
  EXPECT_EQ(s.cameras[0].view * glm::vec4(0, 1, 4, 1), glm::vec4(0, 0, 0, 1));
}

TEST(GltfLoad, ReadsAnOrthographicCameraWithItsExtent) {
  // Skipped before issue 15; now rendered by 3dr and raycast (projection=orthographic).
  TestDir dir;
  GltfBuilder b;
  b.doc["cameras"] = {
      {{"type", "orthographic"}, {"orthographic", {{"xmag", -3.0}, {"ymag", 2.0}, {"znear", 0.0}, {"zfar", 50.0}}}}};
  // A quad too: a scene with nothing to draw is refused (gltf_io.h).
  b.scene({b.node({{"camera", 0}, {"translation", {0, 1, 4}}}), b.node({{"mesh", b.quad()}})});
  Scene s = loadGltf(b.writeGltf(dir / "ortho.gltf").string());
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_EQ(s.cameras[0].projection, CameraProjection::Orthographic);
  EXPECT_EQ(s.cameras[0].xmag, 3.0f);  // the magnitude: the sign only mirrors the image
  EXPECT_EQ(s.cameras[0].ymag, 2.0f);
  EXPECT_EQ(s.cameras[0].znear, 0.0f);
  EXPECT_EQ(s.cameras[0].zfar, 50.0f);
  EXPECT_EQ(s.cameras[0].view * glm::vec4(0, 1, 4, 1), glm::vec4(0, 0, 0, 1));
}

TEST(GltfLoadErrors, AnOrthographicCameraWithoutExtentNamesTheField) {
  TestDir dir;
  GltfBuilder b;
  b.doc["cameras"] = {
      {{"type", "orthographic"}, {"orthographic", {{"xmag", 0.0}, {"ymag", 2.0}, {"znear", 0.0}, {"zfar", 50.0}}}}};
  b.scene({b.node({{"camera", 0}})});
  expectInputError(b.writeGltf(dir / "flat.gltf"), {"cameras[0].orthographic", "non-zero"});
}

// ---- bad input ----------------------------------------------------------------------------------

TEST(GltfLoadErrors, MissingFileNamesThePath) {
  TestDir dir;
  expectInputError(dir / "nope.gltf", {"no such file"});
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

TEST(GltfLoadErrors, ZeroOrNegativeLightRangeNamesTheLight) {
  TestDir dir;
  for (double range : {0.0, -2.0}) {
    GltfBuilder b = quadWithLight({{"type", "point"}, {"intensity", 5}, {"range", range}});
    expectInputError(b.writeGltf(dir / "range.gltf"), {"KHR_lights_punctual.lights[0].range", "> 0"});
  }
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

// Found by fuzz_gltf: numbers that a double holds but the scene's floats do not (beyond 3.4e38)
// became inf, and a camera node of scale 0 an inf/NaN view; each now names its field.
TEST(GltfLoadErrors, ANumberBeyondAFloatOrACameraWithoutAViewNamesItsField) {
  TestDir dir;
  GltfBuilder far = quadWithLight({{"type", "point"}, {"intensity", 8}});
  far.doc["nodes"][1]["translation"] = {0, 3e120, 0};  // the light's node
  expectInputError(far.writeGltf(dir / "far.gltf"), {"nodes[1]", "beyond 3.4e38"});
  GltfBuilder nested = quadWithLight({{"type", "point"}, {"intensity", 8}});  // 1e20 * 1e20
  nested.doc["nodes"][1]["scale"] = {1e20, 1e20, 1e20};
  nested.doc["nodes"][1]["children"] = {nested.node({{"mesh", 0}, {"translation", {1e20, 0, 0}}})};
  expectInputError(nested.writeGltf(dir / "nested.gltf"), {"nodes[2]", "beyond 3.4e38"});
  for (const char* key : {"intensity", "range"}) {
    json light = {{"type", "point"}, {"intensity", 8}};
    light[key] = 1e39;
    GltfBuilder bright = quadWithLight(light);
    expectInputError(bright.writeGltf(dir / "bright.gltf"),
                     {std::string("KHR_lights_punctual.lights[0].") + key, "1e+39"});
  }
  GltfBuilder colored = quadWithLight({{"type", "point"}, {"color", {1, 1e39, 1}}});
  expectInputError(colored.writeGltf(dir / "colored.gltf"), {"lights[0].color", "1e+39"});
  GltfBuilder flat;
  flat.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.05}}}}};
  flat.scene({flat.node({{"camera", 0}, {"scale", {1, 0, 1}}})});
  expectInputError(flat.writeGltf(dir / "flat-camera.gltf"), {"nodes (of cameras[0])", "inverse"});
  GltfBuilder deep;
  deep.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 1e39}}}}};
  deep.scene({deep.node({{"camera", 0}})});
  expectInputError(deep.writeGltf(dir / "deep-camera.gltf"), {"cameras[0].perspective.znear"});
}

// Found by fuzz_gltf: tinygltf sized its read of an external file by seeking to the end, which for
// a directory is 2^63 - 1 on ext4, and the bad_alloc escaped the loader as an internal error.
TEST(GltfLoadErrors, ABufferOrImageUriThatNamesADirectoryIsAnInputError) {
  TestDir dir;
  fs::create_directories(dir / "textures");
  GltfBuilder image;
  image.quad(true, 0);
  image.doc["images"] = {{{"uri", "textures/"}}};
  image.doc["textures"] = {{{"source", 0}}};
  image.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  image.scene({image.node({{"mesh", 0}})});
  expectInputError(image.writeGltf(dir / "image-dir.gltf"), {"images[0]", "textures/"});

  GltfBuilder buffer = quadWithLight({{"type", "point"}, {"intensity", 8}});
  const fs::path path = buffer.writeGltf(dir / "buffer-dir.gltf");
  json doc = json::parse(std::ifstream(path));
  doc["buffers"][0]["uri"] = "textures";
  std::ofstream(path) << doc.dump();
  expectInputError(path, {"textures", "not a regular file"});
}

}  // namespace
}  // namespace hb::gltf_test

// Required extensions the loader cannot read are named in one line (exit 2 from the tool), optional
// ones it ignores in one warning (gltf_extensions.cpp); WebP and AVIF textures decode, KTX2 ones
// leave their factors and one warning (gltf_materials.cpp).
#include <webp/encode.h>

#include <gtest/gtest.h>

#include "gltf/gltf_test_util.h"
#include "scene/environment.h"

#ifndef HYBRIDBENCH_SOURCE_DIR
#error "HYBRIDBENCH_SOURCE_DIR must name the source tree (for scenes/environments/)"
#endif

namespace hb::gltf_test {
namespace {

// A texture whose only image is KTX2 / Basis Universal (no Debian library transcodes it) is not a
// refusal: its material renders with its factors, and one warning line counts such textures.
TEST(GltfExtensions, Ktx2TexturesLeaveTheFactorsAndOneWarning) {
  TestDir dir;
  GltfBuilder b = quadWithLight({{"type", "point"}, {"intensity", 10}});
  // Two textures with a KTX2 image (its header is all the loader looks at): one named by
  // KHR_texture_basisu alone, one as the core source.
  std::vector<uint8_t> ktx2 = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, 0x0D, 0x0A, 0x1A, 0x0A, 0, 0, 0, 0};
  b.doc["images"] = {{{"bufferView", b.view(ktx2)}, {"mimeType", "image/ktx2"}}};
  b.doc["textures"] = {{{"extensions", {{"KHR_texture_basisu", {{"source", 0}}}}}},
                       {{"source", 0}, {"extensions", {{"KHR_texture_basisu", {{"source", 0}}}}}}};
  b.doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  b.doc["materials"][0]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 1}};
  b.doc["extensionsUsed"] = {"KHR_lights_punctual", "KHR_texture_basisu"};
  b.doc["extensionsRequired"] = {"KHR_texture_basisu"};
  GltfLoadWarnings warnings;
  const Scene s = loadGltf(b.writeGltf(dir / "ktx2.gltf").string(), &warnings);
  EXPECT_TRUE(s.textures.empty());
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].baseColorTexture, -1);
  EXPECT_EQ(s.materials[0].metallicRoughnessTexture, -1);
  EXPECT_EQ(s.materials[0].baseColorFactor, glm::vec4(1, 0, 0, 1));
  ASSERT_EQ(warnings.messages.size(), 1u);
  EXPECT_NE(warnings.messages[0].find("2 texture(s) in KHR_texture_basisu (2) not decoded"), std::string::npos)
      << warnings.messages[0];
  EXPECT_NE(warnings.messages[0].find("their factors"), std::string::npos) << warnings.messages[0];
}

// An EXT_texture_webp image decodes (libwebp) to the texels it was encoded from: lossless WebP
// (libwebp's own encoder here) is exact, so every texel is compared for equality, with no warning.
// Its bytes cut short, or a file that only looks like AVIF, is one InputError naming the image.
TEST(GltfExtensions, WebpTexturesDecodeToTheirTexelsAndBrokenImagesAreNamed) {
  TestDir dir;
  // 3x2 texels, every channel different, alpha included (none 0: libwebp's encoder drops the colour
  // of fully transparent texels unless told to keep it).
  const std::vector<uint8_t> texels = {255, 0,  0,  255, 0,  255, 0,  200, 0,  0,   255, 100,
                                       10,  20, 30, 40,  50, 60,  70, 80,  90, 100, 110, 1};
  uint8_t* encoded = nullptr;
  const size_t size = WebPEncodeLosslessRGBA(texels.data(), 3, 2, 3 * 4, &encoded);
  ASSERT_GT(size, 0u);
  const std::vector<uint8_t> webp(encoded, encoded + size);
  WebPFree(encoded);
  auto withImage = [&](const std::vector<uint8_t>& bytes, const char* mimeType, const char* extension) {
    GltfBuilder b = quadWithLight({{"type", "point"}, {"intensity", 10}});
    b.doc["images"] = {{{"bufferView", b.view(bytes)}, {"mimeType", mimeType}}};
    b.doc["textures"] = {{{"extensions", {{extension, {{"source", 0}}}}}}};
    b.doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    b.doc["extensionsUsed"] = {"KHR_lights_punctual", extension};
    b.doc["extensionsRequired"] = {extension};
    return b;
  };
  GltfLoadWarnings warnings;
  const Scene s =
      loadGltf(withImage(webp, "image/webp", "EXT_texture_webp").writeGltf(dir / "webp.gltf").string(), &warnings);
  EXPECT_TRUE(warnings.messages.empty()) << warnings.messages[0];
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.textures[0].width, 3u);
  EXPECT_EQ(s.textures[0].height, 2u);
  EXPECT_EQ(s.textures[0].rgba, texels);
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].baseColorTexture, 0);

  const std::vector<uint8_t> truncated(webp.begin(), webp.begin() + static_cast<std::ptrdiff_t>(webp.size() / 2));
  expectInputError(withImage(truncated, "image/webp", "EXT_texture_webp").writeGlb(dir / "truncated.glb"),
                   {"images[0]", "WebP", "(truncated or corrupt)"});
  std::vector<uint8_t> avif(64, 0xFF);  // an ftyp box of brand avif, then nothing an AVIF holds
  const std::string ftyp = std::string("\0\0\0\x18", 4) + "ftypavif";
  std::copy(ftyp.begin(), ftyp.end(), avif.begin());
  expectInputError(withImage(avif, "image/avif", "EXT_texture_avif").writeGlb(dir / "corrupt.glb"),
                   {"images[0]", "AVIF", "does not decode", "(truncated or corrupt)"});
  // The file is valid glTF; its texture is not: the line blames the image alone.
  try {
    (void)loadGltf((dir / "truncated.glb").string());
    ADD_FAILURE() << "truncated.glb loaded";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).find("not a valid glTF"), std::string::npos) << e.what();
  }
}

TEST(GltfExtensions, AnUnknownRequiredExtensionIsNamedAndOptionalOnesAreAWarning) {
  TestDir dir;
  GltfBuilder req = quadWithLight({{"type", "point"}, {"intensity", 10}});
  req.doc["extensionsUsed"] = {"KHR_lights_punctual", "EXT_made_up"};
  req.doc["extensionsRequired"] = {"EXT_made_up"};
  expectInputError(req.writeGltf(dir / "required.gltf"), {"requires EXT_made_up", "re-export it without"});

  GltfBuilder opt = quadWithLight({{"type", "point"}, {"intensity", 10}});
  opt.doc["extensionsUsed"] = {"KHR_lights_punctual", "KHR_materials_clearcoat", "KHR_materials_sheen"};
  GltfLoadWarnings warnings;
  const Scene s = loadGltf(opt.writeGltf(dir / "optional.gltf").string(), &warnings);
  EXPECT_EQ(s.lights.size(), 1u);
  ASSERT_EQ(warnings.messages.size(), 1u);
  EXPECT_NE(warnings.messages[0].find("KHR_materials_clearcoat, KHR_materials_sheen"), std::string::npos)
      << warnings.messages[0];
  EXPECT_EQ(warnings.messages[0].find("KHR_lights_punctual"), std::string::npos) << warnings.messages[0];

  // The lights extension alone (what our exporter writes) warns about nothing.
  GltfLoadWarnings none;
  loadGltf(quadWithLight({{"type", "point"}, {"intensity", 10}}).writeGltf(dir / "plain.gltf").string(), &none);
  EXPECT_TRUE(none.messages.empty());
}

// Strips and fans are triangles: they load as the triangle lists glTF 2.0 §3.7.2.1 defines (a
// strip keeps every triangle's winding). Points or lines alone draw nothing: refused by name.
TEST(GltfModes, StripsAndFansLoadAsTriangleListsAndPointsAloneAreRefused) {
  TestDir dir;
  for (int mode : {5, 6}) {
    GltfBuilder b;
    b.quad();
    // The quad's 4 vertices (0,0) (1,0) (1,1) (0,1) as a strip 0 1 3 2 and as a fan 0 1 2 3.
    const int idx = b.accessor(
        b.view(mode == 5 ? std::vector<uint16_t>{0, 1, 3, 2} : std::vector<uint16_t>{0, 1, 2, 3}), kU16, "SCALAR", 4);
    b.doc["meshes"][0]["primitives"][0]["indices"] = idx;
    b.doc["meshes"][0]["primitives"][0]["mode"] = mode;
    b.scene({b.node({{"mesh", 0}})});
    GltfLoadWarnings warnings;
    const Scene s = loadGltf(b.writeGltf(dir / ("mode" + std::to_string(mode) + ".gltf")).string(), &warnings);
    EXPECT_EQ(warnings.skippedPrimitives, 0u);
    const std::vector<uint32_t> expected =
        mode == 5 ? std::vector<uint32_t>{0, 1, 3, 1, 2, 3} : std::vector<uint32_t>{1, 2, 0, 2, 3, 0};
    EXPECT_EQ(s.indices, expected) << "mode " << mode;
    // Both triangles face +z like the quad's TRIANGLES (counter-clockwise seen from +z).
    for (size_t t = 0; t < 2; ++t) {
      const glm::vec3 a = s.vertices[s.indices[3 * t]].position, b2 = s.vertices[s.indices[3 * t + 1]].position,
                      c = s.vertices[s.indices[3 * t + 2]].position;
      EXPECT_GT(glm::cross(b2 - a, c - a).z, 0.0f) << "mode " << mode << " triangle " << t;
    }
  }
  GltfBuilder points;
  points.quad();
  points.doc["meshes"][0]["primitives"][0]["mode"] = 0;
  points.scene({points.node({{"mesh", 0}})});
  expectInputError(points.writeGltf(dir / "points.gltf"), {"meshes[0].primitives[0] (mode 0)", "points or lines"});
}

// A glTF scene's extras.environment, its image relative to the glTF file; EXT_lights_image_based
// loads with one warning line that says where the environment goes instead.
TEST(GltfExtensions, AGltfSceneCarriesItInExtrasAndImageBasedLightIsOneWarning) {
  TestDir dir;
  fs::copy_file(fs::path(HYBRIDBENCH_SOURCE_DIR) / "scenes/environments/sky.hdr", dir / "sky.hdr");
  GltfBuilder b = quadWithLight({{"type", "point"}, {"intensity", 10}});
  b.doc["scenes"][0]["extras"]["environment"] = {{"image", "sky.hdr"}, {"intensity", 0.5}};
  b.doc["extensionsUsed"].push_back("EXT_lights_image_based");
  b.doc["extensionsRequired"] = {"EXT_lights_image_based"};
  GltfLoadWarnings warnings;
  const Scene s = loadGltf(b.writeGltf(dir / "env.gltf").string(), &warnings);
  ASSERT_TRUE(s.environment.has_value());
  EXPECT_EQ(s.environment->width, 128u);
  EXPECT_FLOAT_EQ(s.environment->intensity, 0.5f);
  ASSERT_EQ(warnings.messages.size(), 1u);
  EXPECT_NE(warnings.messages[0].find("ignores EXT_lights_image_based"), std::string::npos) << warnings.messages[0];
  EXPECT_NE(warnings.messages[0].find("extras.environment"), std::string::npos) << warnings.messages[0];

  GltfBuilder missing = quadWithLight({{"type", "point"}, {"intensity", 10}});
  missing.doc["scenes"][0]["extras"]["environment"] = {{"image", "nowhere.hdr"}};
  try {
    loadGltf(missing.writeGltf(dir / "missing.gltf").string());
    ADD_FAILURE() << "a missing image loaded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scenes[0].extras.environment.image"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hb::gltf_test

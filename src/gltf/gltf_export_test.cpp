// exportGltf round trips (.gltf and .glb), the Khronos validator on its output,
// sceneInfoJson/sceneInfoText and sceneSha256.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <sstream>

#include "base/errors.h"
#include "base/sha256.h"
#include "gltf/gltf_io.h"
#include "gltf/gltf_test_util.h"

namespace hb::gltf_test {
namespace {

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
    const glm::vec3 n = glm::normalize(glm::vec3(0.1f, 0.2f, 1.0f));  // deliberately not axis-aligned
    for (int i = 0; i < 4; ++i)
      s.vertices.push_back({glm::vec3(0.3f * (i & 1), 0.7f * (i >> 1), z), n, glm::vec2(0.1f * i, 1.0f / 3.0f * i)});
    for (uint32_t i : {0u, 1u, 3u, 0u, 3u, 2u}) s.indices.push_back(i);
    return p;
  };
  s.meshes.push_back({"two-prims", {addQuad(0.0f, 0), addQuad(0.5f, 1)}});
  s.meshes.push_back({"one-prim", {addQuad(-1.25f, 2)}});
  s.instances.push_back({0, glm::mat4(1.0f)});
  s.instances.push_back({1, glm::translate(glm::mat4(1.0f), glm::vec3(3.1f, -2.0f, 0.7f))});
  s.instances.push_back(
      {1, glm::rotate(glm::mat4(1.0f), 0.3f, glm::vec3(0, 1, 0)) * glm::scale(glm::mat4(1.0f), glm::vec3(1.5f))});

  Texture tex;
  tex.name = "checker";
  tex.width = 4;
  tex.height = 3;
  tex.srgb = true;
  for (uint32_t i = 0; i < 12; ++i)
    tex.rgba.insert(tex.rgba.end(), {uint8_t(i * 20), uint8_t(255 - i * 7), uint8_t(i * i), uint8_t(200 + i)});
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
  cam.view = glm::lookAt(glm::vec3(6.0f, 2.5f, 7.0f), glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(0, 1, 0));
  cam.yfov = 0.9f;
  cam.znear = 0.05f;
  cam.zfar = 250.0f;
  Camera ortho = cam;  // and an orthographic one (glTF carries both kinds)
  ortho.name = "plan";
  ortho.projection = CameraProjection::Orthographic;
  ortho.xmag = 8.0f;
  ortho.ymag = 4.5f;
  ortho.znear = 0.0f;
  ortho.yfov = Camera{}.yfov;  // not part of an orthographic camera: loads as the default
  s.cameras = {cam, ortho};
  return s;
}

void expectSameScene(const Scene& a, const Scene& b) {
  EXPECT_EQ(a.name, b.name);
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  EXPECT_EQ(0, std::memcmp(a.vertices.data(), b.vertices.data(), a.vertices.size() * sizeof(Vertex)));
  EXPECT_EQ(a.indices, b.indices);
  // Meshes, instances (float -> JSON double -> float is exact), materials and textures (PNG is
  // lossless) come back field for field.
  EXPECT_EQ(a.meshes, b.meshes);
  EXPECT_EQ(a.instances, b.instances);
  EXPECT_EQ(a.materials, b.materials);
  EXPECT_EQ(a.textures, b.textures);
  ASSERT_EQ(a.lights.size(), b.lights.size());
  for (size_t i = 0; i < a.lights.size(); ++i) {
    // The position is the node's translation column, exact. The loader normalises the exported
    // -Z column (= the float direction d) in double. A float normalize leaves | |d| - 1 | <=
    // 3·2^-24, so dividing by |d| moves each component (|c| <= 1) by at most 3·2^-24, and
    // rounding back to float adds at most 2^-25: below 2^-22. Every other field is exact.
    Light y = b.lights[i];
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(a.lights[i].direction[k], y.direction[k], 0x1p-22f) << "light " << i;
    y.direction = a.lights[i].direction;
    EXPECT_EQ(a.lights[i], y) << "light " << i;
  }
  ASSERT_EQ(a.cameras.size(), b.cameras.size());
  for (size_t i = 0; i < a.cameras.size(); ++i) {
    // view -> inverse (double, exported) -> inverse (double, loaded) -> float. Two 4x4 inverses
    // of a rigid transform with |t| <= T have error <= c·n·2^-53·kappa·||V|| with kappa <=
    // (1 + T)^2, ||V|| <= 1 + T; with c·n = 64 and T = 10 (|eye| = 9.5) that is 64·2^-53·1331 ~
    // 1e-11, far below a float ulp, so an entry comes back as the same float or, where it is 0,
    // as a number within that bound; the test allows 1 float ulp of the entry plus 1e-11. Every
    // other field is exact.
    Camera y = b.cameras[i];
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) {
        const float e = a.cameras[i].view[c][r];
        const float ulp = std::nextafter(std::abs(e), INFINITY) - std::abs(e);
        EXPECT_NEAR(e, y.view[c][r], ulp + 1e-11) << "view[" << c << "][" << r << "]";
      }
    y.view = a.cameras[i].view;
    EXPECT_EQ(a.cameras[i], y) << "camera " << i;
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
  EXPECT_NE(std::find(doc["extensionsUsed"].begin(), doc["extensionsUsed"].end(), "KHR_lights_punctual"),
            doc["extensionsUsed"].end());
  const json& lights = doc["extensions"]["KHR_lights_punctual"]["lights"];
  ASSERT_EQ(lights.size(), 3u);
  EXPECT_EQ(lights[0]["range"].get<float>(), 12.5f);
  EXPECT_EQ(lights[1]["range"].get<float>(), static_cast<float>(rangeFromIntensity(7.0)));
  EXPECT_EQ(doc["asset"]["version"], "2.0");
  EXPECT_EQ(doc["buffers"][0]["uri"].get<std::string>().rfind("data:application/octet-stream;base64,", 0), 0u);
}

TEST(GltfExport, UnwritablePathIsAnInputError) {
  TestDir dir;
  EXPECT_THROW(exportGltf(handBuiltScene(), (dir / "missing" / "x.gltf").string()), InputError);
}

// The Khronos glTF Validator (scripts/validate-gltf.mjs; node and the validator come from
// scripts/setup.sh) on features of the exporter that no built-in scene has, so that
// tests/gltf_validator_test.sh does not reach them: textures (PNG in the buffer), spot and
// directional lights, an orthographic camera, a double-sided material, rotated and scaled instances.
TEST(GltfValidator, HandBuiltSceneWithEveryExportedFeatureHasNoErrorsOrWarnings) {
  TestDir dir;
  exportGltf(handBuiltScene(), (dir / "scene.gltf").string());
  exportGltf(handBuiltScene(), (dir / "scene.glb").string());
  const std::string log = (dir / "validator.log").string();
  const std::string command = "node '" HYBRIDBENCH_SOURCE_DIR "/scripts/validate-gltf.mjs' '" +
                              (dir / "scene.gltf").string() + "' '" + (dir / "scene.glb").string() + "' > '" + log +
                              "' 2>&1";
  const int status = std::system(command.c_str());
  std::stringstream output;
  output << std::ifstream(log).rdbuf();
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
      << output.str() << "(node and the validator come from scripts/setup.sh)";
}

// ---- info and hash ------------------------------------------------------------------------------

TEST(SceneInfo, CountsAndBoundsOfTheQuad) {
  TestDir dir;
  Scene s = loadGltf(quadWithLight({{"type", "point"}, {"intensity", 50}}).writeGltf(dir / "q.gltf").string());
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
  EXPECT_EQ(sha256Hex("abc", 3), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

}  // namespace
}  // namespace hb::gltf_test

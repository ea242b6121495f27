#include "gltf/gltf_structure.h"

#include <gtest/gtest.h>

#include <functional>

#include "base/input_error_of.h"

namespace hb::gltf_detail {
namespace {

using nlohmann::json;

std::string errorOf(const json& doc) {
  return inputErrorOf([&] { checkGltfStructure(doc, "f.gltf"); });
}

const json kGood = {{"asset", {{"version", "2.0"}}},
                    {"scene", 0},
                    {"scenes", {{{"nodes", {0}}}}},
                    {"nodes", {{{"mesh", 0}, {"translation", {0, 1, 2}}}}},
                    {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"mode", 4}}}}}}},
                    {"accessors", {{{"componentType", 5126}, {"count", 3}, {"type", "VEC3"}}}}};

TEST(GltfStructure, AWellFormedDocumentPasses) { EXPECT_EQ(errorOf(kGood), ""); }

// Each wrong type is named by its glTF path, with what was expected and what was found.
TEST(GltfStructure, AWrongTypeNamesItsGltfPath) {
  auto with = [](const std::function<void(json&)>& edit) {
    json d = kGood;
    edit(d);
    return errorOf(d);
  };
  EXPECT_EQ(with([](json& d) { d["meshes"][0]["primitives"] = d["meshes"][0]["primitives"][0]; }),
            "f.gltf: meshes[0].primitives: expected an array, got an object; fix the exporter's output (the Khronos "
            "glTF validator shows every such error)");
  EXPECT_NE(with([](json& d) {
              d["nodes"][0]["translation"] = {0, 1};
            }).find("nodes[0].translation: expected an array of 3 numbers"),
            std::string::npos);
  EXPECT_NE(with([](json& d) {
              d["accessors"][0]["count"] = "3";
            }).find("accessors[0].count: expected a non-negative integer, got the string \"3\""),
            std::string::npos);
  EXPECT_NE(with([](json& d) {
              d["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = -1;
            }).find("meshes[0].primitives[0].attributes.POSITION: expected an accessor index, got -1"),
            std::string::npos);
  EXPECT_NE(with([](json& d) { d["scenes"][0]["nodes"] = 0; }).find("scenes[0].nodes: expected an array, got 0"),
            std::string::npos);
  EXPECT_NE(with([](json& d) { d["scene"] = 0.5; }).find("f.gltf: scene: expected a non-negative integer, got 0.5"),
            std::string::npos);
  EXPECT_NE(with([](json& d) { d["nodes"] = json::object(); }).find("f.gltf: nodes: expected an array, got an object"),
            std::string::npos);
}

json edited(const std::function<void(json&)>& edit) {
  json d = kGood;
  edit(d);
  return d;
}

// A name changes nothing drawn: one that is not a string is counted in one warning line, not refused.
TEST(GltfStructure, ANameThatIsNotAStringIsCountedNotRefused) {
  std::vector<std::string> warnings;
  const json d = edited([](json& x) {
    x["scenes"][0]["name"] = 7;
    x["nodes"][0]["name"] = json::array();
    x["accessors"][0]["name"] = "fine";
  });
  EXPECT_EQ(inputErrorOf([&] { warnings = checkGltfStructure(d, "f.gltf"); }), "");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0],
            "f.gltf: ignored 2 name(s) that are not strings (a name changes nothing drawn), first scenes[0].name (7)");
  EXPECT_TRUE(checkGltfStructure(kGood, "f.gltf").empty());
}

// What changes the image is refused when ill-typed: a texture transform, a light's numbers.
TEST(GltfStructure, AnIllTypedTextureTransformOrLightIsRefused) {
  auto transform = [](const json& t) {
    return edited([&](json& x) {
      x["materials"] = {{{"emissiveTexture", {{"index", 0}, {"extensions", {{"KHR_texture_transform", t}}}}}}};
    });
  };
  EXPECT_EQ(errorOf(transform({{"offset", {0.5, 0.5}}, {"scale", {2, 2}}, {"rotation", 1.5}, {"texCoord", 0}})), "");
  EXPECT_NE(errorOf(transform({{"offset", {0.5}}}))
                .find("materials[0].emissiveTexture.extensions.KHR_texture_transform.offset: expected an array of 2 "
                      "numbers, got an array"),
            std::string::npos);
  EXPECT_NE(errorOf(transform({{"scale", {"2", 2}}})).find("KHR_texture_transform.scale[0]: expected a number"),
            std::string::npos);
  EXPECT_NE(errorOf(transform({{"rotation", "1.5"}})).find("KHR_texture_transform.rotation: expected a number"),
            std::string::npos);
  EXPECT_NE(errorOf(transform({{"texCoord", -1}})).find("KHR_texture_transform.texCoord: expected a non-negative"),
            std::string::npos);

  auto light = [](const json& l) {
    return edited([&](json& x) { x["extensions"]["KHR_lights_punctual"]["lights"] = {l}; });
  };
  EXPECT_EQ(errorOf(light({{"type", "spot"}, {"color", {1, 1, 1}}, {"spot", {{"outerConeAngle", 0.5}}}})), "");
  EXPECT_NE(
      errorOf(light({{"type", "point"}, {"range", "5"}}))
          .find("f.gltf: extensions.KHR_lights_punctual.lights[0].range: expected a number, got the string \"5\""),
      std::string::npos);
  EXPECT_NE(errorOf(light({{"type", "point"}, {"color", {1, 1}}})).find("lights[0].color: expected an array of 3"),
            std::string::npos);
  EXPECT_NE(errorOf(light({{"type", "spot"}, {"spot", {{"innerConeAngle", true}}}}))
                .find("lights[0].spot.innerConeAngle: expected a number"),
            std::string::npos);
}

TEST(GltfStructure, Gltf1IsNamedAsGltf1WithHowToConvertIt) {
  auto refusal = [](const json& doc, const std::vector<uint8_t>& bytes = {}, bool binary = false) {
    return inputErrorOf([&] { refuseGltf1(doc, bytes, binary, "dir/box.gltf"); });
  };
  EXPECT_EQ(refusal(kGood), "");
  const std::string v1 = refusal(edited([](json& x) { x["asset"]["version"] = "1.0"; }));
  EXPECT_NE(v1.find("dir/box.gltf: is glTF 1.0 (asset.version \"1.0\"), which hybridbench does not read"),
            std::string::npos)
      << v1;
  EXPECT_NE(v1.find("gltf-pipeline -i box.gltf -o box-2.0.gltf"), std::string::npos) << v1;
  EXPECT_NE(refusal({{"scene", "defaultScene"}, {"scenes", {{"defaultScene", json::object()}}}}).find("glTF 1.0"),
            std::string::npos);
  const std::vector<uint8_t> header = {'g', 'l', 'T', 'F', 1, 0, 0, 0};
  EXPECT_NE(refusal(nullptr, header, true).find("binary glTF 1.0"), std::string::npos);
  EXPECT_EQ(refusal(nullptr, {'g', 'l', 'T', 'F', 2, 0, 0, 0}, true), "");
}

TEST(GltfStructure, AnExternalBufferThatIsNotThereIsNamedWithWhereItWasLookedFor) {
  const std::string dir = ::testing::TempDir();
  const json doc = edited([](json& x) {
    x["buffers"] = {{{"uri", "data:application/octet-stream;base64,AAAA"}, {"byteLength", 3}},
                    {{"uri", "no%20such.bin"}, {"byteLength", 4}}};
  });
  const std::string e = inputErrorOf([&] { checkExternalBuffers(doc, "f.gltf", dir); });
  EXPECT_NE(e.find("f.gltf: buffers[1].uri: the file \"no%20such.bin\" is not there (looked for "), std::string::npos)
      << e;
  EXPECT_NE(e.find("no such.bin); supply it"), std::string::npos) << e;
}

}  // namespace
}  // namespace hb::gltf_detail

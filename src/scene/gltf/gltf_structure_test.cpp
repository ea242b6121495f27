#include "scene/gltf/gltf_structure.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace hb::gltf_detail

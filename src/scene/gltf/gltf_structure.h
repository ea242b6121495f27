// The JSON types of the glTF 2.0 fields the loader reads, checked before tinygltf parses the file:
// tinygltf skips a field of the wrong type without a word (a "primitives" object gives a mesh of
// nothing), so a file that breaks the glTF schema this way loads as an empty scene. Each check
// names the field's glTF path, e.g. "meshes[0].primitives: expected an array, got an object".
#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace hb::gltf_detail {

// Throws InputError "<path>: <glTF path>: expected <type>, got <what>; <fix>" at the first field
// of the wrong type (glTF 2.0 schema: the top-level arrays, scene, scenes, nodes, meshes and their
// primitives, accessors, bufferViews, buffers, materials, textures, images, samplers, cameras).
// Fields the loader does not read (animations, skins) are checked only for being arrays.
void checkGltfStructure(const nlohmann::json& doc, const std::string& path);

}  // namespace hb::gltf_detail

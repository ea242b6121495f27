// What is checked of a glTF file before tinygltf parses it: that it is glTF 2.0 (a 1.0 file is
// refused as such, with how to convert it), the JSON types of the fields the loader reads
// (tinygltf skips a field of the wrong type without a word: a "primitives" object gives a mesh of
// nothing, so a file that breaks the glTF schema this way would load as an empty scene), and that
// the external files its buffers name are there. Each check names the field's glTF path, e.g.
// "meshes[0].primitives: expected an array, got an object".
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace hb::gltf_detail {

// Throws InputError "<path>: is glTF 1.0 ...; convert it to glTF 2.0 ..." when the file is glTF 1.0:
// a binary file whose header says version 1, or a JSON document whose asset.version is 1.x (or,
// without one, whose "scene" is a string or whose meshes are an object: 1.0's forms).
// `doc` is the file's JSON (null when it does not parse), `bytes` the file.
void refuseGltf1(const nlohmann::json& doc, std::span<const uint8_t> bytes, bool binary, const std::string& path);

// Throws InputError "<path>: <glTF path>: expected <type>, got <what>; <fix>" at the first field
// whose type changes what is drawn (glTF 2.0 schema: the top-level arrays, scene, scenes, nodes,
// meshes and their primitives, accessors, bufferViews, buffers, materials and their textures'
// KHR_texture_transform, textures, images, samplers, cameras, KHR_lights_punctual lights).
// Fields that change nothing drawn are not refused: a "name" that is not a string is ignored and
// counted in the one warning line returned (empty when there is none); accessors' min/max and
// bufferViews' target are not read. docs/usage.md "Loader strictness" lists each choice.
std::vector<std::string> checkGltfStructure(const nlohmann::json& doc, const std::string& path);

// Throws InputError "<path>: buffers[i].uri: the file "x.bin" is not there (looked for ...); put it
// ..." when a buffer names an external file (not a data: URI) that does not exist, relative to
// baseDir (the working directory when empty), its URI percent-decoded as tinygltf reads it.
void checkExternalBuffers(const nlohmann::json& doc, const std::string& path, const std::string& baseDir);

}  // namespace hb::gltf_detail

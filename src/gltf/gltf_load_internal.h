// Internals of loadGltf (gltf_io.h), shared by the files it is split into: the Loader declared
// here has its members defined by concern in gltf_io.cpp (entry, node graph, cameras, lights),
// gltf_accessors.cpp (accessor/bufferView validation and reading), gltf_meshes.cpp (primitives)
// and gltf_materials.cpp (images, textures, materials). Not for use outside those files.
#pragma once
#include <tiny_gltf.h>

#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <initializer_list>
#include <map>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "gltf/gltf_io.h"

namespace hb::gltf_detail {

// tinygltf's image loader callback (userData = the tinygltf::Model being parsed): fails with a
// message naming the image if its bufferView lies outside its buffer, else decodes to RGBA.
bool checkedImageLoader(tinygltf::Image* image, const int imageIndex, std::string* err, std::string* warn, int width,
                        int height, const unsigned char* bytes, int size, void* userData);

// A validated accessor: `count` elements of `elementSize` bytes, `stride` apart from `data`.
// The file's extensions against what the loader reads (gltf_extensions.cpp): an unknown required
// one is an InputError naming it; optional ones the loader ignores go into one warning line.
void checkExtensions(const tinygltf::Model& model, const std::string& path, GltfLoadWarnings& warnings);

// ---- compressed geometry (gltf_compression.cpp) ----
// What prepareCompressed changed in a file so that tinygltf parses it, for decodeCompressed.
struct CompressedInput {
  std::vector<uint8_t> bytes;                             // the file to parse instead; empty: the file as it is
  std::map<size_t, uint64_t> fallbackBuffers;             // EXT_meshopt_compression fallback buffer → byteLength
  std::map<std::pair<size_t, size_t>, int> dracoIndices;  // (mesh, primitive) of a Draco one → indices accessor
};
// `doc` is the file's JSON (null when it does not parse: nothing changes); `bytes` the file.
CompressedInput prepareCompressed(const nlohmann::json& doc, std::span<const uint8_t> bytes, bool binary);
// Decodes every EXT_meshopt_compression bufferView into its buffer and every Draco primitive into
// plain accessors (its indices restored from `input`), so that the Loader reads them as any
// others. Returns the compression extensions the file used, comma-joined ("" when none). Throws
// InputError (file, mesh, extension, what does not decode) on a truncated or corrupt stream.
std::string decodeCompressed(tinygltf::Model& model, const CompressedInput& input, const std::string& path);

struct AccessorView {
  const uint8_t* data = nullptr;
  size_t count = 0;
  size_t stride = 0;
  size_t elementSize = 0;
  int componentType = 0;
  bool normalized = false;  // integer components map to [0, 1] or [-1, 1] (glTF 2.0 §3.11)
};

// Converts one parsed tinygltf::Model into an hb::Scene, checking every index and byte range it
// reads. `model` and `rawLights` must outlive the Loader; load() is called once.
class Loader {
 public:
  Loader(std::string path, const tinygltf::Model& model, const nlohmann::json& rawLights)
      : path_(std::move(path)), model_(model), rawLights_(rawLights) {}

  Scene load(GltfLoadWarnings& warnings);

 private:
  // ---- errors (gltf_io.cpp) ----
  [[noreturn]] void fail(const std::string& field, const std::string& problem, const std::string& fix) const;
  // A scene with no triangles: an InputError naming why (no scenes or nodes, a scene without
  // nodes, nodes without meshes).
  [[noreturn]] void refuseEmptyScene() const;
  // One warning line naming the skins, morph targets and animations that are not read, if any.
  void warnIgnoredAnimation(GltfLoadWarnings& warnings) const;
  // Checks that `index` names an element of an array of `size` (the array `arrayName` at top
  // level) and returns it as size_t.
  size_t checkIndex(int index, size_t size, const std::string& field, const std::string& arrayName) const;

  // ---- accessors (gltf_accessors.cpp) ----
  // Validates accessor `index` for `field`: its type must be `type` (TINYGLTF_TYPE_*), its
  // component type one of `componentTypes`, and the glTF spec's byte range
  //   accessor.byteOffset + stride * (count - 1) + elementSize <= bufferView.byteLength,
  //   bufferView.byteOffset + bufferView.byteLength <= buffer size
  // must hold, all in 64-bit arithmetic after bounding count so nothing can overflow.
  AccessorView accessor(int index, const std::string& field, int type, std::initializer_list<int> componentTypes) const;
  // Reads float or integer vectors, normalized or not (KHR_mesh_quantization; instantiated for
  // N = 2 and 3).
  template <int N>
  std::vector<glm::vec<N, float>> readVectors(const AccessorView& view) const;
  // Reads unsigned byte/short/int indices.
  std::vector<uint32_t> readIndices(const AccessorView& view) const;

  // ---- textures and materials (gltf_materials.cpp) ----
  void loadTextures();
  int textureIndex(const tinygltf::TextureInfo& info, const std::string& field) const;
  void loadMaterials();
  // The "default" material for primitives without one, appended on first use.
  uint32_t defaultMaterial();
  void markSrgbTextures();

  // ---- meshes (gltf_meshes.cpp) ----
  // A primitive's vertices and indices, read and checked, before they join the scene.
  struct PrimitiveData {
    std::vector<glm::vec3> positions, normals;
    std::vector<glm::vec2> uvs;  // empty: no TEXCOORD_0
    std::vector<uint32_t> indices;
    int material = -1;  // a checked index into the file's materials; -1: the "default" one
  };
  // Appends the mesh; a primitive whose data is broken is skipped and counted (its InputError kept).
  void loadMesh(int meshIndex);
  // Throws InputError when the primitive's data is broken: no POSITION, an accessor that does not
  // fit its buffer, counts that differ, an index past its vertices, a count that makes no triangles.
  PrimitiveData readPrimitive(const tinygltf::Primitive& prim, const std::string& field) const;
  // Appends it to the scene's shared arrays (InputError past 2^32 vertices or indices).
  Primitive appendPrimitive(const PrimitiveData& data, const std::string& field);

  // ---- nodes, cameras, lights (gltf_io.cpp) ----
  void loadNodes();
  glm::dmat4 localTransform(const tinygltf::Node& node, const std::string& field) const;
  void visitNode(int nodeIndex, const glm::dmat4& parent, int depth);
  void addCamera(size_t c, const glm::dmat4& world);
  void addLight(size_t l, const glm::dmat4& world);

  std::string path_;
  const tinygltf::Model& model_;
  const nlohmann::json& rawLights_;
  GltfLoadWarnings* warnings_ = nullptr;
  Scene scene_;
  int defaultMaterial_ = -1;
  std::vector<int> textureSlot_;  // glTF texture → Scene::textures index; -1: not decoded (KTX2, WebP, AVIF)
  std::string firstSkippedPrimitive_, firstSkippedCamera_;
  std::string firstBrokenPrimitive_;  // its InputError's message, and the mesh's name
  std::string firstBrokenMesh_;
  std::vector<uint8_t> onPath_;
};

}  // namespace hb::gltf_detail

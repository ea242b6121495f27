// glTF 2.0 loading (tinygltf parses, this file validates and converts). tinygltf checks the JSON
// structure but not that accessors fit their buffers or that indices fit their vertices, so every
// byte range and index is checked here before it is read.
#include "gltf_io.h"

#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <iostream>
#include <limits>
#include <sstream>

#include "errors.h"

namespace hb {
namespace {

constexpr const char* kLightsExtension = "KHR_lights_punctual";
constexpr float kDefaultZfar = 1000.0f;  // used when a perspective camera has no zfar
// A light of zero intensity gets range 0 from eq. 4.1; it lights nothing, but range > 0 must hold.
constexpr float kMinEq41Range = 1e-3f;
constexpr int kMaxNodeDepth = 1024;  // deeper than any real hierarchy; guards the recursion

// tinygltf's messages end in newlines and may hold several lines; an InputError is one line.
std::string oneLine(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '\n' || c == '\r') {
      if (!out.empty() && out.back() != ' ') out += "; ";
    } else {
      out += c;
    }
  }
  while (!out.empty() && (out.back() == ' ' || out.back() == ';')) out.pop_back();
  return out;
}

std::string componentTypeName(int componentType) {
  const char* name = "unknown";
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      name = "BYTE";
      break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      name = "UNSIGNED_BYTE";
      break;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      name = "SHORT";
      break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      name = "UNSIGNED_SHORT";
      break;
    case TINYGLTF_COMPONENT_TYPE_INT:
      name = "INT";
      break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      name = "UNSIGNED_INT";
      break;
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      name = "FLOAT";
      break;
    case TINYGLTF_COMPONENT_TYPE_DOUBLE:
      name = "DOUBLE";
      break;
  }
  return std::to_string(componentType) + " (" + name + ")";
}

std::string num(double v) {  // shortest readable form: 5, -2, 0.25, 1e+30, nan
  std::ostringstream s;
  s << v;
  return s.str();
}

// tinygltf hands an image stored in a bufferView to its decoder without checking that the view
// lies inside its buffer; this loader checks first (the buffers are parsed before the images),
// then decodes with tinygltf's stb loader, which expands every image to RGBA.
bool checkedImageLoader(tinygltf::Image* image, const int imageIndex, std::string* err,
                        std::string* warn, int width, int height, const unsigned char* bytes,
                        int size, void* userData) {
  const auto* model = static_cast<const tinygltf::Model*>(userData);
  if (image->bufferView >= 0) {
    const tinygltf::BufferView& view = model->bufferViews[static_cast<size_t>(image->bufferView)];
    const tinygltf::Buffer& buffer = model->buffers[static_cast<size_t>(view.buffer)];
    if (static_cast<uint64_t>(view.byteOffset) + view.byteLength > buffer.data.size()) {
      *err += "images[" + std::to_string(imageIndex) + "].bufferView: bufferViews[" +
              std::to_string(image->bufferView) + "] ends past the end of buffers[" +
              std::to_string(view.buffer) + "] (" + std::to_string(buffer.data.size()) + " bytes)";
      return false;
    }
  }
  return tinygltf::LoadImageData(image, imageIndex, err, warn, width, height, bytes, size, nullptr);
}

// A validated accessor: `count` elements of `elementSize` bytes, `stride` apart from `data`.
struct AccessorView {
  const uint8_t* data = nullptr;
  size_t count = 0;
  size_t stride = 0;
  size_t elementSize = 0;
  int componentType = 0;
};

class Loader {
 public:
  Loader(std::string path, const tinygltf::Model& model, const nlohmann::json& rawLights)
      : path_(std::move(path)), model_(model), rawLights_(rawLights) {}

  Scene load(GltfLoadWarnings& warnings) {
    warnings_ = &warnings;
    loadTextures();
    loadMaterials();
    for (size_t m = 0; m < model_.meshes.size(); ++m) loadMesh(static_cast<int>(m));
    loadNodes();
    markSrgbTextures();
    if (warnings.skippedPrimitives > 0)
      warnings.messages.push_back(
          path_ + ": skipped " + std::to_string(warnings.skippedPrimitives) +
          " primitive(s) whose mode is not TRIANGLES (4), first " + firstSkippedPrimitive_);
    if (warnings.skippedCameras > 0)
      warnings.messages.push_back(path_ + ": skipped " + std::to_string(warnings.skippedCameras) +
                                  " camera node(s) that are not perspective, first " +
                                  firstSkippedCamera_);
    return std::move(scene_);
  }

 private:
  [[noreturn]] void fail(const std::string& field, const std::string& problem,
                         const std::string& fix) const {
    throw InputError(path_ + ": " + field + ": " + problem + "; " + fix);
  }

  // Checks that `index` names an element of an array of `size` (the array `arrayName` at top
  // level) and returns it as size_t.
  size_t checkIndex(int index, size_t size, const std::string& field,
                    const std::string& arrayName) const {
    if (index < 0 || static_cast<size_t>(index) >= size)
      fail(field,
           "index " + std::to_string(index) + " does not exist (" + arrayName + " has " +
               std::to_string(size) + " elements)",
           "point it at an existing element of " + arrayName);
    return static_cast<size_t>(index);
  }

  // ---- accessors -------------------------------------------------------------------------------

  // Validates accessor `index` for `field`: its type must be `type` (TINYGLTF_TYPE_*), its
  // component type one of `componentTypes`, and the glTF spec's byte range
  //   accessor.byteOffset + stride * (count - 1) + elementSize <= bufferView.byteLength,
  //   bufferView.byteOffset + bufferView.byteLength <= buffer size
  // must hold, all in 64-bit arithmetic after bounding count so nothing can overflow.
  AccessorView accessor(int index, const std::string& field, int type,
                        std::initializer_list<int> componentTypes) const {
    size_t a = checkIndex(index, model_.accessors.size(), field, "accessors");
    const tinygltf::Accessor& acc = model_.accessors[a];
    const std::string where = field + " (accessors[" + std::to_string(a) + "])";
    if (acc.sparse.isSparse)
      fail(where, "sparse accessors are not supported", "write the data densely");
    if (acc.type != type)
      fail(where,
           "type is " + std::to_string(acc.type) + ", expected " + std::to_string(type) +
               " (tinygltf TINYGLTF_TYPE_* code)",
           "store this attribute with the type the glTF spec requires");
    bool supported = false;
    std::string allowed;
    for (int ct : componentTypes) {
      supported |= ct == acc.componentType;
      allowed += (allowed.empty() ? "" : " or ") + componentTypeName(ct);
    }
    if (!supported)
      fail(where, "unsupported componentType " + componentTypeName(acc.componentType),
           "store it as " + allowed);
    if (acc.count == 0) fail(where, "count is 0", "give the accessor at least one element");
    if (acc.bufferView < 0)
      fail(where, "has no bufferView (an all-zero accessor)", "give it a bufferView with data");
    size_t v =
        checkIndex(acc.bufferView, model_.bufferViews.size(), where + ".bufferView", "bufferViews");
    const tinygltf::BufferView& view = model_.bufferViews[v];
    size_t b = checkIndex(view.buffer, model_.buffers.size(),
                          "bufferViews[" + std::to_string(v) + "].buffer", "buffers");
    const tinygltf::Buffer& buffer = model_.buffers[b];

    const uint64_t elementSize =
        static_cast<uint64_t>(
            tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(acc.componentType))) *
        static_cast<uint64_t>(tinygltf::GetNumComponentsInType(static_cast<uint32_t>(acc.type)));
    const uint64_t stride = view.byteStride != 0 ? view.byteStride : elementSize;
    if (stride < elementSize)
      fail("bufferViews[" + std::to_string(v) + "].byteStride",
           "stride " + std::to_string(stride) + " is smaller than the " +
               std::to_string(elementSize) + "-byte elements of " + where,
           "set byteStride to 0 or at least " + std::to_string(elementSize));
    const uint64_t viewEnd = static_cast<uint64_t>(view.byteOffset) + view.byteLength;
    if (viewEnd > buffer.data.size())
      fail("bufferViews[" + std::to_string(v) + "] (read by " + where + ")",
           "ends at byte " + std::to_string(viewEnd) + " but buffers[" + std::to_string(b) +
               "] holds only " + std::to_string(buffer.data.size()) + " bytes",
           "fix byteOffset/byteLength or supply the whole buffer");
    // count <= byteLength + 1 bounds stride * (count - 1) below 2^8 * 2^64 / 2^8: no overflow.
    const bool countFits = acc.count <= view.byteLength + 1;
    const uint64_t need =
        countFits ? acc.byteOffset + stride * (acc.count - 1) + elementSize : ~uint64_t(0);
    if (!countFits || need > view.byteLength)
      fail(where,
           std::to_string(acc.count) + " elements from byteOffset " +
               std::to_string(acc.byteOffset) + " with stride " + std::to_string(stride) +
               " need " + (countFits ? std::to_string(need) : std::string("more")) +
               " bytes but bufferViews[" + std::to_string(v) + "] has only " +
               std::to_string(view.byteLength),
           "fix the accessor's count/byteOffset or make the bufferView and buffer longer");
    AccessorView out;
    out.data = buffer.data.data() + view.byteOffset + acc.byteOffset;
    out.count = acc.count;
    out.stride = stride;
    out.elementSize = elementSize;
    out.componentType = acc.componentType;
    return out;
  }

  static float readComponent(const uint8_t* p, int componentType) {
    switch (componentType) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: {
        float f;
        std::memcpy(&f, p, 4);
        return f;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return static_cast<float>(*p) / 255.0f;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t u;
        std::memcpy(&u, p, 2);
        return static_cast<float>(u) / 65535.0f;
      }
      default:
        HB_ASSERT(false);
    }
  }

  template <int N>
  std::vector<glm::vec<N, float>> readVectors(const AccessorView& view) const {
    std::vector<glm::vec<N, float>> out(view.count);
    const size_t componentSize = view.elementSize / N;
    for (size_t i = 0; i < view.count; ++i)
      for (int c = 0; c < N; ++c)
        out[i][c] =
            readComponent(view.data + i * view.stride + c * componentSize, view.componentType);
    return out;
  }

  std::vector<uint32_t> readIndices(const AccessorView& view) const {
    std::vector<uint32_t> out(view.count);
    for (size_t i = 0; i < view.count; ++i) {
      const uint8_t* p = view.data + i * view.stride;
      if (view.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
        out[i] = *p;
      } else if (view.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
        uint16_t u;
        std::memcpy(&u, p, 2);
        out[i] = u;
      } else {
        std::memcpy(&out[i], p, 4);
      }
    }
    return out;
  }

  // ---- textures and materials ------------------------------------------------------------------

  void loadTextures() {
    for (size_t t = 0; t < model_.textures.size(); ++t) {
      const tinygltf::Texture& tex = model_.textures[t];
      const std::string field = "textures[" + std::to_string(t) + "].source";
      if (tex.source < 0)
        fail(field, "the texture has no PNG/JPEG source image (only extension sources?)",
             "give it a source image that stb can decode (PNG or JPEG)");
      size_t i = checkIndex(tex.source, model_.images.size(), field, "images");
      const tinygltf::Image& image = model_.images[i];
      const std::string imageField = "images[" + std::to_string(i) + "]";
      const size_t pixels = static_cast<size_t>(std::max(image.width, 0)) *
                            static_cast<size_t>(std::max(image.height, 0));
      const size_t bytesPerChannel = image.bits == 16 ? 2 : 1;
      if (pixels == 0 || image.component < 1 || image.component > 4 ||
          (image.bits != 8 && image.bits != 16) ||
          image.image.size() < pixels * image.component * bytesPerChannel)
        fail(imageField, "image '" + image.uri.substr(0, 64) + "' was not found or not decoded",
             "put the image file next to the .gltf or embed it as PNG/JPEG");
      Texture out;
      out.name = !tex.name.empty() ? tex.name : image.name;
      out.width = static_cast<uint32_t>(image.width);
      out.height = static_cast<uint32_t>(image.height);
      out.rgba.resize(pixels * 4);
      for (size_t p = 0; p < pixels; ++p) {
        uint8_t channel[4] = {0, 0, 0, 255};
        for (int c = 0; c < image.component; ++c) {
          const size_t at = (p * image.component + c) * bytesPerChannel;
          if (bytesPerChannel == 1) {
            channel[c] = image.image[at];
          } else {
            uint16_t u;
            std::memcpy(&u, &image.image[at], 2);
            channel[c] = static_cast<uint8_t>((u * 255u + 32767u) / 65535u);  // round to nearest
          }
        }
        if (image.component <= 2) {  // grey or grey+alpha: replicate grey, move alpha to A
          channel[3] = image.component == 2 ? channel[1] : 255;
          channel[1] = channel[2] = channel[0];
        }
        std::memcpy(&out.rgba[p * 4], channel, 4);
      }
      scene_.textures.push_back(std::move(out));
    }
  }

  int textureIndex(const tinygltf::TextureInfo& info, const std::string& field) const {
    if (info.index < 0) return -1;
    return static_cast<int>(checkIndex(info.index, model_.textures.size(), field, "textures"));
  }

  void loadMaterials() {
    for (size_t m = 0; m < model_.materials.size(); ++m) {
      const tinygltf::Material& mat = model_.materials[m];
      const std::string field = "materials[" + std::to_string(m) + "].pbrMetallicRoughness";
      const tinygltf::PbrMetallicRoughness& pbr = mat.pbrMetallicRoughness;
      Material out;
      out.name = mat.name;
      if (pbr.baseColorFactor.size() != 4)
        fail(field + ".baseColorFactor",
             "has " + std::to_string(pbr.baseColorFactor.size()) + " numbers", "give it 4 (RGBA)");
      for (int c = 0; c < 4; ++c)
        out.baseColorFactor[c] = static_cast<float>(pbr.baseColorFactor[c]);
      out.metallicFactor = static_cast<float>(pbr.metallicFactor);
      out.roughnessFactor = static_cast<float>(pbr.roughnessFactor);
      if (!std::isfinite(out.metallicFactor) || !std::isfinite(out.roughnessFactor) ||
          !std::isfinite(glm::dot(out.baseColorFactor, out.baseColorFactor)))
        fail(field, "a factor is not a finite number", "write factors as numbers in [0, 1]");
      out.baseColorTexture = textureIndex(pbr.baseColorTexture, field + ".baseColorTexture.index");
      out.metallicRoughnessTexture =
          textureIndex(pbr.metallicRoughnessTexture, field + ".metallicRoughnessTexture.index");
      out.doubleSided = mat.doubleSided;
      scene_.materials.push_back(std::move(out));
    }
  }

  uint32_t defaultMaterial() {
    if (defaultMaterial_ < 0) {
      defaultMaterial_ = static_cast<int>(scene_.materials.size());
      Material mat;
      mat.name = "default";
      scene_.materials.push_back(mat);
    }
    return static_cast<uint32_t>(defaultMaterial_);
  }

  void markSrgbTextures() {
    for (const Material& m : scene_.materials)
      if (m.baseColorTexture >= 0)
        scene_.textures[static_cast<size_t>(m.baseColorTexture)].srgb = true;
  }

  // ---- meshes ----------------------------------------------------------------------------------

  void loadMesh(int meshIndex) {
    const tinygltf::Mesh& mesh = model_.meshes[static_cast<size_t>(meshIndex)];
    Mesh out;
    out.name = mesh.name;
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
      const std::string field =
          "meshes[" + std::to_string(meshIndex) + "].primitives[" + std::to_string(p) + "]";
      const tinygltf::Primitive& prim = mesh.primitives[p];
      if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES) {
        if (warnings_->skippedPrimitives++ == 0)
          firstSkippedPrimitive_ = field + " (mode " + std::to_string(prim.mode) + ")";
        continue;
      }
      out.primitives.push_back(loadPrimitive(prim, field));
    }
    scene_.meshes.push_back(std::move(out));
  }

  Primitive loadPrimitive(const tinygltf::Primitive& prim, const std::string& field) {
    auto attribute = [&](const char* name) {
      auto it = prim.attributes.find(name);
      return it == prim.attributes.end() ? -1 : it->second;
    };
    const int positionAccessor = attribute("POSITION");
    if (positionAccessor < 0)
      fail(field + ".attributes", "has no POSITION", "give every primitive a POSITION accessor");
    const std::string positionField = field + ".attributes.POSITION";
    std::vector<glm::vec3> positions = readVectors<3>(accessor(
        positionAccessor, positionField, TINYGLTF_TYPE_VEC3, {TINYGLTF_COMPONENT_TYPE_FLOAT}));
    for (size_t i = 0; i < positions.size(); ++i)
      if (!std::isfinite(positions[i].x) || !std::isfinite(positions[i].y) ||
          !std::isfinite(positions[i].z))
        fail(positionField, "vertex " + std::to_string(i) + " is not finite (NaN or Inf)",
             "re-export the mesh with finite positions");
    const size_t vertexCount = positions.size();

    std::vector<glm::vec3> normals;
    if (int a = attribute("NORMAL"); a >= 0) {
      normals = readVectors<3>(accessor(a, field + ".attributes.NORMAL", TINYGLTF_TYPE_VEC3,
                                        {TINYGLTF_COMPONENT_TYPE_FLOAT}));
      if (normals.size() != vertexCount)
        fail(field + ".attributes.NORMAL",
             "count " + std::to_string(normals.size()) + " differs from POSITION's " +
                 std::to_string(vertexCount),
             "give every attribute of a primitive the same count");
    }
    std::vector<glm::vec2> uvs;
    if (int a = attribute("TEXCOORD_0"); a >= 0) {
      // The spec allows normalized unsigned byte/short texture coordinates besides float.
      uvs = readVectors<2>(
          accessor(a, field + ".attributes.TEXCOORD_0", TINYGLTF_TYPE_VEC2,
                   {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                    TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT}));
      if (uvs.size() != vertexCount)
        fail(field + ".attributes.TEXCOORD_0",
             "count " + std::to_string(uvs.size()) + " differs from POSITION's " +
                 std::to_string(vertexCount),
             "give every attribute of a primitive the same count");
    }

    std::vector<uint32_t> indices;
    const std::string indicesField = field + ".indices";
    if (prim.indices >= 0) {
      indices = readIndices(
          accessor(prim.indices, indicesField, TINYGLTF_TYPE_SCALAR,
                   {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                    TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT}));
      for (size_t i = 0; i < indices.size(); ++i)
        if (indices[i] >= vertexCount)
          fail(indicesField,
               "index " + std::to_string(i) + " is " + std::to_string(indices[i]) +
                   " but the primitive has only " + std::to_string(vertexCount) + " vertices",
               "fix the index buffer or the POSITION accessor's count");
    } else {
      indices.resize(vertexCount);
      for (size_t i = 0; i < vertexCount; ++i) indices[i] = static_cast<uint32_t>(i);
    }
    if (indices.size() % 3 != 0)
      fail(prim.indices >= 0 ? indicesField : positionField,
           std::to_string(indices.size()) + " vertices do not make whole triangles",
           "give TRIANGLES primitives a multiple of 3 indices (or vertices)");
    if (normals.empty()) normals = areaWeightedNormals(positions, indices);

    Primitive out;
    if (scene_.vertices.size() + vertexCount > std::numeric_limits<uint32_t>::max() ||
        scene_.indices.size() + indices.size() > std::numeric_limits<uint32_t>::max())
      fail(field, "the scene exceeds 2^32 vertices or indices", "split or simplify the scene");
    out.firstIndex = static_cast<uint32_t>(scene_.indices.size());
    out.indexCount = static_cast<uint32_t>(indices.size());
    out.vertexOffset = static_cast<uint32_t>(scene_.vertices.size());
    out.vertexCount = static_cast<uint32_t>(vertexCount);
    out.material = prim.material >= 0
                       ? static_cast<uint32_t>(checkIndex(prim.material, model_.materials.size(),
                                                          field + ".material", "materials"))
                       : defaultMaterial();
    for (size_t i = 0; i < vertexCount; ++i)
      scene_.vertices.push_back({positions[i], normals[i], uvs.empty() ? glm::vec2(0.0f) : uvs[i]});
    scene_.indices.insert(scene_.indices.end(), indices.begin(), indices.end());
    return out;
  }

  // Smooth normals: each vertex sums the unnormalised face normals (cross products, whose length
  // is twice the triangle's area, hence area-weighted) of the triangles around it. A vertex with
  // only degenerate triangles gets +Z so that the normal is always unit.
  static std::vector<glm::vec3> areaWeightedNormals(const std::vector<glm::vec3>& positions,
                                                    const std::vector<uint32_t>& indices) {
    std::vector<glm::dvec3> sum(positions.size(), glm::dvec3(0.0));
    for (size_t t = 0; t + 2 < indices.size(); t += 3) {
      glm::dvec3 a(positions[indices[t]]), b(positions[indices[t + 1]]),
          c(positions[indices[t + 2]]);
      glm::dvec3 n = glm::cross(b - a, c - a);
      for (int k = 0; k < 3; ++k) sum[indices[t + k]] += n;
    }
    std::vector<glm::vec3> out(positions.size());
    for (size_t i = 0; i < sum.size(); ++i) {
      double len = glm::length(sum[i]);
      out[i] = len > 0.0 ? glm::vec3(sum[i] / len) : glm::vec3(0.0f, 0.0f, 1.0f);
    }
    return out;
  }

  // ---- nodes, cameras, lights ------------------------------------------------------------------

  void loadNodes() {
    std::vector<int> roots;
    if (!model_.scenes.empty()) {
      int s = model_.defaultScene >= 0 ? model_.defaultScene : 0;
      const tinygltf::Scene& gscene =
          model_.scenes[checkIndex(s, model_.scenes.size(), "scene", "scenes")];
      roots = gscene.nodes;
      scene_.name = gscene.name;
      for (size_t r = 0; r < roots.size(); ++r)
        checkIndex(roots[r], model_.nodes.size(),
                   "scenes[" + std::to_string(s) + "].nodes[" + std::to_string(r) + "]", "nodes");
    } else {  // no scene: every node that is nobody's child
      std::vector<uint8_t> isChild(model_.nodes.size(), 0);
      for (size_t n = 0; n < model_.nodes.size(); ++n)
        for (size_t c = 0; c < model_.nodes[n].children.size(); ++c)
          isChild[checkIndex(model_.nodes[n].children[c], model_.nodes.size(),
                             "nodes[" + std::to_string(n) + "].children[" + std::to_string(c) + "]",
                             "nodes")] = 1;
      for (size_t n = 0; n < model_.nodes.size(); ++n)
        if (!isChild[n]) roots.push_back(static_cast<int>(n));
    }
    onPath_.assign(model_.nodes.size(), 0);
    for (int root : roots) visitNode(root, glm::dmat4(1.0), 0);
  }

  glm::dmat4 localTransform(const tinygltf::Node& node, const std::string& field) const {
    glm::dmat4 local(1.0);
    if (!node.matrix.empty()) {
      if (node.matrix.size() != 16)
        fail(field + ".matrix", "has " + std::to_string(node.matrix.size()) + " numbers",
             "give it 16 (column-major)");
      local = glm::make_mat4(node.matrix.data());  // glTF and glm are both column-major
    } else {
      auto need = [&](const std::vector<double>& v, size_t n, const char* name) {
        if (!v.empty() && v.size() != n)
          fail(field + "." + name, "has " + std::to_string(v.size()) + " numbers",
               "give it " + std::to_string(n));
        return !v.empty();
      };
      glm::dmat4 t(1.0), r(1.0), s(1.0);
      if (need(node.translation, 3, "translation"))
        t = glm::translate(glm::dmat4(1.0), glm::make_vec3(node.translation.data()));
      if (need(node.rotation, 4,
               "rotation"))  // glTF stores x, y, z, w; glm's constructor takes w first
        r = glm::mat4_cast(
            glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
      if (need(node.scale, 3, "scale"))
        s = glm::scale(glm::dmat4(1.0), glm::make_vec3(node.scale.data()));
      local = t * r * s;
    }
    for (int c = 0; c < 4; ++c)
      for (int k = 0; k < 4; ++k)
        if (!std::isfinite(local[c][k]))
          fail(field, "the transform is not finite", "write finite matrix/TRS numbers");
    return local;
  }

  void visitNode(int nodeIndex, const glm::dmat4& parent, int depth) {
    const std::string field = "nodes[" + std::to_string(nodeIndex) + "]";
    const size_t n = checkIndex(nodeIndex, model_.nodes.size(), field, "nodes");
    if (onPath_[n] || depth > kMaxNodeDepth)
      fail(field + ".children",
           "the node hierarchy has a cycle (or is deeper than " + std::to_string(kMaxNodeDepth) +
               ")",
           "make the nodes a tree: no node may be its own ancestor");
    const tinygltf::Node& node = model_.nodes[n];
    const glm::dmat4 world = parent * localTransform(node, field);
    if (node.mesh >= 0) {
      Instance inst;
      inst.mesh = static_cast<uint32_t>(
          checkIndex(node.mesh, model_.meshes.size(), field + ".mesh", "meshes"));
      inst.transform = glm::mat4(world);
      scene_.instances.push_back(inst);
    }
    if (node.camera >= 0)
      addCamera(checkIndex(node.camera, model_.cameras.size(), field + ".camera", "cameras"),
                world);
    if (auto it = node.extensions.find(kLightsExtension); it != node.extensions.end()) {
      const std::string lightField = field + ".extensions." + kLightsExtension + ".light";
      if (!it->second.IsObject() || !it->second.Get("light").IsNumber())
        fail(lightField, "missing or not an integer", "write {\"light\": <index>}");
      size_t l = checkIndex(it->second.Get("light").GetNumberAsInt(), model_.lights.size(),
                            lightField, std::string("extensions.") + kLightsExtension + ".lights");
      addLight(l, world);
    }
    onPath_[n] = 1;
    for (int child : node.children) visitNode(child, world, depth + 1);
    onPath_[n] = 0;
  }

  void addCamera(size_t c, const glm::dmat4& world) {
    const tinygltf::Camera& cam = model_.cameras[c];
    const std::string field = "cameras[" + std::to_string(c) + "]";
    if (cam.type != "perspective") {
      if (warnings_->skippedCameras++ == 0) firstSkippedCamera_ = field + " (" + cam.type + ")";
      return;
    }
    const tinygltf::PerspectiveCamera& p = cam.perspective;
    if (!(p.yfov > 0.0 && p.yfov < glm::pi<double>()))
      fail(field + ".perspective.yfov", "is " + num(p.yfov),
           "give a field of view in (0, pi) radians");
    if (!(p.znear > 0.0 && std::isfinite(p.znear)))
      fail(field + ".perspective.znear", "is " + num(p.znear), "give a positive near distance");
    if (p.zfar != 0.0 && !(p.zfar > p.znear && std::isfinite(p.zfar)))  // tinygltf: 0 = absent
      fail(field + ".perspective.zfar", "is " + num(p.zfar) + ", not beyond znear",
           "give a far distance greater than znear or leave it out");
    Camera out;
    out.name = cam.name;
    // Inverted in double: the result is within a few double ulps of the exact inverse, so it
    // rounds to the float a float inverse would only approximate.
    out.view = glm::mat4(glm::inverse(world));
    out.yfov = static_cast<float>(p.yfov);
    out.znear = static_cast<float>(p.znear);
    out.zfar = p.zfar != 0.0 ? static_cast<float>(p.zfar) : kDefaultZfar;
    scene_.cameras.push_back(out);
  }

  void addLight(size_t l, const glm::dmat4& world) {
    const tinygltf::Light& light = model_.lights[l];
    const std::string field =
        std::string("extensions.") + kLightsExtension + ".lights[" + std::to_string(l) + "]";
    const nlohmann::json* raw =
        rawLights_.is_array() && l < rawLights_.size() && rawLights_[l].is_object() ? &rawLights_[l]
                                                                                    : nullptr;
    Light out;
    out.name = light.name;
    if (light.type == "point")
      out.type = LightType::Point;
    else if (light.type == "spot")
      out.type = LightType::Spot;
    else if (light.type == "directional")
      out.type = LightType::Directional;
    else
      fail(field + ".type", "'" + light.type + "' is not a punctual light type",
           "use point, spot or directional");
    if (!light.color.empty()) {
      if (light.color.size() != 3)
        fail(field + ".color", "has " + std::to_string(light.color.size()) + " numbers",
             "give it 3 (linear RGB)");
      out.color = glm::vec3(glm::make_vec3(light.color.data()));
    }
    if (!(light.intensity >= 0.0 && std::isfinite(light.intensity)))
      fail(field + ".intensity", "is " + num(light.intensity), "give a finite intensity >= 0");
    out.intensity = static_cast<float>(light.intensity);
    // tinygltf reads a missing range as 0, so whether it was written comes from the raw JSON.
    const bool hasRange = raw != nullptr && raw->contains("range");
    if (hasRange && !(light.range > 0.0 && std::isfinite(light.range)))
      fail(field + ".range", "is " + num(light.range) + " but must be > 0",
           "give a positive range in metres or leave it out (then thesis eq. 4.1 sets it)");
    if (out.type == LightType::Directional) {
      out.range = 0.0f;  // a directional light reaches everywhere
    } else if (hasRange) {
      out.range = static_cast<float>(light.range);
    } else {
      out.range = std::max(static_cast<float>(rangeFromIntensity(light.intensity)), kMinEq41Range);
      out.rangeFromEq41 = true;
    }
    if (out.type == LightType::Spot) {
      const double inner = light.spot.innerConeAngle, outer = light.spot.outerConeAngle;
      if (!(inner >= 0.0 && inner < outer && outer <= glm::half_pi<double>()))
        fail(field + ".spot",
             "cone angles inner " + num(inner) + ", outer " + num(outer) + " are invalid",
             "use 0 <= innerConeAngle < outerConeAngle <= pi/2");
      out.innerConeAngle = static_cast<float>(inner);
      out.outerConeAngle = static_cast<float>(outer);
    }
    if (light.extras.IsObject()) {
      if (light.extras.Has("castShadows")) {
        if (!light.extras.Get("castShadows").IsBool())
          fail(field + ".extras.castShadows", "is not true/false", "write true or false");
        out.castShadows = light.extras.Get("castShadows").Get<bool>();
      }
      // Written by exportGltf: the explicit range was derived from eq. 4.1 originally.
      if (hasRange && light.extras.Has("rangeFromEq41") &&
          light.extras.Get("rangeFromEq41").IsBool())
        out.rangeFromEq41 = light.extras.Get("rangeFromEq41").Get<bool>();
    }
    out.position = glm::vec3(world[3]);
    const glm::dvec3 forward = -glm::dvec3(world[2]);  // world * (0, 0, -1, 0)
    const double len = glm::length(forward);
    if (!(len > 0.0))
      fail("nodes (of " + field + ")", "the node's transform collapses its -Z axis",
           "give the light's node a non-zero scale");
    out.direction = glm::vec3(forward / len);
    scene_.lights.push_back(out);
  }

  std::string path_;
  const tinygltf::Model& model_;
  const nlohmann::json& rawLights_;
  GltfLoadWarnings* warnings_ = nullptr;
  Scene scene_;
  int defaultMaterial_ = -1;
  std::string firstSkippedPrimitive_, firstSkippedCamera_;
  std::vector<uint8_t> onPath_;
};

// The KHR_lights_punctual light array as written, read past tinygltf to see which lights have a
// "range" (tinygltf stores a missing range as 0). Null when the file has none.
nlohmann::json rawLightsJson(const std::vector<char>& bytes, bool binary) {
  std::string text;
  if (binary) {
    // GLB: 12-byte header, then chunk 0 = JSON: uint32 length, uint32 type, data.
    uint32_t length = 0;
    if (bytes.size() < 20) return nullptr;
    std::memcpy(&length, bytes.data() + 12, 4);
    if (length > bytes.size() - 20) return nullptr;
    text.assign(bytes.data() + 20, length);
  } else {
    text.assign(bytes.begin(), bytes.end());
  }
  nlohmann::json doc = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!doc.is_object()) return nullptr;
  auto ext = doc.find("extensions");
  if (ext == doc.end() || !ext->is_object()) return nullptr;
  auto lights = ext->find(kLightsExtension);
  if (lights == ext->end() || !lights->is_object()) return nullptr;
  auto array = lights->find("lights");
  return array != lights->end() ? *array : nlohmann::json();
}

}  // namespace

Scene loadGltf(const std::string& path, GltfLoadWarnings* warnings) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(path + ": file not found (or not a regular file); check the path");
  std::vector<char> bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    if (!in.good() && !in.eof())
      throw InputError(path + ": cannot read the file; check its permissions");
  }
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;

  tinygltf::TinyGLTF gltf;
  tinygltf::Model model;
  gltf.SetImageLoader(checkedImageLoader, &model);
  std::string err, warn;
  bool ok = binary ? gltf.LoadBinaryFromFile(&model, &err, &warn, path)
                   : gltf.LoadASCIIFromFile(&model, &err, &warn, path);
  if (!ok)
    throw InputError(path + ": not a valid glTF 2.0 " +
                     (binary ? "binary (.glb)" : "JSON (.gltf)") +
                     " file: " + oneLine(err.empty() ? warn : err) +
                     "; re-export it as glTF 2.0 or check it with the Khronos glTF validator");
  if (model.asset.version.rfind("2.", 0) != 0)
    throw InputError(path + ": asset.version: '" + model.asset.version +
                     "' is not 2.x; re-export it as glTF 2.0");

  GltfLoadWarnings local;
  const nlohmann::json rawLights = rawLightsJson(bytes, binary);
  Scene scene = Loader(path, model, rawLights).load(warnings ? *warnings : local);
  if (scene.name.empty()) scene.name = std::filesystem::path(path).stem().string();
  if (!warnings)
    for (const std::string& line : local.messages) std::cerr << "warning: " << line << "\n";
  return scene;
}

}  // namespace hb

// Compressed glTF geometry, decoded before the Loader reads accessors: KHR_draco_mesh_compression
// (Debian's libdraco) and EXT_meshopt_compression (Debian's libmeshoptimizer). Both leave the file
// in a shape tinygltf 2.7 refuses (a meshopt fallback buffer has a byteLength but no bytes; a Draco
// primitive's indices accessor has no bufferView), so prepareCompressed first rewrites those JSON
// fields, tinygltf parses, and decodeCompressed then writes the decoded bytes where a plain file
// would hold them: a meshopt bufferView's bytes into its own (fallback) buffer, a Draco
// primitive's attributes and indices into a buffer appended to the model. The accessors are read
// afterwards by the Loader's ordinary checks, so a decoded stream that does not fit them is
// refused as any other bad accessor.
#include <draco/compression/decode.h>
#include <meshoptimizer.h>

#include <cstring>
#include <set>

#include "base/errors.h"
#include "gltf/gltf_load_internal.h"

namespace hb::gltf_detail {
namespace {

constexpr const char* kDraco = "KHR_draco_mesh_compression";
constexpr const char* kMeshopt = "EXT_meshopt_compression";
// A one-byte data URI: tinygltf refuses a buffer without bytes (an empty data URI, or no uri in a
// .gltf), so a fallback buffer is handed to it as this and sized to its byteLength after parsing.
constexpr const char* kPlaceholderUri = "data:application/octet-stream;base64,AA==";
// No meshopt stream decodes to more than 64 times its size plus its tail: the vertex codec spends
// at least 2 header bits per 16 bytes of a byte group (x64), the index codec at least 4 bits per
// triangle of 12 bytes (x24), the index sequence at least a byte per index (x4); the vertex
// stream's tail is at most 256 bytes (one vertex) plus its 1-byte header. A count past that is
// a corrupt file; checking it first keeps such a file from allocating gigabytes.
constexpr uint64_t kMeshoptMaxRatio = 64, kMeshoptMaxTail = 257;

bool isObject(const nlohmann::json& j, const char* key) { return j.contains(key) && j[key].is_object(); }

// The GLB container with a new JSON chunk and the rest (the BIN chunk) as it was (glTF 2.0 §4.4).
std::vector<uint8_t> withJsonChunk(std::span<const uint8_t> glb, const std::string& json) {
  uint32_t oldLength = 0;
  std::memcpy(&oldLength, glb.data() + 12, 4);
  std::string text = json;
  while (text.size() % 4) text += ' ';
  const size_t rest = 20 + static_cast<size_t>(oldLength);
  std::vector<uint8_t> out(glb.begin(), glb.begin() + 12);
  auto u32 = [&](uint32_t v) {
    out.insert(out.end(), reinterpret_cast<uint8_t*>(&v), reinterpret_cast<uint8_t*>(&v) + 4);
  };
  u32(static_cast<uint32_t>(text.size()));
  u32(0x4E4F534Au);  // "JSON"
  out.insert(out.end(), text.begin(), text.end());
  out.insert(out.end(), glb.begin() + static_cast<std::ptrdiff_t>(rest), glb.end());
  const auto total = static_cast<uint32_t>(out.size());
  std::memcpy(out.data() + 8, &total, 4);
  return out;
}

std::string ordinal(const std::string& what, size_t i, const std::string& name) {
  return what + " " + std::to_string(i) + (name.empty() ? "" : " (\"" + name + "\")");
}

// "mesh 3 ("arch")": the first mesh with a primitive whose accessors read bufferView v, for a
// message about a stream the user knows by its mesh; "bufferView 7" when no mesh reads it.
std::string meshReading(const tinygltf::Model& model, size_t v) {
  for (size_t m = 0; m < model.meshes.size(); ++m)
    for (const tinygltf::Primitive& prim : model.meshes[m].primitives) {
      std::vector<int> accessors{prim.indices};
      for (const auto& [name, a] : prim.attributes) accessors.push_back(a);
      for (int a : accessors)
        if (a >= 0 && static_cast<size_t>(a) < model.accessors.size() &&
            model.accessors[static_cast<size_t>(a)].bufferView == static_cast<int>(v))
          return ordinal("mesh", m, model.meshes[m].name);
    }
  return "bufferView " + std::to_string(v);
}

int intField(const tinygltf::Value& object, const char* key, int otherwise) {
  const tinygltf::Value& v = object.Get(key);
  return v.IsNumber() ? v.GetNumberAsInt() : otherwise;
}

// One meshopt-compressed bufferView decoded into its own buffer range. Throws InputError naming
// the mesh and the extension when the stream or its parameters are not what the codec takes.
void decodeMeshoptView(tinygltf::Model& model, size_t v, const CompressedInput& input, const std::string& path) {
  tinygltf::BufferView& view = model.bufferViews[v];
  const tinygltf::Value& ext = view.extensions.at(kMeshopt);
  const std::string where = path + ": " + meshReading(model, v) + ": " + kMeshopt + ": ";
  auto corrupt = [&](const std::string& problem) {
    throw InputError(where + problem + " (truncated or corrupt); re-export it");
  };
  if (!ext.IsObject()) corrupt("bufferViews[" + std::to_string(v) + "].extensions is not an object");
  const int source = intField(ext, "buffer", -1);
  const int byteOffset = intField(ext, "byteOffset", 0);
  const int byteLength = intField(ext, "byteLength", -1);
  const int stride = intField(ext, "byteStride", -1);
  const int count = intField(ext, "count", -1);
  const std::string mode = ext.Get("mode").IsString() ? ext.Get("mode").Get<std::string>() : "";
  const std::string filter = ext.Get("filter").IsString() ? ext.Get("filter").Get<std::string>() : "NONE";
  const std::string stream = "the compressed " +
                             std::string(mode == "ATTRIBUTES"  ? "vertex"
                                         : mode == "TRIANGLES" ? "triangle"
                                                               : "index") +
                             " stream of bufferView " + std::to_string(v);
  if (source < 0 || static_cast<size_t>(source) >= model.buffers.size() || byteOffset < 0 || byteLength < 0 ||
      static_cast<uint64_t>(byteOffset) + static_cast<uint64_t>(byteLength) >
          model.buffers[static_cast<size_t>(source)].data.size())
    corrupt(stream + " lies outside its buffer");
  // The codec's preconditions (meshoptimizer.h), checked here: Debian's build asserts them.
  const bool attributes = mode == "ATTRIBUTES", triangles = mode == "TRIANGLES", indices = mode == "INDICES";
  if (!attributes && !triangles && !indices)
    corrupt(stream + " has mode '" + mode + "', not ATTRIBUTES, TRIANGLES or INDICES");
  if (count < 0 || stride <= 0 || (attributes && (stride % 4 != 0 || stride > 256)) ||
      (!attributes && stride != 2 && stride != 4) || (triangles && count % 3 != 0))
    corrupt(stream + " has count " + std::to_string(count) + " and byteStride " + std::to_string(stride) +
            ", which its mode " + mode + " does not allow");
  const bool filterFits = filter == "NONE" || (attributes && filter == "OCTAHEDRAL" && (stride == 4 || stride == 8)) ||
                          (attributes && filter == "QUATERNION" && stride == 8) ||
                          (attributes && filter == "EXPONENTIAL" && stride % 4 == 0);
  if (!filterFits)
    corrupt(stream + " has filter '" + filter + "', which does not fit byteStride " + std::to_string(stride));
  const uint64_t decodedSize = static_cast<uint64_t>(count) * static_cast<uint64_t>(stride);
  if (decodedSize > kMeshoptMaxRatio * static_cast<uint64_t>(byteLength) + kMeshoptMaxTail)
    corrupt(stream + " is " + std::to_string(byteLength) + " bytes, too short for " + std::to_string(count) +
            " elements");
  if (decodedSize > view.byteLength)
    corrupt(stream + " decodes to " + std::to_string(decodedSize) + " bytes but the bufferView holds " +
            std::to_string(view.byteLength));
  if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model.buffers.size())
    corrupt("bufferView " + std::to_string(v) + " has no buffer to decode into");
  tinygltf::Buffer& target = model.buffers[static_cast<size_t>(view.buffer)];
  const uint64_t end = static_cast<uint64_t>(view.byteOffset) + decodedSize;
  if (input.fallbackBuffers.count(static_cast<size_t>(view.buffer)) && end > target.data.size()) {
    // The fallback buffer holds no bytes of its own (or only the placeholder): it grows to what the
    // views decoded into it need, never to a byteLength a corrupt file could make enormous.
    if (end > input.fallbackBuffers.at(static_cast<size_t>(view.buffer)))
      corrupt(stream + " decodes past the end of its fallback buffer " + std::to_string(view.buffer));
    target.data.resize(end, 0);
  }
  if (end > target.data.size()) corrupt(stream + " decodes past the end of buffer " + std::to_string(view.buffer));
  // Decoded into a copy: the source and target may be the same buffer, which may also move.
  const std::vector<uint8_t> encoded(model.buffers[static_cast<size_t>(source)].data.begin() + byteOffset,
                                     model.buffers[static_cast<size_t>(source)].data.begin() + byteOffset + byteLength);
  std::vector<uint8_t> decoded(decodedSize);
  const size_t n = static_cast<size_t>(count), s = static_cast<size_t>(stride);
  int rc = attributes  ? meshopt_decodeVertexBuffer(decoded.data(), n, s, encoded.data(), encoded.size())
           : triangles ? meshopt_decodeIndexBuffer(decoded.data(), n, s, encoded.data(), encoded.size())
                       : meshopt_decodeIndexSequence(decoded.data(), n, s, encoded.data(), encoded.size());
  if (rc != 0) corrupt(stream + " does not decode");
  if (filter == "OCTAHEDRAL") meshopt_decodeFilterOct(decoded.data(), n, s);
  if (filter == "QUATERNION") meshopt_decodeFilterQuat(decoded.data(), n, s);
  if (filter == "EXPONENTIAL") meshopt_decodeFilterExp(decoded.data(), n, s);
  std::memcpy(target.data.data() + view.byteOffset, decoded.data(), decoded.size());
  // The decoded view is plain data: its stride is the stream's (the extension's byteStride).
  view.byteStride = attributes ? s : 0;
}

// Writes `count` elements of `components` values of type T from the Draco attribute into `out`.
template <typename T>
bool convertDraco(const draco::PointAttribute& attr, size_t count, int components, std::vector<uint8_t>& out) {
  const size_t start = out.size();
  out.resize(start + count * static_cast<size_t>(components) * sizeof(T));
  std::vector<T> element(static_cast<size_t>(components));
  for (size_t p = 0; p < count; ++p) {
    if (!attr.ConvertValue<T>(attr.mapped_index(draco::PointIndex(static_cast<uint32_t>(p))),
                              static_cast<int8_t>(components), element.data()))
      return false;
    std::memcpy(out.data() + start + p * element.size() * sizeof(T), element.data(), element.size() * sizeof(T));
  }
  return true;
}

bool convertDraco(const draco::PointAttribute& attr, size_t count, int components, int componentType,
                  std::vector<uint8_t>& out) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return convertDraco<float>(attr, count, components, out);
    case TINYGLTF_COMPONENT_TYPE_BYTE: return convertDraco<int8_t>(attr, count, components, out);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return convertDraco<uint8_t>(attr, count, components, out);
    case TINYGLTF_COMPONENT_TYPE_SHORT: return convertDraco<int16_t>(attr, count, components, out);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return convertDraco<uint16_t>(attr, count, components, out);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return convertDraco<uint32_t>(attr, count, components, out);
    default: return false;
  }
}

// Points `accessor` at `bytes` appended to `buffer` as a new bufferView.
void attach(tinygltf::Model& model, size_t buffer, tinygltf::Accessor& accessor, const std::vector<uint8_t>& bytes) {
  std::vector<unsigned char>& data = model.buffers[buffer].data;
  while (data.size() % 4) data.push_back(0);
  tinygltf::BufferView view;
  view.buffer = static_cast<int>(buffer);
  view.byteOffset = data.size();
  view.byteLength = bytes.size();
  data.insert(data.end(), bytes.begin(), bytes.end());
  model.bufferViews.push_back(view);
  accessor.bufferView = static_cast<int>(model.bufferViews.size() - 1);
  accessor.byteOffset = 0;
}

// One Draco-compressed primitive decoded into plain accessors (its indices as UNSIGNED_INT).
void decodeDracoPrimitive(tinygltf::Model& model, size_t m, size_t p, int indicesAccessor, size_t outBuffer,
                          const std::string& path) {
  tinygltf::Primitive& prim = model.meshes[m].primitives[p];
  const tinygltf::Value& ext = prim.extensions.at(kDraco);
  const std::string where = path + ": " + ordinal("mesh", m, model.meshes[m].name) + ": " + kDraco + ": primitive " +
                            std::to_string(p) + ": ";
  auto corrupt = [&](const std::string& problem) {
    throw InputError(where + problem + " (truncated or corrupt); re-export it");
  };
  const int v = ext.IsObject() ? intField(ext, "bufferView", -1) : -1;
  if (v < 0 || static_cast<size_t>(v) >= model.bufferViews.size()) corrupt("its bufferView does not exist");
  const tinygltf::BufferView& view = model.bufferViews[static_cast<size_t>(v)];
  if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model.buffers.size() ||
      static_cast<uint64_t>(view.byteOffset) + view.byteLength >
          model.buffers[static_cast<size_t>(view.buffer)].data.size())
    corrupt("bufferView " + std::to_string(v) + " lies outside its buffer");
  draco::DecoderBuffer buffer;
  buffer.Init(
      reinterpret_cast<const char*>(model.buffers[static_cast<size_t>(view.buffer)].data.data() + view.byteOffset),
      view.byteLength);
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok())
    corrupt("the compressed mesh of bufferView " + std::to_string(v) +
            " does not decode (Draco: " + decoded.status().error_msg_string() + ")");
  const draco::Mesh& mesh = *decoded.value();
  const size_t points = mesh.num_points();
  const tinygltf::Value& attributes = ext.Get("attributes");
  if (!attributes.IsObject()) corrupt("its extension has no attributes object");
  for (const auto& [name, a] : prim.attributes) {
    if (!attributes.Has(name)) continue;  // an attribute stored plainly beside the compressed ones
    const tinygltf::Value& id = attributes.Get(name);
    const draco::PointAttribute* attr = id.IsNumber() && id.GetNumberAsInt() >= 0
                                            ? mesh.GetAttributeByUniqueId(static_cast<uint32_t>(id.GetNumberAsInt()))
                                            : nullptr;
    if (attr == nullptr) corrupt("attribute " + name + " is not in the compressed mesh");
    if (a < 0 || static_cast<size_t>(a) >= model.accessors.size()) continue;  // the Loader names the bad index
    tinygltf::Accessor& accessor = model.accessors[static_cast<size_t>(a)];
    const int components = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(accessor.type));
    std::vector<uint8_t> bytes;
    if (components <= 0 || !convertDraco(*attr, points, components, accessor.componentType, bytes))
      corrupt("attribute " + name + " does not convert to its accessor's type");
    accessor.count = points;
    attach(model, outBuffer, accessor, bytes);
  }
  if (indicesAccessor >= 0 && static_cast<size_t>(indicesAccessor) < model.accessors.size()) {
    std::vector<uint8_t> bytes(static_cast<size_t>(mesh.num_faces()) * 3 * sizeof(uint32_t));
    for (uint32_t f = 0; f < mesh.num_faces(); ++f)
      for (int k = 0; k < 3; ++k) {
        const uint32_t index = mesh.face(draco::FaceIndex(f))[k].value();
        std::memcpy(bytes.data() + (size_t(f) * 3 + size_t(k)) * 4, &index, 4);
      }
    tinygltf::Accessor& accessor = model.accessors[static_cast<size_t>(indicesAccessor)];
    accessor.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    accessor.count = bytes.size() / 4;
    attach(model, outBuffer, accessor, bytes);
  }
  prim.indices = indicesAccessor;
}

}  // namespace

CompressedInput prepareCompressed(const nlohmann::json& doc, std::span<const uint8_t> bytes, bool binary) {
  CompressedInput out;
  if (!doc.is_object()) return out;
  nlohmann::json rewritten = doc;
  bool changed = false;
  if (rewritten.contains("buffers") && rewritten["buffers"].is_array())
    for (size_t b = 0; b < rewritten["buffers"].size(); ++b) {
      nlohmann::json& buffer = rewritten["buffers"][b];
      if (!buffer.is_object() || buffer.contains("uri") || !isObject(buffer, "extensions") ||
          !isObject(buffer["extensions"], kMeshopt) || !buffer.contains("byteLength") ||
          !buffer["byteLength"].is_number_unsigned())
        continue;
      // A buffer without a uri is the GLB's BIN chunk only when it is the first one (glTF 2.0 §4.4).
      if (binary && b == 0) continue;
      out.fallbackBuffers[b] = buffer["byteLength"].get<uint64_t>();
      buffer["uri"] = kPlaceholderUri;
      buffer["byteLength"] = 1;
      changed = true;
    }
  if (rewritten.contains("meshes") && rewritten["meshes"].is_array())
    for (size_t m = 0; m < rewritten["meshes"].size(); ++m) {
      nlohmann::json& mesh = rewritten["meshes"][m];
      if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
      for (size_t p = 0; p < mesh["primitives"].size(); ++p) {
        nlohmann::json& prim = mesh["primitives"][p];
        if (!prim.is_object() || !isObject(prim, "extensions") || !isObject(prim["extensions"], kDraco)) continue;
        // tinygltf 2.7 refuses an indices accessor without a bufferView, which a Draco primitive's is.
        out.dracoIndices[{m, p}] =
            prim.contains("indices") && prim["indices"].is_number_integer() ? prim["indices"].get<int>() : -1;
        prim.erase("indices");
        changed = true;
      }
    }
  if (!changed) return out;
  const std::string text = rewritten.dump();
  out.bytes = binary ? withJsonChunk(bytes, text) : std::vector<uint8_t>(text.begin(), text.end());
  return out;
}

std::string decodeCompressed(tinygltf::Model& model, const CompressedInput& input, const std::string& path) {
  std::set<std::string> used;
  // The placeholders shrink back to nothing before views decode into them.
  for (const auto& [b, length] : input.fallbackBuffers)
    if (b < model.buffers.size()) model.buffers[b].data.clear();
  for (size_t v = 0; v < model.bufferViews.size(); ++v)
    if (model.bufferViews[v].extensions.count(kMeshopt)) {
      decodeMeshoptView(model, v, input, path);
      used.insert(kMeshopt);
    }
  if (!input.dracoIndices.empty()) {
    model.buffers.emplace_back();
    const size_t outBuffer = model.buffers.size() - 1;
    for (const auto& [at, indices] : input.dracoIndices) {
      const auto [m, p] = at;
      if (m >= model.meshes.size() || p >= model.meshes[m].primitives.size()) continue;
      decodeDracoPrimitive(model, m, p, indices, outBuffer, path);
      used.insert(kDraco);
    }
  }
  for (const std::string& e : model.extensionsUsed)
    if (e == "KHR_mesh_quantization") used.insert(e);
  std::string joined;
  for (const std::string& e : used) joined += (joined.empty() ? "" : ", ") + e;
  return joined;
}

}  // namespace hb::gltf_detail

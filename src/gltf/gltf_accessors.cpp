// glTF accessors: validation of their bufferView/buffer byte ranges and reading of their
// elements (Loader members declared in gltf_load_internal.h).
#include <algorithm>
#include <cstring>

#include "base/errors.h"
#include "gltf/gltf_load_internal.h"

namespace hb::gltf_detail {
namespace {

// "5126 (FLOAT)": a glTF componentType code with its name, for error messages.
std::string componentTypeName(int componentType) {
  const char* name = "unknown";
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: name = "BYTE"; break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: name = "UNSIGNED_BYTE"; break;
    case TINYGLTF_COMPONENT_TYPE_SHORT: name = "SHORT"; break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: name = "UNSIGNED_SHORT"; break;
    case TINYGLTF_COMPONENT_TYPE_INT: name = "INT"; break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: name = "UNSIGNED_INT"; break;
    case TINYGLTF_COMPONENT_TYPE_FLOAT: name = "FLOAT"; break;
    case TINYGLTF_COMPONENT_TYPE_DOUBLE: name = "DOUBLE"; break;
  }
  return std::to_string(componentType) + " (" + name + ")";
}

// One component as a float: normalized integers map to [0, 1] (unsigned) or [-1, 1] (signed,
// max(c / (2^(n-1) - 1), -1)), glTF 2.0 §3.11; others are their integer value (quantized
// positions, KHR_mesh_quantization, whose node transform scales them back).
float readComponent(const uint8_t* p, int componentType, bool normalized) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float f;
      std::memcpy(&f, p, 4);
      return f;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? static_cast<float>(*p) / 255.0f : float(*p);
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const auto c = static_cast<int8_t>(*p);
      return normalized ? std::max(static_cast<float>(c) / 127.0f, -1.0f) : float(c);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t u;
      std::memcpy(&u, p, 2);
      return normalized ? static_cast<float>(u) / 65535.0f : float(u);
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t c;
      std::memcpy(&c, p, 2);
      return normalized ? std::max(static_cast<float>(c) / 32767.0f, -1.0f) : float(c);
    }
    default: HB_ASSERT(false);
  }
}

}  // namespace

AccessorView Loader::accessor(int index, const std::string& field, int type,
                              std::initializer_list<int> componentTypes) const {
  size_t a = checkIndex(index, model_.accessors.size(), field, "accessors");
  const tinygltf::Accessor& acc = model_.accessors[a];
  const std::string where = field + " (accessors[" + std::to_string(a) + "])";
  if (acc.sparse.isSparse) fail(where, "sparse accessors are not supported", "write the data densely");
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
    fail(where, "unsupported componentType " + componentTypeName(acc.componentType), "store it as " + allowed);
  if (acc.count == 0) fail(where, "count is 0", "give the accessor at least one element");
  if (acc.bufferView < 0) fail(where, "has no bufferView (an all-zero accessor)", "give it a bufferView with data");
  size_t v = checkIndex(acc.bufferView, model_.bufferViews.size(), where + ".bufferView", "bufferViews");
  const tinygltf::BufferView& view = model_.bufferViews[v];
  size_t b = checkIndex(view.buffer, model_.buffers.size(), "bufferViews[" + std::to_string(v) + "].buffer", "buffers");
  const tinygltf::Buffer& buffer = model_.buffers[b];

  const uint64_t elementSize =
      static_cast<uint64_t>(tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(acc.componentType))) *
      static_cast<uint64_t>(tinygltf::GetNumComponentsInType(static_cast<uint32_t>(acc.type)));
  const uint64_t stride = view.byteStride != 0 ? view.byteStride : elementSize;
  if (stride < elementSize)
    fail("bufferViews[" + std::to_string(v) + "].byteStride",
         "stride " + std::to_string(stride) + " is smaller than the " + std::to_string(elementSize) +
             "-byte elements of " + where,
         "set byteStride to 0 or at least " + std::to_string(elementSize));
  const uint64_t viewEnd = static_cast<uint64_t>(view.byteOffset) + view.byteLength;
  if (viewEnd > buffer.data.size())
    fail("bufferViews[" + std::to_string(v) + "] (read by " + where + ")",
         "ends at byte " + std::to_string(viewEnd) + " but buffers[" + std::to_string(b) + "] holds only " +
             std::to_string(buffer.data.size()) + " bytes",
         "fix byteOffset/byteLength or supply the whole buffer");
  // count <= byteLength + 1 bounds stride * (count - 1) below 2^8 * 2^64 / 2^8: no overflow.
  const bool countFits = acc.count <= view.byteLength + 1;
  const uint64_t need = countFits ? acc.byteOffset + stride * (acc.count - 1) + elementSize : ~uint64_t(0);
  if (!countFits || need > view.byteLength)
    fail(where,
         std::to_string(acc.count) + " elements from byteOffset " + std::to_string(acc.byteOffset) + " with stride " +
             std::to_string(stride) + " need " + (countFits ? std::to_string(need) : std::string("more")) +
             " bytes but bufferViews[" + std::to_string(v) + "] has only " + std::to_string(view.byteLength),
         "fix the accessor's count/byteOffset or make the bufferView and buffer longer");
  AccessorView out;
  out.data = buffer.data.data() + view.byteOffset + acc.byteOffset;
  out.count = acc.count;
  out.stride = stride;
  out.elementSize = elementSize;
  out.componentType = acc.componentType;
  out.normalized = acc.normalized;
  return out;
}

template <int N>
std::vector<glm::vec<N, float>> Loader::readVectors(const AccessorView& view) const {
  std::vector<glm::vec<N, float>> out(view.count);
  const size_t componentSize = view.elementSize / N;
  for (size_t i = 0; i < view.count; ++i)
    for (int c = 0; c < N; ++c)
      out[i][c] = readComponent(view.data + i * view.stride + c * componentSize, view.componentType, view.normalized);
  return out;
}

// The two sizes loadPrimitive reads: TEXCOORD_0 (VEC2), POSITION and NORMAL (VEC3).
template std::vector<glm::vec2> Loader::readVectors<2>(const AccessorView& view) const;
template std::vector<glm::vec3> Loader::readVectors<3>(const AccessorView& view) const;

std::vector<uint32_t> Loader::readIndices(const AccessorView& view) const {
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

}  // namespace hb::gltf_detail

// glTF meshes: TRIANGLES primitives (and strips and fans, as triangle lists) appended to the scene's shared vertex and
// index arrays, with computed normals and sequential indices where the file has none (Loader members declared in
// gltf_load_internal.h).
#include <cmath>
#include <limits>

#include "base/errors.h"
#include "gltf/gltf_load_internal.h"

namespace hb::gltf_detail {
namespace {

// Smooth normals: each vertex sums the unnormalised face normals (cross products, whose length
// is twice the triangle's area, hence area-weighted) of the triangles around it. A vertex with
// only degenerate triangles gets +Z so that the normal is always unit.
std::vector<glm::vec3> areaWeightedNormals(const std::vector<glm::vec3>& positions,
                                           const std::vector<uint32_t>& indices) {
  std::vector<glm::dvec3> sum(positions.size(), glm::dvec3(0.0));
  for (size_t t = 0; t + 2 < indices.size(); t += 3) {
    glm::dvec3 a(positions[indices[t]]), b(positions[indices[t + 1]]), c(positions[indices[t + 2]]);
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

// A strip or fan as a triangle list, with glTF 2.0's vertex order (§3.7.2.1): strip triangle i is
// (v_i, v_{i+1+i%2}, v_{i+2-i%2}), which keeps every triangle's winding; fan triangle i is
// (v_{i+1}, v_{i+2}, v_0).
std::vector<uint32_t> triangleList(const std::vector<uint32_t>& v, int mode) {
  std::vector<uint32_t> out;
  for (size_t i = 0; i + 2 < v.size(); ++i) {
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP)
      out.insert(out.end(), {v[i], v[i + 1 + i % 2], v[i + 2 - i % 2]});
    else
      out.insert(out.end(), {v[i + 1], v[i + 2], v[0]});
  }
  return out;
}

// KHR_texture_transform of one texture slot as the 2x3 matrix the extension defines,
// T(offset) * R(rotation) * S(scale), applied to (u, v, 1); identity when the slot has none.
glm::dmat3x2 textureTransform(const tinygltf::ExtensionMap& extensions) {
  glm::dmat3x2 m(1.0);
  auto it = extensions.find("KHR_texture_transform");
  if (it == extensions.end() || !it->second.IsObject()) return m;
  const tinygltf::Value& t = it->second;
  auto pair = [&](const char* key, glm::dvec2 otherwise) {
    const tinygltf::Value& v = t.Get(key);
    if (!v.IsArray() || v.ArrayLen() != 2 || !v.Get(0).IsNumber() || !v.Get(1).IsNumber()) return otherwise;
    return glm::dvec2(v.Get(0).GetNumberAsDouble(), v.Get(1).GetNumberAsDouble());
  };
  const glm::dvec2 offset = pair("offset", glm::dvec2(0.0)), scale = pair("scale", glm::dvec2(1.0));
  const double r = t.Get("rotation").IsNumber() ? t.Get("rotation").GetNumberAsDouble() : 0.0;
  // Columns of translation * rotation * scale, rotation = [cos sin; -sin cos] (row-major in the spec).
  m[0] = glm::dvec2(std::cos(r) * scale.x, -std::sin(r) * scale.x);
  m[1] = glm::dvec2(std::sin(r) * scale.y, std::cos(r) * scale.y);
  m[2] = offset;
  return m;
}

bool drawsTriangles(int mode) {
  return mode == -1 || mode == TINYGLTF_MODE_TRIANGLES || mode == TINYGLTF_MODE_TRIANGLE_STRIP ||
         mode == TINYGLTF_MODE_TRIANGLE_FAN;
}

}  // namespace

void Loader::loadMesh(int meshIndex) {
  const tinygltf::Mesh& mesh = model_.meshes[static_cast<size_t>(meshIndex)];
  Mesh out;
  out.name = mesh.name;
  for (size_t p = 0; p < mesh.primitives.size(); ++p) {
    const std::string field = "meshes[" + std::to_string(meshIndex) + "].primitives[" + std::to_string(p) + "]";
    const tinygltf::Primitive& prim = mesh.primitives[p];
    if (!drawsTriangles(prim.mode)) {
      if (warnings_->skippedPrimitives++ == 0)
        firstSkippedPrimitive_ = field + " (mode " + std::to_string(prim.mode) + ")";
      continue;
    }
    PrimitiveData data;
    try {
      data = readPrimitive(prim, field);
    } catch (const InputError& e) {
      // Left out as points and lines are, with one warning line; a scene of nothing else is
      // refused with this message (Loader::load).
      if (warnings_->skippedBroken++ == 0) {
        firstBrokenPrimitive_ = e.what();
        firstBrokenMesh_ = mesh.name;
      }
      continue;
    }
    out.primitives.push_back(appendPrimitive(data, field));
  }
  scene_.meshes.push_back(std::move(out));
}

Loader::PrimitiveData Loader::readPrimitive(const tinygltf::Primitive& prim, const std::string& field) const {
  auto attribute = [&](const char* name) {
    auto it = prim.attributes.find(name);
    return it == prim.attributes.end() ? -1 : it->second;
  };
  const int positionAccessor = attribute("POSITION");
  if (positionAccessor < 0) fail(field + ".attributes", "has no POSITION", "give every primitive a POSITION accessor");
  const std::string positionField = field + ".attributes.POSITION";
  // Integer positions, normals and texture coordinates are KHR_mesh_quantization's: positions
  // normalized or not (the node transform scales them back), normals normalized signed.
  constexpr int kByte = TINYGLTF_COMPONENT_TYPE_BYTE, kUByte = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                kShort = TINYGLTF_COMPONENT_TYPE_SHORT, kUShort = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                kFloat = TINYGLTF_COMPONENT_TYPE_FLOAT;
  std::vector<glm::vec3> positions = readVectors<3>(
      accessor(positionAccessor, positionField, TINYGLTF_TYPE_VEC3, {kFloat, kByte, kUByte, kShort, kUShort}));
  for (size_t i = 0; i < positions.size(); ++i)
    if (!std::isfinite(positions[i].x) || !std::isfinite(positions[i].y) || !std::isfinite(positions[i].z))
      fail(positionField, "vertex " + std::to_string(i) + " is not finite (NaN or Inf)",
           "re-export the mesh with finite positions");
  const size_t vertexCount = positions.size();

  std::vector<glm::vec3> normals;
  if (int a = attribute("NORMAL"); a >= 0) {
    normals = readVectors<3>(accessor(a, field + ".attributes.NORMAL", TINYGLTF_TYPE_VEC3, {kFloat, kByte, kShort}));
    // Quantized normals are unit only to their precision (and a filter's octahedral decode to
    // 1/2^15): the shaders expect unit normals, as a float file gives them.
    for (glm::vec3& n : normals) {
      const float length = glm::length(n);
      n = length > 0.0f && std::isfinite(length) ? n / length : glm::vec3(0.0f, 0.0f, 1.0f);
    }
    if (normals.size() != vertexCount)
      fail(field + ".attributes.NORMAL",
           "count " + std::to_string(normals.size()) + " differs from POSITION's " + std::to_string(vertexCount),
           "give every attribute of a primitive the same count");
  }
  std::vector<glm::vec2> uvs;
  if (int a = attribute("TEXCOORD_0"); a >= 0) {
    // The core spec allows normalized unsigned byte/short texture coordinates besides float;
    // KHR_mesh_quantization also signed and unnormalized ones.
    uvs = readVectors<2>(
        accessor(a, field + ".attributes.TEXCOORD_0", TINYGLTF_TYPE_VEC2, {kFloat, kByte, kUByte, kShort, kUShort}));
    if (uvs.size() != vertexCount)
      fail(field + ".attributes.TEXCOORD_0",
           "count " + std::to_string(uvs.size()) + " differs from POSITION's " + std::to_string(vertexCount),
           "give every attribute of a primitive the same count");
  }

  std::vector<uint32_t> indices;
  const std::string indicesField = field + ".indices";
  if (prim.indices >= 0) {
    indices = readIndices(accessor(prim.indices, indicesField, TINYGLTF_TYPE_SCALAR,
                                   {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                    TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT}));
    for (size_t i = 0; i < indices.size(); ++i)
      if (indices[i] >= vertexCount)
        fail(indicesField,
             "index " + std::to_string(i) + " is " + std::to_string(indices[i]) + " but the primitive has only " +
                 std::to_string(vertexCount) + " vertices",
             "fix the index buffer or the POSITION accessor's count");
  } else {
    indices.resize(vertexCount);
    for (size_t i = 0; i < vertexCount; ++i) indices[i] = static_cast<uint32_t>(i);
  }
  if (prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP || prim.mode == TINYGLTF_MODE_TRIANGLE_FAN) {
    if (indices.size() < 3)
      fail(prim.indices >= 0 ? indicesField : positionField,
           std::to_string(indices.size()) + " vertices make no triangle of a strip or fan", "give it at least 3");
    indices = triangleList(indices, prim.mode);
  }
  if (indices.size() % 3 != 0)
    fail(prim.indices >= 0 ? indicesField : positionField,
         std::to_string(indices.size()) + " vertices do not make whole triangles",
         "give TRIANGLES primitives a multiple of 3 indices (or vertices)");
  if (normals.empty()) normals = areaWeightedNormals(positions, indices);
  if (!uvs.empty() && prim.material >= 0 && static_cast<size_t>(prim.material) < model_.materials.size()) {
    // KHR_texture_transform (what gltfpack writes to scale quantized texture coordinates back),
    // applied to the coordinates themselves: the scene has one set per vertex and a primitive's
    // vertices are its own. The base colour's transform wins; the metallic-roughness texture's is
    // used only when the base colour has no texture.
    const tinygltf::PbrMetallicRoughness& pbr =
        model_.materials[static_cast<size_t>(prim.material)].pbrMetallicRoughness;
    const glm::dmat3x2 t = textureTransform(pbr.baseColorTexture.index >= 0 ? pbr.baseColorTexture.extensions
                                                                            : pbr.metallicRoughnessTexture.extensions);
    if (t != glm::dmat3x2(1.0))
      for (glm::vec2& uv : uvs) uv = glm::vec2(t * glm::dvec3(glm::dvec2(uv), 1.0));
  }

  PrimitiveData out;
  out.material =
      prim.material >= 0
          ? static_cast<int>(checkIndex(prim.material, model_.materials.size(), field + ".material", "materials"))
          : -1;
  out.positions = std::move(positions);
  out.normals = std::move(normals);
  out.uvs = std::move(uvs);
  out.indices = std::move(indices);
  return out;
}

Primitive Loader::appendPrimitive(const PrimitiveData& data, const std::string& field) {
  const size_t vertexCount = data.positions.size();
  Primitive out;
  if (scene_.vertices.size() + vertexCount > std::numeric_limits<uint32_t>::max() ||
      scene_.indices.size() + data.indices.size() > std::numeric_limits<uint32_t>::max())
    fail(field, "the scene exceeds 2^32 vertices or indices", "split or simplify the scene");
  out.firstIndex = static_cast<uint32_t>(scene_.indices.size());
  out.indexCount = static_cast<uint32_t>(data.indices.size());
  out.vertexOffset = static_cast<uint32_t>(scene_.vertices.size());
  out.vertexCount = static_cast<uint32_t>(vertexCount);
  out.material = data.material >= 0 ? static_cast<uint32_t>(data.material) : defaultMaterial();
  for (size_t i = 0; i < vertexCount; ++i)
    scene_.vertices.push_back({data.positions[i], data.normals[i], data.uvs.empty() ? glm::vec2(0.0f) : data.uvs[i]});
  scene_.indices.insert(scene_.indices.end(), data.indices.begin(), data.indices.end());
  return out;
}

}  // namespace hb::gltf_detail

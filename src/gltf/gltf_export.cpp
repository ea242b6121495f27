// glTF 2.0 export through tinygltf's writer: one buffer (data URI in .gltf, BIN chunk in .glb),
// non-interleaved float attributes, uint32 indices, PNG images stored in the buffer. Its output
// passes the Khronos glTF Validator with no error and no warning (tests/gltf_validator_test.sh).
#include <stb_image_write.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <glm/gtc/matrix_inverse.hpp>
#include <limits>

#include "base/errors.h"
#include "base/text_format.h"
#include "gltf/gltf_io.h"
#include "scene/ambient_json.h"
#include "scene/environment.h"

namespace hb {
namespace {

// nlohmann::json → tinygltf::Value (for extras): null, booleans, numbers, strings, arrays, objects.
tinygltf::Value toValue(const nlohmann::json& j) {
  if (j.is_boolean()) return tinygltf::Value(j.get<bool>());
  if (j.is_number_integer()) return tinygltf::Value(j.get<int>());
  if (j.is_number()) return tinygltf::Value(j.get<double>());
  if (j.is_string()) return tinygltf::Value(j.get<std::string>());
  if (j.is_array()) {
    tinygltf::Value::Array a;
    for (const auto& e : j) a.push_back(toValue(e));
    return tinygltf::Value(std::move(a));
  }
  if (j.is_object()) {
    tinygltf::Value::Object o;
    for (const auto& [k, v] : j.items()) o[k] = toValue(v);
    return tinygltf::Value(std::move(o));
  }
  return tinygltf::Value();
}

class Exporter {
 public:
  explicit Exporter(const Scene& scene) : scene_(scene) {}

  tinygltf::Model build() {
    model_.asset.version = "2.0";
    model_.asset.generator = "hybridbench";
    for (const Texture& t : scene_.textures) addTexture(t);
    for (const Material& m : scene_.materials) addMaterial(m);
    for (const Mesh& m : scene_.meshes) addMesh(m);
    tinygltf::Scene gscene;
    gscene.name = scene_.name;
    for (const Instance& inst : scene_.instances) {
      HB_ASSERT(inst.mesh < scene_.meshes.size());
      tinygltf::Node node;
      node.mesh = static_cast<int>(inst.mesh);
      node.matrix = matrixOf(glm::dmat4(inst.transform));
      gscene.nodes.push_back(addNode(std::move(node)));
    }
    for (const Camera& c : scene_.cameras) gscene.nodes.push_back(addCamera(c));
    for (const Light& l : scene_.lights) gscene.nodes.push_back(addLight(l));
    // What the scene calls for and its ambient term travel with it (plan/effects.h, scene.h).
    tinygltf::Value::Object extras;
    if (!scene_.effects.is_null()) extras["effects"] = toValue(scene_.effects);
    if (scene_.ambient) extras["ambient"] = toValue(toJson(*scene_.ambient));
    if (scene_.environment) extras["environment"] = toValue(toJson(*scene_.environment));
    if (!extras.empty()) gscene.extras = tinygltf::Value(std::move(extras));
    model_.scenes.push_back(std::move(gscene));
    model_.defaultScene = 0;
    if (!bin_.empty()) {
      tinygltf::Buffer buffer;
      buffer.data = std::move(bin_);
      model_.buffers.push_back(std::move(buffer));
    }
    return std::move(model_);
  }

 private:
  static std::vector<double> matrixOf(const glm::dmat4& m) {
    std::vector<double> out(16);
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) out[static_cast<size_t>(4 * c + r)] = m[c][r];  // column-major
    return out;
  }

  int addNode(tinygltf::Node node) {
    // The identity is glTF's default transform: written out, the Khronos validator reports it
    // (NODE_MATRIX_DEFAULT), and a node without a matrix loads as the identity anyway.
    if (node.matrix == matrixOf(glm::dmat4(1.0))) node.matrix.clear();
    model_.nodes.push_back(std::move(node));
    return static_cast<int>(model_.nodes.size() - 1);
  }

  // Appends bytes to the one buffer at a 4-byte boundary (glTF requires accessor offsets to be
  // multiples of the component size, at most 4 here) and returns the new bufferView.
  int addView(const void* data, size_t bytes, int target) {
    while (bin_.size() % 4 != 0) bin_.push_back(0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = bin_.size();
    view.byteLength = bytes;
    view.target = target;
    const auto* p = static_cast<const unsigned char*>(data);
    bin_.insert(bin_.end(), p, p + bytes);
    model_.bufferViews.push_back(view);
    return static_cast<int>(model_.bufferViews.size() - 1);
  }

  int addAccessor(int view, int componentType, int type, size_t count) {
    tinygltf::Accessor acc;
    acc.bufferView = view;
    acc.componentType = componentType;
    acc.type = type;
    acc.count = count;
    model_.accessors.push_back(acc);
    return static_cast<int>(model_.accessors.size() - 1);
  }

  void addTexture(const Texture& t) {
    HB_ASSERT(t.rgba.size() == size_t(t.width) * t.height * 4 && t.width > 0 && t.height > 0);
    std::vector<unsigned char> png;
    auto append = [](void* context, void* data, int size) {
      auto* out = static_cast<std::vector<unsigned char>*>(context);
      const auto* p = static_cast<const unsigned char*>(data);
      out->insert(out->end(), p, p + size);
    };
    HB_ASSERT(stbi_write_png_to_func(append, &png, static_cast<int>(t.width), static_cast<int>(t.height), 4,
                                     t.rgba.data(), static_cast<int>(t.width * 4)) != 0);
    tinygltf::Image image;
    image.name = t.name;
    image.mimeType = "image/png";
    image.bufferView = addView(png.data(), png.size(), 0);
    model_.images.push_back(std::move(image));
    tinygltf::Texture tex;
    tex.name = t.name;
    tex.source = static_cast<int>(model_.images.size() - 1);
    model_.textures.push_back(std::move(tex));
  }

  void addMaterial(const Material& m) {
    auto texture = [&](int index) {
      HB_ASSERT(index < static_cast<int>(scene_.textures.size()));
      return index;
    };
    tinygltf::Material mat;
    mat.name = m.name;
    mat.pbrMetallicRoughness.baseColorFactor = {m.baseColorFactor.r, m.baseColorFactor.g, m.baseColorFactor.b,
                                                m.baseColorFactor.a};
    mat.pbrMetallicRoughness.metallicFactor = m.metallicFactor;
    mat.pbrMetallicRoughness.roughnessFactor = m.roughnessFactor;
    mat.pbrMetallicRoughness.baseColorTexture.index = texture(m.baseColorTexture);
    mat.pbrMetallicRoughness.metallicRoughnessTexture.index = texture(m.metallicRoughnessTexture);
    mat.doubleSided = m.doubleSided;
    model_.materials.push_back(std::move(mat));
  }

  void addMesh(const Mesh& m) {
    tinygltf::Mesh mesh;
    mesh.name = m.name;
    for (const Primitive& p : m.primitives) {
      HB_ASSERT(size_t(p.vertexOffset) + p.vertexCount <= scene_.vertices.size());
      HB_ASSERT(size_t(p.firstIndex) + p.indexCount <= scene_.indices.size());
      HB_ASSERT(p.material < scene_.materials.size());
      std::vector<glm::vec3> positions(p.vertexCount), normals(p.vertexCount);
      std::vector<glm::vec2> uvs(p.vertexCount);
      glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
      for (uint32_t v = 0; v < p.vertexCount; ++v) {
        const Vertex& vertex = scene_.vertices[p.vertexOffset + v];
        positions[v] = vertex.position;
        normals[v] = vertex.normal;
        uvs[v] = vertex.uv;
        lo = glm::min(lo, vertex.position);
        hi = glm::max(hi, vertex.position);
      }
      const std::vector<uint32_t> indices(scene_.indices.begin() + p.firstIndex,
                                          scene_.indices.begin() + p.firstIndex + p.indexCount);
      for (uint32_t i : indices) HB_ASSERT(i < p.vertexCount);

      tinygltf::Primitive prim;
      prim.mode = TINYGLTF_MODE_TRIANGLES;
      prim.material = static_cast<int>(p.material);
      const int position =
          addAccessor(addView(positions.data(), positions.size() * sizeof(glm::vec3), TINYGLTF_TARGET_ARRAY_BUFFER),
                      TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, p.vertexCount);
      if (p.vertexCount > 0) {  // the spec requires POSITION bounds
        model_.accessors[static_cast<size_t>(position)].minValues = {lo.x, lo.y, lo.z};
        model_.accessors[static_cast<size_t>(position)].maxValues = {hi.x, hi.y, hi.z};
      }
      prim.attributes["POSITION"] = position;
      prim.attributes["NORMAL"] =
          addAccessor(addView(normals.data(), normals.size() * sizeof(glm::vec3), TINYGLTF_TARGET_ARRAY_BUFFER),
                      TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, p.vertexCount);
      // Coordinates that are all +0 are what the loader gives a primitive without TEXCOORD_0, so
      // they are left out (the validator reports an attribute no texture reads, UNUSED_OBJECT);
      // any others are written, read by a texture or not, so that the scene loads back the same.
      const bool allZero = std::all_of(uvs.begin(), uvs.end(), [](const glm::vec2& uv) {
        return uv.x == 0.0f && uv.y == 0.0f && !std::signbit(uv.x) && !std::signbit(uv.y);
      });
      if (!allZero)
        prim.attributes["TEXCOORD_0"] =
            addAccessor(addView(uvs.data(), uvs.size() * sizeof(glm::vec2), TINYGLTF_TARGET_ARRAY_BUFFER),
                        TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, p.vertexCount);
      prim.indices =
          addAccessor(addView(indices.data(), indices.size() * sizeof(uint32_t), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                      TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, indices.size());
      mesh.primitives.push_back(std::move(prim));
    }
    model_.meshes.push_back(std::move(mesh));
  }

  int addCamera(const Camera& c) {
    tinygltf::Camera cam;
    cam.name = c.name;
    // glTF has perspective and orthographic cameras; a paraboloid or latlong view is written as
    // the perspective camera at the same node (the projection itself is a render setting).
    if (c.projection == CameraProjection::Orthographic) {
      cam.type = "orthographic";
      cam.orthographic.xmag = c.xmag;
      cam.orthographic.ymag = c.ymag;
      cam.orthographic.znear = c.znear;
      cam.orthographic.zfar = c.zfar;
    } else {
      cam.type = "perspective";
      cam.perspective.yfov = c.yfov;
      cam.perspective.znear = c.znear;
      cam.perspective.zfar = c.zfar;
    }
    model_.cameras.push_back(std::move(cam));
    tinygltf::Node node;
    node.camera = static_cast<int>(model_.cameras.size() - 1);
    // In double, so that the loader's inverse of this comes back to the float view exactly
    // except for entries that should be 0 (those come back within ~1e-16 of it).
    node.matrix = matrixOf(glm::inverse(glm::dmat4(c.view)));
    return addNode(std::move(node));
  }

  int addLight(const Light& l) {
    tinygltf::Light light;
    light.name = l.name;
    light.color = {l.color.r, l.color.g, l.color.b};
    light.intensity = l.intensity;
    switch (l.type) {
      case LightType::Point: light.type = "point"; break;
      case LightType::Spot: light.type = "spot"; break;
      case LightType::Directional: light.type = "directional"; break;
    }
    if (l.type != LightType::Directional) HB_ASSERT(l.range > 0.0f);
    light.range = l.range;  // tinygltf writes it when > 0: always for point and spot lights
    light.spot.innerConeAngle = l.innerConeAngle;
    light.spot.outerConeAngle = l.outerConeAngle;
    tinygltf::Value::Object extras;
    extras["castShadows"] = tinygltf::Value(l.castShadows);
    extras["rangeFromEq41"] = tinygltf::Value(l.rangeFromEq41);
    light.extras = tinygltf::Value(std::move(extras));
    model_.lights.push_back(std::move(light));

    // The node's -Z axis is the light's direction (KHR_lights_punctual); its local Z column is
    // exactly -direction so that the loader's -Z comes back to the same vector; X and Y complete
    // a right-handed orthonormal frame around it.
    const glm::dvec3 z = -glm::dvec3(l.direction);
    const glm::dvec3 up = std::abs(z.y) < 0.9 * glm::length(z) ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
    const glm::dvec3 x = glm::normalize(glm::cross(up, z));
    const glm::dvec3 y = glm::normalize(glm::cross(z, x));
    const glm::dmat4 frame(glm::dvec4(x, 0.0), glm::dvec4(y, 0.0), glm::dvec4(z, 0.0),
                           glm::dvec4(glm::dvec3(l.position), 1.0));
    tinygltf::Node node;
    node.name = l.name;
    tinygltf::Value::Object ref;
    ref["light"] = tinygltf::Value(static_cast<int>(model_.lights.size() - 1));
    node.extensions["KHR_lights_punctual"] = tinygltf::Value(std::move(ref));
    node.matrix = matrixOf(frame);
    return addNode(std::move(node));
  }

  const Scene& scene_;
  tinygltf::Model model_;
  std::vector<unsigned char> bin_;
};

bool endsWithGlb(const std::string& path) {
  if (path.size() < 4) return false;
  return asciiLower(path.substr(path.size() - 4)) == ".glb";
}

}  // namespace

void exportGltf(const Scene& scene, const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
    throw InputError(path + ": the directory " + parent.string() + " does not exist; create it first");
  if (std::filesystem::is_directory(path, ec))
    throw InputError(path + ": is a folder, not a file; give the file to write, e.g. " +
                     (std::filesystem::path(path) / "scene.gltf").string());
  const tinygltf::Model model = Exporter(scene).build();
  tinygltf::TinyGLTF writer;
  const bool glb = endsWithGlb(path);
  if (!writer.WriteGltfSceneToFile(&model, path, /*embedImages=*/true, /*embedBuffers=*/true,
                                   /*prettyPrint=*/!glb, /*writeBinary=*/glb))
    throw InputError(path + ": cannot write the file; check that its directory is writable");
}

}  // namespace hb

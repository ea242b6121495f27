// sceneInfoText / sceneInfoJson / sceneSha256 (declared in gltf_io.h).
#include <algorithm>
#include <bit>
#include <cstring>
#include <limits>
#include <sstream>

#include "base/sha256.h"
#include "gltf/gltf_io.h"

namespace hb {
namespace {

const char* lightTypeName(LightType type) {
  switch (type) {
    case LightType::Point: return "point";
    case LightType::Spot: return "spot";
    case LightType::Directional: return "directional";
  }
  return "unknown";
}

// Feeds SHA-256 in 1 MiB blocks (one EVP call per value would dominate on large scenes). Values
// are written little-endian, fields one by one, so struct padding never reaches the hash.
class HashWriter {
 public:
  static_assert(std::endian::native == std::endian::little, "the hash layout is little-endian");

  void bytes(const void* data, size_t size) {
    // resize + memcpy rather than insert(): GCC 12 misreports insert() here (-Wstringop-overflow).
    const size_t old = buffer_.size();
    buffer_.resize(old + size);
    if (size) std::memcpy(buffer_.data() + old, data, size);
    if (buffer_.size() >= (1u << 20)) flush();
  }
  void u32(uint32_t v) { bytes(&v, 4); }
  void u64(uint64_t v) { bytes(&v, 8); }
  void f32(float v) { bytes(&v, 4); }
  void vec(const float* v, int n) { bytes(v, sizeof(float) * static_cast<size_t>(n)); }
  void mat(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c) vec(&m[c][0], 4);
  }
  void tag(const char* name) {  // section names keep differently split content apart
    u64(std::strlen(name));
    bytes(name, std::strlen(name));
  }
  std::string hexDigest() {
    flush();
    return sha_.hexDigest();
  }

 private:
  void flush() {
    sha_.update(buffer_.data(), buffer_.size());
    buffer_.clear();
  }
  Sha256 sha_;
  std::vector<uint8_t> buffer_;
};

}  // namespace

nlohmann::json sceneInfoJson(const Scene& scene) {
  nlohmann::json j;
  j["name"] = scene.name;
  j["triangles"] = scene.triangleCount();
  j["vertices"] = scene.vertices.size();
  j["indices"] = scene.indices.size();
  j["meshes"] = scene.meshes.size();
  j["instances"] = scene.instances.size();
  j["materials"] = scene.materials.size();
  j["textures"] = scene.textures.size();
  j["cameras"] = scene.cameras.size();

  nlohmann::json lights;
  size_t byType[3] = {0, 0, 0}, fromEq41 = 0;
  float rangeMin = std::numeric_limits<float>::max(), rangeMax = 0.0f;
  nlohmann::json list = nlohmann::json::array();
  for (const Light& l : scene.lights) {
    ++byType[static_cast<size_t>(l.type)];
    if (l.type != LightType::Directional) {  // a directional light's range means nothing
      rangeMin = std::min(rangeMin, l.range);
      rangeMax = std::max(rangeMax, l.range);
    }
    fromEq41 += l.rangeFromEq41 ? 1 : 0;
    list.push_back({{"name", l.name},
                    {"type", lightTypeName(l.type)},
                    {"range", l.range},
                    {"range_from_eq41", l.rangeFromEq41},
                    {"intensity", l.intensity},
                    {"cast_shadows", l.castShadows}});
  }
  lights["total"] = scene.lights.size();
  lights["point"] = byType[0];
  lights["spot"] = byType[1];
  lights["directional"] = byType[2];
  const bool anyRange = byType[0] + byType[1] > 0;
  lights["range_min"] = anyRange ? nlohmann::json(rangeMin) : nlohmann::json(nullptr);
  lights["range_max"] = anyRange ? nlohmann::json(rangeMax) : nlohmann::json(nullptr);
  lights["ranges_from_eq41"] = fromEq41;
  lights["list"] = std::move(list);
  j["lights"] = std::move(lights);
  // What the scene calls for (extras.effects); {} when it says nothing (the defaults apply).
  j["effects"] = scene.effects.is_null() ? nlohmann::json::object() : scene.effects;
  // How the file stored its geometry: null when plainly, else the compression extensions it used.
  j["compression"] = scene.compression.empty() ? nlohmann::json(nullptr) : nlohmann::json(scene.compression);

  if (scene.triangleCount() > 0) {
    glm::vec3 lo, hi;
    scene.bounds(lo, hi);
    const glm::vec3 size = hi - lo;
    j["bounds"] = {{"min", {lo.x, lo.y, lo.z}}, {"max", {hi.x, hi.y, hi.z}}, {"size_m", {size.x, size.y, size.z}}};
  } else {
    j["bounds"] = nullptr;
  }
  return j;
}

std::string sceneInfoText(const Scene& scene) {
  const nlohmann::json j = sceneInfoJson(scene);
  std::ostringstream out;
  out << "scene      " << scene.name << "\n"
      << "triangles  " << j["triangles"].get<uint64_t>() << " (over instances)\n"
      << "vertices   " << scene.vertices.size() << ", indices " << scene.indices.size() << "\n"
      << "meshes     " << scene.meshes.size() << ", instances " << scene.instances.size() << "\n"
      << "materials  " << scene.materials.size() << ", textures " << scene.textures.size() << "\n"
      << "cameras    " << scene.cameras.size() << "\n";
  const nlohmann::json& lights = j["lights"];
  out << "lights     " << scene.lights.size() << " (point " << lights["point"].get<size_t>() << ", spot "
      << lights["spot"].get<size_t>() << ", directional " << lights["directional"].get<size_t>() << ")";
  if (!lights["range_min"].is_null())
    out << ", range " << lights["range_min"].get<float>() << " .. " << lights["range_max"].get<float>() << " m, "
        << lights["ranges_from_eq41"].get<size_t>() << " from eq. 4.1";
  out << "\n";
  for (const Light& l : scene.lights) {
    out << "  " << lightTypeName(l.type) << " '" << l.name << "' intensity " << l.intensity;
    if (l.type != LightType::Directional) out << " range " << l.range << " m" << (l.rangeFromEq41 ? " (eq. 4.1)" : "");
    out << (l.castShadows ? "" : " no shadows") << "\n";
  }
  out << "effects    " << (scene.effects.is_null() ? std::string("(none: the defaults apply)") : scene.effects.dump())
      << "\n";
  if (!scene.compression.empty()) out << "compressed " << scene.compression << "\n";
  if (j["bounds"].is_null()) {
    out << "bounds     (empty)\n";
  } else {
    auto v3 = [](const nlohmann::json& a) {
      std::ostringstream s;
      s << "(" << a[0].get<float>() << ", " << a[1].get<float>() << ", " << a[2].get<float>() << ")";
      return s.str();
    };
    out << "bounds     " << v3(j["bounds"]["min"]) << " .. " << v3(j["bounds"]["max"]) << "\n"
        << "size       " << v3(j["bounds"]["size_m"]) << " m\n";
  }
  return out.str();
}

std::string sceneGeometrySha256(const Scene& scene) {
  HashWriter h;
  h.tag("hybridbench-geometry-v1");
  const std::vector<glm::vec3> tris = scene.worldTriangles();
  h.u64(tris.size() / 3);
  for (const glm::vec3& v : tris) h.vec(&v.x, 3);
  return h.hexDigest();
}

std::string sceneSha256(const Scene& scene) {
  HashWriter h;
  h.tag("hybridbench-scene-v1");
  h.tag("vertices");
  h.u64(scene.vertices.size());
  for (const Vertex& v : scene.vertices) {
    h.vec(&v.position.x, 3);
    h.vec(&v.normal.x, 3);
    h.vec(&v.uv.x, 2);
  }
  h.tag("indices");
  h.u64(scene.indices.size());
  h.bytes(scene.indices.data(), scene.indices.size() * sizeof(uint32_t));
  h.tag("meshes");
  h.u64(scene.meshes.size());
  for (const Mesh& m : scene.meshes) {
    h.u64(m.primitives.size());
    for (const Primitive& p : m.primitives) {
      h.u32(p.firstIndex);
      h.u32(p.indexCount);
      h.u32(p.vertexOffset);
      h.u32(p.vertexCount);
      h.u32(p.material);
    }
  }
  h.tag("instances");
  h.u64(scene.instances.size());
  for (const Instance& i : scene.instances) {
    h.u32(i.mesh);
    h.mat(i.transform);
  }
  h.tag("materials");
  h.u64(scene.materials.size());
  for (const Material& m : scene.materials) {
    h.vec(&m.baseColorFactor.x, 4);
    h.f32(m.metallicFactor);
    h.f32(m.roughnessFactor);
    h.u32(static_cast<uint32_t>(m.baseColorTexture));
    h.u32(static_cast<uint32_t>(m.metallicRoughnessTexture));
    h.u32(m.doubleSided ? 1 : 0);
  }
  h.tag("textures");
  h.u64(scene.textures.size());
  for (const Texture& t : scene.textures) {
    h.u32(t.width);
    h.u32(t.height);
    h.u32(t.srgb ? 1 : 0);
    h.u64(t.rgba.size());
    h.bytes(t.rgba.data(), t.rgba.size());
  }
  h.tag("lights");
  h.u64(scene.lights.size());
  for (const Light& l : scene.lights) {
    h.u32(static_cast<uint32_t>(l.type));
    h.vec(&l.position.x, 3);
    h.vec(&l.direction.x, 3);
    h.vec(&l.color.x, 3);
    h.f32(l.intensity);
    h.f32(l.range);
    h.u32(l.rangeFromEq41 ? 1 : 0);
    h.f32(l.innerConeAngle);
    h.f32(l.outerConeAngle);
    h.u32(l.castShadows ? 1 : 0);
  }
  if (!scene.effects.is_null()) {  // only when present: hashes of scenes without it stay as they were
    h.tag("effects");
    const std::string text = scene.effects.dump();
    h.bytes(text.data(), text.size());
  }
  h.tag("cameras");
  h.u64(scene.cameras.size());
  for (const Camera& c : scene.cameras) {
    h.mat(c.view);
    h.f32(c.yfov);
    h.f32(c.znear);
    h.f32(c.zfar);
  }
  return h.hexDigest();
}

}  // namespace hb

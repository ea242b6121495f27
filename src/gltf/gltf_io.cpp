// glTF 2.0 loading (tinygltf parses, this file validates and converts). tinygltf checks the JSON
// structure but not that accessors fit their buffers or that indices fit their vertices, so every
// byte range and index is checked here before it is read.
// The Loader (gltf_load_internal.h) is split by concern: this file holds loadGltf, the node
// graph, cameras and lights; gltf_accessors.cpp, gltf_meshes.cpp and gltf_materials.cpp the rest.
#include "gltf/gltf_io.h"

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

#include "base/errors.h"
#include "base/input_file.h"
#include "gltf/gltf_load_internal.h"
#include "gltf/gltf_structure.h"
#include "plan/effects.h"
#include "scene/ambient_json.h"
#include "scene/environment.h"

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

// Whether the scene's floats can hold a double of the file: finite and at most 3.4e38 in magnitude
// (found by fuzz_gltf: a node translation of 3e120, finite as the file's double, put a light at
// infinity; a camera node of scale 0 gave an inf/NaN view).
bool fitsFloat(double v) { return std::abs(v) <= double(std::numeric_limits<float>::max()); }
bool fitsFloat(const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int k = 0; k < 4; ++k)
      if (!fitsFloat(m[c][k])) return false;
  return true;
}

std::string num(double v) {  // shortest readable form: 5, -2, 0.25, 1e+30, nan
  std::ostringstream s;
  s << v;
  return s.str();
}

// The KHR_lights_punctual light array as written, read past tinygltf to see which lights have a
// "range" (tinygltf stores a missing range as 0). Null when the file has none.
// The file's JSON as nlohmann::json (tinygltf's Value drops what these readers need to check),
// or null when it cannot be read (tinygltf has then already failed with its own message).
nlohmann::json rawDocument(std::span<const uint8_t> bytes, bool binary) {
  std::string text;
  if (binary) {
    // GLB: 12-byte header, then chunk 0 = JSON: uint32 length, uint32 type, data.
    uint32_t length = 0;
    if (bytes.size() < 20) return nullptr;
    std::memcpy(&length, bytes.data() + 12, 4);
    if (length > bytes.size() - 20) return nullptr;
    text.assign(reinterpret_cast<const char*>(bytes.data()) + 20, length);
  } else {
    text.assign(bytes.begin(), bytes.end());
  }
  nlohmann::json doc = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  return doc.is_object() ? doc : nlohmann::json();
}

// tinygltf's file reader for external buffers and images, but only for regular files. Its own
// sizes the buffer by seeking to the end, which on a directory (a URI such as "textures/") gives
// 2^63 - 1 on ext4: it threw bad_alloc, out of the loader as an internal error (found by
// fuzz_gltf). A FIFO or device would block or read nothing; the URI must name a file.
bool readRegularFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* userData) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    if (err) *err += "not a regular file (a directory?)";
    return false;
  }
  return tinygltf::ReadWholeFile(out, err, path, userData);
}

nlohmann::json rawLightsJson(const nlohmann::json& doc) {
  if (!doc.is_object()) return nullptr;
  auto ext = doc.find("extensions");
  if (ext == doc.end() || !ext->is_object()) return nullptr;
  auto lights = ext->find(kLightsExtension);
  if (lights == ext->end() || !lights->is_object()) return nullptr;
  auto array = lights->find("lights");
  return array != lights->end() ? *array : nlohmann::json();
}

// The effects the scene calls for: scenes[s].extras.effects of the scene that is loaded, checked
// against the effects schema (plan/effects.h) with the file and key path in every message; and
// its ambient term, scenes[s].extras.ambient (scene/ambient_json.h), and its environment,
// scenes[s].extras.environment (scene/environment.h).
void readSceneEffects(const nlohmann::json& doc, const tinygltf::Model& model, const std::string& path, Scene& scene) {
  if (!doc.is_object() || !doc.contains("scenes") || !doc["scenes"].is_array() || model.scenes.empty()) return;
  const size_t s = static_cast<size_t>(model.defaultScene >= 0 ? model.defaultScene : 0);
  if (s >= doc["scenes"].size()) return;
  const nlohmann::json& gscene = doc["scenes"][s];
  if (!gscene.is_object() || !gscene.contains("extras") || !gscene["extras"].is_object()) return;
  const std::string extrasPath = "scenes[" + std::to_string(s) + "].extras";
  if (gscene["extras"].contains("ambient"))
    scene.ambient = readAmbient(nlohmann::ordered_json(gscene["extras"]["ambient"]),
                                json_reader::Where{path, extrasPath + ".ambient"});
  if (gscene["extras"].contains("environment"))
    scene.environment = readEnvironment(nlohmann::ordered_json(gscene["extras"]["environment"]),
                                        json_reader::Where{path, extrasPath + ".environment"},
                                        std::filesystem::path(path).parent_path());
  if (!gscene["extras"].contains("effects")) return;
  const nlohmann::json& effects = gscene["extras"]["effects"];
  validateEffects(effects, json_reader::Where{path, "scenes[" + std::to_string(s) + "].extras.effects"});
  scene.effects = effects;
  scene.effectsOrigin = path;
}

}  // namespace

namespace gltf_detail {

Scene Loader::load(GltfLoadWarnings& warnings) {
  warnings_ = &warnings;
  checkExtensions(model_, path_, warnings);
  loadTextures();
  loadMaterials();
  for (size_t m = 0; m < model_.meshes.size(); ++m) loadMesh(static_cast<int>(m));
  loadNodes();
  markSrgbTextures();
  if (warnings.skippedBroken > 0) {
    if (scene_.triangleCount() == 0) throw InputError(firstBrokenPrimitive_);  // nothing else to draw
    const std::string message =
        firstBrokenPrimitive_.substr(firstBrokenPrimitive_.rfind(path_ + ": ", 0) == 0 ? path_.size() + 2 : 0);
    warnings.messages.push_back(path_ + ": skipped " + std::to_string(warnings.skippedBroken) +
                                " triangle primitive(s) whose data is broken, so the image lacks them; first" +
                                (firstBrokenMesh_.empty() ? "" : " in mesh \"" + firstBrokenMesh_ + "\"") + ": " +
                                message);
  }
  warnIgnoredAnimation(warnings);
  if (warnings.skippedPrimitives > 0) {
    if (scene_.indices.empty())
      fail(firstSkippedPrimitive_, "every primitive is points or lines, which draw no surface to render",
           "give the scene triangle primitives (mode 4, 5 or 6)");
    warnings.messages.push_back(path_ + ": skipped " + std::to_string(warnings.skippedPrimitives) +
                                " primitive(s) of points or lines (they draw no surface), first " +
                                firstSkippedPrimitive_);
  }
  if (scene_.triangleCount() == 0) refuseEmptyScene();
  if (warnings.skippedCameras > 0)
    warnings.messages.push_back(path_ + ": skipped " + std::to_string(warnings.skippedCameras) +
                                " camera node(s) that are neither perspective nor orthographic, first " +
                                firstSkippedCamera_);
  return std::move(scene_);
}

// Skins, morph targets and animations are not read: the scene is drawn as its nodes and meshes
// stand. One line names what was left, so that a figure that should move does not stand still unsaid.
void Loader::warnIgnoredAnimation(GltfLoadWarnings& warnings) const {
  size_t morphed = 0;
  for (const tinygltf::Mesh& mesh : model_.meshes)
    for (const tinygltf::Primitive& prim : mesh.primitives) morphed += prim.targets.empty() ? 0 : 1;
  std::vector<std::string> parts;
  if (!model_.skins.empty()) parts.push_back(std::to_string(model_.skins.size()) + " skin(s)");
  if (morphed > 0) parts.push_back("the morph targets of " + std::to_string(morphed) + " primitive(s)");
  if (!model_.animations.empty()) parts.push_back(std::to_string(model_.animations.size()) + " animation(s)");
  if (parts.empty()) return;
  std::string list;
  for (size_t i = 0; i < parts.size(); ++i) list += (i == 0 ? "" : i + 1 == parts.size() ? " and " : ", ") + parts[i];
  warnings.messages.push_back(path_ + ": ignored " + list +
                              " (not read): meshes are drawn in their bind pose and base shape, nodes where "
                              "their own transforms put them");
}

// Nothing to draw: says why, at the glTF path where it shows (checked before any message is printed
// or folder created, so a refused scene leaves nothing behind).
void Loader::refuseEmptyScene() const {
  if (model_.scenes.empty() && model_.nodes.empty())
    fail("scenes", "the file holds no scene and no nodes, so nothing to draw",
         "export the scene itself (its scenes and nodes), not only its meshes or materials");
  if (!model_.scenes.empty()) {
    const int s = model_.defaultScene >= 0 ? model_.defaultScene : 0;
    const std::string at = "scenes[" + std::to_string(s) + "]";
    if (model_.scenes[static_cast<size_t>(s)].nodes.empty())
      fail(at + ".nodes", "the scene has no nodes, so nothing to draw", "list the scene's root nodes in it");
    fail(at, "none of its nodes (nor their children) has a mesh of triangles", "give a node of the scene a mesh");
  }
  fail("nodes", "the file has no scenes and none of its root nodes (nor their children) has a mesh of triangles",
       "give a node a mesh, and list the root nodes in a scene");
}

void Loader::fail(const std::string& field, const std::string& problem, const std::string& fix) const {
  throw InputError(path_ + ": " + field + ": " + problem + "; " + fix);
}

size_t Loader::checkIndex(int index, size_t size, const std::string& field, const std::string& arrayName) const {
  if (index < 0 || static_cast<size_t>(index) >= size)
    fail(field,
         "index " + std::to_string(index) + " does not exist (" + arrayName + " has " + std::to_string(size) +
             " elements)",
         "point it at an existing element of " + arrayName);
  return static_cast<size_t>(index);
}

void Loader::loadNodes() {
  std::vector<int> roots;
  if (!model_.scenes.empty()) {
    int s = model_.defaultScene >= 0 ? model_.defaultScene : 0;
    const tinygltf::Scene& gscene = model_.scenes[checkIndex(s, model_.scenes.size(), "scene", "scenes")];
    roots = gscene.nodes;
    scene_.name = gscene.name;
    for (size_t r = 0; r < roots.size(); ++r)
      checkIndex(roots[r], model_.nodes.size(), "scenes[" + std::to_string(s) + "].nodes[" + std::to_string(r) + "]",
                 "nodes");
  } else {  // no scene: every node that is nobody's child
    std::vector<uint8_t> isChild(model_.nodes.size(), 0);
    for (size_t n = 0; n < model_.nodes.size(); ++n)
      for (size_t c = 0; c < model_.nodes[n].children.size(); ++c)
        isChild[checkIndex(model_.nodes[n].children[c], model_.nodes.size(),
                           "nodes[" + std::to_string(n) + "].children[" + std::to_string(c) + "]", "nodes")] = 1;
    for (size_t n = 0; n < model_.nodes.size(); ++n)
      if (!isChild[n]) roots.push_back(static_cast<int>(n));
  }
  onPath_.assign(model_.nodes.size(), 0);
  for (int root : roots) visitNode(root, glm::dmat4(1.0), 0);
}

glm::dmat4 Loader::localTransform(const tinygltf::Node& node, const std::string& field) const {
  glm::dmat4 local(1.0);
  if (!node.matrix.empty()) {
    if (node.matrix.size() != 16)
      fail(field + ".matrix", "has " + std::to_string(node.matrix.size()) + " numbers", "give it 16 (column-major)");
    local = glm::make_mat4(node.matrix.data());  // glTF and glm are both column-major
  } else {
    auto need = [&](const std::vector<double>& v, size_t n, const char* name) {
      if (!v.empty() && v.size() != n)
        fail(field + "." + name, "has " + std::to_string(v.size()) + " numbers", "give it " + std::to_string(n));
      return !v.empty();
    };
    glm::dmat4 t(1.0), r(1.0), s(1.0);
    if (need(node.translation, 3, "translation"))
      t = glm::translate(glm::dmat4(1.0), glm::make_vec3(node.translation.data()));
    if (need(node.rotation, 4,
             "rotation"))  // glTF stores x, y, z, w; glm's constructor takes w first
      r = glm::mat4_cast(glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
    if (need(node.scale, 3, "scale")) s = glm::scale(glm::dmat4(1.0), glm::make_vec3(node.scale.data()));
    local = t * r * s;
  }
  for (int c = 0; c < 4; ++c)
    for (int k = 0; k < 4; ++k)
      if (!std::isfinite(local[c][k])) fail(field, "the transform is not finite", "write finite matrix/TRS numbers");
  return local;
}

void Loader::visitNode(int nodeIndex, const glm::dmat4& parent, int depth) {
  const std::string field = "nodes[" + std::to_string(nodeIndex) + "]";
  const size_t n = checkIndex(nodeIndex, model_.nodes.size(), field, "nodes");
  if (onPath_[n] || depth > kMaxNodeDepth)
    fail(field + ".children",
         "the node hierarchy has a cycle (or is deeper than " + std::to_string(kMaxNodeDepth) + ")",
         "make the nodes a tree: no node may be its own ancestor");
  const tinygltf::Node& node = model_.nodes[n];
  const glm::dmat4 world = parent * localTransform(node, field);
  if (!fitsFloat(world))
    fail(field, "its world transform (its ancestors' times its own) has a number beyond 3.4e38",
         "scale the node transforms down so that a float holds them");
  if (node.mesh >= 0) {
    Instance inst;
    inst.mesh = static_cast<uint32_t>(checkIndex(node.mesh, model_.meshes.size(), field + ".mesh", "meshes"));
    inst.transform = glm::mat4(world);
    scene_.instances.push_back(inst);
  }
  if (node.camera >= 0) addCamera(checkIndex(node.camera, model_.cameras.size(), field + ".camera", "cameras"), world);
  if (auto it = node.extensions.find(kLightsExtension); it != node.extensions.end()) {
    const std::string lightField = field + ".extensions." + kLightsExtension + ".light";
    if (!it->second.IsObject() || !it->second.Get("light").IsNumber())
      fail(lightField, "missing or not an integer", "write {\"light\": <index>}");
    size_t l = checkIndex(it->second.Get("light").GetNumberAsInt(), model_.lights.size(), lightField,
                          std::string("extensions.") + kLightsExtension + ".lights");
    addLight(l, world);
  }
  onPath_[n] = 1;
  for (int child : node.children) visitNode(child, world, depth + 1);
  onPath_[n] = 0;
}

void Loader::addCamera(size_t c, const glm::dmat4& world) {
  const tinygltf::Camera& cam = model_.cameras[c];
  const std::string field = "cameras[" + std::to_string(c) + "]";
  auto viewOf = [&] {  // the node's inverse, in double
    const glm::dmat4 view = glm::inverse(world);
    if (!fitsFloat(view))
      fail("nodes (of " + field + ")", "the node's transform has no inverse a float can hold",
           "give the camera's node a non-zero scale");
    return glm::mat4(view);
  };
  if (cam.type == "orthographic") {
    const tinygltf::OrthographicCamera& o = cam.orthographic;
    if (!(o.xmag != 0.0 && fitsFloat(o.xmag)) || !(o.ymag != 0.0 && fitsFloat(o.ymag)))
      fail(field + ".orthographic", "has xmag " + num(o.xmag) + ", ymag " + num(o.ymag),
           "give non-zero finite half-extents");
    if (!(o.znear >= 0.0 && fitsFloat(o.znear)))
      fail(field + ".orthographic.znear", "is " + num(o.znear), "give a near distance >= 0");
    if (!(o.zfar > o.znear && fitsFloat(o.zfar)))
      fail(field + ".orthographic.zfar", "is " + num(o.zfar) + ", not beyond znear",
           "give a far distance greater than znear");
    Camera out;
    out.name = cam.name;
    out.view = viewOf();
    out.projection = CameraProjection::Orthographic;
    // glTF's signs of xmag/ymag flip the image; the view's extent is their magnitude.
    out.xmag = static_cast<float>(std::abs(o.xmag));
    out.ymag = static_cast<float>(std::abs(o.ymag));
    out.znear = static_cast<float>(o.znear);
    out.zfar = static_cast<float>(o.zfar);
    scene_.cameras.push_back(out);
    return;
  }
  if (cam.type != "perspective") {
    if (warnings_->skippedCameras++ == 0) firstSkippedCamera_ = field + " (" + cam.type + ")";
    return;
  }
  const tinygltf::PerspectiveCamera& p = cam.perspective;
  if (!(p.yfov > 0.0 && p.yfov < glm::pi<double>()))
    fail(field + ".perspective.yfov", "is " + num(p.yfov), "give a field of view in (0, pi) radians");
  if (!(p.znear > 0.0 && fitsFloat(p.znear)))
    fail(field + ".perspective.znear", "is " + num(p.znear), "give a positive near distance");
  if (p.zfar != 0.0 && !(p.zfar > p.znear && fitsFloat(p.zfar)))  // tinygltf: 0 = absent
    fail(field + ".perspective.zfar", "is " + num(p.zfar) + ", not beyond znear",
         "give a far distance greater than znear or leave it out");
  Camera out;
  out.name = cam.name;
  // Inverted in double: the result is within a few double ulps of the exact inverse, so it
  // rounds to the float a float inverse would only approximate.
  out.view = viewOf();
  out.yfov = static_cast<float>(p.yfov);
  out.znear = static_cast<float>(p.znear);
  out.zfar = p.zfar != 0.0 ? static_cast<float>(p.zfar) : kDefaultZfar;
  scene_.cameras.push_back(out);
}

void Loader::addLight(size_t l, const glm::dmat4& world) {
  const tinygltf::Light& light = model_.lights[l];
  const std::string field = std::string("extensions.") + kLightsExtension + ".lights[" + std::to_string(l) + "]";
  const nlohmann::json* raw =
      rawLights_.is_array() && l < rawLights_.size() && rawLights_[l].is_object() ? &rawLights_[l] : nullptr;
  Light out;
  out.name = light.name;
  if (light.type == "point")
    out.type = LightType::Point;
  else if (light.type == "spot")
    out.type = LightType::Spot;
  else if (light.type == "directional")
    out.type = LightType::Directional;
  else
    fail(field + ".type", "'" + light.type + "' is not a punctual light type", "use point, spot or directional");
  if (!light.color.empty()) {
    if (light.color.size() != 3)
      fail(field + ".color", "has " + std::to_string(light.color.size()) + " numbers", "give it 3 (linear RGB)");
    for (double component : light.color)
      if (!fitsFloat(component))
        fail(field + ".color", "has " + num(component), "give linear RGB factors below 3.4e38");
    out.color = glm::vec3(glm::make_vec3(light.color.data()));
  }
  if (!(light.intensity >= 0.0 && fitsFloat(light.intensity)))
    fail(field + ".intensity", "is " + num(light.intensity), "give a finite intensity >= 0");
  out.intensity = static_cast<float>(light.intensity);
  // tinygltf reads a missing range as 0, so whether it was written comes from the raw JSON.
  const bool hasRange = raw != nullptr && raw->contains("range");
  if (hasRange && !(light.range > 0.0 && fitsFloat(light.range)))
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
      fail(field + ".spot", "cone angles inner " + num(inner) + ", outer " + num(outer) + " are invalid",
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
    if (hasRange && light.extras.Has("rangeFromEq41") && light.extras.Get("rangeFromEq41").IsBool())
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

}  // namespace gltf_detail

Scene loadGltf(const std::string& path, GltfLoadWarnings* warnings) {
  const std::vector<uint8_t> bytes =
      readInputBytes(path, "give a .gltf or .glb file, or a built-in scene name (hybridbench scene list)");
  // The base directory tinygltf's own file loaders use: all before the last '/' or '\'.
  const size_t slash = path.find_last_of("/\\");
  return loadGltfFromMemory(bytes, path, slash == std::string::npos ? "" : path.substr(0, slash), warnings);
}

Scene loadGltfFromMemory(std::span<const uint8_t> bytes, const std::string& path, const std::string& baseDir,
                         GltfLoadWarnings* warnings) {
  if (bytes.size() > std::numeric_limits<uint32_t>::max())  // tinygltf takes 32-bit sizes
    throw InputError(path + ": is larger than 4 GiB, more than glTF can hold; split the scene");
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;

  // glTF 1.0, then the fields' JSON types (tinygltf would skip a field of the wrong type without a
  // word), then the external buffers (tinygltf's "File not found" reads as a file that is not glTF).
  const nlohmann::json doc = rawDocument(bytes, binary);
  gltf_detail::refuseGltf1(doc, bytes, binary, path);
  GltfLoadWarnings local;
  GltfLoadWarnings& said = warnings ? *warnings : local;
  for (std::string& line : gltf_detail::checkGltfStructure(doc, path)) said.messages.push_back(std::move(line));
  gltf_detail::checkExternalBuffers(doc, path, baseDir);

  // Compressed geometry: the few JSON fields tinygltf 2.7 refuses are rewritten, and decoded after.
  const gltf_detail::CompressedInput compressed = gltf_detail::prepareCompressed(doc, bytes, binary);
  if (!compressed.bytes.empty()) bytes = compressed.bytes;
  tinygltf::TinyGLTF gltf;
  tinygltf::Model model;
  gltf.SetImageLoader(gltf_detail::checkedImageLoader, &model);
  gltf.SetFsCallbacks(
      {&tinygltf::FileExists, &tinygltf::ExpandFilePath, &readRegularFile, &tinygltf::WriteWholeFile, nullptr});
  const auto size = static_cast<unsigned int>(bytes.size());
  std::string err, warn;
  bool ok = false;
  if (bytes.empty())
    err = "Empty file.";  // what tinygltf's file loader says
  else if (binary)
    ok = gltf.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), size, baseDir);
  else
    ok = gltf.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(bytes.data()), size, baseDir);
  // An image our loader refused (gltf_materials.cpp checkedImageLoader: "images[N]..."): the file is
  // valid glTF, its texture is not; the line says so and names the image.
  if (!ok && err.rfind("images[", 0) == 0) throw InputError(path + ": " + oneLine(err));
  if (!ok)
    throw InputError(path + ": not a valid glTF 2.0 " + (binary ? "binary (.glb)" : "JSON (.gltf)") +
                     " file: " + oneLine(err.empty() ? warn : err) +
                     "; re-export it as glTF 2.0 or check it with the Khronos glTF validator");
  if (model.asset.version.rfind("2.", 0) != 0)
    throw InputError(path + ": asset.version: '" + model.asset.version + "' is not 2.x; re-export it as glTF 2.0");

  const std::string compression = gltf_detail::decodeCompressed(model, compressed, path);

  const nlohmann::json rawLights = rawLightsJson(doc);
  Scene scene = gltf_detail::Loader(path, model, rawLights).load(said);
  scene.compression = compression;
  readSceneEffects(doc, model, path, scene);
  if (scene.name.empty()) scene.name = std::filesystem::path(path).stem().string();
  if (!warnings)
    for (const std::string& line : local.messages) std::cerr << "warning: " << line << "\n";
  return scene;
}

}  // namespace hb

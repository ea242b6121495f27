#include "gltf/gltf_structure.h"

#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <utility>

#include "base/errors.h"

namespace hb::gltf_detail {

namespace {

using nlohmann::json;

enum class Kind { Object, Array, Integer, Number, String, Bool };

const char* kindName(Kind k) {
  switch (k) {
    case Kind::Object: return "an object";
    case Kind::Array: return "an array";
    case Kind::Integer: return "a non-negative integer";
    case Kind::Number: return "a number";
    case Kind::String: return "a string";
    case Kind::Bool: return "true or false";
  }
  return "?";
}

std::string describe(const json& v) {
  switch (v.type()) {
    case json::value_t::object: return "an object";
    case json::value_t::array: return "an array";
    case json::value_t::string: return "the string " + v.dump();
    case json::value_t::boolean: return v.dump();
    case json::value_t::null: return "null";
    default: return v.dump();
  }
}

std::string join(const std::string& at, const char* key) { return at.empty() ? std::string(key) : at + "." + key; }

bool is(const json& v, Kind k) {
  switch (k) {
    case Kind::Object: return v.is_object();
    case Kind::Array: return v.is_array();
    case Kind::Integer: return v.is_number_unsigned() || (v.is_number_integer() && v.get<int64_t>() >= 0);
    case Kind::Number: return v.is_number();
    case Kind::String: return v.is_string();
    case Kind::Bool: return v.is_boolean();
  }
  return false;
}

class Checker {
 public:
  explicit Checker(std::string path) : path_(std::move(path)) {}

  // A "name" changes nothing drawn: one that is not a string is not refused but counted (tinygltf
  // leaves it empty; the scene's own name then comes from the file's).
  void name(const json& v, const std::string& at) {
    if (!v.contains("name") || v["name"].is_string()) return;
    if (ignoredNames_++ == 0) firstIgnoredName_ = join(at, "name") + " (" + describe(v["name"]) + ")";
  }
  // The one warning line about ignored names, or none.
  std::vector<std::string> warnings() const {
    if (ignoredNames_ == 0) return {};
    return {path_ + ": ignored " + std::to_string(ignoredNames_) +
            " name(s) that are not strings (a name changes nothing drawn), first " + firstIgnoredName_};
  }

  [[noreturn]] void fail(const std::string& field, const std::string& expected, const json& got) const {
    throw InputError(path_ + ": " + field + ": expected " + expected + ", got " + describe(got) +
                     "; fix the exporter's output (the Khronos glTF validator shows every such error)");
  }

  // `v[key]` when present must be of kind k.
  void field(const json& v, const std::string& at, const char* key, Kind k) const {
    if (!v.contains(key)) return;
    if (!is(v[key], k)) fail(join(at, key), kindName(k), v[key]);
  }

  // `v[key]` when present must be an array of kind k elements (of exactly n when n > 0).
  void arrayOf(const json& v, const std::string& at, const char* key, Kind k, size_t n = 0) const {
    if (!v.contains(key)) return;
    const json& a = v[key];
    const std::string name = join(at, key);
    if (!a.is_array()) fail(name, n ? "an array of " + std::to_string(n) + " numbers" : std::string("an array"), a);
    if (n && a.size() != n) fail(name, "an array of " + std::to_string(n) + " numbers", a);
    for (size_t i = 0; i < a.size(); ++i)
      if (!is(a[i], k)) fail(name + "[" + std::to_string(i) + "]", kindName(k), a[i]);
  }

  // `v[key]`, when present, must be an array of objects; calls each(element, its path). prefix:
  // the path of v with a trailing ".", empty at the top level.
  template <class F>
  void objects(const json& v, const std::string& prefix, const char* key, F each) const {
    if (!v.contains(key)) return;
    const json& a = v[key];
    if (!a.is_array()) fail(prefix + key, "an array", a);
    for (size_t i = 0; i < a.size(); ++i) {
      const std::string at = prefix + key + "[" + std::to_string(i) + "]";
      if (!a[i].is_object()) fail(at, "an object", a[i]);
      each(a[i], at);
    }
  }

  // v[key] when present must be an object; then each(object, its path).
  template <class F>
  void object(const json& v, const std::string& at, const char* key, F each) const {
    if (!v.contains(key)) return;
    if (!v[key].is_object()) fail(join(at, key), "an object", v[key]);
    each(v[key], join(at, key));
  }

  void textureInfo(const json& v, const std::string& at, const char* key) const {
    object(v, at, key, [&](const json& t, const std::string& tat) {
      field(t, tat, "index", Kind::Integer);
      field(t, tat, "texCoord", Kind::Integer);
      field(t, tat, "scale", Kind::Number);
      field(t, tat, "strength", Kind::Number);
      // KHR_texture_transform moves, turns and scales the texture: a field of the wrong type would
      // draw it untransformed.
      object(t, tat, "extensions", [&](const json& e, const std::string& eat) {
        object(e, eat, "KHR_texture_transform", [&](const json& x, const std::string& xat) {
          arrayOf(x, xat, "offset", Kind::Number, 2);
          arrayOf(x, xat, "scale", Kind::Number, 2);
          field(x, xat, "rotation", Kind::Number);
          field(x, xat, "texCoord", Kind::Integer);
        });
      });
    });
  }

 private:
  std::string path_;
  size_t ignoredNames_ = 0;
  std::string firstIgnoredName_;
};

}  // namespace

std::vector<std::string> checkGltfStructure(const json& doc, const std::string& path) {
  if (!doc.is_object()) return {};  // not JSON at all: tinygltf's parse error says so
  Checker c(path);
  c.field(doc, "", "scene", Kind::Integer);
  c.object(doc, "", "asset", [&](const json& a, const std::string& at) { c.field(a, at, "version", Kind::String); });
  c.arrayOf(doc, "", "extensionsUsed", Kind::String);
  c.arrayOf(doc, "", "extensionsRequired", Kind::String);
  c.objects(doc, "", "scenes", [&](const json& s, const std::string& at) {
    c.arrayOf(s, at, "nodes", Kind::Integer);
    c.name(s, at);
  });
  c.objects(doc, "", "nodes", [&](const json& n, const std::string& at) {
    for (const char* k : {"camera", "mesh", "skin"}) c.field(n, at, k, Kind::Integer);
    c.arrayOf(n, at, "children", Kind::Integer);
    c.arrayOf(n, at, "matrix", Kind::Number, 16);
    c.arrayOf(n, at, "rotation", Kind::Number, 4);
    c.arrayOf(n, at, "scale", Kind::Number, 3);
    c.arrayOf(n, at, "translation", Kind::Number, 3);
    c.name(n, at);
  });
  c.objects(doc, "", "meshes", [&](const json& m, const std::string& at) {
    c.objects(m, at + ".", "primitives", [&](const json& p, const std::string& pAt) {
      c.object(p, pAt, "attributes", [&](const json& attrs, const std::string& aat) {
        for (auto it = attrs.begin(); it != attrs.end(); ++it)
          if (!is(it.value(), Kind::Integer)) c.fail(aat + "." + it.key(), "an accessor index", it.value());
      });
      for (const char* k : {"indices", "material", "mode"}) c.field(p, pAt, k, Kind::Integer);
      if (p.contains("targets") && !p["targets"].is_array()) c.fail(pAt + ".targets", "an array", p["targets"]);
    });
    c.name(m, at);
  });
  // min and max (bounds for a viewer) and a bufferView's target (a GPU binding hint) are not read:
  // the loader checks every index and byte range itself.
  c.objects(doc, "", "accessors", [&](const json& a, const std::string& at) {
    for (const char* k : {"bufferView", "byteOffset", "componentType", "count"}) c.field(a, at, k, Kind::Integer);
    c.field(a, at, "type", Kind::String);
    c.field(a, at, "normalized", Kind::Bool);
    c.object(a, at, "sparse", [](const json&, const std::string&) {});
    c.name(a, at);
  });
  c.objects(doc, "", "bufferViews", [&](const json& b, const std::string& at) {
    for (const char* k : {"buffer", "byteOffset", "byteLength", "byteStride"}) c.field(b, at, k, Kind::Integer);
    c.name(b, at);
  });
  c.objects(doc, "", "buffers", [&](const json& b, const std::string& at) {
    c.field(b, at, "byteLength", Kind::Integer);
    c.field(b, at, "uri", Kind::String);
    c.name(b, at);
  });
  c.objects(doc, "", "materials", [&](const json& m, const std::string& at) {
    c.object(m, at, "pbrMetallicRoughness", [&](const json& p, const std::string& pat) {
      c.arrayOf(p, pat, "baseColorFactor", Kind::Number, 4);
      c.field(p, pat, "metallicFactor", Kind::Number);
      c.field(p, pat, "roughnessFactor", Kind::Number);
      c.textureInfo(p, pat, "baseColorTexture");
      c.textureInfo(p, pat, "metallicRoughnessTexture");
    });
    for (const char* k : {"normalTexture", "occlusionTexture", "emissiveTexture"}) c.textureInfo(m, at, k);
    c.arrayOf(m, at, "emissiveFactor", Kind::Number, 3);
    c.field(m, at, "alphaMode", Kind::String);
    c.field(m, at, "alphaCutoff", Kind::Number);
    c.field(m, at, "doubleSided", Kind::Bool);
    c.name(m, at);
  });
  c.objects(doc, "", "textures", [&](const json& t, const std::string& at) {
    c.field(t, at, "sampler", Kind::Integer);
    c.field(t, at, "source", Kind::Integer);
    // A WebP or AVIF source replaces the core one: of the wrong type, the fallback would be drawn.
    c.object(t, at, "extensions", [&](const json& e, const std::string& eat) {
      for (const char* k : {"EXT_texture_webp", "EXT_texture_avif"})
        c.object(e, eat, k, [&](const json& x, const std::string& xat) { c.field(x, xat, "source", Kind::Integer); });
    });
    c.name(t, at);
  });
  c.objects(doc, "", "images", [&](const json& i, const std::string& at) {
    c.field(i, at, "uri", Kind::String);
    c.field(i, at, "mimeType", Kind::String);
    c.field(i, at, "bufferView", Kind::Integer);
    c.name(i, at);
  });
  c.objects(doc, "", "samplers", [&](const json& s, const std::string& at) {
    for (const char* k : {"magFilter", "minFilter", "wrapS", "wrapT"}) c.field(s, at, k, Kind::Integer);
    c.name(s, at);
  });
  c.objects(doc, "", "cameras", [&](const json& cam, const std::string& at) {
    c.field(cam, at, "type", Kind::String);
    for (const char* kind : {"perspective", "orthographic"})
      c.object(cam, at, kind, [&](const json& p, const std::string& pat) {
        for (const char* k : {"aspectRatio", "yfov", "zfar", "znear", "xmag", "ymag"}) c.field(p, pat, k, Kind::Number);
      });
    c.name(cam, at);
  });
  // KHR_lights_punctual: a light's colour, intensity, range or cone of the wrong type would be
  // drawn with the default (tinygltf keeps it without a word).
  c.object(doc, "", "extensions", [&](const json& e, const std::string& eat) {
    c.object(e, eat, "KHR_lights_punctual", [&](const json& k, const std::string& kat) {
      c.objects(k, kat + ".", "lights", [&](const json& l, const std::string& lat) {
        c.field(l, lat, "type", Kind::String);
        c.arrayOf(l, lat, "color", Kind::Number, 3);
        for (const char* f : {"intensity", "range"}) c.field(l, lat, f, Kind::Number);
        c.object(l, lat, "spot", [&](const json& s, const std::string& sat) {
          for (const char* f : {"innerConeAngle", "outerConeAngle"}) c.field(s, sat, f, Kind::Number);
        });
        c.name(l, lat);
      });
    });
  });
  for (const char* k : {"animations", "skins"})
    c.objects(doc, "", k, [&](const json& x, const std::string& at) { c.name(x, at); });
  return c.warnings();
}

void refuseGltf1(const json& doc, std::span<const uint8_t> bytes, bool binary, const std::string& path) {
  // Binary glTF 1.0 (KHR_binary_glTF): "glTF", then the uint32 version 1 (2.0's GLB has 2).
  uint32_t headerVersion = 0;
  if (binary && bytes.size() >= 8) std::memcpy(&headerVersion, bytes.data() + 4, 4);
  std::string version;
  if (doc.is_object() && doc.contains("asset") && doc["asset"].is_object() && doc["asset"].contains("version") &&
      doc["asset"]["version"].is_string())
    version = doc["asset"]["version"].get<std::string>();
  // Without a version, 1.0's own forms: the default scene named by a string, objects keyed by ID.
  const bool oneZeroForms =
      version.empty() && doc.is_object() &&
      ((doc.contains("scene") && doc["scene"].is_string()) || (doc.contains("meshes") && doc["meshes"].is_object()));
  if (headerVersion != 1 && version.rfind("1.", 0) != 0 && version != "1" && !oneZeroForms) return;
  const std::string what = headerVersion == 1 ? "binary glTF 1.0 (its header says version 1)"
                           : !version.empty() ? "glTF 1.0 (asset.version \"" + version + "\")"
                                              : "glTF 1.0 (its \"scene\" is a name, its meshes an object)";
  throw InputError(path + ": is " + what +
                   ", which hybridbench does not read (it reads glTF 2.0); convert it to glTF 2.0, e.g. with "
                   "gltf-pipeline (npm install -g gltf-pipeline; gltf-pipeline -i " +
                   std::filesystem::path(path).filename().string() + " -o " +
                   std::filesystem::path(path).stem().string() + "-2.0" + (binary ? ".glb" : ".gltf") +
                   "), or export it again from its source as glTF 2.0");
}

namespace {

// A URI's percent-escapes decoded as tinygltf decodes them before it opens the file ('+' is a space).
std::string decodedUri(const std::string& uri) {
  auto hex = [](char c) {
    return c >= '0' && c <= '9'   ? c - '0'
           : c >= 'a' && c <= 'f' ? c - 'a' + 10
           : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                  : 0;
  };
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '+') {
      out += ' ';
    } else if (uri[i] == '%' && i + 2 < uri.size()) {
      out += static_cast<char>(hex(uri[i + 1]) * 16 + hex(uri[i + 2]));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

}  // namespace

void checkExternalBuffers(const json& doc, const std::string& path, const std::string& baseDir) {
  if (!doc.is_object() || !doc.contains("buffers") || !doc["buffers"].is_array()) return;
  const json& buffers = doc["buffers"];
  for (size_t b = 0; b < buffers.size(); ++b) {
    if (!buffers[b].is_object() || !buffers[b].contains("uri") || !buffers[b]["uri"].is_string()) continue;
    const std::string uri = buffers[b]["uri"].get<std::string>();
    if (uri.rfind("data:", 0) == 0) continue;
    // tinygltf looks beside the file, then in the working directory.
    const std::filesystem::path name = decodedUri(uri), beside = std::filesystem::path(baseDir) / name;
    std::error_code ec;
    if (std::filesystem::exists(beside, ec) || std::filesystem::exists(name, ec)) continue;
    throw InputError(path + ": buffers[" + std::to_string(b) + "].uri: the file \"" + uri +
                     "\" is not there (looked for " + beside.lexically_normal().string() +
                     "); supply it: a .gltf keeps its geometry in the files its buffers name, so put " +
                     name.filename().string() + " there");
  }
}

}  // namespace hb::gltf_detail

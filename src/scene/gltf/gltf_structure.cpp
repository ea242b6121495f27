#include "scene/gltf/gltf_structure.h"

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
    });
  }

 private:
  std::string path_;
};

}  // namespace

void checkGltfStructure(const json& doc, const std::string& path) {
  if (!doc.is_object()) return;  // not JSON at all: tinygltf's parse error says so
  const Checker c(path);
  c.field(doc, "", "scene", Kind::Integer);
  c.object(doc, "", "asset", [&](const json& a, const std::string& at) { c.field(a, at, "version", Kind::String); });
  c.arrayOf(doc, "", "extensionsUsed", Kind::String);
  c.arrayOf(doc, "", "extensionsRequired", Kind::String);
  c.objects(doc, "", "scenes", [&](const json& s, const std::string& at) {
    c.arrayOf(s, at, "nodes", Kind::Integer);
    c.field(s, at, "name", Kind::String);
  });
  c.objects(doc, "", "nodes", [&](const json& n, const std::string& at) {
    for (const char* k : {"camera", "mesh", "skin"}) c.field(n, at, k, Kind::Integer);
    c.arrayOf(n, at, "children", Kind::Integer);
    c.arrayOf(n, at, "matrix", Kind::Number, 16);
    c.arrayOf(n, at, "rotation", Kind::Number, 4);
    c.arrayOf(n, at, "scale", Kind::Number, 3);
    c.arrayOf(n, at, "translation", Kind::Number, 3);
    c.field(n, at, "name", Kind::String);
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
    c.field(m, at, "name", Kind::String);
  });
  c.objects(doc, "", "accessors", [&](const json& a, const std::string& at) {
    for (const char* k : {"bufferView", "byteOffset", "componentType", "count"}) c.field(a, at, k, Kind::Integer);
    c.field(a, at, "type", Kind::String);
    c.field(a, at, "normalized", Kind::Bool);
    c.arrayOf(a, at, "min", Kind::Number);
    c.arrayOf(a, at, "max", Kind::Number);
    c.object(a, at, "sparse", [](const json&, const std::string&) {});
  });
  c.objects(doc, "", "bufferViews", [&](const json& b, const std::string& at) {
    for (const char* k : {"buffer", "byteOffset", "byteLength", "byteStride", "target"})
      c.field(b, at, k, Kind::Integer);
  });
  c.objects(doc, "", "buffers", [&](const json& b, const std::string& at) {
    c.field(b, at, "byteLength", Kind::Integer);
    c.field(b, at, "uri", Kind::String);
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
  });
  c.objects(doc, "", "textures", [&](const json& t, const std::string& at) {
    c.field(t, at, "sampler", Kind::Integer);
    c.field(t, at, "source", Kind::Integer);
  });
  c.objects(doc, "", "images", [&](const json& i, const std::string& at) {
    c.field(i, at, "uri", Kind::String);
    c.field(i, at, "mimeType", Kind::String);
    c.field(i, at, "bufferView", Kind::Integer);
  });
  c.objects(doc, "", "samplers", [&](const json& s, const std::string& at) {
    for (const char* k : {"magFilter", "minFilter", "wrapS", "wrapT"}) c.field(s, at, k, Kind::Integer);
  });
  c.objects(doc, "", "cameras", [&](const json& cam, const std::string& at) {
    c.field(cam, at, "type", Kind::String);
    for (const char* kind : {"perspective", "orthographic"})
      c.object(cam, at, kind, [&](const json& p, const std::string& pat) {
        for (const char* k : {"aspectRatio", "yfov", "zfar", "znear", "xmag", "ymag"}) c.field(p, pat, k, Kind::Number);
      });
  });
  for (const char* k : {"animations", "skins"}) c.objects(doc, "", k, [](const json&, const std::string&) {});
}

}  // namespace hb::gltf_detail

#include "base/json_diff.h"

#include <algorithm>
#include <set>

namespace hb {

using nlohmann::json;

namespace {

// An array of these is entered element by element; an array of numbers or strings (a resolution,
// a list of names) is one value, shown whole.
bool isStructured(const json& v) { return v.is_object() || v.is_array(); }

}  // namespace

std::optional<JsonDifference> firstDifference(const json& a, const json& b, const std::string& prefix) {
  if (a == b) return std::nullopt;
  if (a.is_object() && b.is_object()) {
    std::set<std::string> keys;
    for (auto it = a.begin(); it != a.end(); ++it) keys.insert(it.key());
    for (auto it = b.begin(); it != b.end(); ++it) keys.insert(it.key());
    for (const std::string& key : keys) {
      const std::string path = prefix.empty() ? key : prefix + "." + key;
      const bool inA = a.contains(key), inB = b.contains(key);
      if (!inA || !inB)
        return JsonDifference{path, inA ? std::optional<json>(a[key]) : std::nullopt,
                              inB ? std::optional<json>(b[key]) : std::nullopt};
      if (auto d = firstDifference(a[key], b[key], path)) return d;
    }
  } else if (a.is_array() && b.is_array() && std::all_of(a.begin(), a.end(), isStructured) &&
             std::all_of(b.begin(), b.end(), isStructured)) {
    const size_t n = std::max(a.size(), b.size());
    for (size_t i = 0; i < n; ++i) {
      const std::string path = prefix + "[" + std::to_string(i) + "]";
      if (i >= a.size() || i >= b.size())
        return JsonDifference{path, i < a.size() ? std::optional<json>(a[i]) : std::nullopt,
                              i < b.size() ? std::optional<json>(b[i]) : std::nullopt};
      if (auto d = firstDifference(a[i], b[i], path)) return d;
    }
  }
  return JsonDifference{prefix, a, b};  // different kinds, or scalars that differ
}

std::string shortJson(const std::optional<json>& v) {
  if (!v) return "(absent)";
  const std::string s = v->dump();
  return s.size() > 60 ? s.substr(0, 57) + "..." : s;
}

std::string describeDifference(const JsonDifference& d, const std::string& labelA, const std::string& labelB) {
  return (d.path.empty() ? std::string("the value") : d.path) + " differs (" + labelA + ": " + shortJson(d.a) + ", " +
         labelB + ": " + shortJson(d.b) + ")";
}

}  // namespace hb

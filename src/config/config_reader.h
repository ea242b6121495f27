// Strict reading of JSON values for config files (internal to config*.cpp): every check throws an
// hb::InputError of one line, "<source>: <key path>: <what is wrong and how to fix it>".
#pragma once
#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "config/config.h"

namespace hb::config_reader {

using Json = nlohmann::ordered_json;

// Where a value sits: the file (or "--set k=v") and the key path inside it, e.g.
// "variants[2].params.tile_size". An empty path means the document itself.
struct Where {
  std::string source;
  std::string path;

  Where key(std::string_view k) const;
  Where index(size_t i) const;
  std::string prefix() const;  // "source: path" or "source"
  [[noreturn]] void fail(const std::string& message) const;
};

// A short, quoted-where-needed rendering of a value for messages: 12, "yes", [1,2], {...}.
std::string describe(const Json& value);

// The closest of `allowed` to `key` by edit distance, or "" when none is plausibly a typo.
std::string closestKey(std::string_view key, const std::vector<std::string_view>& allowed);

// Requires an object whose keys are all in `allowed`; an unknown key fails naming the object's
// path with a did-you-mean suggestion (or the allowed keys).
void requireObjectWithKeys(const Json& value, const Where& where,
                           const std::vector<std::string_view>& allowed);
[[noreturn]] void failUnknownKey(std::string_view key, const Where& container,
                                 const std::vector<std::string_view>& allowed);

bool readBool(const Json& value, const Where& where);
std::string readString(const Json& value, const Where& where);
// An integer in [lo, hi] (floats such as 8.0 are refused: counts are integers).
int64_t readInt(const Json& value, const Where& where, int64_t lo, int64_t hi);
// An integer that is one of `choices`.
int64_t readIntChoice(const Json& value, const Where& where, std::initializer_list<int64_t> choices);
// A finite number in (lo, hi] when loExclusive, else [lo, hi]; hi may be infinity.
double readNumber(const Json& value, const Where& where, double lo, double hi, bool loExclusive);
// A string that is one of `choices`; returns its index.
size_t readChoice(const Json& value, const Where& where, std::initializer_list<const char*> choices);
// An array of exactly n finite numbers.
std::vector<double> readNumbers(const Json& value, const Where& where, size_t n, const char* shape);

// Parses text as JSON (comments allowed). Malformed text fails as "<source>:<line>:<col>: malformed
// JSON: ..."; a key given twice in one object fails naming its path.
Json parseText(const std::string& text, const std::string& source);

// --- variant parameters (config_params.cpp) ---------------------------------------------------

// 16384 is the maxImageDimension2D of current desktop GPUs and of lavapipe; a device with a smaller
// limit refuses the image when it is created, not here.
constexpr int64_t kMaxResolution = 16384;
// The atrium's own limits (atrium.h: makeAtrium refuses anything outside them).
constexpr int64_t kMaxLightCount = 4096;
constexpr double kMinTriangleScale = 0.25;
constexpr double kMaxTriangleScale = 64.0;

// The keys a params object may hold, in schema order.
const std::vector<std::string_view>& paramKeys();
// Sets one parameter; `where` is the value's own path (e.g. "defaults.tile_size"), `container` the
// object's path for the unknown-key message.
void applyParam(VariantParams& params, std::string_view key, const Json& value, const Where& where,
                const Where& container);
// Applies every key of a params object.
void applyParams(VariantParams& params, const Json& object, const Where& where);
// How a grid value appears in a generated variant name: 8, naive, true, 1920x1080, 4.
std::string valueLabel(const Json& value);

}  // namespace hb::config_reader

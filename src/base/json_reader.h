// Strict reading of JSON documents (configs, glTF extras): every check throws an hb::InputError
// of one line, "<source>: <key path>: <what is wrong and how to fix it>".
#pragma once
#include <cstdint>
#include <initializer_list>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace hb::json_reader {

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
void requireObjectWithKeys(const Json& value, const Where& where, const std::vector<std::string_view>& allowed);
[[noreturn]] void failUnknownKey(std::string_view key, const Where& container,
                                 const std::vector<std::string_view>& allowed);

bool readBool(const Json& value, const Where& where);
std::string readString(const Json& value, const Where& where);
// An integer in [lo, hi] (floats such as 8.0 are refused: counts are integers).
int64_t readInt(const Json& value, const Where& where, int64_t lo, int64_t hi);
// An integer that is one of `choices`.
int64_t readIntChoice(const Json& value, const Where& where, std::initializer_list<int64_t> choices);
int64_t readIntChoice(const Json& value, const Where& where, std::span<const int64_t> choices);
// A finite number in (lo, hi] when loExclusive, else [lo, hi]; hi may be infinity.
double readNumber(const Json& value, const Where& where, double lo, double hi, bool loExclusive);
// A string that is one of `choices`; returns its index.
size_t readChoice(const Json& value, const Where& where, std::initializer_list<const char*> choices);
// The same from a table (config_params.cpp's parameter schema keeps its choices as data).
size_t readChoice(const Json& value, const Where& where, std::span<const std::string_view> choices);
// An array of exactly n finite numbers.
std::vector<double> readNumbers(const Json& value, const Where& where, size_t n, const char* shape);
// readNumber and readNumbers for values kept as float: a number beyond a float's range (3.4e38)
// fails too, where a cast would make it inf (and a direction normalised from it NaN).
float readFloat(const Json& value, const Where& where, double lo, double hi, bool loExclusive);
std::vector<float> readFloats(const Json& value, const Where& where, size_t n, const char* shape);

// Parses text as JSON (comments allowed). Malformed text fails as "<source>:<line>:<col>: malformed
// JSON: ...", a number beyond a double's range (1e999) as "<source>: malformed JSON: number overflow
// parsing '1e999'; ..."; a key given twice in one object fails naming its path.
Json parseText(const std::string& text, const std::string& source);

}  // namespace hb::json_reader

#include "base/json_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>

#include "base/errors.h"

namespace hb::json_reader {

Where Where::key(std::string_view k) const {
  return {source, path.empty() ? std::string(k) : path + "." + std::string(k)};
}

Where Where::index(size_t i) const { return {source, path + "[" + std::to_string(i) + "]"}; }

std::string Where::prefix() const { return path.empty() ? source : source + ": " + path; }

void Where::fail(const std::string& message) const { throw InputError(prefix() + ": " + message); }

std::string describe(const Json& value) {
  if (value.is_object()) return value.empty() ? "{}" : "an object";
  std::string s = value.dump();
  constexpr size_t kMaxShown = 40;  // keeps the error on one readable line
  if (s.size() > kMaxShown) s = s.substr(0, kMaxShown - 3) + "...";
  return s;
}

static size_t editDistance(std::string_view a, std::string_view b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1] ? 1 : 0)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::string closestKey(std::string_view key, const std::vector<std::string_view>& allowed) {
  // A typo changes a few characters: accept up to a third of the key (at least 2) as plausible.
  size_t best = SIZE_MAX;
  std::string_view bestKey;
  for (std::string_view candidate : allowed) {
    size_t d = editDistance(key, candidate);
    if (d < best) best = d, bestKey = candidate;
  }
  size_t plausible = std::max<size_t>(2, key.size() / 3);
  return best <= plausible ? std::string(bestKey) : std::string();
}

void failUnknownKey(std::string_view key, const Where& container, const std::vector<std::string_view>& allowed) {
  std::string message = "unknown key \"" + std::string(key) + "\"";
  std::string guess = closestKey(key, allowed);
  if (!guess.empty()) {
    message += " (did you mean \"" + guess + "\"?)";
  } else {
    message += " (allowed: ";
    for (size_t i = 0; i < allowed.size(); ++i) message += (i ? ", " : "") + std::string(allowed[i]);
    message += ")";
  }
  container.fail(message);
}

void requireObjectWithKeys(const Json& value, const Where& where, const std::vector<std::string_view>& allowed) {
  if (!value.is_object()) where.fail("expected an object, got " + describe(value));
  for (const auto& item : value.items()) {
    if (std::find(allowed.begin(), allowed.end(), item.key()) == allowed.end())
      failUnknownKey(item.key(), where, allowed);
  }
}

bool readBool(const Json& value, const Where& where) {
  if (!value.is_boolean()) where.fail("expected true or false, got " + describe(value));
  return value.get<bool>();
}

std::string readString(const Json& value, const Where& where) {
  if (!value.is_string()) where.fail("expected a string, got " + describe(value));
  return value.get<std::string>();
}

int64_t readInt(const Json& value, const Where& where, int64_t lo, int64_t hi) {
  if (!value.is_number_integer()) where.fail("expected an integer, got " + describe(value));
  // Unsigned values above INT64_MAX are out of every range we accept.
  if (value.is_number_unsigned() && value.get<uint64_t>() > uint64_t(INT64_MAX))
    where.fail(describe(value) + " is out of range " + std::to_string(lo) + ".." + std::to_string(hi));
  int64_t v = value.get<int64_t>();
  if (v < lo || v > hi)
    where.fail(std::to_string(v) + " is out of range " + std::to_string(lo) + ".." + std::to_string(hi));
  return v;
}

int64_t readIntChoice(const Json& value, const Where& where, std::initializer_list<int64_t> choices) {
  return readIntChoice(value, where, std::span<const int64_t>(choices.begin(), choices.size()));
}

int64_t readIntChoice(const Json& value, const Where& where, std::span<const int64_t> choices) {
  std::string list;
  for (int64_t c : choices) list += (list.empty() ? "" : ", ") + std::to_string(c);
  if (!value.is_number_integer()) where.fail("expected one of " + list + ", got " + describe(value));
  bool representable = !value.is_number_unsigned() || value.get<uint64_t>() <= uint64_t(INT64_MAX);
  for (int64_t c : choices)
    if (representable && value.get<int64_t>() == c) return c;
  where.fail(describe(value) + " is not one of " + list);
}

static std::string formatNumber(double v) {
  Json j = v;
  return j.dump();
}

double readNumber(const Json& value, const Where& where, double lo, double hi, bool loExclusive) {
  if (!value.is_number()) where.fail("expected a number, got " + describe(value));
  double v = value.get<double>();
  bool ok = std::isfinite(v) && (loExclusive ? v > lo : v >= lo) && v <= hi;
  if (ok) return v;
  if (std::isinf(hi))
    where.fail(describe(value) + " is out of range: must be " + (loExclusive ? "> " : ">= ") + formatNumber(lo));
  where.fail(describe(value) + " is out of range " + (loExclusive ? "(" : "[") + formatNumber(lo) + ", " +
             formatNumber(hi) + "]");
  return v;
}

// Found by fuzz_config: a light direction of [0.3, -1, 2e307] became (0.3, -1, inf) as a float and
// NaN once normalised.
static float checkedFloat(double v, const Json& value, const Where& where) {
  if (!(std::abs(v) <= double(std::numeric_limits<float>::max())))
    where.fail(describe(value) + " is out of range for a float; give a magnitude below 3.4e38");
  return static_cast<float>(v);
}

float readFloat(const Json& value, const Where& where, double lo, double hi, bool loExclusive) {
  return checkedFloat(readNumber(value, where, lo, hi, loExclusive), value, where);
}

std::vector<float> readFloats(const Json& value, const Where& where, size_t n, const char* shape) {
  const std::vector<double> numbers = readNumbers(value, where, n, shape);
  std::vector<float> out;
  for (size_t i = 0; i < n; ++i) out.push_back(checkedFloat(numbers[i], value[i], where.index(i)));
  return out;
}

size_t readChoice(const Json& value, const Where& where, std::initializer_list<const char*> choices) {
  const std::vector<std::string_view> views(choices.begin(), choices.end());
  return readChoice(value, where, std::span<const std::string_view>(views));
}

size_t readChoice(const Json& value, const Where& where, std::span<const std::string_view> choices) {
  std::string list;
  for (std::string_view c : choices) list += (list.empty() ? "\"" : ", \"") + std::string(c) + "\"";
  if (!value.is_string()) where.fail("expected one of " + list + ", got " + describe(value));
  const std::string& s = value.get_ref<const std::string&>();
  for (size_t i = 0; i < choices.size(); ++i)
    if (s == choices[i]) return i;
  where.fail(describe(value) + " is not one of " + list);
}

std::vector<double> readNumbers(const Json& value, const Where& where, size_t n, const char* shape) {
  if (!value.is_array() || value.size() != n) where.fail(std::string("expected ") + shape + ", got " + describe(value));
  std::vector<double> out;
  for (size_t i = 0; i < n; ++i) {
    if (!value[i].is_number() || !std::isfinite(value[i].get<double>()))
      where.index(i).fail("expected a number, got " + describe(value[i]));
    out.push_back(value[i].get<double>());
  }
  return out;
}

// Tracks the key path during parsing so that a key given twice can be reported where it is
// (nlohmann::json would silently keep the last one).
class DuplicateKeyCheck {
 public:
  explicit DuplicateKeyCheck(std::string source) : source_(std::move(source)) {}

  bool operator()(int /*depth*/, nlohmann::json::parse_event_t event, Json& parsed) {
    using E = nlohmann::json::parse_event_t;
    switch (event) {
      case E::object_start: frames_.push_back({true, {}, {}, 0}); break;
      case E::array_start: frames_.push_back({false, {}, {}, 0}); break;
      case E::key: {
        Frame& f = frames_.back();
        f.currentKey = parsed.get<std::string>();
        if (!f.keys.insert(f.currentKey).second)
          Where{source_, path()}.fail("key \"" + f.currentKey + "\" is given twice; keep one");
        break;
      }
      case E::object_end:
      case E::array_end:
        frames_.pop_back();
        elementDone();
        break;
      case E::value: elementDone(); break;
    }
    return true;
  }

 private:
  struct Frame {
    bool isObject;
    std::set<std::string> keys;
    std::string currentKey;
    size_t index;
  };

  void elementDone() {
    if (!frames_.empty() && !frames_.back().isObject) ++frames_.back().index;
  }

  // The path of the innermost object (the one that holds the repeated key).
  std::string path() const {
    std::string p;
    for (size_t i = 0; i + 1 < frames_.size(); ++i) {
      const Frame& f = frames_[i];
      // Appended piecewise: GCC 12's -Wrestrict misfires on `"[" + std::to_string(...) + "]"`.
      if (f.isObject) {
        if (!p.empty()) p += '.';
        p += f.currentKey;
      } else {
        p += '[';
        p += std::to_string(f.index);
        p += ']';
      }
    }
    return p;
  }

  std::string source_;
  std::vector<Frame> frames_;
};

Json parseText(const std::string& text, const std::string& source) {
  try {
    return Json::parse(text, DuplicateKeyCheck(source), /*allow_exceptions=*/true,
                       /*ignore_comments=*/true);
  } catch (const nlohmann::json::parse_error& e) {
    // what() reads "[json.exception.parse_error.101] parse error at line L, column C: <detail>".
    std::string what = e.what();
    unsigned line = 0, column = 0;
    int consumed = 0;
    size_t at = what.find("line ");
    if (at != std::string::npos &&
        std::sscanf(what.c_str() + at, "line %u, column %u: %n", &line, &column, &consumed) == 2 && consumed > 0)
      throw InputError(source + ":" + std::to_string(line) + ":" + std::to_string(column) +
                       ": malformed JSON: " + what.substr(at + size_t(consumed)));
    throw InputError(source + ": malformed JSON at byte " + std::to_string(e.byte) + ": " + what);
  } catch (const nlohmann::json::out_of_range& e) {
    // The parser's one other error (406): a number beyond a double's range, e.g. 1e999. Its
    // what() reads "[json.exception.out_of_range.406] number overflow parsing '1e999'" and carries
    // no position; the number itself names the place.
    std::string what = e.what();
    if (size_t at = what.find("] "); at != std::string::npos) what.erase(0, at + 2);
    throw InputError(source + ": malformed JSON: " + what +
                     "; write a number a double can hold (magnitude below 1.8e308)");
  }
}

}  // namespace hb::json_reader

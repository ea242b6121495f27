// The first place where two JSON values differ, with both values there: what a refusal to
// compare two results files, or to resume a sweep, names so that the difference shows.
#pragma once
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace hb {

struct JsonDifference {
  // Where: object keys joined by '.', positions in arrays of objects as [i], after the prefix given to
  // firstDifference ("context.config.variants[3].params.aa"); the prefix alone when the two
  // differ at their roots (a number against a string, ...).
  std::string path;
  // The values there; a side that lacks the key or the array element holds nothing.
  std::optional<nlohmann::json> a, b;
};

// The first difference in document order: objects by key in sorted order (nlohmann::json keeps
// keys sorted), arrays of objects or arrays by position (a longer array's first extra element
// last); an array that holds a number or string ([1920,1080]) differs as a whole. Numbers compare
// by value (1 equals 1.0). Empty when a == b.
std::optional<JsonDifference> firstDifference(const nlohmann::json& a, const nlohmann::json& b,
                                              const std::string& prefix = "");

// A value as one short line: its JSON text, cut to 60 characters with "..." (the cut is never
// where the difference is: that is at the path), or "(absent)".
std::string shortJson(const std::optional<nlohmann::json>& v);

// "<path> differs (<labelA>: <value>, <labelB>: <value>)", e.g.
// `context.config.variants[0].params.aa differs (A: "none", B: "fxaa")`.
std::string describeDifference(const JsonDifference& d, const std::string& labelA, const std::string& labelB);

}  // namespace hb

// Config-specific strict readers (internal to config*.cpp): variant parameters. The generic readers
// (Where, readBool, ...) are in base/json_reader.h.
#pragma once
#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/json_reader.h"
#include "config/config.h"

namespace hb::config_reader {

using namespace hb::json_reader;  // Json, Where and the strict readers

// --- variant parameters (config_params.cpp) ---------------------------------------------------

// 16384 is the maxImageDimension2D of current desktop GPUs and of lavapipe; a device with a smaller
// limit refuses the image when it is created, not here.
constexpr int64_t kMaxResolution = 16384;
// The atrium's own limits (atrium.h: makeAtrium refuses anything outside them).
constexpr int64_t kMaxLightCount = 4096;
constexpr double kMinTriangleScale = 0.25;
constexpr double kMaxTriangleScale = 64.0;

enum class ParamKind { Bool, Int, IntChoice, Choice, Number, Resolution, Effects };

// One variant parameter: how its value is checked, what it means, and how it is stored.
struct ParamSpec {
  std::string_view key;
  ParamKind kind;
  std::vector<std::string_view> choices;  // Choice: the strings, in the order of the enum stored
  std::vector<int64_t> intChoices;        // IntChoice
  double lo = 0, hi = 0;                  // Int, Number, Resolution (each side): inclusive range
  std::string_view rule;                  // a rule beyond the range (store checks it), "" if none
  std::string_view unit;                  // "" if none
  std::string_view absentDefault;         // what applies when VariantParams leaves it empty
  std::string_view description;           // one line, for `hybridbench help params`
  // Stores a value that passed the kind's check; `choice` is its index in `choices` (Choice).
  void (*store)(VariantParams& params, const Json& value, size_t choice, const Where& where);
};

// Every parameter, in schema order (config_params.cpp).
const std::vector<ParamSpec>& paramSpecs();
const ParamSpec* findParam(std::string_view key);  // nullptr if no parameter is called that
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

// `hybridbench help params|effects`: reference tables printed from the schemas the parser itself
// uses (config_reader::paramSpecs, allEffects), so generated docs cannot drift from the code. The
// output depends on nothing but the binary: no device, no files, no date.
#include <cstdio>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "base/errors.h"
#include "config/config.h"
#include "config/config_reader.h"
#include "effects/effects.h"

namespace hb {

namespace {

using config_reader::ParamKind;
using config_reader::ParamSpec;

// One row of a table; `cells` in the order of the table's header.
using Row = std::vector<std::string>;

struct Table {
  std::vector<std::string> header;
  std::vector<Row> rows;
};

std::string joined(const std::vector<std::string>& parts, const char* separator) {
  std::string s;
  for (const std::string& p : parts) s += (s.empty() ? "" : separator) + p;
  return s;
}

// A number as a config file would write it: 64, not 64.0.
std::string numberText(double v) {
  if (v == double(int64_t(v))) return std::to_string(int64_t(v));
  return nlohmann::json(v).dump();
}

// A default value as written in a config file, arrays with a space after each comma.
std::string valueText(const nlohmann::json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_array()) {
    std::vector<std::string> items;
    for (const auto& item : v) items.push_back(valueText(item));
    return "[" + joined(items, ", ") + "]";
  }
  return v.dump();
}

const char* typeName(ParamKind kind) {
  switch (kind) {
    case ParamKind::Bool: return "boolean";
    case ParamKind::Int:
    case ParamKind::IntChoice: return "integer";
    case ParamKind::Choice: return "string";
    case ParamKind::Number: return "number";
    case ParamKind::Resolution: return "[integer, integer]";
    case ParamKind::Effects: return "object";
  }
  return "?";
}

std::string allowedText(const ParamSpec& s) {
  std::string text;
  switch (s.kind) {
    case ParamKind::Bool: text = "true, false"; break;
    case ParamKind::Int:
    case ParamKind::Number: text = numberText(s.lo) + ".." + numberText(s.hi); break;
    case ParamKind::IntChoice: {
      std::vector<std::string> items;
      for (int64_t c : s.intChoices) items.push_back(std::to_string(c));
      text = joined(items, ", ");
      break;
    }
    case ParamKind::Choice: text = joined(std::vector<std::string>(s.choices.begin(), s.choices.end()), ", "); break;
    case ParamKind::Resolution: text = numberText(s.lo) + ".." + numberText(s.hi) + " each"; break;
    case ParamKind::Effects: text = "an effects object (help effects)"; break;
  }
  if (!s.rule.empty()) text += ", " + std::string(s.rule);
  return text;
}

std::string defaultText(const ParamSpec& s, const nlohmann::json& defaults) {
  if (defaults.contains(s.key)) return valueText(defaults[std::string(s.key)]);
  return std::string(s.absentDefault);
}

Table paramsTable() {
  Table t{{"Parameter", "Type", "Default", "Allowed", "Unit", "Description"}, {}};
  const nlohmann::json defaults = toJson(VariantParams{});
  for (const ParamSpec& s : config_reader::paramSpecs())
    t.rows.push_back({std::string(s.key), typeName(s.kind), defaultText(s, defaults), allowedText(s),
                      std::string(s.unit), std::string(s.description)});
  return t;
}

// What an effect's validator says about `value` given as its setting `setting` (empty: as the
// effect's whole value), without the "help: path: " prefix; "" when it accepts the value.
std::string validatorSays(const EffectDef& e, const std::string& setting, const nlohmann::ordered_json& value) {
  const json_reader::Where where{"help", ""};
  const nlohmann::ordered_json probe = setting.empty() ? value : nlohmann::ordered_json{{setting, value}};
  try {
    e.validate(probe, where);
  } catch (const InputError& error) {
    std::string message = error.what();
    const std::string prefix = setting.empty() ? "help: " : "help: " + setting + ": ";
    if (message.rfind(prefix, 0) == 0) message = message.substr(prefix.size());
    return message;
  }
  return "";
}

// An effect's settings with what each accepts. EffectDef holds only a validator, so they are read
// from its answers: an unknown key lists the settings, and a wrong type and an out-of-range value
// name what a setting accepts. {} when the effect takes no object (true or false only).
std::vector<std::pair<std::string, std::string>> effectSettings(const EffectDef& e) {
  std::vector<std::pair<std::string, std::string>> settings;
  // A key no effect could have and no did-you-mean would match.
  const std::string unknown = validatorSays(e, "", {{"~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~", 0}});
  const std::string allowedMarker = "(allowed: ";
  const size_t at = unknown.find(allowedMarker);
  if (at == std::string::npos || unknown.back() != ')') return settings;
  std::string list = unknown.substr(at + allowedMarker.size());
  list.pop_back();
  std::stringstream names(list);
  for (std::string name; std::getline(names, name, ',');) {
    if (!name.empty() && name[0] == ' ') name.erase(0, 1);
    // A wrong type names the kind of value ("expected an integer, got {}").
    std::string accepts = validatorSays(e, name, nlohmann::ordered_json::object());
    const size_t got = accepts.rfind(", got ");
    if (got != std::string::npos) accepts = accepts.substr(0, got);
    if (accepts.rfind("expected ", 0) == 0) accepts = accepts.substr(9);
    // A huge value, else a hugely negative one, names the range ("... is out of range 1..2048",
    // "... is out of range: must be > 0").
    if (accepts == "an integer" || accepts == "a number") {
      const bool integer = accepts == "an integer";
      for (double sign : {1.0, -1.0}) {
        const std::string says = validatorSays(
            e, name, integer ? nlohmann::ordered_json(int64_t(sign) << 62) : nlohmann::ordered_json(sign * 1e300));
        const std::string marker = "is out of range";
        const size_t r = says.find(marker);
        if (r == std::string::npos) continue;
        const std::string range = says.substr(r + marker.size());  // " 1..2048" or ": must be > 0"
        accepts += range.rfind(": ", 0) == 0 ? ", " + range.substr(2) : " in" + range;
        break;
      }
    }
    settings.push_back({name, accepts});
  }
  return settings;
}

std::vector<std::string> effectPasses(const EffectDef& e) { return {e.passes.begin(), e.passes.end()}; }

Table effectsTable() {
  Table t{{"Effect", "Default", "Settings", "Passes", "Summary"}, {}};
  for (const EffectDef* e : allEffects()) {
    std::vector<std::string> names;
    for (const auto& [name, accepts] : effectSettings(*e)) names.push_back(name);
    t.rows.push_back({e->name, valueText(e->defaultValue),
                      names.empty() ? "none (true or false)" : "true, false or {" + joined(names, ", ") + "}",
                      joined(effectPasses(*e), ", "), e->summary});
  }
  return t;
}

Table effectSettingsTable() {
  Table t{{"Effect", "Setting", "Accepts"}, {}};
  for (const EffectDef* e : allEffects())
    for (const auto& [name, accepts] : effectSettings(*e)) t.rows.push_back({e->name, name, accepts});
  return t;
}

std::string markdownCell(const std::string& text) {
  std::string s;
  for (char c : text) s += c == '|' ? std::string("\\|") : std::string(1, c);
  return s.empty() ? " " : s;
}

std::string markdown(const Table& t) {
  std::string s = "|";
  for (const std::string& h : t.header) s += " " + h + " |";
  s += "\n|";
  for (size_t i = 0; i < t.header.size(); ++i) s += " --- |";
  s += "\n";
  for (const Row& row : t.rows) {
    s += "|";
    for (const std::string& cell : row) s += " " + markdownCell(cell) + " |";
    s += "\n";
  }
  return s;
}

// Plain text: the first column, then "header: value" for each non-empty other cell, indented.
std::string text(const Table& t) {
  std::string s;
  for (const Row& row : t.rows) {
    s += row[0] + "\n";
    for (size_t i = 1; i < row.size(); ++i)
      if (!row[i].empty()) s += "    " + t.header[i] + ": " + row[i] + "\n";
  }
  return s;
}

// Each effect's row, then what each of its settings accepts, under it.
std::string effectsText() {
  const Table t = effectsTable();
  std::string s;
  for (size_t i = 0; i < t.rows.size(); ++i) {
    s += text(Table{t.header, {t.rows[i]}});
    for (const auto& [name, accepts] : effectSettings(*allEffects()[i])) s += "      " + name + ": " + accepts + "\n";
  }
  return s;
}

nlohmann::ordered_json paramsJson() {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  const nlohmann::json defaults = toJson(VariantParams{});
  for (const ParamSpec& s : config_reader::paramSpecs()) {
    nlohmann::ordered_json p = {{"name", s.key}, {"type", typeName(s.kind)}};
    if (defaults.contains(s.key))
      p["default"] = defaults[std::string(s.key)];
    else
      p["default_when_absent"] = s.absentDefault;
    p["allowed"] = allowedText(s);
    if (s.kind == ParamKind::Choice) p["choices"] = s.choices;
    if (s.kind == ParamKind::IntChoice) p["choices"] = s.intChoices;
    if (s.kind == ParamKind::Int || s.kind == ParamKind::Number || s.kind == ParamKind::Resolution) {
      p["min"] = s.lo;
      p["max"] = s.hi;
    }
    if (!s.rule.empty()) p["rule"] = s.rule;
    if (!s.unit.empty()) p["unit"] = s.unit;
    p["description"] = s.description;
    list.push_back(p);
  }
  return {{"params", list}};
}

nlohmann::ordered_json effectsJson() {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const EffectDef* e : allEffects()) {
    nlohmann::ordered_json settings = nlohmann::ordered_json::array();
    for (const auto& [name, accepts] : effectSettings(*e)) settings.push_back({{"name", name}, {"accepts", accepts}});
    list.push_back({{"name", e->name},
                    {"default", e->defaultValue},
                    {"settings", settings},
                    {"passes", effectPasses(*e)},
                    {"summary", e->summary}});
  }
  return {{"effects", list}};
}

}  // namespace

std::string helpText(const std::string& topic, const std::string& format) {
  if (format != "md" && format != "text" && format != "json")
    throw InputError("help: unknown --format \"" + format + "\"; use md, text or json");
  if (topic == "params") {
    if (format == "json") return paramsJson().dump(2) + "\n";
    return format == "md" ? markdown(paramsTable()) : text(paramsTable());
  }
  if (topic == "effects") {
    if (format == "json") return effectsJson().dump(2) + "\n";
    if (format == "md") return markdown(effectsTable()) + "\n" + markdown(effectSettingsTable());
    return effectsText();
  }
  throw InputError(topic.empty() ? "help: name a topic: hybridbench help params or hybridbench help effects"
                                 : "help: unknown topic \"" + topic + "\"; use params or effects");
}

int cmdHelp(const std::string& topic, const std::string& format) {
  std::cout << helpText(topic, format);
  return kExitOk;
}

}  // namespace hb

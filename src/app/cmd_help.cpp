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
#include "plan/effects.h"

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

// An effect's settings and what each accepts, from its schema (EffectDef::settings, which its
// validator reads; src/effects/builtin/effects_test.cpp holds the two to each other).
std::vector<std::pair<std::string, std::string>> effectSettings(const EffectDef& e) {
  std::vector<std::pair<std::string, std::string>> settings;
  for (const EffectSetting& s : e.settings) settings.push_back({s.name, s.accepts});
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
  Table t{{"Effect", "Setting", "Accepts", "Default", "Description"}, {}};
  for (const EffectDef* e : allEffects())
    for (const EffectSetting& s : e->settings)
      t.rows.push_back({e->name, s.name, s.accepts, s.defaultValue, s.description});
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
    for (const EffectSetting& s : e->settings)
      settings.push_back({{"name", s.name},
                          {"accepts", s.accepts},
                          {"default", nlohmann::ordered_json::parse(s.defaultValue)},
                          {"description", s.description}});
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

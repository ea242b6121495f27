#include "app/cli_suggest.h"

#include <string_view>

#include <CLI/CLI.hpp>

#include "base/json_reader.h"

namespace hb {
namespace {

// "render" or "scene export": the subcommand's words from the top (the program's own name left out).
std::string commandPath(const CLI::App& app) {
  std::string path;
  for (const CLI::App* a = &app; a->get_parent() != nullptr; a = a->get_parent())
    path = a->get_name() + (path.empty() ? "" : " " + path);
  return path;
}

std::string helpHint(const CLI::App& app) {
  const std::string path = commandPath(app);
  return "; see hybridbench " + (path.empty() ? "" : path + " ") + "--help";
}

// The option "--name" as `app` or one of its parents knows it (CLI11 passes an option a
// subcommand does not know up to its parent), or null.
const CLI::Option* findOption(const CLI::App& app, const std::string& name) {
  for (const CLI::App* a = &app; a != nullptr; a = a->get_parent())
    if (const CLI::Option* o = a->get_option_no_throw("--" + name)) return o;
  return nullptr;
}

// Every long option name (without "--") that `app` and its parents show in --help.
std::vector<std::string> visibleOptionNames(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* a = &app; a != nullptr; a = a->get_parent())
    for (const CLI::Option* o : a->get_options())
      if (!o->get_group().empty())
        for (const std::string& n : o->get_lnames()) names.push_back(n);
  return names;
}

std::string closest(const std::string& word, const std::vector<std::string>& names) {
  const std::vector<std::string_view> views(names.begin(), names.end());
  return json_reader::closestKey(word, views);
}

}  // namespace

std::string suggestForUnknownArgument(const CLI::App& app, const std::vector<std::string>& args) {
  const CLI::App* current = &app;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& word = args[i];
    if (word == "--") break;  // the rest are positionals
    if (word.rfind("--", 0) == 0) {
      const size_t eq = word.find('=');
      const std::string name = word.substr(2, eq == std::string::npos ? std::string::npos : eq - 2);
      if (const CLI::Option* o = findOption(*current, name)) {
        if (eq == std::string::npos && o->get_items_expected_min() > 0) ++i;  // its value
        continue;
      }
      const std::string guess = closest(name, visibleOptionNames(*current));
      if (guess.empty()) return "";
      const std::string path = commandPath(*current);
      return (path.empty() ? "" : path + ": ") + "unknown flag \"--" + name + "\" (did you mean \"--" + guess + "\"?)" +
             helpHint(*current);
    }
    if (word.rfind('-', 0) == 0) continue;  // -h and the like: CLI11 judges them
    const std::vector<const CLI::App*> subcommands = current->get_subcommands([](const CLI::App*) { return true; });
    const CLI::App* entered = nullptr;
    std::vector<std::string> names;
    for (const CLI::App* s : subcommands) {
      if (s->check_name(word)) entered = s;
      names.push_back(s->get_name());
    }
    if (entered != nullptr) {
      current = entered;
      continue;
    }
    // A word where a positional may stand is a value, not a command.
    if (!current->get_options([](const CLI::Option* o) { return o->get_positional(); }).empty()) continue;
    if (names.empty()) continue;
    const std::string guess = closest(word, names);
    if (guess.empty()) return "";
    const std::string path = commandPath(*current);
    return (path.empty() ? "" : path + ": ") + "unknown command \"" + word + "\" (did you mean \"" + guess + "\"?)" +
           helpHint(*current);
  }
  return "";
}

}  // namespace hb

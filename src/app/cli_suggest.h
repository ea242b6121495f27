// A did-you-mean for a command line that CLI11 refused: "rendr" for "render", "--sizes" for
// "--size" (docs/usage.md "Exit codes"). The closeness rule is the config keys' (json_reader.h
// closestKey), so a typo is caught the same way on the command line and in a file.
#pragma once
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace hb {

// Walks `args` (argv without the program) through `app` as CLI11 would: a word that names a
// subcommand enters it; a "--name" or "--name=value" is looked up in the subcommand and its
// parents, and its value skipped; a word where only subcommands may stand is a subcommand name.
// Returns one line for the first unknown one that is close to a known name, e.g.
//   unknown command "rendr" (did you mean "render"?); see hybridbench --help
//   render: unknown flag "--sizes" (did you mean "--size"?); see hybridbench render --help
// or "" when there is none (CLI11's own message then stands). Hidden options (no group) are never
// suggested.
std::string suggestForUnknownArgument(const CLI::App& app, const std::vector<std::string>& args);

}  // namespace hb

// An output folder that already holds a command's results (docs/usage.md "Output folders"): a
// sweep or render into it is refused unless the user says what to do with them, so earlier results
// are never lost without a word.
#pragma once
#include <filesystem>
#include <string>

namespace hb {

enum class Existing { Refuse, Resume, Replace };

// `dir` holding `marker` (results.json for sweep, render.json for render) holds earlier results.
// Refuse: InputError naming the folder and the ways on (--resume where resumable, --force, a fresh
// folder). Resume: nothing to do. Replace: every entry of dir except earlier previous-*/ folders is
// moved into dir/previous-<UTC time>/, whose path is returned (empty when nothing was there).
// Throws InputError also when dir exists as a file. Creates nothing when it refuses.
std::string prepareOutDir(const std::filesystem::path& dir, const std::string& marker, Existing existing,
                          const std::string& command, bool resumable);

}  // namespace hb

// Reading a file the user named (a config, a results file, a scene, an image): every way it can be
// wrong — missing, a folder, unreadable — is one InputError line naming the path and what to pass
// instead (docs/usage.md "Exit codes": exit 2). `hint` is what the command wants, e.g. "pass a
// results.json written by 'hybridbench sweep'".
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace hb {

// Throws InputError unless `path` names a readable regular file (or a FIFO, e.g. <(...)).
void requireReadableFile(const std::filesystem::path& path, const std::string& hint);
// The file's text. A gzip file (by its magic bytes, whatever its name: results.json.gz, say) is
// inflated first, so a committed study can keep its results compressed (docs/results-format.md).
std::string readInputText(const std::filesystem::path& path, const std::string& hint);
// The file's bytes as they are (images, glTF binaries): nothing is inflated.
std::vector<uint8_t> readInputBytes(const std::filesystem::path& path, const std::string& hint);

// An output folder the user named: refused (InputError) when it exists as something other than a
// folder, e.g. `--out results.json`.
void requireOutputFolder(const std::filesystem::path& path, const std::string& flag);

}  // namespace hb

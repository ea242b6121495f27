#include "base/input_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <system_error>

#include "base/errors.h"

namespace hb {

namespace fs = std::filesystem;

void requireReadableFile(const fs::path& path, const std::string& hint) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (path.empty()) throw InputError("an empty path was given; " + hint);
  if (!fs::exists(st)) throw InputError(path.string() + ": no such file; " + hint);
  if (fs::is_directory(st)) throw InputError(path.string() + ": is a folder, not a file; " + hint);
  if (!fs::is_regular_file(st) && !fs::is_fifo(st))
    throw InputError(path.string() + ": is not a regular file; " + hint);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot be read (" + std::strerror(errno) + "); " + hint);
}

std::string readInputText(const fs::path& path, const std::string& hint) {
  requireReadableFile(path, hint);
  std::ifstream in(path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(path.string() + ": cannot be read (" + std::strerror(errno) + "); " + hint);
  return text;
}

std::vector<uint8_t> readInputBytes(const fs::path& path, const std::string& hint) {
  const std::string text = readInputText(path, hint);
  return std::vector<uint8_t>(text.begin(), text.end());
}

void requireOutputFolder(const fs::path& path, const std::string& flag) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (fs::exists(st) && !fs::is_directory(st))
    throw InputError(flag + " " + path.string() +
                     ": is a file, not a folder; name a folder to write into (it is "
                     "created if missing)");
}

}  // namespace hb

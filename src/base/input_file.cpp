#include "base/input_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <system_error>

#include <zlib.h>

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

namespace {

std::string readRaw(const fs::path& path, const std::string& hint) {
  requireReadableFile(path, hint);
  std::ifstream in(path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(path.string() + ": cannot be read (" + std::strerror(errno) + "); " + hint);
  return text;
}

bool isGzip(const std::string& bytes) {
  return bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0x1f &&
         static_cast<unsigned char>(bytes[1]) == 0x8b;
}

// The whole of a gzip stream (RFC 1952) inflated; a truncated or corrupt one is an InputError.
std::string gunzip(const std::string& bytes, const fs::path& path, const std::string& hint) {
  z_stream z{};
  if (inflateInit2(&z, 15 + 16) != Z_OK)  // 15: the largest window; +16: a gzip header, not zlib's
    throw InputError(path.string() + ": cannot start zlib to read this gzip file; " + hint);
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
  z.avail_in = static_cast<uInt>(bytes.size());
  std::string out;
  char chunk[1 << 16];
  int rc = Z_OK;
  while (rc == Z_OK) {
    z.next_out = reinterpret_cast<Bytef*>(chunk);
    z.avail_out = sizeof(chunk);
    rc = inflate(&z, Z_NO_FLUSH);
    out.append(chunk, sizeof(chunk) - z.avail_out);
    if (rc == Z_BUF_ERROR && z.avail_in == 0) break;  // the input ended before the stream did
  }
  inflateEnd(&z);
  if (rc != Z_STREAM_END)
    throw InputError(path.string() + ": a gzip file that is " + (rc == Z_BUF_ERROR ? "truncated" : "corrupt") +
                     " (zlib: " + (z.msg ? z.msg : std::to_string(rc)) + "); " + hint);
  return out;
}

}  // namespace

std::string readInputText(const fs::path& path, const std::string& hint) {
  std::string text = readRaw(path, hint);
  return isGzip(text) ? gunzip(text, path, hint) : text;
}

std::vector<uint8_t> readInputBytes(const fs::path& path, const std::string& hint) {
  const std::string bytes = readRaw(path, hint);
  return std::vector<uint8_t>(bytes.begin(), bytes.end());
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

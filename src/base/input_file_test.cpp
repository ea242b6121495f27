#include "base/input_file.h"

#include <zlib.h>

#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "base/errors.h"

namespace hb {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("hb-input-file-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

std::string gzipped(const std::string& text) {
  z_stream z{};
  EXPECT_EQ(deflateInit2(&z, 9, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY), Z_OK);
  std::string out(deflateBound(&z, text.size()) + 32, '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(text.data()));
  z.avail_in = static_cast<uInt>(text.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(out.size());
  EXPECT_EQ(deflate(&z, Z_FINISH), Z_STREAM_END);
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

void write(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

// A committed results.json.gz reads as the JSON it holds; its bytes as they are.
TEST(InputFile, AGzipFileReadsAsItsTextAndItsBytesStayAsTheyAre) {
  std::string text = "{\"schema_version\": 1, \"runs\": [";
  for (int i = 0; i < 20000; ++i) text += std::to_string(i * 0.001) + ",";  // > one 64 KiB chunk inflated
  text += "0]}\n";
  const std::string gz = gzipped(text);
  ASSERT_LT(gz.size(), text.size());
  const fs::path p = scratch("results.json.gz");
  write(p, gz);
  EXPECT_EQ(readInputText(p, "hint"), text);
  const std::vector<uint8_t> bytes = readInputBytes(p, "hint");
  EXPECT_EQ(std::string(bytes.begin(), bytes.end()), gz);
  const fs::path plain = scratch("results.json");
  write(plain, text);
  EXPECT_EQ(readInputText(plain, "hint"), text);
}

// A gzip file cut short or damaged is one line naming the file and the fault, not a JSON error.
TEST(InputFile, ATruncatedOrCorruptGzipFileIsOneLineNamingIt) {
  const std::string gz = gzipped(std::string(100000, 'x'));
  const fs::path cut = scratch("cut.json.gz");
  write(cut, gz.substr(0, gz.size() / 2));
  try {
    readInputText(cut, "pass a results file");
    FAIL() << "a truncated gzip file was read";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(cut.string()), std::string::npos) << m;
    EXPECT_NE(m.find("truncated"), std::string::npos) << m;
    EXPECT_NE(m.find("pass a results file"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
  std::string bad = gz;
  bad[bad.size() - 6] ^= 0x55;  // in the trailer's CRC-32 of the text (RFC 1952): the text no longer matches it
  const fs::path corrupt = scratch("corrupt.json.gz");
  write(corrupt, bad);
  try {
    readInputText(corrupt, "pass a results file");
    FAIL() << "a corrupt gzip file was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("corrupt"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hb

#include "base/image_io.h"

#include <stb_image.h>
#include <stb_image_write.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "base/errors.h"
#include "base/input_file.h"

namespace hb {

namespace {

constexpr std::array<uint8_t, 8> kPngSignature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
constexpr Rgb8 kMagenta{255, 0, 255};  // non-finite input, in every visualisation
constexpr Rgb8 kSkyBlue{16, 24, 88};   // cleared depth (nothing drawn)

uint8_t toByte(double v01) { return uint8_t(std::lround(std::clamp(v01, 0.0, 1.0) * 255.0)); }

void putPixel(ImageRGBA8& img, size_t i, Rgb8 c, uint8_t a = 255) {
  img.px[4 * i + 0] = c.r;
  img.px[4 * i + 1] = c.g;
  img.px[4 * i + 2] = c.b;
  img.px[4 * i + 3] = a;
}

ImageRGBA8 makeImage(uint32_t width, uint32_t height) {
  ImageRGBA8 img;
  img.width = width;
  img.height = height;
  img.px.assign(size_t(width) * height * 4, 0);
  return img;
}

void putBigEndian32(std::vector<uint8_t>& out, uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(uint8_t(v >> shift));
}

uint32_t getBigEndian32(const uint8_t* p) {
  return (uint32_t(p[0]) << 24) | (uint32_t(p[1]) << 16) | (uint32_t(p[2]) << 8) | uint32_t(p[3]);
}

// One chunk: length, type, data, CRC over type and data (PNG spec 5.3).
void appendChunk(std::vector<uint8_t>& out, const char (&type)[5], const std::vector<uint8_t>& data) {
  putBigEndian32(out, uint32_t(data.size()));
  const size_t typeAt = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data.begin(), data.end());
  const uint32_t crc = crc32Png(std::span<const uint8_t>(out.data() + typeAt, 4 + data.size()));
  putBigEndian32(out, crc);
}

// PNG spec 11.3.4.3: keywords are 1-79 Latin-1 printable characters, no leading/trailing space.
bool isValidPngKeyword(const std::string& key) {
  if (key.empty() || key.size() > 79 || key.front() == ' ' || key.back() == ' ') return false;
  return std::all_of(key.begin(), key.end(), [](char ch) {
    const auto c = uint8_t(ch);
    return (c >= 32 && c <= 126) || c >= 161;
  });
}

std::vector<uint8_t> textChunkData(const std::string& key, const std::string& value, bool international) {
  std::vector<uint8_t> data(key.begin(), key.end());
  data.push_back(0);
  if (international) {
    // iTXt: compression flag 0, method 0, empty language tag, empty translated keyword (11.3.4.5).
    data.insert(data.end(), {0, 0, 0, 0});
  }
  data.insert(data.end(), value.begin(), value.end());
  return data;
}

std::vector<uint8_t> readFileBytes(const std::filesystem::path& path) {
  return readInputBytes(path, "give the path of a PNG file");
}

void stbAppend(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<uint8_t>*>(context);
  const auto* bytes = static_cast<const uint8_t*>(data);
  out->insert(out->end(), bytes, bytes + size);
}

}  // namespace

// ---- PNG ---------------------------------------------------------------------------------------

uint32_t crc32Png(std::span<const uint8_t> bytes, uint32_t crc) {
  static const std::array<uint32_t, 256> table = [] {
    std::array<uint32_t, 256> t{};
    for (uint32_t n = 0; n < 256; ++n) {
      uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  uint32_t c = crc ^ 0xFFFFFFFFu;
  for (uint8_t b : bytes) c = table[(c ^ b) & 0xFF] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

void writePng(const std::filesystem::path& path, const ImageRGBA8& image,
              const std::map<std::string, std::string>& textChunks) {
  HB_ASSERT(image.width > 0 && image.height > 0);
  HB_ASSERT(image.px.size() == size_t(image.width) * image.height * 4);
  for (const auto& [key, value] : textChunks) {
    if (!isValidPngKeyword(key))
      throw InputError("PNG text key '" + key + "' for '" + path.string() +
                       "' is invalid: use 1-79 printable characters without leading/trailing spaces");
    if (value.find('\0') != std::string::npos)
      throw InputError("PNG text value of key '" + key + "' for '" + path.string() + "' contains a NUL byte");
  }

  std::vector<uint8_t> encoded;
  if (!stbi_write_png_to_func(stbAppend, &encoded, int(image.width), int(image.height), 4, image.px.data(),
                              int(image.width * 4)))
    throw std::runtime_error("stb_image_write failed to encode '" + path.string() + "'");
  // stb writes signature, then IHDR (4 length + 4 type + 13 data + 4 CRC = 25 bytes).
  constexpr size_t kAfterIhdr = 8 + 25;
  HB_ASSERT(encoded.size() > kAfterIhdr && std::memcmp(encoded.data() + 12, "IHDR", 4) == 0);

  std::vector<uint8_t> out(encoded.begin(), encoded.begin() + kAfterIhdr);
  for (const auto& [key, value] : textChunks) {
    const bool ascii = std::all_of(value.begin(), value.end(), [](char c) { return uint8_t(c) < 0x80; });
    if (ascii)
      appendChunk(out, "tEXt", textChunkData(key, value, false));
    else
      appendChunk(out, "iTXt", textChunkData(key, value, true));
  }
  out.insert(out.end(), encoded.begin() + kAfterIhdr, encoded.end());

  // Write beside the target and rename: readers never see a half-written file (POSIX rename is
  // atomic within one file system).
  std::filesystem::path tmp = path;
  tmp += ".tmp-" + std::to_string(::getpid());
  const auto fail = [&](const std::string& why) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    return InputError("cannot write PNG '" + path.string() + "': " + why +
                      "; check that its directory exists and is writable");
  };
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) throw fail(std::strerror(errno));
    f.write(reinterpret_cast<const char*>(out.data()), std::streamsize(out.size()));
    f.close();
    if (!f) throw fail("write failed");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw fail(ec.message());
}

ImageRGBA8 readPng(const std::filesystem::path& path) {
  const std::vector<uint8_t> bytes = readFileBytes(path);
  int w = 0, h = 0, channels = 0;
  stbi_uc* data = stbi_load_from_memory(bytes.data(), int(bytes.size()), &w, &h, &channels, 4);
  if (!data) throw InputError("cannot decode PNG '" + path.string() + "': " + stbi_failure_reason());
  ImageRGBA8 img = makeImage(uint32_t(w), uint32_t(h));
  std::memcpy(img.px.data(), data, img.px.size());
  stbi_image_free(data);
  return img;
}

std::map<std::string, std::string> readPngTextChunks(const std::filesystem::path& path) {
  const std::vector<uint8_t> bytes = readFileBytes(path);
  const auto bad = [&](const std::string& why) {
    return InputError("'" + path.string() + "' is not a well-formed PNG: " + why);
  };
  if (bytes.size() < 8 || !std::equal(kPngSignature.begin(), kPngSignature.end(), bytes.begin()))
    throw bad("missing PNG signature");
  std::map<std::string, std::string> text;
  size_t at = 8;
  while (at < bytes.size()) {
    if (bytes.size() - at < 12) throw bad("truncated chunk header at byte " + std::to_string(at));
    const uint32_t length = getBigEndian32(&bytes[at]);
    if (bytes.size() - at - 12 < length) throw bad("truncated chunk at byte " + std::to_string(at));
    const std::string type(reinterpret_cast<const char*>(&bytes[at + 4]), 4);
    const uint8_t* data = &bytes[at + 8];
    const uint32_t storedCrc = getBigEndian32(data + length);
    if (crc32Png(std::span<const uint8_t>(&bytes[at + 4], 4 + size_t(length))) != storedCrc)
      throw bad("CRC mismatch in chunk '" + type + "'");
    const std::string payload(reinterpret_cast<const char*>(data), length);
    const size_t nul = payload.find('\0');
    if (type == "tEXt" && nul != std::string::npos) {
      text[payload.substr(0, nul)] = payload.substr(nul + 1);
    } else if (type == "iTXt" && nul != std::string::npos && nul + 2 < payload.size() &&
               payload[nul + 1] == 0) {  // uncompressed iTXt only
      const size_t langEnd = payload.find('\0', nul + 3);
      const size_t transEnd = langEnd == std::string::npos ? langEnd : payload.find('\0', langEnd + 1);
      if (transEnd != std::string::npos) text[payload.substr(0, nul)] = payload.substr(transEnd + 1);
    }
    at += 12 + size_t(length);
    if (type == "IEND") break;
  }
  return text;
}

// ---- visualisations ----------------------------------------------------------------------------

ImageRGBA8 depthToImage(std::span<const float> depth, uint32_t width, uint32_t height, float znear, float zfar,
                        bool affine) {
  HB_ASSERT(depth.size() == size_t(width) * height);
  HB_ASSERT(znear > 0 && zfar > znear);
  // Inverse of camera.h's reverse-Z mapping depth = C + D/d, d = -z_view the view distance.
  const double zn = znear, zf = zfar;
  const double c = zn / (zf - zn), d = zf * zn / (zf - zn);
  const double logRange = std::log(zf / zn);
  ImageRGBA8 img = makeImage(width, height);
  for (size_t i = 0; i < depth.size(); ++i) {
    const float z = depth[i];
    if (!std::isfinite(z)) {
      putPixel(img, i, kMagenta);
    } else if (z <= 0.0f) {
      putPixel(img, i, kSkyBlue);
    } else {
      const double clamped = std::min(double(z), 1.0);
      const double distance = affine ? zf - clamped * (zf - zn) : d / (clamped + c);
      const double t = std::clamp(std::log(distance / zn) / logRange, 0.0, 1.0);
      const uint8_t grey = toByte(1.0 - t);
      putPixel(img, i, {grey, grey, grey});
    }
  }
  return img;
}

Rgb8 thesisHeatColor(double t) {
  struct Stop {
    double t, r, g, b;
  };
  // Thesis Figure 5.2 bands at 10 lights: 0-3 black/blue, 4-7 cyan/green, 8-10 yellow/red.
  static constexpr std::array<Stop, 6> kStops = {
      {{0.0, 0, 0, 0}, {0.3, 0, 0, 1}, {0.4, 0, 1, 1}, {0.7, 0, 1, 0}, {0.8, 1, 1, 0}, {1.0, 1, 0, 0}}};
  if (!std::isfinite(t)) return kMagenta;
  t = std::clamp(t, 0.0, 1.0);
  size_t k = 1;
  while (k + 1 < kStops.size() && t > kStops[k].t) ++k;
  const Stop& a = kStops[k - 1];
  const Stop& b = kStops[k];
  const double s = (t - a.t) / (b.t - a.t);
  return {toByte(a.r + s * (b.r - a.r)), toByte(a.g + s * (b.g - a.g)), toByte(a.b + s * (b.b - a.b))};
}

ImageRGBA8 heatmapThesis(std::span<const uint32_t> counts, uint32_t width, uint32_t height, uint32_t maxValue) {
  HB_ASSERT(counts.size() == size_t(width) * height);
  ImageRGBA8 img = makeImage(width, height);
  for (size_t i = 0; i < counts.size(); ++i)
    putPixel(img, i, thesisHeatColor(maxValue == 0 ? 0.0 : double(counts[i]) / maxValue));
  return img;
}

ImageRGBA8 heatmapLegend(uint32_t maxValue, uint32_t width, uint32_t height) {
  HB_ASSERT(width >= maxValue + 1 && height >= 1);
  ImageRGBA8 img = makeImage(width, height);
  for (uint32_t x = 0; x < width; ++x) {
    const uint32_t value = uint32_t(uint64_t(x) * (maxValue + 1) / width);
    const Rgb8 c = thesisHeatColor(maxValue == 0 ? 0.0 : double(value) / maxValue);
    for (uint32_t y = 0; y < height; ++y) putPixel(img, size_t(y) * width + x, c);
  }
  return img;
}

ImageRGBA8 normalsToImage(std::span<const float> normals, std::span<const uint8_t> valid, uint32_t width,
                          uint32_t height) {
  const size_t n = size_t(width) * height;
  HB_ASSERT(normals.size() == 3 * n);
  HB_ASSERT(valid.empty() || valid.size() == n);
  ImageRGBA8 img = makeImage(width, height);
  for (size_t i = 0; i < n; ++i) {
    if (!valid.empty() && !valid[i]) {
      putPixel(img, i, {0, 0, 0});
      continue;
    }
    const float* v = &normals[3 * i];
    if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
      putPixel(img, i, kMagenta);
      continue;
    }
    putPixel(img, i, {toByte(v[0] * 0.5 + 0.5), toByte(v[1] * 0.5 + 0.5), toByte(v[2] * 0.5 + 0.5)});
  }
  return img;
}

Rgb8 viridisColor(double t) {
  // Matt Zucker's published degree-6 polynomial fit of matplotlib's viridis, evaluated in
  // display (sRGB-encoded) space. image_io_test.cpp holds it to matplotlib's table at t = 0, 0.5, 1
  // and checks that its luminance rises monotonically (the property an error map needs).
  static constexpr double kCoeff[7][3] = {{0.2777273272234177, 0.005407344544966578, 0.3340998053353061},
                                          {0.1050930431085774, 1.404613529898575, 1.384590162594685},
                                          {-0.3308618287255563, 0.214847559468213, 0.09509516302823659},
                                          {-4.634230498983486, -5.799100973351585, -19.33244095627987},
                                          {6.228269936347081, 14.17993336680509, 56.69055260068105},
                                          {4.776384997670288, -13.74514537774601, -65.35303263337234},
                                          {-5.435455855934631, 4.645852612178535, 26.3124352495832}};
  if (!std::isfinite(t)) return kMagenta;
  t = std::clamp(t, 0.0, 1.0);
  double rgb[3];
  for (int ch = 0; ch < 3; ++ch) {
    double v = kCoeff[6][ch];
    for (int k = 5; k >= 0; --k) v = v * t + kCoeff[k][ch];  // Horner
    rgb[ch] = v;
  }
  return {toByte(rgb[0]), toByte(rgb[1]), toByte(rgb[2])};
}

ImageRGBA8 errorMapToImage(std::span<const float> errors, uint32_t width, uint32_t height, float maxErr) {
  HB_ASSERT(errors.size() == size_t(width) * height);
  HB_ASSERT(maxErr > 0);
  ImageRGBA8 img = makeImage(width, height);
  for (size_t i = 0; i < errors.size(); ++i)
    putPixel(img, i, std::isfinite(errors[i]) ? viridisColor(double(errors[i]) / maxErr) : kMagenta);
  return img;
}

// ---- tone mapping ------------------------------------------------------------------------------

ToneMapOperator toneMapOperatorFromName(const std::string& name) {
  if (name == "aces") return ToneMapOperator::AcesFitted;
  if (name == "reinhard") return ToneMapOperator::Reinhard;
  throw InputError("unknown tone-mapping operator '" + name + "': use \"aces\" or \"reinhard\"");
}

const char* toneMapOperatorName(ToneMapOperator op) { return op == ToneMapOperator::AcesFitted ? "aces" : "reinhard"; }

double linearToSrgb(double linear) {
  linear = std::clamp(linear, 0.0, 1.0);
  return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

double srgbToLinear(double encoded) {
  encoded = std::clamp(encoded, 0.0, 1.0);
  return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

ToneMapResult toneMapToSrgb(const ImageF& hdr, float exposure, ToneMapOperator op) {
  HB_ASSERT(hdr.channels == 3 || hdr.channels == 4);
  const size_t n = size_t(hdr.width) * hdr.height;
  HB_ASSERT(hdr.px.size() == n * hdr.channels);
  ToneMapResult result;
  result.image = makeImage(hdr.width, hdr.height);
  // Double precision: x² of a large finite float cannot overflow, so only real NaN/Inf are flagged.
  const double scale = std::exp2(double(exposure));
  for (size_t i = 0; i < n; ++i) {
    const float* p = &hdr.px[i * hdr.channels];
    const uint8_t alpha = hdr.channels == 4 && std::isfinite(p[3]) ? toByte(p[3]) : 255;
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      putPixel(result.image, i, kMagenta, alpha);
      ++result.nonFinitePixels;
      continue;
    }
    double c[3];
    for (int k = 0; k < 3; ++k) c[k] = std::max(0.0, double(p[k]) * scale);
    if (op == ToneMapOperator::AcesFitted) {
      // Narkowicz 2016, "ACES Filmic Tone Mapping Curve": fit of the ACES RRT+ODT; -> 2.51/2.43 as x -> inf.
      for (double& x : c) x = (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14);
    } else {
      // Reinhard et al. 2002 (eq. 3) on luminance, applied to the colour to keep its hue.
      const double luminance = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
      for (double& x : c) x = x / (1.0 + luminance);
    }
    putPixel(result.image, i, {toByte(linearToSrgb(c[0])), toByte(linearToSrgb(c[1])), toByte(linearToSrgb(c[2]))},
             alpha);
  }
  return result;
}

}  // namespace hb

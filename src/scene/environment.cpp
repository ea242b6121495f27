#include "scene/environment.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>

#include <stb_image.h>

#include "base/errors.h"
#include "base/numbers.h"

namespace hb {

namespace {

// stb_image decodes a truncated Radiance file without complaint (it reads zeros past the end), so
// the scanlines are walked first: the file must hold all `height` of them after the header, each
// either flat (4 bytes a pixel) or new-style run-length encoded (2, 2, width; per channel, runs of
// 1..127 equal bytes or literals of 1..128 bytes), as stb reads them. "" when complete, else what
// is wrong.
std::string hdrScanlinesProblem(const std::vector<uint8_t>& f) {
  size_t pos = 0;
  auto line = [&]() {
    std::string l;
    while (pos < f.size() && f[pos] != '\n') l += char(f[pos++]);
    ++pos;
    return l;
  };
  while (pos < f.size() && !line().empty()) {
  }
  int height = 0, width = 0;
  if (std::sscanf(line().c_str(), "-Y %d +X %d", &height, &width) != 2 || height <= 0 || width <= 0)
    return "its resolution line is not \"-Y <height> +X <width>\"";
  for (int y = 0; y < height; ++y) {
    const bool rle =
        width >= 8 && width < 32768 && pos + 4 <= f.size() && f[pos] == 2 && f[pos + 1] == 2 && !(f[pos + 2] & 0x80);
    if (!rle) {
      pos += size_t(width) * 4;
    } else {
      if ((int(f[pos + 2]) << 8 | f[pos + 3]) != width)
        return "scanline " + std::to_string(y) + " has the wrong length";
      pos += 4;
      for (int channel = 0; channel < 4; ++channel)
        for (int x = 0; x < width;) {
          if (pos >= f.size()) return "it ends in scanline " + std::to_string(y);
          const int c = f[pos++];
          const int n = c > 128 ? c - 128 : c;
          if (n == 0 || x + n > width) return "scanline " + std::to_string(y) + " has a bad run";
          pos += c > 128 ? 1 : size_t(n);
          x += n;
        }
    }
    if (pos > f.size()) return "it ends in scanline " + std::to_string(y) + " of " + std::to_string(height);
  }
  return "";
}

}  // namespace

Environment readEnvironment(const nlohmann::ordered_json& value, const json_reader::Where& where,
                            const std::filesystem::path& baseDir) {
  using namespace json_reader;
  requireObjectWithKeys(value, where, {"image", "color", "intensity", "rotation"});
  if (!value.contains("image") && !value.contains("color"))
    where.fail(
        "has neither \"image\" nor \"color\"; give an equirectangular .hdr (\"image\": \"sky.hdr\") or a "
        "uniform colour (\"color\": [r, g, b])");
  Environment e;
  const double inf = std::numeric_limits<double>::infinity();
  if (value.contains("intensity")) e.intensity = readFloat(value["intensity"], where.key("intensity"), 0.0, inf, false);
  if (value.contains("rotation"))
    e.rotationDegrees = readFloat(value["rotation"], where.key("rotation"), -360.0, 360.0, false);
  if (value.contains("color")) {
    const std::vector<float> c = readFloats(value["color"], where.key("color"), 3, "[r, g, b]");
    for (int i = 0; i < 3; ++i) {
      if (!(c[i] >= 0.0f)) where.key("color").fail("has a negative component; give linear RGB >= 0");
      e.color[i] = c[i];
    }
  }
  if (!value.contains("image")) return e;
  const Where w = where.key("image");
  std::filesystem::path p(readString(value["image"], w));
  if (p.is_relative()) p = baseDir / p;
  p = std::filesystem::absolute(p).lexically_normal();
  e.image = p.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(p, ec))
    w.fail("'" + e.image + "' does not exist or is not a file; give the path of a Radiance .hdr, relative to " +
           (baseDir.empty() ? std::string("the working directory") : "'" + baseDir.string() + "'"));
  // A flat 4096 x 2048 map is 32 MiB after its header; a larger file cannot be one we accept.
  if (std::filesystem::file_size(p, ec) > (kEnvironmentMaxTexels * 4 + (1u << 20)) || ec)
    w.fail("'" + e.image + "' is larger than a 4096 x 2048 Radiance .hdr can be; downsample it");
  if (!stbi_is_hdr(e.image.c_str()))
    w.fail("'" + e.image +
           "' is not a Radiance .hdr (RGBE) file; convert it, e.g. with ImageMagick: convert in.exr out.hdr");
  {
    std::ifstream in(p, std::ios::binary);
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (const std::string problem = hdrScanlinesProblem(bytes); !problem.empty())
      w.fail("'" + e.image + "' is truncated or corrupt (" + problem + "); re-save it as a Radiance .hdr");
  }
  int width = 0, height = 0, channels = 0;
  float* data = stbi_loadf(e.image.c_str(), &width, &height, &channels, 3);
  if (!data) w.fail("cannot decode '" + e.image + "': " + stbi_failure_reason() + "; re-save it as a Radiance .hdr");
  const uint64_t texels = uint64_t(width) * uint64_t(height);
  if (texels > kEnvironmentMaxTexels) {
    stbi_image_free(data);
    w.fail("'" + e.image + "' is " + std::to_string(width) + " x " + std::to_string(height) +
           ", more than 4096 x 2048 texels; downsample it (the GPU holds it as one buffer)");
  }
  e.width = uint32_t(width);
  e.height = uint32_t(height);
  e.texels.resize(texels);
  for (uint64_t i = 0; i < texels; ++i) {
    e.texels[i] = glm::vec3(data[3 * i], data[3 * i + 1], data[3 * i + 2]);
    if (!std::isfinite(e.texels[i].r + e.texels[i].g + e.texels[i].b) || e.texels[i].r < 0.0f || e.texels[i].g < 0.0f ||
        e.texels[i].b < 0.0f) {
      stbi_image_free(data);
      w.fail("'" + e.image + "' has a negative or non-finite texel at (" + std::to_string(i % e.width) + ", " +
             std::to_string(i / e.width) + "); fix the file");
    }
  }
  stbi_image_free(data);
  return e;
}

nlohmann::json toJson(const Environment& e) {
  nlohmann::json j;
  if (!e.image.empty()) j["image"] = e.image;
  j["color"] = {e.color.r, e.color.g, e.color.b};
  j["intensity"] = e.intensity;
  j["rotation"] = e.rotationDegrees;
  return j;
}

glm::dvec3 environmentRadiance(const Environment& e, const glm::dvec3& d) {
  const double a = double(e.rotationDegrees) * kPi / 180.0, c = std::cos(a), s = std::sin(a);
  const glm::dvec3 r(c * d.x - s * d.z, d.y, s * d.x + c * d.z);  // R_y(−rotation)·d
  const double phi = std::atan2(r.x, -r.z), theta = std::acos(std::clamp(r.y, -1.0, 1.0));
  const double fu = (phi + kPi) / (2.0 * kPi) * e.width - 0.5, fv = theta / kPi * e.height - 0.5;
  const double x0 = std::floor(fu), y0 = std::floor(fv), tx = fu - x0, ty = fv - y0;
  auto texel = [&](int64_t x, int64_t y) {
    x = ((x % int64_t(e.width)) + int64_t(e.width)) % int64_t(e.width);
    y = std::clamp<int64_t>(y, 0, int64_t(e.height) - 1);
    return glm::dvec3(e.texels[size_t(y) * e.width + size_t(x)]);
  };
  const int64_t ix = int64_t(x0), iy = int64_t(y0);
  const glm::dvec3 top = (1.0 - tx) * texel(ix, iy) + tx * texel(ix + 1, iy);
  const glm::dvec3 bottom = (1.0 - tx) * texel(ix, iy + 1) + tx * texel(ix + 1, iy + 1);
  return ((1.0 - ty) * top + ty * bottom) * glm::dvec3(e.color) * double(e.intensity);
}

}  // namespace hb

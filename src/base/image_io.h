// CPU-side images: PNG files with text metadata, and the visualisations the tool writes
// (depth, ray-count heatmaps, normals, error maps, tone-mapped HDR colour).
#pragma once
#include <cstdint>
#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace hb {

// 8-bit sRGB-encoded RGBA, row-major, top row first; px.size() == width*height*4.
struct ImageRGBA8 {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> px;
};

// Float image, row-major, `channels` interleaved values per pixel; px.size() == width*height*channels.
struct ImageF {
  uint32_t width = 0, height = 0, channels = 0;
  std::vector<float> px;
};

struct Rgb8 {
  uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb8&) const = default;
};

// ---- PNG ---------------------------------------------------------------------------------------

// Writes `image` as an RGBA PNG. Each textChunks entry becomes a tEXt chunk (iTXt when the value
// is not plain ASCII, so UTF-8 survives) placed right after IHDR, e.g. {"tonemap", "aces"}.
// Keys must be 1-79 printable Latin-1 characters (PNG spec 11.3.4.3); no NUL in keys or values.
// The file appears atomically (written to a temporary beside it, then renamed).
// Throws InputError (one line, names the path) when the file cannot be written.
void writePng(const std::filesystem::path& path, const ImageRGBA8& image,
              const std::map<std::string, std::string>& textChunks = {});

// Reads any PNG stb_image understands, converted to RGBA8. Throws InputError naming the path.
ImageRGBA8 readPng(const std::filesystem::path& path);

// The tEXt and (uncompressed) iTXt chunks of a PNG file, keyword -> text. Throws InputError when
// the file is missing or is not a well-formed PNG chunk stream.
std::map<std::string, std::string> readPngTextChunks(const std::filesystem::path& path);

// CRC-32 as PNG uses it (ISO 3309 / ITU-T V.42, polynomial 0xEDB88320, PNG spec annex D).
uint32_t crc32Png(std::span<const uint8_t> bytes, uint32_t crc = 0);

// ---- visualisations ----------------------------------------------------------------------------

// Reverse-Z depth (camera.h: near -> 1, far -> 0) to grey: the view distance
// d = D/(depth + C) (C = zn/(zf-zn), D = zf*zn/(zf-zn)) maps logarithmically from white at znear
// to black at zfar, so near and far structure are both visible. depth == 0 (cleared: sky) is
// dark blue; non-finite depth is magenta. `affine`: the orthographic mapping depth = (zf - d)/(zf - zn)
// instead. Preconditions: depth.size() == width*height, 0 < znear < zfar.
ImageRGBA8 depthToImage(std::span<const float> depth, uint32_t width, uint32_t height, float znear, float zfar,
                        bool affine = false);

// The thesis's ray-count colours (section 5, Figure 5.2): black/blue for 0-3 of 10, cyan/green
// for 4-7, yellow/red for 8-10, as a piecewise-linear ramp through
//   t = 0 black, 0.3 blue, 0.4 cyan, 0.7 green, 0.8 yellow, 1 red
// (so at maxValue 10: 3 is blue, 4 cyan, 7 green, 8 yellow, 10 red),
// with t = value/maxValue clamped to [0,1] (maxValue == 0 maps everything to black).
Rgb8 thesisHeatColor(double t);
// Preconditions: counts.size() == width*height. maxValue is the light count (the most rays a
// pixel can trace); it maps to red.
ImageRGBA8 heatmapThesis(std::span<const uint32_t> counts, uint32_t width, uint32_t height, uint32_t maxValue);
// A legend strip for heatmapThesis: maxValue+1 equal cells, left to right, cell i coloured as the
// count i. Preconditions: width >= maxValue+1, height >= 1.
ImageRGBA8 heatmapLegend(uint32_t maxValue, uint32_t width, uint32_t height);

// Unit normals (3 floats per pixel) to colour n*0.5+0.5; pixels whose valid byte is 0 are black.
// An empty `valid` means every pixel is valid. Preconditions: normals.size() == 3*width*height,
// valid.empty() || valid.size() == width*height.
ImageRGBA8 normalsToImage(std::span<const float> normals, std::span<const uint8_t> valid, uint32_t width,
                          uint32_t height);

// A perceptual colour map (viridis, polynomial fit) of t in [0,1]: dark purple -> teal -> yellow,
// luminance increasing monotonically.
Rgb8 viridisColor(double t);
// errors / maxErr clamped to [0,1] through viridisColor; non-finite errors are magenta.
// Preconditions: errors.size() == width*height, maxErr > 0.
ImageRGBA8 errorMapToImage(std::span<const float> errors, uint32_t width, uint32_t height, float maxErr);

// ---- tone mapping ------------------------------------------------------------------------------

enum class ToneMapOperator { AcesFitted, Reinhard };

// "aces" / "reinhard" (case-sensitive). Throws InputError naming the value and the choices.
ToneMapOperator toneMapOperatorFromName(const std::string& name);
const char* toneMapOperatorName(ToneMapOperator op);

struct ToneMapResult {
  ImageRGBA8 image;
  uint64_t nonFinitePixels = 0;  // pixels with a NaN/Inf channel, painted magenta
};

// Linear HDR RGB(A) to 8-bit sRGB: scale by 2^exposure, tone map, sRGB OETF (IEC 61966-2-1),
// round to nearest. AcesFitted is Narkowicz's 2016 fit (2.51x²+0.03x)/(2.43x²+0.59x+0.14);
// Reinhard divides the colour by 1 + its Rec.709 luminance. Negative values are clamped to 0.
// Alpha (4-channel input) is copied; 3-channel input gets alpha 255.
// Preconditions: hdr.channels is 3 or 4, hdr.px.size() == width*height*channels.
ToneMapResult toneMapToSrgb(const ImageF& hdr, float exposure, ToneMapOperator op);

// sRGB OETF / EOTF on [0,1] (IEC 61966-2-1).
double linearToSrgb(double linear);
double srgbToLinear(double encoded);

}  // namespace hb

#include "base/image_io.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>

#include "base/errors.h"

namespace hb {
namespace {

namespace fs = std::filesystem;

// A fresh directory per test, removed afterwards.
struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& name)
      : path(fs::temp_directory_path() / ("hb_image_io_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

// Hue in degrees [0, 360) of an 8-bit colour (the HSV hexcone), -1 for greys.
double hueDegrees(Rgb8 c) {
  const double r = c.r, g = c.g, b = c.b;
  const double mx = std::max({r, g, b}), mn = std::min({r, g, b});
  if (mx == mn) return -1;
  double h;
  if (mx == r)
    h = 60 * std::fmod((g - b) / (mx - mn), 6.0);
  else if (mx == g)
    h = 60 * ((b - r) / (mx - mn) + 2);
  else
    h = 60 * ((r - g) / (mx - mn) + 4);
  return h < 0 ? h + 360 : h;
}

Rgb8 pixelAt(const ImageRGBA8& img, size_t i) { return {img.px[4 * i], img.px[4 * i + 1], img.px[4 * i + 2]}; }

TEST(Crc32Png, MatchesTheStandardCheckValues) {
  // CRC-32 check value of "123456789" (ISO 3309) and the CRC every PNG's IEND chunk carries.
  const char* digits = "123456789";
  EXPECT_EQ(crc32Png({reinterpret_cast<const uint8_t*>(digits), 9}), 0xCBF43926u);
  EXPECT_EQ(crc32Png({reinterpret_cast<const uint8_t*>("IEND"), 4}), 0xAE426082u);
}

TEST(Png, RoundTripKeepsPixelsAndTextChunks) {
  TempDir dir("roundtrip");
  ImageRGBA8 img{5, 3, {}};
  std::mt19937 rng(1234);
  for (size_t i = 0; i < size_t(5) * 3 * 4; ++i) img.px.push_back(uint8_t(rng()));
  const std::map<std::string, std::string> text = {{"tonemap", "aces"},
                                                   {"device", "NVIDIA H100 80GB HBM3"},
                                                   {"config", "{\"tile\": 8}"},
                                                   {"note", "lavapipe \xC2\xB5s"}};  // non-ASCII UTF-8: stored as iTXt
  const fs::path file = dir.path / "img.png";
  writePng(file, img, text);

  const ImageRGBA8 back = readPng(file);
  EXPECT_EQ(back.width, 5u);
  EXPECT_EQ(back.height, 3u);
  EXPECT_EQ(back.px, img.px);
  EXPECT_EQ(readPngTextChunks(file), text);

  // The first text chunk sits right after IHDR (8-byte signature + 25-byte IHDR, then length).
  std::ifstream in(file, std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 41u);
  const std::string firstAfterIhdr(bytes.data() + 33 + 4, 4);
  EXPECT_TRUE(firstAfterIhdr == "tEXt" || firstAfterIhdr == "iTXt") << firstAfterIhdr;

  // Atomic write: nothing but the PNG is left in the directory.
  size_t entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path)) ++entries;
  EXPECT_EQ(entries, 1u);
}

TEST(Png, WritingIntoAMissingDirectoryThrowsInputErrorNamingThePath) {
  const fs::path file = fs::temp_directory_path() / "hb_no_such_dir_for_png" / "out.png";
  ImageRGBA8 img{1, 1, {1, 2, 3, 4}};
  try {
    writePng(file, img);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
}

TEST(Png, AnInvalidTextKeyIsRejected) {
  TempDir dir("badkey");
  ImageRGBA8 img{1, 1, {1, 2, 3, 4}};
  EXPECT_THROW(writePng(dir.path / "a.png", img, {{"", "x"}}), InputError);
  EXPECT_THROW(writePng(dir.path / "a.png", img, {{std::string(80, 'k'), "x"}}), InputError);
}

TEST(Png, ReadingAMissingFileThrowsInputError) {
  EXPECT_THROW(readPng("/nonexistent/hb.png"), InputError);
  EXPECT_THROW(readPngTextChunks("/nonexistent/hb.png"), InputError);
}

TEST(Heatmap, ThesisColoursAtZeroThreeSevenTenOfTen) {
  // Thesis Figure 5.2: black/blue 0-3, cyan/green 4-7, yellow/red 8-10. The ramp's stops sit
  // exactly on 0, 3, 7 and 10 of 10, so these are exact colours, not approximations.
  const std::vector<uint32_t> counts = {0, 3, 7, 10, 4, 8};
  const ImageRGBA8 img = heatmapThesis(counts, 6, 1, 10);
  EXPECT_EQ(pixelAt(img, 0), (Rgb8{0, 0, 0}));
  EXPECT_EQ(pixelAt(img, 1), (Rgb8{0, 0, 255}));
  EXPECT_EQ(pixelAt(img, 2), (Rgb8{0, 255, 0}));
  EXPECT_EQ(pixelAt(img, 3), (Rgb8{255, 0, 0}));
  EXPECT_EQ(pixelAt(img, 4), (Rgb8{0, 255, 255}));
  EXPECT_EQ(pixelAt(img, 5), (Rgb8{255, 255, 0}));
}

TEST(Heatmap, EveryCountFallsInItsThesisBand) {
  // Hue bands (HSV): blue = 240, cyan..green = 180..120, yellow..red = 60..0.
  for (uint32_t c = 1; c <= 10; ++c) {
    const double h = hueDegrees(thesisHeatColor(c / 10.0));
    if (c <= 3)
      EXPECT_DOUBLE_EQ(h, 240) << c;
    else if (c <= 7)
      EXPECT_TRUE(h >= 120 && h <= 180) << c << " hue " << h;
    else
      EXPECT_TRUE(h >= 0 && h <= 60) << c << " hue " << h;
  }
}

TEST(Heatmap, ScalesToTheLightCountAndClampsAboveIt) {
  const std::vector<uint32_t> counts = {2, 4, 9};
  const ImageRGBA8 img = heatmapThesis(counts, 3, 1, 4);
  EXPECT_EQ(pixelAt(img, 0), thesisHeatColor(0.5));
  EXPECT_EQ(pixelAt(img, 1), (Rgb8{255, 0, 0}));
  EXPECT_EQ(pixelAt(img, 2), (Rgb8{255, 0, 0}));
  const ImageRGBA8 noLights = heatmapThesis(counts, 3, 1, 0);
  EXPECT_EQ(pixelAt(noLights, 2), (Rgb8{0, 0, 0}));
}

TEST(Heatmap, LegendHasOneCellPerCount) {
  const ImageRGBA8 legend = heatmapLegend(10, 110, 4);
  for (uint32_t v = 0; v <= 10; ++v) EXPECT_EQ(pixelAt(legend, 3 * 110 + v * 10 + 5), thesisHeatColor(v / 10.0));
}

TEST(ToneMap, NonFinitePixelsArePaintedMagentaAndCounted) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  ImageF hdr{4, 1, 3, {0.5f, 0.5f, 0.5f, nan, 0.f, 0.f, 0.f, inf, 0.f, 0.f, 0.f, 0.f}};
  for (ToneMapOperator op : {ToneMapOperator::AcesFitted, ToneMapOperator::Reinhard}) {
    const ToneMapResult r = toneMapToSrgb(hdr, 0.0f, op);
    EXPECT_EQ(r.nonFinitePixels, 2u);
    EXPECT_EQ(pixelAt(r.image, 1), (Rgb8{255, 0, 255}));
    EXPECT_EQ(pixelAt(r.image, 2), (Rgb8{255, 0, 255}));
    EXPECT_NE(pixelAt(r.image, 0), (Rgb8{255, 0, 255}));
    EXPECT_EQ(pixelAt(r.image, 3), (Rgb8{0, 0, 0}));
  }
}

TEST(ToneMap, KnownValuesOfBothOperators) {
  // Reinhard: grey 1 has luminance 1 -> 0.5 linear -> sRGB 1.055*0.5^(1/2.4)-0.055 = 0.7354 -> 188.
  // ACES fit: x = 1 -> 2.54/3.16 = 0.80380 -> sRGB 0.90824 -> 231.6 -> 232. A huge value saturates to 255
  // (the curve tends to 2.51/2.43 > 1). Exposure 1 doubles the input: 0.5 * 2 behaves as 1.
  ImageF hdr{3, 1, 4, {1.f, 1.f, 1.f, 0.25f, 1e30f, 1e30f, 1e30f, 1.f, 0.5f, 0.5f, 0.5f, 1.f}};
  const ToneMapResult reinhard = toneMapToSrgb(hdr, 0.0f, ToneMapOperator::Reinhard);
  EXPECT_EQ(pixelAt(reinhard.image, 0), (Rgb8{188, 188, 188}));
  EXPECT_EQ(reinhard.image.px[3], 64);  // alpha 0.25 copied
  const ToneMapResult aces = toneMapToSrgb(hdr, 0.0f, ToneMapOperator::AcesFitted);
  EXPECT_EQ(pixelAt(aces.image, 0), (Rgb8{232, 232, 232}));
  EXPECT_EQ(pixelAt(aces.image, 1), (Rgb8{255, 255, 255}));
  EXPECT_EQ(aces.nonFinitePixels, 0u);
  const ToneMapResult acesUp = toneMapToSrgb(hdr, 1.0f, ToneMapOperator::AcesFitted);
  EXPECT_EQ(pixelAt(acesUp.image, 2), (Rgb8{232, 232, 232}));
}

TEST(ToneMap, OperatorNamesRoundTripAndUnknownNamesAreInputErrors) {
  for (ToneMapOperator op : {ToneMapOperator::AcesFitted, ToneMapOperator::Reinhard})
    EXPECT_EQ(toneMapOperatorFromName(toneMapOperatorName(op)), op);
  EXPECT_THROW(toneMapOperatorFromName("filmic"), InputError);
}

TEST(Srgb, OetfAndEotfAreInverse) {
  // Both are monotone closed forms; double round trip error is a few ULPs of 1 (< 1e-12).
  for (int i = 0; i <= 1000; ++i) EXPECT_NEAR(srgbToLinear(linearToSrgb(i / 1000.0)), i / 1000.0, 1e-12);
}

TEST(DepthImage, NearIsWhiteFarIsDarkSkyIsBlueAndTheLogMidpointIsMidGrey) {
  const float zn = 0.1f, zf = 100.f;
  // depth = D/d - C (camera.h: (C*z + D)/(-z) with z = -d); the geometric mean distance
  // sqrt(zn*zf) is halfway in log distance.
  const double c = zn / double(zf - zn), dd = double(zf) * zn / (zf - zn);
  const double mid = std::sqrt(double(zn) * zf);
  const std::vector<float> depth = {1.0f, 0.0f, float(dd / mid - c), float(dd / 99.0 - c),
                                    std::numeric_limits<float>::quiet_NaN()};
  const ImageRGBA8 img = depthToImage(depth, 5, 1, zn, zf);
  EXPECT_EQ(pixelAt(img, 0), (Rgb8{255, 255, 255}));
  const Rgb8 sky = pixelAt(img, 1);
  EXPECT_GT(sky.b, sky.r);  // distinct from every grey
  // t = 0.5 -> 127.5; float rounding of the stored depth moves t by ~1e-6, so 127 or 128.
  EXPECT_NEAR(pixelAt(img, 2).r, 127.5, 0.5);
  EXPECT_LE(pixelAt(img, 3).r, 1);  // log(990)/log(1000) = 0.9985 -> 0.4 of a level
  EXPECT_EQ(pixelAt(img, 4), (Rgb8{255, 0, 255}));
}

TEST(DepthImage, AnOrthographicViewsAffineDepthMapsToTheSameGreys) {
  // depth = (zf - d)/(zf - zn): the same distances as above give the same greys.
  const float zn = 0.1f, zf = 100.f;
  const double mid = std::sqrt(double(zn) * zf);
  const std::vector<float> depth = {1.0f, 0.0f, float((zf - mid) / (zf - zn)), float((zf - 99.0) / (zf - zn))};
  const ImageRGBA8 img = depthToImage(depth, 4, 1, zn, zf, true);
  EXPECT_EQ(pixelAt(img, 0), (Rgb8{255, 255, 255}));
  EXPECT_EQ(pixelAt(img, 1), pixelAt(depthToImage(std::vector<float>{0.0f}, 1, 1, zn, zf), 0));
  // Float depth near 0.97 has an absolute step of 6e-8, i.e. 6e-6 m at d = 3.16: t moves ~1e-6.
  EXPECT_NEAR(pixelAt(img, 2).r, 127.5, 0.5);
  EXPECT_LE(pixelAt(img, 3).r, 1);
}

TEST(NormalsImage, MapsUnitVectorsAndBlanksInvalidPixels) {
  const std::vector<float> n = {0, 0, 1, -1, 0, 0, 0, 1, 0};
  const std::vector<uint8_t> valid = {1, 1, 0};
  const ImageRGBA8 img = normalsToImage(n, valid, 3, 1);
  EXPECT_EQ(pixelAt(img, 0), (Rgb8{128, 128, 255}));  // 0.5*255 = 127.5 rounds to 128
  EXPECT_EQ(pixelAt(img, 1), (Rgb8{0, 128, 128}));
  EXPECT_EQ(pixelAt(img, 2), (Rgb8{0, 0, 0}));
  EXPECT_EQ(pixelAt(normalsToImage(n, {}, 3, 1), 2), (Rgb8{128, 255, 128}));
}

TEST(ErrorMap, ViridisMatchesMatplotlibAndItsLuminanceRises) {
  // matplotlib viridis: #440154, #21918c, #fde725. A legend colour within 5/255 (2 %) is
  // indistinguishable at a glance; the polynomial fit is held to that.
  const auto near = [](Rgb8 a, Rgb8 b) {
    return std::abs(a.r - b.r) <= 5 && std::abs(a.g - b.g) <= 5 && std::abs(a.b - b.b) <= 5;
  };
  EXPECT_TRUE(near(viridisColor(0.0), {68, 1, 84}));
  EXPECT_TRUE(near(viridisColor(0.5), {33, 145, 140}));
  EXPECT_TRUE(near(viridisColor(1.0), {253, 231, 37}));
  // Luminance must rise along the map; checked at steps of 1/16 on the 8-bit output. Rounding a
  // channel to 8 bits moves its linear value by at most 0.5/255 * max d(linear)/d(encoded)
  // = 0.5/255 * 2.4/1.055 = 0.0045, so Y (weights sum to 1) by at most 0.0045 per colour, 0.009
  // per difference. Over 1/16 viridis's Y rises by at least 0.0105 > 0.009, so rounding cannot
  // flip the order; finer steps would test 8-bit rounding, not the map.
  double previous = -1;
  for (int i = 0; i <= 16; ++i) {
    const Rgb8 c = viridisColor(i / 16.0);
    const double y =
        0.2126 * srgbToLinear(c.r / 255.0) + 0.7152 * srgbToLinear(c.g / 255.0) + 0.0722 * srgbToLinear(c.b / 255.0);
    EXPECT_GT(y, previous) << i;
    previous = y;
  }
}

TEST(ErrorMap, ClampsAboveTheMaximumAndFlagsNaN) {
  const std::vector<float> e = {0.f, 2.f, 5.f, std::numeric_limits<float>::quiet_NaN()};
  const ImageRGBA8 img = errorMapToImage(e, 4, 1, 2.f);
  EXPECT_EQ(pixelAt(img, 0), viridisColor(0));
  EXPECT_EQ(pixelAt(img, 1), viridisColor(1));
  EXPECT_EQ(pixelAt(img, 2), viridisColor(1));
  EXPECT_EQ(pixelAt(img, 3), (Rgb8{255, 0, 255}));
}

}  // namespace
}  // namespace hb

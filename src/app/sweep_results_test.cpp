#include "app/sweep_results.h"

#include <unistd.h>
#include <filesystem>

#include <fstream>

#include <gtest/gtest.h>

namespace hb {
namespace {

namespace fs = std::filesystem;

// One field of each image, in order.
std::vector<std::string> each(const std::vector<ReportImage>& images, std::string ReportImage::*field) {
  std::vector<std::string> out;
  for (const ReportImage& image : images) out.push_back(image.*field);
  return out;
}
using nlohmann::json;

void touchImageFile(const fs::path& p) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << "x";
}

// A sweep's folder: results beside one folder per variant (slug of its name), and a page written
// elsewhere: each image's path is taken from the page's folder, colour first.
TEST(SweepResults, VariantImagesArePathsFromThePagesFolderColourFirst) {
  const fs::path root = fs::temp_directory_path() / ("hb-variant-images-" + std::to_string(::getpid()));
  fs::remove_all(root);
  const fs::path sweep = root / "out" / "sweep", pages = root / "pages";
  touchImageFile(sweep / "light-culling-aabb" / "rays.png");
  touchImageFile(sweep / "light-culling-aabb" / "ao.png");  // before "color" by name
  touchImageFile(sweep / "light-culling-aabb" / "color.png");
  touchImageFile(sweep / "light-culling-aabb" / "flip_error.png");
  touchImageFile(sweep / "light-culling-aabb" / "notes.txt");  // not an image
  fs::create_directories(sweep / "empty");
  fs::create_directories(pages);
  const json results = {{"runs", {{{"name", "light culling + AABB"}}, {{"name", "empty"}}, {{"name", "gone"}}}}};

  const auto images = variantImages(sweep.string(), pages.string(), results);
  ASSERT_EQ(images.size(), 1u);  // "empty" and "gone" have none
  const std::vector<ReportImage>& v = images.at("light culling + AABB");
  EXPECT_EQ(each(v, &ReportImage::label), (std::vector<std::string>{"color", "ao", "flip error", "rays"}));
  EXPECT_EQ(v.at(0).href, "../out/sweep/light-culling-aabb/color.png");
  for (const ReportImage& image : v) EXPECT_TRUE(fs::is_regular_file(pages / image.href)) << image.href;

  // The page beside the results: paths inside the folder.
  const auto beside = variantImages(sweep.string(), sweep.string(), results);
  EXPECT_EQ(beside.at("light culling + AABB")[0].href, "light-culling-aabb/color.png");
  fs::remove_all(root);
}

// Committed results keep WebP previews of the PNGs (scripts/previews.sh): a page shows the preview
// where there is one, the PNG where there is only that, and each image once.
TEST(SweepResults, VariantImagesShowThePreviewWhereThereIsOne) {
  const fs::path root = fs::temp_directory_path() / ("hb-variant-previews-" + std::to_string(::getpid()));
  fs::remove_all(root);
  touchImageFile(root / "v" / "color.png");
  touchImageFile(root / "v" / "color.webp");
  touchImageFile(root / "v" / "rays.webp");  // the preview alone, as in a clone
  touchImageFile(root / "v" / "depth.png");  // no preview yet
  const json results = {{"runs", {{{"name", "v"}}}}};

  const std::vector<ReportImage> v = variantImages(root.string(), root.string(), results).at("v");
  EXPECT_EQ(each(v, &ReportImage::href), (std::vector<std::string>{"v/color.webp", "v/depth.png", "v/rays.webp"}));
  EXPECT_EQ(each(v, &ReportImage::label), (std::vector<std::string>{"color", "depth", "rays"}));
  fs::remove_all(root);
}

}  // namespace
}  // namespace hb

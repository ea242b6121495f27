// The anti-aliasing table (aa_table.h) from hand-made results: each AA run against its own variant
// without AA, the paper's factors where Fig. 8 gives them, "—" where a figure is missing, and no
// table for results without anti-aliasing.
#include "report/aa_table.h"

#include <gtest/gtest.h>

namespace hb {
namespace {

using nlohmann::json;

json aaRun(const std::string& name, const std::string& primary, const std::string& aa, double frame, double prim,
           double samples) {
  json run = {{"name", name},
              {"status", "ok"},
              {"params", {{"primary", primary}, {"aa", aa}, {"tile_size", 8}}},
              {"frame_ms", {{"median", frame}}},
              {"accuracy", {{"image_error", 0.01}, {"image_error_flip", {{"reference", "64 samples a pixel"}}}}}};
  const char* pass = primary == "hardware" ? "depth_prepass" : "raster3d";
  run["passes"][pass] = {{"median", prim}};
  run["passes"]["shading"] = {{"median", 0.25}};
  if (samples > 0) run["passes"]["raster3d.samples"] = {{"median", samples}};
  if (primary != "hardware" && aa != "none")
    run["primary"]["aa"]["sample_coverage_check"] = {{"holes", 0}, {"double_covers", 0}};
  return run;
}

TEST(AaTable, EachRunIsComparedWithItsOwnVariantWithoutAntiAliasing) {
  json results = {{"runs", json::array()}};
  results["runs"].push_back(aaRun("binned none", "3dr-binned", "none", 2.0, 0.5, 0));
  results["runs"].push_back(aaRun("binned msaa16", "3dr-binned", "msaa16", 8.0, 6.0, 5.5));
  results["runs"].push_back(aaRun("binned csaa", "3dr-binned", "csaa-4-12", 3.0, 2.0, 1.5));
  results["runs"].push_back(aaRun("hw msaa8", "hardware", "msaa8", 5.0, 0.9, 0));  // no baseline of its own
  const std::string md = aaTableMarkdown(results);
  EXPECT_NE(
      md.find("| binned none | 3dr-binned | none | 2.000 | 1.00x | — | 0.500 | 1.00x | — | 0.250 | 0.01000 | — |"),
      std::string::npos)
      << md;
  EXPECT_NE(
      md.find("| binned msaa16 | 3dr-binned | msaa16 | 8.000 | 4.00x | 11x | 6.000 | 12.00x | 5.500 | 0.250 | 0.01000 "
              "| 0 / 0 |"),
      std::string::npos)
      << md;
  EXPECT_NE(md.find("| binned csaa | 3dr-binned | csaa-4-12 | 3.000 | 1.50x | 4.3x | 2.000 | 4.00x |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| hw msaa8 | hardware | msaa8 | 5.000 | — | — | 0.900 | — | — | 0.250 | 0.01000 | — |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("the reference (64 samples a pixel)"), std::string::npos) << md;
}

TEST(AaTable, NoTableWithoutAntiAliasing) {
  json results = {{"runs", json::array()}};
  results["runs"].push_back(aaRun("binned none", "3dr-binned", "none", 2.0, 0.5, 0));
  EXPECT_EQ(aaTableMarkdown(results), "");
  json old = {{"runs", {{{"name", "before aa existed"}, {"status", "ok"}, {"params", {{"primary", "3dr"}}}}}}};
  EXPECT_EQ(aaTableMarkdown(old), "");
}

}  // namespace
}  // namespace hb

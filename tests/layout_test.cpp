// The folders of src/ follow the frame's data flow (README "Layout"): a file includes only headers
// of its own folder or of folders lower in this order. The order is the one the code has, checked
// here on every include so that a move cannot quietly put a file in the wrong place.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#ifndef HYBRIDBENCH_SOURCE_DIR
#error "HYBRIDBENCH_SOURCE_DIR must name the source tree"
#endif

namespace fs = std::filesystem;

namespace {

// Lowest first, one rank a folder: a file's folder is the first component of its path under src/
// (effects/shadows/x.h is in effects/). plan/ (the effects schema, the registry and the frame plan)
// reads scenes (can an effect act on this one?); gltf/ sits above it: the glTF loader builds
// Scenes and checks their extras.effects against the effects schema. effects/ holds every effect's
// own folder (effects/<name>/: its passes, analysis, report and table) and builtin/, the list of
// them: above everything it uses and below the commands.
const std::vector<std::string> kOrder = {"base", "scene", "plan",     "gltf",   "config",  "reference",
                                         "gpu",  "frame", "analysis", "report", "effects", "app"};

int rankOf(const std::string& relPath) {  // "gpu/accel.h" -> rank of "gpu"; -1 if not in a folder
  const size_t slash = relPath.find('/');
  if (slash == std::string::npos) return -1;
  const auto it = std::find(kOrder.begin(), kOrder.end(), relPath.substr(0, slash));
  return it == kOrder.end() ? -1 : int(it - kOrder.begin());
}

}  // namespace

TEST(Layout, EveryFileOfSrcIsInAFolderOfTheFrameOrder) {
  const fs::path src = fs::path(HYBRIDBENCH_SOURCE_DIR) / "src";
  size_t files = 0;
  for (const auto& e : fs::recursive_directory_iterator(src)) {
    if (!e.is_regular_file()) continue;
    const std::string rel = fs::relative(e.path(), src).generic_string();
    EXPECT_GE(rankOf(rel), 0) << rel << " is not in any folder of the layout (tests/layout_test.cpp kOrder)";
    ++files;
  }
  EXPECT_GT(files, 50u);
}

TEST(Layout, AFolderIncludesOnlyItselfAndFoldersBelowIt) {
  const fs::path src = fs::path(HYBRIDBENCH_SOURCE_DIR) / "src";
  const std::regex include(R"re(^\s*#\s*include\s+"([^"]+)")re");
  size_t checked = 0;
  for (const auto& e : fs::recursive_directory_iterator(src)) {
    if (!e.is_regular_file()) continue;
    const std::string rel = fs::relative(e.path(), src).generic_string();
    const int own = rankOf(rel);
    std::ifstream in(e.path());
    std::string line;
    int lineNo = 0;
    while (std::getline(in, line)) {
      ++lineNo;
      std::smatch m;
      if (!std::regex_search(line, m, include)) continue;
      const std::string target = m[1];
      if (!fs::exists(src / target)) continue;  // shaders/shared/*.h, generated headers
      ++checked;
      const int theirs = rankOf(target);
      EXPECT_LE(theirs, own) << rel << ":" << lineNo << " includes " << target << ", which is above "
                             << kOrder[std::max(own, 0)] << "/ in the frame order";
    }
  }
  EXPECT_GT(checked, 100u);
}

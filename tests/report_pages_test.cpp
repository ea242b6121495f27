// The committed report pages (README.md and results/README.md link them) are what `hybridbench
// report` writes today from the committed results beside them, byte for byte: the page records no
// time of writing, so a difference means the page is stale. With HYBRIDBENCH_WRITE_PAGES=1 the test
// writes every page instead (after a change to the page: regenerate them all, look, commit):
//   HYBRIDBENCH_WRITE_PAGES=1 build/hybridbench_tests --gtest_filter=HtmlReport.CommittedPages*
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "tool_process.h"

namespace {

using namespace hb::testing;

struct CommittedPage {
  const char* page;
  const char* args;  // from the repository root, without --out
};

// The H100 thesis sweep (its images were not kept), the sweep at 608c60f against it, and the H200
// thesis sweep merged from three parts against the same sweep whole.
constexpr CommittedPage kCommittedPages[] = {
    {"results/h100/thesis/report.html", "report results/h100/thesis/results.json.gz"},
    {"results/h100/thesis-608c60f/report.html",
     "report results/h100/thesis-608c60f/results.json.gz --compare results/h100/thesis/results.json.gz"},
    // The H200 thesis sweep as three parts merged (#35), against the same sweep whole.
    {"results/h200/fleet-35/thesis-merged/report-vs-whole.html",
     "report results/h200/fleet-35/thesis-merged/results.json.gz --compare "
     "results/h200/fleet-35/thesis-whole/results.json.gz"},
    // Its folders' own pages (what sweep and merge write; no images were kept).
    {"results/h200/fleet-35/thesis-whole/report.html", "report results/h200/fleet-35/thesis-whole/results.json.gz"},
    {"results/h200/fleet-35/thesis-merged/report.html", "report results/h200/fleet-35/thesis-merged/results.json.gz"},
    {"results/h200/fleet-35/shard-0/report.html", "report results/h200/fleet-35/shard-0/results.json.gz"},
    {"results/h200/fleet-35/shard-1/report.html", "report results/h200/fleet-35/shard-1/results.json.gz"},
    {"results/h200/fleet-35/shard-2/report.html", "report results/h200/fleet-35/shard-2/results.json.gz"},
    // The same on three GPUs of one host at once, and the CI config's page with its images (#35).
    {"results/h200/fleet-35-x4/thesis-merged/report-vs-whole.html",
     "report results/h200/fleet-35-x4/thesis-merged/results.json.gz --compare "
     "results/h200/fleet-35-x4/thesis-whole/results.json.gz"},
    {"results/h200/fleet-35-x4/ci-images/report.html", "report results/h200/fleet-35-x4/ci-images/results.json.gz"},
};

TEST(HtmlReport, CommittedPagesAreWhatReportWritesFromTheirResults) {
  for (const CommittedPage& p : kCommittedPages) {
    // Written beside the committed page (then removed): a page names its images by their path from
    // its own folder, so a page written elsewhere would name them otherwise.
    const fs::path committedPath = fs::path(HYBRIDBENCH_SOURCE_DIR) / p.page;
    const fs::path fresh = committedPath.parent_path() / (".report-pages-test-" + std::to_string(::getpid()) + ".html");
    const std::string regenerate = std::string("hybridbench ") + p.args + " --out " + p.page;
    // From the repository root, as the page names its results by the path given.
    const std::string cmd = std::string("cd '") + HYBRIDBENCH_SOURCE_DIR + "' && '" + HYBRIDBENCH_BINARY + "' " +
                            p.args + " --out '" + fresh.string() + "' > /dev/null";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    const std::string written = hb::testing::readFile(fresh);
    fs::remove(fresh);
    if (const char* write = std::getenv("HYBRIDBENCH_WRITE_PAGES"); write && std::string(write) == "1") {
      hb::testing::writeFile(committedPath, written);
      std::printf("wrote %s\n", p.page);
      continue;
    }
    const std::string committed = hb::testing::readFile(committedPath);
    EXPECT_FALSE(committed.empty()) << p.page << " is missing; write it with: " << regenerate;
    EXPECT_TRUE(committed == written)
        << p.page
        << " differs from what report writes now; regenerate it from the repository root with: " << regenerate;
  }
}

}  // namespace

#include "report/html_report.h"

#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "report/xml_test_util.h"

#include "base/errors.h"
#include "report/results_fixture_test_util.h"
#include "report/stats.h"

namespace hb {
namespace {

using nlohmann::json;

json reportFixture() { return testing::thesisResultsFixture(); }

std::string reportPage(const json& results, std::map<std::string, std::vector<ReportImage>> images = {},
                       const json* base = nullptr) {
  HtmlReportInput in;
  in.results = &results;
  in.source = "results/x/results.json";
  in.images = std::move(images);
  in.base = base;
  in.baseSource = "results/base/results.json";
  return htmlReport(in);
}

size_t htmlOccurrences(const std::string& s, const std::string& what) {
  size_t n = 0;
  for (size_t at = s.find(what); at != std::string::npos; at = s.find(what, at + what.size())) ++n;
  return n;
}

// The text between the first `open` and the `close` after it.
std::string textBetween(const std::string& s, const std::string& open, const std::string& close) {
  const size_t a = s.find(open);
  if (a == std::string::npos) return "";
  const size_t b = s.find(close, a);
  return s.substr(a, b == std::string::npos ? std::string::npos : b - a);
}

TEST(HtmlReport, EveryRunHasItsVariantBlockItsParetoPointAndItsFrameBar) {
  const json r = reportFixture();
  const std::string html = reportPage(r);
  const std::string pareto = textBetween(html, "<figure id=\"pareto\">", "</figure>");
  const std::string frameBars = textBetween(html, "<svg class=\"bars\" data-pass=\"frame\"", "</svg>");
  ASSERT_FALSE(pareto.empty());
  ASSERT_FALSE(frameBars.empty());
  EXPECT_EQ(htmlOccurrences(pareto, "<circle data-variant="), r["runs"].size());
  EXPECT_EQ(htmlOccurrences(html, "<details class=\"variant\" id=\"variant-"), r["runs"].size());
  for (const json& run : r["runs"]) {
    const std::string name = run["name"];
    EXPECT_NE(html.find("data-variant=\"" + name + "\"><summary><b>" + name + "</b>"), std::string::npos) << name;
    EXPECT_NE(pareto.find("<circle data-variant=\"" + name + "\""), std::string::npos) << name;
    EXPECT_NE(frameBars.find("<g data-variant=\"" + name + "\""), std::string::npos) << name;
  }
  // One bar chart per timed pass of the runs, frame first.
  for (const char* pass : {"frame", "depth_prepass", "light_culling", "shadows", "shading"})
    EXPECT_EQ(htmlOccurrences(html, std::string("<svg class=\"bars\" data-pass=\"") + pass + "\""), 1u) << pass;
  EXPECT_EQ(testing::xmlProblem(passBarsSvg(r)), "");
  // The study's tables, rendered from their Markdown into HTML tables.
  EXPECT_NE(html.find("<table>\n<thead>"), std::string::npos);
  EXPECT_EQ(html.find("|---|"), std::string::npos);
}

TEST(HtmlReport, NamesAndContextAreEscaped) {
  json r = reportFixture();
  const std::string evil = "<script>alert(\"x\")</script> & 'co'";
  r["runs"][1]["name"] = evil;
  r["context"]["device"]["name"] = "GPU <b>";
  const std::string html = reportPage(r);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("GPU <b>"), std::string::npos);
  EXPECT_NE(html.find("&lt;script&gt;alert(&quot;x&quot;)&lt;/script&gt; &amp; &apos;co&apos;"), std::string::npos);
  EXPECT_NE(html.find("GPU &lt;b&gt;"), std::string::npos);
  // In the Markdown tables too (here compare's), a name is shown whole, as text: not dropped as raw
  // HTML, its "&" not read as an entity.
  json base = r;
  base["runs"][1]["name"] = evil;
  const std::string compared = reportPage(r, {}, &base);
  EXPECT_EQ(compared.find("<script"), std::string::npos);
  EXPECT_EQ(htmlOccurrences(compared, "<td>&lt;script&gt;alert(&quot;x&quot;)&lt;/script&gt; &amp; 'co'</td>"),
            r["runs"][1]["passes"].size() + 1);  // its frame and each pass
}

TEST(HtmlReport, FailedRunsAreListedAtTheTopAndHaveNoPoint) {
  json r = reportFixture();
  json& failed = r["runs"][2];
  const std::string name = failed["name"];
  failed = {{"name", name}, {"status", "timeout"}, {"last_step", "warm-up"}, {"seconds", 601}, {"timeout_s", 600}};
  const std::string html = reportPage(r);
  const std::string section = textBetween(html, "<section id=\"failed\"", "</section>");
  ASSERT_FALSE(section.empty());
  EXPECT_LT(html.find("<section id=\"failed\""), html.find("<section id=\"context\""));
  EXPECT_NE(section.find("<b>" + name + "</b>: timeout — last_step: warm-up; seconds: 601; timeout_s: 600"),
            std::string::npos)
      << section;
  const std::string pareto = textBetween(html, "<figure id=\"pareto\">", "</figure>");
  EXPECT_EQ(pareto.find("data-variant=\"" + name + "\""), std::string::npos);
  EXPECT_EQ(htmlOccurrences(pareto, "<circle data-variant="), r["runs"].size() - 1);
  EXPECT_NE(html.find("no images: the variant did not finish"), std::string::npos);
  // No failed run, no section.
  EXPECT_EQ(reportPage(reportFixture()).find("<section id=\"failed\""), std::string::npos);
}

TEST(HtmlReport, AVariantThatThrottledIsAWarningAndTheContextSaysWhereItsClocksWereRead) {
  json r = reportFixture();
  const std::string name = r["runs"][1]["name"];
  r["runs"][1]["telemetry"] = {{"available", true},
                               {"throttled", true},
                               {"throttle_reasons", {"sw_power_cap"}},
                               {"warning", "the GPU's clocks were held down while it was measured"}};
  r["runs"][2]["telemetry"] = {{"available", true}, {"throttled", false}, {"throttle_reasons", json::array()}};
  r["context"]["device"]["telemetry"] = {
      {"available", true}, {"max_sm_clock_mhz", 1980}, {"max_memory_clock_mhz", 3201}};
  const std::string html = reportPage(r);
  const std::string warnings = textBetween(html, "<section id=\"warnings\"", "</section>");
  EXPECT_NE(
      warnings.find("<li>" + name + ": telemetry: the GPU&apos;s clocks were held down while it was measured</li>"),
      std::string::npos)
      << warnings;
  EXPECT_EQ(htmlOccurrences(warnings, ": telemetry: "), 1u);  // the run that did not throttle has none
  EXPECT_NE(html.find("<th>telemetry</th><td>NVML, max SM clock 1980 MHz, max memory clock 3201 MHz</td>"),
            std::string::npos);
  r["context"]["device"]["telemetry"] = {{"available", false}, {"reason", "no libnvidia-ml.so.1"}};
  EXPECT_NE(reportPage(r).find("<th>telemetry</th><td>none: no libnvidia-ml.so.1</td>"), std::string::npos);
  // Results written before telemetry: no row, no warning.
  const std::string before = reportPage(reportFixture());
  EXPECT_EQ(before.find("<th>telemetry</th>"), std::string::npos);
  EXPECT_EQ(before.find(": telemetry: "), std::string::npos);
}

TEST(HtmlReport, ReferencesNothingOutsideTheReportsFolderAndNoScript) {
  const json r = reportFixture();
  std::map<std::string, std::vector<ReportImage>> images;
  images[r["runs"][0]["name"]] = {{"lc/color.png", "color"}, {"lc/flip_error.png", "flip error"}};
  const std::string html = reportPage(r, images);
  // Every src and href: an anchor in the page or a relative path that stays inside the folder.
  const std::regex ref("(src|href)=\"([^\"]*)\"");
  size_t refs = 0;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), ref); it != std::sregex_iterator(); ++it, ++refs) {
    const std::string target = (*it)[2];
    EXPECT_FALSE(std::regex_search(target, std::regex("^[A-Za-z][A-Za-z0-9+.-]*:"))) << target;  // no scheme
    EXPECT_NE(target.front(), '/') << target;
    EXPECT_EQ(target.find(".."), std::string::npos) << target;
  }
  EXPECT_EQ(refs, 8u /* nav */ - 1 /* no comparison */ + 4 /* two images, each src and href */);
  EXPECT_NE(html.find("<img src=\"lc/color.png\" alt=\"color\""), std::string::npos);
  EXPECT_NE(html.find("<img src=\"lc/flip_error.png\" alt=\"flip error\""), std::string::npos);
  for (const char* resource : {"<script", "<link", "url(", "@import", "<iframe", "<object"})
    EXPECT_EQ(html.find(resource), std::string::npos) << resource;
  // The runs without images say why.
  EXPECT_EQ(htmlOccurrences(html, "no images beside the results"), r["runs"].size() - 1);
}

TEST(HtmlReport, IsTheSameBytesEveryTime) {
  const json r = reportFixture();
  EXPECT_EQ(reportPage(r), reportPage(r));
}

// The whisker is the 5th to 95th percentile of the samples, type 7: with samples 1..21 ms
// h = (n - 1) q = 20 * 0.05 = 1 and 20 * 0.95 = 19, exactly samples[1] = 2 and samples[19] = 20.
TEST(HtmlReport, WhiskersSpanTheFifthToNinetyFifthPercentile) {
  json r = reportFixture();
  std::vector<double> samples;
  for (int i = 21; i >= 1; --i) samples.push_back(i);  // unsorted, as frames come
  r["runs"][0]["frame_ms"] = toJson(summarize(samples), samples);
  const std::string bars = passBarsSvg(r);
  EXPECT_NE(bars.find("<title>5th-95th percentile 2-20 ms</title>"), std::string::npos);
  EXPECT_NE(bars.find(": median 11 ms</title>"), std::string::npos);
}

TEST(HtmlReport, ComparisonHasTheTableAndAPointWithItsIntervalPerRow) {
  const json a = reportFixture();
  json b = a;
  // B's shadows twice as slow in one run: that row is "slower", the rest "same".
  json& shadows = b["runs"][0]["passes"]["shadows"];
  std::vector<double> doubled;
  for (const json& v : shadows["samples"]) doubled.push_back(2 * v.get<double>());
  shadows = toJson(summarize(doubled), doubled);
  const std::string html = reportPage(b, {}, &a);
  const std::string section = textBetween(html, "<section id=\"compare\"", "</section>");
  ASSERT_FALSE(section.empty());
  CompareReport report = compareResults(a, b, CompareOptions{});
  const std::string plot = ratioPlotSvg(report);
  EXPECT_EQ(testing::xmlProblem(plot), "");
  EXPECT_NE(section.find(plot), std::string::npos);
  EXPECT_EQ(htmlOccurrences(plot, "<circle "), report.rows.size());
  for (const CompareRow& row : report.rows)
    EXPECT_NE(plot.find("<g data-variant=\"" + row.variant + "\" data-pass=\"" + row.pass + "\">"), std::string::npos);
  const std::string slowerRow =
      textBetween(plot, "<g data-variant=\"" + std::string(a["runs"][0]["name"]) + "\" data-pass=\"shadows\">", "</g>");
  EXPECT_NE(slowerRow.find("fill=\"#d62728\""), std::string::npos) << slowerRow;  // slower: red
  EXPECT_NE(slowerRow.find(">slower</text>"), std::string::npos);
  // compare's table, as HTML: the row's verdict (the default gate counts frames only).
  EXPECT_NE(section.find("<td>shadows</td>"), std::string::npos);
  EXPECT_EQ(htmlOccurrences(section, "<td>slower</td>"), 1u);
  EXPECT_NE(html.find("<a href=\"#compare\">"), std::string::npos);
}

TEST(HtmlReport, RefusesWhatIsNotAResultsFile) {
  const json render = {{"passes_run", json::array()}};
  EXPECT_THROW(reportPage(render), InputError);
  const json a = reportFixture();
  json other = a;
  other["context"]["scene"]["sha256"] = "another";
  EXPECT_THROW(reportPage(other, {}, &a), InputError);  // compare's rule: another scene
}

}  // namespace
}  // namespace hb

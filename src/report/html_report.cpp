#include "report/html_report.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <mutex>
#include <set>
#include <vector>

#include <cmark-gfm-core-extensions.h>
#include <cmark-gfm.h>

#include "base/errors.h"
#include "base/text_format.h"
#include "report/accuracy_report.h"
#include "report/all_tables.h"
#include "report/report_summary.h"
#include "report/results_identity.h"
#include "report/results_json.h"
#include "report/roofline.h"
#include "report/stats.h"

namespace hb {

using nlohmann::json;

namespace {

// Text for HTML: the XML entities are HTML's too.
std::string htmlText(const std::string& s) { return escapeXml(s); }

std::string reportText(const json& j, const char* key) {
  const json& v = results::at(j, key);
  return v.is_string() ? v.get<std::string>() : v.is_null() ? std::string() : v.dump();
}

// GitHub-flavoured Markdown (the tables' and compare's own format) to HTML through Debian's
// cmark-gfm with its table extension. Raw HTML in the text is not passed through (cmark's safe
// default), so a variant name cannot inject markup. hardBreaks: each line of a paragraph stays a
// line (compare's header lines).
// The Markdown the report writers produce holds names as they are (a variant may be called
// "16x16 <tiles>"): cmark's safe mode would drop "<tiles>" as raw HTML and decode "&amp;", so
// outside code spans '<' and '&' are backslash-escaped into text (CommonMark 2.4).
std::string markdownTextAsText(const std::string& markdown) {
  std::string out;
  out.reserve(markdown.size());
  bool code = false;
  for (char c : markdown) {
    if (c == '`') code = !code;
    if (c == '\n') code = false;  // the writers' code spans never span lines
    if (!code && (c == '<' || c == '&')) out += '\\';
    out += c;
  }
  return out;
}

std::string markdownToHtml(const std::string& text, bool hardBreaks) {
  const std::string markdown = markdownTextAsText(text);
  static std::once_flag registered;  // the registry is global and not thread-safe
  std::call_once(registered, [] { cmark_gfm_core_extensions_ensure_registered(); });
  const int options = CMARK_OPT_DEFAULT | (hardBreaks ? CMARK_OPT_HARDBREAKS : 0);
  cmark_parser* parser = cmark_parser_new(options);
  if (cmark_syntax_extension* table = cmark_find_syntax_extension("table"))
    cmark_parser_attach_syntax_extension(parser, table);
  cmark_parser_feed(parser, markdown.data(), markdown.size());
  cmark_node* document = cmark_parser_finish(parser);
  char* rendered = cmark_render_html(document, options, cmark_parser_get_syntax_extensions(parser));
  std::string out = rendered ? rendered : "";
  std::free(rendered);  // cmark's default allocator is malloc's
  cmark_node_free(document);
  cmark_parser_free(parser);
  return out;
}

// An SVG document (accuracy_report.h, roofline.h) as an element of the page: without its XML
// declaration, which HTML does not allow there.
std::string svgElement(std::string svg) {
  if (svg.rfind("<?xml", 0) == 0) svg.erase(0, svg.find('\n') + 1);
  return svg;
}

// A tick step of 1, 2 or 5 times a power of ten giving at most about `ticks` intervals over span.
double reportTickStep(double span, int ticks) {
  if (!(span > 0)) return 1;
  const double raw = span / ticks, decade = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0})
    if (m * decade >= raw) return m * decade;
  return 10 * decade;
}

// Ticks of a log axis over [lo, hi] (lo > 0) whose labels do not overlap: 1 first (the line of no
// change), then the powers of ten, then 2 and 5 times them, then the steps of a linear axis over the
// span (1, 2 or 5 times a power of ten), each kept only where its label (11 px sans-serif, about
// 6.1 px a character) clears those already kept by 6 px. px maps a ratio to its x.
template <typename ToPx>
std::vector<double> logAxisTicks(double lo, double hi, const ToPx& px) {
  std::vector<double> candidates;
  if (lo <= 1 && 1 <= hi) candidates.push_back(1);
  const double d0 = std::floor(std::log10(lo)), d1 = std::ceil(std::log10(hi));
  for (double d = d0; d <= d1; d += 1) candidates.push_back(std::pow(10.0, d));
  for (double d = d0; d <= d1; d += 1)
    for (double m : {2.0, 5.0}) candidates.push_back(m * std::pow(10.0, d));
  const double step = reportTickStep(hi - lo, 6);
  for (double v = std::ceil(lo / step) * step; v <= hi; v += step) candidates.push_back(std::round(v / step) * step);
  auto halfWidth = [](double v) { return 0.5 * 6.1 * double(format("%g", v).size()); };
  std::vector<double> kept;
  for (double v : candidates) {
    if (!(v >= lo && v <= hi)) continue;
    bool clear = true;
    for (double k : kept) clear = clear && std::fabs(px(v) - px(k)) >= halfWidth(v) + halfWidth(k) + 6;
    if (clear) kept.push_back(v);
  }
  std::sort(kept.begin(), kept.end());
  return kept;
}

std::vector<double> reportSamples(const json& stats) {
  std::vector<double> out;
  for (const json& v : results::at(stats, "samples"))
    if (v.is_number()) out.push_back(v.get<double>());
  return out;
}

// The passes of the ok runs in frame order: "frame" first, then each run's pass_order (or its
// passes' keys), a pass the first time a run names it.
std::vector<std::string> reportPassOrder(const json& results) {
  std::vector<std::string> order{"frame"};
  std::set<std::string> seen{"frame"};
  for (const json& run : results["runs"]) {
    if (reportText(run, "status") != "ok") continue;
    std::vector<std::string> names;
    if (results::at(run, "pass_order").is_array()) {
      for (const json& p : run["pass_order"])
        if (p.is_string()) names.push_back(p.get<std::string>());
    } else if (results::at(run, "passes").is_object()) {
      for (const auto& [pass, stats] : run["passes"].items()) names.push_back(pass);
    }
    for (const std::string& p : names)
      if (seen.insert(p).second) order.push_back(p);
  }
  return order;
}

const json& reportStatsOf(const json& run, const std::string& pass) {
  return pass == "frame" ? results::at(run, "frame_ms") : results::at(results::at(run, "passes"), pass.c_str());
}

// Figure geometry shared by the bar and ratio plots: a column of labels (variant names), then the
// plot kPlotWidth wide, then a value or verdict.
constexpr double kPlotWidth = 400, kValueWidth = 90, kRowHeight = 18, kTopMargin = 30;

// Where the plot starts: right of the longest label. 11 px sans-serif averages about 0.55 em
// (6.1 px) a character; 6.4 keeps a long name of wide letters inside the figure.
double labelColumnWidth(const std::vector<std::string>& labels) {
  size_t longest = 0;
  for (const std::string& l : labels) longest = std::max(longest, l.size());
  return std::clamp(12 + 6.4 * double(longest), 120.0, 520.0);
}

std::string onePassBars(const json& results, const std::string& pass, double plotLeft) {
  const double plotRight = plotLeft + kPlotWidth, figureWidth = plotRight + kValueWidth;
  struct Bar {
    std::string name;
    double median, low, high;  // low/high: p5, p95; NaN without samples
  };
  std::vector<Bar> bars;
  for (const json& run : results["runs"]) {
    if (reportText(run, "status") != "ok") continue;
    const json& stats = reportStatsOf(run, pass);
    const double median = results::medianOf(stats);
    if (!std::isfinite(median)) continue;
    std::vector<double> s = reportSamples(stats);
    std::sort(s.begin(), s.end());
    const double nan = std::numeric_limits<double>::quiet_NaN();
    bars.push_back({reportText(run, "name"), median, s.empty() ? nan : quantileSorted(s, 0.05),
                    s.empty() ? nan : quantileSorted(s, 0.95)});
  }
  if (bars.empty()) return "";
  double top = 0;
  for (const Bar& b : bars) top = std::max({top, b.median, std::isfinite(b.high) ? b.high : 0.0});
  const double step = reportTickStep(top, 5), axisMax = top > 0 ? std::ceil(top / step) * step : 1;
  const double height = kTopMargin + kRowHeight * double(bars.size()) + 30;
  auto px = [&](double ms) { return plotLeft + ms / axisMax * (plotRight - plotLeft); };
  std::string s = format(
      "<svg class=\"bars\" data-pass=\"%s\" width=\"%.0f\" height=\"%.0f\" viewBox=\"0 0 %.0f %.0f\" "
      "font-family=\"sans-serif\" font-size=\"11\" role=\"img\">\n",
      htmlText(pass).c_str(), figureWidth, height, figureWidth, height);
  s += "<text x=\"4\" y=\"16\" font-size=\"13\" font-weight=\"bold\">" + htmlText(pass) + " (ms)</text>\n";
  const double plotBottom = kTopMargin + kRowHeight * double(bars.size());
  for (double v = 0; v <= axisMax + 0.5 * step; v += step) {
    s += format("<line x1=\"%.1f\" y1=\"%.0f\" x2=\"%.1f\" y2=\"%.0f\" stroke=\"#ddd\"/>", px(v), kTopMargin - 4, px(v),
                plotBottom);
    s += format("<text x=\"%.1f\" y=\"%.0f\" text-anchor=\"middle\">%g</text>\n", px(v), plotBottom + 14, v);
  }
  for (size_t i = 0; i < bars.size(); ++i) {
    const Bar& b = bars[i];
    const double y = kTopMargin + kRowHeight * double(i);
    s += format("<g data-variant=\"%s\"><text x=\"%.0f\" y=\"%.1f\" text-anchor=\"end\">", htmlText(b.name).c_str(),
                plotLeft - 6, y + 12) +
         htmlText(b.name) + "</text>";
    s += format("<rect x=\"%.0f\" y=\"%.1f\" width=\"%.1f\" height=\"%.0f\" fill=\"#6a9fd4\"><title>", plotLeft, y + 3,
                px(b.median) - plotLeft, kRowHeight - 6) +
         htmlText(b.name + format(": median %.4g ms", b.median)) + "</title></rect>";
    double labelX = px(b.median) + 4;
    if (std::isfinite(b.low)) {
      const double ym = y + kRowHeight / 2;
      s += format(
               "<path d=\"M %.1f %.1f H %.1f M %.1f %.1f V %.1f M %.1f %.1f V %.1f\" stroke=\"#222\" "
               "stroke-width=\"1.2\" fill=\"none\"><title>",
               px(b.low), ym, px(b.high), px(b.low), ym - 4, ym + 4, px(b.high), ym - 4, ym + 4) +
           htmlText(format("5th-95th percentile %.4g-%.4g ms", b.low, b.high)) + "</title></path>";
      labelX = std::max(labelX, px(b.high) + 4);
    }
    s += format("<text x=\"%.1f\" y=\"%.1f\" fill=\"#444\">%.3f</text></g>\n", labelX, y + 12, b.median);
  }
  return s + "</svg>\n";
}

// Failed runs: status other than "ok", with what the results say about why.
std::string failedSection(const json& results) {
  std::string items;
  for (const json& run : results["runs"]) {
    const std::string status = reportText(run, "status");
    if (status == "ok") continue;
    std::string why;
    for (const char* key : {"error", "last_step", "seconds", "timeout_s", "process"})
      if (!results::at(run, key).is_null())
        why += std::string(why.empty() ? "" : "; ") + key + ": " + reportText(run, key);
    items += "<li><b>" + htmlText(reportText(run, "name")) +
             "</b>: " + htmlText(status.empty() ? "no status" : status) + (why.empty() ? "" : " — " + htmlText(why)) +
             "</li>\n";
  }
  if (items.empty()) return "";
  return "<section id=\"failed\" class=\"alert\"><h2>Failed variants</h2>\n<ul>\n" + items + "</ul></section>\n";
}

// What the results say their figures cannot be used for, and what the sweep noted.
std::vector<std::string> warningsOf(const json& results) {
  std::vector<std::string> out;
  for (const std::string& c : results::timingCaveats(results)) out.push_back("timing: " + c);
  const json& context = results::at(results, "context");
  for (const json& n : results::at(results::at(context, "config"), "notes"))
    if (n.is_string()) out.push_back("config: " + n.get<std::string>());
  for (const json& w : results::at(results::at(results::at(context, "device"), "peaks"), "warnings"))
    if (w.is_string()) out.push_back("device peaks: " + w.get<std::string>());
  if (const json& w = results::at(results::at(results::at(context, "device"), "warm_up"), "warning"); w.is_string())
    out.push_back("device: " + w.get<std::string>());
  for (const json& run : results["runs"])
    if (results::at(run, "analysis_not_run").is_string())
      out.push_back(reportText(run, "name") + ": analysis not run: " + run["analysis_not_run"].get<std::string>());
  // A variant whose clocks throttled while its frames were measured (gpu/telemetry.h).
  for (const json& run : results["runs"])
    if (const std::string w = results::throttleWarningOf(run); !w.empty())
      out.push_back(reportText(run, "name") + ": telemetry: " + w);
  return out;
}

// Where the clocks around each variant's frames were read (gpu/telemetry.h), or why none were.
std::string telemetryText(const json& telemetry) {
  if (results::at(telemetry, "available") != true) return "none: " + reportText(telemetry, "reason");
  std::string s = "NVML";
  if (const std::string sm = reportText(telemetry, "max_sm_clock_mhz"); !sm.empty())
    s += ", max SM clock " + sm + " MHz";
  if (const std::string memory = reportText(telemetry, "max_memory_clock_mhz"); !memory.empty())
    s += ", max memory clock " + memory + " MHz";
  return s;
}

std::string contextSection(const json& results, const std::string& source) {
  const json& c = results::at(results, "context");
  const json &device = results::at(c, "device"), &tool = results::at(c, "tool"), &host = results::at(c, "host"),
             &scene = results::at(c, "scene"), &config = results::at(c, "config"), &frames = results::at(c, "frames");
  std::string rows;
  auto row = [&](const std::string& key, const std::string& value) {
    if (!value.empty()) rows += "<tr><th>" + htmlText(key) + "</th><td>" + htmlText(value) + "</td></tr>\n";
  };
  auto joined = [](std::initializer_list<std::string> parts) {
    std::string s;
    for (const std::string& p : parts)
      if (!p.empty()) s += (s.empty() ? "" : ", ") + p;
    return s;
  };
  row("results", source);
  row("sweep", joined({reportText(config, "name"), reportText(config, "description")}));
  row("device", joined({reportText(device, "name"), reportText(device, "type"), reportText(device, "vendor")}));
  row("driver",
      joined({reportText(device, "driver"),
              reportText(device, "api_version").empty() ? "" : "Vulkan " + reportText(device, "api_version")}));
  row("ray tracing", results::tracedBy(results));  // what traced (backend_choice), not what the device offers
  row("revision", joined({reportText(tool, "name"), reportText(tool, "version"), reportText(tool, "git")}));
  row("host", joined({reportText(host, "hostname"), reportText(host, "os"), reportText(host, "cpu"),
                      reportText(host, "cores").empty() ? "" : reportText(host, "cores") + " cores"}));
  row("date", reportText(host, "date"));
  row("scene", joined({reportText(scene, "name"),
                       reportText(scene, "triangles").empty() ? "" : reportText(scene, "triangles") + " triangles",
                       reportText(scene, "lights").empty() ? "" : reportText(scene, "lights") + " lights",
                       reportText(scene, "sha256").empty() ? "" : "sha256 " + reportText(scene, "sha256")}));
  std::string paths;  // where the config, scene and environment lay (results_identity.h inputPaths)
  const json inputs = results::inputPaths(c);
  for (auto it = inputs.begin(); it != inputs.end(); ++it)
    paths += (paths.empty() ? "" : ", ") + it.key() + " " + it.value().get<std::string>();
  row("inputs", paths);
  const json& res = results::at(c, "resolution");
  if (res.is_array() && res.size() == 2) row("resolution", res[0].dump() + " x " + res[1].dump());
  if (frames.is_object())
    row("frames", joined({reportText(frames, "warmup") + " warm-up", reportText(frames, "measured") + " measured"}));
  row("timing", reportText(c, "timing_source"));
  if (const json& t = results::at(device, "telemetry"); t.is_object()) row("telemetry", telemetryText(t));
  std::string out = "<section id=\"context\"><h2>Context</h2>\n<table class=\"kv\">\n" + rows + "</table>\n";
  if (!config.is_null())
    out += "<details><summary>the full config</summary><pre>" + htmlText(config.dump(2)) + "</pre></details>\n";
  return out + "</section>\n";
}

// A variant's parameters that differ from the config's defaults ("tile_size=16, backend=rayquery").
std::string paramsLine(const json& results, const json& run) {
  const json& defaults = results::at(results::at(results::at(results, "context"), "config"), "defaults");
  std::string s;
  const json& params = results::at(run, "params");
  if (!params.is_object()) return s;
  for (const auto& [key, value] : params.items()) {
    if (defaults.is_object() && defaults.contains(key) && defaults[key] == value) continue;
    s += (s.empty() ? "" : ", ") + key + "=" + (value.is_string() ? value.get<std::string>() : value.dump());
  }
  return s;
}

std::string variantsSection(const HtmlReportInput& in) {
  const json& results = *in.results;
  std::string out =
      "<section id=\"variants\"><h2>Variants</h2>\n<p>Each variant's images, side by side: open a variant to see "
      "them; click an image for its full size.</p>\n";
  if (in.images.empty()) out += "<p class=\"note\">" + htmlText(in.imagesMissing) + ".</p>\n";
  size_t index = 0;
  for (const json& run : results["runs"]) {
    ++index;
    const std::string name = reportText(run, "name"), status = reportText(run, "status");
    const auto found = in.images.find(name);
    const size_t count = found == in.images.end() ? 0 : found->second.size();
    const double frame = results::medianOf(results::at(run, "frame_ms"));
    out += format("<details class=\"variant\" id=\"variant-%zu\" data-variant=\"", index) + htmlText(name) +
           "\"><summary><b>" + htmlText(name) + "</b> — " +
           (status == "ok" ? std::string("ok") : "<span class=\"bad\">" + htmlText(status) + "</span>") +
           (std::isfinite(frame) ? format(", frame %.3f ms (median)", frame) : std::string()) + ", " +
           htmlText(countOf(count, "image")) + "</summary>\n";
    const std::string params = paramsLine(results, run);
    if (!params.empty()) out += "<p class=\"params\">" + htmlText(params) + "</p>\n";
    if (count == 0) {
      out += "<p class=\"note\">" +
             htmlText(status == "ok" ? in.imagesMissing : "no images: the variant did not finish") + "</p>\n";
    } else {
      out += "<div class=\"images\">\n";
      for (const ReportImage& image : found->second)
        out += "<figure><a href=\"" + htmlText(image.href) + "\"><img src=\"" + htmlText(image.href) + "\" alt=\"" +
               htmlText(image.label) + "\" loading=\"lazy\"></a><figcaption>" + htmlText(image.label) +
               "</figcaption></figure>\n";
      out += "</div>\n";
    }
    out += "</details>\n";
  }
  return out + "</section>\n";
}

bool hasRoofline(const json& results) {
  for (const json& run : results["runs"])
    if (results::at(run, "roofline").is_object() && !run["roofline"].empty()) return true;
  return false;
}

constexpr const char* kStyle = R"(<style>
body { font-family: sans-serif; margin: 1.5em auto; max-width: 1200px; padding: 0 1em; color: #222; }
h1 { font-size: 1.5em; } h2 { border-bottom: 1px solid #ccc; margin-top: 1.6em; }
nav a { margin-right: 1em; }
table { border-collapse: collapse; margin: 0.5em 0; font-size: 0.9em; }
th, td { border: 1px solid #ccc; padding: 2px 6px; text-align: left; vertical-align: top; }
td[align="right"], th[align="right"] { text-align: right; }
table.kv th { background: #f4f4f4; white-space: nowrap; }
.alert { background: #fff0f0; border: 2px solid #d62728; padding: 0.2em 1em; }
.warn { background: #fffbe6; border: 2px solid #e0a800; padding: 0.2em 1em; }
.alert h2, .warn h2 { border: none; }
.bad { color: #d62728; font-weight: bold; }
.note, .legend { color: #555; font-style: italic; }
svg { max-width: 100%; height: auto; display: block; margin: 0.5em 0; }
details.variant { border: 1px solid #ccc; margin: 0.3em 0; padding: 0.3em 0.6em; }
details.variant summary { cursor: pointer; }
.images { display: flex; flex-wrap: wrap; gap: 8px; }
.images figure { margin: 0; width: 260px; }
.images img { width: 260px; height: auto; image-rendering: pixelated; border: 1px solid #ccc; }
.images figcaption { font-size: 0.8em; text-align: center; }
pre { background: #f7f7f7; padding: 0.5em; overflow-x: auto; font-size: 0.8em; }
</style>
)";

}  // namespace

const char* reportStyle() { return kStyle; }

std::string passBarsSvg(const json& results) {
  results::requireResultsFile(results);
  std::vector<std::string> names;
  for (const json& run : results["runs"]) names.push_back(reportText(run, "name"));
  const double left = labelColumnWidth(names);
  std::string out;
  for (const std::string& pass : reportPassOrder(results)) out += onePassBars(results, pass, left);
  return out;
}

std::string ratioPlotSvg(const CompareReport& report) {
  const std::vector<CompareRow>& rows = report.rows;
  if (rows.empty()) return "";
  std::vector<std::string> labels;
  for (const CompareRow& r : rows) labels.push_back(r.variant + " · " + r.pass);
  const double plotLeft = labelColumnWidth(labels), plotRight = plotLeft + kPlotWidth,
               figureWidth = plotRight + kValueWidth;
  // A log axis: B/A = 2 and 0.5 are as far from 1. It spans the threshold band and the timed rows:
  // a "not timed" row (a pass on a CPU device) can have an interval of decades that says nothing,
  // and would squeeze every other row into a corner; it is drawn cut at the axis' ends.
  double lo = 1 - report.thresholdPct / 100, hi = 1 + report.thresholdPct / 100;
  for (const CompareRow& r : rows)
    if (r.verdict != "not timed")
      for (double v : {r.ratio, r.ciLow, r.ciHigh})
        if (std::isfinite(v) && v > 0) lo = std::min(lo, v), hi = std::max(hi, v);
  const double pad = 0.05 * (std::log(hi) - std::log(lo));
  const double logLo = std::log(lo) - pad, logHi = std::log(hi) + pad;
  const double axisLo = std::exp(logLo), axisHi = std::exp(logHi);
  auto px = [&](double r) { return plotLeft + (std::log(r) - logLo) / (logHi - logLo) * (plotRight - plotLeft); };
  const double plotBottom = kTopMargin + kRowHeight * double(rows.size());
  const double height = plotBottom + 34;
  std::string s = format(
      "<svg class=\"ratios\" data-axis=\"%.6g %.6g\" width=\"%.0f\" height=\"%.0f\" viewBox=\"0 0 %.0f %.0f\" "
      "font-family=\"sans-serif\" font-size=\"11\" role=\"img\">\n",
      axisLo, axisHi, figureWidth, height, figureWidth, height);
  s += format("<text x=\"4\" y=\"16\" font-size=\"13\" font-weight=\"bold\">B/A per variant and pass, %.4g %% interval",
              100 * (1 - report.alpha)) +
       "</text>\n";
  s += format("<rect x=\"%.1f\" y=\"%.0f\" width=\"%.1f\" height=\"%.0f\" fill=\"#eee\"><title>",
              px(1 - report.thresholdPct / 100), kTopMargin - 4,
              px(1 + report.thresholdPct / 100) - px(1 - report.thresholdPct / 100), plotBottom - kTopMargin + 4) +
       htmlText(format("within the threshold, 1 ± %.4g %%", report.thresholdPct)) + "</title></rect>\n";
  for (double v : logAxisTicks(axisLo, axisHi, px)) {
    s += format("<line x1=\"%.1f\" y1=\"%.0f\" x2=\"%.1f\" y2=\"%.0f\" stroke=\"#ccc\"/>", px(v), kTopMargin - 4, px(v),
                plotBottom);
    s += format("<text class=\"tick\" x=\"%.1f\" y=\"%.0f\" text-anchor=\"middle\">%g</text>\n", px(v), plotBottom + 14,
                v);
  }
  s += format("<line x1=\"%.1f\" y1=\"%.0f\" x2=\"%.1f\" y2=\"%.0f\" stroke=\"#222\"/>\n", px(1), kTopMargin - 4, px(1),
              plotBottom);
  s += format("<text x=\"%.0f\" y=\"%.0f\" text-anchor=\"middle\">B/A (log scale; right of 1: B slower)</text>\n",
              0.5 * (plotLeft + plotRight), plotBottom + 28);
  for (size_t i = 0; i < rows.size(); ++i) {
    const CompareRow& r = rows[i];
    const double y = kTopMargin + kRowHeight * double(i), ym = y + kRowHeight / 2;
    const char* color = r.verdict == "slower"      ? "#d62728"
                        : r.verdict == "faster"    ? "#2ca02c"
                        : r.verdict == "too noisy" ? "#e0a800"
                        : r.verdict == "not timed" ? "#aaa"
                                                   : "#1f77b4";
    s += "<g data-variant=\"" + htmlText(r.variant) + "\" data-pass=\"" + htmlText(r.pass) + "\">";
    s += format("<text x=\"%.0f\" y=\"%.1f\" text-anchor=\"end\">", plotLeft - 6, y + 12) + htmlText(labels[i]) +
         "</text>";
    const std::string what = r.variant + " · " + r.pass + ": B/A " + formatNear1(r.ratio) + " [" +
                             formatNear1(r.ciLow) + ", " + formatNear1(r.ciHigh) + "], " + r.verdict;
    // Cut at the axis (only a "not timed" row reaches past it): a cut end has no cap, a point past an
    // end sits on it, hollow.
    auto onAxis = [&](double v) { return std::clamp(v, axisLo, axisHi); };
    if (std::isfinite(r.ciLow) && std::isfinite(r.ciHigh) && r.ciLow > 0) {
      const double x0 = px(onAxis(r.ciLow)), x1 = px(onAxis(r.ciHigh));
      std::string d = format("M %.1f %.1f H %.1f", x0, ym, x1);
      if (r.ciLow >= axisLo) d += format(" M %.1f %.1f V %.1f", x0, ym - 4, ym + 4);
      if (r.ciHigh <= axisHi) d += format(" M %.1f %.1f V %.1f", x1, ym - 4, ym + 4);
      s += "<path d=\"" + d + "\" stroke=\"" + color + "\" fill=\"none\"/>";
    }
    if (std::isfinite(r.ratio) && r.ratio > 0) {
      const bool inside = r.ratio >= axisLo && r.ratio <= axisHi;
      s += format("<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4\" fill=\"%s\" stroke=\"%s\"><title>", px(onAxis(r.ratio)), ym,
                  inside ? color : "white", color) +
           htmlText(what) + "</title></circle>";
    }
    s += format("<text x=\"%.0f\" y=\"%.1f\" fill=\"%s\">", plotRight + 8, y + 12, color) + htmlText(r.verdict) +
         "</text></g>\n";
  }
  return s + "</svg>\n";
}

std::string htmlReport(const HtmlReportInput& in) {
  HB_ASSERT(in.results != nullptr);
  const json& results = *in.results;
  results::requireResultsFile(results, in.source.empty() ? "results" : in.source);
  const json& context = results::at(results, "context");
  const std::string sweep = reportText(results::at(context, "config"), "name");
  const std::string device = reportText(results::at(context, "device"), "name");
  const std::string title =
      "hybridbench report: " + (sweep.empty() ? in.source : sweep) + (device.empty() ? "" : " on " + device);

  CompareReport compare;
  if (in.base) {
    results::requireResultsFile(*in.base, in.baseSource.empty() ? "base" : in.baseSource);
    compare = compareResults(*in.base, results, in.compareOptions);
  }

  std::string body = reportSummaryHtml(results);
  body += failedSection(results);
  std::vector<std::string> warnings = warningsOf(results);
  if (in.base && !(compare.warnings.empty() && compare.caveats.empty()))
    warnings.push_back("the comparison has " + countOf(compare.warnings.size() + compare.caveats.size(), "warning") +
                       " and caveats: see Comparison");
  if (!warnings.empty()) {
    body += "<section id=\"warnings\" class=\"warn\"><h2>Warnings</h2>\n<ul>\n";
    for (const std::string& w : warnings) body += "<li>" + htmlText(w) + "</li>\n";
    body += "</ul></section>\n";
  }
  body += contextSection(results, in.source);

  if (in.base) {
    body += "<section id=\"compare\"><h2>Comparison against the base</h2>\n<p>A: " + htmlText(in.baseSource) +
            "<br>B: " + htmlText(in.source) + "</p>\n";
    body += "<figure id=\"ratios\">" + ratioPlotSvg(compare) +
            format(
                "<figcaption class=\"legend\">Point: B/A, the Hodges-Lehmann estimate of the ratio of B's frame "
                "or pass time to A's; whisker: its %.4g %% confidence interval (Moses' distribution-free interval, "
                "Hollander and Wolfe 4.3); grey band: within the threshold of %.4g %%. Colour: the verdict.",
                100 * (1 - compare.alpha), compare.thresholdPct) +
            "</figcaption></figure>\n";
    body += markdownToHtml(formatCompare(compare), true) + "</section>\n";
  }

  body += "<section id=\"times\"><h2>Frame and pass times</h2>\n";
  for (const std::string& c : results::timingCaveats(results)) body += "<p class=\"note\">" + htmlText(c) + "</p>\n";
  const std::string bars = passBarsSvg(results);
  body += bars.empty() ? std::string("<p class=\"note\">no ok run has times</p>\n")
                       : bars +
                             "<p class=\"legend\">Bar: the median of the measured frames' GPU times; whisker: "
                             "their 5th to 95th percentile (quantiles of type 7, as numpy's default): the spread of "
                             "single frames, not an interval of the median.</p>\n";
  body += "</section>\n";

  body += "<section id=\"accuracy\"><h2>Accuracy against time</h2>\n<figure id=\"pareto\">" +
          svgElement(accuracyReportSvg(results)) + "</figure>\n";
  body +=
      "<p class=\"legend\">" + htmlText(accuracyMeasureDefinition(accuracyFront(results).measure)) + "</p></section>\n";

  body += "<section id=\"roofline\"><h2>Roofline</h2>\n";
  body += hasRoofline(results)
              ? "<figure>" + svgElement(rooflineSvg(results)) + "</figure>\n"
              : std::string(
                    "<p class=\"note\">no roofline in these results (no run carries a \"roofline\": swept "
                    "before it was recorded)</p>\n");
  body += "</section>\n";

  body +=
      "<section id=\"tables\"><h2>Tables</h2>\n" + markdownToHtml(allTablesMarkdown(results), false) + "</section>\n";
  body += variantsSection(in);

  std::string nav = "<nav>";
  for (const auto& [id, label] : std::vector<std::pair<std::string, std::string>>{{"summary", "summary"},
                                                                                  {"context", "context"},
                                                                                  {"compare", "comparison"},
                                                                                  {"times", "times"},
                                                                                  {"accuracy", "accuracy"},
                                                                                  {"roofline", "roofline"},
                                                                                  {"tables", "tables"},
                                                                                  {"variants", "variants"}})
    if (id != "compare" || in.base) nav += "<a href=\"#" + id + "\">" + label + "</a>";
  nav += "</nav>\n";

  return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" + htmlText(title) +
         "</title>\n" + kStyle + "</head>\n<body>\n<h1>" + htmlText(title) + "</h1>\n" + nav + body +
         "</body>\n</html>\n";
}

}  // namespace hb

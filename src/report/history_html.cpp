#include "report/history_html.h"

#include <algorithm>
#include <cmath>

#include "base/text_format.h"
#include "report/html_report.h"

namespace hb {

namespace {

constexpr double kSeriesWidth = 760, kSeriesHeight = 220;
constexpr double kSeriesLeft = 64, kSeriesRight = 16, kSeriesTop = 28, kSeriesBottom = 34;

// The revision as a table shows it: 7 hex digits, and "-dirty" where the build had local changes.
std::string pageRevision(const std::string& r) {
  if (r.empty()) return "unknown";
  const size_t dash = r.find('-');
  const std::string hash = r.substr(0, dash);
  return (hash.size() > 7 ? hash.substr(0, 7) : hash) + (dash == std::string::npos ? "" : r.substr(dash));
}

}  // namespace

std::string historySeriesSvg(const HistorySeries& s) {
  const size_t n = s.points.size();
  double lo = s.points.empty() ? 0 : s.points[0].medianMs, hi = lo;
  for (const HistoryPoint& p : s.points) {
    lo = std::min(lo, p.medianMs);
    hi = std::max(hi, p.medianMs);
  }
  // 10 % of the span (or of the level, for a flat series) above and below: no point on the frame.
  const double pad = hi > lo ? 0.1 * (hi - lo) : 0.05 * std::max(hi, 1e-9);
  lo -= pad;
  hi += pad;
  auto px = [&](size_t i) {
    return kSeriesLeft + (n > 1 ? double(i) / double(n - 1) : 0.5) * (kSeriesWidth - kSeriesLeft - kSeriesRight);
  };
  auto py = [&](double ms) {
    return kSeriesTop + (hi - ms) / (hi - lo) * (kSeriesHeight - kSeriesTop - kSeriesBottom);
  };
  const std::string title = s.variant + " / " + s.pass + " (ms)";
  std::string out = format(
      "<svg class=\"series\" width=\"%.0f\" height=\"%.0f\" viewBox=\"0 0 %.0f %.0f\" font-family=\"sans-serif\" "
      "font-size=\"11\" role=\"img\">\n",
      kSeriesWidth, kSeriesHeight, kSeriesWidth, kSeriesHeight);
  out += "<text x=\"4\" y=\"16\" font-size=\"13\" font-weight=\"bold\">" + escapeXml(title) + "</text>\n";
  const double bottom = kSeriesHeight - kSeriesBottom;
  // Decimals enough that the five levels, a quarter of the range apart, read differently.
  const int decimals = std::clamp(int(std::ceil(-std::log10((hi - lo) / 4))) + 1, 0, 9);
  for (int k = 0; k <= 4; ++k) {  // five levels, lowest to highest
    const double v = lo + (hi - lo) * k / 4;
    out += format("<line x1=\"%.0f\" y1=\"%.1f\" x2=\"%.0f\" y2=\"%.1f\" stroke=\"#eee\"/>", kSeriesLeft, py(v),
                  kSeriesWidth - kSeriesRight, py(v));
    out += format("<text x=\"%.0f\" y=\"%.1f\" text-anchor=\"end\">%.*f</text>\n", kSeriesLeft - 4, py(v) + 4, decimals,
                  v);
  }
  for (const HistoryChange& c : s.changes) {
    const double x = (px(c.index - 1) + px(c.index)) / 2;
    out += format(
               "<line class=\"change\" x1=\"%.1f\" y1=\"%.0f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#d62728\" "
               "stroke-dasharray=\"4 3\"><title>",
               x, kSeriesTop, x, bottom) +
           escapeXml(pageRevision(c.revisionBefore) + " -> " + pageRevision(c.revisionAfter) +
                     format(": x%.3f, p %.3f", c.ratio, c.p) +
                     (c.tracerAfter.empty() ? "" : ", ray tracer " + c.tracerBefore + " -> " + c.tracerAfter)) +
           "</title></line>\n";
  }
  // Each segment's level (the median of its runs' medians) as a grey line across its runs.
  for (size_t k = 0; k < s.changes.size() + (s.changes.empty() ? 0 : 1); ++k) {
    const size_t from = k == 0 ? 0 : s.changes[k - 1].index;
    const size_t to = k < s.changes.size() ? s.changes[k].index : n;
    const double levelMs = k < s.changes.size() ? s.changes[k].medianBefore : s.changes.back().medianAfter;
    out += format(
               "<line class=\"level\" x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#999\" "
               "stroke-width=\"2\"><title>",
               px(from), py(levelMs), px(to - 1), py(levelMs)) +
           escapeXml(format("level %.4g ms", levelMs)) + "</title></line>\n";
  }
  std::string path;
  for (size_t i = 0; i < n; ++i) path += format("%s %.1f %.1f ", i == 0 ? "M" : "L", px(i), py(s.points[i].medianMs));
  if (n > 1) out += "<path d=\"" + path + "\" stroke=\"#6a9fd4\" fill=\"none\"/>\n";
  for (size_t i = 0; i < n; ++i) {
    const HistoryPoint& p = s.points[i];
    out += format("<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4\" fill=\"#1f77b4\"><title>", px(i), py(p.medianMs)) +
           escapeXml(pageRevision(p.revision) + ", " + p.date + ", " + p.file + format(": %.4g ms", p.medianMs)) +
           "</title></circle>\n";
  }
  // The revisions under the first and last runs; the rest are in the circles' titles.
  if (n > 0) {
    out += format("<text x=\"%.1f\" y=\"%.0f\" text-anchor=\"start\">", px(0), bottom + 16) +
           escapeXml(pageRevision(s.points[0].revision)) + "</text>";
    if (n > 1)
      out += format("<text x=\"%.1f\" y=\"%.0f\" text-anchor=\"end\">", px(n - 1), bottom + 16) +
             escapeXml(pageRevision(s.points[n - 1].revision)) + "</text>\n";
  }
  return out + "</svg>\n";
}

std::string historyHtml(const HistoryReport& report, bool allSeries) {
  std::string out =
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>hybridbench "
      "history</title>\n";
  out += reportStyle();
  out += "</head>\n<body>\n<h1>hybridbench history</h1>\n";
  const HistoryOptions& o = report.options;
  out += "<p>" +
         escapeXml(format("%zu results files, %zu groups, %zu series. E-divisive on the log of each run's median, "
                          "%s, alpha %.4g, min segment %zu; changes within %.4g %% are not shown.",
                          report.files, report.groups.size(), report.series.size(), historyTestText(o).c_str(), o.alpha,
                          o.minSegment, o.thresholdPct)) +
         "</p>\n";
  if (report.regression) {
    out += "<div class=\"alert\"><h2>Slower since the last change</h2><ul>\n";
    for (const std::string& f : report.failures) out += "<li>" + escapeXml(f) + "</li>\n";
    out += "</ul></div>\n";
  }
  out += "<h2>Changes</h2>\n";
  bool any = false;
  std::string table =
      "<table>\n<tr><th>group</th><th>variant</th><th>pass</th><th>revisions</th><th>date</th><th "
      "align=\"right\">median (ms)</th><th align=\"right\">ratio</th><th align=\"right\">p</th></tr>\n";
  for (const HistorySeries& s : report.series)
    for (const HistoryChange& c : s.changes) {
      any = true;
      table +=
          "<tr><td>" + escapeXml(groupLabel(report.groups[s.group])) + "</td><td>" + escapeXml(s.variant) +
          "</td><td>" + escapeXml(s.pass) + "</td><td>" +
          escapeXml(pageRevision(c.revisionBefore) + " → " + pageRevision(c.revisionAfter)) + "</td><td>" +
          escapeXml(c.date.substr(0, 10)) + "</td><td align=\"right\">" +
          format("%.3f → %.3f", c.medianBefore, c.medianAfter) + "</td><td align=\"right\">" + format("%.3f", c.ratio) +
          (c.tracerAfter.empty() ? "" : " (ray tracer " + escapeXml(c.tracerBefore + " → " + c.tracerAfter) + ")") +
          "</td><td align=\"right\">" + format("%.3f", c.p) + "</td></tr>\n";
    }
  out += any ? table + "</table>\n" : "<p class=\"note\">No change beyond the threshold in any series.</p>\n";
  for (size_t g = 0; g < report.groups.size(); ++g) {
    std::string plots;
    for (const HistorySeries& s : report.series)
      if (s.group == g && (allSeries || !s.changes.empty())) plots += historySeriesSvg(s);
    if (plots.empty()) continue;
    out += "<h2>" + escapeXml(groupLabel(report.groups[g])) + "</h2>\n" + plots;
  }
  if (!report.warnings.empty()) {
    out += "<h2>Warnings</h2>\n<ul>\n";
    for (const std::string& w : report.warnings) out += "<li>" + escapeXml(w) + "</li>\n";
    out += "</ul>\n";
  }
  return out + "</body>\n</html>\n";
}

}  // namespace hb

#include "report/report_summary.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "base/text_format.h"
#include "report/accuracy_report.h"
#include "report/results_json.h"

namespace hb {

using nlohmann::json;

namespace {

std::string summaryText(const std::string& s) { return escapeXml(s); }

std::string nameOf(const AccuracyPoint& p) { return "<b>" + summaryText(p.name) + "</b>"; }

std::string msText(double ms) { return format("%.3f ms", ms); }

std::string errorText(double e) { return format("%.4g", e); }

// "1.90x the time of X" / "the same time as X" / "0.80x": a ratio of two times.
std::string timesText(double ms, double baseMs) {
  if (!(baseMs > 0)) return "";
  const double ratio = ms / baseMs;
  if (std::fabs(ratio - 1) < 0.005) return "about the same time";
  return format("%.2fx the time", ratio);
}

// The accuracy part for one group of the front: its most accurate run against its fastest, and
// its front from fast to accurate.
std::string groupSummary(const AccuracyFront& front, const std::string& group, const std::string& timeLabel) {
  std::vector<const AccuracyPoint*> pts;
  for (const AccuracyPoint& p : front.points)
    if (p.ok && p.group == group && std::isfinite(p.timeMs) && std::isfinite(p.error)) pts.push_back(&p);
  if (pts.empty()) return "";
  const std::string in = group.empty() ? std::string() : " (" + summaryText(group) + ")";
  // Ties: the more accurate of the fastest, the faster of the most accurate (the front's ends).
  const AccuracyPoint* fast = *std::min_element(pts.begin(), pts.end(), [](const auto* a, const auto* b) {
    return a->timeMs < b->timeMs || (a->timeMs == b->timeMs && a->error < b->error);
  });
  const AccuracyPoint* best = *std::min_element(pts.begin(), pts.end(), [](const auto* a, const auto* b) {
    return a->error < b->error || (a->error == b->error && a->timeMs < b->timeMs);
  });
  std::string out;
  const std::string measure = summaryText(accuracyMeasureLabel(front.measure));
  if (best == fast) {
    out += "<li>Most accurate" + in + ": " + nameOf(*best) + ", " + measure + " " + errorText(best->error) +
           ", which is also the fastest by " + summaryText(timeLabel) + " (" + msText(best->timeMs) +
           "): accuracy costs no time here.</li>\n";
  } else {
    out += "<li>Most accurate" + in + ": " + nameOf(*best) + ", " + measure + " " + errorText(best->error) + " in " +
           msText(best->timeMs) + " (" + summaryText(timeLabel) + "): " + timesText(best->timeMs, fast->timeMs) +
           (group.empty() ? " of the fastest, " : " of the fastest of its group, ") + nameOf(*fast) + " (" +
           msText(fast->timeMs) + ", error " + errorText(fast->error) + ").</li>\n";
  }
  std::vector<const AccuracyPoint*> onFront;
  for (const AccuracyPoint* p : pts)
    if (p->onFront) onFront.push_back(p);
  std::sort(onFront.begin(), onFront.end(), [](const auto* a, const auto* b) {
    return a->timeMs < b->timeMs || (a->timeMs == b->timeMs && a->error < b->error);
  });
  std::string chain;
  for (const AccuracyPoint* p : onFront)
    chain += (chain.empty() ? "" : " → ") + nameOf(*p) + " (" + msText(p->timeMs) + ", " + errorText(p->error) + ")";
  out += "<li class=\"front\">Pareto front" + in + ", from fast to accurate (" + countOf(onFront.size(), "variant") +
         " that no other variant beats in both time and error): " + chain + ".</li>\n";
  return out;
}

}  // namespace

std::string reportSummaryHtml(const json& results) {
  const AccuracyFront front = accuracyFront(results);  // checks the file
  const AccuracyPoint* fastest = nullptr;
  size_t ok = 0, failed = 0;
  for (const AccuracyPoint& p : front.points) {
    if (!p.ok) {
      ++failed;
      continue;
    }
    ++ok;
    if (std::isfinite(p.frameMs) && (!fastest || p.frameMs < fastest->frameMs)) fastest = &p;
  }
  std::string items;
  if (fastest) {
    const AccuracyPoint* slowest = fastest;
    for (const AccuracyPoint& p : front.points)
      if (p.ok && std::isfinite(p.frameMs) && p.frameMs > slowest->frameMs) slowest = &p;
    items += "<li>Fastest: " + nameOf(*fastest) + ", frame " + msText(fastest->frameMs) + " (median)" +
             (slowest != fastest
                  ? "; the slowest, " + nameOf(*slowest) + ", takes " +
                        format("%.2fx", slowest->frameMs / fastest->frameMs) + " (" + msText(slowest->frameMs) + ")"
                  : std::string()) +
             ".</li>\n";
  } else {
    items += "<li>No variant has a frame time: nothing to rank.</li>\n";
  }
  if (front.measure == AccuracyMeasure::None) {
    items +=
        "<li>Accuracy: no measure of error that every variant carries (swept without analysis), so no most "
        "accurate variant and no Pareto front.</li>\n";
  } else {
    const std::string timeLabel = front.time == "frame time, median (ms)" ? "frame time" : front.time;
    for (const std::string& group : front.groups) items += groupSummary(front, group, timeLabel);
  }
  if (failed > 0)
    items += "<li class=\"bad\">" + summaryText(countOf(failed, "variant")) + " of " + std::to_string(ok + failed) +
             " failed: see Failed variants.</li>\n";
  const std::vector<std::string> caveats = results::timingCaveats(results);
  if (!caveats.empty())
    items +=
        "<li>These times were measured where they do not rank the variants as a GPU would (see Warnings); the "
        "counts and errors hold.</li>\n";
  return "<section id=\"summary\"><h2>Summary</h2>\n<ul>\n" + items + "</ul></section>\n";
}

}  // namespace hb

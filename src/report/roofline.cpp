#include "report/roofline.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "base/text_format.h"
#include "frame/renderer.h"

namespace hb {

using json = nlohmann::json;

std::map<std::string, double> peakRates(const Peaks& peaks, double raybenchRaysPerS, const std::string& backend) {
  std::map<std::string, double> rates;
  for (const char* unit : {"bytes", "atomics", "atomics64", "fma", "triangles", "fragments"})
    rates[unit] = peaks.rateFor(unit);
  // Ray passes against the rate of the backend they traced with.
  for (const char* unit : {"rays_coherent", "rays_random", "rays_occlusion", "rays_ao"})
    rates[unit] = peaks.rateFor(unit, backend);
  rates["rays"] = raybenchRaysPerS;
  return rates;
}

std::string peakFractionText(double fraction) {
  return format("%.1f %%", 100 * fraction) + (fraction > 1 ? std::string(", ") + kOverPeakMeaning : std::string());
}

json rooflineJson(const std::vector<PassWork>& works, const std::map<std::string, double>& medianMs,
                  const std::map<std::string, double>& peaks) {
  json out = json::object();
  for (const PassWork& w : works) {
    const auto t = medianMs.find(w.entry);
    if (t == medianMs.end() || w.items.empty()) continue;
    const double ms = t->second;
    json loads = json::array();
    int best = -1;
    double bestFraction = -1;
    for (size_t i = 0; i < w.items.size(); ++i) {
      const WorkItem& item = w.items[i];
      const double achieved = ms > 0 ? item.amount / (ms * 1e-3) : 0.0;
      const auto p = peaks.find(item.unit);
      const double peak = p == peaks.end() ? 0.0 : p->second;
      json load = {{"unit", item.unit},
                   {"work", item.amount},
                   {"achieved_per_s", achieved},
                   {"peak_per_s", peak},
                   {"source", item.source}};
      load["fraction"] = peak > 0 ? json(achieved / peak) : json(nullptr);
      if (peak > 0 && achieved / peak > bestFraction) {
        bestFraction = achieved / peak;
        best = int(i);
      }
      loads.push_back(load);
    }
    const json& bound = loads[size_t(std::max(best, 0))];
    out[w.entry] = {{"bound", bound["unit"]},
                    {"work", bound["work"]},
                    {"unit", bound["unit"]},
                    {"ms", ms},
                    {"achieved_per_s", bound["achieved_per_s"]},
                    {"peak_per_s", bound["peak_per_s"]},
                    {"fraction", bound["fraction"]},
                    {"source", bound["source"]},
                    {"loads", loads}};
  }
  return out;
}

json rooflineOf(const Renderer& renderer, const json& run, const std::map<std::string, double>& medianMs,
                const Peaks& peaks) {
  std::vector<PassWork> works;
  for (const FramePass* pass : renderer.framePasses())
    if (pass->work) {
      std::vector<PassWork> w = pass->work(run);
      works.insert(works.end(), w.begin(), w.end());
    }
  double rays = 0;
  if (run.contains("raybench")) rays = run["raybench"].value("rays_per_s", 0.0);
  // Our BVH's rates were measured at each width: "compute" (2), "compute-w4" and "compute-w8".
  std::string backend = run.value("backend", std::string());
  if (backend == "compute" && run.contains("params") && run["params"].value("bvh_width", 2) != 2)
    backend = "compute-w" + std::to_string(run["params"].value("bvh_width", 2));
  return rooflineJson(works, medianMs, peakRates(peaks, rays, backend));
}

namespace {

struct Load {
  std::string unit, source;
  double achieved = 0, peak = 0;
};

struct Point {
  std::string variant, entry, unit, source;
  double ms = 0, achieved = 0, peak = 0;
  bool hasFraction = false;
  std::vector<Load> loads;
  nlohmann::json params;
};

std::vector<Point> points(const json& results) {
  std::vector<Point> pts;
  for (const json& run : results.value("runs", json::array())) {
    if (run.value("status", "") != "ok" || !run.contains("roofline")) continue;
    // In the frame's own order (pass_order), the rest after it.
    std::vector<std::string> order = run.value("pass_order", std::vector<std::string>{});
    for (const auto& [entry, r] : run["roofline"].items())
      if (std::find(order.begin(), order.end(), entry) == order.end()) order.push_back(entry);
    for (const std::string& entry : order) {
      if (!run["roofline"].contains(entry)) continue;
      const json& r = run["roofline"][entry];
      Point p{run.value("name", ""), entry, r.value("unit", ""), r.value("source", "")};
      p.ms = r.value("ms", 0.0);
      p.achieved = r.value("achieved_per_s", 0.0);
      p.peak = r.value("peak_per_s", 0.0);
      p.hasFraction = r.contains("fraction") && r["fraction"].is_number();
      for (const json& l : r.value("loads", json::array()))
        p.loads.push_back(
            {l.value("unit", ""), l.value("source", ""), l.value("achieved_per_s", 0.0), l.value("peak_per_s", 0.0)});
      p.params = run.value("params", json::object());
      pts.push_back(p);
    }
  }
  return pts;
}

std::string deviceOf(const json& results) {
  const json& ctx = results.value("context", json::object());
  std::string s = ctx.value("device", json::object()).value("name", "unknown device");
  const json& res = ctx.value("resolution", json());
  if (res.is_array() && res.size() == 2) s += format(", %dx%d", res[0].get<int>(), res[1].get<int>());
  return s;
}

// Vendor data-sheet figures (not measurements) for the devices this project measures on, to set
// the measured peaks beside: NVIDIA H100 SXM5 80GB and H200 SXM data sheets (memory bandwidth;
// FP32 67 TFLOPS = 33.5 T FMA/s).
struct DataSheet {
  const char* deviceName;  // as the driver names the device
  const char* figure;      // the peaks figure it bounds
  double perSecond;
  const char* source;
};
constexpr DataSheet kDataSheets[] = {
    {"NVIDIA H100 80GB HBM3", "memory_read", 3.35e12, "H100 SXM5 data sheet: 3.35 TB/s"},
    {"NVIDIA H100 80GB HBM3", "memory_write", 3.35e12, "H100 SXM5 data sheet: 3.35 TB/s"},
    {"NVIDIA H100 80GB HBM3", "memory_copy", 3.35e12, "H100 SXM5 data sheet: 3.35 TB/s"},
    {"NVIDIA H100 80GB HBM3", "fma_fp32", 33.5e12, "H100 SXM5 data sheet: FP32 67 TFLOPS"},
    {"NVIDIA H200", "memory_read", 4.8e12, "H200 SXM data sheet: 4.8 TB/s"},
    {"NVIDIA H200", "memory_write", 4.8e12, "H200 SXM data sheet: 4.8 TB/s"},
    {"NVIDIA H200", "memory_copy", 4.8e12, "H200 SXM data sheet: 4.8 TB/s"},
    {"NVIDIA H200", "fma_fp32", 33.5e12, "H200 SXM data sheet: FP32 67 TFLOPS"},
};

}  // namespace

std::string peaksMarkdown(const json& results) {
  const json& device = results.value("context", json::object()).value("device", json::object());
  const json peaks = device.value("peaks", json::object());
  if (!peaks.contains("figures")) return "";
  const std::string name = device.value("name", "");
  std::string s =
      "### Device peaks (hybridbench peaks)\n\n" + name + ", " + peaks.value("driver", "") + ", " +
      peaks.value("timing", "") +
      ".\n\n| Figure | Measured | Median ms | Data sheet | Measured / data sheet |\n|---|---|---|---|---|\n";
  for (const auto& [key, f] : peaks["figures"].items()) {
    const double perS = f.value("per_s", 0.0);
    std::string sheet = "—", ratio = "—";
    for (const DataSheet& d : kDataSheets)
      if (name == d.deviceName && key == d.figure) {
        sheet = d.source;
        ratio = format("%.2f", perS / d.perSecond);
      }
    const double ms = f.contains("ms") ? f["ms"].value("median", 0.0) : 0.0;
    s += "| " + key + " | " + formatRate(perS, f.value("unit", "")) + " | " + format("%.4g", ms) + " | " + sheet +
         " | " + ratio + " |\n";
  }
  return s + "\n";
}

std::string ceilingKey(const std::string& entry, const std::string& unit, const json& params) {
  auto param = [&params](const char* key) {
    return params.is_object() && params.contains(key) ? params[key].dump() : std::string("-");
  };
  return entry + " | " + unit + " | primary " + param("primary") + " | aa " + param("aa");
}

bool rateOnlyUnit(const std::string& unit) {
  return unit == "tile_loop_steps" || unit == "triangles_set_up" || unit == "pixels_resolved" || unit == "splat_tests";
}

MeasuredCeilings measuredCeilings(const json& ceilingResults, const std::string& file) {
  MeasuredCeilings c;
  c.file = file;
  for (const Point& p : points(ceilingResults))
    for (const Load& l : p.loads) {
      if (!rateOnlyUnit(l.unit) || !(l.achieved > 0)) continue;  // a device peak rates it; no rate
      MeasuredCeiling& m = c.rates[ceilingKey(p.entry, l.unit, p.params)];
      if (l.achieved > m.perSecond) m = {l.achieved, p.variant};
    }
  return c;
}

size_t ceilingMatches(const json& results, const MeasuredCeilings& ceilings) {
  size_t matches = 0;
  for (const Point& p : points(results))
    for (const Load& l : p.loads)
      matches += rateOnlyUnit(l.unit) && ceilings.rates.count(ceilingKey(p.entry, l.unit, p.params)) > 0;
  return matches;
}

std::string rooflineMarkdown(const json& results, const MeasuredCeilings* ceilings) {
  std::string s = "## Roofline: how close each pass runs to the device's peak\n\n";
  s += "Device: " + deviceOf(results) +
       ". Peaks: `hybridbench peaks` (context.device.peaks); rays: the frame's own shadow rays traced alone "
       "(raybench). Bound: the unit whose fraction of its peak is highest.\n\n";
  const json& ctx = results.value("context", json::object());
  if (ctx.contains("timing_caveat")) s += "Caveat: " + ctx["timing_caveat"].get<std::string>() + "\n\n";
  s += peaksMarkdown(results);
  // An empty dispatch between two timestamps: the floor under any timed pass. A pass within a few
  // times of it is bound by latency (launch, barriers), whatever its bytes.
  double emptyMs = 0;
  const json empty = ctx.value("device", json::object())
                         .value("peaks", json::object())
                         .value("figures", json::object())
                         .value("dispatch_empty", json::object());
  if (empty.contains("ms")) emptyMs = empty["ms"].value("median", 0.0);
  if (emptyMs > 0)
    s += format("Empty dispatch: %.4g ms (peaks dispatch_empty); \"x empty\" is the pass's time over it.\n\n", emptyMs);
  if (ceilings)
    s += "Measured ceilings: " + ceilings->file +
         " (the same passes on a ceiling workload; a unit no device peak counts is rated against the "
         "highest rate its runs reached for the same pass, primary and aa, named in \"Work is\").\n\n";
  // The share of its ceiling only with measured ceilings: the tables of earlier studies keep their
  // columns.
  if (ceilings)
    s += "\"Share of its ceiling\": the largest of the bound's fraction and the empty dispatch's time over "
         "the pass's (launch).\n\n";
  s += std::string("| Variant | Pass | ms | x empty | Bound | Achieved | Peak | Fraction of the limit | ") +
       (ceilings ? "Share of its ceiling | " : "") + "Work is |\n";
  s += std::string("|---|---|---|---|---|---|---|---|") + (ceilings ? "---|" : "") + "---|\n";
  std::vector<Point> pts = points(results);
  for (Point& p : pts) {
    // With measured ceilings, a unit without a device peak takes its ceiling run's rate, and the
    // bound is again the unit closest to its peak.
    if (ceilings)
      for (const Load& l : p.loads) {
        if (!rateOnlyUnit(l.unit)) continue;
        const auto c = ceilings->rates.find(ceilingKey(p.entry, l.unit, p.params));
        if (c == ceilings->rates.end()) continue;
        const double fraction = l.achieved / c->second.perSecond;
        if (p.hasFraction && fraction <= p.achieved / p.peak) continue;
        p.unit = l.unit;
        p.achieved = l.achieved;
        p.peak = c->second.perSecond;
        p.hasFraction = true;
        p.source = l.source + "; ceiling: \"" + c->second.variant + "\" of the ceiling runs";
      }
    const double fraction = p.hasFraction ? p.achieved / p.peak : 0.0;
    const double launch = emptyMs > 0 && p.ms > 0 ? emptyMs / p.ms : 0.0;
    const std::string share = launch > fraction ? peakFractionText(launch) + " (launch)"
                              : p.hasFraction   ? peakFractionText(fraction) + " (" + p.unit + ")"
                                                : std::string("—");
    s += "| " + p.variant + " | " + p.entry + " | " + format("%.4g", p.ms) + " | " +
         (emptyMs > 0 ? format("%.1f", p.ms / emptyMs) : "—") + " | " + p.unit + " | " +
         formatRate(p.achieved, p.unit) + " | " + (p.peak > 0 ? formatRate(p.peak, p.unit) : "—") + " | " +
         (p.hasFraction ? peakFractionText(fraction) : "—") + " | " + (ceilings ? share + " | " : "") + p.source +
         " |\n";
  }
  if (pts.empty()) s += std::string("| (no run carries a roofline) | | | | | | | | ") + (ceilings ? "| " : "") + "|\n";
  return s + "\n";
}

std::string rooflineSvg(const json& results) {
  const std::vector<Point> all = points(results);
  std::vector<Point> pts;
  for (const Point& p : all)
    if (p.hasFraction && p.achieved > 0) pts.push_back(p);
  constexpr double kW = 1100, kH = 620, kL = 90, kR = 640, kT = 70, kB = 540;
  double lo = 1e300, hi = 0;
  // A pass over its peak is plotted at the peak (on the diagonal, as a triangle): its rate says the
  // peak is not its own, and would stretch the axes by decades for nothing.
  auto plotted = [](const Point& p) { return std::min(p.achieved, p.peak); };
  for (const Point& p : pts) {
    lo = std::min({lo, plotted(p), p.peak});
    hi = std::max(hi, p.peak);
  }
  if (pts.empty()) lo = 1, hi = 10;
  // Log axes over whole decades; both axes share them so the diagonal is "at the peak".
  const double d0 = std::floor(std::log10(lo)), d1 = std::max(std::ceil(std::log10(hi)), d0 + 1);
  auto px = [&](double v) { return kL + (std::log10(v) - d0) / (d1 - d0) * (kR - kL); };
  auto py = [&](double v) { return kB - (std::log10(v) - d0) / (d1 - d0) * (kB - kT); };
  std::string s =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" " +
      format("width=\"%.0f\" height=\"%.0f\" viewBox=\"0 0 %.0f %.0f\"", kW, kH, kW, kH) +
      " font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  s += format("<text x=\"%.0f\" y=\"28\" font-size=\"16\" font-weight=\"bold\">", kL) +
       escapeXml("Roofline — " + deviceOf(results)) + "</text>\n";
  s += format("<text x=\"%.0f\" y=\"48\">", kL) +
       escapeXml(
           "each pass's achieved rate against its device peak (units per second, log); on the diagonal = at "
           "the peak; dashed: 10 % and 1 %") +
       "</text>\n";
  if (std::any_of(pts.begin(), pts.end(), [](const Point& p) { return p.achieved > p.peak; }))
    s += format("<text x=\"%.0f\" y=\"64\">", kL) +
         escapeXml("triangle: a pass over 100 % of its peak, plotted at the peak (" + std::string(kOverPeakMeaning) +
                   ")") +
         "</text>\n";
  for (double d = d0; d <= d1; d += 1) {
    const double v = std::pow(10.0, d);
    s += format("<line x1=\"%.1f\" y1=\"%.0f\" x2=\"%.1f\" y2=\"%.0f\" stroke=\"#e0e0e0\"/>\n", px(v), kT, px(v), kB);
    s += format("<line x1=\"%.0f\" y1=\"%.1f\" x2=\"%.0f\" y2=\"%.1f\" stroke=\"#e0e0e0\"/>\n", kL, py(v), kR, py(v));
    s += format("<text x=\"%.1f\" y=\"%.0f\" text-anchor=\"middle\">1e%.0f</text>\n", px(v), kB + 18, d);
    s += format("<text x=\"%.0f\" y=\"%.1f\" text-anchor=\"end\">1e%.0f</text>\n", kL - 6, py(v) + 4, d);
  }
  s += format("<rect x=\"%.0f\" y=\"%.0f\" width=\"%.0f\" height=\"%.0f\" fill=\"none\" stroke=\"black\"/>\n", kL, kT,
              kR - kL, kB - kT);
  const double a = std::pow(10.0, d0), b = std::pow(10.0, d1);
  s += format("<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"black\"/>\n", px(a), py(a), px(b), py(b));
  for (double f : {0.1, 0.01})
    s += format("<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#888\" stroke-dasharray=\"4 3\"/>\n",
                px(a / f), py(a), px(b), py(b * f));
  s += format("<text x=\"%.0f\" y=\"%.0f\" text-anchor=\"middle\">peak of the pass's bound (per s)</text>\n",
              0.5 * (kL + kR), kB + 42);
  s += format("<text transform=\"translate(24 %.0f) rotate(-90)\" text-anchor=\"middle\">achieved (per s)</text>\n",
              0.5 * (kT + kB));
  // One colour per unit: ten units at most (frame_pass.h WorkItem), ten colours.
  constexpr const char* colors[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                    "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"};
  constexpr size_t kColors = sizeof colors / sizeof colors[0];
  std::vector<std::string> units;
  for (const Point& p : pts)
    if (std::find(units.begin(), units.end(), p.unit) == units.end()) units.push_back(p.unit);
  for (size_t i = 0; i < pts.size(); ++i) {
    const Point& p = pts[i];
    const size_t u = size_t(std::find(units.begin(), units.end(), p.unit) - units.begin());
    const double x = px(p.peak) + (double(i % 7) - 3.0) * 2.0;  // a little spread: equal peaks, one column
    const std::string title = p.variant + " — " + p.entry + ": " + formatRate(p.achieved, p.unit) + " of " +
                              formatRate(p.peak, p.unit) + " (" + peakFractionText(p.achieved / p.peak) + ")";
    if (p.achieved > p.peak) {
      const double y = py(p.peak);
      s += format(
               "<path class=\"over-peak\" d=\"M %.1f %.1f L %.1f %.1f L %.1f %.1f Z\" fill=\"%s\" fill-opacity=\"0.7\">"
               "<title>",
               x, y - 5, x - 5, y + 4, x + 5, y + 4, colors[u % kColors]) +
           escapeXml(title) + "</title></path>\n";
      continue;
    }
    s += format("<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4\" fill=\"%s\" fill-opacity=\"0.7\"><title>", x, py(p.achieved),
                colors[u % kColors]) +
         escapeXml(title) + "</title></circle>\n";
  }
  // Legend: the units, then the passes in one line each (numbered by first appearance).
  double y = kT + 4;
  for (size_t u = 0; u < units.size(); ++u, y += 18)
    s += format("<circle cx=\"%.0f\" cy=\"%.0f\" r=\"5\" fill=\"%s\"/><text x=\"%.0f\" y=\"%.0f\">", kR + 24, y,
                colors[u % kColors], kR + 36, y + 4) +
         escapeXml(units[u]) + "</text>\n";
  y += 10;
  std::vector<std::string> entries;
  for (const Point& p : pts)
    if (std::find(entries.begin(), entries.end(), p.entry) == entries.end()) entries.push_back(p.entry);
  for (const std::string& e : entries) {
    double best = 0;
    std::string unit;
    for (const Point& p : pts)
      if (p.entry == e && p.achieved / p.peak > best) best = p.achieved / p.peak, unit = p.unit;
    if (y > kH - 20) break;
    s += format("<text x=\"%.0f\" y=\"%.0f\">", kR + 18, y) +
         escapeXml(e + ": up to " + format("%.1f", 100 * best) + " % of its " + unit + " peak") + "</text>\n";
    y += 16;
    if (best > 1 && y <= kH - 20) {
      s += format("<text x=\"%.0f\" y=\"%.0f\" fill=\"#a00\">", kR + 30, y) + escapeXml(kOverPeakMeaning) + "</text>\n";
      y += 16;
    }
  }
  if (pts.empty())
    s += format("<text x=\"%.0f\" y=\"%.0f\" text-anchor=\"middle\">no pass has a measured peak</text>\n",
                0.5 * (kL + kR), 0.5 * (kT + kB));
  return s + "</svg>\n";
}

}  // namespace hb

#include "report/accuracy_report.h"
#include "base/numbers.h"
#include "base/text_format.h"
#include "report/aa_table.h"
#include "report/results_json.h"
#include "report/roofline.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <limits>

#include "base/errors.h"

namespace hb {

using nlohmann::json;

namespace {

using namespace results;  // at, numberAt, medianOf, escapeCell, csvField, requireResultsFile

const char* const kDash = "—";

// Compared as a string, not through json == "ok": GCC 12 warns falsely (-Warray-bounds) on the
// temporary json that comparison builds once it is inlined here.
bool isOk(const json& run) {
  const json& status = at(run, "status");
  return status.is_string() && status.get_ref<const std::string&>() == "ok";
}

double measureOf(const json& run, AccuracyMeasure m) {
  const json& acc = at(run, "accuracy");
  switch (m) {
    case AccuracyMeasure::AoError: return numberAt(at(at(run, "ambient_occlusion"), "vs_reference"), "mae");
    case AccuracyMeasure::IndirectError: return numberAt(at(at(run, "indirect"), "vs_reference"), "rel_mse");
    case AccuracyMeasure::EnvironmentError:
      return numberAt(at(at(run, "environment_light"), "vs_reference"), "rel_mse");
    case AccuracyMeasure::ImageError: return numberAt(acc, "image_error");
    case AccuracyMeasure::ShadowMismatchRate: {
      const json& sm = at(acc, "shadow_mismatches");
      const double pairs = numberAt(sm, "pairs_compared");
      if (!(pairs > 0)) return kNaN;
      return (numberAt(sm, "wrongly_dark") + numberAt(sm, "wrongly_lit")) / pairs;
    }
    case AccuracyMeasure::RayDeficit: {
      const json& rays = at(run, "rays");
      const double oracle = numberAt(rays, "oracle"), traced = numberAt(rays, "traced");
      if (!(oracle > 0) || !std::isfinite(traced)) return kNaN;
      return std::max(0.0, oracle - traced) / oracle;
    }
    case AccuracyMeasure::None: break;
  }
  return kNaN;
}

std::string cell(double v, const char* fmt) { return std::isfinite(v) ? format(fmt, v) : kDash; }

std::string stringOr(const json& v, const std::string& fallback) {
  return v.is_string() ? v.get<std::string>() : fallback;
}

// "NVIDIA H100 80GB HBM3, 1920×1080, scene atrium" from the context block; absent parts left out.
std::string contextLine(const json& results) {
  const json& ctx = at(results, "context");
  std::string s = stringOr(at(at(ctx, "device"), "name"), "unknown device");
  const json& res = at(ctx, "resolution");
  if (res.is_array() && res.size() == 2 && res[0].is_number() && res[1].is_number())
    s += format(", %d×%d", res[0].get<int>(), res[1].get<int>());
  const json& scene = at(at(ctx, "scene"), "name");
  if (scene.is_string()) s += ", scene " + scene.get<std::string>();
  return s;
}

std::string sweepName(const json& results) {
  return stringOr(at(at(at(results, "context"), "config"), "name"), "sweep");
}

}  // namespace

const char* accuracyMeasureLabel(AccuracyMeasure m) {
  switch (m) {
    case AccuracyMeasure::AoError: return "AO error (MAE vs the Monte Carlo reference)";
    case AccuracyMeasure::IndirectError: return "indirect error (relative MSE vs the gathered reference)";
    case AccuracyMeasure::EnvironmentError:
      return "environment light error (relative MSE vs the Monte Carlo reference)";
    case AccuracyMeasure::ImageError: return "image error (FLIP mean)";
    case AccuracyMeasure::ShadowMismatchRate: return "shadow mismatch rate";
    case AccuracyMeasure::RayDeficit: return "ray deficit (1 − traced/oracle, ≥ 0)";
    case AccuracyMeasure::None: break;
  }
  return "no accuracy measure";
}

std::string accuracyMeasureDefinition(AccuracyMeasure m) {
  switch (m) {
    case AccuracyMeasure::IndirectError:
      return "indirect.vs_reference.rel_mse, the relative mean squared error of the indirect irradiance's "
             "luminance against the gathered reference of as many bounces (cosine-weighted rays per pixel, path traced "
             "beyond the first bounce) on the same surface "
             "(0 for the reference itself)";
    case AccuracyMeasure::EnvironmentError:
      return "environment_light.vs_reference.rel_mse, the relative mean squared error of the environment light's "
             "luminance against 1024 stratified cosine-weighted rays per pixel, each weighted by the environment, on "
             "the same surface (0 for the reference itself)";
    case AccuracyMeasure::AoError:
      return "ambient_occlusion.vs_reference.mae, the mean absolute error of the AO image against 1024 "
             "stratified cosine-weighted rays per pixel on the same surface (0 for the reference itself)";
    case AccuracyMeasure::ImageError:
      return "accuracy.image_error, the mean FLIP error against the run's reference render "
             "(accuracy.image_error_flip.reference: the same scene, camera and resolution with no culling, or "
             "with reference_ssaa the run's own frame supersampled)";
    case AccuracyMeasure::ShadowMismatchRate:
      return "(wrongly dark + wrongly lit) / pairs compared, the fraction of (pixel, light) pairs "
             "whose shadow test differs from the reference; used because not every run carries "
             "an image error";
    case AccuracyMeasure::RayDeficit:
      return "max(0, oracle − traced) / oracle rays, a lower bound on the fraction of needed "
             "shadow rays not traced; used because not every run carries an image error or shadow "
             "mismatches";
    case AccuracyMeasure::None: break;
  }
  return "none: not every ok run carries an image error, shadow mismatches or traced and oracle "
         "ray counts, so no front is marked";
}

AccuracyFront accuracyFront(const json& results) {
  requireResultsFile(results);
  const json& runs = results["runs"];
  AccuracyFront front;

  // The first measure that every ok run with a frame time carries, so all points share a scale, and
  // that the study varies: an effect every run computes alike (the Cornell box's AO in a sweep of
  // indirect light) says nothing about the runs, so the first measure whose values differ is
  // preferred; if none differs, the first carried.
  front.measure = AccuracyMeasure::None;
  AccuracyMeasure firstCarried = AccuracyMeasure::None;
  for (AccuracyMeasure m :
       {AccuracyMeasure::AoError, AccuracyMeasure::EnvironmentError, AccuracyMeasure::IndirectError,
        AccuracyMeasure::ImageError, AccuracyMeasure::ShadowMismatchRate, AccuracyMeasure::RayDeficit}) {
    bool all = true, any = false, varies = false;
    double first = kNaN;
    for (const json& run : runs) {
      if (!isOk(run) || !std::isfinite(medianOf(at(run, "frame_ms")))) continue;
      any = true;
      const double v = measureOf(run, m);
      all = all && std::isfinite(v);
      if (!std::isfinite(v)) continue;
      if (std::isnan(first)) first = v;
      varies = varies || v != first;
    }
    if (!(any && all)) continue;
    if (firstCarried == AccuracyMeasure::None) firstCarried = m;
    if (varies) {
      front.measure = m;
      break;
    }
  }
  if (front.measure == AccuracyMeasure::None) front.measure = firstCarried;

  const bool ao = front.measure == AccuracyMeasure::AoError;
  const bool env = front.measure == AccuracyMeasure::EnvironmentError;
  // Indirect light of several bounce counts: each run is measured against the reference of its own
  // K, so the fronts are per K (as AO's are per d_max).
  bool perBounces = false;
  if (front.measure == AccuracyMeasure::IndirectError)
    for (const json& run : runs) perBounces = perBounces || numberAt(at(run, "indirect"), "bounces") > 1;
  if (ao) front.time = "AO time: ldm_build + ambient_occlusion medians (ms)";
  if (env) front.time = "environment light time: environment_ldm_build + environment_light medians (ms)";
  for (const json& run : runs) {
    AccuracyPoint p;
    p.name = stringOr(at(run, "name"), "(unnamed)");
    p.ok = isOk(run);
    if (!p.ok) p.failure = stringOr(at(run, "error"), "status " + at(run, "status").dump());
    p.frameMs = medianOf(at(run, "frame_ms"));
    p.timeMs = p.frameMs;
    if (ao) {
      const json& passes = at(run, "passes");
      const double build = medianOf(at(passes, "ldm_build")), pass = medianOf(at(passes, "ambient_occlusion"));
      p.timeMs = (std::isfinite(build) ? build : 0.0) + pass;
      const json& dMax = at(at(run, "ambient_occlusion"), "d_max");
      p.group = dMax.is_number() ? format("d_max = %g m", dMax.get<double>()) : "d_max = none";
    }
    if (perBounces) {
      const double k = numberAt(at(run, "indirect"), "bounces");
      p.group = std::isfinite(k) ? format("bounces = %g", k) : "bounces = 1";
    }
    if (env) {
      const json& passes = at(run, "passes");
      const double build = medianOf(at(passes, "environment_ldm_build"));
      p.timeMs = (std::isfinite(build) ? build : 0.0) + medianOf(at(passes, "environment_light"));
    }
    p.error = measureOf(run, front.measure);
    if (std::find(front.groups.begin(), front.groups.end(), p.group) == front.groups.end())
      front.groups.push_back(p.group);
    front.points.push_back(p);
  }

  // O(n²) dominance test within each group; sweeps have tens of runs.
  auto eligible = [](const AccuracyPoint& p) { return p.ok && std::isfinite(p.timeMs) && std::isfinite(p.error); };
  for (AccuracyPoint& p : front.points) {
    if (!eligible(p)) continue;
    p.onFront = true;
    for (const AccuracyPoint& q : front.points) {
      if (&q == &p || !eligible(q) || q.group != p.group) continue;
      const bool noWorse = q.timeMs <= p.timeMs && q.error <= p.error;
      const bool better = q.timeMs < p.timeMs || q.error < p.error;
      if (noWorse && better) {
        p.onFront = false;
        break;
      }
    }
  }
  return front;
}

// "shadows 97.1 % (rays)": the longest top-level pass with a roofline fraction, or "—".
static std::string longestPassFraction(const json& run) {
  const json& roofline = at(run, "roofline");
  if (!roofline.is_object()) return kDash;
  std::string best;
  double bestMs = -1;
  for (const auto& [pass, r] : roofline.items())
    if (pass.find('.') == std::string::npos && r.value("fraction", json()).is_number() && r.value("ms", 0.0) > bestMs) {
      bestMs = r.value("ms", 0.0);
      best = pass + " " + peakFractionText(r["fraction"].get<double>()) + " (" + r.value("unit", "") + ")";
    }
  return best.empty() ? kDash : best;
}

std::string accuracyReportMarkdown(const json& results) {
  const AccuracyFront front = accuracyFront(results);
  const json& runs = results["runs"];

  bool anyImage = false, anyShadow = false, anyAo = false, anyIndirect = false, anyRoofline = false, anyEnv = false;
  for (const json& run : runs) {
    anyRoofline = anyRoofline || at(run, "roofline").is_object();
    const json& acc = at(run, "accuracy");
    anyAo = anyAo || at(at(run, "ambient_occlusion"), "vs_reference").is_object();
    anyIndirect = anyIndirect || at(at(run, "indirect"), "vs_reference").is_object();
    anyEnv = anyEnv || at(at(run, "environment_light"), "vs_reference").is_object();
    anyImage = anyImage || at(acc, "image_error").is_number();
    anyShadow = anyShadow || at(acc, "shadow_mismatches").is_object();
  }

  std::string out = "## Accuracy vs frame time — " + escapeCell(sweepName(results)) + "\n\n" +
                    escapeCell(contextLine(results)) + "\n\n";
  for (const std::string& caveat : timingCaveats(results)) out += "Caveat: " + caveat + "\n\n";
  out +=
      "| Run | Frame (ms, median) | Rays traced | Ray efficiency | Culling FP rate | Lights reaching no "
      "pixel | False negatives | Normal error (°) | Normal image error | World-pos error";
  std::string rule = "|---|--:|--:|--:|--:|--:|--:|--:|--:|--:";
  if (anyImage) out += " | Image error (FLIP)", rule += "|--:";
  if (anyShadow) out += " | Wrongly dark | Wrongly lit", rule += "|--:|--:";
  if (anyAo) out += " | AO time (ms) | d_max (m) | AO error (MAE vs reference)", rule += "|--:|--:|--:";
  if (anyIndirect) out += " | Indirect error (relMSE vs reference)", rule += "|--:";
  if (anyEnv) out += " | Environment time (ms) | Environment error (relMSE vs reference)", rule += "|--:|--:";
  if (anyRoofline) out += " | Fraction of the limit", rule += "|--:";
  out += " | Pareto |\n" + rule + "|:-:|\n";

  std::vector<const AccuracyPoint*> failed;
  for (size_t i = 0; i < runs.size(); ++i) {
    const json& run = runs[i];
    const AccuracyPoint& p = front.points[i];
    const int extra = (anyImage ? 1 : 0) + (anyShadow ? 2 : 0) + (anyAo ? 3 : 0) + (anyIndirect ? 1 : 0) +
                      (anyEnv ? 2 : 0) + (anyRoofline ? 1 : 0);
    out += "| " + escapeCell(p.name) + " | ";
    if (!p.ok) {
      failed.push_back(&p);
      out += "failed";
      for (int c = 0; c < 9 + extra; ++c) out += std::string(" | ") + kDash;
      out += std::string(" | ") + kDash + " |\n";
      continue;
    }
    const json& rays = at(run, "rays");
    const json& cull = at(run, "culling");
    const json& acc = at(run, "accuracy");
    const json& sm = at(acc, "shadow_mismatches");
    out += cell(p.frameMs, "%.3f") + " | " + cell(numberAt(rays, "traced"), "%.0f") + " | " +
           (std::isfinite(numberAt(rays, "efficiency")) ? formatNear1(numberAt(rays, "efficiency"))
                                                        : cell(numberAt(rays, "efficiency"), "%.3f")) +
           " | " + cell(numberAt(cull, "false_positive_rate"), "%.3f") + " | " +
           cell(numberAt(cull, "geometry_false_positive_rate"), "%.3f") + " | " +
           cell(numberAt(cull, "false_negatives"), "%.0f") + " | " +
           cell(numberAt(acc, "normal_angular_error_deg"), "%.2f") + " | " +
           cell(numberAt(acc, "normal_image_error"), "%.4g") + " | " +
           cell(numberAt(acc, "world_pos_rel_error"), "%.2e");
    if (anyImage) out += " | " + cell(numberAt(acc, "image_error"), "%.4g");
    if (anyShadow)
      out += " | " + cell(numberAt(sm, "wrongly_dark"), "%.0f") + " | " + cell(numberAt(sm, "wrongly_lit"), "%.0f");
    if (anyAo) {
      const json& a = at(run, "ambient_occlusion");
      out += " | " + cell(front.measure == AccuracyMeasure::AoError ? p.timeMs : kNaN, "%.3f") + " | " +
             (at(a, "d_max").is_number() ? format("%g", at(a, "d_max").get<double>()) : std::string(kDash)) + " | " +
             cell(numberAt(at(a, "vs_reference"), "mae"), "%.4f");
    }
    if (anyIndirect) out += " | " + cell(numberAt(at(at(run, "indirect"), "vs_reference"), "rel_mse"), "%.4f");
    if (anyEnv)
      out += " | " + cell(front.measure == AccuracyMeasure::EnvironmentError ? p.timeMs : kNaN, "%.3f") + " | " +
             cell(numberAt(at(at(run, "environment_light"), "vs_reference"), "rel_mse"), "%.5f");
    if (anyRoofline) out += " | " + escapeCell(longestPassFraction(run));
    const bool placed = std::isfinite(p.timeMs) && std::isfinite(p.error);
    out += std::string(" | ") + (p.onFront ? "**yes**" : placed ? "no" : kDash) + " |\n";
  }

  out += "\nPareto front: " + front.time + " against " + accuracyMeasureLabel(front.measure) + " = " +
         accuracyMeasureDefinition(front.measure) + ". A run is on the front when no other ok run" +
         (front.groups.size() > 1 ? std::string(front.groups[0].rfind("bounces", 0) == 0 ? " of the same bounce count"
                                                                                         : " of the same d_max") +
                                        " (each against its own reference)"
                                  : std::string()) +
         " is at least as fast and at least as "
         "accurate, and strictly better in one. Surplus rays (1 − ray efficiency) are wasted "
         "work, not error, and do not enter the measure. Culling FP rate: stored (tile, light) pairs whose "
         "light misses the tile's depth-bounded frustum (the thesis's measure); lights reaching no pixel: "
         "stored pairs whose light reaches none of the tile's pixels (what depth slices cut). False "
         "negatives: lights a tile had to keep and lost (the frustum's lights; with depth slices, the "
         "lights reaching a pixel). \"—\": the results do not carry the figure (normal errors: the "
         "variant reconstructs no normals)." +
         std::string(anyRoofline ? " Fraction of the limit: the frame's longest pass with a measured peak, its "
                                   "achieved rate over the device's peak for its bound (roofline.md)."
                                 : "") +
         "\n";
  if (!failed.empty()) {
    out += "\nFailed runs (not on the front):\n";
    for (const AccuracyPoint* p : failed) out += "- " + escapeCell(p->name) + ": " + escapeCell(p->failure) + "\n";
  }
  // Anti-aliasing is one more accuracy-for-time trade: its own table where the runs study it.
  if (const std::string aa = aaTableMarkdown(results); !aa.empty()) out += "\n" + aa;
  return out;
}

namespace {

struct Axis {
  double lo, hi, step;
  int decimals;
};
constexpr int kMaxTicks = 20;  // niceAxis asks for about 6: a bound, whatever the rounding

// Ticks at 1, 2 or 5 × 10^k, about `target` of them, covering [lo, hi].
Axis niceAxis(double lo, double hi, int target) {
  if (!(hi > lo)) {  // one value (or none): open a window around it
    const double pad = std::abs(hi) > 0 ? std::abs(hi) * 0.1 : 1.0;
    lo = lo >= 0 && lo - pad < 0 ? 0 : lo - pad;
    hi += pad;
  }
  const double raw = (hi - lo) / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / mag;
  const double step = (f <= 1 ? 1 : f <= 2 ? 2 : f <= 5 ? 5 : 10) * mag;
  Axis a{std::floor(lo / step) * step, std::ceil(hi / step) * step, step, 0};
  a.decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
  return a;
}

}  // namespace

std::string accuracyReportSvg(const json& results) {
  const AccuracyFront front = accuracyFront(results);

  // Layout (px): plot area left 80..620, top 70..470; legend to the right, as tall as it needs.
  constexpr double kW = 1040, kL = 80, kR = 620, kT = 70, kB = 470;
  const double kH = std::max(540.0, kT + 30 + 18.0 * double(front.points.size()));
  std::vector<const AccuracyPoint*> pts;
  for (const AccuracyPoint& p : front.points)
    if (p.ok && std::isfinite(p.timeMs) && std::isfinite(p.error)) pts.push_back(&p);
  // One group: the front red, the rest blue. Several: a colour a group, its front filled.
  static constexpr const char* kGroupColors[] = {"#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};
  const bool grouped = front.groups.size() > 1;
  auto groupColor = [&](const std::string& g) {
    const size_t i = size_t(std::find(front.groups.begin(), front.groups.end(), g) - front.groups.begin());
    return kGroupColors[i % std::size(kGroupColors)];
  };

  double xMin = INFINITY, xMax = -INFINITY, yMax = 0;
  for (const AccuracyPoint* p : pts) {
    xMin = std::min(xMin, p->timeMs);
    xMax = std::max(xMax, p->timeMs);
    yMax = std::max(yMax, p->error);
  }
  if (pts.empty()) xMin = 0, xMax = 1;
  const Axis xa = niceAxis(xMin, xMax, 6);
  const Axis ya = niceAxis(0, yMax, 5);  // errors are ≥ 0; the axis starts at 0
  // Times spanning more than 30x (AO from screen space to Monte Carlo) on a log axis, by decades.
  const bool logX = xMin > 0 && xMax / xMin > 30;
  const double decLo = logX ? std::floor(std::log10(xMin)) : 0, decHi = logX ? std::ceil(std::log10(xMax)) : 1;
  auto px = [&](double x) {
    return logX ? kL + (std::log10(x) - decLo) / (decHi - decLo) * (kR - kL)
                : kL + (x - xa.lo) / (xa.hi - xa.lo) * (kR - kL);
  };
  auto py = [&](double y) { return kB - (y - ya.lo) / (ya.hi - ya.lo) * (kB - kT); };

  std::string s =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" " +
      format("width=\"%.0f\" height=\"%.0f\" viewBox=\"0 0 %.0f %.0f\"", kW, kH, kW, kH) +
      " font-family=\"sans-serif\" font-size=\"12\">\n"
      "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  s += format("<text x=\"%.0f\" y=\"28\" font-size=\"16\" font-weight=\"bold\">", kL) +
       escapeXml("Accuracy vs time — " + contextLine(results)) + "</text>\n";
  s += format("<text x=\"%.0f\" y=\"48\">", kL) +
       escapeXml("sweep " + sweepName(results) +
                 (grouped ? "; a colour per group, filled: on its group's Pareto front (lower-left is better)"
                          : "; red: Pareto front (lower-left is better)")) +
       "</text>\n";

  // Grid, ticks and tick labels.
  if (logX) {
    for (double d = decLo; d <= decHi && d - decLo <= kMaxTicks; ++d)
      for (double m : {1.0, 2.0, 5.0}) {
        const double v = m * std::pow(10.0, d), x = px(v);
        if (x > kR + 0.5) break;
        s += format("<line x1=\"%.1f\" y1=\"%.0f\" x2=\"%.1f\" y2=\"%.0f\" stroke=\"#e0e0e0\"/>\n", x, kT, x, kB);
        s += format("<text x=\"%.1f\" y=\"%.0f\" text-anchor=\"middle\">%g</text>\n", x, kB + 18, v);
      }
  } else {
    for (int i = 0; i <= kMaxTicks && xa.lo + i * xa.step <= xa.hi + 0.5 * xa.step; ++i) {
      const double v = xa.lo + i * xa.step, x = px(v);
      s += format("<line x1=\"%.1f\" y1=\"%.0f\" x2=\"%.1f\" y2=\"%.0f\" stroke=\"#e0e0e0\"/>\n", x, kT, x, kB);
      s += format("<text x=\"%.1f\" y=\"%.0f\" text-anchor=\"middle\">%.*f</text>\n", x, kB + 18, xa.decimals, v);
    }
  }
  for (int i = 0; i <= kMaxTicks && ya.lo + i * ya.step <= ya.hi + 0.5 * ya.step; ++i) {
    const double v = ya.lo + i * ya.step, y = py(v);
    s += format("<line x1=\"%.0f\" y1=\"%.1f\" x2=\"%.0f\" y2=\"%.1f\" stroke=\"#e0e0e0\"/>\n", kL, y, kR, y);
    s += format("<text x=\"%.0f\" y=\"%.1f\" text-anchor=\"end\">%.*f</text>\n", kL - 6, y + 4, ya.decimals, v);
  }
  s += format(
      "<rect x=\"%.0f\" y=\"%.0f\" width=\"%.0f\" height=\"%.0f\" fill=\"none\" "
      "stroke=\"black\"/>\n",
      kL, kT, kR - kL, kB - kT);
  s += format("<text x=\"%.0f\" y=\"%.0f\" text-anchor=\"middle\">", 0.5 * (kL + kR), kB + 42) +
       escapeXml(front.time + (logX ? ", log scale" : "")) + "</text>\n";
  s += format("<text transform=\"translate(20 %.0f) rotate(-90)\" text-anchor=\"middle\">", 0.5 * (kT + kB)) +
       escapeXml(accuracyMeasureLabel(front.measure)) + "</text>\n";

  // Staircase through the front, sorted by time: right at the current error, then down — the
  // boundary of the region the front dominates.
  for (const std::string& group : front.groups) {
    std::vector<const AccuracyPoint*> fr;
    for (const AccuracyPoint* p : pts)
      if (p->onFront && p->group == group) fr.push_back(p);
    std::sort(fr.begin(), fr.end(), [](auto* a, auto* b) {
      return a->timeMs < b->timeMs || (a->timeMs == b->timeMs && a->error > b->error);
    });
    if (fr.size() < 2) continue;
    s += format("<path d=\"M %.1f %.1f", px(fr[0]->timeMs), py(fr[0]->error));
    for (size_t i = 1; i < fr.size(); ++i) s += format(" H %.1f V %.1f", px(fr[i]->timeMs), py(fr[i]->error));
    s += format("\" fill=\"none\" stroke=\"%s\" stroke-width=\"1.5\" stroke-dasharray=\"4 3\"/>\n",
                grouped ? groupColor(group) : "#d62728");
  }

  // Points numbered in results order, with a legend of full names.
  if (pts.empty())
    s += format("<text x=\"%.0f\" y=\"%.0f\" text-anchor=\"middle\">", 0.5 * (kL + kR), 0.5 * (kT + kB)) +
         escapeXml(front.measure == AccuracyMeasure::None ? "no accuracy measure in the results"
                                                          : "no ok runs to plot") +
         "</text>\n";
  std::vector<std::pair<double, double>> labels;  // placed number labels, to avoid overprinting
  for (size_t i = 0; i < pts.size(); ++i) {
    const AccuracyPoint& p = *pts[i];
    const char* color = grouped ? groupColor(p.group) : p.onFront ? "#d62728" : "#1f77b4";
    const double x = px(p.timeMs), y = py(p.error);
    // data-variant: the run a point stands for, for a page that shows this plot (html_report.h).
    s += "<circle data-variant=\"" + escapeXml(p.name) + "\" " +
         format("cx=\"%.1f\" cy=\"%.1f\" r=\"5\" fill=\"%s\" fill-opacity=\"%s\" stroke=\"%s\"><title>", x, y, color,
                grouped && !p.onFront ? "0" : "0.7", color) +
         escapeXml(p.name + format(": %.3f ms, %.4g", p.timeMs, p.error)) + "</title></circle>\n";
    double lx = x + 6;  // shift right past labels already placed at about the same spot
    // Each move takes lx past one placed label, so there are at most labels.size() of them.
    for (size_t pass = 0, moved = 1; moved && pass <= labels.size(); ++pass) {
      moved = 0;
      for (const auto& [ox, oy] : labels)
        if (std::abs(ox - lx) < 12 && std::abs(oy - (y - 6)) < 11) lx = ox + 12, moved = 1;
    }
    labels.emplace_back(lx, y - 6);
    s += format("<text x=\"%.1f\" y=\"%.1f\" font-size=\"11\" fill=\"%s\">%zu</text>\n", lx, y - 6, color, i + 1);
    s += format("<text x=\"%.0f\" y=\"%.0f\" fill=\"%s\">", kR + 20, kT + 10 + 18.0 * i, color) +
         escapeXml(format("%zu  ", i + 1) + p.name +
                   (grouped && p.name.find(p.group.substr(0, 5)) == std::string::npos ? " [" + p.group + "]" : "") +
                   (p.onFront ? " (front)" : "")) +
         "</text>\n";
  }
  size_t row = pts.size();
  for (const AccuracyPoint& p : front.points)
    if (!p.ok)
      s += format("<text x=\"%.0f\" y=\"%.0f\" fill=\"#777777\">", kR + 20, kT + 10 + 18.0 * row++) +
           escapeXml("failed: " + p.name) + "</text>\n";
  s += "</svg>\n";
  return s;
}

}  // namespace hb

// The accuracy-vs-time report of one sweep: each variant's frame time against its errors, with
// the Pareto front marked, as a Markdown table and an SVG scatter plot. Input is a results file
// (docs/results-format.md); a figure the file lacks prints as "—", never invented.
//
// The accuracy measure of the front (the y axis of the plot) is chosen once per sweep, as the
// first of these that EVERY ok run with a frame time carries, so all points are on one scale:
//   0. AoError: ambient_occlusion.vs_reference.mae, in a sweep of ambient occlusion variants (the
//      AO image against the converged Monte Carlo reference on the same surface);
//   0b. IndirectError: indirect.vs_reference.rel_mse, in a sweep of indirect-light variants (the
//      irradiance's relative MSE against the gathered single bounce on the same surface);
//   1. ImageError: accuracy.image_error, the mean FLIP error against the reference render of the
//      same scene/camera/resolution with no culling (what a viewer would see);
//   2. ShadowMismatchRate: (accuracy.shadow_mismatches.wrongly_dark + .wrongly_lit) /
//      .pairs_compared, the fraction of (pixel, light) pairs whose shadow test is wrong;
//   3. RayDeficit: max(0, rays.oracle − rays.traced) / rays.oracle, a lower bound on the fraction
//      of needed shadow rays that were not traced (counts alone cannot pair rays up).
//   4. None: no measure; no run is on the front.
// Surplus rays (1 − rays.efficiency, traced but not needed) are wasted WORK, not error: they cost
// frame time, which the x axis already shows, and never change the image.
//
// A run is on the Pareto front when no other ok run is at least as fast (median frame_ms) AND at
// least as accurate (lower or equal measure), strictly better in one. Runs with identical time
// and error are therefore both on the front. Runs whose status is not "ok" are listed as failed
// and never take part in the front.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace hb {

enum class AccuracyMeasure {
  AoError,
  EnvironmentError,
  IndirectError,
  ImageError,
  ShadowMismatchRate,
  RayDeficit,
  None
};

// Short axis label ("image error (FLIP mean)") and a one-sentence definition for the report.
const char* accuracyMeasureLabel(AccuracyMeasure m);
std::string accuracyMeasureDefinition(AccuracyMeasure m);

struct AccuracyPoint {
  std::string name;
  bool ok = false;       // status == "ok"
  std::string failure;   // the run's "error" (or status) when not ok
  double frameMs = 0;    // median frame_ms; NaN when absent
  double timeMs = 0;     // the x coordinate: frameMs, or for AO the effect's own passes (AccuracyFront::time)
  double error = 0;      // the sweep's accuracy measure; NaN when absent or measure None
  std::string group;     // runs are compared within their group only ("" for all; AO: "d_max = 1 m")
  bool onFront = false;  // false for failed runs and runs with a NaN coordinate
};

struct AccuracyFront {
  AccuracyMeasure measure = AccuracyMeasure::None;
  // What timeMs is: "frame time, median (ms)", or with the AO error "AO time: ldm_build +
  // ambient_occlusion medians (ms)" (the passes that differ between AO methods; the rest of the
  // frame is the same for all). AO runs are grouped by d_max: each is measured against the
  // reference of its own d_max, so only runs of one d_max are compared.
  std::string time = "frame time, median (ms)";
  std::vector<AccuracyPoint> points;  // one per run, in results order
  std::vector<std::string> groups;    // the distinct groups, in order of first appearance
};

// Chooses the measure and marks the front. Throws InputError when `results` is not a schema-1
// results file with a "runs" array.
AccuracyFront accuracyFront(const nlohmann::json& results);

// Markdown: a heading naming sweep, device, resolution and scene; a table with one row per run in
// results order (failed runs as "failed" rows with "—" figures); then the measure definition and
// the failed runs' errors. Columns "Image error (FLIP)" and "Wrongly dark/lit" appear only when
// some run carries them. Throws as accuracyFront.
std::string accuracyReportMarkdown(const nlohmann::json& results);

// A self-contained SVG 1.1 document: x = the front's time (ms), y = the accuracy measure (from
// 0), one <circle> per ok run with both coordinates, numbered, with a legend of full names; the
// front in red joined by a staircase (the boundary of the dominated region); with several groups,
// a colour and a staircase per group, its front filled, the rest hollow. Title names
// context.device.name and context.resolution. Text is XML-escaped. Throws as accuracyFront.
std::string accuracyReportSvg(const nlohmann::json& results);

}  // namespace hb

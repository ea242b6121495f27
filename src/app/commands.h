// The subcommands of the CLI (main.cpp parses flags and calls these). Each returns the process
// exit code; user errors throw InputError (exit 2), device failures DeviceError (exit 3).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "report/compare.h"
#include "report/history.h"
#include "report/noise_model.h"
#include "scene/scene.h"

namespace hb {

class Renderer;

int cmdDevices(bool json);
// The device's own ceilings (gpu/peaks.h): measured afresh, printed (a table, or JSON with json),
// and written to the peaks cache (without the ray rates, which are measured on `scene`: a built-in
// name or a glTF path). device: index or name substring (empty: device 0).
int cmdPeaks(const std::string& device, const std::string& scene, bool json);

struct RenderOptions {
  std::string config;             // optional config file; its defaults apply
  std::string scene = "atrium";   // built-in name or glTF path
  bool sceneGiven = false;        // --scene was on the command line (it wins over a config's scene)
  std::string size;               // "WxH" (empty: config's or 1920x1080)
  std::string device;             // index or name substring
  std::vector<std::string> sets;  // key=value overrides
  std::string out;                // output directory (required)
  bool force = false;             // out holds a render.json: move the folder's files aside first
  std::string raysOut;            // the frame's own rays as ray files here (writeFrameRayFiles)
};
int cmdRender(const RenderOptions& options);

// `rays export`: the ray sets of reference/ray_sets.h from a scene's first camera at `size`, one
// ray file each (NAME.bin and NAME.json in out).
struct RaysExportOptions {
  std::string scene = "atrium";                 // built-in name or glTF path
  std::string size;                             // "WxH" (empty: 1920x1080)
  std::string kind = "all";                     // camera | ao | shadow | all
  std::string out;                              // folder (created)
  double offset = 1e-3;                         // ao, shadow: off the surface along the geometric normal
  double aoTMax = 1.0;                          // ao: the rays' length
  uint64_t seed = 1;                            // ao: the directions' seed
  std::vector<double> light = {0.0, 6.0, 0.0};  // shadow: the point light
};
int cmdRaysExport(const RaysExportOptions& options);
// `render --rays-out DIR`: the rays the frame traced, rebuilt from its analysis frame
// (analysis/frame_rays.h): frame-shadow.bin, and frame-ao.bin where AO is ray traced. The check
// throws InputError (one line) when the frame has none to give: call it before anything is written.
void checkFrameRaysOut(const Renderer& renderer);
std::vector<std::string> writeFrameRayFiles(const Renderer& renderer, const std::string& dir);
// `rays table FILE.json...`: raybench --json files side by side, one row a file (its rays' kind and
// the revision that traced them), one column a backend, in G rays/s (the docs' generated tables);
// `work`: then the traversal's work a ray that each file carries; `compiled`: first what the driver
// compiled each compute kernel into, where the files carry it.
int cmdRaysTable(const std::vector<std::string>& files, bool work, bool compiled = false);
// `raybench FILE.bin`: the file through every backend, timed (median and spread), each backend's
// hits against the CPU's double-precision ones; refused in one line when the file is of another
// scene than `scene` (default: the scene the file names, a built-in).
struct RaybenchOptions {
  std::string file;
  std::string scene;
  std::string device;
  std::string json;     // write the figures here too
  std::string hitsOut;  // folder: each backend's hits a ray (t, triangle, barycentrics), and the CPU's
};
int cmdRaybench(const RaybenchOptions& options);

// Several files: their runs one after another under the first file's context (a study whose runs
// did not fit one sweep); refused unless every file was measured on a device of the same name.
// A variant in two files is refused unless allowDuplicates; then each row's name carries its file.
int cmdTables(const std::vector<std::string>& resultsPaths, const std::string& format, bool allowDuplicates = false,
              const std::vector<std::string>& ceilingPaths = {});
// `merge`: the parts of one sweep (`sweep --shard K/N`, one folder each) as one results folder in
// out: every variant of the config once, in config order, with its images. Throws InputError when
// the parts' config, scene hash, revision or device name differ (force: devices may, and each run
// records its own), a variant is in no part or in two, or out holds results (force: moved aside).
int cmdMerge(const std::vector<std::string>& dirs, const std::string& out, bool force);
// format: md (a Markdown table), json or junit (formatCompareJunit).
// noise: the noise file to read into options.noise ("" for none).
int cmdCompare(const std::string& a, const std::string& b, CompareOptions options, const std::string& format,
               const std::string& noise);

// `hybridbench noise A1 B1 [A2 B2 ...]`: the between-run noise model of A/A pairs
// (report/noise_model.h), printed with its false alarms and detection; --out writes the noise file.
struct NoiseOptions {
  std::vector<std::string> pairs;
  std::string out;
  double thresholdPct = 5, plantedPct = 5;
  size_t trials = 100;
  bool noCheck = false;
};
int cmdNoise(const NoiseOptions& options);
// A noise file's model (InputError naming the path when it is not one).
NoiseModel readNoiseFile(const std::string& path);

// `history`: many results files (or folders searched for results.json and results.json.gz) as series
// over time, their changes found by E-divisive (report/history.h): a Markdown table on stdout, the
// series and changes as JSON (json) and an HTML page of plots (html: the series with changes, every
// series with allSeries). With gate, exit 1 when some series' newest segment is slower.
struct HistoryCommand {
  std::vector<std::string> paths;
  HistoryOptions options;
  std::string json;  // file to write, or empty
  std::string html;  // file to write, or empty
  bool allSeries = false;
  bool gate = false;
};
int cmdHistory(const HistoryCommand& command);

// `report`: the page of a results file (report/html_report.h) written to out, with the images of
// the variants found beside the results file; with compare, the comparison against that base.
struct ReportOptions {
  std::string results;  // results.json
  std::string compare;  // base results.json (A), or empty
  std::string out;      // the page to write (its folder must exist)
  CompareOptions compareOptions;
  std::string noise;  // a noise file for the comparison, or empty
};
int cmdReport(const ReportOptions& options);

// --no-camera / --no-lights leave them out: a file like most glTF assets, for the automatic ones.
int cmdSceneExport(const std::string& name, const std::string& out, bool noCamera = false, bool noLights = false);
int cmdSceneInfo(const std::string& path, bool json);
// Lists the built-in scenes (name, triangles, lights, a one-line description) and the .gltf/.glb
// files in a scenes folder and its subfolders (path, triangles, lights, what the file's
// extras.effects calls for; a file that does not load is listed with its error, and the listing
// still succeeds). dir: that folder; empty: ./scenes when the current directory has one, else the
// scenes/ of the repository the executable sits in (the nearest of its ancestor directories that
// holds both scenes/ and CMakeLists.txt), else none. Throws InputError when a given dir is not a
// directory.
int cmdSceneList(const std::string& dir, bool json);

// `help params|effects`: the config parameters or the effects as a table printed from the schema
// the parser uses. format: md (GitHub Markdown tables, for generated docs), text or json. Throws
// InputError for an unknown topic or format. helpText is what cmdHelp prints.
std::string helpText(const std::string& topic, const std::string& format);
int cmdHelp(const std::string& topic, const std::string& format);

// A built-in scene name (see builtinSceneNames) or a path to a .gltf/.glb file.
Scene loadSceneArg(const std::string& nameOrPath);

// "1920x1080" → width, height. Throws InputError naming the flag.
void parseSize(const std::string& text, uint32_t& width, uint32_t& height, const std::string& what);

}  // namespace hb

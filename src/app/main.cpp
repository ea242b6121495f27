// hybridbench: a headless benchmark of hybrid rendering, rasterization with ray tracing (see README.md).
#include <cstdio>
#include <exception>
#include <map>
#include <string>

#include <CLI/CLI.hpp>

#include "app/cli_suggest.h"
#include "app/commands.h"
#include "app/sweep.h"
#include "app/sweep_worker.h"
#include "base/errors.h"
#include "base/version.h"
#include "gpu/vk_context.h"

int main(int argc, char** argv) {
  // A sweep runs its variants in this same executable, started again as a worker (sweep_worker.h).
  hb::setSweepWorkerExecutable("/proc/self/exe");
  using namespace hb;
  CLI::App app{
      "hybridbench: a headless Vulkan benchmark of hybrid rendering, rasterization with ray tracing: the thesis's "
      "Forward+ with ray-traced shadows, 3D rasterization, and layered depth maps for ambient occlusion, indirect "
      "and environment light. It sweeps variants, times each GPU pass, counts rays against the minimum needed, "
      "measures accuracy against exact references, and compares runs."};
  app.set_version_flag("--version", toolVersion() + " (" + gitRevision() + ")");
  app.require_subcommand(0, 1);

  bool devicesJson = false;
  auto* devices = app.add_subcommand("devices", "list Vulkan devices and their ray-tracing support");
  devices->add_flag("--json", devicesJson, "machine-readable output");

  bool peaksJson = false;
  std::string peaksDevice, peaksScene = "atrium";
  auto* peaksCmd = app.add_subcommand(
      "peaks", "measure the device's own ceilings: memory bandwidth, atomics, FP32 FMA, the rasterizer");
  peaksCmd->add_option("--device", peaksDevice, "device index or name substring");
  peaksCmd->add_option("--scene", peaksScene,
                       "built-in scene name or .gltf/.glb path whose TLAS the ray rates use (default atrium)");
  peaksCmd->add_flag("--json", peaksJson, "machine-readable output");

  RenderOptions render;
  auto* renderCmd = app.add_subcommand("render", "render one frame and write its images and statistics");
  renderCmd->add_option("config", render.config, "config file whose defaults apply");
  auto* sceneOpt = renderCmd->add_option("--scene", render.scene, "built-in scene name or .gltf/.glb path");
  renderCmd->add_option("--size", render.size, "resolution WxH, e.g. 1920x1080");
  renderCmd->add_option("--device", render.device, "device index or name substring");
  renderCmd->add_option("--set", render.sets, "parameter override key=value (repeatable)")->allow_extra_args(false);
  renderCmd->add_option("--out", render.out, "output directory")->required();
  renderCmd->add_option("--rays-out", render.raysOut,
                        "write the rays the frame traced (its shadow rays after culling, its ray-traced AO's) as ray "
                        "files here");
  renderCmd->add_flag("--force", render.force,
                      "--out holds a render: move its files to --out/previous-<time>/ and write afresh");

  SweepOptions sweep;
  bool noImages = false;
  auto* sweepCmd =
      app.add_subcommand("sweep", "run a benchmark sweep from a config (default: the embedded thesis.json)");
  sweepCmd->add_option("config", sweep.config, "config file (JSON)");
  sweepCmd->add_option("--device", sweep.device,
                       "device index, name substring, a comma-separated list of them (0,1), or all; several sweep "
                       "concurrently, one folder each");
  sweepCmd->add_option("--out", sweep.out, "results directory (default out/<config>-<device>-<time>-<git>)");
  sweepCmd->add_flag("--resume", sweep.resume, "continue the sweep in --out: skip the variants it finished");
  sweepCmd->add_flag("--force", sweep.force,
                     "--out holds results: move them to --out/previous-<time>/ and start afresh");
  sweepCmd->add_option("--frames", sweep.frames, "measured frames per variant (overrides the config)")
      ->check(CLI::Range(1, 1000000));
  sweepCmd->add_option("--warmup", sweep.warmup, "warm-up frames per variant (overrides the config)")
      ->check(CLI::Range(0, 100000));
  sweepCmd->add_flag("--no-images", noImages, "write no per-variant images");
  sweepCmd->add_option("--scene", sweep.scene, "built-in scene name or .gltf/.glb path (instead of the config's)");
  sweepCmd->add_option("--size", sweep.size, "resolution WxH of every variant, e.g. 1280x720");
  sweepCmd->add_option("--set", sweep.sets, "parameter or effect for every variant, key=value (repeatable)")
      ->allow_extra_args(false);
  sweepCmd
      ->add_option("--variant-timeout", sweep.variantTimeout,
                   "seconds a variant may run before the watchdog ends it and the sweep goes on (default: 600, or "
                   "2 s a frame where that is longer)")
      ->check(CLI::PositiveNumber);
  sweepCmd->add_flag("--retry-failed", sweep.retryFailed,
                     "with --resume: run again the variants that timed out or crashed");
  sweepCmd->add_option("--worker-fd", sweep.workerFd)->group("");  // internal: the variants' child process
  sweepCmd->add_option("--worker-variants", sweep.workerVariants)->group("");
  sweepCmd->add_flag("--dry-run", sweep.dryRun,
                     "print the variants with their parameters, the frame count and a time estimate; run nothing");
  sweepCmd->add_option("--shard", sweep.shard,
                       "K/N: run only the K-th (from 0) of N parts of the variants, balanced by estimated cost; "
                       "merge the parts with 'hybridbench merge' (docs/fleet.md)");

  std::vector<std::string> mergeDirs;
  std::string mergeOut;
  bool mergeForce = false;
  auto* mergeCmd =
      app.add_subcommand("merge", "combine the folders of a sweep's parts (sweep --shard K/N) into one results folder");
  mergeCmd->add_option("dirs", mergeDirs, "the parts' output folders (each holds results.json)")->required();
  mergeCmd->add_option("--out", mergeOut, "the merged results folder")->required();
  mergeCmd->add_flag("--force", mergeForce,
                     "merge parts from devices of different names (each run records its own), and move earlier "
                     "results in --out to --out/previous-<time>/");

  std::vector<std::string> tablesPaths;
  std::string tablesFormat = "md";
  auto* tablesCmd = app.add_subcommand("tables", "regenerate the thesis tables from a results file");
  tablesCmd
      ->add_option("results", tablesPaths,
                   "results.json; several files of one study on one kind of device are read as one (their runs "
                   "in order)")
      ->required();
  tablesCmd
      ->add_option("--format", tablesFormat,
                   "md (thesis tables + accuracy-vs-time report + roofline table), csv (thesis tables), svg "
                   "(accuracy-vs-time plot), accuracy (the accuracy-vs-time report alone), roofline (the device's "
                   "peaks and the roofline table), roofline-svg (the roofline plot), built (what the frame built "
                   "once: BVHs, LDM sets, with build time and memory)")
      ->check(CLI::IsMember({"md", "csv", "svg", "accuracy", "roofline", "roofline-svg", "built"}));
  bool tablesAllowDuplicates = false;
  tablesCmd->add_flag("--allow-duplicates", tablesAllowDuplicates,
                      "read files that hold the same variant; every row is then named with its file");
  std::vector<std::string> tablesCeiling;
  tablesCmd->add_option("--ceiling", tablesCeiling,
                        "with --format roofline: a results.json of configs/ceilings*.json from the same device "
                        "(repeatable); a loop's steps (no device peak counts them) are rated against the same "
                        "pass there");

  std::string compareA, compareB;
  CompareOptions compareOpts;
  bool compareJson = false;
  std::string compareFormat = "md";
  auto* compareCmd = app.add_subcommand("compare", "compare two results files (B against A); exit 1 on a regression");
  compareCmd->add_option("a", compareA, "baseline results.json")->required();
  compareCmd->add_option("b", compareB, "candidate results.json")->required();
  compareCmd->add_option("--threshold", compareOpts.thresholdPct,
                         "slower beyond this many percent is a regression (default 5)");
  compareCmd->add_option("--alpha", compareOpts.alpha, "significance level of the Mann-Whitney U test (default 0.05)");
  compareCmd->add_flag("--force", compareOpts.force, "compare even when scenes or configs differ");
  std::string compareGate = "frame";
  compareCmd
      ->add_option("--gate", compareGate, "which slower rows are a regression (exit 1): frame (default), passes or all")
      ->check(CLI::IsMember({"frame", "passes", "all"}));
  compareCmd->add_option("--min-ms", compareOpts.minMs,
                         "a pass under this median (ms) on both sides is reported but does not gate (default 0: each "
                         "row's floor, from the timestamps' resolution and the noise file's launch jitter)");
  std::string compareNoise;
  compareCmd->add_option(
      "--noise", compareNoise,
      "a noise file ('hybridbench noise'): gate only beyond the between-run spread of A/A pairs too");
  compareCmd->add_flag("--json", compareJson, "machine-readable report (the same as --format json)");
  compareCmd
      ->add_option("--format", compareFormat,
                   "md (default: a Markdown table, also for a CI job summary), json, junit (JUnit XML: a test case per "
                   "variant and pass, failed when slower)")
      ->check(CLI::IsMember({"md", "json", "junit"}));
  const CLI::Option* compareFormatOpt = compareCmd->get_option("--format");

  std::vector<std::string> noisePaths;
  NoiseOptions noiseOpts;
  auto* noiseCmd = app.add_subcommand(
      "noise", "the between-run noise of A/A pairs (a noise file for compare --noise), its false alarms and detection");
  noiseCmd
      ->add_option("pairs", noisePaths, "A/A pairs of results files: A1 B1 [A2 B2 ...] (the same config swept twice)")
      ->required();
  noiseCmd->add_option("--out", noiseOpts.out, "write the noise file here (JSON)");
  noiseCmd->add_option("--threshold", noiseOpts.thresholdPct, "compare's threshold in the check (default 5)");
  noiseCmd->add_option("--planted", noiseOpts.plantedPct,
                       "the slowdown planted in the detection trials, % (default 5)");
  noiseCmd->add_option("--trials", noiseOpts.trials, "resamples per A/A row in the detection trials (default 100)");
  noiseCmd->add_flag("--no-check", noiseOpts.noCheck, "write the model only: no false-alarm or detection trials");

  ReportOptions report;
  std::string reportGate = "frame";
  auto* reportCmd = app.add_subcommand(
      "report", "write one HTML page of a results file: context, tables, times, plots, images (report.html)");
  reportCmd->add_option("results", report.results, "results.json")->required();
  reportCmd->add_option("--compare", report.compare, "base results.json (A): add the comparison B/A against it");
  reportCmd->add_option("--out", report.out, "the page to write, e.g. report.html")->required();
  reportCmd->add_option("--threshold", report.compareOptions.thresholdPct, "as compare's (default 5)");
  reportCmd->add_option("--alpha", report.compareOptions.alpha, "as compare's (default 0.05)");
  reportCmd->add_option("--gate", reportGate, "as compare's: frame (default), passes or all")
      ->check(CLI::IsMember({"frame", "passes", "all"}));
  reportCmd->add_option("--min-ms", report.compareOptions.minMs, "as compare's (default 0)");
  reportCmd->add_option("--noise", report.noise, "as compare's: a noise file");
  reportCmd->add_flag("--force", report.compareOptions.force, "compare even when scenes or configs differ");

  HistoryCommand history;
  auto* historyCmd = app.add_subcommand(
      "history", "the runs of many results files as series over revisions, and where they changed (E-divisive)");
  historyCmd
      ->add_option("paths", history.paths,
                   "results files (results.json, results.json.gz, any name) or folders searched for them")
      ->required();
  historyCmd->add_option("--threshold", history.options.thresholdPct,
                         "report a change only when the level moves by more than this many percent (default 5)");
  historyCmd->add_option("--alpha", history.options.alpha, "significance level of each split's test (default 0.01)");
  historyCmd
      ->add_option("--test", history.options.test,
                   "how a split is tested: welch (default: Welch's t-test of the two sides, as Apache Otava) or "
                   "permutation (Matteson & James's, 999 permutations: needs long series)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, HistoryTest>{
          {"welch", HistoryTest::Welch}, {"permutation", HistoryTest::Permutation}}));
  historyCmd
      ->add_option("--min-segment", history.options.minSegment,
                   "the fewest runs between two changes (default 2: one run alone is not a change)")
      ->check(CLI::PositiveNumber);
  historyCmd
      ->add_option("--min-ms", history.options.minMs,
                   "a change whose levels are both under this many ms never gates (default 0: each change's floor, "
                   "twice its runs' timestamp resolution, decides)")
      ->check(CLI::NonNegativeNumber);
  historyCmd->add_option("--json", history.json, "write the series and changes as JSON to this file");
  historyCmd->add_option("--html", history.html, "write a page with one plot per series that changed");
  historyCmd->add_flag("--all-series", history.allSeries,
                       "with --html: plot every series, not only those that changed");
  historyCmd->add_flag("--gate", history.gate,
                       "exit 1 when some series' newest segment is slower than the one before beyond the threshold");

  RaysExportOptions raysExport;
  auto* raysCmd = app.add_subcommand("rays", "write ray files another tracer can trace (rays export)");
  raysCmd->require_subcommand(1);
  auto* raysExportCmd = raysCmd->add_subcommand(
      "export", "write the camera, AO and shadow rays of a scene's first camera as ray files (NAME.bin + NAME.json)");
  raysExportCmd->add_option("--scene", raysExport.scene, "built-in scene name or .gltf/.glb path (default atrium)");
  raysExportCmd->add_option("--size", raysExport.size, "image size WxH of the camera rays (default 1920x1080)");
  raysExportCmd->add_option("--kind", raysExport.kind, "camera, ao, shadow or all (default)")
      ->check(CLI::IsMember({"camera", "ao", "shadow", "all"}));
  raysExportCmd->add_option("--out", raysExport.out, "output folder")->required();
  raysExportCmd->add_option("--offset", raysExport.offset, "ao, shadow: start this far off the surface (default 0.001)")
      ->check(CLI::PositiveNumber);
  raysExportCmd->add_option("--ao-t-max", raysExport.aoTMax, "ao: the rays' length (default 1)")
      ->check(CLI::PositiveNumber);
  raysExportCmd->add_option("--seed", raysExport.seed, "ao: the directions' seed (default 1)");
  raysExportCmd->add_option("--light", raysExport.light, "shadow: the point light x y z (default 0 6 0)")->expected(3);
  std::vector<std::string> raysTableFiles;
  auto* raysTableCmd = raysCmd->add_subcommand(
      "table", "raybench --json files side by side: a row a file, a column a backend, in G rays/s");
  raysTableCmd->add_option("files", raysTableFiles, "files written by raybench --json")->required();
  bool raysTableWork = false;
  raysTableCmd->add_flag("--work", raysTableWork, "then the traversal's work a ray each file carries");
  bool raysTableCompiled = false;
  raysTableCmd->add_flag("--compiled", raysTableCompiled,
                         "then what the driver compiled each kernel into (registers, local memory, ...)");
  RaybenchOptions raybench;
  auto* raybenchCmd =
      app.add_subcommand("raybench", "trace a ray file with every backend: rays/s and hits against the CPU's");
  raybenchCmd->add_option("file", raybench.file, "the ray file's .bin (its .json beside it)")->required();
  raybenchCmd->add_option(
      "--scene", raybench.scene,
      "the scene the rays are of: a built-in name or .gltf/.glb path (default: the file's, built-in)");
  raybenchCmd->add_option("--device", raybench.device, "device index or name substring");
  raybenchCmd->add_option("--json", raybench.json, "write the figures to this file too");
  raybenchCmd->add_option("--hits-out", raybench.hitsOut,
                          "folder: each backend's hit a ray (t, triangle id, barycentrics) and the CPU's, "
                          "BACKEND.hits.bin + hits.json");

  auto* sceneCmd = app.add_subcommand("scene", "export, inspect or list scenes");
  sceneCmd->require_subcommand(1);
  std::string exportName, exportOut, infoPath;
  bool infoJson = false;
  auto* exportCmd = sceneCmd->add_subcommand("export", "write a built-in scene as glTF");
  exportCmd->add_option("name", exportName, "built-in scene name")->required();
  exportCmd->add_option("out", exportOut, "output .gltf or .glb")->required();
  bool exportNoCamera = false, exportNoLights = false;
  exportCmd->add_flag("--no-camera", exportNoCamera, "leave the cameras out (what most glTF assets look like)");
  exportCmd->add_flag("--no-lights", exportNoLights, "leave the lights out");
  auto* infoCmd = sceneCmd->add_subcommand("info", "print a scene's statistics");
  infoCmd->add_option("path", infoPath, "built-in scene name or .gltf/.glb path")->required();
  infoCmd->add_flag("--json", infoJson, "machine-readable output");
  std::string listDir;
  bool listJson = false;
  auto* listCmd = sceneCmd->add_subcommand("list", "list the built-in scenes and the .gltf/.glb files in scenes/");
  listCmd->add_option("--dir", listDir,
                      "folder to list (default: ./scenes, else the executable's repository's scenes/)");
  listCmd->add_flag("--json", listJson, "machine-readable output");

  std::string helpTopic, helpFormat = "text";
  auto* helpCmd =
      app.add_subcommand("help", "print the config parameters or the effects as a table (from the code's schema)");
  helpCmd->add_option("topic", helpTopic, "params or effects");
  helpCmd->add_option("--format", helpFormat, "text (default), md (GitHub Markdown tables) or json");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // A typo of a command or flag gets a did-you-mean; other refusals keep CLI11's message.
    const std::string typo = suggestForUnknownArgument(app, std::vector<std::string>(argv + 1, argv + argc));
    if (!typo.empty())
      std::fprintf(stderr, "hybridbench: %s\n", typo.c_str());
    else
      std::fprintf(stderr, "hybridbench: %s (see hybridbench --help)\n", e.what());
    return kExitBadInput;
  }

  try {
    gpuTimeoutSeconds();  // a malformed HYBRIDBENCH_GPU_TIMEOUT_S is bad input before anything is written
    if (*devices) return cmdDevices(devicesJson);
    if (*peaksCmd) return cmdPeaks(peaksDevice, peaksScene, peaksJson);
    if (*renderCmd) {
      render.sceneGiven = sceneOpt->count() > 0;
      return cmdRender(render);
    }
    if (*sweepCmd) {
      sweep.images = !noImages;
      return cmdSweep(sweep);
    }
    if (*tablesCmd) return cmdTables(tablesPaths, tablesFormat, tablesAllowDuplicates, tablesCeiling);
    if (*mergeCmd) return cmdMerge(mergeDirs, mergeOut, mergeForce);
    if (*compareCmd) {
      if (compareJson && compareFormatOpt->count() > 0 && compareFormat != "json")
        throw InputError("compare: --json and --format " + compareFormat +
                         " contradict each other (--json is --format json); give one");
      compareOpts.gate = compareGate == "all"      ? CompareGate::All
                         : compareGate == "passes" ? CompareGate::Passes
                                                   : CompareGate::Frame;
    }
    if (*compareCmd)
      return cmdCompare(compareA, compareB, compareOpts, compareJson ? "json" : compareFormat, compareNoise);
    if (*noiseCmd) {
      noiseOpts.pairs = noisePaths;
      return cmdNoise(noiseOpts);
    }
    if (*reportCmd) {
      report.compareOptions.gate = reportGate == "all"      ? CompareGate::All
                                   : reportGate == "passes" ? CompareGate::Passes
                                                            : CompareGate::Frame;
      return cmdReport(report);
    }
    if (*historyCmd) return cmdHistory(history);
    if (*raysExportCmd) return cmdRaysExport(raysExport);
    if (*raysTableCmd) return cmdRaysTable(raysTableFiles, raysTableWork, raysTableCompiled);
    if (*raybenchCmd) return cmdRaybench(raybench);
    if (*exportCmd) return cmdSceneExport(exportName, exportOut, exportNoCamera, exportNoLights);
    if (*infoCmd) return cmdSceneInfo(infoPath, infoJson);
    if (*listCmd) return cmdSceneList(listDir, listJson);
    if (*helpCmd) return cmdHelp(helpTopic, helpFormat);
    // No subcommand: the main job, the embedded default sweep (configs/thesis.json) on device 0.
    return cmdSweep(SweepOptions{});
  } catch (const InputError& e) {
    std::fprintf(stderr, "hybridbench: %s\n", e.what());
    return kExitBadInput;
  } catch (const DeviceError& e) {
    std::fprintf(stderr, "hybridbench: device failure: %s\n", e.what());
    return kExitDeviceFailure;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hybridbench: internal error: %s\n", e.what());
    return kExitDeviceFailure;
  }
}

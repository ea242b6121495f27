// What makes two results files (or two parts of one sweep) runs of the same thing, and what only
// says where their inputs lay (docs/results-format.md#identity). A scene is its content:
// context.scene.sha256 (a built-in also its name and scene_params, which the config holds); an
// environment image likewise (context.scene.environment_sha256). The absolute paths a config
// records (its glTF scene, its environment image, context.config_file) are a checkout's own: a
// baseline swept on one machine and a run on another differ there and nowhere else.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace hb::results {

// An effective config (context.config) with the paths of its files (a glTF scene, an environment
// image) replaced by "(a file)": what two sweeps must agree on. Other fields are kept as they are.
nlohmann::json configIdentity(nlohmann::json config);

// The paths of a results' inputs as its context records them: {"config": context.config_file,
// "scene": the config's glTF scene, "environment": the config's environment image}, each only
// where recorded (a built-in scene has no path; an embedded config no file).
nlohmann::json inputPaths(const nlohmann::json& context);

// An input that two contexts name by different paths.
struct MovedInput {
  std::string what;  // "config", "scene" or "environment" (inputPaths' keys)
  std::string a, b;  // the paths
};

// The inputs whose paths differ between two results' contexts (context.config_file, the config's
// glTF scene and environment image), in that order; empty when every path agrees or a side does not
// record one.
std::vector<MovedInput> movedInputs(const nlohmann::json& contextA, const nlohmann::json& contextB);

// One line for a warning: `the inputs lie at other paths, their content the same (scene sha256
// 4bbad0b1...): scene (A: "/x/scenes/cornell-box.gltf", B: "/y/scenes/cornell-box.gltf"); config
// (...)`; without sameContent (a forced comparison of different scenes) only "the inputs lie at
// other paths: ...". moved must not be empty.
std::string describeMovedInputs(const std::vector<MovedInput>& moved, const nlohmann::json& contextA, bool sameContent,
                                const std::string& labelA, const std::string& labelB);

// The content hashes of the inputs that must agree (context.scene.sha256, and
// context.scene.environment_sha256 where both record it): "" when they agree, else one line that
// names the field and both hashes in full, e.g. `the scenes differ in content: context.scene.sha256
// is 4bbad0b1... in A and 90c1e2... in B`.
std::string contentDifference(const nlohmann::json& contextA, const nlohmann::json& contextB, const std::string& labelA,
                              const std::string& labelB);

// The ray tracer that traced the runs (runs[].backend_choice.ran: "compute", "pipeline",
// "rayquery"), as the report and tables show it: "compute" when every run that traced agrees,
// "compute (3 runs: a, b, c), pipeline (1 run: d)" when runs differ; where no run records one
// (files written before backend_choice), the device's (context.device.rt_backend) with "(the
// device's; the runs record no backend_choice)"; "" when neither is known.
std::string tracedBy(const nlohmann::json& results);

// The ray tracer of one run (runs[k]: its backend_choice.ran), "" when it records none.
std::string tracerOfRun(const nlohmann::json& run);

// The warning of a measurement whose GPU was throttled (its telemetry.warning, gpu/telemetry.h):
// a run of a results file, a render.json or peaks --json; "" when there is none.
std::string throttleWarningOf(const nlohmann::json& measured);

}  // namespace hb::results

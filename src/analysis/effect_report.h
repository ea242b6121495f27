// What an effect's report hook (plan/effect.h EffectDef::report) is given after an analysis
// frame: the frame, the readbacks every report shares (read once), and where its results go —
// its key in render.json / the results run, its images, its console summary lines and the run's
// accuracy figures (docs/results-format.md).
#pragma once
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/culling_analysis.h"
#include "base/image_io.h"
#include "config/config.h"
#include "frame/renderer.h"

namespace hb {

struct ReferenceFrame;

// Writes an image (name relative to the run's directory; PNG text chunks) when images are on.
struct ImageWriter {
  std::function<void(const std::string&, const ImageRGBA8&, std::map<std::string, std::string>)> write;
  void operator()(const std::string& name, const ImageRGBA8& image,
                  std::map<std::string, std::string> text = {}) const {
    write(name, image, std::move(text));
  }
};

struct EffectReport {
  const VulkanContext& ctx;
  const Renderer& renderer;
  const Scene& scene;
  const VariantParams& params;
  const ReferenceFrame* reference;  // null: accuracy against the reference is not measured
  bool writeImages;
  nlohmann::json& run;       // the run's object: the effect writes run[its name], and may add
                             // shared keys ("backend", "rays", "culling.*")
  nlohmann::json& accuracy;  // the run's "accuracy" object
  std::vector<std::string>& summary;
  ImageWriter write;
  std::function<void(const char* stage)> lap;  // records the analysis's wall time per stage
  // Shared readbacks.
  const std::vector<float>& depth;
  const CullingReadback& culling;  // empty unless the frame has light lists and a perspective view
  CullingInputs& cullingInputs;    // what the light culling saw
  bool perspective;                // the CPU references reconstruct perspective views only
};

}  // namespace hb

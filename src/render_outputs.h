// What an analysis frame produces: images (depth, colour, per-light visibility, normals, heatmaps)
// and the JSON of its statistics (culling, rays, accuracy). Used by `render` and by the sweep's
// analysis frame. Precondition: renderer.renderFrame(true) was the last frame.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "config.h"
#include "renderer.h"

namespace hb {

struct RenderOutputs {
  nlohmann::json json;               // passes_run, passes_skipped, culling, rays, accuracy, images
  std::vector<std::string> files;    // written, relative to the output directory
  std::vector<std::string> summary;  // lines for the console
};

// Writes the images into dir (created if needed) and returns the statistics. writeImages=false
// computes the statistics only.
RenderOutputs writeRenderOutputs(const VulkanContext& ctx, const Renderer& renderer, const Scene& scene,
                                 const VariantParams& params, const std::string& dir, bool writeImages = true);

}  // namespace hb

// What an analysis frame produces: images (depth, colour, per-light visibility, normals, heatmaps)
// and the JSON of its statistics (culling, rays, accuracy). Used by `render` and by the sweep's
// analysis frame. Precondition: renderer.renderFrame(true) was the last frame.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/image_io.h"
#include "config/config.h"
#include "frame/renderer.h"

namespace hb {

struct RenderOutputs {
  nlohmann::json json;               // passes_run, passes_skipped, culling, rays, accuracy, images
  std::vector<std::string> files;    // written, relative to the output directory
  std::vector<std::string> summary;  // lines for the console
};

// The reference a variant's accuracy is measured against (docs/methods/thesis.md "Accuracy"): the same scene,
// camera, resolution and backend with no culling of any kind (every light of every pixel traced).
struct ReferenceFrame {
  uint32_t width = 0, height = 0;
  uint32_t lightCount = 0;        // visibility is kept for scenes of at most 64 lights
  std::vector<uint64_t> visible;  // per pixel: bit l = scene light l reaches it unoccluded
  ImageRGBA8 color;               // tone-mapped as color.png
  std::string description = "same scene/camera/resolution/backend, no culling";
};
// Captures the reference from a renderer whose last frame was an analysis frame of the
// reference parameters (light culling off, normal culling off, no range test).
ReferenceFrame captureReference(const Renderer& renderer, const Scene& scene);
// The reference parameters of a variant: same resolution, backend, scene and tile size; nothing culled.
VariantParams referenceParams(const VariantParams& params);
// reference_ssaa n > 1: the variant's own frame with aa none at sqrt(n) times its width and height.
VariantParams supersampledReferenceParams(const VariantParams& params);
// The colour of such a frame box-filtered (in linear HDR) down to width × height, then tone-mapped
// as color.png; no shadow visibility (its pixels are not the variant's).
ReferenceFrame captureSupersampledReference(const Renderer& renderer, uint32_t width, uint32_t height);

// Writes the images into dir (created if needed) and returns the statistics. writeImages=false
// computes the statistics only. With a reference: accuracy.image_error (LDR-FLIP of color.png
// against the reference's) and accuracy.shadow_mismatches (wrongly dark / wrongly lit pairs).
RenderOutputs writeRenderOutputs(const VulkanContext& ctx, const Renderer& renderer, const Scene& scene,
                                 const VariantParams& params, const std::string& dir, bool writeImages = true,
                                 const ReferenceFrame* reference = nullptr);

}  // namespace hb

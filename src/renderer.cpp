#include "renderer.h"

#include <cstring>

#include "errors.h"

namespace hb {

Renderer::Renderer(const VulkanContext& ctx, const Scene& scene, const RenderSettings& settings)
    : ctx_(ctx),
      settings_(settings),
      gpuScene_(ctx, scene),
      depth_(ctx, settings.width, settings.height, kDepthFormat,
             VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
             VK_IMAGE_ASPECT_DEPTH_BIT),
      depthPrepass_(ctx),
      timer_(ctx, 16) {
  if (scene.cameras.empty()) throw InputError("scene \"" + scene.name + "\" has no camera; add one or set a camera in the config");
  if (settings.cameraIndex >= scene.cameras.size())
    throw InputError("camera index " + std::to_string(settings.cameraIndex) + " does not exist; the scene has " +
                     std::to_string(scene.cameras.size()));
  camera_ = scene.cameras[settings.cameraIndex];
  view_ = camera_.view;
  proj_ = reverseZProjection(float(settings.width) / float(settings.height), camera_.yfov, camera_.znear, camera_.zfar);
  ctx.submitAndWait([&](VkCommandBuffer cmd) {
    imageBarrier(cmd, depth_, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                 VK_PIPELINE_STAGE_2_NONE, 0, VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT,
                 VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
  });
}

Renderer::~Renderer() = default;

FrameTiming Renderer::renderFrame() {
  passesRun_.clear();
  ctx_.submitAndWait([&](VkCommandBuffer cmd) {
    timer_.reset(cmd);
    timer_.frameBegin(cmd);
    timer_.begin(cmd, "depth_prepass");
    depthPrepass_.record(cmd, gpuScene_, proj_ * view_, depth_);
    timer_.end(cmd);
    passesRun_.push_back("depth_prepass");
    // The next frame's clear (and readbacks) wait for this frame's depth writes.
    imageBarrier(cmd, depth_, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                 VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                 VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                 VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_SHADER_READ_BIT);
    timer_.frameEnd(cmd);
  });
  FrameTiming t;
  t.passMs = timer_.read(&t.frameMs);
  return t;
}

std::vector<float> Renderer::readDepth() const {
  std::vector<uint8_t> bytes = readbackImage(ctx_, depth_, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, 4);
  std::vector<float> out(bytes.size() / 4);
  std::memcpy(out.data(), bytes.data(), bytes.size());
  return out;
}

}  // namespace hb

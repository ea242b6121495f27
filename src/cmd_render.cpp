#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "errors.h"
#include "image_io.h"
#include "renderer.h"
#include "vk_context.h"

namespace hb {

int cmdRender(const RenderOptions& options) {
  if (options.out.empty()) throw InputError("render: --out DIR is required (the directory the images and JSON go to)");
  RenderSettings settings;
  if (!options.size.empty()) parseSize(options.size, settings.width, settings.height, "--size");
  Scene scene = loadSceneArg(options.scene);
  std::vector<DeviceInfo> devices = enumerateDevices();
  uint32_t deviceIndex = resolveDevice(devices, options.device);
  std::filesystem::create_directories(options.out);

  VulkanContext ctx(deviceIndex);
  Renderer renderer(ctx, scene, settings);
  FrameTiming timing = renderer.renderFrame();
  std::vector<float> depth = renderer.readDepth();
  const Camera& cam = renderer.camera();
  writePng(std::filesystem::path(options.out) / "depth.png",
           depthToImage(depth, settings.width, settings.height, cam.znear, cam.zfar),
           {{"hybridbench", "depth (reverse-Z), log distance to grey, sky dark blue"}, {"device", ctx.info().name}});
  std::printf("device: %s (%s)\n", ctx.info().name.c_str(), ctx.info().driverInfo.c_str());
  std::printf("scene: %s, %llu triangles, %zu lights, %ux%u\n", scene.name.c_str(),
              (unsigned long long)scene.triangleCount(), scene.lights.size(), settings.width, settings.height);
  for (const auto& [pass, ms] : timing.passMs) std::printf("%-16s %9.3f ms\n", pass.c_str(), ms);
  std::printf("%-16s %9.3f ms\n", "frame", timing.frameMs);
  std::printf("wrote %s\n", (std::filesystem::path(options.out) / "depth.png").c_str());
  return ctx.validationMessages() ? kExitDeviceFailure : kExitOk;
}

}  // namespace hb

#include "frame/passes/primary_3dr.h"

#include <cmath>
#include <cstring>
#include <tuple>

#include <glm/gtc/matrix_inverse.hpp>

#include "base/errors.h"

namespace hb {

gpu::Raster3dConstants raster3dConstants(const Camera& camera, uint32_t width, uint32_t height,
                                         uint32_t triangleCount, uint32_t smallArea) {
  const glm::dmat4 viewInv = glm::inverse(glm::dmat4(camera.view));
  const glm::dvec3 right(viewInv[0]), up(viewInv[1]), back(viewInv[2]), eye(viewInv[3]);
  const glm::dvec3 forward = -back;
  const double w = width, h = height, a = w / h, tanHalf = std::tan(double(camera.yfov) * 0.5);
  // Pixel (x, y) centre in NDC: (2(x + 0.5)/W − 1, 2(y + 0.5)/H − 1), Vulkan y down; view-space
  // direction (ndc.x·a·tan, −ndc.y·tan, −1), as reverseZProjection maps it (camera.h).
  const glm::dvec3 d0 = forward + right * ((-1.0 + 1.0 / w) * a * tanHalf) + up * ((1.0 - 1.0 / h) * tanHalf);
  const glm::dvec3 dx = right * (2.0 * a * tanHalf / w);
  const glm::dvec3 dy = -up * (2.0 * tanHalf / h);
  const double zn = camera.znear, zf = camera.zfar;
  gpu::Raster3dConstants c{};
  c.rayD0 = glm::vec4(glm::vec3(d0), 0.0f);
  c.rayDx = glm::vec4(glm::vec3(dx), 0.0f);
  c.rayDy = glm::vec4(glm::vec3(dy), 0.0f);
  c.eye = glm::vec4(glm::vec3(eye), 1.0f);
  c.forward = glm::vec4(glm::vec3(forward), 0.0f);
  c.right = glm::vec4(glm::vec3(right), 0.0f);
  c.up = glm::vec4(glm::vec3(up), 0.0f);
  // C and D as camera.cpp computes them in float for the hardware path's projection.
  const float fzn = camera.znear, fzf = camera.zfar;
  c.depth = glm::vec4(float(zn), float(zf), fzn / (fzf - fzn), fzf * fzn / (fzf - fzn));
  c.project = glm::vec4(float(w / (2.0 * a * tanHalf)), float(h / (2.0 * tanHalf)), float(w / 2.0 - 0.5),
                        float(h / 2.0 - 0.5));
  c.width = width;
  c.height = height;
  c.triangleCount = triangleCount;
  c.smallArea = smallArea;
  // Work items of big boxes: 64 per 8x8 tile of the screen (boxes overlap: the atrium at 1080p
  // needs about 40 with 8,118,546 covered pairs in 44.6 M box pixels, H100 run at 9c6b312). A
  // full list is handled, not dropped (raster3d.comp.glsl), and counted (tile_list_overflows).
  c.itemCapacity = 64u * ((width + 7) / 8) * ((height + 7) / 8);
  c.tileWorkgroups = 4096;
  return c;
}

namespace {
std::vector<Binding> rasterBindings() {
  const VkShaderStageFlags cs = VK_SHADER_STAGE_COMPUTE_BIT;
  return {{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, cs}, {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, cs},
          {2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, cs}, {3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, cs},
          {4, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, cs}, {5, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, cs},
          {6, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, cs}};
}
std::vector<Binding> resolveBindings() {
  const VkShaderStageFlags cs = VK_SHADER_STAGE_COMPUTE_BIT;
  return {{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, cs}, {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, cs},
          {2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, cs}};
}
std::vector<glm::vec4> packTriangles(const Scene& scene) {
  std::vector<glm::vec4> out;
  for (const glm::vec3& v : scene.worldTriangles()) out.emplace_back(v, 1.0f);
  return out;
}
}  // namespace

Raster3dPass::Raster3dPass(const VulkanContext& ctx, const Scene& scene, const Camera& camera, uint32_t width,
                           uint32_t height, uint32_t smallArea, bool fp64Fallback, bool binned)
    : ctx_(ctx),
      width_(width),
      height_(height),
      triangleCount_(uint32_t(scene.triangleCount())),
      rasterSets_(ctx, rasterBindings()),
      resolveSets_(ctx, resolveBindings()),
      smallTimed_(ctx),
      smallAnalysis_(ctx),
      bigTimed_(ctx),
      bigAnalysis_(ctx),
      resolve_(ctx) {
  if (!ctx.info().bufferInt64Atomics || !ctx.info().shaderFloat64)
    throw DeviceError("device \"" + ctx.info().name +
                      "\" lacks 64-bit buffer atomics or shaderFloat64, which primary=3dr needs; use primary=hardware");
  const size_t pixels = size_t(width) * height;
  const gpu::Raster3dConstants c = raster3dConstants(camera, width, height, triangleCount_, smallArea);
  constants_ = Buffer(ctx, sizeof c, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, true, MemClass::Other);
  std::memcpy(constants_.mapped(), &c, sizeof c);
  const std::vector<glm::vec4> tris = packTriangles(scene);
  triangles_ = uploadBuffer(ctx, tris.data(), tris.size() * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                            MemClass::Geometry);
  const VkBufferUsageFlags rw =
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
  vis_ = Buffer(ctx, pixels * sizeof(uint64_t), rw, false, MemClass::Images);
  tileWorkgroups_ = c.tileWorkgroups;
  big_ = Buffer(ctx, 16 + size_t(c.itemCapacity) * 2 * sizeof(uint32_t), rw, false, MemClass::Other);
  counters_ = Buffer(ctx, gpu::kR3dCounterCount * sizeof(uint64_t), rw, false, MemClass::Other);
  coverage_ = Buffer(ctx, pixels * sizeof(uint32_t), rw, false, MemClass::Images);
  tested_ = Buffer(ctx, pixels * sizeof(uint32_t), rw, false, MemClass::Images);
  depthStaging_ = Buffer(ctx, pixels * sizeof(float), rw, false, MemClass::Images);

  rasterSets_.writeBuffer(0, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, constants_.handle());
  rasterSets_.writeBuffer(0, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, triangles_.handle());
  rasterSets_.writeBuffer(0, 2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, vis_.handle());
  rasterSets_.writeBuffer(0, 3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, big_.handle());
  rasterSets_.writeBuffer(0, 4, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, counters_.handle());
  rasterSets_.writeBuffer(0, 5, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, coverage_.handle());
  rasterSets_.writeBuffer(0, 6, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, tested_.handle());
  resolveSets_.writeBuffer(0, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, constants_.handle());
  resolveSets_.writeBuffer(0, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, vis_.handle());
  resolveSets_.writeBuffer(0, 2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, depthStaging_.handle());
  // Specialization constants (raster3d.comp.glsl): 0 pass (0 per triangle, 1 tiles), 1 analysis,
  // 2 fp64 fallback, 3 binned.
  for (auto [p, pass, analysis] : {std::tuple{&smallTimed_, 0u, 0u}, std::tuple{&smallAnalysis_, 0u, 1u},
                                   std::tuple{&bigTimed_, 1u, 0u}, std::tuple{&bigAnalysis_, 1u, 1u}}) {
    p->createLayout({rasterSets_.layout()}, 0);
    p->createCompute("raster3d.comp", {{pass, analysis, fp64Fallback ? 1u : 0u, binned ? 1u : 0u}});
  }
  resolve_.createLayout({resolveSets_.layout()}, 0);
  resolve_.createCompute("raster3d_resolve.comp");
}

Raster3dPass::~Raster3dPass() = default;

void Raster3dPass::record(VkCommandBuffer cmd, const Image& depth, bool analysis) const {
  vkCmdFillBuffer(cmd, vis_.handle(), 0, VK_WHOLE_SIZE, 0xFFFFFFFFu);  // "nothing": the largest key
  vkCmdFillBuffer(cmd, big_.handle(), 0, 16, 0);  // the item count
  if (analysis) {
    vkCmdFillBuffer(cmd, counters_.handle(), 0, VK_WHOLE_SIZE, 0);
    vkCmdFillBuffer(cmd, coverage_.handle(), 0, VK_WHOLE_SIZE, 0);
    vkCmdFillBuffer(cmd, tested_.handle(), 0, VK_WHOLE_SIZE, 0);
  }
  memoryBarrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_READ_BIT | VK_ACCESS_2_SHADER_WRITE_BIT);
  VkDescriptorSet set = rasterSets_.set();
  const Pipeline& small = analysis ? smallAnalysis_ : smallTimed_;
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, small.handle());
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, small.layout(), 0, 1, &set, 0, nullptr);
  vkCmdDispatch(cmd, (triangleCount_ + 63) / 64, 1, 1);
  memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_WRITE_BIT,
                VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_READ_BIT | VK_ACCESS_2_SHADER_WRITE_BIT);
  const Pipeline& big = analysis ? bigAnalysis_ : bigTimed_;
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, big.handle());
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, big.layout(), 0, 1, &set, 0, nullptr);
  vkCmdDispatch(cmd, tileWorkgroups_, 1, 1);
  memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_WRITE_BIT,
                VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_READ_BIT);
  VkDescriptorSet rset = resolveSets_.set();
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, resolve_.handle());
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, resolve_.layout(), 0, 1, &rset, 0, nullptr);
  vkCmdDispatch(cmd, uint32_t((size_t(width_) * height_ + 63) / 64), 1, 1);
  memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_WRITE_BIT,
                VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
  imageBarrier(cmd, depth, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
               VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
               VK_ACCESS_2_TRANSFER_WRITE_BIT);
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 0, 1};
  region.imageExtent = {width_, height_, 1};
  vkCmdCopyBufferToImage(cmd, depthStaging_.handle(), depth.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
  imageBarrier(cmd, depth, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL,
               VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
               VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR |
                   VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT |
                   VK_PIPELINE_STAGE_2_COPY_BIT,
               VK_ACCESS_2_SHADER_SAMPLED_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                   VK_ACCESS_2_TRANSFER_READ_BIT);
  // The visibility buffer is read by the shading pass (fragment shader) and by readbacks.
  memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_WRITE_BIT,
                VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT |
                    VK_PIPELINE_STAGE_2_COPY_BIT,
                VK_ACCESS_2_SHADER_READ_BIT | VK_ACCESS_2_TRANSFER_READ_BIT);
}

template <typename T>
static std::vector<T> readAs(const VulkanContext& ctx, const Buffer& b) {
  const std::vector<uint8_t> bytes = readbackBuffer(ctx, b);
  std::vector<T> out(bytes.size() / sizeof(T));
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
  return out;
}

std::vector<uint64_t> Raster3dPass::readVisibility() const { return readAs<uint64_t>(ctx_, vis_); }
std::vector<uint32_t> Raster3dPass::readCoverage() const { return readAs<uint32_t>(ctx_, coverage_); }
std::vector<uint32_t> Raster3dPass::readPixelTests() const { return readAs<uint32_t>(ctx_, tested_); }

Raster3dCounters Raster3dPass::readCounters() const {
  const std::vector<uint64_t> c = readAs<uint64_t>(ctx_, counters_);
  Raster3dCounters r;
  r.setups = c[gpu::kR3dCounterSetups];
  r.edgeEvaluations = c[gpu::kR3dCounterEdgeEvals];
  r.fallbacks = c[gpu::kR3dCounterFallbacks];
  r.pixelsTested = c[gpu::kR3dCounterPixelsTested];
  r.covered = c[gpu::kR3dCounterCovered];
  r.atomics = c[gpu::kR3dCounterAtomics];
  r.bigTriangles = c[gpu::kR3dCounterBig];
  r.listOverflows = c[gpu::kR3dCounterOverflow];
  return r;
}

}  // namespace hb

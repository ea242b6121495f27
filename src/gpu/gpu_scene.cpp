#include "gpu/gpu_scene.h"

#include "base/errors.h"

namespace hb {

GpuScene::GpuScene(const VulkanContext& ctx, const Scene& scene) : scene_(scene) {
  if (scene.vertices.empty() || scene.indices.empty())
    throw InputError("scene \"" + scene.name + "\" has no triangles; give it at least one mesh");
  // Storage + device address usage so the acceleration-structure builds can read them too.
  const VkBufferUsageFlags rtUsage =
      ctx.info().accelerationStructure
          ? VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT | VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR
          : 0;
  vertices_ = uploadBuffer(ctx, scene.vertices.data(), scene.vertices.size() * sizeof(Vertex),
                           VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | rtUsage,
                           MemClass::Geometry);
  indices_ = uploadBuffer(ctx, scene.indices.data(), scene.indices.size() * sizeof(uint32_t),
                          VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | rtUsage,
                          MemClass::Geometry);
  for (const Instance& inst : scene.instances)
    for (const Primitive& p : scene.meshes[inst.mesh].primitives)
      draws_.push_back({inst.transform, p.firstIndex, p.indexCount, p.vertexOffset, p.material});
}

}  // namespace hb

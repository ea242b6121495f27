#include "gpu/gpu_scene.h"

#include <glm/gtc/matrix_inverse.hpp>

#include "base/errors.h"

namespace hb {

GpuScene::GpuScene(const VulkanContext& ctx, const Scene& scene) : scene_(scene) {
  if (scene.vertices.empty() || scene.indices.empty())
    throw InputError("scene \"" + scene.name + "\" has no triangles; give it at least one mesh");
  // Storage + device address usage so the acceleration-structure builds can read them too.
  const VkBufferUsageFlags rtUsage = ctx.info().accelerationStructure
                                         ? VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT |
                                               VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR
                                         : 0;
  vertices_ = uploadBuffer(ctx, scene.vertices.data(), scene.vertices.size() * sizeof(Vertex),
                           VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | rtUsage,
                           MemClass::Geometry);
  indices_ =
      uploadBuffer(ctx, scene.indices.data(), scene.indices.size() * sizeof(uint32_t),
                   VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | rtUsage, MemClass::Geometry);
  for (const Instance& inst : scene.instances)
    for (const Primitive& p : scene.meshes[inst.mesh].primitives)
      draws_.push_back({inst.transform, p.firstIndex, p.indexCount, p.vertexOffset, p.material});
}

DrawTables drawTables(const GpuScene& scene) {
  DrawTables t;
  uint32_t base = 0;
  for (const DrawItem& d : scene.draws()) {
    const glm::mat4 normal = glm::mat4(glm::transpose(glm::inverse(glm::mat3(d.model))));
    t.draws.push_back({d.model, normal, d.material, d.firstIndex, d.vertexOffset, base});
    t.triangleDraw.insert(t.triangleDraw.end(), d.indexCount / 3, uint32_t(t.draws.size() - 1));
    base += d.indexCount / 3;
  }
  return t;
}

std::vector<uint32_t> triangleIdBase(const Scene& scene) {
  std::vector<uint32_t> out(scene.instances.size());
  uint32_t id = 0;
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    out[i] = uint32_t(out.size());
    for (const Primitive& p : scene.meshes[scene.instances[i].mesh].primitives) {
      if (p.indexCount >= 3) out.push_back(id);
      id += p.indexCount / 3;
    }
  }
  out.push_back(0);  // never empty
  return out;
}

}  // namespace hb

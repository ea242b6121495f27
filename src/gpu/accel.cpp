#include "gpu/accel.h"

#include <atomic>
#include <chrono>
#include <cstring>

#include "base/errors.h"
#include "gpu/sync.h"

namespace hb {

static std::atomic<uint64_t> gAccelBuilds{0};

uint64_t AccelerationStructures::buildCount() { return gAccelBuilds.load(); }

AccelerationStructures::AccelerationStructures(const VulkanContext& ctx, const GpuScene& gpuScene) : ctx_(ctx) {
  ++gAccelBuilds;
  HB_ASSERT(ctx.info().accelerationStructure);
  const Scene& scene = gpuScene.scene();
  const RtFunctions& rt = ctx.rt();
  VkPhysicalDeviceAccelerationStructurePropertiesKHR asProps{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_PROPERTIES_KHR};
  VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &asProps};
  vkGetPhysicalDeviceProperties2(ctx.physical(), &p2);
  const VkDeviceSize scratchAlign = std::max<VkDeviceSize>(asProps.minAccelerationStructureScratchOffsetAlignment, 256);

  // --- bottom level: one per mesh ---------------------------------------------------------------
  struct MeshBuild {
    std::vector<VkAccelerationStructureGeometryKHR> geometries;
    std::vector<VkAccelerationStructureBuildRangeInfoKHR> ranges;
    VkAccelerationStructureBuildGeometryInfoKHR info{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
    VkDeviceSize scratchOffset = 0;
  };
  std::vector<MeshBuild> builds(scene.meshes.size());
  VkDeviceSize scratchTotal = 0;
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    MeshBuild& b = builds[m];
    std::vector<uint32_t> counts;
    for (const Primitive& p : scene.meshes[m].primitives) {
      if (p.indexCount < 3) continue;
      VkAccelerationStructureGeometryKHR g{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
      g.geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR;
      g.flags = VK_GEOMETRY_OPAQUE_BIT_KHR;
      auto& t = g.geometry.triangles;
      t.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR;
      t.vertexFormat = VK_FORMAT_R32G32B32_SFLOAT;
      t.vertexData.deviceAddress = gpuScene.vertices().address() + VkDeviceSize(p.vertexOffset) * sizeof(Vertex);
      t.vertexStride = sizeof(Vertex);
      t.maxVertex = p.vertexCount ? p.vertexCount - 1 : 0;
      t.indexType = VK_INDEX_TYPE_UINT32;
      t.indexData.deviceAddress = gpuScene.indices().address() + VkDeviceSize(p.firstIndex) * sizeof(uint32_t);
      b.geometries.push_back(g);
      b.ranges.push_back({p.indexCount / 3, 0, 0, 0});
      counts.push_back(p.indexCount / 3);
    }
    b.info.type = VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR;
    b.info.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
    b.info.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
    b.info.geometryCount = uint32_t(b.geometries.size());
    b.info.pGeometries = b.geometries.data();
    VkAccelerationStructureBuildSizesInfoKHR sizes{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
    rt.getBuildSizes(ctx.device(), VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &b.info, counts.data(), &sizes);
    Buffer buf(ctx, sizes.accelerationStructureSize,
               VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
               false, MemClass::AccelerationStructure);
    VkAccelerationStructureCreateInfoKHR ci{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR};
    ci.buffer = buf.handle();
    ci.size = sizes.accelerationStructureSize;
    ci.type = VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR;
    VkAccelerationStructureKHR as = VK_NULL_HANDLE;
    VK_CHECK(rt.createAccelerationStructure(ctx.device(), &ci, nullptr, &as));
    blas_.push_back(as);
    blasBuffers_.push_back(std::move(buf));
    bytes_ += sizes.accelerationStructureSize;
    b.info.dstAccelerationStructure = as;
    b.scratchOffset = scratchTotal;
    scratchTotal += alignUp(sizes.buildScratchSize, scratchAlign);
  }

  // --- top level: one instance per scene instance ------------------------------------------------
  std::vector<VkAccelerationStructureInstanceKHR> inst;
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& in = scene.instances[i];
    VkAccelerationStructureInstanceKHR vi{};
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) vi.transform.matrix[r][c] = in.transform[c][r];  // glm is column-major
    vi.instanceCustomIndex = uint32_t(i) & 0xFFFFFF;
    vi.mask = 0xFF;
    vi.flags = VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR;  // shadows from both faces
    VkAccelerationStructureDeviceAddressInfoKHR ai{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR};
    ai.accelerationStructure = blas_[in.mesh];
    vi.accelerationStructureReference = rt.getAddress(ctx.device(), &ai);
    inst.push_back(vi);
  }
  instances_ = uploadBuffer(
      ctx, inst.data(), inst.size() * sizeof(VkAccelerationStructureInstanceKHR),
      VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT | VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR,
      MemClass::AccelerationStructure);
  VkAccelerationStructureGeometryKHR tg{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
  tg.geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR;
  tg.flags = VK_GEOMETRY_OPAQUE_BIT_KHR;
  tg.geometry.instances.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR;
  tg.geometry.instances.data.deviceAddress = instances_.address();
  VkAccelerationStructureBuildGeometryInfoKHR tinfo{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
  tinfo.type = VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR;
  tinfo.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
  tinfo.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
  tinfo.geometryCount = 1;
  tinfo.pGeometries = &tg;
  uint32_t instCount = uint32_t(inst.size());
  VkAccelerationStructureBuildSizesInfoKHR tsizes{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
  rt.getBuildSizes(ctx.device(), VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &tinfo, &instCount, &tsizes);
  tlasBuffer_ =
      Buffer(ctx, tsizes.accelerationStructureSize,
             VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT, false,
             MemClass::AccelerationStructure);
  VkAccelerationStructureCreateInfoKHR tci{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR};
  tci.buffer = tlasBuffer_.handle();
  tci.size = tsizes.accelerationStructureSize;
  tci.type = VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR;
  VK_CHECK(rt.createAccelerationStructure(ctx.device(), &tci, nullptr, &tlas_));
  bytes_ += tsizes.accelerationStructureSize;
  tinfo.dstAccelerationStructure = tlas_;
  const VkDeviceSize tlasScratchOffset = scratchTotal;
  scratchTotal += alignUp(tsizes.buildScratchSize, scratchAlign);

  Buffer scratch(ctx, scratchTotal + scratchAlign,
                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT, false,
                 MemClass::Staging);
  const VkDeviceAddress scratchBase = alignUp(scratch.address(), scratchAlign);
  for (MeshBuild& b : builds) b.info.scratchData.deviceAddress = scratchBase + b.scratchOffset;
  tinfo.scratchData.deviceAddress = scratchBase + tlasScratchOffset;

  auto t0 = std::chrono::steady_clock::now();
  ctx.submitAndWait(
      [&](VkCommandBuffer cmd) {
        std::vector<VkAccelerationStructureBuildGeometryInfoKHR> infos;
        std::vector<const VkAccelerationStructureBuildRangeInfoKHR*> ranges;
        for (MeshBuild& b : builds) {
          infos.push_back(b.info);
          ranges.push_back(b.ranges.data());
        }
        // The BLAS builds write their structures and the scratch; the TLAS build reads the BLASes and
        // the instances and writes its structure and the scratch (another range, one buffer).
        Sync sync;
        std::vector<Use> blas = {{scratch, access::kAccelBuildWrite}};
        for (const Buffer& b : blasBuffers_) blas.push_back({b, access::kAccelBuildWrite});
        sync.use(cmd, blas);
        if (!infos.empty()) rt.cmdBuild(cmd, uint32_t(infos.size()), infos.data(), ranges.data());
        std::vector<Use> tlas = {{scratch, access::kAccelBuildWrite},
                                 {tlasBuffer_, access::kAccelBuildWrite},
                                 {instances_, access::kAccelBuildInput}};
        for (const Buffer& b : blasBuffers_)
          tlas.push_back({b,
                          {VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                           VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR}});
        sync.use(cmd, tlas);
        VkAccelerationStructureBuildRangeInfoKHR tr{instCount, 0, 0, 0};
        const VkAccelerationStructureBuildRangeInfoKHR* trp = &tr;
        rt.cmdBuild(cmd, 1, &tinfo, &trp);
        // The frames that trace it are later submissions, after this one is waited for.
      },
      "the BLAS/TLAS build");
  buildMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

AccelerationStructures::~AccelerationStructures() {
  const RtFunctions& rt = ctx_.rt();
  if (tlas_) rt.destroyAccelerationStructure(ctx_.device(), tlas_, nullptr);
  for (VkAccelerationStructureKHR as : blas_) rt.destroyAccelerationStructure(ctx_.device(), as, nullptr);
}

}  // namespace hb

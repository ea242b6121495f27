#include "frame/frame_builder.h"

#include "base/errors.h"
#include "frame/pass_work.h"
#include "frame/passes/ldm_build.h"

namespace hb {

SurfaceInputs surfaceInputs(const FrameBuilder& f) {
  SurfaceInputs s;
  s.hitIds = f.resources.buffer(res::kVisibility);
  s.hitRays = f.resources.buffer(res::kVisibilityRays);
  s.hitTriangles = f.resources.buffer(res::kVisibilityTriangles);
  s.worldPos = f.settings.worldPos;
  s.normals = s.hitIds ? NormalCulling::Geometric : NormalCulling::Improved;
  if (s.worldPos == WorldPosMethod::Hit && !s.hitIds)
    throw InputError(
        "world_pos=hit needs the triangle ids of a computed primary visibility: set primary=3dr, "
        "3dr-binned, 2dr or raycast");
  return s;
}

SurfaceBindings surfaceBindings(const FrameBuilder& f, const SurfaceInputs& surface) {
  const FrameResources& r = f.resources;
  return {&r.requireBuffer(res::kFrameConstants),
          &r.requireImage(res::kDepth),
          r.sampler(res::kPointSampler),
          r.tlas(res::kTlas),
          surface.hitIds,
          surface.hitRays,
          surface.hitTriangles};
}

void provideSurfaceHits(DescriptorBinder& binder, const SurfaceBindings& surface, const Buffer& placeholder) {
  binder.provide("HitIds", surface.hitIds ? *surface.hitIds : placeholder);
  binder.provide("HitRays", *(surface.hitRays ? surface.hitRays : surface.frameConstants));
  binder.provide("HitTriangles", surface.hitTriangles ? *surface.hitTriangles : placeholder);
}

std::vector<std::string> surfaceReads(const SurfaceInputs& surface) {
  std::vector<std::string> reads = {res::kFrameConstants, res::kDepth};
  if (surface.hitIds) reads.insert(reads.end(), {res::kVisibility, res::kVisibilityRays, res::kVisibilityTriangles});
  return reads;
}

std::string accelerationStructuresKey() {
  return "acceleration_structures: a BLAS per mesh, a TLAS over the instances";
}

std::string traceBvhKey(uint32_t width) {
  return "trace_bvh: binary SAH" + (width == 2 ? std::string() : ", collapsed to width " + std::to_string(width));
}

const TraceBvh& frameTraceBvh(FrameResources& resources, const VulkanContext& ctx, const Scene& scene, uint32_t width,
                              const std::string& who) {
  return resources.build<TraceBvh>(
      res::kTraceBvh, traceBvhKey(width), who,
      [&] { return std::make_unique<TraceBvh>(buildTraceBvh(ctx, scene, width)); },
      [](const TraceBvh& b) { return b.bytes; });
}

FrameLdmSet frameLdmSet(FrameBuilder& f, const std::vector<glm::dvec3>& dirs, uint32_t resolution,
                        LdmBuildMethod method, LdmList list, const char* effect, const char* resource,
                        const char* buildPass) {
  FrameLdmSet set;
  set.key = "ldm: ldmDirections(" + std::to_string(dirs.size()) + "), " + std::to_string(resolution) + " x " +
            std::to_string(resolution) + ", ldm_build=" + toString(method) + ", ldm_list=" + toString(list);
  set.built = f.resources.built(set.key) == nullptr;
  set.ldm = &f.resources.build<LdmBuild>(
      resource, set.key, buildPass,
      [&] { return makeSizedLdmBuild(f.ctx, f.gpuScene, f.scene, dirs, resolution, method, list, effect); },
      [](const LdmBuild& l) { return l.memoryBytes(); });
  const BuiltResource* entry = f.resources.built(set.key);
  set.resource = entry->name;
  set.buildPass = entry->builtBy;
  return set;
}

void addLdmBuildPass(FrameBuilder& f, const FrameLdmSet& set, const char* ownBuildPass, const char* effect,
                     std::vector<FramePass>& passes, std::vector<std::pair<std::string, std::string>>& skipped) {
  if (set.built)
    passes.push_back(ldmBuildPass(f, *set.ldm, ownBuildPass, set.resource.c_str(), effect));
  else
    skipped.push_back(
        {ownBuildPass, set.buildPass + " builds its LDM set (" + set.resource + ", the same key: " + set.key + ")"});
}

FramePass ldmBuildPass(FrameBuilder& frame, const LdmBuild& ldm, const char* name, const char* resource,
                       const char* effect) {
  frame.resources.publish(resource, ldm.links(), "u64 or u32 list nodes", "counted per frame + 5 %");
  FramePass pass;
  pass.name = name;
  pass.reads = {res::kSceneVertices, res::kSceneIndices};
  pass.writes = {resource};
  pass.subPasses = ldm.subPasses(name);
  pass.syncedInside = {resource};  // each step declares its own
  pass.record = [&ldm, name](VkCommandBuffer cmd, const PassFrame& f) { ldm.record(cmd, *f.sync, f.timer, name); };
  pass.work = [name, effect, triangles = double(frame.scene.triangleCount())](const nlohmann::json& a) {
    return ldmBuildWork(name, a.contains(effect) ? a[effect] : nlohmann::json::object(), triangles);
  };
  return pass;
}

}  // namespace hb

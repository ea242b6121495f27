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

std::vector<std::string> surfaceReads(const SurfaceInputs& surface) {
  std::vector<std::string> reads = {res::kFrameConstants, res::kDepth};
  if (surface.hitIds) reads.insert(reads.end(), {res::kVisibility, res::kVisibilityRays, res::kVisibilityTriangles});
  return reads;
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

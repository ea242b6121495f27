// What a part of the frame is built from (plan/effect.h EffectDef::build): the device, the
// scene, the settings and plan, the view, and the frame's resources so far. Parts are built in
// frame order, so a part finds what earlier parts published (resources.buffer("light_lists.grid"))
// and publishes what it writes for the parts after it.
#pragma once
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

#include "frame/frame_pass.h"
#include "frame/ray_backend.h"
#include "frame/render_settings.h"
#include "gpu/descriptor_binder.h"
#include "gpu/gpu_scene.h"
#include "gpu/trace_bvh.h"
#include "gpu/vk_context.h"
#include "plan/effects.h"
#include "plan/ldm_settings.h"
#include "scene/camera.h"
#include "scene/scene.h"
#include "shared/gpu_types.h"

namespace hb {

// The names of the resources the base frame publishes (the parts publish their own).
namespace res {
inline constexpr const char* kSceneVertices = "scene.vertices";  // gpu_scene.h
inline constexpr const char* kSceneIndices = "scene.indices";
inline constexpr const char* kFrameConstants = "frame_constants";  // gpu::FrameConstants (UBO)
inline constexpr const char* kLights = "lights";                   // gpu::GpuLight per scene light
inline constexpr const char* kDepth = "depth";                     // reverse-Z depth, D32_SFLOAT
inline constexpr const char* kPointSampler = "point_sampler";
inline constexpr const char* kTlas = "tlas";           // the ray tracer's scene
inline constexpr const char* kTraceBvh = "trace_bvh";  // backend=compute: our BVH (trace_bvh.h)
// Primary visibility by compute (raster3d / raycast): a visibility buffer and what decodes it.
inline constexpr const char* kVisibility = "visibility";                     // u64 per pixel: depth | triangle id
inline constexpr const char* kVisibilityRays = "visibility.rays";            // gpu::Raster3dConstants (UBO)
inline constexpr const char* kVisibilityTriangles = "visibility.triangles";  // 3 vec4 per triangle, world
// Light lists (light culling).
inline constexpr const char* kListLights = "light_lists.lights";    // the lights as the lists index them
inline constexpr const char* kListGrid = "light_lists.grid";        // u32 x 4 per tile
inline constexpr const char* kListIndices = "light_lists.indices";  // indices or bit masks (+ z-bins)
// Shading.
inline constexpr const char* kColor = "color";                   // linear HDR, RGBA16F
inline constexpr const char* kRefNormals = "reference_normals";  // analysis: true face normals
}  // namespace res

struct FrameBuilder {
  const VulkanContext& ctx;
  const Scene& scene;
  const RenderSettings& settings;
  const FramePlan& plan;
  const Camera& camera;
  glm::mat4 view, proj;
  const GpuScene& gpuScene;
  FrameResources& resources;
  // The frame's constants, uploaded once every part is built: a part may set its fields
  // (light culling its list layout, ambient occlusion the ambient term).
  gpu::FrameConstants& constants;
  // The value of the effect being built, after precedence (null for a base part).
  nlohmann::json value;
  // The frame's ray tracer (ray_backend.h): the backend that runs and what it traces through, for
  // every pass that traces; null when nothing in the frame traces.
  const RayTracer* tracer = nullptr;
};

}  // namespace hb

namespace hb {

// The surface a per-pixel effect starts from, as the shadow pass takes it (shaders/surface.glsl.inc):
// 3D rasterization's visibility buffer, rays and world triangles (null after the hardware
// prepass), and which positions and normals to use.
struct SurfaceInputs {
  const Buffer* hitIds = nullptr;
  const Buffer* hitRays = nullptr;
  const Buffer* hitTriangles = nullptr;
  WorldPosMethod worldPos = WorldPosMethod::Alg41;
  // An effect without an "off" for normals (ambient occlusion, indirect light): the triangle's
  // own where the primary gives ids, else the improved reconstruction.
  NormalCulling normals = NormalCulling::Improved;
};
// Throws InputError when world_pos=hit asks for ids this frame's primary visibility does not give.
SurfaceInputs surfaceInputs(const FrameBuilder& frame);

// The frame resources a per-pixel pass binds to meet its surface and trace from it.
struct SurfaceBindings {
  const Buffer* frameConstants = nullptr;
  const Image* depth = nullptr;  // DEPTH_READ_ONLY_OPTIMAL
  VkSampler sampler = VK_NULL_HANDLE;
  VkAccelerationStructureKHR tlas = VK_NULL_HANDLE;  // the ray tracer's scene, or null
  // As SurfaceInputs: 3D rasterization's visibility buffer, rays and world triangles, or null.
  const Buffer* hitIds = nullptr;
  const Buffer* hitRays = nullptr;
  const Buffer* hitTriangles = nullptr;
};
SurfaceBindings surfaceBindings(const FrameBuilder& frame, const SurfaceInputs& surface);
// Provides the surface's hit buffers under their shader names (surface.glsl.inc HitIds, HitRays,
// HitTriangles). Without hits they are never read, and `placeholder` (any storage buffer) and the
// frame constants stand in for them.
void provideSurfaceHits(DescriptorBinder& binder, const SurfaceBindings& surface, const Buffer& placeholder);
// The frame resources a pass on that surface reads: the constants, the depth, and the visibility
// buffer with its rays and triangles where the primary gives them.
std::vector<std::string> surfaceReads(const SurfaceInputs& surface);

// The keyed resources of the frame (FrameResources::build): built once per frame for their key,
// shared by every part and pass that asks for the same. A key holds everything that decides the
// content; the scene is the frame's, one per Renderer.
//  - the driver's acceleration structures (published as "tlas"): one key, a BLAS per mesh and a TLAS;
//  - our BVH (published as "trace_bvh"): its width;
//  - an LDM set (published as the first asker's "<effect>.ldm"): its directions (ldmDirections(N),
//    one set for every effect: no effect rotates or jitters them), resolution, build method and
//    list kind; its node pool is then sized by a counting build of exactly these.
std::string accelerationStructuresKey();
std::string traceBvhKey(uint32_t width);
// Our BVH of `width` over the frame's scene; `who` builds it if it is the first to ask.
const TraceBvh& frameTraceBvh(FrameResources& resources, const VulkanContext& ctx, const Scene& scene, uint32_t width,
                              const std::string& who);

class LdmBuild;
// The LDM set an effect asks for, as the frame holds it.
struct FrameLdmSet {
  const LdmBuild* ldm = nullptr;
  std::string key;
  std::string resource;   // the frame resource its lists are published as (the builder's name)
  std::string buildPass;  // the pass that draws its lists each frame
  bool built = false;     // this request built it (its build pass runs); else buildPass is an earlier effect's
};
// The LDM set of these settings: built (sized, frame/passes/ldm_build.h makeSizedLdmBuild) by the
// first effect that asks, whose `buildPass` draws it each frame and publishes it as `resource`; a
// later effect with the same key gets the same set. `effect` names the asker in errors.
FrameLdmSet frameLdmSet(FrameBuilder& frame, const std::vector<glm::dvec3>& dirs, uint32_t resolution,
                        LdmBuildMethod method, LdmList list, const char* effect, const char* resource,
                        const char* buildPass);
// An effect's layered depth maps as a frame pass: publishes ldm's lists as `resource`, rebuilds them
// every frame timed as `name` with their steps as sub-passes (LdmBuild::subPasses), and takes its
// work from the analysis record's `effect` entry (pass_work.h ldmBuildWork).
FramePass ldmBuildPass(FrameBuilder& frame, const LdmBuild& ldm, const char* name, const char* resource,
                       const char* effect);
// What an effect of `set` adds to the frame for it: its build pass where it built the set (into
// `passes`), else that pass `ownBuildPass` listed as skipped, naming the pass that builds it.
void addLdmBuildPass(FrameBuilder& frame, const FrameLdmSet& set, const char* ownBuildPass, const char* effect,
                     std::vector<FramePass>& passes, std::vector<std::pair<std::string, std::string>>& skipped);

}  // namespace hb

#include "frame/base_parts.h"

#include <algorithm>
#include <string>

#include "base/errors.h"
#include "frame/pass_work.h"
#include "shared/gpu_types.h"

namespace hb {

// --- primary visibility -------------------------------------------------------------------------

namespace {

// Anti-aliasing: the sample planes' work (render.json primary.aa), all in the ".samples" sub-pass.
void samplesWork(const std::string& name, const nlohmann::json& a, std::vector<PassWork>& w) {
  if (!a.contains("primary") || !a["primary"].contains("aa")) return;
  const nlohmann::json& aa = a["primary"]["aa"];
  w.push_back({name + ".samples",
               {counted("fma", figureAt(aa, {"sample_paper_scalar_ops_estimate"}),
                        "the sample planes' setups and pixel tests x the paper's Fig. 10 ops"),
                counted("atomics64", figureAt(aa, {"sample_atomics"}), "64-bit atomicMin on the sample planes")}});
}

// What primary visibility by compute did, per sub-pass (raster3d.cpp's dispatches), from the
// analysis frame's counters ("primary" in the run's record) and the frame's sizes. The scalar-op
// counts are the paper's (Davidovic et al., Fig. 10: 57 per 3DR triangle setup, 12 per pixel
// test), each at most one FMA issue slot.
std::vector<PassWork> primaryWork(const std::string& name, const nlohmann::json& a, double pixels, double tiles,
                                  PrimaryMethod method, bool depthCopy) {
  const bool cast = method == PrimaryMethod::RayCast, bvh = primaryUsesBvh(method);
  const bool binned = method == PrimaryMethod::Raster3dBinned || method == PrimaryMethod::Raster2dBinned;
  // Fig. 10's scalar ops: 3DR 57 a setup and 12 a pixel; the 2D homogeneous baseline 73 and 14.
  const bool twoD = method == PrimaryMethod::Raster2d || method == PrimaryMethod::Raster2dBinned;
  const double setupCost = twoD ? 73 : 57, pixelCost = twoD ? 14 : 12;
  const double setups = figureAt(a, {"primary", "triangle_setups"});
  const double triangles = figureAt(a, {"primary", "triangles"});
  const double tested = figureAt(a, {"primary", "pixels_tested"});
  const double atomics = figureAt(a, {"primary", "atomics"});
  const double entries = figureAt(a, {"primary", "list_entries"});
  // The resolve reads 8 B of visibility and writes 4 B of depth per pixel; where a pass draws
  // against the depth, it is then copied into the D32 image (4 B read + 4 B written).
  const WorkItem resolve = derived("bytes", 12 * pixels, "8 B visibility read + 4 B depth written a pixel");
  // Rates no device peak counts (tables --ceiling rates them against the same sub-pass on a ceiling
  // run: docs/methods/3d-rasterization.md "Measured ceilings").
  const WorkItem resolved = derived("pixels_resolved", pixels, "one a pixel");
  const WorkItem copy = derived("bytes", 8 * pixels, "4 B read + 4 B written a pixel");
  std::vector<PassWork> w;
  if (cast) {
    w.push_back({name,
                 {derived("rays_coherent", pixels, "one primary ray per pixel"),
                  depthCopy ? derived("bytes", 20 * pixels, "resolve and depth copy")
                            : derived("bytes", 12 * pixels, "resolve (the depth written where it is read)")}});
  } else {
    const WorkItem setupOps =
        counted("fma", setupCost * setups,
                "triangle setups x " + std::to_string(int(setupCost)) + " scalar ops (paper Fig. 10)");
    const double big = figureAt(a, {"primary", "big_triangles"});
    // Binned, the per-triangle dispatch also writes each big triangle's setup (gpu::R3dSetupRecord),
    // which the count, fill and tile dispatches read instead of setting it up again.
    const WorkItem setupBytes = binned ? derived("bytes", 48 * triangles + double(sizeof(gpu::R3dSetupRecord)) * big,
                                                 "3 vertices read a triangle + a big triangle's setup written (" +
                                                     std::to_string(sizeof(gpu::R3dSetupRecord)) + " B)")
                                       : derived("bytes", 48 * triangles, "3 vertices read a triangle");
    const WorkItem testOps = counted("fma", pixelCost * tested,
                                     "pixel tests x " + std::to_string(int(pixelCost)) + " scalar ops (paper Fig. 10)");
    const WorkItem visAtomics = counted("atomics64", atomics, "64-bit atomicMin on the visibility buffer");
    w.push_back({name,
                 {counted("fma", setupCost * setups + pixelCost * tested,
                          "setups x " + std::to_string(int(setupCost)) + " + pixel tests x " +
                              std::to_string(int(pixelCost)) + " (paper Fig. 10)"),
                  visAtomics,
                  depthCopy ? derived("bytes", 48 * triangles + 20 * pixels, "triangles read + resolve + depth copy")
                            : derived("bytes", 48 * triangles + 12 * pixels, "triangles read + resolve")}});
    if (bvh) {
      const double nodes = figureAt(a, {"primary", "bvh_nodes_visited"});
      w.push_back({name + ".traverse",
                   {counted("fma", setupCost * setups + pixelCost * tested,
                            "setups x 57 + pixel tests x 12 (paper Fig. 10; node tests not counted)"),
                    visAtomics,
                    counted("bytes", 48 * nodes + 48 * setups,
                            "48 B a node visited + 48 B a triangle set up (3 vertices as vec4)")}});
      samplesWork(name, a, w);
      w.push_back({name + ".resolve", {resolve, resolved}});
      if (depthCopy) w.push_back({name + ".depth_copy", {copy}});
      return w;
    }
    w.push_back(
        {name + ".triangles",
         {setupOps, setupBytes,
          counted("triangles_set_up", triangles, "every triangle the per-triangle pass took (primary.triangles)")}});
    if (binned) {
      const WorkItem listAtomics = counted("atomics", entries, "one atomicAdd per (triangle, tile) list entry");
      w.push_back({name + ".count", {listAtomics}});
      w.push_back(
          {name + ".scan", {derived("bytes", 12 * tiles, "per 8x8 tile its count read, offset and cursor written")}});
      w.push_back({name + ".fill", {listAtomics, derived("bytes", 4 * entries, "each list entry written")}});
    }
    // The tile pass's loop: every thread of a tile's workgroup (64) takes each (triangle, tile) pair of
    // the tile's list once. No device peak counts these; `tables --ceiling` rates them against the
    // same pass on a ceiling run (docs/methods/3d-rasterization.md "Measured ceilings").
    std::vector<WorkItem> tileItems = {testOps, visAtomics};
    if (binned)
      tileItems.push_back(counted("tile_loop_steps", 64 * figureAt(a, {"primary", "bins_refined"}),
                                  "(triangle, tile) pairs the tile pass tested (primary.bins_refined) x 64 "
                                  "threads: its loop's steps"));
    w.push_back({name + ".tiles", tileItems});
  }
  samplesWork(name, a, w);
  w.push_back({name + ".resolve", {resolve, resolved}});
  if (depthCopy) w.push_back({name + ".depth_copy", {copy}});
  return w;
}

}  // namespace

PrimaryPart::PrimaryPart(FrameBuilder& f) {
  const Image& depth = f.resources.requireImage(res::kDepth);
  FramePass pass;
  pass.name = primaryPassOf(f.settings.primary);
  pass.writes = {res::kDepth};
  if (f.settings.primary == PrimaryMethod::Hardware) {
    prepass_ = std::make_unique<DepthPrepass>(f.ctx);
    pass.reads = {res::kSceneVertices, res::kSceneIndices};
    pass.stages = VK_PIPELINE_STAGE_2_VERTEX_INPUT_BIT;
    pass.access = {{res::kDepth, access::kDepthAttachment.discarding()},
                   {res::kSceneVertices, access::kVertexInput},
                   {res::kSceneIndices, access::kVertexInput}};
    const glm::mat4 viewProj = f.proj * f.view;
    pass.record = [this, &gpuScene = f.gpuScene, viewProj, &depth](VkCommandBuffer cmd, const PassFrame&) {
      prepass_->record(cmd, gpuScene, viewProj, depth);
    };
    const double triangles = double(f.scene.triangleCount());
    const double pixels = double(f.settings.width) * f.settings.height;
    pass.work = [name = pass.name, triangles, pixels](const nlohmann::json&) {
      return std::vector<PassWork>{
          {name,
           {derived("triangles", triangles, "every scene triangle drawn once"),
            derived("fragments", pixels, "one per pixel (overdraw not counted)"),
            derived("bytes", 12 * triangles + 4 * pixels,
                    "the index buffer read and the depth written once (vertex fetches not counted)")}}};
    };
  } else {
    const RayTracer cast = f.tracer ? *f.tracer : RayTracer{};
    raster3d_ = std::make_unique<Raster3dPass>(
        f.ctx, f.scene, f.camera, f.settings.width, f.settings.height, f.settings.primary, f.settings.raster3dThreadBox,
        f.settings.fp64Fallback, cast, f.settings.raster3dListPerTile,
        Raster3dFrustumOptions{f.settings.raster3dFrustum, f.settings.raster3dMinFrustum, f.settings.raster3dEarlyZ,
                               f.settings.raster3dStackEntries},
        f.settings.aa);
    if (!f.settings.raster3dListGrows) raster3d_->fixListSize();
    const bool depthCopy = depth.aspect() & VK_IMAGE_ASPECT_DEPTH_BIT;
    if (!depthCopy) raster3d_->resolveInto(depth);
    if (f.settings.primary == PrimaryMethod::RayCast)
      pass.reads = {cast.bvh ? res::kTraceBvh : res::kTlas};
    else
      pass.reads = {res::kSceneVertices, res::kSceneIndices};
    pass.writes.insert(pass.writes.end(), {res::kVisibility, res::kVisibilityRays, res::kVisibilityTriangles});
    pass.subPasses = raster3d_->subPasses();
    pass.work = [name = pass.name, pixels = double(f.settings.width) * f.settings.height,
                 tiles = double(raster3d_->screenTiles()), method = f.settings.primary,
                 depthCopy](const nlohmann::json& a) { return primaryWork(name, a, pixels, tiles, method, depthCopy); };
    // Its steps declare their own accesses (a dispatch writes the visibility buffer, a copy the depth).
    pass.syncedInside = {res::kDepth, res::kVisibility, res::kVisibilityRays, res::kVisibilityTriangles};
    if (f.settings.primary == PrimaryMethod::RayCast) pass.stages = access::kRayStages;
    // Leaves a D32 depth in DEPTH_READ_ONLY_OPTIMAL, the colour one in GENERAL.
    pass.record = [this, &depth](VkCommandBuffer cmd, const PassFrame& frame) {
      raster3d_->record(cmd, *frame.sync, depth, frame.analysis, frame.timer);
    };
    f.resources.publish(res::kVisibility, raster3d_->visibility(), "u64: t bits << 32 | triangle id",
                        std::to_string(f.settings.width) + " x " + std::to_string(f.settings.height));
    f.resources.publish(res::kVisibilityRays, raster3d_->constants(), "gpu::Raster3dConstants", "1");
    f.resources.publish(res::kVisibilityTriangles, raster3d_->triangles(), "3 x vec4 per triangle (world)",
                        std::to_string(raster3d_->triangleCount()) + " triangles");
  }
  passes_.push_back(std::move(pass));
}

// --- light lists --------------------------------------------------------------------------------

LightListsPart::LightListsPart(FrameBuilder& f) {
  const RenderSettings& s = f.settings;
  const uint32_t lightCount = uint32_t(f.scene.lights.size());
  CullingSettings cs{.tileSize = s.tileSize,
                     .lightCulling = s.lightCulling,
                     .aabb = s.aabb,
                     .depthSlices = s.depthSlices,
                     .lists = s.lightLists,
                     .lightCount = lightCount};
  if (s.lightLists == LightLists::Zbin) {
    // The bins span the near plane to the farthest corner of the scene's bounds in view depth.
    glm::vec3 lo, hi;
    f.scene.bounds(lo, hi);
    float far = 0.0f;
    for (int c = 0; c < 8; ++c) {
      const glm::vec3 corner(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z);
      far = std::max(far, -(f.view * glm::vec4(corner, 1.0f)).z);
    }
    cs.zbinNear = f.camera.znear;
    cs.zbinFar = std::max(far, 2.0f * f.camera.znear);
  }
  culling_ =
      std::make_unique<LightCulling>(f.ctx, cs, s.width, s.height, f.resources.requireBuffer(res::kFrameConstants),
                                     f.resources.requireBuffer(res::kLights), f.resources.requireImage(res::kDepth),
                                     f.resources.sampler(res::kPointSampler));
  f.constants.lists = culling_->listConstants();
  f.constants.zbins = culling_->zbinConstants();
  const CullingOutputs o = culling_->outputs();
  const std::string tiles = std::to_string(o.tilesX) + " x " + std::to_string(o.tilesY) + " tiles";
  f.resources.publish(res::kListLights, *o.lights, "gpu::GpuLight", std::to_string(lightCount) + " lights");
  f.resources.publish(res::kListGrid, *o.grid, "u32 x 4 per tile (offset, count, total, -)", tiles);
  f.resources.publish(res::kListIndices, *o.indices,
                      s.lightLists == LightLists::Tile ? "u32 light index per slot" : "u32 mask words per tile", tiles);

  FramePass pass;
  pass.name = kLightCullingPass;
  pass.reads = {res::kFrameConstants, res::kLights, res::kDepth};
  pass.writes = {res::kListLights, res::kListGrid, res::kListIndices};
  pass.subPasses = culling_->subPasses();
  pass.syncedInside = pass.writes;  // each dispatch declares its own
  pass.record = [this, lightCount](VkCommandBuffer cmd, const PassFrame& frame) {
    culling_->recordCulling(cmd, *frame.sync, lightCount, frame.timer);
  };
  pass.work = [this, pixels = double(s.width) * s.height, lightCount](const nlohmann::json&) {
    const double bytes = 4 * pixels + double(lightCount) * sizeof(gpu::GpuLight) + double(culling_->memoryBytes());
    std::vector<PassWork> work{
        {kLightCullingPass,
         {derived("bytes", bytes, "the depth and the lights read once, the grid and lists written once")}}};
    for (const LightCulling::SubPassWork& w : culling_->subPassWork(lightCount)) {
      PassWork sub{w.name, {derived("bytes", w.bytes, "what the dispatch reads and writes once (sizes)")}};
      if (w.compares > 0)
        sub.items.push_back(derived("fma", w.compares, "a compare-and-count per pair of lights (one issue slot)"));
      work.push_back(std::move(sub));
    }
    return work;
  };
  passes_.push_back(std::move(pass));
}

void LightListsPart::recordOnce(VkCommandBuffer cmd, Sync& sync) const { culling_->recordFrustums(cmd, sync); }

// --- shading ------------------------------------------------------------------------------------

ShadingPart::ShadingPart(FrameBuilder& f) {
  const FrameResources& r = f.resources;
  const RenderSettings& s = f.settings;
  const bool lists = r.has(res::kListGrid);
  ShadingInputs in{&r.requireBuffer(res::kFrameConstants),
                   lists ? &r.requireBuffer(res::kListLights) : &r.requireBuffer(res::kLights),
                   r.buffer(res::kListGrid),
                   r.buffer(res::kListIndices),
                   r.buffer(res::kShadowVisibility),
                   &r.requireImage(res::kDepth),
                   s.tileSize,
                   lists ? f.constants.lists.x : gpu::kListTile,
                   r.buffer(res::kVisibility),
                   s.raster3dShadingDepthTest,
                   s.shading == ShadingMethod::Visbuffer,
                   r.buffer(res::kVisibilityRays)};
  for (const ShadingTerm& t : r.shadingTerms())
    in.terms.push_back({t, t.storage == ShadingTerm::Storage::Rgba32fImage ? nullptr : &r.requireBuffer(t.resource),
                        t.storage == ShadingTerm::Storage::Rgba32fImage ? &r.requireImage(t.resource) : nullptr});
  // What this frame does not use is specialised away (shading.h): the shadow pass's words per
  // pixel (tile lists hold at most 32 lights; masks and z-bins one bit per scene light), the view.
  const uint32_t listMode = lists ? f.constants.lists.x : gpu::kListTile;
  in.visibilityWords = lists && listMode == gpu::kListTile ? 1u : (f.constants.lightCount + 31u) / 32u;
  in.perspective = f.proj[3][3] != 1.0f;
  in.aa = s.aa;
  in.planeStride = visibilityPlaneStride(s.width, s.height);
  shading_ = std::make_unique<ShadingPass>(f.ctx, f.gpuScene, s.width, s.height, in);
  f.resources.publish(res::kColor, shading_->color(), "", VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  f.resources.publish(res::kRefNormals, shading_->refNormals(), "", VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);

  FramePass pass;
  pass.name = kShadingPass;
  pass.reads = {res::kFrameConstants, res::kDepth, res::kSceneVertices, res::kSceneIndices};
  for (const char* optional : {res::kListLights, res::kListGrid, res::kListIndices, res::kShadowVisibility,
                               res::kVisibility, res::kVisibilityRays})
    if (r.has(optional)) pass.reads.push_back(optional);
  for (const ShadingTerm& t : r.shadingTerms()) pass.reads.push_back(t.resource);
  if (!lists) pass.reads.push_back(res::kLights);
  pass.writes = {res::kColor, res::kRefNormals};
  if (s.shading == ShadingMethod::Visbuffer) {
    pass.access = {{res::kColor, access::kComputeWrite}, {res::kRefNormals, access::kComputeWrite}};
  } else {  // a draw: the targets cleared and written, the depth tested and sampled, never written
    pass.stages = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
    const Access depth{access::kDepthTest.stages | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                       access::kDepthTest.access | VK_ACCESS_2_SHADER_SAMPLED_READ_BIT,
                       VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL};
    pass.access = {{res::kColor, access::kColorAttachment.discarding()},
                   {res::kRefNormals, access::kColorAttachment.discarding()},
                   {res::kDepth, depth},
                   {res::kSceneVertices, access::kVertexInput},
                   {res::kSceneIndices, access::kVertexInput}};
  }
  // Per pixel: depth (or the visibility buffer's 8 B), the shadow pass's words, the colour
  // (RGBA16F) written; the lists, materials and textures are not counted.
  const bool visbuffer = s.shading == ShadingMethod::Visbuffer;
  const double perPixel =
      (visbuffer ? 8.0 : 4.0) + 4.0 * (r.has(res::kShadowVisibility) ? in.visibilityWords : 0) + 8.0;
  pass.work = [visbuffer, perPixel, pixels = double(s.width) * s.height](const nlohmann::json&) {
    PassWork w{
        kShadingPass,
        {derived("bytes", perPixel * pixels,
                 "per pixel its depth or visibility, shadow words and colour (lists and textures not counted)")}};
    if (!visbuffer) w.items.push_back(derived("fragments", pixels, "one per pixel (the EQUAL depth test)"));
    return std::vector<PassWork>{w};
  };
  const glm::mat4 viewProj = f.proj * f.view;
  pass.record = [this, viewProj](VkCommandBuffer cmd, const PassFrame& frame) {
    shading_->record(cmd, viewProj, frame.analysis);
  };
  passes_.push_back(std::move(pass));
}

bool PrimaryPart::afterFrame() { return raster3d_ && raster3d_->growList(); }

}  // namespace hb

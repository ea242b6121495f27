#include "frame/passes/raster3d.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <span>
#include <string_view>
#include <tuple>

#include <glm/gtc/matrix_inverse.hpp>

#include "base/errors.h"
#include "frame/passes/aa_samples.h"
#include "frame/passes/depth_prepass.h"
#include "frame/render_settings.h"
#include "gpu/descriptor_binder.h"
#include "gpu/gpu_scene.h"
#include "gpu/primary_bvh.h"

namespace hb {

gpu::Raster3dConstants raster3dConstants(const Camera& camera, uint32_t width, uint32_t height, uint32_t triangleCount,
                                         uint32_t smallArea, uint32_t listPerTile, glm::vec2 sample) {
  const glm::dmat4 viewInv = glm::inverse(glm::dmat4(camera.view));
  const glm::dvec3 right(viewInv[0]), up(viewInv[1]), back(viewInv[2]), eye(viewInv[3]);
  const glm::dvec3 forward = -back;
  const double w = width, h = height, a = w / h, tanHalf = std::tan(double(camera.yfov) * 0.5);
  // Pixel (x, y) centre in NDC: (2(x + 0.5)/W − 1, 2(y + 0.5)/H − 1), Vulkan y down; view-space
  // direction (ndc.x·a·tan, −ndc.y·tan, −1), as reverseZProjection maps it (camera.h). A sample
  // (sx, sy) of the pixel instead of its centre: 2(x + sx)/W − 1 (sx = 0.5 gives the same bits).
  const double sx = sample.x, sy = sample.y;
  const glm::dvec3 d0 = forward + right * ((-1.0 + 2.0 * sx / w) * a * tanHalf) + up * ((1.0 - 2.0 * sy / h) * tanHalf);
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
  // Screen position to the index of the pixel whose sample is there (the centre: w/2 − 0.5).
  c.project =
      glm::vec4(float(w / (2.0 * a * tanHalf)), float(h / (2.0 * tanHalf)), float(w / 2.0 - sx), float(h / 2.0 - sy));
  c.width = width;
  c.height = height;
  c.triangleCount = triangleCount;
  c.smallArea = smallArea;
  // Work items of big boxes: listPerTile (default 64) per 8x8 tile of the screen (boxes overlap:
  // the atrium at 1080p needs about 40 with 8,118,546 covered pairs in 44.6 M box pixels, H100 run
  // at 9c6b312): the size the list starts with. It grows to what a view asks for (growList); a list
  // that is full (before it grows, or never with raster3dListGrows false) is handled, not dropped
  // (raster3d.comp.glsl), and counted (tile_list_overflows).
  c.itemCapacity = listPerTile * ((width + 7) / 8) * ((height + 7) / 8);
  c.tileWorkgroups = 4096;
  c.projection = uint32_t(camera.projection);
  // How far pixel (x, y)'s float ray may project from x with the float constants (r3dScreenBox's
  // tight box). Each constant is its double value rounded once (relative u = 2^-24 a component).
  // With S the larger scale (pixels a unit of tangent), R = W + H: |dx*|, |dy*| = 1/S, |d0*| <=
  // 1 + R/S, so the exact ray d* of a pixel on the screen has |d*| <= 1 + 2R/S and d*·forward = 1.
  // The float ray and the float right, forward move d·right and d·forward by at most
  // 2√3·u·(1 + 2R/S) each; the quotient (|d*·right| <= R/S) by that times (1 + R/S) and 1.01 for
  // the denominator; scaled by S and with scale's and offset's own rounding (u·R each):
  // |π(d(x, y)) − x| <= 3.6u·(S + 2R)·(1 + R/S) + 2u·R. Twice that, rounded up to a float.
  if (camera.projection == CameraProjection::Perspective) {
    const double u = std::ldexp(1.0, -24), S = std::max(double(c.project.x), double(c.project.y)),
                 Sm = std::min(double(c.project.x), double(c.project.y)), R = w + h;
    const double m = 2.0 * (3.6 * u * (S + 2.0 * R) * (1.0 + R / Sm) + 2.0 * u * R);
    const float f = float(m);
    c.boxMargin = double(f) < m ? std::nextafter(f, INFINITY) : f;
  }
  static_assert(uint32_t(CameraProjection::Latlong) == gpu::kProjectionLatlong);
  switch (camera.projection) {
    case CameraProjection::Perspective: break;
    case CameraProjection::Orthographic: {
      // Parallel rays along forward from the view plane through the eye: pixel (x, y)'s centre at
      // NDC (2(x + 0.5)/W − 1, 2(y + 0.5)/H − 1) starts at eye + ndc.x·xmag·right − ndc.y·ymag·up.
      const double xm = camera.xmag, ym = camera.ymag;
      c.rayD0 = glm::vec4(glm::vec3(forward), 0.0f);
      c.rayDx = c.rayDy = glm::vec4(0.0f);
      c.origin0 = glm::vec4(glm::vec3(right * ((-1.0 + 2.0 * sx / w) * xm) + up * ((1.0 - 2.0 * sy / h) * ym)), 0.0f);
      c.originX = glm::vec4(glm::vec3(right * (2.0 * xm / w)), 0.0f);
      c.originY = glm::vec4(glm::vec3(-up * (2.0 * ym / h)), 0.0f);
      c.project = glm::vec4(float(w / (2.0 * xm)), float(h / (2.0 * ym)), float(w / 2.0 - sx), float(h / 2.0 - sy));
      // The orthographic matrix's C and D, as camera.cpp computes them in float: depth = D − C·t.
      c.depth.z = 1.0f / (fzf - fzn);
      c.depth.w = fzf / (fzf - fzn);
      break;
    }
    case CameraProjection::Paraboloid: {
      HB_ASSERT(sx == 0.5 && sy == 0.5);
      // The hemisphere around forward in the largest centred disk (camera_ray.glsl.inc).
      const double radius = 0.5 * double(std::min(width, height));
      c.view = glm::vec4(float(w / 2.0 - 0.5), float(h / 2.0 - 0.5), float(1.0 / radius), float(radius));
      break;
    }
    case CameraProjection::Latlong: {
      HB_ASSERT(sx == 0.5 && sy == 0.5);
      const double pi = 3.14159265358979323846;
      c.view = glm::vec4(float(2.0 * pi / w), float(pi / h), 0.0f, 0.0f);
      break;
    }
  }
  return c;
}

namespace {
std::vector<glm::vec4> packTriangles(const Scene& scene) {
  std::vector<glm::vec4> out;
  for (const glm::vec3& v : scene.worldTriangles()) out.emplace_back(v, 1.0f);
  return out;
}
const char* subPassName(PrimaryMethod mode) { return primaryPassOf(mode); }

// Plane p's constants at p·256 B (minUniformBufferOffsetAlignment is at most 256).
constexpr size_t kConstantsStride = (sizeof(gpu::Raster3dConstants) + 255) / 256 * 256;
// The work list's header (raster3d_common.glsl.inc Items): items and spans taken, demand, most demand, then items.
constexpr size_t kItemsHeader = 32;
constexpr size_t kDemandMaxOffset = 16;
}  // namespace

Raster3dPass::Raster3dPass(const VulkanContext& ctx, const Scene& scene, const Camera& camera, uint32_t width,
                           uint32_t height, PrimaryMethod mode, uint32_t smallArea, bool fp64Fallback,
                           const RayTracer& rayCast, uint32_t listPerTile, const Raster3dFrustumOptions& frusta,
                           AntiAliasing aa)
    : ctx_(ctx),
      mode_(mode),
      width_(width),
      height_(height),
      triangleCount_(uint32_t(scene.triangleCount())),
      planes_(1 + aaStoredSamples(aa)),
      planeStride_(visibilityPlaneStride(width, height)),
      resolve_(ctx) {
  if (!ctx.info().bufferInt64Atomics || !ctx.info().shaderFloat64)
    throw DeviceError("device \"" + ctx.info().name +
                      "\" lacks 64-bit buffer atomics or shaderFloat64, which primary=" +
                      std::string(mode == PrimaryMethod::RayCast ? "raycast" : "3dr") + " needs; use primary=hardware");
  const size_t pixels = size_t(width) * height;
  const gpu::Raster3dConstants c = raster3dConstants(camera, width, height, triangleCount_, smallArea, listPerTile);
  if (aa != AntiAliasing::None) {
    if (mode == PrimaryMethod::RayCast)
      throw InputError(std::string("aa=") + toString(aa) +
                       " needs a rasterizing primary: set primary=3dr, 3dr-binned, 2dr, 2dr-binned or a BVH method");
    if (camera.projection != CameraProjection::Perspective && camera.projection != CameraProjection::Orthographic)
      throw InputError(std::string("aa=") + toString(aa) + " needs a planar view (perspective or orthographic), not " +
                       toString(camera.projection) + ": set aa=none");
  }
  constants_ = Buffer(ctx, kConstantsStride * planes_, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, true, MemClass::Other);
  std::memcpy(constants_.mapped(), &c, sizeof c);
  const std::span<const glm::vec2> samples = aaStoredPositions(aa);
  for (uint32_t p = 1; p < planes_; ++p) {
    const gpu::Raster3dConstants cp =
        raster3dConstants(camera, width, height, triangleCount_, smallArea, listPerTile, samples[p - 1]);
    std::memcpy(static_cast<char*>(constants_.mapped()) + p * kConstantsStride, &cp, sizeof cp);
  }
  sharedPlanes_ = planes_ > 1 && mode == PrimaryMethod::Raster3dBinned &&
                  camera.projection == CameraProjection::Perspective && !frusta.earlyZ;
  static_assert(gpu::kR3dMaxPlanes >= 1 + 16, "the centre and msaa16's samples");
  HB_ASSERT(planes_ <= gpu::kR3dMaxPlanes);
  gpu::R3dPlaneRays rays{};
  for (uint32_t p = 0; p < planes_; ++p)
    std::memcpy(
        &rays.d0[p],
        static_cast<const char*>(constants_.mapped()) + p * kConstantsStride + offsetof(gpu::Raster3dConstants, rayD0),
        sizeof(glm::vec4));
  // Each plane's sample offset, and how far the floats d0[p] lie from d0[0] + offset·(dx, dy), in
  // double: the products of a float by a multiple of 1/16 and the floats are exact there, and the
  // two sums round by at most 2^-52 of their magnitude, which the margin covers.
  const glm::dvec3 d0c(rays.d0[0]), dx(c.rayDx), dy(c.rayDy);
  glm::dvec3 slack(0.0);
  for (uint32_t p = 1; p < planes_; ++p) {
    const glm::dvec2 o = glm::dvec2(samples[p - 1]) - 0.5;
    rays.offset[p] = glm::vec4(glm::vec2(o), 0.0f, 0.0f);
    const glm::dvec3 moved = d0c + o.x * dx + o.y * dy;
    const glm::dvec3 margin = std::ldexp(1.0, -50) * (glm::abs(d0c) + glm::abs(o.x * dx) + glm::abs(o.y * dy));
    slack = glm::max(slack, glm::abs(glm::dvec3(rays.d0[p]) - moved) + margin);
  }
  for (int k = 0; k < 3; ++k) {  // rounded up to float
    const float f = float(slack[k]);
    rays.slack[k] = double(f) < slack[k] ? std::nextafter(f, INFINITY) : f;
  }
  rays.info = glm::uvec4(planeStride_, planes_, 0, 0);
  planeRays_ = Buffer(ctx, sizeof rays, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, true, MemClass::Other);
  std::memcpy(planeRays_.mapped(), &rays, sizeof rays);
  const std::vector<glm::vec4> tris = packTriangles(scene);
  triangles_ = uploadBuffer(ctx, tris.data(), std::max<size_t>(1, tris.size()) * sizeof(glm::vec4),
                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemClass::Geometry);
  const VkBufferUsageFlags rw =
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
  vis_ = Buffer(ctx, size_t(planeStride_) * planes_ * sizeof(uint64_t), rw, false, MemClass::Images);
  counters_ = Buffer(ctx, gpu::kR3dCounterCount * sizeof(uint64_t), rw, false, MemClass::Other);
  sampleCounters_ = Buffer(ctx, gpu::kR3dCounterCount * sizeof(uint64_t), rw, false, MemClass::Other);
  coverage_ = Buffer(ctx, size_t(planeStride_) * planes_ * sizeof(uint32_t), rw, false, MemClass::Images);
  tested_ = Buffer(ctx, size_t(planeStride_) * planes_ * sizeof(uint32_t), rw, false, MemClass::Images);
  depthStaging_ = Buffer(ctx, pixels * sizeof(float), rw, false, MemClass::Images);
  // Plane 0's resources, which the resolve and the ray cast read too; the sample planes' follow.
  DescriptorBinder binder("raster3d");
  binder.provide("Constants", constants_, 0, sizeof c);
  binder.provide("Visibility", vis_, 0, pixels * sizeof(uint64_t));
  binder.provide("Depth", depthStaging_);
  binder.provide("Counters", counters_);
  binder.provide("Coverage", coverage_, 0, pixels * sizeof(uint32_t));
  resolve_.createCompute(binder, "raster3d_resolve.comp", 0);

  if (mode == PrimaryMethod::RayCast) {
    HB_ASSERT(rayCast.tlas != VK_NULL_HANDLE || rayCast.bvh != nullptr);
    const std::vector<uint32_t> idBase = triangleIdBase(scene);
    idBase_ = uploadBuffer(ctx, idBase.data(), idBase.size() * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                           MemClass::Other);
    if (rayCast.bvh) {  // our traversal gives draw-order ids itself; the driver's hits need the table
      binder.provide("BvhNodes", rayCast.bvh->nodes);
      binder.provide("BvhTriangles", rayCast.bvh->triangles);
    } else {
      binder.provide("tlas", rayCast.tlas);
      binder.provide("IdBase", idBase_);
    }
    if (rayCast.rayQuery() || rayCast.bvh) {
      castTimed_ = std::make_unique<Pipeline>(ctx);
      castAnalysis_ = std::make_unique<Pipeline>(ctx);
      for (auto [p, analysis] : {std::pair{castTimed_.get(), 0u}, std::pair{castAnalysis_.get(), 1u}}) {
        if (rayCast.bvh)  // 8x8 threads a group
          p->createCompute(
              binder, "primary_raycast_compute.comp", 0,
              {{analysis, rayCast.bvh->stack, traceStackShared(*rayCast.bvh, 64, true) ? 1u : 0u, rayCast.bvh->width}});
        else
          p->createCompute(binder, "primary_raycast.comp", 0, {{analysis}});
      }
    } else {
      castRtTimed_ = std::make_unique<RaygenMissPipeline>(ctx, binder, "primary_raycast.rgen", "primary_raycast.rmiss",
                                                          SpecConstants{{0u}}, "primary_raycast.rchit");
      castRtAnalysis_ = std::make_unique<RaygenMissPipeline>(
          ctx, binder, "primary_raycast.rgen", "primary_raycast.rmiss", SpecConstants{{1u}}, "primary_raycast.rchit");
    }
    binder.checkEveryNameRead();
    return;
  }

  tileWorkgroups_ = c.tileWorkgroups;
  screenTiles_ = ((width + 7) / 8) * ((height + 7) / 8);
  const bool bvh = primaryUsesBvh(mode);
  const bool binned = mode == PrimaryMethod::Raster3dBinned || mode == PrimaryMethod::Raster2dBinned;
  auto log2Of8 = [](uint32_t side) {  // side = 8 << result
    uint32_t l = 0;
    while ((8u << l) < side) ++l;
    return l;
  };
  if (bvh) {
    // The traversal shader's shared HiZ holds levels 0..5 (config_params limits the choices).
    HB_ASSERT(frusta.frustum >= 8 && frusta.frustum <= 256 && (frusta.frustum & (frusta.frustum - 1)) == 0);
    if (frusta.minFrustum > frusta.frustum)
      throw InputError("r3d_min_frustum=" + std::to_string(frusta.minFrustum) + " is larger than r3d_frustum=" +
                       std::to_string(frusta.frustum) + ": set r3d_min_frustum to at most r3d_frustum");
    const PrimaryBvh tree = buildPrimaryBvh(scene.worldTriangles());
    bvhNodes_ = uploadBuffer(ctx, tree.nodes.data(), tree.nodes.size() * sizeof(gpu::PrimaryBvhNode),
                             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemClass::Geometry);
    const std::vector<uint32_t> order = tree.order.empty() ? std::vector<uint32_t>{0u} : tree.order;
    bvhOrder_ = uploadBuffer(ctx, order.data(), order.size() * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                             MemClass::Geometry);
    bvhStats_ = {uint32_t(tree.nodes.size()), tree.depth,
                 uint64_t(tree.nodes.size() * sizeof(gpu::PrimaryBvhNode) + order.size() * sizeof(uint32_t)),
                 tree.buildMs};
    frusta_ = ((width + frusta.frustum - 1) / frusta.frustum) * ((height + frusta.frustum - 1) / frusta.frustum);
  } else {
    bvhNodes_ = Buffer(ctx, sizeof(gpu::PrimaryBvhNode), rw, false, MemClass::Other);
    bvhOrder_ = Buffer(ctx, sizeof(uint32_t), rw, false, MemClass::Other);
  }
  bins_ = Buffer(ctx, (binned ? 3 * size_t(screenTiles_) : 1) * sizeof(uint32_t), rw, false, MemClass::Other);
  // The dispatches in order: (shader, its PASS). Specialization constants (raster3d_common.glsl.inc):
  // 0 pass, 1 analysis, 2 fp64 fallback, 3 binned, 4 2D homogeneous, 5 projection; the tile pass's
  // 6 early-z; the BVH traversal's (raster3d_bvh.comp.glsl) 6 split, 7 occlusion, 8 binning,
  // 9 early-z, 10 log2(r3d_frustum / 8), 11 log2(r3d_min_frustum / 8).
  using Stages = std::vector<std::pair<const char*, uint32_t>>;
  const Stages stages = bvh      ? Stages{{"raster3d_bvh.comp", 0}}
                        : binned ? Stages{{"raster3d.comp", 0},
                                          {"raster3d.comp", 3},
                                          {"raster3d_scan.comp", 2},
                                          {"raster3d.comp", 4},
                                          {"raster3d_tiles.comp", 1}}
                                 : Stages{{"raster3d.comp", 0}, {"raster3d.comp", 1}};
  const bool twoD = mode == PrimaryMethod::Raster2d || mode == PrimaryMethod::Raster2dBinned;
  const bool split = mode == PrimaryMethod::Raster3dFrustumSplit || mode == PrimaryMethod::Raster3dFull;
  const bool full = mode == PrimaryMethod::Raster3dFull;
  // The dispatches share one set (raster3d_common.glsl.inc), laid out from their shaders together.
  std::vector<std::string> shaders;
  for (const auto& [shader, pass] : stages)
    if (std::find(shaders.begin(), shaders.end(), shader) == shaders.end()) shaders.emplace_back(shader);
  // Shared sample planes: timed frames' tile pass is its own shader (the plane-by-plane one has none
  // of its code).
  constexpr const char* kPlanesTiles = "raster3d_tiles_planes.comp";
  if (sharedPlanes_) shaders.emplace_back(kPlanesTiles);
  rasterProgram_ = std::make_unique<ShaderProgram>(shaders);
  demandOut_ = Buffer(ctx, sizeof(uint64_t), VK_BUFFER_USAGE_TRANSFER_DST_BIT, true, MemClass::Other);
  makeLists(c.itemCapacity);
  for (const auto& [shader, pass] : stages)
    for (uint32_t analysis = 0; analysis < 2; ++analysis) {
      auto p = std::make_unique<Pipeline>(ctx);
      p->createLayout({rasterSets_[0]->layout()}, 0);
      std::vector<uint32_t> spec{pass,           analysis,    fp64Fallback ? 1u : 0u, binned ? 1u : 0u,
                                 twoD ? 1u : 0u, c.projection};
      if (bvh)
        spec.insert(spec.end(), {split ? 1u : 0u, split ? 1u : 0u, split && !full ? 0u : 1u, full ? 1u : 0u,
                                 log2Of8(frusta.frustum), log2Of8(frusta.minFrustum), frusta.stackEntries});
      else  // 6 early-z (the tile pass), 7 the planes a pass rasterizes (raster3d_common.glsl.inc)
        spec.insert(spec.end(), {mode == PrimaryMethod::Raster2dBinned || frusta.earlyZ ? 1u : 0u,
                                 sharedPlanes_ && analysis == 0 ? planes_ : 1u});
      const bool planesTiles = sharedPlanes_ && analysis == 0 && std::string_view(shader) == "raster3d_tiles.comp";
      p->createCompute(*rasterProgram_, planesTiles ? kPlanesTiles : shader, {spec});
      (analysis ? analysis_ : timed_).push_back(std::move(p));
    }
}

void Raster3dPass::makeLists(uint64_t capacity) {
  const bool bvh = primaryUsesBvh(mode_);
  const bool binned = mode_ == PrimaryMethod::Raster3dBinned || mode_ == PrimaryMethod::Raster2dBinned;
  // Item slots are addressed by 32-bit indices (raster3d.comp.glsl): a list past them cannot be had.
  HB_ASSERT(capacity <= 0xFFFFFFFFull);
  itemCapacity_ = capacity;
  const VkBufferUsageFlags rw =
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
  big_ = Buffer(ctx_, kItemsHeader + (bvh ? 1 : size_t(capacity)) * 2 * sizeof(uint32_t), rw, false, MemClass::Other);
  // A span (id, first item) per big triangle, at most one a triangle (raster3d_common.glsl.inc Spans).
  spans_ =
      Buffer(ctx_, (bvh ? 1 : std::max<size_t>(triangleCount_, 1)) * 2 * sizeof(uint32_t), rw, false, MemClass::Other);
  // Binned: each big triangle's setup, made once by the per-triangle dispatch at its span's index
  // and read by the count, fill and tile dispatches (raster3d_common.glsl.inc Setups).
  setups_ = Buffer(ctx_, (binned ? std::max<size_t>(triangleCount_, 1) : 1) * sizeof(gpu::R3dSetupRecord), rw, false,
                   MemClass::Other);
  binList_ = Buffer(ctx_, (binned ? size_t(capacity) : 1) * sizeof(uint32_t), rw, false, MemClass::Other);
  for (uint32_t p = 0; p < planes_; ++p) {
    gpu::Raster3dConstants c;
    char* at = static_cast<char*>(constants_.mapped()) + p * kConstantsStride;
    std::memcpy(&c, at, sizeof c);
    c.itemCapacity = uint32_t(capacity);
    std::memcpy(at, &c, sizeof c);
  }
  // Set p rasterizes plane p: its constants, its visibility, coverage and test counts; the sample
  // planes count their work apart from plane 0's (readSampleCounters).
  const size_t pixels = size_t(width_) * height_;
  rasterSets_.clear();
  for (uint32_t p = 0; p < planes_; ++p) {
    DescriptorBinder b("raster3d");
    b.provide("Constants", constants_, p * kConstantsStride, sizeof(gpu::Raster3dConstants));
    // Shared sample planes: set 0's dispatches write every plane (timed frames).
    b.provide("Visibility", vis_, size_t(p) * planeStride_ * 8,
              sharedPlanes_ && p == 0 ? size_t(planes_) * planeStride_ * 8 : pixels * 8);
    b.provide("Counters", p == 0 ? counters_ : sampleCounters_);
    b.provide("Coverage", coverage_, size_t(p) * planeStride_ * 4, pixels * 4);
    b.provide("Tested", tested_, size_t(p) * planeStride_ * 4, pixels * 4);
    b.provide("Triangles", triangles_);
    if (bvh) {  // the traversal reads the tree; the brute-force and binned dispatches their work lists
      b.provide("BvhNodes", bvhNodes_);
      b.provide("BvhOrder", bvhOrder_);
    } else {
      b.provide("PlaneRays", planeRays_);
      b.provide("Items", big_);
      b.provide("Spans", spans_);
      b.provide("Setups", setups_);
      b.provide("Bins", bins_);
      b.provide("BinList", binList_);
    }
    rasterSets_.push_back(b.write(ctx_, *rasterProgram_));
    b.checkEveryNameRead();
  }
}

bool Raster3dPass::growList() {
  if (!demandCopied_ || listFits_) return false;
  demandCopied_ = false;
  uint64_t demand = 0;
  std::memcpy(&demand, demandOut_.mapped(), sizeof demand);
  if (demand <= itemCapacity_) {
    listFits_ = true;  // this view's frames fit: no more copies
    return false;
  }
  // As large as a storage buffer binding may be (and 32-bit item indices): past that a full list
  // is handled as before (counted as tile_list_overflows), and the list stops growing.
  const uint64_t bindable = (uint64_t(ctx_.properties().limits.maxStorageBufferRange) - kItemsHeader) / 8;
  const uint64_t most = std::min<uint64_t>(bindable, 0xFFFFFFFFull) / 64 * 64;
  const uint64_t grown = std::min<uint64_t>((demand + 63) / 64 * 64, most);
  if (grown <= itemCapacity_) {
    listFits_ = true;
    return false;
  }
  if (grownFrom_ == 0) grownFrom_ = itemCapacity_;
  vkDeviceWaitIdle(ctx_.device());  // the old lists' last frame is done (the caller waited on it)
  makeLists(grown);
  return true;
}

Raster3dPass::~Raster3dPass() = default;

std::vector<std::string> Raster3dPass::subPasses() const {
  const std::string pass = subPassName(mode_);
  std::vector<std::string> names;
  if (primaryUsesBvh(mode_))
    names.push_back(pass + ".traverse");
  else if (mode_ == PrimaryMethod::Raster3dBinned || mode_ == PrimaryMethod::Raster2dBinned)
    for (const char* s : {"triangles", "count", "scan", "fill", "tiles"}) names.push_back(pass + "." + s);
  else if (mode_ != PrimaryMethod::RayCast)
    for (const char* s : {"triangles", "tiles"}) names.push_back(pass + "." + s);
  if (planes_ > 1 && !sharedPlanes_) names.push_back(pass + ".samples");
  names.push_back(pass + ".resolve");
  if (!depthImage_) names.push_back(pass + ".depth_copy");
  return names;
}

void Raster3dPass::resolveInto(const Image& depth) {
  HB_ASSERT(depth.format() == kComputeDepthFormat && depth.width() == width_ && depth.height() == height_);
  DescriptorBinder binder("raster3d resolve");
  binder.provide("Constants", constants_, 0, sizeof(gpu::Raster3dConstants));
  binder.provide("Visibility", vis_, 0, size_t(width_) * height_ * sizeof(uint64_t));
  binder.provide("depthImage", depth, VK_IMAGE_LAYOUT_GENERAL);
  resolveImage_ = std::make_unique<Pipeline>(ctx_);
  resolveImage_->createCompute(binder, "raster3d_resolve_image.comp", 0);
  depthImage_ = &depth;
}

nlohmann::json Raster3dPass::compiled() const {
  if (!ctx_.info().pipelineStatistics) return nullptr;
  std::vector<std::string> names;
  if (primaryUsesBvh(mode_))
    names = {"traverse"};
  else if (mode_ == PrimaryMethod::Raster3dBinned || mode_ == PrimaryMethod::Raster2dBinned)
    names = {"triangles", "count", "scan", "fill", "tiles"};
  else if (mode_ != PrimaryMethod::RayCast)
    names = {"triangles", "tiles"};
  nlohmann::json out = nlohmann::json::object();
  for (size_t k = 0; k < names.size() && k < timed_.size(); ++k)
    out[names[k]] = pipelineStatistics(ctx_, timed_[k]->handle());
  out["resolve"] = pipelineStatistics(ctx_, (resolveImage_ ? *resolveImage_ : resolve_).handle());
  return out;
}

std::vector<Use> Raster3dPass::working(Access a, bool analysis) const {
  std::vector<Use> uses;
  // The counters and coverage too in a timed frame: some dispatches update them whatever the frame
  // (the anti-aliasing sample counters), and they share the steps' one barrier call anyway.
  (void)analysis;
  for (const Buffer* b : {&vis_, &triangles_, &depthStaging_, &big_, &spans_, &setups_, &bins_, &binList_, &idBase_,
                          &bvhNodes_, &bvhOrder_, &counters_, &sampleCounters_, &coverage_, &tested_})
    uses.push_back({*b, a});
  return uses;
}

void Raster3dPass::recordRaster(VkCommandBuffer cmd, Sync& sync, bool analysis, GpuTimer* timer) const {
  recordPlane(cmd, sync, 0, analysis, timer);
  if (planes_ == 1 || (sharedPlanes_ && !analysis)) return;  // shared: plane 0's dispatches did every plane
  // The anti-aliasing samples: the same dispatches once per sample plane, timed together.
  // (Analysis frames of shared planes go plane by plane untimed: subPasses() has no ".samples".)
  if (sharedPlanes_) timer = nullptr;
  if (timer) timer->begin(cmd, std::string(subPassName(mode_)) + ".samples");
  for (uint32_t p = 1; p < planes_; ++p) {
    const bool binned = mode_ == PrimaryMethod::Raster3dBinned || mode_ == PrimaryMethod::Raster2dBinned;
    std::vector<Use> cleared = {{big_, access::kFill}};
    if (binned) cleared.push_back({bins_, access::kFill});
    sync.use(cmd, cleared);
    vkCmdFillBuffer(cmd, big_.handle(), 0, 16, 0);
    if (binned) vkCmdFillBuffer(cmd, bins_.handle(), 0, VK_WHOLE_SIZE, 0);
    recordPlane(cmd, sync, p, analysis, nullptr);
  }
  if (timer) timer->end(cmd);
}

void Raster3dPass::recordPlane(VkCommandBuffer cmd, Sync& sync, uint32_t plane, bool analysis, GpuTimer* timer) const {
  VkDescriptorSet set = rasterSets_[plane]->set();
  const bool binned = mode_ == PrimaryMethod::Raster3dBinned || mode_ == PrimaryMethod::Raster2dBinned;
  // Each dispatch reads what the one before it wrote and atomically updates the working buffers:
  // each waits for the one before (the barrier falls between the sub-passes' intervals).
  const std::vector<Use> rw = working(access::kComputeWrite, analysis);
  auto dispatch = [&](uint32_t pass, uint32_t groups, const char* name) {
    sync.use(cmd, rw);
    if (timer) timer->begin(cmd, std::string(subPassName(mode_)) + "." + name);
    const Pipeline& p = *(analysis ? analysis_ : timed_)[pass];
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.handle());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.layout(), 0, 1, &set, 0, nullptr);
    vkCmdDispatch(cmd, groups, 1, 1);
    if (timer) timer->end(cmd);
  };
  if (primaryUsesBvh(mode_)) {
    dispatch(0, frusta_, "traverse");
    return;
  }
  const uint32_t triangleGroups = (triangleCount_ + 63) / 64;
  dispatch(0, triangleGroups, "triangles");
  if (binned) {
    dispatch(1, tileWorkgroups_, "count");
    dispatch(2, 1, "scan");
    dispatch(3, tileWorkgroups_, "fill");
    dispatch(4, screenTiles_, "tiles");
  } else {
    dispatch(1, tileWorkgroups_, "tiles");
  }
}

void Raster3dPass::recordRayCast(VkCommandBuffer cmd, Sync& sync, bool analysis) const {
  sync.use(cmd, working(access::kRayWrite, analysis));
  if (castTimed_) {
    const Pipeline& p = analysis ? *castAnalysis_ : *castTimed_;
    VkDescriptorSet set = p.set();
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.handle());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.layout(), 0, 1, &set, 0, nullptr);
    vkCmdDispatch(cmd, (width_ + 7) / 8, (height_ + 7) / 8, 1);
  } else {
    const RaygenMissPipeline& p = analysis ? *castRtAnalysis_ : *castRtTimed_;
    VkDescriptorSet set = p.pipeline().set();
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, p.pipeline().handle());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, p.pipeline().layout(), 0, 1, &set, 0, nullptr);
    p.traceRays(cmd, width_, height_);
  }
}

void Raster3dPass::record(VkCommandBuffer cmd, Sync& sync, const Image& depth, bool analysis, GpuTimer* timer) const {
  const bool cast = mode_ == PrimaryMethod::RayCast;
  std::vector<Use> cleared;
  if (!cast) cleared = {{vis_, access::kFill}, {big_, access::kFill}};
  if (mode_ == PrimaryMethod::Raster3dBinned || mode_ == PrimaryMethod::Raster2dBinned)
    cleared.push_back({bins_, access::kFill});
  if (analysis)
    for (const Buffer* b : {&counters_, &sampleCounters_, &coverage_, &tested_}) cleared.push_back({*b, access::kFill});
  sync.use(cmd, cleared);
  if (!cast) vkCmdFillBuffer(cmd, vis_.handle(), 0, VK_WHOLE_SIZE, 0xFFFFFFFFu);  // "nothing": the largest key
  if (!cast) vkCmdFillBuffer(cmd, big_.handle(), 0, kItemsHeader, 0);             // the item count and demands
  if (mode_ == PrimaryMethod::Raster3dBinned || mode_ == PrimaryMethod::Raster2dBinned)
    vkCmdFillBuffer(cmd, bins_.handle(), 0, VK_WHOLE_SIZE, 0);
  if (analysis) {
    vkCmdFillBuffer(cmd, counters_.handle(), 0, VK_WHOLE_SIZE, 0);
    vkCmdFillBuffer(cmd, sampleCounters_.handle(), 0, VK_WHOLE_SIZE, 0);
    vkCmdFillBuffer(cmd, coverage_.handle(), 0, VK_WHOLE_SIZE, 0);
    vkCmdFillBuffer(cmd, tested_.handle(), 0, VK_WHOLE_SIZE, 0);
  }
  if (cast)
    recordRayCast(cmd, sync, analysis);
  else
    recordRaster(cmd, sync, analysis, timer);
  // Until a frame's list fits: the most items a plane asked for, to the host (growList).
  if (!cast && !primaryUsesBvh(mode_) && !listFits_) {
    sync.use(cmd, {{big_, access::kCopyRead}, {demandOut_, access::kCopyWrite}});
    const VkBufferCopy region{kDemandMaxOffset, 0, sizeof(uint64_t)};
    vkCmdCopyBuffer(cmd, big_.handle(), demandOut_.handle(), 1, &region);
    demandCopied_ = true;
  }
  // The resolve reads the visibility buffer into the depth image itself (resolveInto: 8 x 8 pixels
  // a workgroup, the image's tiles), or into a buffer that is then copied into it.
  HB_ASSERT(!depthImage_ || &depth == depthImage_);
  std::vector<Use> resolve = working(access::kComputeRead, analysis);
  resolve.push_back(depthImage_ ? Use{depth, access::kComputeWrite.discarding()}
                                : Use{depthStaging_, access::kComputeWrite});
  sync.use(cmd, resolve);
  if (timer) timer->begin(cmd, std::string(subPassName(mode_)) + ".resolve");
  const Pipeline& rp = depthImage_ ? *resolveImage_ : resolve_;
  VkDescriptorSet rset = rp.set();
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, rp.handle());
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, rp.layout(), 0, 1, &rset, 0, nullptr);
  if (depthImage_)
    vkCmdDispatch(cmd, (width_ + 7) / 8, (height_ + 7) / 8, 1);
  else
    vkCmdDispatch(cmd, uint32_t((size_t(width_) * height_ + 63) / 64), 1, 1);
  if (timer) timer->end(cmd);
  if (depthImage_) return;  // its readers declare their reads: the frame records the barriers before them
  // The depth buffer into the depth image (a depth format cannot be a storage image), timed on its
  // own so that the roofline tells the resolve's bandwidth from the copy's.
  if (timer) timer->begin(cmd, std::string(subPassName(mode_)) + ".depth_copy");
  sync.use(cmd, {{depthStaging_, access::kCopyRead}, {depth, access::kCopyWrite.discarding()}});
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 0, 1};
  region.imageExtent = {width_, height_, 1};
  vkCmdCopyBufferToImage(cmd, depthStaging_.handle(), depth.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
  if (timer) timer->end(cmd);
  // The passes after it declare their reads of the depth and the visibility buffer: the frame
  // records the barriers (and the depth's move to DEPTH_READ_ONLY_OPTIMAL) before them.
}

template <typename T>
static std::vector<T> readAs(const VulkanContext& ctx, const Buffer& b) {
  const std::vector<uint8_t> bytes = readbackBuffer(ctx, b);
  std::vector<T> out(bytes.size() / sizeof(T));
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
  return out;
}

// Plane `plane` of a buffer of planes_ planes (planeStride_ entries apart) of width_·height_ values.
template <typename T>
static std::vector<T> readPlane(const VulkanContext& ctx, const Buffer& b, uint32_t plane, uint32_t stride,
                                size_t pixels) {
  std::vector<T> all = readAs<T>(ctx, b);
  HB_ASSERT((size_t(plane) * stride + pixels) <= all.size());
  return std::vector<T>(all.begin() + ptrdiff_t(size_t(plane) * stride),
                        all.begin() + ptrdiff_t(size_t(plane) * stride + pixels));
}

std::vector<uint64_t> Raster3dPass::readVisibility(uint32_t plane) const {
  return readPlane<uint64_t>(ctx_, vis_, plane, planeStride_, size_t(width_) * height_);
}
std::vector<uint32_t> Raster3dPass::readCoverage(uint32_t plane) const {
  return readPlane<uint32_t>(ctx_, coverage_, plane, planeStride_, size_t(width_) * height_);
}
std::vector<uint32_t> Raster3dPass::readPixelTests(uint32_t plane) const {
  return readPlane<uint32_t>(ctx_, tested_, plane, planeStride_, size_t(width_) * height_);
}

Raster3dCounters Raster3dPass::readCounters() const { return countersOf(readAs<uint64_t>(ctx_, counters_)); }
Raster3dCounters Raster3dPass::readSampleCounters() const {
  return countersOf(readAs<uint64_t>(ctx_, sampleCounters_));
}

Raster3dCounters countersOf(const std::vector<uint64_t>& c) {
  Raster3dCounters r;
  r.setups = c[gpu::kR3dCounterSetups];
  r.edgeEvaluations = c[gpu::kR3dCounterEdgeEvals];
  r.fallbacks = c[gpu::kR3dCounterFallbacks];
  r.pixelsTested = c[gpu::kR3dCounterPixelsTested];
  r.covered = c[gpu::kR3dCounterCovered];
  r.atomics = c[gpu::kR3dCounterAtomics];
  r.bigTriangles = c[gpu::kR3dCounterBig];
  r.listOverflows = c[gpu::kR3dCounterOverflow];
  r.listEntries = c[gpu::kR3dCounterListEntries];
  r.binsRefined = c[gpu::kR3dCounterBinsRefined];
  r.binsEmpty = c[gpu::kR3dCounterBinsEmpty];
  r.nodesVisited = c[gpu::kR3dCounterNodes];
  r.frusta = c[gpu::kR3dCounterFrusta];
  r.frustaSplit = c[gpu::kR3dCounterSplits];
  r.culledFrustum = c[gpu::kR3dCounterCulledFrustum];
  r.culledOcclusion = c[gpu::kR3dCounterCulledOcclusion];
  r.culledEarlyZ = c[gpu::kR3dCounterCulledEarlyZ];
  r.stackOverflows = c[gpu::kR3dCounterStackOverflows];
  return r;
}

}  // namespace hb

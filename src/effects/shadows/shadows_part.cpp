#include "effects/shadows/shadows_part.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "base/errors.h"
#include "effects/shadows/shadows_effect.h"
#include "frame/base_parts.h"
#include "frame/pass_work.h"
#include "gpu/trace_bvh.h"

namespace hb {

namespace {
// Points the shadow pass's settings and inputs at our BVH (backend=compute).
void useBvh(ShadowSettings& ss, ShadowInputs& in, const TraceBvh& bvh, uint32_t tileSize) {
  ss.bvhStack = bvh.stack;
  ss.bvhStackShared = traceStackShared(bvh, tileSize * tileSize);  // a workgroup per tile
  ss.raybenchStackShared = traceStackShared(bvh, 64);
  ss.bvhWidth = bvh.width;
  in.bvhNodes = &bvh.nodes;
  in.bvhTriangles = &bvh.triangles;
}
}  // namespace

ShadowsPart::ShadowsPart(FrameBuilder& f)
    : ctx_(f.ctx),
      scene_(f.scene),
      width_(f.settings.width),
      height_(f.settings.height),
      bvhWidth_(f.settings.bvhWidth),
      resources_(f.resources) {
  const RenderSettings& s = f.settings;
  const FrameResources& r = f.resources;
  // Depth turns back into positions through a planar matrix (perspective or orthographic).
  const bool curved =
      f.camera.projection != CameraProjection::Perspective && f.camera.projection != CameraProjection::Orthographic;
  if (curved && s.worldPos != WorldPosMethod::Hit)
    throw InputError(std::string("projection=") + toString(f.camera.projection) +
                     " with shadows needs world_pos=hit (depth is turned back into positions through a planar "
                     "matrix otherwise)");
  HB_ASSERT(f.tracer != nullptr);  // the plan traces for shadows
  ShadowSettings ss;
  ss.backend = f.tracer->backend();
  ss.tileSize = s.tileSize;
  ss.normals = s.normals;
  ss.worldPos = s.worldPos;
  ss.rangeTest = s.rangeTest;
  ss.listMode = f.constants.lists.x;
  ss.visibilityWords = f.constants.lists.z;
  inputs_ = {&r.requireBuffer(res::kFrameConstants),
             &r.requireBuffer(res::kListLights),
             &r.requireBuffer(res::kListGrid),
             &r.requireBuffer(res::kListIndices),
             &r.requireImage(res::kDepth),
             r.sampler(res::kPointSampler),
             r.tlas(res::kTlas)};
  if (f.tracer->compute()) useBvh(ss, inputs_, *f.tracer->bvh, s.tileSize);
  inputs_.hitIds = r.buffer(res::kVisibility);
  inputs_.hitRays = r.buffer(res::kVisibilityRays);
  inputs_.hitTriangles = r.buffer(res::kVisibilityTriangles);
  shadows_ = std::make_unique<ShadowPass>(f.ctx, ss, s.width, s.height, inputs_);
  f.resources.publish(res::kShadowVisibility, shadows_->visibility(),
                      "u32 x " + std::to_string(ss.visibilityWords) + " per pixel: bit k = the k-th light of the list",
                      std::to_string(s.width) + " x " + std::to_string(s.height));

  FramePass pass;
  pass.name = kShadowsPass;
  pass.reads = {res::kFrameConstants, res::kListLights, res::kListGrid, res::kListIndices, res::kDepth, res::kTlas};
  if (f.tracer->bvh) pass.reads.push_back(res::kTraceBvh);
  if (inputs_.hitIds)
    pass.reads.insert(pass.reads.end(), {res::kVisibility, res::kVisibilityRays, res::kVisibilityTriangles});
  pass.writes = {res::kShadowVisibility};
  pass.stages = access::kRayStages;
  pass.record = [this](VkCommandBuffer cmd, const PassFrame& frame) { shadows_->record(cmd, frame.analysis); };
  pass.work = [](const nlohmann::json& a) {
    return std::vector<PassWork>{
        {kShadowsPass, {counted("rays", figureAt(a, {"rays", "traced"}), "shadow rays traced (rays.traced)")}}};
  };
  passes_.push_back(std::move(pass));
}

template <typename T>
static std::vector<T> bytesAs(const std::vector<uint8_t>& bytes) {
  std::vector<T> out(bytes.size() / sizeof(T));
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
  return out;
}

ShadowReadback ShadowsPart::readShadows() const {
  ShadowReadback r;
  const size_t pixels = size_t(width_) * height_;
  r.words = shadows_->settings().visibilityWords;
  r.visibility = bytesAs<uint32_t>(readbackBuffer(ctx_, shadows_->visibility()));
  HB_ASSERT(r.visibility.size() >= r.words * pixels);
  if (shadows_->settings().listMode == gpu::kListZbin)
    r.ranges.assign(r.visibility.begin() + r.words * pixels, r.visibility.begin() + (r.words + 1) * pixels);
  r.visibility.resize(r.words * pixels);
  r.traced = bytesAs<uint32_t>(readbackBuffer(ctx_, shadows_->traced()));
  HB_ASSERT(r.traced.size() >= r.words * pixels);
  r.traced.resize(r.words * pixels);
  r.accounting = bytesAs<uint32_t>(readbackImage(ctx_, shadows_->accounting(), VK_IMAGE_LAYOUT_GENERAL, 16));
  r.normals = bytesAs<float>(readbackImage(ctx_, shadows_->normals(), VK_IMAGE_LAYOUT_GENERAL, 16));
  r.positions = bytesAs<float>(readbackImage(ctx_, shadows_->positions(), VK_IMAGE_LAYOUT_GENERAL, 16));
  return r;
}

std::vector<RtBackend> ShadowsPart::rayBenchBackends() const {
  std::vector<RtBackend> out{shadows_->settings().backend};
  for (RtBackend b : {RtBackend::RayQuery, RtBackend::Pipeline, RtBackend::Compute}) {
    const bool available = b == RtBackend::Compute    ? true
                           : b == RtBackend::RayQuery ? ctx_.info().rayQuery
                                                      : ctx_.info().rayTracingPipeline;
    if (available && b != out.front()) out.push_back(b);
  }
  return out;
}

std::vector<double> ShadowsPart::rayBench(GpuTimer& timer, uint32_t repetitions, std::optional<RtBackend> backend) {
  const RtBackend b = backend.value_or(shadows_->settings().backend);
  std::unique_ptr<RayBenchPass>& bench = rayBenches_[size_t(b)];
  if (!bench) {
    ShadowInputs in = inputs_;
    const TraceBvh* bvh = nullptr;
    if (b == RtBackend::Compute) {  // the frame's BVH, built here (keyed) when the frame traces with the driver's
      bvh = &frameTraceBvh(resources_, ctx_, scene_, bvhWidth_, "raybench");
      resources_.use(res::kTraceBvh, "raybench");
      in.bvhNodes = &bvh->nodes;
      in.bvhTriangles = &bvh->triangles;
    }
    bench = std::make_unique<RayBenchPass>(ctx_, b, width_, height_, in, *shadows_, bvh);
  }
  std::vector<double> ms;
  for (uint32_t rep = 0; rep < repetitions; ++rep) {
    ctx_.submitAndWait([&](VkCommandBuffer cmd) {
      timer.reset(cmd);
      timer.frameBegin(cmd);
      timer.begin(cmd, "raybench");
      bench->record(cmd);
      timer.end(cmd);
      timer.frameEnd(cmd);
    });
    auto t = timer.read(nullptr);
    ms.push_back(t.empty() ? 0.0 : t[0].second);
  }
  return ms;
}

std::vector<uint32_t> ShadowsPart::readRayBench(std::optional<RtBackend> backend) const {
  const std::unique_ptr<RayBenchPass>& bench = rayBenches_[size_t(backend.value_or(shadows_->settings().backend))];
  HB_ASSERT(bench);
  return bench->readResult();
}

ShadowsPart* shadowsOf(const Renderer& renderer) { return renderer.part<ShadowsPart>(shadowsEffect().name); }

std::unique_ptr<FramePart> buildShadows(FrameBuilder& frame) { return std::make_unique<ShadowsPart>(frame); }

}  // namespace hb

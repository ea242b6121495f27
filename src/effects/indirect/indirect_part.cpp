#include "effects/indirect/indirect_part.h"

#include <cmath>
#include <string>

#include "effects/indirect/indirect_effect.h"
#include "frame/base_parts.h"
#include "frame/pass_work.h"
#include "shared/gpu_types.h"

namespace hb {

IndirectPart::IndirectPart(FrameBuilder& f) {
  const SurfaceInputs surface = surfaceInputs(f);
  IndirectPassSettings is;
  is.indirect = indirectSettingsOf(f.value);
  is.worldPos = surface.worldPos;  // the surface as ambient occlusion takes it
  is.normals = surface.normals;
  is.tracer = f.tracer;
  const IndirectInputs ii{surfaceBindings(f, surface), &f.resources.requireBuffer(res::kLights)};
  FrameLdmSet ldm;
  const LdmSource ldmSource = [&](const std::vector<glm::dvec3>& dirs) -> const LdmBuild& {
    const IndirectSettings& s = is.indirect;
    ldm =
        frameLdmSet(f, dirs, s.ldmResolution, s.ldmBuild, s.ldmList, "indirect", "indirect.ldm", kIndirectLdmBuildPass);
    return *ldm.ldm;
  };
  indirect_ = std::make_unique<IndirectPass>(f.ctx, f.gpuScene, f.scene, is, f.settings.width, f.settings.height, ii,
                                             ldmSource);
  f.resources.publish(kIndirectIrradianceResource, indirect_->irradiance(), "");
  // Reflected as Lambertian: albedo·(1 − metallic)/π·E. The scale is float's 1/π rounded from
  // float's π: where a division by a constant is compiled as the product with its reciprocal,
  // shading's former x / π exactly (else within one RGBA16F step: docs/frame.md "Shading terms").
  constexpr float kInvPi = 1.0f / 3.14159265358979f;
  f.resources.addShadingTerm({kIndirectIrradianceResource,
                              ShadingTerm::Storage::Rgba32fImage,
                              {kInvPi, kInvPi, kInvPi},
                              ShadingTerm::Weight::DiffuseAlbedo,
                              0.0f});

  const double pixels = double(f.settings.width) * f.settings.height;
  const uint32_t bin = indirect_->settings().indirect.splatBin;
  const uint32_t binsX = (f.settings.width + bin - 1) / bin, binsY = (f.settings.height + bin - 1) / bin;
  const double bins = double(binsX) * binsY;
  const double tilesABin = double(bin / gpu::kSplatTile) * double(bin / gpu::kSplatTile);
  // What each pass did, from the analysis frame's "indirect" record and the frame's sizes.
  auto workOf = [pixels, bins, binsX, binsY, tilesABin](const std::string& name, const nlohmann::json& a) {
    const nlohmann::json& in = a.contains("indirect") ? a["indirect"] : nlohmann::json::object();
    const double slots = figureAt(in, {"split_photons", "slots"});
    std::vector<WorkItem> items;
    if (name == kPhotonTracePass && in.value("method", "") == "ldm")
      items = {derived("bytes", 8 * slots, "at least one 8 B list node read per photon slot")};
    else if (name == kPhotonTracePass)
      items = {derived("rays_random", slots, "one ray per photon slot")};
    else if (name == kPhotonSplatPass && in.value("splat", "raster") == "compute") {
      // The steps (photon_splat_bin.comp.glsl, photon_splat.comp.glsl): each slot's 64 B photon read
      // and 12 B of boxes written; its 4 B coarse box read by every group of a row's bins, counting
      // and filling (the fill stops early once its bins are full: at most that); each list entry
      // written, then read with its 8 B box by every tile of its bin; the target written.
      const double entries = figureAt(in, {"splat_bins", "entries"});
      const double gather = tilesABin * entries * 12 + 16 * pixels;
      const std::string byEntries =
          "counted list entries (splat_bins.entries) x the tiles a bin x (4 B entry + 8 B box), "
          "and the RGBA32F target written once";
      // The gathers' arithmetic where the analysis frame counted it: each coverage test is the quad's
      // four edges at the pixel's centre (8 FP32 operations), each term splatAt's expressions (29:
      // photon_splat.glsl.inc), a lower bound on the issue slots.
      auto fmaOf = [&in](const char* tests, const char* terms) {
        const double t = figureAt(in, {"splat_work", tests}), e = figureAt(in, {"splat_work", terms});
        return WorkItem{"fma", 8 * t + 29 * e,
                        std::string("counted: splat_work.") + tests + " x 8 + splat_work." + terms +
                            " x 29 FP32 operations (the coverage test's edges, splatAt's expressions)"};
      };
      const bool counted = in.contains("splat_work");
      std::vector<WorkItem> gatherItems = {derived("bytes", gather, byEntries)};
      // The pixel-photon coverage tests alone, a rate with no device peak: `tables --ceiling` rates it
      // against the same gather on a ceiling run (docs/methods/layered-depth-maps.md).
      auto testsOf = [&in](const char* tests) {
        return WorkItem{"splat_tests", figureAt(in, {"splat_work", tests}),
                        std::string("counted: splat_work.") + tests + " (pixel-photon coverage tests)"};
      };
      if (counted) {
        gatherItems.push_back(fmaOf("tests", "terms"));
        gatherItems.push_back(testsOf("tests"));
      }
      // later_bounce_stride > 1: the count, scan and fill run once over the first bounce's slots and
      // once over the later bounces' ("photon_splat.later.*"); the boxes step over every slot.
      double first = slots;
      if (in.value("later_bounce_stride", 1) > 1 && in.contains("split_photons") &&
          in["split_photons"].contains("per_bounce") && !in["split_photons"]["per_bounce"].empty())
        first = in["split_photons"]["per_bounce"][0].value("slots", slots);
      const double rest = slots - first;
      // The count and fill groups: rowBins bins of a row each (IndirectPass::splatRowBins), reading
      // each of the run's slots' coarse box once.
      auto binRowsOf = [&](double n) {
        const uint32_t r = IndirectPass::splatRowBins(uint64_t(std::ceil(n / gpu::kSplatChunk)), binsX, binsY);
        return double((binsX + r - 1) / r) * binsY;
      };
      auto binning = [&](const std::string& prefix, double n, double listed, const std::string& entriesNote) {
        const double binRows = binRowsOf(n);
        return std::vector<PassWork>{
            {prefix + ".count",
             {derived("bytes", binRows * n * 4,
                      "each of its slots' 4 B coarse box read once by every group of a row's bins")}},
            {prefix + ".scan",
             {derived("bytes", bins * std::ceil(n / gpu::kSplatChunk) * 4 * 3,
                      "each (bin, chunk) count read twice and its start written once, by one workgroup")}},
            {prefix + ".fill",
             {derived("bytes", binRows * n * 4 + listed * 4,
                      "each of its slots' coarse box read by every group of a row's bins (at most: a group "
                      "stops once its bins are full), each list entry written" +
                          entriesNote)}}};
      };
      std::vector<PassWork> later;
      if (rest > 0) {
        later = binning(name + ".later", rest, 0, " (the later run's entries are not counted: its boxes only)");
        if (counted && in["splat_work"].contains("later_tests"))
          later.push_back({name + ".later.gather", {fmaOf("later_tests", "later_terms"), testsOf("later_tests")}});
      }
      std::vector<PassWork> out{
          {name,
           {derived("bytes",
                    slots * 76 + 2 * (binRowsOf(first) * first + binRowsOf(rest) * rest) * 4 + entries * 4 + gather,
                    "its steps' bytes together (photon_splat.*)")}},
          {name + ".boxes", {derived("bytes", slots * 76, "each slot's 64 B photon read, 12 B of boxes written")}},
          {name + ".gather", gatherItems}};
      const std::vector<PassWork> own = binning(name, first, entries, " (splat_bins.entries)");
      out.insert(out.end(), own.begin(), own.end());
      out.insert(out.end(), later.begin(), later.end());
      return out;
    } else if (name == kPhotonSplatPass)
      items = {derived("triangles", 2 * slots, "one quad (two triangles) per photon slot"),
               derived("bytes", 16 * pixels + 64 * slots, "RGBA32F target written once, a 64 B photon read per slot")};
    else
      items = {derived("rays_random", pixels * figureAt(in, {"directions"}), "one gather ray per direction per pixel")};
    return std::vector<PassWork>{{name, items}};
  };
  auto add = [&](const char* name, std::vector<std::string> reads, std::vector<std::string> writes,
                 void (IndirectPass::*record)(VkCommandBuffer, Sync&) const) {
    FramePass pass;
    pass.name = name;
    pass.reads = std::move(reads);
    pass.writes = std::move(writes);
    pass.stages = access::kRayStages;
    pass.syncedInside = pass.writes;  // declared by its steps
    pass.record = [this, record](VkCommandBuffer cmd, const PassFrame& frame) {
      (indirect_.get()->*record)(cmd, *frame.sync);
    };
    pass.work = [workOf, name = std::string(name)](const nlohmann::json& a) { return workOf(name, a); };
    passes_.push_back(std::move(pass));
  };
  std::vector<std::string> traceReads = surfaceReads(surface);
  traceReads.push_back(res::kTlas);
  if (indirect_->settings().computeBvh()) traceReads.push_back(res::kTraceBvh);  // backend=compute: our BVH
  traceReads.push_back(res::kLights);
  if (indirect_->buildsLdms()) {
    addLdmBuildPass(f, ldm, kIndirectLdmBuildPass, "indirect", passes_, skipped_);
    traceReads.push_back(ldm.resource);
  }
  if (indirect_->method() == IndirectMethod::Reference) {
    add(kIndirectGatherPass, traceReads, {kIndirectIrradianceResource}, &IndirectPass::recordGather);
  } else {
    f.resources.publish("indirect.photons", indirect_->photonSlots(), "gpu::Photon per slot",
                        std::to_string(indirect_->slots()) + " slots (primaries x N, then each further bounce's)");
    add(kPhotonTracePass, traceReads, {"indirect.photons"}, &IndirectPass::recordTrace);
    FramePass splat;
    splat.name = kPhotonSplatPass;
    splat.reads = {"indirect.photons", res::kFrameConstants, res::kDepth};
    // splat=raster draws: its vertex and fragment shaders read the photons and sample the depth.
    splat.stages = access::kRayStages | VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
    splat.writes = {kIndirectIrradianceResource};
    splat.subPasses = indirect_->splatSubPasses();  // splat=compute: its five steps, timed inside
    splat.syncedInside = {"indirect.photons", kIndirectIrradianceResource};  // declared by its steps
    splat.record = [this](VkCommandBuffer cmd, const PassFrame& frame) {
      indirect_->recordSplat(cmd, *frame.sync, frame.timer, frame.analysis);
    };
    splat.work = [workOf](const nlohmann::json& a) { return workOf(kPhotonSplatPass, a); };
    passes_.push_back(std::move(splat));
  }
}

IndirectPass* indirectPassOf(const Renderer& renderer) {
  const IndirectPart* p = renderer.part<IndirectPart>(indirectEffect().name);
  return p ? &p->pass() : nullptr;
}

std::unique_ptr<FramePart> buildIndirect(FrameBuilder& frame) { return std::make_unique<IndirectPart>(frame); }

}  // namespace hb

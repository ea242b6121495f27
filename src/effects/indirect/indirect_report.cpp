// The indirect-light effect's report hook (plan/effect.h EffectDef::report).
#include <cstdio>
#include <string>
#include <vector>

#include "analysis/effect_report.h"
#include "analysis/ldm_report.h"
#include "effects/indirect/indirect_analysis.h"
#include "effects/indirect/indirect_effect.h"
#include "effects/indirect/indirect_part.h"

namespace hb {

// Indirect light: its settings, memory, photons and flux, the irradiance image, and its errors
// against the same photons ray traced and the gathered reference (IndirectPass::computeWith).
static nlohmann::json indirectJson(IndirectPass& ind, uint32_t w, uint32_t h, const ImageWriter& write,
                                   std::vector<std::string>& summary) {
  nlohmann::json j = ind.settings().indirect.toJson();
  const IndirectMemory m = ind.memory();
  j["memory_bytes"] = {{"ldm", m.ldmBytes},       {"photons", m.photonBytes},
                       {"faces", m.faceBytes},    {"directions", m.directionBytes},
                       {"target", m.targetBytes}, {"textures", m.textureBytes},
                       {"splat", m.splatBytes},   {"total", m.total()}};
  if (const LdmBuild* ldm = ind.ldm()) j["ldm"] = ldmJson(*ldm, ldm->links().size());
  if (const auto st = ind.splatStats())  // splat=compute's binning, from the frame just rendered
    j["splat_bins"] = {{"entries", st->entries},
                       {"bins", st->bins},
                       {"over_capacity", st->overCapacity},
                       {"capacity", st->capacity},
                       {"source",
                        "counted: the coarse bins' ranges after the analysis frame (with later_bounce_stride > 1, the "
                        "first bounce's run)"}};
  if (nlohmann::json ps = ind.splatPipelineStatistics(); !ps.is_null()) j["splat_pipelines"] = std::move(ps);
  if (const auto st = ind.splatStats(); st && st->counted) {
    j["splat_work"] = {{"tests", st->tests},
                       {"terms", st->terms},
                       {"source",
                        "counted by the analysis frame's gathers: pixel-photon coverage tests (a listed photon "
                        "against a receiving pixel's centre) and the terms added (covered, facing, inside the "
                        "ellipse)"}};
    if (ind.settings().indirect.laterBounceStride > 1 && ind.settings().indirect.bounces > 1) {
      j["splat_work"]["later_tests"] = st->laterTests;
      j["splat_work"]["later_terms"] = st->laterTerms;
    }
  }
  j["emitters"] = ind.emitters();
  j["flux_emitted_w"] = ind.emittedFlux();
  const IndirectMethod method = ind.method();
  std::vector<gpu::Photon> photons;
  const std::vector<float> mine = ind.computeWith(method, &photons);
  if (method != IndirectMethod::Reference) {
    const PhotonTally t = tallyPhotons(photons);
    j["split_photons"] = {
        {"primaries", ind.primaries()},
        {"slots", t.slots},
        {"stored", t.stored},
        {"hidden", t.hidden},
        {"escaped", t.escaped},
        {"grazing", t.grazing},
        {"empty", t.empty},
        {"flux_reflected_w", t.fluxReflected()},
        {"flux_stored_w", t.fluxStored},
        {"flux_hidden_w", t.fluxHidden},
        {"flux_escaped_w", t.fluxEscaped},
        {"flux_grazing_w", t.fluxGrazing},
        {"discarded_share", t.slots ? double(t.hidden + t.escaped + t.grazing) / double(t.slots) : 0.0}};
    // With bounces: each bounce's own tally (its slots: IndirectPass::bounceFirstSlot). Bounce b
    // reflects what bounce b − 1 landed (stored, hidden, grazing) times the albedo it met.
    const uint32_t bounces = ind.settings().indirect.bounces;
    if (bounces > 1) {
      j["split_photons"]["per_bounce"] = nlohmann::json::array();
      for (uint32_t b = 1; b <= bounces; ++b) {
        const auto first = photons.begin() + std::ptrdiff_t(ind.bounceFirstSlot(b));
        const PhotonTally tb =
            tallyPhotons(std::vector<gpu::Photon>(first, first + std::ptrdiff_t(ind.bounceSlots(b))));
        j["split_photons"]["per_bounce"].push_back({{"bounce", b},
                                                    {"directions", ind.settings().indirect.directionsAtBounce(b)},
                                                    {"slots", tb.slots},
                                                    {"stored", tb.stored},
                                                    {"hidden", tb.hidden},
                                                    {"escaped", tb.escaped},
                                                    {"grazing", tb.grazing},
                                                    {"empty", tb.empty},
                                                    {"flux_reflected_w", tb.fluxReflected()},
                                                    {"flux_stored_w", tb.fluxStored},
                                                    {"flux_landed_w", tb.fluxStored + tb.fluxHidden + tb.fluxGrazing}});
      }
    }
  }
  const float scale = indirectScale(mine);
  j["image_scale"] = scale;
  write("indirect.png", indirectToImage(mine, w, h, scale),
        {{"Description", std::string("indirect irradiance (") + toString(method) + "), ACES after x" +
                             std::to_string(scale) + " (its 99th percentile to 1)"}});
  for (IndirectMethod ref : {IndirectMethod::RayTraced, IndirectMethod::Reference}) {
    const std::string name = std::string("vs_") + toString(ref);
    if (ref == method) {
      j[name] = {{"rel_mse", 0.0}, {"total_ratio", 1.0}, {"flip", 0.0}, {"itself", true}};
      continue;
    }
    if (method == IndirectMethod::Reference) continue;  // the reference is not held against photons
    std::vector<gpu::Photon> refPhotons;
    const std::vector<float> r = ind.computeWith(ref, ref == IndirectMethod::RayTraced ? &refPhotons : nullptr);
    const IndirectErrors e = indirectErrors(mine, r, w, h);
    j[name] = toJson(e);
    if (ref == IndirectMethod::RayTraced) {
      const PhotonAgreement a = comparePhotons(photons, refPhotons, ind.landingTolerance());
      j[name]["photons"] = {{"same_status_share", a.slots ? double(a.sameStatus) / double(a.slots) : 0.0},
                            {"both_stored", a.bothStored},
                            {"off_surface", a.offSurface},
                            {"landing_tolerance_m", ind.landingTolerance()},
                            {"median_distance_m", a.p50Distance},
                            {"p99_distance_m", a.p99Distance},
                            {"max_distance_m", a.maxDistance}};
    }
    const float rs = indirectScale(r);
    write("indirect_" + std::string(toString(ref)) + ".png", indirectToImage(r, w, h, rs),
          {{"Description",
            std::string("indirect irradiance (") + toString(ref) + "), ACES after x" + std::to_string(rs)}});
    write("indirect_error_" + name + ".png", indirectErrorToImage(mine, r, w, h, rs),
          {{"Description",
            std::string("|Y - Y ") + toString(ref) + "| over the reference's 99th percentile, viridis 0..0.5"}});
    char line[200];
    std::snprintf(line, sizeof line, "indirect (%s) vs %s: relMSE %.4f, total %.4f, FLIP %.4f", toString(method),
                  toString(ref), e.relMse, e.totalRatio, e.flip);
    summary.push_back(line);
  }
  return j;
}

void reportIndirect(EffectReport& r) {
  IndirectPass* ind = indirectPassOf(r.renderer);
  if (!ind) return;
  const RenderSettings& s = r.renderer.settings();
  r.run[indirectEffect().name] = indirectJson(*ind, s.width, s.height, r.write, r.summary);
}

}  // namespace hb

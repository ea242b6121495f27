// The shadows effect's report hook (plan/effect.h EffectDef::report): ray accounting against
// the oracle, the accuracy of positions and normals, the shadow mismatches against the reference
// frame, and the per-light visibility images (docs/methods/thesis.md "Accuracy", "The oracle").
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "analysis/culling_analysis.h"
#include "analysis/effect_report.h"
#include "analysis/ray_analysis.h"
#include "analysis/render_outputs.h"
#include "base/errors.h"
#include "base/parallel.h"
#include "base/text_format.h"
#include "effects/shadows/shadows_effect.h"
#include "effects/shadows/shadows_part.h"
#include "reference/bvh.h"
#include "reference/reconstruct_ref.h"

namespace hb {

// Images of lights 0..count-1: white lit (in the pixel's list, ray reached the light); dark red in
// the list but shadowed or culled by the normal/range test; black not in the pixel's list; dark
// blue sky. One walk of each pixel's list for all of them, rows on every core.
static std::vector<ImageRGBA8> visibilityOfLights(const ShadowReadback& sh, const CullingReadback& cr,
                                                  const std::vector<float>& depth, uint32_t w, uint32_t h,
                                                  uint32_t tileSize, uint32_t count) {
  std::vector<ImageRGBA8> imgs(count, ImageRGBA8{w, h, std::vector<uint8_t>(size_t(w) * h * 4, 255)});
  const size_t pixels = size_t(w) * h;
  const bool zbin = cr.lists == LightLists::Zbin;
  parallelFor(h, [&](size_t yy) {
    const uint32_t y = uint32_t(yy);
    for (uint32_t x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      auto paint = [&](uint32_t l, uint8_t r, uint8_t g, uint8_t b) {
        uint8_t* px = &imgs[l].px[i * 4];
        px[0] = r, px[1] = g, px[2] = b;
      };
      if (!(depth[i] > 0.0f)) {
        for (uint32_t l = 0; l < count; ++l) paint(l, 16, 24, 80);
        continue;
      }
      for (uint32_t l = 0; l < count; ++l) paint(l, 0, 0, 0);  // not in the list unless found below
      const uint32_t tile = (y / tileSize) * cr.tilesX + x / tileSize;
      const auto [first, last] = cr.pixelSlice(tile, zbin ? sh.ranges[i] : 0u);
      for (uint32_t k = first; k < last; ++k) {
        const uint32_t l = cr.indices[k];
        if (l >= count) continue;
        const uint32_t slot = k - first;
        if ((sh.visibility[size_t(slot / 32) * pixels + i] >> (slot % 32)) & 1u)
          paint(l, 255, 255, 255);
        else
          paint(l, 110, 20, 20);
      }
    }
  });
  return imgs;
}

// Per pixel, the scene lights whose bit is set in the pixel's visibility words (bit k = the k-th
// light of its walk). Sky: 0. Precondition: every light index < 64.
static std::vector<uint64_t> visibleSceneLights(const ShadowReadback& sh, const CullingReadback& cr,
                                                const std::vector<float>& depth, uint32_t w, uint32_t h,
                                                uint32_t tileSize) {
  const size_t pixels = size_t(w) * h;
  std::vector<uint64_t> out(pixels, 0);
  const bool zbin = cr.lists == LightLists::Zbin;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      if (!(depth[i] > 0.0f)) continue;
      const uint32_t tile = (y / tileSize) * cr.tilesX + x / tileSize;
      const auto [first, last] = cr.pixelSlice(tile, zbin ? sh.ranges[i] : 0u);
      for (uint32_t k = 0; k < last - first; ++k)
        if ((sh.visibility[size_t(k / 32) * pixels + i] >> (k % 32)) & 1u) {
          HB_ASSERT(cr.indices[first + k] < 64);
          out[i] |= 1ull << cr.indices[first + k];
        }
    }
  return out;
}

// Does light l send light to the true surface point p with true normal n (range, cone, N·L)? Only
// those (pixel, light) pairs change the image, so only they count as shadow mismatches.
static bool lightReaches(const Light& l, const glm::dvec3& p, const glm::dvec3& n) {
  if (l.type == LightType::Directional) return glm::dot(n, -glm::dvec3(l.direction)) > 0.0;
  glm::dvec3 d = glm::dvec3(l.position) - p;
  const double dist = glm::length(d);
  if (!(dist > 0.0) || dist > l.range) return false;
  d /= dist;
  if (l.type == LightType::Spot &&
      glm::dot(-d, glm::normalize(glm::dvec3(l.direction))) < std::cos(double(l.outerConeAngle)))
    return false;
  return glm::dot(n, d) > 0.0;
}

void reportShadows(EffectReport& r) {
  ShadowsPart* shadows = shadowsOf(r.renderer);
  if (!shadows) return;
  if (!r.perspective || !r.renderer.hasCulling()) return;
  const Renderer& renderer = r.renderer;
  const Scene& scene = r.scene;
  const RenderSettings& s = renderer.settings();
  const uint32_t w = s.width, h = s.height;
  const CullingReadback& cr = r.culling;
  const std::vector<float>& depth = r.depth;
  CullingInputs& ci = r.cullingInputs;
  const ReferenceFrame* reference = r.reference;
  const VariantParams& params = r.params;
  const bool writeImages = r.writeImages;
  nlohmann::json& accuracy = r.accuracy;
  auto& lap = r.lap;
  const ImageWriter& write = r.write;
  const ShadowReadback sh = shadows->readShadows();
  // Ray accounting, the oracle and the accuracy of positions and normals (docs/methods/thesis.md "Accuracy").
  const uint32_t lightCount = uint32_t(scene.lights.size());
  RayAccounting acc = accountRays(sh, cr, depth, w, h, s.tileSize, lightCount);
  lap("ray accounting");
  if (cr.lists == LightLists::Zbin) {
    r.run["culling"]["zbin_missed_pairs"] = zbinMissedPairs(ci, cr, sh.ranges);
    lap("z-bin check");
  }
  const Bvh bvh = buildBvh(scene);
  lap("bvh");
  const auto rcam = reconstructionCamera<double>(glm::dmat4(renderer.view()), glm::dmat4(renderer.proj()), w, h);
  const ReferenceSurface surface = referenceSurface(bvh, depth, rcam);
  lap("reference surface");
  const OracleRays oracle = oracleRays(scene, surface);
  lap("oracle");
  nlohmann::json rays = toJson(acc);
  rays["adds_up"] = acc.addsUp();
  rays["oracle"] = oracle.total;
  rays["oracle_pixels_without_true_normal"] = oracle.pixelsWithoutNormal;
  rays["efficiency"] = rayEfficiency(oracle.total, acc.traced);
  r.run["rays"] = rays;
  const uint32_t heatMax = rayHeatmapMax(cr.lists == LightLists::Tile, lightCount, acc.perPixel);
  write(
      "rays.png", rayHeatmap(acc.perPixel, w, h, heatMax),
      {{"Description",
        "shadow rays per pixel, thesis colours (black/blue 0-30 %, cyan/green 40-70 %, yellow/red "
        "80-100 % of " +
            std::to_string(heatMax) + " rays; red = " +
            (cr.lists == LightLists::Tile ? "the most a capped tile list can trace)" : "the most any pixel traced)")}});
  write("rays_oracle.png", rayHeatmap(oracle.perPixel, w, h, heatMax),
        {{"Description", "the oracle's rays per pixel (the fewest any culler could trace)"}});
  if (reference && !reference->visible.empty() && reference->width == w && reference->height == h) {
    // (pixel, light) pairs whose visibility differs from the reference, among the pairs that
    // change the image (the light reaches the true surface): wrongly dark = the reference sees
    // the light, this variant does not (culled or shadowed); wrongly lit = the reverse.
    const std::vector<uint64_t> mine = visibleSceneLights(sh, cr, depth, w, h, s.tileSize);
    uint64_t dark = 0, lit = 0, pairs = 0;
    for (size_t i = 0; i < mine.size(); ++i) {
      if (surface.state[i] != SurfaceState::Matched) continue;
      for (uint32_t l = 0; l < lightCount; ++l) {
        if (!lightReaches(scene.lights[l], surface.position[i], surface.normal[i])) continue;
        ++pairs;
        const bool a = (reference->visible[i] >> l) & 1ull, b = (mine[i] >> l) & 1ull;
        dark += a && !b;
        lit += !a && b;
      }
    }
    accuracy["shadow_mismatches"] = {{"wrongly_dark", dark}, {"wrongly_lit", lit}, {"pairs_compared", pairs}};
  }
  PositionAccuracy pa = positionAccuracy(sh.positions, depth, rcam);
  accuracy["world_pos"] = toJson(pa);
  accuracy["world_pos_rel_error"] = pa.maxRelative;
  {
    // Against the true surface (the eye ray's exact hit in double, where it matches the
    // rasterized depth): what a method's positions are worth, whatever it computes them from.
    double maxRel = 0, sumRel = 0;
    uint64_t compared = 0;
    for (size_t i = 0; i < surface.state.size(); ++i) {
      if (surface.state[i] != SurfaceState::Matched || sh.positions[4 * i + 3] != 1.0f) continue;
      const glm::dvec3 gpuPos(sh.positions[4 * i], sh.positions[4 * i + 1], sh.positions[4 * i + 2]);
      const double rel = glm::length(gpuPos - surface.position[i]) / glm::length(surface.position[i] - surface.eye);
      maxRel = std::max(maxRel, rel);
      sumRel += rel;
      ++compared;
    }
    accuracy["world_pos_vs_surface"] = {{"compared", compared},
                                        {"max_relative", maxRel},
                                        {"mean_relative", compared ? sumRel / double(compared) : 0.0},
                                        {"reference", "the eye ray's exact hit (double, watertight BVH)"}};
  }
  if (params.normalCulling != NormalCulling::Off) {
    NormalAccuracy na = normalAccuracy(sh.normals, surface);
    accuracy["normals"] = toJson(na);
    accuracy["normal_angular_error_deg"] = na.meanAngleDeg;
    accuracy["normal_image_error"] = na.meanImageDifference;
    write(std::string("normal_error_") + toString(params.normalCulling) + ".png",
          errorMapToImage(na.angleDeg, w, h, 45.0f),
          {{"Description", "angle between reconstructed and true normal, viridis 0..45 degrees"}});
    char line[200];
    std::snprintf(line, sizeof line, "normals (%s): mean %.3f deg, p95 %.3f deg, image difference %.5f",
                  toString(params.normalCulling), na.meanAngleDeg, na.p95AngleDeg, na.meanImageDifference);
    r.summary.push_back(line);
  }
  char line[256];
  std::snprintf(line, sizeof line,
                "rays: %llu candidates, %llu culled by tile, %llu by normal, %llu traced; oracle %llu "
                "(efficiency %s%s); accounting %s",
                (unsigned long long)acc.candidates, (unsigned long long)acc.culledByTile,
                (unsigned long long)acc.culledByNormal, (unsigned long long)acc.traced,
                (unsigned long long)oracle.total, formatNear1(rayEfficiency(oracle.total, acc.traced)).c_str(),
                acc.traced < oracle.total ? ", > 1: fewer rays traced than the oracle needs, the culler's misses" : "",
                acc.addsUp() ? "adds up" : "DOES NOT ADD UP");
  r.summary.push_back(line);

  if (writeImages) {  // computed only where written: a walk over every pixel's list
    const uint32_t shown = std::min<uint32_t>(uint32_t(scene.lights.size()), 16);
    const std::vector<ImageRGBA8> images = visibilityOfLights(sh, cr, depth, w, h, s.tileSize, shown);
    for (uint32_t l = 0; l < shown; ++l) {
      char name[64];
      std::snprintf(name, sizeof name, "visibility_light%02u.png", l);
      write(name, images[l],
            {{"Description",
              "white lit, dark red shadowed or culled by the normal/range test, black not in the "
              "pixel's light list, blue sky"}});
    }
  }
  if (params.normalCulling != NormalCulling::Off) {
    std::vector<uint8_t> valid(size_t(w) * h);
    std::vector<float> n3(size_t(w) * h * 3);
    for (size_t i = 0; i < valid.size(); ++i) {
      for (int c = 0; c < 3; ++c) n3[i * 3 + c] = sh.normals[i * 4 + c];
      valid[i] = (n3[i * 3] != 0.0f || n3[i * 3 + 1] != 0.0f || n3[i * 3 + 2] != 0.0f) ? 1 : 0;
    }
    write(std::string("normals_") + toString(params.normalCulling) + ".png", normalsToImage(n3, valid, w, h));
  }
}

void captureShadowsReference(const Renderer& renderer, ReferenceFrame& ref) {
  const ShadowsPart* shadows = shadowsOf(renderer);
  if (!shadows || renderer.camera().projection != CameraProjection::Perspective || !renderer.hasCulling() ||
      ref.lightCount > 64)
    return;
  const RenderSettings& s = renderer.settings();
  ref.visible = visibleSceneLights(shadows->readShadows(), renderer.readCulling(), renderer.readDepth(), s.width,
                                   s.height, s.tileSize);
}

}  // namespace hb

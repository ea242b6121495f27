#include "analysis/render_outputs.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "analysis/culling_analysis.h"
#include "analysis/ao_analysis.h"
#include "analysis/indirect_analysis.h"
#include "analysis/primary_analysis.h"
#include "base/errors.h"
#include "base/parallel.h"
#include "reference/flip.h"
#include "base/image_io.h"
#include "analysis/ray_analysis.h"
#include "reference/reconstruct_ref.h"
#include "shared/gpu_types.h"
#include "base/version.h"

namespace hb {

namespace {

// Images of lights 0..count-1: white lit (in the pixel's list, ray reached the light); dark red in
// the list but shadowed or culled by the normal/range test; black not in the pixel's list; dark
// blue sky. One walk of each pixel's list for all of them, rows on every core.
std::vector<ImageRGBA8> visibilityOfLights(const ShadowReadback& sh, const CullingReadback& cr,
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
        if ((sh.visibility[size_t(slot / 32) * pixels + i] >> (slot % 32)) & 1u) paint(l, 255, 255, 255);
        else paint(l, 110, 20, 20);
      }
    }
  });
  return imgs;
}

// Per pixel, the scene lights whose bit is set in the pixel's visibility words (bit k = the k-th
// light of its walk). Sky: 0. Precondition: every light index < 64.
std::vector<uint64_t> visibleSceneLights(const ShadowReadback& sh, const CullingReadback& cr,
                                         const std::vector<float>& depth, uint32_t w, uint32_t h, uint32_t tileSize) {
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
bool lightReaches(const Light& l, const glm::dvec3& p, const glm::dvec3& n) {
  if (l.type == LightType::Directional) return glm::dot(n, -glm::dvec3(l.direction)) > 0.0;
  glm::dvec3 d = glm::dvec3(l.position) - p;
  const double dist = glm::length(d);
  if (!(dist > 0.0) || dist > l.range) return false;
  d /= dist;
  if (l.type == LightType::Spot && glm::dot(-d, glm::normalize(glm::dvec3(l.direction))) < std::cos(double(l.outerConeAngle)))
    return false;
  return glm::dot(n, d) > 0.0;
}

}  // namespace

VariantParams referenceParams(const VariantParams& params) {
  VariantParams r = params;
  r.lightCulling = false;
  r.aabb = false;
  r.normalCulling = NormalCulling::Off;
  r.rangeTest = false;
  r.depthSlices = 0;  // only acts with culling on; keeps one reference for sliced and unsliced variants
  // The t_min that cannot self-intersect down to N·L = 0.01 (gpu_types.h kShadowTMinPerMetre): a
  // constant-t_min variant's acne then counts as wrongly dark. Within 41.9 m of the eye both are
  // the thesis's 0.001 m, so on such scenes (the atrium) the reference is the same either way.
  r.tMin = ShadowTMin::Scaled;
  // The thesis's forward pass is the reference shading: a visibility-buffer variant's FLIP then
  // measures what shading in compute changes, too.
  // Except for views the forward pass cannot draw (projection other than perspective), which keep
  // their shading and the light_culling=false they need.
  if (!params.projection || *params.projection == CameraProjection::Perspective) r.shading = ShadingMethod::Forward;
  return r;
}

ReferenceFrame captureReference(const Renderer& renderer, const Scene& scene) {
  ReferenceFrame ref;
  const RenderSettings& s = renderer.settings();
  ref.width = s.width;
  ref.height = s.height;
  ref.lightCount = uint32_t(scene.lights.size());
  const std::vector<float> depth = renderer.readDepth();
  if (renderer.camera().projection == CameraProjection::Perspective && renderer.hasCulling() &&
      renderer.hasShadows() && ref.lightCount <= 64)
    ref.visible = visibleSceneLights(renderer.readShadows(), renderer.readCulling(), depth, s.width, s.height,
                                     s.tileSize);
  ImageF hdr{s.width, s.height, 4, renderer.readColor()};
  ref.color = toneMapToSrgb(hdr, 0.0f, ToneMapOperator::AcesFitted).image;
  return ref;
}

// What primary visibility cost in the analysis frame (3D rasterization's counters; the hardware
// prepass has none to read). Counters come from the analysis frame's own pipelines, never from
// timed frames.
static nlohmann::json primaryJson(const Renderer& renderer, const Scene& scene) {
  const Raster3dPass* r3 = renderer.raster3d();
  if (!r3) return {{"method", "hardware"}};
  const RenderSettings& rs = renderer.settings();
  const gpu::Raster3dConstants rays = raster3dConstants(renderer.camera(), rs.width, rs.height, 0, 0);
  const PrimaryComparison exact = comparePrimary(buildBvh(scene), r3->readVisibility(), rays);
  const Raster3dCounters c = r3->readCounters();
  const double pixels = double(renderer.settings().width) * renderer.settings().height;
  auto ratio = [](double a, double b) { return b > 0 ? a / b : 0.0; };
  // Coverage counted additively needs the method's own per-pixel counts: a ray cast has one hit.
  nlohmann::json coverage = "not counted: a ray cast reports one hit per pixel";
  const CameraProjection projection = renderer.camera().projection;
  if (r3->mode() != PrimaryMode::RayCast && projection != CameraProjection::Perspective)
    coverage = "not counted: the exact CPU rasterization covers perspective views (the GPU fill-rule tests check "
               "other views on closed meshes around the eye)";
  else if (r3->mode() != PrimaryMode::RayCast)
    coverage = toJson(compareCoverage(scene, rays, r3->readCoverage()));
  return {{"method", renderer.settings().primary},
          {"projection", toString(projection)},
          {"bins_refined", c.binsRefined},
          {"bins_refined_without_hit", c.binsEmpty},
          {"bins_refined_without_hit_share", ratio(double(c.binsEmpty), double(c.binsRefined))},
          {"coverage_check", coverage},
          {"double_covers", coverage.is_object() ? coverage["double_covers"] : nlohmann::json()},
          {"list_entries", c.listEntries},
          {"triangles", r3->triangleCount()},
          {"triangle_setups", c.setups},
          {"big_triangles", c.bigTriangles},
          {"tile_list_overflows", c.listOverflows},
          {"pixels_tested", c.pixelsTested},
          {"edge_evaluations", c.edgeEvaluations},
          {"edge_evaluations_per_pixel", ratio(double(c.edgeEvaluations), pixels)},
          {"fp64_fallbacks", c.fallbacks},
          {"fp64_fallback_rate", ratio(double(c.fallbacks), double(c.edgeEvaluations))},
          {"covered_pairs", c.covered},
          {"atomics", c.atomics},
          {"atomics_per_pixel", ratio(double(c.atomics), pixels)},
          // The paper's Fig. 10 scalar-operation counts times what this frame did.
          {"paper_scalar_ops_estimate", 57.0 * double(c.setups) + 12.0 * double(c.pixelsTested)},
          {"against_ray_cast", toJson(exact)}};
}

// The LDMs' memory and lists (issue #16: heads, nodes allocated and used, nodes per pixel).
static nlohmann::json ldmJson(const LdmBuild& ldm, uint64_t linkBytes) {
  const LdmCounters c = ldm.readCounters();
  std::vector<uint32_t> lengths = ldm.readListLengths();
  std::sort(lengths.begin(), lengths.end());
  const uint64_t heads = uint64_t(lengths.size());
  const uint64_t exactBytes = ldm.exactBytes(c.allocated);  // a head per map pixel, a node per fragment
  return {{"maps", ldm.mapCount()},
          {"resolution", ldm.resolution()},
          {"heads", heads},
          {"nodes_capacity", ldm.nodeCapacity()},
          {"nodes_used", std::min<uint64_t>(c.allocated, ldm.nodeCapacity())},
          {"fragments", c.allocated},
          {"overflow", c.overflow},
          {"unfinished_insertions", c.unfinished},
          {"cas_retries", c.casRetries},
          {"fp64_edges", c.fp64Edges},
          {"nodes_per_pixel", {{"mean", heads ? double(c.allocated) / double(heads) : 0.0},
                               {"p99", lengths.empty() ? 0u : lengths[size_t(0.99 * double(lengths.size() - 1))]},
                               {"max", lengths.empty() ? 0u : lengths.back()}}},
          {"exact_bytes", exactBytes},
          {"allocated_over_exact", exactBytes ? double(linkBytes) / double(exactBytes) : 0.0}};
}

// Ambient occlusion: its settings, memory and LDM lists, the AO image, and (where the frame has a
// ray tracer) its errors against the same directions ray traced and the Monte Carlo reference, on
// the same surface (AoPass::computeWith), each with an error map.
template <typename Write>
static nlohmann::json aoJson(AoPass& ao, uint32_t w, uint32_t h, Write& write, std::vector<std::string>& summary) {
  nlohmann::json a = ao.settings().ao.toJson();
  const std::vector<float> mine = ao.readAo();
  uint64_t sky = 0, noNormal = 0;
  for (float v : mine) {
    sky += v == gpu::kAoSky;
    noNormal += v == gpu::kAoNoNormal;
  }
  a["pixels_sky"] = sky;
  a["pixels_without_normal"] = noNormal;
  const AoMemory m = ao.memory();
  a["memory_bytes"] = {{"ldm_links", m.ldmLinkBytes}, {"ldm_maps", m.ldmMapBytes}, {"directions", m.directionBytes},
                       {"output", m.outputBytes}, {"total", m.total()}};
  if (const LdmBuild* ldm = ao.ldm()) a["ldm"] = ldmJson(*ldm, m.ldmLinkBytes);
  write("ao.png", aoToImage(mine, w, h),
        {{"Description", std::string("ambient occlusion (") + toString(ao.settings().ao.method) +
                             "): grey = AO, white unoccluded; sky blue; magenta no normal"}});
  if (!ao.canTrace()) {
    a["errors_not_computed"] = "the frame has no ray tracer (shadows off and method ldm): its references need one";
    return a;
  }
  for (AoMethod ref : {AoMethod::RayTraced, AoMethod::Reference}) {
    if (ref == ao.settings().ao.method) {  // the method is its own reference: no error by definition
      a[std::string("vs_") + toString(ref)] = {{"mae", 0.0}, {"rmse", 0.0}, {"bias", 0.0}, {"flip", 0.0}, {"itself", true}};
      continue;
    }
    const std::vector<float> r = ao.computeWith(ref);
    const AoErrors e = aoErrors(mine, r, w, h);
    const std::string name = std::string("vs_") + toString(ref);
    a[name] = toJson(e);
    write("ao_error_" + name + ".png", aoErrorToImage(mine, r, w, h, 0.25f),
          {{"Description", std::string("|AO - AO ") + toString(ref) + "|, viridis 0..0.25"}});
    char line[200];
    std::snprintf(line, sizeof line, "ambient occlusion (%s) vs %s: MAE %.4f, RMSE %.4f, bias %+.4f, p95 %.4f, FLIP %.4f",
                  toString(ao.settings().ao.method), toString(ref), e.mae, e.rmse, e.bias, e.p95, e.flip);
    summary.push_back(line);
  }
  return a;
}

// Indirect light: its settings, memory, photons and flux, the irradiance image, and its errors
// against the same photons ray traced and the gathered reference (IndirectPass::computeWith).
template <typename Write>
static nlohmann::json indirectJson(IndirectPass& ind, uint32_t w, uint32_t h, Write& write,
                                   std::vector<std::string>& summary) {
  nlohmann::json j = ind.settings().indirect.toJson();
  const IndirectMemory m = ind.memory();
  j["memory_bytes"] = {{"ldm", m.ldmBytes}, {"photons", m.photonBytes}, {"faces", m.faceBytes},
                       {"directions", m.directionBytes}, {"target", m.targetBytes}, {"textures", m.textureBytes},
                       {"total", m.total()}};
  if (const LdmBuild* ldm = ind.ldm()) j["ldm"] = ldmJson(*ldm, ldm->links().size());
  j["emitters"] = ind.emitters();
  j["flux_emitted_w"] = ind.emittedFlux();
  const IndirectMethod method = ind.method();
  std::vector<gpu::Photon> photons;
  const std::vector<float> mine = ind.computeWith(method, &photons);
  if (method != IndirectMethod::Reference) {
    const PhotonTally t = tallyPhotons(photons);
    j["split_photons"] = {{"primaries", ind.primaries()}, {"slots", t.slots}, {"stored", t.stored}, {"hidden", t.hidden},
                    {"escaped", t.escaped}, {"grazing", t.grazing}, {"empty", t.empty},
                    {"flux_reflected_w", t.fluxReflected()}, {"flux_stored_w", t.fluxStored},
                    {"flux_hidden_w", t.fluxHidden}, {"flux_escaped_w", t.fluxEscaped}, {"flux_grazing_w", t.fluxGrazing},
                    {"discarded_share", t.slots ? double(t.hidden + t.escaped + t.grazing) / double(t.slots) : 0.0}};
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
                            {"both_stored", a.bothStored}, {"off_surface", a.offSurface},
                            {"landing_tolerance_m", ind.landingTolerance()},
                            {"median_distance_m", a.p50Distance}, {"p99_distance_m", a.p99Distance},
                            {"max_distance_m", a.maxDistance}};
    }
    const float rs = indirectScale(r);
    write("indirect_" + std::string(toString(ref)) + ".png", indirectToImage(r, w, h, rs),
          {{"Description", std::string("indirect irradiance (") + toString(ref) + "), ACES after x" + std::to_string(rs)}});
    write("indirect_error_" + name + ".png", indirectErrorToImage(mine, r, w, h, rs),
          {{"Description", std::string("|Y - Y ") + toString(ref) + "| over the reference's 99th percentile, viridis 0..0.5"}});
    char line[200];
    std::snprintf(line, sizeof line, "indirect (%s) vs %s: relMSE %.4f, total %.4f, FLIP %.4f", toString(method),
                  toString(ref), e.relMse, e.totalRatio, e.flip);
    summary.push_back(line);
  }
  return j;
}

RenderOutputs writeRenderOutputs(const VulkanContext& ctx, const Renderer& renderer, const Scene& scene,
                                 const VariantParams& params, const std::string& dir, bool writeImages,
                                 const ReferenceFrame* reference) {
  namespace fs = std::filesystem;
  RenderOutputs out;
  const RenderSettings& s = renderer.settings();
  const uint32_t w = s.width, h = s.height;
  if (writeImages) fs::create_directories(dir);
  auto write = [&](const std::string& name, const ImageRGBA8& img, std::map<std::string, std::string> text = {}) {
    if (!writeImages) return;
    text["Software"] = "hybridbench " + toolVersion() + " (" + gitRevision() + ")";
    text["Device"] = ctx.info().name + " / " + ctx.info().driverInfo;
    writePng(fs::path(dir) / name, img, text);
    out.files.push_back(name);
  };

  // The CPU analysis's wall time per stage (render.json "analysis_s"); printed as it goes when the
  // frame is large (a million pixel-light pairs take seconds even on every core).
  const bool longAnalysis = double(w) * h * std::max<size_t>(1, scene.lights.size()) >= 5e7;
  const auto analysisStart = std::chrono::steady_clock::now();
  auto lapStart = analysisStart;
  nlohmann::json analysisSeconds = nlohmann::json::object();
  auto lap = [&](const char* stage) {
    const auto now = std::chrono::steady_clock::now();
    const double sec = std::chrono::duration<double>(now - lapStart).count();
    analysisSeconds[stage] = sec;
    lapStart = now;
    if (longAnalysis) std::fprintf(stderr, "analysis: %s %.1f s (%u threads)\n", stage, sec, analysisThreads());
  };

  nlohmann::json j;
  j["effects"] = renderer.plan().effectsJson();
  j["passes_run"] = renderer.passesRun();
  j["passes_skipped"] = nlohmann::json::object();
  for (const auto& [pass, why] : renderer.passesSkipped()) j["passes_skipped"][pass] = why;
  j["backend"] = renderer.backendUsed();
  j["primary"] = primaryJson(renderer, scene);
  if (const Raster3dPass* r3 = renderer.raster3d()) {
    // Edge evaluations per pixel (3 per triangle tested there), viridis from 0 to the 99th
    // percentile (the scale is in the PNG's description and in render.json).
    const std::vector<uint32_t> tests = r3->readPixelTests();
    std::vector<float> evals(tests.size());
    for (size_t i = 0; i < tests.size(); ++i) evals[i] = 3.0f * float(tests[i]);
    std::vector<float> sorted = evals;
    std::sort(sorted.begin(), sorted.end());
    const float p99 = sorted.empty() ? 1.0f : std::max(1.0f, sorted[size_t(0.99 * double(sorted.size() - 1))]);
    j["primary"]["edge_evaluations_heatmap_max"] = p99;
    write("edge_evaluations.png", errorMapToImage(evals, w, h, p99),
          {{"Description", "3D rasterization: edge evaluations per pixel, viridis 0.." + std::to_string(int(p99)) +
                               " (the 99th percentile; above it yellow)"}});
  }
  if (AoPass* ao = renderer.ambientOcclusion()) j["ambient_occlusion"] = aoJson(*ao, w, h, write, out.summary);
  if (IndirectPass* ind = renderer.indirect()) j["indirect"] = indirectJson(*ind, w, h, write, out.summary);
  if (const AccelerationStructures* as = renderer.accel())
    j["acceleration_structures"] = {{"blas", as->blasCount()}, {"bytes", as->bytes()}, {"build_ms", as->buildMs()},
                                    {"build_ms_source", "wall clock, submit to fence"}};

  const std::vector<float> depth = renderer.readDepth();
  const Camera& cam = renderer.camera();
  write("depth.png", depthToImage(depth, w, h, cam.znear, cam.zfar, cam.projection == CameraProjection::Orthographic),
        {{"Description", "reverse-Z depth: log view distance to grey (white = near), sky dark blue"}});

  // Colour: linear HDR → ACES (Narkowicz fit) at exposure 0 → sRGB.
  const std::vector<float> hdr = renderer.readColor();
  ImageF hdrImage{w, h, 4, hdr};
  ToneMapResult tm = toneMapToSrgb(hdrImage, 0.0f, ToneMapOperator::AcesFitted);
  write("color.png", tm.image, {{"ToneMapping", "aces-fitted (Narkowicz 2015), exposure 0 EV, then sRGB OETF"}});
  j["color"] = {{"tone_mapping", "aces-fitted"}, {"exposure_ev", 0.0}, {"non_finite_pixels", tm.nonFinitePixels}};
  nlohmann::json accuracy = nlohmann::json::object();
  if (reference && reference->width == w && reference->height == h) {
    // LDR-FLIP (Andersson et al. 2020) of this variant's image against the reference render,
    // at the default viewing setup (flip.h kDefaultPpd).
    FlipResult flip = ldrFlip(reference->color, tm.image);
    accuracy["image_error"] = flip.mean;
    accuracy["image_error_flip"] = {{"mean", flip.mean}, {"p50", flip.p50}, {"p95", flip.p95}, {"max", flip.max},
                                    {"ppd", kDefaultPpd}, {"reference", "same scene/camera/resolution/backend, no culling"}};
    std::vector<float> e(flip.errorMap.px.begin(), flip.errorMap.px.end());
    write("flip_error.png", errorMapToImage(e, w, h, 1.0f),
          {{"Description", "LDR-FLIP error against the no-culling reference render, viridis 0..1"}});
  }

  // The culling and shadow references reconstruct positions through the perspective matrix; other
  // views are held only to the ray cast (primary.against_ray_cast) and the reference image.
  const bool perspective = renderer.camera().projection == CameraProjection::Perspective;
  if (!perspective && renderer.hasCulling())
    j["analysis_not_run"] = std::string("culling, ray accounting and shadow accuracy: their CPU references "
                                        "reconstruct a perspective view, and this one is ") +
                            toString(renderer.camera().projection);
  // Everything the GPU culling pass saw (culling_analysis.h).
  CullingInputs ci;
  ci.depth = &depth;
  ci.lights = &scene.lights;
  ci.view = renderer.view();
  ci.proj = renderer.proj();
  ci.width = w;
  ci.height = h;
  ci.tileSize = s.tileSize;
  ci.aabb = s.aabb;
  ci.lightCulling = s.lightCulling;
  ci.depthSlices = s.depthSlices;
  lap("readbacks and images");
  // The light lists, read back once (the masks of thousands of lights at 4K are megabytes).
  const CullingReadback cr = perspective && renderer.hasCulling() ? renderer.readCulling() : CullingReadback{};
  if (perspective && renderer.hasCulling()) {
    // Culling statistics against the CPU reference of the same method and the exact test.
    ci.capacity = cr.capacity;
    CullingAnalysis ca = analyzeCulling(ci, cr);
    lap("culling reference");
    j["culling"] = ca.json;
    // What the GPU allocated for the lists (the statistics' memory_bytes is the thesis's formula).
    j["culling"]["light_lists"] = toString(cr.lists);
    j["culling"]["list_memory_bytes"] = renderer.listMemoryBytes();
    if (cr.lists != LightLists::Tile) j["culling"]["memory_bytes"] = renderer.listMemoryBytes();
    write("lights_per_tile.png", ca.heatmap,
          {{"Description", "lights per tile (thesis colours, red = every light of the scene)"}});
    char line[256];
    std::snprintf(line, sizeof line,
                  "culling: %llu tiles, %.2f lights/tile (max %u), %llu overflowing, false positives %.1f %% "
                  "(reaching no pixel %.1f %%), false negatives %llu%s",
                  (unsigned long long)ca.stats.tiles, ca.stats.meanLightsPerTile, ca.stats.maxLightsPerTile,
                  (unsigned long long)ca.stats.overflowTiles, 100.0 * ca.stats.falsePositiveRate,
                  100.0 * ca.stats.uselessRate, (unsigned long long)ca.stats.falseNegatives,
                  s.depthSlices ? (", " + std::to_string(ca.stats.slicedAway) + " cut by " +
                                   std::to_string(s.depthSlices) + " depth slices")
                                      .c_str()
                                : "");
    out.summary.push_back(line);
  }
  if (perspective && renderer.hasCulling() && renderer.hasShadows()) {
    const ShadowReadback sh = renderer.readShadows();
    // Ray accounting, the oracle and the accuracy of positions and normals (design.md "Accuracy").
    const uint32_t lightCount = uint32_t(scene.lights.size());
    RayAccounting acc = accountRays(sh, cr, depth, w, h, s.tileSize, lightCount);
    lap("ray accounting");
    if (cr.lists == LightLists::Zbin) {
      j["culling"]["zbin_missed_pairs"] = zbinMissedPairs(ci, cr, sh.ranges);
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
    j["rays"] = rays;
    const uint32_t heatMax = rayHeatmapMax(cr.lists == LightLists::Tile, lightCount, acc.perPixel);
    write("rays.png", rayHeatmap(acc.perPixel, w, h, heatMax),
          {{"Description", "shadow rays per pixel, thesis colours (black/blue 0-30 %, cyan/green 40-70 %, yellow/red "
                           "80-100 % of " + std::to_string(heatMax) + " rays; red = " +
                           (cr.lists == LightLists::Tile ? "the most a capped tile list can trace)"
                                                         : "the most any pixel traced)")}});
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
      out.summary.push_back(line);
    }
    char line[256];
    std::snprintf(line, sizeof line,
                  "rays: %llu candidates, %llu culled by tile, %llu by normal, %llu traced; oracle %llu "
                  "(efficiency %.3f); accounting %s",
                  (unsigned long long)acc.candidates, (unsigned long long)acc.culledByTile,
                  (unsigned long long)acc.culledByNormal, (unsigned long long)acc.traced,
                  (unsigned long long)oracle.total, rayEfficiency(oracle.total, acc.traced),
                  acc.addsUp() ? "adds up" : "DOES NOT ADD UP");
    out.summary.push_back(line);

    if (writeImages) {  // computed only where written: a walk over every pixel's list
      const uint32_t shown = std::min<uint32_t>(uint32_t(scene.lights.size()), 16);
      const std::vector<ImageRGBA8> images = visibilityOfLights(sh, cr, depth, w, h, s.tileSize, shown);
      for (uint32_t l = 0; l < shown; ++l) {
        char name[64];
        std::snprintf(name, sizeof name, "visibility_light%02u.png", l);
        write(name, images[l],
              {{"Description", "white lit, dark red shadowed or culled by the normal/range test, black not in the "
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
  {
    const std::vector<float> ref = renderer.readRefNormals();
    std::vector<uint8_t> valid(size_t(w) * h);
    std::vector<float> n3(size_t(w) * h * 3);
    for (size_t i = 0; i < valid.size(); ++i) {
      for (int c = 0; c < 3; ++c) n3[i * 3 + c] = ref[i * 4 + c];
      valid[i] = ref[i * 4 + 3] > 0.5f && depth[i] > 0.0f;
    }
    write("normals_reference.png", normalsToImage(n3, valid, w, h),
          {{"Description", "true face normals of the visible triangles (analysis pass)"}});
  }
  if (!accuracy.empty()) j["accuracy"] = accuracy;
  lap("rest");
  analysisSeconds["total"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - analysisStart).count();
  analysisSeconds["threads"] = analysisThreads();
  j["analysis_s"] = analysisSeconds;
  if (longAnalysis) std::fprintf(stderr, "analysis: %.1f s in all\n", analysisSeconds["total"].get<double>());
  out.json = j;
  return out;
}

}  // namespace hb

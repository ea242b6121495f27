#include "analysis/render_outputs.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <span>
#include <string>

#include "analysis/culling_analysis.h"
#include "analysis/effect_report.h"
#include "analysis/primary_analysis.h"
#include "analysis/ray_analysis.h"
#include "base/errors.h"
#include "base/image_io.h"
#include "base/parallel.h"
#include "base/version.h"
#include "frame/passes/aa_samples.h"
#include "frame/passes/raster3d.h"
#include "gpu/trace_bvh.h"
#include "reference/flip.h"
#include "reference/reconstruct_ref.h"
#include "shared/gpu_types.h"

namespace hb {

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
  // Without anti-aliasing: the forward pass after a compute primary draws one sample a pixel, and
  // what AA changes is measured against the supersampled reference (reference_ssaa), not this one.
  r.aa = AntiAliasing::None;
  return r;
}

VariantParams supersampledReferenceParams(const VariantParams& params) {
  VariantParams r = params;
  const uint32_t k = uint32_t(std::lround(std::sqrt(double(params.referenceSsaa))));
  HB_ASSERT(k * k == params.referenceSsaa && k >= 2);
  r.resolution = {params.resolution[0] * k, params.resolution[1] * k};
  r.aa = AntiAliasing::None;
  r.referenceSsaa = 1;
  return r;
}

ReferenceFrame captureSupersampledReference(const Renderer& renderer, uint32_t width, uint32_t height) {
  const RenderSettings& s = renderer.settings();
  const uint32_t k = s.width / width;
  HB_ASSERT(k >= 2 && s.width == k * width && s.height == k * height);
  const std::vector<float> big = renderer.readColor();
  std::vector<float> small(size_t(width) * height * 4, 0.0f);
  const double norm = 1.0 / double(k * k);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x)
      for (uint32_t c = 0; c < 4; ++c) {
        double sum = 0.0;  // a box filter over the k x k samples of the pixel's area
        for (uint32_t j = 0; j < k; ++j)
          for (uint32_t i = 0; i < k; ++i) sum += big[((size_t(y) * k + j) * s.width + size_t(x) * k + i) * 4 + c];
        small[(size_t(y) * width + x) * 4 + c] = float(sum * norm);
      }
  ReferenceFrame ref;
  ref.width = width;
  ref.height = height;
  ref.color = toneMapToSrgb(ImageF{width, height, 4, small}, 0.0f, ToneMapOperator::AcesFitted).image;
  ref.description = std::to_string(k * k) + " samples a pixel: the same frame at " + std::to_string(k) +
                    "x the width and height, aa none, box-filtered in linear HDR";
  return ref;
}

ReferenceFrame captureReference(const Renderer& renderer, const Scene& scene) {
  ReferenceFrame ref;
  const RenderSettings& s = renderer.settings();
  ref.width = s.width;
  ref.height = s.height;
  ref.lightCount = uint32_t(scene.lights.size());
  for (const EffectDef* def : allEffects())
    if (def->captureReference && renderer.plan().runs(def->name)) def->captureReference(renderer, ref);
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
  if (r3->mode() != PrimaryMethod::RayCast && projection != CameraProjection::Perspective)
    coverage =
        "not counted: the exact CPU rasterization covers perspective views (the GPU fill-rule tests check "
        "other views on closed meshes around the eye)";
  else if (r3->mode() != PrimaryMethod::RayCast)
    coverage = toJson(compareCoverage(scene, rays, r3->readCoverage()));
  // Occlusion culling and early-z skip triangles behind the depth so far, so their pixels are
  // counted fewer times than the exact rasterization covers them: "holes" there mean work saved,
  // not an error. Double covers still are one; the visible surface is checked against the ray
  // cast (against_ray_cast) and, in the tests, against 3dr bit for bit.
  const PrimaryMethod m = rs.primary;
  const bool skipsHidden = m == PrimaryMethod::Raster3dFrustumSplit || m == PrimaryMethod::Raster3dFull ||
                           m == PrimaryMethod::Raster2dBinned ||
                           (m == PrimaryMethod::Raster3dBinned && rs.raster3dEarlyZ);
  if (skipsHidden && coverage.is_object()) {
    coverage["pixels_missing_hidden_coverage"] = coverage["holes"];
    coverage["holes"] =
        "not counted: occlusion culling or early-z skips hidden triangles (pixels_missing_hidden_coverage); the "
        "visible surface is checked by against_ray_cast";
  }
  const PrimaryMethod method = renderer.settings().primary;
  // The paper's Fig. 10 scalar-operation counts: 3DR 57 a setup, 12 a pixel test; the 2D
  // homogeneous baseline 73 and 14.
  const bool twoD = method == PrimaryMethod::Raster2d || method == PrimaryMethod::Raster2dBinned;
  const double setupCost = twoD ? 73.0 : 57.0, pixelCost = twoD ? 14.0 : 12.0;
  nlohmann::json j = {{"method", toString(method)},
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
                      {"list_capacity", r3->listCapacity()},
                      {"list_grown_from", r3->listGrownFrom()},
                      {"pixels_tested", c.pixelsTested},
                      {"edge_evaluations", c.edgeEvaluations},
                      {"edge_evaluations_per_pixel", ratio(double(c.edgeEvaluations), pixels)},
                      {"fp64_fallbacks", c.fallbacks},
                      {"fp64_fallback_rate", ratio(double(c.fallbacks), double(c.edgeEvaluations))},
                      {"covered_pairs", c.covered},
                      {"atomics", c.atomics},
                      {"atomics_per_pixel", ratio(double(c.atomics), pixels)},
                      {"paper_scalar_ops_estimate", setupCost * double(c.setups) + pixelCost * double(c.pixelsTested)},
                      {"blocks_culled_early_z", c.culledEarlyZ},
                      {"against_ray_cast", toJson(exact)},
                      {"compiled", r3->compiled()}};
  if (primaryUsesBvh(method)) {
    const Raster3dBvhStats& b = r3->bvhStats();
    j["bvh_nodes"] = b.nodes;
    j["bvh_depth"] = b.depth;
    j["bvh_bytes"] = b.bytes;
    j["bvh_build_ms"] = b.buildMs;
    j["r3d_frustum"] = rs.raster3dFrustum;
    j["bvh_nodes_visited"] = c.nodesVisited;
    j["frusta"] = c.frusta;
    j["frusta_split"] = c.frustaSplit;
    j["triangles_culled_frustum"] = c.culledFrustum;
    j["triangles_culled_occlusion"] = c.culledOcclusion;
    j["bvh_stack_overflows"] = c.stackOverflows;
  }
  if (r3->planes() > 1) {
    // Anti-aliasing: the sample planes' work apart from the centre's, and each sample's coverage
    // against the exact CPU rasterization at that sample's position (0 holes, 0 double covers).
    const Raster3dCounters sc = r3->readSampleCounters();
    nlohmann::json aa = {
        {"mode", toString(rs.aa)},
        {"stored_samples", r3->planes() - 1},
        {"coverage_samples", aaCoverageSamples(rs.aa)},
        {"sample_triangle_setups", sc.setups},
        {"sample_pixels_tested", sc.pixelsTested},
        {"sample_edge_evaluations", sc.edgeEvaluations},
        {"sample_atomics", sc.atomics},
        {"sample_paper_scalar_ops_estimate", setupCost * double(sc.setups) + pixelCost * double(sc.pixelsTested)}};
    if (coverage.is_object() && !skipsHidden) {
      const std::span<const glm::vec2> positions = aaStoredPositions(rs.aa);
      uint64_t holes = 0, doubles = 0;
      for (uint32_t p = 1; p < r3->planes(); ++p) {
        const CoverageComparison cc = compareCoverage(
            scene, raster3dConstants(renderer.camera(), rs.width, rs.height, 0, 0, 64, positions[p - 1]),
            r3->readCoverage(p));
        holes += cc.holes;
        doubles += cc.doubleCovers;
      }
      aa["sample_coverage_check"] = {{"holes", holes}, {"double_covers", doubles}};
    } else {
      aa["sample_coverage_check"] = "not counted (as coverage_check)";
    }
    j["aa"] = aa;
  }
  return j;
}

// Culling statistics against the CPU reference of the same method and the exact test, with the
// lights-per-tile heatmap (render.json "culling").
static void reportCulling(EffectReport& r) {
  const CullingReadback& cr = r.culling;
  const RenderSettings& s = r.renderer.settings();
  // Culling statistics against the CPU reference of the same method and the exact test.
  r.cullingInputs.capacity = cr.capacity;
  CullingAnalysis ca = analyzeCulling(r.cullingInputs, cr);
  r.lap("culling reference");
  r.run["culling"] = ca.json;
  // What the GPU allocated for the lists (the statistics' memory_bytes is the thesis's formula).
  r.run["culling"]["light_lists"] = toString(cr.lists);
  r.run["culling"]["list_memory_bytes"] = r.renderer.listMemoryBytes();
  if (cr.lists != LightLists::Tile) r.run["culling"]["memory_bytes"] = r.renderer.listMemoryBytes();
  r.write("lights_per_tile.png", ca.heatmap,
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
  r.summary.push_back(line);
}

RenderOutputs writeRenderOutputs(const VulkanContext& ctx, const Renderer& renderer, const Scene& scene,
                                 const VariantParams& params, const std::string& dir, bool writeImages,
                                 const ReferenceFrame* reference) {
  namespace fs = std::filesystem;
  RenderOutputs out;
  const RenderSettings& s = renderer.settings();
  const uint32_t w = s.width, h = s.height;
  if (writeImages) fs::create_directories(dir);
  const ImageWriter write{[&](const std::string& name, const ImageRGBA8& img, std::map<std::string, std::string> text) {
    if (!writeImages) return;
    text["Software"] = "hybridbench " + toolVersion() + " (" + gitRevision() + ")";
    text["Device"] = ctx.info().name + " / " + ctx.info().driverInfo;
    writePng(fs::path(dir) / name, img, text);
    out.files.push_back(name);
  }};

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
  j["frame_resources"] = renderer.resources().toJson();
  // The frame's ray tracer (frame/ray_backend.h): every ray pass uses it.
  j["backend"] = renderer.accel() ? toString(renderer.settings().backend) : "none";
  if (renderer.accel()) j["backend_choice"] = toJson(renderer.backendChoice(), renderer.settings().rayRates);
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
  if (const AccelerationStructures* as = renderer.accel())
    j["acceleration_structures"] = {{"blas", as->blasCount()},
                                    {"bytes", as->bytes()},
                                    {"build_ms", as->buildMs()},
                                    {"build_ms_source", "wall clock, submit to fence"}};
  if (const TraceBvh* b = renderer.traceBvh())  // backend=compute: ours, beside the driver's
    j["compute_bvh"] = {
        {"layout",
         b->width != 2
             ? std::to_string(b->width) +
                   "-wide, collapsed from the binary SAH tree (trace_bvh.h: 64 bins on each axis), " +
                   std::to_string(16 * wideNodeVec4s(b->width)) + " B nodes, triangles 3 x vec4 in leaf order"
             : "binary SAH (trace_bvh.h: 64 bins on each axis), 48 B nodes, triangles 3 x vec4 in leaf order"},
        {"width", b->width},
        {"nodes", b->nodeCount},
        {"depth", b->depth},
        {"stack_entries", b->stack},
        {"bytes", b->bytes},
        {"build_ms", b->buildMs},
        {"build_ms_source", "wall clock on the CPU (the upload not counted)"}};

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
    accuracy["image_error_flip"] = {{"mean", flip.mean}, {"p50", flip.p50},    {"p95", flip.p95},
                                    {"max", flip.max},   {"ppd", kDefaultPpd}, {"reference", reference->description}};
    std::vector<float> e(flip.errorMap.px.begin(), flip.errorMap.px.end());
    write("flip_error.png", errorMapToImage(e, w, h, 1.0f),
          {{"Description",
            "LDR-FLIP error against the reference render (" + reference->description + "), viridis 0..1"}});
  }

  // The culling and shadow references reconstruct positions through the perspective matrix; other
  // views are held only to the ray cast (primary.against_ray_cast) and the reference image.
  const bool perspective = renderer.camera().projection == CameraProjection::Perspective;
  if (!perspective && renderer.hasCulling())
    j["analysis_not_run"] = std::string(
                                "culling, ray accounting and shadow accuracy: their CPU references "
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
  // The effects' own reports, in effect order (plan/effect.h EffectDef::report).
  EffectReport report{ctx,         renderer, scene, params, reference, writeImages, j,          accuracy,
                      out.summary, write,    lap,   depth,  cr,        ci,          perspective};
  if (perspective && renderer.hasCulling()) reportCulling(report);
  for (const EffectDef* def : allEffects())
    if (def->report && renderer.plan().runs(def->name)) def->report(report);
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

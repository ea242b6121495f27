// `hybridbench rays export` (reference/ray_sets.h: the camera, AO and shadow ray sets of a scene and
// view, as ray files) and `hybridbench raybench FILE.bin` (gpu/peaks.h traceRayFile: a ray file
// through every backend, against the CPU's double-precision hits).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <tuple>
#include <utility>

#include "analysis/frame_rays.h"
#include "app/auto_scene.h"
#include "app/commands.h"
#include "base/errors.h"
#include "base/input_file.h"
#include "base/text_format.h"
#include "base/version.h"
#include "effects/ambient_occlusion/ao_part.h"
#include "effects/ambient_occlusion/ao_pass.h"
#include "effects/shadows/shadows_part.h"
#include "gltf/gltf_io.h"
#include "gpu/gpu_lights.h"
#include "gpu/peaks.h"
#include "gpu/trace_bvh.h"
#include "gpu/trace_work.h"
#include "reference/eq_partition.h"
#include "reference/ray_sets.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

RayFileInfo infoFor(const Scene& scene, const std::string& sha, const RayView& view, const std::string& kind,
                    size_t count, uint32_t gridWidth) {
  RayFileInfo i;
  i.count = count;
  i.kind = kind;
  i.sceneName = scene.name;
  i.sceneSha256 = sha;
  i.sceneGeometrySha256 = sceneGeometrySha256(scene);
  i.camera = toJson(view, scene.cameras.front());
  i.grid = {gridWidth, uint32_t((count + gridWidth - 1) / gridWidth)};
  i.madeBy = "hybridbench " + toolVersion() + " at " + gitRevision();
  return i;
}

}  // namespace

int cmdRaysExport(const RaysExportOptions& o) {
  const std::vector<std::string> kinds =
      o.kind == "all" ? std::vector<std::string>{"camera", "ao", "shadow"} : std::vector<std::string>{o.kind};
  uint32_t width = 1920, height = 1080;
  if (!o.size.empty()) parseSize(o.size, width, height, "--size");
  Scene scene = loadSceneArg(o.scene);
  const std::string sha = sceneSha256(scene);  // the scene as loaded, before any automatic camera
  if (scene.cameras.empty()) {
    // As render's camera=auto (app/auto_scene.h): the rays are then of that camera, which the ray
    // files record; raybench matches a file by its geometry, which a camera does not change.
    scene.cameras.push_back(autoCamera(scene));
    std::printf("rays export: %s has no camera; framed it automatically (camera=auto, docs/usage.md)\n",
                o.scene.c_str());
  }
  std::error_code ec;
  std::filesystem::create_directories(o.out, ec);
  if (ec) throw InputError("rays export: cannot create --out " + o.out + " (" + ec.message() + ")");
  const RayView view = rayViewOf(scene.cameras.front(), width, height);
  const std::vector<RayRecord> camera = cameraRays(view);
  auto write = [&](const std::string& kind, const std::vector<RayRecord>& rays, uint32_t gridWidth,
                   const nlohmann::json& params, uint64_t seed) {
    RayFileInfo info = infoFor(scene, sha, view, kind, rays.size(), gridWidth);
    info.params = params;
    info.seed = seed;
    const std::string path = (std::filesystem::path(o.out) / (kind + ".bin")).string();
    writeRayFile(path, info, rays);
    std::printf("wrote %s (%zu rays, %s) and its .json\n", path.c_str(), rays.size(), info.query.c_str());
  };
  if (std::find(kinds.begin(), kinds.end(), "camera") != kinds.end())
    write("camera", camera, width, {{"t_max", 1e30}}, 0);
  if (kinds == std::vector<std::string>{"camera"}) return kExitOk;
  std::fprintf(stderr, "rays export: finding where %zu camera rays meet %s (double precision, every core) ...\n",
               camera.size(), scene.name.c_str());
  const Bvh bvh = buildBvh(scene);
  const RayHits hits = traceOnCpu(bvh, camera);
  SecondaryParams p;
  p.offset = o.offset;
  p.tMax = o.aoTMax;
  p.seed = o.seed;
  p.light = glm::dvec3(o.light[0], o.light[1], o.light[2]);
  // The secondary sets hold one ray per camera hit: laid out in rows as wide as the image.
  for (const std::string& kind : kinds) {
    if (kind == "ao")
      write("ao", aoRays(bvh, camera, hits, p), width,
            {{"from", "each camera hit, offset along the geometric normal turned towards the eye"},
             {"offset", p.offset},
             {"directions", "cosine-distributed about that normal"},
             {"t_max", p.tMax}},
            p.seed);
    else if (kind == "shadow")
      write("shadow", shadowRays(bvh, camera, hits, p), width,
            {{"from", "each camera hit, offset along the geometric normal turned towards the eye"},
             {"offset", p.offset},
             {"to", {p.light.x, p.light.y, p.light.z}},
             {"t_max", "the distance to the light"}},
            0);
  }
  return kExitOk;
}

void checkFrameRaysOut(const Renderer& renderer) {
  if (!shadowsOf(renderer))
    throw InputError(
        "--rays-out: this frame traces no shadow rays (the shadows effect is off); the frame's rays are "
        "rebuilt from the shadow pass's readback, so turn shadows on (--set shadows=true), or make ray sets of "
        "any scene with hybridbench rays export");
  if (!renderer.hasCulling())
    throw InputError(
        "--rays-out: the frame's shadow rays are rebuilt from its light lists; render with light culling "
        "(--set light_culling=true)");
}

std::vector<std::string> writeFrameRayFiles(const Renderer& renderer, const std::string& dir) {
  const ShadowsPart* shadows = shadowsOf(renderer);
  HB_ASSERT(shadows && renderer.hasCulling());  // checkFrameRaysOut
  const Scene& scene = renderer.scene();
  const RenderSettings& s = renderer.settings();
  const ShadowReadback sh = shadows->readShadows();
  const CullingReadback culling = renderer.readCulling();
  const gpu::FrameConstants fc = renderer.frameConstants();
  const RayView view = rayViewOf(renderer.camera(), s.width, s.height);
  const std::string sha = sceneSha256(scene);
  const nlohmann::json frame = {{"config", "the render's parameters (render.json \"params\")"},
                                {"backend", toString(s.backend)},
                                {"normals", toString(s.normals)},
                                {"world_pos", toString(s.worldPos)},
                                {"t_min", fc.cameraPos.w > 0.0f ? "scaled" : "fixed"}};
  std::vector<std::string> written;
  auto write = [&](const std::string& kind, const FrameRays& rays, nlohmann::json params) {
    RayFileInfo info = infoFor(scene, sha, view, kind, rays.rays.size(), s.width);
    info.query = "any";
    params["frame"] = frame;
    info.params = std::move(params);
    const std::string path = (fs::path(dir) / (kind + ".bin")).string();
    writeRayFile(path, info, rays.rays);
    written.push_back(path);
    std::printf("wrote %s (%zu rays, %s: %s)\n", path.c_str(), rays.rays.size(), kind.c_str(), info.query.c_str());
  };
  write("frame-shadow",
        frameShadowRays(sh, culling, packLights(scene.lights), fc.cameraPos, s.width, s.height, s.tileSize),
        {{"from",
          "each pixel's stored world position, to each light of its list walk the shadow pass traced "
          "(after its range, N.L and cast-shadows tests), in walk order"},
         {"t_min", "shadowTMin (gpu_types.h)"},
         {"t_max", "the distance to the light (directional: 1000)"}});
  const AoPass* ao = aoPassOf(renderer);
  if (ao && ao->settings().ao.method == AoMethod::RayTraced && !ao->settings().environment) {
    const AoSettings& a = ao->settings().ao;
    std::vector<glm::vec3> dirs;
    for (const glm::dvec3& d : ldmDirections(a.directions)) dirs.emplace_back(d);
    const float dMax = a.dMax ? float(*a.dMax) : 0.0f;
    write("frame-ao", frameAoRays(sh, dirs, fc.cameraPos, dMax, s.width, s.height),
          {{"from",
            "each pixel's stored world position with a normal, along each of the N directions with "
            "n.v != 0, turned into n's hemisphere"},
           {"directions", a.directions},
           {"t_min", "shadowTMin (gpu_types.h)"},
           {"t_max", dMax > 0.0f ? nlohmann::json(dMax) : nlohmann::json(gpu::kDirectionalTMax)}});
  } else if (ao) {
    std::printf(
        "note: --rays-out writes the ambient occlusion's rays for method=raytraced only (this frame's "
        "is %s)\n",
        toString(ao->settings().ao.method));
  }
  return written;
}

namespace {

// A hit as --hits-out writes it: 16 bytes, little-endian.
struct HitRecord {
  float t;      // -1: missed (or the backend gives no t: NaN)
  uint32_t id;  // the triangle's draw-order id (Scene::worldTriangles() / 3); ~0u: missed or not given
  float u, v;   // barycentrics of the triangle's 2nd and 3rd vertices; NaN where no triangle is given
};
static_assert(sizeof(HitRecord) == 16, "a hit record is 4 x 4 bytes");

// Where the ray meets triangle `id`'s plane, as barycentrics (u, v) of its 2nd and 3rd vertices, in
// double (Moller-Trumbore without its range tests): the hit's place on the triangle the tracer named.
std::pair<float, float> barycentricsOf(const std::vector<glm::vec3>& tris, uint32_t id, const RayRecord& r) {
  const glm::dvec3 a(tris[3 * size_t(id)]), b(tris[3 * size_t(id) + 1]), c(tris[3 * size_t(id) + 2]);
  const glm::dvec3 o(r.origin[0], r.origin[1], r.origin[2]), d(r.dir[0], r.dir[1], r.dir[2]);
  const glm::dvec3 e1 = b - a, e2 = c - a, p = glm::cross(d, e2);
  const double det = glm::dot(e1, p);
  if (det == 0.0) return {std::nanf(""), std::nanf("")};
  const glm::dvec3 s = o - a, q = glm::cross(s, e1);
  return {float(glm::dot(s, p) / det), float(glm::dot(d, q) / det)};
}

void writeHits(const std::string& path, const std::vector<HitRecord>& hits) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(hits.data()), std::streamsize(hits.size() * sizeof(HitRecord)));
  if (!out) throw InputError("raybench: cannot write " + path + "; give --hits-out a folder that can be written");
}

}  // namespace

int cmdRaysTable(const std::vector<std::string>& files, bool work, bool compiled) {
  const char* hint = "pass files written by 'hybridbench raybench FILE.bin --json OUT.json'";
  std::vector<nlohmann::json> runs;
  std::vector<std::string> backends, sources;
  for (const std::string& f : files) {
    nlohmann::json j = nlohmann::json::parse(readInputText(f, hint), nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded() || !j.is_object() || !j.contains("backends") || !j["backends"].is_array() ||
        !j.contains("file") || !j["file"].is_object())
      throw InputError(f + ": not a raybench --json file (no \"file\" and \"backends\"); " + hint);
    for (const nlohmann::json& b : j["backends"]) {
      const std::string name = b.value("backend", "");
      if (std::find(backends.begin(), backends.end(), name) == backends.end()) backends.push_back(name);
    }
    const std::string source = j.value("device", "?") + ", " + j.value("driver", "?");
    if (std::find(sources.begin(), sources.end(), source) == sources.end()) sources.push_back(source);
    runs.push_back(std::move(j));
  }
  std::string on;
  for (const std::string& s : sources) on += (on.empty() ? "" : "; ") + s;
  std::printf("G rays/s of each backend on each ray file (%s; `hybridbench raybench --json`):\n\n", on.c_str());
  std::printf("| file | rays | query | count | revision |");
  for (const std::string& b : backends) std::printf(" %s |", b.c_str());
  std::printf("\n|---|---|---|---:|---|");
  for (size_t i = 0; i < backends.size(); ++i) std::printf("---:|");
  std::printf("\n");
  for (size_t r = 0; r < runs.size(); ++r) {
    const nlohmann::json& j = runs[r];
    const nlohmann::json& file = j["file"];
    std::printf("| %s | %s | %s | %llu | %s |", fs::path(files[r]).filename().string().c_str(),
                file.value("kind", "?").c_str(), file.value("query", "?").c_str(),
                (unsigned long long)file.value("count", uint64_t(0)), j.value("revision", "?").c_str());
    for (const std::string& name : backends) {
      std::string cell = "—";
      for (const nlohmann::json& b : j["backends"])
        if (b.value("backend", "") == name && b.value("rays_per_s", 0.0) > 0)
          cell = format("%.3g", b.value("rays_per_s", 0.0) / 1e9);
      std::printf(" %s |", cell.c_str());
    }
    std::printf("\n");
  }
  // How close the traversal runs to its loads ceiling, where a file measured one (raybench's
  // loads_ceiling): the traversal's rate over the ceiling's.
  bool anyCeiling = false;
  for (const nlohmann::json& j : runs)
    anyCeiling = anyCeiling || !j.value("loads_ceiling", nlohmann::json::array()).empty();
  if (anyCeiling) {
    std::printf(
        "\nEach traversal's rate against its loads ceiling (the same fetches alone, each waiting for the one "
        "before, no test; `-half`: a node's 4 children read as 64 B instead of 112 B):\n\n| file | backend | "
        "ceiling | ceiling G rays/s | share of the ceiling |\n|---|---|---|---:|---:|\n");
    for (size_t r = 0; r < runs.size(); ++r)
      for (const nlohmann::json& c : runs[r].value("loads_ceiling", nlohmann::json::array())) {
        double rate = 0;
        for (const nlohmann::json& b : runs[r]["backends"])
          if (b.value("backend", "") == c.value("ceiling", "")) rate = b.value("rays_per_s", 0.0);
        std::printf("| %s | %s | %s | %.3g | %.0f %% |\n", fs::path(files[r]).filename().string().c_str(),
                    c.value("backend", "?").c_str(), c.value("ceiling", "?").c_str(), rate / 1e9,
                    100.0 * c.value("fraction_of_ceiling", 0.0));
      }
  }
  if (compiled) {
    // What the driver compiled each compute kernel into, where the file carries it (raybench's
    // "compiled"): the statistics' names as the driver gives them, one column each.
    std::vector<std::string> names;
    for (const nlohmann::json& j : runs)
      for (const nlohmann::json& b : j["backends"])
        if (b.contains("compiled") && b["compiled"].is_array())
          for (const nlohmann::json& e : b["compiled"]) {
            const nlohmann::json st = e.value("statistics", nlohmann::json::object());
            for (const auto& [name, value] : st.items())
              if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
          }
    if (names.empty()) {
      std::printf("\nNo file carries the driver's pipeline statistics (VK_KHR_pipeline_executable_properties).\n");
    } else {
      std::printf(
          "\nWhat the driver compiled each compute kernel into (raybench's compiled: "
          "VK_KHR_pipeline_executable_properties, its names):\n\n| file | backend |");
      for (const std::string& n : names) std::printf(" %s |", n.c_str());
      std::printf("\n|---|---|");
      for (size_t i = 0; i < names.size(); ++i) std::printf("---:|");
      std::printf("\n");
      for (size_t r = 0; r < runs.size(); ++r)
        for (const nlohmann::json& b : runs[r]["backends"]) {
          if (!b.contains("compiled") || !b["compiled"].is_array()) continue;
          for (const nlohmann::json& e : b["compiled"]) {
            std::printf("| %s | %s |", fs::path(files[r]).filename().string().c_str(), b.value("backend", "?").c_str());
            const nlohmann::json st = e.value("statistics", nlohmann::json::object());
            for (const std::string& n : names) std::printf(" %s |", st.contains(n) ? st[n].dump().c_str() : "—");
            std::printf("\n");
          }
        }
    }
  }
  if (!work) return kExitOk;
  std::printf(
      "\nThe compute traversal's work a ray (raybench's traversal_work: replayed on the CPU over the uploaded "
      "layout):\n\n| file | layout | nodes | boxes | triangles | stack pushes | bytes | at its rate |\n"
      "|---|---|---:|---:|---:|---:|---:|---:|\n");
  for (size_t r = 0; r < runs.size(); ++r)
    for (const nlohmann::json& w : runs[r].value("traversal_work", nlohmann::json::array()))
      std::printf(
          "| %s | %s | %.2f | %.1f | %.2f | %.2f | %.0f | %s |\n", fs::path(files[r]).filename().string().c_str(),
          w.value("backend", "?").c_str(), w.value("nodes_per_ray", 0.0), w.value("boxes_per_ray", 0.0),
          w.value("triangles_per_ray", 0.0), w.value("pushes_per_ray", 0.0),
          w.value("node_bytes_per_ray", 0.0) + w.value("triangle_bytes_per_ray", 0.0),
          w.value("bytes_per_s_at_rate", 0.0) > 0 ? formatRate(w.value("bytes_per_s_at_rate", 0.0), "bytes").c_str()
                                                  : "—");
  return kExitOk;
}

int cmdRaybench(const RaybenchOptions& o) {
  const RayFile file = readRayFile(o.file);  // a bad file is one line before anything runs
  const std::string sceneArg = o.scene.empty() ? file.info.sceneName : o.scene;
  const Scene scene = loadSceneArg(sceneArg);
  // The rays meet triangles only: a file that names its geometry takes any scene of that geometry
  // (a frame's rays of the atrium with its config's lights trace on the built-in atrium).
  const bool byGeometry = !file.info.sceneGeometrySha256.empty();
  const std::string sha = byGeometry ? sceneGeometrySha256(scene) : sceneSha256(scene);
  const std::string& want = byGeometry ? file.info.sceneGeometrySha256 : file.info.sceneSha256;
  if (sha != want)
    throw InputError(o.file + ": its rays are of a scene with " + (byGeometry ? "geometry " : "") + "sha256 " +
                     want.substr(0, 12) + "..., not of " + sceneArg + " (" + sha.substr(0, 12) +
                     "...); give that scene with --scene, or export rays of this one (hybridbench rays export)");
  if (!o.hitsOut.empty()) {  // refused before anything runs
    requireOutputFolder(o.hitsOut, "--hits-out");
    std::error_code ec;
    fs::create_directories(o.hitsOut, ec);
    if (ec) throw InputError("--hits-out " + o.hitsOut + ": cannot create it (" + ec.message() + ")");
  }
  const std::vector<DeviceInfo> devices = enumerateDevices();
  VulkanContext ctx(resolveDevice(devices, o.device.empty() ? "0" : o.device));
  if (!ctx.canTrace())
    throw InputError("raybench: " + ctx.info().name +
                     " cannot trace rays (no acceleration structures); use a device "
                     "that can (hybridbench devices)");
  std::fprintf(stderr, "raybench: %zu %s rays (%s hit) on %s, every backend, then the CPU's double hits ...\n",
               file.rays.size(), file.info.kind.c_str(), file.info.query.c_str(), ctx.info().name.c_str());
  const RayFileTrace trace = traceRayFile(ctx, scene, file);
  const bool any = file.info.query == "any";
  const RayHits cpu = traceOnCpu(buildBvh(scene), file.rays, any);
  nlohmann::json j = {{"file", toJson(file.info)},
                      {"device", ctx.info().name},
                      {"driver", ctx.info().driverName + " " + ctx.info().driverVersion},
                      {"revision", gitRevision()},
                      {"cpu_reference", {{"hits", cpu.hits()}, {"misses", file.rays.size() - cpu.hits()}}},
                      {"backends", nlohmann::json::array()}};
  std::printf("%s, %s: %zu rays of %s (%s hit); the CPU's double-precision BVH hits %zu\n", ctx.info().name.c_str(),
              ctx.info().driverVersion.c_str(), file.rays.size(), o.file.c_str(), file.info.query.c_str(), cpu.hits());
  std::printf(
      "| backend | rays/s | median ms | min ms | max ms | missed | hit or miss unlike the CPU's | t more than 1e-6 "
      "off the CPU's | t: largest relative difference |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const Peak& p : trace.figures) {
    const RayFileHits& h = trace.hits.at(p.backend);
    // A hit whose t is more than kTRelative from the CPU's met another surface than the exact test
    // did (an edge or a crack between triangles), not the same one through float rounding: the
    // float test's t is a few u (2^-24 = 6e-8) of t off the double one away from grazing angles.
    constexpr double kTRelative = 1e-6;
    size_t unlike = 0, otherSurface = 0;
    double worst = 0;
    for (size_t i = 0; i < file.rays.size(); ++i) {
      const bool gpuHit = h.missed[i] == 0, cpuHit = cpu.t[i] >= 0.0;
      unlike += gpuHit != cpuHit;
      if (!any && gpuHit && cpuHit && !h.t.empty() && cpu.t[i] > 0.0) {
        const double rel = std::abs(double(h.t[i]) - cpu.t[i]) / cpu.t[i];
        worst = std::max(worst, rel);
        otherSurface += rel > kTRelative;
      }
    }
    const auto [lo, hi] = std::minmax_element(p.ms.begin(), p.ms.end());
    const double median = p.perSecond > 0 ? double(file.rays.size()) / p.perSecond * 1e3 : 0;
    const bool noT = any || h.t.empty();
    const std::string tDiff = noT ? "—" : format("%.2g", worst), tOff = noT ? "—" : std::to_string(otherSurface);
    std::printf("| %s | %s | %.4g | %.4g | %.4g | %.0f | %zu | %s | %s |\n", p.backend.c_str(),
                formatRate(p.perSecond, "rays").c_str(), median, *lo, *hi, p.missed, unlike, tOff.c_str(),
                tDiff.c_str());
    j["backends"].push_back(
        {{"backend", p.backend},
         {"rays_per_s", p.perSecond},
         {"ms", p.ms},
         {"missed", p.missed},
         {"unlike_cpu", unlike},
         {"t_other_surface", noT ? nlohmann::json() : nlohmann::json(otherSurface)},
         {"t_max_relative_difference", any || h.t.empty() ? nlohmann::json() : nlohmann::json(worst)},
         {"through", p.description},
         {"compiled", p.compiled}});
  }
  // The loads ceiling (gpu/peaks.h traceRayFile): the 4-wide traversal's fetches alone; not a tracer,
  // its missed flags are the CPU replay's. How close the traversal runs to it.
  j["loads_ceiling"] = nlohmann::json::array();
  for (const Peak& ceiling : trace.figures) {
    const size_t at = ceiling.backend.find("-loads");
    if (at == std::string::npos) continue;
    const std::string traced = ceiling.backend.substr(0, at);  // "-loads" or "-loads-half" ends it
    for (const Peak& p : trace.figures)
      if (p.backend == traced && ceiling.perSecond > 0) {
        std::printf(
            "\n%s is the loads alone of %s's traversal (replayed on the CPU, each load waiting for the one before, no "
            "test%s): a ceiling, not a tracer. %s runs at %.0f %% of it.\n",
            ceiling.backend.c_str(), traced.c_str(),
            ceiling.backend.find("-half") != std::string::npos ? "; a node's 4 children read as 64 B, not 112 B" : "",
            traced.c_str(), 100.0 * p.perSecond / ceiling.perSecond);
        j["loads_ceiling"].push_back({{"backend", traced},
                                      {"ceiling", ceiling.backend},
                                      {"fraction_of_ceiling", p.perSecond / ceiling.perSecond}});
      }
  }
  // What the driver compiled each compute kernel into (registers, spills, ...), where it says.
  if (!ctx.info().pipelineStatistics) {
    std::printf("\nThe driver gives no pipeline statistics (VK_KHR_pipeline_executable_properties not offered)\n");
  } else {
    std::printf(
        "\nWhat the driver compiled each compute kernel into (VK_KHR_pipeline_executable_properties, its "
        "names)\n| backend | executable | statistics |\n|---|---|---|\n");
    for (const Peak& p : trace.figures)
      if (p.compiled.is_array())
        for (const nlohmann::json& e : p.compiled) {
          std::string stats;
          for (const auto& [name, value] : e["statistics"].items())
            stats += (stats.empty() ? "" : ", ") + name + " " + value.dump();
          std::printf("| %s | %s | %s |\n", p.backend.c_str(), e["name"].get<std::string>().c_str(), stats.c_str());
        }
  }
  // The triangles our BVH met against the CPU's: the same one, a tie (another triangle at the same
  // t within kTieRelative: a shared edge or vertex, where either answer is right), or another.
  constexpr double kTieRelative = 1e-6;  // as kTRelative above: a few float ulps of t
  const std::vector<glm::vec3> worldTris = scene.worldTriangles();
  if (!any) {
    std::printf(
        "\nThe triangle each hit meets against the CPU's (closest hits through our BVH and ray query; a tie: another "
        "triangle at the same t within %g of it, on a shared edge or vertex)\n",
        kTieRelative);
    std::printf("| backend | same triangle | tie | another triangle |\n|---|---:|---:|---:|\n");
    j["triangles_against_cpu"] = nlohmann::json::array();
    for (const Peak& p : trace.figures) {
      const RayFileHits& h = trace.hits.at(p.backend);
      if (h.ids.empty()) continue;
      size_t same = 0, tie = 0, other = 0;
      for (size_t i = 0; i < file.rays.size(); ++i) {
        if (h.ids[i] == ~0u || cpu.t[i] < 0.0) continue;
        if (h.ids[i] == cpu.triangle[i])
          ++same;
        else if (std::abs(double(h.t[i]) - cpu.t[i]) <= kTieRelative * std::max(cpu.t[i], 1e-30))
          ++tie;
        else
          ++other;
      }
      std::printf("| %s | %zu | %zu | %zu |\n", p.backend.c_str(), same, tie, other);
      j["triangles_against_cpu"].push_back({{"backend", p.backend}, {"same", same}, {"tie", tie}, {"other", other}});
    }
  }
  if (!o.hitsOut.empty()) {
    nlohmann::json desc = {
        {"records",
         "16 bytes a ray, in the ray file's order: float32 t (-1: missed; NaN: the backend gives none), "
         "uint32 triangle id (the scene's draw order; 0xFFFFFFFF: missed or not given), float32 u, v "
         "(barycentrics of the triangle's 2nd and 3rd vertices, in double where the ray meets its plane; "
         "NaN where no triangle is given)"},
        {"rays", toJson(file.info)},
        {"revision", gitRevision()},
        {"device", ctx.info().name},
        {"files", nlohmann::json::object()}};
    auto record = [&](size_t i, double t, uint32_t id) {
      HitRecord r{float(t), id, std::nanf(""), std::nanf("")};
      if (id != ~0u && id < worldTris.size() / 3) std::tie(r.u, r.v) = barycentricsOf(worldTris, id, file.rays[i]);
      return r;
    };
    std::vector<HitRecord> recs(file.rays.size());
    for (size_t i = 0; i < recs.size(); ++i) recs[i] = record(i, cpu.t[i] >= 0 ? cpu.t[i] : -1.0, cpu.triangle[i]);
    writeHits((fs::path(o.hitsOut) / "cpu.hits.bin").string(), recs);
    desc["files"]["cpu"] = "cpu.hits.bin (the CPU's double-precision BVH)";
    for (const Peak& p : trace.figures) {
      if (p.backend.find("-loads") != std::string::npos) continue;  // a ceiling: no hits of its own
      const RayFileHits& h = trace.hits.at(p.backend);
      for (size_t i = 0; i < recs.size(); ++i) {
        const bool missed = h.missed[i] != 0;
        const double t = missed ? -1.0 : h.t.empty() ? double(std::nanf("")) : double(h.t[i]);
        recs[i] = record(i, t, missed || h.ids.empty() ? ~0u : h.ids[i]);
      }
      writeHits((fs::path(o.hitsOut) / (p.backend + ".hits.bin")).string(), recs);
      desc["files"][p.backend] = p.backend + ".hits.bin";
    }
    std::ofstream d((fs::path(o.hitsOut) / "hits.json").string());
    d << desc.dump(1) << "\n";
    if (!d) throw InputError("raybench: cannot write " + (fs::path(o.hitsOut) / "hits.json").string());
    std::fprintf(stderr, "raybench: wrote the hits of %zu backends and the CPU's to %s (hits.json says how)\n",
                 trace.figures.size(), o.hitsOut.c_str());
  }
  // The traversal's work per ray, replayed on the CPU over each width's uploaded layout
  // (gpu/trace_work.h): what each rate above moves and tests.
  std::printf(
      "\nThe compute traversal's work per ray (replayed on the CPU over the uploaded layout; bytes: nodes "
      "and triangles read)\n");
  std::printf("| layout | nodes | boxes | triangles | stack pushes | deepest stack | bytes | at its rate |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|\n");
  j["traversal_work"] = nlohmann::json::array();
  for (uint32_t width : {2u, 4u, 8u}) {
    const TraceWork w = traceWork(layoutTraceBvh(worldTris, width), file.rays, any);
    const std::string backend = width == 2 ? "compute" : "compute-w" + std::to_string(width);
    double rate = 0;
    for (const Peak& p : trace.figures)
      if (p.backend == backend) rate = p.perSecond;
    const double bytesPerRay = w.perRay(w.bytes());
    std::printf("| %s | %.2f | %.1f | %.2f | %.2f | %llu | %.0f | %s |\n", backend.c_str(), w.perRay(w.nodes),
                w.perRay(w.boxes), w.perRay(w.triangles), w.perRay(w.pushes), (unsigned long long)w.maxStack,
                bytesPerRay, rate > 0 ? formatRate(rate * bytesPerRay, "bytes").c_str() : "—");
    j["traversal_work"].push_back({{"backend", backend},
                                   {"nodes_per_ray", w.perRay(w.nodes)},
                                   {"boxes_per_ray", w.perRay(w.boxes)},
                                   {"triangles_per_ray", w.perRay(w.triangles)},
                                   {"pushes_per_ray", w.perRay(w.pushes)},
                                   {"deepest_stack", w.maxStack},
                                   {"node_bytes_per_ray", w.perRay(w.nodeBytes)},
                                   {"triangle_bytes_per_ray", w.perRay(w.triangleBytes)},
                                   {"bytes_per_s_at_rate", rate * bytesPerRay}});
  }
  for (const std::string& w : trace.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  if (!o.json.empty()) {
    std::ofstream out(o.json);
    out << j.dump(1) << "\n";
    if (!out) throw InputError("raybench: cannot write --json " + o.json);
  }
  if (ctx.validationMessages()) {
    std::fprintf(stderr, "hybridbench: %u validation message(s)\n", ctx.validationMessages());
    return kExitDeviceFailure;
  }
  return kExitOk;
}

}  // namespace hb

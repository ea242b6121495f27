// Benchmark configs: a JSON file that names a scene, a camera, lights, frame counts and a sweep of
// renderer variants. Parsing is strict: an unknown key, a wrong type or an out-of-range value is one
// hb::InputError line naming the file and the key path, e.g.
//   configs/x.json: variants[2].params.tile_size: 12 is not one of 8, 16, 32
//   configs/x.json: variants[2].params: unknown key "tilesize" (did you mean "tile_size"?)
//   configs/x.json:7:12: malformed JSON: syntax error while parsing object - unexpected '}'; ...
//
// Schema (every key but "name" is optional; // comments are allowed in config files):
// {
//   "name": "thesis",                 // required; letters, digits, '.', '_', '-' (names output files)
//   "description": "free text",       // copied into the results file
//   "scene": "atrium",                // built-in "atrium" (default), a built-in hard case ("grazing",
//                                     // "far-planes", ...: hard_cases.h, with their own camera and
//                                     // lights), or a .gltf/.glb path; a relative path resolves
//                                     // against the config file's directory
//   "scene_params": {                 // built-in atrium only
//     "triangle_scale": 1.0,          // [0.25, 64]: multiplies the atrium's triangle count
//     "lights": 10,                   // 0..4096 procedural point lights
//     "seed": 1,                      // 0..2^32-1, places the lights
//     "light_range": [0.5, 2.0] },    // optional: every light's range drawn from [min, max] m
//                                     // (default: 3..12 m, two in ten from thesis eq. 4.1)
//   "camera": {"index": 0}            // the scene's camera N (default: camera 0)
//           | {"position": [x,y,z], "target": [x,y,z], "up": [0,1,0],
//              "yfov_deg": 60, "znear": 0.1, "zfar": 100},   // 1 <= yfov_deg <= 179, 0 < znear < zfar
//   "lights": "scene"                 // the scene's own lights (default; the atrium's are procedural)
//           | [ {"type": "point" | "spot" | "directional",   // required
//                "name": "key light",
//                "position": [x,y,z],      // point, spot: required
//                "direction": [x,y,z],     // spot, directional: required, non-zero (normalised)
//                "color": [1,1,1],         // linear RGB, >= 0
//                "intensity": 1,           // >= 0; candela (point, spot) or lux (directional)
//                "range": 10,              // point, spot; > 0; absent: thesis eq. 4.1
//                "inner_cone_deg": 0, "outer_cone_deg": 45,  // spot; 0 <= inner < outer <= 90
//                "cast_shadows": true } ],
//   "resolution": [1920, 1080],       // shorthand for defaults.resolution (not both)
//   "ambient": {"color": [r,g,b], "intensity": x},  // the sky's ambient term (scene.h Ambient),
//                                     // replacing the scene's extras.ambient; lights the frame
//                                     // only through effects.ambient_occlusion
//   "environment": {"image": "sky.hdr", "color": [r,g,b], "intensity": x, "rotation": deg},
//                                     // light from every direction (scene/environment.h),
//                                     // replacing the scene's extras.environment; lights the
//                                     // frame only through effects.environment_light
//   "effects": {"shadows": true, "ambient_occlusion": {...}},  // plan/effects.h: what to
//                                     // simulate; over the scene's extras.effects, under a variant's
//                                     // params.effects and --set. shadows false: no BLAS/TLAS, no
//                                     // shadow pass; ambient_occlusion false: no LDM, no AO pass
//   "frames": {"warmup": 50, "measured": 300},   // warmup 0..100000, measured 1..1000000
//   "defaults": { params },           // applied to every variant, on top of the built-in defaults
//   "variants": [ {"name": "no optimisations", "params": { params }}, ... ],
//   "grid": { "tile_size": [8, 16, 32], "normal_culling": ["naive", "improved"] },
//   "notes": ["..."]                  // free text lines; lowerForCpuDevice adds one
// }
// params (VariantParams; built-in defaults = the thesis's best configuration, Table 5.1/5.2):
//   "tile_size": 8 | 16 | 32                         default 8
//   "light_culling": bool                            default true
//   "aabb": bool        (tile-AABB test; only acts with light culling on)   default true
//   "normal_culling": "off" | "naive" | "improved" | "geometric"   default "improved"
//                       (geometric: the visible triangle's own normal; any primary but hardware)
//   "backend": "auto" | "rayquery" | "pipeline"      default "auto"
//   "resolution": [w, h], 1..16384 each              default [1920, 1080]
//   "world_pos": "alg41" | "matrix" | "hit"          default "alg41" (thesis Alg. 4.1)
//                       (hit: eye + t·d from the primary method's hit; any primary but hardware)
//   "range_test": bool  (per-pixel range test before tracing; beyond the thesis)   default false
//   "depth_slices": 0 | 2..32  (2.5D depth-sliced culling; 0 = off; beyond the thesis) default 0
//   "t_min": "constant" | "scaled"  (shadow rays' t_min: the thesis's 0.001 m, or
//                                    max(0.001 m, 400u · distance to the eye); beyond the thesis)
//                                                    default "constant"
//   "primary": "hardware" | "3dr" | "3dr-binned" | "2dr" | "raycast" | "2dr-binned" |
//              "3dr-frustum-cull" | "3dr-frustum-split" | "3dr-full"  (primary visibility: the
//                                    hardware depth prepass, or in compute (Davidovic et al. 2012)
//                                    3D rasterization brute force over screen boxes or binned into
//                                    8x8 screen tiles, the 2D homogeneous baseline (brute force, or
//                                    binned with early-z), frusta through a BVH (culled; split with
//                                    occlusion culling; both with binning and early-z), or a ray per
//                                    pixel on the TLAS)
//                                                    default "hardware"
//   "shading": "forward" | "visbuffer"  (the thesis's forward pass, or shading in compute from
//                                        the visibility buffer; any primary but hardware)
//                                                              default "forward"
//   "r3d_thread_box": 1..65536  (3dr: a triangle whose screen box has at most this many pixels
//                                is rasterized by its own thread; larger boxes go to 8x8 tiles,
//                                a pixel per thread)            default 64
//   "r3d_list_per_tile": 1..1024  (3dr, 3dr-binned, 2dr: work-list entries per 8x8 screen tile the
//                                list starts with; it grows to what the view asks for, the first
//                                frame rendered again: no triangle finds it full)
//                                                               default 64
//   "r3d_frustum": 8 | 16 | 32 | 64 | 128 | 256  (BVH methods: the screen frusta's side, one
//                                workgroup each)               default 256 (the paper's)
//   "r3d_min_frustum": 8 | ... | 256  (3dr-frustum-split, 3dr-full: split down to this side; at
//                                most r3d_frustum)             default 8 (the paper's)
//   "r3d_early_z": bool  (3dr-binned: early-z in the tile pass)  default false
//   "bvh_width": 2 | 4 | 8  (backend=compute: our BVH binary, or collapsed to 4 or 8 children a node)
//                                                    default 4 (faster on the H200 but for AO rays)
//   "aa": "none" | "msaa4" | "msaa8" | "msaa16" | "csaa-4-12"  (anti-aliasing: coverage at the
//                                standard Vulkan sample positions, shading once per pixel and
//                                distinct triangle; CSAA 4 stored + 12 coverage samples; any
//                                rasterizing primary with shading=visbuffer, or primary=hardware
//                                (the raster pipeline's own multisampling, MSAA only))
//                                                    default "none"
//   "reference_ssaa": 1 | 4 | 16 | 64  (accuracy.image_error against: 1 the no-culling reference;
//                                n the same frame supersampled n times, a sqrt(n)^2 grid)
//                                                    default 1
//   "max_lights_per_tile": 32..1024, a multiple of 32 (one 32-bit visibility word per 32 lights)
//                                                    default 32
//   "light_count": 0..4096       built-in atrium with its own lights only; default scene_params.lights
//   "triangle_scale": [0.25, 64] built-in atrium only; default scene_params.triangle_scale
//   "effects": { effects }       this variant's effects, over the config's "effects" (e.g. one
//                                ambient occlusion method per variant); default none
//
// Sweep expansion: the named variants in file order, then the grid's cartesian product (the first
// axis varies slowest) on top of "defaults", each named "key=value, key=value" in axis order, e.g.
// "tile_size=8, normal_culling=naive". Neither "variants" nor "grid": one variant named "default".
// Two runs with the same name are an error. Names are the identity of a run in results files.
//
// Shipped configs (configs/): thesis-table-5-1 (rows named as in Table 5.1), thesis-table-5-2 (rows
// "8x8", "16x16", "32x32"), thesis (both tables; embedded as the default sweep), ci (thesis at
// 320x180, 2+5 frames), thesis-sponza (thesis on scenes/sponza/Sponza.gltf, with its own camera and
// lights), scaling (light_count, triangle_scale and resolution, one axis at a time), accuracy (the
// normal-culling, world-position, range-test, depth-slice and t_min options against each other),
// depth-slices (256 small lights, 0.5-2 m: each tile size with and without 32 depth slices),
// grazing-far (the hard case of that name: constant against scaled t_min), 3d-rasterization
// (primary visibility methods), 3d-rasterization-views (non-planar views), layered-depth-maps
// (ambient occlusion: the LDM paper's settings and the 512 x 256² target, both LDM builds). In
// thesis.json the 5.1 row "light culling + AABB + improved shadow ray culling" and the 5.2 row "8x8"
// are the same configuration and both are kept: each table is built from its own rows, and the pair
// shows the run-to-run noise.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "scene/atrium.h"
#include "scene/scene.h"
#include "shared/gpu_types.h"

namespace hb {

// The settings a config chooses, as the frame and the shaders take them: where a shader reads a
// setting, the enum's value is the shader's constant (shaders/shared/gpu_types.h), so a setting
// goes from the config to the GPU without a string in between.
enum class NormalCulling : uint32_t {
  Off = gpu::kNormalsOff,
  Naive = gpu::kNormalsNaive,
  Improved = gpu::kNormalsImproved,
  Geometric = gpu::kNormalsGeometric,
};
// compute: our BVH and traversal in a compute shader (shadows and raybench; the other ray passes as auto).
enum class RtBackend { Auto, RayQuery, Pipeline, Compute };
enum class WorldPosMethod : uint32_t {
  Alg41 = gpu::kWorldPosAlg41,
  Matrix = gpu::kWorldPosMatrix,
  Hit = gpu::kWorldPosHit,
};
enum class ShadowTMin { Constant, Scaled };
enum class PrimaryMethod {
  Hardware,
  Raster3d,
  Raster3dBinned,
  Raster2d,
  RayCast,
  Raster2dBinned,
  Raster3dFrustumCull,
  Raster3dFrustumSplit,
  Raster3dFull
};
// The methods that traverse frusta through a BVH (raster3d_bvh.comp.glsl).
inline bool primaryUsesBvh(PrimaryMethod m) {
  return m == PrimaryMethod::Raster3dFrustumCull || m == PrimaryMethod::Raster3dFrustumSplit ||
         m == PrimaryMethod::Raster3dFull;
}
enum class ShadingMethod { Forward, Visbuffer };
// Anti-aliasing (3D rasterization paper, Fig. 8; docs/methods/3d-rasterization.md "Anti-aliasing").
enum class AntiAliasing { None, Msaa4, Msaa8, Msaa16, Csaa4x12 };
// Samples with a visibility entry of their own (CSAA: the 4 stored samples; its 12 coverage
// samples are tested in the resolve against the stored samples' triangles only).
inline uint32_t aaStoredSamples(AntiAliasing a) {
  switch (a) {
    case AntiAliasing::None: return 0;
    case AntiAliasing::Msaa4: return 4;
    case AntiAliasing::Msaa8: return 8;
    case AntiAliasing::Msaa16: return 16;
    case AntiAliasing::Csaa4x12: return 4;
  }
  return 0;
}
// Coverage positions per pixel (MSAA: the stored samples; CSAA: 4 stored + 12 coverage).
inline uint32_t aaCoverageSamples(AntiAliasing a) { return a == AntiAliasing::Csaa4x12 ? 16u : aaStoredSamples(a); }
// tile (the thesis's lists, capped at 32 a tile) | bitmask | zbin: no cap (docs/methods/many-lights.md).
enum class LightLists : uint32_t { Tile = gpu::kListTile, Bitmask = gpu::kListBitmask, Zbin = gpu::kListZbin };

const char* toString(NormalCulling);
const char* toString(RtBackend);
const char* toString(WorldPosMethod);
const char* toString(ShadowTMin);
const char* toString(PrimaryMethod);
const char* toString(ShadingMethod);
const char* toString(LightLists);
const char* toString(AntiAliasing);

struct VariantParams {
  uint32_t tileSize = 8;
  bool lightCulling = true;
  bool aabb = true;
  NormalCulling normalCulling = NormalCulling::Improved;
  RtBackend backend = RtBackend::Auto;
  std::array<uint32_t, 2> resolution{1920, 1080};
  WorldPosMethod worldPos = WorldPosMethod::Alg41;
  bool rangeTest = false;
  uint32_t depthSlices = 0;
  ShadowTMin tMin = ShadowTMin::Constant;
  PrimaryMethod primary = PrimaryMethod::Hardware;
  uint32_t r3dThreadBox = 64;
  uint32_t r3dListPerTile = 64;
  uint32_t r3dFrustum = 256;   // BVH methods: the top frusta's side (px)
  uint32_t r3dMinFrustum = 8;  // 3dr-frustum-split, 3dr-full: split down to this side (px)
  bool r3dEarlyZ = false;      // 3dr-binned: early-z in the tile pass (2dr-binned always has it)
  uint32_t bvhWidth = 4;  // backend=compute: children a node of our BVH (gpu/trace_bvh.h; docs/rays.md "Which width")
  // The view's projection (perspective | orthographic | paraboloid | latlong); empty: the camera's.
  std::optional<CameraProjection> projection;
  ShadingMethod shading =
      ShadingMethod::Forward;  // 3dr: screen boxes up to this many pixels are rasterized by one thread
  AntiAliasing aa = AntiAliasing::None;
  // accuracy.image_error's reference: 1 the no-culling reference; 4, 16 or 64 the same frame
  // rendered at sqrt(n) x sqrt(n) times the resolution with aa none, box-filtered to it.
  uint32_t referenceSsaa = 1;
  uint32_t maxLightsPerTile = 32;
  LightLists lightLists = LightLists::Tile;
  // Built-in atrium only. After parsing an atrium config both hold a value (from scene_params
  // unless a variant overrides them); for glTF scenes and explicit light lists they stay empty.
  std::optional<uint32_t> lightCount;
  std::optional<double> triangleScale;
  // "effects": an effects object (plan/effects.h) layered above the config's own for this variant
  // (e.g. one ambient occlusion method per variant); null: the config's.
  nlohmann::json effects;

  bool operator==(const VariantParams&) const = default;
};

struct Variant {
  std::string name;
  VariantParams params;
};

struct CameraSpec {
  bool autoFrame = false;     // "camera": "auto": app/auto_scene.h's camera, whatever the scene has
  bool explicitPose = false;  // false: use the scene's camera `index`
  uint32_t index = 0;
  glm::vec3 position{0.0f};
  glm::vec3 target{0.0f, 0.0f, -1.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float yfovDeg = 60.0f;
  float znear = 0.1f;
  float zfar = 100.0f;
};

// One axis of a grid: a parameter key and its values (validated JSON, as written).
struct GridAxis {
  std::string key;
  std::vector<nlohmann::json> values;
};

struct Config {
  std::string sourceName;  // the file (or "thesis.json (embedded)") that messages name
  std::string name;
  std::string description;
  // "atrium" or an absolute glTF path (a relative one in the file resolves against its directory)
  std::string scene = "atrium";
  bool sceneIsBuiltin() const { return scene == "atrium"; }
  // A built-in hard case (hard_cases.h: "grazing", "far-planes", ...): its own camera and lights.
  bool sceneIsHardCase() const;
  AtriumParams sceneParams;  // meaningful for the atrium only (atrium.h)
  CameraSpec camera;
  std::optional<Ambient> ambient;            // "ambient": replaces the scene's ambient term (scene.h)
  std::optional<Environment> environment;    // "environment": replaces the scene's (scene.h)
  std::optional<std::vector<Light>> lights;  // empty optional: the scene's lights
  // The "effects" object as the file gives it (validated): keys it leaves out stay the scene's
  // or the built-in default (plan/effects.h). An EffectsRequest layer of source Config.
  nlohmann::json effects = nlohmann::json::object();
  uint32_t warmupFrames = 50;
  uint32_t measuredFrames = 300;
  // Built-in defaults, then "resolution", then scene_params (light_count, triangle_scale), then
  // the "defaults" object.
  VariantParams defaults;
  std::vector<Variant> variants;  // named variants, params complete (defaults applied)
  std::vector<GridAxis> grid;     // in file order when parsed from a file or ordered_json
  // Largest resolution any variant may use (0 = no limit); set by lowerForCpuDevice and applied
  // by expandVariants after naming, so names stay those of the full-size sweep.
  std::array<uint32_t, 2> resolutionCap{0, 0};
  std::vector<std::string> notes;
};

// Reads and validates a config file. Throws InputError (missing file, malformed JSON with line and
// column, any invalid field).
Config loadConfig(const std::string& path);

// Validates a parsed document. sourceName prefixes every message; its directory is the base for a
// relative scene path. With nlohmann::json (keys sorted) the grid axes come out in alphabetical
// order; pass ordered_json to keep the file's order.
Config parseConfig(const nlohmann::json& doc, const std::string& sourceName);
Config parseConfig(const nlohmann::ordered_json& doc, const std::string& sourceName);

// The runs of a config, in order (see the expansion rules above). Non-empty; names are unique.
std::vector<Variant> expandVariants(const Config& config);

// The full effective config, every default filled in, for the results file. The grid is written
// out as explicit variants (file order kept), so parseConfig(toJson(c)) expands to the same runs.
nlohmann::json toJson(const Config& config);
nlohmann::json toJson(const VariantParams& params);

// Every key --set takes: the parameters (help params), the effects (help effects) and camera.
std::vector<std::string> setKeys();
// Applies one command-line "--set key=value" to params, with the validation and messages of a
// config file. The value is JSON if it parses as JSON, else a bare string ("improved"); resolution
// also takes "1920x1080". Throws InputError naming the argument; a key that is no parameter is
// refused with a did-you-mean over setKeys() (an effect or camera is the caller's to apply first).
void applySetOverride(VariantParams& params, const std::string& keyEqualsValue);

// The one default of every parameter: a VariantParams as declared above. RenderSettings and the
// passes' settings take theirs from here (docs/contributing.md "Adding a parameter").
const VariantParams& paramDefaults();
// Checks one parameter's value by its schema row (the check a config file and --set get), for
// settings built without a config (the frame's own consumers, tests): InputError "tile_size: 12 is
// not one of 8, 16, 32".
void checkParam(std::string_view key, const nlohmann::ordered_json& value);

// Checks that params fit the config's scene (light_count/triangle_scale only for the atrium with
// its procedural lights). parseConfig runs it on every variant; run it again after --set.
void checkParamsFitScene(const Config& config, const VariantParams& params, const std::string& where);

// configs/thesis.json as embedded in the binary (byte for byte; a test holds it to the file).
std::string_view embeddedDefaultConfigText();
Config embeddedDefaultConfig();

// For CPU devices (lavapipe): caps every resolution to fit 480x270 (aspect kept, integer divisor),
// warmup to 2 and measured frames to 5, and adds a note saying so to config.notes. Variant names
// are unchanged so runs stay comparable by name with GPU runs.
// The frame counts the user gave on the command line (sweep --frames/--warmup) are kept as given
// and the note says so: "measured frames 12 (--frames)".
struct CpuFrameOverrides {
  std::optional<uint32_t> warmup, measured;
};
Config lowerForCpuDevice(Config config, const CpuFrameOverrides& given = {});

// The scene camera for an explicit pose (precondition: spec.explicitPose).
Camera cameraFromSpec(const CameraSpec& spec);

}  // namespace hb

// VariantParams: reading one parameter strictly, writing them back, and --set key=value.
#include <algorithm>
#include <charconv>

#include "base/errors.h"
#include "config/config.h"
#include "config/config_reader.h"
#include "plan/effects.h"

namespace hb {

using config_reader::Json;
using config_reader::Where;

namespace {

// Each choice's names in its enum's order: a choice's index is its enum value (asserted below), so
// the parser's allowed values, `hybridbench help params` and toString read one list.
constexpr const char* kNormalCullingNames[] = {"off", "naive", "improved", "geometric"};
constexpr const char* kRtBackendNames[] = {"auto", "rayquery", "pipeline", "compute"};
constexpr const char* kWorldPosNames[] = {"alg41", "matrix", "hit"};
constexpr const char* kShadingNames[] = {"forward", "visbuffer"};
constexpr const char* kLightListsNames[] = {"tile", "bitmask", "zbin"};
constexpr const char* kPrimaryNames[] = {"hardware", "3dr",        "3dr-binned",       "2dr",
                                         "raycast",  "2dr-binned", "3dr-frustum-cull", "3dr-frustum-split",
                                         "3dr-full"};
constexpr const char* kShadowTMinNames[] = {"constant", "scaled"};
constexpr const char* kAntiAliasingNames[] = {"none", "msaa4", "msaa8", "msaa16", "csaa-4-12"};

// A list names every value of its enum when its last name is the last enumerator's.
static_assert(std::size(kNormalCullingNames) == size_t(NormalCulling::Geometric) + 1);
static_assert(std::size(kRtBackendNames) == size_t(RtBackend::Compute) + 1);
static_assert(std::size(kWorldPosNames) == size_t(WorldPosMethod::Hit) + 1);
static_assert(std::size(kShadingNames) == size_t(ShadingMethod::Visbuffer) + 1);
static_assert(std::size(kLightListsNames) == size_t(LightLists::Zbin) + 1);
static_assert(std::size(kPrimaryNames) == size_t(PrimaryMethod::Raster3dFull) + 1);
static_assert(std::size(kShadowTMinNames) == size_t(ShadowTMin::Scaled) + 1);
static_assert(std::size(kAntiAliasingNames) == size_t(AntiAliasing::Csaa4x12) + 1);

template <typename Enum, size_t N>
const char* nameIn(const char* const (&names)[N], Enum v) {
  return size_t(v) < N ? names[size_t(v)] : "?";
}

template <size_t N>
std::vector<std::string_view> choicesOf(const char* const (&names)[N]) {
  return {std::begin(names), std::end(names)};
}

}  // namespace

const char* toString(NormalCulling v) { return nameIn(kNormalCullingNames, v); }
const char* toString(RtBackend v) { return nameIn(kRtBackendNames, v); }
const char* toString(WorldPosMethod v) { return nameIn(kWorldPosNames, v); }
const char* toString(ShadingMethod v) { return nameIn(kShadingNames, v); }
const char* toString(LightLists v) { return nameIn(kLightListsNames, v); }
const char* toString(PrimaryMethod v) { return nameIn(kPrimaryNames, v); }
const char* toString(ShadowTMin v) { return nameIn(kShadowTMinNames, v); }
const char* toString(AntiAliasing v) { return nameIn(kAntiAliasingNames, v); }

namespace config_reader {

// A choice's index is its enum value: the choices below are listed in the enums' order.
static_assert(NormalCulling(1) == NormalCulling::Naive && NormalCulling(3) == NormalCulling::Geometric);
static_assert(WorldPosMethod(1) == WorldPosMethod::Matrix && WorldPosMethod(2) == WorldPosMethod::Hit);
static_assert(LightLists(1) == LightLists::Bitmask && LightLists(2) == LightLists::Zbin);

// The parameter schema: one row per key, in schema order. applyParam reads every value through
// its row, and `hybridbench help params` prints the rows, so the allowed values the help shows are
// the ones the parser enforces.
const std::vector<ParamSpec>& paramSpecs() {
  using K = ParamKind;
  static const std::vector<ParamSpec> specs = {
      {"tile_size",
       K::IntChoice,
       {},
       {8, 16, 32},
       0,
       0,
       "",
       "px",
       "",
       "side of the square screen tiles that lights are culled into",
       [](VariantParams& p, const Json& v, size_t, const Where&) { p.tileSize = v.get<uint32_t>(); }},
      {"light_culling",
       K::Bool,
       {},
       {},
       0,
       0,
       "",
       "",
       "",
       "cull lights into per-tile lists; off: every pixel considers every light",
       [](VariantParams& p, const Json& v, size_t, const Where&) { p.lightCulling = v.get<bool>(); }},
      {"aabb",
       K::Bool,
       {},
       {},
       0,
       0,
       "",
       "",
       "",
       "test lights against each tile's depth AABB as well as its frustum (acts with light culling on)",
       [](VariantParams& p, const Json& v, size_t, const Where&) { p.aabb = v.get<bool>(); }},
      {"normal_culling",
       K::Choice,
       choicesOf(kNormalCullingNames),
       {},
       0,
       0,
       "",
       "",
       "",
       "skip shadow rays to lights behind the surface (geometric: the triangle's own normal; any primary but "
       "hardware)",
       [](VariantParams& p, const Json&, size_t i, const Where&) { p.normalCulling = NormalCulling(i); }},
      {"backend",
       K::Choice,
       choicesOf(kRtBackendNames),
       {},
       0,
       0,
       "",
       "",
       "",
       "how every ray pass traces (shadows, AO, the ray-cast primary, photons, raybench): ray queries in "
       "compute, the ray-tracing pipeline, our own BVH and traversal in compute, or auto: the driver's unless "
       "the device's measured ray rates favour ours (render.json backend_choice)",
       [](VariantParams& p, const Json&, size_t i, const Where&) { p.backend = RtBackend(i); }},
      {"resolution",
       K::Resolution,
       {},
       {},
       1,
       double(kMaxResolution),
       "",
       "px",
       "",
       "render size [width, height] (--set also takes WIDTHxHEIGHT)",
       [](VariantParams& p, const Json& v, size_t, const Where&) {
         p.resolution = {v[0].get<uint32_t>(), v[1].get<uint32_t>()};
       }},
      {"world_pos",
       K::Choice,
       choicesOf(kWorldPosNames),
       {},
       0,
       0,
       "",
       "",
       "",
       "how a pixel's world position is rebuilt: thesis Alg. 4.1, the inverse view-projection, or the primary "
       "method's hit (any primary but hardware)",
       [](VariantParams& p, const Json&, size_t i, const Where&) { p.worldPos = WorldPosMethod(i); }},
      {"range_test",
       K::Bool,
       {},
       {},
       0,
       0,
       "",
       "",
       "",
       "per-pixel light range test before tracing (beyond the thesis)",
       [](VariantParams& p, const Json& v, size_t, const Where&) { p.rangeTest = v.get<bool>(); }},
      {"depth_slices",
       K::Int,
       {},
       {},
       0,
       32,
       "not 1 (0 = off)",
       "",
       "",
       "2.5D depth-sliced light culling: slices per tile (beyond the thesis)",
       [](VariantParams& p, const Json& v, size_t, const Where& where) {
         if (v.get<int64_t>() == 1) where.fail("1 is not allowed: use 0 (off) or 2..32 slices");
         p.depthSlices = v.get<uint32_t>();
       }},
      {"t_min",
       K::Choice,
       choicesOf(kShadowTMinNames),
       {},
       0,
       0,
       "",
       "",
       "",
       "shadow rays' t_min: the thesis's 0.001 m, or max(0.001 m, 400u x distance to the eye)",
       [](VariantParams& p, const Json&, size_t i, const Where&) { p.tMin = ShadowTMin(i); }},
      {"primary",
       K::Choice,
       choicesOf(kPrimaryNames),
       {},
       0,
       0,
       "",
       "",
       "",
       "primary visibility: the hardware depth prepass, compute 3D rasterization (brute force or binned into "
       "8x8 tiles), the 2D homogeneous baseline (brute force, or binned with early-z), frusta through a BVH "
       "(culled, split with occlusion culling, or both with binning and early-z), or a ray per pixel",
       [](VariantParams& p, const Json&, size_t i, const Where&) { p.primary = PrimaryMethod(i); }},
      {"projection",
       K::Choice,
       {"perspective", "orthographic", "paraboloid", "latlong"},
       {},
       0,
       0,
       "",
       "",
       "the camera's",
       "the view's projection, replacing the camera's",
       [](VariantParams& p, const Json&, size_t i, const Where&) { p.projection = CameraProjection(i); }},
      {"r3d_thread_box",
       K::Int,
       {},
       {},
       1,
       65536,
       "",
       "px",
       "",
       "3dr: a triangle whose screen box has at most this many pixels is rasterized by its own thread",
       [](VariantParams& p, const Json& v, size_t, const Where&) { p.r3dThreadBox = v.get<uint32_t>(); }},
      {"r3d_list_per_tile",
       K::Int,
       {},
       {},
       1,
       1024,
       "",
       "entries",
       "",
       "3dr, 3dr-binned, 2dr: work-list entries per 8x8 screen tile the list starts with; it grows to what the "
       "view asks for (the first frame rendered again), so no triangle finds it full (tile_list_overflows 0, "
       "list_capacity and list_grown_from in the results)",
       [](VariantParams& p, const Json& v, size_t, const Where&) { p.r3dListPerTile = v.get<uint32_t>(); }},
      {"r3d_frustum",
       K::IntChoice,
       {},
       {8, 16, 32, 64, 128, 256},
       0,
       0,
       "",
       "px",
       "",
       "3dr-frustum-cull, 3dr-frustum-split, 3dr-full: the side of the screen frusta that traverse the BVH, "
       "each one a workgroup (the paper's 256)",
       [](VariantParams& p, const Json& v, size_t, const Where&) { p.r3dFrustum = v.get<uint32_t>(); }},
      {"r3d_min_frustum",
       K::IntChoice,
       {},
       {8, 16, 32, 64, 128, 256},
       0,
       0,
       "",
       "px",
       "",
       "3dr-frustum-split, 3dr-full: frusta split down to this side (the paper's 8; at most r3d_frustum)",
       [](VariantParams& p, const Json& v, size_t, const Where&) { p.r3dMinFrustum = v.get<uint32_t>(); }},
      {"bvh_width",
       K::IntChoice,
       {},
       {2, 4, 8},
       0,
       0,
       "",
       "",
       "",
       "backend=compute: children a node of our BVH has (2: the binary SAH tree; 4 or 8: collapsed, four or eight "
       "boxes tested a node)",
       [](VariantParams& p, const Json& v, size_t, const Where&) { p.bvhWidth = v.get<uint32_t>(); }},
      {"r3d_early_z",
       K::Bool,
       {},
       {},
       0,
       0,
       "",
       "",
       "",
       "3dr-binned: skip a tile's triangles that lie behind every pixel's nearest hit so far (2dr-binned and "
       "3dr-full always do)",
       [](VariantParams& p, const Json& v, size_t, const Where&) { p.r3dEarlyZ = v.get<bool>(); }},
      {"shading",
       K::Choice,
       choicesOf(kShadingNames),
       {},
       0,
       0,
       "",
       "",
       "",
       "the forward pass, or shading in compute from the visibility buffer (any primary but hardware)",
       [](VariantParams& p, const Json&, size_t i, const Where&) { p.shading = ShadingMethod(i); }},
      {"aa",
       K::Choice,
       choicesOf(kAntiAliasingNames),
       {},
       0,
       0,
       "",
       "",
       "",
       "anti-aliasing: coverage at the standard Vulkan sample positions, shading once per pixel and distinct "
       "triangle (CSAA: 4 stored + 12 coverage samples); shading=visbuffer after a compute primary, or "
       "primary=hardware (MSAA only)",
       [](VariantParams& p, const Json&, size_t i, const Where&) { p.aa = AntiAliasing(i); }},
      {"reference_ssaa",
       K::IntChoice,
       {},
       {1, 4, 16, 64},
       0,
       0,
       "",
       "samples",
       "",
       "accuracy.image_error's reference: 1 the no-culling render; n the same frame rendered at sqrt(n) times "
       "the width and height with aa none and box-filtered (64: the supersampled reference of the AA study)",
       [](VariantParams& p, const Json& v, size_t, const Where&) { p.referenceSsaa = v.get<uint32_t>(); }},
      {"max_lights_per_tile",
       K::Int,
       {},
       {},
       32,
       1024,
       "a multiple of 32",
       "lights",
       "",
       "capacity of a tile's light list (one 32-bit visibility word per 32 lights)",
       [](VariantParams& p, const Json& v, size_t, const Where& where) {
         const int64_t n = v.get<int64_t>();
         // The visibility bitmask holds one 32-bit word per 32 lights of a tile.
         if (n % 32 != 0) where.fail(std::to_string(n) + " is not a multiple of 32");
         p.maxLightsPerTile = uint32_t(n);
       }},
      {"light_lists",
       K::Choice,
       choicesOf(kLightListsNames),
       {},
       0,
       0,
       "",
       "",
       "",
       "light list layout: the thesis's capped tile lists, or uncapped bitmasks or z-bins",
       [](VariantParams& p, const Json&, size_t i, const Where&) { p.lightLists = LightLists(i); }},
      {"light_count",
       K::Int,
       {},
       {},
       0,
       double(kMaxLightCount),
       "",
       "lights",
       "scene_params.lights",
       "procedural point lights (built-in atrium with its own lights only)",
       [](VariantParams& p, const Json& v, size_t, const Where&) { p.lightCount = v.get<uint32_t>(); }},
      {"triangle_scale",
       K::Number,
       {},
       {},
       kMinTriangleScale,
       kMaxTriangleScale,
       "",
       "",
       "scene_params.triangle_scale",
       "multiplies the atrium's triangle count (built-in atrium only)",
       [](VariantParams& p, const Json& v, size_t, const Where&) { p.triangleScale = v.get<double>(); }},
      {"effects",
       K::Effects,
       {},
       {},
       0,
       0,
       "",
       "",
       "none",
       "this variant's effects object, over the config's \"effects\" (see hybridbench help effects)",
       [](VariantParams& p, const Json& v, size_t, const Where&) { p.effects = nlohmann::json(v); }},
  };
  return specs;
}

const ParamSpec* findParam(std::string_view key) {
  for (const ParamSpec& s : paramSpecs())
    if (s.key == key) return &s;
  return nullptr;
}

const std::vector<std::string_view>& paramKeys() {
  static const std::vector<std::string_view> keys = [] {
    std::vector<std::string_view> k;
    for (const ParamSpec& s : paramSpecs()) k.push_back(s.key);
    return k;
  }();
  return keys;
}

void applyParam(VariantParams& p, std::string_view key, const Json& v, const Where& where, const Where& container) {
  const ParamSpec* spec = findParam(key);
  if (!spec) failUnknownKey(key, container, paramKeys());
  size_t choice = 0;
  switch (spec->kind) {
    case ParamKind::Bool: readBool(v, where); break;
    case ParamKind::Int: readInt(v, where, int64_t(spec->lo), int64_t(spec->hi)); break;
    case ParamKind::IntChoice: readIntChoice(v, where, spec->intChoices); break;
    case ParamKind::Choice: choice = readChoice(v, where, spec->choices); break;
    case ParamKind::Number: readNumber(v, where, spec->lo, spec->hi, /*loExclusive=*/false); break;
    case ParamKind::Resolution:
      if (!v.is_array() || v.size() != 2) where.fail("expected [width, height], got " + describe(v));
      readInt(v[0], where.index(0), int64_t(spec->lo), int64_t(spec->hi));
      readInt(v[1], where.index(1), int64_t(spec->lo), int64_t(spec->hi));
      break;
    case ParamKind::Effects: validateEffects(v, where); break;  // the schema of plan/effects.h
  }
  spec->store(p, v, choice, where);
}

void applyParams(VariantParams& p, const Json& object, const Where& where) {
  requireObjectWithKeys(object, where, paramKeys());
  for (const auto& item : object.items()) applyParam(p, item.key(), item.value(), where.key(item.key()), where);
}

std::string valueLabel(const Json& value) {
  if (value.is_string()) return value.get<std::string>();
  if (value.is_array() && value.size() == 2)  // a resolution
    return valueLabel(value[0]) + "x" + valueLabel(value[1]);
  return value.dump();
}

}  // namespace config_reader

nlohmann::json toJson(const VariantParams& p) {
  nlohmann::json j;
  j["tile_size"] = p.tileSize;
  j["light_culling"] = p.lightCulling;
  j["aabb"] = p.aabb;
  j["normal_culling"] = toString(p.normalCulling);
  j["backend"] = toString(p.backend);
  j["resolution"] = {p.resolution[0], p.resolution[1]};
  j["world_pos"] = toString(p.worldPos);
  j["range_test"] = p.rangeTest;
  j["depth_slices"] = p.depthSlices;
  j["t_min"] = toString(p.tMin);
  j["primary"] = toString(p.primary);
  j["r3d_thread_box"] = p.r3dThreadBox;
  j["r3d_list_per_tile"] = p.r3dListPerTile;
  j["r3d_frustum"] = p.r3dFrustum;
  j["r3d_min_frustum"] = p.r3dMinFrustum;
  j["r3d_early_z"] = p.r3dEarlyZ;
  j["bvh_width"] = p.bvhWidth;
  if (p.projection) j["projection"] = toString(*p.projection);
  j["shading"] = toString(p.shading);
  j["aa"] = toString(p.aa);
  j["reference_ssaa"] = p.referenceSsaa;
  j["max_lights_per_tile"] = p.maxLightsPerTile;
  j["light_lists"] = toString(p.lightLists);
  if (p.lightCount) j["light_count"] = *p.lightCount;
  if (p.triangleScale) j["triangle_scale"] = *p.triangleScale;
  if (!p.effects.is_null()) j["effects"] = p.effects;
  return j;
}

std::vector<std::string> setKeys() {
  std::vector<std::string> keys(config_reader::paramKeys().begin(), config_reader::paramKeys().end());
  for (const EffectDef* e : allEffects()) keys.push_back(e->name);
  keys.push_back("camera");
  keys.push_back("environment");
  return keys;
}

const VariantParams& paramDefaults() {
  static const VariantParams defaults{};
  return defaults;
}

void checkParam(std::string_view key, const Json& value) {
  VariantParams scratch;
  const Where where{std::string(key), ""};
  config_reader::applyParam(scratch, key, value, where, where);
}

void applySetOverride(VariantParams& params, const std::string& keyEqualsValue) {
  Where where{"--set " + keyEqualsValue, ""};
  const std::vector<std::string> keys = setKeys();
  const std::vector<std::string_view> keyViews(keys.begin(), keys.end());
  size_t eq = keyEqualsValue.find('=');
  if (eq == std::string::npos || eq == 0) {
    std::string list;
    for (const std::string& k : keys) list += (list.empty() ? "" : ", ") + k;
    where.fail("expected key=value, e.g. --set tile_size=16 (keys: " + list + ")");
  }
  std::string key = keyEqualsValue.substr(0, eq);
  // Not a parameter: one line with a did-you-mean over every key --set takes (parameters, effects,
  // camera), the same schema `help params` and `help effects` print.
  const auto& params_ = config_reader::paramKeys();
  if (std::find(params_.begin(), params_.end(), key) == params_.end()) failUnknownKey(key, where, keyViews);
  std::string text = keyEqualsValue.substr(eq + 1);

  // A value is JSON when it parses as JSON (16, true, [640,360]); otherwise a bare word (improved).
  Json value = Json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (value.is_discarded()) value = text;
  if (key == "resolution" && value.is_string()) {  // 1920x1080
    const std::string& s = value.get_ref<const std::string&>();
    size_t x = s.find('x');
    uint64_t w = 0, h = 0;
    bool ok = x != std::string::npos && std::from_chars(s.data(), s.data() + x, w).ptr == s.data() + x && x > 0 &&
              std::from_chars(s.data() + x + 1, s.data() + s.size(), h).ptr == s.data() + s.size() && x + 1 < s.size();
    if (!ok) where.key(key).fail("expected WIDTHxHEIGHT (e.g. 1920x1080) or [w, h], got \"" + s + "\"");
    value = Json::array({w, h});
  }
  config_reader::applyParam(params, key, value, where.key(key), where);
}

}  // namespace hb

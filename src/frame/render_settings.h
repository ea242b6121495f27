// What a frame is rendered with: the variant's settings as the frame takes them (the config's own
// enums, app/scene_setup.h renderSettingsFor) plus the effects asked for above the scene.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "config/config.h"
#include "plan/effects.h"
#include "scene/scene.h"

namespace hb {

// The device's measured ray rates (peaks: the same random rays through each backend) that
// backend=auto chooses from (ray_backend.h chooseBackend). 0: not measured.
struct RayRates {
  double driverOcclusion = 0, computeOcclusion = 0;  // rays/s, any hit (shadow and AO rays)
  double driverClosest = 0, computeClosest = 0;      // rays/s, closest hit (primary rays, photons)
  std::string driver;                                // the driver backend measured: rayquery | pipeline
  std::string source;                                // where the figures come from
};

struct RenderSettings {
  uint32_t width = 1920;
  uint32_t height = 1080;
  uint32_t cameraIndex = 0;
  // The view's projection instead of the camera's own (config "projection"); empty: the camera's.
  std::optional<CameraProjection> projection;
  uint32_t tileSize = 16;
  bool lightCulling = true;
  bool aabb = false;
  // The effects asked for above the scene's own (config, --set); the frame is planned from them
  // and the scene (plan/effects.h planFrame). Empty: the scene's extras.effects or the defaults.
  EffectsRequest effects;
  RtBackend backend = RtBackend::Auto;
  std::optional<RayRates> rayRates;  // backend=auto: the measurements it may choose compute from
  uint32_t bvhWidth = 8;             // backend=compute: our BVH's children a node (2, 4 or 8; trace_bvh.h)
  NormalCulling normals = NormalCulling::Off;
  WorldPosMethod worldPos = WorldPosMethod::Alg41;
  bool rangeTest = false;
  uint32_t depthSlices = 0;                  // 0 off, 2..32: 2.5D slab test in light culling
  LightLists lightLists = LightLists::Tile;  // tile (capped at 32, the thesis) | bitmask | zbin
  ShadowTMin tMin = ShadowTMin::Constant;    // scaled: max(kShadowTMin, kShadowTMinPerMetre·dist)
  PrimaryMethod primary = PrimaryMethod::Hardware;
  bool fp64Fallback = true;                        // raster3d: false only to measure what the fallback prevents
  uint32_t raster3dListPerTile = 64;               // raster3d: work-list entries per 8x8 screen tile
  uint32_t raster3dFrustum = 256;                  // BVH methods: the top frusta's side (px)
  uint32_t raster3dMinFrustum = 8;                 // split methods: the smallest frustum's side (px)
  bool raster3dEarlyZ = false;                     // 3dr-binned: early-z in the tile pass
  uint32_t raster3dStackEntries = 768;             // BVH methods' stack (tests only: to reach its fallback)
  uint32_t raster3dThreadBox = 64;                 // raster3d: the largest box one thread rasterizes
  ShadingMethod shading = ShadingMethod::Forward;  // visbuffer: in compute from the visibility buffer
  AntiAliasing aa = AntiAliasing::None;            // compute primaries with visbuffer shading, or hardware MSAA
  bool raster3dShadingDepthTest = true;            // raster3d: early depth test before the id test (false: check only)
};

// The pass that computes primary visibility for a method (effects.h kDepthPrepassPass, ...).
inline const char* primaryPassOf(PrimaryMethod method) {
  if (method == PrimaryMethod::Hardware) return kDepthPrepassPass;
  return method == PrimaryMethod::RayCast ? kRayCastPass : kRaster3dPass;
}

}  // namespace hb

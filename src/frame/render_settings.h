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
  // A parameter the config has takes its one default from it (config.h paramDefaults).
  uint32_t width = paramDefaults().resolution[0];
  uint32_t height = paramDefaults().resolution[1];
  uint32_t cameraIndex = 0;
  // The view's projection instead of the camera's own (config "projection"); empty: the camera's.
  std::optional<CameraProjection> projection;
  uint32_t tileSize = paramDefaults().tileSize;
  bool lightCulling = paramDefaults().lightCulling;
  bool aabb = paramDefaults().aabb;
  // The effects asked for above the scene's own (config, --set); the frame is planned from them
  // and the scene (plan/effects.h planFrame). Empty: the scene's extras.effects or the defaults.
  EffectsRequest effects;
  RtBackend backend = paramDefaults().backend;
  std::optional<RayRates> rayRates;              // backend=auto: the measurements it may choose compute from
  uint32_t bvhWidth = paramDefaults().bvhWidth;  // backend=compute: our BVH's children a node (2, 4 or 8; trace_bvh.h)
  NormalCulling normals = paramDefaults().normalCulling;
  WorldPosMethod worldPos = paramDefaults().worldPos;
  bool rangeTest = paramDefaults().rangeTest;
  uint32_t depthSlices = paramDefaults().depthSlices;  // 0 off, 2..32: 2.5D slab test in light culling
  LightLists lightLists = paramDefaults().lightLists;  // tile (capped at 32, the thesis) | bitmask | zbin
  ShadowTMin tMin = paramDefaults().tMin;              // scaled: max(kShadowTMin, kShadowTMinPerMetre·dist)
  PrimaryMethod primary = paramDefaults().primary;
  bool fp64Fallback = true;  // raster3d: false only to measure what the fallback prevents
  uint32_t raster3dListPerTile = paramDefaults().r3dListPerTile;  // raster3d: work-list entries per 8x8 screen tile
  // raster3d: the work list grows to what the view asks for (Raster3dPass::growList); false keeps
  // r3d_list_per_tile's size, so that a triangle can find it full (tests of that path).
  bool raster3dListGrows = true;
  uint32_t raster3dFrustum = paramDefaults().r3dFrustum;        // BVH methods: the top frusta's side (px)
  uint32_t raster3dMinFrustum = paramDefaults().r3dMinFrustum;  // split methods: the smallest frustum's side (px)
  bool raster3dEarlyZ = paramDefaults().r3dEarlyZ;              // 3dr-binned: early-z in the tile pass
  uint32_t raster3dStackEntries = 768;                        // BVH methods' stack (tests only: to reach its fallback)
  uint32_t raster3dThreadBox = paramDefaults().r3dThreadBox;  // raster3d: the largest box one thread rasterizes
  ShadingMethod shading = paramDefaults().shading;            // visbuffer: in compute from the visibility buffer
  AntiAliasing aa = paramDefaults().aa;  // compute primaries with visbuffer shading, or hardware MSAA
  bool raster3dShadingDepthTest = true;  // raster3d: early depth test before the id test (false: check only)
};

// The pass that computes primary visibility for a method (effects.h kDepthPrepassPass, ...).
inline const char* primaryPassOf(PrimaryMethod method) {
  if (method == PrimaryMethod::Hardware) return kDepthPrepassPass;
  return method == PrimaryMethod::RayCast ? kRayCastPass : kRaster3dPass;
}

}  // namespace hb

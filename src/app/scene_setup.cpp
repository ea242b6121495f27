#include "app/scene_setup.h"

#include <cstdio>
#include <filesystem>

#include "app/auto_scene.h"
#include "base/errors.h"
#include "gltf/gltf_io.h"
#include "scene/atrium.h"
#include "scene/hard_cases.h"
#include "shared/gpu_types.h"

namespace hb {

void applySceneOverrides(const Config& config, Scene& scene) {
  if (config.lights) {
    scene.lights = *config.lights;
    scene.lightsSource = "config";
  }
  if (config.ambient) scene.ambient = *config.ambient;
  if (config.environment) scene.environment = *config.environment;
  if (config.camera.autoFrame) return;  // completeScene makes it
  if (config.camera.explicitPose) {
    scene.cameras.insert(scene.cameras.begin(), cameraFromSpec(config.camera));
    scene.cameraSource = "config";
  } else if (config.camera.index > 0) {
    if (config.camera.index >= scene.cameras.size())
      throw InputError(config.sourceName + ": camera.index: " + std::to_string(config.camera.index) +
                       " but the scene has " + std::to_string(scene.cameras.size()) + " camera(s)");
    std::swap(scene.cameras[0], scene.cameras[config.camera.index]);
  }
}

Scene sceneForVariant(const Config& config, const VariantParams& params) {
  Scene scene;
  if (config.sceneIsBuiltin()) {
    AtriumParams ap = config.sceneParams;
    if (params.lightCount) ap.lightCount = *params.lightCount;
    if (params.triangleScale) ap.triangleScale = *params.triangleScale;
    scene = makeAtrium(ap);
  } else if (config.sceneIsHardCase()) {
    scene = makeBuiltinScene(config.scene);
  } else {
    if (!std::filesystem::exists(config.scene)) {
      std::string hint =
          config.scene.find("ponza") != std::string::npos
              ? "; fetch it with scripts/fetch-sponza.sh (needs internet) or point \"scene\" at your copy"
              : "; check the path (relative paths resolve against the config's directory)";
      throw InputError(config.sourceName + ": scene: \"" + config.scene + "\" does not exist" + hint);
    }
    scene = loadGltf(config.scene);
  }
  applySceneOverrides(config, scene);
  AutoRequest request;
  request.camera = config.camera.autoFrame;
  if (!config.sceneIsBuiltin()) request.lightCount = params.lightCount;  // the atrium draws its own
  for (const std::string& line : completeScene(scene, request)) std::fprintf(stderr, "%s\n", line.c_str());
  return scene;
}

EffectsRequest effectsRequestFor(const Config& config) {
  EffectsRequest request;
  if (!config.effects.empty()) request.add(EffectSource::Config, config.sourceName, config.effects);
  return request;
}

RenderSettings renderSettingsFor(const VariantParams& p, const EffectsRequest& effects) {
  if (p.maxLightsPerTile != gpu::kMaxLightsPerTile)
    throw InputError("max_lights_per_tile=" + std::to_string(p.maxLightsPerTile) +
                     ": the thesis's tile lists hold 32 (one 32-bit visibility word per pixel); for more lights "
                     "a tile without a cap set light_lists=bitmask or light_lists=zbin");
  RenderSettings s;
  s.width = p.resolution[0];
  s.height = p.resolution[1];
  s.tileSize = p.tileSize;
  s.lightCulling = p.lightCulling;
  s.aabb = p.aabb;
  s.effects = effects;
  if (!p.effects.is_null()) s.effects.add(EffectSource::Config, "the variant's params.effects", p.effects);
  s.backend = p.backend;
  s.normals = p.normalCulling;
  s.worldPos = p.worldPos;
  s.rangeTest = p.rangeTest;
  s.depthSlices = p.depthSlices;
  s.lightLists = p.lightLists;
  s.tMin = p.tMin;
  s.primary = p.primary;
  s.raster3dThreadBox = p.r3dThreadBox;
  s.raster3dListPerTile = p.r3dListPerTile;
  s.raster3dFrustum = p.r3dFrustum;
  s.raster3dMinFrustum = p.r3dMinFrustum;
  s.raster3dEarlyZ = p.r3dEarlyZ;
  s.bvhWidth = p.bvhWidth;
  s.aa = p.aa;
  s.shading = p.shading;
  s.projection = p.projection;
  return s;
}

const Scene& SceneCache::get(const Config& config, const VariantParams& params) {
  auto key = std::make_tuple(params.lightCount.value_or(0), params.triangleScale.value_or(0.0));
  auto it = scenes_.find(key);
  if (it == scenes_.end()) it = scenes_.emplace(key, std::make_unique<Scene>(sceneForVariant(config, params))).first;
  return *it->second;
}

}  // namespace hb

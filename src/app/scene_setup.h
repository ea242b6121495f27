// From a config and a variant to what the renderer needs: the scene (with the config's lights
// and camera, and the atrium's light count and triangle scale) and the render settings.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <tuple>

#include "config/config.h"
#include "frame/renderer.h"
#include "scene/scene.h"

namespace hb {

// The config's scene for this variant. Throws InputError (a missing glTF names the file and, for
// Sponza, how to fetch it).
Scene sceneForVariant(const Config& config, const VariantParams& params);

// Applies the config's camera and light overrides to a loaded scene.
void applySceneOverrides(const Config& config, Scene& scene);

// The config's "effects" as the request layer above the scene's own (plan/effects.h).
EffectsRequest effectsRequestFor(const Config& config);

RenderSettings renderSettingsFor(const VariantParams& params, const EffectsRequest& effects);

// Builds each distinct scene once (the atrium at ×16 takes seconds).
class SceneCache {
 public:
  const Scene& get(const Config& config, const VariantParams& params);

 private:
  std::map<std::tuple<uint32_t, double>, std::unique_ptr<Scene>> scenes_;
};

}  // namespace hb

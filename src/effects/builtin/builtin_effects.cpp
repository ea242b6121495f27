// The built-in effects, in the order reports list them: one line per effect (its folder holds the
// rest: docs/contributing.md "Adding an effect or a pass").
#include "effects/ambient_occlusion/ao_effect.h"
#include "effects/environment_light/env_effect.h"
#include "effects/indirect/indirect_effect.h"
#include "effects/shadows/shadows_effect.h"
#include "plan/effects.h"

namespace hb {

std::vector<const EffectDef*> builtinEffects() {
  return {
      &shadowsEffect(),
      &ambientOcclusionEffect(),
      &indirectEffect(),
      &environmentLightEffect(),
  };
}

}  // namespace hb

// Direct environment light traced by layered depth maps (Aalund, Frisvad, Bærentzen 2015, Fig. 1
// right and Fig. 11): the light of the scene's environment (scene.h Environment) that reaches each
// visible point, (1/π)∫ L(ω) V(x, ω) cos θ dω per colour channel, which a Lambertian surface of
// albedo a reflects as a times it. It is ambient occlusion's integral with the environment's
// radiance in it (with a uniform environment c it equals c·AO), computed by the same pass
// (effects/ambient_occlusion/ao_pass.h with an environment).
// Value: false | true (the defaults below) | an object of these settings, each optional:
//   method          "ldm" (the N LDM directions, each weighted by the environment along it)
//                   | "raytraced" (the same N directions through the ray tracer: differs from
//                     ldm by the LDM approximation alone)
//                   | "reference" (cosine-weighted Monte Carlo, `samples` stratified rays, each
//                     weighted by the environment: the converged answer)
//   directions, ldm_resolution, bias, ldm_list, ldm_build, samples: as ambient_occlusion's.
// It acts when the scene has an environment; the frame then adds albedo·(1 − metallic)·E.
#pragma once
#include "effects/ambient_occlusion/ao_effect.h"
#include "plan/effect.h"

namespace hb {

// The settings of a value that passed validation, in ambient occlusion's form (no d_max: the
// environment is light from infinitely far). Precondition: called for.
AoSettings environmentSettingsOf(const nlohmann::json& value);

const EffectDef& environmentLightEffect();
void reportEnvironmentLight(EffectReport& report);                    // env_report.cpp
std::string environmentTableMarkdown(const nlohmann::json& results);  // env_report.cpp

}  // namespace hb

// Ambient occlusion (Aalund, Frisvad, Bærentzen 2015, Sect. 3.3): how much of the sky's ambient
// light (scene.h Ambient) reaches each visible point, AO(x) = (1/π)∫ V(x, ω) cos θ dω.
// Value: false | true (the defaults below) | an object of these settings, each optional:
//   method          "ldm" (layered depth maps along N deterministic directions, Eq. 2)
//                   | "raytraced" (the same N directions, positions and normals through the
//                     ray tracer: differs from ldm by the LDM approximation alone)
//                   | "reference" (cosine-weighted Monte Carlo, `samples` stratified rays: the
//                     converged answer, which differs from raytraced by the direction count)
//   directions      N, the LDMs (each traced both ways), 1..2048             default 64
//   ldm_resolution  R: each map is R×R over the scene's bounding sphere, 8..4096  default 128
//   d_max           obscurance: occluders farther than this (m) do not count; null = none
//   bias            scale of the derived slope-scaled LDM bias (ao.glsl.inc), > 0   default 1
//   ldm_list        how the lists are built: "max64" (64-bit atomicMax insertion) | "cas" (the
//                   paper's: 32-bit links swung by compare-and-swap) | "sbuffer" (count, scan,
//                   fill, sort each range: exact allocation, deterministic words)  default max64
//   ldm_build       "hardware" (one instanced draw over the N maps) | "3dr" (compute: one
//                   thread per (triangle, map), orthographic 3D edge functions) default hardware
//   samples         reference rays per pixel, a square 16..65536                  default 1024
//   steps           hbao samples per screen direction, gtao per side of a slice  default 32
// It acts when the scene has an ambient term; the frame then composes direct + ambient·AO.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "plan/effect.h"
#include "plan/ldm_settings.h"

namespace hb {

enum class AoMethod : uint32_t { Ldm = 0, RayTraced = 1, Reference = 2, Hbao = 3, Gtao = 4 };

// The analysis frame's converged reference: this many stratified cosine-weighted rays a pixel,
// whatever `samples` the run's own method uses (a cheaper reference run is measured against it).
inline constexpr uint32_t kAoReferenceSamples = 1024;
const char* toString(AoMethod m);

struct AoSettings {
  AoMethod method = AoMethod::Ldm;
  uint32_t directions = 64;
  uint32_t ldmResolution = 128;
  std::optional<double> dMax;
  double bias = 1.0;
  LdmList ldmList = LdmList::Max64;
  LdmBuildMethod ldmBuild = LdmBuildMethod::Hardware;
  uint32_t samples = kAoReferenceSamples;
  uint32_t steps = 32;
  nlohmann::json toJson() const;
  // Whether this is the analysis frame's own reference (method reference at kAoReferenceSamples):
  // then its error against the reference is 0 by definition.
  bool isTheReference() const { return method == AoMethod::Reference && samples == kAoReferenceSamples; }
};

// The settings of a value that passed validation (true: the defaults). Precondition: called for.
AoSettings aoSettingsOf(const nlohmann::json& value);

const EffectDef& ambientOcclusionEffect();
void reportAmbientOcclusion(EffectReport& report);  // ao_report.cpp

// The settings the LDM effects share (ambient occlusion, environment light, indirect light),
// read where `value` has them: ldm_list and ldm_build; readLdmSettings adds the maps' directions
// (1..2048), ldm_resolution (8..4096) and bias (> 0) into a settings struct with those fields; and
// samples (a square 16..65536: the strata are side x side).
void readLdmListAndBuild(const nlohmann::ordered_json& value, const json_reader::Where& where, LdmList& list,
                         LdmBuildMethod& build);
template <typename LdmSettings>
void readLdmSettings(const nlohmann::ordered_json& value, const json_reader::Where& where, LdmSettings& s) {
  using namespace json_reader;
  if (value.contains("directions"))
    s.directions = uint32_t(readInt(value["directions"], where.key("directions"), 1, 2048));
  if (value.contains("ldm_resolution"))
    s.ldmResolution = uint32_t(readInt(value["ldm_resolution"], where.key("ldm_resolution"), 8, 4096));
  if (value.contains("bias")) s.bias = readNumber(value["bias"], where.key("bias"), 0.0, 1e6, true);
  readLdmListAndBuild(value, where, s.ldmList, s.ldmBuild);
}
// The LDM settings' schema entries (EffectDef::settings): ldm_list and ldm_build the same for every
// LDM effect; the maps' resolution and bias as ambient occlusion and environment light word them.
extern const EffectSetting kLdmListSetting, kLdmBuildSetting, kLdmResolutionSetting, kLdmBiasSetting;
void readSquareSamples(const nlohmann::ordered_json& value, const json_reader::Where& where, uint32_t& samples);

}  // namespace hb

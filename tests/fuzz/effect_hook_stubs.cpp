// The fuzz targets link the effects' schemas (src/effects/<name>/*_effect.cpp: what the config
// parser and the glTF loader validate against), not the frame: an effect's frame hooks (its part,
// report and table, which need the GPU code) are never called when a config or a scene is parsed.
// These stand in for them at link time and abort if anything ever calls one. A new effect adds
// its hooks here (docs/contributing.md "Adding an effect or a pass").
#include <cstdlib>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "plan/effect.h"

namespace hb {

namespace {
[[noreturn]] void notInAFuzzTarget() { std::abort(); }
}  // namespace

std::unique_ptr<FramePart> buildShadows(FrameBuilder&) { notInAFuzzTarget(); }
void reportShadows(EffectReport&) { notInAFuzzTarget(); }
void captureShadowsReference(const Renderer&, ReferenceFrame&) { notInAFuzzTarget(); }
std::unique_ptr<FramePart> buildAmbientOcclusion(FrameBuilder&) { notInAFuzzTarget(); }
void reportAmbientOcclusion(EffectReport&) { notInAFuzzTarget(); }
std::string aoTableMarkdown(const nlohmann::json&) { notInAFuzzTarget(); }
std::unique_ptr<FramePart> buildIndirect(FrameBuilder&) { notInAFuzzTarget(); }
void reportIndirect(EffectReport&) { notInAFuzzTarget(); }
std::string indirectTableMarkdown(const nlohmann::json&) { notInAFuzzTarget(); }
std::unique_ptr<FramePart> buildEnvironmentLight(FrameBuilder&) { notInAFuzzTarget(); }
void reportEnvironmentLight(EffectReport&) { notInAFuzzTarget(); }
std::string environmentTableMarkdown(const nlohmann::json&) { notInAFuzzTarget(); }

}  // namespace hb

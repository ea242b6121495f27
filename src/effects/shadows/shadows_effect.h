// Ray-traced hard shadows (the thesis): for each pixel and each light of its tile, one shadow ray
// culled by N·L (and optionally the range test), traced against the scene's BLAS/TLAS.
// Value: true | false.
#pragma once
#include "plan/effect.h"

namespace hb {

const EffectDef& shadowsEffect();

// Its hooks (shadows_report.cpp).
void reportShadows(EffectReport& report);
void captureShadowsReference(const Renderer& renderer, ReferenceFrame& reference);

}  // namespace hb

// Packing scene lights and the camera into the GPU structs of shaders/shared/gpu_types.h.
#pragma once
#include <vector>

#include "scene/scene.h"
#include "shared/gpu_types.h"

namespace hb {

// World-space lights as the shaders read them; tanOuter follows cull_ref.h's spotConeTan
// (-1: no cone test).
std::vector<gpu::GpuLight> packLights(const std::vector<Light>& lights);

gpu::FrameConstants makeFrameConstants(const glm::mat4& view, const glm::mat4& proj, uint32_t width, uint32_t height,
                                       uint32_t tileSize, uint32_t lightCount, float tMinPerMetre = 0.0f);
// tMinPerMetre goes to cameraPos.w: 0 gives every shadow ray the thesis's t_min (kShadowTMin);
// kShadowTMinPerMetre gives max(kShadowTMin, kShadowTMinPerMetre · distance to the eye) (t_min=scaled).

}  // namespace hb

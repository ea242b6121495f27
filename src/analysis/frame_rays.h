// The rays a frame traced, as ray files (reference/ray_file.h; `render --rays-out`,
// docs/usage.md "The frame's own rays"): rebuilt on the CPU from an analysis frame's readbacks, in
// float, by the shaders' own formulas, so that another tracer (or `raybench`) traces the frame's
// work and nothing else.
//  shadow  the thesis's shadow rays after culling: per pixel (row-major) the lights of its list walk
//          whose ray the shadow pass traced (its "traced" bits: after the range, N·L and
//          cast-shadows tests), in walk order; origin the stored world position, direction the unit
//          vector to the light (or the directional light's), t in [shadowTMin, distance]
//          (shaders/shadows/raybench_common.glsl.inc, which re-traces the same rays). Any hit.
//  ao      the ray-traced AO's rays (shaders/ambient_occlusion/ao_common.glsl.inc): per pixel with
//          a surface and a normal, each of the N directions v_i with n·v_i != 0, turned into n's
//          hemisphere, t in [shadowTMin, d_max or kDirectionalTMax]. The AO pass reads the surface
//          the shadow pass stores (surface.glsl.inc, the frame's one normal and position method),
//          so its rays are rebuilt from the shadow pass's readback. Any hit.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "frame/renderer.h"
#include "reference/ray_file.h"
#include "shared/gpu_types.h"

namespace hb {

struct FrameRays {
  std::vector<RayRecord> rays;
  std::vector<uint32_t> pixel;  // per ray: the pixel (row-major) that traced it
  std::vector<float> weight;    // ao: per ray |n·v_i| (the ray's weight in the pixel's AO); else empty
};

// The frame's shadow rays. shadows: readShadows() with its traced words; lights: packLights of the
// scene's lights (scene order; culling.indices name them); cameraPos: the frame constants' (w: the
// t_min scale). Preconditions: shadows.traced and culling are of the same analysis frame,
// width × height pixels, tiles of tileSize.
FrameRays frameShadowRays(const ShadowReadback& shadows, const CullingReadback& culling,
                          const std::vector<gpu::GpuLight>& lights, const glm::vec4& cameraPos, uint32_t width,
                          uint32_t height, uint32_t tileSize);

// The frame's ray-traced AO rays. directions: the AO pass's (ldmDirections(N) as float); dMax:
// ao.d_max (0: kDirectionalTMax). Pixels are those the shadow pass stored a position for (w = 1)
// with a nonzero normal.
FrameRays frameAoRays(const ShadowReadback& shadows, const std::vector<glm::vec3>& directions,
                      const glm::vec4& cameraPos, float dMax, uint32_t width, uint32_t height);

}  // namespace hb

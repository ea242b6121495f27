// The ray sets `hybridbench rays export` writes from any scene and view (docs/usage.md "Ray files"),
// made on the CPU from the scene's camera and the double-precision BVH (bvh.h), so another tracer can
// trace exactly the rays we trace:
//  camera  one ray a pixel centre, row-major, from the eye (closest hit);
//  ao      from each camera ray's hit, offset `offset` along the geometric normal turned towards the
//          eye, a cosine-distributed direction about that normal, t <= t_max (closest hit, as the
//          public figures were traced; any hit is the AO pass's own query);
//  shadow  from each camera ray's hit, offset the same way, towards a point light, t up to the light.
// AO and shadow sets hold one ray per camera hit, in the camera rays' order (sky pixels have none).
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "reference/bvh.h"
#include "reference/ray_file.h"
#include "scene/scene.h"

namespace hb {

// The view the rays come from: the camera's pose and field of view, and the image's size.
struct RayView {
  glm::dvec3 eye, forward, right, up;  // right and up scaled by tan(xfov / 2) and tan(yfov / 2)
  uint32_t width = 0, height = 0;
};
RayView rayViewOf(const Camera& camera, uint32_t width, uint32_t height);
nlohmann::json toJson(const RayView& view, const Camera& camera);

// One ray a pixel centre (as shaders/peaks/peaks_rays.glsl.inc's camera rays), unit directions,
// t in [0, 1e30].
std::vector<RayRecord> cameraRays(const RayView& view);

// Where each ray of `rays` first meets the scene (closest hit, the double BVH): t and triangle
// (the BVH's input index), t < 0 for a miss. Runs on every core.
struct RayHits {
  std::vector<double> t;
  std::vector<uint32_t> triangle;
  size_t hits() const;
};
RayHits traceOnCpu(const Bvh& bvh, const std::vector<RayRecord>& rays, bool anyHit = false);

struct SecondaryParams {
  double offset = 1e-3;             // along the geometric normal (scene units)
  double tMax = 1.0;                // ao: the rays' length
  uint64_t seed = 1;                // ao: the directions' seed (a hash of seed and the ray's index: any thread order)
  glm::dvec3 light{0.0, 6.0, 0.0};  // shadow: the point light
};
std::vector<RayRecord> aoRays(const Bvh& bvh, const std::vector<RayRecord>& camera, const RayHits& hits,
                              const SecondaryParams& params);
std::vector<RayRecord> shadowRays(const Bvh& bvh, const std::vector<RayRecord>& camera, const RayHits& hits,
                                  const SecondaryParams& params);

}  // namespace hb

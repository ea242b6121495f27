#version 460
// The device's ray rates through our own BVH (backend=compute; peaks_rays.glsl.inc,
// compute_occluded.glsl.inc), 8x8 rays a group. MODE 0 also writes each camera ray's t for MODE 3.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8, local_size_y = 8) in;
#include "shared/gpu_types.h"
#include "peaks_rays.glsl.inc"

#define HB_BVH_NODES_BINDING HB_PEAKS_BVH_NODES
#define HB_BVH_TRIANGLES_BINDING HB_PEAKS_BVH_TRIANGLES
#define HB_BVH_STACK_ID 1
#define HB_BVH_THREADS 64u
#define HB_BVH_CLOSEST  // closest hits: the stack keeps entry distances
#include "compute_occluded.glsl.inc"
layout(push_constant) uniform Size { uvec2 size; };

void main() {
  const uvec2 id = gl_GlobalInvocationID.xy;
  if (id.x >= size.x || id.y >= size.y) return;
  const uint index = id.y * size.x + id.x;
  vec3 origin, dir;
  if (!peaksRay(id, size, origin, dir)) {
    missedOut[index] = 1u;
    return;
  }
  bool hit;
  if (MODE >= 2u) {
    hit = occluded(origin, dir, 0.0, p.forward.w);
  } else {
    float t;
    uint tri;
    hit = closestHitBvh(origin, dir, 0.0, p.forward.w, t, tri);
    if (MODE == 0u) cameraHitT[index] = hit ? t : -1.0;
  }
  missedOut[index] = hit ? 0u : 1u;
}

#version 460
// primary=raycast through the ray-tracing pipeline (devices without ray query: the H100);
// primary_raycast.glsl.inc. The closest-hit shader returns (t, id); the miss shader leaves ~0.
#extension GL_GOOGLE_include_directive : require
#include "primary_raycast_pipeline.glsl.inc"
layout(location = 0) rayPayloadEXT uvec2 hitTId;  // (t bits, id); id ~0 = missed

void main() {
  const uvec2 p = gl_LaunchIDEXT.xy;
  hitTId = uvec2(0u, 0xFFFFFFFFu);
  if (!cameraHasRay(r3.projection, r3, float(p.x), float(p.y))) {  // paraboloid: outside the disk
    storeHit(p, false, 0.0, 0u);
    return;
  }
  traceRayEXT(tlas, gl_RayFlagsOpaqueEXT, 0xFF, 0, 0, 0, cameraRayOrigin(r3.projection, r3, float(p.x), float(p.y)), r3.depth.x,
              cameraRayDir(r3.projection, r3, float(p.x), float(p.y)), r3.depth.y, 0);
  storeHit(p, hitTId.y != 0xFFFFFFFFu, uintBitsToFloat(hitTId.x), hitTId.y);
}

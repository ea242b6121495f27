#version 460
// Pass 2 (thesis 4.2.3): the four side planes of every tile's frustum in view space, once per
// camera/resolution/tile size. Mirrors cull_ref.h tileCornerRays/tileSidePlanes op for op.
#extension GL_GOOGLE_include_directive : require
#include "shared/gpu_types.h"

layout(local_size_x = 64) in;

layout(set = 0, binding = 0) uniform Frame { FrameConstants frame; };
layout(set = 0, binding = 2) writeonly buffer Frustums { TileFrustum frustums[]; };

vec3 cornerRay(uvec2 px) {
  // ndc = 2*(px/W) - 1; view = (ndc.x/A, ndc.y/B, -1): a point on the plane z = -1.
  vec2 ndc = 2.0 * (vec2(px) / frame.extent.xy) - 1.0;
  return vec3(ndc.x / frame.proj[0][0], ndc.y / frame.proj[1][1], -1.0);
}

void main() {
  uint tile = gl_GlobalInvocationID.x;
  if (tile >= frame.tileCountX * frame.tileCountY) return;
  uvec2 t = uvec2(tile % frame.tileCountX, tile / frame.tileCountX);
  uvec2 size = uvec2(frame.extent.xy);
  uvec2 p0 = t * frame.tileSize;
  uvec2 p1 = min(p0 + frame.tileSize, size);  // partial edge tiles are clamped to the image
  vec3 c0 = cornerRay(uvec2(p0.x, p0.y));     // top-left
  vec3 c1 = cornerRay(uvec2(p1.x, p0.y));     // top-right
  vec3 c2 = cornerRay(uvec2(p1.x, p1.y));     // bottom-right
  vec3 c3 = cornerRay(uvec2(p0.x, p1.y));     // bottom-left
  // Planes through the eye (origin): normals point into the tile (A > 0, B < 0), d = 0.
  frustums[tile].planes[0] = vec4(normalize(cross(c3, c0)), 0.0);  // left
  frustums[tile].planes[1] = vec4(normalize(cross(c0, c1)), 0.0);  // top
  frustums[tile].planes[2] = vec4(normalize(cross(c1, c2)), 0.0);  // right
  frustums[tile].planes[3] = vec4(normalize(cross(c2, c3)), 0.0);  // bottom
}

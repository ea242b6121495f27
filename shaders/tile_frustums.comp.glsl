#version 460
// Pass 2 (thesis 4.2.3): the four side planes of every tile's frustum in view space, once per
// camera/resolution/tile size (culling.glsl.inc mirrors cull_ref.h op for op).
#extension GL_GOOGLE_include_directive : require
#include "culling.glsl.inc"

layout(local_size_x = 64) in;

uniform Frame { FrameConstants frame; };
writeonly buffer Frustums { TileFrustum frustums[]; };

void main() {
  uint tile = gl_GlobalInvocationID.x;
  if (tile >= frame.tileCountX * frame.tileCountY) return;
  uvec2 t = uvec2(tile % frame.tileCountX, tile / frame.tileCountX);
  frustums[tile] = computeTileFrustum(t, frame.tileSize, uvec2(frame.extent.xy), frame.proj[0][0], frame.proj[1][1]);
}

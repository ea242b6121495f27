#version 460
// The resolve into the frame's depth image itself, where no pass draws against it (the depth is
// an R32F colour image, sampled as the D32 one would be): no copy. 8 x 8 pixels a workgroup, the
// image's tiles.
#extension GL_GOOGLE_include_directive : require
#include "raster3d_resolve.glsl.inc"

layout(local_size_x = 8, local_size_y = 8) in;
layout(r32f) uniform writeonly image2D depthImage;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= r3.width || p.y >= r3.height) return;
  imageStore(depthImage, ivec2(p), vec4(resolvedDepth(p.y * r3.width + p.x)));
}

#version 460
// The resolve into a buffer of floats, which the frame copies into its depth image (a D32 image
// cannot be a storage image) where a pass draws against the depth: forward shading, MSAA.
#extension GL_GOOGLE_include_directive : require
#include "raster3d_resolve.glsl.inc"

layout(local_size_x = 64) in;
writeonly buffer Depth { float depth[]; };

void main() {
  const uint pixel = gl_GlobalInvocationID.x;
  if (pixel >= r3.width * r3.height) return;
  depth[pixel] = resolvedDepth(pixel);
}

#version 460
// Pass 4, compute backend (backend=compute: our BVH and traversal, compute_occluded.glsl.inc; the
// rest as the ray-query backend, shadows_rayquery.comp.glsl): one workgroup per tile; the tile's depth plus the border
// the normal method needs live in group shared memory. Normals only use samples along the two
// axes, so the border is a cross (no corners): TILE^2 + 4*2*TILE texels, which is at most two
// fetches per thread for every tile size (8: 128 = 2*64).
#extension GL_GOOGLE_include_directive : require
#include "shadows_constants.glsl.inc"
layout(local_size_x_id = 0, local_size_y_id = 0) in;

#include "shadows_common.glsl.inc"

#include "depth_texel.glsl.inc"
#define HB_BVH_STACK_ID 6
#define HB_BVH_THREADS (TILE * TILE)

const int kBorder = 2;  // improved normals read +-2 samples per axis
const int kSide = int(TILE) + 2 * kBorder;
shared float sDepth[kSide * kSide];

ivec2 gTileOrigin;

float depthAt(ivec2 p) {
  ivec2 q = p - gTileOrigin + ivec2(kBorder);
  return sDepth[q.y * kSide + q.x];
}

#include "compute_occluded.glsl.inc"

void main() {
  gTileOrigin = ivec2(gl_WorkGroupID.xy * TILE);
  ivec2 local = ivec2(gl_LocalInvocationID.xy);
  // Fetch 1: the thread's own texel.
  sDepth[(local.y + kBorder) * kSide + local.x + kBorder] = fetchDepth(gTileOrigin + local);
  // Fetch 2: one texel of the four 2-wide border strips (left, right, top, bottom), 8*TILE texels.
  int i = int(gl_LocalInvocationIndex);
  if (i < 8 * int(TILE)) {
    int strip = i / (2 * int(TILE)), j = i % (2 * int(TILE));
    int along = j / 2, across = j % 2;
    ivec2 q;  // shared-memory coordinates
    if (strip == 0) q = ivec2(across, along + kBorder);                           // left
    else if (strip == 1) q = ivec2(int(TILE) + kBorder + across, along + kBorder);  // right
    else if (strip == 2) q = ivec2(along + kBorder, across);                      // top
    else q = ivec2(along + kBorder, int(TILE) + kBorder + across);                 // bottom
    sDepth[q.y * kSide + q.x] = fetchDepth(gTileOrigin + q - ivec2(kBorder));
  }
  barrier();
  shadePixel(gTileOrigin + local);
}

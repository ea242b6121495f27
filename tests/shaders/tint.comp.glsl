#version 460
// The test-only "tint" effect (tests/tint_effect_test.cpp): adds redPerLight x (the pixel's tile
// light-list length) to the red channel of the shaded image, in place.
layout(local_size_x = 8, local_size_y = 8) in;

layout(rgba16f) uniform image2D color;
layout(std430) readonly buffer Grid { uint grid[]; };  // 4 words per tile: offset, count, ...

layout(push_constant) uniform Push {
  uvec2 size;
  uint tileSize;
  uint tilesX;
  float redPerLight;
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(p, pc.size))) return;
  const uint tile = (p.y / pc.tileSize) * pc.tilesX + p.x / pc.tileSize;
  vec4 c = imageLoad(color, ivec2(p));
  c.r += pc.redPerLight * float(grid[4u * tile + 1u]);
  imageStore(color, ivec2(p), c);
}

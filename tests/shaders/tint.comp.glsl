#version 460
// The test-only "tint" effect (tests/tint_effect_test.cpp): writes each pixel's tile light-list
// length as its term, which shading adds as red (the effect's declared ShadingTerm scales it).
layout(local_size_x = 8, local_size_y = 8) in;

writeonly buffer Term { float term[]; };               // one float per pixel
readonly buffer Grid { uint grid[]; };                  // 4 words per tile: offset, count, ...

layout(push_constant) uniform Push {
  uvec2 size;
  uint tileSize;
  uint tilesX;
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(p, pc.size))) return;
  const uint tile = (p.y / pc.tileSize) * pc.tilesX + p.x / pc.tileSize;
  term[p.y * pc.size.x + p.x] = float(grid[4u * tile + 1u]);
}

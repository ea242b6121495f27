#version 460
// tests/raybench_gpu_test.cpp: overwrites the world positions the shadow pass stored for some pixels
// (its rgba32f positions image, which the ray benchmark reads its ray origins from) with given points.
layout(local_size_x = 64) in;

struct MovedPoint {
  uvec4 pixel;    // xy: the pixel
  vec4 position;  // what its stored position becomes (w = 1: a surface)
};

layout(rgba32f) uniform writeonly image2D positions;
layout(std430) readonly buffer Moves { MovedPoint moves[]; };

layout(push_constant) uniform Push { uint count; } pc;

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  imageStore(positions, ivec2(moves[i].pixel.xy), moves[i].position);
}

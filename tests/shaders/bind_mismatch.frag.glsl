#version 460
// tests/descriptor_binder_gpu_test.cpp: Params as a storage buffer (bind_mismatch.vert: a uniform one).
readonly buffer Params { vec4 colors[]; };
layout(location = 0) out vec4 color;

void main() { color = colors[0]; }

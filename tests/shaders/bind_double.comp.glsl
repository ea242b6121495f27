#version 460
// A test's pass (tests/descriptor_binder_gpu_test.cpp): doubles Source into Doubled, so that a set
// laid out from the shader's reflection and written by name is seen to work. No binding numbers.
layout(local_size_x = 64) in;

readonly buffer Source { uint source[]; };
writeonly buffer Doubled { uint doubled[]; };

void main() {
  doubled[gl_GlobalInvocationID.x] = 2u * source[gl_GlobalInvocationID.x];
}

#version 460
// tests/descriptor_binder_gpu_test.cpp: declares Params as a uniform buffer where
// bind_mismatch.frag declares it as a storage buffer, which one pipeline cannot have.
uniform Params { vec4 offset; };

void main() { gl_Position = offset; }

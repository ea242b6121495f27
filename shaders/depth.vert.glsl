#version 460
// Depth prepass (thesis 4.1): positions only, reverse-Z projection, no fragment shader.
layout(location = 0) in vec3 inPosition;

layout(push_constant) uniform Push {
  mat4 modelViewProj;
} pc;

void main() {
  gl_Position = pc.modelViewProj * vec4(inPosition, 1.0);
}

#version 460
// Shading pass (thesis 4.4): the scene drawn again against the prepass depth (EQUAL).
#extension GL_GOOGLE_include_directive : require
#include "shared/gpu_types.h"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;
layout(push_constant) uniform Push { DrawConstants draw; };

layout(location = 0) out vec3 outWorldPos;
layout(location = 1) out vec3 outNormal;
layout(location = 2) out vec2 outUv;

invariant gl_Position;  // must match depth.vert.glsl bit for bit

void main() {
  gl_Position = draw.modelViewProj * vec4(inPosition, 1.0);
  outWorldPos = (draw.model * vec4(inPosition, 1.0)).xyz;
  outNormal = transpose(inverse(mat3(draw.model))) * inNormal;
  outUv = inUv;
}

#version 460
// Depth prepass (thesis 4.1): positions only, reverse-Z projection, no fragment shader.
// gl_Position is invariant so the shading pass's EQUAL depth test sees bit-identical depths.
#extension GL_GOOGLE_include_directive : require
#include "shared/gpu_types.h"

layout(location = 0) in vec3 inPosition;
layout(push_constant) uniform Push { DrawConstants draw; };

invariant gl_Position;

void main() { gl_Position = draw.modelViewProj * vec4(inPosition, 1.0); }

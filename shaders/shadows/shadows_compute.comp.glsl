#version 460
// Pass 4, compute backend (backend=compute): our BVH and traversal; the rest as the ray-query
// backend (shadows_tile.glsl.inc).
#extension GL_GOOGLE_include_directive : require
#define SHADOWS_COMPUTE 1
#include "shadows_tile.glsl.inc"

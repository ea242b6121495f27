#version 460
// Pass 4, ray-query backend (thesis 4.3): the device's ray query; the rest as the compute backend
// (shadows_tile.glsl.inc).
#extension GL_GOOGLE_include_directive : require
#define SHADOWS_COMPUTE 0
#include "shadows_tile.glsl.inc"

#version 460
#extension GL_GOOGLE_include_directive : require
// The gather of analysis frames: photon_splat_gather.glsl.inc with its work counted per tile.
#define HB_SPLAT_COUNT 1
#include "photon_splat_gather.glsl.inc"

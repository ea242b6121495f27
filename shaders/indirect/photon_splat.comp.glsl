#version 460
#extension GL_GOOGLE_include_directive : require
// The timed gather of the compute splat: photon_splat_gather.glsl.inc, without the work counts.
#include "photon_splat_gather.glsl.inc"

#version 460
// Indirect light, miss: nothing hit (id ~0), for closest-hit and occlusion rays alike.
#extension GL_EXT_ray_tracing : require

layout(location = 0) rayPayloadInEXT uvec2 hitTId;

void main() { hitTId.y = 0xFFFFFFFFu; }

#version 460
// primary=raycast, miss: the payload keeps "nothing" (id ~0), set by the ray-generation shader.
#extension GL_EXT_ray_tracing : require
layout(location = 0) rayPayloadInEXT uvec2 hitTId;
void main() {}

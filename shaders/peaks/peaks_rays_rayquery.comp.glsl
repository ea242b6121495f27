#version 460
// The device's ray rates through ray query (peaks_rays.glsl.inc), 8x8 rays a group.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_query : require
layout(local_size_x = 8, local_size_y = 8) in;
#define HB_PEAKS_COMPUTE_MAIN
#include "peaks_rays.glsl.inc"

uniform accelerationStructureEXT tlas;
// MODE 4: the triangle each file ray meets (its draw-order id; 0xFFFFFFFF: missed), for raybench's
// --hits-out and its comparison of triangles. idBase[instance] is the first entry of that
// instance's geometries in idBase, idBase[that + geometry] the id of the geometry's first triangle
// (gpu_scene.h triangleIdBase).
layout(std430) buffer HitIds { uint hitIdOut[]; };
layout(std430) readonly buffer IdBase { uint idBase[]; };
bool peaksHit(vec3 origin, vec3 dir, float tMin, float tMax, uint index) {
  rayQueryEXT rq;
  rayQueryInitializeEXT(rq, tlas, gl_RayFlagsOpaqueEXT | (anyHitMode() ? gl_RayFlagsTerminateOnFirstHitEXT : 0u), 0xFF,
                        origin, tMin, dir, tMax);
  while (rayQueryProceedEXT(rq)) {
  }
  const bool hit = rayQueryGetIntersectionTypeEXT(rq, true) != gl_RayQueryCommittedIntersectionNoneEXT;
  if (MODE == 4u) {
    cameraHitT[index] = hit ? rayQueryGetIntersectionTEXT(rq, true) : -1.0;
    hitIdOut[index] = hit ? idBase[idBase[uint(rayQueryGetIntersectionInstanceCustomIndexEXT(rq, true))] +
                                   uint(rayQueryGetIntersectionGeometryIndexEXT(rq, true))] +
                                uint(rayQueryGetIntersectionPrimitiveIndexEXT(rq, true))
                          : 0xFFFFFFFFu;
  }
  return hit;
}

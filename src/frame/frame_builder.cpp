#include "frame/frame_builder.h"

#include "base/errors.h"

namespace hb {

SurfaceInputs surfaceInputs(const FrameBuilder& f) {
  SurfaceInputs s;
  s.hitIds = f.resources.buffer(res::kVisibility);
  s.hitRays = f.resources.buffer(res::kVisibilityRays);
  s.hitTriangles = f.resources.buffer(res::kVisibilityTriangles);
  s.worldPos = f.settings.worldPos;
  s.normals = s.hitIds ? NormalCulling::Geometric : NormalCulling::Improved;
  if (s.worldPos == WorldPosMethod::Hit && !s.hitIds)
    throw InputError(
        "world_pos=hit needs the triangle ids of a computed primary visibility: set primary=3dr, "
        "3dr-binned, 2dr or raycast");
  return s;
}

}  // namespace hb

// The oracle (docs/methods/thesis.md "The oracle"): the fewest shadow rays any correct culler could trace.
#pragma once
#include <cstdint>
#include <vector>

#include "analysis/reference_surface.h"
#include "scene/scene.h"

namespace hb {

// docs/methods/thesis.md "The oracle": per non-sky pixel the lights that cast shadows, whose range contains the
// point (point, spot), whose outer cone contains it (spot) and that the true geometric normal
// faces (N·L > 0). No culler that is correct can trace fewer rays. Unmatched pixels have no true
// normal: the N·L test is skipped there (their count is an upper bound) and they are counted.
struct OracleRays {
  uint64_t total = 0;
  std::vector<uint32_t> perPixel;
  uint64_t pixelsWithoutNormal = 0;
};
OracleRays oracleRays(const Scene& scene, const ReferenceSurface& surface);
// oracle / traced (1 when nothing was traced). <= 1 for a conservative variant. It can exceed 1
// when a variant drops rays the oracle needs: tile overflow (droppedByOverflow), culling false
// negatives, or a reconstructed normal that wrongly faces away from a light the true normal faces
// (naive normals at depth discontinuities), and on unmatched pixels (see OracleRays).
double rayEfficiency(uint64_t oracle, uint64_t traced);

}  // namespace hb

// The procedural atrium: the embedded default scene, shaped like Crytek Sponza (the thesis's
// scene) so that the thesis experiments run anywhere with no download.
//
// At triangleScale 1: about 262k triangles (Sponza: 262,267), 29.8 m (x) x 12.4 m (y, up) x
// 18.3 m (z), 25 materials. A floor, outer walls, an open courtyard along x framed by two storeys
// of columns and arches, galleries behind them, hanging curtains, vases with plants, lion-head
// ornaments and strings of small beads round the arches (most of the sub-3-pixel triangles).
// Every part but the curtains (open sheets, double-sided fabric) is a union of closed solids; no
// triangle is degenerate; winding is counter-clockwise around outward normals. One mesh per part
// (8 meshes), one identity instance each. About 38 % of the triangles in the default camera's
// view at 1920x1080 fit in 3 x 3 pixels.
#pragma once
#include <cstdint>

#include "scene/scene.h"

namespace hb {

struct AtriumParams {
  // Multiplies the triangle count roughly linearly (x1 ~262k, x4 ~1M, x16 ~4M) by tessellating
  // every curved part more finely (sqrt(triangleScale) more divisions in each direction).
  // Must be in [0.25, 64].
  double triangleScale = 1.0;
  uint32_t lightCount = 10;  // point lights, in the courtyard and both galleries; <= 4096
  uint32_t seed = 1;         // the lights' positions, colours, intensities and ranges
  // Explicit ranges drawn from [lightRangeMin, lightRangeMax] m for every light (none from eq.
  // 4.1) when lightRangeMax > 0; the default 0 keeps the mix above (3..12 m, two in ten from
  // eq. 4.1). Positions, colours and intensities stay the same for a given seed.
  double lightRangeMin = 0.0, lightRangeMax = 0.0;
};

// Builds the atrium. Deterministic: the same params give bit-identical scenes on every compiler
// (no std:: distributions). cameras[0] is the fixed central camera: in the courtyard at 1.8 m,
// looking along +x between the colonnades, yfov 60 degrees, znear 0.1, zfar 100.
// Throws InputError when triangleScale or lightCount is outside the range above.
Scene makeAtrium(const AtriumParams& params = {});

}  // namespace hb

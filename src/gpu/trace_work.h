// The work our compute traversal (shaders/compute_occluded.glsl.inc) does for a set of rays,
// replayed on the CPU over the same uploaded layout (trace_bvh.h) in the same order and in float:
// the nodes it fetches, the boxes it tests, the triangles it tests, the stack entries it pushes and
// the bytes it reads. raybench prints it beside the rates, so a rate can be read against the
// traffic it needs (docs/rays.md "What bounds the traversal"). The counts are the traversal's, not
// a timing: the float replay can differ from the GPU's at a rounding tie, which moves a count by a
// node or a triangle, never the totals' order of magnitude.
#pragma once
#include <cstdint>
#include <vector>

#include "gpu/trace_bvh.h"
#include "reference/ray_file.h"

namespace hb {

struct TraceWork {
  uint64_t rays = 0;
  uint64_t nodes = 0;      // nodes fetched (a wide node whole: width / 4 groups of 128 B)
  uint64_t boxes = 0;      // child boxes tested (a wide node's slots, a binary node's two children)
  uint64_t triangles = 0;  // triangles tested
  uint64_t pushes = 0;     // stack entries written
  uint64_t maxStack = 0;   // the deepest stack of any ray
  uint64_t nodeBytes = 0, triangleBytes = 0;
  uint64_t bytes() const { return nodeBytes + triangleBytes; }
  double perRay(uint64_t v) const { return rays ? double(v) / double(rays) : 0.0; }
};

// anyHit: the occlusion query (the first hit ends the ray); else the closest hit. With `events`
// (width 4 or 8), each ray's fetches in order: a wide node's code (< kWideLeaf), or kWideLeaf | the
// triangle slot for a triangle tested (raybench's loads ceiling replays them on the GPU); and with
// `missed`, whether each ray ended without a hit.
TraceWork traceWork(const TraceBvhLayout& layout, const std::vector<RayRecord>& rays, bool anyHit,
                    std::vector<std::vector<uint32_t>>* events = nullptr, std::vector<uint8_t>* missed = nullptr);

}  // namespace hb

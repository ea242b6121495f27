// Optimizing a built binary BVH by reinsertion (Bittner, Hapala and Havran 2013, "Fast
// insertion-based optimization of bounding volume hierarchies"): an interior node whose box is
// large against its children's is taken out, its sibling takes its parent's place, and its two
// children are put back, each beside the node where it adds the least surface area to the tree (a
// branch-and-bound search from the root). Each child is put back greedily, one after the other, so a
// move can also raise the cost; a round that gains less than the stop (or loses) ends the rounds,
// and its tree is the one kept. Leaves keep their triangles; the tree is laid out again depth first,
// so its ranges and order stay valid.
#pragma once
#include <cstdint>

#include "gpu/primary_bvh.h"

namespace hb {

struct BvhReinsertStats {
  uint32_t rounds = 0;      // rounds run (each moves the batch of nodes it picked)
  uint64_t reinserted = 0;  // interior nodes taken out and their children put back
  double costBefore = 0.0;  // the binary tree's SAH cost (root area 1, a node 1, a triangle 1)
  double costAfter = 0.0;
  uint32_t depthBefore = 0, depthAfter = 0;
};

// Rounds of reinsertion: each picks the nodes of the largest inefficiency (Bittner's product of
// the node's area, its area over its children's mean and over their smaller), 1 % of the candidates
// (interior nodes but the root and its children, not picked before: by index, and a reinsertion
// reuses the indices it frees), and reinserts them one after another. Stops after `maxRounds`
// or when a round lowers the cost by less than 0.01 %. Deterministic: the same tree in gives the
// same tree out (one thread).
BvhReinsertStats reinsertBvh(PrimaryBvh& tree, uint32_t maxRounds);

// The SAH cost of a binary tree as reinsertBvh counts it.
double bvhSahCost(const PrimaryBvh& tree);

}  // namespace hb

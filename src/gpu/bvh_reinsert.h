// Optimizing a built binary BVH by reinsertion (Bittner, Hapala and Havran 2013, "Fast
// insertion-based optimization of bounding volume hierarchies"): a node whose box is large against
// its children's is taken out with its subtree, its sibling takes its parent's place, and the
// subtree is put back beside the node where it adds the least surface area to the tree (a
// branch-and-bound search from the root). Each move keeps or lowers the tree's SAH cost. Leaves keep
// their triangles; the tree is laid out again depth first, so its ranges and order stay valid.
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
// the node's area, its area over its children's mean and over their smaller), 1 % of the nodes,
// and reinserts them one after another; a node is picked in one round only. Stops after `maxRounds`
// or when a round lowers the cost by less than 0.01 %. Deterministic: the same tree in gives the
// same tree out (one thread).
BvhReinsertStats reinsertBvh(PrimaryBvh& tree, uint32_t maxRounds);

// The SAH cost of a binary tree as reinsertBvh counts it.
double bvhSahCost(const PrimaryBvh& tree);

}  // namespace hb

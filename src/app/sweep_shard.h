// `sweep --shard K/N` (docs/fleet.md): the K-th of N parts of a config's variants, so that a study
// can be split over the machines of a fleet and merged afterwards (`hybridbench merge`). The parts
// are a pure function of the config and the scene's light count: every machine computes the same
// partition without talking to the others.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "config/config.h"

namespace hb {

// K/N with 0 <= K < N (0-based, as Slurm's array index and Kubernetes' JOB_COMPLETION_INDEX).
struct ShardSpec {
  size_t index = 0;
  size_t count = 0;  // 0: no --shard, every variant
  bool active() const { return count > 0; }
};

// "K/N" → spec. Throws InputError naming --shard and the accepted form for anything else (a
// missing slash, signs, N = 0, K >= N, numbers beyond 1,000,000).
ShardSpec parseShard(const std::string& text);

// The estimated cost of running one variant, in arbitrary units; only ratios matter:
//   pixels × (lights + 1) × reference_ssaa × Π weight(effect on)
// pixels and lights scale the analysis frame's CPU references (every (pixel, light) pair is
// culled and traced exactly) and the frames themselves; lights + 1 because a frame without lights
// still costs. reference_ssaa multiplies the pixels of the reference frame the variant needs.
// effects: the config's "effects" with the variant's params.effects over it; an effect other than
// shadows that is on multiplies by kEffectCostWeight (its exact reference traces many rays a pixel).
// The weight is a coarse assumption, not a measurement: a wrong one unbalances the parts, never
// changes a result, and `sweep --dry-run --shard K/N` prints every part's estimate.
// sceneLights: the light count of a variant without params.lightCount (the config's scene).
double variantCost(const VariantParams& params, const nlohmann::json& configEffects, size_t sceneLights);
constexpr double kEffectCostWeight = 4.0;

struct ShardPlan {
  std::vector<std::vector<size_t>> parts;  // variant positions (config order) of each part
  std::vector<double> partCosts;           // the sum of each part's variant costs
  std::vector<double> variantCosts;        // per variant, config order
};

// Longest processing time first: variants by cost, largest first (ties: config order), each to the
// part with the least cost so far (ties: the lowest part). Each part lists its variants in config
// order. Deterministic: the same costs always give the same parts. parts >= 1.
ShardPlan partitionByCost(const std::vector<double>& costs, size_t parts);

// The plan of `variants` (expandVariants of config) into count parts.
ShardPlan planShards(const Config& config, const std::vector<Variant>& variants, size_t sceneLights, size_t count);

// results.json context.shard: {"index", "count", "variants" (this part's names, config order),
// "cost" (this part's estimate), "part_costs" (every part's), "cost_model"}.
nlohmann::json shardContext(const ShardSpec& spec, const ShardPlan& plan, const std::vector<Variant>& variants);

}  // namespace hb

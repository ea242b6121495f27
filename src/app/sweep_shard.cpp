#include "app/sweep_shard.h"

#include <algorithm>
#include <numeric>

#include "base/errors.h"

namespace hb {

namespace {

// A whole number of at most 7 digits (a fleet of a million machines is plenty), else -1.
long parseShardNumber(const std::string& s) {
  if (s.empty() || s.size() > 7 || s.find_first_not_of("0123456789") != std::string::npos) return -1;
  return std::stol(s);
}

}  // namespace

ShardSpec parseShard(const std::string& text) {
  const size_t slash = text.find('/');
  const long k = slash == std::string::npos ? -1 : parseShardNumber(text.substr(0, slash));
  const long n = slash == std::string::npos ? -1 : parseShardNumber(text.substr(slash + 1));
  if (k < 0 || n < 1)
    throw InputError("--shard " + text +
                     ": expected K/N, the K-th of N parts counted from 0 (e.g. --shard 0/4 ... --shard 3/4)");
  if (k >= n)
    throw InputError("--shard " + text + ": part " + std::to_string(k) + " of " + std::to_string(n) +
                     " does not exist; parts are counted from 0, so K runs from 0 to " + std::to_string(n - 1));
  return ShardSpec{size_t(k), size_t(n)};
}

double variantCost(const VariantParams& params, const nlohmann::json& configEffects, size_t sceneLights) {
  const double pixels = double(params.resolution[0]) * double(params.resolution[1]);
  const double lights = double(params.lightCount ? *params.lightCount : sceneLights) + 1.0;
  nlohmann::json effects = configEffects.is_object() ? configEffects : nlohmann::json::object();
  if (params.effects.is_object())
    for (const auto& [key, value] : params.effects.items()) effects[key] = value;
  double weight = 1.0;
  for (const auto& [key, value] : effects.items())
    if (key != "shadows" && !(value.is_boolean() && !value.get<bool>()) && !value.is_null())
      weight *= kEffectCostWeight;
  return pixels * lights * double(std::max(params.referenceSsaa, 1u)) * weight;
}

ShardPlan partitionByCost(const std::vector<double>& costs, size_t parts) {
  HB_ASSERT(parts >= 1);
  ShardPlan plan;
  plan.parts.resize(parts);
  plan.partCosts.assign(parts, 0.0);
  plan.variantCosts = costs;
  std::vector<size_t> order(costs.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return costs[a] > costs[b]; });
  for (size_t k : order) {
    // min_element returns the first of equal loads: the lowest part.
    const size_t p = size_t(std::min_element(plan.partCosts.begin(), plan.partCosts.end()) - plan.partCosts.begin());
    plan.parts[p].push_back(k);
    plan.partCosts[p] += costs[k];
  }
  for (std::vector<size_t>& part : plan.parts) std::sort(part.begin(), part.end());
  return plan;
}

ShardPlan planShards(const Config& config, const std::vector<Variant>& variants, size_t sceneLights, size_t count) {
  std::vector<double> costs;
  for (const Variant& v : variants) costs.push_back(variantCost(v.params, config.effects, sceneLights));
  return partitionByCost(costs, count);
}

nlohmann::json shardContext(const ShardSpec& spec, const ShardPlan& plan, const std::vector<Variant>& variants) {
  nlohmann::json names = nlohmann::json::array();
  for (size_t k : plan.parts[spec.index]) names.push_back(variants[k].name);
  return {{"index", spec.index},
          {"count", spec.count},
          {"variants", names},
          {"cost", plan.partCosts[spec.index]},
          {"part_costs", plan.partCosts},
          {"cost_model",
           "pixels x (lights + 1) x reference_ssaa x 4 per effect other than shadows; longest first into the "
           "cheapest part (src/app/sweep_shard.h)"}};
}

}  // namespace hb

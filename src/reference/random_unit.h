// A uniformly distributed unit vector (normalised Gaussian triple), for the references' tests.
#pragma once

#include <glm/glm.hpp>
#include <random>

namespace hb {

inline glm::dvec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  return glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
}

}  // namespace hb

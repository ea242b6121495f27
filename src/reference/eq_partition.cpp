#include "reference/eq_partition.h"
#include "base/numbers.h"

#include <cmath>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <string>

#include "base/errors.h"

namespace hb {

namespace {

// Area of the cap of colatitude s on the unit sphere: 2π(1 - cos s) = 4π sin²(s/2); the sine
// form has no cancellation near the pole.
double capArea(double s) {
  const double h = std::sin(0.5 * s);
  return 4.0 * kPi * h * h;
}

// Inverse of capArea on [0, 4π]: s = 2 asin(√(area/4π)) (Leopardi's sradius_of_cap, dim 2).
double capColatitude(double area) { return 2.0 * std::asin(std::sqrt(std::min(1.0, area / (4.0 * kPi)))); }

// The toolbox's circle_offset (without the extra twist), in turns: half the difference of one
// sector of each ring lines the sectors up, gcd/(2 m m') then turns by half the smallest angle
// between centres of the two rings.
double circleOffset(uint32_t mTop, uint32_t mBottom) {
  const double a = mTop, b = mBottom;
  return (1.0 / b - 1.0 / a) / 2.0 + double(std::gcd(mTop, mBottom)) / (2.0 * a * b);
}

glm::dvec3 unitFromPolar(double colatitude, double longitude) {
  const double s = std::sin(colatitude);
  return {s * std::cos(longitude), s * std::sin(longitude), std::cos(colatitude)};
}

}  // namespace

EqPartition eqPartition(uint32_t regions) {
  HB_ASSERT(regions >= 1);
  EqPartition p;
  p.regions = regions;
  if (regions == 1) {
    p.ringCounts = {1};
    p.capColatitudes = {kPi};
    return p;
  }
  const double regionArea = 4.0 * kPi / regions;
  const double polar = regions == 2 ? kPi / 2.0 : capColatitude(regionArea);
  uint32_t collars = 0;
  if (regions > 2) {
    const double idealAngle = std::sqrt(regionArea);  // side of a square of one region's area
    collars = uint32_t(std::max(1.0, std::round((kPi - 2.0 * polar) / idealAngle)));
  }
  // Ideal (real) region counts of `collars` collars of equal angular width, caps included.
  std::vector<double> ideal(collars + 2, 1.0);
  const double width = collars > 0 ? (kPi - 2.0 * polar) / collars : 0.0;
  for (uint32_t c = 1; c <= collars; ++c)
    ideal[c] = (capArea(polar + c * width) - capArea(polar + (c - 1) * width)) / regionArea;
  // Round one after another, carrying what rounding took or gave (std::round: half away from
  // zero, as MATLAB's round). The caps' ideal counts are exactly 1 and the total is M, so the
  // counts sum to M.
  double carried = 0.0;
  for (double r : ideal) {
    const double n = std::round(r + carried);
    HB_ASSERT(n >= 1.0);
    carried += r - n;
    p.ringCounts.push_back(uint32_t(n));
  }
  HB_ASSERT(std::accumulate(p.ringCounts.begin(), p.ringCounts.end(), uint64_t(0)) == regions);
  // Collar boundaries at the caps holding the cumulative counts exactly.
  p.capColatitudes.push_back(polar);
  uint64_t cumulative = 1;
  for (uint32_t c = 1; c <= collars; ++c) {
    cumulative += p.ringCounts[c];
    p.capColatitudes.push_back(capColatitude(double(cumulative) * regionArea));
  }
  p.capColatitudes.push_back(kPi);
  return p;
}

std::vector<EqRegion> eqRegions(uint32_t regions) {
  const EqPartition p = eqPartition(regions);
  const uint32_t zones = uint32_t(p.ringCounts.size());
  std::vector<EqRegion> out;
  out.reserve(regions);
  out.push_back({0, 0.0, p.capColatitudes[0], 0.0, 2.0 * kPi, 0.0, 0.0});
  if (zones == 1) return out;
  double offset = 0.0;  // turns
  for (uint32_t z = 1; z + 1 < zones; ++z) {
    const uint32_t m = p.ringCounts[z];
    const double top = p.capColatitudes[z - 1], bottom = p.capColatitudes[z];
    for (uint32_t k = 0; k < m; ++k) {
      double lo = double(k) / m + offset;
      lo -= std::floor(lo);
      double centre = lo + 0.5 / m;
      if (centre >= 1.0) centre -= 1.0;
      out.push_back(
          {z, top, bottom, 2.0 * kPi * lo, 2.0 * kPi * (lo + 1.0 / m), 0.5 * (top + bottom), 2.0 * kPi * centre});
    }
    offset += circleOffset(m, p.ringCounts[z + 1]);
    offset -= std::floor(offset);
  }
  out.push_back({zones - 1, p.capColatitudes[zones - 2], kPi, 0.0, 2.0 * kPi, kPi, 0.0});
  return out;
}

std::vector<glm::dvec3> eqPointSet(uint32_t regions) {
  const uint32_t lastZone = uint32_t(eqPartition(regions).ringCounts.size()) - 1;
  std::vector<glm::dvec3> points;
  points.reserve(regions);
  for (const EqRegion& r : eqRegions(regions)) {
    if (r.zone == 0)
      points.emplace_back(0.0, 0.0, 1.0);  // the poles exactly (sin π is 1.2e-16, not 0)
    else if (r.zone == lastZone)
      points.emplace_back(0.0, 0.0, -1.0);
    else
      points.push_back(unitFromPolar(r.colatitude, r.longitude));
  }
  return points;
}

std::vector<glm::dvec3> ldmDirections(uint32_t n) {
  const auto refuse = [n](const std::string& why) {
    return std::invalid_argument("ldmDirections(" + std::to_string(n) + "): " + why);
  };
  if (n == 0 || n > 0x7fffffffu) throw refuse("n must be in [1, 2^31 - 1]");
  const uint32_t m = 2 * n;
  const std::vector<EqRegion> regions = eqRegions(m);
  const std::vector<glm::dvec3> points = eqPointSet(m);
  // A collar centre is on the equator when its collar is symmetric about it. Cap colatitudes come
  // from asin to a few ulps (~1e-15); any other collar's centre lies half a collar width, at least
  // ~√(4π/M)/2 > 1e-4 for M < 1e9, from the equator. 1e-12 separates the two with room to spare.
  constexpr double kEquatorTol = 1e-12;
  std::vector<glm::dvec3> dirs;
  std::vector<const EqRegion*> equator;
  for (size_t i = 0; i < regions.size(); ++i) {
    const double c = regions[i].colatitude;
    if (c < kPi / 2.0 - kEquatorTol)
      dirs.push_back(points[i]);
    else if (std::abs(c - kPi / 2.0) <= kEquatorTol)
      equator.push_back(&regions[i]);
  }
  if (equator.size() % 2 != 0) throw refuse("the equator ring of EQ(2, 2n) has an odd count");
  // Centres k and k + m/2 of the ring are antipodal; keep the one with the smaller longitude.
  const size_t half = equator.size() / 2;
  for (size_t k = 0; k < half; ++k) {
    const double a = equator[k]->longitude, b = equator[k + half]->longitude;
    const double lon = std::min(a, b);
    dirs.emplace_back(std::cos(lon), std::sin(lon), 0.0);
  }
  if (dirs.size() != n)
    throw refuse("EQ(2, 2n) is not symmetric about the equator (" + std::to_string(dirs.size()) +
                 " directions, not n)");
  // A component that is 0 in exact arithmetic can come out as a rounding: sin or cos of a multiple
  // of π/2 in double, and the collars' offsets rounded as they add up. For n = 1..2048 and the
  // larger n the test takes, these are at most 8.9e-16 (n = 295), and every true component is at
  // least 1.0e-6 (LdmDirections.NoComponentIsTheRoundingOfZero; n = 256's fifth direction had
  // y = 2.1e-17). Left so, a direction lies a rounding off an axis plane, and n · v ≠ 0 in float
  // for a wall on that plane: a split photon then runs along the wall (the floor of a box), and
  // from an x1 that a driver rounded outside the wall it left the closed box (on the H200). A
  // component under 1e-14 is written 0. That moves the unit direction by less than 1e-14, under
  // 1e-6 of a float ulp of its largest component (at least 1/√3, so an ulp of at least 6e-8): no
  // other float component changes. Beyond the tested n nothing is shown either way, and zeroing a
  // true component that small would change no float component but itself.
  constexpr double kRoundingOfZero = 1e-14;
  for (glm::dvec3& d : dirs)
    for (int k = 0; k < 3; ++k)
      if (std::abs(d[k]) < kRoundingOfZero) d[k] = 0.0;
  return dirs;
}

}  // namespace hb

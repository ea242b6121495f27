// Leopardi's recursive zonal equal-area partition of the 2-sphere, EQ(2, M) (P. Leopardi, "A
// partition of the unit sphere into regions of equal area and small diameter", ETNA 25, 2006;
// the algorithm of his MATLAB toolbox eq_sphere_partitions: eq_caps, eq_regions,
// eq_point_set_polar, without the experimental 'extra' offsets), and the LDM directions drawn
// from it (LDM paper, Section 3.2).
//
// Coordinates: colatitude θ from the +z pole, longitude φ from +x towards +y;
// the point (θ, φ) is (sin θ cos φ, sin θ sin φ, cos θ).
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace hb {

// The zones of EQ(2, M), from the north pole down: the polar caps and the collars between them.
//  ringCounts[z]     regions in zone z: [1, m_1, ..., m_k, 1] (M = 1: [1]; M = 2: [1, 1]);
//                    they sum to M.
//  capColatitudes[z] colatitude of the cap that zone z closes, increasing, the last one π:
//                    the cap of colatitude s has area 4π sin²(s/2) = (regions in zones 0..z)·4π/M.
// Construction (toolbox): the polar cap has area 4π/M (θ_c = 2 asin(√(1/M)), π/2 for M = 2);
// k = max(1, round((π - 2θ_c)/√(4π/M))) collars of equal angular width would hold a real number
// of regions each; those are rounded one after another, carrying the remainder (round half
// away from zero, as MATLAB's round), and the collar boundaries moved to the colatitudes whose
// caps hold the cumulative counts exactly. Precondition: M >= 1.
struct EqPartition {
  uint32_t regions = 0;
  std::vector<uint32_t> ringCounts;
  std::vector<double> capColatitudes;
};
EqPartition eqPartition(uint32_t regions);

// One region of EQ(2, M): colatitudes [top, bottom], longitudes [lonLo, lonHi] (lonLo in [0, 2π),
// lonHi = lonLo + 2π/m for a collar of m regions, so it may run past 2π: read it modulo 2π;
// [0, 2π] for a cap), and its centre point (colatitude, longitude), longitude in [0, 2π).
//  Centres: the caps' are the poles. In a collar of m regions between colatitudes top and
//  bottom, region k = 0..m-1 spans longitudes from 2π(k/m + o) mod 2π onwards by 2π/m and its
//  centre sits at colatitude (top + bottom)/2, longitude 2π((k + 1/2)/m + o) mod 2π. The offset
//  o (in turns) is 0 in the first collar; after a collar of m regions followed by a zone of m'
//  it grows by (1/m' - 1/m)/2 + gcd(m, m')/(2 m m'), taken modulo 1 (the toolbox's
//  circle_offset: line the two rings' sectors up, then turn by half the smallest angle between
//  their centres).
struct EqRegion {
  uint32_t zone;
  double top, bottom;
  double lonLo, lonHi;
  double colatitude, longitude;
};
// All M regions, zone by zone from the north pole, within a zone by k.
std::vector<EqRegion> eqRegions(uint32_t regions);

// The centres of eqRegions(M) as unit vectors, in the same order. |length - 1| <= a few ulps.
std::vector<glm::dvec3> eqPointSet(uint32_t regions);

// The n directions of n LDMs: the centres of EQ(2, 2n) with z > 0 (the upper hemisphere, z the
// pole axis), and, where the middle collar straddles the equator, half of its ring: its centres
// lie on the equator (colatitude π/2 exactly, z = 0 written exactly) in antipodal pairs (k and
// k + m/2), and of each pair the one with the smaller longitude in [0, 2π) is kept (the one in
// [0, π)). No direction is the negative of another, and every direction stands for itself and
// its negative (an LDM is traced both ways), so together they cover the sphere with equal-area
// regions. Order: as eqRegions, the equator half last. A component that is 0 but for rounding
// (under 1e-14) is written 0, so no direction lies a rounding off an axis plane.
// The count is exactly n for every n in [1, 2048] (tested exhaustively) and for n = 3000, 4096,
// 8192, 16384, 65536 (tested). It holds whenever the rounded ring counts of EQ(2, 2n) are
// mirror-symmetric about the equator, which carried rounding gives unless a cumulative ideal
// count lands on exactly k + 1/2.
// Throws std::invalid_argument naming n when n == 0, n > 2^31 - 1, or the count is not n.
std::vector<glm::dvec3> ldmDirections(uint32_t n);

}  // namespace hb

#include "report/stats.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace hb {
namespace {

// Hand values below are written to 10+ significant digits; where a comparison is against such a
// rounded hand value the tolerance is half a unit of its last written digit. Where the hand value
// is exact, the tolerance is the floating-point error of the few operations that compute it.

TEST(Summarize, MatchesHandComputedStatistics) {
  // x = {2, 4, 4, 4, 5, 5, 7, 9}, n = 8, sum 40 -> mean 5.
  // Squared deviations 9,1,1,1,0,0,4,16 = 32 -> sample variance 32/7, stddev sqrt(32/7)
  // = 2.138089935299, cv = 2.138089935299 / 5 = 0.4276179870599.
  // Type 7: median h = 7 * 0.5 = 3.5 -> x[3] + 0.5 (x[4] - x[3]) = 4 + 0.5 = 4.5;
  // p95 h = 7 * 0.95 = 6.65 -> x[6] + 0.65 (x[7] - x[6]) = 7 + 0.65 * 2 = 8.3.
  const std::vector<double> x = {5, 2, 9, 4, 4, 7, 4, 5};  // unsorted on purpose
  const Summary s = summarize(x);
  EXPECT_EQ(s.n, 8u);
  EXPECT_DOUBLE_EQ(s.mean, 5.0);
  EXPECT_DOUBLE_EQ(s.median, 4.5);
  EXPECT_DOUBLE_EQ(s.min, 2.0);
  EXPECT_DOUBLE_EQ(s.max, 9.0);
  EXPECT_NEAR(s.stddev, 2.138089935299, 5e-13);
  EXPECT_NEAR(s.cv, 0.4276179870599, 5e-14);
  // 0.95 and 0.65 are not exact in binary: h and the fraction each carry <= 1 ulp, the
  // interpolation ~3 ulps of 8.3 (1.8e-15 each) -> < 1e-14.
  EXPECT_NEAR(s.p95, 8.3, 1e-14);
}

TEST(Summarize, OddCountMedianIsTheMiddleValueAndOneSampleHasNoSpread) {
  const std::vector<double> x = {3, 1, 2};
  EXPECT_DOUBLE_EQ(summarize(x).median, 2.0);
  const std::vector<double> one = {7};
  const Summary s = summarize(one);
  EXPECT_EQ(s.n, 1u);
  EXPECT_DOUBLE_EQ(s.median, 7.0);
  EXPECT_DOUBLE_EQ(s.p95, 7.0);
  EXPECT_TRUE(std::isnan(s.stddev));  // sample stddev is undefined for n = 1
  EXPECT_TRUE(std::isnan(summarize(std::vector<double>{}).median));
}

TEST(Summarize, JsonHasTheResultsFileFields) {
  const std::vector<double> x = {1, 2, 3, 4};
  const nlohmann::json j = toJson(summarize(x), x);
  for (const char* key : {"median", "mean", "stddev", "cv", "min", "max", "p95", "samples"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["samples"].size(), 4u);
  EXPECT_DOUBLE_EQ(j["median"].get<double>(), 2.5);
}

// first, first + 1, ..., last: the samples of the hand-computed examples.
std::vector<double> integers(int first, int last) {
  std::vector<double> v;
  for (int i = first; i <= last; ++i) v.push_back(i);
  return v;
}

TEST(MannWhitney, ExactPValueForSeparatedSmallSamples) {
  // a = {1,2,3}, b = {4,5,6}: U_a = 0. Of the C(6,3) = 20 equally likely splits, U = 0 and U = 9
  // are the only ones as extreme -> p = 2/20 = 0.1.
  // Normal approximation: mu = 4.5, var = 3*3*7/12 = 5.25, z = -(4.5 - 0.5)/sqrt(5.25)
  // = -1.745743121888.
  const std::vector<double> a = {1, 2, 3}, b = {4, 5, 6};
  const MannWhitney r = mannWhitneyU(a, b);
  EXPECT_TRUE(r.exact);
  EXPECT_DOUBLE_EQ(r.u, 0.0);
  EXPECT_DOUBLE_EQ(r.p, 0.1);
  EXPECT_NEAR(r.z, -1.745743121888, 5e-13);
  // Swapping the sides mirrors U (9 - 0) and z, not p.
  const MannWhitney s = mannWhitneyU(b, a);
  EXPECT_DOUBLE_EQ(s.u, 9.0);
  EXPECT_NEAR(s.z, 1.745743121888, 5e-13);
  EXPECT_DOUBLE_EQ(s.p, 0.1);
}

TEST(MannWhitney, ExactPValueUsesMidranksForTies) {
  // a = {1,2,2}, b = {2,3,4}. Pooled ranks: 1 -> 1; the three 2s -> (2+3+4)/3 = 3; 3 -> 5; 4 -> 6.
  // R_a = 1+3+3 = 7, U_a = 7 - 3*4/2 = 1, |U - 4.5| = 3.5, i.e. R <= 7 or R >= 14.
  // Splits of the rank multiset {1,3,3,3,5,6} into 3: R = 7 is {1,3,3}: C(3,2) = 3 ways;
  // R >= 14 is {3,5,6}: 3 ways; nothing else qualifies -> p = 6/20 = 0.3.
  // Normal: tie term 3^3 - 3 = 24; var = 9/12 (7 - 24/30) = 4.65; z = -3/sqrt(4.65)
  // = -1.391216687281.
  const std::vector<double> a = {1, 2, 2}, b = {2, 3, 4};
  const MannWhitney r = mannWhitneyU(a, b);
  EXPECT_DOUBLE_EQ(r.u, 1.0);
  EXPECT_DOUBLE_EQ(r.p, 0.3);
  EXPECT_NEAR(r.z, -1.391216687281, 5e-13);
}

TEST(MannWhitney, NormalApproximationAboveTheExactLimit) {
  // a = 1..10, b = 11..20: U_a = 0, mu = 50, var = 10*10*21/12 = 175,
  // z = -(50 - 0.5)/sqrt(175) = -3.741848282791, p = erfc(3.741848282791/sqrt 2)
  // = 1.826717911096e-4 (scipy.stats.mannwhitneyu(..., method="asymptotic") gives the same).
  const std::vector<double> a = integers(1, 10), b = integers(11, 20);
  const MannWhitney r = mannWhitneyU(a, b);
  EXPECT_FALSE(r.exact);
  EXPECT_DOUBLE_EQ(r.u, 0.0);
  EXPECT_NEAR(r.z, -3.741848282791, 5e-13);
  EXPECT_NEAR(r.p, 1.826717911096e-4, 5e-16);
}

TEST(MannWhitney, NormalApproximationCorrectsVarianceForTies) {
  // a = 1..9, b = 5..13 (9 each); 5..9 appear twice -> five tie pairs, tie term 5 (8 - 2) = 30.
  // Midranks: 1..4 -> 1..4; 5..9 -> 5.5, 7.5, 9.5, 11.5, 13.5; 10..13 -> 15..18.
  // R_a = 10 + 47.5 = 57.5, U_a = 57.5 - 45 = 12.5 (pair count: .5+1.5+2.5+3.5+4.5 = 12.5).
  // mu = 40.5; var = 81/12 (19 - 30/(18*17)) = 127.5882352941; z = -(28 - 0.5)/sqrt(var)
  // = -2.434598659251; p = erfc(|z|/sqrt 2) = 0.01490831505187.
  const std::vector<double> a = integers(1, 9), b = integers(5, 13);
  const MannWhitney r = mannWhitneyU(a, b);
  EXPECT_DOUBLE_EQ(r.u, 12.5);
  EXPECT_NEAR(r.z, -2.434598659251, 5e-13);
  EXPECT_NEAR(r.p, 0.01490831505187, 5e-15);
}

TEST(MannWhitney, AllTiedIsNotSignificant) {
  const std::vector<double> a(12, 1.0), b(12, 1.0);
  const MannWhitney r = mannWhitneyU(a, b);
  EXPECT_DOUBLE_EQ(r.p, 1.0);
  EXPECT_DOUBLE_EQ(r.z, 0.0);
  EXPECT_DOUBLE_EQ(r.u, 72.0);
}

TEST(NormalQuantile, InvertsTheCdf) {
  // z_{0.975} = 1.959963984540 (tables); bisection stops at a bracket of 1e-15.
  EXPECT_NEAR(normalQuantile(0.975), 1.959963984540, 5e-13);
  EXPECT_NEAR(normalQuantile(0.75), 0.6744897501961, 5e-14);
}

TEST(RatioInterval, MatchesHandComputedMosesInterval) {
  // a = {1,2,4}, b = {2,4,8}: the 9 ratios b_j/a_i sorted are .5, 1, 1, 2, 2, 2, 4, 4, 8;
  // estimate = 5th = 2.
  // alpha = 0.5: z = 0.6744897502, C = floor(9/2 - z sqrt(9*7/12)) = floor(4.5 - 1.5455) = 2
  //   -> [2nd, 8th] = [1, 4].
  // alpha = 0.05: C = floor(4.5 - 1.96 * 2.291) = 0 < 1 -> whole range [0.5, 8].
  // Each bound is exp(log b - log a): <= 1 ulp per log, 0.5 for the difference (|D| <= ln 8),
  // 1 for exp -> relative error <= (2 * 2.08 + 1.5) * 1.1e-16 < 1e-15.
  const std::vector<double> a = {1, 2, 4}, b = {2, 4, 8};
  const RatioInterval half = ratioInterval(a, b, 0.5);
  EXPECT_NEAR(half.estimate, 2.0, 2e-15);
  EXPECT_NEAR(half.low, 1.0, 1e-15);
  EXPECT_NEAR(half.high, 4.0, 4e-15);
  const RatioInterval wide = ratioInterval(a, b, 0.05);
  EXPECT_NEAR(wide.low, 0.5, 5e-16);
  EXPECT_NEAR(wide.high, 8.0, 8e-15);
}

TEST(RatioInterval, SelectionEqualsSortingAllPairwiseDifferences) {
  // The bisection must return exactly the k-th of the materialised differences (same doubles).
  std::mt19937 rng(20240611u);
  auto uniform = [&] { return static_cast<double>(rng()) / 4294967296.0; };
  std::vector<double> a, b;
  for (int i = 0; i < 37; ++i) a.push_back(9.0 + uniform());
  for (int i = 0; i < 41; ++i) b.push_back(9.3 + uniform());
  a[3] = a[5];  // ties inside a side
  b[7] = a[1];  // and across the sides
  std::vector<double> la, lb, d;
  for (double v : a) la.push_back(std::log(v));
  for (double v : b) lb.push_back(std::log(v));
  for (double y : lb)
    for (double x : la) d.push_back(y - x);
  std::sort(d.begin(), d.end());
  const double alpha = 0.05;
  const double n = static_cast<double>(d.size());
  const size_t c =
      static_cast<size_t>(std::floor(n / 2 - normalQuantile(1 - alpha / 2) * std::sqrt(n * (37 + 41 + 1) / 12)));
  ASSERT_GE(c, 1u);
  const RatioInterval r = ratioInterval(a, b, alpha);
  EXPECT_EQ(r.low, std::exp(d[c - 1]));
  EXPECT_EQ(r.high, std::exp(d[d.size() - c]));
  ASSERT_EQ(d.size() % 2, 1u);  // 37 * 41 = 1517 pairs: the estimate is the middle one
  EXPECT_EQ(r.estimate, std::exp(d[d.size() / 2]));
  EXPECT_LT(r.low, r.estimate);
  EXPECT_LT(r.estimate, r.high);
}

TEST(RatioInterval, NonPositiveSamplesGiveNaN) {
  const std::vector<double> a = {1, 0}, b = {1, 2};
  EXPECT_TRUE(std::isnan(ratioInterval(a, b, 0.05).low));
}

}  // namespace
}  // namespace hb

namespace hb {
namespace {

// Student's t against its closed forms: df = 1 (Cauchy) P(|T| >= t) = 1 - (2/pi) atan t, df = 2
// P = 1 - t / sqrt(2 + t^2), and a large df the normal's 2 (1 - Phi(t)) (the t's excess over the
// normal is about (t^3 + t) phi(t) / (4 df): under 1e-5 at df = 1e6 for these t). 1e-12: the
// continued fraction stops at a relative 1e-14, and the closed forms round to a few ulps.
TEST(StudentT, TwoSidedPMatchesClosedFormsAndTheNormalLimit) {
  for (double t : {0.0, 0.3, 1.0, 2.0, 5.0, 30.0}) {
    EXPECT_NEAR(studentTwoSidedP(t, 1), 1 - 2 / M_PI * std::atan(t), 1e-12) << t;
    EXPECT_NEAR(studentTwoSidedP(-t, 2), 1 - t / std::sqrt(2 + t * t), 1e-12) << t;
    EXPECT_NEAR(studentTwoSidedP(t, 1e6), 2 * (1 - normalCdf(t)), 1e-5) << t;
  }
  EXPECT_EQ(studentTwoSidedP(std::numeric_limits<double>::infinity(), 3), 0);
  EXPECT_TRUE(std::isnan(studentTwoSidedP(1, 0)));
}

// Welch's test on two small samples, by hand: a = {1, 2, 3} (mean 2, s^2 1), b = {4, 6} (mean 5,
// s^2 2): t = -3 / sqrt(1/3 + 1) = -2.598, df = (4/3)^2 / ((1/3)^2 / 2 + 1^2 / 1) = 1.6842.
TEST(StudentT, WelchsTestOfTwoSmallSamples) {
  const std::vector<double> a = {1, 2, 3}, b = {4, 6};
  const WelchT w = welchT(a, b);
  EXPECT_NEAR(w.t, -3 / std::sqrt(4.0 / 3), 1e-12);
  EXPECT_NEAR(w.df, (16.0 / 9) / (1.0 / 18 + 1), 1e-12);
  // P(|T| >= t) falls as df grows, so at df = 1.68 it lies between the closed forms at 1 and 2.
  const double t = std::abs(w.t);
  EXPECT_LT(w.p, 1 - 2 / M_PI * std::atan(t));
  EXPECT_GT(w.p, 1 - t / std::sqrt(2 + t * t));
  const std::vector<double> flat = {1, 1}, other = {2, 2};
  EXPECT_EQ(welchT(flat, other).p, 0);
  EXPECT_EQ(welchT(flat, flat).p, 1);
}

}  // namespace
}  // namespace hb

// Statistics for timing samples: summaries (median, mean, sample stddev, CV, p95), the two-sided
// Mann-Whitney U test, and a distribution-free confidence interval for the ratio B/A of two
// runs' typical times. Everything is deterministic (no random resampling).
#pragma once
#include <cstddef>
#include <span>

#include <nlohmann/json.hpp>

namespace hb {

struct Summary {
  size_t n = 0;
  double median = 0, mean = 0, stddev = 0, cv = 0, min = 0, max = 0, p95 = 0;
};

// Quantile q in [0, 1] of `sorted` (ascending, non-empty), Hyndman-Fan type 7 (numpy's and R's
// default): h = (n-1)q, x[floor h] + (h - floor h)(x[floor h + 1] - x[floor h]), 0-based.
double quantileSorted(std::span<const double> sorted, double q);

// Median, mean, sample standard deviation (divisor n-1), cv = stddev/mean, min, max and p95
// (type 7, above). n = 0 gives all NaN; n = 1 gives stddev and cv NaN (undefined with one
// sample); mean 0 gives cv NaN. NaN is written to JSON as null.
Summary summarize(std::span<const double> samples);

// The results-file form (docs/results-format.md): {median, mean, stddev, cv, min, max, p95,
// samples: [...]}.
nlohmann::json toJson(const Summary& s, std::span<const double> samples);

// Two-sided Mann-Whitney U test of a against b.
// u: the U statistic of a = #pairs (a_i > b_j) + 0.5 #pairs (a_i == b_j); u near |a||b|/2 when
// neither side tends to be larger. z: normal approximation with tie-corrected variance and a 0.5
// continuity correction towards the mean, positive when a tends to be larger (0 when every value
// is tied). p: exact permutation p-value (midranks, so ties are handled) when both sides have at
// most kExactMannWhitneyMaxN samples (at most C(16,8) = 12870 splits to enumerate), otherwise
// 2(1 - Phi(|z|)). Precondition: both sides non-empty (else p = 1, u = z = 0).
constexpr size_t kExactMannWhitneyMaxN = 8;
struct MannWhitney {
  double u = 0, z = 0, p = 1;
  bool exact = false;
};
MannWhitney mannWhitneyU(std::span<const double> a, std::span<const double> b);

// Confidence interval for the ratio of B's typical value to A's, Hodges-Lehmann style (Moses'
// interval, Hollander & Wolfe "Nonparametric Statistical Methods" 4.3): with D the n_a*n_b
// pairwise differences log b_j - log a_i sorted ascending and
// C = floor(n_a n_b / 2 - z_{1-alpha/2} sqrt(n_a n_b (n_a + n_b + 1) / 12)),
// the interval is [exp D_(C), exp D_(n_a n_b + 1 - C)] (1-based), the shift estimate exp(median D).
// It inverts the Mann-Whitney test (no tie correction), so it excludes 1 roughly when that test
// is significant; when C < 1 the interval is the whole range of pairwise ratios.
// Preconditions: every sample > 0 and both sides non-empty; otherwise all fields are NaN.
// Each order statistic costs at most 64 bisection steps of O(n_a + n_b) (plus the sorts); the
// n_a*n_b differences are never materialised, so 10^4 samples a side is cheap.
struct RatioInterval {
  double estimate = 0, low = 0, high = 0;
};
RatioInterval ratioInterval(std::span<const double> a, std::span<const double> b, double alpha);

// The two-sided p-value of Student's t statistic with df degrees of freedom (df > 0, not
// necessarily whole: Welch's): P(|T| >= |t|) = I_{df/(df+t^2)}(df/2, 1/2), the regularized
// incomplete beta function (DLMF 8.17.2, 8.17.22: its continued fraction, by Lentz's method, to a
// relative 1e-14). NaN for a NaN t or df <= 0; 0 for an infinite t.
double studentTwoSidedP(double t, double df);

// Welch's two-sample t-test of a against b (each >= 2 values): t = (mean a - mean b) /
// sqrt(s_a^2/n_a + s_b^2/n_b) with the Welch-Satterthwaite degrees of freedom, and its two-sided
// p. Both variances 0: p = 0 when the means differ, 1 when they do not.
struct WelchT {
  double t = 0, df = 0, p = 1;
};
WelchT welchT(std::span<const double> a, std::span<const double> b);

// Standard normal CDF and its inverse (bisection on erfc, |error| < 1e-12 in p).
double normalCdf(double z);
double normalQuantile(double p);

}  // namespace hb

#include "report/stats.h"
#include "base/numbers.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <utility>
#include <vector>

namespace hb {

namespace {

std::vector<double> sortedCopy(std::span<const double> v) {
  std::vector<double> s(v.begin(), v.end());
  std::sort(s.begin(), s.end());
  return s;
}

// Midranks (1-based; tied values share the mean of their ranks), doubled so that they are
// integers: a tie group at sorted positions [i, j) gets rank (i + 1 + j) / 2, doubled i + 1 + j.
// Also returns sum over tie groups of (t^3 - t), the tie term of the U variance.
struct Ranks {
  std::vector<int64_t> doubledRank;  // indexed like the pooled input
  double tieTerm = 0;
};

Ranks midranks(const std::vector<double>& pooled) {
  std::vector<size_t> order(pooled.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](size_t x, size_t y) { return pooled[x] < pooled[y]; });
  Ranks r;
  r.doubledRank.resize(pooled.size());
  for (size_t i = 0; i < order.size();) {
    size_t j = i + 1;
    while (j < order.size() && pooled[order[j]] == pooled[order[i]]) ++j;
    for (size_t k = i; k < j; ++k) r.doubledRank[order[k]] = static_cast<int64_t>(i + 1 + j);
    const double t = static_cast<double>(j - i);
    r.tieTerm += t * t * t - t;
    i = j;
  }
  return r;
}

// Exact two-sided permutation p-value: every way of choosing which na of the N pooled values
// belong to a is equally likely under H0; p = share of splits whose |2U - na nb| is at least the
// observed one. Doubled ranks keep everything in integers, so there is no rounding to tie-break.
double exactMannWhitneyP(const std::vector<int64_t>& doubledRank, size_t na, int64_t observedDev2) {
  const size_t n = doubledRank.size();
  const int64_t nb = static_cast<int64_t>(n - na);
  const int64_t naI = static_cast<int64_t>(na);
  uint64_t extreme = 0, total = 0;
  for (uint32_t mask = 0; mask < (1u << n); ++mask) {
    if (static_cast<size_t>(std::popcount(mask)) != na) continue;
    int64_t rankSum2 = 0;
    for (size_t i = 0; i < n; ++i)
      if (mask & (1u << i)) rankSum2 += doubledRank[i];
    // 2U = 2R - na(na+1); deviation from the mean, doubled: 2U - na nb.
    const int64_t dev2 = std::abs(rankSum2 - naI * (naI + 1) - naI * nb);
    ++total;
    if (dev2 >= observedDev2) ++extreme;
  }
  return static_cast<double>(extreme) / static_cast<double>(total);
}

// Doubles mapped to unsigned integers in the same order, so that bisection over the key visits
// every double between two bounds in at most 64 steps.
uint64_t orderKey(double x) {
  const uint64_t u = std::bit_cast<uint64_t>(x);
  return (u >> 63) ? ~u : (u | (uint64_t{1} << 63));
}
double fromOrderKey(uint64_t k) { return std::bit_cast<double>((k >> 63) ? (k & ~(uint64_t{1} << 63)) : ~k); }

// Number of pairs (i, j) with fl(y_j - x_i) <= t, x and y ascending. fl(y - x) is monotone in
// both arguments (rounding is monotone), so the per-i count only grows with i: two pointers.
uint64_t countDifferencesAtMost(const std::vector<double>& x, const std::vector<double>& y, double t) {
  uint64_t count = 0;
  size_t j = 0;
  for (double xi : x) {
    while (j < y.size() && y[j] - xi <= t) ++j;
    count += j;
  }
  return count;
}

// k-th smallest (1-based) of the pairwise differences fl(y_j - x_i). Bisection over orderKey
// keeps count(lo) < k <= count(hi); it ends with lo and hi adjacent doubles, and the k-th
// difference, itself a double in (lo, hi], is then exactly hi.
double kthDifference(const std::vector<double>& x, const std::vector<double>& y, uint64_t k) {
  uint64_t lo = orderKey(y.front() - x.back()) - 1;  // below the smallest difference
  uint64_t hi = orderKey(y.back() - x.front());      // the largest difference
  while (hi - lo > 1) {
    const uint64_t mid = lo + (hi - lo) / 2;
    if (countDifferencesAtMost(x, y, fromOrderKey(mid)) >= k)
      hi = mid;
    else
      lo = mid;
  }
  return fromOrderKey(hi);
}

}  // namespace

double normalCdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

double normalQuantile(double p) {
  if (!(p > 0 && p < 1)) return p == 0 ? -INFINITY : p == 1 ? INFINITY : kNaN;
  double lo = -40, hi = 40;  // Phi(-40) ~ 1e-350: below every double p > 0
  for (int i = 0; i < 200 && hi - lo > 1e-15; ++i) {
    const double mid = 0.5 * (lo + hi);
    (normalCdf(mid) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double quantileSorted(std::span<const double> sorted, double q) {
  if (sorted.empty()) return kNaN;
  const double h = static_cast<double>(sorted.size() - 1) * q;
  const size_t lo = static_cast<size_t>(std::floor(h));
  if (lo + 1 >= sorted.size()) return sorted.back();
  return sorted[lo] + (h - static_cast<double>(lo)) * (sorted[lo + 1] - sorted[lo]);
}

Summary summarize(std::span<const double> samples) {
  Summary s;
  s.n = samples.size();
  if (s.n == 0) {
    s.median = s.mean = s.stddev = s.cv = s.min = s.max = s.p95 = kNaN;
    return s;
  }
  const std::vector<double> sorted = sortedCopy(samples);
  s.min = sorted.front();
  s.max = sorted.back();
  s.median = quantileSorted(sorted, 0.5);
  s.p95 = quantileSorted(sorted, 0.95);
  s.mean = std::accumulate(sorted.begin(), sorted.end(), 0.0) / static_cast<double>(s.n);
  if (s.n < 2) {
    s.stddev = s.cv = kNaN;
    return s;
  }
  // Two-pass variance: sum of squared deviations from the mean, no cancellation of large squares.
  double ss = 0;
  for (double v : sorted) ss += (v - s.mean) * (v - s.mean);
  s.stddev = std::sqrt(ss / static_cast<double>(s.n - 1));
  s.cv = s.mean != 0 ? s.stddev / s.mean : kNaN;
  return s;
}

nlohmann::json toJson(const Summary& s, std::span<const double> samples) {
  return {{"median", s.median}, {"mean", s.mean},
          {"stddev", s.stddev}, {"cv", s.cv},
          {"min", s.min},       {"max", s.max},
          {"p95", s.p95},       {"samples", std::vector<double>(samples.begin(), samples.end())}};
}

MannWhitney mannWhitneyU(std::span<const double> a, std::span<const double> b) {
  MannWhitney r;
  if (a.empty() || b.empty()) return r;
  std::vector<double> pooled(a.begin(), a.end());
  pooled.insert(pooled.end(), b.begin(), b.end());
  const Ranks ranks = midranks(pooled);
  const size_t na = a.size(), nb = b.size(), n = na + nb;
  const double naD = static_cast<double>(na), nbD = static_cast<double>(nb);
  const double nD = static_cast<double>(n);

  int64_t rankSum2 = 0;  // doubled rank sum of a
  for (size_t i = 0; i < na; ++i) rankSum2 += ranks.doubledRank[i];
  const int64_t naI = static_cast<int64_t>(na), nbI = static_cast<int64_t>(nb);
  const int64_t u2 = rankSum2 - naI * (naI + 1);  // 2U = 2R - na(na+1)
  r.u = 0.5 * static_cast<double>(u2);

  // Var U under H0 with ties: na nb / 12 * ((n + 1) - sum(t^3 - t) / (n (n - 1))).
  const double var = naD * nbD / 12.0 * ((nD + 1) - ranks.tieTerm / (nD * (nD - 1)));
  const double dev = r.u - 0.5 * naD * nbD;
  if (var > 0) {
    const double corrected = std::max(std::abs(dev) - 0.5, 0.0);  // continuity correction
    r.z = std::copysign(corrected / std::sqrt(var), dev);
    r.p = std::min(1.0, std::erfc(std::abs(r.z) / std::sqrt(2.0)));
  } else {
    r.z = 0;  // every value tied: no evidence either way
    r.p = 1;
  }
  if (na <= kExactMannWhitneyMaxN && nb <= kExactMannWhitneyMaxN) {
    r.p = exactMannWhitneyP(ranks.doubledRank, na, std::abs(u2 - naI * nbI));
    r.exact = true;
  }
  return r;
}

RatioInterval ratioInterval(std::span<const double> a, std::span<const double> b, double alpha) {
  RatioInterval r{kNaN, kNaN, kNaN};
  if (a.empty() || b.empty() || !(alpha > 0 && alpha < 1)) return r;
  auto positive = [](double v) { return v > 0 && std::isfinite(v); };
  if (!std::all_of(a.begin(), a.end(), positive) || !std::all_of(b.begin(), b.end(), positive)) return r;
  std::vector<double> la, lb;
  for (double v : a) la.push_back(std::log(v));
  for (double v : b) lb.push_back(std::log(v));
  std::sort(la.begin(), la.end());
  std::sort(lb.begin(), lb.end());

  const uint64_t pairs = static_cast<uint64_t>(la.size()) * lb.size();
  r.estimate = pairs % 2 == 1
                   ? std::exp(kthDifference(la, lb, (pairs + 1) / 2))
                   : std::exp(0.5 * (kthDifference(la, lb, pairs / 2) + kthDifference(la, lb, pairs / 2 + 1)));
  const double pairsD = static_cast<double>(pairs);
  const double z = normalQuantile(1 - alpha / 2);
  const double c = std::floor(pairsD / 2 - z * std::sqrt(pairsD * static_cast<double>(la.size() + lb.size() + 1) / 12));
  if (c < 1) {
    r.low = std::exp(lb.front() - la.back());
    r.high = std::exp(lb.back() - la.front());
  } else {
    const uint64_t k = static_cast<uint64_t>(c);
    r.low = std::exp(kthDifference(la, lb, k));
    r.high = std::exp(kthDifference(la, lb, pairs + 1 - k));
  }
  return r;
}

namespace {

// I_x(a, b), the regularized incomplete beta function, for 0 < x < 1: the continued fraction
// I_x(a, b) = x^a (1 - x)^b / (a B(a, b)) * 1 / (1 + d_1 / (1 + d_2 / (1 + ...))), with
// d_{2m+1} = -(a + m)(a + b + m) x / ((a + 2m)(a + 2m + 1)) and d_{2m} = m (b - m) x / ((a + 2m - 1)(a + 2m))
// (DLMF 8.17.22), evaluated by the modified Lentz method. It converges fast for x < (a + 1) /
// (a + b + 2); above, I_x(a, b) = 1 - I_{1-x}(b, a) (DLMF 8.17.4).
double incompleteBeta(double x, double a, double b) {
  if (x <= 0) return 0;
  if (x >= 1) return 1;
  if (x > (a + 1) / (a + b + 2)) return 1 - incompleteBeta(1 - x, b, a);
  const double front =
      std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x)) / a;
  constexpr double kTiny = 1e-300;  // Lentz: keeps a denominator off 0
  double f = 1, c = 1, d = 0;
  for (int i = 0; i <= 1000; ++i) {
    const double m = double(i / 2);
    const double num = i == 0       ? 1.0
                       : i % 2 == 0 ? m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m))
                                    : -((a + m) * (a + b + m) * x) / ((a + 2 * m) * (a + 2 * m + 1));
    d = 1 + num * d;
    d = 1 / (std::abs(d) < kTiny ? kTiny : d);
    c = 1 + num / c;
    if (std::abs(c) < kTiny) c = kTiny;
    f *= c * d;
    if (std::abs(1 - c * d) < 1e-14) break;
  }
  return front * (f - 1);
}

}  // namespace

double studentTwoSidedP(double t, double df) {
  if (std::isnan(t) || !(df > 0)) return std::numeric_limits<double>::quiet_NaN();
  if (std::isinf(t)) return 0;
  return incompleteBeta(df / (df + t * t), df / 2, 0.5);
}

WelchT welchT(std::span<const double> a, std::span<const double> b) {
  WelchT w;
  if (a.size() < 2 || b.size() < 2) return w;
  auto meanVar = [](std::span<const double> v) {
    double mean = 0;
    for (double x : v) mean += x;
    mean /= double(v.size());
    double ss = 0;
    for (double x : v) ss += (x - mean) * (x - mean);
    return std::pair<double, double>(mean, ss / double(v.size() - 1));
  };
  const auto [ma, va] = meanVar(a);
  const auto [mb, vb] = meanVar(b);
  const double sa = va / double(a.size()), sb = vb / double(b.size());
  if (sa + sb == 0) {
    w.t = ma == mb ? 0 : std::copysign(std::numeric_limits<double>::infinity(), ma - mb);
    w.df = double(a.size() + b.size() - 2);
    w.p = ma == mb ? 1 : 0;
    return w;
  }
  w.t = (ma - mb) / std::sqrt(sa + sb);
  w.df = (sa + sb) * (sa + sb) / (sa * sa / double(a.size() - 1) + sb * sb / double(b.size() - 1));
  w.p = studentTwoSidedP(w.t, w.df);
  return w;
}

}  // namespace hb

// The warm-up's stopping rule (gpu/warm_up.h warmUntilSteady) on sequences of round times shaped as
// a cold GPU's: clocks that ramp up, then hold; a device that never holds; and the time bound.
#include "gpu/warm_up.h"

#include <gtest/gtest.h>

#include <vector>

namespace hb {
namespace {

// Rounds from a list (the last repeated), each taking `secondsPerRound` of a fake clock.
struct Scripted {
  std::vector<double> ms;
  double secondsPerRound = 0.1;
  size_t next = 0;
  double now = 0;
  double round() {
    now += secondsPerRound;
    const double v = ms[std::min(next, ms.size() - 1)];
    ++next;
    return v;
  }
};

WarmUp run(Scripted& s, const WarmUpPolicy& policy = {}) {
  return warmUntilSteady([&] { return s.round(); }, policy, [&] { return s.now; });
}

TEST(WarmUp, StopsOnceTheLastWindowAgreesAfterTheClocksRampUp) {
  // 100 ms rounds at idle clocks, falling to 50 ms as the clocks rise, then 50 ± 0.4 %.
  Scripted s{{100, 90, 80, 70, 62, 56, 52, 50.2, 50.0, 49.9, 50.1, 50.0, 50.2, 49.9, 50.0}};
  const WarmUp w = run(s);
  EXPECT_TRUE(w.ran);
  EXPECT_TRUE(w.settled);
  // The first window of 5 within 2 %: rounds 8..12 (50.2 .. 50.0); 7..11 still holds the 52.
  EXPECT_EQ(w.rounds, 12u);
  EXPECT_LE(w.spread, 0.02);
  EXPECT_EQ(w.ms.size(), 12u);
  EXPECT_NEAR(w.seconds, 1.2, 1e-9);
}

TEST(WarmUp, RunsAtLeastItsMinimumEvenWhenSteadyFromTheStart) {
  Scripted s{{50.0}};
  const WarmUp w = run(s);
  EXPECT_TRUE(w.settled);
  EXPECT_EQ(w.rounds, WarmUpPolicy{}.minRounds);
}

TEST(WarmUp, ADeviceThatNeverHoldsStopsAtTheTimeBoundUnsettledAndSaysSo) {
  // Alternating 50 and 60 ms: a spread of 20 % in every window, for ever.
  std::vector<double> ms;
  for (int i = 0; i < 1000; ++i) ms.push_back(i % 2 ? 60.0 : 50.0);
  Scripted s{ms, 0.5};
  const WarmUp w = run(s);
  EXPECT_FALSE(w.settled);
  EXPECT_GE(w.seconds, WarmUpPolicy{}.maxSeconds);
  EXPECT_EQ(w.rounds, 30u);                  // 15 s of 0.5 s rounds
  EXPECT_NEAR(w.spread, 10.0 / 60.0, 1e-9);  // (60 − 50) / the last window's median (60, 50, 60, 50, 60)
  const std::string warning = warmUpWarning(w);
  EXPECT_NE(warning.find("never settled"), std::string::npos) << warning;
  EXPECT_EQ(toJson(w)["settled"], false);
}

TEST(WarmUp, ASkippedWarmUpSaysWhyAndWarnsOfNothing) {
  WarmUp w;
  w.skipped = "a CPU device: no clocks to warm";
  EXPECT_EQ(toJson(w)["ran"], false);
  EXPECT_EQ(toJson(w)["skipped"], w.skipped);
  EXPECT_EQ(warmUpWarning(w), "");
}

}  // namespace
}  // namespace hb

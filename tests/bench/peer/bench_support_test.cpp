// Tests of the benchmarks' shared helpers (bench_support.h): a peer's time at a given error,
// against a curve whose time is a closed form of its error (t = e^-2, so log-log interpolation
// is exact between its points and extrapolation along the last two is exact beyond them).
#include "bench_support.h"

#include <gtest/gtest.h>

namespace {

TEST(TimeAtError, InterpolatesAndExtrapolatesAPowerLawExactly) {
  // t = 1e-2 e^-2 at e = 0.1, 0.05, 0.025: times 1, 4, 16, fastest first.
  const std::vector<std::pair<double, double>> curve{{1.0, 0.1}, {4.0, 0.05}, {16.0, 0.025}};
  std::string how;
  for (double e : {0.1, 0.07, 0.05, 0.03, 0.025}) {
    EXPECT_NEAR(wfbench::timeAtError(curve, e, how), 1e-2 / (e * e), 1e-9 / (e * e)) << e;
    EXPECT_EQ(how, "interpolated") << e;
  }
  EXPECT_NEAR(wfbench::timeAtError(curve, 0.0125, how), 64.0, 1e-9);
  EXPECT_EQ(how, "extrapolated");
  // Above the fastest point's error: that point's time (it already reaches the error).
  EXPECT_EQ(wfbench::timeAtError(curve, 0.2, how), 1.0);
  EXPECT_EQ(how, "above the fastest run's error");
}

TEST(TimeAtError, OnePointOrNoneGivesWhatItCan) {
  std::string how;
  const std::vector<std::pair<double, double>> one{{2.0, 0.1}};
  EXPECT_EQ(wfbench::timeAtError(one, 0.1, how), 2.0);
  EXPECT_EQ(how, "above the fastest run's error");
  EXPECT_EQ(wfbench::timeAtError(one, 0.05, how), 0.0);  // below its only point: unknown
  EXPECT_EQ(how, "n/a");
  EXPECT_EQ(wfbench::timeAtError({}, 0.1, how), 0.0);
  EXPECT_EQ(how, "n/a");
  // Two points of equal error (no slope): the bracket is skipped, no 0/0.
  const std::vector<std::pair<double, double>> flat{{1.0, 0.1}, {3.0, 0.1}};
  EXPECT_EQ(wfbench::timeAtError(flat, 0.1, how), 1.0);
  EXPECT_EQ(wfbench::timeAtError(flat, 0.05, how), 3.0);
  EXPECT_EQ(how, "extrapolated");
}

}  // namespace

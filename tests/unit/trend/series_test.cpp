// SPDX-License-Identifier: Apache-2.0
// Selections of a metric's series: time order, NaN skipped and counted, windows, restarts.
#include "ncqual/trend/series.hpp"
#include "trend_test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace ncqual::trend {
namespace {

using namespace testing;  // trend_test_support.hpp

std::vector<std::int64_t> times_of(const Series& s) {
  std::vector<std::int64_t> t;
  for (const Point& p : s.points) t.push_back(p.time_ns);
  return t;
}

TEST(Series, FinitePointsSortsByTimeAndCountsWhatItSkips) {
  const std::vector<Point> in{{kT0 + 2 * kDay, 2.0},  {kT0, 0.0},        {kT0 + kDay, kNaN},
                              {kT0 + 3 * kDay, kInf}, {kT0 + kDay, 1.0}, {kT0 + kDay, 1.5}};
  const Series s = finite_points(in);
  EXPECT_EQ(s.skipped, 2u);
  ASSERT_EQ(s.points.size(), 4u);
  EXPECT_EQ(times_of(s), (std::vector<std::int64_t>{kT0, kT0 + kDay, kT0 + kDay, kT0 + 2 * kDay}));
  // Equal times keep their input order (stable).
  EXPECT_EQ(s.points[1].value, 1.0);
  EXPECT_EQ(s.points[2].value, 1.5);
}

TEST(Series, BetweenIncludesBothEnds) {
  std::vector<Point> in;
  for (int d = 0; d < 10; ++d) in.push_back({kT0 + d * kDay, d == 4 ? kNaN : double(d)});
  const Series s = between(in, kT0 + 2 * kDay, kT0 + 6 * kDay);
  EXPECT_EQ(times_of(s), (std::vector<std::int64_t>{kT0 + 2 * kDay, kT0 + 3 * kDay, kT0 + 5 * kDay,
                                                    kT0 + 6 * kDay}));
  EXPECT_EQ(s.skipped, 1u);  // day 4
  EXPECT_TRUE(between(in, kT0 + 6 * kDay, kT0 + 2 * kDay).points.empty());
}

TEST(Series, LastNCountsTheFiniteOnesAndTheNaNInItsWindow) {
  std::vector<Point> in;
  for (int d = 0; d < 10; ++d) in.push_back({kT0 + d * kDay, double(d)});
  in[1].value = kNaN;  // before the window
  in[8].value = kNaN;  // inside it
  const Series s = last_n(in, 3);
  EXPECT_EQ(times_of(s),
            (std::vector<std::int64_t>{kT0 + 6 * kDay, kT0 + 7 * kDay, kT0 + 9 * kDay}));
  EXPECT_EQ(s.skipped, 1u);
  EXPECT_EQ(last_n(in, 100).points.size(), 8u);
  EXPECT_EQ(last_n(in, 100).skipped, 2u);
  EXPECT_TRUE(last_n(in, 0).points.empty());
}

TEST(Series, RestartAfterKeepsWhatFollowsTheLatestIntervention) {
  std::vector<Point> in;
  for (int d = 0; d < 10; ++d) in.push_back({kT0 + d * kDay, double(d)});
  // Restarts unsorted; the latest is at day 6 exactly: the check of day 6 is before it.
  const Series s = restart_after(in, {kT0 + 2 * kDay + 5, kT0 + 6 * kDay, kT0 + 3 * kDay});
  EXPECT_EQ(times_of(s),
            (std::vector<std::int64_t>{kT0 + 7 * kDay, kT0 + 8 * kDay, kT0 + 9 * kDay}));
  EXPECT_EQ(restart_after(in, {}).points.size(), 10u);
  EXPECT_TRUE(restart_after(in, {kT0 + 20 * kDay}).points.empty());
  EXPECT_EQ(last_restart({kT0 + 2 * kDay, kT0 + 6 * kDay}, kT0 + 5 * kDay), kT0 + 2 * kDay);
  EXPECT_EQ(last_restart({kT0 + 2 * kDay}, kT0 + kDay), std::nullopt);
}

TEST(Series, DaysAndDates) {
  EXPECT_EQ(days_between(kT0, kT0 + 3 * kDay / 2), 1.5);
  EXPECT_EQ(days_between(kT0 + kDay, kT0), -1.0);
  EXPECT_EQ(add_days(kT0, 2.5), kT0 + 5 * kDay / 2);
  EXPECT_EQ(add_days(kT0, -1.0), kT0 - kDay);
  // int64 nanoseconds end in April 2262; a date after it, or no date, is no date.
  EXPECT_EQ(add_days(kT0, 100'000.0), std::nullopt);
  EXPECT_EQ(add_days(kT0, kNaN), std::nullopt);
  EXPECT_EQ(add_days(kT0, kInf), std::nullopt);
  // Far-apart extremes do not overflow.
  EXPECT_GT(days_between(std::numeric_limits<std::int64_t>::min(),
                         std::numeric_limits<std::int64_t>::max()),
            200'000.0);
}

TEST(Series, SideNames) {
  EXPECT_EQ(to_string(Side::Above), "above");
  EXPECT_EQ(to_string(Side::Below), "below");
}

}  // namespace
}  // namespace ncqual::trend

// SPDX-License-Identifier: Apache-2.0
// The axis helper: nice steps, ticks, the linear mapping, UTC dates and calendar time ticks.
#include "ncqual/charts/axis.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace charts = ncqual::charts;

namespace {

constexpr std::int64_t kSecond = 1'000'000'000;
constexpr std::int64_t kHour = 3600 * kSecond;
constexpr std::int64_t kDay = 24 * kHour;
// 2026-01-01 00:00 UTC: 20454 days after the epoch (56 years, 14 of them leap years).
constexpr std::int64_t k2026 = 20454 * kDay;

std::vector<std::string> dates(const std::vector<std::int64_t>& ticks, bool with_time = false) {
  std::vector<std::string> out;
  for (const auto t : ticks)
    out.push_back(with_time ? charts::utc_date_time(t) : charts::utc_date(t));
  return out;
}

TEST(Axis, NiceStepIsTheSmallestOneTwoFiveAtLeastTheRoughStep) {
  auto value = [](double rough) { return charts::nice_step(rough).value(); };
  EXPECT_DOUBLE_EQ(value(0.005), 0.005);  // 0.025 / 5: a nice number stays itself
  EXPECT_DOUBLE_EQ(value(0.025 / 5), 0.005);
  EXPECT_DOUBLE_EQ(value(0.0051), 0.01);
  EXPECT_DOUBLE_EQ(value(1.1), 2);
  EXPECT_DOUBLE_EQ(value(2.22), 5);
  EXPECT_DOUBLE_EQ(value(7), 10);
  EXPECT_DOUBLE_EQ(value(1500), 2000);
  EXPECT_EQ(charts::nice_step(0.005).decimals(), 3);
  EXPECT_EQ(charts::nice_step(20).decimals(), 0);
}

TEST(Axis, TicksOfZeroToTwentyFiveThousandthsAreEveryFiveThousandth) {
  const charts::NiceAxis a = charts::nice_axis(0, 0.025, 5);
  // Exactly the decimal numbers: 3 × 0.005 is the double nearest 0.015, not 0.015000000000000001.
  EXPECT_EQ(a.ticks, (std::vector<double>{0, 0.005, 0.01, 0.015, 0.02, 0.025}));
  EXPECT_EQ(a.lo, 0);
  EXPECT_EQ(a.hi, 0.025);
  EXPECT_EQ(charts::tick_label(a.ticks[3], a.step), "0.015");
}

TEST(Axis, EndsRoundOutwardsToTheStep) {
  // (7.9 - -3.2) / 5 = 2.22 -> step 5 -> from floor(-3.2 / 5) × 5 = -5 to ceil(7.9 / 5) × 5 = 10.
  const charts::NiceAxis a = charts::nice_axis(7.9, -3.2, 5);
  EXPECT_EQ(a.ticks, (std::vector<double>{-5, 0, 5, 10}));
  EXPECT_EQ(charts::tick_label(-5, a.step),
            "\xE2\x88\x92"
            "5");
}

TEST(Axis, AnEmptyRangeIsWidenedAroundItsValue) {
  // 0.5 ± 10 % = 0.45..0.55; 0.1 / 5 = 0.02 -> 0.44..0.56.
  const charts::NiceAxis a = charts::nice_axis(0.5, 0.5, 5);
  EXPECT_DOUBLE_EQ(a.lo, 0.44);
  EXPECT_DOUBLE_EQ(a.hi, 0.56);
  const charts::NiceAxis zero = charts::nice_axis(0, 0, 2);  // ±1 -> step 1
  EXPECT_EQ(zero.ticks, (std::vector<double>{-1, 0, 1}));
}

TEST(Axis, TicksWithinLeaveOutWhatIsOutside) {
  EXPECT_EQ(charts::ticks_within(0.5, 24.5, charts::TickStep{5, 0}),
            (std::vector<double>{5, 10, 15, 20}));
  EXPECT_EQ(charts::ticks_within(-0.3, 0.3, charts::TickStep{1, -1}),
            (std::vector<double>{-0.3, -0.2, -0.1, 0, 0.1, 0.2, 0.3}));
}

TEST(Axis, LinearScaleMapsAValueOnPaper) {
  // 0..25 µm onto y 300 (bottom) .. 50 (top): 10 px per µm upwards; 20 µm is 200 px above 300.
  const charts::LinearScale y(0, 25, 300, 50);
  EXPECT_DOUBLE_EQ(y(20), 100);
  EXPECT_DOUBLE_EQ(y(0), 300);
  EXPECT_DOUBLE_EQ(y(-5), 350);
  EXPECT_DOUBLE_EQ(y.pixels_per_unit(), -10);
  const charts::LinearScale flat(3, 3, 0, 100);
  EXPECT_DOUBLE_EQ(flat(3), 50);
}

TEST(Axis, UtcDates) {
  EXPECT_EQ(charts::utc_date(0), "1970-01-01");
  EXPECT_EQ(charts::utc_date(-1), "1969-12-31");
  EXPECT_EQ(charts::utc_date(k2026), "2026-01-01");
  // 2024-02-29: 19782 days after the epoch.
  EXPECT_EQ(charts::utc_date(19782 * kDay), "2024-02-29");
  EXPECT_EQ(charts::utc_date_time(k2026 + 60 * kDay + 6 * kHour + 30 * 60 * kSecond + 59 * kSecond),
            "2026-03-02 06:30");
  EXPECT_EQ(charts::utc_date_time(-kSecond), "1969-12-31 23:59");
}

TEST(Axis, HalfAYearGetsMonthlyTicksOnTheFirst) {
  // 2026-01-01 .. 2026-06-30: 14-day ticks would be 13 (> 8); months give 6.
  const auto t = charts::time_ticks(k2026, k2026 + 180 * kDay, 8);
  EXPECT_EQ(dates(t.ticks), (std::vector<std::string>{"2026-01-01", "2026-02-01", "2026-03-01",
                                                      "2026-04-01", "2026-05-01", "2026-06-01"}));
  EXPECT_TRUE(t.whole_days);
}

TEST(Axis, SixWeeksGetWeeklyTicksOnMondays) {
  // 2026-11-01 is a Sunday (day 20758); 2-day ticks would be 22, weeks give 7 from Monday 11-02.
  const std::int64_t from = 20758 * kDay;
  const auto t = charts::time_ticks(from, from + 44 * kDay, 8);
  EXPECT_EQ(dates(t.ticks),
            (std::vector<std::string>{"2026-11-02", "2026-11-09", "2026-11-16", "2026-11-23",
                                      "2026-11-30", "2026-12-07", "2026-12-14"}));
}

TEST(Axis, AShiftGetsHourTicksWithTheTimeInTheirLabels) {
  // 05:10 .. 21:50: 2-hour ticks would be 8 (> 6); 3-hour ticks 06:00 .. 21:00 are 6.
  const std::int64_t day = k2026 + 60 * kDay;
  const auto t =
      charts::time_ticks(day + 5 * kHour + 600 * kSecond, day + 21 * kHour + 3000 * kSecond, 6);
  EXPECT_EQ(dates(t.ticks, true),
            (std::vector<std::string>{"2026-03-02 06:00", "2026-03-02 09:00", "2026-03-02 12:00",
                                      "2026-03-02 15:00", "2026-03-02 18:00", "2026-03-02 21:00"}));
  EXPECT_FALSE(t.whole_days);
  EXPECT_EQ(charts::default_time_label(t, t.ticks[0]), "2026-03-02 06:00");
}

TEST(Axis, DecadesGetYearTicksOnTheFirstOfJanuary) {
  // 2000-01-01 (day 10957) .. 2026-06-01: 2-year ticks would be 14 (> 6); 5-year ticks 6.
  const auto t = charts::time_ticks(10957 * kDay, k2026 + 151 * kDay, 6);
  EXPECT_EQ(dates(t.ticks), (std::vector<std::string>{"2000-01-01", "2005-01-01", "2010-01-01",
                                                      "2015-01-01", "2020-01-01", "2025-01-01"}));
}

}  // namespace

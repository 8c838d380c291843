// SPDX-License-Identifier: Apache-2.0
// The assessment the historian publishes TrendWarnings from: which warnings are active now,
// since when, and that restarts, NaN, "now" and too few points are handled.
#include "ncqual/trend/assess.hpp"
#include "trend_test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <ctime>
#include <iostream>
#include <limits>

namespace ncqual::trend {
namespace {

using namespace testing;  // trend_test_support.hpp

constexpr std::int64_t kHour = 3'600'000'000'000;

// The baseline of spc_test: 10 values alternating ±0.564, mean 0 and sigma_within exactly 1.
std::vector<double> unit_baseline() {
  std::vector<double> v;
  for (int i = 0; i < 10; ++i) v.push_back(i % 2 == 0 ? 0.564 : -0.564);
  return v;
}

// 10 baseline values, then 20 at 1.5 sigma above the centre.
std::vector<double> step_series() {
  std::vector<double> v = unit_baseline();
  for (int i = 0; i < 20; ++i) v.push_back(1.5);
  return v;
}

// A drift of 0.2 µm a day from 0 with ±0.5 µm of alternating scatter, in mm.
std::vector<double> drift(int days) {
  std::vector<double> v;
  for (int i = 0; i < days; ++i) v.push_back(0.0002 * i + (i % 2 == 0 ? 0.0005 : -0.0005));
  return v;
}

std::vector<WarningKind> kinds(const Assessment& a) {
  std::vector<WarningKind> k;
  for (const Warning& w : a.warnings) k.push_back(w.kind);
  return k;
}

TEST(Assess, WarningKindNamesAreStable) {
  const std::vector<std::string_view> names{
      "control_limit", "western_electric_2", "western_electric_3", "western_electric_4",
      "ewma",          "cusum_up",           "cusum_down",         "forecast"};
  ASSERT_EQ(names.size(), static_cast<std::size_t>(kWarningKindCount));
  for (int i = 0; i < kWarningKindCount; ++i) {
    const auto kind = static_cast<WarningKind>(i);
    EXPECT_EQ(to_string(kind), names[static_cast<std::size_t>(i)]);
    EXPECT_EQ(parse_warning_kind(names[static_cast<std::size_t>(i)]), kind);
  }
  EXPECT_EQ(parse_warning_kind("Forecast"), std::nullopt);
}

TEST(Assess, StepAboveTheBaseline) {
  // By hand (sigma 1, centre 0): C+ over the baseline alternates 0.064 (0.564 - 0.5) and 0;
  // then each 1.5 adds 1.0: C+ = 1, 2, 3, 4, 5 at indices 10..14 (5 is not above H = 5) and 6 at
  // 15: cusum_up since 15. Rule 3 (4 of 5 beyond 1 sigma): the window 10..13 plus index 9: fires
  // at 13 and holds to the end. Rule 4 (8 above the centre): indices 10..17, since 17. 1.5 is
  // within 2 sigma: no rule 2, no control_limit; nothing below.
  const auto points = daily(step_series());
  const Assessment a = assess(points, {-10, 10}, {}, points.back().time_ns);
  ASSERT_TRUE(a.ok()) << a.error;
  ASSERT_TRUE(a.baseline.ok());
  EXPECT_EQ(a.baseline.sigma_within, 1.0);
  EXPECT_EQ(kinds(a),
            (std::vector<WarningKind>{WarningKind::WesternElectric3, WarningKind::WesternElectric4,
                                      WarningKind::Ewma, WarningKind::CusumUp}));
  EXPECT_EQ(a.warning(WarningKind::CusumUp)->since_index, 15u);
  EXPECT_EQ(a.warning(WarningKind::CusumUp)->since_ns, kT0 + 15 * kDay);
  EXPECT_EQ(a.warning(WarningKind::WesternElectric3)->since_index, 13u);
  EXPECT_EQ(a.warning(WarningKind::WesternElectric4)->since_index, 17u);
  EXPECT_EQ(a.warning(WarningKind::Ewma)->side, Side::Above);
  EXPECT_EQ(a.warning(WarningKind::Ewma)->since_index, *a.ewma.first_signal);
  EXPECT_EQ(a.warning(WarningKind::CusumDown), nullptr);
  // One check earlier than index 15, no CUSUM warning yet.
  const Assessment before = assess(points, {-10, 10}, {}, points[14].time_ns);
  EXPECT_EQ(before.warning(WarningKind::CusumUp), nullptr);
  EXPECT_NE(before.warning(WarningKind::WesternElectric3), nullptr);
}

// A magnitude toleranced [0, U] (probe_c_offset_mm [0, 0.015]) watched on its upper side only
// (docs/trends.md, "One-sided metrics"): the step series mirrored below a centre of 5 (sigma 1)
// is the magnitude getting smaller. As a two-sided metric it gives the mirror image of
// StepAboveTheBaseline's warnings, below; as a magnitude none (it improves), and its 0 is no
// limit the forecast heads to. The step series itself above 5 warns the same either way.
TEST(Assess, AMagnitudeWarnsOnlyWhenItGrows) {
  std::vector<double> down, up;
  for (const double v : step_series()) {
    down.push_back(5 - v);
    up.push_back(5 + v);
  }
  const auto smaller = daily(down);
  const std::int64_t now = smaller.back().time_ns;
  const Assessment two_sided = assess(smaller, {-10, 20}, {}, now);
  EXPECT_EQ(two_sided.watched, std::nullopt);
  EXPECT_EQ(kinds(two_sided),
            (std::vector<WarningKind>{WarningKind::WesternElectric3, WarningKind::WesternElectric4,
                                      WarningKind::Ewma, WarningKind::CusumDown}));
  const Assessment magnitude = assess(smaller, {0, 20}, {}, now);
  ASSERT_TRUE(magnitude.ok()) << magnitude.error;
  EXPECT_EQ(magnitude.watched, Side::Above);
  EXPECT_TRUE(magnitude.warnings.empty()) << to_string(magnitude.warnings.front().kind);
  EXPECT_TRUE(magnitude.rules.empty()) << "no rule runs below the centre line";
  EXPECT_EQ(magnitude.forecast.heading, Side::Below);
  EXPECT_EQ(magnitude.forecast.expected.status, DateStatus::NoLimit) << "0 is no limit";
  EXPECT_FALSE(magnitude.capability.cp.has_value()) << "one-sided: Cpu only";
  ASSERT_TRUE(magnitude.capability.cpu.has_value());
  EXPECT_EQ(magnitude.capability.cpk, magnitude.capability.cpu);

  const auto larger = daily(up);
  EXPECT_EQ(kinds(assess(larger, {0, 20}, {}, larger.back().time_ns)),
            kinds(assess(larger, {-10, 20}, {}, larger.back().time_ns)));
  EXPECT_EQ(kinds(assess(larger, {0, 20}, {}, larger.back().time_ns)),
            (std::vector<WarningKind>{WarningKind::WesternElectric3, WarningKind::WesternElectric4,
                                      WarningKind::Ewma, WarningKind::CusumUp}));
  // A band with only a lower limit is watched below.
  EXPECT_EQ(assess(smaller, {-10, kInf}, {}, now).watched, Side::Below);
}

TEST(Assess, AnOutlierWarnsUntilTheNextCheck) {
  std::vector<double> v = unit_baseline();
  v.push_back(0.3);
  v.push_back(-3.5);  // beyond 3 sigma, below
  const Assessment a = assess(daily(v), {-10, 10}, {}, kT0 + 20 * kDay);
  ASSERT_NE(a.warning(WarningKind::ControlLimit), nullptr);
  EXPECT_EQ(a.warning(WarningKind::ControlLimit)->side, Side::Below);
  EXPECT_EQ(a.warning(WarningKind::ControlLimit)->since_index, 11u);
  v.push_back(0.1);
  const Assessment next = assess(daily(v), {-10, 10}, {}, kT0 + 20 * kDay);
  EXPECT_EQ(next.warning(WarningKind::ControlLimit), nullptr);
}

TEST(Assess, ARestartEndsEveryWarning) {
  const auto points = daily(step_series());
  const std::int64_t now = points.back().time_ns + kHour;
  // An intervention after index 25: the segment is the 4 points after it, too few for a
  // baseline (and for SPC warnings).
  const std::int64_t fixed = points[25].time_ns + kHour;
  const Assessment a = assess(points, {-10, 10}, {fixed}, now);
  ASSERT_TRUE(a.ok());
  EXPECT_EQ(a.restart_ns, fixed);
  EXPECT_EQ(a.segment.points.size(), 4u);
  EXPECT_EQ(a.segment.points.front().time_ns, points[26].time_ns);
  EXPECT_FALSE(a.baseline.ok());
  EXPECT_EQ(a.baseline.error, "not enough points: 4 of 10");
  EXPECT_FALSE(a.ewma.ok());
  EXPECT_TRUE(a.warnings.empty());
  EXPECT_EQ(a.forecast.error, "not enough points: 4 of 5");
  // A restart recorded after "now" does not count yet.
  const Assessment earlier = assess(points, {-10, 10}, {fixed}, points[24].time_ns);
  EXPECT_EQ(earlier.restart_ns, std::nullopt);
  EXPECT_EQ(earlier.segment.points.size(), 25u);  // and points after now are left out
  EXPECT_NE(earlier.warning(WarningKind::CusumUp), nullptr);
}

TEST(Assess, NaNPointsAreSkippedCountedAndChangeNothingElse) {
  const auto clean = daily(step_series());
  std::vector<Point> holes = clean;
  holes.insert(holes.begin() + 12, Point{clean[11].time_ns + kHour, kNaN});
  holes.insert(holes.begin() + 3, Point{clean[2].time_ns + kHour, kNaN});
  const std::int64_t now = clean.back().time_ns;
  const Assessment a = assess(clean, {-10, 10}, {}, now);
  const Assessment b = assess(holes, {-10, 10}, {}, now);
  ASSERT_TRUE(b.ok());
  EXPECT_EQ(b.segment.skipped, 2u);
  EXPECT_EQ(b.forecast.skipped, 2u);
  ASSERT_EQ(kinds(a), kinds(b));
  for (std::size_t i = 0; i < a.warnings.size(); ++i) {
    EXPECT_EQ(a.warnings[i].since_ns, b.warnings[i].since_ns);
  }
}

TEST(Assess, TooFewPointsGiveAnAnswerAndNoWarning) {
  for (const std::vector<Point>& points :
       {std::vector<Point>{}, daily({0.001, 0.002, 0.003}), daily({kNaN, kNaN, kNaN, kNaN})}) {
    const Assessment a = assess(points, {-0.01, 0.01}, {}, kT0 + 10 * kDay);
    ASSERT_TRUE(a.ok()) << a.error;
    EXPECT_TRUE(a.warnings.empty());
    EXPECT_FALSE(a.baseline.ok());
    EXPECT_FALSE(a.forecast.ok());
    EXPECT_FALSE(a.theil_sen.ok());
    EXPECT_FALSE(a.capability.ok());
    EXPECT_EQ(a.forecast.earliest.status, DateStatus::NotEnoughPoints);
    EXPECT_FALSE(a.forecast.earliest.time_ns.has_value());
  }
}

TEST(Assess, DriftTowardsTheLimitWarnsWithinTheHorizon) {
  // 60 days of drift(): the line heads up at 0.2 µm a day, ~0.012 mm at the last point; the
  // upper limit 0.0175 is ~27 days ahead on the line, the 95 % bound reaches it a little sooner.
  const auto points = daily(drift(60));
  const std::int64_t now = points.back().time_ns + 2 * kHour;
  const Band band{-0.02, 0.0175};
  const Assessment a = assess(points, band, {}, now);
  ASSERT_TRUE(a.ok());
  ASSERT_TRUE(a.forecast.trend);
  ASSERT_EQ(a.forecast.earliest.status, DateStatus::Date);
  const double ahead = days_between(now, *a.forecast.earliest.time_ns);
  ASSERT_GT(ahead, 1.0);
  ASSERT_LT(ahead, 30.0);
  const Warning* w = a.warning(WarningKind::Forecast);
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->side, Side::Above);
  EXPECT_EQ(w->earliest_ns, a.forecast.earliest.time_ns);
  EXPECT_EQ(w->expected_ns, a.forecast.expected.time_ns);
  EXPECT_LT(*w->earliest_ns, *w->expected_ns);
  // It started at `since`: there, with the points up to it and "now" its time, the warning was
  // on; one point earlier it was not.
  ASSERT_GT(w->since_index, 0u);
  auto up_to = [&](std::size_t i) {
    return assess(std::vector<Point>(points.begin(), points.begin() + i + 1), band, {},
                  points[i].time_ns);
  };
  EXPECT_NE(up_to(w->since_index).warning(WarningKind::Forecast), nullptr);
  EXPECT_EQ(up_to(w->since_index - 1).warning(WarningKind::Forecast), nullptr);
  // With a one-day horizon the same forecast is no warning.
  AssessOptions short_horizon;
  short_horizon.horizon_days = 1;
  EXPECT_EQ(assess(points, band, {}, now, short_horizon).warning(WarningKind::Forecast), nullptr);
  // Nor without a limit on the side it heads to.
  EXPECT_EQ(assess(points, {-0.02, std::numeric_limits<double>::infinity()}, {}, now)
                .warning(WarningKind::Forecast),
            nullptr);
}

TEST(Assess, ALimitAlreadyReachedIsAForecastWarning) {
  const auto points = daily(drift(60));
  const Assessment a = assess(points, {-0.02, 0.011}, {}, points.back().time_ns);
  EXPECT_EQ(a.forecast.earliest.status, DateStatus::AlreadyBeyond);
  const Warning* w = a.warning(WarningKind::Forecast);
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->earliest_ns, points.back().time_ns);
}

TEST(Assess, RefusesOptionsAndBandsItCannotUse) {
  const auto points = daily(drift(20));
  AssessOptions o;
  o.baseline_points = 4;
  EXPECT_FALSE(assess(points, {-1, 1}, {}, kT0, o).ok());
  o = {};
  o.min_points = 2;
  EXPECT_FALSE(assess(points, {-1, 1}, {}, kT0, o).ok());
  o = {};
  o.horizon_days = kNaN;
  EXPECT_FALSE(assess(points, {-1, 1}, {}, kT0, o).ok());
  o = {};
  o.ewma_lambda = 1.5;
  EXPECT_FALSE(assess(points, {-1, 1}, {}, kT0, o).ok());
  EXPECT_FALSE(assess(points, {1, -1}, {}, kT0).ok());
}

// CPU time of this thread, so that other processes on the machine do not count.
double thread_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

TEST(Assess, AYearOfDailyChecksTakesWellUnderAMillisecond) {
  // 260 checks (a year of working days), drifting from the start above an upper limit of 0.001
  // so that the forecast warning has held since the first few points: the worst case for
  // finding when it started (every prefix is fitted).
  std::vector<Point> points;
  for (int i = 0; i < 260; ++i) {
    const double scatter = 0.0004 * std::sin(1.7 * i);
    points.push_back({kT0 + i * kDay * 7 / 5, 0.002 + 0.00005 * i + scatter});
  }
  const Band band{-0.02, 0.001};
  const std::int64_t now = points.back().time_ns;
  const Assessment first = assess(points, band, {}, now);
  ASSERT_NE(first.warning(WarningKind::Forecast), nullptr);
  ASSERT_LT(first.warning(WarningKind::Forecast)->since_index, 20u);
  ASSERT_TRUE(first.theil_sen.ok());
  AssessOptions warnings_only;
  warnings_only.theil_sen = false;
  const int runs = 100;
  auto average_ms = [&](const AssessOptions& o) {
    std::size_t total = 0;
    const double start = thread_ms();
    for (int i = 0; i < runs; ++i) total += assess(points, band, {}, now, o).warnings.size();
    EXPECT_EQ(total, runs * first.warnings.size());  // deterministic
    return (thread_ms() - start) / runs;
  };
  const double all = average_ms({});
  const double fast = average_ms(warnings_only);
  std::cout << "assess of 260 points: " << all << " ms CPU, without Theil-Sen " << fast
            << " ms; forecast warning since index "
            << first.warning(WarningKind::Forecast)->since_index << "\n";
#ifdef NDEBUG
  EXPECT_LT(all, 1.0);
  EXPECT_LT(fast, 0.5);
#endif
}

TEST(Assess, LongSeriesStayCheap) {
  // Ten years of checks every 12 hours (7300 points), drifting above the limit from the start:
  // the forecast warning's start is found from running moments (linear in the count), and
  // Theil-Sen runs over the last theil_sen_max_points checks only.
  std::vector<Point> points;
  for (int i = 0; i < 7300; ++i) {
    points.push_back({kT0 + i * kDay / 2, 0.002 + 0.00001 * i + 0.0004 * std::sin(1.7 * i)});
  }
  const Band band{-0.02, 0.001};
  const std::int64_t now = points.back().time_ns;
  const double start = thread_ms();
  const Assessment a = assess(points, band, {}, now);
  const double ms = thread_ms() - start;
  ASSERT_TRUE(a.ok());
  const Warning* w = a.warning(WarningKind::Forecast);
  ASSERT_NE(w, nullptr);
  // Its start agrees with the assessments of the checks up to it (exact fits) and one before.
  ASSERT_GT(w->since_index, 0u);
  ASSERT_LT(w->since_index, 100u);
  auto up_to = [&](std::size_t i) {
    return assess(std::vector<Point>(points.begin(), points.begin() + i + 1), band, {},
                  points[i].time_ns);
  };
  EXPECT_NE(up_to(w->since_index).warning(WarningKind::Forecast), nullptr);
  EXPECT_EQ(up_to(w->since_index - 1).warning(WarningKind::Forecast), nullptr);
  ASSERT_TRUE(a.theil_sen.ok());
  EXPECT_EQ(a.theil_sen.points, 1000u);
  EXPECT_EQ(a.theil_sen.reference_ns, points[6300].time_ns);
  EXPECT_EQ(a.forecast.points, 7300u);
  std::cout << "assess of 7300 points: " << ms << " ms CPU\n";
#ifdef NDEBUG
  EXPECT_LT(ms, 100.0);
#endif
}

}  // namespace
}  // namespace ncqual::trend

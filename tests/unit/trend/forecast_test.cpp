// SPDX-License-Identifier: Apache-2.0
// Forecasts on data sets worked by hand (in the comments): the least-squares line, its slope
// interval, prediction interval, expected, earliest and latest dates; Theil-Sen; and every way
// a forecast can have no date.
#include "ncqual/trend/forecast.hpp"
#include "trend_test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace ncqual::trend {
namespace {

using namespace testing;  // trend_test_support.hpp

double days_of(const LimitDate& d) { return days_between(kT0, *d.time_ns); }

// Five daily checks, x = 0..4 days, y = 1.0, 1.2, 1.1, 1.5, 1.7 (mm):
//   x-bar = 2, Sxx = 4 + 1 + 0 + 1 + 4 = 10, y-bar = 6.5 / 5 = 1.3
//   Sxy = (-2)(-0.3) + (-1)(-0.1) + 0 + (1)(0.2) + (2)(0.4) = 1.7
//   b = 0.17 mm/day, a = 1.3 - 0.17 * 2 = 0.96
//   fitted 0.96, 1.13, 1.30, 1.47, 1.64; residuals 0.04, 0.07, -0.20, 0.03, 0.06
//   SSE = 0.0016 + 0.0049 + 0.04 + 0.0009 + 0.0036 = 0.051, s = sqrt(0.051 / 3) = 0.1303840
//   se(b) = s / sqrt(10) = 0.0412311, se(a) = s sqrt(1/5 + 4/10) = 0.1009950
//   t(0.975, 3 df) = 3.182446; b ± t se(b) = [0.038784, 0.301216]: a trend (excludes 0)
const std::vector<double> kFive{1.0, 1.2, 1.1, 1.5, 1.7};

TEST(Forecast, LeastSquaresByHand) {
  const LinearForecast f = linear_forecast(daily(kFive), {-1.0, 2.5});
  ASSERT_TRUE(f.ok()) << f.error;
  EXPECT_EQ(f.points, 5u);
  EXPECT_EQ(f.reference_ns, kT0);
  EXPECT_DOUBLE_EQ(f.mean_x, 2.0);
  EXPECT_DOUBLE_EQ(f.sxx, 10.0);
  EXPECT_NEAR(f.slope, 0.17, 1e-14);
  EXPECT_NEAR(f.intercept, 0.96, 1e-14);
  EXPECT_NEAR(f.residual_sd, 0.1303840, 1e-7);
  EXPECT_NEAR(f.slope_se, 0.0412311, 1e-7);
  EXPECT_NEAR(f.intercept_se, 0.1009950, 1e-7);
  EXPECT_NEAR(f.t_quantile, 3.182446, 1e-6);
  EXPECT_NEAR(f.slope_low, 0.038784, 1e-6);
  EXPECT_NEAR(f.slope_high, 0.301216, 1e-6);
  EXPECT_TRUE(f.trend);
  EXPECT_EQ(f.heading, Side::Above);
  EXPECT_EQ(f.limit, 2.5);
  EXPECT_NEAR(f.value_at(kT0 + 4 * kDay), 1.64, 1e-14);
}

TEST(Forecast, PredictionIntervalByHand) {
  // At x = 4: 1.64 ± t s sqrt(1 + 1/5 + (4 - 2)^2 / 10) = 1.64 ± 3.182446 * 0.1303840 * sqrt(1.6)
  // = 1.64 ± 0.524862: [1.115138, 2.164862]. At x = 2 (the centre): ± 0.414940 * sqrt(1.2).
  const LinearForecast f = linear_forecast(daily(kFive), {-1.0, 2.5});
  const Interval at4 = prediction_interval(f, kT0 + 4 * kDay);
  EXPECT_NEAR(at4.fitted, 1.64, 1e-14);
  EXPECT_NEAR(at4.lower, 1.115138, 1e-6);
  EXPECT_NEAR(at4.upper, 2.164862, 1e-6);
  const Interval at2 = prediction_interval(f, kT0 + 2 * kDay);
  EXPECT_NEAR(at2.upper - at2.fitted, 0.414940 * std::sqrt(1.2), 1e-6);
  const Interval none = prediction_interval(linear_forecast(daily({1, 2}), {}), kT0);
  EXPECT_TRUE(std::isnan(none.upper));
}

TEST(Forecast, DatesByHand) {
  // Upper limit 2.5. Expected: 0.96 + 0.17 x = 2.5, x = 1.54 / 0.17 = 9.058824 days.
  // Inverse prediction, u = x - 2, D = 2.5 - 1.3 = 1.2, b = 0.17, t s = 0.414940,
  // t^2 se(b)^2 = 0.0172177, A = 0.0289 - 0.0172177 = 0.0116823 (> 0: a trend),
  // C = 1.44 - 0.172177 * 1.2 = 1.233388, (discriminant / 4) = 0.0172177 * 1.44 + A * 0.2066124
  // = 0.0272074, its root 0.164947; u = (0.204 ∓ 0.164947) / 0.0116823 = 3.3430, 31.581:
  // earliest x = 5.3430 days (the upper 95 % bound reaches 2.5: 0.96 + 0.17 * 5.3430 +
  // 0.414940 sqrt(1.2 + 3.3430^2 / 10) = 1.86831 + 0.63169 = 2.5000), latest x = 33.581 days.
  const LinearForecast f = linear_forecast(daily(kFive), {-1.0, 2.5});
  ASSERT_EQ(f.expected.status, DateStatus::Date);
  EXPECT_NEAR(days_of(f.expected), 9.058824, 1e-6);
  ASSERT_EQ(f.earliest.status, DateStatus::Date);
  EXPECT_NEAR(days_of(f.earliest), 5.3430, 1e-4);
  ASSERT_EQ(f.latest.status, DateStatus::Date);
  EXPECT_NEAR(days_of(f.latest), 33.581, 1e-3);
  // And on the bounds themselves: the upper bound at the earliest date is the limit.
  EXPECT_NEAR(prediction_interval(f, *f.earliest.time_ns).upper, 2.5, 1e-9);
  EXPECT_NEAR(prediction_interval(f, *f.latest.time_ns).lower, 2.5, 1e-9);
}

TEST(Forecast, AlreadyBeyondAtTheLastPoint) {
  // Upper limit 2.0: the upper bound at x = 4 is 2.164862 >= 2.0, so the earliest date is the
  // last point; the fitted line (1.64 at x = 4) reaches 2.0 only at x = 1.04 / 0.17 = 6.117647.
  const LinearForecast f = linear_forecast(daily(kFive), {-1.0, 2.0});
  EXPECT_EQ(f.earliest.status, DateStatus::AlreadyBeyond);
  EXPECT_EQ(f.earliest.time_ns, kT0 + 4 * kDay);
  ASSERT_EQ(f.expected.status, DateStatus::Date);
  EXPECT_NEAR(days_of(f.expected), 6.117647, 1e-6);
  EXPECT_EQ(f.latest.status, DateStatus::Date);
  // Limit 1.5: the line itself crossed it at x = 0.54 / 0.17 = 3.176471, before the last point.
  const LinearForecast past = linear_forecast(daily(kFive), {-1.0, 1.5});
  EXPECT_EQ(past.expected.status, DateStatus::AlreadyBeyond);
  EXPECT_NEAR(days_of(past.expected), 3.176471, 1e-6);
  // Limit 1.0, far below the last values: even the lower bound is beyond it.
  EXPECT_EQ(linear_forecast(daily(kFive), {-1.0, 1.0}).latest.status, DateStatus::AlreadyBeyond);
}

TEST(Forecast, HeadingDownMirrorsHeadingUp) {
  std::vector<double> down;
  for (double v : kFive) down.push_back(-v);
  const LinearForecast f = linear_forecast(daily(down), {-2.5, 1.0});
  EXPECT_EQ(f.heading, Side::Below);
  EXPECT_EQ(f.limit, -2.5);
  EXPECT_NEAR(days_of(f.expected), 9.058824, 1e-6);
  EXPECT_NEAR(days_of(f.earliest), 5.3430, 1e-4);
  EXPECT_NEAR(days_of(f.latest), 33.581, 1e-3);
  // A one-sided band with no lower limit: nothing to head to.
  const LinearForecast open = linear_forecast(daily(down), {-kInf, 1.0});
  EXPECT_FALSE(open.limit.has_value());
  EXPECT_EQ(open.expected.status, DateStatus::NoLimit);
  EXPECT_EQ(open.earliest.status, DateStatus::NoLimit);
  EXPECT_FALSE(open.earliest.time_ns.has_value());
}

TEST(Forecast, NoTrendGivesNoExpectedDateAndNeverALatestOne) {
  // y = 1, 2, 1, 2, 1.2 at x = 0..4: y-bar = 1.44, Sxy = 0.88 - 0.56 + 0 + 0.56 - 0.48 = 0.40,
  // b = 0.04, a = 1.36; residuals -0.36, 0.60, -0.44, 0.52, -0.32, SSE = 1.056,
  // s = sqrt(0.352) = 0.593296, t se(b) = 3.182446 * 0.593296 / sqrt(10) = 0.597080 > 0.04:
  // the interval [-0.557, 0.637] contains 0. The far bound never stays beyond the limit; the near
  // one, widening without end, still reaches it at some date after the last point. (At x = 4 it
  // is 1.52 + 3.182446 * 0.593296 * sqrt(1.6) = 3.908: a limit of 6 lies ahead of it.)
  const LinearForecast f = linear_forecast(daily({1, 2, 1, 2, 1.2}), {-1.0, 6.0});
  ASSERT_TRUE(f.ok());
  EXPECT_NEAR(f.slope, 0.04, 1e-14);
  EXPECT_NEAR(f.t_quantile * f.slope_se, 0.597080, 1e-6);
  EXPECT_FALSE(f.trend);
  EXPECT_EQ(f.expected.status, DateStatus::NoTrend);
  EXPECT_FALSE(f.expected.time_ns.has_value());
  EXPECT_EQ(f.latest.status, DateStatus::Never);
  ASSERT_EQ(f.earliest.status, DateStatus::Date);
  EXPECT_GT(*f.earliest.time_ns, kT0 + 4 * kDay);
  EXPECT_NEAR(prediction_interval(f, *f.earliest.time_ns).upper, 6.0, 1e-9);
  EXPECT_EQ(linear_forecast(daily({1, 2, 1, 2, 1.2}), {-1.0, 2.5}).earliest.status,
            DateStatus::AlreadyBeyond);
}

TEST(Forecast, ConstantSeriesHasNoSlope) {
  const LinearForecast f =
      linear_forecast(daily({0.003, 0.003, 0.003, 0.003, 0.003, 0.003}), {-0.01, 0.01});
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(f.slope, 0.0);
  EXPECT_EQ(f.residual_sd, 0.0);
  EXPECT_FALSE(f.trend);
  EXPECT_FALSE(f.heading.has_value());
  EXPECT_EQ(f.expected.status, DateStatus::NoTrend);
  EXPECT_EQ(f.earliest.status, DateStatus::NoTrend);
}

TEST(Forecast, TooFewPointsSaySoAndGiveNoDate) {
  // Six points, two NaN: four finite, fewer than the default five.
  const LinearForecast f = linear_forecast(daily({1, kNaN, 2, 3, kNaN, 4}), {0, 10});
  EXPECT_FALSE(f.ok());
  EXPECT_EQ(f.error, "not enough points: 4 of 5");
  EXPECT_EQ(f.points, 4u);
  EXPECT_EQ(f.skipped, 2u);
  for (const LimitDate* d : {&f.expected, &f.earliest, &f.latest}) {
    EXPECT_EQ(d->status, DateStatus::NotEnoughPoints);
    EXPECT_FALSE(d->time_ns.has_value());
  }
  // With a minimum of 4 the same points are enough.
  EXPECT_TRUE(linear_forecast(daily({1, kNaN, 2, 3, kNaN, 4}), {0, 10}, {4, 0.95}).ok());
  // Every point at the same time: no slope.
  const std::vector<Point> same(6, Point{kT0, 1.0});
  EXPECT_EQ(linear_forecast(same, {0, 10}).error, "every point is at the same time: no slope");
  // Nothing at all, options and bands that cannot be used.
  EXPECT_FALSE(linear_forecast({}, {0, 10}).ok());
  EXPECT_FALSE(linear_forecast(daily(kFive), {0, 10}, {2, 0.95}).ok());
  EXPECT_FALSE(linear_forecast(daily(kFive), {0, 10}, {5, 1.0}).ok());
  EXPECT_FALSE(linear_forecast(daily(kFive), {10, 0}).ok());
}

TEST(Forecast, DatesBeyondACenturyAreTooFar) {
  // 1e-6 mm (1 nm) a day with ±1e-9 mm of scatter: a clear trend, reaching +1 mm in a million
  // days.
  std::vector<double> v;
  for (int i = 0; i < 10; ++i) v.push_back(1e-6 * i + (i % 2 == 0 ? 1e-9 : -1e-9));
  const LinearForecast f = linear_forecast(daily(v), {-1.0, 1.0});
  ASSERT_TRUE(f.trend);
  EXPECT_EQ(f.expected.status, DateStatus::TooFar);
  EXPECT_EQ(f.earliest.status, DateStatus::TooFar);
  EXPECT_FALSE(f.expected.time_ns.has_value());
}

TEST(Forecast, TheilSenByHand) {
  // (0, 1), (1, 2), (2, 3.5), (3, 3), (4, 100): the last check is an outlier. The 10 pairwise
  // slopes: 1, 1.25, 0.6667, 24.75, 1.5, 0.5, 32.667, -0.5, 48.25, 97; sorted:
  // -0.5, 0.5, 0.6667, 1, 1.25, 1.5, 24.75, 32.667, 48.25, 97. Median (1.25 + 1.5) / 2 = 1.375;
  // intercept median(y) - 1.375 median(x) = 3 - 2.75 = 0.25. Sen's interval: sigma^2 = 5 * 4 *
  // 15 / 18 = 16.667, sigma = 4.0825, z = -1.959964; ranks max(round((10 - 8.0015) / 2) - 1, 0) =
  // 0 and min(round((10 + 8.0015) / 2), 9) = 9: [-0.5, 97], no trend. Least squares, pulled by
  // the outlier: y-bar = 21.9, Sxy = 41.8 + 19.9 - 18.9 + 156.2 = 199, slope 19.9.
  const std::vector<Point> p = daily({1, 2, 3.5, 3, 100});
  const TheilSen t = theil_sen(p, {0, 50});
  ASSERT_TRUE(t.ok()) << t.error;
  EXPECT_DOUBLE_EQ(t.slope, 1.375);
  EXPECT_DOUBLE_EQ(t.intercept, 0.25);
  EXPECT_DOUBLE_EQ(t.slope_low, -0.5);
  EXPECT_DOUBLE_EQ(t.slope_high, 97.0);
  EXPECT_FALSE(t.trend);
  EXPECT_EQ(t.expected.status, DateStatus::NoTrend);
  EXPECT_NEAR(linear_forecast(p, {0, 50}).slope, 19.9, 1e-12);
}

TEST(Forecast, TheilSenLineAndItsDate) {
  // Twelve points on y = 0.5 + 0.25 x except x = 5 at 10: every pair not involving x = 5 has
  // slope 0.25 exactly (55 of 66); the 11 with x = 5 are 6 negative ones (-8 .. -1.125) and 5
  // above 1.9, so the sorted slopes are 0.25 from rank 6 to 60. The median (ranks 32, 33) and
  // both ends of Sen's interval (n = 12: sigma^2 = 12 * 11 * 29 / 18 = 212.67, sigma = 14.583;
  // ranks max(round((66 - 28.583) / 2) - 1, 0) = 18, min(round((66 + 28.583) / 2), 65) = 47) are
  // 0.25: a trend. Sorted y: 0.5 .. 1.5, 2, 2.25, .., 3.25, 10 (1.75 replaced by 10), median
  // (2 + 2.25) / 2 = 2.125, intercept 2.125 - 0.25 * 5.5 = 0.75. Limit 4: x = 3.25 / 0.25 = 13.
  // Least squares is pulled up by the outlier.
  std::vector<double> v;
  for (int i = 0; i < 12; ++i) v.push_back(i == 5 ? 10.0 : 0.5 + 0.25 * i);
  const TheilSen t = theil_sen(daily(v), {-4, 4});
  ASSERT_TRUE(t.ok());
  EXPECT_DOUBLE_EQ(t.slope, 0.25);
  EXPECT_DOUBLE_EQ(t.slope_low, 0.25);
  EXPECT_DOUBLE_EQ(t.slope_high, 0.25);
  EXPECT_DOUBLE_EQ(t.intercept, 0.75);
  EXPECT_TRUE(t.trend);
  EXPECT_EQ(t.heading, Side::Above);
  ASSERT_EQ(t.expected.status, DateStatus::Date);
  EXPECT_NEAR(days_between(kT0, *t.expected.time_ns), 13.0, 1e-9);
  EXPECT_GT(linear_forecast(daily(v), {-4, 4}).intercept, 1.0);
  EXPECT_EQ(theil_sen(daily({1, 2, 3}), {0, 5}).error, "not enough points: 3 of 5");
}

TEST(Forecast, StatusNames) {
  EXPECT_EQ(to_string(DateStatus::Date), "date");
  EXPECT_EQ(to_string(DateStatus::AlreadyBeyond), "already_beyond");
  EXPECT_EQ(to_string(DateStatus::Never), "never");
  EXPECT_EQ(to_string(DateStatus::NoTrend), "no_trend");
  EXPECT_EQ(to_string(DateStatus::NoLimit), "no_limit");
  EXPECT_EQ(to_string(DateStatus::TooFar), "too_far");
  EXPECT_EQ(to_string(DateStatus::NotEnoughPoints), "not_enough_points");
}

}  // namespace
}  // namespace ncqual::trend

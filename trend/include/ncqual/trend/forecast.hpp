// SPDX-License-Identifier: Apache-2.0
// Forecasts of one metric: when does its drift carry it to the tolerance limit
// (docs/trends.md)?
//
// Two straight lines through the segment's points, value = intercept + slope * x, with x in days
// since the segment's first point (reference_ns) and the slope in the metric's unit per day:
//
// Least squares ([DS] chapters 1-3; [MPV] §2.3-2.5):
//   n points (x_i, y_i), x-bar, y-bar, Sxx = Σ (x_i - x-bar)², Sxy = Σ (x_i - x-bar)(y_i - y-bar)
//   slope b = Sxy / Sxx, intercept a = y-bar - b x-bar
//   s = sqrt(Σ (y_i - a - b x_i)² / (n - 2))            residual standard deviation
//   se(b) = s / sqrt(Sxx), se(a) = s sqrt(1/n + x-bar² / Sxx)
//   t = the (1 + confidence)/2 quantile of Student's t with n - 2 degrees of freedom
//   slope interval b ± t se(b); "trend" when it excludes zero (a two-sided test of b = 0 at
//   1 - confidence), "no trend" when it contains zero
//   prediction interval of one new check at x: a + b x ± t s sqrt(1 + 1/n + (x - x-bar)² / Sxx)
// The limit the line heads to is the upper one for b > 0, the lower one for b < 0.
//   expected: the date the fitted line reaches it, x = (limit - a) / b; only with a trend.
//   earliest: the first date at or after the last point at which the near prediction bound
//     (the upper bound heading up, the lower bound heading down) reaches it: the earliest date a
//     single check could plausibly (one-sided (1 + confidence)/2, 97.5 % by default) be beyond.
//   latest: the first date at or after the last point from which the far bound is beyond it:
//     from then on a check is beyond the limit with that confidence.
//   [earliest, latest] is the inverse-prediction (calibration) interval of the date the line
//   reaches the limit ([DS] §3.2, Fieller): the x at which the limit lies on a prediction
//   bound solve (limit - y-bar - b u)² = t² s² (1 + 1/n + u² / Sxx), u = x - x-bar, a quadratic
//   A u² - 2 D b u + C = 0 with A = b² - t² se(b)², D = limit - y-bar, C = D² - t² s² (1 + 1/n).
//   A > 0 exactly when there is a trend: then the near bound meets the limit at the smaller root
//   and the far bound at the larger one. Without a trend (A <= 0) the far bound never stays
//   beyond the limit ("never"), while the near bound, which widens without end as x leaves the
//   data, still reaches it (at the smallest root after the last point): earliest is computed,
//   but the assessment warns only with a trend.
//
// Theil-Sen ([T], [S], [C]): the slope is the median of the slopes (y_j - y_i) / (x_j - x_i)
// of every pair with x_j > x_i (pairs at the same time are left out); the intercept is
// median(y) - slope median(x) (Conover's; scipy.stats.theilslopes's default method='separate'),
// so the line passes through (median x, median y). The slope's interval is Sen's (1968,
// eq. 2.6), as scipy.stats.theilslopes computes low_slope and high_slope: with N slopes sorted,
// sigma² = (n(n-1)(2n+5) - Σ_ties-in-x t(t-1)(2t+5) - Σ_ties-in-y t(t-1)(2t+5)) / 18 and
// z = the normal (1 - confidence)/2 quantile (negative), the bounds are the sorted slopes at
// 0-based ranks max(round((N + z sigma)/2) - 1, 0) and min(round((N - z sigma)/2), N - 1),
// rounding half to even as numpy does. It resists outliers (a bad touch, a mistyped value)
// that pull the least-squares line; its "trend" is its interval excluding zero, and its line
// gives an expected date the same way.
//
// References:
//   [DS]  N. R. Draper, H. Smith, Applied Regression Analysis, 3rd ed., Wiley 1998.
//   [MPV] D. C. Montgomery, E. A. Peck, G. G. Vining, Introduction to Linear Regression
//         Analysis, 5th ed., Wiley 2012.
//   [T]   H. Theil, A rank-invariant method of linear and polynomial regression analysis, 1950.
//   [S]   P. K. Sen, Estimates of the regression coefficient based on Kendall's tau, JASA 63
//         (1968) 1379-1389.
//   [C]   W. J. Conover, Practical Nonparametric Statistics, 1980.
#pragma once

#include "ncqual/trend/series.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ncqual::trend {

// Dates further than this after the last point are not given (DateStatus::TooFar): a straight
// line says nothing about a machine a century on, and int64 nanoseconds end in 2262.
inline constexpr double kMaxForecastDays = 36525;  // 100 years

enum class DateStatus {
  Date,             // time_ns is the date, after the last point
  AlreadyBeyond,    // the line (bound) is at or beyond the limit at the last point
  Never,            // the bound does not reach the limit, however long one waits
  NoTrend,          // expected: the slope's interval contains zero; earliest/latest: slope 0
  NoLimit,          // the band has no limit on the side the line heads to
  TooFar,           // more than kMaxForecastDays after the last point
  NotEnoughPoints,  // no fit (see the fit's error)
};
// "date", "already_beyond", "never", "no_trend", "no_limit", "too_far", "not_enough_points"
std::string_view to_string(DateStatus status);

struct LimitDate {
  DateStatus status = DateStatus::NotEnoughPoints;
  // Date: the date. AlreadyBeyond: for `expected`, the date the fitted line crossed the limit
  // (at or before the last point); for `earliest` and `latest`, the last point's time.
  // Otherwise std::nullopt.
  std::optional<std::int64_t> time_ns;
};

struct ForecastOptions {
  std::size_t min_points = 5;  // fewer finite points: NotEnoughPoints (at least 3: n - 2 >= 1)
  double confidence = 0.95;    // of the slope's interval and of the prediction interval
};

struct LinearForecast {
  std::string error;       // non-empty when there is no fit; says why ("not enough points: 3 of 5")
  std::size_t points = 0;  // finite points used
  std::size_t skipped = 0;        // non-finite values left out
  std::int64_t reference_ns = 0;  // x = 0: the first point's time
  double last_x = 0;              // the last point, days after reference_ns
  double mean_x = 0, mean_y = 0, sxx = 0;
  double intercept = 0;    // at reference_ns
  double slope = 0;        // per day
  double residual_sd = 0;  // s
  double slope_se = 0;
  double intercept_se = 0;
  double t_quantile = 0;
  double slope_low = 0, slope_high = 0;
  bool trend = false;
  std::optional<Side> heading;  // Above: towards the upper limit; std::nullopt when slope == 0
  std::optional<double> limit;  // the limit it heads to; std::nullopt when that side has none
  LimitDate expected, earliest, latest;

  bool ok() const { return error.empty(); }
  // The fitted value at a time.
  double value_at(std::int64_t time_ns) const;
};
// Points need not be sorted; non-finite values are skipped and counted.
LinearForecast linear_forecast(const std::vector<Point>& points, const Band& band,
                               const ForecastOptions& options = {});

struct Interval {
  double fitted = 0;
  double lower = 0;
  double upper = 0;
};
// The prediction interval of one new check at time_ns (NaN bounds when the fit is not ok).
Interval prediction_interval(const LinearForecast& fit, std::int64_t time_ns);

struct TheilSen {
  std::string error;
  std::size_t points = 0;
  std::size_t skipped = 0;
  std::int64_t reference_ns = 0;
  double last_x = 0;
  double slope = 0;      // per day
  double intercept = 0;  // at reference_ns
  double slope_low = 0, slope_high = 0;
  bool trend = false;  // the slope's interval excludes zero
  std::optional<Side> heading;
  std::optional<double> limit;
  LimitDate expected;

  bool ok() const { return error.empty(); }
};
TheilSen theil_sen(const std::vector<Point>& points, const Band& band,
                   const ForecastOptions& options = {});

}  // namespace ncqual::trend

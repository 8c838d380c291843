// SPDX-License-Identifier: Apache-2.0
// The least-squares forecast over the first `count` points of a sorted, finite series, without
// copying them, and over every prefix of a series from running moments: the assessment
// evaluates the forecast warning on every prefix of a segment to find when it started.
#pragma once

#include "ncqual/trend/forecast.hpp"

#include <string>
#include <vector>

namespace ncqual::trend::detail {

// x[i]: days from points[0] to points[i] (empty when count is 0).
std::vector<double> days_from_first(const Point* points, std::size_t count);
// Precondition: points[0..count) finite and in time order, x = days_from_first of them (or of
// a longer series with the same first point).
LinearForecast fit_sorted(const Point* points, const double* x, std::size_t count,
                          std::size_t skipped, const Band& band, const ForecastOptions& options);

// The running moments of points[0..k]: means of x and of y - y_0, and the centred sums of
// squares and products.
struct Moments {
  double mean_x = 0, mean_dy = 0, sxx = 0, sxy = 0, syy = 0;
};
// The moments of every prefix, in one pass (Welford's updates).
std::vector<Moments> prefix_moments(const Point* points, const double* x, std::size_t count);
// The forecast of points[0..count) from its moments (prefix_moments()[count - 1]) in O(1): the
// residual sum of squares is Syy - Sxy^2 / Sxx, less accurate than fit_sorted's residuals when
// the points lie almost exactly on a line, and exact enough to decide a warning. The assessment
// uses it to find when a forecast warning started without refitting every prefix.
LinearForecast fit_prefix(const Point* points, const double* x, std::size_t count,
                          const Moments& moments, const Band& band, const ForecastOptions& options);

// Non-empty when the band or the options cannot be used; says why.
std::string check_band(const Band& band);
std::string check_options(const ForecastOptions& options);

}  // namespace ncqual::trend::detail

// SPDX-License-Identifier: Apache-2.0
// The least-squares forecast over the first `count` points of a sorted, finite series, without
// copying them: the assessment evaluates it on every prefix of a segment to find when a forecast
// warning started.
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

// Non-empty when the band or the options cannot be used; says why.
std::string check_band(const Band& band);
std::string check_options(const ForecastOptions& options);

}  // namespace ncqual::trend::detail

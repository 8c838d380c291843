// SPDX-License-Identifier: Apache-2.0
// Shared by the trend library's tests: a day, the first day of the series worked by hand, the
// doubles that are not numbers, and a series of one value a day.
#pragma once

#include "ncqual/trend/series.hpp"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace ncqual::trend::testing {

constexpr std::int64_t kDay = 86'400'000'000'000;
constexpr std::int64_t kT0 = 1'767'225'600'000'000'000;  // 2026-01-01T00:00:00Z
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// values[i] at kT0 + i days.
inline std::vector<Point> daily(const std::vector<double>& values) {
  std::vector<Point> p;
  for (std::size_t i = 0; i < values.size(); ++i) {
    p.push_back({kT0 + static_cast<std::int64_t>(i) * kDay, values[i]});
  }
  return p;
}

}  // namespace ncqual::trend::testing

// SPDX-License-Identifier: Apache-2.0
// Small helpers every check uses to build its CheckResult (internal to the solver library).
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/common/model.hpp"

#include <string>
#include <string_view>

namespace ncqual::solver::detail {

// A result carrying the identity of the set it answers (machine, request, kind) and its origin
// (measured or simulated), verdict INVALID until a check decides otherwise.
CheckResult result_for(const MeasurementSet& set);

// Marks `result` INVALID with `reason`, dropping any metrics; returns it.
CheckResult invalid(CheckResult result, std::string reason);

// A metric judged against its tolerance band: pass when lower <= value <= upper (a NaN value
// never passes).
Metric judged_metric(std::string_view name, double value, std::string_view unit,
                     const Tolerance& band);

// "0.0412 mm is above the upper limit 0.025 mm by 0.0162 mm" for a metric out of its band.
std::string describe_out_of_band(const Metric& metric);

// Numbers in reasons: 6 significant digits (or `digits`), "nan" and "inf" as such.
std::string format_number(double value, int digits = 6);
std::string format_vector(const Eigen::Vector3d& v, int digits = 6);

// Values quoted in a refusal of input: 10 significant digits, so what the caller gave shows in
// full.
inline std::string quote_number(double value) { return format_number(value, 10); }
inline std::string quote_vector(const Eigen::Vector3d& v) { return format_vector(v, 10); }

}  // namespace ncqual::solver::detail

// SPDX-License-Identifier: Apache-2.0
#include "result_building.hpp"

#include <cmath>
#include <cstdio>

namespace ncqual::solver::detail {

CheckResult result_for(const MeasurementSet& set) {
  CheckResult result;
  result.machine_id = set.machine_id;
  result.request_id = set.request_id;
  result.kind = set.kind;
  result.verdict = Verdict::Invalid;
  result.origin = set.origin;  // a verdict on simulated numbers says nothing of a machine
  return result;
}

CheckResult invalid(CheckResult result, std::string reason) {
  result.verdict = Verdict::Invalid;
  result.metrics.clear();
  result.likely_causes.clear();
  result.correction.reset();
  result.reason = std::move(reason);
  return result;
}

Metric judged_metric(std::string_view name, double value, std::string_view unit,
                     const Tolerance& band) {
  Metric m;
  m.name = std::string(name);
  m.value = value;
  m.unit = std::string(unit);
  m.lower = band.lower;
  m.upper = band.upper;
  m.pass = std::isfinite(value) && band.contains(value);
  return m;
}

std::string describe_out_of_band(const Metric& metric) {
  const std::string unit = metric.unit.empty() ? "" : " " + metric.unit;
  std::string text = metric.name + " = " + format_number(metric.value) + unit;
  if (!std::isfinite(metric.value)) return text + " is not a finite number";
  if (metric.value > metric.upper) {
    return text + " is above the upper limit " + format_number(metric.upper) + unit + " by " +
           format_number(metric.value - metric.upper) + unit;
  }
  return text + " is below the lower limit " + format_number(metric.lower) + unit + " by " +
         format_number(metric.lower - metric.value) + unit;
}

std::string format_number(double value, int digits) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, value);
  return buffer;
}

std::string format_vector(const Eigen::Vector3d& v, int digits) {
  return "(" + format_number(v.x(), digits) + ", " + format_number(v.y(), digits) + ", " +
         format_number(v.z(), digits) + ")";
}

}  // namespace ncqual::solver::detail

// SPDX-License-Identifier: Apache-2.0
#include "touch_input.hpp"

#include "result_building.hpp"

#include <cmath>

namespace ncqual::solver::detail {

namespace {
constexpr double kTwoPi = 2 * 3.14159265358979323846;
}

std::string touch_field(std::size_t i, const std::string& field) {
  return "MeasurementSet.touches[" + std::to_string(i) + "]." + field;
}

std::optional<std::string> why_touch_not_finite(const Touch& t, std::size_t i) {
  const struct {
    const char* name;
    double value;
  } axes[] = {{"axes.x_mm", t.axes.x_mm},   {"axes.y_mm", t.axes.y_mm},
              {"axes.z_mm", t.axes.z_mm},   {"axes.w_mm", t.axes.w_mm},
              {"axes.a_rad", t.axes.a_rad}, {"axes.c_rad", t.axes.c_rad}};
  for (const auto& axis : axes) {
    if (!std::isfinite(axis.value)) {
      return touch_field(i, axis.name) + " = " + format_number(axis.value) + " is not finite";
    }
  }
  if (!t.approach.allFinite()) {
    return touch_field(i, "approach") + " = " + format_vector(t.approach) + " is not finite";
  }
  if (std::abs(t.approach.norm() - 1) > kUnitTolerance) {
    return touch_field(i, "approach") + " = " + format_vector(t.approach) + " has length " +
           format_number(t.approach.norm()) + ", expected a unit vector";
  }
  return std::nullopt;
}

double angle_difference(double a, double b) { return std::remainder(a - b, kTwoPi); }

bool head_at(const AxisPosition& axes, double a_rad, double c_rad) {
  return std::abs(angle_difference(axes.a_rad, a_rad)) <= kHeadAngleTolerance &&
         std::abs(angle_difference(axes.c_rad, c_rad)) <= kHeadAngleTolerance;
}

std::string describe_head(const AxisPosition& axes) {
  return "A = " + format_number(axes.a_rad) + " rad, C = " + format_number(axes.c_rad) + " rad";
}

std::optional<std::string> why_not_a_set_of(const MeasurementSet& set, CheckKind expected,
                                            std::string_view check) {
  if (!set.error.empty()) return "MeasurementSet.error: " + set.error;
  if (set.kind != expected) {
    return "MeasurementSet.kind = '" + std::string(to_string(set.kind)) +
           "': " + std::string(check) + " needs '" + std::string(to_string(expected)) + "'";
  }
  return std::nullopt;
}

std::string machine_where(const MachineConfig& m) {
  return "machine '" + m.machine_id + "'" +
         (m.source_path.empty() ? "" : " (" + m.source_path + ")");
}

std::optional<std::string> why_probe_unusable(const MachineConfig& m) {
  const std::string where = machine_where(m) + ": ";
  if (!std::isfinite(m.probe.ball_radius_mm) || m.probe.ball_radius_mm < 0) {
    return where + "probe.ball_radius_mm = " + format_number(m.probe.ball_radius_mm) +
           " must be a non-negative number";
  }
  if (!std::isfinite(m.probe.tool_length_mm) || !m.probe.stylus_offset_mm.allFinite()) {
    return where + "probe.tool_length_mm = " + format_number(m.probe.tool_length_mm) +
           " or the stylus offset is not finite";
  }
  return std::nullopt;
}

const Tolerance* find_tolerance(const MachineConfig& m, std::string_view metric) {
  const auto it = m.tolerances.find(std::string(metric));
  return it == m.tolerances.end() ? nullptr : &it->second;
}

std::optional<std::string> why_tolerances_missing(const MachineConfig& m,
                                                  const std::vector<std::string_view>& metrics,
                                                  std::string_view check) {
  for (std::string_view metric : metrics) {
    if (!find_tolerance(m, metric)) {
      return machine_where(m) + ": tolerances." + std::string(metric) + " is not configured; " +
             std::string(check) + " reports that metric";
    }
  }
  return std::nullopt;
}

Eigen::Vector3d contact_point(const Eigen::Vector3d& ball_centre, const Eigen::Vector3d& approach,
                              double ball_radius) {
  return ball_centre + ball_radius * approach;
}

void decide_verdict(CheckResult& result, const std::vector<std::string>& causes) {
  std::string out_of_band;
  for (const auto& metric : result.metrics) {
    if (metric.pass) continue;
    if (!out_of_band.empty()) out_of_band += "; ";
    out_of_band += describe_out_of_band(metric);
  }
  if (out_of_band.empty()) {
    result.verdict = Verdict::Pass;
    result.reason.clear();
    result.likely_causes.clear();
    return;
  }
  result.verdict = Verdict::Fail;
  result.reason = out_of_band;
  result.likely_causes = causes;
}

}  // namespace ncqual::solver::detail

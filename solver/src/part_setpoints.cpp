// SPDX-License-Identifier: Apache-2.0
// The per-part set-point check:
//   0. make sure every configured set point has its three touches, at home head angles;
//   1. contact point of each touch from the nominal kinematics;
//   2. each set point's measured reference corner and its deviation from the intended one;
//   3. verdict; on PASS, the primary set point's deviation becomes the part program's zero
//      reference (a work offset), on FAIL the likely causes.
#include "ncqual/solver/part_setpoints.hpp"

#include "ncqual/common/kinematics.hpp"
#include "result_building.hpp"
#include "touch_input.hpp"

#include <cmath>
#include <map>
#include <optional>
#include <string>

namespace ncqual::solver {

namespace setpoints {
std::string axis_metric(const std::string& point, char axis) {
  return "setpoint_" + point + "_d" + std::string(1, axis) + "_mm";
}
std::string deviation_metric(const std::string& point) { return "setpoint_" + point + "_dev_mm"; }
}  // namespace setpoints

namespace {

using namespace setpoints;
using detail::format_vector;
using detail::machine_where;
using detail::touch_field;

// Unit approach of the touch of each axis: onto the -X face along +X, the -Y face along +Y, the
// top face along -Z.
Eigen::Vector3d approach_of(int axis) {
  return axis == 2 ? Eigen::Vector3d(-Eigen::Vector3d::UnitZ()) : Eigen::Vector3d::Unit(axis);
}

struct Measured {
  Eigen::Vector3d corner = Eigen::Vector3d::Constant(std::nan(""));
  int touches[3] = {0, 0, 0};
};

}  // namespace

CheckResult check_part_setpoints(const MeasurementSet& set, const MachineConfig& machine) {
  CheckResult result = detail::result_for(set);

  // Step 0: usable config and input.
  if (auto why = detail::why_not_a_set_of(set, CheckKind::PartSetPoints, "the set-point check")) {
    return detail::invalid(result, *why);
  }
  if (machine.setpoints.points.empty()) {
    return detail::invalid(result, machine_where(machine) +
                                       ": setpoints.points is empty: the machine has no set "
                                       "points to check");
  }
  if (auto why = detail::why_probe_unusable(machine)) return detail::invalid(result, *why);
  if (auto why = detail::why_tolerances_missing(machine, {kMaxDeviation}, "the set-point check")) {
    return detail::invalid(result, *why);
  }
  if (set.touches.empty()) {
    return detail::invalid(result,
                           "MeasurementSet.touches is empty: the set-point check needs "
                           "an x, y and z touch of every set point");
  }

  // Step 1: contact points, filed by set point and axis.
  std::map<std::string, Measured> measured;
  for (const auto& point : machine.setpoints.points) measured[point.name];
  for (std::size_t i = 0; i < set.touches.size(); ++i) {
    const Touch& t = set.touches[i];
    if (auto why = detail::why_touch_not_finite(t, i)) return detail::invalid(result, *why);
    const std::string& f = t.feature;
    const std::size_t last = f.rfind(':');
    const bool shaped = f.rfind(kFeaturePrefix, 0) == 0 && last != std::string::npos &&
                        last > kFeaturePrefix.size() && last + 2 == f.size() &&
                        (f.back() == 'x' || f.back() == 'y' || f.back() == 'z');
    if (!shaped) {
      return detail::invalid(result, touch_field(i, "feature") + " = '" + f +
                                         "': expected 'setpoint:<name>:x', ':y' or ':z'");
    }
    const std::string name = f.substr(kFeaturePrefix.size(), last - kFeaturePrefix.size());
    auto it = measured.find(name);
    if (it == measured.end()) {
      return detail::invalid(result, touch_field(i, "feature") + " = '" + f + "': '" + name +
                                         "' is not a set point of " + machine_where(machine));
    }
    const int axis = f.back() - 'x';
    if (!detail::head_at(t.axes, 0, 0)) {
      return detail::invalid(result,
                             touch_field(i, "axes") + ": head at " + detail::describe_head(t.axes) +
                                 ": set points are probed with the head at home (A = C = 0)");
    }
    if ((t.approach - approach_of(axis)).norm() > 4 * detail::kHeadAngleTolerance) {
      return detail::invalid(
          result, touch_field(i, "approach") + " = " + format_vector(t.approach) + ": a '" + f +
                      "' touch approaches along " + format_vector(approach_of(axis)));
    }
    if (it->second.touches[axis]++ > 0) {
      return detail::invalid(
          result, touch_field(i, "feature") + " = '" + f + "': a second touch of the same face");
    }
    const Eigen::Vector3d p = detail::contact_point(stylus_ball_centre(t.axes, machine.probe),
                                                    t.approach, machine.probe.ball_radius_mm);
    it->second.corner[axis] = p[axis];
  }
  for (const auto& point : machine.setpoints.points) {
    const Measured& m = measured[point.name];
    for (int axis = 0; axis < 3; ++axis) {
      if (m.touches[axis] == 0) {
        return detail::invalid(result, "MeasurementSet.touches: no 'setpoint:" + point.name + ":" +
                                           std::string(1, static_cast<char>('x' + axis)) +
                                           "' touch; every set point needs x, y and z");
      }
    }
  }

  // Step 2: deviations from the intended corners.
  const Tolerance& max_band = *detail::find_tolerance(machine, kMaxDeviation);
  const Tolerance axis_band{-max_band.upper, max_band.upper};
  double largest = 0;
  Eigen::Vector3d primary = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < machine.setpoints.points.size(); ++k) {
    const SetPointConfig& point = machine.setpoints.points[k];
    const Eigen::Vector3d d = measured[point.name].corner - point.intended_mm;
    if (k == 0) primary = d;
    for (int axis = 0; axis < 3; ++axis) {
      result.metrics.push_back(detail::judged_metric(
          axis_metric(point.name, static_cast<char>('x' + axis)), d[axis], "mm", axis_band));
    }
    result.metrics.push_back(
        detail::judged_metric(deviation_metric(point.name), d.norm(), "mm", max_band));
    largest = std::max(largest, d.norm());
  }
  result.metrics.push_back(detail::judged_metric(kMaxDeviation, largest, "mm", max_band));

  // Step 3: verdict. A part that does not sit where intended is most often just badly seated;
  // a block that moved, or a fixture out of position, are the next suspects.
  detail::decide_verdict(result, {std::string(kCauseSeating), std::string(kCauseBlockMoved),
                                  std::string(kCauseFixture)});
  if (result.verdict == Verdict::Pass) {
    Correction zero;
    zero.target = std::string(kWorkOffsetTarget) + machine.machine_id;
    zero.offsets = {
        {"dx_mm", primary.x(), "mm"}, {"dy_mm", primary.y(), "mm"}, {"dz_mm", primary.z(), "mm"}};
    result.correction = zero;
  }
  return result;
}

}  // namespace ncqual::solver

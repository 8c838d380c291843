// SPDX-License-Identifier: Apache-2.0
// Daily probe checks 1, 2 and 4 against the monument. Each follows its procedure in the patent:
//   0. make sure the touches (head orientations, surfaces, approach) and the config can support
//      a verdict;
//   1. turn each touch's latched readouts into a stylus ball centre (nominal kinematics) and the
//      point where the ball met the surface;
//   2. measure the monument feature at each head orientation;
//   3. derive the error from the disagreement between the orientations;
//   4. verdict and likely causes in the order to investigate them.
#include "ncqual/solver/monument_probe_checks.hpp"

#include "ncqual/common/kinematics.hpp"
#include "ncqual/solver/circle_fit.hpp"
#include "ncqual/common/units.hpp"
#include "result_building.hpp"
#include "touch_input.hpp"

#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace ncqual::solver {
namespace {

using detail::find_tolerance;
using detail::format_number;
using detail::format_vector;
using detail::machine_where;
using detail::touch_field;
using units::kPi;

// A unit vector is "along" an expected axis when it differs from it by at most this (about the
// head angle tolerance, with room for rounding in the rotation).
constexpr double kDirectionTolerance = 4 * detail::kHeadAngleTolerance;

bool along(const Eigen::Vector3d& v, const Eigen::Vector3d& expected) {
  return (v - expected).norm() <= kDirectionTolerance;
}

std::string quoted(std::string_view s) { return "'" + std::string(s) + "'"; }

double mean(const std::vector<double>& values) {
  double sum = 0;
  for (double v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

// The gauge's vertical edges are gauge_width_mm apart; checks 2 and 4 need that width.
std::optional<std::string> why_gauge_unusable(const MachineConfig& m, std::string_view check) {
  const double w = m.monument.gauge_width_mm;
  if (!std::isfinite(w) || w <= 0) {
    return machine_where(m) + ": monument.gauge_width_mm = " + format_number(w) + ": " +
           std::string(check) + " needs the gauge's known width (a positive length)";
  }
  return std::nullopt;
}

// ============================================================================================
// Probe check 1: probe alignment with the C axis
// ============================================================================================

struct HoleEdgeTouches {
  std::vector<Eigen::Vector2d> rough;  // ball centres (XY) with the head at C = 0
  std::vector<std::size_t> rough_index;
  std::vector<Eigen::Vector2d> fine;  // with the head at C = 180 deg
  std::vector<std::size_t> fine_index;
};

// Step 0 and 1: every touch a horizontal hole-edge touch at A = 0 with C = 0 or 180 deg;
// its ball centre from the nominal kinematics.
std::optional<std::string> sort_c_alignment_touches(const MeasurementSet& set,
                                                    const ProbeGeometry& probe,
                                                    HoleEdgeTouches* out) {
  using namespace c_alignment;
  if (set.touches.empty()) {
    return "MeasurementSet.touches is empty: check 1 needs '" + std::string(kHoleEdge) +
           "' touches at C = 0 and C = 180 deg";
  }
  for (std::size_t i = 0; i < set.touches.size(); ++i) {
    const Touch& t = set.touches[i];
    if (auto why = detail::why_touch_not_finite(t, i)) return why;
    if (t.feature != kHoleEdge) {
      return touch_field(i, "feature") + " = '" + t.feature + "': check 1 uses only '" +
             std::string(kHoleEdge) + "' touches";
    }
    if (std::abs(t.approach.z()) > detail::kUnitTolerance) {
      return touch_field(i, "approach") + " = " + format_vector(t.approach) +
             ": a hole-edge touch must approach horizontally";
    }
    const Eigen::Vector2d xy = stylus_ball_centre(t.axes, probe).head<2>();
    if (detail::head_at(t.axes, 0, 0)) {
      out->rough.push_back(xy);
      out->rough_index.push_back(i);
    } else if (detail::head_at(t.axes, 0, kPi)) {
      out->fine.push_back(xy);
      out->fine_index.push_back(i);
    } else {
      return touch_field(i, "axes") + ": head at " + detail::describe_head(t.axes) +
             ": check 1 takes its touches at A = 0 with C = 0 or C = 180 deg";
    }
  }
  for (const auto& [count, head] :
       {std::pair{out->rough.size(), "C = 0"}, std::pair{out->fine.size(), "C = 180 deg"}}) {
    if (count < 3) {
      return "MeasurementSet.touches: " + std::to_string(count) + " '" + std::string(kHoleEdge) +
             "' touches with the head at " + head + ", check 1 needs at least 3";
    }
  }
  return std::nullopt;
}

struct HoleCentre {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double consistency_mm = 0;  // largest leave-one-out disagreement; 0 with three touches
};

// Step 2: the hole centre seen at one head angle. Ball centres touching the bore from inside
// lie on a circle of radius D/2 - r about the hole axis: three touches fix it. Each further
// touch is a check: the distance of a touch from the circle through the others.
std::optional<std::string> measure_hole_centre(const std::vector<Eigen::Vector2d>& xy,
                                               const std::vector<std::size_t>& index,
                                               const char* head, const MachineConfig& m,
                                               HoleCentre* out) {
  using namespace c_alignment;
  const CircleFit circle = fit_circle(xy);
  if (!circle.ok()) {
    return "MeasurementSet.touches: the hole-edge touches at " + std::string(head) +
           " give no circle: " + circle.error;
  }
  const double expected = m.monument.hole_diameter_mm / 2 - m.probe.ball_radius_mm;
  const double limit = std::min(1.0, 0.1 * expected);
  if (!(std::abs(circle.radius - expected) <= limit)) {
    return "MeasurementSet.touches: the hole-edge ball centres at " + std::string(head) +
           " lie on a circle of radius " + format_number(circle.radius) +
           " mm, expected hole_diameter_mm/2 - ball_radius_mm = " + format_number(expected) +
           " mm (limit " + format_number(limit) + " mm): the touches missed the hole edge";
  }
  out->centre = circle.centre;
  out->consistency_mm = 0;
  // With four or more touches, each is checked against the circle through the others. One
  // redundant touch detects a bad touch but cannot say which one it was (with four, every
  // leave-one-out disagreement is the same size), so a gross one voids the whole head angle.
  std::size_t worst = 0;
  for (std::size_t k = 0; xy.size() >= 4 && k < xy.size(); ++k) {
    std::vector<Eigen::Vector2d> others;
    for (std::size_t j = 0; j < xy.size(); ++j) {
      if (j != k) others.push_back(xy[j]);
    }
    const CircleFit without = fit_circle(others);
    if (!without.ok()) continue;  // e.g. the others collinear: no check from this touch
    const double off = std::abs((xy[k] - without.centre).norm() - without.radius);
    if (off > out->consistency_mm) {
      out->consistency_mm = off;
      worst = k;
    }
  }
  if (out->consistency_mm > kGrossInconsistencyMm) {
    return "MeasurementSet.touches: the hole-edge touches at " + std::string(head) +
           " disagree: touches[" + std::to_string(index[worst]) + "] lies " +
           format_number(out->consistency_mm) + " mm from the circle through the others (limit " +
           format_number(kGrossInconsistencyMm) + " mm): one of them did not land on the hole edge";
  }
  return std::nullopt;
}

}  // namespace

CheckResult check_c_axis_alignment(const MeasurementSet& set, const MachineConfig& machine) {
  using namespace c_alignment;
  CheckResult result = detail::result_for(set);

  // Step 0: usable input and config.
  if (auto why = detail::why_not_a_set_of(set, CheckKind::MonumentCAlignment, "check 1")) {
    return detail::invalid(result, *why);
  }
  if (auto why = detail::why_probe_unusable(machine)) return detail::invalid(result, *why);
  const double d = machine.monument.hole_diameter_mm;
  if (!std::isfinite(d) || d <= 2 * machine.probe.ball_radius_mm) {
    return detail::invalid(result, machine_where(machine) + ": monument.hole_diameter_mm = " +
                                       format_number(d) + " must exceed the stylus ball diameter");
  }
  if (auto why = detail::why_tolerances_missing(machine, {kDx, kDy, kOffset}, "check 1")) {
    return detail::invalid(result, *why);
  }

  // Step 1: ball centres, sorted by head angle.
  HoleEdgeTouches touches;
  if (auto why = sort_c_alignment_touches(set, machine.probe, &touches)) {
    return detail::invalid(result, *why);
  }

  // Step 2: rough centre (head at 0 deg) and fine centre (head at 180 deg).
  HoleCentre rough, fine;
  if (auto why =
          measure_hole_centre(touches.rough, touches.rough_index, "C = 0", machine, &rough)) {
    return detail::invalid(result, *why);
  }
  if (auto why =
          measure_hole_centre(touches.fine, touches.fine_index, "C = 180 deg", machine, &fine)) {
    return detail::invalid(result, *why);
  }

  // Step 3: the ball's offset from the C axis is half the distance between the two centres.
  const Eigen::Vector2d offset = (fine.centre - rough.centre) / 2;
  result.metrics.push_back(
      detail::judged_metric(kDx, offset.x(), "mm", *find_tolerance(machine, kDx)));
  result.metrics.push_back(
      detail::judged_metric(kDy, offset.y(), "mm", *find_tolerance(machine, kDy)));
  result.metrics.push_back(
      detail::judged_metric(kOffset, offset.norm(), "mm", *find_tolerance(machine, kOffset)));
  if (const Tolerance* band = find_tolerance(machine, kConsistency)) {
    result.metrics.push_back(detail::judged_metric(
        kConsistency, std::max(rough.consistency_mm, fine.consistency_mm), "mm", *band));
  }

  // Step 4: verdict. The stylus itself is the likeliest and cheapest to look at, then the
  // probe's switches, then the wrist.
  detail::decide_verdict(result, {std::string(kCauseBentStylus), std::string(kCauseProbeSwitches),
                                  std::string(kCauseAHome), std::string(kCauseANotPerpendicular)});
  return result;
}

// ============================================================================================
// Probe check 2: composite tool length
// ============================================================================================

CheckResult check_composite_tool_length(const MeasurementSet& set, const MachineConfig& machine) {
  using namespace tool_length;
  CheckResult result = detail::result_for(set);

  // Step 0: usable input and config.
  if (auto why = detail::why_not_a_set_of(set, CheckKind::MonumentToolLength, "check 2")) {
    return detail::invalid(result, *why);
  }
  if (auto why = detail::why_probe_unusable(machine)) return detail::invalid(result, *why);
  if (auto why = why_gauge_unusable(machine, "check 2")) return detail::invalid(result, *why);
  if (auto why = detail::why_tolerances_missing(machine, {kError}, "check 2")) {
    return detail::invalid(result, *why);
  }
  if (set.touches.empty()) {
    return detail::invalid(result, "MeasurementSet.touches is empty: check 2 needs one '" +
                                       std::string(kEdgePlusX) + "' and one '" +
                                       std::string(kEdgeMinusX) + "' touch");
  }

  // Step 1: contact points. The +X edge is met by the probe pointing along -X (A = +90 deg,
  // C = 90 deg) moving along -X; the -X edge by the probe pointing along +X moving along +X.
  std::vector<double> x_plus, x_minus;
  const double r = machine.probe.ball_radius_mm;
  for (std::size_t i = 0; i < set.touches.size(); ++i) {
    const Touch& t = set.touches[i];
    if (auto why = detail::why_touch_not_finite(t, i)) return detail::invalid(result, *why);
    const bool plus = t.feature == kEdgePlusX;
    if (!plus && t.feature != kEdgeMinusX) {
      return detail::invalid(result, touch_field(i, "feature") + " = '" + t.feature +
                                         "': check 2 uses only " + quoted(kEdgePlusX) + " and " +
                                         quoted(kEdgeMinusX) + " touches");
    }
    const Eigen::Vector3d along_x(plus ? -1.0 : 1.0, 0.0, 0.0);
    if (!along(t.approach, along_x)) {
      return detail::invalid(result, touch_field(i, "approach") + " = " +
                                         format_vector(t.approach) + ": a '" + t.feature +
                                         "' touch must approach along " + format_vector(along_x));
    }
    const Eigen::Vector3d tool = tool_direction(t.axes.a_rad, t.axes.c_rad);
    if (!along(tool, along_x)) {
      return detail::invalid(
          result, touch_field(i, "axes") + ": head at " + detail::describe_head(t.axes) +
                      " points the probe along " + format_vector(tool) + "; a '" + t.feature +
                      "' touch needs it along " + format_vector(along_x) +
                      " (C = 90 deg, A = " + (plus ? "+" : "-") + "90 deg)");
    }
    const Eigen::Vector3d p =
        detail::contact_point(stylus_ball_centre(t.axes, machine.probe), t.approach, r);
    (plus ? x_plus : x_minus).push_back(p.x());
  }
  if (x_plus.empty() || x_minus.empty()) {
    return detail::invalid(result, "MeasurementSet.touches: " + std::to_string(x_plus.size()) +
                                       " " + quoted(kEdgePlusX) + " and " +
                                       std::to_string(x_minus.size()) + " " + quoted(kEdgeMinusX) +
                                       " touches; check 2 needs at least one of each");
  }

  // Step 2: the gauge width as the probe sees it with the nominal tool length.
  const double seen_width = mean(x_plus) - mean(x_minus);

  // Step 3: each touch puts the tip L' - L further out than the nominal kinematics assume,
  // so the gauge looks 2 (L' - L) wider than it is.
  const double length_error = (seen_width - machine.monument.gauge_width_mm) / 2;
  const double nominal = machine.probe.tool_length_mm;
  const Tolerance& error_band = *find_tolerance(machine, kError);
  const Tolerance* length_band = find_tolerance(machine, kLength);
  const Tolerance derived{nominal + error_band.lower, nominal + error_band.upper};
  result.metrics.push_back(detail::judged_metric(kLength, nominal + length_error, "mm",
                                                 length_band ? *length_band : derived));
  result.metrics.push_back(detail::judged_metric(kError, length_error, "mm", error_band));

  // Step 4: verdict. The patent's three parts that make up the length, outermost first.
  detail::decide_verdict(
      result, {std::string(kCauseBody), std::string(kCauseWServo), std::string(kCauseProbe)});
  return result;
}

// ============================================================================================
// Probe check 4: C-axis rotational accuracy
// ============================================================================================

CheckResult check_c_rotation(const MeasurementSet& set, const MachineConfig& machine) {
  using namespace c_rotation;
  CheckResult result = detail::result_for(set);

  // Step 0: usable input and config.
  if (auto why = detail::why_not_a_set_of(set, CheckKind::MonumentCRotation, "check 4")) {
    return detail::invalid(result, *why);
  }
  if (auto why = detail::why_probe_unusable(machine)) return detail::invalid(result, *why);
  if (auto why = why_gauge_unusable(machine, "check 4")) return detail::invalid(result, *why);
  const double length = machine.probe.tool_length_mm;
  if (!(length > 0)) {
    return detail::invalid(result, machine_where(machine) + ": probe.tool_length_mm = " +
                                       format_number(length) + ": check 4 needs a positive length");
  }
  if (auto why = detail::why_tolerances_missing(machine, {kAngleError}, "check 4")) {
    return detail::invalid(result, *why);
  }
  if (set.touches.empty()) {
    return detail::invalid(result, "MeasurementSet.touches is empty: check 4 needs two '" +
                                       std::string(kEdgePlusY) + "' touches");
  }

  // Step 1: contact points on the upper edge, split by where the probe pointed.
  std::vector<double> y_probe_minus_x, y_probe_plus_x;
  const double r = machine.probe.ball_radius_mm;
  for (std::size_t i = 0; i < set.touches.size(); ++i) {
    const Touch& t = set.touches[i];
    if (auto why = detail::why_touch_not_finite(t, i)) return detail::invalid(result, *why);
    if (t.feature != kEdgePlusY) {
      return detail::invalid(result, touch_field(i, "feature") + " = '" + t.feature +
                                         "': check 4 uses only " + quoted(kEdgePlusY) + " touches");
    }
    if (!along(t.approach, -Eigen::Vector3d::UnitY())) {
      return detail::invalid(result, touch_field(i, "approach") + " = " +
                                         format_vector(t.approach) +
                                         ": the upper edge is touched along (0, -1, 0)");
    }
    const Eigen::Vector3d tool = tool_direction(t.axes.a_rad, t.axes.c_rad);
    const bool minus_x = along(tool, -Eigen::Vector3d::UnitX());
    if (!minus_x && !along(tool, Eigen::Vector3d::UnitX())) {
      return detail::invalid(result, touch_field(i, "axes") + ": head at " +
                                         detail::describe_head(t.axes) +
                                         " points the probe along " + format_vector(tool) +
                                         "; check 4 needs it along -X or +X (C = 90 deg, "
                                         "A = +90 or -90 deg)");
    }
    const Eigen::Vector3d p =
        detail::contact_point(stylus_ball_centre(t.axes, machine.probe), t.approach, r);
    (minus_x ? y_probe_minus_x : y_probe_plus_x).push_back(p.y());
  }
  if (y_probe_minus_x.empty() || y_probe_plus_x.empty()) {
    return detail::invalid(result,
                           "MeasurementSet.touches: " + std::to_string(y_probe_minus_x.size()) +
                               " touches with the probe along -X and " +
                               std::to_string(y_probe_plus_x.size()) +
                               " along +X; check 4 needs at least one of each");
  }

  // Step 2 and 3: the edge seen from both sides; half the difference over L is sin e.
  const double difference = mean(y_probe_minus_x) - mean(y_probe_plus_x);
  const double sine = difference / (2 * length);
  if (!(std::abs(sine) <= 1)) {
    return detail::invalid(result,
                           "MeasurementSet.touches: the upper edge seen with the probe "
                           "along -X and +X differs by " +
                               format_number(difference) +
                               " mm, more than 2 L = " + format_number(2 * length) + " mm");
  }
  const double angle_error = std::asin(sine);
  result.metrics.push_back(detail::judged_metric(kAngleError, units::rad_to_arcsec(angle_error),
                                                 "arcsec", *find_tolerance(machine, kAngleError)));

  // Step 4: verdict.
  detail::decide_verdict(result, {std::string(kCauseCRotation)});
  return result;
}

}  // namespace ncqual::solver

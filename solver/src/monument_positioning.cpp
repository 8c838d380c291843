// SPDX-License-Identifier: Apache-2.0
// Probe check 3, repeatable X, Y, Z positioning against the monument. The code follows the
// procedure of the patent (probe check number 3):
//   0. make sure the touches and the taught monument can support a verdict;
//   1. turn each touch's latched axis readouts into a stylus ball centre (nominal kinematics);
//   2. measured hole centre: circle through the ball centres of the hole-edge touches;
//   3. measured face Z: ball centre of the face touch less the ball radius;
//   4. compare both with the taught hole centre and face;
//   5. verdict, likely causes in the order to investigate, reason.
#include "ncqual/solver/monument_positioning.hpp"

#include "ncqual/common/kinematics.hpp"
#include "ncqual/solver/circle_fit.hpp"
#include "result_building.hpp"
#include "touch_input.hpp"

#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace ncqual::solver {
namespace {

using namespace positioning;
using detail::format_number;
using detail::format_vector;
using detail::machine_where;
using detail::touch_field;

// ---- Step 0: can the input support a verdict? ---------------------------------------------

std::optional<std::string> why_touch_unusable(const Touch& t, std::size_t i) {
  if (auto why = detail::why_touch_not_finite(t, i)) return why;
  if (t.feature != kHoleEdge && t.feature != kFace) {
    return touch_field(i, "feature") + " = '" + t.feature + "': check 3 uses only '" +
           std::string(kHoleEdge) + "' and '" + std::string(kFace) + "' touches";
  }
  // Face Z = ball centre z - ball radius holds only when the ball comes down onto the face.
  if (t.feature == kFace && t.approach.z() > -(1 - kUnitTolerance)) {
    return touch_field(i, "approach") + " = " + format_vector(t.approach) +
           ": a 'face' touch must approach along -Z (0, 0, -1)";
  }
  return std::nullopt;
}

// All touches must be taken at one head angle: the hole centre and the face are compared with
// values taught at one head orientation, and mixing orientations mixes in the probe's errors.
std::optional<std::string> why_head_angles_differ(const std::vector<Touch>& touches) {
  const AxisPosition& first = touches.front().axes;
  for (std::size_t i = 1; i < touches.size(); ++i) {
    const AxisPosition& axes = touches[i].axes;
    if (!detail::head_at(axes, first.a_rad, first.c_rad)) {
      return touch_field(i, "axes") + ": head at " + detail::describe_head(axes) +
             " differs from touches[0] (" + detail::describe_head(first) + ") by more than " +
             format_number(kHeadAngleTolerance) +
             " rad; check 3 needs every touch at one head angle";
    }
  }
  return std::nullopt;
}

std::size_t count_feature(const std::vector<Touch>& touches, std::string_view feature) {
  std::size_t n = 0;
  for (const auto& t : touches) n += t.feature == feature ? 1 : 0;
  return n;
}

std::optional<std::string> why_set_unusable(const MeasurementSet& set) {
  if (auto why = detail::why_not_a_set_of(set, CheckKind::MonumentPositioning, "check 3")) {
    return why;
  }
  if (set.touches.empty()) {
    return "MeasurementSet.touches is empty: check 3 needs '" + std::string(kHoleEdge) + "' and '" +
           std::string(kFace) + "' touches";
  }
  for (std::size_t i = 0; i < set.touches.size(); ++i) {
    if (auto why = why_touch_unusable(set.touches[i], i)) return why;
  }
  if (auto why = why_head_angles_differ(set.touches)) return why;
  const std::size_t edges = count_feature(set.touches, kHoleEdge);
  if (edges < 3) {
    return "MeasurementSet.touches: " + std::to_string(edges) + " '" + std::string(kHoleEdge) +
           "' touches, check 3 needs at least 3";
  }
  const std::size_t faces = count_feature(set.touches, kFace);
  if (faces < 1) {
    return "MeasurementSet.touches: 0 '" + std::string(kFace) +
           "' touches, check 3 needs at least 1";
  }
  return std::nullopt;
}

std::optional<std::string> why_config_unusable(const MachineConfig& m) {
  const MonumentConfig& mon = m.monument;
  if (auto why = detail::why_probe_unusable(m)) return why;
  const std::string where = machine_where(m) + ": ";
  if (!std::isfinite(mon.hole_diameter_mm) || mon.hole_diameter_mm <= 0) {
    return where + "monument.hole_diameter_mm = " + format_number(mon.hole_diameter_mm) +
           " must be positive";
  }
  if (mon.hole_diameter_mm <= 2 * m.probe.ball_radius_mm) {
    return where + "monument.hole_diameter_mm = " + format_number(mon.hole_diameter_mm) +
           " does not exceed the stylus ball diameter " +
           format_number(2 * m.probe.ball_radius_mm) +
           " (probe.ball_radius_mm = " + format_number(m.probe.ball_radius_mm) + ")";
  }
  if (!mon.hole_center_mm.allFinite()) {
    return where + "monument.hole_center_mm = (" + format_number(mon.hole_center_mm.x()) + ", " +
           format_number(mon.hole_center_mm.y()) + ") is not finite";
  }
  if (!std::isfinite(mon.face_z_mm)) {
    return where + "monument.face_z_mm = " + format_number(mon.face_z_mm) + " is not finite";
  }
  return std::nullopt;
}

using detail::find_tolerance;

// ---- Step 1: stylus ball centres of the touches --------------------------------------------

// Ball centre of each touch from its latched readouts with the nominal kinematics:
//   b = P + Rz(c) Rx(a) ((ox, oy, 0) - (L + w) e_z)     (see ncqual/common/kinematics.hpp)
struct TouchedBallCentres {
  std::vector<Eigen::Vector3d> hole_edge;
  std::vector<Eigen::Vector3d> face;
};

TouchedBallCentres ball_centres_of_touches(const std::vector<Touch>& touches,
                                           const ProbeGeometry& nominal_probe) {
  TouchedBallCentres centres;
  for (const auto& t : touches) {
    const Eigen::Vector3d b = stylus_ball_centre(t.axes, nominal_probe);
    (t.feature == kHoleEdge ? centres.hole_edge : centres.face).push_back(b);
  }
  return centres;
}

// ---- Step 2: measured hole centre ----------------------------------------------------------

// The hole is a vertical cylinder of radius R_h = D/2. A ball of radius r_b touching its wall
// from inside has its centre at horizontal distance R_h - r_b from the hole axis, so the XY of
// the ball centres lie on a circle of that radius about the hole centre: fit it.
struct MeasuredHole {
  CircleFit circle;
  std::string error;  // non-empty when the touches do not give a credible hole
};

double nominal_ball_circle_radius(const MachineConfig& m) {
  return m.monument.hole_diameter_mm / 2 - m.probe.ball_radius_mm;
}

MeasuredHole measure_hole_centre(const std::vector<Eigen::Vector3d>& edge_ball_centres,
                                 const MachineConfig& m) {
  std::vector<Eigen::Vector2d> xy;
  xy.reserve(edge_ball_centres.size());
  for (const auto& b : edge_ball_centres) xy.push_back(b.head<2>());
  MeasuredHole hole;
  hole.circle = fit_circle(xy);
  if (!hole.circle.ok()) {
    hole.error = "MeasurementSet.touches: the '" + std::string(kHoleEdge) +
                 "' touches give no circle: " + hole.circle.error;
    return hole;
  }
  // A circle far from the expected size means the touches did not land on the hole's wall.
  const double expected = nominal_ball_circle_radius(m);
  const double limit = std::min(kRadiusOffLimitMm, kRadiusOffLimitFraction * expected);
  const double off = hole.circle.radius - expected;
  if (!(std::abs(off) <= limit)) {
    hole.error =
        "MeasurementSet.touches: the '" + std::string(kHoleEdge) +
        "' ball centres lie on a circle of radius " + format_number(hole.circle.radius) + " mm, " +
        format_number(off) +
        " mm from the expected hole_diameter_mm/2 - ball_radius_mm = " + format_number(expected) +
        " mm (limit " + format_number(limit) + " mm): the touches missed the hole edge";
  }
  return hole;
}

// ---- Step 3: measured face Z ---------------------------------------------------------------

// A ball coming down along -Z onto a face parallel to XY touches it with its lowest point:
//   z_face = z_ball - r_b,  averaged over the face touches.
double measure_face_z(const std::vector<Eigen::Vector3d>& face_ball_centres, double ball_radius) {
  double sum = 0;
  for (const auto& b : face_ball_centres) sum += b.z() - ball_radius;
  return sum / static_cast<double>(face_ball_centres.size());
}

// ---- Step 4: comparison with the taught monument -------------------------------------------

// Deviations measured - taught (mm):
//   center_dx = x_c - X_taught,  center_dy = y_c - Y_taught,  face_dz = z_face - Z_taught,
//   hole_diameter_error = 2 (r_fit + r_b) - D   (only when a tolerance for it is configured).
std::vector<Metric> compare_with_taught(const MeasuredHole& hole, double face_z,
                                        const MachineConfig& m) {
  const MonumentConfig& taught = m.monument;
  std::vector<Metric> metrics;
  metrics.push_back(detail::judged_metric(kCenterDx,
                                          hole.circle.centre.x() - taught.hole_center_mm.x(), "mm",
                                          *find_tolerance(m, kCenterDx)));
  metrics.push_back(detail::judged_metric(kCenterDy,
                                          hole.circle.centre.y() - taught.hole_center_mm.y(), "mm",
                                          *find_tolerance(m, kCenterDy)));
  metrics.push_back(
      detail::judged_metric(kFaceDz, face_z - taught.face_z_mm, "mm", *find_tolerance(m, kFaceDz)));
  if (const Tolerance* band = find_tolerance(m, kHoleDiameterError)) {
    const double diameter = 2 * (hole.circle.radius + m.probe.ball_radius_mm);
    metrics.push_back(
        detail::judged_metric(kHoleDiameterError, diameter - taught.hole_diameter_mm, "mm", *band));
  }
  return metrics;
}

// ---- Step 5: verdict -----------------------------------------------------------------------

// PASS when every metric is within its band. A failure of the hole centre or the face is traced
// first to the machine (its axes no longer position where they did when the hole was taught),
// then to the monument itself having moved on its pedestal. A wrong hole size alone points at
// the probe instead.
void decide_verdict(CheckResult& result) {
  std::string out_of_band;
  bool position_out = false;
  bool diameter_out = false;
  for (const auto& metric : result.metrics) {
    if (metric.pass) continue;
    if (!out_of_band.empty()) out_of_band += "; ";
    out_of_band += detail::describe_out_of_band(metric);
    (metric.name == kHoleDiameterError ? diameter_out : position_out) = true;
  }
  if (out_of_band.empty()) {
    result.verdict = Verdict::Pass;
    result.reason.clear();
    return;
  }
  result.verdict = Verdict::Fail;
  result.reason = out_of_band;
  result.likely_causes = {std::string(kCauseMachineShifted), std::string(kCauseMonumentShifted)};
  if (diameter_out && !position_out) result.likely_causes.emplace_back(kCauseProbeCalibration);
}

}  // namespace

CheckResult check_repeatable_positioning(const MeasurementSet& set, const MachineConfig& machine) {
  CheckResult result = detail::result_for(set);

  // Step 0: is the input usable?
  if (auto why = why_set_unusable(set)) return detail::invalid(result, *why);
  if (auto why = why_config_unusable(machine)) return detail::invalid(result, *why);
  if (auto why =
          detail::why_tolerances_missing(machine, {kCenterDx, kCenterDy, kFaceDz}, "check 3")) {
    return detail::invalid(result, *why);
  }

  // Step 1: ball centres of the touches.
  const TouchedBallCentres centres = ball_centres_of_touches(set.touches, machine.probe);

  // Step 2: measured hole centre.
  const MeasuredHole hole = measure_hole_centre(centres.hole_edge, machine);
  if (!hole.error.empty()) return detail::invalid(result, hole.error);

  // Step 3: measured face Z.
  const double face_z = measure_face_z(centres.face, machine.probe.ball_radius_mm);

  // Step 4: compare with the taught monument.
  result.metrics = compare_with_taught(hole, face_z, machine);

  // Step 5: verdict and likely causes.
  decide_verdict(result);
  return result;
}

}  // namespace ncqual::solver

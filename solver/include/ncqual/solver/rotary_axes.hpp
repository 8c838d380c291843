// SPDX-License-Identifier: Apache-2.0
// Monthly laser-tracker check, step 3: the W, A and C axes with X, Y, Z fixed.
//
// Patent ("Global Machine Accuracy Check"): "a check of the W, A, and C axes is made with the
// laser tracking unit ... the X, Y, and Z axes of the machine are fixed, and the machine wrist is
// moved through a series of rotations about the A and C axes and translations of the spindle
// along the W axis. The machine is stopped at each of a plurality of points and position
// coordinates of the target are measured ... discrepancies between the measured positions and
// the intended positions of the target are graphically displayed".
//
// The target (tracker reflector) sits in the spindle; its nominal position is
// stylus_ball_centre(commanded, geometry) (ncqual/common/kinematics.hpp) with
// geometry.tool_length_mm = the pivot-to-target distance at W = 0 and geometry.stylus_offset_mm =
// the target's offset off the tool axis in the body frame (ball_radius_mm is not used). Measured
// positions are in the master frame (master_frame.hpp), which stands for the machine frame.
//
// A and C: the target sweeps a circle about the axis. Nominal axis through the pivot
// P = (x, y, z): C along machine +Z, A along Rz(c) +X (the head's own axis). The fit is the
// total-least-squares plane of the measured points (normal oriented like the nominal axis), then
// the geometric least-squares circle of the points projected into it (fit_circle). With
// r_i = measured_i - fitted centre, in the fitted plane:
//   dR_i = |r_i in the plane| - R_nominal                        (mm)
//   dA_i = angle of r_i about the fitted axis (right hand), from the nominal zero direction,
//          - commanded angle, wrapped to (-pi, pi]                (rad)
// The nominal zero direction is the nominal target at the axis angle 0 (the other axes as
// commanded) minus the nominal centre, in the master frame, projected into the fitted plane.
//
// Relation to Wang & Chung eq. (4). They hold the tool tip still while A turns, measure the
// change of the pivot (dXp, dZp) and resolve it, on a circle of radius R, into
//   dR = -(dXp sin A + dZp cos A)       the radial error of the tool tip w.r.t. the centre of
//                                        rotation,
//   dA = -(dXp cos A - dZp sin A) / R   the tangential error divided by R.
// Here the pivot stays still and the tool tip (the target) moves; its error e_i = measured -
// nominal has the opposite sign of their pivot change. Resolved into the radial unit vector
// rho_i and the tangential unit vector tau_i = axis x rho_i, to first order
//   dR_i = e_i . rho_i  and  dA_i = (e_i . tau_i) / R,
// i.e. the same two quantities, signed outward (dR > 0: further from the axis than nominal) and
// in the positive sense of rotation (dA > 0: the axis turned further than commanded). One
// difference: ours are taken about the fitted centre, so the axis location error is reported
// once (centre_offset_mm) instead of showing as a once-per-revolution term in dR_i and dA_i.
// The mean of dR_i is the radius error (a target length or offset error); the mean of dA_i
// is the zero offset of the axis.
//
// W: the target moves along the tool axis d = tool_direction(a, c), the direction of increasing
// W. The fit is the total-least-squares line of the measured points, oriented like d.
//
// Tilt components: the fitted direction n against the nominal k is the rotation vector
// theta = angle(k, n) (k x n)/|k x n| of the smallest rotation taking k to n, given by its
// components (rad, reported in micro-radians) along two reference directions perpendicular to k:
//   C: (machine X, machine Y)                                      - tilt of the C axis from Z
//   A: (Rz(c) Y, machine Z)          - the head's Y (machine Y at C = 0) and the vertical
//   W: (Rz(c) X, Rz(c) Rx(a) Y)      - the body's X and Y (machine X and Y at A = C = 0)
#pragma once

#include "ncqual/common/kinematics.hpp"
#include "ncqual/common/model.hpp"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ncqual::solver {

enum class RotaryAxis { W, A, C };

// "W", "A", "C".
std::string_view rotary_axis_name(RotaryAxis axis);

namespace rotary_axes {
// Fewest points. Three points define a plane and a circle in it exactly (two define the W line),
// leaving nothing to check. With 5, the plane fit and the in-plane circle fit each have 2 points
// more than they need (the W line 3), so that a bad point or a real error shows as a residual
// (dR, dA, axial scatter, straightness) instead of being absorbed by the fit.
inline constexpr int kMinPoints = 5;
// X, Y, Z (mm) and the held axes (mm, rad) must stay within this of the first point's.
inline constexpr double kHeldMm = 1e-6;
inline constexpr double kHeldRad = 1e-6;
// Two commanded angles closer than this (rad, modulo 2 pi), or W closer than kHeldMm, are
// duplicates.
inline constexpr double kSameAngleRad = 1e-6;
// Coverage criterion: the commanded angles must cover at least this arc (rad, 90 degrees),
// coverage = 2 pi - the largest gap between circularly consecutive commanded angles. The
// centre of a short arc is confounded with its radius: the standard error of the centre along
// the arc's symmetry line grows as ~1/arc^2 (about 3.3 sigma/sqrt(n) for 180 degrees, 11 for 90,
// 45 for 45), so below 90 degrees the axis location and dR are not worth reporting.
inline constexpr double kMinArcRad = 1.5707963267948966;
// The nominal target must be at least this far from the axis (mm) for a circle to be seen.
inline constexpr double kMinRadiusMm = 1.0;
// The measured points of a circle must spread by more than kCoincidentMm (rms, mm; no tracker
// resolves a nanometre) and across their best line by more than kMinSpreadRatio of their spread
// along it; else they coincide or are collinear and define no plane.
inline constexpr double kCoincidentMm = 1e-9;
inline constexpr double kMinSpreadRatio = 1e-6;
// The measured W travel must be within this fraction of the commanded travel (see
// master_frame::kMaxScaleDeviation): otherwise wrong unit, wrong points, or no motion.
inline constexpr double kMaxScaleDeviation = 0.1;
}  // namespace rotary_axes

// One tracker reading of the W, A or C check: commanded axes and the target in the master frame.
struct RotaryPoint {
  std::string label;
  AxisPosition commanded;
  Eigen::Vector3d measured_master_mm = Eigen::Vector3d::Zero();
};

struct CirclePointResult {
  std::string label;
  double commanded_rad = 0;                                // commanded angle of the checked axis
  Eigen::Vector3d nominal_mm = Eigen::Vector3d::Zero();    // stylus_ball_centre(commanded)
  Eigen::Vector3d deviation_mm = Eigen::Vector3d::Zero();  // measured - nominal
  double measured_rad = 0;   // angle about the fitted axis from the nominal zero direction
  double dR_mm = 0;          // in-plane distance from the fitted centre - nominal radius
  double dA_rad = 0;         // measured_rad - commanded_rad, wrapped to (-pi, pi]
  double tangential_mm = 0;  // dA_rad * nominal radius
  double axial_mm = 0;       // signed distance from the fitted plane (along the axis)
};

struct RotaryCircleResult {
  RotaryAxis axis = RotaryAxis::C;
  // Nominal: axis direction (unit, master = machine frame), centre on it, radius.
  Eigen::Vector3d nominal_axis_direction = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d nominal_centre_mm = Eigen::Vector3d::Zero();
  double nominal_radius_mm = 0;
  // Fitted: plane normal (oriented like the nominal axis), circle centre, radius.
  Eigen::Vector3d axis_direction = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();
  double radius_mm = 0;
  // Tilt of the fitted axis from the nominal, about tilt_reference_1 and _2 (see the top).
  Eigen::Vector3d tilt_reference_1 = Eigen::Vector3d::UnitX();
  Eigen::Vector3d tilt_reference_2 = Eigen::Vector3d::UnitY();
  Eigen::Vector2d tilt_urad = Eigen::Vector2d::Zero();
  // Axis location error: fitted - nominal centre (mm); its part perpendicular to the nominal
  // axis (the axis is displaced) and its signed part along it (also moved by a target length
  // error when the target is off the pivot along the axis).
  Eigen::Vector3d centre_offset_mm = Eigen::Vector3d::Zero();
  double centre_offset_radial_mm = 0;
  double centre_offset_axial_mm = 0;
  double radius_error_mm = 0;   // fitted - nominal radius
  double arc_coverage_rad = 0;  // the coverage of the commanded angles (see kMinArcRad)
  // Summary of the points.
  double dA_mean_arcsec = 0;   // mean dA: the zero offset of the axis
  double dA_range_arcsec = 0;  // max - min dA
  double dA_max_abs_arcsec = 0;
  double dR_max_abs_mm = 0;
  double axial_max_abs_mm = 0;            // out-of-plane scatter (wobble)
  double circle_rms_mm = 0;               // rms of the in-plane circle fit residuals
  std::vector<CirclePointResult> points;  // in input order
};

struct WPointResult {
  std::string label;
  double commanded_w_mm = 0;
  Eigen::Vector3d nominal_mm = Eigen::Vector3d::Zero();    // stylus_ball_centre(commanded)
  Eigen::Vector3d deviation_mm = Eigen::Vector3d::Zero();  // measured - nominal
  double travel_mm = 0;             // measured displacement along the fitted line from point 0
  double positioning_error_mm = 0;  // travel_mm - (commanded W - commanded W of point 0)
  double distance_mm = 0;           // perpendicular distance from the fitted line
};

struct WAxisResult {
  Eigen::Vector3d nominal_direction = -Eigen::Vector3d::UnitZ();  // tool_direction(a, c)
  Eigen::Vector3d direction = -Eigen::Vector3d::UnitZ();          // fitted, oriented like it
  Eigen::Vector3d tilt_reference_1 = Eigen::Vector3d::UnitX();
  Eigen::Vector3d tilt_reference_2 = Eigen::Vector3d::UnitY();
  Eigen::Vector2d tilt_urad = Eigen::Vector2d::Zero();
  // Least-squares slope of the measured travel against the commanded W, minus 1, um/m.
  double w_scale_um_per_m = 0;
  double straightness_mm = 0;       // largest perpendicular distance from the fitted line
  double positioning_range_mm = 0;  // max - min positioning error (ISO 230-2 style range)
  double positioning_max_abs_mm = 0;
  Eigen::Vector3d mean_deviation_mm = Eigen::Vector3d::Zero();  // mean of measured - nominal
  std::vector<WPointResult> points;  // in input order; point 0 is the reference
};

struct RotaryAxisResult {
  RotaryAxis axis = RotaryAxis::C;
  std::optional<RotaryCircleResult> circle;  // A and C
  std::optional<WAxisResult> w;              // W
};

// The A or C check: circle fit, axis tilt and location, radius error, dR_i and dA_i (see the
// top of this file). All points must hold X, Y, Z and W, and A for the C check or C for the A
// check.
// Refuses (std::invalid_argument naming the field, the point label and the value): axis W;
// fewer than rotary_axes::kMinPoints points; non-finite commanded or measured values; an axis
// that should be held that is not (kHeldMm, kHeldRad); duplicate commanded angles
// (kSameAngleRad); commanded angles covering less than rotary_axes::kMinArcRad; a nominal target
// closer than kMinRadiusMm to the axis; measured points that define no circle (coincident,
// collinear: kCoincidentMm, kMinSpreadRatio).
RotaryCircleResult analyze_circle_axis(RotaryAxis axis, const std::vector<RotaryPoint>& points,
                                       const ProbeGeometry& geometry);

// The W check: line fit, its tilt from the tool axis, positioning error from point 0, scale,
// straightness. All points must hold X, Y, Z, A and C.
// Refuses (std::invalid_argument as above): fewer than kMinPoints points; non-finite values;
// an axis not held; duplicate commanded W (kHeldMm); a measured travel that does not match the
// commanded one (kMaxScaleDeviation).
WAxisResult analyze_w_axis(const std::vector<RotaryPoint>& points, const ProbeGeometry& geometry);

// Dispatches to analyze_circle_axis (A, C) or analyze_w_axis (W); same refusals.
RotaryAxisResult analyze_rotary_axis(RotaryAxis axis, const std::vector<RotaryPoint>& points,
                                     const ProbeGeometry& geometry);

}  // namespace ncqual::solver

// SPDX-License-Identifier: Apache-2.0
// Daily probe checks 1, 2 and 4 against the fixed monument (check 3 is in
// monument_positioning.hpp). They run in the order 1, 2, 3, 4: each isolates one error of the
// probe or the wrist so that the next can trust it.
//
// Patent US 6,909,517, "Probe Check Number 1: C-Axis Alignment", "Number 2: Composite Tool
// Length", "Number 4: C-Axis Rotational Accuracy". All three read touches taken with the head
// in defined orientations and turn the latched axis readouts into stylus ball centres with the
// NOMINAL kinematics (ncqual/common/kinematics.hpp); the error the check looks for is what makes
// touches of one surface disagree between two head orientations.
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/common/model.hpp"

#include <string_view>

namespace ncqual::solver {

namespace c_alignment {
// Metrics (public interface: historian, reports, tolerances in config).
// Offset of the stylus ball from the C axis with the head at C = 0, in machine X and Y:
//   (c_align_dx, c_align_dy) = (fine centre - rough centre) / 2
inline constexpr std::string_view kDx = "c_align_dx_mm";
inline constexpr std::string_view kDy = "c_align_dy_mm";
// Its length: half the distance between the rough and the fine centre.
inline constexpr std::string_view kOffset = "probe_c_offset_mm";
// Reported only when configured: the largest disagreement of one hole-edge touch with the
// circle through the others at the same head angle (the patent's "fourth point as a check").
inline constexpr std::string_view kConsistency = "c_align_consistency_mm";

inline constexpr std::string_view kHoleEdge = "hole_edge";

// Likely causes of a failure, in the order to investigate them.
inline constexpr std::string_view kCauseBentStylus = "bent stylus";
inline constexpr std::string_view kCauseProbeSwitches = "bent microswitches in the probe head";
inline constexpr std::string_view kCauseAHome = "body not at its A home position";
inline constexpr std::string_view kCauseANotPerpendicular = "A axis not perpendicular to C";

// A touch further than this from the circle through the others means it did not land on the
// hole edge (a chip, a missed move): no verdict.
inline constexpr double kGrossInconsistencyMm = 0.1;
}  // namespace c_alignment

namespace tool_length {
inline constexpr std::string_view kLength = "tool_length_mm";       // measured L
inline constexpr std::string_view kError = "tool_length_error_mm";  // measured - nominal L

// The two opposite vertical edges of the gauge, touched with the probe along -X and +X.
inline constexpr std::string_view kEdgePlusX = "gauge_edge_+x";
inline constexpr std::string_view kEdgeMinusX = "gauge_edge_-x";

inline constexpr std::string_view kCauseBody = "body (spindle housing) shifted";
inline constexpr std::string_view kCauseWServo = "W-axis servo drive not at its home position";
inline constexpr std::string_view kCauseProbe = "probe (stylus length or seating in the spindle)";
}  // namespace tool_length

namespace c_rotation {
// Angle by which the head turned about C more than commanded (arc-seconds, true - commanded).
inline constexpr std::string_view kAngleError = "c_angle_error_arcsec";

// The gauge's upper edge (parallel to XZ), touched along -Y with the probe along -X and +X.
inline constexpr std::string_view kEdgePlusY = "gauge_edge_+y";

inline constexpr std::string_view kCauseCRotation = "rotation about C more or less than commanded";
}  // namespace c_rotation

// Probe check 1. Head at A = 0 with C = 0 and C = 180 deg; at each, at least three 'hole_edge'
// touches approaching horizontally. Rough centre: circle through the ball centres at C = 0;
// fine centre: likewise at C = 180 deg. A stylus ball off the C axis by o (machine frame at
// C = 0) shifts the apparent centre by -o at C = 0 and by +o at C = 180 deg, so
//   o = (fine - rough) / 2,  |fine - rough| = 2 |o|.
CheckResult check_c_axis_alignment(const MeasurementSet& set, const MachineConfig& machine);

// Probe check 2. Head at C = 90 deg; one touch of the gauge edge at +X with A = +90 deg (probe
// along -X, approach -X), one of the edge at -X with A = -90 deg (probe along +X, approach +X).
// With nominal L the contact points are x+ = X_a - L - r and x- = X_b + L + r; with the true
// length L' the gauge appears w + 2 (L' - L) wide:
//   L' = L + (x+ - x- - w) / 2
// independent of where the gauge and the machine's X zero are.
CheckResult check_composite_tool_length(const MeasurementSet& set, const MachineConfig& machine);

// Probe check 4. Head at C = 90 deg; the gauge's upper edge touched along -Y once with the
// probe along -X (A = +90 deg) and once along +X (A = -90 deg). If the head turned by e more
// than commanded, the tip moves by e L (z x d) sideways: -e L in Y for the first touch, +e L
// for the second, so the two measured edge positions differ by 2 L sin e:
//   e = asin((y_first - y_second) / (2 L))
CheckResult check_c_rotation(const MeasurementSet& set, const MachineConfig& machine);

}  // namespace ncqual::solver

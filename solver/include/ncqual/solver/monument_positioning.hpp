// SPDX-License-Identifier: Apache-2.0
// Daily probe check 3 against the monument: repeatable X, Y, Z positioning of the machine.
//
// Patent (probe check number 3): "the machine is moved in the X and Y directions to cause the
// tip of the stylus to contact three circumferentially spaced points ... on the edge of the
// hole H in the ring gauge G. From these three points, the X and Y coordinates of the center
// of the hole are calculated ... The measured center is compared to a previously taught
// center of the hole. ... the machine is moved in the Z direction to cause the stylus tip to
// contact a face of the ring gauge that is parallel to the XY plane. The Z position of the
// ring gauge's face is compared to a previously taught Z position for the face."
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/common/model.hpp"

#include <string_view>

namespace ncqual::solver {

namespace positioning {
// Metric names: a public interface (historian columns, reports, tolerances in config).
inline constexpr std::string_view kCenterDx = "center_dx_mm";  // measured - taught hole X
inline constexpr std::string_view kCenterDy = "center_dy_mm";  // measured - taught hole Y
inline constexpr std::string_view kFaceDz = "face_dz_mm";      // measured - taught face Z
// Reported only when the machine config has a tolerance of this name:
// 2 (fitted ball-centre radius + ball radius) - nominal hole diameter.
inline constexpr std::string_view kHoleDiameterError = "hole_diameter_error_mm";

// Touch features the check reads.
inline constexpr std::string_view kHoleEdge = "hole_edge";
inline constexpr std::string_view kFace = "face";

// Likely causes of a failure, in the order to investigate them.
inline constexpr std::string_view kCauseMachineShifted = "machine shifted along its axes";
inline constexpr std::string_view kCauseMonumentShifted = "monument shifted";
// Added after the two above when only the hole diameter is out of tolerance.
inline constexpr std::string_view kCauseProbeCalibration =
    "stylus ball size or probe trigger calibration";

// Touches must share one head angle within this (rad).
inline constexpr double kHeadAngleTolerance = 1e-6;
// An approach vector is a unit vector when | |u| - 1 | is within this.
inline constexpr double kUnitTolerance = 1e-6;
// A fitted ball-centre radius further than min(1 mm, 10 %) from hole radius - ball radius
// means the touches did not land on the hole edge.
inline constexpr double kRadiusOffLimitMm = 1.0;
inline constexpr double kRadiusOffLimitFraction = 0.10;
}  // namespace positioning

// Probe check 3. Reads the touches of `set` (feature "hole_edge": at least 3 on the hole edge;
// feature "face": at least 1, approaching along -Z) with the machine's nominal probe and taught
// monument. Verdict PASS when every metric lies in its tolerance band, FAIL otherwise, INVALID
// (with `reason` naming the field and value) when the data or config cannot support a verdict.
// Never throws for bad measurement data. Fills machine_id, request_id and kind from `set`;
// time_ns is left 0 (solve() stamps it).
CheckResult check_repeatable_positioning(const MeasurementSet& set, const MachineConfig& machine);

}  // namespace ncqual::solver

// SPDX-License-Identifier: Apache-2.0
// The per-part check: probe the primary and secondary set points of the loaded workpiece and
// compare them with their intended positions; only a PASS lets machining proceed.
//
// Patent US 6,909,517: "a series of primary and secondary set points on the workpiece are
// probed to verify that the workpiece is located in the proper location relative to the
// machine ... if the differences between measured and intended positions are within acceptable
// limits, then the machining and unloading of the workpiece proceed"; and the set point block
// "serves as a reference for the machine so that the machine can be calibrated to the
// workpiece": its measured position becomes the zero reference of the part program.
#pragma once

#include "ncqual/common/check_kinds.hpp"
#include "ncqual/common/config.hpp"
#include "ncqual/common/model.hpp"

#include <string>
#include <string_view>

namespace ncqual::solver {

namespace setpoints {
// Metrics. Per set point <name> (machine.setpoints.points): "setpoint_<name>_dx_mm",
// "_dy_mm", "_dz_mm" (measured - intended) and "setpoint_<name>_dev_mm" (the length of that
// deviation); and the largest deviation of any set point:
inline constexpr std::string_view kMaxDeviation = "setpoint_max_dev_mm";
// The per-axis metrics are judged against +-(upper of setpoint_max_dev_mm), the lengths
// against the setpoint_max_dev_mm band itself.

std::string axis_metric(const std::string& point, char axis);  // "setpoint_primary_dx_mm"
std::string deviation_metric(const std::string& point);        // "setpoint_primary_dev_mm"

// Touch features: "setpoint:<name>:x" (approach +X onto the -X face), ":y" (+Y onto -Y),
// ":z" (-Z onto the top face).
inline constexpr std::string_view kFeaturePrefix = "setpoint:";

// On PASS the result carries the zero reference of the part program: a correction with this
// target prefix ("work_offset:<machine_id>") and offsets dx_mm, dy_mm, dz_mm = the deviation of
// the first (primary) set point.
inline constexpr std::string_view kWorkOffsetTarget = kWorkOffsetTargetPrefix;

inline constexpr std::string_view kCauseSeating =
    "part not seated on its locators (unload, clean and reload the part)";
inline constexpr std::string_view kCauseBlockMoved =
    "set-point block moved on its fixturing device";
inline constexpr std::string_view kCauseFixture =
    "fixture out of position (run the weekly fixture pre-calibration)";
}  // namespace setpoints

// The set-point check. Every configured set point must have one touch of each axis; the touch
// positions are contact points p = b + r u from the nominal kinematics. Deviation of a set
// point = (p_x of its x touch, p_y of its y touch, p_z of its z touch) - intended corner.
CheckResult check_part_setpoints(const MeasurementSet& set, const MachineConfig& machine);

}  // namespace ncqual::solver

// SPDX-License-Identifier: Apache-2.0
// Step 0 of every probe check, shared: is a touch usable, does the machine config support the
// check, which tolerances does it need; and the verdict from judged metrics. Internal to the
// solver library.
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/common/model.hpp"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ncqual::solver::detail {

// An approach vector is a unit vector when | |u| - 1 | is within this.
inline constexpr double kUnitTolerance = 1e-6;
// Two head angles are the same when they differ by at most this (rad, about 0.2 arcsec).
inline constexpr double kHeadAngleTolerance = 1e-6;

// "MeasurementSet.touches[3].axes.c_rad"
std::string touch_field(std::size_t i, const std::string& field);

// Finite axis readouts and a finite unit approach vector; else why not, naming the field.
std::optional<std::string> why_touch_not_finite(const Touch& touch, std::size_t i);

// Difference of two angles, wrapped into [-pi, pi].
double angle_difference(double a, double b);

// Whether the head of `axes` is at (a, c) within kHeadAngleTolerance (angles modulo 2 pi).
bool head_at(const AxisPosition& axes, double a_rad, double c_rad);

// "A = 1.5708 rad, C = 0 rad"
std::string describe_head(const AxisPosition& axes);

// MeasurementSet.error and MeasurementSet.kind: the set answers a `check` of kind `expected`.
std::optional<std::string> why_not_a_set_of(const MeasurementSet& set, CheckKind expected,
                                            std::string_view check);

// "machine 'pm1' (deploy/machines/pm1.yaml)"
std::string machine_where(const MachineConfig& m);

// The nominal probe has a finite tool length and stylus offset and a non-negative ball radius.
std::optional<std::string> why_probe_unusable(const MachineConfig& m);

const Tolerance* find_tolerance(const MachineConfig& m, std::string_view metric);

// Every metric in `metrics` has a configured tolerance; else which one is missing.
std::optional<std::string> why_tolerances_missing(const MachineConfig& m,
                                                  const std::vector<std::string_view>& metrics,
                                                  std::string_view check);

// The point where the ball met the surface: its centre moved by the ball radius along the
// direction it was travelling, p = b + r u.
Eigen::Vector3d contact_point(const Eigen::Vector3d& ball_centre, const Eigen::Vector3d& approach,
                              double ball_radius);

// PASS when every metric lies in its band; else FAIL with the out-of-band metrics as reason and
// `causes` (in the order to investigate them) as the likely causes.
void decide_verdict(CheckResult& result, const std::vector<std::string>& causes);

}  // namespace ncqual::solver::detail

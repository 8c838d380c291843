// SPDX-License-Identifier: Apache-2.0
// What the Monte Carlo of the verification's uncertainty (verification_uncertainty.cpp) shares
// with the tracker's part (verification_tracker.cpp; internal to the solver library): the
// refusals of bad input, the checks of the tracker and of what it sees, and the tracker's noise of
// eq. 23-24.
#pragma once

#include "ncqual/solver/verification_uncertainty.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <string>

namespace ncqual::solver::detail {

// std::invalid_argument "<field> = <value>: <why>".
[[noreturn]] void refuse(const std::string& field, const std::string& value,
                         const std::string& why);
// Refuse a value that is not finite; need_sigma: not finite or below 0.
void need_finite(const std::string& field, double v);
void need_finite(const std::string& field, const Eigen::Vector3d& v);
void need_sigma(const std::string& field, double v);
void need_sigma(const std::string& field, const Eigen::Vector3d& v);

// Refuses a tracker model with a pose that is not finite, a negative sigma or no samples.
void check_tracker(const TrackerUncertaintyModel& t);
// "VerificationDesign.points[<i>] ('<label>').<field>", the name of a design point's field.
std::string point_field(std::size_t i, const DesignPoint& p, const std::string& field);
// Refuses a design point at the tracker's position (no direction to measure it along).
void check_tracker_sees(const VerificationDesign& d, const TrackerUncertaintyModel& t);

// Eq. 23-24: the tracker's noise in its spherical coordinates, and what it makes of one point.
struct NoiseScale {
  double range0, range1_per_mm, angle;  // one averaged point
};
NoiseScale noise_scale(const TrackerUncertaintyModel& t);
TrackerPointUncertainty point_uncertainty(const NoiseScale& n,
                                          const Eigen::Matrix3d& machine_from_tracker,
                                          const Eigen::Vector3d& position,
                                          const Eigen::Vector3d& point);

}  // namespace ncqual::solver::detail

// SPDX-License-Identifier: Apache-2.0
// The tracker's part of the verification's uncertainty: what it alone introduces at a point (eq.
// 23-24 of Aguado et al.) and the tracker location that minimises it; with the input checks the
// Monte Carlo (verification_uncertainty.cpp) shares, declared in verification_tracker.hpp.
#include "ncqual/solver/verification_uncertainty.hpp"

#include "result_building.hpp"
#include "verification_tracker.hpp"

#include "ncqual/common/kinematics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace ncqual::solver {

namespace {

using detail::check_tracker;
using detail::check_tracker_sees;
using detail::need_finite;
using detail::need_sigma;
using detail::noise_scale;
using detail::NoiseScale;
using detail::point_field;
using detail::point_uncertainty;
using detail::refuse;
using Eigen::Matrix3d;
using Eigen::Vector3d;

constexpr double kAtTrackerMm = 1e-6;  // a point this close to the tracker has no direction
constexpr double kMaxCandidates = 1e6;

// u_p^2 of eq. 24 for a point at range r, elevation e.
double up_squared(const NoiseScale& n, double r, double e) {
  const double ur = n.range0 + n.range1_per_mm * r;
  const double ce = std::cos(e);
  return ur * ur + r * r * n.angle * n.angle * (1.0 + ce * ce);
}

}  // namespace

namespace detail {

// ----------------------------------------------------------------------------------------------
// Messages

[[noreturn]] void refuse(const std::string& field, const std::string& value,
                         const std::string& why) {
  throw std::invalid_argument(field + " = " + value + ": " + why);
}

void need_finite(const std::string& field, double v) {
  if (!std::isfinite(v)) refuse(field, detail::quote_number(v), "not finite");
}

void need_finite(const std::string& field, const Vector3d& v) {
  if (!v.allFinite()) refuse(field, detail::quote_vector(v), "not finite");
}

void need_sigma(const std::string& field, double v) {
  if (!(std::isfinite(v) && v >= 0))
    refuse(field, detail::quote_number(v), "expected a finite value >= 0");
}

void need_sigma(const std::string& field, const Vector3d& v) {
  if (!v.allFinite() || (v.array() < 0).any())
    refuse(field, detail::quote_vector(v), "expected finite values >= 0");
}

// ----------------------------------------------------------------------------------------------
// Validation

void check_tracker(const TrackerUncertaintyModel& t) {
  need_finite("TrackerUncertaintyModel.position_mm", t.position_mm);
  need_finite("TrackerUncertaintyModel.ypr_rad", t.ypr_rad);
  need_sigma("TrackerUncertaintyModel.angular_sigma_rad", t.angular_sigma_rad);
  need_sigma("TrackerUncertaintyModel.radial_sigma_mm", t.radial_sigma_mm);
  need_sigma("TrackerUncertaintyModel.radial_sigma_mm_per_m", t.radial_sigma_mm_per_m);
  if (t.samples_per_point < 1) {
    refuse("TrackerUncertaintyModel.samples_per_point", std::to_string(t.samples_per_point),
           "expected >= 1");
  }
  need_sigma("TrackerUncertaintyModel.position_sigma_mm", t.position_sigma_mm);
  need_sigma("TrackerUncertaintyModel.orientation_sigma_rad", t.orientation_sigma_rad);
}

std::string point_field(std::size_t i, const DesignPoint& p, const std::string& field) {
  return "VerificationDesign.points[" + std::to_string(i) + "] ('" + p.label + "')." + field;
}

void check_tracker_sees(const VerificationDesign& d, const TrackerUncertaintyModel& t) {
  for (std::size_t i = 0; i < d.points.size(); ++i) {
    const DesignPoint& p = d.points[i];
    if ((p.commanded_mm + p.tool_offset_mm - t.position_mm).norm() < kAtTrackerMm) {
      refuse(point_field(i, p, "commanded_mm + tool_offset_mm"),
             detail::quote_vector(p.commanded_mm + p.tool_offset_mm),
             "at the tracker's position " + detail::quote_vector(t.position_mm) +
                 " (no direction to measure)");
    }
  }
}

// ----------------------------------------------------------------------------------------------
// Eq. 23-24

NoiseScale noise_scale(const TrackerUncertaintyModel& t) {
  const double avg = 1.0 / std::sqrt(static_cast<double>(t.samples_per_point));
  return {t.radial_sigma_mm * avg, t.radial_sigma_mm_per_m / 1000.0 * avg,
          t.angular_sigma_rad * avg};
}

TrackerPointUncertainty point_uncertainty(const NoiseScale& n, const Matrix3d& machine_from_tracker,
                                          const Vector3d& position, const Vector3d& point) {
  const Vector3d local = machine_from_tracker.transpose() * (point - position);
  const Vector3d s = tracker_spherical(local);
  const double r = s[0], a = s[1], e = s[2];
  const double ur = n.range0 + n.range1_per_mm * r;
  // Columns: d(x, y, z) / d(r, azimuth, elevation).
  Matrix3d J;
  J << std::cos(e) * std::cos(a), -r * std::cos(e) * std::sin(a), -r * std::sin(e) * std::cos(a),
      std::cos(e) * std::sin(a), r * std::cos(e) * std::cos(a), -r * std::sin(e) * std::sin(a),
      std::sin(e), 0.0, r * std::cos(e);
  const Vector3d var(ur * ur, n.angle * n.angle, n.angle * n.angle);
  const Matrix3d cov_tracker = J * var.asDiagonal() * J.transpose();
  const Matrix3d cov_machine =
      machine_from_tracker * cov_tracker * machine_from_tracker.transpose();
  TrackerPointUncertainty out;
  out.range_mm = r;
  out.azimuth_rad = a;
  out.elevation_rad = e;
  out.u_tracker_mm = cov_tracker.diagonal().cwiseMax(0.0).cwiseSqrt();
  out.u_machine_mm = cov_machine.diagonal().cwiseMax(0.0).cwiseSqrt();
  out.u_p_mm = std::sqrt(up_squared(n, r, e));
  return out;
}

}  // namespace detail

TrackerPointUncertainty tracker_point_uncertainty(const TrackerUncertaintyModel& tracker,
                                                  const Eigen::Vector3d& point_mm) {
  check_tracker(tracker);
  need_finite("point_mm", point_mm);
  if ((point_mm - tracker.position_mm).norm() < kAtTrackerMm) {
    refuse("point_mm", detail::quote_vector(point_mm),
           "at the tracker's position " + detail::quote_vector(tracker.position_mm));
  }
  return point_uncertainty(noise_scale(tracker), tracker.rotation(), tracker.position_mm, point_mm);
}

TrackerLocationSearch best_tracker_location(const VerificationDesign& design,
                                            const TrackerUncertaintyModel& tracker,
                                            const TrackerRegion& region,
                                            const LocationSearchOptions& options) {
  if (design.points.empty()) {
    throw std::invalid_argument("VerificationDesign.points: empty; a grid of points is needed");
  }
  for (std::size_t i = 0; i < design.points.size(); ++i) {
    need_finite(point_field(i, design.points[i], "commanded_mm"), design.points[i].commanded_mm);
    need_finite(point_field(i, design.points[i], "tool_offset_mm"),
                design.points[i].tool_offset_mm);
  }
  check_tracker(tracker);
  need_finite("TrackerRegion.lo_mm", region.lo_mm);
  need_finite("TrackerRegion.hi_mm", region.hi_mm);
  for (int k = 0; k < 3; ++k) {
    if (region.lo_mm[k] > region.hi_mm[k]) {
      refuse("TrackerRegion.lo_mm[" + std::string(1, "xyz"[k]) + "]",
             detail::quote_number(region.lo_mm[k]),
             "above hi_mm[" + std::string(1, "xyz"[k]) +
                 "] = " + detail::quote_number(region.hi_mm[k]));
    }
    if (region.steps[k] < 1) {
      refuse("TrackerRegion.steps[" + std::string(1, "xyz"[k]) + "]",
             std::to_string(region.steps[k]), "expected >= 1");
    }
  }
  const double grid_size = static_cast<double>(region.steps[0]) * region.steps[1] * region.steps[2];
  if (grid_size > kMaxCandidates) {
    refuse("TrackerRegion.steps",
           "(" + std::to_string(region.steps[0]) + ", " + std::to_string(region.steps[1]) + ", " +
               std::to_string(region.steps[2]) + ")",
           "more than " + detail::quote_number(kMaxCandidates) + " candidates");
  }
  need_sigma("TrackerRegion.envelope_clearance_mm", region.envelope_clearance_mm);
  need_sigma("TrackerRegion.min_range_mm", region.min_range_mm);
  if (!(std::isfinite(region.max_range_mm) && region.max_range_mm > region.min_range_mm)) {
    refuse("TrackerRegion.max_range_mm", detail::quote_number(region.max_range_mm),
           "expected finite and above min_range_mm = " + detail::quote_number(region.min_range_mm));
  }
  if (options.report < 1)
    refuse("LocationSearchOptions.report", std::to_string(options.report), "expected >= 1");

  const std::size_t n = design.points.size();
  std::vector<Vector3d> targets;
  targets.reserve(n);
  Vector3d env_lo = Vector3d::Constant(std::numeric_limits<double>::infinity());
  Vector3d env_hi = -env_lo;
  for (const DesignPoint& p : design.points) {
    targets.push_back(p.commanded_mm + p.tool_offset_mm);
    env_lo = env_lo.cwiseMin(targets.back());
    env_hi = env_hi.cwiseMax(targets.back());
  }
  const Vector3d centre = (env_lo + env_hi) / 2;
  const Vector3d keep_out_lo = env_lo.array() - region.envelope_clearance_mm;
  const Vector3d keep_out_hi = env_hi.array() + region.envelope_clearance_mm;
  const NoiseScale noise = noise_scale(tracker);

  const auto evaluate = [&](const Vector3d& position, const Matrix3d& R, TrackerCandidate& c) {
    double mx = -1, sum = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const Vector3d local = R.transpose() * (targets[i] - position);
      const double r = local.norm();
      const double e = std::asin(std::clamp(local.z() / r, -1.0, 1.0));
      const double u = std::sqrt(up_squared(noise, r, e));
      sum += u;
      if (u > mx) {
        mx = u;
        c.worst_point = static_cast<int>(i);
      }
    }
    c.max_u_mm = mx;
    c.mean_u_mm = sum / static_cast<double>(n);
  };

  TrackerLocationSearch out;
  {
    check_tracker_sees(design, tracker);
    TrackerCandidate given;
    evaluate(tracker.position_mm, tracker.rotation(), given);
    out.given_max_u_mm = given.max_u_mm;
  }
  std::vector<TrackerCandidate> tried;
  const auto coordinate = [&](int axis, int i) {
    const int steps = region.steps[axis];
    if (steps == 1) return (region.lo_mm[axis] + region.hi_mm[axis]) / 2;
    return region.lo_mm[axis] + (region.hi_mm[axis] - region.lo_mm[axis]) * i / (steps - 1);
  };
  for (int iz = 0; iz < region.steps[2]; ++iz) {
    for (int iy = 0; iy < region.steps[1]; ++iy) {
      for (int ix = 0; ix < region.steps[0]; ++ix) {
        const Vector3d position(coordinate(0, ix), coordinate(1, iy), coordinate(2, iz));
        const bool inside = (position.array() >= keep_out_lo.array()).all() &&
                            (position.array() <= keep_out_hi.array()).all();
        bool in_range = true;
        for (const Vector3d& t : targets) {
          const double r = (t - position).norm();
          if (r < region.min_range_mm || r > region.max_range_mm || r < kAtTrackerMm) {
            in_range = false;
            break;
          }
        }
        if (inside || !in_range) {
          ++out.excluded;
          continue;
        }
        TrackerCandidate c;
        c.position_mm = position;
        const Vector3d to_centre = centre - position;
        c.yaw_rad = (std::abs(to_centre.x()) + std::abs(to_centre.y()) > 0)
                        ? std::atan2(to_centre.y(), to_centre.x())
                        : tracker.ypr_rad[0];
        evaluate(position,
                 rotation_from_ypr(Vector3d(c.yaw_rad, tracker.ypr_rad[1], tracker.ypr_rad[2])), c);
        tried.push_back(c);
      }
    }
  }
  out.tried = static_cast<int>(tried.size());
  if (tried.empty()) {
    throw std::invalid_argument(
        "TrackerRegion: all " + std::to_string(out.excluded) +
        " candidate positions are excluded (inside the working envelope " +
        detail::quote_vector(env_lo) + " .. " + detail::quote_vector(env_hi) +
        " grown by envelope_clearance_mm = " + detail::quote_number(region.envelope_clearance_mm) +
        ", or a design point outside min_range_mm = " + detail::quote_number(region.min_range_mm) +
        " .. max_range_mm = " + detail::quote_number(region.max_range_mm) + ")");
  }
  std::stable_sort(tried.begin(), tried.end(),
                   [](const TrackerCandidate& a, const TrackerCandidate& b) {
                     if (a.max_u_mm != b.max_u_mm) return a.max_u_mm < b.max_u_mm;
                     return a.mean_u_mm < b.mean_u_mm;
                   });
  const TrackerCandidate& best = tried.front();
  out.best = tracker;
  out.best.position_mm = best.position_mm;
  out.best.ypr_rad[0] = best.yaw_rad;
  out.max_u_mm = best.max_u_mm;
  out.mean_u_mm = best.mean_u_mm;
  tried.resize(std::min(tried.size(), static_cast<std::size_t>(options.report)));
  out.candidates = std::move(tried);
  return out;
}

}  // namespace ncqual::solver

// SPDX-License-Identifier: Apache-2.0
#include "ncqual/solver/rotary_axes.hpp"

#include "ncqual/common/enum_names.hpp"

#include "ncqual/common/units.hpp"
#include "result_building.hpp"

#include "ncqual/solver/circle_fit.hpp"

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

namespace ncqual::solver {
namespace {

using units::kPi;
constexpr double kArcsecPerRad = 180.0 * 3600.0 / kPi;

// Wraps an angle to (-pi, pi].
double wrap(double a) {
  double w = std::remainder(a, 2 * kPi);
  if (w <= -kPi) w += 2 * kPi;
  return w;
}

// The fields of AxisPosition by name, for the checks of held axes.
struct AxisField {
  const char* name;
  double AxisPosition::*member;
  bool angle;
};
constexpr AxisField kFields[] = {
    {"x_mm", &AxisPosition::x_mm, false},  {"y_mm", &AxisPosition::y_mm, false},
    {"z_mm", &AxisPosition::z_mm, false},  {"w_mm", &AxisPosition::w_mm, false},
    {"a_rad", &AxisPosition::a_rad, true}, {"c_rad", &AxisPosition::c_rad, true},
};

// Checks shared by the circle and W checks: count, finite values, held axes. `moving` is the
// AxisPosition member of the checked axis; every other axis must be held.
void validate_common(const std::string& who, const std::vector<RotaryPoint>& points,
                     const ProbeGeometry& geometry, double AxisPosition::*moving,
                     const std::string& why_count) {
  if (static_cast<int>(points.size()) < rotary_axes::kMinPoints) {
    throw std::invalid_argument(
        who + ": " + std::to_string(points.size()) + " points given; at least " +
        std::to_string(rotary_axes::kMinPoints) + " are needed (" + why_count + ")");
  }
  if (!std::isfinite(geometry.tool_length_mm) || !geometry.stylus_offset_mm.allFinite()) {
    throw std::invalid_argument(
        who + ": geometry.tool_length_mm = " + detail::quote_number(geometry.tool_length_mm) +
        ", stylus_offset_mm = (" + detail::quote_number(geometry.stylus_offset_mm.x()) + ", " +
        detail::quote_number(geometry.stylus_offset_mm.y()) + ") must be finite");
  }
  for (const auto& p : points) {
    for (const auto& f : kFields) {
      if (!std::isfinite(p.commanded.*(f.member))) {
        throw std::invalid_argument(who + ": point '" + p.label + "' commanded." + f.name + " = " +
                                    detail::quote_number(p.commanded.*(f.member)) +
                                    " is not finite");
      }
    }
    if (!p.measured_master_mm.allFinite()) {
      throw std::invalid_argument(who + ": point '" + p.label + "' measured_master_mm = " +
                                  detail::quote_vector(p.measured_master_mm) + " is not finite");
    }
  }
  const RotaryPoint& first = points.front();
  for (const auto& p : points) {
    for (const auto& f : kFields) {
      if (f.member == moving) continue;
      const double diff = p.commanded.*(f.member) - first.commanded.*(f.member);
      const double limit = f.angle ? rotary_axes::kHeldRad : rotary_axes::kHeldMm;
      if (std::abs(diff) > limit) {
        throw std::invalid_argument(who + ": point '" + p.label + "' commanded." + f.name + " = " +
                                    detail::quote_number(p.commanded.*(f.member)) +
                                    " differs from that of the first point '" + first.label +
                                    "' (" + detail::quote_number(first.commanded.*(f.member)) +
                                    ") by " + detail::quote_number(diff) +
                                    ": this check holds every axis but the one it checks");
      }
    }
  }
}

// The rotation vector of the smallest rotation taking unit k to unit n, as components along
// two reference directions perpendicular to k (rad).
Eigen::Vector2d tilt_components(const Eigen::Vector3d& k, const Eigen::Vector3d& n,
                                const Eigen::Vector3d& ref1, const Eigen::Vector3d& ref2) {
  const Eigen::Vector3d cross = k.cross(n);
  const double s = cross.norm();
  if (s == 0) return Eigen::Vector2d::Zero();
  const Eigen::Vector3d theta = std::atan2(s, k.dot(n)) * cross / s;
  return Eigen::Vector2d(theta.dot(ref1), theta.dot(ref2));
}

// Principal axes of the measured points (eigenvalues increasing).
PrincipalAxes scatter_of(const std::vector<RotaryPoint>& points) {
  std::vector<Eigen::Vector3d> measured;
  measured.reserve(points.size());
  for (const auto& p : points) measured.push_back(p.measured_master_mm);
  return principal_axes(measured);
}

}  // namespace

std::string_view rotary_axis_name(RotaryAxis axis) {
  constexpr std::array<std::string_view, 3> kNames = {"W", "A", "C"};
  return name_of(kNames, axis);
}

RotaryCircleResult analyze_circle_axis(RotaryAxis axis, const std::vector<RotaryPoint>& points,
                                       const ProbeGeometry& geometry) {
  const std::string who = "analyze_circle_axis";
  if (axis != RotaryAxis::A && axis != RotaryAxis::C) {
    throw std::invalid_argument(who + ": axis = " + std::string(rotary_axis_name(axis)) +
                                " is not a rotary axis (A or C); use analyze_w_axis");
  }
  double AxisPosition::*moving =
      axis == RotaryAxis::C ? &AxisPosition::c_rad : &AxisPosition::a_rad;
  const std::string moving_name = axis == RotaryAxis::C ? "c_rad" : "a_rad";

  // Step 0: the points are usable.
  validate_common(who, points, geometry, moving,
                  "3 points fit a plane and a circle in it exactly; 5 leave 2 to check each");
  std::vector<std::pair<double, const RotaryPoint*>> angles;
  for (const auto& p : points) {
    double a = std::fmod(p.commanded.*moving, 2 * kPi);
    if (a < 0) a += 2 * kPi;
    angles.emplace_back(a, &p);
  }
  std::stable_sort(angles.begin(), angles.end(),
                   [](const auto& l, const auto& r) { return l.first < r.first; });
  double largest_gap = 0;
  for (std::size_t i = 0; i < angles.size(); ++i) {
    const std::size_t j = (i + 1) % angles.size();
    double gap = angles[j].first - angles[i].first;
    if (j == 0) gap += 2 * kPi;
    if (gap <= rotary_axes::kSameAngleRad || gap >= 2 * kPi - rotary_axes::kSameAngleRad) {
      throw std::invalid_argument(
          who + ": points '" + angles[i].second->label + "' and '" + angles[j].second->label +
          "' have the same commanded." + moving_name + " (" +
          detail::quote_number(angles[i].second->commanded.*moving) + " and " +
          detail::quote_number(angles[j].second->commanded.*moving) +
          ", modulo 2 pi): duplicate angle");
    }
    largest_gap = std::max(largest_gap, gap);
  }
  const double coverage = 2 * kPi - largest_gap;
  if (coverage < rotary_axes::kMinArcRad) {
    throw std::invalid_argument(who + ": the commanded " + moving_name + " cover an arc of " +
                                detail::quote_number(coverage * 180 / kPi) +
                                " degrees (2 pi minus the largest gap between consecutive " +
                                "angles); at least " +
                                detail::quote_number(rotary_axes::kMinArcRad * 180 / kPi) +
                                " are needed to locate the centre of the circle");
  }

  // Step 1: the nominal circle. Axis through the pivot P: C along +Z, A along Rz(c) +X.
  const RotaryPoint& first = points.front();
  const Eigen::Vector3d pivot(first.commanded.x_mm, first.commanded.y_mm, first.commanded.z_mm);
  RotaryCircleResult out;
  out.axis = axis;
  const Eigen::Vector3d k =
      axis == RotaryAxis::C
          ? Eigen::Vector3d::UnitZ()
          : Eigen::Vector3d(std::cos(first.commanded.c_rad), std::sin(first.commanded.c_rad), 0);
  out.nominal_axis_direction = k;
  const Eigen::Vector3d p0 = stylus_ball_centre(first.commanded, geometry) - pivot;
  out.nominal_centre_mm = pivot + p0.dot(k) * k;
  out.nominal_radius_mm = (p0 - p0.dot(k) * k).norm();
  if (!(out.nominal_radius_mm >= rotary_axes::kMinRadiusMm)) {
    throw std::invalid_argument(
        who + ": the nominal target is " + detail::quote_number(out.nominal_radius_mm) +
        " mm from the " + std::string(rotary_axis_name(axis)) +
        " axis (geometry.tool_length_mm = " + detail::quote_number(geometry.tool_length_mm) +
        ", point '" + first.label + "'); at least " +
        detail::quote_number(rotary_axes::kMinRadiusMm) +
        " mm is needed for the target to sweep a circle" +
        (axis == RotaryAxis::C ? " (tilt A or offset the target)" : ""));
  }
  AxisPosition zero = first.commanded;
  zero.*moving = 0;
  const Eigen::Vector3d zero_direction = stylus_ball_centre(zero, geometry) - out.nominal_centre_mm;
  if (axis == RotaryAxis::C) {
    out.tilt_reference_1 = Eigen::Vector3d::UnitX();
    out.tilt_reference_2 = Eigen::Vector3d::UnitY();
  } else {
    out.tilt_reference_1 =
        Eigen::Vector3d(-std::sin(first.commanded.c_rad), std::cos(first.commanded.c_rad), 0);
    out.tilt_reference_2 = Eigen::Vector3d::UnitZ();
  }

  // Step 2: the plane of the measured points (total least squares), normal oriented like k.
  const PrincipalAxes s = scatter_of(points);
  const double count = static_cast<double>(points.size());
  const double rms_along = std::sqrt(std::max(0.0, s.values(2)) / count);
  const double rms_across = std::sqrt(std::max(0.0, s.values(1)) / count);
  if (!(rms_along > rotary_axes::kCoincidentMm) ||
      !(rms_across > rotary_axes::kMinSpreadRatio * rms_along)) {
    throw std::invalid_argument(
        who + ": the measured_master_mm of the " + std::string(rotary_axis_name(axis)) +
        " points " +
        (rms_along > rotary_axes::kCoincidentMm ? "are (nearly) collinear" : "all coincide") +
        " (rms spread " + detail::quote_number(rms_along) + " mm along their line, " +
        detail::quote_number(rms_across) + " mm across it): they define no circle");
  }
  Eigen::Vector3d n = s.vectors.col(0).normalized();
  if (n.dot(k) < 0) n = -n;
  out.axis_direction = n;

  // Step 3: the circle in the plane, in the basis (e1, e2): e1 the nominal zero direction
  // projected into the plane, e2 = n x e1 (so angles from e1 about n are right-handed).
  Eigen::Vector3d e1 = zero_direction - zero_direction.dot(n) * n;
  if (!(e1.norm() > 1e-9 * (1 + zero_direction.norm()))) {
    throw std::invalid_argument(who + ": the fitted plane (normal " + detail::quote_vector(n) +
                                ") is perpendicular to the nominal zero direction " +
                                detail::quote_vector(zero_direction) +
                                ": the measured points are not a circle "
                                "about the " +
                                std::string(rotary_axis_name(axis)) + " axis");
  }
  e1.normalize();
  const Eigen::Vector3d e2 = n.cross(e1);
  std::vector<Eigen::Vector2d> in_plane;
  for (const auto& p : points) {
    const Eigen::Vector3d d = p.measured_master_mm - s.centroid;
    in_plane.emplace_back(d.dot(e1), d.dot(e2));
  }
  const CircleFit circle = fit_circle(in_plane);
  if (!circle.ok()) {
    throw std::invalid_argument(who + ": measured_master_mm of the " +
                                std::string(rotary_axis_name(axis)) + " points: " + circle.error);
  }
  out.centre_mm = s.centroid + circle.centre.x() * e1 + circle.centre.y() * e2;
  out.radius_mm = circle.radius;
  out.circle_rms_mm = circle.rms_residual;

  // Step 4: axis tilt and location, radius error.
  const Eigen::Vector2d tilt = tilt_components(k, n, out.tilt_reference_1, out.tilt_reference_2);
  out.tilt_urad = tilt * 1e6;
  out.centre_offset_mm = out.centre_mm - out.nominal_centre_mm;
  out.centre_offset_axial_mm = out.centre_offset_mm.dot(k);
  out.centre_offset_radial_mm = (out.centre_offset_mm - out.centre_offset_axial_mm * k).norm();
  out.radius_error_mm = out.radius_mm - out.nominal_radius_mm;
  out.arc_coverage_rad = coverage;

  // Step 5: dR_i, dA_i, axial scatter.
  double da_sum = 0, da_min = INFINITY, da_max = -INFINITY;
  for (const auto& p : points) {
    CirclePointResult r;
    r.label = p.label;
    r.commanded_rad = p.commanded.*moving;
    r.nominal_mm = stylus_ball_centre(p.commanded, geometry);
    r.deviation_mm = p.measured_master_mm - r.nominal_mm;
    const Eigen::Vector3d d = p.measured_master_mm - out.centre_mm;
    const double x = d.dot(e1), y = d.dot(e2);
    r.measured_rad = std::atan2(y, x);
    r.dR_mm = std::hypot(x, y) - out.nominal_radius_mm;
    r.dA_rad = wrap(r.measured_rad - r.commanded_rad);
    r.tangential_mm = r.dA_rad * out.nominal_radius_mm;
    r.axial_mm = d.dot(n);
    da_sum += r.dA_rad;
    da_min = std::min(da_min, r.dA_rad);
    da_max = std::max(da_max, r.dA_rad);
    out.dA_max_abs_arcsec = std::max(out.dA_max_abs_arcsec, std::abs(r.dA_rad) * kArcsecPerRad);
    out.dR_max_abs_mm = std::max(out.dR_max_abs_mm, std::abs(r.dR_mm));
    out.axial_max_abs_mm = std::max(out.axial_max_abs_mm, std::abs(r.axial_mm));
    out.points.push_back(r);
  }
  out.dA_mean_arcsec = da_sum / static_cast<double>(points.size()) * kArcsecPerRad;
  out.dA_range_arcsec = (da_max - da_min) * kArcsecPerRad;
  return out;
}

WAxisResult analyze_w_axis(const std::vector<RotaryPoint>& points, const ProbeGeometry& geometry) {
  const std::string who = "analyze_w_axis";
  // Step 0: the points are usable.
  validate_common(who, points, geometry, &AxisPosition::w_mm,
                  "2 points fit a line exactly; 5 leave 3 to show straightness and "
                  "positioning error");
  std::vector<const RotaryPoint*> sorted;
  sorted.reserve(points.size());
  for (const auto& p : points) sorted.push_back(&p);
  std::stable_sort(sorted.begin(), sorted.end(), [](const RotaryPoint* l, const RotaryPoint* r) {
    return l->commanded.w_mm < r->commanded.w_mm;
  });
  for (std::size_t i = 1; i < sorted.size(); ++i) {
    if (sorted[i]->commanded.w_mm - sorted[i - 1]->commanded.w_mm <= rotary_axes::kHeldMm) {
      throw std::invalid_argument(
          who + ": points '" + sorted[i - 1]->label + "' and '" + sorted[i]->label +
          "' have the same commanded.w_mm = " + detail::quote_number(sorted[i]->commanded.w_mm) +
          " (duplicate position)");
    }
  }

  WAxisResult out;
  const RotaryPoint& first = points.front();
  const double a = first.commanded.a_rad, c = first.commanded.c_rad;
  out.nominal_direction = tool_direction(a, c);
  const Eigen::Matrix3d body = wrist_rotation(a, c);
  out.tilt_reference_1 = body.col(0);
  out.tilt_reference_2 = body.col(1);

  // Step 1: the line (total least squares) and its scale, oriented towards increasing W.
  const PrincipalAxes s = scatter_of(points);
  Eigen::Vector3d u = s.vectors.col(2).normalized();
  double mean_w = 0;
  for (const auto& p : points) mean_w += p.commanded.w_mm;
  mean_w /= static_cast<double>(points.size());
  double sxy = 0, sxx = 0;
  for (const auto& p : points) {
    const double along = (p.measured_master_mm - s.centroid).dot(u);
    const double w = p.commanded.w_mm - mean_w;
    sxy += along * w;
    sxx += w * w;
  }
  double slope = sxy / sxx;
  if (slope < 0) {
    u = -u;
    slope = -slope;
  }
  if (!std::isfinite(slope) || std::abs(slope - 1) > rotary_axes::kMaxScaleDeviation) {
    throw std::invalid_argument(who + ": the measured travel along the fitted line is " +
                                detail::quote_number(slope) +
                                " times the commanded W travel (allowed 1 +- " +
                                detail::quote_number(rotary_axes::kMaxScaleDeviation) +
                                "): wrong unit, wrong points, or the spindle did not move");
  }
  out.direction = u;
  out.tilt_urad =
      tilt_components(out.nominal_direction, u, out.tilt_reference_1, out.tilt_reference_2) * 1e6;
  out.w_scale_um_per_m = (slope - 1) * 1e6;

  // Step 2: positioning error from point 0, straightness, deviation from nominal.
  double e_min = INFINITY, e_max = -INFINITY;
  for (const auto& p : points) {
    WPointResult r;
    r.label = p.label;
    r.commanded_w_mm = p.commanded.w_mm;
    r.nominal_mm = stylus_ball_centre(p.commanded, geometry);
    r.deviation_mm = p.measured_master_mm - r.nominal_mm;
    r.travel_mm = (p.measured_master_mm - first.measured_master_mm).dot(u);
    r.positioning_error_mm = r.travel_mm - (p.commanded.w_mm - first.commanded.w_mm);
    const Eigen::Vector3d d = p.measured_master_mm - s.centroid;
    r.distance_mm = (d - d.dot(u) * u).norm();
    e_min = std::min(e_min, r.positioning_error_mm);
    e_max = std::max(e_max, r.positioning_error_mm);
    out.straightness_mm = std::max(out.straightness_mm, r.distance_mm);
    out.positioning_max_abs_mm =
        std::max(out.positioning_max_abs_mm, std::abs(r.positioning_error_mm));
    out.mean_deviation_mm += r.deviation_mm;
    out.points.push_back(r);
  }
  out.mean_deviation_mm /= static_cast<double>(points.size());
  out.positioning_range_mm = e_max - e_min;
  return out;
}

RotaryAxisResult analyze_rotary_axis(RotaryAxis axis, const std::vector<RotaryPoint>& points,
                                     const ProbeGeometry& geometry) {
  RotaryAxisResult out;
  out.axis = axis;
  if (axis == RotaryAxis::W) {
    out.w = analyze_w_axis(points, geometry);
  } else {
    out.circle = analyze_circle_axis(axis, points, geometry);
  }
  return out;
}

}  // namespace ncqual::solver

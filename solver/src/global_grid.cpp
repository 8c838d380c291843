// SPDX-License-Identifier: Apache-2.0
#include "ncqual/solver/global_grid.hpp"

#include "ncqual/solver/circle_fit.hpp"

#include "ncqual/common/units.hpp"
#include "result_building.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace ncqual::solver {
namespace {

using units::kPi;

[[noreturn]] void refuse(const std::string& why) {
  throw std::invalid_argument("analyze_grid: " + why);
}

// Angle between two vectors minus 90 degrees (rad), positive when the angle is larger.
double non_orthogonality(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) - kPi / 2;
}

void validate(const MasterFrame& frame, const std::vector<FramePoint>& grid,
              const GridOptions& options) {
  if (options.worst_point_count < 0) {
    refuse("options.worst_point_count = " + std::to_string(options.worst_point_count) +
           " is negative");
  }
  if (!std::isfinite(options.plane_tolerance_mm) || !(options.plane_tolerance_mm > 0)) {
    refuse("options.plane_tolerance_mm = " + detail::quote_number(options.plane_tolerance_mm) +
           " must be a positive length");
  }
  const Eigen::Matrix3d r = frame.instrument_to_master.linear();
  const Eigen::Vector3d t = frame.instrument_to_master.translation();
  if (!r.allFinite() || !t.allFinite()) {
    refuse("frame.instrument_to_master is not finite (translation " + detail::quote_vector(t) +
           ")");
  }
  const double orthonormal_error =
      (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (orthonormal_error > global_grid::kOrthonormalTolerance || r.determinant() < 0) {
    refuse("frame.instrument_to_master is not a rotation (|R^T R - I| = " +
           detail::quote_number(orthonormal_error) +
           ", det = " + detail::quote_number(r.determinant()) + ")");
  }
  if (static_cast<int>(grid.size()) < global_grid::kMinPoints) {
    refuse("grid has " + std::to_string(grid.size()) + " points; at least " +
           std::to_string(global_grid::kMinPoints) +
           " are needed (the affine fit has 4 unknowns per coordinate)");
  }
  std::set<std::string> labels;
  for (const auto& p : grid) {
    if (!labels.insert(p.label).second) refuse("grid label '" + p.label + "' appears twice");
    if (!p.commanded_mm.allFinite()) {
      refuse("grid point '" + p.label + "' commanded_mm = " + detail::quote_vector(p.commanded_mm) +
             " is not finite");
    }
    if (!p.measured_mm.allFinite()) {
      refuse("grid point '" + p.label + "' measured_mm = " + detail::quote_vector(p.measured_mm) +
             " is not finite");
    }
  }
  // The commanded positions must span 3-D. First the cases the procedure can get wrong by
  // itself (one plane, one column), named; then any other coplanarity.
  const char* const names[3] = {"z", "x", "y"};
  const int order[3] = {2, 0, 1};
  for (int k = 0; k < 3; ++k) {
    const int axis = order[k];
    double lo = INFINITY, hi = -INFINITY;
    for (const auto& p : grid) {
      lo = std::min(lo, p.commanded_mm(axis));
      hi = std::max(hi, p.commanded_mm(axis));
    }
    if (hi - lo <= options.plane_tolerance_mm) {
      std::string why = "all " + std::to_string(grid.size()) +
                        " grid points lie on the one plane " + names[k] + " = " +
                        detail::quote_number(lo) + " mm (spread " + detail::quote_number(hi - lo) +
                        " mm)";
      if (axis == 2) {
        why +=
            ": the Z scale and the YZ and ZX squareness would be undefined; measure at least "
            "two constant-Z planes";
      } else {
        why += std::string(": the ") + (axis == 0 ? "X" : "Y") +
               " scale and the squareness "
               "with " +
               (axis == 0 ? "X" : "Y") + " would be undefined";
      }
      refuse(why);
    }
  }
  std::vector<Eigen::Vector3d> commanded;
  commanded.reserve(grid.size());
  for (const auto& p : grid) commanded.push_back(p.commanded_mm);
  const PrincipalAxes axes = principal_axes(commanded);
  const double smallest = std::sqrt(std::max(0.0, axes.values(0)));
  const double largest = std::sqrt(std::max(0.0, axes.values(2)));
  if (!(smallest >= global_grid::kMinSpreadRatio * largest)) {
    refuse("the commanded grid positions are (nearly) coplanar (normal " +
           detail::quote_vector(axes.vectors.col(0)) + ", spread across the plane " +
           detail::quote_number(largest > 0 ? smallest / largest : 0.0) +
           " of that along it): the affine fit of the axis motions needs points spanning 3-D");
  }
}

// Least-squares affine fit master ~ M commanded + t. With the commanded and master coordinates
// centred on their means (C, Y: one row per point), M^T = argmin |C M^T - Y|^2 and
// t = mean(master) - M mean(commanded).
AxisMotionFit fit_axis_motion(const std::vector<FramePoint>& grid,
                              std::vector<GridPointResult>* points) {
  const Eigen::Index n = static_cast<Eigen::Index>(grid.size());
  Eigen::Vector3d mean_c = Eigen::Vector3d::Zero(), mean_m = Eigen::Vector3d::Zero();
  for (const auto& r : *points) {
    mean_c += r.commanded_mm;
    mean_m += r.master_mm;
  }
  mean_c /= static_cast<double>(n);
  mean_m /= static_cast<double>(n);
  Eigen::MatrixXd c(n, 3), y(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto& r = (*points)[static_cast<std::size_t>(i)];
    c.row(i) = (r.commanded_mm - mean_c).transpose();
    y.row(i) = (r.master_mm - mean_m).transpose();
  }
  const Eigen::Matrix3d mt = c.colPivHouseholderQr().solve(y);

  AxisMotionFit fit;
  fit.motion = mt.transpose();
  fit.offset_mm = mean_m - fit.motion * mean_c;
  const Eigen::Vector3d mx = fit.motion.col(0), my = fit.motion.col(1), mz = fit.motion.col(2);
  fit.scale_x_um_per_m = (mx.norm() - 1) * 1e6;
  fit.scale_y_um_per_m = (my.norm() - 1) * 1e6;
  fit.scale_z_um_per_m = (mz.norm() - 1) * 1e6;
  fit.squareness_xy_urad = non_orthogonality(mx, my) * 1e6;
  fit.squareness_yz_urad = non_orthogonality(my, mz) * 1e6;
  fit.squareness_zx_urad = non_orthogonality(mz, mx) * 1e6;
  fit.ec_0x_y_urad = fit.squareness_xy_urad;
  fit.ea_0y_z_urad = fit.squareness_yz_urad;
  fit.eb_0x_z_urad = -fit.squareness_zx_urad;
  double sum_sq = 0;
  for (auto& r : *points) {
    r.affine_residual_mm = r.master_mm - (fit.motion * r.commanded_mm + fit.offset_mm);
    sum_sq += r.affine_residual_mm.squaredNorm();
  }
  fit.residual_rms_mm = std::sqrt(sum_sq / static_cast<double>(n));
  return fit;
}

}  // namespace

GridAnalysis analyze_grid(const MasterFrame& frame, const std::vector<FramePoint>& grid,
                          const GridOptions& options) {
  validate(frame, grid, options);
  GridAnalysis out;

  // Step 1: each point in the master frame and its deviation from the commanded position.
  double sum_sq = 0;
  for (const auto& p : grid) {
    GridPointResult r;
    r.label = p.label;
    r.commanded_mm = p.commanded_mm;
    r.master_mm = frame.instrument_to_master * p.measured_mm;
    r.deviation_mm = r.master_mm - r.commanded_mm;
    r.deviation_norm_mm = r.deviation_mm.norm();
    sum_sq += r.deviation_mm.squaredNorm();
    out.max_abs_dx_mm = std::max(out.max_abs_dx_mm, std::abs(r.deviation_mm.x()));
    out.max_abs_dy_mm = std::max(out.max_abs_dy_mm, std::abs(r.deviation_mm.y()));
    out.max_abs_dz_mm = std::max(out.max_abs_dz_mm, std::abs(r.deviation_mm.z()));
    out.points.push_back(r);
  }
  out.rms_deviation_mm = std::sqrt(sum_sq / static_cast<double>(grid.size()));

  // Step 2: the worst points, largest |deviation| first.
  std::vector<std::size_t> order(out.points.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return out.points[a].deviation_norm_mm > out.points[b].deviation_norm_mm;
  });
  out.max_deviation_mm = out.points[order.front()].deviation_norm_mm;
  out.max_deviation_label = out.points[order.front()].label;
  const std::size_t worst =
      std::min(order.size(), static_cast<std::size_t>(options.worst_point_count));
  out.worst_points.assign(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(worst));

  // Step 3: the constant-Z planes and the worst point of each.
  std::vector<std::size_t> by_z(out.points.size());
  std::iota(by_z.begin(), by_z.end(), std::size_t{0});
  std::stable_sort(by_z.begin(), by_z.end(), [&](std::size_t a, std::size_t b) {
    return out.points[a].commanded_mm.z() < out.points[b].commanded_mm.z();
  });
  std::size_t start = 0;
  while (start < by_z.size()) {
    std::size_t end = start + 1;
    while (end < by_z.size() &&
           out.points[by_z[end]].commanded_mm.z() - out.points[by_z[end - 1]].commanded_mm.z() <=
               options.plane_tolerance_mm) {
      ++end;
    }
    GridPlaneSummary plane;
    double z_sum = 0, plane_sq = 0;
    for (std::size_t k = start; k < end; ++k) {
      const std::size_t i = by_z[k];
      const GridPointResult& r = out.points[i];
      z_sum += r.commanded_mm.z();
      plane_sq += r.deviation_mm.squaredNorm();
      plane.max_abs_deviation_mm = plane.max_abs_deviation_mm.cwiseMax(r.deviation_mm.cwiseAbs());
      if (k == start || r.deviation_norm_mm > plane.worst_deviation_mm ||
          (r.deviation_norm_mm == plane.worst_deviation_mm && i < plane.worst_index)) {
        plane.worst_index = i;
        plane.worst_deviation_mm = r.deviation_norm_mm;
      }
    }
    plane.point_count = static_cast<int>(end - start);
    plane.z_mm = z_sum / static_cast<double>(plane.point_count);
    plane.rms_deviation_mm = std::sqrt(plane_sq / static_cast<double>(plane.point_count));
    plane.worst_label = out.points[plane.worst_index].label;
    out.planes.push_back(plane);
    start = end;
  }

  // Step 4: the affine fit of the axis motions.
  out.affine = fit_axis_motion(grid, &out.points);
  return out;
}

GridAnalysis analyze_grid(const std::vector<FramePoint>& x_run,
                          const std::vector<FramePoint>& y_run, const std::vector<FramePoint>& grid,
                          const GridOptions& options) {
  return analyze_grid(fit_master_frame(x_run, y_run), grid, options);
}

}  // namespace ncqual::solver

// SPDX-License-Identifier: Apache-2.0
#include "ncqual/solver/master_frame.hpp"

#include "ncqual/solver/circle_fit.hpp"

#include "ncqual/common/units.hpp"
#include "result_building.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

namespace ncqual::solver {
namespace {

using units::kPi;
const char* const kAxisNames[3] = {"x", "y", "z"};

[[noreturn]] void refuse(const std::string& why) {
  throw std::invalid_argument("fit_master_frame: " + why);
}

// Step 0: the run is usable. `run` names it ("x_run"), `axis` is its own axis (0 = x, 1 = y).
void validate_run(const std::vector<FramePoint>& points, const std::string& run, int axis) {
  if (static_cast<int>(points.size()) < master_frame::kMinRunPoints) {
    refuse(run + " has " + std::to_string(points.size()) + " points; a run needs at least " +
           std::to_string(master_frame::kMinRunPoints) + " (two define a line, the third shows " +
           "its straightness)");
  }
  for (const auto& p : points) {
    if (!p.commanded_mm.allFinite()) {
      refuse(run + " point '" + p.label +
             "' commanded_mm = " + detail::quote_vector(p.commanded_mm) + " is not finite");
    }
    if (!p.measured_mm.allFinite()) {
      refuse(run + " point '" + p.label + "' measured_mm = " + detail::quote_vector(p.measured_mm) +
             " is not finite");
    }
  }
  const FramePoint& first = points.front();
  for (const auto& p : points) {
    for (int k = 0; k < 3; ++k) {
      if (k == axis) continue;
      const double diff = p.commanded_mm(k) - first.commanded_mm(k);
      if (std::abs(diff) > master_frame::kSameCommandedMm) {
        refuse(run + " point '" + p.label + "' commanded " + kAxisNames[k] + " = " +
               detail::quote_number(p.commanded_mm(k)) +
               " mm differs from that of its first point '" + first.label + "' (" +
               detail::quote_number(first.commanded_mm(k)) + " mm) by " +
               detail::quote_number(diff) + " mm: an " + kAxisNames[axis] + " run moves " +
               kAxisNames[axis] + " only");
      }
    }
  }
  std::vector<const FramePoint*> sorted;
  sorted.reserve(points.size());
  for (const auto& p : points) sorted.push_back(&p);
  std::stable_sort(sorted.begin(), sorted.end(), [axis](const FramePoint* a, const FramePoint* b) {
    return a->commanded_mm(axis) < b->commanded_mm(axis);
  });
  for (std::size_t i = 1; i < sorted.size(); ++i) {
    const double gap = sorted[i]->commanded_mm(axis) - sorted[i - 1]->commanded_mm(axis);
    if (gap <= master_frame::kSameCommandedMm) {
      refuse(run + " points '" + sorted[i - 1]->label + "' and '" + sorted[i]->label +
             "' have the same commanded " + kAxisNames[axis] + " = " +
             detail::quote_number(sorted[i]->commanded_mm(axis)) +
             " mm (duplicate commanded position)");
    }
  }
}

// Step 1: the total-least-squares line through the run's measured points, oriented towards
// increasing commanded coordinate, and its along-line scale.
struct Line {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();
  double mean_commanded = 0;
  double slope = 1;  // d(along)/d(commanded)
};

Line fit_run_line(const std::vector<FramePoint>& points, const std::string& run, int axis) {
  const double n = static_cast<double>(points.size());
  Line line;
  std::vector<Eigen::Vector3d> measured;
  measured.reserve(points.size());
  for (const auto& p : points) {
    measured.push_back(p.measured_mm);
    line.mean_commanded += p.commanded_mm(axis);
  }
  line.mean_commanded /= n;
  // Principal direction: eigenvector of the largest eigenvalue of the scatter matrix.
  const PrincipalAxes axes = principal_axes(measured);
  line.centroid = axes.centroid;
  line.direction = axes.vectors.col(2).normalized();
  // Slope of along-line position s_i = (p_i - centroid).u against commanded a_i:
  //   slope = sum s_i (a_i - mean a) / sum (a_i - mean a)^2.
  double sxy = 0, sxx = 0;
  for (const auto& p : points) {
    const double s = (p.measured_mm - line.centroid).dot(line.direction);
    const double a = p.commanded_mm(axis) - line.mean_commanded;
    sxy += s * a;
    sxx += a * a;
  }
  line.slope = sxy / sxx;
  if (line.slope < 0) {
    line.direction = -line.direction;
    line.slope = -line.slope;
  }
  if (!std::isfinite(line.slope) || std::abs(line.slope - 1) > master_frame::kMaxScaleDeviation) {
    refuse(run + ": the measured travel along the fitted line is " +
           detail::quote_number(line.slope) + " times the commanded travel (allowed 1 +- " +
           detail::quote_number(master_frame::kMaxScaleDeviation) +
           "): wrong unit, wrong points, or the target did not move");
  }
  return line;
}

// Step 4: the per-run report. `axis` is the run's axis; `cross_reference` the master axis the
// first cross direction follows (master Y for the X run, master X for the Y run).
RunFit report_run(const std::vector<FramePoint>& points, const std::string& run, int axis,
                  const Line& line, const Eigen::Isometry3d& to_master,
                  const Eigen::Vector3d& cross_reference, const Eigen::Vector3d& master_z) {
  RunFit fit;
  fit.run = run;
  fit.point_instrument_mm = line.centroid;
  fit.direction_instrument = line.direction;
  fit.direction_master = to_master.linear() * line.direction;
  const Eigen::Vector3d& u = line.direction;
  Eigen::Vector3d e1 = cross_reference - cross_reference.dot(u) * u;
  e1.normalize();
  Eigen::Vector3d e2 = axis == 0 ? u.cross(e1) : e1.cross(u);  // both ~ +master Z
  if (e2.dot(master_z) < 0) e2 = -e2;
  fit.cross_direction_1_instrument = e1;
  fit.cross_direction_2_instrument = e2;
  fit.scale_um_per_m = (line.slope - 1) * 1e6;

  Eigen::Vector2d lo = Eigen::Vector2d::Constant(INFINITY);
  Eigen::Vector2d hi = Eigen::Vector2d::Constant(-INFINITY);
  for (const auto& p : points) {
    RunPointResidual r;
    r.label = p.label;
    r.commanded_mm = p.commanded_mm(axis);
    const Eigen::Vector3d d = p.measured_mm - line.centroid;
    r.along_mm = d.dot(u);
    r.along_residual_mm = r.along_mm - line.slope * (r.commanded_mm - line.mean_commanded);
    const Eigen::Vector3d perp = d - r.along_mm * u;
    r.cross_mm = Eigen::Vector2d(perp.dot(e1), perp.dot(e2));
    r.distance_mm = perp.norm();
    r.deviation_mm = to_master * p.measured_mm - p.commanded_mm;
    lo = lo.cwiseMin(r.cross_mm);
    hi = hi.cwiseMax(r.cross_mm);
    fit.max_distance_mm = std::max(fit.max_distance_mm, r.distance_mm);
    fit.points.push_back(r);
  }
  fit.straightness_mm = hi - lo;
  return fit;
}

}  // namespace

MasterFrame fit_master_frame(const std::vector<FramePoint>& x_run,
                             const std::vector<FramePoint>& y_run) {
  // Step 0: the runs are usable.
  validate_run(x_run, "x_run", 0);
  validate_run(y_run, "y_run", 1);
  const double zx = x_run.front().commanded_mm.z();
  const double zy = y_run.front().commanded_mm.z();
  if (std::abs(zx - zy) > master_frame::kSameCommandedMm) {
    refuse("x_run is at commanded z = " + detail::quote_number(zx) + " mm (point '" +
           x_run.front().label + "'), y_run at z = " + detail::quote_number(zy) + " mm (point '" +
           y_run.front().label + "'): both runs must be at one commanded Z");
  }

  // Step 1: the two lines.
  const Line lx = fit_run_line(x_run, "x_run", 0);
  const Line ly = fit_run_line(y_run, "y_run", 1);
  const Eigen::Vector3d& u = lx.direction;
  const Eigen::Vector3d& v = ly.direction;
  const double angle = std::atan2(u.cross(v).norm(), u.dot(v));
  const double non_orthogonality = angle - kPi / 2;
  if (std::abs(non_orthogonality) > master_frame::kMaxNonOrthogonalityRad) {
    refuse("the fitted x_run and y_run lines are " + detail::quote_number(angle * 180 / kPi) +
           " degrees apart (directions " + detail::quote_vector(u) + " and " +
           detail::quote_vector(v) +
           "): (nearly) parallel lines cannot define a frame; allowed 90 +- " +
           detail::quote_number(master_frame::kMaxNonOrthogonalityRad * 180 / kPi) + " degrees");
  }

  // Step 2: the symmetric orthonormal pair nearest to (u, v), Z = X x Y.
  const Eigen::Vector3d b = (u + v).normalized();
  const Eigen::Vector3d d = (u - v).normalized();
  const Eigen::Vector3d ex = (b + d).normalized();
  const Eigen::Vector3d ey = (b - d).normalized();
  const Eigen::Vector3d ez = ex.cross(ey).normalized();
  Eigen::Matrix3d rotation;
  rotation.row(0) = ex.transpose();
  rotation.row(1) = ey.transpose();
  rotation.row(2) = ez.transpose();

  // Step 3: the origin, t = mean over both runs of (commanded - R measured).
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  for (const auto* run : {&x_run, &y_run}) {
    for (const auto& p : *run) t += p.commanded_mm - rotation * p.measured_mm;
  }
  const double total = static_cast<double>(x_run.size() + y_run.size());
  t /= total;

  MasterFrame frame;
  frame.instrument_to_master = Eigen::Isometry3d::Identity();
  frame.instrument_to_master.linear() = rotation;
  frame.instrument_to_master.translation() = t;
  frame.x_axis_instrument = ex;
  frame.y_axis_instrument = ey;
  frame.z_axis_instrument = ez;
  frame.orthogonality_urad = non_orthogonality * 1e6;

  // Step 4: the per-run reports.
  frame.x_run = report_run(x_run, "x_run", 0, lx, frame.instrument_to_master, ey, ez);
  frame.y_run = report_run(y_run, "y_run", 1, ly, frame.instrument_to_master, ex, ez);
  double sum_sq = 0;
  for (const auto* fit : {&frame.x_run, &frame.y_run}) {
    for (const auto& r : fit->points) sum_sq += r.deviation_mm.squaredNorm();
  }
  frame.origin_rms_mm = std::sqrt(sum_sq / total);
  return frame;
}

}  // namespace ncqual::solver

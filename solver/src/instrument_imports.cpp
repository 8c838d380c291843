// SPDX-License-Identifier: Apache-2.0
// Instrument files as the tracker points of a MeasurementSet, labelled as the monthly programs
// label them (`ncqual import`): tracker_points_for_grid, _for_linear_run, _for_circle.
#include "ncqual/solver/instrument_files.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace ncqual::solver {

namespace {

TrackerPoint tracker_point(std::string label, const Eigen::Vector3d& commanded_target,
                           const Eigen::Vector3d& measured, const ProbeGeometry& target) {
  // stylus_ball_centre at A = C = W = 0 is pivot + (ox, oy, -L).
  const Eigen::Vector3d pivot =
      commanded_target - Eigen::Vector3d(target.stylus_offset_mm.x(), target.stylus_offset_mm.y(),
                                         -target.tool_length_mm);
  TrackerPoint p;
  p.label = std::move(label);
  p.commanded.x_mm = pivot.x();
  p.commanded.y_mm = pivot.y();
  p.commanded.z_mm = pivot.z();
  p.measured_mm = measured;
  return p;
}

}  // namespace

std::vector<TrackerPoint> tracker_points_for_grid(const std::vector<GridFilePoint>& x_run,
                                                  const std::vector<GridFilePoint>& y_run,
                                                  const std::vector<GridFilePoint>& grid,
                                                  const ProbeGeometry& target) {
  std::vector<TrackerPoint> out;
  for (std::size_t i = 0; i < x_run.size(); ++i) {
    out.push_back(tracker_point("x_run:" + std::to_string(i), x_run[i].commanded_mm,
                                x_run[i].measured_mm, target));
  }
  for (std::size_t i = 0; i < y_run.size(); ++i) {
    out.push_back(tracker_point("y_run:" + std::to_string(i), y_run[i].commanded_mm,
                                y_run[i].measured_mm, target));
  }
  for (std::size_t i = 0; i < grid.size(); ++i) {
    out.push_back(tracker_point("grid:" + std::to_string(i) + ":t0", grid[i].commanded_mm,
                                grid[i].measured_mm, target));
  }
  return out;
}

std::vector<TrackerPoint> tracker_points_for_linear_run(const Iso230_2File& run, int axis,
                                                        const Eigen::Vector3d& at_mm,
                                                        const ProbeGeometry& target) {
  if (axis < 0 || axis > 2)
    throw std::invalid_argument("axis " + std::to_string(axis) + ": expected 0, 1 or 2");
  std::vector<double> targets;
  for (const auto& r : run.readings) targets.push_back(r.target_mm);
  std::sort(targets.begin(), targets.end());
  targets.erase(std::unique(targets.begin(), targets.end()), targets.end());
  std::vector<TrackerPoint> out;
  for (const auto& r : run.readings) {
    const auto rank =
        std::lower_bound(targets.begin(), targets.end(), r.target_mm) - targets.begin();
    Eigen::Vector3d commanded = at_mm, measured = at_mm;
    commanded[axis] = r.target_mm;
    measured[axis] = r.measured_mm;
    out.push_back(tracker_point("run:" + std::to_string(r.cycle) + ":" +
                                    std::string(to_string(r.direction)) + ":" +
                                    std::to_string(rank),
                                commanded, measured, target));
  }
  return out;
}

std::vector<TrackerPoint> tracker_points_for_circle(const CircleFile& circle,
                                                    const Eigen::Vector3d& centre_mm,
                                                    const ProbeGeometry& target) {
  const int u = circle.input.plane == Plane::YZ ? 1 : 0;
  const int v = circle.input.plane == Plane::XY ? 1 : 2;
  std::vector<TrackerPoint> out;
  int counts[2] = {0, 0};
  for (const auto& p : circle.input.points) {
    const bool ccw = p.direction == PathDirection::Ccw;
    Eigen::Vector3d at = centre_mm;
    at[u] += p.uv_mm.x();
    at[v] += p.uv_mm.y();
    out.push_back(tracker_point(std::string(ccw ? "ccw:" : "cw:") + std::to_string(counts[ccw]++),
                                at, at, target));
  }
  return out;
}

}  // namespace ncqual::solver

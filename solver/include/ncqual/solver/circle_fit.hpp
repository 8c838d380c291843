// SPDX-License-Identifier: Apache-2.0
// Least-squares circle through points in a plane, and the principal axes of a point cloud (the
// total-least-squares line or plane through it).
//
// Used by probe check 3 (the hole centre from touches on the edge of the monument's ring
// gauge hole), the C-alignment check, the tracker's master-frame runs, rotary axes, circles
// and linear axis runs.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace ncqual::solver {

struct CircleFit {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 0;
  // Root mean square of the geometric residuals e_i = |p_i - centre| - radius.
  double rms_residual = 0;
  int point_count = 0;
  int iterations = 0;  // refinement iterations used (0 for the algebraic fit alone)
  std::string error;   // non-empty when no circle could be fitted; says why

  bool ok() const { return error.empty(); }
};

// Algebraic (Kasa) fit: minimises sum_i (x_i^2 + y_i^2 + D x_i + E y_i + F)^2, a linear least
// squares problem; then centre = (-D/2, -E/2), radius = sqrt(centre^2 - F).
// Fast and robust, but biased towards smaller radii on short noisy arcs.
CircleFit fit_circle_algebraic(const std::vector<Eigen::Vector2d>& points);

// Geometric least-squares fit: minimises sum_i (|p_i - c| - r)^2 over (c, r), starting from the
// algebraic fit and refined with Levenberg-Marquardt.
// Refuses (error non-empty) fewer than 3 points, non-finite coordinates, coincident and
// (near-)collinear points.
CircleFit fit_circle(const std::vector<Eigen::Vector2d>& points);

// Centroid of 3-D points and the eigen-decomposition of their scatter matrix
// sum_i (p_i - centroid)(p_i - centroid)^T, eigenvalues increasing: the total-least-squares line
// through the points runs along vectors.col(2), the plane through them has normal vectors.col(0).
// Needs at least one point (an empty set gives a NaN centroid).
struct PrincipalAxes {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d values = Eigen::Vector3d::Zero();
  Eigen::Matrix3d vectors = Eigen::Matrix3d::Identity();
};
PrincipalAxes principal_axes(const std::vector<Eigen::Vector3d>& points);

}  // namespace ncqual::solver

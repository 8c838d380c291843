// SPDX-License-Identifier: Apache-2.0
#include "ncqual/solver/circle_fit.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <cstdio>
#include <string>

namespace ncqual::solver {
namespace {

// Points whose spread across their best straight line is less than this fraction of the spread
// along it are refused as collinear. An arc of angle theta has a width/length ratio of about
// theta / 8, so this accepts arcs down to about 1e-5 rad, far below anything probed.
constexpr double kCollinearRatio = 1e-6;
constexpr int kMaxIterations = 100;

std::string format_point(const Eigen::Vector2d& p) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%.10g, %.10g)", p.x(), p.y());
  return buffer;
}

// Why the points cannot define a circle, or an empty string.
std::string why_points_unusable(const std::vector<Eigen::Vector2d>& points) {
  if (points.size() < 3) {
    return "fit_circle: " + std::to_string(points.size()) +
           " points given, a circle needs at least 3";
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) {
      return "fit_circle: point " + std::to_string(i) + " = " + format_point(points[i]) +
             " is not finite";
    }
  }
  return "";
}

// The points moved to their centroid and scaled to unit RMS distance from it, so that the
// fit is well conditioned whatever the coordinates (machine coordinates are ~1e3 mm, radii
// ~10 mm): q_i = (p_i - m) / s, m = mean(p_i), s = sqrt(mean |p_i - m|^2).
struct Normalised {
  std::vector<Eigen::Vector2d> q;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  double scale = 0;
};

Normalised normalise(const std::vector<Eigen::Vector2d>& points) {
  Normalised n;
  for (const auto& p : points) n.mean += p;
  n.mean /= static_cast<double>(points.size());
  double sum_sq = 0;
  for (const auto& p : points) sum_sq += (p - n.mean).squaredNorm();
  n.scale = std::sqrt(sum_sq / static_cast<double>(points.size()));
  n.q.reserve(points.size());
  for (const auto& p : points)
    n.q.push_back(n.scale > 0 ? Eigen::Vector2d((p - n.mean) / n.scale) : Eigen::Vector2d::Zero());
  return n;
}

// Collinearity test on normalised points: the eigenvalues of the scatter matrix
// S = (1/n) sum q_i q_i^T are the squared spreads along and across the best line.
std::string why_collinear(const Normalised& n) {
  if (!(n.scale > 0)) return "fit_circle: all points coincide";
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const auto& q : n.q) scatter += q * q.transpose();
  scatter /= static_cast<double>(n.q.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
  const double across = std::sqrt(std::max(0.0, eig.eigenvalues()(0)));
  const double along = std::sqrt(std::max(0.0, eig.eigenvalues()(1)));
  if (across < kCollinearRatio * along) {
    char buffer[160];
    std::snprintf(buffer, sizeof buffer,
                  "fit_circle: the %zu points are (nearly) collinear (spread across their line "
                  "%.3g of that along it); a circle needs points off a straight line",
                  n.q.size(), along > 0 ? across / along : 0.0);
    return buffer;
  }
  return "";
}

// Kasa fit on normalised points. The circle (x - a)^2 + (y - b)^2 = r^2 expands to
//   x^2 + y^2 + D x + E y + F = 0,  D = -2a, E = -2b, F = a^2 + b^2 - r^2,
// linear in (D, E, F): solve [x_i y_i 1] (D E F)^T = -(x_i^2 + y_i^2) in least squares.
bool kasa_normalised(const std::vector<Eigen::Vector2d>& q, Eigen::Vector2d* centre,
                     double* radius) {
  const Eigen::Index n = static_cast<Eigen::Index>(q.size());
  Eigen::MatrixXd design(n, 3);
  Eigen::VectorXd rhs(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    design.row(i) << q[static_cast<std::size_t>(i)].x(), q[static_cast<std::size_t>(i)].y(), 1.0;
    rhs(i) = -q[static_cast<std::size_t>(i)].squaredNorm();
  }
  const Eigen::Vector3d def = design.colPivHouseholderQr().solve(rhs);
  *centre = Eigen::Vector2d(-def(0) / 2, -def(1) / 2);
  const double r_sq = centre->squaredNorm() - def(2);
  if (!std::isfinite(r_sq) || r_sq <= 0 || !centre->allFinite()) return false;
  *radius = std::sqrt(r_sq);
  return true;
}

// Sum of squared geometric residuals e_i = |q_i - c| - r.
double geometric_cost(const std::vector<Eigen::Vector2d>& q, const Eigen::Vector3d& x) {
  double cost = 0;
  for (const auto& p : q) {
    const double e = (p - x.head<2>()).norm() - x(2);
    cost += e * e;
  }
  return cost;
}

// Levenberg-Marquardt on x = (cx, cy, r) with residuals e_i = |q_i - c| - r and Jacobian rows
//   de_i/dc = -(q_i - c)^T / |q_i - c|,   de_i/dr = -1.
// Step: (J^T J + lambda diag(J^T J)) dx = -J^T e; lambda shrinks on success, grows on failure.
int refine_geometric(const std::vector<Eigen::Vector2d>& q, Eigen::Vector3d* x) {
  double lambda = 1e-3;
  double cost = geometric_cost(q, *x);
  int iterations = 0;
  for (; iterations < kMaxIterations; ++iterations) {
    Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
    Eigen::Vector3d jte = Eigen::Vector3d::Zero();
    for (const auto& p : q) {
      const Eigen::Vector2d d = p - x->head<2>();
      const double dist = d.norm();
      Eigen::Vector3d row(0, 0, -1);
      if (dist > 0) row.head<2>() = -d / dist;  // a point at the centre has no direction
      const double e = dist - (*x)(2);
      jtj += row * row.transpose();
      jte += row * e;
    }
    bool improved = false;
    Eigen::Vector3d step = Eigen::Vector3d::Zero();
    for (int tries = 0; tries < 20 && !improved; ++tries) {
      Eigen::Matrix3d damped = jtj;
      damped.diagonal() += lambda * jtj.diagonal();
      step = damped.ldlt().solve(-jte);
      const Eigen::Vector3d candidate = *x + step;
      const double candidate_cost = geometric_cost(q, candidate);
      if (step.allFinite() && candidate_cost <= cost) {
        *x = candidate;
        cost = candidate_cost;
        lambda = std::max(lambda / 10, 1e-12);
        improved = true;
      } else {
        lambda *= 10;
      }
    }
    if (!improved || step.norm() < 1e-15 * (1 + x->norm())) break;
  }
  return iterations;
}

CircleFit denormalise(const Normalised& n, const Eigen::Vector2d& centre, double radius,
                      int iterations) {
  CircleFit fit;
  fit.centre = n.mean + n.scale * centre;
  fit.radius = n.scale * radius;
  fit.point_count = static_cast<int>(n.q.size());
  fit.iterations = iterations;
  Eigen::Vector3d x(centre.x(), centre.y(), radius);
  fit.rms_residual = n.scale * std::sqrt(geometric_cost(n.q, x) / static_cast<double>(n.q.size()));
  if (!fit.centre.allFinite() || !std::isfinite(fit.radius) || !(fit.radius > 0)) {
    fit.error = "fit_circle: the fit did not converge to a finite circle";
  }
  return fit;
}

CircleFit refused(const std::string& why, std::size_t count) {
  CircleFit fit;
  fit.error = why;
  fit.point_count = static_cast<int>(count);
  return fit;
}

}  // namespace

// The steps both fits share: refuse unusable points, normalise, algebraic (Kasa) fit.
// Returns an empty string and fills n, centre, radius; or why the points were refused.
static std::string algebraic_start(const std::vector<Eigen::Vector2d>& points, Normalised* n,
                                   Eigen::Vector2d* centre, double* radius) {
  if (auto why = why_points_unusable(points); !why.empty()) return why;
  *n = normalise(points);
  if (auto why = why_collinear(*n); !why.empty()) return why;
  if (!kasa_normalised(n->q, centre, radius)) {
    return "fit_circle: the algebraic fit found no real circle";
  }
  return "";
}

CircleFit fit_circle_algebraic(const std::vector<Eigen::Vector2d>& points) {
  Normalised n;
  Eigen::Vector2d centre;
  double radius = 0;
  if (auto why = algebraic_start(points, &n, &centre, &radius); !why.empty()) {
    return refused(why, points.size());
  }
  return denormalise(n, centre, radius, 0);
}

CircleFit fit_circle(const std::vector<Eigen::Vector2d>& points) {
  // Step 1: algebraic start.
  Normalised n;
  Eigen::Vector2d centre;
  double radius = 0;
  if (auto why = algebraic_start(points, &n, &centre, &radius); !why.empty()) {
    return refused(why, points.size());
  }
  // Step 2: geometric refinement.
  Eigen::Vector3d x(centre.x(), centre.y(), radius);
  const int iterations = refine_geometric(n.q, &x);
  return denormalise(n, x.head<2>(), std::abs(x(2)), iterations);
}

PrincipalAxes principal_axes(const std::vector<Eigen::Vector3d>& points) {
  PrincipalAxes axes;
  for (const auto& p : points) axes.centroid += p;
  axes.centroid /= static_cast<double>(points.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& p : points) {
    const Eigen::Vector3d d = p - axes.centroid;
    scatter += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
  axes.values = eig.eigenvalues();
  axes.vectors = eig.eigenvectors();
  return axes;
}

}  // namespace ncqual::solver

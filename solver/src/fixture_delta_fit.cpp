// SPDX-License-Identifier: Apache-2.0
// Step 6 of the fixture post-calibration on its own: the fit of the pogos' deltas against their
// commanded positions, fit_fixture_deltas (its model: ncqual/solver/fixture_checks.hpp).
#include "ncqual/solver/fixture_checks.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace ncqual::solver {

namespace {

// A commanded coordinate "varies" within a pogo when its range exceeds this (mm).
constexpr double kVariesMm = 1e-6;
// Points at one commanded coordinate: rounded to this resolution (mm) to group them.
constexpr double kGroupResolutionMm = 1e-3;
// The fit's columns are independent when the pivoted QR finds them so at this relative threshold.
constexpr double kRankThreshold = 1e-8;

}  // namespace

FixtureDeltaFit fit_fixture_deltas(const std::vector<PogoDelta>& points) {
  FixtureDeltaFit fit;
  const int n = static_cast<int>(points.size());
  fit.points = n;
  std::map<std::string, std::vector<int>> by_pogo;
  for (int i = 0; i < n; ++i) by_pogo[points[static_cast<std::size_t>(i)].pogo].push_back(i);
  fit.pogos = static_cast<int>(by_pogo.size());
  if (n == 0) {
    fit.error = "no points to fit";
    return fit;
  }

  // The pogo means removed: X = c - mean_p(c), Y = delta - mean_p(delta).
  Eigen::MatrixXd X(n, 3), Y(n, 3);
  for (const auto& [pogo, members] : by_pogo) {
    Eigen::Vector3d mean_c = Eigen::Vector3d::Zero(), mean_d = Eigen::Vector3d::Zero();
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
    for (int i : members) {
      const PogoDelta& p = points[static_cast<std::size_t>(i)];
      mean_c += p.commanded_mm;
      mean_d += p.delta_mm;
      lo = lo.cwiseMin(p.commanded_mm);
      hi = hi.cwiseMax(p.commanded_mm);
    }
    mean_c /= static_cast<double>(members.size());
    mean_d /= static_cast<double>(members.size());
    fit.span_mm = fit.span_mm.cwiseMax(hi - lo);
    for (int i : members) {
      const PogoDelta& p = points[static_cast<std::size_t>(i)];
      X.row(i) = (p.commanded_mm - mean_c).transpose();
      Y.row(i) = (p.delta_mm - mean_d).transpose();
    }
  }

  // Slopes on the commanded axes that vary within some pogo, columns scaled to unit rms.
  std::vector<int> columns;
  for (int j = 0; j < 3; ++j) {
    if (fit.span_mm[j] > kVariesMm) columns.push_back(j);
  }
  const int k = static_cast<int>(columns.size());
  Eigen::MatrixXd R = Y;
  if (k == 0) {
    fit.error = "the commanded positions do not change within any pogo: no slope to fit";
  } else {
    Eigen::MatrixXd Xs(n, k);
    Eigen::VectorXd scale(k);
    for (int c = 0; c < k; ++c) {
      scale[c] = std::sqrt(X.col(columns[static_cast<std::size_t>(c)]).squaredNorm() / n);
      Xs.col(c) = X.col(columns[static_cast<std::size_t>(c)]) / scale[c];
    }
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Xs);
    qr.setThreshold(kRankThreshold);
    if (qr.rank() < k) {
      fit.error =
          "the commanded X, Y and Z do not change independently within the pogos: their "
          "slopes cannot be told apart";
    } else {
      const Eigen::MatrixXd B = qr.solve(Y);  // k x 3
      R = Y - Xs * B;
      fit.degrees_of_freedom = n - fit.pogos - k;
      Eigen::MatrixXd covariance;
      if (fit.degrees_of_freedom > 0) covariance = (Xs.transpose() * Xs).inverse();
      for (int c = 0; c < k; ++c) {
        const int j = columns[static_cast<std::size_t>(c)];
        fit.fitted[j] = true;
        for (int i = 0; i < 3; ++i) {
          fit.slope(i, j) = B(c, i) / scale[c];
          if (fit.degrees_of_freedom > 0) {
            const double s2 = R.col(i).squaredNorm() / fit.degrees_of_freedom;
            fit.slope_standard_error(i, j) = std::sqrt(s2 * covariance(c, c)) / scale[c];
          } else {
            fit.slope_standard_error(i, j) = INFINITY;
          }
        }
      }
    }
  }
  for (int i = 0; i < 3; ++i) fit.residual_rms_mm[i] = std::sqrt(R.col(i).squaredNorm() / n);

  // The residual grouped by each absolute commanded coordinate.
  for (int g = 0; g < 3; ++g) {
    std::map<long long, std::vector<int>> groups;
    for (int i = 0; i < n; ++i) {
      groups[std::llround(points[static_cast<std::size_t>(i)].commanded_mm[g] / kGroupResolutionMm)]
          .push_back(i);
    }
    const int count = static_cast<int>(groups.size());
    if (count < 2 || n < 3 * count) continue;
    for (int i = 0; i < 3; ++i) {
      const double total = R.col(i).squaredNorm();
      if (!(total > 0)) continue;
      double between = 0, peak = 0;
      for (const auto& [key, members] : groups) {
        double sum = 0;
        for (int m : members) sum += R(m, i);
        const double mean = sum / static_cast<double>(members.size());
        between += static_cast<double>(members.size()) * mean * mean;
        peak = std::max(peak, std::abs(mean));
      }
      const double fraction = between / total;
      if (fraction > fit.systematic_fraction[i]) {
        fit.systematic_fraction[i] = fraction;
        fit.systematic_residual_mm[i] = peak;
        fit.systematic_axis[i] = g;
      }
    }
  }
  return fit;
}

}  // namespace ncqual::solver

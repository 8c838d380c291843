// SPDX-License-Identifier: Apache-2.0
#include "ncqual/solver/circle_fit.hpp"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace ncqual::solver {
namespace {

constexpr double kPi = 3.14159265358979323846;

double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

struct Circle {
  Eigen::Vector2d centre;
  double radius;
};

// n points on an arc of `span` rad starting at `start` rad, evenly spaced (endpoints included
// unless the arc is a full circle), each moved radially by N(0, sigma).
std::vector<Eigen::Vector2d> points_on_arc(const Circle& c, int n, double start, double span,
                                           double sigma, std::mt19937_64& rng,
                                           std::vector<double>* angles = nullptr) {
  std::normal_distribution<double> noise(0, sigma > 0 ? sigma : 1);
  std::vector<Eigen::Vector2d> pts;
  const bool full = span >= 2 * kPi - 1e-12;
  for (int i = 0; i < n; ++i) {
    const double t = start + span * i / (full ? n : n - 1);
    const double r = c.radius + (sigma > 0 ? noise(rng) : 0);
    pts.push_back(c.centre + r * Eigen::Vector2d(std::cos(t), std::sin(t)));
    if (angles) angles->push_back(t);
  }
  return pts;
}

// Covariance of (cx, cy, r) for radial noise sigma at the given angles: sigma^2 (J^T J)^-1 with
// J rows (-cos t, -sin t, -1), the linearisation of e_i = |p_i - c| - r at the truth.
Eigen::Matrix3d fit_covariance(const std::vector<double>& angles, double sigma) {
  Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
  for (double t : angles) {
    const Eigen::Vector3d row(-std::cos(t), -std::sin(t), -1);
    jtj += row * row.transpose();
  }
  return sigma * sigma * jtj.inverse();
}

TEST(CircleFit, RecoversRandomCirclesExactlyWithoutNoise) {
  std::mt19937_64 rng(101);
  for (int i = 0; i < 500; ++i) {
    const Circle truth{Eigen::Vector2d(uniform(rng, -3000, 3000), uniform(rng, -3000, 3000)),
                       uniform(rng, 0.5, 500)};
    const int n = std::uniform_int_distribution<int>(3, 40)(rng);
    const double span = i % 3 == 0 ? 2 * kPi : uniform(rng, kPi / 9, 2 * kPi);
    const auto pts = points_on_arc(truth, n, uniform(rng, 0, 2 * kPi), span, 0, rng);
    const CircleFit fit = fit_circle(pts);
    ASSERT_TRUE(fit.ok()) << fit.error;
    // Rounding of coordinates ~3e3 mm is ~1e-12 mm; short arcs amplify it by ~(1/span)^2.
    const double tol = 1e-10 * (1 + truth.centre.norm()) / (span * span);
    EXPECT_NEAR(fit.centre.x(), truth.centre.x(), tol) << "case " << i;
    EXPECT_NEAR(fit.centre.y(), truth.centre.y(), tol) << "case " << i;
    EXPECT_NEAR(fit.radius, truth.radius, tol) << "case " << i;
    EXPECT_LT(fit.rms_residual, tol);
    EXPECT_EQ(fit.point_count, n);
  }
}

TEST(CircleFit, RecoversNoisyCirclesWithinTheNoiseDerivedBound) {
  std::mt19937_64 rng(102);
  int beyond_3_sigma = 0, comparisons = 0;
  for (int i = 0; i < 500; ++i) {
    const Circle truth{Eigen::Vector2d(uniform(rng, -2000, 2000), uniform(rng, -2000, 2000)),
                       uniform(rng, 5, 200)};
    const int n = std::uniform_int_distribution<int>(5, 40)(rng);
    const double span = i % 2 == 0 ? 2 * kPi : uniform(rng, kPi / 3, 2 * kPi);
    // Noise small against the radius so that the linearised covariance is the right yardstick.
    const double sigma = uniform(rng, 1e-4, 1e-2);
    std::vector<double> angles;
    const auto pts = points_on_arc(truth, n, uniform(rng, 0, 2 * kPi), span, sigma, rng, &angles);
    const CircleFit fit = fit_circle(pts);
    ASSERT_TRUE(fit.ok()) << fit.error;
    const Eigen::Matrix3d cov = fit_covariance(angles, sigma);
    const Eigen::Vector3d err(fit.centre.x() - truth.centre.x(), fit.centre.y() - truth.centre.y(),
                              fit.radius - truth.radius);
    for (int k = 0; k < 3; ++k) {
      const double sd = std::sqrt(cov(k, k));
      // 1500 comparisons: a 5 sigma bound is exceeded by chance with probability ~1e-3 overall.
      EXPECT_LE(std::abs(err(k)), 5 * sd) << "case " << i << " parameter " << k;
      beyond_3_sigma += std::abs(err(k)) > 3 * sd ? 1 : 0;
      ++comparisons;
    }
    // The residuals are the noise less what the 3 fitted parameters absorb.
    EXPECT_LT(fit.rms_residual, 3 * sigma) << "case " << i;
  }
  // P(|z| > 3) = 0.0027: expect ~4 of 1500; more than 15 means the errors are not that noise.
  EXPECT_LE(beyond_3_sigma, 15) << "of " << comparisons;
}

TEST(CircleFit, CentreOfEvenlySpacedTouchesHasSigmaSqrtTwoOverN) {
  // The bound the check-3 tests use: N evenly spaced points with radial noise sigma give a
  // centre with standard deviation sigma sqrt(2 / N) per axis.
  std::mt19937_64 rng(103);
  for (int n : {3, 4, 8}) {
    const double sigma = 0.001;
    const int trials = 4000;
    double sum_sq_x = 0, sum_sq_y = 0;
    for (int t = 0; t < trials; ++t) {
      const Circle truth{Eigen::Vector2d(1200, 800), 22};
      const auto pts = points_on_arc(truth, n, 0, 2 * kPi, sigma, rng);
      const CircleFit fit = fit_circle(pts);
      ASSERT_TRUE(fit.ok());
      sum_sq_x += std::pow(fit.centre.x() - 1200, 2);
      sum_sq_y += std::pow(fit.centre.y() - 800, 2);
    }
    const double expected = sigma * std::sqrt(2.0 / n);
    // Standard error of an sd estimated from 4000 samples: about 1.1 %; allow 6 %.
    EXPECT_NEAR(std::sqrt(sum_sq_x / trials), expected, 0.06 * expected) << "n = " << n;
    EXPECT_NEAR(std::sqrt(sum_sq_y / trials), expected, 0.06 * expected) << "n = " << n;
  }
}

TEST(CircleFit, ThreePointsGiveTheCircleThroughThem) {
  const std::vector<Eigen::Vector2d> pts = {{1, 0}, {0, 1}, {-1, 0}};
  const CircleFit fit = fit_circle(pts);
  ASSERT_TRUE(fit.ok());
  EXPECT_NEAR(fit.centre.norm(), 0, 1e-14);
  EXPECT_NEAR(fit.radius, 1, 1e-14);
}

TEST(CircleFit, GeometricFitBeatsAlgebraicOnAShortNoisyArc) {
  // The Kasa fit is biased towards small radii on short arcs; the refinement minimises the
  // geometric residuals, so its sum of squares can only be smaller.
  std::mt19937_64 rng(104);
  int closer = 0;
  for (int i = 0; i < 50; ++i) {
    const Circle truth{Eigen::Vector2d(0, 0), 50};
    const auto pts = points_on_arc(truth, 20, 0, kPi / 4, 0.05, rng);
    const CircleFit algebraic = fit_circle_algebraic(pts);
    const CircleFit geometric = fit_circle(pts);
    ASSERT_TRUE(algebraic.ok() && geometric.ok());
    EXPECT_LE(geometric.rms_residual, algebraic.rms_residual * (1 + 1e-12));
    EXPECT_GT(geometric.iterations, 0);
    closer += std::abs(geometric.radius - 50) < std::abs(algebraic.radius - 50) ? 1 : 0;
  }
  EXPECT_GT(closer, 25);
}

TEST(CircleFit, RefusesTooFewPoints) {
  for (std::size_t n = 0; n < 3; ++n) {
    std::vector<Eigen::Vector2d> pts;
    for (std::size_t i = 0; i < n; ++i) pts.emplace_back(std::cos(i), std::sin(i));
    const CircleFit fit = fit_circle(pts);
    EXPECT_FALSE(fit.ok());
    EXPECT_NE(fit.error.find(std::to_string(n) + " points"), std::string::npos) << fit.error;
    EXPECT_NE(fit.error.find("at least 3"), std::string::npos) << fit.error;
  }
}

TEST(CircleFit, RefusesNonFiniteCoordinates) {
  const double bad[] = {std::numeric_limits<double>::quiet_NaN(),
                        std::numeric_limits<double>::infinity(),
                        -std::numeric_limits<double>::infinity()};
  for (double b : bad) {
    std::vector<Eigen::Vector2d> pts = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    pts[2].y() = b;
    const CircleFit fit = fit_circle(pts);
    EXPECT_FALSE(fit.ok());
    EXPECT_NE(fit.error.find("point 2"), std::string::npos) << fit.error;
    EXPECT_NE(fit.error.find("not finite"), std::string::npos) << fit.error;
  }
}

TEST(CircleFit, RefusesCollinearAndCoincidentPoints) {
  std::mt19937_64 rng(105);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector2d origin(uniform(rng, -2000, 2000), uniform(rng, -2000, 2000));
    const double angle = uniform(rng, 0, 2 * kPi);
    const Eigen::Vector2d dir(std::cos(angle), std::sin(angle));
    const Eigen::Vector2d across(-dir.y(), dir.x());
    std::vector<Eigen::Vector2d> pts;
    const int n = std::uniform_int_distribution<int>(3, 10)(rng);
    for (int k = 0; k < n; ++k) {
      // On the line, or off it by far less than the line's extent (near-collinear).
      const double off = i % 2 == 0 ? 0.0 : uniform(rng, -1e-9, 1e-9);
      pts.push_back(origin + uniform(rng, -50, 50) * dir + off * across);
    }
    const CircleFit fit = fit_circle(pts);
    EXPECT_FALSE(fit.ok()) << "case " << i << " radius " << fit.radius;
    EXPECT_NE(fit.error.find("collinear"), std::string::npos) << fit.error;
  }
  const std::vector<Eigen::Vector2d> same = {{5, 5}, {5, 5}, {5, 5}};
  EXPECT_NE(fit_circle(same).error.find("coincide"), std::string::npos);
  const std::vector<Eigen::Vector2d> two_distinct = {{5, 5}, {5, 5}, {7, 5}};
  EXPECT_FALSE(fit_circle(two_distinct).ok());
  EXPECT_FALSE(fit_circle_algebraic(two_distinct).ok());
}

TEST(CircleFit, AcceptsAShortButGenuineArc) {
  // A 2 degree arc of a 25 mm circle is 0.87 mm long with a sagitta of 4 um: still a circle.
  std::mt19937_64 rng(106);
  const Circle truth{Eigen::Vector2d(1200, 800), 25};
  const auto pts = points_on_arc(truth, 5, 0.3, 2 * kPi / 180, 0, rng);
  const CircleFit fit = fit_circle(pts);
  ASSERT_TRUE(fit.ok()) << fit.error;
  EXPECT_NEAR(fit.radius, 25, 1e-5);
}

}  // namespace
}  // namespace ncqual::solver

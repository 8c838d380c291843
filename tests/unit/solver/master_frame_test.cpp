// SPDX-License-Identifier: Apache-2.0
#include "ncqual/solver/master_frame.hpp"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include "tracker_truth.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace ncqual::solver {
namespace {

constexpr double kPi = 3.14159265358979323846;

// ---- Truth, written independently of the code under test ------------------------------------

using testing::Placement;
using testing::TruthMachine;

Placement random_placement(std::mt19937_64& rng) { return testing::random_placement(rng, 4000); }

// X run: 11 points x = -1000 .. 1000 step 200 at (y0, z0); Y run: 10 points y = -900 .. 900
// step 200 at (x0, z0). Measured = tracker reading of the true position plus N(0, sigma) per
// coordinate (tracker frame).
struct Runs {
  std::vector<FramePoint> x_run, y_run;
  std::vector<Eigen::Vector3d> truth_x, truth_y;  // noise-free true positions, machine frame
};

Runs make_runs(const TruthMachine& m, const Placement& tracker, double sigma, std::mt19937_64& rng,
               double y0 = 0, double x0 = 0, double z0 = 500) {
  std::normal_distribution<double> noise(0, 1);
  auto n3 = [&]() -> Eigen::Vector3d {
    return Eigen::Vector3d(noise(rng), noise(rng), noise(rng)) * sigma;
  };
  Runs r;
  for (int i = 0; i <= 10; ++i) {
    const Eigen::Vector3d c(-1000 + 200 * i, y0, z0);
    const Eigen::Vector3d p = m.position(c);
    r.truth_x.push_back(p);
    r.x_run.push_back({"X" + std::to_string(i), c, tracker.to_tracker(p) + n3()});
  }
  for (int i = 0; i < 10; ++i) {
    const Eigen::Vector3d c(x0, -900 + 200 * i, z0);
    const Eigen::Vector3d p = m.position(c);
    r.truth_y.push_back(p);
    r.y_run.push_back({"Y" + std::to_string(i), c, tracker.to_tracker(p) + n3()});
  }
  return r;
}

// The expected master frame of a machine whose X and Y motions lie in the machine XY plane
// (as TruthMachine's do) with Y turned by exy about Z: the fitted lines are e_x and Rz(exy) e_y,
// the symmetric frame turns each by half the non-orthogonality, i.e. master axes Rz(exy/2) (in
// machine coordinates). master = Rz(exy/2)^T machine + t', with t' from the definition of the
// origin (mean over both runs of commanded - Rz(exy/2)^T true position).
Eigen::Isometry3d expected_tracker_to_master(const TruthMachine& m, const Placement& tracker,
                                             const Runs& runs) {
  const Eigen::Matrix3d rt =
      Eigen::AngleAxisd(m.exy / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix().transpose();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < runs.x_run.size(); ++i)
    t += runs.x_run[i].commanded_mm - rt * runs.truth_x[i];
  for (std::size_t i = 0; i < runs.y_run.size(); ++i)
    t += runs.y_run[i].commanded_mm - rt * runs.truth_y[i];
  t /= static_cast<double>(runs.x_run.size() + runs.y_run.size());
  // master = rt (R q + T) + t for a tracker point q.
  Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
  iso.linear() = rt * tracker.rotation;
  iso.translation() = rt * tracker.translation + t;
  return iso;
}

// Standard deviation of a fitted line's direction (each perpendicular component, rad) for
// N(0, sigma) noise: the slope of a least-squares line, sigma / sqrt(sum (a_i - mean a)^2), with
// a_i the positions along the run (to first order the TLS direction error is this slope error).
double direction_sigma(const std::vector<FramePoint>& run, int axis, double sigma) {
  double mean = 0;
  for (const auto& p : run) mean += p.commanded_mm(axis);
  mean /= static_cast<double>(run.size());
  double ss = 0;
  for (const auto& p : run) ss += (p.commanded_mm(axis) - mean) * (p.commanded_mm(axis) - mean);
  return sigma / std::sqrt(ss);
}

// 5-sigma bound on the error of the fitted master transform at a point q (machine frame).
// The frame's rotation error has components (about master X, Y, Z) of standard deviations
// (s_y, s_x, sqrt(s_x^2 + s_y^2) / 2) (the Y line's tilt out of the plane, the X line's, the
// mean of their in-plane turns), s_x, s_y the direction sigmas of the runs: total sigma
// sqrt(1.25 (s_x^2 + s_y^2)). The origin is fixed at the centroid of the run points, where its
// error is the mean noise, sigma / sqrt(n) per coordinate (sqrt(3/n) sigma in norm). A point q
// is moved by the translation error plus the rotation error times its distance from that
// centroid. 5 sigma of each, added.
double frame_error_bound(const Runs& runs, double sigma, const Eigen::Vector3d& q) {
  const double sx = direction_sigma(runs.x_run, 0, sigma);
  const double sy = direction_sigma(runs.y_run, 1, sigma);
  const double rot = std::sqrt(1.25 * (sx * sx + sy * sy));
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : runs.truth_x) centroid += p;
  for (const auto& p : runs.truth_y) centroid += p;
  const double n = static_cast<double>(runs.truth_x.size() + runs.truth_y.size());
  centroid /= n;
  return 5 * sigma * std::sqrt(3 / n) + 5 * rot * (q - centroid).norm();
}

std::string refusal(const std::vector<FramePoint>& x, const std::vector<FramePoint>& y) {
  try {
    fit_master_frame(x, y);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

// ---- Hand-worked examples ----------------------------------------------------------------------

// Tracker = machine frame; the X run exactly along +X, the Y run along Rz(0.01) +Y (the Y axis
// leans 0.01 rad towards -X, so the lines are 90.573 degrees apart). By hand: orthogonality
// +0.01 rad = +10000 urad; the symmetric frame turns X by +0.005 rad and Y by -0.005 rad, i.e.
// master X = (cos 0.005, sin 0.005, 0) and master Y = (-sin 0.005, cos 0.005, 0) in the tracker
// frame; Z = +Z. Straightness and scale are 0.
TEST(MasterFrame, HandWorkedSkewSplitsSymmetrically) {
  const double e = 0.01;
  std::vector<FramePoint> x, y;
  for (int i = 0; i < 5; ++i) {
    const double s = -400 + 200 * i;
    x.push_back({"X" + std::to_string(i), {s, 0, 100}, {s, 0, 100}});
    y.push_back({"Y" + std::to_string(i), {0, s, 100}, {-std::sin(e) * s, std::cos(e) * s, 100}});
  }
  const MasterFrame f = fit_master_frame(x, y);
  EXPECT_NEAR(f.orthogonality_urad, 1e4, 1e-6);
  EXPECT_NEAR((f.x_axis_instrument - Eigen::Vector3d(std::cos(e / 2), std::sin(e / 2), 0)).norm(),
              0, 1e-12);
  EXPECT_NEAR((f.y_axis_instrument - Eigen::Vector3d(-std::sin(e / 2), std::cos(e / 2), 0)).norm(),
              0, 1e-12);
  EXPECT_NEAR((f.z_axis_instrument - Eigen::Vector3d::UnitZ()).norm(), 0, 1e-12);
  // The two lines each make 0.005 rad with their master axis, in opposite senses.
  EXPECT_NEAR(f.x_run.direction_master.y(), -std::sin(e / 2), 1e-12);
  EXPECT_NEAR(f.y_run.direction_master.x(), -std::sin(e / 2), 1e-12);
  EXPECT_NEAR(f.x_run.straightness_mm.norm() + f.y_run.straightness_mm.norm(), 0, 1e-9);
  EXPECT_NEAR(f.x_run.scale_um_per_m, 0, 1e-6);
  EXPECT_NEAR(f.y_run.scale_um_per_m, 0, 1e-6);
  // Origin: the mean of commanded - R measured. By symmetry of the runs about 0 it is (0,0,0).
  EXPECT_NEAR(f.instrument_to_master.translation().norm(), 0, 1e-9);
}

// A Y line leaning the other way gives a negative orthogonality; a 1 % longer X travel a scale of
// +10000 um/m; a point 0.3 mm off the X line in +Z, the others on it, a Z straightness whose
// range is 0.3 mm (the TLS line moves towards the point, all residuals shift alike).
TEST(MasterFrame, HandWorkedSignsOfOrthogonalityScaleAndStraightness) {
  const double e = -2e-4;
  std::vector<FramePoint> x, y;
  for (int i = 0; i < 5; ++i) {
    const double s = -400 + 200 * i;
    Eigen::Vector3d mx(1.01 * s, 0, 0);
    if (i == 2) mx.z() = 0.3;
    x.push_back({"X" + std::to_string(i), {s, 0, 0}, mx});
    y.push_back({"Y" + std::to_string(i), {0, s, 0}, {-std::sin(e) * s, std::cos(e) * s, 0}});
  }
  const MasterFrame f = fit_master_frame(x, y);
  EXPECT_NEAR(f.orthogonality_urad, -200, 1e-6);
  EXPECT_NEAR(f.x_run.scale_um_per_m, 1e4, 1e-6);
  EXPECT_NEAR(f.x_run.straightness_mm(1), 0.3, 1e-9);
  EXPECT_NEAR(f.x_run.straightness_mm(0), 0, 1e-9);
  // The middle point is 0.3 - 0.3/5 = 0.24 mm from the line, the largest distance.
  EXPECT_NEAR(f.x_run.max_distance_mm, 0.24, 1e-9);
  EXPECT_NEAR(f.x_run.points[2].cross_mm(1), 0.24, 1e-9);
}

// ---- Simulated machines ----------------------------------------------------------------------

// A perfect machine without noise: the master frame is the machine frame, whatever the tracker's
// placement, and everything the runs report is zero.
TEST(MasterFrame, PerfectMachineGivesTheTrackerPlacementExactly) {
  for (std::uint64_t seed : {11u, 12u, 13u}) {
    std::mt19937_64 rng(seed);
    const Placement tracker = random_placement(rng);
    const Runs runs = make_runs(TruthMachine{}, tracker, 0, rng);
    const MasterFrame f = fit_master_frame(runs.x_run, runs.y_run);
    // master = machine = R tracker + T.
    EXPECT_NEAR((f.instrument_to_master.linear() - tracker.rotation).norm(), 0, 1e-12);
    EXPECT_NEAR((f.instrument_to_master.translation() - tracker.translation).norm(), 0, 1e-8);
    EXPECT_NEAR(f.orthogonality_urad, 0, 1e-6);
    EXPECT_NEAR(f.x_run.scale_um_per_m, 0, 1e-6);
    EXPECT_NEAR(f.y_run.scale_um_per_m, 0, 1e-6);
    EXPECT_LT(f.x_run.max_distance_mm, 1e-9);
    EXPECT_LT(f.y_run.max_distance_mm, 1e-9);
    EXPECT_LT(f.origin_rms_mm, 1e-9);
  }
}

// An erroneous machine seen by a randomly placed tracker with noise. Bounds (5 sigma):
//  - orthogonality: the difference of two direction errors, sqrt(s_x^2 + s_y^2) (s_* from
//    direction_sigma: 0.002 mm / 2098 mm = 0.95 urad for X, 0.002 / 1817 = 1.1 urad for Y);
//  - scale: slope of a least-squares line against the commanded position, same s_* (um/m);
//  - straightness: max - min of (truth + noise residual); each residual's noise part has a
//    standard deviation below sigma, so the range moves by at most 2 * 5 sigma;
//  - the transform: frame_error_bound at each run point.
TEST(MasterFrame, RecoversInjectedErrorsWithinNoiseBounds) {
  TruthMachine m;
  m.sx = 80e-6;
  m.sy = -50e-6;
  m.sz = 30e-6;
  m.exy = 60e-6;
  m.bow_x_in_y = 0.05;
  m.bow_x_in_z = -0.04;
  m.bow_y_in_x = 0.03;
  m.bow_y_in_z = 0.06;
  m.half_x = 1000;
  m.half_y = 900;
  m.offset = Eigen::Vector3d(0.3, -0.2, 0.1);
  const double sigma = 0.002;
  for (std::uint64_t seed : {21u, 22u, 23u, 24u, 25u}) {
    std::mt19937_64 rng(seed);
    const Placement tracker = random_placement(rng);
    const Runs runs = make_runs(m, tracker, sigma, rng);
    const MasterFrame f = fit_master_frame(runs.x_run, runs.y_run);
    const double sx = direction_sigma(runs.x_run, 0, sigma);
    const double sy = direction_sigma(runs.y_run, 1, sigma);

    EXPECT_NEAR(f.orthogonality_urad, m.exy * 1e6, 5 * std::hypot(sx, sy) * 1e6) << seed;
    EXPECT_NEAR(f.x_run.scale_um_per_m, m.sx * 1e6, 5 * sx * 1e6) << seed;
    EXPECT_NEAR(f.y_run.scale_um_per_m, m.sy * 1e6, 5 * sy * 1e6) << seed;
    // Sampled sags: b (1 - (c/half)^2) is b at c = 0 and 0 at the ends (X run), and
    // b (1 - (100/900)^2) .. 0 (Y run, y = +-100 .. +-900): ranges b and b (1 - 1/81).
    const double y_fraction = 1 - 1.0 / 81;
    EXPECT_NEAR(f.x_run.straightness_mm(0), std::abs(m.bow_x_in_y), 10 * sigma) << seed;
    EXPECT_NEAR(f.x_run.straightness_mm(1), std::abs(m.bow_x_in_z), 10 * sigma) << seed;
    EXPECT_NEAR(f.y_run.straightness_mm(0), std::abs(m.bow_y_in_x) * y_fraction, 10 * sigma)
        << seed;
    EXPECT_NEAR(f.y_run.straightness_mm(1), std::abs(m.bow_y_in_z) * y_fraction, 10 * sigma)
        << seed;

    const Eigen::Isometry3d expected = expected_tracker_to_master(m, tracker, runs);
    for (const auto* run : {&runs.truth_x, &runs.truth_y}) {
      for (const Eigen::Vector3d& p : *run) {
        const Eigen::Vector3d q = tracker.to_tracker(p);
        EXPECT_LT((f.instrument_to_master * q - expected * q).norm(),
                  frame_error_bound(runs, sigma, p))
            << seed;
      }
    }
    // By the definition of the origin, the deviations average to zero over both runs.
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& r : f.x_run.points) mean += r.deviation_mm;
    for (const auto& r : f.y_run.points) mean += r.deviation_mm;
    EXPECT_LT(mean.norm() / 21, 1e-9);
    // Directions are unit, oriented towards increasing commanded coordinate.
    EXPECT_GT(f.x_run.direction_master.x(), 0.999);
    EXPECT_GT(f.y_run.direction_master.y(), 0.999);
  }
}

// The same machine and the same noise (drawn in the machine frame) seen from two tracker
// placements gives the same master coordinates: the fit depends on the tracker only through a
// rigid transform.
TEST(MasterFrame, IndependentOfTrackerPlacementAndPointOrder) {
  TruthMachine m;
  m.sx = 40e-6;
  m.exy = -30e-6;
  m.bow_x_in_z = 0.02;
  for (std::uint64_t seed : {31u, 32u, 33u}) {
    std::mt19937_64 rng(seed);
    const Placement a = random_placement(rng);
    const Placement b = random_placement(rng);
    Placement machine;  // identity: tracker = machine
    Runs ra = make_runs(m, machine, 0.003, rng);
    Runs rb = ra;
    for (auto* run : {&ra.x_run, &ra.y_run}) {
      for (auto& p : *run) p.measured_mm = a.to_tracker(p.measured_mm);
    }
    for (auto* run : {&rb.x_run, &rb.y_run}) {
      for (auto& p : *run) p.measured_mm = b.to_tracker(p.measured_mm);
    }
    // b also lists its points in reverse order.
    std::reverse(rb.x_run.begin(), rb.x_run.end());
    std::reverse(rb.y_run.begin(), rb.y_run.end());
    const MasterFrame fa = fit_master_frame(ra.x_run, ra.y_run);
    const MasterFrame fb = fit_master_frame(rb.x_run, rb.y_run);
    EXPECT_NEAR(fa.orthogonality_urad, fb.orthogonality_urad, 1e-5);
    EXPECT_NEAR(fa.x_run.scale_um_per_m, fb.x_run.scale_um_per_m, 1e-5);
    EXPECT_NEAR((fa.x_run.straightness_mm - fb.x_run.straightness_mm).norm(), 0, 1e-9);
    const std::size_t n = ra.x_run.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d da = fa.x_run.points[i].deviation_mm;
      const Eigen::Vector3d db = fb.x_run.points[n - 1 - i].deviation_mm;
      EXPECT_NEAR((da - db).norm(), 0, 1e-8);
    }
  }
}

// ---- Refusals ----------------------------------------------------------------------------------

class MasterFrameRefusals : public ::testing::Test {
 protected:
  void SetUp() override {
    std::mt19937_64 rng(41);
    runs_ = make_runs(TruthMachine{}, random_placement(rng), 0.001, rng);
  }
  Runs runs_;
};

TEST_F(MasterFrameRefusals, TooFewPoints) {
  auto x = runs_.x_run;
  x.resize(2);
  const std::string why = refusal(x, runs_.y_run);
  EXPECT_NE(why.find("x_run has 2 points"), std::string::npos) << why;
  auto y = runs_.y_run;
  y.resize(1);
  EXPECT_NE(refusal(runs_.x_run, y).find("y_run has 1 points"), std::string::npos);
}

TEST_F(MasterFrameRefusals, RunMovingInAnotherAxis) {
  auto x = runs_.x_run;
  x[4].commanded_mm.y() += 0.01;
  const std::string why = refusal(x, runs_.y_run);
  EXPECT_NE(why.find("x_run point 'X4' commanded y = 0.01"), std::string::npos) << why;
  auto y = runs_.y_run;
  y[3].commanded_mm.z() += 1e-3;
  const std::string why_y = refusal(runs_.x_run, y);
  EXPECT_NE(why_y.find("y_run point 'Y3' commanded z = 500.001"), std::string::npos) << why_y;
  // Within 1e-6 mm is constant.
  auto ok = runs_.x_run;
  ok[4].commanded_mm.y() += 5e-7;
  EXPECT_EQ(refusal(ok, runs_.y_run), "");
}

TEST_F(MasterFrameRefusals, DuplicateCommandedPositions) {
  auto x = runs_.x_run;
  x[7].commanded_mm = x[2].commanded_mm;
  const std::string why = refusal(x, runs_.y_run);
  EXPECT_NE(why.find("x_run points 'X2' and 'X7' have the same commanded x = -600"),
            std::string::npos)
      << why;
}

TEST_F(MasterFrameRefusals, RunsAtDifferentZ) {
  auto y = runs_.y_run;
  for (auto& p : y) p.commanded_mm.z() = 600;
  const std::string why = refusal(runs_.x_run, y);
  EXPECT_NE(why.find("x_run is at commanded z = 500 mm"), std::string::npos) << why;
  EXPECT_NE(why.find("y_run at z = 600 mm"), std::string::npos) << why;
}

TEST_F(MasterFrameRefusals, NonFiniteValues) {
  auto x = runs_.x_run;
  x[5].measured_mm.z() = std::numeric_limits<double>::quiet_NaN();
  const std::string why = refusal(x, runs_.y_run);
  EXPECT_NE(why.find("x_run point 'X5' measured_mm"), std::string::npos) << why;
  EXPECT_NE(why.find("not finite"), std::string::npos) << why;
  auto y = runs_.y_run;
  y[0].commanded_mm.y() = std::numeric_limits<double>::infinity();
  const std::string why_y = refusal(runs_.x_run, y);
  EXPECT_NE(why_y.find("y_run point 'Y0' commanded_mm = (0, inf, 500)"), std::string::npos)
      << why_y;
}

TEST_F(MasterFrameRefusals, NearlyParallelLines) {
  // The Y run measured along the X run's line (the runs mixed up): 0 degrees apart.
  auto y = runs_.y_run;
  for (std::size_t i = 0; i < y.size(); ++i) {
    y[i].measured_mm = runs_.x_run[0].measured_mm +
                       (runs_.x_run[10].measured_mm - runs_.x_run[0].measured_mm) *
                           (y[i].commanded_mm.y() + 1000) / 2000.0 +
                       Eigen::Vector3d(0, 0, 0.001 * static_cast<double>(i % 2));
  }
  const std::string why = refusal(runs_.x_run, y);
  EXPECT_NE(why.find("(nearly) parallel"), std::string::npos) << why;
}

TEST_F(MasterFrameRefusals, TravelNotMatchingTheCommandedOne) {
  // Tracker readings in inches.
  auto x = runs_.x_run;
  for (auto& p : x) p.measured_mm /= 25.4;
  const std::string why = refusal(x, runs_.y_run);
  EXPECT_NE(why.find("x_run: the measured travel along the fitted line is 0.039"),
            std::string::npos)
      << why;
  // A target that did not move.
  auto y = runs_.y_run;
  for (auto& p : y) p.measured_mm = runs_.y_run[0].measured_mm;
  EXPECT_NE(refusal(runs_.x_run, y).find("y_run: the measured travel"), std::string::npos);
}

}  // namespace
}  // namespace ncqual::solver

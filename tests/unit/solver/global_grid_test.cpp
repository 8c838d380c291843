// SPDX-License-Identifier: Apache-2.0
#include "ncqual/solver/global_grid.hpp"
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

// The machine of these tests: X travel +-2000 mm.
struct TruthMachine : testing::TruthMachine {
  TruthMachine() { half_x = 2000; }
};

// Angle between two vectors minus 90 degrees, rad (by acos, the test's own formula).
double truth_squareness(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(a.dot(b) / (a.norm() * b.norm())) - kPi / 2;
}

Placement random_placement(std::mt19937_64& rng) { return testing::random_placement(rng, 5000); }

// The measurement: X run (11 points, x = -2000 .. 2000 step 400, y = 0, z = 300), Y run (10
// points, y = -900 .. 900 step 200, x = 0, z = 300) and the patent's grid of 216 points: 9 x
// (-2000 .. 2000 step 500) by 6 y (-1000 .. 1000 step 400) on 4 planes z = 0, 200, 400, 600.
// Every true position gets N(0, sigma) noise per coordinate, drawn in the machine frame (so that
// two placements can see the very same noise), and is then read in the tracker frame.
struct Measurement {
  std::vector<FramePoint> x_run, y_run, grid;
  std::vector<Eigen::Vector3d> truth_runs;  // noise-free true positions of the run points
  std::vector<Eigen::Vector3d> truth_grid;  // and of the grid points (machine frame)
};

Measurement measure(const TruthMachine& m, double sigma, std::mt19937_64& rng) {
  std::normal_distribution<double> noise(0, 1);
  auto n3 = [&]() -> Eigen::Vector3d {
    return Eigen::Vector3d(noise(rng), noise(rng), noise(rng)) * sigma;
  };
  Measurement out;
  for (int i = 0; i <= 10; ++i) {
    const Eigen::Vector3d c(-2000 + 400 * i, 0, 300);
    out.truth_runs.push_back(m.position(c));
    out.x_run.push_back({"X" + std::to_string(i), c, out.truth_runs.back() + n3()});
  }
  for (int i = 0; i < 10; ++i) {
    const Eigen::Vector3d c(0, -900 + 200 * i, 300);
    out.truth_runs.push_back(m.position(c));
    out.y_run.push_back({"Y" + std::to_string(i), c, out.truth_runs.back() + n3()});
  }
  for (int k = 0; k < 4; ++k) {
    for (int j = 0; j < 6; ++j) {
      for (int i = 0; i < 9; ++i) {
        const Eigen::Vector3d c(-2000 + 500 * i, -1000 + 400 * j, 200 * k);
        out.truth_grid.push_back(m.position(c));
        out.grid.push_back(
            {"Z" + std::to_string(k) + "Y" + std::to_string(j) + "X" + std::to_string(i), c,
             out.truth_grid.back() + n3()});
      }
    }
  }
  return out;
}

Measurement seen_from(Measurement m, const Placement& tracker) {
  for (auto* set : {&m.x_run, &m.y_run, &m.grid}) {
    for (auto& p : *set) p.measured_mm = tracker.to_tracker(p.measured_mm);
  }
  return m;
}

// Expected master coordinates of a true position: the runs' lines are e_x and Rz(exy) e_y, the
// symmetric frame turns each by half their non-orthogonality, so master = Rz(exy/2)^T machine + t'
// with t' the mean over the run points of (commanded - Rz(exy/2)^T true position).
struct ExpectedMaster {
  Eigen::Matrix3d rt;
  Eigen::Vector3d t;
  Eigen::Vector3d operator()(const Eigen::Vector3d& machine) const { return rt * machine + t; }
};

ExpectedMaster expected_master(const TruthMachine& m, const Measurement& meas) {
  ExpectedMaster e;
  e.rt = Eigen::AngleAxisd(m.exy / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix().transpose();
  e.t = Eigen::Vector3d::Zero();
  std::size_t k = 0;
  for (const auto* run : {&meas.x_run, &meas.y_run}) {
    for (const auto& p : *run) e.t += p.commanded_mm - e.rt * meas.truth_runs[k++];
  }
  e.t /= static_cast<double>(k);
  return e;
}

// 5-sigma bound on the master frame's error at a point q (machine frame); the derivation is in
// master_frame_test.cpp (frame_error_bound): 5 sigma sqrt(3/n) at the runs' centroid plus
// 5 sqrt(1.25 (s_x^2 + s_y^2)) |q - centroid| for the rotation, s = sigma / sqrt(sum (a - mean)^2)
// the direction sigma of each run.
double frame_error_bound(const Measurement& meas, double sigma, const Eigen::Vector3d& q) {
  auto spread = [](const std::vector<FramePoint>& run, int axis) {
    double mean = 0, ss = 0;
    for (const auto& p : run) mean += p.commanded_mm(axis);
    mean /= static_cast<double>(run.size());
    for (const auto& p : run) ss += std::pow(p.commanded_mm(axis) - mean, 2);
    return std::sqrt(ss);
  };
  const double sx = sigma / spread(meas.x_run, 0), sy = sigma / spread(meas.y_run, 1);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : meas.truth_runs) centroid += p;
  const double n = static_cast<double>(meas.truth_runs.size());
  centroid /= n;
  return 5 * sigma * std::sqrt(3 / n) +
         5 * std::sqrt(1.25 * (sx * sx + sy * sy)) * (q - centroid).norm();
}

// sqrt(sum over the grid of (c_k - mean c_k)^2): the lever of the affine fit's column k.
double grid_spread(const std::vector<FramePoint>& grid, int k) {
  double mean = 0, ss = 0;
  for (const auto& p : grid) mean += p.commanded_mm(k);
  mean /= static_cast<double>(grid.size());
  for (const auto& p : grid) ss += std::pow(p.commanded_mm(k) - mean, 2);
  return std::sqrt(ss);
}

std::string refusal(const MasterFrame& f, const std::vector<FramePoint>& grid,
                    const GridOptions& options = {}) {
  try {
    analyze_grid(f, grid, options);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

// ---- Hand-worked examples ----------------------------------------------------------------------

// Identity frame (the tracker reads master coordinates), 8 points on 2 planes with chosen
// deviations: by hand, max |dev| = |(0, 0.3, 0.4)| = 0.5 at "B", rms = sqrt((0.25 + 0.01 + 0.10 +
// 0.0004 + 0.16 + 0.0009 + 0.01) / 8), max |dx| 0.3 (D), |dy| 0.3 (B), |dz| 0.4 (B, F);
// plane z = 0 worst "B", plane z = 100 worst "F" (0.4).
TEST(GlobalGrid, HandWorkedDeviationsAndWorstRegions) {
  const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> cd = {
      {{0, 0, 0}, {0, 0, 0}},        {{100, 0, 0}, {0, 0.3, 0.4}},
      {{0, 100, 0}, {0.1, 0, 0}},    {{100, 100, 0}, {-0.3, 0, 0.1}},
      {{0, 0, 100}, {0, 0.02, 0}},   {{100, 0, 100}, {0, 0, -0.4}},
      {{0, 100, 100}, {0, 0, 0.03}}, {{100, 100, 100}, {0.1, 0, 0}},
  };
  const char* labels[] = {"A", "B", "C", "D", "E", "F", "G", "H"};
  std::vector<FramePoint> grid;
  for (std::size_t i = 0; i < cd.size(); ++i) {
    grid.push_back({labels[i], cd[i].first, cd[i].first + cd[i].second});
  }
  GridOptions options;
  options.worst_point_count = 3;
  const GridAnalysis g = analyze_grid(MasterFrame{}, grid, options);
  EXPECT_NEAR(g.max_deviation_mm, 0.5, 1e-12);
  EXPECT_EQ(g.max_deviation_label, "B");
  EXPECT_NEAR(g.rms_deviation_mm,
              std::sqrt((0.25 + 0.01 + 0.10 + 0.0004 + 0.16 + 0.0009 + 0.01) / 8), 1e-12);
  EXPECT_NEAR(g.max_abs_dx_mm, 0.3, 1e-12);
  EXPECT_NEAR(g.max_abs_dy_mm, 0.3, 1e-12);
  EXPECT_NEAR(g.max_abs_dz_mm, 0.4, 1e-12);
  ASSERT_EQ(g.worst_points.size(), 3u);
  EXPECT_EQ(g.points[g.worst_points[0]].label, "B");  // 0.5
  EXPECT_EQ(g.points[g.worst_points[1]].label, "F");  // 0.4
  EXPECT_EQ(g.points[g.worst_points[2]].label, "D");  // sqrt(0.1) = 0.316
  ASSERT_EQ(g.planes.size(), 2u);
  EXPECT_NEAR(g.planes[0].z_mm, 0, 1e-12);
  EXPECT_EQ(g.planes[0].worst_label, "B");
  EXPECT_EQ(g.planes[0].point_count, 4);
  EXPECT_NEAR(g.planes[1].z_mm, 100, 1e-12);
  EXPECT_EQ(g.planes[1].worst_label, "F");
  EXPECT_NEAR(g.planes[1].worst_deviation_mm, 0.4, 1e-12);
  EXPECT_NEAR((g.planes[1].max_abs_deviation_mm - Eigen::Vector3d(0.1, 0.02, 0.4)).norm(), 0,
              1e-12);
  EXPECT_NEAR((g.points[3].deviation_mm - Eigen::Vector3d(-0.3, 0, 0.1)).norm(), 0, 1e-12);
}

// The ISO 230-1 signs, each error alone on a noise-free machine read directly in machine
// coordinates: a Y motion turned by +e about +Z is EC(0X)Y = +e (the XY angle is 90 + e);
// Z turned by +e about +X is EA(0Y)Z = +e (YZ angle 90 + e); Z turned by +e about +Y is
// EB(0X)Z = +e, where the ZX angle is 90 - e, so squareness_zx = -e.
TEST(GlobalGrid, IsoSquarenessSignsFromSingleRotations) {
  const double e = 1e-4;
  std::mt19937_64 rng(1);
  for (int which = 0; which < 3; ++which) {
    TruthMachine m;
    (which == 0 ? m.exy : which == 1 ? m.eyz : m.ezx) = e;
    const Measurement meas = measure(m, 0, rng);
    const GridAnalysis g = analyze_grid(MasterFrame{}, meas.grid);
    const double tol = 1e-6;  // urad
    EXPECT_NEAR(g.affine.squareness_xy_urad, which == 0 ? 100 : 0, tol) << which;
    EXPECT_NEAR(g.affine.squareness_yz_urad, which == 1 ? 100 : 0, tol) << which;
    EXPECT_NEAR(g.affine.squareness_zx_urad, which == 2 ? -100 : 0, tol) << which;
    EXPECT_NEAR(g.affine.ec_0x_y_urad, which == 0 ? 100 : 0, tol) << which;
    EXPECT_NEAR(g.affine.ea_0y_z_urad, which == 1 ? 100 : 0, tol) << which;
    EXPECT_NEAR(g.affine.eb_0x_z_urad, which == 2 ? 100 : 0, tol) << which;
    EXPECT_NEAR(g.affine.scale_x_um_per_m, 0, 1e-6);
    EXPECT_LT(g.affine.residual_rms_mm, 1e-9);
  }
}

// ---- Simulated machines ----------------------------------------------------------------------

TEST(GlobalGrid, PerfectMachineGivesZero) {
  for (std::uint64_t seed : {51u, 52u, 53u}) {
    std::mt19937_64 rng(seed);
    const Measurement meas = seen_from(measure(TruthMachine{}, 0, rng), random_placement(rng));
    const GridAnalysis g = analyze_grid(meas.x_run, meas.y_run, meas.grid);
    EXPECT_LT(g.max_deviation_mm, 1e-8) << seed;
    EXPECT_NEAR(g.affine.scale_x_um_per_m, 0, 1e-5);
    EXPECT_NEAR(g.affine.scale_y_um_per_m, 0, 1e-5);
    EXPECT_NEAR(g.affine.scale_z_um_per_m, 0, 1e-5);
    EXPECT_NEAR(g.affine.squareness_xy_urad, 0, 1e-5);
    EXPECT_NEAR(g.affine.squareness_yz_urad, 0, 1e-5);
    EXPECT_NEAR(g.affine.squareness_zx_urad, 0, 1e-5);
    EXPECT_EQ(g.points.size(), 216u);
    EXPECT_EQ(g.planes.size(), 4u);
  }
}

// An erroneous machine, randomly placed tracker, noise sigma = 2 um. Bounds (5 sigma):
//  - deviation of each point, per coordinate: its own noise (sigma) plus the master frame's error
//    there (frame_error_bound);
//  - scale of axis k: the grid is a full factorial, so the centred commanded coordinates are
//    uncorrelated and each column of M is a simple regression slope with standard deviation
//    sigma / S_k, S_k = sqrt(sum (c_k - mean)^2) (S_x = 18974, S_y = 10040, S_z = 3286 mm);
//    the rigid master frame error changes neither lengths nor angles;
//  - squareness of k and l: the two columns' cross components, sigma sqrt(1/S_k^2 + 1/S_l^2).
// The quadratic bows are symmetric in a symmetric grid: they add nothing to M.
TEST(GlobalGrid, RecoversScaleSquarenessAndDeviationsWithinNoiseBounds) {
  TruthMachine m;
  m.sx = 80e-6;
  m.sy = -60e-6;
  m.sz = 120e-6;
  m.exy = 40e-6;
  m.eyz = 30e-6;
  m.ezx = -25e-6;
  m.bow_x_in_y = 0.03;
  m.bow_x_in_z = -0.05;
  m.bow_y_in_z = 0.02;
  m.offset = Eigen::Vector3d(0.2, -0.1, 0.05);
  const double sigma = 0.002;
  for (std::uint64_t seed : {61u, 62u, 63u, 64u, 65u}) {
    std::mt19937_64 rng(seed);
    const Measurement truth_frame = measure(m, sigma, rng);
    const Measurement meas = seen_from(truth_frame, random_placement(rng));
    const GridAnalysis g = analyze_grid(meas.x_run, meas.y_run, meas.grid);

    const double sx = sigma / grid_spread(meas.grid, 0);
    const double sy = sigma / grid_spread(meas.grid, 1);
    const double sz = sigma / grid_spread(meas.grid, 2);
    EXPECT_NEAR(g.affine.scale_x_um_per_m, m.sx * 1e6, 5 * sx * 1e6) << seed;
    EXPECT_NEAR(g.affine.scale_y_um_per_m, m.sy * 1e6, 5 * sy * 1e6) << seed;
    EXPECT_NEAR(g.affine.scale_z_um_per_m, m.sz * 1e6, 5 * sz * 1e6) << seed;
    EXPECT_NEAR(g.affine.squareness_xy_urad, truth_squareness(m.x_motion(), m.y_motion()) * 1e6,
                5 * std::hypot(sx, sy) * 1e6)
        << seed;
    EXPECT_NEAR(g.affine.squareness_yz_urad, truth_squareness(m.y_motion(), m.z_motion()) * 1e6,
                5 * std::hypot(sy, sz) * 1e6)
        << seed;
    EXPECT_NEAR(g.affine.squareness_zx_urad, truth_squareness(m.z_motion(), m.x_motion()) * 1e6,
                5 * std::hypot(sz, sx) * 1e6)
        << seed;
    // The injected squareness is recovered under its ISO name too (first order in the angles).
    EXPECT_NEAR(g.affine.eb_0x_z_urad, m.ezx * 1e6, 5 * std::hypot(sz, sx) * 1e6 + 0.01);

    const ExpectedMaster expected = expected_master(m, meas);
    double expected_max = 0;
    double worst_error = 0;
    for (std::size_t i = 0; i < g.points.size(); ++i) {
      const Eigen::Vector3d dev = expected(meas.truth_grid[i]) - meas.grid[i].commanded_mm;
      const double bound = 5 * sigma + frame_error_bound(meas, sigma, meas.truth_grid[i]);
      const Eigen::Vector3d err = g.points[i].deviation_mm - dev;
      EXPECT_LT(err.cwiseAbs().maxCoeff(), bound) << seed << " " << g.points[i].label;
      expected_max = std::max(expected_max, dev.norm());
      worst_error = std::max(worst_error, bound * std::sqrt(3.0));
    }
    // |max |a| - max |b|| <= max |a - b|.
    EXPECT_NEAR(g.max_deviation_mm, expected_max, worst_error) << seed;
    // The deviations are real (hundreds of um), far above the bounds (tens of um).
    EXPECT_GT(expected_max, 0.2);

    // Worst points in order, and each plane's worst is its largest.
    for (std::size_t k = 1; k < g.worst_points.size(); ++k) {
      EXPECT_GE(g.points[g.worst_points[k - 1]].deviation_norm_mm,
                g.points[g.worst_points[k]].deviation_norm_mm);
    }
    EXPECT_EQ(g.points[g.worst_points[0]].label, g.max_deviation_label);
    ASSERT_EQ(g.planes.size(), 4u);
    for (int k = 0; k < 4; ++k) {
      const GridPlaneSummary& plane = g.planes[static_cast<std::size_t>(k)];
      EXPECT_NEAR(plane.z_mm, 200 * k, 1e-9);
      EXPECT_EQ(plane.point_count, 54);
      double worst = 0;
      for (const auto& r : g.points) {
        if (std::abs(r.commanded_mm.z() - plane.z_mm) < 1) {
          worst = std::max(worst, r.deviation_norm_mm);
        }
      }
      EXPECT_EQ(plane.worst_deviation_mm, worst);
      EXPECT_EQ(g.points[plane.worst_index].label, plane.worst_label);
    }
    // Residual of the affine fit: the noise plus the bows (their sag about its mean, ~ the
    // sag / 3 in rms); a loose check that it is of that size.
    EXPECT_GT(g.affine.residual_rms_mm, sigma);
    EXPECT_LT(g.affine.residual_rms_mm, 0.05);
  }
}

// Frame invariance: the same machine and the same noise seen from two tracker placements give
// the same grid results (up to rounding).
TEST(GlobalGrid, SameResultsFromTwoTrackerPlacements) {
  TruthMachine m;
  m.sx = 50e-6;
  m.exy = -70e-6;
  m.eyz = 20e-6;
  m.bow_x_in_z = 0.04;
  for (std::uint64_t seed : {71u, 72u, 73u}) {
    std::mt19937_64 rng(seed);
    const Measurement machine = measure(m, 0.003, rng);
    const Measurement a = seen_from(machine, random_placement(rng));
    const Measurement b = seen_from(machine, random_placement(rng));
    const GridAnalysis ga = analyze_grid(a.x_run, a.y_run, a.grid);
    const GridAnalysis gb = analyze_grid(b.x_run, b.y_run, b.grid);
    for (std::size_t i = 0; i < ga.points.size(); ++i) {
      EXPECT_LT((ga.points[i].deviation_mm - gb.points[i].deviation_mm).norm(), 1e-8);
    }
    EXPECT_NEAR(ga.max_deviation_mm, gb.max_deviation_mm, 1e-8);
    EXPECT_EQ(ga.max_deviation_label, gb.max_deviation_label);
    EXPECT_NEAR(ga.affine.scale_x_um_per_m, gb.affine.scale_x_um_per_m, 1e-4);
    EXPECT_NEAR(ga.affine.scale_z_um_per_m, gb.affine.scale_z_um_per_m, 1e-4);
    EXPECT_NEAR(ga.affine.squareness_xy_urad, gb.affine.squareness_xy_urad, 1e-4);
    EXPECT_NEAR(ga.affine.squareness_yz_urad, gb.affine.squareness_yz_urad, 1e-4);
    EXPECT_NEAR(ga.affine.squareness_zx_urad, gb.affine.squareness_zx_urad, 1e-4);
    EXPECT_NEAR(ga.affine.residual_rms_mm, gb.affine.residual_rms_mm, 1e-9);
  }
}

// ---- Refusals ----------------------------------------------------------------------------------

class GlobalGridRefusals : public ::testing::Test {
 protected:
  void SetUp() override {
    std::mt19937_64 rng(81);
    meas_ = measure(TruthMachine{}, 0.001, rng);
  }
  Measurement meas_;
  MasterFrame frame_;  // identity
};

TEST_F(GlobalGridRefusals, TooFewPoints) {
  std::vector<FramePoint> grid(meas_.grid.begin(), meas_.grid.begin() + 4);
  const std::string why = refusal(frame_, grid);
  EXPECT_NE(why.find("grid has 4 points; at least 5"), std::string::npos) << why;
}

TEST_F(GlobalGridRefusals, DuplicateLabels) {
  auto grid = meas_.grid;
  grid[100].label = grid[7].label;
  const std::string why = refusal(frame_, grid);
  EXPECT_NE(why.find("grid label 'Z0Y0X7' appears twice"), std::string::npos) << why;
}

TEST_F(GlobalGridRefusals, AllPointsOnOnePlane) {
  std::vector<FramePoint> grid(meas_.grid.begin(), meas_.grid.begin() + 54);  // plane z = 0
  const std::string why = refusal(frame_, grid);
  EXPECT_NE(why.find("all 54 grid points lie on the one plane z = 0 mm"), std::string::npos) << why;
  EXPECT_NE(why.find("Z scale and the YZ and ZX squareness would be undefined"), std::string::npos)
      << why;
  // One constant X column is named too.
  std::vector<FramePoint> column;
  for (const auto& p : meas_.grid) {
    if (p.commanded_mm.x() == 500) column.push_back(p);
  }
  EXPECT_NE(refusal(frame_, column).find("one plane x = 500 mm"), std::string::npos);
  // A tilted plane (z = 0.1 x): coplanar though no coordinate is constant.
  auto tilted = meas_.grid;
  for (auto& p : tilted) p.commanded_mm.z() = 0.1 * p.commanded_mm.x();
  EXPECT_NE(refusal(frame_, tilted).find("(nearly) coplanar"), std::string::npos);
}

TEST_F(GlobalGridRefusals, NonFiniteValues) {
  auto grid = meas_.grid;
  grid[3].measured_mm.x() = std::numeric_limits<double>::quiet_NaN();
  const std::string why = refusal(frame_, grid);
  EXPECT_NE(why.find("grid point 'Z0Y0X3' measured_mm = (nan"), std::string::npos) << why;
  grid = meas_.grid;
  grid[5].commanded_mm.y() = std::numeric_limits<double>::infinity();
  EXPECT_NE(refusal(frame_, grid).find("grid point 'Z0Y0X5' commanded_mm"), std::string::npos);
}

TEST_F(GlobalGridRefusals, BadFrameAndOptions) {
  MasterFrame bad;
  bad.instrument_to_master.linear() *= 1.01;  // not a rotation
  EXPECT_NE(refusal(bad, meas_.grid).find("not a rotation"), std::string::npos);
  GridOptions options;
  options.worst_point_count = -1;
  EXPECT_NE(refusal(frame_, meas_.grid, options).find("options.worst_point_count = -1"),
            std::string::npos);
  options = GridOptions{};
  options.plane_tolerance_mm = 0;
  EXPECT_NE(refusal(frame_, meas_.grid, options).find("options.plane_tolerance_mm = 0"),
            std::string::npos);
}

TEST_F(GlobalGridRefusals, FrameRefusalsPassThroughTheConvenienceOverload) {
  auto x = meas_.x_run;
  x.resize(2);
  try {
    analyze_grid(x, meas_.y_run, meas_.grid);
    ADD_FAILURE() << "no refusal";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("fit_master_frame: x_run has 2 points"),
              std::string::npos);
  }
}

}  // namespace
}  // namespace ncqual::solver

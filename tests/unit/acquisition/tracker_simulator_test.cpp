// SPDX-License-Identifier: Apache-2.0
// The laser tracker simulator: its readings are the true target seen from the tracker's frame,
// with the configured noise in range and angles; its machine has the configured reversal,
// thermal expansion, rigid-body and wrist errors.
#include "ncqual/sim/tracker_simulator.hpp"

#include "ncqual/common/kinematics.hpp"
#include "ncqual/common/units.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

namespace ncqual::sim {
namespace {

MachineConfig pm1() { return load_machine_config(NCQUAL_SOURCE_DIR "/deploy/machines/pm1.yaml"); }

SimulatorConfig quiet(const MachineConfig& m) {
  SimulatorConfig c = m.simulator;
  c.volumetric.repeatability_sigma_mm = 0;
  c.tracker.angular_sigma_rad = 0;
  c.tracker.radial_sigma_mm = 0;
  c.tracker.radial_sigma_mm_per_m = 0;
  return c;
}

CheckRequest request(CheckKind kind, const std::string& id) {
  CheckRequest r;
  r.machine_id = "pm1";
  r.request_id = id;
  r.kind = kind;
  return r;
}

TEST(TrackerSimulator, NoiselessReadingsAreTheTrueTargetInTheTrackerFrame) {
  const MachineConfig m = pm1();
  const TrackerSimulator t(m, quiet(m));
  const MeasurementSet set = t.perform(request(CheckKind::GlobalGrid, "g"), 5);
  EXPECT_EQ(set.instrument, "laser_tracker");
  EXPECT_EQ(set.frame, "tracker");
  ASSERT_EQ(set.tracker_points.size(), 21u + 4 * 216u);
  for (const TrackerPoint& p : set.tracker_points) {
    const int target = p.label.find(":t") == std::string::npos ? 0 : p.label.back() - '0';
    const Eigen::Vector3d machine = t.tracker_rotation() * p.measured_mm + t.tracker_position();
    // The axes arrive from one of eight direction combinations (the reversal state of the
    // program): the reading is the true target of one of them.
    double closest = 1e9;
    for (int d = 0; d < 8; ++d) {
      const Eigen::Vector3i dir(d & 1 ? 1 : -1, d & 2 ? 1 : -1, d & 4 ? 1 : -1);
      closest = std::min(
          closest,
          (machine - t.true_target(p.commanded, m.global_check->targets[target], dir)).norm());
    }
    EXPECT_LT(closest, 1e-9) << p.label;
  }
}

TEST(TrackerSimulator, ReversalThermalAndSquarenessMoveTheTargetAsConfigured) {
  const MachineConfig m = pm1();
  SimulatorConfig c = quiet(m);
  c.volumetric = VolumetricTruth{};
  c.volumetric.temperature_C = Eigen::Vector3d::Constant(20);
  c.errors = SimulatorErrors{};
  const ProbeGeometry& target = m.global_check->targets[0];
  AxisPosition at;
  at.x_mm = 1000;
  at.y_mm = 500;
  at.z_mm = 800;
  const Eigen::Vector3d nominal = stylus_ball_centre(at, target);
  EXPECT_LT((TrackerSimulator(m, c).true_target(at, target) - nominal).norm(), 1e-12);

  SimulatorConfig b = c;
  b.volumetric.backlash_mm = Eigen::Vector3d(0.02, 0, 0);
  const TrackerSimulator with_backlash(m, b);
  const double dx = with_backlash.true_target(at, target, {1, 1, 1}).x() -
                    with_backlash.true_target(at, target, {-1, 1, 1}).x();
  EXPECT_NEAR(dx, -0.02, 1e-12);  // arriving upwards the axis lags below the command

  SimulatorConfig th = c;
  th.volumetric.temperature_C = Eigen::Vector3d(22, 20, 20);
  EXPECT_NEAR(TrackerSimulator(m, th).true_target(at, target).x() - nominal.x(), 1000 * 11.5e-6 * 2,
              1e-9);

  SimulatorConfig sq = c;
  sq.volumetric.rigid_body.ec0xy_rad = 100e-6;  // Y leans towards -X
  EXPECT_NEAR(TrackerSimulator(m, sq).true_target(at, target).x() - nominal.x(), -500 * 100e-6,
              1e-6);

  SimulatorConfig cz = c;
  cz.errors.c_angle_error_rad = 1e-4;
  AxisPosition tilted = at;
  tilted.a_rad = units::deg_to_rad(90);
  const Eigen::Vector3d moved =
      TrackerSimulator(m, cz).true_target(tilted, target) - stylus_ball_centre(tilted, target);
  // A = 90 deg puts the target 300 mm off the C axis: the C error moves it 0.03 mm sideways.
  EXPECT_NEAR(moved.norm(), 300 * 1e-4, 1e-6);
}

TEST(TrackerSimulator, NoiseHasTheConfiguredSigmaInRangeAndAngles) {
  const MachineConfig m = pm1();
  SimulatorConfig noisy = quiet(m);
  noisy.tracker.angular_sigma_rad = 20e-6;
  noisy.tracker.radial_sigma_mm = 0.004;
  noisy.tracker.radial_sigma_mm_per_m = 0.0008;
  noisy.tracker.samples_per_point = 4;
  const TrackerSimulator clean(m, quiet(m)), t(m, noisy);
  double chi2_range = 0, chi2_angle = 0;
  int n = 0;
  for (int k = 0; k < 3; ++k) {
    const auto req = request(CheckKind::GlobalGrid, "noise" + std::to_string(k));
    const MeasurementSet a = clean.perform(req, 0), b = t.perform(req, 0);
    for (std::size_t i = 0; i < a.tracker_points.size(); ++i) {
      const Eigen::Vector3d p = a.tracker_points[i].measured_mm,
                            q = b.tracker_points[i].measured_mm;
      const double r = p.norm();
      const double sigma_r = (0.004 + 0.0008 * r / 1000) / 2;
      const double sigma_t = 20e-6 * r / 2;
      const double dr = q.norm() - r;
      const Eigen::Vector3d transverse = (q - p) - dr * p / r;
      chi2_range += (dr / sigma_r) * (dr / sigma_r);
      chi2_angle += transverse.squaredNorm() / (sigma_t * sigma_t);  // two angles per point
      ++n;
    }
  }
  // Chi-square with n (range) and ~2n (angles) degrees of freedom: mean 1 per degree, its
  // relative sigma sqrt(2 / dof); 5 sigma.
  EXPECT_NEAR(chi2_range / n, 1.0, 5 * std::sqrt(2.0 / n));
  EXPECT_NEAR(chi2_angle / (2 * n), 1.0, 5 * std::sqrt(2.0 / (2 * n)) + 0.01);
}

TEST(TrackerSimulator, IsReproduciblePerRequestAndRefusesProbeChecks) {
  const MachineConfig m = pm1();
  const TrackerSimulator t(m, m.simulator);
  const auto a = t.perform(request(CheckKind::CircleXY, "same"), 0);
  const auto b = t.perform(request(CheckKind::CircleXY, "same"), 0);
  const auto c = t.perform(request(CheckKind::CircleXY, "other"), 0);
  ASSERT_EQ(a.tracker_points.size(), b.tracker_points.size());
  EXPECT_EQ(a.tracker_points[30].measured_mm, b.tracker_points[30].measured_mm);
  EXPECT_NE(a.tracker_points[30].measured_mm, c.tracker_points[30].measured_mm);
  const auto probe = t.perform(request(CheckKind::MonumentPositioning, "p"), 0);
  EXPECT_TRUE(probe.tracker_points.empty());
  EXPECT_NE(probe.error.find("cannot perform check kind 'monument_positioning'"),
            std::string::npos);
  MachineConfig none = m;
  none.global_check.reset();
  EXPECT_THROW(TrackerSimulator(none, m.simulator), std::invalid_argument);
}

TEST(TrackerSimulator, ConfigRefusesUnknownVolumetricKeysAndMissingRanges) {
  // pm1 with one thing of its simulator section changed (the file extends pm1).
  auto pm1_with = [](const std::string& simulator) {
    return parse_machine_config("extends: " NCQUAL_SOURCE_DIR
                                "/deploy/machines/pm1.yaml\n"
                                "simulator:\n" +
                                    simulator,
                                "t1.yaml");
  };
  EXPECT_THROW(pm1_with("  volumetric: {EXX_mm: [0, 1]}\n"), ConfigError);
  try {
    pm1_with("  volumetric: {range_mm: ~}\n");
    ADD_FAILURE() << "accepted error functions without range_mm";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("range_mm"), std::string::npos) << e.what();
  }
  EXPECT_THROW(pm1_with("  tracker: {samples_per_point: 0}\n"), ConfigError);
}

}  // namespace
}  // namespace ncqual::sim

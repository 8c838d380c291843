// SPDX-License-Identifier: Apache-2.0
#include "ncqual/sim/machine_simulator.hpp"

#include "ncqual/common/kinematics.hpp"
#include "test_machines.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

namespace ncqual::sim {
namespace {

using testing::pm1_like_machine;
using testing::random_machine;
using testing::request;
using testing::simulator_config;
using testing::uniform;

Eigen::Vector3d ball_centre(const Touch& t, const ProbeGeometry& probe) {
  return stylus_ball_centre(t.axes, probe);
}

SimulatorErrors random_errors(std::mt19937_64& rng) {
  SimulatorErrors e;
  for (int i = 0; i < 3; ++i) {
    e.machine_shift_mm[i] = uniform(rng, -0.5, 0.5);
    e.monument_shift_mm[i] = uniform(rng, -0.5, 0.5);
  }
  e.stylus_offset_mm = Eigen::Vector2d(uniform(rng, -0.2, 0.2), uniform(rng, -0.2, 0.2));
  e.tool_length_error_mm = uniform(rng, -0.3, 0.3);
  e.c_angle_error_rad = uniform(rng, -1e-3, 1e-3);
  e.a_home_error_rad = uniform(rng, -1e-3, 1e-3);
  return e;
}

TEST(MachineSimulator, PositioningProgramShapeAndHeader) {
  const MachineConfig m = pm1_like_machine();
  const MachineSimulator sim(m, simulator_config(0.001));
  const MeasurementSet set = sim.perform(request("pm1", "r-1"), 123456789);
  EXPECT_TRUE(set.error.empty()) << set.error;
  EXPECT_EQ(set.machine_id, "pm1");
  EXPECT_EQ(set.request_id, "r-1");
  EXPECT_EQ(set.kind, CheckKind::MonumentPositioning);
  EXPECT_EQ(set.instrument, "touch_probe");
  EXPECT_EQ(set.frame, "machine");
  EXPECT_EQ(set.time_ns, 123456789);
  ASSERT_EQ(set.touches.size(), static_cast<std::size_t>(m.monument.hole_touches + 1));
  for (int k = 0; k < m.monument.hole_touches; ++k) {
    const Touch& t = set.touches[static_cast<std::size_t>(k)];
    EXPECT_EQ(t.feature, "hole_edge");
    const double theta = 2 * 3.14159265358979323846 * k / m.monument.hole_touches;
    EXPECT_NEAR((t.approach - Eigen::Vector3d(std::cos(theta), std::sin(theta), 0)).norm(), 0,
                1e-15);
    EXPECT_EQ(t.axes.a_rad, 0);
    EXPECT_EQ(t.axes.c_rad, 0);
    EXPECT_EQ(t.axes.w_mm, 0);
  }
  EXPECT_EQ(set.touches.back().feature, "face");
  EXPECT_EQ(set.touches.back().approach, Eigen::Vector3d(0, 0, -1));
}

TEST(MachineSimulator, SameRequestIdGivesIdenticalTouchesWhateverTheOrder) {
  const MachineSimulator sim(pm1_like_machine(), simulator_config(0.001));
  const MeasurementSet a1 = sim.perform(request("pm1", "req-a"), 1);
  const MeasurementSet b1 = sim.perform(request("pm1", "req-b"), 2);
  const MachineSimulator fresh(pm1_like_machine(), simulator_config(0.001));
  const MeasurementSet b2 = fresh.perform(request("pm1", "req-b"), 3);
  const MeasurementSet a2 = fresh.perform(request("pm1", "req-a"), 4);
  ASSERT_EQ(a1.touches.size(), a2.touches.size());
  for (std::size_t i = 0; i < a1.touches.size(); ++i) {
    EXPECT_EQ(a1.touches[i].axes.x_mm, a2.touches[i].axes.x_mm);
    EXPECT_EQ(a1.touches[i].axes.y_mm, a2.touches[i].axes.y_mm);
    EXPECT_EQ(a1.touches[i].axes.z_mm, a2.touches[i].axes.z_mm);
    EXPECT_EQ(b1.touches[i].axes.x_mm, b2.touches[i].axes.x_mm);
    EXPECT_EQ(b1.touches[i].axes.z_mm, b2.touches[i].axes.z_mm);
  }
}

TEST(MachineSimulator, DifferentRequestIdsOrSeedsGiveDifferentNoise) {
  const MachineSimulator sim(pm1_like_machine(), simulator_config(0.001, 5));
  const MachineSimulator other_seed(pm1_like_machine(), simulator_config(0.001, 6));
  const MeasurementSet a = sim.perform(request("pm1", "req-a"), 1);
  const MeasurementSet b = sim.perform(request("pm1", "req-b"), 1);
  const MeasurementSet c = other_seed.perform(request("pm1", "req-a"), 1);
  ASSERT_EQ(a.touches.size(), b.touches.size());
  for (std::size_t i = 0; i < a.touches.size(); ++i) {
    const Eigen::Vector3d pa(a.touches[i].axes.x_mm, a.touches[i].axes.y_mm,
                             a.touches[i].axes.z_mm);
    const Eigen::Vector3d pb(b.touches[i].axes.x_mm, b.touches[i].axes.y_mm,
                             b.touches[i].axes.z_mm);
    const Eigen::Vector3d pc(c.touches[i].axes.x_mm, c.touches[i].axes.y_mm,
                             c.touches[i].axes.z_mm);
    EXPECT_GT((pa - pb).norm(), 0) << "touch " << i;
    EXPECT_GT((pa - pc).norm(), 0) << "touch " << i;
    // Noise only: the touches agree to within a few sigma.
    EXPECT_LT((pa - pb).norm(), 0.01) << "touch " << i;
  }
}

TEST(MachineSimulator, WithoutNoiseOrErrorsBallCentresLieExactlyOnTheGauge) {
  std::mt19937_64 rng(21);
  for (int i = 0; i < 100; ++i) {
    const MachineConfig m = random_machine(rng);
    const MachineSimulator sim(m, simulator_config(0.0));
    const MeasurementSet set = sim.perform(request(m.machine_id, "r" + std::to_string(i)), 0);
    ASSERT_TRUE(set.error.empty()) << set.error;
    ASSERT_EQ(set.touches.size(), static_cast<std::size_t>(m.monument.hole_touches + 1));
    const double ball_circle = m.monument.hole_diameter_mm / 2 - m.probe.ball_radius_mm;
    for (const Touch& t : set.touches) {
      const Eigen::Vector3d b = ball_centre(t, m.probe);
      if (t.feature == "hole_edge") {
        EXPECT_NEAR((b.head<2>() - m.monument.hole_center_mm).norm(), ball_circle, 1e-9);
        EXPECT_NEAR(b.z(), m.monument.face_z_mm - m.monument.probe_depth_mm, 1e-9);
      } else {
        EXPECT_NEAR(b.z() - m.probe.ball_radius_mm, m.monument.face_z_mm, 1e-9);
        EXPECT_NEAR(b.x(), m.monument.hole_center_mm.x() + m.monument.face_offset_mm, 1e-9);
      }
    }
  }
}

TEST(MachineSimulator, WithEveryErrorTrueBallCentresLieExactlyOnTheTrueGauge) {
  // The engine is general: whatever the errors, the true ball centre at each latched readout
  // touches the true (shifted) monument.
  std::mt19937_64 rng(22);
  for (int i = 0; i < 100; ++i) {
    const MachineConfig m = random_machine(rng);
    SimulatorConfig c = simulator_config(0.0);
    c.errors = random_errors(rng);
    const MachineSimulator sim(m, c);
    const MeasurementSet set = sim.perform(request(m.machine_id, "r" + std::to_string(i)), 0);
    ASSERT_TRUE(set.error.empty()) << set.error;
    const Eigen::Vector2d true_centre =
        m.monument.hole_center_mm + c.errors.monument_shift_mm.head<2>();
    const double true_face = m.monument.face_z_mm + c.errors.monument_shift_mm.z();
    const double ball_circle = m.monument.hole_diameter_mm / 2 - m.probe.ball_radius_mm;
    for (const Touch& t : set.touches) {
      const Eigen::Vector3d b = sim.true_ball_centre(t.axes);
      if (t.feature == "hole_edge") {
        EXPECT_NEAR((b.head<2>() - true_centre).norm(), ball_circle, 1e-9);
      } else {
        EXPECT_NEAR(b.z() - m.probe.ball_radius_mm, true_face, 1e-9);
      }
    }
    // And the true ball centre is the kinematics formula with the true parameters.
    ProbeGeometry truth = m.probe;
    truth.tool_length_mm += c.errors.tool_length_error_mm;
    truth.stylus_offset_mm += c.errors.stylus_offset_mm;
    AxisPosition axes = set.touches.front().axes;
    const Eigen::Vector3d expected = stylus_ball_centre(
        AxisPosition{
            axes.x_mm + c.errors.machine_shift_mm.x(), axes.y_mm + c.errors.machine_shift_mm.y(),
            axes.z_mm + c.errors.machine_shift_mm.z(), axes.w_mm,
            axes.a_rad + c.errors.a_home_error_rad, axes.c_rad + c.errors.c_angle_error_rad},
        truth);
    EXPECT_NEAR((sim.true_ball_centre(axes) - expected).norm(), 0, 1e-12);
  }
}

TEST(MachineSimulator, ShiftsMoveTheNominalBallCentresByMonumentLessMachine) {
  const MachineConfig m = pm1_like_machine();
  SimulatorConfig c = simulator_config(0.0);
  c.errors.machine_shift_mm = Eigen::Vector3d(0.03, -0.01, 0.02);
  c.errors.monument_shift_mm = Eigen::Vector3d(-0.01, 0.015, -0.005);
  const Eigen::Vector3d d = c.errors.monument_shift_mm - c.errors.machine_shift_mm;
  const MachineSimulator sim(m, c);
  const MeasurementSet set = sim.perform(request("pm1", "shift"), 0);
  ASSERT_TRUE(set.error.empty()) << set.error;
  const double ball_circle = m.monument.hole_diameter_mm / 2 - m.probe.ball_radius_mm;
  for (const Touch& t : set.touches) {
    const Eigen::Vector3d b = ball_centre(t, m.probe);
    if (t.feature == "hole_edge") {
      EXPECT_NEAR((b.head<2>() - m.monument.hole_center_mm - d.head<2>()).norm(), ball_circle,
                  1e-9);
    } else {
      EXPECT_NEAR(b.z() - m.probe.ball_radius_mm - m.monument.face_z_mm, d.z(), 1e-9);
    }
  }
}

TEST(MachineSimulator, TriggerNoiseHasTheConfiguredSigma) {
  // With no errors every touch's deviation from its exact contact is the trigger noise alone:
  // radial for edge touches (they move radially), vertical for the face touch.
  const MachineConfig m = pm1_like_machine();
  const double sigma = 0.002;
  const MachineSimulator sim(m, simulator_config(sigma, 31));
  const double ball_circle = m.monument.hole_diameter_mm / 2 - m.probe.ball_radius_mm;
  double sum = 0, sum_sq = 0;
  int n = 0;
  for (int r = 0; r < 1000; ++r) {
    const MeasurementSet set = sim.perform(request("pm1", "noise-" + std::to_string(r)), 0);
    ASSERT_TRUE(set.error.empty()) << set.error;
    for (const Touch& t : set.touches) {
      const Eigen::Vector3d b = ball_centre(t, m.probe);
      // The readout moved past the contact by the noise: deviation along the approach.
      const double e = t.feature == "hole_edge"
                           ? (b.head<2>() - m.monument.hole_center_mm).norm() - ball_circle
                           : -(b.z() - m.probe.ball_radius_mm - m.monument.face_z_mm);
      sum += e;
      sum_sq += e * e;
      ++n;
    }
  }
  const double mean = sum / n;
  const double sd = std::sqrt(sum_sq / n - mean * mean);
  // n = 5000: standard error of the mean sigma/sqrt(n), of the sd about sigma/sqrt(2n).
  EXPECT_NEAR(mean, 0, 5 * sigma / std::sqrt(n));
  EXPECT_NEAR(sd, sigma, 5 * sigma / std::sqrt(2.0 * n));
}

TEST(MachineSimulator, EdgeTouchesBelowThePlateMissAndRaiseAnAlarm) {
  MachineConfig m = pm1_like_machine();
  SimulatorConfig c = simulator_config(0.001);
  m.monument.probe_depth_mm = c.plate_thickness_mm + m.probe.ball_radius_mm + 1;
  const MachineSimulator sim(m, c);
  const MeasurementSet set = sim.perform(request("pm1", "deep"), 0);
  EXPECT_NE(set.error.find("probe alarm"), std::string::npos) << set.error;
  EXPECT_NE(set.error.find("move 0 ('hole_edge')"), std::string::npos) << set.error;
  EXPECT_NE(set.error.find("did not trigger"), std::string::npos) << set.error;
  ASSERT_EQ(set.touches.size(), 1u);  // only the face touch
  EXPECT_EQ(set.touches.front().feature, "face");
}

TEST(MachineSimulator, FaceTouchOverTheHoleMisses) {
  MachineConfig m = pm1_like_machine();
  m.monument.face_offset_mm = 5;  // inside the hole: the ball goes down into it
  const MachineSimulator sim(m, simulator_config(0.001));
  const MeasurementSet set = sim.perform(request("pm1", "over-hole"), 0);
  EXPECT_NE(set.error.find("('face')"), std::string::npos) << set.error;
  EXPECT_EQ(set.touches.size(), static_cast<std::size_t>(m.monument.hole_touches));
}

TEST(MachineSimulator, ShiftLargerThanTheHoleDeflectsTheProbeAtTheStart) {
  const MachineConfig m = pm1_like_machine();
  SimulatorConfig c = simulator_config(0.001);
  c.errors.machine_shift_mm = Eigen::Vector3d(23, 0, 0);  // ball starts inside the wall
  const MachineSimulator sim(m, c);
  const MeasurementSet set = sim.perform(request("pm1", "crash"), 0);
  EXPECT_NE(set.error.find("deflected at the start"), std::string::npos) << set.error;
  EXPECT_LT(set.touches.size(), static_cast<std::size_t>(m.monument.hole_touches));
}

TEST(MachineSimulator, KindsItCannotPerformAreRefusedWithoutTouches) {
  // pm1_like_machine has neither set points nor a fixture, and the tracker is not simulated.
  const MachineSimulator sim(pm1_like_machine(), simulator_config(0.001));
  for (CheckKind kind : all_check_kinds()) {
    if (static_cast<int>(kind) <= static_cast<int>(CheckKind::MonumentCRotation)) continue;
    if (kind == CheckKind::FixturePreCalibration || kind == CheckKind::FixturePostCalibration) {
      continue;  // refused with their own reason: see the fixture simulator's tests
    }
    const MeasurementSet set = sim.perform(request("pm1", "k", kind), 5);
    EXPECT_EQ(set.error,
              "the simulator cannot perform check kind '" + std::string(to_string(kind)) + "' yet");
    EXPECT_TRUE(set.touches.empty());
    EXPECT_TRUE(set.tracker_points.empty());
    EXPECT_EQ(set.kind, kind);
    EXPECT_EQ(set.time_ns, 5);
  }
}

TEST(MachineSimulator, RequestForAnotherMachineIsRefused) {
  const MachineSimulator sim(pm1_like_machine(), simulator_config(0.001));
  const MeasurementSet set = sim.perform(request("pm2", "x"), 0);
  EXPECT_NE(set.error.find("'pm2'"), std::string::npos) << set.error;
  EXPECT_TRUE(set.touches.empty());
}

TEST(MachineSimulator, GroundTruthIsTheConfiguredErrors) {
  std::mt19937_64 rng(24);
  SimulatorConfig c = simulator_config(0.001);
  c.errors = random_errors(rng);
  const MachineSimulator sim(pm1_like_machine(), c);
  EXPECT_EQ(sim.ground_truth().machine_shift_mm, c.errors.machine_shift_mm);
  EXPECT_EQ(sim.ground_truth().monument_shift_mm, c.errors.monument_shift_mm);
  EXPECT_EQ(sim.ground_truth().stylus_offset_mm, c.errors.stylus_offset_mm);
  EXPECT_EQ(sim.ground_truth().tool_length_error_mm, c.errors.tool_length_error_mm);
  EXPECT_EQ(sim.ground_truth().c_angle_error_rad, c.errors.c_angle_error_rad);
  EXPECT_EQ(sim.ground_truth().a_home_error_rad, c.errors.a_home_error_rad);
  EXPECT_EQ(sim.true_monument().hole_centre_mm,
            pm1_like_machine().monument.hole_center_mm + c.errors.monument_shift_mm.head<2>());
}

TEST(MachineSimulator, ProgramStartsPutTheNominalBallWhereIntended) {
  const MachineConfig m = pm1_like_machine();
  for (const ProbingMove& move : probing::monument_positioning_program(m)) {
    const Eigen::Vector3d b = stylus_ball_centre(move.start, m.probe);
    if (move.feature == "hole_edge") {
      EXPECT_NEAR((b - Eigen::Vector3d(1200, 800, 145)).norm(), 0, 1e-12);
    } else {
      EXPECT_NEAR((b - Eigen::Vector3d(1235, 800, 150 + 3 + kDefaultProbingClearanceMm)).norm(), 0,
                  1e-12);
    }
  }
}

}  // namespace
}  // namespace ncqual::sim

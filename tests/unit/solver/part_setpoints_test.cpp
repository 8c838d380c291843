// SPDX-License-Identifier: Apache-2.0
// The per-part set-point check against the simulator's ground truth: blocks moved on their
// fixturing devices, parts seated off their locators, and the machine's own errors.
#include "ncqual/solver/part_setpoints.hpp"

#include "ncqual/common/kinematics.hpp"
#include "ncqual/sim/machine_simulator.hpp"
#include "ncqual/solver/solve.hpp"
#include "ncqual/common/units.hpp"
#include "test_machines.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace ncqual::solver {
namespace {

using testing::metric;
using testing::pm1_like_machine;
using testing::request;
using testing::simulator_config;
using testing::uniform;

MachineConfig machine_with_setpoints() {
  MachineConfig m = pm1_like_machine();
  m.setpoints.probe_depth_mm = 5;
  m.setpoints.inset_mm = 10;
  m.setpoints.points = {{"primary", {600, 300, 400}}, {"secondary", {3400, 300, 420}}};
  m.tolerances["setpoint_max_dev_mm"] = {0, 0.05};
  return m;
}

TEST(PartSetPoints, RecoversBlockShiftsAndSeatingWithMachineErrors) {
  // Truth: with the head at home every error of the machine and probe moves the true ball by
  // one vector v = true ball - nominal ball (the same for every readout), so each measured
  // face is the true face less v. Noise: one touch per face, sigma_t per axis.
  std::mt19937_64 rng(401);
  int passes = 0, fails = 0;
  for (int i = 0; i < 200; ++i) {
    const MachineConfig m = machine_with_setpoints();
    sim::SimulatorConfig c = simulator_config(uniform(rng, 0.0005, 0.002), rng());
    c.part_seating_sigma_mm = 0.01;
    for (const char* name : {"primary", "secondary"}) {
      c.errors.setpoint_shift_mm[name] = Eigen::Vector3d(
          uniform(rng, -0.05, 0.05), uniform(rng, -0.05, 0.05), uniform(rng, -0.05, 0.05));
    }
    for (int k = 0; k < 3; ++k) c.errors.machine_shift_mm[k] = uniform(rng, -0.01, 0.01);
    c.errors.tool_length_error_mm = uniform(rng, -0.01, 0.01);
    c.errors.stylus_offset_mm = Eigen::Vector2d(uniform(rng, -0.005, 0.005), 0);
    const sim::MachineSimulator simulator(m, c);
    const std::string id = "part-" + std::to_string(i);
    const MeasurementSet set =
        simulator.perform(request("pm1", id, CheckKind::PartSetPoints), 1000);
    ASSERT_TRUE(set.error.empty()) << set.error;
    ASSERT_EQ(set.touches.size(), 6u);
    const CheckResult r = check_part_setpoints(set, m);
    ASSERT_NE(r.verdict, Verdict::Invalid) << r.reason;

    AxisPosition home;
    const Eigen::Vector3d v = simulator.true_ball_centre(home) - stylus_ball_centre(home, m.probe);
    const auto blocks = simulator.true_setpoint_blocks(id);
    const double sigma = c.trigger_noise_sigma_mm;
    double largest_truth = 0;
    for (const auto& point : m.setpoints.points) {
      const Eigen::Vector3d truth = blocks.at(point.name).corner_mm - v - point.intended_mm;
      for (int axis = 0; axis < 3; ++axis) {
        EXPECT_NEAR(metric(r, setpoints::axis_metric(point.name, "xyz"[axis])).value, truth[axis],
                    5 * sigma)
            << point.name << " axis " << axis << " case " << i;
      }
      largest_truth = std::max(largest_truth, truth.norm());
    }
    const Metric& max = metric(r, "setpoint_max_dev_mm");
    EXPECT_NEAR(max.value, largest_truth, 5 * std::sqrt(3.0) * sigma);
    if (largest_truth > 0.05 + 9 * sigma) {
      EXPECT_EQ(r.verdict, Verdict::Fail) << "case " << i;
    }
    if (r.verdict == Verdict::Pass) {
      ++passes;
      // The primary set point's deviation becomes the part program's zero reference.
      ASSERT_TRUE(r.correction.has_value());
      EXPECT_EQ(r.correction->target, "work_offset:pm1");
      ASSERT_EQ(r.correction->offsets.size(), 3u);
      EXPECT_DOUBLE_EQ(r.correction->offsets[0].value, metric(r, "setpoint_primary_dx_mm").value);
      EXPECT_DOUBLE_EQ(r.correction->offsets[2].value, metric(r, "setpoint_primary_dz_mm").value);
    } else {
      ++fails;
      EXPECT_FALSE(r.correction.has_value());
      ASSERT_EQ(r.likely_causes.size(), 3u);
      EXPECT_EQ(r.likely_causes[0],
                "part not seated on its locators (unload, clean and reload the part)");
    }
  }
  EXPECT_GT(passes, 20);
  EXPECT_GT(fails, 20);
}

TEST(PartSetPoints, SeatingIsReproduciblePerRequestAndDiffersBetweenParts) {
  MachineConfig m = machine_with_setpoints();
  sim::SimulatorConfig c = simulator_config(0.0);
  c.part_seating_sigma_mm = 0.02;
  const sim::MachineSimulator s(m, c);
  EXPECT_EQ(s.part_seating_mm("a"), s.part_seating_mm("a"));
  EXPECT_NE(s.part_seating_mm("a"), s.part_seating_mm("b"));
  // The seating moves every set point alike: what the check sees of it on a perfect machine.
  const CheckResult r =
      check_part_setpoints(s.perform(request("pm1", "a", CheckKind::PartSetPoints), 1), m);
  const Eigen::Vector3d seat = s.part_seating_mm("a");
  EXPECT_NEAR(metric(r, "setpoint_secondary_dy_mm").value, seat.y(), 1e-9);
  EXPECT_NEAR(metric(r, "setpoint_primary_dz_mm").value, seat.z(), 1e-9);
}

TEST(PartSetPoints, BadInputIsInvalidWithTheFieldNamed) {
  const struct {
    const char* name;
    std::function<void(MeasurementSet&, MachineConfig&)> spoil;
    const char* reason_contains;
  } cases[] = {
      {"missing z touch",
       [](MeasurementSet& s, MachineConfig&) { s.touches.erase(s.touches.begin()); },
       "no 'setpoint:primary:z' touch"},
      {"wrong head", [](MeasurementSet& s, MachineConfig&) { s.touches[4].axes.c_rad = 1; },
       "MeasurementSet.touches[4].axes: head at A = 0 rad, C = 1 rad"},
      {"unknown set point",
       [](MeasurementSet& s, MachineConfig&) { s.touches[1].feature = "setpoint:tertiary:x"; },
       "'tertiary' is not a set point"},
      {"malformed feature",
       [](MeasurementSet& s, MachineConfig&) { s.touches[1].feature = "setpoint:primary"; },
       "MeasurementSet.touches[1].feature = 'setpoint:primary'"},
      {"approach reversed", [](MeasurementSet& s, MachineConfig&) { s.touches[2].approach *= -1; },
       "MeasurementSet.touches[2].approach"},
      {"no set points configured",
       [](MeasurementSet&, MachineConfig& m) { m.setpoints.points.clear(); },
       "setpoints.points is empty"},
      {"tolerance missing",
       [](MeasurementSet&, MachineConfig& m) { m.tolerances.erase("setpoint_max_dev_mm"); },
       "tolerances.setpoint_max_dev_mm is not configured"},
  };
  for (const auto& bad : cases) {
    MachineConfig m = machine_with_setpoints();
    MeasurementSet set = sim::MachineSimulator(m, simulator_config(0.001))
                             .perform(request("pm1", bad.name, CheckKind::PartSetPoints), 1);
    ASSERT_EQ(solve(set, m, 1).verdict, Verdict::Pass) << bad.name;
    bad.spoil(set, m);
    const CheckResult r = solve(set, m, 1);
    EXPECT_EQ(r.verdict, Verdict::Invalid) << bad.name;
    EXPECT_NE(r.reason.find(bad.reason_contains), std::string::npos)
        << bad.name << ": " << r.reason;
  }
}

}  // namespace
}  // namespace ncqual::solver

// SPDX-License-Identifier: Apache-2.0
#include "ncqual/solver/solve.hpp"

#include "ncqual/sim/machine_simulator.hpp"
#include "test_machines.hpp"

#include <gtest/gtest.h>

namespace ncqual::solver {
namespace {

using testing::pm1_like_machine;
using testing::request;
using testing::simulator_config;

PlantConfig plant_with(std::vector<MachineConfig> machines) {
  PlantConfig p;
  p.plant = "bay3";
  p.machines = std::move(machines);
  return p;
}

MeasurementSet positioning_set(const MachineConfig& m, const std::string& id) {
  return sim::MachineSimulator(m, simulator_config(0.001)).perform(request(m.machine_id, id), 10);
}

TEST(Solve, DispatchesCheck3AndStampsIdentityAndTime) {
  MachineConfig other = pm1_like_machine();
  other.machine_id = "pm2";
  const PlantConfig plant = plant_with({other, pm1_like_machine()});
  const MeasurementSet set = positioning_set(pm1_like_machine(), "req-77");
  const CheckResult r = solve(set, plant, 1'800'000'000'000'000'000);
  EXPECT_EQ(r.verdict, Verdict::Pass) << r.reason;
  EXPECT_EQ(r.machine_id, "pm1");
  EXPECT_EQ(r.request_id, "req-77");
  EXPECT_EQ(r.kind, CheckKind::MonumentPositioning);
  EXPECT_EQ(r.time_ns, 1'800'000'000'000'000'000);
  EXPECT_NE(find_metric(r, "center_dx_mm"), nullptr);
}

// A verdict carries the origin of the numbers it judged: simulated sets give simulated results,
// measured ones measured, a set that did not say (wire contract 1) a result that does not either;
// also when the verdict is INVALID (an unknown machine, another machine's set, an instrument's
// error, an empty set).
TEST(Solve, EveryResultCarriesTheOriginOfItsSet) {
  const PlantConfig plant = plant_with({pm1_like_machine()});
  const MeasurementSet simulated = positioning_set(pm1_like_machine(), "r-origin");
  EXPECT_EQ(simulated.origin, DataOrigin::Simulated);  // the simulator says so itself
  for (const DataOrigin origin :
       {DataOrigin::Simulated, DataOrigin::Measured, DataOrigin::Unknown}) {
    MeasurementSet set = simulated;
    set.origin = origin;
    EXPECT_EQ(solve(set, plant, 1).origin, origin);
    EXPECT_EQ(solve(set, plant, 1).verdict, Verdict::Pass);
    MeasurementSet unknown_machine = set;
    unknown_machine.machine_id = "x";
    EXPECT_EQ(solve(unknown_machine, plant, 1).origin, origin);
    EXPECT_EQ(solve(unknown_machine, pm1_like_machine(), 1).origin, origin);
    MeasurementSet failed = set;
    failed.error = "probe not connected";
    EXPECT_EQ(solve(failed, plant, 1).verdict, Verdict::Invalid);
    EXPECT_EQ(solve(failed, plant, 1).origin, origin);
    MeasurementSet empty = set;
    empty.touches.clear();
    EXPECT_EQ(solve(empty, plant, 1).verdict, Verdict::Invalid);
    EXPECT_EQ(solve(empty, plant, 1).origin, origin);
  }
}

TEST(Solve, UsesTheMachineTheSetNames) {
  // Same touches judged against two machines that differ in taught centre: the one the set
  // names decides.
  MachineConfig moved = pm1_like_machine();
  moved.machine_id = "pm2";
  moved.monument.hole_center_mm.x() += 0.1;
  const PlantConfig plant = plant_with({moved, pm1_like_machine()});
  MeasurementSet set = positioning_set(pm1_like_machine(), "r");
  EXPECT_EQ(solve(set, plant, 0).verdict, Verdict::Pass);
  set.machine_id = "pm2";
  EXPECT_EQ(solve(set, plant, 0).verdict, Verdict::Fail);
}

TEST(Solve, UnknownMachineIsInvalid) {
  const PlantConfig plant = plant_with({pm1_like_machine()});
  MeasurementSet set = positioning_set(pm1_like_machine(), "r-unknown");
  set.machine_id = "x";
  const CheckResult r = solve(set, plant, 42);
  EXPECT_EQ(r.verdict, Verdict::Invalid);
  EXPECT_EQ(r.reason, "machine_id 'x' is not configured in plant 'bay3'");
  EXPECT_EQ(r.machine_id, "x");
  EXPECT_EQ(r.request_id, "r-unknown");
  EXPECT_EQ(r.time_ns, 42);
}

TEST(Solve, MachineOverloadRefusesAnotherMachinesSet) {
  MeasurementSet set = positioning_set(pm1_like_machine(), "r");
  set.machine_id = "pm9";
  const CheckResult r = solve(set, pm1_like_machine(), 0);
  EXPECT_EQ(r.verdict, Verdict::Invalid);
  EXPECT_NE(r.reason.find("machine_id 'pm9'"), std::string::npos) << r.reason;
}

TEST(Solve, EveryKindIsImplemented) {
  for (CheckKind kind : all_check_kinds()) EXPECT_TRUE(is_implemented(kind)) << to_string(kind);
}

TEST(Solve, TrackerCheckOfAMachineWithoutGlobalCheckSectionIsInvalidSayingSo) {
  const PlantConfig plant = plant_with({pm1_like_machine()});
  for (CheckKind kind : all_check_kinds()) {
    if (!is_tracker_check(kind)) continue;
    MeasurementSet set = positioning_set(pm1_like_machine(), "r-kind");
    set.kind = kind;
    set.tracker_points.push_back(TrackerPoint{"x_run:0", {}, Eigen::Vector3d::Zero()});
    const CheckResult r = solve(set, plant, 9);
    EXPECT_EQ(r.verdict, Verdict::Invalid);
    EXPECT_NE(r.reason.find("has no global_check: section"), std::string::npos) << r.reason;
    EXPECT_EQ(r.kind, kind);
    EXPECT_EQ(r.time_ns, 9);
  }
}

TEST(Solve, SimulatorRefusalBecomesInvalidCarryingItsMessage) {
  const sim::MachineSimulator simulator(pm1_like_machine(), simulator_config(0.001));
  const MeasurementSet set = simulator.perform(request("pm1", "r-grid", CheckKind::GlobalGrid), 3);
  const CheckResult r = solve(set, plant_with({pm1_like_machine()}), 4);
  EXPECT_EQ(r.verdict, Verdict::Invalid);
  EXPECT_NE(r.reason.find("the simulator cannot perform check kind 'global_grid' yet"),
            std::string::npos)
      << r.reason;
}

TEST(Solve, EmptySetIsInvalidNotAThrow) {
  MeasurementSet set;
  set.machine_id = "pm1";
  CheckResult r;
  ASSERT_NO_THROW(r = solve(set, pm1_like_machine(), 0));
  EXPECT_EQ(r.verdict, Verdict::Invalid);
  EXPECT_NE(r.reason.find("MeasurementSet.touches is empty"), std::string::npos);
}

}  // namespace
}  // namespace ncqual::solver

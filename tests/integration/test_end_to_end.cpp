// SPDX-License-Identifier: Apache-2.0
// The four real executables over Fast DDS on loopback, two simulated machines, one solver and
// one historian: the scheduler's start-up cycle runs check 3 on both, and the stored results
// must match the errors injected into each simulated machine.
#include "cli_runner.hpp"
#include "harness.hpp"

#include "ncqual/common/version.hpp"
#include "ncqual/common/config.hpp"
#include "ncqual/sim/machine_simulator.hpp"
#include "ncqual/sim/simulator_config.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace ncqual::testing {
namespace {

TEST(EndToEnd, CheckThreeOfTwoMachinesIsStoredAndMatchesInjectedErrors) {
  Plant plant("e2e", TestDomain::EndToEnd);
  // pm-good: no errors (PASS). pm-shifted: the machine has shifted (FAIL, first cause machine).
  const auto good = plant.add_machine(
      "pm-good", machine_yaml("pm-good", "    machine_shift_mm: [0, 0, 0]\n", 11));
  const auto shifted =
      plant.add_machine("pm-shifted", machine_yaml("pm-shifted",
                                                   "    machine_shift_mm: [0.040, -0.031, 0.027]\n"
                                                   "    monument_shift_mm: [0.002, 0.001, 0.0]\n",
                                                   12));
  plant.write_plant();
  plant.start("historian");
  plant.start("solver");
  plant.start("acquisition", {"--machine", "pm-good"});
  plant.start("acquisition", {"--machine", "pm-shifted"});
  plant.start("scheduler");

  // Topics arrive independently (a result may be stored before its request): wait until each
  // machine's check is complete in the database.
  ASSERT_TRUE(plant.wait_for_db([](storage::Database& db) {
    for (const char* id : {"pm-good", "pm-shifted"}) {
      storage::HistoryQuery q;
      q.machine_id = id;
      const auto records = db.history(q);
      if (records.empty()) return false;
      const auto& r = records.front();
      if (!r.request || !r.measurement || !r.result) return false;
    }
    return true;
  })) << plant.log("solver")
      << plant.log("historian");

  auto db = storage::Database::open_readonly(plant.db_path());
  const double bound = 3 * 0.001;  // 3 sigma of the 1 um trigger noise
  for (const auto& path : {good, shifted}) {
    const MachineConfig machine = load_machine_config(path);
    const auto truth = machine.simulator.errors;
    storage::HistoryQuery q;
    q.machine_id = machine.machine_id;
    const auto records = db.history(q);
    ASSERT_EQ(records.size(), 1u) << machine.machine_id;
    const auto& rec = records.front();
    ASSERT_TRUE(rec.request.has_value()) << "request stored";
    ASSERT_TRUE(rec.result.has_value()) << "result stored";
    EXPECT_EQ(rec.request->requested_by, "scheduler");
    EXPECT_EQ(rec.result->kind, CheckKind::MonumentPositioning);
    // The verdict names the software that made it: this build's solver.
    EXPECT_EQ(rec.result->produced_by, version_line("ncqual-solver"));
    // The simulator measured it: the set says so on the wire, the solver's verdict carries it,
    // and the historian keeps both (issue 37 point 5).
    ASSERT_TRUE(rec.measurement.has_value());
    EXPECT_EQ(rec.measurement->origin, DataOrigin::Simulated) << machine.machine_id;
    EXPECT_EQ(rec.result->origin, DataOrigin::Simulated) << machine.machine_id;
    // Check 3 sees the monument relative to the machine: monument shift minus machine shift.
    const Eigen::Vector3d expected = truth.monument_shift_mm - truth.machine_shift_mm;
    const Metric* dx = find_metric(*rec.result, "center_dx_mm");
    const Metric* dy = find_metric(*rec.result, "center_dy_mm");
    const Metric* dz = find_metric(*rec.result, "face_dz_mm");
    ASSERT_TRUE(dx && dy && dz) << machine.machine_id;
    EXPECT_NEAR(dx->value, expected.x(), bound) << machine.machine_id;
    EXPECT_NEAR(dy->value, expected.y(), bound) << machine.machine_id;
    EXPECT_NEAR(dz->value, expected.z(), bound) << machine.machine_id;
    const auto set = db.load_measurement_set(rec.request_id);
    ASSERT_TRUE(set.has_value());
    EXPECT_GE(set->touches.size(), 4u);
  }
  storage::HistoryQuery good_q;
  good_q.machine_id = "pm-good";
  const auto good_rec = db.history(good_q).front();
  EXPECT_EQ(good_rec.result->verdict, Verdict::Pass);
  storage::HistoryQuery bad_q;
  bad_q.machine_id = "pm-shifted";
  const auto bad_rec = db.history(bad_q).front();
  EXPECT_EQ(bad_rec.result->verdict, Verdict::Fail);
  ASSERT_FALSE(bad_rec.result->likely_causes.empty());
  EXPECT_EQ(bad_rec.result->likely_causes.front(), "machine shifted along its axes");

  // The scheduler published each machine's status after the result, and the historian kept it.
  ASSERT_TRUE(plant.wait_for_db([](storage::Database& d) {
    auto a = d.latest_status("pm-good");
    auto b = d.latest_status("pm-shifted");
    return a && b && a->state == MachineState::Qualified &&
           b->state == MachineState::NeedsIntervention;
  })) << plant.log("scheduler");

  // An order the scheduler refuses (a part check on a held machine) exits 9, REFUSED, with the
  // scheduler's reason; not 4, which is the verdict INVALID (issue 37).
  const testing_cli::CliRun refused =
      testing_cli::run_cli({"check", "--plant", plant.plant_file(), "--machine", "pm-shifted",
                            "--kind", "part_setpoints"},
                           testing_cli::Capture::Separate);
  EXPECT_EQ(refused.exit_code, 9) << refused.err;
  EXPECT_NE(refused.err.find("the scheduler refused"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("held (NEEDS_INTERVENTION)"), std::string::npos) << refused.err;
}

TEST(EndToEnd, OperatorCheckGoesThroughTheSchedulerAndTheCliPrintsHistory) {
  Plant plant("cli", TestDomain::OperatorCheck);
  plant.add_machine("pm1", machine_yaml("pm1", "    machine_shift_mm: [0, 0, 0]\n"));
  plant.write_plant("[]");  // no start-up cycle: only the operator's order
  plant.start("historian");
  Process& solver = plant.start("solver");
  plant.start("acquisition", {"--machine", "pm1"});
  Process& scheduler = plant.start("scheduler");

  const testing_cli::CliRun check =
      testing_cli::run_cli({"check", "--plant", plant.plant_file(), "--machine", "pm1", "--kind",
                            "monument_positioning", "--wait", "60", "--json"});
  ASSERT_EQ(check.exit_code, 0) << plant.log("scheduler");
  const std::string json = check.out;
  EXPECT_NE(json.find("\"verdict\": \"PASS\""), std::string::npos) << json;
  EXPECT_NE(json.find("center_dx_mm"), std::string::npos) << json;

  ASSERT_TRUE(plant.wait_for_db([](storage::Database& db) {
    const auto records = db.history({});
    return !records.empty() && records.front().request && records.front().result;
  }));
  auto db = storage::Database::open_readonly(plant.db_path());
  const auto rec = db.history({}).front();
  EXPECT_EQ(rec.request->requested_by.rfind("operator:", 0), 0u) << rec.request->requested_by;

  // An unknown machine is refused by the tool with a message naming it, exit code 2.
  const testing_cli::CliRun bad =
      testing_cli::run_cli({"check", "--plant", plant.plant_file(), "--machine", "nope", "--kind",
                            "monument_positioning"});
  EXPECT_EQ(bad.exit_code, 2);
  const std::string msg = bad.out;
  EXPECT_NE(msg.find("'nope'"), std::string::npos) << msg;

  // Issue 37: after the services stopped, `ncqual status` listed them as running (their last
  // heartbeats were fresh) and advised `ncqual intervene`, which then waited for a scheduler that
  // was not there. A stopped service says so; a machine without a live scheduler says so.
  const auto liveness = [&](const nlohmann::json& doc, const std::string& service) {
    std::string found = "absent";
    for (const auto& s : doc.at("services")) {
      if (s.at("service") == service) found = s.at("liveness").get<std::string>();
    }
    return found;
  };
  const auto status = [&] {
    const testing_cli::CliRun r = testing_cli::run_cli(
        {"status", "--plant", plant.plant_file(), "--json"}, testing_cli::Capture::Separate);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(r.out);
  };
  ASSERT_TRUE(plant.wait_for_db([](storage::Database& d) {
    int heard = 0;
    for (const Heartbeat& beat : d.services()) {
      heard += beat.service == "solver" || beat.service == "scheduler" ? 1 : 0;
    }
    return heard == 2;
  })) << "the solver's and the scheduler's heartbeats are stored";
  const nlohmann::json running = status();
  EXPECT_EQ(liveness(running, "solver"), "live") << running.dump(2);
  EXPECT_EQ(liveness(running, "scheduler"), "live") << running.dump(2);
  EXPECT_EQ(running.at("machines").at(0).at("scheduler"), "live");
  scheduler.terminate();
  solver.terminate();
  ASSERT_EQ(scheduler.wait(), 0) << plant.log("scheduler");
  ASSERT_EQ(solver.wait(), 0) << plant.log("solver");
  // The historian acknowledged their last heartbeats before they exited (dds::Service::run).
  const nlohmann::json stopped = status();
  EXPECT_EQ(liveness(stopped, "solver"), "stopped") << stopped.dump(2);
  EXPECT_EQ(liveness(stopped, "scheduler"), "stopped") << stopped.dump(2);
  EXPECT_EQ(liveness(stopped, "historian"), "live") << stopped.dump(2);
  EXPECT_EQ(stopped.at("machines").at(0).at("scheduler"), "stopped");
  const testing_cli::CliRun text = testing_cli::run_cli({"status", "--plant", plant.plant_file()},
                                                        testing_cli::Capture::Separate);
  EXPECT_NE(text.out.find("no scheduler is running for it (it stopped)"), std::string::npos)
      << text.out;
  const std::size_t row = text.out.find("\n  scheduler    ");
  ASSERT_NE(row, std::string::npos) << text.out;
  const std::string line = text.out.substr(row + 1, text.out.find('\n', row + 1) - row - 1);
  EXPECT_NE(line.find(" stopped "), std::string::npos) << line;
  EXPECT_EQ(line.find("running"), std::string::npos) << line;
}

}  // namespace
}  // namespace ncqual::testing

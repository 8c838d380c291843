// SPDX-License-Identifier: Apache-2.0
// Restart and bad input across real processes.
#include "harness.hpp"
#include "test_participant.hpp"

#include "cli_runner.hpp"

#include "ncqual/dds/acknowledged_send.hpp"
#include "ncqual/dds/endpoint.hpp"
#include "ncqual/dds/topics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

namespace ncqual::testing {
namespace {

// Orders `count` checks through the scheduler, as `ncqual check` would.
std::vector<std::string> order_checks(ncqual::dds::Writer<ncqual::dds::CheckCommandTopic>& commands,
                                      const std::string& machine, int first, int count) {
  std::vector<std::string> ids;
  for (int i = first; i < first + count; ++i) {
    CheckCommand cmd{machine,
                     "restart-test-" + std::to_string(i),
                     CheckKind::MonumentPositioning,
                     "test",
                     WallClock().now_ns(),
                     {}};
    EXPECT_TRUE(commands.write(cmd));
    ids.push_back(cmd.request_id);
  }
  EXPECT_TRUE(commands.wait_for_acknowledgments(std::chrono::seconds(10)));
  return ids;
}

TEST(HistorianRestart, SigkillWhileChecksAreProducedStoresEveryCheckExactlyOnce) {
  Plant plant("restart", TestDomain::HistorianRestart);
  plant.add_machine("pm1", machine_yaml("pm1", "    machine_shift_mm: [0.001, 0, 0]\n"));
  plant.write_plant("[]");
  Process* historian = &plant.start("historian");
  plant.start("solver");
  plant.start("acquisition", {"--machine", "pm1"});
  plant.start("scheduler");

  ncqual::dds::Participant participant(test_participant(plant));
  ncqual::dds::Writer<ncqual::dds::CheckCommandTopic> commands(participant);
  ASSERT_TRUE(commands.wait_for_readers(1, std::chrono::seconds(30)));

  // First batch; kill the historian as soon as some, not all, of it is stored.
  auto ids = order_checks(commands, "pm1", 0, 20);
  ASSERT_TRUE(plant.wait_for_db([](storage::Database& db) { return db.count_results() >= 3; }))
      << plant.log("historian");
  historian->signal(SIGKILL);
  historian->wait();

  // Checks go on while the historian is down.
  auto more = order_checks(commands, "pm1", 20, 10);
  ids.insert(ids.end(), more.begin(), more.end());

  // Restarted, it receives what it missed from the writers' durable histories.
  plant.start("historian");
  ASSERT_TRUE(plant.wait_for_db([&](storage::Database& db) {
    for (const auto& id : ids) {
      auto rec = db.find_check(id);
      if (!rec || !rec->request || !rec->result || !rec->measurement) return false;
    }
    return true;
  })) << plant.log("historian");

  // Exactly once: as many results as checks ordered, and each id once in the history.
  auto db = storage::Database::open_readonly(plant.db_path());
  EXPECT_EQ(db.count_results(std::string("pm1")), static_cast<std::int64_t>(ids.size()));
  storage::HistoryQuery q;
  q.limit = 1000;
  std::multiset<std::string> seen;
  for (const auto& r : db.history(q)) seen.insert(r.request_id);
  for (const auto& id : ids) EXPECT_EQ(seen.count(id), 1u) << id;
}

TEST(BadInput, MalformedMeasurementSetsGetInvalidResultsAndNothingIsLost) {
  Plant plant("bad", TestDomain::BadInput);
  plant.add_machine("pm1", machine_yaml("pm1", "    machine_shift_mm: [0, 0, 0]\n"));
  plant.write_plant();  // the start-up cycle stores one good check first
  plant.start("historian");
  Process& solver = plant.start("solver");
  plant.start("acquisition", {"--machine", "pm1"});
  plant.start("scheduler");
  ASSERT_TRUE(plant.wait_for_db([](storage::Database& db) { return db.count_results() >= 1; }));

  ncqual::dds::Participant participant(test_participant(plant));
  ncqual::dds::Writer<ncqual::dds::MeasurementSetTopic> sets(participant);
  ASSERT_TRUE(sets.wait_for_readers(2, std::chrono::seconds(30)));  // solver and historian

  auto base = [](const std::string& id) {
    MeasurementSet s;
    s.machine_id = "pm1";
    s.request_id = id;
    s.kind = CheckKind::MonumentPositioning;
    s.instrument = "touch_probe";
    s.frame = "machine";
    s.time_ns = WallClock().now_ns();
    return s;
  };
  const Eigen::Vector3d out_x(1, 0, 0);
  auto empty = base("bad-empty");
  auto nan = base("bad-nan");
  for (int i = 0; i < 4; ++i) {
    nan.touches.push_back(Touch{"hole_edge", {1200, 800, 497, 0, 0, 0}, out_x});
  }
  nan.touches[1].axes.y_mm = std::numeric_limits<double>::quiet_NaN();
  nan.touches.push_back(Touch{"face", {1230, 800, 503, 0, 0, 0}, {0, 0, -1}});
  auto unknown = base("bad-unknown-machine");
  unknown.machine_id = "no-such-machine";
  auto wrong_kind = base("bad-kind");
  wrong_kind.kind = CheckKind::GlobalGrid;
  for (const auto* s : {&empty, &nan, &unknown, &wrong_kind}) ASSERT_TRUE(sets.write(*s));

  ASSERT_TRUE(plant.wait_for_db([](storage::Database& db) {
    for (const char* id : {"bad-empty", "bad-nan", "bad-unknown-machine", "bad-kind"}) {
      auto rec = db.find_check(id);
      if (!rec || !rec->result) return false;
    }
    return true;
  })) << plant.log("solver");

  auto db = storage::Database::open_readonly(plant.db_path());
  auto reason_of = [&](const char* id) {
    auto rec = db.find_check(id);
    EXPECT_EQ(rec->result->verdict, Verdict::Invalid) << id;
    return rec->result->reason;
  };
  EXPECT_NE(reason_of("bad-empty").find("touches"), std::string::npos);
  EXPECT_NE(reason_of("bad-nan").find("touches[1].axes.y_mm"), std::string::npos)
      << reason_of("bad-nan");
  EXPECT_NE(reason_of("bad-unknown-machine").find("no-such-machine"), std::string::npos);
  EXPECT_NE(reason_of("bad-kind").find("global_grid"), std::string::npos);

  // No process exited, and the good check stored before is still there.
  EXPECT_TRUE(solver.running());
  EXPECT_GE(db.count_results(std::string("pm1")), 4);
  storage::HistoryQuery q;
  q.machine_id = "pm1";
  q.limit = 100;
  int passes = 0;
  for (const auto& r : db.history(q)) passes += r.result && r.result->verdict == Verdict::Pass;
  EXPECT_EQ(passes, 1);
}

// A plant whose QoS profiles do not load would run every service on Fast DDS's defaults, where
// nothing is durable: refused at start, unless the plant says allow_default_qos: true.
TEST(BadInput, APlantWhoseQosProfilesDoNotLoadIsRefusedUnlessItAllowsTheDefaults) {
  Plant plant("default-qos", TestDomain::DefaultQos);
  plant.add_machine("pm1", machine_yaml("pm1", "    machine_shift_mm: [0, 0, 0]\n"));
  plant.set_qos_lines("");  // no qos_profiles: key
  plant.write_plant("[]");
  Process& refused = plant.start("historian");
  ASSERT_TRUE(refused.wait_for(std::chrono::seconds(60))) << plant.log("historian");
  EXPECT_EQ(refused.wait(), 2);
  const std::string said = plant.log("historian");
  EXPECT_NE(said.find("QoS profiles not loaded"), std::string::npos) << said;
  EXPECT_NE(said.find("allow_default_qos: true"), std::string::npos) << said;

  plant.set_qos_lines("allow_default_qos: true\n");
  plant.write_plant("[]");
  Process& allowed = plant.start("historian");
  // It runs: its own heartbeat, written and read on Fast DDS's defaults, is stored.
  ASSERT_TRUE(plant.wait_for_db([](storage::Database& db) { return !db.services().empty(); }))
      << plant.log("historian");
  EXPECT_NE(plant.log("historian").find("running on Fast DDS's defaults"), std::string::npos);
  allowed.terminate();
  EXPECT_EQ(allowed.wait(), 0) << plant.log("historian");
}

// A forged PASS must not hide a genuine FAIL: a second, different result for a stored request is
// kept beside the first and flagged, never stored over it or dropped; the same result again is a
// duplicate, stored once. Every answer is the historian's acknowledgement.
TEST(Conflict, ASecondDifferentResultForAStoredRequestIsKeptAndFlagged) {
  Plant plant("conflict", TestDomain::Conflict);
  plant.add_machine("pm1", machine_yaml("pm1", "    machine_shift_mm: [0, 0, 0]\n"));
  plant.write_plant("[]");
  plant.start("historian");

  ncqual::dds::Participant participant(test_participant(plant));
  ncqual::dds::Writer<ncqual::dds::CheckResultTopic> results(participant);
  CheckResult genuine;
  genuine.machine_id = "pm1";
  genuine.request_id = "pm1-monument_positioning-1";
  genuine.kind = CheckKind::MonumentPositioning;
  genuine.verdict = Verdict::Fail;
  genuine.reason = "center_dx_mm = 0.045 beyond 0.025";
  genuine.metrics = {{"center_dx_mm", 0.045, "mm", -0.025, 0.025, false}};
  genuine.time_ns = WallClock().now_ns();
  CheckResult forged = genuine;
  forged.verdict = Verdict::Pass;
  forged.reason.clear();
  forged.metrics[0].value = 0.001;
  forged.metrics[0].pass = true;

  const auto outcome_of = [&](const CheckResult& r) {
    const auto answer = ncqual::dds::send_acknowledged(participant, results, r, {roles::kHistorian},
                                                       std::chrono::seconds(30));
    EXPECT_TRUE(answer.silent.empty()) << plant.log("historian");
    return answer.answers.count(roles::kHistorian) ? answer.answers.at(roles::kHistorian).outcome
                                                   : AckOutcome::Refused;
  };
  // The first is stored; its answer is STORED, or DUPLICATE when the STORED one left before our
  // acknowledgement reader was matched on the historian's side and the rewrite was answered
  // instead (both say: stored). Once is what the database shows below.
  const AckOutcome first = outcome_of(genuine);
  EXPECT_TRUE(first == AckOutcome::Stored || first == AckOutcome::Duplicate) << to_string(first);
  EXPECT_EQ(outcome_of(genuine), AckOutcome::Duplicate);
  EXPECT_EQ(outcome_of(forged), AckOutcome::Conflict);

  // It is raised as an alarm, for whoever watches the plant (durable: a late monitor sees it).
  ncqual::dds::Reader<ncqual::dds::AlarmTopic> alarms(participant);
  std::vector<Alarm> raised;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (raised.empty() && std::chrono::steady_clock::now() < deadline) {
    for (const auto& in : alarms.take()) raised.push_back(in.value);
    if (raised.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  // Once, though the forged result may reach the historian twice (a resend before its answer).
  std::string listed;
  for (const auto& a : raised) listed += a.alarm_id + ": " + a.text + "\n";
  ASSERT_EQ(raised.size(), 1u) << listed << plant.log("historian");
  EXPECT_EQ(raised[0].kind, AlarmKind::Conflict);
  EXPECT_TRUE(raised[0].active);
  EXPECT_EQ(raised[0].machine_id, "pm1");
  EXPECT_EQ(raised[0].source, roles::kHistorian);
  EXPECT_NE(raised[0].alarm_id.find("conflict/ncqual/CheckResult/" + genuine.request_id),
            std::string::npos)
      << raised[0].alarm_id;
  // What the scheduler holds the machine for, naming both writers (GUIDs on an open plant).
  EXPECT_EQ(
      raised[0].text.rfind(
          "conflicting results of " + genuine.request_id + " of machine 'pm1' from writer ", 0),
      0u)
      << raised[0].text;
  EXPECT_NE(raised[0].text.find(" and writer "), std::string::npos) << raised[0].text;

  auto db = storage::Database::open_readonly(plant.db_path());
  const auto record = db.find_check(genuine.request_id);
  ASSERT_TRUE(record && record->result);
  EXPECT_EQ(record->result->verdict, Verdict::Fail);  // the first stays
  EXPECT_EQ(record->conflicts, 1);
  EXPECT_EQ(db.count_results(), 1);
  const auto conflicts = db.conflicts("pm1");
  ASSERT_EQ(conflicts.size(), 1u);
  EXPECT_EQ(conflicts[0].topic, "ncqual/CheckResult");
  EXPECT_EQ(conflicts[0].sample_id, genuine.request_id);
  EXPECT_NE(conflicts[0].content_hash, conflicts[0].stored_hash);
  EXPECT_FALSE(conflicts[0].writer.empty());
  EXPECT_NE(conflicts[0].document.find("\"verdict\":\"PASS\""), std::string::npos)
      << conflicts[0].document;

  // People see it: the history flags the check.
  const auto history = testing_cli::run_cli({"history", "--db", plant.db_path()});
  EXPECT_EQ(history.exit_code, 0) << history.out;
  EXPECT_NE(history.out.find("CONFLICT: 1 other sample(s)"), std::string::npos) << history.out;
}

// Two different measurement sets for one request (a second acquisition configured for the same
// machine, a replay into a live plant): the record of that check is in doubt. The historian keeps
// both and raises the conflict naming both writers, the solver does not solve the second one nor
// call it "already solved", and the scheduler holds the machine, though the first set's PASS had
// released it, until a person records an intervention, which re-runs the check.
TEST(Conflict, AConflictingMeasurementHoldsTheMachineUntilAPersonDecides) {
  Plant plant("conflict-hold", TestDomain::ConflictHold);
  plant.add_machine("pm1", machine_yaml("pm1", "    machine_shift_mm: [0.002, 0, 0]\n"));
  plant.write_plant();
  plant.start("historian");
  plant.start("solver");
  plant.start("scheduler");
  plant.start("acquisition", {"--machine", "pm1"});
  // Qualified, and the set behind it stored: the set reaches the historian from the acquisition,
  // the status from the scheduler, so either may be stored first.
  std::string request;
  std::optional<MeasurementSet> stored;
  ASSERT_TRUE(plant.wait_for_db([&](storage::Database& db) {
    const auto st = db.latest_status("pm1");
    if (!st || st->state != MachineState::Qualified) return false;
    request = st->request_id;
    stored = db.load_measurement_set(request);
    return stored.has_value();
  })) << plant.log("scheduler");

  // Another writer's set for the same request: the same check, other touches.
  MeasurementSet other = *stored;
  ASSERT_FALSE(other.touches.empty());
  other.touches[0].axes.x_mm += 0.040;
  ncqual::dds::Participant participant(test_participant(plant));
  ncqual::dds::Writer<ncqual::dds::MeasurementSetTopic> sets(participant,
                                                             ncqual::dds::InPartitionOf{"pm1"});
  const auto answered = ncqual::dds::send_acknowledged(
      participant, sets, other, {roles::kHistorian, roles::kSolver}, std::chrono::seconds(60));
  ASSERT_TRUE(answered.silent.empty()) << plant.log("historian") << plant.log("solver");
  EXPECT_EQ(answered.answers.at(roles::kHistorian).outcome, AckOutcome::Conflict);
  EXPECT_EQ(answered.answers.at(roles::kSolver).outcome, AckOutcome::Conflict);
  EXPECT_NE(answered.answers.at(roles::kSolver).detail.find("not solved again"), std::string::npos)
      << answered.answers.at(roles::kSolver).detail;

  // Held, saying why and what to do.
  std::string detail;
  ASSERT_TRUE(plant.wait_for_db([&](storage::Database& db) {
    const auto st = db.latest_status("pm1");
    if (!st || st->state != MachineState::NeedsIntervention) return false;
    detail = st->detail;
    return true;
  })) << plant.log("scheduler")
      << plant.log("historian");
  EXPECT_EQ(
      detail.rfind("conflicting measurements of " + request + " of machine 'pm1' from writer ", 0),
      0u)
      << detail;
  EXPECT_NE(detail.find(" and writer "), std::string::npos) << detail;
  EXPECT_NE(detail.find("ncqual intervene --machine pm1 --check monument_positioning"),
            std::string::npos)
      << detail;
  const auto status = testing_cli::run_cli({"status", "--plant", plant.plant_file()});
  EXPECT_NE(status.out.find("conflicting measurements of " + request), std::string::npos)
      << status.out;
  {
    auto db = storage::Database::open_readonly(plant.db_path());
    EXPECT_EQ(db.find_check(request)->conflicts, 1);
    EXPECT_EQ(db.count_results("pm1"), 1);  // the second set was not solved
  }

  // A person decides: the intervention re-runs the check, whose PASS releases the machine.
  const auto intervened = testing_cli::run_cli(
      {"intervene", "--machine", "pm1", "--check", "monument_positioning", "--note",
       "second acquisition of pm1 stopped", "--plant", plant.plant_file()});
  ASSERT_EQ(intervened.exit_code, 0) << intervened.out;
  ASSERT_TRUE(plant.wait_for_db([&](storage::Database& db) {
    const auto st = db.latest_status("pm1");
    return st && st->state == MachineState::Qualified && st->request_id != request;
  })) << plant.log("scheduler");
}

}  // namespace
}  // namespace ncqual::testing

// SPDX-License-Identifier: Apache-2.0
// What the scheduler acknowledges (services/scheduler/core/include/ncqual/scheduler/answer.hpp),
// on a real state file: a sample that cannot be read or that the scheduler refuses is REFUSED
// with the reason, one it decided on is ACCEPTED once the decision is saved, and nothing is
// acknowledged when the save failed (writes beyond a file size limit, as on a full disk), so its
// sender sends it again; and the command-line choices settle as the help says.
#include "ncqual/scheduler/answer.hpp"
#include "ncqual/scheduler/driver.hpp"

#include "scheduler_test_support.hpp"
#include "storage_test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>

namespace ncqual::scheduler {
namespace {

using test_support::one_machine;
using test_support::with_state_database;

struct Rig {
  Rig() : state(open_state()), scheduler(plant, clock, outputs(), &state) {
    scheduler.start({CheckKind::MonumentCAlignment});
  }
  static storage::StateFile open_state() {
    const std::string file = ::testing::TempDir() + "ncqual-scheduler-answer-" +
                             ::testing::UnitTest::GetInstance()->current_test_info()->name() +
                             ".db";
    std::filesystem::remove(file);
    return storage::StateFile::open(file);
  }
  Scheduler::Outputs outputs() {
    Scheduler::Outputs out;
    out.request = [this](const CheckRequest& r) { requests.push_back(r); };
    return out;
  }
  CheckResult pass_of_first() const {
    CheckResult r;
    r.machine_id = "m1";
    r.request_id = requests.at(0).request_id;
    r.kind = requests.at(0).kind;
    r.verdict = Verdict::Pass;
    return r;
  }

  PlantConfig plant = with_state_database(one_machine());
  SimulatedClock clock{1'000'000'000};
  std::vector<CheckRequest> requests;
  storage::StateFile state;
  Scheduler scheduler;
};

TEST(SchedulerAnswer, AnUnreadableSampleIsRefusedWithTheReadersReasonAndChangesNothing) {
  Rig rig;
  const auto a = answer_result(rig.scheduler, rig.pass_of_first(), "verdict 9 is not a verdict");
  EXPECT_EQ(a.ack, AckOutcome::Refused);
  EXPECT_EQ(a.detail, "verdict 9 is not a verdict");
  EXPECT_EQ(rig.scheduler.state("m1"), MachineState::Checking);
}

TEST(SchedulerAnswer, AResultDecidedOnIsAcceptedOnceSaved) {
  Rig rig;
  const auto a = answer_result(rig.scheduler, rig.pass_of_first(), "");
  EXPECT_EQ(a.ack, AckOutcome::Accepted);
  EXPECT_EQ(rig.scheduler.state("m1"), MachineState::Qualified);
}

TEST(SchedulerAnswer, ACommandTheSchedulerRefusesIsRefusedNamingWhy) {
  Rig rig;
  const auto a = answer_command(
      rig.scheduler, {"m9", "r1", CheckKind::MonumentPositioning, "operator:ann", 0, {}}, "");
  EXPECT_EQ(a.ack, AckOutcome::Refused);
  EXPECT_NE(a.detail.find("m9"), std::string::npos) << a.detail;
  const auto ok = answer_command(
      rig.scheduler, {"m1", "r2", CheckKind::MonumentPositioning, "operator:ann", 0, {}}, "");
  EXPECT_EQ(ok.ack, AckOutcome::Accepted) << ok.detail;
}

TEST(SchedulerAnswer, AnInterventionThatChangesNothingIsAcceptedSayingSo) {
  Rig rig;
  Intervention iv;
  iv.machine_id = "m1";
  iv.intervention_id = "i1";
  iv.kind = CheckKind::MonumentPositioning;  // not the check the machine is held for: none is
  iv.note = "replaced stylus";
  iv.operator_name = "ann";
  const auto a = answer_intervention(rig.scheduler, iv, "");
  EXPECT_EQ(a.ack, AckOutcome::Accepted);
  EXPECT_FALSE(a.detail.empty()) << "why it changed nothing";
}

TEST(SchedulerAnswer, NothingIsAcknowledgedWhenTheDecisionCouldNotBeSaved) {
  Rig rig;
  Answer a;
  Answer c;
  {
    const storage::testing::FullDisk full;  // writes past a file size limit fail
    a = answer_result(rig.scheduler, rig.pass_of_first(), "");
    c = answer_command(rig.scheduler,
                       {"m1", "r3", CheckKind::MonumentPositioning, "operator:ann", 0, {}}, "");
  }
  EXPECT_FALSE(a.ack.has_value()) << "the solver sends the result again";
  EXPECT_FALSE(c.ack.has_value()) << "the operator's tool sends the order again";

  // Sent again once the disk takes writes: decided and accepted.
  EXPECT_EQ(answer_result(rig.scheduler, rig.pass_of_first(), "").ack, AckOutcome::Accepted);
}

TEST(SchedulerAnswer, OnlyAReadableConflictAlarmReachesTheScheduler) {
  Rig rig;
  Alarm storage_alarm;
  storage_alarm.kind = AlarmKind::Storage;
  storage_alarm.alarm_id = "storage/historian-1";
  EXPECT_FALSE(answer_alarm(rig.scheduler, storage_alarm, ""));
  Alarm conflict;
  conflict.machine_id = "m1";
  conflict.kind = AlarmKind::Conflict;
  conflict.active = true;
  conflict.alarm_id = "conflict/ncqual/MeasurementSet/" + rig.requests.at(0).request_id + "/ab";
  conflict.text = "conflicting measurements of " + rig.requests.at(0).request_id;
  EXPECT_FALSE(answer_alarm(rig.scheduler, conflict, "bad CDR"));
  EXPECT_EQ(rig.scheduler.state("m1"), MachineState::Checking);
  EXPECT_TRUE(answer_alarm(rig.scheduler, conflict, ""));
  EXPECT_EQ(rig.scheduler.state("m1"), MachineState::NeedsIntervention);
}

TEST(SchedulerFlags, TheFlagsSettleTheServedMachinesCycleStateAndRun) {
  Flags flags;
  Settings s = settle(with_state_database(one_machine()), flags);
  EXPECT_EQ(s.state_file, "/var/lib/ncqual/scheduler.db");
  EXPECT_EQ(s.run.stall, std::chrono::seconds(30));
  EXPECT_FALSE(s.run.until_ns.has_value());
  flags.machine_list = "m1";
  flags.cycle = "monument_c_alignment";
  flags.stall_s = 2.5;
  s = settle(with_state_database(one_machine()), flags);
  EXPECT_EQ(s.state_file, "/var/lib/ncqual/scheduler-m1.db");
  EXPECT_EQ(s.cycle, (std::vector<CheckKind>{CheckKind::MonumentCAlignment}));
  EXPECT_EQ(s.run.stall, std::chrono::milliseconds(2500));
  flags.state = "/tmp/mine.db";
  EXPECT_EQ(settle(with_state_database(one_machine()), flags).state_file, "/tmp/mine.db");
  flags.speed = 10;
  try {
    settle(with_state_database(one_machine()), flags);
    ADD_FAILURE() << "--speed on the wall clock was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "--speed needs the plant's clock.mode: simulated");
  }
}

}  // namespace
}  // namespace ncqual::scheduler

// SPDX-License-Identifier: Apache-2.0
#include "ncqual/scheduler/scheduler.hpp"

#include <gtest/gtest.h>

namespace ncqual::scheduler {
namespace {

struct Recorder {
  std::vector<CheckRequest> requests;
  std::vector<MachineStatus> statuses;
  Scheduler::Outputs outputs() {
    Scheduler::Outputs out;
    out.request = [this](const CheckRequest& r) { requests.push_back(r); };
    out.status = [this](const MachineStatus& s) { statuses.push_back(s); };
    return out;
  }
};

PlantConfig two_machines() {
  PlantConfig p;
  p.plant = "t";
  p.machines.resize(2);
  p.machines[0].machine_id = "m1";
  p.machines[1].machine_id = "m2";
  return p;
}

FixtureConfig fixture(const std::string& id) {
  FixtureConfig f;
  f.fixture_id = id;
  f.z_planes_mm = {0, 152.4, 304.8, 457.2, 609.6};  // five planes: ten configurations
  return f;
}

CheckResult result_of(const CheckRequest& r, Verdict v, std::vector<std::string> causes = {}) {
  CheckResult res;
  res.machine_id = r.machine_id;
  res.request_id = r.request_id;
  res.kind = r.kind;
  res.verdict = v;
  res.likely_causes = std::move(causes);
  return res;
}

TEST(Scheduler, RunsTheCycleInOrderAndAFailureStopsTheRest) {
  const PlantConfig plant = two_machines();
  SimulatedClock clock(1'000'000'000);
  Recorder rec;
  Scheduler s(plant, clock, rec.outputs());
  s.start({CheckKind::MonumentCAlignment, CheckKind::MonumentToolLength,
           CheckKind::MonumentPositioning});
  ASSERT_EQ(rec.requests.size(), 2u);  // the first check of each machine, nothing more yet
  EXPECT_EQ(rec.requests[0].kind, CheckKind::MonumentCAlignment);
  EXPECT_NE(rec.requests[0].request_id, rec.requests[1].request_id);

  // m1 passes check 1: check 2 follows. m2 fails check 1: nothing follows, intervention needed.
  const CheckRequest m1_first =
      rec.requests[0].machine_id == "m1" ? rec.requests[0] : rec.requests[1];
  const CheckRequest m2_first =
      rec.requests[0].machine_id == "m2" ? rec.requests[0] : rec.requests[1];
  s.result(result_of(m1_first, Verdict::Pass));
  ASSERT_EQ(rec.requests.size(), 3u);
  EXPECT_EQ(rec.requests[2].kind, CheckKind::MonumentToolLength);
  s.result(result_of(m2_first, Verdict::Fail, {"bent stylus"}));
  EXPECT_EQ(rec.requests.size(), 3u);
  EXPECT_EQ(s.state("m2"), MachineState::NeedsIntervention);
  EXPECT_NE(rec.statuses.back().detail.find("bent stylus"), std::string::npos);

  // A duplicate result (DDS redelivery) changes nothing.
  s.result(result_of(m1_first, Verdict::Pass));
  EXPECT_EQ(rec.requests.size(), 3u);

  s.result(result_of(rec.requests[2], Verdict::Pass));
  s.result(result_of(rec.requests[3], Verdict::Pass));
  EXPECT_EQ(s.state("m1"), MachineState::Qualified);
  EXPECT_EQ(rec.requests.size(), 4u);
}

TEST(Scheduler, OperatorCommandsAreValidated) {
  const PlantConfig plant = two_machines();
  SimulatedClock clock;
  Recorder rec;
  Scheduler s(plant, clock, rec.outputs());
  EXPECT_NE(s.command({"nope", "r1", CheckKind::MonumentPositioning, "op", 0, {}}).find("'nope'"),
            std::string::npos);
  EXPECT_NE(s.command({"m1", "", CheckKind::MonumentPositioning, "op", 0, {}}).find("request_id"),
            std::string::npos);
  EXPECT_TRUE(rec.requests.empty());
  EXPECT_EQ(s.command({"m1", "r1", CheckKind::MonumentPositioning, "operator:ann", 0, {}}), "");
  EXPECT_EQ(s.command({"m1", "r1", CheckKind::MonumentPositioning, "operator:ann", 0, {}}), "");
  ASSERT_EQ(rec.requests.size(), 1u);  // the resent order is not a second request
  EXPECT_EQ(rec.requests[0].request_id, "r1");
  EXPECT_EQ(rec.requests[0].requested_by, "operator:ann");
  EXPECT_EQ(s.state("m1"), MachineState::Checking);
  // Sent again after its check is done (the sender missed the acknowledgement): still one request.
  s.result(result_of(rec.requests[0], Verdict::Pass));
  EXPECT_EQ(s.command({"m1", "r1", CheckKind::MonumentPositioning, "operator:ann", 0, {}}), "");
  EXPECT_EQ(rec.requests.size(), 1u);
  EXPECT_EQ(s.state("m1"), MachineState::Qualified);
}

Alarm conflict_alarm(const std::string& machine, const std::string& topic,
                     const std::string& request_id, const std::string& text) {
  Alarm a;
  a.machine_id = machine;
  a.alarm_id = "conflict/" + topic + "/" + request_id + "/0a1b2c3d";
  a.kind = AlarmKind::Conflict;
  a.active = true;
  a.source = "historian";
  a.text = text;
  return a;
}

TEST(Scheduler, ConflictAlarmsOfSetsAndResultsNameTheirRequest) {
  const auto set = check_conflict_of(conflict_alarm(
      "m1", "ncqual/MeasurementSet", "m1-monument_positioning-20260105T060000Z-1", "x"));
  ASSERT_TRUE(set);
  EXPECT_EQ(set->topic, "ncqual/MeasurementSet");
  EXPECT_EQ(set->request_id, "m1-monument_positioning-20260105T060000Z-1");
  const auto result = check_conflict_of(conflict_alarm("m1", "ncqual/CheckResult", "op-7", "x"));
  ASSERT_TRUE(result);
  EXPECT_EQ(result->request_id, "op-7");
  // Not a check's conflict: a request's, an intervention's, a storage alarm, a cleared one.
  EXPECT_FALSE(check_conflict_of(conflict_alarm("m1", "ncqual/CheckRequest", "op-7", "x")));
  EXPECT_FALSE(check_conflict_of(conflict_alarm("m1", "ncqual/Intervention", "iv-1", "x")));
  Alarm storage = conflict_alarm("", "ncqual/MeasurementSet", "op-7", "x");
  storage.kind = AlarmKind::Storage;
  EXPECT_FALSE(check_conflict_of(storage));
  Alarm cleared = conflict_alarm("m1", "ncqual/MeasurementSet", "op-7", "x");
  cleared.active = false;
  EXPECT_FALSE(check_conflict_of(cleared));
  Alarm cut = conflict_alarm("m1", "ncqual/MeasurementSet", "", "x");
  cut.alarm_id = "conflict/ncqual/MeasurementSet/";
  EXPECT_FALSE(check_conflict_of(cut));
}

// Two different measurement sets for one request (an acquisition writing for a machine it does
// not serve, a replay into a live plant): the check's record is in doubt, so the machine is held
// until a person decides, even though its result already released it. Not "already solved" and
// forgotten.
TEST(Scheduler, AConflictingMeasurementOfAJudgedCheckHoldsTheMachineUntilAnIntervention) {
  const PlantConfig plant = two_machines();
  SimulatedClock clock(1'000'000'000);
  Recorder rec;
  Scheduler s(plant, clock, rec.outputs());
  s.start({CheckKind::MonumentPositioning});
  ASSERT_EQ(rec.requests.size(), 2u);
  const CheckRequest m1 = rec.requests[0].machine_id == "m1" ? rec.requests[0] : rec.requests[1];
  s.result(result_of(m1, Verdict::Pass));
  ASSERT_EQ(s.state("m1"), MachineState::Qualified);

  const std::string text = "conflicting measurements of " + m1.request_id +
                           " of machine 'm1' from acquisition-m2 (writer a) and acquisition-m1 "
                           "(writer b) (content 1 stored first, 2 kept beside it)";
  const Alarm alarm = conflict_alarm("m1", "ncqual/MeasurementSet", m1.request_id, text);
  EXPECT_EQ(s.conflict("m1", *check_conflict_of(alarm), alarm.text), "");
  EXPECT_EQ(s.state("m1"), MachineState::NeedsIntervention);
  EXPECT_EQ(rec.statuses.back().state, MachineState::NeedsIntervention);
  EXPECT_EQ(rec.statuses.back().request_id, m1.request_id);
  EXPECT_EQ(rec.statuses.back().detail.rfind(text + "; next: compare the two", 0), 0u)
      << rec.statuses.back().detail;
  EXPECT_NE(rec.statuses.back().detail.find("ncqual intervene --machine m1 --check "
                                            "monument_positioning"),
            std::string::npos);
  EXPECT_EQ(s.state("m2"), MachineState::Checking);  // the other machine goes on

  // The same alarm again (durable redelivery, a restart) changes nothing.
  const std::size_t statuses = rec.statuses.size();
  EXPECT_EQ(s.conflict("m1", *check_conflict_of(alarm), alarm.text), "");
  EXPECT_EQ(rec.statuses.size(), statuses);
  // An operator's order of a later check is refused while held, naming the conflict.
  const std::string refused =
      s.command({"m1", "op-1", CheckKind::PartSetPoints, "operator:ann", 0, {}});
  EXPECT_NE(refused.find("conflicting measurements of " + m1.request_id), std::string::npos)
      << refused;

  // A person decides: the intervention re-runs the check under a new id; its PASS releases.
  Intervention iv;
  iv.machine_id = "m1";
  iv.intervention_id = "iv-1";
  iv.kind = CheckKind::MonumentPositioning;
  iv.note = "acquisition-m2 misconfigured; re-measured";
  EXPECT_EQ(s.intervention(iv), "");
  const CheckRequest rerun = rec.requests.back();
  EXPECT_EQ(rerun.machine_id, "m1");
  EXPECT_EQ(rerun.kind, CheckKind::MonumentPositioning);
  EXPECT_NE(rerun.request_id, m1.request_id);
  s.result(result_of(rerun, Verdict::Pass));
  EXPECT_EQ(s.state("m1"), MachineState::Qualified);
}

// A conflict of a check still waiting for its result takes the check off: whichever result
// comes, it does not count. One of a request the scheduler never issued (an import) changes
// nothing and says why; a machine already held keeps its hold, with the conflict added.
TEST(Scheduler, AConflictOfAPendingCheckTakesItOffAndOneOfAnUnknownRequestChangesNothing) {
  const PlantConfig plant = two_machines();
  SimulatedClock clock(1'000'000'000);
  Recorder rec;
  Scheduler s(plant, clock, rec.outputs());
  s.start({CheckKind::MonumentPositioning});
  const CheckRequest m1 = rec.requests[0].machine_id == "m1" ? rec.requests[0] : rec.requests[1];
  const CheckRequest m2 = rec.requests[0].machine_id == "m2" ? rec.requests[0] : rec.requests[1];

  const Alarm unknown = conflict_alarm("m1", "ncqual/MeasurementSet", "import-3", "x");
  EXPECT_NE(s.conflict("m1", *check_conflict_of(unknown), unknown.text).find("import-3"),
            std::string::npos);
  EXPECT_EQ(s.state("m1"), MachineState::Checking);

  const Alarm pending = conflict_alarm("m1", "ncqual/CheckResult", m1.request_id,
                                       "conflicting results of " + m1.request_id);
  EXPECT_EQ(s.conflict("m1", *check_conflict_of(pending), pending.text), "");
  EXPECT_EQ(s.state("m1"), MachineState::NeedsIntervention);
  s.result(result_of(m1, Verdict::Pass));  // the result of the doubtful check: not counted
  EXPECT_EQ(s.state("m1"), MachineState::NeedsIntervention);

  s.result(result_of(m2, Verdict::Fail, {"bent stylus"}));
  ASSERT_EQ(s.state("m2"), MachineState::NeedsIntervention);
  const Alarm late = conflict_alarm("m2", "ncqual/MeasurementSet", m2.request_id,
                                    "conflicting measurements of " + m2.request_id);
  EXPECT_EQ(s.conflict("m2", *check_conflict_of(late), late.text), "");
  const std::string detail = rec.statuses.back().detail;
  EXPECT_NE(detail.find("bent stylus"), std::string::npos) << detail;
  EXPECT_NE(detail.find("; also: conflicting measurements of " + m2.request_id), std::string::npos)
      << detail;
}

// The weekly fixture loop: pre-calibration FAIL with zero offsets -> post-calibration that
// names the correction it verifies -> PASS continues the cycle, FAIL holds the machine.
TEST(Scheduler, FixturePreCalibrationFailureWithZeroOffsetsIsVerifiedByAPostCalibration) {
  PlantConfig plant = two_machines();
  plant.machines.resize(1);
  plant.machines[0].fixture = fixture("UHF1");
  SimulatedClock clock(5);
  Recorder rec;
  Scheduler s(plant, clock, rec.outputs());
  s.start({CheckKind::FixturePreCalibration, CheckKind::MonumentCAlignment});
  ASSERT_EQ(rec.requests.size(), 1u);
  const CheckRequest pre = rec.requests[0];
  EXPECT_EQ(pre.kind, CheckKind::FixturePreCalibration);
  const NamedValue* cfg = find_value(pre.parameters, "fixture_configuration");
  ASSERT_NE(cfg, nullptr);
  EXPECT_EQ(cfg->value, 0);  // a fixture never checked starts its rotation at 0

  CheckResult failed = result_of(pre, Verdict::Fail, {"fixture zero positions drifted"});
  failed.correction = Correction{"fixture:UHF1", {{"C1R1.dx_mm", 0.03, "mm"}}};
  s.result(failed);
  ASSERT_EQ(rec.requests.size(), 2u);
  const CheckRequest post = rec.requests[1];
  EXPECT_EQ(post.kind, CheckKind::FixturePostCalibration);
  EXPECT_EQ(post.verifies_correction_of, pre.request_id);
  ASSERT_NE(find_value(post.parameters, "fixture_configuration"), nullptr);
  EXPECT_EQ(find_value(post.parameters, "fixture_configuration")->value, 0);
  EXPECT_NE(s.state("m1"), MachineState::NeedsIntervention);

  // The correction held: the cycle goes on with the daily checks.
  s.result(result_of(post, Verdict::Pass));
  ASSERT_EQ(rec.requests.size(), 3u);
  EXPECT_EQ(rec.requests[2].kind, CheckKind::MonumentCAlignment);
}

TEST(Scheduler, FailedPostCalibrationOrPreCalibrationWithoutOffsetsHoldsTheMachine) {
  PlantConfig plant = two_machines();
  plant.machines.resize(1);
  SimulatedClock clock(1'000);
  Recorder rec;
  Scheduler s(plant, clock, rec.outputs());
  s.start({CheckKind::FixturePreCalibration, CheckKind::MonumentCAlignment});
  CheckResult failed = result_of(rec.requests[0], Verdict::Fail);
  failed.correction = Correction{"fixture:UHF1", {}};
  s.result(failed);
  ASSERT_EQ(rec.requests.size(), 2u);
  s.result(
      result_of(rec.requests[1], Verdict::Fail, {"fixture axes misaligned with the machine axes"}));
  EXPECT_EQ(rec.requests.size(), 2u);  // no daily checks after a failed fixture
  EXPECT_EQ(s.state("m1"), MachineState::NeedsIntervention);
  EXPECT_NE(rec.statuses.back().detail.find("fixture_postcal FAIL"), std::string::npos)
      << rec.statuses.back().detail;
  EXPECT_NE(rec.statuses.back().detail.find("misaligned"), std::string::npos);

  // An INVALID pre-calibration (no offsets) is no correction loop: it holds the machine.
  Recorder rec2;
  Scheduler s2(plant, clock, rec2.outputs());
  s2.start({CheckKind::FixturePreCalibration, CheckKind::MonumentCAlignment});
  s2.result(result_of(rec2.requests[0], Verdict::Invalid));
  EXPECT_EQ(rec2.requests.size(), 1u);
  EXPECT_EQ(s2.state("m1"), MachineState::NeedsIntervention);
}

}  // namespace
}  // namespace ncqual::scheduler

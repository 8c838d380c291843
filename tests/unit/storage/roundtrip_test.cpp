// SPDX-License-Identifier: Apache-2.0
// Every sample type comes back exactly as stored, and storing it again changes nothing.
#include "storage_test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace ncqual::storage {
namespace {

using namespace testing;  // storage_test_support.hpp

class StorageRoundTrip : public ::testing::Test {
 protected:
  TempDir dir_;
  std::string path_ = dir_.file("historian.db");
  Database db_ = Database::open(path_);
};

TEST_F(StorageRoundTrip, CheckRequestComesBackAndIsStoredOnce) {
  const CheckRequest request = make_request("r1");
  EXPECT_TRUE(db_.store(request));
  EXPECT_FALSE(db_.store(request));

  const auto record = db_.find_check("r1");
  ASSERT_TRUE(record.has_value());
  ASSERT_TRUE(record->request.has_value());
  EXPECT_EQ(record->request->machine_id, "M1");
  EXPECT_EQ(record->request->request_id, "r1");
  EXPECT_EQ(record->request->kind, CheckKind::MonumentCAlignment);
  EXPECT_EQ(record->request->requested_by, "operator:ada");
  EXPECT_EQ(record->request->time_ns, 1'000);
  EXPECT_EQ(record->request->attempt, 2);
  EXPECT_FALSE(record->result.has_value());
  EXPECT_FALSE(record->measurement.has_value());

  RawDb raw(path_);
  EXPECT_EQ(raw.count("requests"), 1);
  EXPECT_EQ(raw.text("SELECT kind_name FROM requests"), "monument_c_alignment");
  EXPECT_EQ(raw.count("checks"), 1);
}

TEST_F(StorageRoundTrip, MeasurementSetComesBackExactlyWithEveryPoint) {
  const MeasurementSet set = make_measurement_set("r1");
  EXPECT_TRUE(db_.store(set));
  EXPECT_FALSE(db_.store(set));

  const auto loaded = db_.load_measurement_set("r1");
  ASSERT_TRUE(loaded.has_value());
  EXPECT_EQ(loaded->machine_id, set.machine_id);
  EXPECT_EQ(loaded->request_id, set.request_id);
  EXPECT_EQ(loaded->kind, set.kind);
  EXPECT_EQ(loaded->instrument, set.instrument);
  EXPECT_EQ(loaded->frame, set.frame);
  EXPECT_EQ(loaded->time_ns, set.time_ns);
  EXPECT_EQ(loaded->error, set.error);
  ASSERT_EQ(loaded->touches.size(), set.touches.size());
  for (std::size_t i = 0; i < set.touches.size(); ++i) {
    EXPECT_EQ(loaded->touches[i].feature, set.touches[i].feature);
    expect_axes_eq(loaded->touches[i].axes, set.touches[i].axes);
    EXPECT_EQ(loaded->touches[i].approach, set.touches[i].approach);
  }
  ASSERT_EQ(loaded->tracker_points.size(), set.tracker_points.size());
  for (std::size_t i = 0; i < set.tracker_points.size(); ++i) {
    EXPECT_EQ(loaded->tracker_points[i].label, set.tracker_points[i].label);
    expect_axes_eq(loaded->tracker_points[i].commanded, set.tracker_points[i].commanded);
    EXPECT_EQ(loaded->tracker_points[i].measured_mm, set.tracker_points[i].measured_mm);
  }

  const auto record = db_.find_check("r1");
  ASSERT_TRUE(record && record->measurement);
  EXPECT_EQ(record->measurement->instrument, "touch_probe");
  EXPECT_EQ(record->measurement->touches, 4);
  EXPECT_EQ(record->measurement->tracker_points, 3);
  EXPECT_EQ(record->measurement->error, "");

  RawDb raw(path_);
  EXPECT_EQ(raw.count("measurement_sets"), 1);
  EXPECT_EQ(raw.count("touches"), 4);
  EXPECT_EQ(raw.count("tracker_points"), 3);
  EXPECT_FALSE(db_.load_measurement_set("nope").has_value());
}

TEST_F(StorageRoundTrip, ParametersOfRequestAndMeasurementSetComeBackInOrder) {
  CheckRequest request = make_request("r1");
  request.kind = CheckKind::FixturePreCalibration;
  request.parameters = {{"fixture_configuration", 7, ""}, {"z_plane_mm", 304.8, "mm"}};
  request.verifies_correction_of = "precal-9";
  MeasurementSet set = make_measurement_set("r1");
  set.kind = CheckKind::FixturePreCalibration;
  set.parameters = {{"fixture_configuration", 7, ""}};
  ASSERT_TRUE(db_.store(request));
  ASSERT_TRUE(db_.store(set));

  const auto record = db_.find_check("r1");
  ASSERT_TRUE(record && record->request);
  ASSERT_EQ(record->request->parameters.size(), 2u);
  EXPECT_EQ(record->request->parameters[0].name, "fixture_configuration");
  EXPECT_EQ(record->request->parameters[0].value, 7);
  EXPECT_EQ(record->request->parameters[1].name, "z_plane_mm");
  EXPECT_EQ(record->request->parameters[1].value, 304.8);
  EXPECT_EQ(record->request->parameters[1].unit, "mm");
  EXPECT_EQ(record->request->verifies_correction_of, "precal-9");
  const auto loaded = db_.load_measurement_set("r1");
  ASSERT_TRUE(loaded.has_value());
  ASSERT_EQ(loaded->parameters.size(), 1u);
  EXPECT_EQ(loaded->parameters[0].name, "fixture_configuration");
  EXPECT_EQ(loaded->parameters[0].value, 7);

  RawDb raw(path_);
  EXPECT_EQ(raw.count("request_parameters"), 2);
  EXPECT_EQ(raw.count("measurement_parameters"), 1);
}

TEST_F(StorageRoundTrip, FailedMeasurementSetKeepsItsErrorAndNoPoints) {
  MeasurementSet set = make_measurement_set("r1");
  set.touches.clear();
  set.tracker_points.clear();
  set.error = "probe did not trigger within 5 mm";
  EXPECT_TRUE(db_.store(set));
  const auto loaded = db_.load_measurement_set("r1");
  ASSERT_TRUE(loaded.has_value());
  EXPECT_EQ(loaded->error, set.error);
  EXPECT_TRUE(loaded->touches.empty());
  EXPECT_TRUE(loaded->tracker_points.empty());
}

TEST_F(StorageRoundTrip, CheckResultComesBackWithMetricsCausesInOrderAndCorrection) {
  const CheckResult result = make_result("r1");
  EXPECT_TRUE(db_.store(result));
  EXPECT_FALSE(db_.store(result));

  const auto record = db_.find_check("r1");
  ASSERT_TRUE(record && record->result);
  expect_result_eq(*record->result, result);
  EXPECT_EQ(record->machine_id, "M1");
  EXPECT_EQ(record->kind, CheckKind::MonumentCAlignment);
  EXPECT_FALSE(record->request.has_value());  // a result may arrive before its request

  RawDb raw(path_);
  EXPECT_EQ(raw.count("results"), 1);
  EXPECT_EQ(raw.count("metrics"), 3);
  EXPECT_EQ(raw.count("causes"), 3);
  EXPECT_EQ(raw.count("result_offsets"), 2);
  EXPECT_EQ(db_.count_results(), 1);
}

// Whether a set and its result were measured or simulated comes back as it was sent; a sample that
// did not say (wire contract 1) comes back Unknown, never as measured.
TEST_F(StorageRoundTrip, TheOriginOfASetAndOfItsResultComesBack) {
  for (const DataOrigin origin :
       {DataOrigin::Measured, DataOrigin::Simulated, DataOrigin::Unknown}) {
    const std::string id = "r-" + std::string(to_string(origin));
    MeasurementSet set = make_measurement_set(id);
    set.origin = origin;
    CheckResult result = make_result(id);
    result.origin = origin;
    ASSERT_TRUE(db_.store(set));
    ASSERT_TRUE(db_.store(result));
    const auto record = db_.find_check(id);
    ASSERT_TRUE(record && record->measurement && record->result);
    EXPECT_EQ(record->measurement->origin, origin);
    expect_result_eq(*record->result, result);
    EXPECT_EQ(db_.load_measurement_set(id)->origin, origin);
    EXPECT_EQ(origin_of(*record), origin);
  }
  // A result that does not say (an older solver) takes its set's word.
  MeasurementSet set = make_measurement_set("r-mixed");
  set.origin = DataOrigin::Simulated;
  ASSERT_TRUE(db_.store(set));
  ASSERT_TRUE(db_.store(make_result("r-mixed")));
  EXPECT_EQ(origin_of(*db_.find_check("r-mixed")), DataOrigin::Simulated);
}

// A figure that could not be evaluated is kept (NULL in the file) and comes back as NaN; the
// result is never refused for it (issue 14: a NaN metric left an imported check pending forever).
TEST_F(StorageRoundTrip, AMetricThatCouldNotBeEvaluatedIsStoredAndComesBackNaN) {
  CheckResult result = make_result("r-nan");
  result.verdict = Verdict::Invalid;
  result.reason = "linear_A_mm could not be evaluated";
  result.metrics[0].value = std::nan("");
  result.metrics[1].value = std::numeric_limits<double>::infinity();
  ASSERT_TRUE(db_.store(result));
  const auto record = db_.find_check("r-nan");
  ASSERT_TRUE(record && record->result);
  ASSERT_EQ(record->result->metrics.size(), result.metrics.size());
  EXPECT_TRUE(std::isnan(record->result->metrics[0].value));
  EXPECT_TRUE(std::isnan(record->result->metrics[1].value));  // infinite is stored NULL too
  EXPECT_EQ(record->result->metrics[2].value, result.metrics[2].value);
  EXPECT_EQ(record->result->reason, result.reason);
  RawDb raw(path_);
  EXPECT_EQ(raw.count("metrics"), static_cast<std::int64_t>(result.metrics.size()));
}

TEST_F(StorageRoundTrip, CorrectionPresentWithoutOffsetsDiffersFromNoCorrection) {
  CheckResult with_empty = make_result("r1");
  with_empty.correction->offsets.clear();
  CheckResult without = make_result("r2");
  without.correction.reset();
  without.verdict = Verdict::Invalid;
  without.metrics.clear();
  without.likely_causes.clear();
  ASSERT_TRUE(db_.store(with_empty));
  ASSERT_TRUE(db_.store(without));

  const auto a = db_.find_check("r1");
  ASSERT_TRUE(a && a->result && a->result->correction);
  EXPECT_EQ(a->result->correction->target, "machine:work_offset");
  EXPECT_TRUE(a->result->correction->offsets.empty());
  const auto b = db_.find_check("r2");
  ASSERT_TRUE(b && b->result);
  expect_result_eq(*b->result, without);
}

TEST_F(StorageRoundTrip, ResendWithDifferentContentKeepsTheFirst) {
  const CheckResult first = make_result("r1");
  CheckResult second = first;
  second.verdict = Verdict::Pass;
  second.metrics.pop_back();
  ASSERT_TRUE(db_.store(first));
  EXPECT_FALSE(db_.store(second));
  const auto record = db_.find_check("r1");
  ASSERT_TRUE(record && record->result);
  expect_result_eq(*record->result, first);
  RawDb raw(path_);
  EXPECT_EQ(raw.count("metrics"), 3);
}

// With content hashes: the same content again is a duplicate; other content a conflict, kept
// once, and a resend of that conflicting content says it is no new conflict (nothing to raise).
TEST_F(StorageRoundTrip, AConflictIsKeptOnceAndItsResendIsNoNewConflict) {
  const CheckResult first = make_result("r1");
  CheckResult forged = first;
  forged.verdict = Verdict::Pass;
  const Origin a{"hash-a", "writer-1", 1};
  const Origin b{"hash-b", "writer-2", 2};
  EXPECT_EQ(db_.store(first, a).outcome, StoreOutcome::Stored);
  EXPECT_EQ(db_.store(first, a).outcome, StoreOutcome::Duplicate);
  const StoreResult conflict = db_.store(forged, b);
  EXPECT_EQ(conflict.outcome, StoreOutcome::Conflict);
  EXPECT_EQ(conflict.stored_hash, "hash-a");
  EXPECT_TRUE(conflict.new_conflict);
  const StoreResult again = db_.store(forged, b);
  EXPECT_EQ(again.outcome, StoreOutcome::Conflict);
  EXPECT_FALSE(again.new_conflict);
  EXPECT_EQ(db_.conflicts().size(), 1u);
  EXPECT_EQ(db_.find_check("r1")->result->verdict, first.verdict);
}

TEST_F(StorageRoundTrip, MachineStatusComesBackAndIsStoredOnce) {
  MachineStatus status;
  status.machine_id = "M1";
  status.request_id = "r1";
  status.state = MachineState::NeedsIntervention;
  status.last_kind = CheckKind::MonumentToolLength;
  status.last_verdict = Verdict::Fail;
  status.detail = "tool length off by 0.03 mm";
  status.time_ns = 5'000;
  EXPECT_TRUE(db_.store(status));
  EXPECT_FALSE(db_.store(status));

  // Same time and state but no request: a different status change.
  MachineStatus plain;
  plain.machine_id = "M1";
  plain.state = MachineState::Qualified;
  plain.time_ns = 4'000;
  EXPECT_TRUE(db_.store(plain));
  EXPECT_FALSE(db_.store(plain));

  const auto latest = db_.latest_status("M1");
  ASSERT_TRUE(latest.has_value());
  EXPECT_EQ(latest->machine_id, "M1");
  EXPECT_EQ(latest->request_id, "r1");
  EXPECT_EQ(latest->state, MachineState::NeedsIntervention);
  EXPECT_EQ(latest->last_kind, CheckKind::MonumentToolLength);
  EXPECT_EQ(latest->last_verdict, Verdict::Fail);
  EXPECT_EQ(latest->detail, status.detail);
  EXPECT_EQ(latest->time_ns, 5'000);

  RawDb raw(path_);
  EXPECT_EQ(raw.count("status_changes"), 2);
  EXPECT_FALSE(db_.latest_status("M2").has_value());
}

TEST_F(StorageRoundTrip, StatusWithoutLastKindOrVerdictComesBackEmpty) {
  MachineStatus status;
  status.machine_id = "M1";
  status.state = MachineState::Offline;
  status.time_ns = 7;
  ASSERT_TRUE(db_.store(status));
  const auto latest = db_.latest_status("M1");
  ASSERT_TRUE(latest.has_value());
  EXPECT_EQ(latest->state, MachineState::Offline);
  EXPECT_EQ(latest->request_id, "");
  EXPECT_FALSE(latest->last_kind.has_value());
  EXPECT_FALSE(latest->last_verdict.has_value());
}

TEST_F(StorageRoundTrip, InterventionComesBackNewestFirstAndIsStoredOnce) {
  Intervention older{"M1", "i1", CheckKind::FixturePreCalibration, "re-seated pogo 3", "bob", 10};
  Intervention newer{"M1", "i2", CheckKind::MonumentPositioning, "cleaned monument", "eve", 20};
  EXPECT_TRUE(db_.store(older));
  EXPECT_TRUE(db_.store(newer));
  EXPECT_FALSE(db_.store(older));

  const auto list = db_.interventions("M1");
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0].intervention_id, "i2");
  EXPECT_EQ(list[1].intervention_id, "i1");
  EXPECT_EQ(list[1].machine_id, "M1");
  EXPECT_EQ(list[1].kind, CheckKind::FixturePreCalibration);
  EXPECT_EQ(list[1].note, "re-seated pogo 3");
  EXPECT_EQ(list[1].operator_name, "bob");
  EXPECT_EQ(list[1].time_ns, 10);
  EXPECT_TRUE(db_.interventions("M2").empty());
}

TEST_F(StorageRoundTrip, CompensationComesBackAndIsStoredOncePerTarget) {
  Compensation compensation;
  compensation.machine_id = "M1";
  compensation.request_id = "r1";
  compensation.correction = Correction{
      "fixture:F1", {NamedValue{"dx_mm", 0.012, "mm"}, NamedValue{"dy_mm", -0.004, "mm"}}};
  compensation.time_ns = 9'000;
  EXPECT_TRUE(db_.store(compensation));
  EXPECT_FALSE(db_.store(compensation));
  Compensation other_target = compensation;
  other_target.correction.target = "fixture:F2";
  other_target.time_ns = 9'001;
  EXPECT_TRUE(db_.store(other_target));

  const auto list = db_.compensations("M1");
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0].correction.target, "fixture:F2");
  const Compensation& back = list[1];
  EXPECT_EQ(back.machine_id, "M1");
  EXPECT_EQ(back.request_id, "r1");
  EXPECT_EQ(back.time_ns, 9'000);
  EXPECT_EQ(back.correction.target, "fixture:F1");
  ASSERT_EQ(back.correction.offsets.size(), 2u);
  EXPECT_EQ(back.correction.offsets[1].name, "dy_mm");
  EXPECT_EQ(back.correction.offsets[1].value, -0.004);
  EXPECT_EQ(back.correction.offsets[1].unit, "mm");

  RawDb raw(path_);
  EXPECT_EQ(raw.count("compensations"), 2);
  EXPECT_EQ(raw.count("compensation_offsets"), 4);
}

TEST_F(StorageRoundTrip, HeartbeatUpsertsAndNeverGoesBackInTime) {
  Heartbeat start{"acquisition", "host-a:41", "M1", "starting", 100, "ok", "", 0, 0};
  EXPECT_TRUE(db_.store(start));
  EXPECT_FALSE(db_.store(start));
  Heartbeat running = start;
  running.state = "running";
  running.time_ns = 200;
  EXPECT_FALSE(db_.store(running));  // known instance: updated, not new
  EXPECT_FALSE(db_.store(start));    // stale: must not move the state back

  Heartbeat historian{"historian", "host-b:7", "", "running", 150, "ok", "", 0, 0};
  EXPECT_TRUE(db_.store(historian));

  const auto list = db_.services();
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0].service, "acquisition");
  EXPECT_EQ(list[0].instance, "host-a:41");
  EXPECT_EQ(list[0].machine_id, "M1");
  EXPECT_EQ(list[0].state, "running");
  EXPECT_EQ(list[0].time_ns, 200);
  EXPECT_EQ(list[1].service, "historian");
  EXPECT_EQ(list[1].machine_id, "");

  // The acquisition's machine is seen; a plant-wide service names no machine.
  EXPECT_EQ(db_.machines(), std::vector<std::string>{"M1"});
  RawDb raw(path_);
  EXPECT_EQ(raw.count("services"), 2);
}

TEST_F(StorageRoundTrip, EveryStoreRecordsTheMachineFirstAndLastSeen) {
  ASSERT_TRUE(db_.store(make_result("r1", "M2", 3'000)));
  ASSERT_TRUE(db_.store(make_request("r1", "M2", 1'000)));  // arrives late, is older
  ASSERT_TRUE(db_.store(make_measurement_set("r1", "M2", 2'000)));
  ASSERT_TRUE(db_.store(Intervention{"M3", "i1", CheckKind::RotaryA, "", "", 50}));
  MachineStatus status;
  status.machine_id = "M4";
  status.time_ns = 60;
  ASSERT_TRUE(db_.store(status));
  Compensation compensation{"M5", "r9", Correction{"machine:work_offset", {}}, 70};
  ASSERT_TRUE(db_.store(compensation));

  EXPECT_EQ(db_.machines(), (std::vector<std::string>{"M2", "M3", "M4", "M5"}));
  const auto m2 = db_.machine("M2");
  ASSERT_TRUE(m2.has_value());
  EXPECT_EQ(m2->first_seen_ns, 1'000);
  EXPECT_EQ(m2->last_seen_ns, 3'000);
  EXPECT_FALSE(db_.machine("M9").has_value());
}

TEST_F(StorageRoundTrip, StringsKeepEmbeddedNulAndUnicode) {
  CheckRequest request = make_request("r-ü-1");
  request.requested_by = std::string("operator:a\0b", 12);
  ASSERT_TRUE(db_.store(request));
  const auto record = db_.find_check("r-ü-1");
  ASSERT_TRUE(record && record->request);
  EXPECT_EQ(record->request->requested_by, request.requested_by);
}

}  // namespace
}  // namespace ncqual::storage

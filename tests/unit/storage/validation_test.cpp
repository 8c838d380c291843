// SPDX-License-Identifier: Apache-2.0
// Bad input is refused with a message naming the field and the value, and nothing of the sample
// is written, neither when validation refuses it nor when SQLite fails half way through.
#include "storage_test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>

namespace ncqual::storage {
namespace {

using namespace testing;  // storage_test_support.hpp

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

class StorageValidation : public ::testing::Test {
 protected:
  // Runs `store`, expects a StorageError for bad input (sqlite_code 0) whose message contains
  // `expected`, and checks that nothing at all was written.
  void expect_refused(const std::function<void()>& store, const std::string& expected) {
    try {
      store();
      ADD_FAILURE() << "no StorageError, expected one containing: " << expected;
    } catch (const StorageError& error) {
      EXPECT_NE(std::string(error.what()).find(expected), std::string::npos)
          << "message: " << error.what() << "\nexpected to contain: " << expected;
      EXPECT_EQ(error.sqlite_code(), 0) << error.what();
    }
    expect_empty();
  }

  void expect_empty() {
    RawDb raw(path_);
    for (const char* table :
         {"machines", "requests", "measurement_sets", "touches", "tracker_points", "results",
          "metrics", "causes", "result_offsets", "checks", "status_changes", "interventions",
          "compensations", "compensation_offsets", "services"}) {
      EXPECT_EQ(raw.count(table), 0) << table;
    }
  }

  TempDir dir_;
  std::string path_ = dir_.file("historian.db");
  Database db_ = Database::open(path_);
};

// A metric's value may be NaN (kept as NULL: StorageRoundTrip.AMetricThatCouldNotBeEvaluated...);
// its band may not.
TEST_F(StorageValidation, BadValueLateInTheSampleWritesNothingBeforeIt) {
  CheckResult result = make_result("r1");
  result.metrics[1].upper = kNaN;
  expect_refused([&] { db_.store(result); }, "Metric.upper of 'center_dy_mm' is NaN");
  result = make_result("r1");
  result.correction->offsets[1].value = kNaN;
  expect_refused([&] { db_.store(result); }, "NamedValue.value of 'dc_rad' is NaN");
}

TEST_F(StorageValidation, NaNRequestParameterIsRefusedNamingIt) {
  CheckRequest request = make_request("r1");
  request.parameters = {{"fixture_configuration", kNaN, ""}};
  expect_refused([&] { db_.store(request); },
                 "CheckRequest.parameters[0].value ('fixture_configuration') is NaN");
}

TEST_F(StorageValidation, EmptyIdentitiesAreRefused) {
  CheckResult result = make_result("");
  expect_refused([&] { db_.store(result); }, "CheckResult.request_id is empty");
  result = make_result("r1", "");
  expect_refused([&] { db_.store(result); }, "CheckResult.machine_id is empty");
  expect_refused([&] { db_.store(make_request("")); }, "CheckRequest.request_id is empty");
  expect_refused([&] { db_.store(make_measurement_set("r1", "")); },
                 "MeasurementSet.machine_id is empty");
  expect_refused([&] { db_.store(MachineStatus{}); }, "MachineStatus.machine_id is empty");
  expect_refused(
      [&] {
        db_.store(Intervention{"M1", "", CheckKind::RotaryC, "", "", 0});
      },
      "Intervention.intervention_id is empty");
  expect_refused(
      [&] {
        db_.store(Compensation{"M1", "r1", Correction{}, 0});
      },
      "Compensation.correction.target is empty (Compensation 'r1')");
  expect_refused(
      [&] {
        db_.store(Heartbeat{"", "host:1", "", "running", 0, "ok", "", 0, 0});
      },
      "Heartbeat.service is empty");
  expect_refused(
      [&] {
        db_.store(Heartbeat{"solver", "", "", "running", 0, "ok", "", 0, 0});
      },
      "Heartbeat.instance is empty");
}

TEST_F(StorageValidation, OutOfRangeEnumsAreRefusedWithTheirValue) {
  CheckRequest request = make_request("r1");
  request.kind = static_cast<CheckKind>(42);
  expect_refused([&] { db_.store(request); }, "CheckRequest.kind is 42, not a check kind");
  CheckResult result = make_result("r1");
  result.verdict = static_cast<Verdict>(7);
  expect_refused([&] { db_.store(result); }, "CheckResult.verdict is 7, not a verdict");
  MachineStatus status;
  status.machine_id = "M1";
  status.state = static_cast<MachineState>(-1);
  expect_refused([&] { db_.store(status); }, "MachineStatus.state is -1, not a machine state");
  status.state = MachineState::Qualified;
  status.last_kind = static_cast<CheckKind>(kCheckKindCount);
  expect_refused([&] { db_.store(status); }, "MachineStatus.last_kind is 16, not a check kind");
}

TEST_F(StorageValidation, NonFiniteMeasurementsAreRefusedNamingThePoint) {
  MeasurementSet set = make_measurement_set("r1");
  set.touches[3].axes.c_rad = kNaN;
  expect_refused([&] { db_.store(set); },
                 "Touch.axes.c_rad of touch 3 'face' is NaN (MeasurementSet 'r1')");
  set = make_measurement_set("r1");
  set.tracker_points[2].measured_mm.y() = kInf;
  expect_refused([&] { db_.store(set); },
                 "TrackerPoint.measured_mm.y of tracker point 2 'P2' is inf");
}

TEST_F(StorageValidation, EmptyNamesInsideASampleAreRefused) {
  CheckResult result = make_result("r1");
  result.metrics[1].name.clear();
  expect_refused([&] { db_.store(result); }, "Metric.name of metric 1 is empty");
  result = make_result("r1");
  result.likely_causes[2].clear();
  expect_refused([&] { db_.store(result); }, "CheckResult.likely_causes[2] is empty");
}

TEST_F(StorageValidation, PartsOfOneCheckMustAgreeOnMachineAndKind) {
  ASSERT_TRUE(db_.store(make_request("r1", "M1")));
  try {
    db_.store(make_result("r1", "M2"));
    FAIL() << "expected a StorageError";
  } catch (const StorageError& error) {
    EXPECT_NE(std::string(error.what()).find("CheckResult.machine_id 'M2' differs from 'M1'"),
              std::string::npos)
        << error.what();
  }
  MeasurementSet set = make_measurement_set("r1");
  set.kind = CheckKind::GlobalGrid;
  EXPECT_THROW(db_.store(set), StorageError);

  RawDb raw(path_);
  EXPECT_EQ(raw.count("results"), 0);
  EXPECT_EQ(raw.count("metrics"), 0);
  EXPECT_EQ(raw.count("measurement_sets"), 0);
  EXPECT_EQ(raw.count("touches"), 0);
  EXPECT_EQ(raw.count("checks"), 1);
}

// SQLite fails after the result row and two metrics are written: the whole sample must go, and
// the same sample must store cleanly once the cause is gone.
TEST_F(StorageValidation, SqliteFailureHalfWayRollsBackTheWholeSample) {
  {
    RawDb raw(path_);
    raw.exec(
        "CREATE TRIGGER fail_third_metric BEFORE INSERT ON metrics WHEN NEW.idx = 2 "
        "BEGIN SELECT RAISE(ABORT, 'disk on fire'); END");
  }
  const CheckResult result = make_result("r1");
  try {
    db_.store(result);
    FAIL() << "expected a StorageError";
  } catch (const StorageError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("store CheckResult 'r1'"), std::string::npos) << message;
    EXPECT_NE(message.find("insert metric"), std::string::npos) << message;
    EXPECT_NE(message.find("disk on fire"), std::string::npos) << message;
    EXPECT_NE(error.sqlite_code(), 0);
  }
  {
    RawDb raw(path_);
    EXPECT_EQ(raw.count("results"), 0);
    EXPECT_EQ(raw.count("metrics"), 0);
    EXPECT_EQ(raw.count("checks"), 0);
    EXPECT_EQ(raw.count("machines"), 0);
    raw.exec("DROP TRIGGER fail_third_metric");
  }
  EXPECT_TRUE(db_.store(result));
  EXPECT_EQ(db_.count_results(), 1);
}

TEST_F(StorageValidation, InfiniteToleranceBoundIsAOneSidedBandAndAccepted) {
  CheckResult result = make_result("r1");
  result.metrics[0].upper = kInf;
  ASSERT_TRUE(db_.store(result));
  const auto record = db_.find_check("r1");
  ASSERT_TRUE(record && record->result);
  EXPECT_EQ(record->result->metrics[0].upper, kInf);
  EXPECT_EQ(record->result->metrics[2].lower, -kInf);
}

}  // namespace
}  // namespace ncqual::storage

// SPDX-License-Identifier: Apache-2.0
// What the historian does with each sample (services/historian/core/include/ncqual/historian/
// store.hpp, file_guard.hpp) on real SQLite files: stored, the same again a duplicate, other
// content under a stored id a conflict kept beside it and raised once, an unreadable or invalid
// sample refused with its reason, and a database fault rethrown so that the sample waits in the
// ingest unacknowledged; the file removed or moved away while open holds every attempt and is
// rescued once.
#include "ncqual/historian/file_guard.hpp"
#include "ncqual/historian/ingest.hpp"
#include "ncqual/historian/store.hpp"

#include "storage_test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace ncqual::historian {
namespace {

using storage::testing::make_measurement_set;
using storage::testing::make_request;
using storage::testing::make_result;
using storage::testing::RawDb;
using storage::testing::TempDir;
using namespace std::chrono_literals;

const SampleKind kRequest{"request", nullptr, "ncqual/CheckRequest"};
const SampleKind kSet{"measurement set", "measurements", "ncqual/MeasurementSet"};
const SampleKind kResult{"result", "results", "ncqual/CheckResult"};

std::string named(const std::string& guid) { return "writer " + guid; }

Arrival from(const std::string& hash, const std::string& writer) {
  return {"", hash, writer, "in partition 'ncqual/machine/M1'"};
}

class HistorianStore : public ::testing::Test {
 protected:
  template <typename Model>
  Outcome store(const SampleKind& kind, const Model& value, const Arrival& in) {
    return store_sample(db_, kind, value, in, 1000, true, named);
  }
  TempDir dir_;
  std::string path_ = dir_.file("historian.db");
  storage::Database db_ = storage::Database::open(path_);
};

TEST_F(HistorianStore, StoredOnceThenADuplicateThenAConflictRaisedOnlyOnce) {
  const CheckRequest request = make_request("R1");
  const Outcome first = store(kRequest, request, from("hash-a", "guid-1"));
  EXPECT_EQ(first.ack, AckOutcome::Stored);
  EXPECT_TRUE(first.newly_stored);
  EXPECT_FALSE(first.alarm);
  EXPECT_EQ(first.ack_detail, "");

  const Outcome again = store(kRequest, request, from("hash-a", "guid-1"));
  EXPECT_EQ(again.ack, AckOutcome::Duplicate);
  EXPECT_FALSE(again.newly_stored) << "the trend watch does not run twice for one sample";
  EXPECT_FALSE(again.alarm);

  CheckRequest other = request;
  other.requested_by = "operator:bob";
  const Outcome conflict = store(kRequest, other, from("hash-b", "guid-2"));
  EXPECT_EQ(conflict.ack, AckOutcome::Conflict);
  EXPECT_EQ(conflict.ack_detail, "stored first with content hash-a");
  EXPECT_FALSE(conflict.newly_stored);
  ASSERT_TRUE(conflict.alarm);
  EXPECT_EQ(conflict.alarm->kind, AlarmKind::Conflict);
  EXPECT_TRUE(conflict.alarm->active);
  EXPECT_EQ(conflict.alarm->machine_id, "M1");
  EXPECT_EQ(conflict.alarm->alarm_id, "conflict/ncqual/CheckRequest/R1/hash-b");
  EXPECT_EQ(conflict.alarm->text,
            "request R1 of machine 'M1' from writer guid-2 differs from the one stored from "
            "writer guid-1 (content hash-a stored first, hash-b kept beside it); both kept, the "
            "stored one unchanged");

  // Sent again (its acknowledgement was lost): answered CONFLICT, not raised again.
  const Outcome resent = store(kRequest, other, from("hash-b", "guid-2"));
  EXPECT_EQ(resent.ack, AckOutcome::Conflict);
  EXPECT_FALSE(resent.alarm);
  RawDb raw(path_);
  EXPECT_EQ(raw.count("requests"), 1) << "the stored one unchanged";
}

// The scheduler holds a machine for a conflict of a check's measurements or results; the text
// opens with what Scheduler::conflict names.
TEST_F(HistorianStore, AConflictOfACheckPartNamesBothWritersTheWayTheSchedulerHoldsFor) {
  store(kSet, make_measurement_set("R2"), from("aaaaaaaaaaaa1111", "guid-1"));
  MeasurementSet other = make_measurement_set("R2");
  other.touches[0].axes.x_mm += 0.001;
  const Outcome conflict = store(kSet, other, from("bbbbbbbbbbbb2222", "guid-2"));
  ASSERT_TRUE(conflict.alarm);
  EXPECT_EQ(conflict.alarm->text,
            "conflicting measurements of R2 of machine 'M1' from writer guid-1 and writer guid-2 "
            "(content aaaaaaaaaaaa stored first, bbbbbbbbbbbb kept beside it); both kept, the "
            "stored one unchanged");
}

TEST_F(HistorianStore, AnUnreadableSampleIsRefusedWithTheReadersReasonAndNotStored) {
  Arrival bad = from("h", "guid-1");
  bad.error = "touches[1].axes.x is NaN";
  const Outcome out = store(kSet, make_measurement_set("R3"), bad);
  EXPECT_EQ(out.ack, AckOutcome::Refused);
  EXPECT_EQ(out.ack_detail, "touches[1].axes.x is NaN");
  EXPECT_FALSE(out.newly_stored);
  RawDb raw(path_);
  EXPECT_EQ(raw.count("measurement_sets"), 0);
}

TEST_F(HistorianStore, ASampleValidationRefusesIsRefusedForGoodWithTheStoragesReason) {
  CheckResult result = make_result("R4");
  result.metrics[1].upper = std::nan("");
  const Outcome out = store(kResult, result, from("h", "guid-1"));
  EXPECT_EQ(out.ack, AckOutcome::Refused);
  EXPECT_NE(out.ack_detail.find("Metric.upper of 'center_dy_mm' is NaN"), std::string::npos)
      << out.ack_detail;
}

// A write lock held by another connection: the store throws (SQLite's code), the ingest keeps
// the sample unacknowledged, and it is stored and acknowledged once the lock is gone.
TEST_F(HistorianStore, ADatabaseFaultLeavesTheSampleUnacknowledgedUntilItIsStored) {
  db_.set_busy_timeout(20ms);
  std::vector<AckOutcome> acknowledged;
  Ingest ingest(IngestOptions{}, [](storage::StorageHealth, const std::string&) {});
  const auto receive = [&](const CheckRequest& r, Steady now) {
    ingest.submit(
        1,
        [&, r] {
          acknowledged.push_back(store(kRequest, r, from("hash-" + r.request_id, "g")).ack);
        },
        now);
  };
  RawDb other(path_);
  other.exec("BEGIN EXCLUSIVE");
  bool threw = false;
  try {
    store(kRequest, make_request("R5"), from("hash-R5", "g"));
  } catch (const storage::StorageError& e) {
    threw = e.sqlite_code() != 0;
  }
  EXPECT_TRUE(threw) << "a database fault is not a refusal";
  const Steady t{};
  receive(make_request("R5"), t);
  EXPECT_TRUE(acknowledged.empty());
  EXPECT_EQ(ingest.backlog(), 1u);
  other.exec("COMMIT");
  ingest.retry(t + 1h);
  EXPECT_EQ(acknowledged, (std::vector<AckOutcome>{AckOutcome::Stored}));
  EXPECT_EQ(ingest.backlog(), 0u);
}

TEST_F(HistorianStore, TheStorageAlarmIsRaisedWithItsDetailAndClearedNamingTheFile) {
  const Alarm raised =
      storage_alarm(storage::StorageHealth::Failed, "disk full", "/var/h.db", "hist-1");
  EXPECT_EQ(raised.alarm_id, "storage/hist-1");
  EXPECT_EQ(raised.kind, AlarmKind::Storage);
  EXPECT_TRUE(raised.active);
  EXPECT_EQ(raised.text, "failed: disk full");
  const Alarm cleared = storage_alarm(storage::StorageHealth::Ok, "", "/var/h.db", "hist-1");
  EXPECT_FALSE(cleared.active);
  EXPECT_EQ(cleared.text, "/var/h.db stores and acknowledges again");
}

TEST_F(HistorianStore, HeartbeatsAreStoredOnlyWhileNothingWaits) {
  Ingest ingest(IngestOptions{}, [](storage::StorageHealth, const std::string&) {});
  Heartbeat beat;
  beat.service = "solver";
  beat.instance = "solver-1";
  beat.state = "running";
  beat.time_ns = 5;
  store_heartbeat(db_, ingest, beat, "");
  RawDb raw(path_);
  EXPECT_EQ(raw.count("services"), 1);
  beat.instance = "solver-2";
  store_heartbeat(db_, ingest, beat, "bad CDR");
  EXPECT_EQ(raw.count("services"), 1) << "an unreadable heartbeat is ignored";

  // A sample waits (the database was locked when it came): the heartbeat is skipped even once the
  // lock is gone, so that it never goes ahead of what waits.
  db_.set_busy_timeout(20ms);
  raw.exec("BEGIN EXCLUSIVE");
  ingest.submit(
      1, [&] { db_.store(make_request("R6")); }, Steady{});
  raw.exec("COMMIT");
  ASSERT_EQ(ingest.backlog(), 1u);
  store_heartbeat(db_, ingest, beat, "");
  EXPECT_EQ(raw.count("services"), 1);
  ingest.retry(Steady{} + 1h);
  store_heartbeat(db_, ingest, beat, "");
  EXPECT_EQ(raw.count("services"), 2);
}

// 2026-11-28T07:15:00.5Z, worked by hand: 20,785 days after 1970-01-01, plus 26,100.5 s.
TEST(FileGuard, TheRescuedCopyIsNamedForTheUtcTimeWithoutColons) {
  const std::int64_t t = (20785LL * 86400 + 7 * 3600 + 15 * 60) * 1'000'000'000LL + 500'000'000;
  EXPECT_EQ(rescue_name("/var/h.db", t), "/var/h.db.rescued-2026-11-28T071500.500Z");
}

TEST(FileGuard, AFileMovedAwayHoldsEveryAttemptIsRescuedOnceAndIsReleasedWhenBack) {
  TempDir dir;
  const std::string path = dir.file("h.db");
  auto db = storage::Database::open(path);
  db.store(make_request("R1"));
  FileGuard guard(db, path);
  EXPECT_EQ(guard.check(0), "");

  std::filesystem::rename(path, dir.file("moved.db"));
  const std::string held = guard.check(1'000'000'000);
  EXPECT_NE(held.find("nothing is stored or acknowledged until it is back"), std::string::npos)
      << held;
  const std::string copy = guard.rescued_to();
  ASSERT_FALSE(copy.empty());
  EXPECT_EQ(copy, rescue_name(path, 1'000'000'000));
  {
    RawDb raw(copy);
    EXPECT_EQ(raw.count("requests"), 1) << "the copy holds what was stored";
  }
  EXPECT_NE(guard.check(2'000'000'000), "");
  EXPECT_EQ(guard.rescued_to(), copy) << "one copy per fault";
  EXPECT_FALSE(std::filesystem::exists(rescue_name(path, 2'000'000'000)));

  std::filesystem::rename(dir.file("moved.db"), path);
  EXPECT_EQ(guard.check(3'000'000'000), "");
  EXPECT_EQ(guard.rescued_to(), "");
}

}  // namespace
}  // namespace ncqual::historian

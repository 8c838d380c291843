// SPDX-License-Identifier: Apache-2.0
// Retention: Database::thin_points deletes the raw points of old measurement sets, in short
// transactions, and keeps everything else; a dry run changes nothing; a thinned set says so.
#include "storage_test_support.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

namespace ncqual::storage {
namespace {

using namespace testing;  // storage_test_support.hpp

constexpr std::int64_t kSecond = 1'000'000'000;

// The whole historian as text, but for the tables and columns thinning may change: what must
// stay exactly as it was.
std::string everything_but_points(RawDb& raw) {
  std::string all;
  for (const char* sql :
       {"SELECT group_concat(request_id || kind || requested_by || time_ns, ';') FROM requests",
        "SELECT group_concat(request_id || name || value, ';') FROM request_parameters",
        "SELECT group_concat(request_id || machine_id || instrument || frame || time_ns || error "
        "|| "
        "coalesce(content_hash, '-'), ';') FROM measurement_sets",
        "SELECT group_concat(request_id || name || value, ';') FROM measurement_parameters",
        "SELECT group_concat(request_id || verdict || reason || time_ns, ';') FROM results",
        "SELECT group_concat(request_id || idx || name || coalesce(value, 'NULL') || lower || "
        "upper, "
        "';') FROM metrics",
        "SELECT group_concat(request_id || rank || cause, ';') FROM causes",
        "SELECT group_concat(request_id || name || value, ';') FROM result_offsets",
        "SELECT group_concat(request_id || coalesce(requested_at_ns, '') || "
        "coalesce(measured_at_ns, '') || coalesce(result_at_ns, ''), ';') FROM checks",
        "SELECT group_concat(machine_id || state || time_ns, ';') FROM status_changes",
        "SELECT group_concat(request_id || target || time_ns, ';') FROM compensations",
        "SELECT group_concat(compensation_id || name || value, ';') FROM compensation_offsets",
        "SELECT group_concat(machine_id || first_seen_ns || last_seen_ns, ';') FROM machines"}) {
    all += raw.text(sql) + "\n";
  }
  return all;
}

class Retention : public ::testing::Test {
 protected:
  // Sets at 10 s, 20 s, ..., 100 s (r1..r10) on two machines, each with 4 touches and 3 tracker
  // points, a request, a result with a correction and a compensation; r0 at 5 s has no points (an
  // instrument error).
  void SetUp() override {
    path_ = dir_.file("historian.db");
    Database db = Database::open(path_);
    for (int i = 1; i <= 10; ++i) {
      const std::string id = "r" + std::to_string(i);
      const std::string machine = i % 2 ? "M1" : "M2";
      const std::int64_t t = i * 10 * kSecond;
      db.store(make_request(id, machine, t - 1));
      MeasurementSet set = make_measurement_set(id, machine, t);
      set.parameters = {{"fixture_configuration", 3, ""}};
      db.store(set, {"hash-" + id, "writer", t});
      db.store(make_result(id, machine, t + 1));
      Compensation c;
      c.machine_id = machine;
      c.request_id = id;
      c.time_ns = t + 2;
      c.correction = *make_result(id).correction;
      db.store(c);
      MachineStatus status;
      status.machine_id = machine;
      status.request_id = id;
      status.state = MachineState::Qualified;
      status.time_ns = t + 3;
      db.store(status);
    }
    MeasurementSet failed = make_measurement_set("r0", "M1", 5 * kSecond);
    failed.touches.clear();
    failed.tracker_points.clear();
    failed.error = "probe did not trigger";
    db.store(failed);
  }

  TempDir dir_;
  std::string path_;
};

TEST_F(Retention, ThinningDeletesOnlyTheOldPointsAndMarksTheirSets) {
  std::string kept_before;
  {
    RawDb raw(path_);
    kept_before = everything_but_points(raw);
    ASSERT_EQ(raw.count("touches"), 40);
    ASSERT_EQ(raw.count("tracker_points"), 30);
  }
  Database db = Database::open(path_);
  const auto r3_before = db.find_check("r3");
  ASSERT_TRUE(r3_before && r3_before->result);

  // A dry run counts what a run would do, and changes nothing.
  const ThinReport dry = db.thin_points(55 * kSecond, {true});
  EXPECT_TRUE(dry.dry_run);
  EXPECT_EQ(dry.sets, 5);  // r1..r5; r0 has no points
  EXPECT_EQ(dry.touches, 20);
  EXPECT_EQ(dry.tracker_points, 15);
  EXPECT_EQ(dry.oldest_ns, 10 * kSecond);
  EXPECT_EQ(dry.newest_ns, 50 * kSecond);
  EXPECT_EQ(dry.transactions, 0);
  {
    RawDb raw(path_);
    EXPECT_EQ(raw.count("touches"), 40);
    EXPECT_EQ(raw.count("measurement_sets", "points_thinned_ns IS NOT NULL"), 0);
  }

  // Two sets per transaction: r0 (no points, passed over) and r1..r5 take three, and a fourth
  // finds nothing more.
  ThinOptions options;
  options.now_ns = 1'000 * kSecond;
  options.sets_per_transaction = 2;
  options.pause = std::chrono::milliseconds(0);
  const ThinReport done = db.thin_points(55 * kSecond, options);
  EXPECT_FALSE(done.dry_run);
  EXPECT_EQ(done.sets, dry.sets);
  EXPECT_EQ(done.touches, dry.touches);
  EXPECT_EQ(done.tracker_points, dry.tracker_points);
  EXPECT_EQ(done.oldest_ns, dry.oldest_ns);
  EXPECT_EQ(done.newest_ns, dry.newest_ns);
  EXPECT_EQ(done.transactions, 4);

  {
    RawDb raw(path_);
    EXPECT_EQ(raw.count("touches"), 20);
    EXPECT_EQ(raw.count("tracker_points"), 15);
    EXPECT_EQ(raw.count("touches", "request_id IN ('r1','r2','r3','r4','r5')"), 0);
    EXPECT_EQ(raw.count("measurement_sets", "points_thinned_ns = 1000000000000"), 5);
    EXPECT_EQ(raw.count("measurement_sets", "thinned_touches = 4 AND thinned_tracker_points = 3"),
              5);
    EXPECT_EQ(raw.count("measurement_sets", "request_id = 'r0' AND points_thinned_ns IS NULL"), 1);
    EXPECT_EQ(everything_but_points(raw), kept_before) << "thinning changed what it must keep";
    EXPECT_EQ(raw.text("PRAGMA foreign_key_check"), "");
  }

  // A thinned check still reads whole: its result as judged, its set with the counts measured and
  // the date its points went; the set comes back without points.
  const auto r3 = db.find_check("r3");
  ASSERT_TRUE(r3 && r3->measurement && r3->result);
  expect_result_eq(*r3->result, *r3_before->result);
  EXPECT_EQ(r3->measurement->touches, 4);
  EXPECT_EQ(r3->measurement->tracker_points, 3);
  EXPECT_EQ(r3->measurement->points_thinned_ns, 1'000 * kSecond);
  const auto set = db.load_measurement_set("r3");
  ASSERT_TRUE(set);
  EXPECT_TRUE(set->touches.empty());
  EXPECT_TRUE(set->tracker_points.empty());
  ASSERT_EQ(set->parameters.size(), 1u);
  const auto r6 = db.find_check("r6");
  ASSERT_TRUE(r6 && r6->measurement);
  EXPECT_FALSE(r6->measurement->points_thinned_ns);
  EXPECT_EQ(db.load_measurement_set("r6")->touches.size(), 4u);

  // The same set sent again is a duplicate: its points do not come back.
  MeasurementSet again = make_measurement_set("r3", "M1", 30 * kSecond);
  EXPECT_EQ(db.store(again, {"hash-r3", "writer", 0}).outcome, StoreOutcome::Duplicate);
  EXPECT_TRUE(db.load_measurement_set("r3")->touches.empty());

  // Idempotent: nothing left before that time.
  const ThinReport second = db.thin_points(55 * kSecond, options);
  EXPECT_EQ(second.sets, 0);
  EXPECT_EQ(second.touches + second.tracker_points, 0);
  EXPECT_FALSE(second.oldest_ns);
  EXPECT_EQ(db.thin_points(55 * kSecond, {true}).sets, 0);
  EXPECT_EQ(db.integrity_check(), "ok");
}

// A transaction stops taking sets once it holds points_per_transaction points, never splitting a
// set: with 7 points per set and a limit of 10, each transaction thins two sets.
TEST_F(Retention, ATransactionHoldsABoundedNumberOfPoints) {
  Database db = Database::open(path_);
  ThinOptions options;
  options.points_per_transaction = 10;
  options.pause = std::chrono::milliseconds(0);
  const ThinReport report = db.thin_points(1'000 * kSecond, options);
  EXPECT_EQ(report.sets, 10);
  EXPECT_EQ(report.touches, 40);
  EXPECT_EQ(report.tracker_points, 30);
  EXPECT_EQ(report.transactions, 5);  // r1 r2, r3 r4, r5 r6, r7 r8, r9 r10 (the last)
  RawDb raw(path_);
  EXPECT_EQ(raw.count("touches") + raw.count("tracker_points"), 0);
}

TEST_F(Retention, AReadOnlyConnectionRefusesToThin) {
  Database reader = Database::open_readonly(path_);
  EXPECT_EQ(reader.thin_points(1'000 * kSecond, {true}).sets, 10);  // counting is reading
  EXPECT_THROW(reader.thin_points(1'000 * kSecond), StorageError);
  EXPECT_EQ(RawDb(path_).count("touches"), 40);
}

// The historian keeps storing while another connection thins: every store succeeds, and the new
// sets (after the cut) keep their points.
TEST_F(Retention, AWriterKeepsStoringWhileThinningRuns) {
  std::atomic<bool> stop{false};
  std::atomic<int> stored{0};
  std::thread writer([&] {
    Database db = Database::open(path_);
    for (int i = 0; !stop || i < 20; ++i) {
      const std::string id = "new-" + std::to_string(i);
      db.store(make_measurement_set(id, "M1", (2'000 + i) * kSecond));
      db.store(make_result(id, "M1", (2'000 + i) * kSecond + 1));
      ++stored;
    }
  });
  Database db = Database::open(path_);
  ThinOptions options;
  options.sets_per_transaction = 1;
  const ThinReport report = db.thin_points(1'000 * kSecond, options);
  stop = true;
  writer.join();
  EXPECT_EQ(report.sets, 10);
  RawDb raw(path_);
  EXPECT_EQ(raw.count("measurement_sets", "request_id LIKE 'new-%'"), stored.load());
  EXPECT_EQ(raw.count("touches"), 4 * stored.load());
  EXPECT_EQ(raw.count("measurement_sets", "points_thinned_ns IS NOT NULL"), 10);
}

}  // namespace
}  // namespace ncqual::storage

// SPDX-License-Identifier: Apache-2.0
// A metric's history, its restarts and the trend warnings the historian keeps
// (ncqual/storage/trend.hpp), on real SQLite files; and the query plans of those reads: every
// one walks an index, none scans a table.
#include "storage_test_support.hpp"

#include "ncqual/storage/trend.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace ncqual::storage {
namespace {

using namespace testing;  // storage_test_support.hpp

constexpr std::int64_t kDay = 86'400'000'000'000;

// A result of `kind` on `machine` at day `day` with center_dy_mm = value (and two more metrics).
CheckResult result_at(const std::string& id, const std::string& machine, CheckKind kind, int day,
                      double value) {
  CheckResult r = make_result(id, machine, day * kDay);
  r.kind = kind;
  r.verdict = std::abs(value) <= 0.01 ? Verdict::Pass : Verdict::Fail;
  r.metrics[1].value = value;
  r.metrics[1].pass = r.verdict == Verdict::Pass;
  r.correction.reset();
  return r;
}

class TrendStore : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = dir_.file("historian.db");
    Database db = Database::open(path_);
    // M1: monument_positioning on days 1..10 with center_dy_mm = day/1000 (day 4 NaN), and the
    // same metric from monument_c_alignment on days 2 and 12; M2: days 1..3.
    for (int day = 1; day <= 10; ++day) {
      db.store(result_at("p" + std::to_string(day), "M1", CheckKind::MonumentPositioning, day,
                         day == 4 ? std::nan("") : day / 1000.0));
    }
    db.store(result_at("c2", "M1", CheckKind::MonumentCAlignment, 2, 0.5));
    db.store(result_at("c12", "M1", CheckKind::MonumentCAlignment, 12, 0.7));
    for (int day = 1; day <= 3; ++day) {
      db.store(result_at("q" + std::to_string(day), "M2", CheckKind::MonumentPositioning, day,
                         -day / 1000.0));
    }
    Intervention i;
    i.machine_id = "M1";
    i.intervention_id = "i1";
    i.note = "stylus replaced";
    i.operator_name = "ann";
    i.time_ns = 5 * kDay + 1;
    db.store(i);
    Compensation c;
    c.machine_id = "M1";
    c.request_id = "p7";
    c.time_ns = 7 * kDay + 2;
    c.correction = Correction{"machine:work_offset", {NamedValue{"dy_mm", -0.007, "mm"}}};
    db.store(c);
    Compensation same_time = c;  // another target at the same time: one restart
    same_time.correction.target = "fixture:zero_offset";
    db.store(same_time);
  }

  TempDir dir_;
  std::string path_;
};

TEST_F(TrendStore, ASeriesIsEveryCheckOfTheMetricOldestFirstAcrossKinds) {
  Database db = Database::open_readonly(path_);
  const auto all = metric_series(db, {"M1", "center_dy_mm"});
  ASSERT_EQ(all.size(), 12u);
  EXPECT_EQ(all.front().request_id, "p1");
  EXPECT_EQ(all[1].request_id, "c2");  // day 2: c2 before p2 (same time, by request id)
  EXPECT_EQ(all[1].kind, CheckKind::MonumentCAlignment);
  EXPECT_EQ(all[2].request_id, "p2");
  EXPECT_EQ(all[2].kind, CheckKind::MonumentPositioning);
  EXPECT_EQ(all.back().request_id, "c12");
  for (std::size_t i = 1; i < all.size(); ++i) EXPECT_LE(all[i - 1].time_ns, all[i].time_ns);
  const MetricValue& nan = all[4];
  EXPECT_EQ(nan.request_id, "p4");
  EXPECT_TRUE(std::isnan(nan.value)) << "a metric stored NULL reads back NaN";
  EXPECT_DOUBLE_EQ(all[3].value, 0.003);
  EXPECT_EQ(all[3].unit, "mm");
  EXPECT_DOUBLE_EQ(all[3].lower, -0.01);
  EXPECT_DOUBLE_EQ(all[3].upper, 0.01);
  EXPECT_EQ(all[3].verdict, Verdict::Pass);

  MetricQuery range{"M1", "center_dy_mm", 3 * kDay, 6 * kDay};
  const auto some = metric_series(db, range);
  ASSERT_EQ(some.size(), 4u);
  EXPECT_EQ(some.front().request_id, "p3");
  EXPECT_EQ(some.back().request_id, "p6");
  range.last = 2;
  const auto last = metric_series(db, range);
  ASSERT_EQ(last.size(), 2u);
  EXPECT_EQ(last[0].request_id, "p5");
  EXPECT_EQ(last[1].request_id, "p6");
  EXPECT_EQ(metric_series(db, {"M1", "center_dy_mm", 0, 20 * kDay, 3}).back().request_id, "c12");

  EXPECT_EQ(metric_series(db, {"M2", "center_dy_mm"}).size(), 3u);
  EXPECT_TRUE(metric_series(db, {"M1", "no_such_metric"}).empty());
  EXPECT_TRUE(metric_series(db, {"M9", "center_dy_mm"}).empty());
}

TEST_F(TrendStore, AMachinesMetricsAreThoseItsChecksReport) {
  Database db = Database::open_readonly(path_);
  const auto metrics = machine_metrics(db, "M1");
  ASSERT_EQ(metrics.size(), 6u);  // three metrics of two kinds
  EXPECT_EQ(metrics[0].kind, CheckKind::MonumentCAlignment);
  EXPECT_EQ(metrics[0].name, "center_dx_mm");
  EXPECT_EQ(metrics[1].name, "center_dy_mm");
  EXPECT_EQ(metrics[1].count, 2);
  EXPECT_EQ(metrics[1].last_ns, 12 * kDay);
  EXPECT_EQ(metrics[2].name, "tilt_arcsec");
  EXPECT_TRUE(std::isinf(metrics[2].lower));
  EXPECT_EQ(metrics[4].kind, CheckKind::MonumentPositioning);
  EXPECT_EQ(metrics[4].name, "center_dy_mm");
  EXPECT_EQ(metrics[4].count, 10);
  EXPECT_EQ(metrics[4].last_ns, 10 * kDay);
  EXPECT_TRUE(machine_metrics(db, "M9").empty());
}

// A newest result that reports fewer metrics (an INVALID check that measured nothing; a fixture
// check of another pogo rotation) hides none of the older ones' history: the kinds that ever
// reported a metric are kept (schema 10, reported_metrics) as results are stored, and filled from
// what was stored before the migration.
TEST_F(TrendStore, ANewestResultWithFewerMetricsHidesNoneOfTheirHistory) {
  {
    Database db = Database::open(path_);
    CheckResult invalid = result_at("p11", "M1", CheckKind::MonumentPositioning, 11, 0);
    invalid.verdict = Verdict::Invalid;
    invalid.reason = "the probe did not trigger";
    invalid.metrics.clear();
    db.store(invalid);
    CheckResult other = result_at("p13", "M1", CheckKind::MonumentPositioning, 13, 0);
    other.metrics = {{"rotation_b_mm", 0.001, "mm", -0.01, 0.01, true}};
    db.store(other);
  }
  Database db = Database::open_readonly(path_);
  const auto series = metric_series(db, {"M1", "center_dy_mm"});
  ASSERT_EQ(series.size(), 12u);  // p1..p10 and c2, c12, as before the two newest checks
  EXPECT_EQ(series[series.size() - 2].request_id, "p10");
  const auto metrics = machine_metrics(db, "M1");
  ASSERT_EQ(metrics.size(), 7u);  // three of monument_c_alignment, four of monument_positioning
  EXPECT_EQ(metrics[3].kind, CheckKind::MonumentPositioning);
  EXPECT_EQ(metrics[3].name, "center_dx_mm");  // place 0 in its newest check, then by name
  EXPECT_EQ(metrics[4].name, "rotation_b_mm");
  EXPECT_EQ(metrics[4].count, 1);
  EXPECT_EQ(metrics[4].last_ns, 13 * kDay);
  EXPECT_EQ(metrics[5].name, "center_dy_mm");
  EXPECT_EQ(metrics[5].count, 10);
  EXPECT_EQ(metrics[5].last_ns, 10 * kDay);  // p11 reported nothing
  EXPECT_EQ(metrics[6].name, "tilt_arcsec");

  // A historian of schema 9 (before reported_metrics) gets the table filled when migrated.
  {
    RawDb raw(path_);
    raw.exec(
        "ALTER TABLE measurement_sets DROP COLUMN origin; ALTER TABLE results DROP COLUMN origin; "
        "DROP TRIGGER metrics_reported; DROP TABLE reported_metrics; PRAGMA user_version = 9");
  }
  Database migrated = Database::open(path_);
  EXPECT_EQ(metric_series(migrated, {"M1", "center_dy_mm"}).size(), 12u);
  EXPECT_EQ(machine_metrics(migrated, "M1").size(), 7u);
}

// The intervention restarts every series. At day 7 two compensations: "machine:work_offset", a
// target ncqual does not know (every series), and fixture zero offsets (the fixture's series).
TEST_F(TrendStore, RestartsAreTheInterventionsAndTheCompensationsThatConcernTheSeries) {
  Database db = Database::open(path_);
  const std::vector<std::int64_t> both{5 * kDay + 1, 7 * kDay + 2};
  EXPECT_EQ(restart_times(db, "M1", CheckKind::MonumentPositioning, "center_dy_mm"), both)
      << "each time once";
  EXPECT_EQ(restart_times(db, "M1", CheckKind::FixturePreCalibration, "fixture_dx_mm"), both);
  EXPECT_TRUE(restart_times(db, "M2", CheckKind::MonumentPositioning, "center_dy_mm").empty());

  // By what the compensation corrects (its target; docs/trends.md, "What restarts a series"):
  // zero offsets restart the fixture's series (pre- and post-calibration), not the monument's; a
  // volumetric compensation the series over the volume and the fixture fit's shape terms, not
  // the monument's, the probe's or the pogo deltas; a part's work offset none.
  const auto compensate = [&](const std::string& id, CheckKind kind, int day,
                              const std::string& target) {
    CheckRequest request = testing::make_request(id, "M2", day * kDay - 10);
    request.kind = kind;
    db.store(request);
    Compensation c;
    c.machine_id = "M2";
    c.request_id = id;
    c.time_ns = day * kDay;
    c.correction = Correction{target, {NamedValue{"dx_mm", 0.001, "mm"}}};
    db.store(c);
  };
  compensate("f1", CheckKind::FixturePreCalibration, 20, "fixture:F1");
  compensate("g1", CheckKind::GlobalGrid, 30, "volumetric:M2");
  compensate("s1", CheckKind::PartSetPoints, 40, "work_offset:M2");
  const std::vector<std::int64_t> none;
  EXPECT_EQ(restart_times(db, "M2", CheckKind::MonumentPositioning, "center_dy_mm"), none);
  EXPECT_EQ(restart_times(db, "M2", CheckKind::MonumentCAlignment, "probe_c_offset_mm"), none);
  EXPECT_EQ(restart_times(db, "M2", CheckKind::PartSetPoints, "setpoint_max_dev_mm"), none);
  EXPECT_EQ(restart_times(db, "M2", CheckKind::RotaryC, "c_dR_max_mm"), none);
  EXPECT_EQ(restart_times(db, "M2", CheckKind::GlobalGrid, "grid_max_deviation_mm"),
            std::vector<std::int64_t>{30 * kDay});
  EXPECT_EQ(restart_times(db, "M2", CheckKind::CircleXY, "circle_xy_G_mm"),
            std::vector<std::int64_t>{30 * kDay});
  EXPECT_EQ(restart_times(db, "M2", CheckKind::FixturePreCalibration, "fixture_dx_mm"),
            std::vector<std::int64_t>{20 * kDay});
  EXPECT_EQ(restart_times(db, "M2", CheckKind::FixturePostCalibration, "fixture_dx_mm"),
            std::vector<std::int64_t>{20 * kDay});
  EXPECT_EQ(restart_times(db, "M2", CheckKind::FixturePostCalibration, "fixture_fit_dy_per_y_ppm"),
            (std::vector<std::int64_t>{20 * kDay, 30 * kDay}));
  EXPECT_EQ(
      restart_times(db, "M2", CheckKind::FixturePostCalibration, "fixture_fit_scatter_rms_mm"),
      std::vector<std::int64_t>{20 * kDay});
}

// The plans of the trend reads on a file with many machines and checks: each statement uses an
// index (SEARCH ... USING INDEX / PRIMARY KEY), none scans a table (SCAN <table> without an
// index).
TEST_F(TrendStore, TheTrendReadsWalkIndexesNotTables) {
  {
    Database db = Database::open(path_);
    for (int m = 0; m < 20; ++m) {
      for (int day = 1; day <= 30; ++day) {
        const std::string id = "g" + std::to_string(m) + "-" + std::to_string(day);
        db.store(
            result_at(id, "G" + std::to_string(m), CheckKind::MonumentPositioning, day, day / 1e4));
        // A compensation and an intervention every third day: tables the planner must search.
        if (day % 3 == 0) {
          Compensation c;
          c.machine_id = "G" + std::to_string(m);
          c.request_id = id;
          c.time_ns = day * kDay + 1;
          c.correction = Correction{"machine:work_offset", {NamedValue{"dy_mm", 0.001, "mm"}}};
          db.store(c);
          Intervention i;
          i.machine_id = c.machine_id;
          i.intervention_id = "i-" + id;
          i.time_ns = day * kDay + 2;
          db.store(i);
        }
      }
    }
  }
  RawDb raw(path_);
  raw.exec("ANALYZE");
  const std::vector<std::string> statements = {
      "SELECT DISTINCT kind FROM results WHERE machine_id = 'G3'",
      "SELECT r.request_id, r.time_ns, r.verdict, m.value, m.unit, m.lower, m.upper, m.pass "
      "FROM results AS r JOIN metrics AS m ON m.request_id = r.request_id AND m.name = "
      "'center_dy_mm' WHERE r.machine_id = 'G3' AND r.kind = 2 AND r.time_ns >= 0 AND r.time_ns "
      "<= 9000000000000000000 ORDER BY r.time_ns, r.request_id",
      "SELECT time_ns, NULL FROM interventions WHERE machine_id = 'G3' UNION ALL SELECT "
      "time_ns, target FROM compensations WHERE machine_id = 'G3'",
      "SELECT * FROM trend_warnings WHERE machine_id = 'M1' AND metric = 'x' AND ended_ns IS NULL",
      "SELECT * FROM trend_warnings WHERE machine_id = 'M1' ORDER BY ended_ns IS NOT NULL, "
      "raised_ns DESC LIMIT 10",
  };
  for (const std::string& sql : statements) {
    SCOPED_TRACE(sql);
    sqlite3_stmt* stmt = nullptr;
    ASSERT_EQ(
        sqlite3_prepare_v2(raw.get(), ("EXPLAIN QUERY PLAN " + sql).c_str(), -1, &stmt, nullptr),
        SQLITE_OK);
    std::string plan;
    bool scans_a_table = false;
    while (sqlite3_step(stmt) == SQLITE_ROW) {
      const std::string detail = reinterpret_cast<const char*>(sqlite3_column_text(stmt, 3));
      plan += detail + "\n";
      // "SCAN t" reads the whole table; "SCAN t USING ... INDEX" an index in order (none here
      // without a SEARCH on its leading column).
      if (detail.rfind("SCAN ", 0) == 0 && detail.find("INDEX") == std::string::npos) {
        scans_a_table = true;
      }
    }
    sqlite3_finalize(stmt);
    EXPECT_FALSE(scans_a_table) << plan;
    EXPECT_NE(plan.find("SEARCH"), std::string::npos) << plan;
  }
}

}  // namespace
}  // namespace ncqual::storage

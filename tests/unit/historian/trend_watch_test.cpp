// SPDX-License-Identifier: Apache-2.0
// The historian's trend watch on a real SQLite file: a forecast warning raised at the check that
// makes the drift a trend, its dates those of the hand-worked example of docs/trends.md (checks
// on 5 consecutive days of 1.0, 1.2, 1.1, 1.5, 1.7 mm against an upper limit of 2.5 mm: the line
// reaches it at day 9.06, its upper 95 % prediction bound at day 5.34), raised once, ended by an
// intervention and not by a compensation of another check, nor by a volumetric one (which does not
// correct a drift against the monument); a late result does not raise it
// again.
#include "ncqual/historian/trend_watch.hpp"
#include "ncqual/historian/watch_worker.hpp"

#include "storage_test_support.hpp"

#include "ncqual/storage/trend.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <mutex>

namespace ncqual::historian {
namespace {

constexpr std::int64_t kDay = 86'400'000'000'000;
constexpr std::int64_t kT0 = 1'767'225'600'000'000'000;  // 2026-01-01T00:00:00Z

CheckResult check(const std::string& id, double day, double dy, double dx = 0.0) {
  CheckResult r;
  r.machine_id = "M1";
  r.request_id = id;
  r.kind = CheckKind::MonumentPositioning;
  r.verdict = Verdict::Pass;
  r.metrics = {Metric{"center_dx_mm", dx, "mm", -2.5, 2.5, true},
               Metric{"center_dy_mm", dy, "mm", -2.5, 2.5, std::abs(dy) <= 2.5}};
  r.time_ns = kT0 + static_cast<std::int64_t>(day * static_cast<double>(kDay));
  return r;
}

storage::TrendWarningQuery of_machine(const std::string& machine_id) {
  storage::TrendWarningQuery q;
  q.machine_id = machine_id;
  return q;
}

class TrendWatchTest : public ::testing::Test {
 protected:
  std::vector<TrendWarning> store(const CheckResult& r) {
    EXPECT_TRUE(db_.store(r));
    return watch_.after_result(db_, r);
  }

  storage::testing::TempDir dir_;
  storage::Database db_ = storage::Database::open(dir_.file("historian.db"));
  TrendWatch watch_;
};

TEST_F(TrendWatchTest, AForecastIsRaisedOnceWithTheHandWorkedDatesAndEndedByAnIntervention) {
  const double values[] = {1.0, 1.2, 1.1, 1.5, 1.7};
  for (int day = 0; day < 4; ++day) {
    EXPECT_TRUE(store(check("r" + std::to_string(day), day, values[day])).empty())
        << "fewer than 5 checks: no forecast, no chart (baseline 10)";
  }
  const std::vector<TrendWarning> raised = store(check("r4", 4, values[4]));
  ASSERT_EQ(raised.size(), 1u);
  const TrendWarning& w = raised[0];
  EXPECT_EQ(w.machine_id, "M1");
  EXPECT_EQ(w.metric, "center_dy_mm");
  EXPECT_EQ(w.check_kind, CheckKind::MonumentPositioning);
  EXPECT_EQ(w.kind, "forecast");
  EXPECT_EQ(w.side, "above");
  EXPECT_TRUE(w.active);
  EXPECT_EQ(w.raised_by, "r4");
  EXPECT_EQ(w.time_ns, kT0 + 4 * kDay);
  // The forecast held first at the 5th check: its episode starts there.
  EXPECT_EQ(w.started_ns, kT0 + 4 * kDay);
  ASSERT_TRUE(w.expected_crossing_ns && w.earliest_crossing_ns);
  const auto days = [](std::int64_t ns) {
    return static_cast<double>(ns - kT0) / static_cast<double>(kDay);
  };
  // Hand-worked: x = (2.5 - 0.96) / 0.17 = 9.0588; the upper bound 0.96 + 0.17 x + 3.1824 *
  // 0.13038 * sqrt(1 + 1/5 + (x - 2)^2 / 10) = 2.5 at x = 5.34.
  EXPECT_NEAR(days(*w.expected_crossing_ns), 9.0588, 1e-3);
  EXPECT_NEAR(days(*w.earliest_crossing_ns), 5.34, 5e-3);
  EXPECT_NE(w.text.find("center_dy_mm drifts"), std::string::npos) << w.text;
  EXPECT_NE(w.text.find("2026-01-06"), std::string::npos) << "earliest date, day 5.34\n" << w.text;
  EXPECT_NE(w.text.find("2026-01-10"), std::string::npos) << "expected date, day 9.06\n" << w.text;

  // The next check moves the dates: stored, not announced again.
  EXPECT_TRUE(store(check("r5", 5, 1.9)).empty());
  auto stored = storage::trend_warnings(db_, {"M1", {}, true});
  ASSERT_EQ(stored.size(), 1u);
  EXPECT_EQ(stored[0].raised_by, "r4");
  EXPECT_NE(stored[0].expected_crossing_ns, w.expected_crossing_ns);

  // A fixture check's zero offsets do not concern the monument's series.
  CheckRequest fixture_check;
  fixture_check.machine_id = "M1";
  fixture_check.request_id = "f1";
  fixture_check.kind = CheckKind::FixturePreCalibration;
  fixture_check.time_ns = kT0 + 5 * kDay + kDay / 4;
  ASSERT_TRUE(db_.store(fixture_check));
  Compensation offsets;
  offsets.machine_id = "M1";
  offsets.request_id = "f1";
  offsets.time_ns = kT0 + 5 * kDay + kDay / 3;
  offsets.correction = Correction{"work_offset:M1", {NamedValue{"dx_mm", 0.01, "mm"}}};
  ASSERT_TRUE(db_.store(offsets));
  EXPECT_TRUE(watch_.after_compensation(db_, offsets).empty());

  // Nor does the monthly grid's volumetric compensation: it corrects the shape of X, Y and Z
  // over the volume, not a drift of the machine against its monument (docs/trends.md, "What
  // restarts a series"); the warning stays active, its episode unbroken.
  CheckRequest grid_check = fixture_check;
  grid_check.request_id = "g1";
  grid_check.kind = CheckKind::GlobalGrid;
  grid_check.time_ns = kT0 + 5 * kDay + kDay / 5;
  ASSERT_TRUE(db_.store(grid_check));
  Compensation volumetric;
  volumetric.machine_id = "M1";
  volumetric.request_id = "g1";
  volumetric.time_ns = kT0 + 5 * kDay + kDay / 4;
  volumetric.correction = Correction{"volumetric:M1", {NamedValue{"EYX P2", 1e-6, "rad"}}};
  ASSERT_TRUE(db_.store(volumetric));
  EXPECT_TRUE(watch_.after_compensation(db_, volumetric).empty());
  ASSERT_EQ(storage::trend_warnings(db_, {"M1", {}, true}).size(), 1u);
  EXPECT_EQ(storage::trend_warnings(db_, {"M1", {}, true})[0].started_ns, kT0 + 4 * kDay);

  // An intervention ends it.
  Intervention i;
  i.machine_id = "M1";
  i.intervention_id = "i1";
  i.time_ns = kT0 + 5 * kDay + kDay / 2;
  i.note = "Y scale reading head fixed";
  ASSERT_TRUE(db_.store(i));
  const std::vector<TrendWarning> ended = watch_.after_intervention(db_, i);
  ASSERT_EQ(ended.size(), 1u);
  EXPECT_FALSE(ended[0].active);
  EXPECT_EQ(ended[0].kind, "forecast");
  EXPECT_EQ(ended[0].ended_by, "i1");
  EXPECT_EQ(ended[0].time_ns, i.time_ns);
  EXPECT_TRUE(storage::trend_warnings(db_, {"M1", {}, true}).empty());

  // A result from before the intervention that arrives after it: the segment it belonged to has
  // ended, nothing is raised.
  EXPECT_TRUE(store(check("r4b", 4.5, 1.8)).empty());
  // The same checks again (a replay): nothing changes.
  EXPECT_TRUE(watch_.after_result(db_, check("r5", 5, 1.9)).empty());
  EXPECT_EQ(storage::trend_warnings(db_, of_machine("M1")).size(), 1u);
}

// A flat series with scatter raises no forecast: the slope's interval contains zero.
TEST_F(TrendWatchTest, AFlatSeriesRaisesNothing) {
  const double noise[] = {0.02,   -0.01, 0.015,  -0.02, 0.0,   0.01,
                          -0.015, 0.02,  -0.005, 0.005, -0.01, 0.015};
  for (int day = 0; day < 12; ++day) {
    EXPECT_TRUE(store(check("r" + std::to_string(day), day, noise[day])).empty()) << day;
  }
  EXPECT_TRUE(storage::trend_warnings(db_, {}).empty());
}

// One check far outside the baseline's control limits: a control_limit warning that the next
// normal check ends.
TEST_F(TrendWatchTest, AnOutlierRaisesAControlLimitWarningThatTheNextCheckEnds) {
  const double noise[] = {0.02, -0.01, 0.015, -0.02, 0.0, 0.01, -0.015, 0.02, -0.005, 0.005};
  for (int day = 0; day < 10; ++day) store(check("r" + std::to_string(day), day, noise[day]));
  const auto raised = store(check("r10", 10, 0.3));
  std::vector<std::string> kinds;
  for (const auto& w : raised) kinds.push_back(w.kind);
  ASSERT_FALSE(raised.empty());
  EXPECT_EQ(raised[0].kind, "control_limit");
  EXPECT_EQ(raised[0].side, "above");
  EXPECT_NE(raised[0].text.find("control limit"), std::string::npos) << raised[0].text;
  const auto after = store(check("r11", 11, 0.0));
  bool ended = false;
  for (const auto& w : after)
    ended |= w.kind == "control_limit" && !w.active && w.ended_by == "r11";
  EXPECT_TRUE(ended);
}

// The worker runs the same watch on its own connection, in the order the jobs were handed over:
// the forecast of the hand-worked example raised by r4, then ended by the intervention; what it
// wrote is what the historian's connection reads.
TEST_F(TrendWatchTest, TheWorkerRunsTheWatchOnItsOwnConnectionInOrder) {
  std::mutex mutex;
  std::vector<TrendWarning> published;
  WatchWorker worker(db_.open_another(), [&](const std::vector<TrendWarning>& changes) {
    std::lock_guard lock(mutex);
    published.insert(published.end(), changes.begin(), changes.end());
  });
  const double values[] = {1.0, 1.2, 1.1, 1.5, 1.7};
  for (int day = 0; day < 5; ++day) {
    const CheckResult r = check("r" + std::to_string(day), day, values[day]);
    ASSERT_TRUE(db_.store(r));
    worker.after_result(r);
  }
  // The watch reads what is stored when it runs: the intervention stored now would already end
  // the series for the results' jobs, so it is stored once they are done.
  worker.drain();
  Intervention i;
  i.machine_id = "M1";
  i.intervention_id = "i1";
  i.time_ns = kT0 + 4 * kDay + kDay / 2;
  ASSERT_TRUE(db_.store(i));
  worker.after_intervention(i);
  worker.drain();
  EXPECT_EQ(worker.pending(), 0u);

  std::lock_guard lock(mutex);
  ASSERT_EQ(published.size(), 2u);
  EXPECT_TRUE(published[0].active);
  EXPECT_EQ(published[0].raised_by, "r4");
  EXPECT_FALSE(published[1].active);
  EXPECT_EQ(published[1].ended_by, "i1");
  const auto stored = storage::trend_warnings(db_, of_machine("M1"));
  ASSERT_EQ(stored.size(), 1u);
  EXPECT_EQ(stored[0].ended_by, "i1");
}

TEST(DatabaseOpenAnother, RefusesAnInMemoryDatabase) {
  auto db = storage::Database::open(":memory:");
  EXPECT_THROW((void)db.open_another(), storage::StorageError);
}

}  // namespace
}  // namespace ncqual::historian

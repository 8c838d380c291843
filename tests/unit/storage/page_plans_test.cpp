// SPDX-License-Identifier: Apache-2.0
// The query plans of what the plant page, a machine page, `ncqual status`, `ncqual trend` and the
// report read, on a generated historian (tests/support/history_gen.hpp): every statement those
// libraries run is caught as it runs (sqlite3_trace_v2 on the library's own connection) and its
// EXPLAIN QUERY PLAN must not scan one of the big tables (SCAN <table> without an index): a page
// stays fast as the historian grows (docs/history-bench.md has the figures on a year of 50
// machines).
#include "database_impl.hpp"
#include "history_gen.hpp"
#include "storage_test_support.hpp"

#include "ncqual/status/plant_status.hpp"
#include "ncqual/report/metric_trend.hpp"
#include "ncqual/storage/database.hpp"
#include "ncqual/storage/trend.hpp"
#include "ncqual/storage/changes.hpp"
#if NCQUAL_TEST_HAS_REPORT
#include "ncqual/report/machine_report.hpp"
#endif

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <vector>

namespace ncqual::storage {
namespace {

using testing::TempDir;

// The tables that grow with every check.
const std::set<std::string> kBigTables = {"results",
                                          "metrics",
                                          "requests",
                                          "measurement_sets",
                                          "status_changes",
                                          "trend_warnings",
                                          "checks",
                                          "causes",
                                          "touches",
                                          "tracker_points",
                                          "interventions",
                                          "compensations",
                                          "request_parameters",
                                          "measurement_parameters",
                                          "result_offsets",
                                          "compensation_offsets",
                                          "conflicts"};

// Statements allowed to read a big table whole, each with why.
struct Allowed {
  const char* sql_part;
  const char* table;
  const char* why;
};
const Allowed kAllowed[] = {
    // ncqual/storage/changes.hpp: the change token reads the trend warnings whole (their count,
    // how many ended, a fingerprint of their dates and texts): one row per warning episode, a few
    // thousand a year for a plant of 50 machines.
    {"w.fingerprint", "trend_warnings", "change token: the warnings read whole, by design"},
};

// Statements that must read only the rows they return: a plan that sorts them (a temporary
// b-tree) walked every row of the machine first. By a part of their text.
const char* const kSearchOnly[] = {
    "verdict <> 'PASS' ORDER BY time_ns DESC",  // storage::recent_failures (plant, machine page)
    "max(time_ns) FROM results",                // Database::last_pass_ns (every period's status)
};

int collect(unsigned type, void* context, void* p, void* /*x*/) {
  if (type == SQLITE_TRACE_STMT) {
    const char* sql = sqlite3_sql(static_cast<sqlite3_stmt*>(p));
    if (sql) static_cast<std::set<std::string>*>(context)->insert(sql);
  }
  return 0;
}

// The table a "SCAN t ..." line reads whole, or "" when the line does not (a SEARCH, an index
// walked in order: "SCAN t USING INDEX ...", a subquery or a temporary b-tree).
std::string scanned_table(const std::string& detail) {
  if (detail.rfind("SCAN ", 0) != 0 || detail.find("INDEX") != std::string::npos) return "";
  std::string table = detail.substr(5);
  table = table.substr(0, table.find(' '));
  return table;
}

TEST(StorageQueryPlans, ThePagesReadsWalkIndexesOnAGeneratedPlant) {
  TempDir dir;
  const std::string path = dir.file("plant.db");
  history::GenerateOptions options;
  options.machines = 4;
  options.days = 22;
  options.watch = true;
  options.fault_per_day = 0.1;  // interventions and their restarts in three weeks
  options.machine_file = std::string(NCQUAL_SOURCE_DIR) + "/deploy/machines/pm1.yaml";
  history::GenerateReport generated;
  {
    Database db = Database::open(path);
    generated = history::generate_history(db, options);
  }
  ASSERT_GT(generated.checks, 200);
  ASSERT_GT(generated.interventions, 0);

  Database db = Database::open_readonly(path);
  sqlite3* handle = DatabaseAccess::impl(db).db.get();
  std::set<std::string> statements;
  ASSERT_EQ(sqlite3_trace_v2(handle, SQLITE_TRACE_STMT, collect, &statements), SQLITE_OK);
  const PlantConfig plant = history::generated_plant(options, generated.machine_ids);
  const Calendar calendar = plant_status::plant_calendar(plant);
  const std::string machine = generated.machine_ids.front();
  const std::int64_t now = generated.last_ns;
  // The plant page and `ncqual status`.
  const auto status = plant_status::plant_status(db, plant, calendar, {{}, now});
  ASSERT_EQ(status.machines.size(), 4u);
  for (const auto& id : generated.machine_ids) (void)recent_failures(db, id, 20);
  (void)change_token(db);
  // A machine page: its status, failures, newest checks and one of them, its report.
  (void)plant_status::plant_status(db, plant, calendar, {machine, now});
  HistoryQuery history;
  history.machine_id = machine;
  history.limit = 50;
  const auto checks = db.history(history);
  ASSERT_FALSE(checks.empty());
  (void)db.find_check(checks.front().request_id);
  (void)db.load_measurement_set(checks.front().request_id);
#if NCQUAL_TEST_HAS_REPORT
  report::MachineReportQuery query;
  query.machine_id = machine;
  query.since_ns = now - 90 * 86'400'000'000'000LL;
  query.now_ns = now;
  query.machine = plant.find_machine(machine);
  (void)report::gather_machine_report(db, query);
#endif
  // `ncqual trend` and the forecast.
  (void)machine_metrics(db, machine);
  (void)metric_series(db, {machine, "center_dy_mm"});
  (void)restart_times(db, machine, CheckKind::MonumentPositioning, "center_dy_mm");
  (void)trend_warnings(db, {machine, std::string("center_dy_mm"), false});
  report::MetricTrendQuery trend_query;
  trend_query.machine_id = machine;
  trend_query.metric = "center_dy_mm";
  (void)report::metric_trend(db, trend_query);
  sqlite3_trace_v2(handle, 0, nullptr, nullptr);
  ASSERT_GT(statements.size(), 10u);

  int planned = 0, searched = 0;
  for (const std::string& sql : statements) {
    if (sql.rfind("SELECT", 0) != 0 && sql.rfind("WITH", 0) != 0) continue;  // BEGIN, PRAGMA
    SCOPED_TRACE(sql);
    sqlite3_stmt* stmt = nullptr;
    ASSERT_EQ(sqlite3_prepare_v2(handle, ("EXPLAIN QUERY PLAN " + sql).c_str(), -1, &stmt, nullptr),
              SQLITE_OK)
        << sqlite3_errmsg(handle);
    std::string plan;
    std::set<std::string> scanned;
    while (sqlite3_step(stmt) == SQLITE_ROW) {
      const std::string detail = reinterpret_cast<const char*>(sqlite3_column_text(stmt, 3));
      plan += detail + "\n";
      const std::string table = scanned_table(detail);
      if (kBigTables.count(table)) scanned.insert(table);
    }
    sqlite3_finalize(stmt);
    ++planned;
    // NCQUAL_PRINT_PLANS=1: every statement with its plan, to look at them.
    if (std::getenv("NCQUAL_PRINT_PLANS")) std::printf("%s\n%s\n", sql.c_str(), plan.c_str());
    for (const Allowed& a : kAllowed) {
      if (sql.find(a.sql_part) != std::string::npos) scanned.erase(a.table);
    }
    EXPECT_TRUE(scanned.empty()) << "scans " << *scanned.begin() << ":\n" << plan;
    for (const char* part : kSearchOnly) {
      if (sql.find(part) == std::string::npos) continue;
      ++searched;
      EXPECT_EQ(plan.find("TEMP B-TREE"), std::string::npos) << plan;
      EXPECT_NE(plan.find("SEARCH results USING INDEX results_"), std::string::npos) << plan;
    }
  }
  EXPECT_GT(planned, 10);
  EXPECT_EQ(searched, 2);  // both hot statements ran and were planned
}

}  // namespace
}  // namespace ncqual::storage

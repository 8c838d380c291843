// SPDX-License-Identifier: Apache-2.0
// A historian written at schema version 1 (tests/data/historian-v1.sql: the first migration and
// rows in every table) is opened by this build: it migrates to the latest version, and every row
// reads back through the query API with the values it was written with.
#include "schema.hpp"
#include "storage_test_support.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#ifndef NCQUAL_SOURCE_DIR
#error "NCQUAL_SOURCE_DIR must be defined by the test target"
#endif

namespace ncqual::storage {
namespace {

using namespace testing;  // storage_test_support.hpp

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string fixture_text() {
  std::ifstream in(NCQUAL_SOURCE_DIR "/tests/data/historian-v1.sql");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A database file made from `sql` with the sqlite3 API alone.
void create(const std::string& path, const std::string& sql) {
  RawDb raw(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  raw.exec("PRAGMA foreign_keys = ON");
  raw.exec(sql);
}

// Every table and index of the file with the SQL that made it, by name.
std::string schema_of(const std::string& path) {
  return RawDb(path).text(
      "SELECT group_concat(type || ' ' || name || ': ' || sql, char(10)) FROM "
      "(SELECT type, name, sql FROM sqlite_schema WHERE sql IS NOT NULL ORDER BY name)");
}

void expect_request(const CheckRecord& record, const std::string& requested_by,
                    std::int64_t time_ns, std::int32_t attempt) {
  ASSERT_TRUE(record.request) << record.request_id;
  EXPECT_EQ(record.request->request_id, record.request_id);
  EXPECT_EQ(record.request->machine_id, record.machine_id);
  EXPECT_EQ(record.request->kind, record.kind);
  EXPECT_EQ(record.request->requested_by, requested_by);
  EXPECT_EQ(record.request->time_ns, time_ns);
  EXPECT_EQ(record.request->attempt, attempt);
  // Version 2's columns: a version 1 request had no parameters and verified nothing.
  EXPECT_TRUE(record.request->parameters.empty());
  EXPECT_EQ(record.request->verifies_correction_of, "");
}

// The measurement summary of a check.
void expect_measurement(const CheckRecord& record, const std::string& instrument,
                        const std::string& frame, std::int64_t time_ns, std::int64_t touches,
                        std::int64_t tracker_points, const std::string& error = "") {
  ASSERT_TRUE(record.measurement) << record.request_id;
  EXPECT_EQ(record.measurement->instrument, instrument);
  EXPECT_EQ(record.measurement->frame, frame);
  EXPECT_EQ(record.measurement->time_ns, time_ns);
  EXPECT_EQ(record.measurement->touches, touches);
  EXPECT_EQ(record.measurement->tracker_points, tracker_points);
  EXPECT_EQ(record.measurement->error, error);
  // Schema 11's column: a set stored before does not say whether it was measured or simulated.
  EXPECT_EQ(record.measurement->origin, DataOrigin::Unknown);
}

// The record's result, which must be `expected` (machine, kind and id are the record's).
void expect_result(const CheckRecord& record, CheckResult expected) {
  ASSERT_TRUE(record.result) << record.request_id;
  expected.machine_id = record.machine_id;
  expected.request_id = record.request_id;
  expected.kind = record.kind;
  expect_result_eq(*record.result, expected);
}

void expect_touch(const Touch& t, const std::string& feature, AxisPosition a, Eigen::Vector3d u) {
  EXPECT_EQ(t.feature, feature);
  expect_axes_eq(t.axes, a);
  EXPECT_EQ(t.approach, u) << feature;
}

void expect_point(const TrackerPoint& p, const std::string& label, AxisPosition a,
                  Eigen::Vector3d measured) {
  EXPECT_EQ(p.label, label);
  expect_axes_eq(p.commanded, a);
  EXPECT_EQ(p.measured_mm, measured) << label;
}

// The zero offsets of pm1-precal-1, in its result and in its Compensation.
const Correction kPogoCorrection{
    "fixture:F1", {{"pogo_C2R3_dx_mm", -0.046875, "mm"}, {"pogo_C2R3_dy_mm", 0.015625, "mm"}}};

TEST(StorageMigration, TheFixtureIsTheFirstMigrationsSchemaAtVersionOne) {
  TempDir dir;
  const std::string fixture = dir.file("fixture.db"), first = dir.file("first.db");
  create(fixture, fixture_text());
  create(first, std::string("BEGIN; ") + schema::migrations().front().sql + " COMMIT;");
  EXPECT_EQ(schema_of(fixture), schema_of(first));
  RawDb raw(fixture);
  EXPECT_EQ(raw.text("PRAGMA user_version"), "1");
  EXPECT_EQ(raw.text("PRAGMA application_id"), "1852010869");
  EXPECT_EQ(raw.text("PRAGMA foreign_key_check"), "");
  for (const char* table :
       {"machines", "requests", "measurement_sets", "touches", "tracker_points", "results",
        "metrics", "causes", "result_offsets", "checks", "status_changes", "interventions",
        "compensations", "compensation_offsets", "services"}) {
    EXPECT_GT(raw.count(table), 0) << table << " has no row in the fixture";
  }
}

TEST(StorageMigration, VersionOneFileReadsBackEveryRowAtTheLatestVersion) {
  TempDir dir;
  const std::string path = dir.file("historian.db");
  create(path, fixture_text());
  ASSERT_EQ(RawDb(path).text("PRAGMA user_version"), "1");

  Database db = Database::open(path);
  EXPECT_EQ(db.info().schema_version, Database::latest_schema_version());
  EXPECT_EQ(RawDb(path).text("PRAGMA user_version"),
            std::to_string(Database::latest_schema_version()));
  EXPECT_EQ(db.integrity_check(), "ok");
  // The migrated file has the schema of a file this build creates.
  { Database fresh = Database::open(dir.file("fresh.db")); }
  EXPECT_EQ(schema_of(path), schema_of(dir.file("fresh.db")));

  // Checks, newest first.
  HistoryQuery all;
  all.limit = 0;
  std::vector<std::string> ids;
  for (const CheckRecord& r : db.history(all)) ids.push_back(r.request_id);
  EXPECT_EQ(ids, (std::vector<std::string>{"pm1-late-1", "pm2-master-2", "pm2-master-1",
                                           "pm1-precal-1", "pm1-c-align-1"}));
  EXPECT_EQ(db.count_results(), 4);
  EXPECT_EQ(db.count_results("pm1"), 3);

  {
    const auto rec = db.find_check("pm1-c-align-1");
    ASSERT_TRUE(rec);
    EXPECT_EQ(rec->machine_id, "pm1");
    EXPECT_EQ(rec->kind, CheckKind::MonumentCAlignment);
    expect_request(*rec, "scheduler", 1780000000000000000, 1);
    expect_measurement(*rec, "touch_probe", "machine", 1780000060000000000, 4, 0);
    CheckResult expected;
    expected.verdict = Verdict::Pass;
    expected.time_ns = 1780000120000000000;
    expected.metrics = {{"c_align_dx_mm", 0.00390625, "mm", -0.015625, 0.015625, true},
                        {"c_align_dy_mm", -0.001953125, "mm", -0.015625, 0.015625, true},
                        {"probe_c_offset_mm", 0.0078125, "mm", -kInf, 0.03125, true}};
    expected.likely_causes = {"bent stylus", "probe microswitches"};
    expect_result(*rec, expected);

    const auto set = db.load_measurement_set("pm1-c-align-1");
    ASSERT_TRUE(set);
    EXPECT_EQ(set->machine_id, "pm1");
    EXPECT_EQ(set->kind, CheckKind::MonumentCAlignment);
    EXPECT_TRUE(set->parameters.empty());
    ASSERT_EQ(set->touches.size(), 4u);
    EXPECT_TRUE(set->tracker_points.empty());
    expect_touch(set->touches[0], "hole_edge", {1225.0078125, 800.0, 145.0, 0.0, 0.0, 0.0},
                 {-1.0, 0.0, 0.0});
    expect_touch(set->touches[1], "hole_edge", {1174.9921875, 800.0, 145.0, 0.0, 0.0, 0.0},
                 {1.0, 0.0, 0.0});
    expect_touch(set->touches[2], "hole_edge", {1200.0, 825.00390625, 145.0, 0.0, 0.0, 3.140625},
                 {0.0, -1.0, 0.0});
    expect_touch(set->touches[3], "face", {1200.0, 774.99609375, 145.0, 0.5, -1.5703125, 3.140625},
                 {0.0, 0.0, -1.0});
  }
  {
    const auto rec = db.find_check("pm1-precal-1");
    ASSERT_TRUE(rec);
    EXPECT_EQ(rec->kind, CheckKind::FixturePreCalibration);
    expect_request(*rec, "scheduler", 1780000600000000000, 2);
    expect_measurement(*rec, "fixture_probe", "fixture", 1780000660000000000, 2, 0);
    CheckResult expected;
    expected.verdict = Verdict::Fail;
    expected.reason = "pogo_C2R3_dx_mm = 0.047 mm: out of tolerance";
    expected.time_ns = 1780000720000000000;
    expected.metrics = {{"pogo_C2R3_dx_mm", 0.046875, "mm", -0.03125, 0.03125, false},
                        {"fixture_max_dx_mm", 0.046875, "mm", -kInf, 0.03125, false}};
    expected.likely_causes = {"pogo C2R3 displaced", "fixture base moved",
                              "thermal growth of the fixture"};
    expected.correction = kPogoCorrection;
    expect_result(*rec, expected);

    const auto set = db.load_measurement_set("pm1-precal-1");
    ASSERT_TRUE(set);
    ASSERT_EQ(set->touches.size(), 2u);
    expect_touch(set->touches[0], "pogo_C2R3", {410.25, 220.5, 95.125, 0.0, 0.0, 0.0},
                 {0.0, 0.0, -1.0});
    expect_touch(set->touches[1], "pogo_C4R1", {610.75, 20.5, 95.0625, 0.0, 0.0, 0.0},
                 {0.0, 0.0, -1.0});
  }
  {
    const auto rec = db.find_check("pm2-master-1");
    ASSERT_TRUE(rec);
    EXPECT_EQ(rec->machine_id, "pm2");
    EXPECT_EQ(rec->kind, CheckKind::GlobalMasterFrame);
    expect_request(*rec, "operator:ada", 1780001200000000000, 1);
    expect_measurement(*rec, "laser_tracker", "tracker", 1780001260000000000, 0, 3);
    CheckResult expected;
    expected.verdict = Verdict::Invalid;
    expected.reason = "tracker_points: 3, the master frame needs 11";
    expected.time_ns = 1780001320000000000;
    expected.metrics = {{"master_orthogonality_urad", 12.5, "urad", -40.0, 40.0, true}};
    expect_result(*rec, expected);

    const auto set = db.load_measurement_set("pm2-master-1");
    ASSERT_TRUE(set);
    EXPECT_TRUE(set->touches.empty());
    ASSERT_EQ(set->tracker_points.size(), 3u);
    expect_point(set->tracker_points[0], "P0", {0.0, 0.0, 500.0, 0.0, 0.0, 0.0},
                 {1500.0078125, -250.00390625, 300.0});
    expect_point(set->tracker_points[1], "P1", {500.0, 0.0, 500.0, 0.0, 0.0, 0.0},
                 {2000.015625, -250.0078125, 300.001953125});
    expect_point(set->tracker_points[2], "P2", {0.0, 500.0, 500.0, 12.5, 0.25, -0.125},
                 {1499.9921875, 250.0, 300.0});
  }
  {
    const auto rec = db.find_check("pm2-master-2");
    ASSERT_TRUE(rec);
    expect_request(*rec, "operator:ada", 1780001800000000000, 1);
    expect_measurement(*rec, "laser_tracker", "tracker", 1780001860000000000, 0, 0,
                       "tracker lost the reflector at P2");
    EXPECT_FALSE(rec->result);
  }
  {
    const auto rec = db.find_check("pm1-late-1");
    ASSERT_TRUE(rec);
    EXPECT_EQ(rec->kind, CheckKind::MonumentPositioning);
    EXPECT_FALSE(rec->request);
    EXPECT_FALSE(rec->measurement);
    CheckResult expected;
    expected.verdict = Verdict::Pass;
    expected.time_ns = 1780002400000000000;
    expected.metrics = {{"center_dx_mm", 0.0009765625, "mm", -0.03125, 0.03125, true}};
    expect_result(*rec, expected);
  }
  EXPECT_EQ(db.last_pass_ns("pm1", CheckKind::MonumentPositioning), 1780002400000000000);
  EXPECT_EQ(db.last_pass_ns("pm1", CheckKind::FixturePreCalibration), std::nullopt);

  // Statuses, interventions, compensations, services, machines.
  const auto pm1_status = db.latest_status("pm1");
  ASSERT_TRUE(pm1_status);
  EXPECT_EQ(pm1_status->request_id, "pm1-precal-1");
  EXPECT_EQ(pm1_status->state, MachineState::NeedsIntervention);
  EXPECT_EQ(pm1_status->last_kind, CheckKind::FixturePreCalibration);
  EXPECT_EQ(pm1_status->last_verdict, Verdict::Fail);
  EXPECT_EQ(pm1_status->detail, "fixture_precal FAIL: pogo C2R3");
  EXPECT_EQ(pm1_status->time_ns, 1780000721000000000);
  const auto pm2_status = db.latest_status("pm2");
  ASSERT_TRUE(pm2_status);
  EXPECT_EQ(pm2_status->request_id, "");
  EXPECT_EQ(pm2_status->state, MachineState::Unknown);
  EXPECT_FALSE(pm2_status->last_kind);
  EXPECT_FALSE(pm2_status->last_verdict);
  EXPECT_EQ(pm2_status->detail, "scheduler started");
  EXPECT_EQ(pm2_status->time_ns, 1780000000000000000);

  const auto interventions = db.interventions("pm1");
  ASSERT_EQ(interventions.size(), 1u);
  EXPECT_EQ(interventions[0].intervention_id, "int-pm1-1");
  EXPECT_EQ(interventions[0].machine_id, "pm1");
  EXPECT_EQ(interventions[0].kind, CheckKind::FixturePreCalibration);
  EXPECT_EQ(interventions[0].note, "re-seated pogo C2R3, torqued to 12 N\u00b7m");
  EXPECT_EQ(interventions[0].operator_name, "ada");
  EXPECT_EQ(interventions[0].time_ns, 1780000900000000000);
  EXPECT_TRUE(db.interventions("pm2").empty());

  const auto compensations = db.compensations("pm1");
  ASSERT_EQ(compensations.size(), 1u);
  EXPECT_EQ(compensations[0].request_id, "pm1-precal-1");
  EXPECT_EQ(compensations[0].machine_id, "pm1");
  EXPECT_EQ(compensations[0].time_ns, 1780000720000000000);
  CheckResult with_correction;
  with_correction.correction = compensations[0].correction;
  CheckResult expected;
  expected.correction = kPogoCorrection;
  expect_result_eq(with_correction, expected);  // the correction's target and offsets

  const auto services = db.services();
  ASSERT_EQ(services.size(), 2u);
  EXPECT_EQ(services[0].service, "acquisition");
  EXPECT_EQ(services[0].instance, "cell-pc:4712");
  EXPECT_EQ(services[0].machine_id, "pm1");
  EXPECT_EQ(services[0].state, "running");
  EXPECT_EQ(services[0].time_ns, 1780002390000000000);
  EXPECT_EQ(services[1].service, "historian");
  EXPECT_EQ(services[1].instance, "cell-pc:4711");
  EXPECT_EQ(services[1].machine_id, "");
  EXPECT_EQ(services[1].time_ns, 1780002400000000000);

  EXPECT_EQ(db.machines(), (std::vector<std::string>{"pm1", "pm2"}));
  const auto pm1 = db.machine("pm1");
  ASSERT_TRUE(pm1);
  EXPECT_EQ(pm1->first_seen_ns, 1779999995000000000);
  EXPECT_EQ(pm1->last_seen_ns, 1780002400000000000);
  const auto pm2 = db.machine("pm2");
  ASSERT_TRUE(pm2);
  EXPECT_EQ(pm2->first_seen_ns, 1780000000000000000);
  EXPECT_EQ(pm2->last_seen_ns, 1780001860000000000);

  // The migrated file takes new samples, and the old identities still hold.
  EXPECT_FALSE(db.store(testing::make_result("pm1-c-align-1", "pm1")));
  CheckRequest request = testing::make_request("pm1-v2-1", "pm1", 1780003000000000000);
  request.parameters = {NamedValue{"fixture_configuration", 3, ""}};
  request.verifies_correction_of = "pm1-precal-1";
  ASSERT_TRUE(db.store(request));
  const auto stored = db.find_check("pm1-v2-1");
  ASSERT_TRUE(stored && stored->request);
  EXPECT_EQ(stored->request->verifies_correction_of, "pm1-precal-1");
  ASSERT_EQ(stored->request->parameters.size(), 1u);
  EXPECT_EQ(stored->request->parameters[0].value, 3);
}

// A historian of schema 10 (the version before sets and results said whether they were measured or
// simulated) takes schema 11's origin columns: its rows read back as Unknown (never assumed
// measured), and what is stored from then on keeps its origin, in the file as 'measured' or
// 'simulated' and nothing else.
TEST(StorageMigration, SetsAndResultsStoredBeforeSchemaElevenReadAsOfUnknownOrigin) {
  TempDir dir;
  const std::string path = dir.file("historian-v10.db");
  {
    std::string sql = "BEGIN; ";
    for (const auto& m : schema::migrations()) {
      if (m.version > 10) break;
      sql += m.sql;
    }
    create(path, sql + " PRAGMA user_version = 10; COMMIT;");
    RawDb raw(path);
    raw.exec(
        "INSERT INTO measurement_sets (request_id, machine_id, kind, instrument, frame, time_ns, "
        "error) VALUES ('old-1', 'pm1', 2, 'touch_probe', 'machine', 1000, '');"
        "INSERT INTO results (request_id, machine_id, kind, verdict, reason, time_ns) "
        "VALUES ('old-1', 'pm1', 2, 'PASS', '', 2000);"
        "INSERT INTO checks (request_id, machine_id, kind, measured_at_ns, result_at_ns) "
        "VALUES ('old-1', 'pm1', 2, 1000, 2000);");
  }
  Database db = Database::open(path);
  EXPECT_EQ(db.info().schema_version, 11);
  const auto old = db.find_check("old-1");
  ASSERT_TRUE(old && old->measurement && old->result);
  EXPECT_EQ(old->measurement->origin, DataOrigin::Unknown);
  EXPECT_EQ(old->result->origin, DataOrigin::Unknown);
  EXPECT_EQ(origin_of(*old), DataOrigin::Unknown);
  EXPECT_EQ(db.load_measurement_set("old-1")->origin, DataOrigin::Unknown);

  MeasurementSet set = make_measurement_set("sim-1", "pm1");
  set.origin = DataOrigin::Simulated;
  CheckResult result = make_result("sim-1", "pm1");
  result.kind = set.kind;
  result.origin = DataOrigin::Simulated;
  ASSERT_TRUE(db.store(set));
  ASSERT_TRUE(db.store(result));
  MeasurementSet measured = make_measurement_set("real-1", "pm1");
  measured.origin = DataOrigin::Measured;
  ASSERT_TRUE(db.store(measured));  // its result has not arrived: the set says
  const auto sim = db.find_check("sim-1");
  ASSERT_TRUE(sim && sim->measurement && sim->result);
  EXPECT_EQ(sim->measurement->origin, DataOrigin::Simulated);
  EXPECT_EQ(sim->result->origin, DataOrigin::Simulated);
  EXPECT_EQ(origin_of(*db.find_check("real-1")), DataOrigin::Measured);
  EXPECT_EQ(db.load_measurement_set("real-1")->origin, DataOrigin::Measured);

  RawDb raw(path);
  EXPECT_EQ(raw.text("SELECT origin FROM measurement_sets WHERE request_id = 'sim-1'"),
            "simulated");
  EXPECT_EQ(raw.text("SELECT origin FROM results WHERE request_id = 'sim-1'"), "simulated");
  EXPECT_EQ(raw.text("SELECT origin FROM measurement_sets WHERE request_id = 'real-1'"),
            "measured");
  EXPECT_EQ(raw.text("SELECT count(*) FROM results WHERE origin IS NULL"), "1");
  EXPECT_THROW(raw.exec("UPDATE results SET origin = 'guessed' WHERE request_id = 'old-1'"),
               std::runtime_error);
}

}  // namespace
}  // namespace ncqual::storage

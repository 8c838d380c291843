// SPDX-License-Identifier: Apache-2.0
// `ncqual db check`, `ncqual db recover`, `ncqual count`, the services and warnings of `ncqual
// status` and `ncqual trend --metric` without DDS: historian files written here with
// storage::Database, damaged by overwriting a page, and the built `ncqual` binary run on them.
// Recovery runs the sqlite3 shell (Debian package sqlite3), which the tests also use to find a page
// of a given table (its dbstat table).
#include "cli_runner.hpp"

#include "ncqual/storage/database.hpp"
#include "ncqual/storage/trend.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace ncqual {
namespace {

namespace fs = std::filesystem;

using namespace testing_cli;  // cli_runner.hpp

constexpr int kChecks = 300;
constexpr std::int64_t kT0 = 1'800'000'000'000'000'000;

CheckRequest request(int i) {
  CheckRequest r;
  r.machine_id = "m1";
  r.request_id = "req-" + std::to_string(i);
  r.kind = CheckKind::MonumentPositioning;
  r.requested_by = "scheduler";
  r.time_ns = kT0 + std::int64_t{i} * 1'000'000'000;
  return r;
}

MeasurementSet measurement(int i) {
  MeasurementSet s;
  s.machine_id = "m1";
  s.request_id = "req-" + std::to_string(i);
  s.kind = CheckKind::MonumentPositioning;
  s.instrument = "touch_probe";
  s.frame = "machine";
  s.time_ns = kT0 + std::int64_t{i} * 1'000'000'000 + 1000;
  for (int t = 0; t < 8; ++t) {
    Touch touch;
    touch.feature = "hole_edge";
    touch.axes.x_mm = 1200 + t;
    touch.axes.y_mm = 800 - t;
    touch.axes.z_mm = 150;
    touch.approach = Eigen::Vector3d(1, 0, 0);
    s.touches.push_back(touch);
  }
  return s;
}

CheckResult result(int i) {
  CheckResult r;
  r.machine_id = "m1";
  r.request_id = "req-" + std::to_string(i);
  r.kind = CheckKind::MonumentPositioning;
  r.verdict = i % 7 == 0 ? Verdict::Fail : Verdict::Pass;
  r.reason = i % 7 == 0 ? "center_dy_mm out of tolerance" : "";
  r.time_ns = kT0 + std::int64_t{i} * 1'000'000'000 + 2000;
  r.produced_by = "ncqual-solver test";
  r.metrics = {{"center_dx_mm", 0.001 * i, "mm", -0.025, 0.025, true},
               {"center_dy_mm", -0.0001 * i, "mm", -0.025, 0.025, i % 7 != 0},
               {"face_dz_mm", 0.002, "mm", -0.025, 0.025, true}};
  return r;
}

std::int64_t wall_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Overwrites `size` bytes at `offset` of the file with 0xFF.
void overwrite(const std::string& path, std::int64_t offset, std::size_t size) {
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  ASSERT_TRUE(f) << path;
  f.seekp(offset);
  const std::string garbage(size, '\xff');
  f.write(garbage.data(), static_cast<std::streamsize>(garbage.size()));
  ASSERT_TRUE(f) << path;
}

// `sqlite3 -readonly FILE SQL`: its output lines (list mode, '|' between columns).
std::vector<std::string> sqlite_lines(const std::string& file, const std::string& sql) {
  const CliRun r = run_command({"sqlite3", "-batch", "-readonly", "-noheader", "-list", file, sql},
                               Capture::Separate);
  EXPECT_EQ(r.exit_code, 0) << sql << "\n" << r.err;
  std::vector<std::string> lines;
  std::istringstream in(r.out);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

class DbCli : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return (tmp_.path() / name).string(); }

  // kChecks whole checks (request, measurement set with 8 touches, result with 3 metrics) and a
  // status per check: 1200 stored samples, a file of over a hundred pages. Closing the last
  // connection checkpoints the WAL into the file.
  std::string historian(const std::string& name) {
    std::string file = path(name);
    {
      auto db = storage::Database::open(file);
      for (int i = 0; i < kChecks; ++i) {
        db.store(request(i));
        db.store(measurement(i));
        db.store(result(i));
        MachineStatus status;
        status.machine_id = "m1";
        status.request_id = "req-" + std::to_string(i);
        status.state = i % 7 == 0 ? MachineState::NeedsIntervention : MachineState::Qualified;
        status.time_ns = kT0 + std::int64_t{i} * 1'000'000'000 + 3000;
        db.store(status);
      }
    }
    EXPECT_TRUE(!fs::exists(file + "-wal") || fs::file_size(file + "-wal") == 0)
        << "the WAL was not checkpointed into " << file;
    return file;
  }

  std::string write_plant(const std::string& db_file, const std::string& extra = "") {
    const std::string machine = tmp_.write("m1.yaml", R"(machine_id: m1
probe: {tool_length_mm: 350.0, ball_radius_mm: 3.0}
monument: {hole_center_mm: [1200.0, 800.0], hole_diameter_mm: 50.0, face_z_mm: 150.0}
tolerances:
  center_dx_mm: 0.025
  center_dy_mm: 0.025
  face_dz_mm: 0.025
)");
    return tmp_.write("plant.yaml",
                      "plant: db-test\ndomain_id: 0\nsimulated: true\nhistorian:\n  database: " +
                          db_file + "\nmachines:\n  - " + machine + "\n" + extra);
  }

  testing_cli::TempDir tmp_{"ncqual-db-cli"};
};

TEST_F(DbCli, CheckOfAnIntactHistorianIsOk) {
  const std::string file = historian("good.db");
  const CliRun r = run_cli({"db", "check", "--db", file}, Capture::Separate);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(r.out, file + ": ok\n");
}

// A leaf page of the results table in the middle of the file is overwritten with 0xFF: the check
// finds it, and the recovery keeps every other row (rows on that page cannot be read by anyone).
TEST_F(DbCli, CheckFindsADamagedPageAndRecoverKeepsTheRest) {
  const std::string file = historian("damaged.db");
  const std::int64_t page_size = std::stoll(sqlite_lines(file, "PRAGMA page_size").at(0));
  const std::int64_t pages = std::stoll(sqlite_lines(file, "PRAGMA page_count").at(0));
  ASSERT_GT(pages, 100) << "too few pages for a page in the middle";
  // The leaf of `results` nearest the middle, and how many rows it holds.
  const auto leaves =
      sqlite_lines(file,
                   "SELECT pageno, ncell FROM dbstat WHERE name = 'results' AND pagetype = 'leaf' "
                   "ORDER BY abs(pageno - " +
                       std::to_string(pages / 2) + ") LIMIT 1");
  ASSERT_EQ(leaves.size(), 1u);
  const auto bar = leaves[0].find('|');
  const std::int64_t page = std::stoll(leaves[0].substr(0, bar));
  const int rows_on_page = std::stoi(leaves[0].substr(bar + 1));
  ASSERT_GT(rows_on_page, 0);
  ASSERT_LT(rows_on_page, kChecks / 4) << "a results page holds a few dozen rows";
  overwrite(file, (page - 1) * page_size, static_cast<std::size_t>(page_size));
  const std::string damaged = read_file(file);

  const CliRun check = run_cli({"db", "check", "--db", file}, Capture::Separate);
  EXPECT_EQ(check.exit_code, 7) << check.out << check.err;
  EXPECT_EQ(check.out.rfind(file + ": CORRUPT\n", 0), 0u) << check.out;
  // SQLite names the page, or (when its integrity_check stops at the page) says it is malformed.
  EXPECT_TRUE(check.out.find("Page " + std::to_string(page)) != std::string::npos ||
              check.out.find("malformed") != std::string::npos)
      << check.out;
  EXPECT_EQ(check.out.find(": ok"), std::string::npos) << check.out;

  const bool had_wal = fs::exists(file + "-wal");  // a reader (db check) may have made one
  const std::string to = path("recovered/historian.db");
  const CliRun recover = run_cli({"db", "recover", file, to}, Capture::Separate);
  ASSERT_EQ(recover.exit_code, 0) << recover.out << recover.err;
  EXPECT_NE(recover.out.find(to + ": ok (PRAGMA integrity_check)"), std::string::npos)
      << recover.out;
  EXPECT_NE(recover.out.find("start the historian with --db " + to), std::string::npos)
      << recover.out;
  EXPECT_EQ(read_file(file), damaged) << "db recover wrote to " << file;
  EXPECT_EQ(fs::exists(file + "-wal"), had_wal);

  // TO is a historian of this build's schema (open_readonly checks application_id and
  // user_version) that passes the integrity check, and everything in it reads back as stored.
  ASSERT_TRUE(fs::exists(to));
  auto db = storage::Database::open_readonly(to);
  EXPECT_EQ(db.integrity_check(), "ok");
  const std::int64_t results = db.count_results();
  // Only the rows of the overwritten page are lost: the other pages of results are intact.
  EXPECT_GE(results, kChecks - rows_on_page) << recover.out;
  EXPECT_LT(results, kChecks) << "the rows of the overwritten page cannot have been read";
  EXPECT_NE(recover.out.find("results           " + std::to_string(results) + "\n"),
            std::string::npos)
      << recover.out;
  storage::HistoryQuery all;
  all.limit = 0;
  const auto records = db.history(all);
  ASSERT_EQ(records.size(), static_cast<std::size_t>(kChecks))
      << "requests and measurement sets lie on intact pages";
  std::int64_t with_result = 0;
  for (const auto& record : records) {
    const int i = std::stoi(record.request_id.substr(4));
    ASSERT_TRUE(record.request) << record.request_id;
    EXPECT_EQ(record.request->time_ns, request(i).time_ns);
    ASSERT_TRUE(record.measurement) << record.request_id;
    EXPECT_EQ(record.measurement->touches, 8);
    if (!record.result) continue;
    ++with_result;
    const CheckResult expected = result(i);
    EXPECT_EQ(record.result->verdict, expected.verdict) << record.request_id;
    EXPECT_EQ(record.result->time_ns, expected.time_ns) << record.request_id;
    EXPECT_EQ(record.result->produced_by, expected.produced_by) << record.request_id;
    ASSERT_EQ(record.result->metrics.size(), expected.metrics.size()) << record.request_id;
    EXPECT_DOUBLE_EQ(record.result->metrics[0].value, expected.metrics[0].value);
  }
  EXPECT_EQ(with_result, results);
  const auto set = db.load_measurement_set("req-" + std::to_string(kChecks - 1));
  ASSERT_TRUE(set);
  EXPECT_EQ(set->touches.size(), 8u);
  EXPECT_DOUBLE_EQ(set->touches[3].axes.x_mm, 1203);
}

TEST_F(DbCli, CheckOfAFileTooDamagedToReadIsCorrupt) {
  const std::string file = historian("schema-gone.db");
  overwrite(file, 100, 4096 - 100);  // page 1 after the file header: the schema table
  const CliRun r = run_cli({"db", "check", "--db", file}, Capture::Separate);
  EXPECT_EQ(r.exit_code, 7) << r.out << r.err;
  EXPECT_EQ(r.out.rfind(file + ": CORRUPT\n", 0), 0u) << r.out;
  EXPECT_NE(r.out.find("malformed"), std::string::npos) << r.out;
}

TEST_F(DbCli, CheckOfAFileThatIsNoHistorianFailsNamingIt) {
  const std::string text = tmp_.write("notes.db",
                                      "not a database at all, but long enough to "
                                      "fill the hundred bytes of a file header ......"
                                      "..............................................");
  const CliRun r = run_cli({"db", "check", "--db", text}, Capture::Separate);
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_EQ(r.out.find("ok"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find(text), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not a database"), std::string::npos) << r.err;

  const std::string other = path("other.db");
  ASSERT_EQ(
      run_command({"sqlite3", other, "CREATE TABLE t (x); INSERT INTO t VALUES (1);"}).exit_code,
      0);
  const CliRun foreign = run_cli({"db", "check", "--db", other}, Capture::Separate);
  EXPECT_EQ(foreign.exit_code, 1) << foreign.out << foreign.err;
  EXPECT_EQ(foreign.out.find("ok"), std::string::npos) << foreign.out;
  EXPECT_NE(foreign.err.find("'" + other + "': no ncqual schema in it"), std::string::npos)
      << foreign.err;
}

TEST_F(DbCli, RecoverRefusesAnExistingTargetAndAMissingSource) {
  const std::string file = historian("from.db");
  const std::string existing = tmp_.write("existing.db", "keep me");
  const CliRun exists = run_cli({"db", "recover", file, existing}, Capture::Separate);
  EXPECT_EQ(exists.exit_code, 1) << exists.out << exists.err;
  EXPECT_NE(exists.err.find(existing + " exists; it is never overwritten"), std::string::npos)
      << exists.err;
  EXPECT_EQ(read_file(existing), "keep me");

  const std::string missing = path("missing.db");
  const std::string to = path("new.db");
  const CliRun none = run_cli({"db", "recover", missing, to}, Capture::Separate);
  EXPECT_EQ(none.exit_code, 6) << none.out << none.err;
  EXPECT_NE(none.err.find("no historian database at " + missing), std::string::npos) << none.err;
  EXPECT_FALSE(fs::exists(to));
}

// A historian of schema version 1 (tests/data/historian-v1.sql) recovers into a file of the same
// version, which the historian of this build migrates when it opens it.
TEST_F(DbCli, RecoverKeepsAnOlderSchemaVersionForTheHistorianToMigrate) {
  const std::string v1 = path("v1.db");
  ASSERT_EQ(run_command({"sqlite3", v1, ".read " NCQUAL_SOURCE_DIR "/tests/data/historian-v1.sql"})
                .exit_code,
            0);
  const std::string to = path("v1-recovered.db");
  const CliRun r = run_cli({"db", "recover", v1, to}, Capture::Separate);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find(to + " has schema version 1, this build's is " +
                       std::to_string(storage::Database::latest_schema_version()) +
                       ": the historian of this build migrates it"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("results           4\n"), std::string::npos) << r.out;
  auto db = storage::Database::open(to);  // migrates, after PRAGMA quick_check
  EXPECT_EQ(db.info().schema_version, storage::Database::latest_schema_version());
  const auto precal = db.find_check("pm1-precal-1");
  ASSERT_TRUE(precal && precal->result);
  EXPECT_EQ(precal->result->verdict, Verdict::Fail);
  ASSERT_EQ(precal->result->metrics.size(), 2u);
  EXPECT_DOUBLE_EQ(precal->result->metrics[0].value, 0.046875);
  EXPECT_TRUE(std::isinf(precal->result->metrics[1].lower)) << "a one-sided band survives";
  EXPECT_EQ(db.count_results(), 4);
}

// `ncqual history` and `trend` show a metric with the resolution its tolerance needs (a tenth of
// the band):
// 350.0601 mm against +-0.025 mm is 350.060, out of tolerance, never a rounded 350.1.
TEST_F(DbCli, HistoryShowsAMetricToATenthOfItsTolerance) {
  const std::string file = path("resolution.db");
  {
    auto db = storage::Database::open(file);
    CheckResult r = result(1);
    r.verdict = Verdict::Fail;
    r.metrics = {{"tool_length_mm", 350.0601, "mm", 349.975, 350.025, false}};
    db.store(request(1));
    db.store(r);
  }
  const CliRun r = run_cli({"history", "--db", file}, Capture::Separate);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("tool_length_mm=350.060(!)"), std::string::npos) << r.out;
  // `trend` printed it as 350.1 mm (4 significant digits).
  const CliRun t = run_cli({"trend", "--machine", "m1", "--db", file, "--plant", write_plant(file)},
                           Capture::Separate);
  ASSERT_EQ(t.exit_code, 0) << t.out << t.err;
  EXPECT_NE(t.out.find("350.060 mm (!)"), std::string::npos) << t.out;
}

// Issue 14: `history` printed UTC while `status` printed the plant's local time, and nothing said
// who ordered a check. Both now read in the plant's zone with the offset; each row names who
// ordered it.
TEST_F(DbCli, HistoryIsInThePlantsTimeZoneWithTheOffsetAndSaysWhoOrdered) {
  const std::string file = path("zone.db");
  {
    auto db = storage::Database::open(file);
    CheckRequest ordered = request(1);
    ordered.requested_by = "operator:ann";
    db.store(ordered);
    db.store(result(1));
    db.store(request(2));  // the scheduler's, no result yet
  }
  // 2027-01-15 08:00:01Z is 09:00:01 in Berlin (CET, +01:00).
  const CliRun local =
      run_cli({"history", "--db", file, "--plant",
               write_plant(file, "scheduler:\n  calendar:\n    time_zone: Europe/Berlin\n")},
              Capture::Separate);
  ASSERT_EQ(local.exit_code, 0) << local.out << local.err;
  EXPECT_NE(local.out.find("time (Europe/Berlin)"), std::string::npos) << local.out;
  EXPECT_NE(local.out.find("2027-01-15 09:00:01 +01:00 CET"), std::string::npos) << local.out;
  EXPECT_NE(local.out.find("ordered by"), std::string::npos) << local.out;
  EXPECT_NE(local.out.find("operator:ann"), std::string::npos) << local.out;
  EXPECT_NE(local.out.find("pending  unknown    scheduler"), std::string::npos) << local.out;
  // Without a plant config: UTC, still with its offset.
  const CliRun utc = run_cli({"history", "--db", file}, Capture::Separate);
  ASSERT_EQ(utc.exit_code, 0) << utc.out << utc.err;
  EXPECT_NE(utc.out.find("2027-01-15 08:00:01 +00:00 UTC"), std::string::npos) << utc.out;
}

// Issue 37 point 7: dates on the command line are read in the plant's zone. In Berlin (CET,
// +01:00 in January) 2027-01-14 23:30Z is 00:30 on the 15th and 22:30Z is 23:30 on the 14th:
// `--since 2027-01-15` (local midnight, 23:00Z) takes the first and not the second. A time with Z
// or an offset means what it says.
TEST_F(DbCli, CommandLineDatesAreReadInThePlantsTimeZone) {
  const std::string file = path("since.db");
  constexpr std::int64_t kLocal0030 = 1'799'969'400'000'000'000;  // 2027-01-14T23:30:00Z
  constexpr std::int64_t kLocal2330 = 1'799'965'800'000'000'000;  // 2027-01-14T22:30:00Z
  {
    auto db = storage::Database::open(file);
    for (const auto& [i, t] : {std::pair{1, kLocal0030}, std::pair{2, kLocal2330}}) {
      CheckRequest q = request(i);
      q.time_ns = t;
      db.store(q);
      CheckResult r = result(i);
      r.time_ns = t + 60'000'000'000;
      db.store(r);
    }
  }
  const std::string berlin =
      write_plant(file, "scheduler:\n  calendar:\n    time_zone: Europe/Berlin\n");
  const auto trend_ids = [&](const std::vector<std::string>& range, const std::string& plant) {
    std::vector<std::string> args{"trend",  "--machine", "m1", "--metric", "center_dx_mm",
                                  "--json", "--db",      file, "--plant",  plant};
    args.insert(args.end(), range.begin(), range.end());
    const CliRun r = run_cli(args, Capture::Separate);
    EXPECT_EQ(r.exit_code, 0) << joined(args) << "\n" << r.out << r.err;
    std::set<std::string> ids;
    if (r.exit_code != 0) return ids;
    const nlohmann::json doc = nlohmann::json::parse(r.out);
    for (const auto& p : doc.at("points")) {
      ids.insert(p.at("request_id").get<std::string>());
    }
    return ids;
  };
  EXPECT_EQ(trend_ids({"--since", "2027-01-15"}, berlin), std::set<std::string>{"req-1"});
  EXPECT_EQ(trend_ids({"--until", "2027-01-15"}, berlin), std::set<std::string>{"req-2"});
  EXPECT_EQ(trend_ids({"--since", "2027-01-15T00:15"}, berlin), std::set<std::string>{"req-1"});
  EXPECT_EQ(trend_ids({"--since", "2027-01-14T22:00Z"}, berlin),
            (std::set<std::string>{"req-1", "req-2"}));
  EXPECT_EQ(trend_ids({"--since", "2027-01-15T00:00+02:00"}, berlin),
            (std::set<std::string>{"req-1", "req-2"}));
  // `export` reads --since the same way and says its range in the zone; the files keep UTC.
  const std::string dir = path("since-export");
  const CliRun e =
      run_cli({"export", "--db", file, "--plant", berlin, "--since", "2027-01-15", "--csv", dir},
              Capture::Separate);
  ASSERT_EQ(e.exit_code, 0) << e.out << e.err;
  EXPECT_NE(e.out.find("from 2027-01-15 00:00:00 +01:00 CET to the newest row"), std::string::npos)
      << e.out;
  const std::string requests = read_file(dir + "/requests.csv");
  EXPECT_NE(requests.find("\nreq-1,"), std::string::npos) << requests;
  EXPECT_EQ(requests.find("req-2"), std::string::npos) << requests;
  // The same check in `history`, read in the same zone: its result, a minute after 00:30 local.
  const CliRun h = run_cli({"history", "--db", file, "--plant", berlin}, Capture::Separate);
  ASSERT_EQ(h.exit_code, 0) << h.err;
  EXPECT_NE(h.out.find("2027-01-15 00:31:00 +01:00 CET"), std::string::npos) << h.out;
  // A date the zone cannot read is named with the zone.
  const CliRun bad = run_cli({"trend", "--machine", "m1", "--metric", "center_dx_mm", "--since",
                              "15.01.2027", "--db", file, "--plant", berlin},
                             Capture::Separate);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--since '15.01.2027': expected a date or time in the plant's time zone "
                         "(Europe/Berlin)"),
            std::string::npos)
      << bad.err;
}

TEST_F(DbCli, CountOfAMissingDatabaseIsNotFound) {
  const std::string missing = path("gone.db");
  const CliRun r = run_cli({"count", "--db", missing}, Capture::Separate);
  EXPECT_EQ(r.exit_code, 6) << r.out << r.err;
  EXPECT_EQ(r.out, "") << "a missing historian must not print a count";
  EXPECT_NE(r.err.find("ncqual count: no historian database at " + missing), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(missing)) << "count must not create the database";

  const std::string file = historian("counted.db");
  const CliRun counted = run_cli({"count", "--db", file}, Capture::Separate);
  EXPECT_EQ(counted.exit_code, 0) << counted.err;
  EXPECT_EQ(counted.out, std::to_string(kChecks) + "\n");
}

TEST_F(DbCli, StatusShowsServicesHealthSilenceAndConflicts) {
  const std::string file = path("status.db");
  const std::int64_t now = wall_now_ns();
  {
    auto db = storage::Database::open(file);
    Heartbeat failed;
    failed.service = "historian";
    failed.instance = "host:101";
    failed.state = "running";
    failed.time_ns = now;
    failed.health = "failed";
    failed.health_detail = "disk full: /var/ncqual/historian.db";
    db.store(failed);
    Heartbeat busy;
    busy.service = "solver";
    busy.instance = "host:102";
    busy.state = "running";
    busy.time_ns = now;
    busy.outbox_depth = 4;
    busy.oldest_unacknowledged_ns = now - 90'000'000'000;
    db.store(busy);
    Heartbeat gone;
    gone.service = "acquisition";
    gone.instance = "host:103";
    gone.machine_id = "m1";
    gone.state = "running";
    gone.time_ns = now - 3'600'000'000'000;  // an hour ago: silent
    db.store(gone);
    // Two results with one request id and other content: the second is kept as a conflict.
    CheckResult first = result(1);
    EXPECT_EQ(db.store(first, {"hash-a", "writer-1", now}).outcome, storage::StoreOutcome::Stored);
    CheckResult second = result(1);
    second.verdict = Verdict::Fail;
    EXPECT_EQ(db.store(second, {"hash-b", "writer-2", now}).outcome,
              storage::StoreOutcome::Conflict);
  }
  const std::string plant = write_plant(file);

  const CliRun json = run_cli({"status", "--plant", plant, "--json"}, Capture::Separate);
  ASSERT_EQ(json.exit_code, 0) << json.out << json.err;
  const nlohmann::json doc = nlohmann::json::parse(json.out);
  EXPECT_EQ(doc.at("plant"), "db-test");  // the keys that were there stay
  ASSERT_EQ(doc.at("machines").size(), 1u);
  EXPECT_EQ(doc.at("machines")[0].at("machine_id"), "m1");
  EXPECT_TRUE(doc.at("machines")[0].contains("periods"));
  EXPECT_EQ(doc.at("machines")[0].at("conflicts"), 1);
  EXPECT_EQ(doc.at("heartbeat_period_ms"), 2000);
  std::map<std::string, nlohmann::json> services;
  for (const auto& s : doc.at("services")) services[s.at("service").get<std::string>()] = s;
  ASSERT_EQ(services.size(), 3u) << json.out;
  const auto& historian = services.at("historian");
  EXPECT_EQ(historian.at("instance"), "host:101");
  EXPECT_EQ(historian.at("health"), "failed");
  EXPECT_EQ(historian.at("health_detail"), "disk full: /var/ncqual/historian.db");
  EXPECT_EQ(historian.at("silent"), false);
  EXPECT_EQ(historian.at("time_ns"), now);
  EXPECT_TRUE(historian.at("oldest_unacknowledged_age_ns").is_null());
  const auto& solver = services.at("solver");
  EXPECT_EQ(solver.at("health"), "ok");
  EXPECT_EQ(solver.at("outbox_depth"), 4);
  EXPECT_EQ(solver.at("oldest_unacknowledged_age_ns"), 90'000'000'000);
  const auto& acquisition = services.at("acquisition");
  EXPECT_EQ(acquisition.at("silent"), true);
  EXPECT_EQ(acquisition.at("liveness"), "stale");
  EXPECT_EQ(acquisition.at("machine_id"), "m1");
  EXPECT_GE(acquisition.at("age_ns").get<std::int64_t>(), 3'600'000'000'000);

  const CliRun text = run_cli({"status", "--plant", plant}, Capture::Separate);
  EXPECT_EQ(text.exit_code, 0) << text.out << text.err;
  EXPECT_NE(text.out.find("CONFLICT: 1"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("!! SERVICE FAILED: historian host:101: disk full: "
                          "/var/ncqual/historian.db"),
            std::string::npos)
      << text.out;
  EXPECT_NE(text.out.find("FAILED"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("stale since"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("90 s"), std::string::npos) << "the solver's oldest sample\n" << text.out;
}

// Issue 37 point 5: whether a check's numbers were measured on the machine or produced by
// ncqual's simulator is said by every output: `history` (its data column, --json "origin"),
// `status` (the newest check), `trend` (both forms) and `export` (results.csv and
// measurement_sets.csv, column origin). A check stored before the historian recorded it says
// "unknown" (an empty field in the CSV), never "measured".
TEST_F(DbCli, HistoryStatusTrendAndExportSayWhetherAChecksDataWasMeasuredOrSimulated) {
  const std::string file = path("origin.db");
  {
    auto db = storage::Database::open(file);
    for (int i = 1; i <= 3; ++i) {
      MeasurementSet set = measurement(i);
      CheckResult r = result(i);
      // req-1 before the historian recorded it, req-2 measured, req-3 (the newest) simulated.
      set.origin = r.origin = i == 1   ? DataOrigin::Unknown
                              : i == 2 ? DataOrigin::Measured
                                       : DataOrigin::Simulated;
      db.store(request(i));
      db.store(set);
      db.store(r);
    }
  }
  const std::string plant = write_plant(file);

  const CliRun history = run_cli({"history", "--plant", plant}, Capture::Separate);
  ASSERT_EQ(history.exit_code, 0) << history.out << history.err;
  EXPECT_NE(history.out.find(" data "), std::string::npos) << history.out;
  for (const char* row : {"PASS     SIMULATED  scheduler", "PASS     measured   scheduler",
                          "PASS     unknown    scheduler"}) {
    EXPECT_NE(history.out.find(row), std::string::npos) << row << "\n" << history.out;
  }
  const CliRun json = run_cli({"history", "--plant", plant, "--json"}, Capture::Separate);
  ASSERT_EQ(json.exit_code, 0) << json.out << json.err;
  std::map<std::string, std::pair<std::string, std::string>> origins;  // check, its measurement
  for (const auto& record : nlohmann::json::parse(json.out)) {
    origins[record.at("request_id").get<std::string>()] = {
        record.at("origin").get<std::string>(),
        record.at("measurement").at("origin").get<std::string>()};
  }
  EXPECT_EQ(origins, (std::map<std::string, std::pair<std::string, std::string>>{
                         {"req-1", {"unknown", "unknown"}},
                         {"req-2", {"measured", "measured"}},
                         {"req-3", {"simulated", "simulated"}}}));

  const CliRun status = run_cli({"status", "--plant", plant}, Capture::Separate);
  ASSERT_EQ(status.exit_code, 0) << status.out << status.err;
  EXPECT_NE(status.out.find("SIMULATED DATA: its last check (req-3) was produced by ncqual's "
                            "simulator and says nothing about the machine"),
            std::string::npos)
      << status.out;
  const CliRun status_json = run_cli({"status", "--plant", plant, "--json"}, Capture::Separate);
  ASSERT_EQ(status_json.exit_code, 0) << status_json.err;
  const nlohmann::json machine = nlohmann::json::parse(status_json.out).at("machines").at(0);
  EXPECT_EQ(machine.at("last_check"), "req-3");
  EXPECT_EQ(machine.at("last_check_origin"), "simulated");

  const CliRun trend = run_cli({"trend", "--machine", "m1", "--plant", plant}, Capture::Separate);
  ASSERT_EQ(trend.exit_code, 0) << trend.out << trend.err;
  EXPECT_NE(trend.out.find("SIMULATED DATA: ncqual's simulator produced 1 of its 3 checks, not "
                           "measured on the machine"),
            std::string::npos)
      << trend.out;
  const CliRun metric =
      run_cli({"trend", "--machine", "m1", "--metric", "center_dx_mm", "--plant", plant},
              Capture::Separate);
  ASSERT_EQ(metric.exit_code, 0) << metric.out << metric.err;
  EXPECT_NE(metric.out.find("SIMULATED DATA: ncqual's simulator produced 1 of these 3 checks, "
                            "not measured on the machine"),
            std::string::npos)
      << metric.out;

  const std::string dir = path("origin-export");
  const CliRun exported = run_cli(
      {"export", "--plant", plant, "--since", "2000-01-01", "--csv", dir}, Capture::Separate);
  ASSERT_EQ(exported.exit_code, 0) << exported.out << exported.err;
  for (const char* table : {"results", "measurement_sets"}) {
    std::istringstream lines(read_file(dir + "/" + table + ".csv"));
    const auto fields = [](const std::string& line) {
      std::vector<std::string> out(1);
      for (char c : line) {
        if (c == ',') {
          out.emplace_back();
        } else if (c != '\r') {
          out.back() += c;
        }
      }
      return out;
    };
    std::string line;
    std::getline(lines, line);
    const std::vector<std::string> header = fields(line);
    const auto column = std::find(header.begin(), header.end(), "origin") - header.begin();
    ASSERT_LT(static_cast<std::size_t>(column), header.size()) << table << ": " << line;
    std::map<std::string, std::string> by_request;
    while (std::getline(lines, line)) {
      const std::vector<std::string> row = fields(line);
      ASSERT_EQ(row.size(), header.size()) << line;
      by_request[row[0]] = row[static_cast<std::size_t>(column)];
    }
    EXPECT_EQ(by_request, (std::map<std::string, std::string>{
                              {"req-1", ""}, {"req-2", "measured"}, {"req-3", "simulated"}}))
        << table;
  }
}

// `ncqual trend --metric` on the hand-worked example of docs/trends.md (checks on 5 consecutive
// days of 1.0, 1.2, 1.1, 1.5, 1.7 mm against an upper limit of 2.5 mm): b = 0.17 mm/day, 95 %
// interval [0.039, 0.301], a = 0.96 mm, s = 0.1304 mm; the line reaches 2.5 mm at day 9.06, the
// upper prediction bound at day 5.34, the lower at day 33.6. An INVALID check without a value is
// counted, not used. Then `status` shows a warning the historian stored.
TEST_F(DbCli, TrendOfAMetricGivesTheHandWorkedFiguresAndStatusShowsItsWarning) {
  const std::string file = path("trend.db");
  constexpr std::int64_t kDay = 86'400'000'000'000;
  const double values[] = {1.0, 1.2, 1.1, 1.5, 1.7};
  {
    auto db = storage::Database::open(file);
    for (int day = 0; day < 5; ++day) {
      CheckResult r = result(day);
      r.verdict = Verdict::Pass;
      r.time_ns = kT0 + day * kDay;
      r.metrics = {{"center_dy_mm", values[day], "mm", -2.5, 2.5, true}};
      db.store(r);
    }
    CheckResult invalid = result(9);
    invalid.verdict = Verdict::Invalid;
    invalid.time_ns = kT0 + 2 * kDay + kDay / 2;
    invalid.metrics = {{"center_dy_mm", std::nan(""), "mm", -2.5, 2.5, false}};
    db.store(invalid);
    storage::TrendWarningRecord w;
    w.check_kind = CheckKind::MonumentPositioning;
    w.kind = "forecast";
    w.side = "above";
    w.started_ns = kT0 + 4 * kDay;
    w.expected_crossing_ns = kT0 + 9 * kDay;
    w.earliest_crossing_ns = kT0 + 5 * kDay;
    w.text = "center_dy_mm drifts +0.17 mm/day";
    storage::apply_trend_warnings(db, "m1", "center_dy_mm", {w}, "req-4", kT0 + 4 * kDay);
  }
  const std::string plant = write_plant(file);
  const CliRun json = run_cli({"trend", "--machine", "m1", "--metric", "center_dy_mm", "--json",
                               "--db", file, "--plant", plant},
                              Capture::Separate);
  ASSERT_EQ(json.exit_code, 0) << json.out << json.err;
  const auto doc = nlohmann::json::parse(json.out);
  EXPECT_EQ(doc.at("checks"), 6);
  EXPECT_EQ(doc.at("not_evaluated"), 1);
  EXPECT_EQ(doc.at("segment_points"), 5);
  EXPECT_EQ(doc.at("pass_rate").at("pass"), 5);
  EXPECT_EQ(doc.at("pass_rate").at("invalid"), 1);
  const auto& ls = doc.at("least_squares");
  EXPECT_NEAR(ls.at("slope_per_day").get<double>(), 0.17, 1e-12);
  EXPECT_NEAR(ls.at("intercept").get<double>(), 0.96, 1e-12);
  EXPECT_NEAR(ls.at("residual_sd").get<double>(), 0.13038, 1e-5);
  EXPECT_NEAR(ls.at("slope_low").get<double>(), 0.039, 1e-3);
  EXPECT_NEAR(ls.at("slope_high").get<double>(), 0.301, 1e-3);
  EXPECT_TRUE(ls.at("trend").get<bool>());
  EXPECT_EQ(ls.at("heading"), "above");
  const auto day_of = [&](const nlohmann::json& date) {
    return static_cast<double>(date.at("time_ns").get<std::int64_t>() - kT0) / kDay;
  };
  EXPECT_NEAR(day_of(ls.at("expected")), 9.0588, 1e-3);
  EXPECT_NEAR(day_of(ls.at("earliest")), 5.34, 5e-3);
  EXPECT_NEAR(day_of(ls.at("latest")), 33.6, 0.05);
  EXPECT_EQ(doc.at("theil_sen").at("method"), "theil_sen");
  // Pairwise slopes 0.2, 0.05, 0.1667, 0.175, -0.1, 0.15, 0.1667, 0.4, 0.3, 0.2: median 0.1708.
  EXPECT_NEAR(doc.at("theil_sen").at("slope_per_day").get<double>(), (0.1667 + 0.175) / 2, 1e-3);
  ASSERT_EQ(doc.at("warnings").size(), 1u) << "the forecast is active now (horizon 30 days)";
  EXPECT_EQ(doc.at("warnings")[0].at("kind"), "forecast");
  ASSERT_EQ(doc.at("raised").size(), 1u);
  EXPECT_EQ(doc.at("raised")[0].at("raised_by"), "req-4");
  EXPECT_EQ(doc.at("points").size(), 6u);
  EXPECT_TRUE(doc.at("points")[3].at("value").is_null()) << doc.at("points")[3];

  const CliRun csv = run_cli({"trend", "--machine", "m1", "--metric", "center_dy_mm", "--csv",
                              "--last", "2", "--db", file, "--plant", plant},
                             Capture::Separate);
  ASSERT_EQ(csv.exit_code, 0) << csv.err;
  EXPECT_EQ(
      csv.out.rfind("time_ns,time_utc,request_id,kind,value,lower,upper,verdict,in_segment,", 0),
      0u)
      << csv.out;
  EXPECT_NE(csv.out.find(",req-4,monument_positioning,1.7,-2.5,2.5,PASS,1,"), std::string::npos)
      << csv.out;
  EXPECT_EQ(std::count(csv.out.begin(), csv.out.end(), '\n'), 3) << "a header and 2 checks";

  const CliRun text = run_cli(
      {"trend", "--machine", "m1", "--metric", "center_dy_mm", "--db", file, "--plant", plant},
      Capture::Separate);
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("a trend"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("warnings now:"), std::string::npos) << text.out;

  const CliRun unknown = run_cli(
      {"trend", "--machine", "m1", "--metric", "centre_dy_mm", "--db", file, "--plant", plant},
      Capture::Separate);
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("'centre_dy_mm'"), std::string::npos) << unknown.err;
  EXPECT_NE(unknown.err.find("center_dy_mm"), std::string::npos) << "lists what it has\n"
                                                                 << unknown.err;
  // A machine of many metrics (a fixture check names every pogo's): the nearest few by name.
  {
    auto db = storage::Database::open(file);
    CheckResult fixture = result(20);
    fixture.kind = CheckKind::FixturePreCalibration;
    fixture.verdict = Verdict::Pass;
    fixture.time_ns = kT0 + 5 * kDay;
    fixture.metrics.clear();
    for (int column = 1; column <= 4; ++column) {
      for (int row = 1; row <= 5; ++row) {
        fixture.metrics.push_back(
            {"pogo_C" + std::to_string(column) + "R" + std::to_string(row) + "_dz_mm", 0.001, "mm",
             -0.05, 0.05, true});
      }
    }
    db.store(fixture);
  }
  const CliRun near = run_cli(
      {"trend", "--machine", "m1", "--metric", "pogo_C3R2_dz", "--db", file, "--plant", plant},
      Capture::Separate);
  EXPECT_EQ(near.exit_code, 2);
  EXPECT_NE(near.err.find("the nearest of its 21 metrics: pogo_C3R2_dz_mm, "), std::string::npos)
      << near.err;
  EXPECT_EQ(near.err.find("pogo_C4R5_dz_mm"), std::string::npos) << "not all 21\n" << near.err;
  EXPECT_EQ(run_cli({"trend", "--machine", "m1", "--json", "--db", file, "--plant", plant},
                    Capture::Separate)
                .exit_code,
            2)
      << "--json without --metric";

  const CliRun status =
      run_cli({"status", "--json", "--db", file, "--plant", plant}, Capture::Separate);
  ASSERT_EQ(status.exit_code, 0) << status.err;
  const auto warnings = nlohmann::json::parse(status.out).at("machines")[0].at("warnings");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].at("metric"), "center_dy_mm");
  EXPECT_EQ(warnings[0].at("earliest_crossing_ns"), kT0 + 5 * kDay);
  const CliRun status_text = run_cli({"status", "--db", file, "--plant", plant}, Capture::Separate);
  EXPECT_NE(status_text.out.find("center_dy_mm FORECAST (above)"), std::string::npos)
      << status_text.out;
}

}  // namespace
}  // namespace ncqual

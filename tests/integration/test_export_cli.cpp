// SPDX-License-Identifier: Apache-2.0
// The historian's data for people and for safekeeping, through the built `ncqual` binary on
// historian files written here with storage::Database: `ncqual export` (CSV files read back with
// Python's csv module and compared value by value with the database through Python's sqlite3,
// check_export.py), `ncqual backup` while a writer commits, and `ncqual db thin` (retention).
#include "cli_runner.hpp"

#include "ncqual/storage/database.hpp"
#include "ncqual/storage/export.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace ncqual {
namespace {

namespace fs = std::filesystem;

using namespace testing_cli;  // cli_runner.hpp

constexpr std::int64_t kSecond = 1'000'000'000;
constexpr std::int64_t kDay = 86'400 * kSecond;
// 2027-01-15T00:00:00Z: day 20833 since the epoch.
constexpr std::int64_t kJan15 = 20833 * kDay;

CheckRequest request(const std::string& id, const std::string& machine, std::int64_t t) {
  CheckRequest r;
  r.machine_id = machine;
  r.request_id = id;
  r.kind = CheckKind::MonumentPositioning;
  r.requested_by = "scheduler";
  r.time_ns = t;
  r.parameters = {{"fixture_configuration", 3, ""}};
  return r;
}

MeasurementSet measurement(const std::string& id, const std::string& machine, std::int64_t t,
                           int touches = 8, int points = 0) {
  MeasurementSet s;
  s.machine_id = machine;
  s.request_id = id;
  s.kind = CheckKind::MonumentPositioning;
  s.instrument = "touch_probe";
  s.frame = "machine";
  s.time_ns = t;
  for (int i = 0; i < touches; ++i) {
    Touch touch;
    touch.feature = "hole_edge";
    touch.axes = AxisPosition{1200.0 + i / 3.0, 800.0 - i / 7.0, 150.0, 0.0, 0.0, 0.1 * i};
    touch.approach = Eigen::Vector3d(1, 0, 0);
    s.touches.push_back(touch);
  }
  for (int i = 0; i < points; ++i) {
    TrackerPoint p;
    p.label = "grid:" + std::to_string(i);
    p.commanded = AxisPosition{10.0 * i, 20.0, 30.0, 0.0, 0.0, 0.0};
    p.measured_mm = Eigen::Vector3d(10.0 * i + 1e-4 / 3, 20.0, 30.0);
    s.tracker_points.push_back(p);
  }
  return s;
}

CheckResult result(const std::string& id, const std::string& machine, std::int64_t t,
                   double value = 0.001) {
  CheckResult r;
  r.machine_id = machine;
  r.request_id = id;
  r.kind = CheckKind::MonumentPositioning;
  r.verdict = Verdict::Pass;
  r.time_ns = t;
  r.produced_by = "ncqual-solver test";
  r.metrics = {{"center_dx_mm", value, "mm", -0.025, 0.025, true},
               {"center_dy_mm", -value / 3, "mm", -0.025, 0.025, true},
               {"face_dz_mm", 0.002, "mm", -0.025, 0.025, true}};
  return r;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// `sqlite3 -readonly FILE SQL`: the first column of the first row.
std::string sqlite_value(const std::string& file, const std::string& sql) {
  const CliRun r = run_command({"sqlite3", "-batch", "-readonly", "-noheader", "-list", file, sql},
                               Capture::Separate);
  EXPECT_EQ(r.exit_code, 0) << sql << "\n" << r.err;
  return r.out.substr(0, r.out.find('\n'));
}

// The records of a CSV file without its header: they end in CRLF (a line break inside a text of
// these files is a bare LF).
std::vector<std::string> data_lines(const std::string& file) {
  const std::string text = read_file(file);
  std::vector<std::string> lines;
  std::size_t start = text.find("\r\n");
  if (start == std::string::npos) return lines;
  for (start += 2; start < text.size();) {
    const std::size_t end = text.find("\r\n", start);
    if (end == std::string::npos) break;
    lines.push_back(text.substr(start, end - start));
    start = end + 2;
  }
  return lines;
}

// The first field of each record of a CSV file (a request id, a machine id, ...).
std::set<std::string> first_fields(const std::string& file) {
  std::set<std::string> out;
  for (const auto& line : data_lines(file)) out.insert(line.substr(0, line.find(',')));
  return out;
}

// ---- ncqual export ------------------------------------------------------------------------------

constexpr const char* kTrickyReason = "center_dy_mm, \"way\" out\nsee the log of Zoë";
const double kSeventeenDigits = 0.1 + 0.2;  // 0.30000000000000004: 17 significant digits

class DbExport : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return (tmp_.path() / name).string(); }

  // Every table of the historian with rows: checks on m1 and m2 at 08:00Z on 10..19 January 2027
  // (req-10..req-19), one of them with the values that are hard to write as text, tracker points,
  // a correction, a compensation, status changes, an intervention, a conflict and services.
  std::string historian() {
    const std::string file = path("historian.db");
    auto db = storage::Database::open(file);
    for (int day = 10; day < 20; ++day) {
      const std::string machine = day % 2 ? "m2" : "m1";
      const std::int64_t t = kJan15 + (day - 15) * kDay + 8 * 3600 * kSecond;
      const std::string id = "req-" + std::to_string(day);
      db.store(request(id, machine, t), {"hash-" + id, "writer|0.0.1.3", t});
      db.store(measurement(id, machine, t + kSecond, 4, day == 12 ? 3 : 0));
      CheckResult r = result(id, machine, t + 2 * kSecond, 0.001 * day / 3);
      if (day == 14) {
        r.verdict = Verdict::Fail;
        r.reason = kTrickyReason;
        r.metrics[0].value = kSeventeenDigits;
        r.metrics[0].pass = false;
        r.metrics[1].value = std::numeric_limits<double>::quiet_NaN();  // stored NULL
        r.metrics[2].lower = -std::numeric_limits<double>::infinity();  // a one-sided band
        r.likely_causes = {"machine shifted", "monument shifted, or \"moved\""};
        r.correction = Correction{"machine:work_offset", {{"dx_mm", -1.0 / 3, "mm"}}};
        Compensation c;
        c.machine_id = machine;
        c.request_id = id;
        c.correction = *r.correction;
        c.time_ns = t + 3 * kSecond;
        db.store(c);
      }
      db.store(r);
      MachineStatus status;
      status.machine_id = machine;
      status.request_id = id;
      status.state = day == 14 ? MachineState::NeedsIntervention : MachineState::Qualified;
      status.last_kind = CheckKind::MonumentPositioning;
      status.last_verdict = r.verdict;
      status.time_ns = t + 4 * kSecond;
      db.store(status);
    }
    Intervention i;
    i.machine_id = "m1";
    i.intervention_id = "int-1";
    i.note = "probe cleaned, stylus replaced";
    i.operator_name = "ann";
    i.time_ns = kJan15 + kDay;
    db.store(i);
    CheckRequest other = request("req-10", "m1", kJan15 - 5 * kDay + 8 * 3600 * kSecond);
    other.attempt = 2;
    db.store(other, {"hash-other", "writer|0.0.1.3", kJan15});  // kept as a conflict
    Heartbeat h;
    h.service = "acquisition";
    h.instance = "cell-1:4242";
    h.machine_id = "m1";
    h.state = "running";
    h.time_ns = kJan15;
    db.store(h);
    // A trend warning, as the historian writes it (storage::apply_trend_warnings): its `kind` is
    // a text, its end NULL while it is active.
    const CliRun warning = run_command(
        {"sqlite3", file,
         "INSERT INTO trend_warnings VALUES ('m1', 'center_dx_mm', 2, 'forecast', " +
             std::to_string(kJan15 - 3 * kDay) + ", 'req-12', " + std::to_string(kJan15) +
             ", NULL, NULL, " + std::to_string(kJan15 + 40 * kDay) +
             ", NULL, 'center_dx_mm drifts 0.4 um/day, out of tolerance in 40 days', 'above')"},
        Capture::Separate);
    EXPECT_EQ(warning.exit_code, 0) << warning.err;
    return file;
  }

  // `ncqual export ...` into `dir`, then check_export.py on it: its JSON report.
  nlohmann::json export_and_check(const std::string& db, const std::string& dir,
                                  const std::vector<std::string>& filter) {
    std::vector<std::string> args{"export", "--db", db, "--csv", dir};
    args.insert(args.end(), filter.begin(), filter.end());
    const CliRun r = run_cli(args, Capture::Separate);
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    const CliRun check = run_command(
        {"/usr/bin/python3", NCQUAL_SOURCE_DIR "/tests/integration/check_export.py", db, dir},
        Capture::Separate);
    EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
    return nlohmann::json::parse(check.out.empty() ? "{}" : check.out);
  }

  testing_cli::TempDir tmp_{"ncqual-db-export"};
};

// Everything since 1 January: every row of every table, compared value by value by Python.
TEST_F(DbExport, EveryTableReadsBackValueByValueWithPython) {
  const std::string db = historian();
  const std::string dir = path("all");
  const nlohmann::json report = export_and_check(db, dir, {"--since", "2027-01-01"});
  ASSERT_TRUE(report.contains("rows")) << report.dump();
  EXPECT_TRUE(report.at("problems").empty()) << report.dump(2);
  const auto& rows = report.at("rows");
  EXPECT_EQ(rows.size(), storage::exported_tables().size());
  EXPECT_EQ(rows.at("requests.csv"), 10);
  EXPECT_EQ(rows.at("request_parameters.csv"), 10);
  EXPECT_EQ(rows.at("touches.csv"), 40);
  EXPECT_EQ(rows.at("tracker_points.csv"), 3);
  EXPECT_EQ(rows.at("metrics.csv"), 30);
  EXPECT_EQ(rows.at("causes.csv"), 2);
  EXPECT_EQ(rows.at("result_offsets.csv"), 1);
  EXPECT_EQ(rows.at("compensations.csv"), 1);
  EXPECT_EQ(rows.at("compensation_offsets.csv"), 1);
  EXPECT_EQ(rows.at("checks.csv"), 10);
  EXPECT_EQ(rows.at("status_changes.csv"), 10);
  EXPECT_EQ(rows.at("interventions.csv"), 1);
  EXPECT_EQ(rows.at("conflicts.csv"), 1);
  EXPECT_EQ(rows.at("services.csv"), 1);
  EXPECT_EQ(rows.at("machines.csv"), 2);
  EXPECT_EQ(rows.at("trend_warnings.csv"), 1);
  EXPECT_GT(report.at("compared").get<int>(), 1000);
  EXPECT_EQ(report.at("kind_names").at("2"), "monument_positioning");

  // As written (Python's csv module reads some of these the same either way): a double to 17
  // digits; the quoted text with its comma, doubled quotes and line break; NULL an empty field,
  // an empty text "".
  const std::string results = read_file(dir + "/results.csv");
  EXPECT_NE(results.find("\"center_dy_mm, \"\"way\"\" out\nsee the log of Zoë\""),
            std::string::npos)
      << results;
  const std::string metrics = read_file(dir + "/metrics.csv");
  EXPECT_NE(metrics.find("req-14,0,center_dx_mm,0.30000000000000004,mm,-0.025,0.025,0\r\n"),
            std::string::npos)
      << metrics;
  EXPECT_NE(metrics.find("req-14,1,center_dy_mm,,mm,-0.025,0.025,1\r\n"), std::string::npos)
      << "a NaN metric is NULL, an empty field\n"
      << metrics;
  EXPECT_NE(metrics.find("req-14,2,face_dz_mm,0.002,mm,-inf,0.025,1\r\n"), std::string::npos)
      << metrics;
  const std::string sets = read_file(dir + "/measurement_sets.csv");
  EXPECT_EQ(sets.rfind("request_id,machine_id,kind,kind_name,instrument,frame,time_ns,time_utc,"
                       "error,content_hash,writer,points_thinned_ns,points_thinned_utc,"
                       "thinned_touches,thinned_tracker_points,origin\r\n",
                       0),
            0u)
      << sets;
  EXPECT_NE(sets.find("req-10,m1,2,monument_positioning,touch_probe,machine,1799568001000000000,"
                      "2027-01-10T08:00:01.000000000Z,\"\",,,,,0,0,\r\n"),
            std::string::npos)
      << "error '' is \"\", content_hash NULL is empty, origin NULL (not recorded) too\n"
      << sets;
  EXPECT_NE(read_file(dir + "/trend_warnings.csv")
                .find(",2,monument_positioning,forecast,1799712000000000000,"
                      "2027-01-12T00:00:00.000000000Z,req-12,"),
            std::string::npos)
      << "a text kind has no _name column";
  const std::string touches = read_file(dir + "/touches.csv");
  EXPECT_NE(touches.find("req-10,1,hole_edge,1200.3333333333333,799.8571428571429,150.0,"),
            std::string::npos)
      << touches;

  const nlohmann::json manifest = nlohmann::json::parse(read_file(dir + "/manifest.json"));
  EXPECT_EQ(manifest.at("schema_version"), storage::Database::latest_schema_version());
  EXPECT_EQ(manifest.at("filter").at("since_utc"), "2027-01-01T00:00:00.000Z");
  EXPECT_TRUE(manifest.at("filter").at("until_ns").is_null());
  EXPECT_EQ(manifest.at("ncqual").get<std::string>().rfind("ncqual ", 0), 0u);
  EXPECT_EQ(manifest.at("files").size(), storage::exported_tables().size());
}

// The time filter at its edges: --since is in, --until is out, to the nanosecond; parts follow
// their sample; --machine keeps that machine's rows.
TEST_F(DbExport, TheTimeRangeIsHalfOpenToTheNanosecondAndMachinesFilter) {
  const std::string db = historian();
  // req-12 and req-14 (m1) were requested at 08:00:00Z on 12 and 14 January, their sets 1 s and
  // their results 2 s later.
  const std::string dir = path("edges");
  const nlohmann::json report = export_and_check(
      db, dir,
      {"--since", "2027-01-12T08:00:00Z", "--until", "2027-01-14T08:00:02Z", "--machine", "m1"});
  EXPECT_TRUE(report.value("problems", nlohmann::json::array()).empty()) << report.dump(2);
  const auto ids = [&](const std::string& file) { return first_fields(dir + "/" + file); };
  // The request at --since exactly (req-12) is in.
  EXPECT_EQ(ids("requests.csv"), (std::set<std::string>{"req-12", "req-14"}));
  EXPECT_EQ(ids("measurement_sets.csv"), (std::set<std::string>{"req-12", "req-14"}));
  // req-14's result at --until exactly is out, and its metrics and causes with it.
  EXPECT_EQ(ids("results.csv"), (std::set<std::string>{"req-12"}));
  EXPECT_EQ(ids("metrics.csv"), (std::set<std::string>{"req-12"}));
  EXPECT_EQ(ids("causes.csv"), std::set<std::string>{});
  EXPECT_EQ(ids("tracker_points.csv"), (std::set<std::string>{"req-12"}));
  EXPECT_EQ(data_lines(dir + "/touches.csv").size(), 8u);
  EXPECT_EQ(ids("machines.csv"), (std::set<std::string>{"m1"}));
  EXPECT_TRUE(ids("interventions.csv").empty()) << "16 January is after --until";
  // The forecast warning started on 12 January at 00:00, before --since, and is still active:
  // it was active in the range, so it is in.
  EXPECT_EQ(ids("trend_warnings.csv"), (std::set<std::string>{"m1"}));
  const std::string before = path("before");
  export_and_check(db, before, {"--since", "2027-01-01", "--until", "2027-01-12T00:00:00Z"});
  EXPECT_TRUE(first_fields(before + "/trend_warnings.csv").empty())
      << "a range that ends as the warning starts does not hold it";

  // One nanosecond later --until, req-14's result is in.
  const std::string later = path("later");
  export_and_check(db, later,
                   {"--since", "2027-01-12T08:00:00Z", "--until", "2027-01-14T08:00:02.000000001Z",
                    "--machine", "m1"});
  EXPECT_EQ(data_lines(later + "/results.csv").size(), 2u);
  EXPECT_EQ(data_lines(later + "/causes.csv").size(), 2u);
  // One nanosecond later --since leaves req-12's request out, but not its set (1 s later).
  const std::string after = path("after");
  export_and_check(db, after, {"--since", "2027-01-12T08:00:00.000000001Z", "--machine", "m1,m2"});
  EXPECT_EQ(first_fields(after + "/requests.csv").count("req-12"), 0u);
  EXPECT_EQ(first_fields(after + "/measurement_sets.csv").count("req-12"), 1u);
  EXPECT_EQ(first_fields(after + "/requests.csv").count("req-13"), 1u) << "m2's too";
}

// Files exported while a writer commits are one snapshot: every metric's result and every
// touch's set is in the files, the counts agree, and checks.csv (written after them) holds
// exactly their checks, though the files are written one by one.
TEST_F(DbExport, FilesAreOneSnapshotWhileAWriterCommits) {
  const std::string db = historian();
  std::atomic<bool> stop{false};
  std::atomic<int> committed{0};
  std::thread writer([&] {
    auto w = storage::Database::open(db);
    for (int i = 0; !stop; ++i) {
      const std::string id = "w-" + std::to_string(i);
      const std::int64_t t = kJan15 + i * kSecond;
      w.store(measurement(id, "m1", t, 200));
      w.store(result(id, "m1", t + 1));
      ++committed;
    }
  });
  while (committed < 50) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  const std::string dir = path("live");
  const CliRun r =
      run_cli({"export", "--db", db, "--csv", dir, "--since", "2027-01-01"}, Capture::Separate);
  const int during = committed;
  stop = true;
  writer.join();
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const std::set<std::string> results = first_fields(dir + "/results.csv");
  const std::set<std::string> sets = first_fields(dir + "/measurement_sets.csv");
  std::size_t metrics = 0, touches = 0;
  for (const auto& line : data_lines(dir + "/metrics.csv")) {
    ++metrics;
    EXPECT_EQ(results.count(line.substr(0, line.find(','))), 1u) << line;
  }
  for (const auto& line : data_lines(dir + "/touches.csv")) {
    ++touches;
    EXPECT_EQ(sets.count(line.substr(0, line.find(','))), 1u) << line;
  }
  EXPECT_EQ(metrics, 3 * results.size());
  ASSERT_GE(sets.size(), 10u + 50u);
  EXPECT_EQ(touches, 200 * (sets.size() - 10) + 4 * 10);
  // checks.csv, written after the others, holds exactly the checks of the sets and results.
  std::set<std::string> parts = sets;
  parts.insert(results.begin(), results.end());
  EXPECT_EQ(first_fields(dir + "/checks.csv"), parts);
  std::cout << "export while writing: " << sets.size() - 10 << " writer sets in the files, "
            << during << " committed by the end of the export\n";
}

TEST_F(DbExport, BadInputIsNamedWithItsExitCode) {
  const std::string db = historian();
  const auto refused = [&](const std::vector<std::string>& args, int code,
                           const std::string& named) {
    const CliRun r = run_cli(args, Capture::Separate);
    EXPECT_EQ(r.exit_code, code) << testing_cli::joined(args) << "\n" << r.out << r.err;
    EXPECT_NE(r.err.find(named), std::string::npos) << testing_cli::joined(args) << "\n" << r.err;
  };
  refused({"export", "--db", db, "--csv", path("a"), "--since", "last week"}, 2,
          "--since 'last week': expected a date or time in the plant's time zone (UTC)");
  refused(
      {"export", "--db", db, "--csv", path("a"), "--since", "2027-01-10", "--until", "2027-01-32"},
      2, "--until '2027-01-32'");
  refused(
      {"export", "--db", db, "--csv", path("a"), "--since", "2027-01-10", "--until", "2027-01-10"},
      2, "--until 2027-01-10 is not after --since 2027-01-10");
  const std::string file = tmp_.write("notes.txt", "keep me");
  refused({"export", "--db", db, "--csv", file, "--since", "2027-01-01"}, 2,
          "--csv '" + file + "' is a file, not a folder");
  EXPECT_EQ(read_file(file), "keep me");
  const std::string full = path("full");
  fs::create_directories(full);
  tmp_.write("full/mine.txt", "mine");
  refused({"export", "--db", db, "--csv", full, "--since", "2027-01-01"}, 2,
          "--csv '" + full + "' is not empty");
  EXPECT_FALSE(fs::exists(full + "/requests.csv"));
  refused({"export", "--db", db, "--csv", path("a"), "--since", "2027-01-01", "--machine", "pm9"},
          2, "--machine 'pm9': the historian " + db + " holds no such machine (it holds m1, m2)");
  const std::string missing = path("none.db");
  refused({"export", "--db", missing, "--csv", path("a"), "--since", "2027-01-01"}, 6,
          "ncqual export: no historian database at " + missing);
  EXPECT_FALSE(fs::exists(missing));
  EXPECT_FALSE(fs::exists(path("a"))) << "nothing is written for a refused export";

  // --overwrite writes into a folder that is not empty; other files stay.
  const CliRun again =
      run_cli({"export", "--db", db, "--csv", full, "--since", "2027-01-01", "--overwrite"},
              Capture::Separate);
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_TRUE(fs::exists(full + "/manifest.json"));
  EXPECT_EQ(read_file(full + "/mine.txt"), "mine");
}

// ---- ncqual backup ------------------------------------------------------------------------------

class DbBackup : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return (tmp_.path() / name).string(); }
  testing_cli::TempDir tmp_{"ncqual-db-backup"};
};

// A backup while a writer commits in a loop: the copy passes integrity_check, holds every row
// committed before the backup began, and is one snapshot (the writer's checks in it are exactly
// its first k, each whole), though the writer went on committing while it was made.
TEST_F(DbBackup, ACopyWhileAWriterCommitsIsWholeAndHoldsEverythingCommittedBefore) {
  const std::string db = path("historian.db");
  constexpr int kChecks = 600;
  {
    auto h = storage::Database::open(db);
    for (int i = 0; i < kChecks; ++i) {
      const std::string id = "req-" + std::to_string(i);
      const std::int64_t t = kJan15 + i * kSecond;
      h.store(measurement(id, i % 2 ? "m2" : "m1", t, 100));
      h.store(result(id, i % 2 ? "m2" : "m1", t + 1));
    }
  }
  std::atomic<bool> stop{false};
  std::atomic<int> committed{0};
  std::thread writer([&] {
    auto w = storage::Database::open(db);
    for (int i = 0; !stop; ++i) {
      // A result and its 3 metrics: one commit.
      w.store(result("w-" + std::to_string(i), "m1", kJan15 + kDay + i));
      ++committed;
    }
  });
  while (committed < 20) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  const int before = committed;
  const std::string copy = path("backup/historian-copy.db");
  const CliRun r =
      run_cli({"backup", "--db", db, "--out", copy, "--step-pages", "8"}, Capture::Separate);
  const int after = committed;
  stop = true;
  writer.join();
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("backed up " + db + " (schema version " +
                       std::to_string(storage::Database::latest_schema_version()) + ") to " + copy +
                       ": "),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("PRAGMA integrity_check: ok"), std::string::npos) << r.out;
  std::cout << r.out;
  // Nothing else is left beside it: no temporary file, no WAL.
  for (const auto& entry : fs::directory_iterator(path("backup"))) {
    EXPECT_EQ(entry.path().filename(), "historian-copy.db") << entry.path();
  }

  auto c = storage::Database::open_readonly(copy);
  EXPECT_EQ(c.integrity_check(), "ok");
  EXPECT_EQ(sqlite_value(copy, "SELECT count(*) FROM touches"), std::to_string(100 * kChecks));
  const int in_copy =
      std::stoi(sqlite_value(copy, "SELECT count(*) FROM results WHERE request_id LIKE 'w-%'"));
  EXPECT_GE(in_copy, before) << "a check committed before the backup began is missing";
  EXPECT_LT(in_copy, after) << "the writer committed nothing while the backup ran: no test";
  // Exactly w-0 .. w-(k-1), each with its metrics: one snapshot.
  EXPECT_EQ(sqlite_value(copy,
                         "SELECT max(CAST(substr(request_id, 3) AS INTEGER)) + 1 FROM "
                         "results WHERE request_id LIKE 'w-%'"),
            std::to_string(in_copy));
  EXPECT_EQ(sqlite_value(copy, "SELECT count(*) FROM metrics WHERE request_id LIKE 'w-%'"),
            std::to_string(3 * in_copy));
  EXPECT_EQ(c.count_results(), kChecks + in_copy);
  std::cout << "backup while writing: " << before << " writer checks before it, " << in_copy
            << " in the copy, " << after << " at its end\n";
}

TEST_F(DbBackup, RefusesAnExistingFileAndAMissingDatabase) {
  const std::string db = path("historian.db");
  {
    auto h = storage::Database::open(db);
    h.store(result("r1", "m1", kJan15));
  }
  const std::string existing = tmp_.write("existing.db", "keep me");
  const CliRun exists = run_cli({"backup", "--db", db, "--out", existing}, Capture::Separate);
  EXPECT_EQ(exists.exit_code, 2) << exists.out << exists.err;
  EXPECT_NE(exists.err.find("--out '" + existing + "' exists already"), std::string::npos)
      << exists.err;
  EXPECT_EQ(read_file(existing), "keep me");
  const CliRun folder =
      run_cli({"backup", "--db", db, "--out", tmp_.path().string()}, Capture::Separate);
  EXPECT_EQ(folder.exit_code, 2) << folder.err;
  EXPECT_NE(folder.err.find("is a folder"), std::string::npos) << folder.err;

  const CliRun replaced = run_cli(
      {"backup", "--db", db, "--out", existing, "--overwrite", "--quick"}, Capture::Separate);
  EXPECT_EQ(replaced.exit_code, 0) << replaced.out << replaced.err;
  EXPECT_NE(replaced.out.find("PRAGMA quick_check: ok"), std::string::npos) << replaced.out;
  EXPECT_EQ(storage::Database::open_readonly(existing).count_results(), 1);

  const std::string missing = path("none.db");
  const CliRun none =
      run_cli({"backup", "--db", missing, "--out", path("b.db")}, Capture::Separate);
  EXPECT_EQ(none.exit_code, 6) << none.err;
  EXPECT_NE(none.err.find("ncqual backup: no historian database at " + missing), std::string::npos)
      << none.err;
  EXPECT_FALSE(fs::exists(path("b.db")));
  EXPECT_FALSE(fs::exists(missing));
}

// ---- ncqual db thin -----------------------------------------------------------------------------

class DbThin : public ::testing::Test {
 protected:
  // Checks on m1 and m2, one a day from 2027-01-01 to 2027-01-20 at 08:00Z, each with 8 touches;
  // every fifth (also) with 5 tracker points.
  std::string historian() {
    const std::string file = (tmp_.path() / "historian.db").string();
    auto db = storage::Database::open(file);
    for (int day = 0; day < 20; ++day) {
      const std::string machine = day % 2 ? "m2" : "m1";
      const std::int64_t t = kJan15 + (day - 14) * kDay + 8 * 3600 * kSecond;
      const std::string id = "req-" + std::to_string(day);
      db.store(request(id, machine, t));
      db.store(measurement(id, machine, t + kSecond, 8, day % 5 == 0 ? 5 : 0));
      db.store(result(id, machine, t + 2 * kSecond, 0.001 * day));
    }
    return file;
  }

  // `history --json`, every record, without the measurement part (what thinning may change).
  nlohmann::json results(const std::string& file) {
    const CliRun r =
        run_cli({"history", "--db", file, "--limit", "0", "--json"}, Capture::Separate);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    nlohmann::json records = nlohmann::json::parse(r.out);
    for (auto& record : records) record.erase("measurement");
    return records;
  }

  std::string plant(const std::string& db_file, const std::string& retention) {
    const std::string machine = tmp_.write("m1.yaml", R"(machine_id: m1
probe: {tool_length_mm: 350.0, ball_radius_mm: 3.0}
monument: {hole_center_mm: [1200.0, 800.0], hole_diameter_mm: 50.0, face_z_mm: 150.0}
tolerances: {center_dx_mm: 0.025, center_dy_mm: 0.025, face_dz_mm: 0.025}
)");
    return tmp_.write("plant.yaml",
                      "plant: thin-test\nsimulated: true\nhistorian:\n  database: " + db_file +
                          "\n" + retention + "machines:\n  - " + machine + "\n");
  }

  testing_cli::TempDir tmp_{"ncqual-db-thin"};
};

TEST_F(DbThin, DryRunCountsThenThinDeletesOnlyOldPointsAndKeepsEveryResult) {
  const std::string file = historian();
  const nlohmann::json before = results(file);
  ASSERT_EQ(before.size(), 20u);
  const std::string touches = sqlite_value(file, "SELECT count(*) FROM touches");
  ASSERT_EQ(touches, "160");
  ASSERT_EQ(sqlite_value(file, "SELECT count(*) FROM tracker_points"), "20");

  // Before 2027-01-10: days 0..8 of January (1st to 9th), 9 sets with 72 touches; days 0 and 5
  // have 5 tracker points each.
  const CliRun dry = run_cli({"db", "thin", "--db", file, "--before", "2027-01-10", "--dry-run"},
                             Capture::Separate);
  ASSERT_EQ(dry.exit_code, 0) << dry.out << dry.err;
  EXPECT_NE(dry.out.find("would thin 9 measurement sets before 2027-01-10 00:00:00 +00:00 UTC"),
            std::string::npos)
      << dry.out;
  EXPECT_NE(dry.out.find("72 touches and 10 tracker points (dry run: nothing changed)"),
            std::string::npos)
      << dry.out;
  EXPECT_EQ(sqlite_value(file, "SELECT count(*) FROM touches"), touches);
  EXPECT_EQ(sqlite_value(file,
                         "SELECT count(*) FROM measurement_sets WHERE points_thinned_ns "
                         "IS NOT NULL"),
            "0");

  const CliRun thin =
      run_cli({"db", "thin", "--db", file, "--before", "2027-01-10"}, Capture::Separate);
  ASSERT_EQ(thin.exit_code, 0) << thin.out << thin.err;
  EXPECT_NE(thin.out.find("thinned 9 measurement sets before 2027-01-10 00:00:00 +00:00 UTC (from "
                          "2027-01-01 08:00 +00:00 UTC to 2027-01-09 08:00 +00:00 UTC): 72 "
                          "touches and 10 tracker points deleted"),
            std::string::npos)
      << thin.out;
  EXPECT_EQ(sqlite_value(file, "SELECT count(*) FROM touches"), "88");
  EXPECT_EQ(sqlite_value(file, "SELECT count(*) FROM tracker_points"), "10");
  EXPECT_EQ(sqlite_value(file,
                         "SELECT count(*) FROM measurement_sets WHERE points_thinned_ns "
                         "IS NOT NULL AND thinned_touches = 8"),
            "9");
  EXPECT_EQ(results(file), before) << "thinning changed a request or a result";
  EXPECT_EQ(sqlite_value(file, "PRAGMA integrity_check"), "ok");

  // history: the thinned checks say so, with what was measured.
  const CliRun history = run_cli({"history", "--db", file, "--limit", "0"}, Capture::Separate);
  ASSERT_EQ(history.exit_code, 0) << history.err;
  std::size_t said = 0;
  for (std::size_t at = history.out.find("points thinned on "); at != std::string::npos;
       at = history.out.find("points thinned on ", at + 1)) {
    ++said;
  }
  EXPECT_EQ(said, 9u) << history.out;
  EXPECT_NE(history.out.find("(8 touches, 5 tracker points no longer stored)"), std::string::npos)
      << history.out;
  const CliRun json =
      run_cli({"history", "--db", file, "--limit", "0", "--json"}, Capture::Separate);
  std::size_t thinned = 0;
  for (const auto& record : nlohmann::json::parse(json.out)) {
    const auto& m = record.at("measurement");
    EXPECT_EQ(m.at("touches"), 8) << record.dump();
    if (!m.at("points_thinned_ns").is_null()) ++thinned;
  }
  EXPECT_EQ(thinned, 9u);

  // Again: nothing left to do.
  const CliRun again =
      run_cli({"db", "thin", "--db", file, "--before", "2027-01-10"}, Capture::Separate);
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.out.find("nothing changed"), std::string::npos) << again.out;
}

TEST_F(DbThin, WithoutBeforeThePlantsPolicyDecidesAndWithoutOneItIsUsage) {
  const std::string file = historian();
  // A policy of 1200 months cuts a century before now: nothing of 2027 is touched.
  const CliRun none = run_cli({"db", "thin", "--plant", plant(file, "")}, Capture::Separate);
  EXPECT_EQ(none.exit_code, 2) << none.out << none.err;
  EXPECT_NE(none.err.find("pass --before D, or set historian.retention.thin_points_after_months"),
            std::string::npos)
      << none.err;
  const CliRun policy = run_cli({"db", "thin", "--dry-run", "--plant",
                                 plant(file, "  retention: {thin_points_after_months: 1200}\n")},
                                Capture::Separate);
  EXPECT_EQ(policy.exit_code, 0) << policy.out << policy.err;
  EXPECT_NE(policy.out.find("nothing would change"), std::string::npos) << policy.out;
}

TEST_F(DbThin, BadInputIsNamedWithItsExitCode) {
  const std::string file = historian();
  const CliRun date =
      run_cli({"db", "thin", "--db", file, "--before", "last year"}, Capture::Separate);
  EXPECT_EQ(date.exit_code, 2) << date.err;
  EXPECT_NE(date.err.find("--before 'last year': expected a date or time in the plant's time zone"),
            std::string::npos)
      << date.err;
  const std::string missing = (tmp_.path() / "none.db").string();
  const CliRun none =
      run_cli({"db", "thin", "--db", missing, "--before", "2027-01-10"}, Capture::Separate);
  EXPECT_EQ(none.exit_code, 6) << none.err;
  EXPECT_NE(none.err.find("no historian database at " + missing), std::string::npos) << none.err;
  EXPECT_FALSE(fs::exists(missing)) << "db thin must not create a database";
}

}  // namespace
}  // namespace ncqual

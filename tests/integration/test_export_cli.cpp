// SPDX-License-Identifier: Apache-2.0
// The historian's data as it ages, through the built `ncqual` binary on historian files written
// here with storage::Database: `ncqual db thin` (retention).
#include "cli_runner.hpp"

#include "ncqual/storage.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

namespace ncqual {
namespace {

namespace fs = std::filesystem;

using testing_cli::Capture;
using testing_cli::CliRun;
using testing_cli::run_cli;
using testing_cli::run_command;

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

// ---- ncqual db thin
// ------------------------------------------------------------------------------

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
    return tmp_.write("plant.yaml", "plant: thin-test\nhistorian:\n  database: " + db_file + "\n" +
                                        retention + "machines:\n  - " + machine + "\n");
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
  EXPECT_NE(date.err.find("--before 'last year': expected a UTC date or time"), std::string::npos)
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

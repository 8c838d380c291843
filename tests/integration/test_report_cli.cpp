// SPDX-License-Identifier: Apache-2.0
// `ncqual report` end to end without DDS: a plant config (pm1 on a simulated clock) and a
// historian built with the storage API (tests/unit/report/report_historian.hpp), the built CLI
// run on them; the file read back by the report's XML inspector (inspect_report.py). Bad input:
// an unknown machine, an unknown check, a bad --since, --check with --since, an --out that
// cannot be written, no historian file.
#include "cli_runner.hpp"
#include "report_historian.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

namespace ncqual {
namespace {

namespace fs = std::filesystem;
using testing_cli::CliRun;
using testing_cli::run_cli;
using testing_cli::run_command;

class ReportCli : public ::testing::Test {
 protected:
  void SetUp() override {
    report::testing::build_report_historian(db_path(), report::testing::report_machine("pm1"));
    plant_ = tmp_.write(
        "plant.yaml",
        "plant: report-test\ndomain_id: 0\nsimulated: true\nhistorian:\n  database: " + db_path() +
            "\nclock: {mode: simulated, start: "
            "2026-03-01T00:00:00Z}\nmachines:\n  - " NCQUAL_SOURCE_DIR
            "/deploy/machines/pm1.yaml\n");
  }
  std::string db_path() const { return (tmp_.path() / "historian.db").string(); }
  std::string out_path() const { return (tmp_.path() / "pm1.html").string(); }

  static std::string read(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
  }

  nlohmann::json inspect(const std::string& file) {
    const CliRun r =
        run_command({"/usr/bin/python3", NCQUAL_REPORT_TEST_DIR "/inspect_report.py", file},
                    testing_cli::Capture::StdoutOnly);
    EXPECT_EQ(r.exit_code, 0) << r.out;
    return nlohmann::json::parse(r.out);
  }

  testing_cli::TempDir tmp_{"ncqual-report-cli"};
  std::string plant_;
};

TEST_F(ReportCli, WritesTheWholeReportAsOfTheSimulatedClock) {
  const CliRun r = run_cli({"report", "--machine", "pm1", "--since", "2026-03-01", "--out",
                            out_path(), "--plant", plant_});
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("wrote " + out_path()), std::string::npos) << r.out;
  const std::string html = read(out_path());
  // "Now" on a simulated clock is the machine's newest status: day 14, 2026-03-16.
  EXPECT_NE(html.find("As of 2026-03-16 00:00 +00:00 UTC; checks since 2026-03-01."),
            std::string::npos);
  // The software that wrote it, as `ncqual --version` names it.
  EXPECT_NE(html.find("Written by ncqual report 0.1.0 (git "), std::string::npos);
  const nlohmann::json doc = inspect(out_path());
  ASSERT_TRUE(doc["ok"].get<bool>()) << doc["error"];
  EXPECT_TRUE(doc["forbidden"].empty()) << doc["forbidden"].dump();
  std::vector<std::string> classes;
  for (const auto& s : doc["sections"]) classes.push_back(s["class"]);
  EXPECT_EQ(classes, (std::vector<std::string>{"ncqual-report-state", "ncqual-report-grid",
                                               "ncqual-report-linear", "ncqual-report-circles",
                                               "ncqual-report-trends", "ncqual-report-checks",
                                               "ncqual-report-budget"}));
  EXPECT_EQ(doc["checks"].size(), 15u);
  EXPECT_EQ(doc["vectors"].size(), 216u);
  // No temporary file is left beside it.
  int files = 0;
  for (const auto& e : fs::directory_iterator(tmp_.path())) {
    files += e.path().filename().string().rfind("pm1.html", 0) == 0;
  }
  EXPECT_EQ(files, 1);
}

// Issue 37 point 7: one clock. In a Berlin plant (CET, +01:00 in March 2026 before the 29th)
// daily-12's result, 2026-03-14 06:00Z, is 07:00 local in `history`, in the report's checks
// table and in the text of its trend chart; the status of 2026-03-16 00:00Z is 01:00 local in
// `status` and in the report. `--since 2026-03-12` is local midnight (2026-03-11 23:00Z): daily-10
// (12 March, 07:00 local) is in, daily-9 (11 March) is not.
TEST_F(ReportCli, EveryTimeAPersonReadsIsInThePlantsZone) {
  const std::string berlin = tmp_.write(
      "berlin.yaml",
      "plant: report-test\ndomain_id: 0\nsimulated: true\nhistorian:\n  database: " + db_path() +
          "\nclock: {mode: simulated, start: 2026-03-01T00:00:00Z}\nmachines:\n  "
          "- " NCQUAL_SOURCE_DIR
          "/deploy/machines/pm1.yaml\nscheduler:\n  calendar:\n    time_zone: "
          "Europe/Berlin\n");
  const CliRun history = run_cli({"history", "--machine", "pm1", "--plant", berlin});
  ASSERT_EQ(history.exit_code, 0) << history.out;
  EXPECT_NE(history.out.find("2026-03-14 07:00:00 +01:00 CET"), std::string::npos) << history.out;
  const CliRun status = run_cli({"status", "--machine", "pm1", "--plant", berlin});
  EXPECT_NE(status.out.find("2026-03-16 01:00 +01:00 CET"), std::string::npos) << status.out;

  const CliRun r = run_cli({"report", "--machine", "pm1", "--since", "2026-03-12", "--out",
                            out_path(), "--plant", berlin});
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const std::string html = read(out_path());
  EXPECT_NE(html.find("As of 2026-03-16 01:00 +01:00 CET; checks since 2026-03-12."),
            std::string::npos);
  EXPECT_NE(html.find("<th>time (Europe/Berlin)</th>"), std::string::npos);
  EXPECT_NE(html.find("date (Europe/Berlin)"), std::string::npos) << "the trend charts' axes";
  EXPECT_EQ(html.find("date (UTC)"), std::string::npos);
  EXPECT_NE(html.find("daily-12: 2026-03-14 07:00 +01:00 CET, "), std::string::npos)
      << "daily-12 in the trend chart's tooltip";
  const nlohmann::json doc = inspect(out_path());
  ASSERT_TRUE(doc["ok"].get<bool>()) << doc["error"];
  std::map<std::string, std::string> checks;  // request id -> time cell
  for (const auto& row : doc["checks"]) checks[row[2].get<std::string>()] = row[0];
  EXPECT_EQ(checks["daily-12"], "2026-03-14 07:00 +01:00 CET");
  EXPECT_EQ(checks["daily-10"], "2026-03-12 07:00 +01:00 CET");
  EXPECT_EQ(checks.count("daily-9"), 0u) << "11 March is before local midnight of the 12th";
}

TEST_F(ReportCli, OneCheckWithDbAlone) {
  const CliRun r = run_cli({"report", "--machine", "pm1", "--check", "daily-12", "--out",
                            out_path(), "--db", db_path()});
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const nlohmann::json doc = inspect(out_path());
  ASSERT_TRUE(doc["ok"].get<bool>()) << doc["error"];
  ASSERT_EQ(doc["checks"].size(), 1u);
  EXPECT_EQ(doc["checks"][0][2], "daily-12");
}

TEST_F(ReportCli, BadInputIsNamedAndWritesNothing) {
  struct Case {
    std::vector<std::string> args;
    int exit_code;
    std::string says;
  };
  const std::string missing_dir = (tmp_.path() / "no-such-folder" / "r.html").string();
  const std::vector<Case> cases{
      {{"--machine", "pm9", "--out", out_path(), "--plant", plant_}, 2, "pm9"},
      {{"--machine", "pm9", "--out", out_path(), "--db", db_path()}, 2, "'pm9'"},
      {{"--machine", "pm1", "--check", "nope-7", "--out", out_path(), "--plant", plant_},
       6,
       "'nope-7'"},
      {{"--machine", "pm1", "--since", "2026-13-45", "--out", out_path(), "--plant", plant_},
       2,
       "2026-13-45"},
      {{"--machine", "pm1", "--since", "2026-03-01", "--check", "daily-1", "--out", out_path(),
        "--plant", plant_},
       2,
       "--check and --since"},
      {{"--machine", "pm1", "--out", missing_dir, "--plant", plant_}, 1, missing_dir},
      {{"--machine", "pm1", "--out", tmp_.path().string(), "--plant", plant_}, 1, "is a folder"},
      {{"--machine", "pm1", "--out", out_path(), "--db", (tmp_.path() / "absent.db").string()},
       6,
       "absent.db"},
      {{"--machine", "pm1", "--out", out_path()}, 2, "--plant"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args{"report"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const CliRun r = run_cli(args);
    EXPECT_EQ(r.exit_code, c.exit_code) << testing_cli::joined(args) << "\n" << r.out;
    EXPECT_NE(r.out.find(c.says), std::string::npos) << testing_cli::joined(args) << "\n" << r.out;
    EXPECT_FALSE(fs::exists(out_path())) << testing_cli::joined(args);
  }
}

TEST_F(ReportCli, UnwritableOutIsNamedAndKeepsTheOldFile) {
  // A folder nobody may create files in (/proc/self, also for root).
  const std::string proc_out = "/proc/self/ncqual-report.html";
  const CliRun proc = run_cli({"report", "--machine", "pm1", "--out", proc_out, "--plant", plant_});
  EXPECT_EQ(proc.exit_code, 1) << proc.out;
  EXPECT_NE(proc.out.find("--out " + proc_out + ": cannot write"), std::string::npos) << proc.out;
  // A read-only folder keeps the file it has (root writes there anyway: then only the above).
  const fs::path folder = tmp_.path() / "read-only";
  fs::create_directories(folder);
  const std::string out = (folder / "r.html").string();
  std::ofstream(out) << "old";
  fs::permissions(folder, fs::perms::owner_read | fs::perms::owner_exec);
  const CliRun r = run_cli({"report", "--machine", "pm1", "--out", out, "--plant", plant_});
  fs::permissions(folder, fs::perms::owner_all);
  if (geteuid() == 0) return;
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.out.find("--out " + out), std::string::npos) << r.out;
  EXPECT_EQ(read(out), "old");
}

}  // namespace
}  // namespace ncqual

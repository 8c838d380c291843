// SPDX-License-Identifier: Apache-2.0
// `ncqual import`: a real instrument's export published as a MeasurementSet goes through the
// real solver and historian processes over DDS (on its own domain) and is stored with its result,
// the figures those of the file worked by hand.
#include "cli_runner.hpp"
#include "harness.hpp"
#include "tracker_export.hpp"

#include "ncqual/storage/database.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ncqual::testing {
namespace {

// Runs the CLI with `args`; returns its exit code and what it printed (stdout and stderr).
std::pair<int, std::string> cli(const std::vector<std::string>& args) {
  const testing_cli::CliRun r = testing_cli::run_cli(args);
  return {r.exit_code, r.out};
}

// The check of `request`, once the historian holds its set and result (nullopt if they did not
// come); stored_import: of the request id `ncqual import` printed (its last line).
std::optional<storage::CheckRecord> stored_check(Plant& plant, const std::string& request) {
  const bool stored = plant.wait_for_db([&](storage::Database& db) {
    const auto rec = db.find_check(request);
    return rec && rec->result && rec->measurement;
  });
  EXPECT_TRUE(stored) << plant.log("solver");
  return storage::Database::open_readonly(plant.db_path()).find_check(request);
}

std::optional<storage::CheckRecord> stored_import(Plant& plant, const std::string& out) {
  const std::size_t at = out.rfind("import-");
  if (at == std::string::npos) return std::nullopt;
  return stored_check(plant, out.substr(at, out.find('\n', at) - at));
}

TEST(Import, InstrumentExportsAreJudgedAndStoredLikeMeasuredChecks) {
  Plant plant("import", TestDomain::Import);
  plant.add_machine("pm1", "extends: " NCQUAL_SOURCE_DIR "/deploy/machines/pm1.yaml\n");
  plant.write_plant("[]");
  plant.start("historian");
  plant.start("solver");
  // 3 targets x 3 cycles, deviations in um (by hand, as in the analyze test):
  //   0:   up 1, 2, 3    down -2, -1, 0   -> B_0 = 2 - (-1) = 3
  //   100: up 4, 6, 8    down 2, 3, 4     -> B_1 = 3, s_up = 2: R_1 = max(2*2 + 2*1 + 3, 8, 4) = 9
  //   200: up -1, 0, 1   down -3, -2, -1  -> B_2 = 2
  // B = 3 um, R = 9 um, E = 6 - (-2) = 8 um, A = (6 + 4) - (-2 - 2) = 14 um.
  const int dev[3][2][3] = {
      {{1, 2, 3}, {-2, -1, 0}}, {{4, 6, 8}, {2, 3, 4}}, {{-1, 0, 1}, {-3, -2, -1}}};
  const std::string file = (plant.dir() / "run.csv").string();
  {
    std::ofstream out(file);
    out.precision(12);
    out << "target_mm,cycle,direction,measured_mm\n";
    for (int t = 0; t < 3; ++t) {
      for (int d = 0; d < 2; ++d) {
        for (int c = 0; c < 3; ++c) {
          out << 1000 + 100 * t << "," << c + 1 << "," << (d == 0 ? "up" : "down") << ","
              << 1000 + 100 * t + dev[t][d][c] * 1e-3 << "\n";
        }
      }
    }
  }
  const auto [code, out] = cli({"import", "iso230-2", file, "--machine", "pm1", "--plant",
                                plant.plant_file(), "--domain", std::to_string(plant.domain())});
  ASSERT_EQ(code, 0) << out;
  const auto rec = stored_import(plant, out);
  ASSERT_TRUE(rec && rec->result);
  EXPECT_EQ(rec->result->kind, CheckKind::LinearAxisRun);
  EXPECT_EQ(rec->result->verdict, Verdict::Pass) << rec->result->reason;
  EXPECT_EQ(rec->measurement->tracker_points, 18);
  EXPECT_EQ(rec->measurement->instrument, "import");
  // An instrument's file: measured, and so is the verdict on it (issue 37 point 5).
  EXPECT_EQ(rec->measurement->origin, DataOrigin::Measured);
  EXPECT_EQ(rec->result->origin, DataOrigin::Measured);
  auto value = [&](const char* name) {
    const Metric* m = find_metric(*rec->result, name);
    return m ? m->value : -1.0;
  };
  EXPECT_NEAR(value("linear_B_mm"), 0.003, 1e-9);
  EXPECT_NEAR(value("linear_R_mm"), 0.009, 1e-9);
  EXPECT_NEAR(value("linear_E_mm"), 0.008, 1e-9);
  EXPECT_NEAR(value("linear_A_mm"), 0.014, 1e-9);

  // A run in one direction only cannot give ISO 230-2's A and B: the check is INVALID, saying
  // why, and is stored like any other, so `ncqual wait --request` ends (it waited for ever while
  // the NaN metrics of such a result were refused by the historian).
  std::ofstream(plant.dir() / "oneway.csv") << "target_mm,cycle,direction,measured_mm\n"
                                               "1000,1,up,1000.001\n1000,2,up,1000.002\n"
                                               "1100,1,up,1100.004\n1100,2,up,1100.006\n"
                                               "1200,1,up,1199.999\n1200,2,up,1200.001\n";
  const auto [one_code, one_out] =
      cli({"import", "iso230-2", (plant.dir() / "oneway.csv").string(), "--machine", "pm1",
           "--plant", plant.plant_file(), "--domain", std::to_string(plant.domain())});
  ASSERT_EQ(one_code, 0) << one_out;
  const auto one_way = stored_import(plant, one_out);
  ASSERT_TRUE(one_way && one_way->result);
  EXPECT_EQ(one_way->result->verdict, Verdict::Invalid);
  EXPECT_NE(one_way->result->reason.find("went up (+) only"), std::string::npos)
      << one_way->result->reason;
  const auto [wait_code, wait_out] = cli(
      {"wait", "--request", one_way->request_id, "--plant", plant.plant_file(), "--timeout", "30"});
  EXPECT_EQ(wait_code, 0) << wait_out;
  EXPECT_NE(wait_out.find("INVALID"), std::string::npos) << wait_out;

  // A bad file is refused before anything is published, naming file, line and column.
  std::ofstream(plant.dir() / "bad.csv") << "target_mm,cycle,direction,measured_mm\n0,1,up,x\n";
  const auto [bad_code, bad_out] = cli({"import", "iso230-2", (plant.dir() / "bad.csv").string(),
                                        "--machine", "pm1", "--plant", plant.plant_file()});
  EXPECT_EQ(bad_code, 1);
  EXPECT_NE(bad_out.find("bad.csv:2:4:"), std::string::npos) << bad_out;

  // A laser tracker's point export of rotary_c, measured to the nominal list `ncqual program`
  // wrote: stored under the list's request with every point, judged as its C points were turned
  // by hand, 10" about the C axis (the list gives positions to 0.05 um: 0.1" over 200 mm).
  const std::string list = (plant.dir() / "rotary_c-nominals.csv").string();
  const auto [list_code, list_out] = cli({"program", "--machine", "pm1", "--check", "rotary_c",
                                          "--plant", plant.plant_file(), "--out", list});
  ASSERT_EQ(list_code, 0) << list_out;
  const std::size_t at = list_out.find("(request ");
  ASSERT_NE(at, std::string::npos) << list_out;
  const std::string request = list_out.substr(at + 9, list_out.find(')', at) - at - 9);
  const std::vector<NominalRow> rows = read_nominal_rows(list);
  const std::string points = (plant.dir() / "rotary_c-export.txt").string();
  std::ofstream(points) << point_export(rows, [](const NominalRow& r) {
    return std::vector<Eigen::Vector3d>{
        r.point.rfind("c:", 0) == 0 ? turned_about_c(r, 10 / 206264.8) : r.nominal_mm};
  });
  const auto [points_code, points_out] =
      cli({"import", "points", points, "--nominals", list, "--machine", "pm1", "--plant",
           plant.plant_file(), "--domain", std::to_string(plant.domain())});
  ASSERT_EQ(points_code, 0) << points_out;
  EXPECT_NE(points_out.find("imported " + std::to_string(rows.size()) + " points as rotary_c"),
            std::string::npos)
      << points_out;
  const auto c = stored_check(plant, request);
  ASSERT_TRUE(c && c->result && c->measurement);
  EXPECT_EQ(c->result->kind, CheckKind::RotaryC);
  EXPECT_EQ(c->result->verdict, Verdict::Pass) << c->result->reason;
  EXPECT_EQ(c->measurement->tracker_points, static_cast<std::int64_t>(rows.size()));
  EXPECT_EQ(c->measurement->instrument, "import");
  EXPECT_EQ(c->measurement->origin, DataOrigin::Measured);
  EXPECT_EQ(c->result->origin, DataOrigin::Measured);
  const Metric* mean = find_metric(*c->result, "c_dA_mean_arcsec");
  ASSERT_NE(mean, nullptr);
  EXPECT_NEAR(mean->value, 10, 0.2);
}

// A large export goes through whole: 200,000 points of a ballbar-like circle (both directions) in
// one file, stored with every point and judged. (The time of a 1,000,000-point import is a
// figure of tests/bench/import_bench.cpp, not asserted here.) A file in micrometres read as
// millimetres is refused at its cell before anything is published.
TEST(Import, ALargeCircleIsStoredWholeAndAFileInAnotherUnitIsRefused) {
  Plant plant("import-large", TestDomain::ImportLarge);
  plant.add_machine("pm1", "extends: " NCQUAL_SOURCE_DIR "/deploy/machines/pm1.yaml\n");
  plant.write_plant("[]");
  plant.start("historian");
  plant.start("solver");
  constexpr int kPerDirection = 100000;
  const std::string file = (plant.dir() / "circle.csv").string();
  {
    std::ofstream out(file);
    out.precision(10);
    out << "x_mm,y_mm,direction\n";
    for (const char* direction : {"ccw", "cw"}) {
      for (int i = 0; i < kPerDirection; ++i) {
        const double a = 2 * 3.14159265358979323846 * i / kPerDirection;
        // 150 mm with 2 um of ovality: G (radial span) about 4 um.
        const double r = 150 + 0.002 * std::cos(2 * a);
        out << r * std::cos(a) << "," << (direction[1] == 'c' ? 1 : -1) * r * std::sin(a) << ","
            << direction << "\n";
      }
    }
  }
  const auto [code, out] = cli({"import", "circle", file, "--machine", "pm1", "--plant",
                                plant.plant_file(), "--domain", std::to_string(plant.domain())});
  ASSERT_EQ(code, 0) << out << plant.log("historian") << plant.log("solver");
  EXPECT_NE(out.find("imported 200000 points as circle_xy of pm1"), std::string::npos) << out;
  const auto rec = stored_import(plant, out);
  ASSERT_TRUE(rec && rec->result && rec->measurement);
  EXPECT_EQ(rec->measurement->tracker_points, 2 * kPerDirection);
  EXPECT_EQ(rec->result->kind, CheckKind::CircleXY);
  const Metric* g = find_metric(*rec->result, "circle_xy_G_mm");
  ASSERT_NE(g, nullptr);
  EXPECT_NEAR(g->value, 0.004, 2e-4);

  // The same circle in micrometres: 150000 "mm" is more than ten spans of pm1's envelope.
  {
    std::ofstream um(plant.dir() / "um.csv");
    um << "x_mm,y_mm\n";
    for (int i = 0; i < 12; ++i) {
      const double a = 2 * 3.14159265358979323846 * i / 12;
      um << 150000 * std::cos(a) << "," << 150000 * std::sin(a) << "\n";
    }
  }
  const auto [um_code, um_out] =
      cli({"import", "circle", (plant.dir() / "um.csv").string(), "--machine", "pm1", "--plant",
           plant.plant_file(), "--domain", std::to_string(plant.domain())});
  EXPECT_EQ(um_code, 1);
  EXPECT_NE(um_out.find("um.csv:2:1: column 'x_mm' = '150000': beyond"), std::string::npos)
      << um_out;
  EXPECT_EQ(storage::Database::open_readonly(plant.db_path()).count_results(), 1);
}

}  // namespace
}  // namespace ncqual::testing

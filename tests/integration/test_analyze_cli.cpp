// SPDX-License-Identifier: Apache-2.0
// `ncqual analyze` end to end: instrument files written here, the built `ncqual` binary run on
// them, its --json document checked against figures worked by hand (independent of the
// solver), and the exit codes and file:line:column messages of bad files and bad usage.
#include "cli_runner.hpp"
#include "tracker_export.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kPi = 3.14159265358979323846;

struct Vec3 {
  double v[3];
};

using ncqual::testing_cli::CliRun;
using ncqual::testing_cli::joined;

class AnalyzeCli : public ::testing::Test {
 protected:
  std::string write(const std::string& name, const std::string& text) {
    return tmp_.write(name, text);
  }

  // Runs `ncqual <args>`, stdout and stderr apart.
  CliRun run(const std::vector<std::string>& args) {
    return ncqual::testing_cli::run_cli(args, ncqual::testing_cli::Capture::Separate);
  }

  json run_json(std::vector<std::string> args) {
    args.push_back("--json");
    const CliRun r = run(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    try {
      return json::parse(r.out);
    } catch (const json::exception& e) {
      ADD_FAILURE() << "not JSON: " << e.what() << "\n" << r.out;
      return json();
    }
  }

  ncqual::testing_cli::TempDir tmp_{"ncqual-analyze-cli"};
  const fs::path dir_ = tmp_.path();
};

// 3 targets x 3 cycles, deviations (µm):
//   0:   up 1, 2, 3 (mean 2, s 1)     down -2, -1, 0 (mean -1, s 1)
//   100: up 4, 6, 8 (mean 6, s 2)     down 2, 3, 4 (mean 3, s 1)
//   200: up -1, 0, 1 (mean 0, s 1)    down -3, -2, -1 (mean -2, s 1)
// By hand (µm): B_i 3, 3, 2 -> B 3, B̄ 8/3; R_i↑ 4, 8, 4 -> R↑ 8; R↓ 4;
// R_i = max(2s↑ + 2s↓ + |B_i|, R↑, R↓) = 7, 9, 6 -> R 9; E↑ 6 - 0 = 6; E↓ 3 - (-2) = 5;
// E = 6 - (-2) = 8; x̄_i 0.5, 4.5, -1 -> M 5.5; A↑ = (6 + 4) - (0 - 2) = 12;
// A↓ = (3 + 2) - (-2 - 2) = 9; A = 10 - (-4) = 14.
std::string run_file(bool with_down) {
  std::string text = "# interferometer export\ntarget_mm,cycle,direction,measured_mm,air_C\n";
  const double up[3][3] = {{1, 2, 3}, {4, 6, 8}, {-1, 0, 1}};
  const double down[3][3] = {{-2, -1, 0}, {2, 3, 4}, {-3, -2, -1}};
  for (int dir = 0; dir < (with_down ? 2 : 1); ++dir) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        const double target = 100.0 * i;
        const double dev = (dir == 0 ? up : down)[i][j] * 1e-3;
        char line[128];
        std::snprintf(line, sizeof line, "%.0f,%d,%s,%.4f,20.0\n", target, j + 1,
                      dir == 0 ? "up" : "down", target + dev);
        text += line;
      }
    }
  }
  return text;
}

TEST_F(AnalyzeCli, Iso230_2JsonHasTheHandWorkedFigures) {
  const std::string path = write("run.csv", run_file(true));
  const json j = run_json({"analyze", "iso230-2", path});
  EXPECT_EQ(j["standard"], "ISO 230-2:2014");
  EXPECT_EQ(j["unit"], "mm");
  EXPECT_EQ(j["targets"], 3);
  EXPECT_EQ(j["cycles"], 3);
  const double tol = 1e-9;
  EXPECT_NEAR(j["A"].get<double>(), 0.014, tol);
  EXPECT_NEAR(j["A_up"].get<double>(), 0.012, tol);
  EXPECT_NEAR(j["A_down"].get<double>(), 0.009, tol);
  EXPECT_NEAR(j["E"].get<double>(), 0.008, tol);
  EXPECT_NEAR(j["E_up"].get<double>(), 0.006, tol);
  EXPECT_NEAR(j["E_down"].get<double>(), 0.005, tol);
  EXPECT_NEAR(j["M"].get<double>(), 0.0055, tol);
  EXPECT_NEAR(j["R"].get<double>(), 0.009, tol);
  EXPECT_NEAR(j["R_up"].get<double>(), 0.008, tol);
  EXPECT_NEAR(j["R_down"].get<double>(), 0.004, tol);
  EXPECT_NEAR(j["B"].get<double>(), 0.003, tol);
  EXPECT_NEAR(j["B_mean"].get<double>(), 0.008 / 3, tol);
  ASSERT_EQ(j["per_target"].size(), 3u);
  const json& t1 = j["per_target"][1];
  EXPECT_NEAR(t1["target_mm"].get<double>(), 100, tol);
  EXPECT_EQ(t1["up"]["n"], 3);
  EXPECT_NEAR(t1["up"]["mean"].get<double>(), 0.006, tol);
  EXPECT_NEAR(t1["up"]["s"].get<double>(), 0.002, tol);
  EXPECT_NEAR(t1["down"]["s"].get<double>(), 0.001, tol);
  EXPECT_NEAR(t1["B"].get<double>(), 0.003, tol);
  EXPECT_NEAR(t1["R"].get<double>(), 0.009, tol);
  EXPECT_NEAR(t1["mean"].get<double>(), 0.0045, tol);
}

TEST_F(AnalyzeCli, Iso230_2UnidirectionalFiguresAreNull) {
  const std::string path = write("up.csv", run_file(false));
  const json j = run_json({"analyze", "iso230-2", path});
  EXPECT_NEAR(j["E_up"].get<double>(), 0.006, 1e-9);
  EXPECT_NEAR(j["A_up"].get<double>(), 0.012, 1e-9);
  for (const char* name : {"A", "A_down", "E", "E_down", "M", "R", "R_down", "B", "B_mean"}) {
    EXPECT_TRUE(j[name].is_null()) << name;
  }
  EXPECT_TRUE(j["per_target"][0]["down"].is_null());
  EXPECT_TRUE(j["per_target"][0]["B"].is_null());
}

TEST_F(AnalyzeCli, Iso230_2TableIsPrinted) {
  const std::string path = write("run.csv", run_file(true));
  const CliRun r = run({"analyze", "iso230-2", path});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("ISO 230-2:2014"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("0.0140"), std::string::npos) << r.out;    // A
  EXPECT_NE(r.out.find("100.0000"), std::string::npos) << r.out;  // a target row
}

// The hand-worked circle: 8 angles, radius 10 mm + ccw 2 cos 2θ µm, cw 1 + sin 2θ µm. The LSC
// of each path and of both is centred at (0, 0) (no first harmonic on 8 even angles); radii
// ccw 10, cw 10.001, both 10.0005. G ccw 0.004, cw 0.002; G(b) 10.002 - 9.998 = 0.004;
// H = max |cw - ccw| = 3 µm; F about the LSC of both: 10.002 - 10.0005, 9.998 - 10.0005.
std::string circle_file(bool with_cw) {
  std::string text = "angle_deg,radius_mm,direction\n";
  const double ccw[] = {2, 0, -2, 0, 2, 0, -2, 0}, cw[] = {1, 2, 1, 0, 1, 2, 1, 0};
  for (int dir = 0; dir < (with_cw ? 2 : 1); ++dir) {
    for (int k = 0; k < 8; ++k) {
      char line[96];
      std::snprintf(line, sizeof line, "%d,%.4f,%s\n", 45 * k,
                    10 + (dir == 0 ? ccw[k] : cw[k]) * 1e-3, dir == 0 ? "ccw" : "cw");
      text += line;
    }
  }
  return text;
}

TEST_F(AnalyzeCli, CircleJsonHasTheHandWorkedFigures) {
  const std::string path = write("circle.csv", circle_file(true));
  const json j = run_json({"analyze", "circle", path, "--plane", "YZ"});
  const double tol = 1e-8;
  EXPECT_EQ(j["plane"], "YZ");
  EXPECT_EQ(j["unit"], "mm");
  EXPECT_EQ(j["points"], 16);
  EXPECT_NEAR(j["lsc_radius_mm"].get<double>(), 10.0005, tol);
  EXPECT_NEAR(j["lsc_centre_mm"][0].get<double>(), 0, tol);
  EXPECT_NEAR(j["lsc_centre_mm"][1].get<double>(), 0, tol);
  EXPECT_NEAR(j["G_mm"].get<double>(), 0.004, tol);
  EXPECT_NEAR(j["G_b_mm"].get<double>(), 0.004, tol);
  EXPECT_NEAR(j["H_mm"].get<double>(), 0.003, tol);
  EXPECT_NEAR(j["F_max_mm"].get<double>(), 0.0015, tol);
  EXPECT_NEAR(j["F_min_mm"].get<double>(), -0.0025, tol);
  EXPECT_EQ(j["F_reference"]["centre"], "lsc");
  EXPECT_EQ(j["F_reference"]["radius"], "lsc");
  EXPECT_NEAR(j["directions"]["ccw"]["G_mm"].get<double>(), 0.004, tol);
  EXPECT_NEAR(j["directions"]["cw"]["G_mm"].get<double>(), 0.002, tol);
  EXPECT_NEAR(j["directions"]["cw"]["lsc_radius_mm"].get<double>(), 10.001, tol);
  // Shape: ccw a2 = 2 µm -> 2 a2 / R = 400 µm/m; cw b2 = 1 µm -> -2 b2 / R = -199.98 µrad;
  // both: a2 = 1, b2 = 0.5 µm about R = 10.0005.
  EXPECT_NEAR(j["directions"]["ccw"]["scale_mismatch_um_per_m"].get<double>(), 400, 1e-3);
  EXPECT_NEAR(j["directions"]["cw"]["squareness_urad"].get<double>(), -2e-3 / 10.001 * 1e6, 1e-3);
  EXPECT_NEAR(j["scale_mismatch_um_per_m"].get<double>(), 2e-3 / 10.0005 * 1e6, 1e-3);
  EXPECT_NEAR(j["squareness_urad"].get<double>(), -1e-3 / 10.0005 * 1e6, 1e-3);
}

TEST_F(AnalyzeCli, CircleRadialDeviationAboutTheNominal) {
  const std::string path = write("circle.csv", circle_file(true));
  // About (0, 0) with R0 = 9.999: the radii 9.998 .. 10.002 give F +0.003 / -0.001.
  const json j = run_json({"analyze", "circle", path, "--plane", "XY", "--nominal-radius-mm",
                           "9.999", "--centre-mm", "0,0"});
  EXPECT_NEAR(j["F_max_mm"].get<double>(), 0.003, 1e-9);
  EXPECT_NEAR(j["F_min_mm"].get<double>(), -0.001, 1e-9);
  EXPECT_EQ(j["F_reference"]["centre"], "nominal");
  EXPECT_EQ(j["F_reference"]["radius"], "nominal");
  EXPECT_NEAR(j["F_reference"]["radius_mm"].get<double>(), 9.999, 1e-12);
  EXPECT_NEAR(j["directions"]["cw"]["F_min_mm"].get<double>(), 0.001, 1e-9);
}

TEST_F(AnalyzeCli, CircleUnidirectionalHasNullBidirectionalFigures) {
  const std::string path = write("ccw.csv", circle_file(false));
  const json j = run_json({"analyze", "circle", path, "--plane", "XZ"});
  EXPECT_TRUE(j["G_b_mm"].is_null());
  EXPECT_TRUE(j["H_mm"].is_null());
  EXPECT_TRUE(j["directions"]["cw"].is_null());
  EXPECT_NEAR(j["G_mm"].get<double>(), 0.004, 1e-8);
}

TEST_F(AnalyzeCli, CircleCoordinatesRecoverScaleMismatchAndSquareness) {
  // A machine moving commanded (x, y) to ((1 + s_x) x - ε y, (1 + s_y) y) about a centre
  // (250, 125), radius 100, 72 points each way, no noise, written with 6 decimals (0.5 nm
  // rounding). First order: mismatch s_x - s_y = 30 µm/m, squareness ε = 20 µrad (the Y motion
  // leaning to -X: the angle between the axes over 90°). Rounding adds at most 1 nm to a2, b2:
  // 2e-6/100 = 0.02 µm/m or µrad; second-order terms ~ 1e-4 of the values.
  const double sx = 20e-6, sy = -10e-6, eps = 20e-6;
  std::string text = "x_mm,y_mm,direction\n";
  for (const char* dir : {"ccw", "cw"}) {
    for (int k = 0; k < 72; ++k) {
      const double t = (k + 0.5) * 2 * kPi / 72;
      const double x = 100 * std::cos(t), y = 100 * std::sin(t);
      char line[128];
      std::snprintf(line, sizeof line, "%.6f,%.6f,%s\n", 250 + (1 + sx) * x - eps * y,
                    125 + (1 + sy) * y, dir);
      text += line;
    }
  }
  const std::string path = write("xy.csv", text);
  const json j = run_json({"analyze", "circle", path});
  EXPECT_EQ(j["plane"], "XY");
  EXPECT_EQ(j["layout"], "coordinates");
  EXPECT_NEAR(j["scale_mismatch_um_per_m"].get<double>(), 30, 0.1);
  EXPECT_NEAR(j["squareness_urad"].get<double>(), 20, 0.1);
  EXPECT_NEAR(j["lsc_centre_mm"][0].get<double>(), 250, 1e-5);
  EXPECT_NEAR(j["lsc_radius_mm"].get<double>(), 100 * (1 + (sx + sy) / 2), 1e-5);
  EXPECT_NEAR(j["H_mm"].get<double>(), 0, 2e-6);
}

TEST_F(AnalyzeCli, BadFileExitsOneWithFileLineColumn) {
  std::string text = run_file(true);
  text.replace(text.find("100.0060"), 8, "100.0O60");  // letter O, line 7
  const std::string path = write("bad.csv", text);
  const CliRun r = run({"analyze", "iso230-2", path, "--json"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_EQ(r.err, path + ":7:4: column 'measured_mm' = '100.0O60': expected a number\n");

  // A repeated reading names both lines.
  const std::string dup = write("dup.csv", run_file(true) + "100,2,up,100.0050,20.0\n");
  const CliRun d = run({"analyze", "iso230-2", dup});
  EXPECT_EQ(d.exit_code, 1);
  EXPECT_EQ(d.err, dup +
                       ":21: target_mm = 100, cycle = 2, direction = up: a second reading of "
                       "the same target, cycle and direction (first at line 7)\n");

  // A circle file whose pair names another plane than --plane.
  const std::string xz = write("xz.csv", "x_mm,z_mm\n1,2\n");
  const CliRun p = run({"analyze", "circle", xz, "--plane", "XY"});
  EXPECT_EQ(p.exit_code, 1);
  EXPECT_EQ(p.err, xz + ":1:1: the header's x_mm, z_mm name plane XZ, but plane XY was asked "
                        "for\n");

  // Too few points of a direction: at its last line.
  std::string few = circle_file(true);
  few.erase(few.rfind("315,"));
  const std::string few_path = write("few.csv", few);
  const CliRun f = run({"analyze", "circle", few_path, "--plane", "XY"});
  EXPECT_EQ(f.exit_code, 1);
  EXPECT_EQ(f.err.rfind(few_path + ":16: direction cw: 7 points;", 0), 0u) << f.err;

  // A file that is not there.
  const std::string missing = (dir_ / "missing.csv").string();
  const CliRun m = run({"analyze", "iso230-2", missing});
  EXPECT_EQ(m.exit_code, 1);
  EXPECT_EQ(m.err, missing + ": cannot read: No such file or directory\n");
}

TEST_F(AnalyzeCli, BadUsageExitsTwoWithTheUsage) {
  const std::string path = write("run.csv", run_file(true));
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
           {"analyze"},
           {"analyze", "nothing", path},
           {"analyze", "iso230-2"},
           {"analyze", "iso230-2", path, path},
           {"analyze", "iso230-2", path, "--plane", "XY"},
           {"analyze", "circle", path, "--plane", "QQ"},
           {"analyze", "circle", path, "--centre-mm", "1"},
           {"analyze", "circle", path, "--centre-mm", "1,x"},
           {"analyze", "circle", path, "--nominal-radius-mm", "-3"}}) {
    const CliRun r = run(args);
    EXPECT_EQ(r.exit_code, 2) << joined(args) << "\n" << r.err;
    EXPECT_NE(r.err.find("usage: ncqual analyze"), std::string::npos) << joined(args) << "\n"
                                                                      << r.err;
    EXPECT_NE(r.err.find("analyze circle FILE"), std::string::npos) << joined(args);
  }
  const CliRun top = run({});
  EXPECT_EQ(top.exit_code, 2);
  EXPECT_NE(top.out.find("analyze iso230-2 FILE"), std::string::npos) << top.out;
}

// A machine whose Y axis leans towards -X by 80 urad (xy out of square by +80 urad) and whose X
// scale is +25 um/m, seen by a tracker turned 30 degrees about Z and shifted; no noise. The runs
// and the grid are written as the tracker would export them.
struct GridFiles {
  std::string x_run, y_run, grid;
};

Vec3 tracker_reading(double x, double y, double z) {
  const double xa = x * (1 + 25e-6) - 80e-6 * y, ya = y, za = z;  // actual (machine frame)
  const double c = std::cos(kPi / 6), s = std::sin(kPi / 6);
  // tracker = R^T (actual - position), R = Rz(30 deg), position (500, -2000, 300)
  const double dx = xa - 500, dy = ya + 2000, dz = za - 300;
  return {c * dx + s * dy, -s * dx + c * dy, dz};
}

std::string grid_line(const std::string& name, double x, double y, double z) {
  const Vec3 m = tracker_reading(x, y, z);
  char line[256];
  std::snprintf(line, sizeof line, "%s,%.1f,%.1f,%.1f,%.9f,%.9f,%.9f\n", name.c_str(), x, y, z,
                m.v[0], m.v[1], m.v[2]);
  return line;
}

const char* kGridHeader = "point,x_cmd,y_cmd,z_cmd,x_meas,y_meas,z_meas\n";

// The X run, the Y run and the 216-point grid of the machine above, as the tracker exports them.
GridFiles sheared_grid() {
  GridFiles f{kGridHeader, kGridHeader, kGridHeader};
  for (int i = 0; i <= 10; ++i) {
    f.x_run += grid_line("x" + std::to_string(i), 200 + 400 * i, 950, 900);
  }
  for (int i = 0; i <= 9; ++i) {
    f.y_run += grid_line("y" + std::to_string(i), 2200, 200 + 150 * i, 900);
  }
  int n = 0;
  for (double z : {600.0, 800.0, 1000.0, 1200.0}) {
    for (double yy : {200.0, 500.0, 800.0, 1100.0, 1400.0, 1700.0}) {
      for (int i = 0; i < 9; ++i) {
        f.grid += grid_line("g" + std::to_string(n++), 200 + 500 * i, yy, z);
      }
    }
  }
  return f;
}

TEST_F(AnalyzeCli, GridJsonRecoversSquarenessAndScaleInTheMasterFrame) {
  const GridFiles files = sheared_grid();
  const std::string &x = files.x_run, &y = files.y_run, &g = files.grid;
  const json r = run_json({"analyze", "grid", "--x-run", write("x.csv", x), "--y-run",
                           write("y.csv", y), "--grid", write("g.csv", g)});
  ASSERT_TRUE(r.is_object());
  EXPECT_EQ(r["points"], 216);
  // By hand: the actual motions are X (1 + 25e-6, 0, 0), Y (-80e-6, 1, 0), Z (0, 0, 1):
  // angle(X, Y) = 90 deg + 80 urad, |X| - 1 = 25 um/m, the rest square and true.
  EXPECT_NEAR(r["squareness_xy_urad"].get<double>(), 80, 0.01);
  EXPECT_NEAR(r["squareness_yz_urad"].get<double>(), 0, 0.01);
  EXPECT_NEAR(r["squareness_zx_urad"].get<double>(), 0, 0.01);
  EXPECT_NEAR(r["scale_x_um_per_m"].get<double>(), 25, 0.01);
  EXPECT_NEAR(r["scale_y_um_per_m"].get<double>(), 0, 0.01);
  EXPECT_NEAR(r["master_frame"]["orthogonality_urad"].get<double>(), 80, 0.01);
  ASSERT_EQ(r["per_point"].size(), 216u);
  // The shear is spread over both axes: the worst point is a far corner, off by about
  // 25e-6 * dx + 40e-6 * dy there, not by the whole 80 urad lever.
  EXPECT_GT(r["max_deviation_mm"].get<double>(), 0.03);
  EXPECT_LT(r["max_deviation_mm"].get<double>(), 0.12);
  const CliRun table = run({"analyze", "grid", "--x-run", write("x2.csv", x), "--y-run",
                            write("y2.csv", y), "--grid", write("g2.csv", g)});
  EXPECT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("squareness xy"), std::string::npos) << table.out;
}

// Issue 37, point 9: with --machine the grid is judged against the machine's tolerances as the
// solver judges the monthly global_grid check. pm1 allows ±60 urad of XY squareness and ±40 um/m
// of scale: the grid above (80 urad, 25 um/m) fails on its squareness (and the rms deviation the
// shear spreads), with the cause the solver names first; without --machine there is no verdict.
TEST_F(AnalyzeCli, GridWithItsMachineIsJudgedAgainstItsTolerances) {
  const GridFiles files = sheared_grid();
  const std::string xf = write("x.csv", files.x_run), yf = write("y.csv", files.y_run),
                    gf = write("g.csv", files.grid);
  const std::string plant = std::string(NCQUAL_SOURCE_DIR) + "/deploy/plant.yaml";
  const std::vector<std::string> args = {"analyze", "grid", "--x-run",   xf,    "--y-run", yf,
                                         "--grid",  gf,     "--machine", "pm1", "--plant", plant};
  std::vector<std::string> with_json = args;
  with_json.push_back("--json");
  const CliRun judged = run(with_json);
  EXPECT_EQ(judged.exit_code, 3) << judged.err;
  const json r = json::parse(judged.out);
  EXPECT_EQ(r["verdict"], "FAIL");
  const json& check = r["check"];
  EXPECT_EQ(check["kind"], "global_grid");
  EXPECT_EQ(check["verdict"], "FAIL");
  std::map<std::string, json> metric;
  for (const json& m : check["metrics"]) metric[m["name"].get<std::string>()] = m;
  EXPECT_NEAR(metric.at("grid_squareness_xy_urad")["value"].get<double>(), 80, 0.01);
  EXPECT_EQ(metric.at("grid_squareness_xy_urad")["upper"].get<double>(), 60);
  EXPECT_FALSE(metric.at("grid_squareness_xy_urad")["pass"].get<bool>());
  EXPECT_NEAR(metric.at("grid_scale_x_um_per_m")["value"].get<double>(), 25, 0.01);
  EXPECT_TRUE(metric.at("grid_scale_x_um_per_m")["pass"].get<bool>());
  // The same figures as the analysis above them.
  EXPECT_NEAR(metric.at("grid_max_deviation_mm")["value"].get<double>(),
              r["max_deviation_mm"].get<double>(), 1e-9);
  // The shear spreads 0.064 mm rms over the grid, over pm1's 0.06: the second failure.
  EXPECT_NEAR(metric.at("grid_rms_deviation_mm")["value"].get<double>(),
              r["rms_deviation_mm"].get<double>(), 1e-9);
  EXPECT_FALSE(metric.at("grid_rms_deviation_mm")["pass"].get<bool>());
  int failed = 0;
  for (const auto& [name, m] : metric) failed += m["pass"].get<bool>() ? 0 : 1;
  EXPECT_EQ(failed, 2) << check["metrics"];
  ASSERT_FALSE(check["likely_causes"].empty());
  EXPECT_EQ(check["likely_causes"][0], "axes x and y out of square (way alignment)");

  const CliRun text = run(args);
  EXPECT_EQ(text.exit_code, 3) << text.err;
  EXPECT_NE(
      text.out.find("global_grid on pm1, judged as the solver judges the monthly check: FAIL"),
      std::string::npos)
      << text.out;
  EXPECT_NE(text.out.find("likely cause 1: axes x and y out of square"), std::string::npos)
      << text.out;

  const CliRun bare = run({"analyze", "grid", "--x-run", xf, "--y-run", yf, "--grid", gf});
  EXPECT_EQ(bare.exit_code, 0) << bare.err;
  EXPECT_NE(bare.out.find("verdict: none (pass --machine M"), std::string::npos) << bare.out;
  EXPECT_TRUE(
      json::parse(run({"analyze", "grid", "--x-run", xf, "--y-run", yf, "--grid", gf, "--json"})
                      .out)["verdict"]
          .is_null());
}

TEST_F(AnalyzeCli, BadGridFilesNameFileLineAndColumn) {
  std::string x = kGridHeader, y = kGridHeader;
  for (int i = 0; i <= 4; ++i) x += grid_line("x" + std::to_string(i), 200 + 400 * i, 950, 900);
  for (int i = 0; i <= 4; ++i) y += grid_line("y" + std::to_string(i), 2200, 200 + 150 * i, 900);
  const std::string xf = write("x.csv", x), yf = write("y.csv", y);
  auto refused = [&](const std::string& grid_text, const std::string& expected) {
    const std::string gf = write("bad.csv", grid_text);
    const CliRun r = run({"analyze", "grid", "--x-run", xf, "--y-run", yf, "--grid", gf});
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find(gf + ":" + expected), std::string::npos) << r.err;
  };
  const std::string a = grid_line("g0", 200, 200, 600), b = grid_line("g1", 700, 200, 800);
  const std::string c = grid_line("g2", 700, 700, 600), d = grid_line("g3", 200, 700, 1000);
  const std::string e = grid_line("g4", 1200, 500, 700);
  refused("point,x_cmd,y_cmd,z_cmd,x_meas,y_meas\ng0,200,200,600,1,2\n", "1:");  // no z_meas
  refused(std::string(kGridHeader) + a + "g1,700,abc,800,1,2,3\n", "3:3:");      // non-numeric
  refused(std::string(kGridHeader) + a + b + c + d + grid_line("g0", 1200, 500, 700), "6:1:");
  refused(std::string(kGridHeader) + a + b + c + d, "5:");                   // 4 < 5 points
  refused(std::string(kGridHeader) + a + b + c + d + e + "g5,1,2\n", "7:");  // cell count
}

// A tracker's point export (a name and x, y, z) has no commanded positions: without --machine it
// is refused saying what to pass; with pm1 a point of the program missing is refused naming it.
TEST_F(AnalyzeCli, TrackerPointExportsNeedTheMachineAndItsProgramsNames) {
  std::string x = kGridHeader, y = kGridHeader;
  for (int i = 0; i <= 4; ++i) x += grid_line("x" + std::to_string(i), 200 + 400 * i, 950, 900);
  for (int i = 0; i <= 4; ++i) y += grid_line("y" + std::to_string(i), 2200, 200 + 150 * i, 900);
  const std::string xf = write("x.csv", x), yf = write("y.csv", y);
  const std::string gf = write("points.txt", "Point\tX (mm)\tY (mm)\tZ (mm)\nGrid 0\t1\t2\t3\n");
  const CliRun bare = run({"analyze", "grid", "--x-run", xf, "--y-run", yf, "--grid", gf});
  EXPECT_EQ(bare.exit_code, 2) << bare.err;
  EXPECT_NE(bare.err.find(gf + " is a tracker's point export (a name and x, y, z, no commanded "
                               "positions): pass --machine M"),
            std::string::npos)
      << bare.err;
  const CliRun with = run({"analyze", "grid", "--x-run", xf, "--y-run", yf, "--grid", gf,
                           "--machine", "pm1", "--plant", NCQUAL_SOURCE_DIR "/deploy/plant.yaml"});
  EXPECT_EQ(with.exit_code, 1) << with.err;
  EXPECT_NE(with.err.find(gf + ":2: 215 of the program's 216 grid points are not in the export "
                               "(grid:1, grid:2, grid:3, grid:4, grid:5, ...)"),
            std::string::npos)
      << with.err;
}

// ---- cmm ----------------------------------------------------------------------------------------

// A PC-DMIS text report of a bracket in inches, worked by hand: PNT1's Z 0.003 in high against
// +-0.002 in fails; the X deviations 0.001 in (+-0.002) and 0.0005 in (+-0.004) weigh 4 : 1, so
// the part sits (4 * 0.001 + 0.0005) / 5 = 0.0009 in = 0.02286 mm high in X; Y and Z each have
// one feature whose full position is not in the report (CIR1 has no Z): no turn is fitted.
TEST_F(AnalyzeCli, CmmReportIsJudgedAndItsOffsetFitted) {
  const std::string report =
      write("bracket.rpt",
            "DIM LOC1= LOCATION OF POINT PNT1  UNITS=IN ,$\n"
            "AX    NOMINAL       +TOL       -TOL       MEAS        DEV     OUTTOL\n"
            "X      4.00000    0.00200    0.00200    4.00100    0.00100    0.00000 ----#----\n"
            "Y      2.00000    0.00200    0.00200    1.99900   -0.00100    0.00000 ----#----\n"
            "Z      0.50000    0.00200    0.00200    0.50300    0.00300    0.00100 --------->\n"
            "DIM LOC2= LOCATION OF CIRCLE CIR1  UNITS=IN ,$\n"
            "AX    NOMINAL       +TOL       -TOL       MEAS        DEV     OUTTOL\n"
            "X      6.00000    0.00400    0.00400    6.00050    0.00050    0.00000 ----#----\n"
            "Y      3.00000    0.00400    0.00400    3.00000    0.00000    0.00000 ----#----\n"
            "D      1.00000    0.00100    0.00000    1.00080    0.00080    0.00000 -------#-\n");
  const CliRun text = run({"analyze", "cmm", report});
  EXPECT_EQ(text.exit_code, 3) << text.err;
  EXPECT_NE(text.out.find("verdict: FAIL (1 of 6 out of tolerance: PNT1 Z)"), std::string::npos)
      << text.out;
  EXPECT_NE(text.out.find("displacement  dx +0.0229  dy -0.0203  dz +0.0762 mm"), std::string::npos)
      << text.out;
  const CliRun as_json = run({"analyze", "cmm", report, "--json"});
  EXPECT_EQ(as_json.exit_code, 3) << as_json.err;
  const json j = json::parse(as_json.out);
  EXPECT_EQ(j["format"], "PC-DMIS text");
  EXPECT_EQ(j["verdict"], "FAIL");
  EXPECT_NEAR(j["offset"]["translation_mm"][0].get<double>(), 0.0009 * 25.4, 1e-9);
  EXPECT_NEAR(j["offset"]["work_offset_correction_mm"][2].get<double>(), -0.003 * 25.4, 1e-9);
  EXPECT_TRUE(j["offset"]["rotation_urad"].is_null());
  EXPECT_EQ(j["per_characteristic"][2]["line"], 5);
  EXPECT_EQ(j["per_characteristic"][2]["in_tolerance"], false);
  EXPECT_NEAR(j["per_characteristic"][5]["upper_mm"].get<double>(), 0.0254, 1e-12);
  // A report whose deviations are nominal - actual is refused at its line, exit 1.
  const std::string reversed = write("reversed.csv",
                                     "Feature,Axis,Nominal (mm),Actual (mm),Deviation (mm)\n"
                                     "P1,X,10.000,10.020,-0.020\n");
  const CliRun refused = run({"analyze", "cmm", reversed});
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.err.find(reversed + ":2:5: the report's deviation -0.02 mm is not actual - "
                                        "nominal"),
            std::string::npos)
      << refused.err;
}

// ---- touches ------------------------------------------------------------------------------------

// The touch log of pm1's daily positioning program as a control writes it, worked by hand: the
// machine's axes read the true pivot minus `shift`; the ball (r = 3) meets the bore (R = 25) 22 mm
// from the taught centre (1200, 800), 5 mm below the face (z = 145), and the face (z = 150) with
// its centre at z = 153 beside the hole (x = 1235); the pivot is 350 mm above the ball.
std::string positioning_log(const std::string& request, Vec3 shift) {
  std::string log = "# request " + request + "\r\ntouch;x;y;z\r\n";
  const double ball[5][3] = {
      {1222, 800, 145}, {1200, 822, 145}, {1178, 800, 145}, {1200, 778, 145}, {1235, 800, 153}};
  for (int k = 0; k < 5; ++k) {
    char line[160];
    std::snprintf(line, sizeof line, "%d;%.6f;%.6f;%.6f\r\n", k + 1, ball[k][0] - shift.v[0],
                  ball[k][1] - shift.v[1], ball[k][2] + 350 - shift.v[2]);
    log += line;
  }
  return log;
}

TEST_F(AnalyzeCli, TouchesOfAHandWorkedLogAreJudgedAsTheServiceJudgesThem) {
  const std::string plant = std::string(NCQUAL_SOURCE_DIR) + "/deploy/plant.yaml";
  const std::string program = (dir_ / "daily3.nc").string();
  const CliRun p = run({"program", "--plant", plant, "--machine", "pm1", "--check",
                        "monument_positioning", "--dialect", "generic-csv", "--out", program});
  ASSERT_EQ(p.exit_code, 0) << p.err;
  const auto at = p.err.find("(request ");
  ASSERT_NE(at, std::string::npos) << p.err;
  const std::string request = p.err.substr(at + 9, p.err.find(')', at) - at - 9);
  EXPECT_NE(p.err.find("writes its touches to ncqual-" + request + ".csv"), std::string::npos);

  // 10 um, -4 um, 6 um: inside the +-25 um tolerances, PASS (exit 0) with the negated shift.
  const std::string log =
      write("ncqual-" + request + ".csv", positioning_log(request, {{0.010, -0.004, 0.006}}));
  const json r = run_json(
      {"analyze", "touches", log, "--program", program, "--machine", "pm1", "--plant", plant});
  EXPECT_EQ(r["verdict"], "PASS") << r.dump(2);
  EXPECT_EQ(r["request_id"], request);
  EXPECT_EQ(r["measurement"]["touches"], 5);
  std::map<std::string, double> value;
  for (const auto& m : r["metrics"]) value[m["name"]] = m["value"];
  EXPECT_NEAR(value["center_dx_mm"], -0.010, 1e-5);
  EXPECT_NEAR(value["center_dy_mm"], 0.004, 1e-5);
  EXPECT_NEAR(value["face_dz_mm"], -0.006, 1e-5);

  // 40 um in X: FAIL, exit 3, the metric flagged.
  const std::string bad =
      write("ncqual-" + request + ".csv", positioning_log(request, {{0.040, 0, 0}}));
  const CliRun fail =
      run({"analyze", "touches", bad, "--program", program, "--machine", "pm1", "--plant", plant});
  EXPECT_EQ(fail.exit_code, 3) << fail.out << fail.err;
  EXPECT_NE(fail.out.find("center_dx_mm"), std::string::npos) << fail.out;
  EXPECT_NE(fail.out.find("(!) out of tolerance"), std::string::npos) << fail.out;
  EXPECT_NE(fail.out.find("likely cause 1:"), std::string::npos) << fail.out;

  // A log with touch 4 missing: refused (exit 1) naming the log and the first missing touch.
  std::string text = positioning_log(request, {{0, 0, 0}});
  const auto four = text.find("\r\n4;");
  text.erase(four + 2, text.find("\r\n", four + 2) - four);
  const std::string missing = write("ncqual-" + request + ".csv", text);
  const CliRun refused = run(
      {"analyze", "touches", missing, "--program", program, "--machine", "pm1", "--plant", plant});
  EXPECT_EQ(refused.exit_code, 1) << refused.err;
  EXPECT_NE(refused.err.find(missing + ":"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("expected 5 touches, found 4; touch 4 is missing"), std::string::npos)
      << refused.err;

  // A tracker check has no control dialect: its program is the nominal point list for the
  // tracker's software, which reads back as a point export of the machine's program.
  const CliRun tracker = run({"program", "--plant", plant, "--machine", "pm1", "--check",
                              "global_grid", "--dialect", "linuxcnc"});
  EXPECT_EQ(tracker.exit_code, 2);
  EXPECT_NE(tracker.err.find("measured by the laser tracker"), std::string::npos) << tracker.err;
  const std::string nominals = (dir_ / "nominals.csv").string();
  const CliRun list = run({"program", "--plant", plant, "--machine", "pm1", "--check",
                           "global_grid", "--out", nominals});
  EXPECT_EQ(list.exit_code, 0) << list.err;
  EXPECT_NE(list.err.find("nominal points of global_grid on pm1"), std::string::npos) << list.err;
  const CliRun as_measured = run({"analyze", "grid", "--x-run", nominals, "--y-run", nominals,
                                  "--grid", nominals, "--machine", "pm1", "--plant", plant});
  EXPECT_EQ(as_measured.exit_code, 0) << as_measured.out << as_measured.err;
  // Each run takes its points from the whole list; what none takes (the grid's reflectors other
  // than 0: 216 points each of three) is said once.
  EXPECT_EQ(std::count(as_measured.err.begin(), as_measured.err.end(), '\n'), 1) << as_measured.err;
  EXPECT_NE(as_measured.err.find(": 648 points are not grid points of pm1's program (or not of "
                                 "its reflector 0) and not used: 'grid:0:t1' (line "),
            std::string::npos)
      << as_measured.err;
  const CliRun no_dialect =
      run({"program", "--plant", plant, "--machine", "pm1", "--check", "monument_positioning"});
  EXPECT_EQ(no_dialect.exit_code, 2);
  EXPECT_NE(no_dialect.err.find("--dialect is required for monument_positioning"),
            std::string::npos)
      << no_dialect.err;
  const CliRun dialect = run({"program", "--plant", plant, "--machine", "pm1", "--check",
                              "monument_positioning", "--dialect", "heidenhain"});
  EXPECT_EQ(dialect.exit_code, 2);
  EXPECT_NE(
      dialect.err.find("--dialect 'heidenhain': expected one of linuxcnc, fanuc, generic-csv"),
      std::string::npos)
      << dialect.err;
}

// ---- points -------------------------------------------------------------------------------------

// A tracker check other than the grid, measured by a real tracker: `ncqual program` writes the
// nominal list of pm1's rotary_c, the tracker's software exports the points under names of its
// own (made here from the list, by hand: the C points turned about the C axis), and `analyze
// points` judges the export against the list as the service judges the check.
TEST_F(AnalyzeCli, APointExportOfARotaryCheckIsJudgedAgainstItsNominalList) {
  using ncqual::testing::NominalRow;
  const std::string plant = std::string(NCQUAL_SOURCE_DIR) + "/deploy/plant.yaml";
  const std::string list = (dir_ / "rotary_c-nominals.csv").string();
  const CliRun p =
      run({"program", "--plant", plant, "--machine", "pm1", "--check", "rotary_c", "--out", list});
  ASSERT_EQ(p.exit_code, 0) << p.err;
  EXPECT_NE(p.err.find("ncqual analyze|import points EXPORT --nominals " + list), std::string::npos)
      << p.err;
  const std::vector<NominalRow> rows = ncqual::testing::read_nominal_rows(list);
  ASSERT_GT(rows.size(), 20u);
  const auto at = p.err.find("(request ");
  ASSERT_NE(at, std::string::npos) << p.err;
  const std::string request = p.err.substr(at + 9, p.err.find(')', at) - at - 9);

  // The C points turned by `arcsec` about the C axis: every dA is that angle, dR and the tilt
  // stay 0. The list gives positions to 0.05 um; over the C circle's radius that is the
  // tolerance of the figures.
  double radius = 1e9;
  for (const NominalRow& r : rows) {
    if (r.point.rfind("c:", 0) != 0) continue;
    radius = std::min(radius, (r.nominal_mm - r.machine_mm).head<2>().norm());
  }
  ASSERT_GT(radius, 10.0);
  const double rounding_arcsec = 2 * 0.05e-3 / radius * 206264.8;
  const auto turned = [&](double arcsec) {
    return ncqual::testing::point_export(rows, [&](const NominalRow& r) {
      return std::vector<Eigen::Vector3d>{
          r.point.rfind("c:", 0) == 0 ? ncqual::testing::turned_about_c(r, arcsec / 206264.8)
                                      : r.nominal_mm};
    });
  };
  // 10": within pm1's +-15", PASS (exit 0); the figures those of the turn.
  const std::string ten = write("rotary_c-10.txt", turned(10));
  const json r = run_json(
      {"analyze", "points", ten, "--nominals", list, "--machine", "pm1", "--plant", plant});
  EXPECT_EQ(r["verdict"], "PASS") << r.dump(2);
  EXPECT_EQ(r["request_id"], request);
  EXPECT_EQ(r["kind"], "rotary_c");
  EXPECT_EQ(r["measurement"]["tracker_points"], static_cast<int>(rows.size()));
  std::map<std::string, double> value;
  for (const auto& m : r["metrics"]) value[m["name"]] = m["value"];
  EXPECT_NEAR(value["c_dA_mean_arcsec"], 10, rounding_arcsec);
  EXPECT_NEAR(value["c_dA_range_arcsec"], 0, 2 * rounding_arcsec);
  EXPECT_NEAR(value["c_dR_max_mm"], 0, 1e-4);
  EXPECT_NEAR(value["c_axis_tilt_urad"], 0, 2);
  // 25": FAIL, exit 3, the mean flagged.
  const CliRun fail = run({"analyze", "points", write("rotary_c-25.txt", turned(25)), "--nominals",
                           list, "--machine", "pm1", "--plant", plant});
  EXPECT_EQ(fail.exit_code, 3) << fail.out << fail.err;
  EXPECT_NE(fail.out.find("rotary_c on pm1: " + std::to_string(rows.size()) + " points of "),
            std::string::npos)
      << fail.out;
  const auto mean = fail.out.find("c_dA_mean_arcsec");
  ASSERT_NE(mean, std::string::npos) << fail.out;
  EXPECT_NE(fail.out.find("(!) out of tolerance", mean), std::string::npos) << fail.out;

  // A point left out of the export: refused (exit 1), naming it.
  const std::string short_export =
      write("short.txt", ncqual::testing::point_export(rows, [](const NominalRow& r) {
              return r.point == "c:3" ? std::vector<Eigen::Vector3d>{}
                                      : std::vector<Eigen::Vector3d>{r.nominal_mm};
            }));
  const CliRun missing = run({"analyze", "points", short_export, "--nominals", list, "--machine",
                              "pm1", "--plant", plant});
  EXPECT_EQ(missing.exit_code, 1) << missing.err;
  EXPECT_NE(missing.err.find(short_export + ":"), std::string::npos) << missing.err;
  EXPECT_NE(missing.err.find("1 of the program's " + std::to_string(rows.size()) +
                             " rotary_c points are not in the export (c:3)"),
            std::string::npos)
      << missing.err;
  // A list whose point the machine's program no longer puts there (the global_check: section
  // changed since): refused, saying to write the list again.
  std::ifstream in(list);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string c3 = "\nc:3,";
  const auto row = text.find(c3);
  ASSERT_NE(row, std::string::npos);
  text.insert(row + c3.size(), "1");  // X gains 1000 mm or more
  const std::string stale = write("stale.csv", text);
  const CliRun refused =
      run({"analyze", "points", ten, "--nominals", stale, "--machine", "pm1", "--plant", plant});
  EXPECT_EQ(refused.exit_code, 1) << refused.err;
  EXPECT_NE(refused.err.find(stale + ": "), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("point 'c:3' is listed at ("), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("changed since the list was written; write the list again (ncqual "
                             "program --check rotary_c)"),
            std::string::npos)
      << refused.err;
  // A probing program is no nominal list.
  const std::string probe = (dir_ / "daily.nc").string();
  ASSERT_EQ(run({"program", "--plant", plant, "--machine", "pm1", "--check", "monument_positioning",
                 "--dialect", "linuxcnc", "--out", probe})
                .exit_code,
            0);
  const CliRun not_a_list =
      run({"analyze", "points", ten, "--nominals", probe, "--machine", "pm1", "--plant", plant});
  EXPECT_EQ(not_a_list.exit_code, 1) << not_a_list.err;
  EXPECT_NE(not_a_list.err.find("no '# NCQUAL TRACKER NOMINALS' line"), std::string::npos)
      << not_a_list.err;
}

}  // namespace

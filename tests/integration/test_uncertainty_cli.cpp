// SPDX-License-Identifier: Apache-2.0
// `ncqual uncertainty` end to end: a plant and machine config written here with a small monthly
// grid and its `global_check.uncertainty:` block, the built binary run with --json, and its
// document checked: the tracker-alone figures against eq. 24 worked here by hand (no solver
// linked), the search against a brute force over the same candidates, the Monte Carlo's response
// to a noisier tracker, its independence of the thread count, and the errors' exit codes.
#include "cli_runner.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using ncqual::testing_cli::CliRun;
using ncqual::testing_cli::run_cli;
using ncqual::testing_cli::run_cli_stdout;
using nlohmann::json;

constexpr double kPi = 3.14159265358979323846;

using V3 = std::array<double, 3>;

// The grid of the test machine: 5 x 4 x 3 pivot positions, 4 targets (tool length, offset).
const std::vector<double> kGridX{200, 700, 1200, 1700, 2200};
const std::vector<double> kGridY{200, 500, 800, 1100};
const std::vector<double> kGridZ{600, 800, 1000};
struct Target {
  double tool_length_mm, offset_x_mm, offset_y_mm;
};
const std::vector<Target> kTargets{{300, 0, 0}, {500, 0, 0}, {300, 150, 0}, {300, 0, 150}};

// The planned tracker (as in kUncertainty below).
const V3 kTrackerMm{1200, -1500, 800};
const V3 kTrackerYprDeg{90, 0.4, -0.3};
constexpr int kSamples = 4;

const char* kMachineHead = R"(probe: {tool_length_mm: 350.0, ball_radius_mm: 3.0}
monument: {hole_center_mm: [1200.0, 800.0], hole_diameter_mm: 50.0, face_z_mm: 150.0}
)";

const char* kGlobalCheck = R"(global_check:
  targets:
    - {tool_length_mm: 300}
    - {tool_length_mm: 500}
    - {tool_length_mm: 300, offset_mm: [150, 0]}
    - {tool_length_mm: 300, offset_mm: [0, 150]}
  master_frame:
    x_run: {x: {from_mm: 200, to_mm: 2200, points: 5}, at_mm: [600, 900]}
    y_run: {y: {from_mm: 200, to_mm: 1000, points: 5}, at_mm: [1200, 900]}
  grid:
    x: {from_mm: 200, to_mm: 2200, points: 5}
    y_mm: [200, 500, 800, 1100]
    z_mm: [600, 800, 1000]
  rotary:
    at_mm: [1200, 600, 1000]
    c: {a_deg: 45, from_deg: 0, to_deg: 300, points: 6}
    a: {c_deg: 0, from_deg: -60, to_deg: 60, points: 5}
    w: {w: {from_mm: 0, to_mm: 200, points: 5}}
  circles: {centre_mm: [1200, 600, 900], radius_mm: 200, points: 12}
  linear_run: {axis: x, at_mm: [0, 600, 900], targets_mm: [200, 1200, 2200], cycles: 2}
)";

// ANGULAR is replaced by the tracker's angular sigma (urad).
const char* kUncertainty = R"(  uncertainty:
    tracker:
      position_mm: [1200, -1500, 800]
      ypr_deg: [90, 0.4, -0.3]
      angular_sigma_urad: ANGULAR
      radial_sigma_mm: "4 um"
      radial_sigma_mm_per_m: "0.8 um"
      samples_per_point: 4
      position_sigma_mm: 0.5
      orientation_sigma_urad: 20
    sources:
      repeatability_sigma_mm: [0.0005, 0.0005, 0.0005]
      temperature_deviation_K: [0.4, 0.3, 0.6]
      temperature_sigma_K: [0.1, 0.1, 0.1]
    trials: 200
    seed: 7
    search:
      x_mm: [0, 2400]
      y_mm: [-2000, -600]
      z_mm: [400, 1200]
      step_mm: 400
)";

// The search box as configured: 7 x 5 x 3 candidates.
constexpr double kSearchLo[3] = {0, -2000, 400}, kSearchHi[3] = {2400, -600, 1200};
constexpr int kSearchSteps[3] = {7, 5, 3};

std::string uncertainty_block(double angular_urad) {
  std::string text = kUncertainty;
  char value[32];
  std::snprintf(value, sizeof value, "%g", angular_urad);
  return text.replace(text.find("ANGULAR"), 7, value);
}

// A nominal target at W = A = C = 0: the tool hangs along -Z from the pivot, offset in X, Y.
V3 target_mm(double x, double y, double z, const Target& t) {
  return {x + t.offset_x_mm, y + t.offset_y_mm, z - t.tool_length_mm};
}

struct GridPoint {
  std::string label;
  V3 target;
};

// In program order: target k outermost, then Z, Y, X; label grid:<(iz ny + iy) nx + ix>:t<k>.
std::vector<GridPoint> grid_points() {
  std::vector<GridPoint> out;
  const std::size_t nx = kGridX.size(), ny = kGridY.size();
  for (std::size_t k = 0; k < kTargets.size(); ++k) {
    for (std::size_t iz = 0; iz < kGridZ.size(); ++iz) {
      for (std::size_t iy = 0; iy < ny; ++iy) {
        for (std::size_t ix = 0; ix < nx; ++ix) {
          out.push_back(
              {"grid:" + std::to_string((iz * ny + iy) * nx + ix) + ":t" + std::to_string(k),
               target_mm(kGridX[ix], kGridY[iy], kGridZ[iz], kTargets[k])});
        }
      }
    }
  }
  return out;
}

// Eq. 24 (the solver header's formula) by hand: the point in the tracker frame, local =
// R^T (p - position) with R = Rz(yaw) Ry(pitch) Rx(roll); range r, elevation e from the tracker's
// x-y plane; one averaged point has u_r = (4 um + 0.8 um/m r) / sqrt(n) and u_a = u_e =
// sigma_angle / sqrt(n); u_p = sqrt(u_r^2 + r^2 u_e^2 + r^2 cos^2 e u_a^2). Returns mm.
double u_p_by_hand(const V3& p, const V3& position, double yaw, double pitch, double roll,
                   double angular_sigma_rad) {
  const double cy = std::cos(yaw), sy = std::sin(yaw), cp = std::cos(pitch), sp = std::sin(pitch);
  const double cr = std::cos(roll), sr = std::sin(roll);
  // Rows of R = Rz Ry Rx.
  const double R[3][3] = {{cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr},
                          {sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr},
                          {-sp, cp * sr, cp * cr}};
  const double d[3] = {p[0] - position[0], p[1] - position[1], p[2] - position[2]};
  double local[3] = {0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) local[i] += R[k][i] * d[k];  // R^T d
  }
  const double r = std::sqrt(local[0] * local[0] + local[1] * local[1] + local[2] * local[2]);
  const double cos2_e = (local[0] * local[0] + local[1] * local[1]) / (r * r);
  const double avg = 1.0 / std::sqrt(static_cast<double>(kSamples));
  const double u_r = (0.004 + 0.0008 * r / 1000) * avg;
  const double u_a = angular_sigma_rad * avg;
  return std::sqrt(u_r * u_r + r * r * u_a * u_a + r * r * cos2_e * u_a * u_a);
}

double rad(double deg) { return deg * kPi / 180; }

class UncertaintyCli : public ::testing::Test {
 protected:
  // A plant with machines: u1 (the block, 20 urad), u2 (40 urad), u3 (global_check without the
  // block), u4 (the block without its search), u5 (no global_check).
  void SetUp() override {
    const std::string head = kMachineHead;
    std::string no_search = uncertainty_block(20);
    no_search.erase(no_search.find("    search:"));
    const std::vector<std::string> machines{
        tmp_.write("u1.yaml", "machine_id: u1\n" + head + kGlobalCheck + uncertainty_block(20)),
        tmp_.write("u2.yaml", "machine_id: u2\n" + head + kGlobalCheck + uncertainty_block(40)),
        tmp_.write("u3.yaml", "machine_id: u3\n" + head + kGlobalCheck),
        tmp_.write("u4.yaml", "machine_id: u4\n" + head + kGlobalCheck + no_search),
        tmp_.write("u5.yaml", "machine_id: u5\n" + head)};
    std::string plant =
        "plant: uncertainty-test\ndomain_id: 0\nsimulated: true\nhistorian:\n  database: " +
        (tmp_.path() / "historian.db").string() + "\nmachines:\n";
    for (const auto& m : machines) plant += "  - " + m + "\n";
    plant_ = tmp_.write("plant.yaml", plant);
  }

  // `ncqual uncertainty` of `machine` with the fixed words of `extra` after it.
  std::vector<std::string> command(const std::string& machine,
                                   const std::string& extra = "") const {
    std::vector<std::string> args{"uncertainty", "--plant", plant_, "--machine", machine};
    for (auto& word : ncqual::testing_cli::words(extra)) args.push_back(word);
    return args;
  }

  // The --json document of a run that must succeed, and its text.
  json run_json(const std::string& machine, const std::string& extra, std::string* text = nullptr) {
    const CliRun r = run_cli_stdout(command(machine, extra + " --json"));
    EXPECT_EQ(r.exit_code, 0) << r.out;
    if (text) *text = r.out;
    try {
      return json::parse(r.out);
    } catch (const json::exception& e) {
      ADD_FAILURE() << "not JSON: " << e.what() << "\n" << r.out;
      return json::object();
    }
  }

  ncqual::testing_cli::TempDir tmp_{"ncqual-uncertainty-cli"};
  std::string plant_;
};

TEST_F(UncertaintyCli, JsonDescribesTheRunAndTheTrackerAloneIsEq24ByHand) {
  const json doc = run_json("u1", "--threads 1 --search");
  ASSERT_TRUE(doc.contains("points")) << doc.dump();
  EXPECT_EQ(doc.at("machine_id"), "u1");
  EXPECT_EQ(doc.at("machine_errors"), "zero");
  EXPECT_EQ(doc.at("method"), "linearised");
  EXPECT_EQ(doc.at("trials"), 200);  // from the config
  EXPECT_EQ(doc.at("seed"), 7);
  const std::vector<GridPoint> grid = grid_points();
  ASSERT_EQ(doc.at("points").size(), grid.size());
  EXPECT_EQ(doc.at("design").at("points"), grid.size());
  EXPECT_EQ(doc.at("design").at("observations"), 3 * grid.size());
  EXPECT_NEAR(doc.at("tracker").at("ypr_deg").at(1).get<double>(), 0.4, 1e-12);
  EXPECT_NEAR(doc.at("tracker").at("radial_sigma_um").get<double>(), 4, 1e-12);
  EXPECT_NEAR(doc.at("sources").at("expansion_um_per_m_K").at(2).get<double>(), 11.5, 1e-9);

  // Every point's tracker u_p, the max, its point and the mean: eq. 24 by hand (um).
  const double yaw = rad(kTrackerYprDeg[0]), pitch = rad(kTrackerYprDeg[1]);
  const double roll = rad(kTrackerYprDeg[2]);
  double max_u = 0, sum_u = 0;
  std::string worst;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const json& p = doc.at("points").at(i);
    ASSERT_EQ(p.at("label"), grid[i].label);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(p.at("target_mm").at(k).get<double>(),
                  grid[i].target[static_cast<std::size_t>(k)], 1e-9);
    }
    const double u = 1e3 * u_p_by_hand(grid[i].target, kTrackerMm, yaw, pitch, roll, 20e-6);
    EXPECT_NEAR(p.at("tracker_u_p_um").get<double>(), u, 1e-9 * u) << grid[i].label;
    sum_u += u;
    if (u > max_u) {
      max_u = u;
      worst = grid[i].label;
    }
  }
  const json& alone = doc.at("tracker_alone");
  EXPECT_NEAR(alone.at("max_u_p_um").get<double>(), max_u, 1e-9 * max_u);
  EXPECT_EQ(alone.at("worst_point"), worst);
  EXPECT_NEAR(alone.at("mean_u_p_um").get<double>(), sum_u / static_cast<double>(grid.size()),
              1e-9 * max_u);

  // The distributions: mean <= 95 % <= largest; the worst points sorted, the first the largest
  // bound of all points.
  for (const char* name : {"trial_max_residual_um", "trial_mean_residual_um"}) {
    const json& s = doc.at(name);
    EXPECT_GT(s.at("mean_um").get<double>(), 0) << name;
    EXPECT_LE(s.at("mean_um").get<double>(), s.at("quantile95_um").get<double>()) << name;
    EXPECT_LE(s.at("quantile95_um").get<double>(), s.at("max_um").get<double>()) << name;
  }
  EXPECT_GE(doc.at("trial_max_residual_um").at("mean_um").get<double>(),
            doc.at("trial_mean_residual_um").at("mean_um").get<double>());
  double largest_bound = 0;
  for (const auto& p : doc.at("points"))
    largest_bound = std::max(largest_bound, p.at("bound95_um").get<double>());
  const json& worst_points = doc.at("worst_points");
  ASSERT_EQ(worst_points.size(), 5u);
  EXPECT_EQ(worst_points.at(0).at("bound95_um").get<double>(), largest_bound);
  EXPECT_EQ(doc.at("max_bound95_um").get<double>(), largest_bound);
  for (std::size_t i = 1; i < worst_points.size(); ++i) {
    EXPECT_LE(worst_points.at(i).at("bound95_um").get<double>(),
              worst_points.at(i - 1).at("bound95_um").get<double>());
  }

  // The search: a brute force over the same candidates (envelope of the targets + 200 mm kept
  // out, every target 0.5 m to 15 m away, facing the envelope's centre) finds the same best.
  V3 lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
  for (const auto& g : grid) {
    for (std::size_t k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], g.target[k]);
      hi[k] = std::max(hi[k], g.target[k]);
    }
  }
  const V3 centre{(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  double best = 1e9;
  int tried = 0, excluded = 0;
  for (int iz = 0; iz < kSearchSteps[2]; ++iz) {
    for (int iy = 0; iy < kSearchSteps[1]; ++iy) {
      for (int ix = 0; ix < kSearchSteps[0]; ++ix) {
        const int idx[3] = {ix, iy, iz};
        V3 c{};
        bool inside = true;
        for (int k = 0; k < 3; ++k) {
          c[static_cast<std::size_t>(k)] =
              kSearchLo[k] + (kSearchHi[k] - kSearchLo[k]) * idx[k] / (kSearchSteps[k] - 1);
          const double v = c[static_cast<std::size_t>(k)];
          inside = inside && v >= lo[static_cast<std::size_t>(k)] - 200 &&
                   v <= hi[static_cast<std::size_t>(k)] + 200;
        }
        bool in_range = true;
        for (const auto& g : grid) {
          const double r = std::hypot(g.target[0] - c[0], g.target[1] - c[1], g.target[2] - c[2]);
          in_range = in_range && r >= 500 && r <= 15000;
        }
        if (inside || !in_range) {
          ++excluded;
          continue;
        }
        ++tried;
        const double facing = std::atan2(centre[1] - c[1], centre[0] - c[0]);
        double mx = 0;
        for (const auto& g : grid)
          mx = std::max(mx, 1e3 * u_p_by_hand(g.target, c, facing, pitch, roll, 20e-6));
        best = std::min(best, mx);
      }
    }
  }
  const json& search = doc.at("search");
  ASSERT_TRUE(search.is_object()) << search.dump();
  EXPECT_EQ(search.at("tried"), tried);
  EXPECT_EQ(search.at("excluded"), excluded);
  EXPECT_EQ(search.at("steps"), json::array({7, 5, 3}));
  EXPECT_NEAR(search.at("best").at("max_u_p_um").get<double>(), best, 1e-9 * best);
  EXPECT_NEAR(search.at("configured").at("max_u_p_um").get<double>(), max_u, 1e-9 * max_u);
}

TEST_F(UncertaintyCli, BoundsGrowWhenTheTrackersAngularSigmaDoubles) {
  const json base = run_json("u1", "--threads 1");
  const json noisy = run_json("u2", "--threads 1");  // 40 urad instead of 20, same seed
  ASSERT_TRUE(base.contains("points") && noisy.contains("points"));
  // Every trial draws the same standard normals (seed 7): the angular part of each reading's
  // noise doubles, the rest (range, repeatability, thermal, placement) stays. The angular noise
  // dominates here (r ~ 1 to 2.5 m: 20 urad x 2 m = 40 um against a 5 um range), so the bounds
  // grow by about 2: a little less for what does not grow, a little more because the BIC (its
  // assumed point sigma fixed) keeps more terms of a noisier fit.
  const double q_base = base.at("trial_max_residual_um").at("quantile95_um").get<double>();
  const double q_noisy = noisy.at("trial_max_residual_um").at("quantile95_um").get<double>();
  EXPECT_GT(q_noisy, 1.5 * q_base);
  EXPECT_LT(q_noisy, 2.5 * q_base);
  const double b_base = base.at("max_bound95_um").get<double>();
  const double b_noisy = noisy.at("max_bound95_um").get<double>();
  EXPECT_GT(b_noisy, 1.5 * b_base);
  EXPECT_LT(b_noisy, 2.5 * b_base);
  int grew = 0;
  const std::size_t n = base.at("points").size();
  for (std::size_t i = 0; i < n; ++i) {
    const double a = base.at("points").at(i).at("bound95_um").get<double>();
    const double b = noisy.at("points").at(i).at("bound95_um").get<double>();
    if (b > 1.2 * a) ++grew;
  }
  EXPECT_EQ(grew, static_cast<int>(n));
  EXPECT_GT(noisy.at("tracker_alone").at("max_u_p_um").get<double>(),
            1.8 * base.at("tracker_alone").at("max_u_p_um").get<double>());
}

TEST_F(UncertaintyCli, SameSeedSameOutputWhateverTheThreads) {
  std::string one, again, two, other;
  run_json("u1", "--threads 1 --trials 120", &one);
  run_json("u1", "--threads 1 --trials 120", &again);
  run_json("u1", "--threads 2 --trials 120", &two);
  run_json("u1", "--threads 2 --trials 120 --seed 8", &other);
  EXPECT_EQ(one, again);
  EXPECT_EQ(one, two);
  EXPECT_NE(one, other);  // the seed matters, so the equalities above say something
  EXPECT_EQ(json::parse(one).at("trials"), 120);
  EXPECT_EQ(json::parse(other).at("seed"), 8);
  // The text report too.
  const CliRun t1 = run_cli(command("u1", "--threads 1 --trials 50"));
  const CliRun t2 = run_cli(command("u1", "--threads 2 --trials 50"));
  EXPECT_EQ(t1.exit_code, 0) << t1.out;
  EXPECT_EQ(t1.out, t2.out);
  EXPECT_NE(t1.out.find("machine errors: zero"), std::string::npos) << t1.out;
  EXPECT_NE(t1.out.find("Tracker alone"), std::string::npos) << t1.out;
}

TEST_F(UncertaintyCli, ErrorsSayWhatIsMissingAndBadUsageExitsTwo) {
  const CliRun no_block = run_cli(command("u3"));
  EXPECT_EQ(no_block.exit_code, 1) << no_block.out;
  EXPECT_NE(no_block.out.find("global_check.uncertainty"), std::string::npos) << no_block.out;

  const CliRun no_search = run_cli(command("u4", "--search"));
  EXPECT_EQ(no_search.exit_code, 1) << no_search.out;
  EXPECT_NE(no_search.out.find("global_check.uncertainty.search"), std::string::npos)
      << no_search.out;

  const CliRun no_global = run_cli(command("u5"));
  EXPECT_EQ(no_global.exit_code, 1) << no_global.out;
  EXPECT_NE(no_global.out.find("no global_check"), std::string::npos) << no_global.out;

  const CliRun unknown = run_cli(command("nope"));
  EXPECT_EQ(unknown.exit_code, 2) << unknown.out;  // bad usage, as in every command
  EXPECT_NE(unknown.out.find("'nope' is not configured"), std::string::npos) << unknown.out;

  const std::string bad_config = tmp_.write(
      "u6.yaml",
      std::string("machine_id: u6\n") + kMachineHead + kGlobalCheck +
          "  uncertainty: {tracker: {position_mm: [0, -900, 500], samples_per_point: 0}}\n");
  const std::string plant6 =
      tmp_.write("plant6.yaml",
                 "plant: p6\ndomain_id: 0\nsimulated: true\nmachines:\n  - " + bad_config + "\n");
  const CliRun bad = run_cli({"uncertainty", "--plant", plant6, "--machine", "u6"});
  EXPECT_EQ(bad.exit_code, 1) << bad.out;
  EXPECT_NE(bad.out.find("global_check.uncertainty.tracker.samples_per_point = '0'"),
            std::string::npos)
      << bad.out;

  for (const char* extra : {"--trials 0", "--trials -3", "--trials many", "--trials 1.5",
                            "--threads 0", "--threads 65", "--seed -1", "--bogus", "extra"}) {
    const CliRun r = run_cli(command("u1", extra));
    EXPECT_EQ(r.exit_code, 2) << extra << "\n" << r.out;
    EXPECT_NE(r.out.find("usage:"), std::string::npos) << extra << "\n" << r.out;
  }
  const CliRun no_machine = run_cli({"uncertainty", "--plant", plant_});
  EXPECT_EQ(no_machine.exit_code, 2) << no_machine.out;
  EXPECT_NE(no_machine.out.find("--machine"), std::string::npos) << no_machine.out;
}

}  // namespace

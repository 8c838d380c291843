// SPDX-License-Identifier: Apache-2.0
// `ncqual budget` end to end without DDS: a plant config with a machine budget, a historian
// written with storage::Database holding known metric values, the built `ncqual` binary run with
// --json, and its document checked against the budget library and hand computations.
#include "cli_runner.hpp"

#include "ncqual/solver/error_budget.hpp"
#include "ncqual/storage/database.hpp"
#include "ncqual/common/units.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace ncqual {
namespace {

namespace fs = std::filesystem;

using testing_cli::CliRun;
using testing_cli::run_cli;
using testing_cli::run_cli_stdout;

class BudgetCli : public ::testing::Test {
 protected:
  std::string write(const std::string& name, const std::string& text) {
    return tmp_.write(name, text);
  }

  std::string db_path() const { return (dir_ / "historian.db").string(); }

  std::string write_plant(const std::vector<std::string>& machine_files) {
    std::string text =
        "plant: budget-test\ndomain_id: 0\nsimulated: true\nhistorian:\n  database: " + db_path() +
        "\nmachines:\n";
    for (const auto& m : machine_files) text += "  - " + m + "\n";
    return write("plant.yaml", text);
  }

  testing_cli::TempDir tmp_{"ncqual-budget-cli"};
  const fs::path dir_ = tmp_.path();
};

const char* kMachineBase = R"(probe: {tool_length_mm: 350.0, ball_radius_mm: 3.0}
monument: {hole_center_mm: [1200.0, 800.0], hole_diameter_mm: 50.0, face_z_mm: 150.0}
tolerances:
  center_dy_mm: 0.025
  face_dz_mm: 0.025
  c_angle_error_arcsec: {lower: -8, upper: 8}
)";

const char* kBudget = R"(budget:
  allowable_total: "0.03 in"
  part: {panel_radius: "74 in", theta_min: "0 deg", theta_max: "25 deg"}
  statistics: {samples: 20000, seed: 3}
  sources:
    - {name: machine_y, direction: y, metrics: [center_dy_mm], capability: "0.004 in"}
    - {name: machine_z, direction: z, metrics: [face_dz_mm], capability: "0.004 in"}
    - name: c_axis_rotation
      direction: y
      metrics: [{name: c_angle_error_arcsec, lever_arm: "350 mm"}]
      capability: "15 arcsec"
    - {name: drill_wander, direction: s, allowance: "0.005 in"}
)";

CheckResult result(const std::string& machine, const std::string& id, CheckKind kind,
                   std::int64_t time_ns, Verdict verdict, std::vector<Metric> metrics) {
  CheckResult r;
  r.machine_id = machine;
  r.request_id = id;
  r.kind = kind;
  r.verdict = verdict;
  r.time_ns = time_ns;
  r.metrics = std::move(metrics);
  return r;
}

Metric metric(const std::string& name, double value, const std::string& unit) {
  return {name, value, unit, -1, 1, true};
}

const nlohmann::json& source_named(const nlohmann::json& doc, const std::string& name) {
  for (const auto& s : doc.at("sources")) {
    if (s.at("name") == name) return s;
  }
  throw std::runtime_error("no source " + name + " in " + doc.dump());
}

TEST_F(BudgetCli, JsonFromAHistorianWithKnownValues) {
  const std::string m1 = write("m1.yaml", std::string("machine_id: m1\n") + kMachineBase + kBudget);
  const std::string plant = write_plant({m1});

  // Six positioning checks (newest last in this list), three C-rotation checks (too few for a
  // capability from history), one INVALID result and another machine's result that must be
  // ignored.
  const std::vector<double> dy = {0.004, -0.003, 0.006, 0.001, 0.002, 0.012};  // oldest first
  const std::vector<double> dz = {0.010, 0.011, 0.009, 0.010, 0.012, 0.008};
  const std::vector<double> dc = {2.0, -4.0, 3.5};
  {
    auto db = storage::Database::open(db_path());
    const std::int64_t t0 = 1'800'000'000'000'000'000;
    for (std::size_t i = 0; i < dy.size(); ++i) {
      db.store(result("m1", "pos-" + std::to_string(i), CheckKind::MonumentPositioning,
                      t0 + static_cast<std::int64_t>(i) * 1'000'000'000, Verdict::Pass,
                      {metric("center_dx_mm", 0.001, "mm"), metric("center_dy_mm", dy[i], "mm"),
                       metric("face_dz_mm", dz[i], "mm")}));
    }
    for (std::size_t i = 0; i < dc.size(); ++i) {
      db.store(result("m1", "crot-" + std::to_string(i), CheckKind::MonumentCRotation,
                      t0 + static_cast<std::int64_t>(i) * 1'000'000'000 + 500, Verdict::Pass,
                      {metric("c_angle_error_arcsec", dc[i], "arcsec")}));
    }
    db.store(result("m1", "bad", CheckKind::MonumentPositioning, t0 + 100'000'000'000,
                    Verdict::Invalid, {metric("center_dy_mm", 9.0, "mm")}));
    db.store(result("m2", "other", CheckKind::MonumentPositioning, t0 + 200'000'000'000,
                    Verdict::Fail, {metric("center_dy_mm", 5.0, "mm")}));
  }

  const CliRun run = run_cli_stdout({"budget", "--plant", plant, "--machine", "m1", "--json"});
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const nlohmann::json doc = nlohmann::json::parse(run.out);

  EXPECT_EQ(doc.at("machine_id"), "m1");
  EXPECT_EQ(doc.at("database"), db_path());
  EXPECT_EQ(doc.at("method"), "rss");
  EXPECT_NEAR(doc.at("allowable_total_mm").get<double>(), 0.762, 1e-12);
  EXPECT_NEAR(doc.at("allowable_total_in").get<double>(), 0.03, 1e-12);
  EXPECT_NEAR(doc.at("theta_max_deg").get<double>(), 25, 1e-9);
  ASSERT_EQ(doc.at("sources").size(), 4u);

  // Largest consumer first.
  double previous = 1e9;
  for (const auto& s : doc.at("sources")) {
    EXPECT_LE(s.at("today_contribution_mm").get<double>(), previous);
    previous = s.at("today_contribution_mm").get<double>();
  }

  // machine_y: capability from its six values (newest first), today's value the newest.
  const std::vector<double> dy_newest_first(dy.rbegin(), dy.rend());
  const solver::MetricCapability cap_y =
      solver::capability_from_history(dy_newest_first, 30, units::inch_to_mm(0.004), 0.9973);
  const auto& my = source_named(doc, "machine_y");
  EXPECT_EQ(my.at("capability_basis"), "history");
  EXPECT_NEAR(my.at("capability_mm").at("y").get<double>(), cap_y.capability, 1e-12);
  const auto& my_metric = my.at("metrics").at(0);
  EXPECT_EQ(my_metric.at("name"), "center_dy_mm");
  EXPECT_EQ(my_metric.at("samples"), 6);
  EXPECT_DOUBLE_EQ(my_metric.at("today_value").get<double>(), 0.012);
  EXPECT_NEAR(my_metric.at("configured_tolerance").at("upper").get<double>(), 0.025, 1e-12);
  EXPECT_NEAR(my_metric.at("sensitivity").get<double>(), 1.0, 1e-12);  // cos 0
  const double scale = doc.at("allocation").at("scale").get<double>();
  EXPECT_NEAR(my.at("allocation_mm").at("y").get<double>(), scale * cap_y.capability, 1e-12);
  EXPECT_NEAR(my_metric.at("derived_tolerance").get<double>(), scale * cap_y.capability, 1e-12);

  // machine_z: the Z metric's sensitivity is sin 25°.
  const auto& mz = source_named(doc, "machine_z");
  EXPECT_NEAR(mz.at("metrics").at(0).at("sensitivity").get<double>(),
              std::sin(units::deg_to_rad(25)), 1e-12);
  EXPECT_DOUBLE_EQ(mz.at("metrics").at(0).at("today_value").get<double>(), 0.008);

  // c_axis_rotation: three values are too few; the default (15 arcsec × 350 mm) stands, today's
  // value is the newest (3.5 arcsec) and the configured tolerance is in arcsec.
  const auto& cr = source_named(doc, "c_axis_rotation");
  EXPECT_EQ(cr.at("capability_basis"), "default");
  EXPECT_NEAR(cr.at("capability_mm").at("y").get<double>(), units::arcsec_to_rad(15) * 350, 1e-12);
  const auto& cr_metric = cr.at("metrics").at(0);
  EXPECT_EQ(cr_metric.at("unit"), "arcsec");
  EXPECT_EQ(cr_metric.at("samples"), 3);
  EXPECT_DOUBLE_EQ(cr_metric.at("today_value").get<double>(), 3.5);
  EXPECT_NEAR(cr_metric.at("configured_tolerance").at("upper").get<double>(), 8, 1e-12);
  EXPECT_NEAR(cr_metric.at("derived_tolerance").get<double>(), scale * 15, 1e-9);

  // Fixed allowance.
  const auto& dw = source_named(doc, "drill_wander");
  EXPECT_TRUE(dw.at("fixed").get<bool>());
  EXPECT_NEAR(dw.at("allocation_mm").at("s").get<double>(), 0.127, 1e-12);

  // Today's total by hand: at θ, sqrt(Σ today ΔS²), and the shares add up to (total / T)².
  const double theta = units::deg_to_rad(doc.at("rss_theta_deg").get<double>());
  const double y_today = 0.012, c_today = units::arcsec_to_rad(3.5) * 350;
  const double by_hand =
      std::sqrt(std::pow(y_today * std::cos(theta), 2) + std::pow(c_today * std::cos(theta), 2) +
                std::pow(0.008 * std::sin(theta), 2) + 0.127 * 0.127);
  EXPECT_NEAR(doc.at("rss_total_mm").get<double>(), by_hand, 1e-12);
  double shares = 0;
  for (const auto& s : doc.at("sources")) shares += s.at("share").get<double>();
  EXPECT_NEAR(shares, std::pow(by_hand / 0.762, 2), 1e-12);
  EXPECT_TRUE(doc.at("within_budget").get<bool>());
  EXPECT_NEAR(doc.at("allocation_rss_total_mm").get<double>(), 0.762, 1e-12);
  EXPECT_GT(doc.at("monte_carlo_total_mm").get<double>(), 0);

  // The table prints too, with the verdict.
  const CliRun table = run_cli({"budget", "--plant", plant, "--machine", "m1"});
  ASSERT_EQ(table.exit_code, 0) << table.out;
  EXPECT_NE(table.out.find("WITHIN BUDGET"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("center_dy_mm"), std::string::npos) << table.out;

  // --last 2: only the two newest values count (too few: back to the default capability).
  const CliRun last2 =
      run_cli_stdout({"budget", "--plant", plant, "--machine", "m1", "--json", "--last", "2"});
  ASSERT_EQ(last2.exit_code, 0) << last2.out;
  const auto doc2 = nlohmann::json::parse(last2.out);
  EXPECT_EQ(source_named(doc2, "machine_y").at("metrics").at(0).at("samples"), 2);
  EXPECT_EQ(source_named(doc2, "machine_y").at("capability_basis"), "default");
}

TEST_F(BudgetCli, OverBudgetWhenTodaysValuesAreLarge) {
  const std::string m1 = write("m1.yaml", std::string("machine_id: m1\n") + kMachineBase + kBudget);
  const std::string plant = write_plant({m1});
  {
    auto db = storage::Database::open(db_path());
    db.store(result("m1", "big", CheckKind::MonumentPositioning, 1'000, Verdict::Fail,
                    {metric("center_dy_mm", -0.9, "mm")}));
  }
  const CliRun run = run_cli_stdout({"budget", "--plant", plant, "--machine", "m1", "--json"});
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto doc = nlohmann::json::parse(run.out);
  EXPECT_FALSE(doc.at("within_budget").get<bool>());
  EXPECT_EQ(doc.at("sources").at(0).at("name"), "machine_y");  // the largest consumer first
  EXPECT_FALSE(doc.at("sources").at(0).at("metrics").at(0).at("today_within_derived_tolerance"));
}

// Issue 37, point 4: a machine the scheduler holds (NEEDS_INTERVENTION after its positioning
// check failed face_dz_mm by 0.05 mm against ±0.025 mm) has a total far within the part's
// allowable (0.05 mm of Z at 25° is 0.021 mm of ΔS), but is never shown within budget; once an
// intervention and a passing check clear it, it is.
TEST_F(BudgetCli, AHeldMachineIsNeverWithinBudget) {
  const std::string m1 = write("m1.yaml", std::string("machine_id: m1\n") + kMachineBase + kBudget);
  const std::string plant = write_plant({m1});
  const std::int64_t t0 = 1'800'000'000'000'000'000;
  const auto status = [](std::int64_t time_ns, MachineState state, const std::string& detail) {
    MachineStatus st;
    st.machine_id = "m1";
    st.request_id = "pos-fail";
    st.state = state;
    st.detail = detail;
    st.time_ns = time_ns;
    return st;
  };
  {
    auto db = storage::Database::open(db_path());
    db.store(result("m1", "pos-fail", CheckKind::MonumentPositioning, t0, Verdict::Fail,
                    {Metric{"center_dy_mm", 0.002, "mm", -0.025, 0.025, true},
                     Metric{"face_dz_mm", 0.05, "mm", -0.025, 0.025, false}}));
    db.store(status(t0 + 1, MachineState::NeedsIntervention, "monument_positioning FAIL"));
  }
  const CliRun run = run_cli_stdout({"budget", "--plant", plant, "--machine", "m1", "--json"});
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto doc = nlohmann::json::parse(run.out);
  EXPECT_TRUE(doc.at("total_within_allowable").get<bool>());  // the arithmetic alone
  EXPECT_FALSE(doc.at("within_budget").get<bool>());
  EXPECT_EQ(doc.at("verdict"), "HELD");
  EXPECT_TRUE(doc.at("held").get<bool>());
  ASSERT_EQ(doc.at("failed_metrics").size(), 1u);
  EXPECT_EQ(doc.at("failed_metrics").at(0).get<std::string>().rfind("face_dz_mm = 0.05 mm", 0), 0u)
      << doc.at("failed_metrics");
  ASSERT_EQ(doc.at("verdict_why").size(), 2u);
  EXPECT_NE(doc.at("verdict_why")
                .at(0)
                .get<std::string>()
                .find("the machine is held: NEEDS_INTERVENTION since"),
            std::string::npos)
      << doc.at("verdict_why");
  // The Z metric's derived tolerance by hand: 0.762 mm shared between machine_y (0.1016 mm
  // along Y), machine_z (0.1016 mm along Z) and the C rotation (15" × 350 mm along Y) at the
  // binding θ, after the drill wander's fixed 0.127 mm: at 25°, k² = (T² - 0.127²) / Σ (c_i s_i)²
  // with s = cos 25° for Y and sin 25° for Z; at 0°, Z counts nothing.
  const double c25 = std::cos(units::deg_to_rad(25)), s25 = std::sin(units::deg_to_rad(25));
  const double cy = 0.1016, cz = 0.1016, cc = units::arcsec_to_rad(15) * 350;
  const double k25 =
      std::sqrt((0.762 * 0.762 - 0.127 * 0.127) /
                (std::pow(cy * c25, 2) + std::pow(cz * s25, 2) + std::pow(cc * c25, 2)));
  const double k0 = std::sqrt((0.762 * 0.762 - 0.127 * 0.127) / (cy * cy + cc * cc));
  const double k = std::min(k25, k0);
  EXPECT_NEAR(doc.at("allocation").at("scale").get<double>(), k, 1e-9);
  EXPECT_NEAR(
      source_named(doc, "machine_z").at("metrics").at(0).at("derived_tolerance").get<double>(),
      k * cz, 1e-9);  // about ±0.32 mm beside the configured ±0.025 mm

  const CliRun table = run_cli({"budget", "--plant", plant, "--machine", "m1"});
  ASSERT_EQ(table.exit_code, 0) << table.out;
  EXPECT_EQ(table.out.find("WITHIN BUDGET"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("Verdict: HELD"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("the machine is held: NEEDS_INTERVENTION"), std::string::npos)
      << table.out;
  EXPECT_NE(table.out.find("derived tol.: how far the metric may read"), std::string::npos)
      << table.out;

  // Cleared: an intervention, the check again, PASS, QUALIFIED.
  {
    auto db = storage::Database::open(db_path());
    db.store(result("m1", "pos-again", CheckKind::MonumentPositioning, t0 + 1'000'000'000,
                    Verdict::Pass,
                    {Metric{"center_dy_mm", 0.002, "mm", -0.025, 0.025, true},
                     Metric{"face_dz_mm", 0.004, "mm", -0.025, 0.025, true}}));
    db.store(status(t0 + 1'000'000'001, MachineState::Qualified, ""));
  }
  const CliRun cleared = run_cli_stdout({"budget", "--plant", plant, "--machine", "m1", "--json"});
  ASSERT_EQ(cleared.exit_code, 0) << cleared.out;
  const auto after = nlohmann::json::parse(cleared.out);
  EXPECT_EQ(after.at("verdict"), "WITHIN_BUDGET");
  EXPECT_TRUE(after.at("within_budget").get<bool>());
  EXPECT_TRUE(after.at("verdict_why").empty());
}

TEST_F(BudgetCli, ErrorsSayWhatIsWrong) {
  const std::string m1 = write("m1.yaml", std::string("machine_id: m1\n") + kMachineBase + kBudget);
  const std::string m2 = write("m2.yaml", std::string("machine_id: m2\n") + kMachineBase);
  const std::string plant = write_plant({m1, m2});

  // No historian file yet: the defaults, with a note.
  const CliRun fresh = run_cli({"budget", "--plant", plant, "--machine", "m1"});
  EXPECT_EQ(fresh.exit_code, 0) << fresh.out;
  EXPECT_NE(fresh.out.find("no historian"), std::string::npos) << fresh.out;

  const CliRun unknown = run_cli({"budget", "--plant", plant, "--machine", "nope"});
  EXPECT_EQ(unknown.exit_code, 2) << unknown.out;  // bad usage, as in every command
  EXPECT_NE(unknown.out.find("'nope' is not configured"), std::string::npos) << unknown.out;

  const CliRun no_budget = run_cli({"budget", "--plant", plant, "--machine", "m2"});
  EXPECT_EQ(no_budget.exit_code, 1) << no_budget.out;
  EXPECT_NE(no_budget.out.find("no budget"), std::string::npos) << no_budget.out;

  const CliRun missing_db =
      run_cli({"budget", "--plant", plant, "--machine", "m1", "--db", (dir_ / "none.db").string()});
  EXPECT_EQ(missing_db.exit_code, 1) << missing_db.out;
  EXPECT_NE(missing_db.out.find("none.db"), std::string::npos) << missing_db.out;

  const std::string bad =
      write("m3.yaml", std::string("machine_id: m3\n") + kMachineBase +
                           "budget: {allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, "
                           "sources: [{name: a, direction: q, allowance: 1}]}\n");
  const std::string plant3 = write_plant({bad});
  const CliRun bad_run = run_cli({"budget", "--plant", plant3, "--machine", "m3"});
  EXPECT_EQ(bad_run.exit_code, 1) << bad_run.out;
  EXPECT_NE(bad_run.out.find("budget.sources[0].direction"), std::string::npos) << bad_run.out;

  const CliRun usage = run_cli({"budget", "--plant", plant});
  EXPECT_EQ(usage.exit_code, 2) << usage.out;
  EXPECT_NE(usage.out.find("--machine"), std::string::npos) << usage.out;
}

}  // namespace
}  // namespace ncqual

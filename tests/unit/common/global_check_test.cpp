// SPDX-License-Identifier: Apache-2.0
// The `global_check:` section of a machine config and the programs of the monthly tracker checks.
#include "machine_text.hpp"

#include "ncqual/common/config.hpp"
#include "ncqual/common/global_check.hpp"
#include "ncqual/common/units.hpp"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>

namespace ncqual {
namespace {

using testing::parse_machine_section;

const std::string kGlobal = R"(
global_check:
  targets:
    - {tool_length_mm: 300}
    - {tool_length_in: 20, offset_mm: [150, 0]}
  master_frame:
    x_run: {x: {from_mm: 200, to_mm: 4200, points: 11}, at_mm: [950, 900]}
    y_run: {y_mm: [200, 500, 800, 1100, 1400, 1700], at_mm: [2200, 900]}
  grid:
    x: {from_mm: 200, to_mm: 4200, points: 9}
    y: {from_mm: 200, to_mm: 1700, points: 6}
    z_in: [24, 32, 40, 48]
  rotary:
    at_mm: [2200, 950, 1000]
    c: {a_deg: 45, from_deg: 0, to_deg: 330, points: 12}
    a: {c_deg: 0, from_deg: -90, to_deg: 90, points: 13}
    w: {w: {from_mm: 0, to_mm: 300, points: 7}}
  circles: {centre_mm: [2200, 950, 900], radius_mm: 300, points: 36, bidirectional: true}
  linear_run:
    axis: y
    at_mm: [1000, 0, 900]
    targets_mm: [200, 610, 1015, 1430]
    cycles: 3
)";

// Replaces the first occurrence of `from` in kGlobal.
std::string with(const std::string& from, const std::string& to) {
  return testing::replace_first(kGlobal, from, to);
}

TEST(GlobalCheckConfig, ParsesRangesListsUnitsAndTargets) {
  const MachineConfig m = parse_machine_section(kGlobal);
  ASSERT_TRUE(m.global_check);
  const GlobalCheckConfig& g = *m.global_check;
  ASSERT_EQ(g.targets.size(), 2u);
  EXPECT_DOUBLE_EQ(g.targets[1].tool_length_mm, 20 * 25.4);
  EXPECT_DOUBLE_EQ(g.targets[1].stylus_offset_mm.x(), 150);
  ASSERT_EQ(g.x_run_mm.size(), 11u);
  EXPECT_DOUBLE_EQ(g.x_run_mm[1], 600);
  EXPECT_EQ(g.y_run_mm.size(), 6u);
  EXPECT_DOUBLE_EQ(g.grid_z_mm[3], 48 * 25.4);
  EXPECT_NEAR(g.c_check_a_rad, units::deg_to_rad(45), 1e-15);
  EXPECT_NEAR(g.c_check_c_rad[11], units::deg_to_rad(330), 1e-12);
  EXPECT_EQ(g.a_check_a_rad.size(), 13u);
  EXPECT_EQ(g.w_check_w_mm.size(), 7u);
  EXPECT_EQ(g.circle.points, 36);
  EXPECT_EQ(g.linear_run.axis, 1);
  EXPECT_EQ(g.linear_run.cycles, 3);
}

TEST(GlobalCheckConfig, NoSectionMeansNoTrackerCheck) {
  EXPECT_FALSE(parse_machine_section("").global_check);
}

TEST(GlobalCheckConfig, RefusesBadValuesNamingTheKey) {
  auto refused = [](const std::string& text, const std::string& key) {
    try {
      parse_machine_section(text);
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
      return;
    }
    ADD_FAILURE() << "accepted: " << key;
  };
  refused(with("- {tool_length_mm: 300}", "- {tool_length_mm: 0}"),
          "global_check.targets[0].tool_length_mm");
  refused(with("points: 9}", "points: 1}"), "global_check.grid.x.points");
  refused(with("a_deg: 45", "a_deg: 0"), "global_check.rotary.c.a_deg");
  refused(with("axis: y", "axis: w"), "global_check.linear_run.axis");
  refused(with("cycles: 3", "cycles: 1"), "global_check.linear_run.cycles");
  refused(with("radius_mm: 300", "radius_mm: -3"), "global_check.circles.radius_mm");
  refused(with("at_mm: [2200, 900]", "at_mm: [2200, 901]"),
          "global_check.master_frame.y_run.at_mm");
  refused(with("y_mm: [200, 500,", "y_mm: [500, 200,"), "global_check.master_frame.y_run.y");
  refused(with("  grid:", "  gird: {}\n  grid:"), "global_check.gird");
}

TEST(GlobalCheckProgram, EveryKindStartsWithTheMasterFrameRuns) {
  const GlobalCheckConfig g = *parse_machine_section(kGlobal).global_check;
  for (CheckKind kind : all_check_kinds()) {
    if (!is_tracker_check(kind)) {
      EXPECT_THROW(global_check_program(kind, g), std::invalid_argument);
      continue;
    }
    const auto moves = global_check_program(kind, g);
    if (kind == CheckKind::LinearAxisRun) {  // its own station: no master-frame runs
      EXPECT_EQ(moves[0].label, "");
      continue;
    }
    ASSERT_GE(moves.size(), 17u) << to_string(kind);
    EXPECT_EQ(moves[0].label, "x_run:0");
    EXPECT_DOUBLE_EQ(moves[10].commanded.x_mm, 4200);
    EXPECT_DOUBLE_EQ(moves[10].commanded.y_mm, 950);
    EXPECT_EQ(moves[11].label, "y_run:0");
    EXPECT_DOUBLE_EQ(moves[16].commanded.y_mm, 1700);
    std::set<std::string> labels;
    for (const auto& m : moves) {
      if (!m.label.empty()) {
        EXPECT_TRUE(labels.insert(m.label).second) << m.label;
      }
    }
  }
}

TEST(GlobalCheckProgram, GridCoversEveryPointWithEveryTarget) {
  const GlobalCheckConfig g = *parse_machine_section(kGlobal).global_check;
  const auto moves = global_check_program(CheckKind::GlobalGrid, g);
  ASSERT_EQ(moves.size(), 17u + 2 * 216);
  // point i = (iz * ny + iy) * nx + ix; target 1 after all of target 0.
  const TrackerMove& m = moves[17 + 216 + (2 * 6 + 3) * 9 + 4];
  EXPECT_EQ(m.label, "grid:" + std::to_string((2 * 6 + 3) * 9 + 4) + ":t1");
  EXPECT_EQ(m.target, 1);
  EXPECT_DOUBLE_EQ(m.commanded.x_mm, 200 + 4 * 500);
  EXPECT_DOUBLE_EQ(m.commanded.y_mm, 200 + 3 * 300);
  EXPECT_DOUBLE_EQ(m.commanded.z_mm, 40 * 25.4);
}

TEST(GlobalCheckProgram, CircleRunsBothWaysFromTheSameSideAndRotaryHoldsXyz) {
  const GlobalCheckConfig g = *parse_machine_section(kGlobal).global_check;
  const auto circle = global_check_program(CheckKind::CircleYZ, g);
  std::map<std::string, AxisPosition> at;
  for (const auto& m : circle) {
    if (!m.label.empty()) at[m.label] = m.commanded;
    if (m.label.rfind("x_run", 0) == 0 || m.label.rfind("y_run", 0) == 0) continue;
    EXPECT_DOUBLE_EQ(m.commanded.x_mm, 2200);  // the YZ plane
  }
  ASSERT_EQ(at.size(), 17u + 72u);
  EXPECT_NEAR(at["ccw:9"].y_mm, 950, 1e-9);  // 90 degrees: +v
  EXPECT_NEAR(at["ccw:9"].z_mm, 900 + 300, 1e-9);
  EXPECT_NEAR(at["cw:9"].z_mm, at["ccw:9"].z_mm, 1e-12);
  for (CheckKind kind : {CheckKind::RotaryA, CheckKind::RotaryC, CheckKind::RotaryW}) {
    for (const auto& m : global_check_program(kind, g)) {
      if (m.label.rfind("x_run", 0) == 0 || m.label.rfind("y_run", 0) == 0) continue;
      EXPECT_DOUBLE_EQ(m.commanded.x_mm, 2200);
      EXPECT_DOUBLE_EQ(m.commanded.y_mm, 950);
      EXPECT_DOUBLE_EQ(m.commanded.z_mm, 1000);
    }
  }
}

TEST(GlobalCheckProgram, LinearRunApproachesEveryTargetFromBothSidesWithOverrun) {
  const GlobalCheckConfig g = *parse_machine_section(kGlobal).global_check;
  const auto moves = global_check_program(CheckKind::LinearAxisRun, g);
  int measured = 0;
  double previous = 0;
  for (std::size_t i = 0; i < moves.size(); ++i) {
    const auto& m = moves[i];
    if (!m.label.empty()) {
      ++measured;
      const bool up = m.label.find(":up:") != std::string::npos;
      // Arrived from below when up, from above when down.
      EXPECT_EQ(m.commanded.y_mm > previous, up) << m.label;
    }
    previous = m.commanded.y_mm;
  }
  EXPECT_EQ(measured, 3 * 2 * 4);
}

// ---- global_check.uncertainty ------------------------------------------------------------------

const std::string kUncertainty = R"(
  uncertainty:
    tracker:
      position_mm: [2200, -1200, 900]
      ypr_deg: [90, 0.3, -0.2]
      angular_sigma_urad: 20
      radial_sigma_mm: "4 um"
      radial_sigma_mm_per_m: 0.0008
      samples_per_point: 16
      position_sigma_mm: 0.5
      orientation_sigma_urad: "0.01 deg"
    sources:
      repeatability_sigma_mm: [0.001, 0.002, 0.0015]
      expansion_per_K: [11.5e-6, 12e-6, 10e-6]
      temperature_deviation_K: [0.4, -0.3, 0.6]
      temperature_sigma_K: [0.1, 0.1, 0.2]
    trials: 500
    seed: 18446744073709551615
    search:
      x_mm: [0, 4400]
      y_mm: [-3500, -400]
      z_mm: [900, 900]
      step_mm: 400
      envelope_clearance_mm: 150
      max_range_mm: 9000
)";

TEST(GlobalCheckUncertainty, ParsesUnitsDefaultsAndTheSearchGrid) {
  const GlobalCheckConfig g = *parse_machine_section(kGlobal + kUncertainty).global_check;
  ASSERT_TRUE(g.uncertainty);
  const VerificationUncertaintyConfig& u = *g.uncertainty;
  EXPECT_EQ(u.tracker.position_mm, Eigen::Vector3d(2200, -1200, 900));
  EXPECT_NEAR(u.tracker.ypr_rad[0], units::kPi / 2, 1e-15);
  EXPECT_NEAR(u.tracker.ypr_rad[1], 0.3 * units::kPi / 180, 1e-15);
  EXPECT_NEAR(u.tracker.ypr_rad[2], -0.2 * units::kPi / 180, 1e-15);
  EXPECT_NEAR(u.tracker.angular_sigma_rad, 20e-6, 1e-18);
  EXPECT_NEAR(u.tracker.radial_sigma_mm, 0.004, 1e-15);
  EXPECT_DOUBLE_EQ(u.tracker.radial_sigma_mm_per_m, 0.0008);
  EXPECT_EQ(u.tracker.samples_per_point, 16);
  EXPECT_DOUBLE_EQ(u.tracker.position_sigma_mm, 0.5);
  EXPECT_NEAR(u.tracker.orientation_sigma_rad, 0.01 * units::kPi / 180, 1e-15);
  EXPECT_EQ(u.sources.repeatability_sigma_mm, Eigen::Vector3d(0.001, 0.002, 0.0015));
  EXPECT_EQ(u.sources.expansion_per_K, Eigen::Vector3d(11.5e-6, 12e-6, 10e-6));
  // Not given: the rule's value for a 2e-6 1/K wide rectangle, 2e-6 / (2 sqrt 3).
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(u.sources.expansion_sigma_per_K[k], 5.7735e-7, 1e-11);
  EXPECT_EQ(u.sources.temperature_deviation_K, Eigen::Vector3d(0.4, -0.3, 0.6));
  EXPECT_EQ(u.sources.temperature_sigma_K, Eigen::Vector3d(0.1, 0.1, 0.2));
  EXPECT_EQ(u.trials, 500);
  EXPECT_EQ(u.seed, 18446744073709551615ull);
  ASSERT_TRUE(u.search);
  EXPECT_EQ(u.search->lo_mm, Eigen::Vector3d(0, -3500, 900));
  EXPECT_EQ(u.search->hi_mm, Eigen::Vector3d(4400, -400, 900));
  // 4400 / 400 = 11 steps exactly: 12 positions; 3100 / 400 = 7.75: 8 steps of 387.5 mm, 9
  // positions; an empty Z range: its one value.
  EXPECT_EQ(u.search->steps, Eigen::Vector3i(12, 9, 1));
  EXPECT_DOUBLE_EQ(u.search->envelope_clearance_mm, 150);
  EXPECT_DOUBLE_EQ(u.search->min_range_mm, 500);  // default
  EXPECT_DOUBLE_EQ(u.search->max_range_mm, 9000);
}

TEST(GlobalCheckUncertainty, MinimalBlockTakesTheSolversDefaults) {
  const GlobalCheckConfig g = *parse_machine_section(kGlobal + R"(
  uncertainty:
    tracker: {position_mm: [0, -2000, 500]}
)")
                                   .global_check;
  ASSERT_TRUE(g.uncertainty);
  const VerificationUncertaintyConfig& u = *g.uncertainty;
  EXPECT_EQ(u.tracker.ypr_rad, Eigen::Vector3d::Zero());
  EXPECT_DOUBLE_EQ(u.tracker.angular_sigma_rad, 20e-6);
  EXPECT_DOUBLE_EQ(u.tracker.radial_sigma_mm, 0.004);
  EXPECT_DOUBLE_EQ(u.tracker.radial_sigma_mm_per_m, 0.0008);
  EXPECT_EQ(u.tracker.samples_per_point, 1);
  EXPECT_EQ(u.tracker.position_sigma_mm, 0);
  EXPECT_EQ(u.tracker.orientation_sigma_rad, 0);
  EXPECT_EQ(u.sources.repeatability_sigma_mm, Eigen::Vector3d::Zero());
  EXPECT_EQ(u.sources.expansion_per_K, Eigen::Vector3d::Constant(11.5e-6));
  EXPECT_EQ(u.sources.temperature_sigma_K, Eigen::Vector3d::Zero());
  EXPECT_EQ(u.trials, 1000);
  EXPECT_EQ(u.seed, 1u);
  EXPECT_FALSE(u.search);
  // And a global_check without the block has none.
  EXPECT_FALSE(parse_machine_section(kGlobal).global_check->uncertainty);
}

TEST(GlobalCheckUncertainty, RefusesBadValuesNamingFileKeyAndValue) {
  const std::string base = kGlobal + kUncertainty;
  auto refused = [&](const std::string& from, const std::string& to, const std::string& message) {
    std::string text = base;
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    try {
      parse_machine_section(text);
    } catch (const ConfigError& e) {
      // "<file>: <key> = '<value>': <why>", like every config error.
      EXPECT_EQ(std::string(e.what()).rfind("t1.yaml: " + message, 0), 0u) << e.what();
      return;
    }
    ADD_FAILURE() << "accepted: " << to;
  };
  const std::string p = "global_check.uncertainty.";
  refused("angular_sigma_urad: 20", "angular_sigma_urad: -20",
          p + "tracker.angular_sigma_urad = '-20': a sigma must be >= 0");
  refused("position_sigma_mm: 0.5", "position_sigma_mm: nan",
          p + "tracker.position_sigma_mm = 'nan': ");
  refused("temperature_deviation_K: [0.4, -0.3, 0.6]", "temperature_deviation_K: [0.4, inf, 0.6]",
          p + "sources.temperature_deviation_K[1] = 'inf': must be finite");
  refused("temperature_sigma_K: [0.1, 0.1, 0.2]", "temperature_sigma_K: [0.1, -0.1, 0.2]",
          p + "sources.temperature_sigma_K[1] = '-0.1': a sigma must be >= 0");
  refused("repeatability_sigma_mm: [0.001, 0.002, 0.0015]",
          "repeatability_sigma_mm: [0.001, 0.002]",
          p + "sources.repeatability_sigma_mm = (not a single value): expected a list of 3");
  refused("trials: 500", "trials: 0", p + "trials = '0': must be an integer from 1 to 1000000");
  refused("trials: 500", "trials: 2.5", p + "trials = '2.5': must be an integer");
  refused("samples_per_point: 16", "samples_per_point: 0",
          p + "tracker.samples_per_point = '0': must be an integer from 1");
  refused("seed: 18446744073709551615", "seed: -1", p + "seed = '-1': expected an integer");
  refused("x_mm: [0, 4400]", "x_mm: [4400, 0]", p + "search.x_mm[1] = '0': max must be >= min");
  refused("step_mm: 400", "step_mm: 0", p + "search.step_mm = '0': must be positive");
  refused("step_mm: 400", "step_mm: 0.1", p + "search.step_mm = '0.1': gives more than 1e6");
  refused("max_range_mm: 9000", "max_range_mm: 400",
          p + "search.max_range_mm = '400': must exceed min_range_mm");
  refused("ypr_deg: [90, 0.3, -0.2]", "ypr_deg: [90, 0.3, \"1 furlong\"]",
          p + "tracker.ypr_deg[2] = ");
  refused("      position_mm: [2200, -1200, 900]\n", "",
          p + "tracker.position_mm = (missing): required");
  refused("    trials: 500", "    trails: 500", p + "trails = '500': unknown key");
  refused("      samples_per_point: 16", "      samples: 16",
          p + "tracker.samples = '16': unknown key");
  refused("    tracker:\n", "    tracer: {}\n    tracker:\n", p + "tracer");
}

}  // namespace
}  // namespace ncqual

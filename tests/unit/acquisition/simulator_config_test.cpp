// SPDX-License-Identifier: Apache-2.0
#include "ncqual/sim/simulator_config.hpp"

#include "ncqual/common/units.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace ncqual::sim {
namespace {

// A machine config whose simulator section is `simulator_yaml` (indented under `simulator:`).
MachineConfig machine_with_simulator(const std::string& simulator_yaml) {
  const std::string text = R"(
machine_id: t1
probe: {tool_length_mm: 300, ball_radius_mm: 2}
monument: {hole_center_mm: [10, 20], hole_diameter_mm: 40, face_z_mm: 100}
)" + simulator_yaml;
  return parse_machine_config(text, "t1.yaml");
}

TEST(SimulatorConfig, DefaultsWhenSectionAbsentOrEmpty) {
  for (const std::string section : {"", "simulator:\n", "simulator: {}\n"}) {
    const SimulatorConfig c = machine_with_simulator(section).simulator;
    EXPECT_EQ(c.seed, 1u) << section;
    EXPECT_DOUBLE_EQ(c.trigger_noise_sigma_mm, 0.001) << section;
    EXPECT_TRUE(c.errors.machine_shift_mm.isZero()) << section;
    EXPECT_TRUE(c.errors.monument_shift_mm.isZero()) << section;
    EXPECT_TRUE(c.errors.stylus_offset_mm.isZero()) << section;
    EXPECT_EQ(c.errors.tool_length_error_mm, 0) << section;
    EXPECT_EQ(c.errors.c_angle_error_rad, 0) << section;
    EXPECT_EQ(c.errors.a_home_error_rad, 0) << section;
  }
}

TEST(SimulatorConfig, ReadsTheExampleMachine) {
  const MachineConfig m = load_machine_config(NCQUAL_SOURCE_DIR "/deploy/machines/pm1.yaml");
  const SimulatorConfig c = m.simulator;
  EXPECT_EQ(c.seed, 42u);
  EXPECT_DOUBLE_EQ(c.trigger_noise_sigma_mm, 0.001);
  EXPECT_TRUE(c.errors.machine_shift_mm.isZero());
  EXPECT_EQ(c.errors.c_angle_error_rad, 0);
}

TEST(SimulatorConfig, ReadsEveryErrorWithItsUnits) {
  const SimulatorConfig c = machine_with_simulator(R"(
simulator:
  seed: 1234
  trigger_noise_sigma_mm: "2 um"
  plate_thickness_mm: 12.5
  errors:
    machine_shift_mm: [0.01, "0.001 in", -0.02]
    monument_shift_mm: [0, 0.005, "-3 um"]
    stylus_offset_mm: [0.004, -0.002]
    tool_length_error_mm: "0.0005 in"
    c_angle_error_arcsec: 30
    a_home_error_deg: 0.01
)")
                                .simulator;
  EXPECT_EQ(c.seed, 1234u);
  EXPECT_NEAR(c.trigger_noise_sigma_mm, 0.002, 1e-15);
  EXPECT_DOUBLE_EQ(c.plate_thickness_mm, 12.5);
  EXPECT_TRUE(
      c.errors.machine_shift_mm.isApprox(Eigen::Vector3d(0.01, units::inch_to_mm(0.001), -0.02)));
  EXPECT_TRUE(c.errors.monument_shift_mm.isApprox(Eigen::Vector3d(0, 0.005, -0.003)));
  EXPECT_TRUE(c.errors.stylus_offset_mm.isApprox(Eigen::Vector2d(0.004, -0.002)));
  EXPECT_DOUBLE_EQ(c.errors.tool_length_error_mm, units::inch_to_mm(0.0005));
  EXPECT_DOUBLE_EQ(c.errors.c_angle_error_rad, units::arcsec_to_rad(30));
  EXPECT_DOUBLE_EQ(c.errors.a_home_error_rad, units::deg_to_rad(0.01));
}

TEST(SimulatorConfig, AnglesUnderRadKeysAndUnitStrings) {
  const SimulatorConfig c = machine_with_simulator(R"(
simulator:
  errors:
    c_angle_error_rad: 0.0001
    a_home_error_arcsec: "0.5 deg"
)")
                                .simulator;
  EXPECT_DOUBLE_EQ(c.errors.c_angle_error_rad, 0.0001);
  EXPECT_DOUBLE_EQ(c.errors.a_home_error_rad, units::deg_to_rad(0.5));
}

struct BadSection {
  const char* yaml;
  std::vector<std::string> message_must_name;
};

TEST(SimulatorConfig, RefusesBadValuesNamingFileKeyAndValue) {
  const BadSection cases[] = {
      {"simulator: 3\n", {"t1.yaml", "simulator", "'3'", "mapping"}},
      {"simulator: {seed: -1}\n", {"t1.yaml", "seed", "'-1'"}},
      {"simulator: {seed: 1.5}\n", {"seed", "'1.5'", "integer"}},
      {"simulator: {seed: nan}\n", {"seed", "'nan'"}},
      {"simulator: {trigger_noise_sigma_mm: -0.001}\n", {"trigger_noise_sigma_mm", "'-0.001'"}},
      {"simulator: {trigger_noise_sigma_mm: 1 furlong}\n",
       {"trigger_noise_sigma_mm", "'1 furlong'", "furlong"}},
      {"simulator: {plate_thickness_mm: 0}\n", {"plate_thickness_mm", "'0'", "positive"}},
      {"simulator: {trigger_noise: 0.1}\n", {"trigger_noise", "unknown key"}},
      {"simulator: {errors: [1, 2]}\n", {"errors", "mapping"}},
      {"simulator: {errors: {machine_shift_mm: [0.1, 0.2]}}\n",
       {"simulator.errors", "machine_shift_mm", "list of 3"}},
      {"simulator: {errors: {machine_shift_mm: [0.1, x, 0]}}\n", {"machine_shift_mm[1]", "'x'"}},
      {"simulator: {errors: {stylus_offset_mm: [0.1, 0.2, 0.3]}}\n",
       {"stylus_offset_mm", "list of 2"}},
      {"simulator: {errors: {machine_shift: [0, 0, 0]}}\n", {"machine_shift", "unknown key"}},
      {"simulator: {errors: {c_angle_error_arcsec: 3, c_angle_error_deg: 1}}\n",
       {"c_angle_error_deg", "c_angle_error_arcsec", "give one"}},
      {"simulator: {errors: {a_home_error_arcsec: 3 mm}}\n", {"a_home_error_arcsec", "'3 mm'"}},
      {"simulator: {errors: {tool_length_error_mm: [1]}}\n", {"tool_length_error_mm"}},
  };
  for (const auto& bad : cases) {
    try {
      machine_with_simulator(bad.yaml).simulator;
      ADD_FAILURE() << "accepted: " << bad.yaml;
    } catch (const ConfigError& e) {
      const std::string what = e.what();
      for (const auto& part : bad.message_must_name) {
        EXPECT_NE(what.find(part), std::string::npos)
            << "message '" << what << "' does not name '" << part << "' for: " << bad.yaml;
      }
    }
  }
}

}  // namespace
}  // namespace ncqual::sim

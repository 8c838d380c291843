// SPDX-License-Identifier: Apache-2.0
// The `fixture:` section of a machine config, the fixture's configurations and the names the
// acquisition and the solver share (pogo labels, touch features, zero offsets).
#include "machine_text.hpp"

#include "ncqual/common/config.hpp"
#include "ncqual/common/fixture.hpp"
#include "ncqual/common/units.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace ncqual {
namespace {

using testing::parse_machine_section;

const std::string kFixture = R"(
fixture:
  fixture_id: UHF1
  origin_mm: [0, 0, "4 in"]
  columns: {count: 4, first_x_mm: 1800, pitch_mm: 600}
  rows: {count: 6, first_y_mm: 250, pitch_mm: 300}
  reference_block: {size_mm: 100, height_mm: 40}
  probe_depth_mm: 10
)";

// Replaces the first occurrence of `from` in kFixture.
std::string fixture_with(const std::string& from, const std::string& to) {
  return testing::replace_first(kFixture, from, to);
}

TEST(FixtureConfig, AbsentSectionMeansNoFixture) {
  EXPECT_FALSE(parse_machine_section("").fixture.has_value());
  EXPECT_FALSE(parse_machine_section("fixture:\n").fixture.has_value());
}

TEST(FixtureConfig, ReadsCountFirstPitchAndDefaults) {
  const MachineConfig m = parse_machine_section(kFixture);
  ASSERT_TRUE(m.fixture);
  const FixtureConfig& f = *m.fixture;
  EXPECT_EQ(f.fixture_id, "UHF1");
  EXPECT_TRUE(f.origin_mm.isApprox(Eigen::Vector3d(0, 0, 101.6)));
  EXPECT_EQ(f.column_home_x_mm, (std::vector<double>{1800, 2400, 3000, 3600}));
  EXPECT_EQ(f.row_home_y_mm, (std::vector<double>{250, 550, 850, 1150, 1450, 1750}));
  // Default planes: 0, 6, 12, 18, 24 in.
  ASSERT_EQ(f.z_planes_mm.size(), 5u);
  for (int k = 0; k < 5; ++k)
    EXPECT_DOUBLE_EQ(f.z_planes_mm[static_cast<std::size_t>(k)], 6 * 25.4 * k);
  EXPECT_EQ(f.precalibration_configuration_count(), 10);
  EXPECT_DOUBLE_EQ(f.block_half_size_mm(), 50);
  EXPECT_DOUBLE_EQ(f.block_height_mm, 40);
  EXPECT_DOUBLE_EQ(f.probe_depth_mm, 10);
  // Default post-calibration: the 6 in and 18 in planes, 2 Y and 3 X offsets.
  EXPECT_EQ(f.postcalibration.z_mm, (std::vector<double>{6 * 25.4, 18 * 25.4}));
  EXPECT_EQ(f.postcalibration.y_offsets_mm, (std::vector<double>{-75, 75}));
  EXPECT_EQ(f.postcalibration.x_offsets_mm, (std::vector<double>{-150, 0, 150}));
  EXPECT_EQ(f.postcalibration_configuration_count(), 12);
  EXPECT_TRUE(f.to_machine(Eigen::Vector3d(1, 2, 3)).isApprox(Eigen::Vector3d(1, 2, 104.6)));
}

TEST(FixtureConfig, ReadsListsInInchesAndThePostCalibrationPattern) {
  const MachineConfig m = parse_machine_section(R"(
fixture:
  fixture_id: F-2
  columns: {home_x_mm: [1000, "50 in", 2000]}
  rows: {home_y_in: [10, 20, 30], count: 3}
  z_planes_mm: [0, 100, 200]
  reference_block: {size_mm: "3 in", height_mm: 30}
  probe_depth_mm: "0.5 in"
  postcalibration:
    z_mm: [50, 150]
    y_offsets_in: [-1, 1]
    x_offsets_mm: [-100, 100]
)");
  const FixtureConfig& f = *m.fixture;
  EXPECT_EQ(f.column_home_x_mm, (std::vector<double>{1000, 1270, 2000}));
  EXPECT_EQ(f.row_home_y_mm, (std::vector<double>{254, 508, 762}));
  EXPECT_EQ(f.z_planes_mm, (std::vector<double>{0, 100, 200}));
  EXPECT_EQ(f.precalibration_configuration_count(), 6);
  EXPECT_DOUBLE_EQ(f.block_size_mm, 76.2);
  EXPECT_DOUBLE_EQ(f.probe_depth_mm, 12.7);
  EXPECT_EQ(f.postcalibration.y_offsets_mm, (std::vector<double>{-25.4, 25.4}));
  EXPECT_EQ(f.postcalibration_configuration_count(), 8);
  // Configuration 3 of 6: the even rows at plane 0.
  const auto c3 = precalibration_configuration(f, 3);
  ASSERT_EQ(c3.size(), 3u);
  EXPECT_EQ(c3[0].pogo, "C1R2");
  EXPECT_DOUBLE_EQ(c3[0].commanded_mm.z(), 0);
}

TEST(FixtureConfig, ThreePlanesOrFewerPostCalibrateAtTheFirstAndLast) {
  const MachineConfig m = parse_machine_section(fixture_with(
      "  probe_depth_mm: 10\n", "  probe_depth_mm: 10\n  z_planes_mm: [10, 20, 30]\n"));
  EXPECT_EQ(m.fixture->postcalibration.z_mm, (std::vector<double>{10, 30}));
}

TEST(FixtureConfig, BadValuesAreRefusedNamingFileKeyAndValue) {
  const struct {
    std::string from, to, message;
  } cases[] = {
      {"fixture_id: UHF1", "fixture_id: UHF 1", "fixture.fixture_id = 'UHF 1': use letters"},
      {"  fixture_id: UHF1\n", "", "fixture.fixture_id = (missing): required"},
      {"probe_depth_mm: 10", "probe_depth_mm: 10\n  colour: red",
       "fixture.colour = 'red': unknown key"},
      {"count: 4,", "count: 0,", "fixture.columns.count = '0': must be an integer from 1 to 999"},
      {"count: 4,", "count: 2.5,", "fixture.columns.count = '2.5'"},
      {"count: 6,", "count: 1,", "fixture.rows.count = '1': must be an integer from 2"},
      {"pitch_mm: 600", "pitch_mm: -600", "fixture.columns.pitch_mm = '-600': must be positive"},
      {"pitch_mm: 300", "pitch_mm: wide", "fixture.rows.pitch_mm = 'wide'"},
      {"first_y_mm: 250,", "firstY: 250,", "fixture.rows.firstY = '250': unknown key"},
      {"{count: 4, first_x_mm: 1800, pitch_mm: 600}", "{home_x_mm: [1800, 1700]}",
       "fixture.columns.home_x_mm = (not a single value): values must be strictly increasing"},
      {"{count: 4, first_x_mm: 1800, pitch_mm: 600}", "{count: 3, home_x_mm: [1, 2]}",
       "fixture.columns.count = '3': does not match the 2 values of fixture.columns.home_x_mm"},
      {"{count: 4, first_x_mm: 1800, pitch_mm: 600}", "{home_x_mm: [1, 2], pitch_mm: 5}",
       "fixture.columns.pitch_mm = '5': not with fixture.columns.home_x_mm"},
      {"{count: 4, first_x_mm: 1800, pitch_mm: 600}", "{home_x_mm: [1, '2 furlongs']}",
       "fixture.columns.home_x_mm[1] = '2 furlongs'"},
      {"{count: 4, first_x_mm: 1800, pitch_mm: 600}", "{home_x_mm: [1], home_x_in: [2]}",
       "also given as fixture.columns.home_x_mm"},
      {"  columns: {count: 4, first_x_mm: 1800, pitch_mm: 600}\n", "",
       "fixture.columns = (missing): required section"},
      {"size_mm: 100", "size_mm: 0", "fixture.reference_block.size_mm = '0': must be positive"},
      {"height_mm: 40", "height_mm: 40, depth_mm: 3",
       "fixture.reference_block.depth_mm = '3': unknown key"},
      {"probe_depth_mm: 10", "probe_depth_mm: 40",
       "fixture.probe_depth_mm = '40': must be positive and less than reference_block.height_mm "
       "(40 mm)"},
      {"origin_mm: [0, 0, \"4 in\"]", "origin_mm: [0, 0]",
       "fixture.origin_mm = (not a single value): expected a list of 3"},
      {"probe_depth_mm: 10", "probe_depth_mm: 10\n  z_planes_in: [0, 12, 6]",
       "fixture.z_planes_in = (not a single value): values must be strictly increasing"},
      {"probe_depth_mm: 10", "probe_depth_mm: 10\n  postcalibration: {z_in: [6, 30]}",
       "fixture.postcalibration.z_in[1] = '30': outside the Z travel of the planes (0 to 609.6 "
       "mm)"},
      {"probe_depth_mm: 10", "probe_depth_mm: 10\n  postcalibration: {x_offsets_mm: [0, 0]}",
       "fixture.postcalibration.x_offsets_mm = (not a single value): values must be distinct"},
      {"probe_depth_mm: 10", "probe_depth_mm: 10\n  postcalibration: {x_offsets_mm: []}",
       "fixture.postcalibration.x_offsets_mm = (not a single value): expected a non-empty list"},
      {"probe_depth_mm: 10", "probe_depth_mm: 10\n  postcalibration: {w_mm: [1]}",
       "fixture.postcalibration.w_mm = (not a single value): unknown key"},
  };
  for (const auto& c : cases) {
    try {
      parse_machine_section(fixture_with(c.from, c.to));
      FAIL() << "accepted: " << c.to;
    } catch (const ConfigError& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind("t1.yaml: ", 0), 0u) << msg;
      EXPECT_NE(msg.find(c.message), std::string::npos)
          << "got: " << msg << "\nwanted: " << c.message;
    }
  }
  try {
    parse_machine_section("fixture: [1, 2]\n");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("fixture = (not a single value): expected a mapping"),
              std::string::npos);
  }
}

TEST(FixtureConfig, TheExampleMachineHasAFixtureWithinReach) {
  const MachineConfig m = load_machine_config(NCQUAL_SOURCE_DIR "/deploy/machines/pm1.yaml");
  ASSERT_TRUE(m.fixture);
  const FixtureConfig& f = *m.fixture;
  EXPECT_EQ(f.fixture_id, "UHF1");
  EXPECT_EQ(f.columns(), 4);
  EXPECT_EQ(f.rows(), 6);
  EXPECT_EQ(f.precalibration_configuration_count(), 10);
  EXPECT_EQ(f.postcalibration_configuration_count(), 12);
  EXPECT_DOUBLE_EQ(m.tolerance("fixture_delta_mm").upper, 0.025);
  // Every probed position, blocks and approaches included, lies in X 0..4000 and Y 0..2000, and
  // clear of the monument's gauge (X 1100..1300).
  const double reach = f.block_half_size_mm() + m.probe.ball_radius_mm + 5;
  auto check = [&](const PogoPlacement& p) {
    const Eigen::Vector3d q = f.to_machine(p.commanded_mm);
    EXPECT_GE(q.x() - reach, 1300) << p.pogo;
    EXPECT_LE(q.x() + reach, 4000) << p.pogo;
    EXPECT_GE(q.y() - reach, 0) << p.pogo;
    EXPECT_LE(q.y() + reach, 2000) << p.pogo;
  };
  for (int k = 0; k < 10; ++k) {
    for (const auto& p : precalibration_configuration(f, k)) check(p);
  }
  for (const auto& configuration : postcalibration_configurations(f)) {
    for (const auto& p : configuration) check(p);
  }
}

// ---- Names -----------------------------------------------------------------------------------

TEST(FixtureNames, PogoLabelsRoundTripAndRejectMalformed) {
  EXPECT_EQ(pogo_label(2, 3), "C2R3");
  EXPECT_EQ(pogo_label(12, 10), "C12R10");
  const auto id = parse_pogo_label("C12R10");
  ASSERT_TRUE(id);
  EXPECT_EQ(id->column, 12);
  EXPECT_EQ(id->row, 10);
  for (const char* bad : {"", "C", "C2", "C2R", "R3C2", "c2r3", "C0R1", "C1R0", "C02R3", "C2R3 ",
                          "C-1R2", "C2R3x", "CxR3"}) {
    EXPECT_FALSE(parse_pogo_label(bad)) << bad;
  }
  FixtureConfig f;
  f.column_home_x_mm = {0, 1};
  f.row_home_y_mm = {0, 1, 2};
  EXPECT_TRUE(fixture_has_pogo(f, {2, 3}));
  EXPECT_FALSE(fixture_has_pogo(f, {3, 1}));
  EXPECT_FALSE(fixture_has_pogo(f, {1, 4}));
}

TEST(FixtureNames, TouchFeaturesRoundTripAndRejectMalformed) {
  for (PogoFace face : kPogoFaces) {
    for (int cfg : {0, 4, 11}) {
      const std::string text = pogo_touch_feature("C2R3", cfg, face);
      const auto parsed = parse_pogo_touch_feature(text);
      ASSERT_TRUE(parsed) << text;
      EXPECT_EQ(parsed->pogo, "C2R3");
      EXPECT_EQ(parsed->id.column, 2);
      EXPECT_EQ(parsed->id.row, 3);
      EXPECT_EQ(parsed->configuration, cfg);
      EXPECT_EQ(parsed->face, face);
    }
  }
  EXPECT_EQ(pogo_touch_feature("C2R3", 4, PogoFace::XMinus), "pogo:C2R3:cfg4:x-");
  EXPECT_EQ(pogo_touch_feature("C1R1", 0, PogoFace::Top), "pogo:C1R1:cfg0:top");
  for (const char* bad :
       {"", "pogo", "pogo:C2R3", "pogo:C2R3:cfg4", "pogo:C2R3:cfg4:", "pogo:C2R3:cfg4:z-",
        "pogo:C2R3:cfg04:x-", "pogo:C2R3:cfg-1:x-", "pogo:C2R3:4:x-", "pogo:C2R3:cfg4:x-:",
        "pogo:X2R3:cfg4:x-", "hole_edge", "pogo::cfg4:x-", "Pogo:C2R3:cfg4:x-"}) {
    EXPECT_FALSE(parse_pogo_touch_feature(bad)) << bad;
  }
  // The faces' normals and offsets from the top-face centre.
  FixtureConfig f;
  f.block_size_mm = 100;
  f.probe_depth_mm = 10;
  EXPECT_EQ(outward_normal(PogoFace::YPlus), Eigen::Vector3d::UnitY());
  EXPECT_EQ(outward_normal(PogoFace::XMinus), -Eigen::Vector3d::UnitX());
  EXPECT_EQ(face_offset(f, PogoFace::Top), Eigen::Vector3d::Zero());
  EXPECT_EQ(face_offset(f, PogoFace::XPlus), Eigen::Vector3d(50, 0, -10));
  EXPECT_EQ(face_offset(f, PogoFace::YMinus), Eigen::Vector3d(0, -50, -10));
}

TEST(FixtureNames, ZeroOffsetNamesRoundTripAndRejectMalformed) {
  EXPECT_EQ(zero_offset_name("C2R3", 0), "C2R3.dx");
  EXPECT_EQ(zero_offset_name("C2R3", 2), "C2R3.dz");
  for (int axis = 0; axis < 3; ++axis) {
    const auto parsed = parse_zero_offset_name(zero_offset_name("C4R6", axis));
    ASSERT_TRUE(parsed);
    EXPECT_EQ(parsed->pogo, "C4R6");
    EXPECT_EQ(parsed->id.column, 4);
    EXPECT_EQ(parsed->axis, axis);
  }
  for (const char* bad : {"", "C2R3", "C2R3.", "C2R3.x", "C2R3.dw", "C2R3_dx", "dx", "C2R3.dx.dy",
                          "pogo_C2R3_dx_mm"}) {
    EXPECT_FALSE(parse_zero_offset_name(bad)) << bad;
  }
}

}  // namespace
}  // namespace ncqual

// SPDX-License-Identifier: Apache-2.0
// Holding fixtures and fixture requests for the fixture simulator and fixture check tests.
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/common/fixture.hpp"
#include "ncqual/common/model.hpp"
#include "ncqual/common/units.hpp"
#include "test_machines.hpp"

#include <random>
#include <string>

namespace ncqual::testing {

// The fixture of deploy/machines/pm1.yaml, built in code.
inline FixtureConfig pm1_fixture() {
  FixtureConfig f;
  f.fixture_id = "UHF1";
  f.origin_mm = Eigen::Vector3d(0, 0, 100);
  f.column_home_x_mm = {1800, 2400, 3000, 3600};
  f.row_home_y_mm = {250, 550, 850, 1150, 1450, 1750};
  for (double in : {0.0, 6.0, 12.0, 18.0, 24.0}) f.z_planes_mm.push_back(units::inch_to_mm(in));
  f.block_size_mm = 100;
  f.block_height_mm = 40;
  f.probe_depth_mm = 10;
  f.postcalibration.z_mm = {units::inch_to_mm(6), units::inch_to_mm(18)};
  f.postcalibration.y_offsets_mm = {-75, 75};
  f.postcalibration.x_offsets_mm = {-150, 0, 150};
  return f;
}

// pm1 with its fixture and the fixture tolerance of deploy/machines/pm1.yaml (0.025 mm).
inline MachineConfig pm1_with_fixture() {
  MachineConfig m = pm1_like_machine();
  m.fixture = pm1_fixture();
  m.tolerances["fixture_delta_mm"] = Tolerance{-0.025, 0.025};
  return m;
}

// A random but sensible fixture: 2 to 5 columns, 2 to 7 rows, pitches that keep the blocks and
// the probing moves apart, random planes, block and depth.
inline FixtureConfig random_fixture(std::mt19937_64& rng) {
  FixtureConfig f;
  f.fixture_id = "F" + std::to_string(std::uniform_int_distribution<int>(1, 99)(rng));
  f.origin_mm =
      Eigen::Vector3d(uniform(rng, -100, 100), uniform(rng, -100, 100), uniform(rng, 0, 300));
  const int columns = std::uniform_int_distribution<int>(2, 5)(rng);
  const int rows = std::uniform_int_distribution<int>(2, 7)(rng);
  const double x0 = uniform(rng, 1500, 2000), x_pitch = uniform(rng, 450, 700);
  const double y0 = uniform(rng, 100, 400), y_pitch = uniform(rng, 220, 320);
  for (int c = 0; c < columns; ++c) f.column_home_x_mm.push_back(x0 + c * x_pitch);
  for (int r = 0; r < rows; ++r) f.row_home_y_mm.push_back(y0 + r * y_pitch);
  const double z0 = uniform(rng, 0, 50), z_pitch = uniform(rng, 100, 160);
  for (int k = 0; k < 5; ++k) f.z_planes_mm.push_back(z0 + k * z_pitch);
  f.block_size_mm = uniform(rng, 60, 120);
  f.block_height_mm = uniform(rng, 30, 60);
  f.probe_depth_mm = uniform(rng, 8, f.block_height_mm - 8);
  f.postcalibration.z_mm = {f.z_planes_mm[1], f.z_planes_mm[3]};
  f.postcalibration.y_offsets_mm = {-75, 75};
  f.postcalibration.x_offsets_mm = {-150, 0, 150};
  return f;
}

inline CheckRequest fixture_request(const std::string& machine_id, const std::string& request_id,
                                    CheckKind kind, std::optional<int> configuration) {
  CheckRequest r = request(machine_id, request_id, kind);
  if (configuration) r.parameters.push_back({"fixture_configuration", double(*configuration), ""});
  return r;
}

}  // namespace ncqual::testing

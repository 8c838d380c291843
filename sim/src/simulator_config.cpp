// SPDX-License-Identifier: Apache-2.0
#include "ncqual/sim/simulator_config.hpp"

#include <cmath>

namespace ncqual::sim {

double drift_days(const SimulatorDrift& drift, std::int64_t now_ns) {
  if (now_ns <= drift.since_ns) return 0.0;
  // The difference is positive and below 2^64: exact in unsigned arithmetic, whatever the signs.
  const std::uint64_t elapsed_ns =
      static_cast<std::uint64_t>(now_ns) - static_cast<std::uint64_t>(drift.since_ns);
  return static_cast<double>(elapsed_ns) / kNsPerDay;
}

SimulatorErrors errors_at(const SimulatorErrors& base, const std::optional<SimulatorDrift>& drift,
                          std::int64_t now_ns) {
  if (!drift) return base;
  const double days = drift_days(*drift, now_ns);
  if (days <= 0) return base;
  SimulatorErrors e = base;
  e.machine_shift_mm += drift->machine_shift_mm_per_day * days;
  e.monument_shift_mm += drift->monument_shift_mm_per_day * days;
  e.tool_length_error_mm += drift->tool_length_error_mm_per_day * days;
  e.c_angle_error_rad += drift->c_angle_error_rad_per_day * days;
  e.a_home_error_rad += drift->a_home_error_rad_per_day * days;
  return e;
}

SimulatorErrors errors_at(const SimulatorConfig& config, std::int64_t now_ns) {
  return errors_at(config.errors, config.drift, now_ns);
}

FixtureErrors fixture_errors_at(const FixtureErrors& base,
                                const std::optional<SimulatorDrift>& drift, std::int64_t now_ns) {
  if (!drift) return base;
  const double days = drift_days(*drift, now_ns);
  if (days <= 0) return base;
  FixtureErrors e = base;
  e.column_x.offset_mm += drift->fixture_column_x_offset_mm_per_day * days;
  e.pogo_y.offset_mm += drift->fixture_pogo_y_offset_mm_per_day * days;
  e.pogo_z.offset_mm += drift->fixture_pogo_z_offset_mm_per_day * days;
  return e;
}

VolumetricTruth volumetric_at(const VolumetricTruth& base,
                              const std::optional<SimulatorDrift>& drift, std::int64_t now_ns) {
  if (!drift) return base;
  const double days = drift_days(*drift, now_ns);
  if (days <= 0) return base;
  VolumetricTruth v = base;
  v.rigid_body.ec0xy_rad += drift->squareness_ec0xy_rad_per_day * days;
  return v;
}

SimulatorConfig config_at(const SimulatorConfig& config, std::int64_t now_ns) {
  SimulatorConfig c = config;
  if (!config.drift) return c;
  c.errors = errors_at(config.errors, config.drift, now_ns);
  c.fixture = fixture_errors_at(config.fixture, config.drift, now_ns);
  c.volumetric = volumetric_at(config.volumetric, config.drift, now_ns);
  c.drift.reset();
  return c;
}

}  // namespace ncqual::sim

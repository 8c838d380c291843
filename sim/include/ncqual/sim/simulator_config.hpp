// SPDX-License-Identifier: Apache-2.0
// The instrument simulator's configuration and its ground truth at a time. The section itself
// (what every key means) is documented and read in the configuration layer:
// ncqual/common/config/simulator.hpp; a machine config holds it as MachineConfig::simulator.
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/common/config/simulator.hpp"
#include "ncqual/common/volumetric.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <optional>

namespace ncqual::sim {

// ---- The truth at a time (pure functions of the config and the time) ----
inline constexpr double kNsPerDay = 86400e9;

// Days the truth has drifted at `now_ns` (ns since the Unix epoch, UTC):
// (now - since) / 86400 s, exact to the nanosecond before the division; 0 when now <= since.
double drift_days(const SimulatorDrift& drift, std::int64_t now_ns);

// The touch-probe errors at `now_ns`: base + rate * drift_days for machine_shift, monument_shift,
// tool_length_error, c_angle_error and a_home_error; stylus_offset and setpoint_shift as the base.
// Without drift, or at or before `since`, exactly `base` (the same bits).
SimulatorErrors errors_at(const SimulatorErrors& base, const std::optional<SimulatorDrift>& drift,
                          std::int64_t now_ns);
SimulatorErrors errors_at(const SimulatorConfig& config, std::int64_t now_ns);

// The fixture's errors at `now_ns`: the offset_mm of column_x, pogo_y and pogo_z grow by their
// rates; everything else as the base. Without drift, or at or before `since`, exactly `base`.
FixtureErrors fixture_errors_at(const FixtureErrors& base,
                                const std::optional<SimulatorDrift>& drift, std::int64_t now_ns);

// The volumetric truth at `now_ns`: rigid_body.ec0xy_rad grows by its rate; everything else as
// the base. Without drift, or at or before `since`, exactly `base`.
VolumetricTruth volumetric_at(const VolumetricTruth& base,
                              const std::optional<SimulatorDrift>& drift, std::int64_t now_ns);

// The whole config frozen at `now_ns`: errors, fixture and volumetric at that time, drift
// cleared (so the result holds at every time). Without drift, a copy of `config`.
SimulatorConfig config_at(const SimulatorConfig& config, std::int64_t now_ns);

}  // namespace ncqual::sim

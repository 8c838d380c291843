// The simulator's section of a machine config: noise, true geometry the taught config does not
// hold, and the injected errors that are the ground truth the solver is checked against.
//
//   simulator:
//     seed: 42
//     trigger_noise_sigma_mm: 0.001      # 1 sigma, along the probing direction
//     plate_thickness_mm: 20             # true thickness of the ring gauge plate
//     errors:
//       machine_shift_mm: [0, 0, 0]      # true pivot = axis readout + shift
//       monument_shift_mm: [0, 0, 0]     # true monument = taught + shift
//       stylus_offset_mm: [0, 0]         # ball off the tool axis, body frame
//       tool_length_error_mm: 0          # true L = nominal L + error
//       c_angle_error_arcsec: 0          # true C = C readout + error (or _rad, _deg, _urad)
//       a_home_error_arcsec: 0           # true A = A readout + error (or _rad, _deg, _urad)
#pragma once

#include "ncqual/config.hpp"

#include <Eigen/Core>

#include <cstdint>

namespace ncqual::sim {

// The errors of the true machine and monument relative to the nominal/taught ones. All zero is
// a perfect machine. Later error kinds (fixture pogos, volumetric squareness and scale) are
// added here as new members and new keys, defaulting to zero.
struct SimulatorErrors {
  Eigen::Vector3d machine_shift_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d monument_shift_mm = Eigen::Vector3d::Zero();
  Eigen::Vector2d stylus_offset_mm = Eigen::Vector2d::Zero();  // added to the nominal offset
  double tool_length_error_mm = 0;
  double c_angle_error_rad = 0;
  double a_home_error_rad = 0;
};

struct SimulatorConfig {
  std::uint64_t seed = 1;
  double trigger_noise_sigma_mm = 0.001;
  // Not part of the taught monument: the plate's true thickness below its face. Hole-edge
  // touches deeper than this pass under the plate and never trigger.
  double plate_thickness_mm = 20.0;
  SimulatorErrors errors;
};

// Reads machine.simulator (absent or null: the defaults above). Unknown keys are refused so a
// misspelt error never silently becomes zero. Throws ConfigError naming file, key and value.
SimulatorConfig parse_simulator_config(const MachineConfig& machine);

}  // namespace ncqual::sim

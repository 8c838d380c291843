// SPDX-License-Identifier: Apache-2.0
// The simulator's section of a machine config (`simulator:`), as read by the configuration layer
// (common/src/config/simulator_section.cpp): noise, the true geometry the taught config does not
// hold, and the injected errors that are the ground truth the solver is checked against. The
// physics that uses it is the acquisition's simulator (ncqual/sim/); it lives here because a
// machine config holds it typed, read and checked at load like every other section.
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
//       setpoint_shift_mm:               # set-point blocks moved, by set point name
//         primary: [0, 0, 0]
//     part_seating_sigma_mm: 0           # each loaded part seats off by N(0, sigma^2) per axis
//     fixture:                           # the true holding fixture
//     (ncqual/sim/fixture_simulator.hpp)
//       column_x:                        # the columns' X actuators; also pogo_y:, pogo_z:
//         offset_mm: 0                   # true travel = command + error(command), where
//         scale_ppm: 0                   #   error(u) = offset + scale 1e-6 u
//         curvature_um_per_m2: 0         #            + curvature 1e-3 (u / 1000)^2
//         sine_amplitude_mm: 0           #            + amplitude sin(2 pi u / period + phase)
//         sine_period_mm: 0              #   (u: the actuator command in the fixture frame, mm)
//         sine_phase_deg: 0              # (or _rad, _arcsec, _urad)
//         misalignment_y_urad: 0         # travel also moves along machine Y by angle * travel
//         misalignment_z_urad: 0         # (pogo_y: misalignment_x_, _z_; pogo_z: _x_, _y_)
//       pogo_offsets_mm:                 # per pogo: [dx, dy, dz] of its reference block
//         C2R3: [0.01, 0, -0.02]
//       wear_sigma_mm: 0                 # each placement of a pogo lands off by N(0, sigma^2)
//                                        # per axis (worn, loose components)
//     tracker:                           # the laser tracker of the monthly check
//       position_mm: [2200, -2500, 1000] # its origin in the machine frame
//       yaw_deg: 90                      # its axes: Rz(yaw) Ry(pitch) Rx(roll) of the machine's
//       pitch_deg: 0
//       roll_deg: 0
//       angular_sigma_urad: 20           # per encoder angle (azimuth, elevation), 1 sigma
//       radial_sigma_um: 4               # range noise: radial_sigma_um + radial_sigma_um_per_m * r
//       radial_sigma_um_per_m: 0.8
//       samples_per_point: 1             # a static point averages this many readings
//       linear_run_standoff_mm: 1000     # ISO 230-2 station on the axis line, before the run
//       ifm_sigma_um: 0.5                # its range noise (interferometer mode):
//       ifm_sigma_um_per_m: 0.4          #   ifm_sigma_um + ifm_sigma_um_per_m * r
//     volumetric:                        # what the tracker sees of the machine (ground truth)
//       repeatability_sigma_mm: 0.001    # each axis lands off by N(0, sigma^2) per move
//       backlash_mm: [0, 0, 0]           # reversal per axis: lags the command by half of it
//       expansion_ppm_per_K: [11.5, 11.5, 11.5]  # per axis scale (1 + alpha (T - 20 C))
//       temperature_C: [20, 20, 20]
//       range_mm: {x: [200, 4200], y: [200, 1700], z: [600, 1200]}  # Legendre ranges
//       EXX_um: [0, 12, -4]              # Legendre coefficients c0, c1, ... of each of the 18
//       EAX_urad: [0, 5]                 #   error functions (ncqual/common/volumetric.hpp): _um
//       for EC(0X)Y_urad: 20                 #   E{X,Y,Z}K, _urad for E{A,B,C}K; squareness
//       EC(0X)Y,
//                                        #   EB(0X)Z, EA(0Y)Z in urad
//       c_axis_tilt_urad: [0, 0]         # C axis tilted about machine X, Y
//       c_periodic_arcsec: 0             # once-per-turn angular error of C (amplitude, phase)
//       c_periodic_phase_deg: 0
//       a_axis_tilt_urad: [0, 0]         # A axis tilted about the head's Y, Z
//       a_periodic_arcsec: 0
//       w_scale_ppm: 0                   # W travel scale error
//       w_misalignment_urad: [0, 0]      # W travel tilted from the tool axis (body X, Y)
//     drift:                             # optional: the truth grows linearly with time (below)
//       since: "2026-01-05T00:00:00Z"    # ISO 8601 UTC; required in the section
//       machine_shift_mm_per_day: [0, 0, 0]
//       monument_shift_mm_per_day: [0, 0, 0]
//       tool_length_error_mm_per_day: 0
//       c_angle_error_arcsec_per_day: 0  # (or _rad_per_day, _deg_per_day, _urad_per_day)
//       a_home_error_arcsec_per_day: 0   # (likewise)
//       fixture_column_x_offset_mm_per_day: 0   # the fixture's zero drifting: offset_mm of
//       fixture_pogo_y_offset_mm_per_day: 0     #   column_x, pogo_y, pogo_z
//       fixture_pogo_z_offset_mm_per_day: 0
//       squareness_ec0xy_urad_per_day: 0 # volumetric EC(0X)Y (or _rad, _deg, _arcsec _per_day)
//   A length rate may carry its own unit ("0.7 um" is 0.7 um per day), an angle rate likewise.
#pragma once

#include "ncqual/common/kinematics.hpp"
#include "ncqual/common/volumetric.hpp"

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <string>

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
  // Set-point blocks moved on their fixturing devices, by set point name: true = intended + shift.
  std::map<std::string, Eigen::Vector3d> setpoint_shift_mm;
};

// Errors of one fixture axis (all columns' X actuators, or all pogos' Y actuators, or all pogos'
// Z extensions). A command u (fixture frame, mm, after the control's zero offsets) moves the pogo
// by (u + error(u)) along direction(), where
//   error(u) = offset + scale_ppm 1e-6 u + curvature_um_per_m2 1e-3 (u / 1000)^2
//              + sine_amplitude sin(2 pi u / sine_period + sine_phase)
//   direction() = e_axis + misalignment_rad (the own component of misalignment_rad is 0: the
//                 other two are the small angles of the travel towards those machine axes).
struct FixtureAxisErrors {
  double offset_mm = 0;
  double scale_ppm = 0;
  double curvature_um_per_m2 = 0;
  double sine_amplitude_mm = 0;
  double sine_period_mm = 0;  // > 0 when sine_amplitude_mm != 0
  double sine_phase_rad = 0;
  Eigen::Vector3d misalignment_rad = Eigen::Vector3d::Zero();

  double error_mm(double u_mm) const {
    constexpr double kTwoPi = 2 * 3.14159265358979323846;
    double e = offset_mm + scale_ppm * 1e-6 * u_mm +
               curvature_um_per_m2 * 1e-3 * (u_mm / 1000) * (u_mm / 1000);
    if (sine_amplitude_mm != 0 && sine_period_mm > 0) {
      e += sine_amplitude_mm * std::sin(kTwoPi * u_mm / sine_period_mm + sine_phase_rad);
    }
    return e;
  }
  Eigen::Vector3d direction(int axis) const {  // axis 0, 1, 2 = X, Y, Z
    Eigen::Vector3d d = misalignment_rad;
    d[axis] = 1.0;
    return d;
  }
};

// The true holding fixture against the nominal one of the machine's `fixture:` section. All zero
// is a perfect fixture.
struct FixtureErrors {
  FixtureAxisErrors column_x;  // the column members' X actuators
  FixtureAxisErrors pogo_y;    // the pogos' Y actuators along their columns
  FixtureAxisErrors pogo_z;    // the pogos' Z extensions
  std::map<std::string, Eigen::Vector3d> pogo_offsets_mm;  // by pogo label, e.g. "C2R3"
  double wear_sigma_mm = 0;
};

// The laser tracker: where it stands and how noisy it is (Aguado et al. 2019: angular encoders
// 20 urad, range 4 um + 0.8 um/m).
struct TrackerModel {
  Eigen::Vector3d position_mm = Eigen::Vector3d(2200, -2500, 1000);
  Eigen::Vector3d ypr_rad = Eigen::Vector3d(1.5707963267948966, 0, 0);  // yaw, pitch, roll
  double angular_sigma_rad = 20e-6;
  double radial_sigma_mm = 0.004;
  double radial_sigma_mm_per_m = 0.0008;
  // A static point is the mean of this many readings (the tracker's measurement time): its noise
  // is the reading noise above / sqrt(samples_per_point).
  int samples_per_point = 1;
  // The linear axis run (ISO 230-2) is measured from a second station on the axis line,
  // `linear_run_standoff_mm` before the first target, looking along the axis, in interferometer
  // (IFM) mode: range noise ifm_sigma + ifm_sigma_per_m * r.
  double linear_run_standoff_mm = 1000;
  double ifm_sigma_mm = 0.0005;
  double ifm_sigma_mm_per_m = 0.0004;

  // Rotation tracker frame -> machine frame.
  Eigen::Matrix3d rotation() const { return rotation_from_ypr(ypr_rad); }
};

// The machine as the tracker sees it over its whole envelope: the 21 rigid-body errors of X, Y, Z,
// thermal expansion, reversal and repeatability of the linear axes, and the errors of the wrist
// (C and A axis tilts and periodic errors, W scale and direction). c_angle_error and a_home_error
// of SimulatorErrors are the rotary zero errors.
struct VolumetricTruth {
  double repeatability_sigma_mm = 0;
  Eigen::Vector3d backlash_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d expansion_per_K = Eigen::Vector3d::Constant(11.5e-6);
  Eigen::Vector3d temperature_C = Eigen::Vector3d::Constant(20);
  volumetric::RigidBodyErrors rigid_body;
  Eigen::Vector2d c_axis_tilt_rad = Eigen::Vector2d::Zero();
  double c_periodic_rad = 0, c_periodic_phase_rad = 0;
  Eigen::Vector2d a_axis_tilt_rad = Eigen::Vector2d::Zero();
  double a_periodic_rad = 0;
  double w_scale_ppm = 0;
  Eigen::Vector2d w_misalignment_rad = Eigen::Vector2d::Zero();
};

// Time-dependent drift of the ground truth (simulator.drift). Before and at `since_ns` the truth
// is the base of the sections above (errors, fixture, volumetric); at a time t after it every
// drifting quantity grows linearly:
//   value(t) = base + rate * days,  days = (t - since) / 86400 s  (0 when t <= since)
// Rates are per day in mm and rad. Quantities without a rate here never drift.
struct SimulatorDrift {
  std::int64_t since_ns = 0;  // ns since the Unix epoch, UTC
  // SimulatorErrors
  Eigen::Vector3d machine_shift_mm_per_day = Eigen::Vector3d::Zero();
  Eigen::Vector3d monument_shift_mm_per_day = Eigen::Vector3d::Zero();
  double tool_length_error_mm_per_day = 0;
  double c_angle_error_rad_per_day = 0;
  double a_home_error_rad_per_day = 0;
  // FixtureErrors: the offset_mm of each fixture axis, the fixture's zero drifting. A pure offset
  // error, so the weekly pre-calibration's zero offsets cancel what has drifted so far.
  double fixture_column_x_offset_mm_per_day = 0;
  double fixture_pogo_y_offset_mm_per_day = 0;
  double fixture_pogo_z_offset_mm_per_day = 0;
  // VolumetricTruth: the squareness EC(0X)Y of the machine's Y axis to X (rigid_body.ec0xy_rad).
  double squareness_ec0xy_rad_per_day = 0;
};

// Read rules: absent or null, the defaults below. Unknown keys are refused so a misspelt error
// never silently becomes zero. `fixture:` needs the machine's own `fixture:` section, and its pogo
// labels must name pogos of it. `drift:` (absent or null: no drift) needs `since`, an ISO 8601 UTC
// time of the years 1900 to 2200; its rates must be numbers (lists of 3 for the shifts) and the
// fixture rates need the machine's `fixture:` section.
struct SimulatorConfig {
  std::uint64_t seed = 1;
  double trigger_noise_sigma_mm = 0.001;
  // Not part of the taught monument: the plate's true thickness below its face. Hole-edge
  // touches deeper than this pass under the plate and never trigger.
  double plate_thickness_mm = 20.0;
  SimulatorErrors errors;
  FixtureErrors fixture;  // the `fixture:` key of the section
  // Each loaded part seats on its locators off by N(0, sigma^2) per axis, drawn per request;
  // the set points move with the part.
  double part_seating_sigma_mm = 0;
  TrackerModel tracker;
  VolumetricTruth volumetric;
  // The `drift:` key of the section; none: the truth above holds at every time.
  std::optional<SimulatorDrift> drift;
};

}  // namespace ncqual::sim

// SPDX-License-Identifier: Apache-2.0
// The monthly global check with a laser tracker (patent "Global Positioning Accuracy Check"):
// what the machine runs while the tracker measures a reflector (the target) in its spindle, and
// the names the acquisition and the solver share for its points.
//
// Patent: a master frame of reference from an X run (e.g. eleven points, Y, Z, W, A, C fixed at
// the middle of the envelope) and a Y run (e.g. ten points); positioning over a grid of the working
// envelope (e.g. 216 points: 9 x 6 on 4 constant-Z planes); W, A and C checks with X, Y, Z fixed;
// circles in the XY, YZ and XZ planes. Beyond the patent: an ISO 230-2 linear axis run and extra
// targets (reflectors at other offsets from the pivot) so that the 21 rigid-body errors of the
// axes can be identified from the grid.
//
// Commanded positions are machine axis readouts (AxisPosition: X, Y, Z of the wrist pivot, W, A,
// C); the target's nominal position is stylus_ball_centre(axes, target) with the target's
// geometry (tool_length_mm: pivot to reflector centre at W = 0, stylus_offset_mm: off the tool
// axis in the body frame).
//
// Point labels of the tracker MeasurementSets (TrackerPoint.label):
//   x_run:<i>, y_run:<i>        master-frame runs (every monthly set but the linear run carries the
//                               runs of its session)
//   grid:<i>:t<k>               grid point i measured with target k (t0 = the main target)
//   c:<i>, a:<i>, w:<i>         rotary checks (C stepped with A tilted, A stepped, W stepped)
//   ccw:<i>, cw:<i>             circle points in either direction
//   run:<cycle>:<up|down>:<i>   ISO 230-2 linear axis run, target i (0-based), cycle from 1
//
// Units: mm and rad inside; the YAML may write inches and degrees (keys ending _in, _deg).
#pragma once

#include "ncqual/common/check_kinds.hpp"
#include "ncqual/common/kinematics.hpp"
#include "ncqual/common/model.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ncqual {

struct CircleTestConfig {
  Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();  // commanded pivot position of the centre
  double radius_mm = 0;
  int points = 0;             // per direction, evenly spaced from angle 0
  bool bidirectional = true;  // ccw then cw
};

struct LinearRunConfig {
  int axis = 0;                                     // 0, 1, 2 = X, Y, Z
  Eigen::Vector3d at_mm = Eigen::Vector3d::Zero();  // the pivot position; the axis' own coordinate
                                                    // is replaced by each target
  std::vector<double> targets_mm;                   // ascending
  int cycles = 5;
  double overrun_mm = 5;  // past the last target before reversing
};

// ---- The verification's uncertainty (`global_check.uncertainty:`) ------------------------------
// What `ncqual uncertainty` needs to simulate the monthly grid verification of a real plant, where
// no simulator knows the tracker: the planned tracker setup, the machine's uncertainty sources and
// the Monte Carlo settings (the math: solver::evaluate_verification_uncertainty and
// solver::best_tracker_location, ncqual/solver/verification_uncertainty.hpp). The solver takes
// the tracker and the sources as they are configured: solver::TrackerUncertaintyModel is
// PlannedTrackerConfig, solver::UncertaintySources is UncertaintySourcesConfig plus the machine's
// systematic errors, solver::TrackerRegion is the TrackerRegion a TrackerSearchConfig is.
//
//   uncertainty:
//     tracker:                          # required
//       position_mm: [x, y, z]          # required: its origin in the machine frame
//       ypr_deg: [yaw, pitch, roll]     # tracker axes = Rz(yaw) Ry(pitch) Rx(roll) machine axes
//       angular_sigma_urad: 20          # per encoder angle, one reading
//       radial_sigma_mm: 0.004          # range noise of one reading: radial_sigma_mm
//       radial_sigma_mm_per_m: 0.0008   #   + radial_sigma_mm_per_m * range / 1000 mm
//       samples_per_point: 1            # readings averaged per point (integer >= 1)
//       position_sigma_mm: 0            # placement: 1 sigma of its position per machine axis
//       orientation_sigma_urad: 0       #   and of a small rotation about each machine axis
//     sources:                          # optional; lists per machine axis X, Y, Z
//       repeatability_sigma_mm: [0, 0, 0]
//       expansion_per_K: [11.5e-6, 11.5e-6, 11.5e-6]      # alpha (1/K)
//       expansion_sigma_per_K: [5.77e-7, ...]             # u(alpha); default 2e-6 / (2 sqrt 3)
//       temperature_deviation_K: [0, 0, 0]                # measured T - 20 C (either sign)
//       temperature_sigma_K: [0, 0, 0]                    # its 1 sigma
//     trials: 1000                      # Monte Carlo trials (integer >= 1)
//     seed: 1                           # integer >= 0
//     search:                           # optional: where the tracker may stand
//       x_mm: [min, max]                # the box of candidate positions (min <= max)
//       y_mm: [min, max]
//       z_mm: [min, max]
//       step_mm: 400                    # required, > 0: candidates at most this far apart
//       envelope_clearance_mm: 200      # keep-out around the working envelope (>= 0)
//       min_range_mm: 500               # the tracker's range to every grid target (>= 0)
//       max_range_mm: 15000             #   (> min_range_mm)
// Lengths may carry their unit ("4 um"), angles too ("0.3 deg" under _urad); bare numbers are in
// the unit the key names. Sigmas must be finite and >= 0, every number finite.

// The tracker as planned for the monthly check, and as the uncertainty model sees it
// (solver::TrackerUncertaintyModel; default noise: Aguado et al., 20 urad per encoder angle,
// 4 um + 0.8 um/m range).
struct PlannedTrackerConfig {
  Eigen::Vector3d position_mm = Eigen::Vector3d::Zero();  // its origin in the machine frame
  Eigen::Vector3d ypr_rad = Eigen::Vector3d::Zero();      // yaw, pitch, roll (YAML ypr_deg)
  double angular_sigma_rad = 20e-6;  // per encoder angle (azimuth, elevation), one reading (_urad)
  double radial_sigma_mm = 0.004;    // range noise of one reading: radial_sigma_mm
  double radial_sigma_mm_per_m = 0.0008;  //   + radial_sigma_mm_per_m * r / 1000
  int samples_per_point = 1;              // a point averages this many readings: noise / sqrt(n)
  // Placement (Monte Carlo only): 1 sigma of the true position per machine axis (mm) and of a
  // small rotation about each machine axis (rad; YAML _urad).
  double position_sigma_mm = 0;
  double orientation_sigma_rad = 0;

  // Rotation tracker frame -> machine frame: Rz(yaw) Ry(pitch) Rx(roll).
  Eigen::Matrix3d rotation() const { return rotation_from_ypr(ypr_rad); }
};

// The machine's uncertainty sources (solver::UncertaintySources adds the systematic errors),
// per machine axis X, Y, Z.
struct UncertaintySourcesConfig {
  Eigen::Vector3d repeatability_sigma_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d expansion_per_K = Eigen::Vector3d::Constant(11.5e-6);  // alpha (1/K)
  // u(alpha) (1/K): the rule of ISO/TR 230-9 for 11.5e-6, a 2e-6 wide rectangle: 5.77e-7.
  Eigen::Vector3d expansion_sigma_per_K =
      Eigen::Vector3d::Constant(2e-6 / (2 * 1.7320508075688772));
  Eigen::Vector3d temperature_deviation_K = Eigen::Vector3d::Zero();  // measured T - 20 C
  Eigen::Vector3d temperature_sigma_K = Eigen::Vector3d::Zero();      // its 1 sigma
};

// Where the tracker may stand (solver::TrackerRegion; what excludes a candidate:
// solver::best_tracker_location): a grid of candidate positions over the box [lo_mm, hi_mm] with
// `steps` candidates per axis (one step: the box's middle on that axis).
struct TrackerRegion {
  Eigen::Vector3d lo_mm = Eigen::Vector3d::Zero(), hi_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3i steps = Eigen::Vector3i(5, 5, 3);
  double envelope_clearance_mm = 200;
  double min_range_mm = 500;
  double max_range_mm = 15000;
};

// The `search:` mapping: the region, with steps = ceil((max - min) / step_mm) + 1 per axis
// (neighbours at most step_mm apart; 1 when min = max: that coordinate). At most 1e6 candidates.
struct TrackerSearchConfig : TrackerRegion {
  double step_mm = 0;
};

struct VerificationUncertaintyConfig {
  PlannedTrackerConfig tracker;
  UncertaintySourcesConfig sources;
  int trials = 1000;  // Monte Carlo trials (1 .. 1e6)
  std::uint64_t seed = 1;
  std::optional<TrackerSearchConfig> search;  // the `search:` mapping, if any
};

struct GlobalCheckConfig {
  // Reflectors in the spindle; [0] is the target of every check, the others are measured on the
  // grid too, for the identification of the angular errors (different lever arms).
  std::vector<ProbeGeometry> targets;
  // Master frame: X run at (y, z) = x_run_at_mm, Y run at (x, z) = y_run_at_mm.
  std::vector<double> x_run_mm, y_run_mm;
  Eigen::Vector2d x_run_at_mm = Eigen::Vector2d::Zero();
  Eigen::Vector2d y_run_at_mm = Eigen::Vector2d::Zero();
  // Grid: every combination, Z planes outermost (point i = (iz * ny + iy) * nx + ix).
  std::vector<double> grid_x_mm, grid_y_mm, grid_z_mm;
  // Rotary checks at a fixed pivot position.
  Eigen::Vector3d rotary_at_mm = Eigen::Vector3d::Zero();
  double c_check_a_rad = 0;           // A held at this tilt while C steps
  std::vector<double> c_check_c_rad;  // C steps
  double a_check_c_rad = 0;           // C held while A steps
  std::vector<double> a_check_a_rad;
  std::vector<double> w_check_w_mm;  // W steps at A = C = 0
  CircleTestConfig circle;           // the same circle in each plane
  LinearRunConfig linear_run;
  // The `uncertainty:` mapping (see above), if any: what `ncqual uncertainty` simulates.
  std::optional<VerificationUncertaintyConfig> uncertainty;
};

// The `global_check:` section is read by the configuration layer
// (common/src/config/global_check_section.cpp); unknown keys are refused.
// Its optional `uncertainty:` mapping goes to GlobalCheckConfig::uncertainty; refused there
// (ConfigError naming the key, e.g. global_check.uncertainty.tracker.angular_sigma_urad, and the
// value): a missing tracker or tracker.position_mm, negative or non-finite sigmas, non-finite
// numbers, samples_per_point or trials not an integer from 1 to 1e6, a seed not an integer >= 0,
// a search box with min > max, step_mm <= 0, more than 1e6 candidates, negative clearance or
// min_range_mm, max_range_mm <= min_range_mm, unknown keys.

// One move of a monthly program: the machine goes to `commanded`; when `label` is non-empty the
// tracker measures target `target` there. Moves without a label are approach moves (e.g. an
// overrun before a reversal): they only change the direction the axes arrive from.
struct TrackerMove {
  std::string label;
  AxisPosition commanded;
  int target = 0;
};

// The moves of a monthly check kind (GlobalMasterFrame, GlobalGrid, RotaryW/A/C, CircleXY/YZ/XZ,
// LinearAxisRun), in the order the machine runs them. Every kind but the master frame and the
// linear run starts with the master-frame runs of its session; the linear run is measured from
// a station on the axis line (the tracker's interferometer mode, as ISO 230-2 expects a laser
// interferometer), in another frame. Throws std::invalid_argument for a kind that is not a
// tracker check.
std::vector<TrackerMove> global_check_program(CheckKind kind, const GlobalCheckConfig& config);

}  // namespace ncqual

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

#include "ncqual/kinematics.hpp"
#include "ncqual/model.hpp"

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace ncqual {

struct CircleTestConfig {
  Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();  // commanded pivot position of the centre
  double radius_mm = 0;
  int points = 0;               // per direction, evenly spaced from angle 0
  bool bidirectional = true;    // ccw then cw
};

struct LinearRunConfig {
  int axis = 0;                               // 0, 1, 2 = X, Y, Z
  Eigen::Vector3d at_mm = Eigen::Vector3d::Zero();  // the pivot position; the axis' own coordinate
                                              // is replaced by each target
  std::vector<double> targets_mm;             // ascending
  int cycles = 5;
  double overrun_mm = 5;                      // past the last target before reversing
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
  double c_check_a_rad = 0;            // A held at this tilt while C steps
  std::vector<double> c_check_c_rad;   // C steps
  double a_check_c_rad = 0;            // C held while A steps
  std::vector<double> a_check_a_rad;
  std::vector<double> w_check_w_mm;    // W steps at A = C = 0
  CircleTestConfig circle;             // the same circle in each plane
  LinearRunConfig linear_run;
};

// Reads the `global_check:` section. Throws ConfigError naming file, key and value. Unknown keys
// are refused.
GlobalCheckConfig parse_global_check_config(const YAML::Node& node, const std::string& where);

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

// True for the kinds measured with the laser tracker.
bool is_tracker_check(CheckKind kind);

}  // namespace ncqual

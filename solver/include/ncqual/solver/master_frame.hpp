// SPDX-License-Identifier: Apache-2.0
// Monthly laser-tracker check, step 1: the master frame of reference.
//
// Patent ("Global Machine Accuracy Check"): "the machine is positioned at the middle of its
// working envelope along the Y and Z axis directions, and the Y, Z, W, A, and C axes of the
// machine are fixed. The machine is run along the X axis direction from one end of the working
// envelope to the other end. At a plurality (e.g., eleven) of points ... the laser tracking unit
// measures the XYZ coordinates of the target ... The machine is then positioned in the middle of
// the working envelope along the X and Z directions ... The slide is run along the Y axis
// direction ... (e.g., ten) points ... Using the points acquired along the X and Y travel of the
// machine, a curve-fitting program ... calculates a best linear fit of the points to determine an
// orthogonal set of coordinate axes defining a master frame of reference." The master frame is
// "relative to the ways of the machine as opposed to ... ground and gravity".
//
// Frames: "instrument" is the tracker's own frame, "master" the frame fitted here (the machine's
// ways), "machine" the commanded (NC) coordinates. master = instrument_to_master * instrument.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace ncqual::solver {

namespace master_frame {
// A run's commanded coordinates other than its own axis, and the two runs' commanded Z, must
// agree within this (mm); two commanded positions closer than this along the run are duplicates.
inline constexpr double kSameCommandedMm = 1e-6;
// Fewest points per run: two define a line, a third is the first that can show straightness.
inline constexpr int kMinRunPoints = 3;
// The fitted X and Y lines must be within this of perpendicular (rad, 45 degrees). A machine's
// squareness error is tens of micro-radians; lines further off than this are (nearly) parallel,
// i.e. the runs are mislabelled or not the X and Y travel, and cannot define a frame.
inline constexpr double kMaxNonOrthogonalityRad = 0.7853981633974483;
// The measured travel along a fitted line must be within this fraction of the commanded travel
// (|slope - 1| <= 0.1). Real scale errors are ~1e-4; beyond this the points are in the wrong
// unit (inches: slope 0.0394), the wrong points, or all coincide (slope 0: no line at all).
inline constexpr double kMaxScaleDeviation = 0.1;
}  // namespace master_frame

// One tracker reading: the commanded target position in machine coordinates (mm) and the
// instrument's (tracker's) reading in its own frame (mm).
struct FramePoint {
  std::string label;
  Eigen::Vector3d commanded_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d measured_mm = Eigen::Vector3d::Zero();
};

// One point of a run against its fitted line.
struct RunPointResidual {
  std::string label;
  double commanded_mm = 0;  // commanded coordinate along the run's axis (x or y)
  // Measured position along the fitted line, from the centroid of the run's points (mm).
  double along_mm = 0;
  // along_mm - (mean along + slope * (commanded - mean commanded)): what the linear scale fit
  // leaves along the line (mm); the positioning non-linearity of the axis.
  double along_residual_mm = 0;
  // Perpendicular residual from the fitted line, in the run's two cross directions (RunFit::
  // cross_direction_*): X run (master Y, master Z), Y run (master X, master Z), mm.
  Eigen::Vector2d cross_mm = Eigen::Vector2d::Zero();
  double distance_mm = 0;  // |perpendicular residual| = distance from the fitted line
  // Master coordinates of the measured point minus the commanded position (mm).
  Eigen::Vector3d deviation_mm = Eigen::Vector3d::Zero();
};

// The total-least-squares line through one run and what it says about the axis.
struct RunFit {
  std::string run;  // "x_run" or "y_run"
  // The line: centroid of the measured points and unit direction, oriented towards increasing
  // commanded coordinate, instrument frame.
  Eigen::Vector3d point_instrument_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction_instrument = Eigen::Vector3d::UnitX();
  // The same direction in the master frame (differs from master X, resp. Y, by half the
  // non-orthogonality of the runs, in the XY plane, plus noise).
  Eigen::Vector3d direction_master = Eigen::Vector3d::UnitX();
  // Unit directions perpendicular to the line in which the residuals are given, instrument
  // frame: the master axes made perpendicular to the line. X run: (~master Y, ~master Z);
  // Y run: (~master X, ~master Z).
  Eigen::Vector3d cross_direction_1_instrument = Eigen::Vector3d::UnitY();
  Eigen::Vector3d cross_direction_2_instrument = Eigen::Vector3d::UnitZ();
  // Straightness in each cross direction: max - min of the perpendicular residual (mm).
  Eigen::Vector2d straightness_mm = Eigen::Vector2d::Zero();
  double max_distance_mm = 0;  // largest distance of a point from the line (mm)
  // Along-axis scale: least-squares slope of the measured along-line position against the
  // commanded coordinate, minus 1, in micrometres per metre (positive: the axis moves further
  // than commanded).
  double scale_um_per_m = 0;
  std::vector<RunPointResidual> points;  // in input order
};

struct MasterFrame {
  // master = instrument_to_master * instrument (rigid: rotation and translation, mm).
  Eigen::Isometry3d instrument_to_master = Eigen::Isometry3d::Identity();
  // The master axes expressed in the instrument frame (the rows of the rotation).
  Eigen::Vector3d x_axis_instrument = Eigen::Vector3d::UnitX();
  Eigen::Vector3d y_axis_instrument = Eigen::Vector3d::UnitY();
  Eigen::Vector3d z_axis_instrument = Eigen::Vector3d::UnitZ();
  // Angle between the fitted X and Y lines minus 90 degrees, micro-radians; positive when the
  // angle is larger than 90 degrees (the ISO 230-1 squareness EC(0X)Y of the runs, see
  // global_grid.hpp).
  double orthogonality_urad = 0;
  // Root mean square over both runs of |master - commanded| (mm): what the frame leaves.
  double origin_rms_mm = 0;
  RunFit x_run;
  RunFit y_run;
};

// Fits the master frame to an X run and a Y run of the tracker target.
//
// 1. Each run: the total-least-squares line through its measured points (centroid and the
//    principal direction of their scatter), oriented towards increasing commanded x (resp. y).
// 2. The frame: with u, v the fitted X and Y directions, b = (u + v)/|u + v| their bisector and
//    d = (u - v)/|u - v|, master X = (b + d)/sqrt 2, master Y = (b - d)/sqrt 2, Z = X x Y. Both
//    axes are turned by half the non-orthogonality, in opposite senses, in the plane of u and v:
//    the orthonormal pair nearest to (u, v) in the least-squares sense (the polar decomposition
//    [u v] (V^T V)^-1/2 of V = [u v]), not "X exact, Y forced perpendicular".
// 3. The origin: master coordinates match the commanded ones on average over both runs. The X run
//    fixes the along-X offset from its commanded x and the Y and Z offsets from its constant
//    commanded y, z; the Y run likewise. Their least-squares combination, one equation per point
//    and coordinate, is t = mean over all points of (commanded - R measured).
// 4. Per run: straightness, largest distance from the line, scale, residuals (RunFit).
//
// Refuses (std::invalid_argument naming the run, the point label and the value): fewer than
// kMinRunPoints points in a run; non-finite commanded or measured coordinates; a run whose
// commanded positions vary in a coordinate other than its own axis (beyond kSameCommandedMm);
// two points of a run at the same commanded position; the two runs at different commanded Z;
// a measured travel that does not match the commanded one (kMaxScaleDeviation); fitted lines
// (nearly) parallel (kMaxNonOrthogonalityRad).
MasterFrame fit_master_frame(const std::vector<FramePoint>& x_run,
                             const std::vector<FramePoint>& y_run);

}  // namespace ncqual::solver

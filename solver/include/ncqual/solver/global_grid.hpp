// SPDX-License-Identifier: Apache-2.0
// Monthly laser-tracker check, step 2: positioning over a grid of the working envelope.
//
// Patent ("Global Machine Accuracy Check"): "the machine is moved along its X, Y, and Z axes so as
// to position the target at each of a plurality of points (e.g., 216 points) spaced throughout
// the three-dimensional working envelope E of the machine. Advantageously, the points are
// arranged on four constant-Z planes ... At each point, the coordinates of the target in the
// master coordinate system are measured by the laser tracking unit ... The measured X, Y, and Z
// positions for each point are compared with the intended values ... Discrepancies between the
// measured and intended position values that exceed maximum acceptable amounts indicate a need
// for physical intervention". The charts per constant-Z plane "make it easy to identify those
// regions of the machine's working envelope in which the errors exceed the allowable amount".
//
// Beyond the patent, an affine fit of the measured positions to the commanded ones separates the
// linear errors of the axes (scale, squareness) from what is left (straightness, non-linearity).
//
// ISO 230-1 squareness. ISO 230-1 names a squareness error E<R>(0<P>)<S>: the rotation, about the
// axis R, of the line of motion of axis S from its nominal direction, taking the line of axis P
// as the reference. Checked for each, with the reference axis line along its nominal direction
// and the second axis' line turned by a small +e (right-hand rule) about the named axis:
//   EC(0X)Y: +e about Z turns +Y to (-sin e, cos e, 0); its angle to X (1, 0, 0) has cosine
//            -sin e, i.e. is 90 deg + e.                  So EC(0X)Y = +squareness_xy_urad.
//   EA(0Y)Z: +e about X turns +Z to (0, -sin e, cos e); its angle to Y has cosine -sin e,
//            i.e. is 90 deg + e.                          So EA(0Y)Z = +squareness_yz_urad.
//   EB(0X)Z: +e about Y turns +Z to (sin e, 0, cos e); its angle to X has cosine +sin e,
//            i.e. is 90 deg - e.                          So EB(0X)Z = -squareness_zx_urad.
// (squareness_ab_urad below is the angle between the fitted motions of axes a and b minus 90
// degrees, positive when the angle exceeds 90 degrees.) AxisMotionFit gives all three also
// under their ISO names.
#pragma once

#include "ncqual/solver/master_frame.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

namespace ncqual::solver {

namespace global_grid {
// Fewest grid points: the affine fit has 4 unknowns per coordinate; 5 leave one redundancy.
inline constexpr int kMinPoints = 5;
// The commanded positions must span 3-D: the smallest singular value of the centred commanded
// coordinates must be at least this fraction of the largest (else they are (nearly) coplanar).
inline constexpr double kMinSpreadRatio = 1e-6;
// The master frame's rotation must be orthonormal within this (|R^T R - I|, max element).
inline constexpr double kOrthonormalTolerance = 1e-9;
}  // namespace global_grid

struct GridOptions {
  int worst_point_count = 10;        // how many of the worst points GridAnalysis lists (>= 0)
  double plane_tolerance_mm = 1e-3;  // points whose commanded Z differ by less share a plane
};

struct GridPointResult {
  std::string label;
  Eigen::Vector3d commanded_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d master_mm = Eigen::Vector3d::Zero();     // measured, in the master frame
  Eigen::Vector3d deviation_mm = Eigen::Vector3d::Zero();  // master - commanded, per axis
  double deviation_norm_mm = 0;                            // |deviation|
  // master - (M commanded + t) of the affine fit: what scale and squareness do not explain.
  Eigen::Vector3d affine_residual_mm = Eigen::Vector3d::Zero();
};

// One constant-Z plane of the grid: the patent's per-plane chart and its "worst region".
struct GridPlaneSummary {
  double z_mm = 0;  // commanded Z of the plane (mean over its points)
  int point_count = 0;
  std::size_t worst_index = 0;  // index into GridAnalysis::points
  std::string worst_label;
  double worst_deviation_mm = 0;  // largest |deviation| in the plane
  double rms_deviation_mm = 0;    // sqrt(mean |deviation|^2) over the plane
  Eigen::Vector3d max_abs_deviation_mm = Eigen::Vector3d::Zero();  // max |dx|, |dy|, |dz|
};

// Least-squares affine fit master ~ M commanded + t over all grid points.
struct AxisMotionFit {
  // Columns: the actual motion of the target per unit commanded motion of X, Y, Z, in the master
  // frame (scaled directions).
  Eigen::Matrix3d motion = Eigen::Matrix3d::Identity();
  Eigen::Vector3d offset_mm = Eigen::Vector3d::Zero();  // t
  // (|M e_k| - 1) 1e6: positive when the axis moves further than commanded.
  double scale_x_um_per_m = 0;
  double scale_y_um_per_m = 0;
  double scale_z_um_per_m = 0;
  // Angle between the fitted motions of the two axes minus 90 degrees, micro-radians,
  // positive when the angle exceeds 90 degrees.
  double squareness_xy_urad = 0;
  double squareness_yz_urad = 0;
  double squareness_zx_urad = 0;
  // The same under their ISO 230-1 names (see the top of this file).
  double ec_0x_y_urad = 0;  // EC(0X)Y = +squareness_xy_urad
  double ea_0y_z_urad = 0;  // EA(0Y)Z = +squareness_yz_urad
  double eb_0x_z_urad = 0;  // EB(0X)Z = -squareness_zx_urad
  // sqrt(mean over points of |residual|^2), mm.
  double residual_rms_mm = 0;
};

struct GridAnalysis {
  std::vector<GridPointResult> points;  // in input order
  double max_deviation_mm = 0;          // largest |deviation|
  std::string max_deviation_label;
  double rms_deviation_mm = 0;  // sqrt(mean |deviation|^2)
  double max_abs_dx_mm = 0;
  double max_abs_dy_mm = 0;
  double max_abs_dz_mm = 0;
  // Indices into `points` of the options.worst_point_count largest |deviation|, largest first
  // (ties in input order).
  std::vector<std::size_t> worst_points;
  std::vector<GridPlaneSummary> planes;  // by increasing commanded Z
  AxisMotionFit affine;
};

// Positioning over the grid: each measured point taken into the master frame
// (frame.instrument_to_master), its deviation master - commanded (mm), the summary over the
// grid and per constant-Z plane, and the affine fit of the axis motions (AxisMotionFit).
// Points are grouped into planes by commanded Z: sorted by Z, a new plane starts where Z jumps
// by more than options.plane_tolerance_mm.
//
// Refuses (std::invalid_argument naming the field and the value): fewer than
// global_grid::kMinPoints points; duplicate labels; non-finite commanded or measured
// coordinates; all points on one constant-Z plane (the Z scale and the YZ and ZX squareness
// would be undefined), or one constant X or Y, or otherwise (nearly) coplanar commanded positions
// (kMinSpreadRatio); a frame whose rotation is not orthonormal or is not finite; negative
// options.worst_point_count or non-positive or non-finite options.plane_tolerance_mm.
GridAnalysis analyze_grid(const MasterFrame& frame, const std::vector<FramePoint>& grid,
                          const GridOptions& options = {});

// The same, fitting the master frame first (fit_master_frame, with its refusals).
GridAnalysis analyze_grid(const std::vector<FramePoint>& x_run,
                          const std::vector<FramePoint>& y_run, const std::vector<FramePoint>& grid,
                          const GridOptions& options = {});

}  // namespace ncqual::solver

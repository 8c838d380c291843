// SPDX-License-Identifier: Apache-2.0
// Identification of the 21 rigid-body errors of the linear axes X, Y, Z (model and names in
// ncqual/common/volumetric.hpp) from
//   A. a laser-tracker grid (Aguado et al.): the tool point measured in the tracker's own frame
//      at commanded positions, possibly with several tool offsets;
//   B. sequential-diagonal ("laser vector") data (Wang & Chung section 2.2): a laser along each
//      of the four body diagonals of the box [lo, hi]^3, X, Y and Z moved one at a time, the
//      displacement along the beam read after each single-axis move.
//
// Both are weighted nonlinear least squares (Ceres, analytic Jacobians, dense normal Cholesky)
// over the Legendre coefficients of the error functions, the three squareness errors and the
// instrument frame, with the exact chain of volumetric::actual_position as the model.
//
// Gauge (what a measurement in an unknown instrument frame cannot see, fixed by convention):
//   - positioning errors EXX, EYY, EZZ: no P_0 term (P_1, the scale error, stays);
//   - straightness errors: no P_0 and no P_1 term (the three squareness errors carry what
//     remains of the linear parts, the frame the rest);
//   - angular errors: no P_0 term, EXCEPT the angular errors of the last axis, EAZ, EBZ, ECZ,
//     which keep their P_0 term. Their constant parts rotate only the tool offset t (the tool's
//     orientation relative to the X, Y, Z motions), which no frame rotation, squareness or
//     straightness reproduces once the gauge above has fixed the frame to the X motion and the
//     Y-Z plane: with several tool offsets whose differences span two or more directions they
//     are identifiable, and a machine with a constant spindle tilt could not be fitted without
//     them. (This departs from "angular errors have no P_0 term", which is exact for one tool
//     offset only.) The constant parts of the other angular errors are frame rotation plus
//     linear straightness, so they stay out.
// Lever arms: ECY and the three angular errors of Z act only through the tool offset t, so they
// are identifiable only when the data has several tool offsets (different t_x, t_y for ECY and
// ECZ, different t_z for EAZ and EBZ); with one tool offset they are lumped into the straightness
// of Y and Z. The identification does not rely on a list: it finds which terms the data cannot
// determine (next paragraph), fixes them to zero and names them.
//
// Procedure (one call):
//   1. Validation (refusals below); axis ranges [lo, hi] from the data (or the options); the
//      highest Legendre order of each axis is min(max_degree, distinct positions - 1).
//   2. Initial frame: weighted rigid best fit (SVD) of measured to commanded + t (or the
//      caller's frame). The model is linearised at zero errors around it.
//   3. Identifiability: the columns of the weighted, column-normalised linearised Jacobian are
//      taken in a fixed order (frame, squareness, positioning and straightness terms by axis
//      and order, angular terms of X, then Y, then Z); a column whose squared distance to the
//      span of the columns already kept is below options.rank_tolerance is fixed to zero (an
//      incremental Cholesky). A function with all its terms fixed is reported unidentifiable.
//   4. Order of each function: Bayesian information criterion with the given sigmas,
//      BIC = chi^2 + (number of coefficients) ln(number of observations), by backward
//      elimination from the highest orders: among the highest remaining term of every function,
//      the one whose removal raises chi^2 least (b_j^2 / C_jj, exact for the current linear
//      model, correlations included) is dropped while that rise is below ln(observations), the
//      solution and covariance being downdated exactly after each drop. Series stay contiguous
//      (a lower order is never dropped before a higher one). The reported bands are conditional
//      on the chosen orders: a true term below ~2.5 sigma of its estimator may be truncated and
//      its effect is then not in the band.
//   5. One Ceres solve of the exact model from the linear solution; covariance (J'WJ)^-1 at the
//      solution, from the given sigmas (not rescaled by chi^2 / dof, which is reported).
//
// Units: mm and rad. Frames: `instrument_from_machine` maps machine coordinates (the gauge frame
// of the model: the X motion along x, the Y motion in the x-y plane, up to squareness) to the
// instrument's: measured = R * p + T.
#pragma once

#include "ncqual/common/volumetric.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace ncqual::solver {

// Input A: one laser-tracker point. `measured_mm` is in the instrument frame; `sigma_mm` is the
// point's 1 sigma per coordinate (weight 1/sigma^2).
struct VolumetricPoint {
  std::string label;
  Eigen::Vector3d commanded_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d tool_offset_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d measured_mm = Eigen::Vector3d::Zero();
  double sigma_mm = 0;
};

// Input B: one sequential-diagonal reading. `diagonal` 0..3 names the body diagonal (any
// numbering; readings of one diagonal are in measurement order, the first is its start);
// `direction` is the unit beam direction in machine axes as aligned (e.g. the nominal diagonal
// (hi - lo)/|hi - lo| with the signs of that diagonal); `displacement_mm` the reading along the
// beam relative to the diagonal's start (the start reading is 0 by definition).
struct DiagonalReading {
  int diagonal = 0;
  Eigen::Vector3d commanded_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();
  double displacement_mm = 0;
  double sigma_mm = 0;
};

struct IdentificationOptions {
  // Highest Legendre order tried for any function (1..12); each axis is further limited to its
  // number of distinct positions - 1.
  int max_degree = 6;
  // A term is fixed to zero when the squared sine of the angle between its normalised column and
  // the span of the columns kept before it is below this (0 < tolerance < 1).
  double rank_tolerance = 1e-8;
  // Initial instrument_from_machine; default: the weighted rigid best fit (A) or identity (B).
  std::optional<Eigen::Isometry3d> initial_instrument_from_machine;
  // Axis ranges [lo, hi] (mm) of the Legendre series, per axis X, Y, Z; default: the range of
  // the commanded positions.
  std::optional<std::array<std::array<double, 2>, 3>> axis_range_mm;
  int max_iterations = 25;  // Ceres iterations, >= 1
};

// One identified parameter: a Legendre coefficient (function 0..17, order), a squareness error
// (squareness 0..2 = EC(0X)Y, EB(0X)Z, EA(0Y)Z) or a frame component (frame 0..2 rotation about
// x, y, z of the instrument_from_machine increment (rad), 3..5 translation (mm)); the others -1.
struct IdentifiedParameter {
  std::string name;  // "EXX P1", "EC(0X)Y", "frame rx", "frame tx", ...
  int function = -1;
  int order = -1;
  int squareness = -1;
  int frame = -1;
  // mm or rad. Frame components: the rotation vector (rad) and translation (mm) of
  // instrument_from_machine; their sigma is that of an increment there, R exp(d), T + dT.
  double value = 0;
  double sigma = 0;
};

// Input A residual of one point: measured - predicted (instrument frame, mm), before (rigid best
// fit of commanded + t only) and after (the identified model) compensation.
struct PointResidual {
  std::string label;
  Eigen::Vector3d before_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d after_mm = Eigen::Vector3d::Zero();
};

// Input B residual of one reading (the start readings excluded): reading - predicted (mm).
struct ReadingResidual {
  int diagonal = 0;
  int reading = 0;  // index within its diagonal, 1 = first move
  double before_mm = 0;
  double after_mm = 0;
};

struct IdentifiedErrors {
  // The errors in the gauge of the header comment. Function f has coefficients c_0..c_degree[f]
  // (orders fixed by the gauge or by identifiability are 0) over the axis range, or none.
  volumetric::RigidBodyErrors errors;
  std::array<int, volumetric::kFunctionCount> degree{};  // highest order kept; -1: none
  // Covariance (mm^2 or rad^2) of each function's coefficients c_0..c_degree (zero rows and
  // columns for fixed orders).
  std::array<Eigen::MatrixXd, volumetric::kFunctionCount> coefficient_covariance;
  Eigen::Vector3d squareness_sigma_rad = Eigen::Vector3d::Zero();  // EC(0X)Y, EB(0X)Z, EA(0Y)Z

  // 1 sigma of function `index` (0..17) at position q (mm or rad), from its covariance; for the
  // squareness indices 18..20 their 1 sigma (q ignored). Throws std::invalid_argument naming
  // the index when outside 0..20.
  double sigma_at(int index, double q_mm) const;

  // measured = instrument_from_machine * p. B: a rotation only (of the set of beams).
  Eigen::Isometry3d instrument_from_machine = Eigen::Isometry3d::Identity();
  // 1 sigma of the frame: rotation increments about x, y, z (rad), then translation (mm; 0 for B).
  Eigen::Matrix<double, 6, 1> frame_sigma = Eigen::Matrix<double, 6, 1>::Zero();

  // Functions the data cannot determine, fixed to zero (e.g. "ECY", "EAZ" with one tool offset).
  std::vector<std::string> unidentifiable;
  // Single terms fixed to zero by identifiability in functions that keep other terms ("EXY P5").
  std::vector<std::string> fixed_terms;
  // B: the angular errors, not modelled: with one target their effect is lumped into the
  // straightness functions (and the fit's residual).
  std::vector<std::string> lumped;

  // Every free parameter of the final solve, with its covariance (same order).
  std::vector<IdentifiedParameter> parameters;
  Eigen::MatrixXd covariance;

  // Residual volumetric error (A: |measured - predicted| per point, instrument frame; B: |reading
  // - predicted| per reading), before compensation (rigid best fit of the nominal model only)
  // and after (the identified model).
  double rms_before_mm = 0, max_before_mm = 0;
  double rms_after_mm = 0, max_after_mm = 0;

  int observations = 0;        // scalar residuals: 3 per point (A), 1 per moved reading (B)
  int degrees_of_freedom = 0;  // observations - parameters
  double chi_square = 0;       // sum of (residual / sigma)^2 after the solve
  // Ceres: iterations, cost = chi^2 / 2 at the start (the linear solution) and at the end.
  int iterations = 0;
  double initial_cost = 0, final_cost = 0;
  bool converged = false;

  std::vector<PointResidual> point_residuals;      // A
  std::vector<ReadingResidual> reading_residuals;  // B
};

// Input A. Identifies the errors and the 6-dof instrument frame from tracker points.
// Refuses (std::invalid_argument naming the field and the value): an empty list; non-finite
// commanded, tool offset or measured coordinates; sigma_mm not finite and > 0; duplicate
// (commanded, tool offset) pairs (equal within 1e-6 mm); an axis with fewer than 2 distinct
// commanded positions (1e-3 mm apart); fewer observations (3 per point) than unknowns of the
// candidate model (both counts named); options out of range; data that cannot fix the frame.
IdentifiedErrors identify_rigid_body_errors(const std::vector<VolumetricPoint>& points,
                                            const IdentificationOptions& options = {});

// Input B. Identifies the nine translational functions (gauge above) and the three squareness
// errors from sequential-diagonal readings, with the rotation of the set of beams relative to
// the machine axes (3 dof; the readings are differences, so no translation).
// What diagonals determine: each single-axis move is seen along four beam directions that span
// space, so the 3-D increment of each axis' translational error between its consecutive
// positions is determined (with redundancy); hence the positioning and straightness functions
// up to their constants, the scale errors, and the linear parts as 3 squareness + the beam-set
// rotation. The beam directions themselves must be known (aligned): a misalignment of one beam
// would alias into the linear parts. Precision: each function is a cumulative sum of noisy
// increments (its low orders carry ~2.5 x the reading noise on 12 steps), and on an elongated box
// the beams lie nearly along the long axis, so the across components are seen weakly (3200 x
// 1000 x 600 mm: weights 0.09 and 0.03 against 1/3 on a cube). What they do not determine: the
// angular errors (one target per beam: their Abbe effect is not separable from straightness; they
// are reported in `lumped` and bias the straightness functions), the constants (gauge), the tool
// offset. Refuses (std::invalid_argument naming the field and the value): an empty list; diagonal
// not in 0..3; non-finite values; direction not a unit vector (1e-6); sigma_mm not finite and > 0;
// a start reading (first of its diagonal) with displacement_mm != 0; a diagonal with a repeated
// commanded position; an axis with fewer than 2 distinct positions; fewer moved readings than
// unknowns (both counts named); options out of range.
IdentifiedErrors identify_from_diagonals(const std::vector<DiagonalReading>& readings,
                                         const IdentificationOptions& options = {});

// What the identified model predicts for a tool point: its actual position (machine frame, the
// gauge's), the same seen by the instrument (instrument_from_machine applied), and their
// covariances from the parameter covariance (actual: error parameters only; in the instrument
// frame: all parameters, frame included). Refuses (std::invalid_argument) non-finite inputs.
struct VolumetricPrediction {
  Eigen::Vector3d actual_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d in_instrument_mm = Eigen::Vector3d::Zero();
  Eigen::Matrix3d actual_covariance_mm2 = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d in_instrument_covariance_mm2 = Eigen::Matrix3d::Zero();
};
VolumetricPrediction predict_position(const IdentifiedErrors& identified,
                                      const Eigen::Vector3d& commanded_mm,
                                      const Eigen::Vector3d& tool_offset_mm);

}  // namespace ncqual::solver

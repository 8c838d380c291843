// SPDX-License-Identifier: Apache-2.0
// The weekly probe checks of the holding fixture: pre-calibration and post-calibration.
//
// Patent ("Probe Checks of Fixture"): "the machine is moved to each of a plurality of the pogos
// and is moved along the Z direction to cause the tip of the stylus to contact a reference surface
// of the pogo that should nominally be at the intended Z position. The machine also probes
// reference surfaces of the pogo along the X and Y directions ... Differences between the measured
// X, Y, and Z coordinates and the intended coordinates are calculated for each probed pogo. If the
// differences are within acceptable limits of zero, then the pre-calibration has been
// satisfactorily completed. If [not] ... the differences between the measured and intended X, Y,
// and Z positions of the pogos are applied as zero offsets within the numerical control unit."
// "In the post-calibration check, the fixture is probed in each of a plurality of different
// configurations ... If the differences are not within acceptable limits of zero, then the
// software corrections made to the fixture are not adequate ... This can be due to some
// nonlinearity in the behavior of the fixture, misalignment of the fixture axes relative to the
// machine axes, wear of fixture components, and other potential causes."
//
// Input: touches named "pogo:<label>:cfg<index>:<face>" (ncqual/common/fixture.hpp), five faces per
// pogo (top, x-, x+, y-, y+), head at home (A = C = 0); the machine config's `fixture:` section
// gives the commanded positions of each configuration.
//
// Tolerances (machine config `tolerances:`): per axis "fixture_dx_mm", "fixture_dy_mm",
// "fixture_dz_mm", each falling back to "fixture_delta_mm" when absent. Every delta of that axis
// and the worst-case summary of the axis are judged against it.
//
// Metrics (public names):
//   pre-calibration:  "pogo_<label>_d<x|y|z>_mm"              e.g. "pogo_C2R3_dx_mm"
//   post-calibration: "cfg<j>_pogo_<label>_d<x|y|z>_mm"       e.g. "cfg4_pogo_C2R3_dx_mm"
//   both:             "fixture_max_dx_mm", "fixture_max_dy_mm", "fixture_max_dz_mm": the signed
//                     delta of largest magnitude of that axis
//   post-calibration, only when the machine config has a tolerance of that very name (bare
//   numbers in the metric's unit), the fit of the deltas against the commanded positions:
//     "fixture_fit_d<i>_per_<j>_urad" (i != j, e.g. "fixture_fit_dx_per_z_urad"): slope of the
//        delta along i with the commanded position along j, micro-radians (misalignment);
//     "fixture_fit_d<i>_per_<i>_ppm": slope along the same axis, ppm (scale);
//     "fixture_fit_systematic_residual_mm": largest residual shared by the points at one commanded
//        X, Y or Z (curvature over travel);
//     "fixture_fit_scatter_rms_mm": largest rms of the residual of an axis.
//   The fitted values are always given in the reason of a FAIL.
// Correction (pre-calibration FAIL): target "fixture:<fixture_id>", one offset per probed pogo and
// axis, named "<label>.d<x|y|z>" (e.g. "C2R3.dx"), unit "mm", value = the delta measured -
// commanded; the fixture's control unit subtracts it from what it commands that pogo.
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/common/model.hpp"

#include <Eigen/Core>

#include <string>
#include <string_view>
#include <vector>

namespace ncqual::solver {

namespace fixture_checks {
// Request / measurement set parameter: the pre-calibration configuration k (0 .. 2n-1). Required
// for pre-calibration; for post-calibration optional, selecting the rows probed (those of k).
inline constexpr std::string_view kConfigurationParameter = "fixture_configuration";

inline constexpr std::string_view kToleranceDx = "fixture_dx_mm";
inline constexpr std::string_view kToleranceDy = "fixture_dy_mm";
inline constexpr std::string_view kToleranceDz = "fixture_dz_mm";
inline constexpr std::string_view kToleranceDelta = "fixture_delta_mm";  // fallback, all axes

inline constexpr std::string_view kMaxDx = "fixture_max_dx_mm";
inline constexpr std::string_view kMaxDy = "fixture_max_dy_mm";
inline constexpr std::string_view kMaxDz = "fixture_max_dz_mm";
inline constexpr std::string_view kSystematicResidual = "fixture_fit_systematic_residual_mm";
inline constexpr std::string_view kScatterRms = "fixture_fit_scatter_rms_mm";

// "pogo_C2R3_dx_mm" (axis 0, 1, 2 = x, y, z)
std::string pogo_metric_name(std::string_view pogo, int axis);
// "cfg4_pogo_C2R3_dx_mm"
std::string post_metric_name(int configuration, std::string_view pogo, int axis);
// "fixture_fit_dx_per_z_urad" (i != j) or "fixture_fit_dx_per_x_ppm" (i == j)
std::string fit_metric_name(int delta_axis, int commanded_axis);

// Likely causes.
inline constexpr std::string_view kCauseZeroDrift =
    "fixture zero positions drifted (software zero offsets issued)";
inline constexpr std::string_view kCauseMisaligned =
    "fixture axes misaligned with the machine axes";
inline constexpr std::string_view kCauseNonlinear = "nonlinearity of a fixture axis";
inline constexpr std::string_view kCauseWear = "wear of fixture components";

// A fitted term is significant when its effect over the probed travel reaches this fraction of
// the tolerance half-width of the delta axis it moves, and (slopes) its estimate is this many
// standard errors from zero; a residual shared by the points at one commanded coordinate is
// systematic when the grouping explains at least kSystematicFraction of the residual's sum of
// squares.
inline constexpr double kSignificantFractionOfTolerance = 0.2;
inline constexpr double kSignificantSigmas = 4.0;
inline constexpr double kSystematicFraction = 0.5;
// The two side faces of a block are size apart; further than min(1 mm, 10 %) from it means the
// touches did not land on the reference block.
inline constexpr double kBlockSizeOffLimitMm = 1.0;
inline constexpr double kBlockSizeOffLimitFraction = 0.10;
}  // namespace fixture_checks

// One probed pogo in one configuration: its commanded position (fixture frame) and the delta
// measured - commanded (mm).
struct PogoDelta {
  std::string pogo;
  int configuration = 0;
  Eigen::Vector3d commanded_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d delta_mm = Eigen::Vector3d::Zero();
};

// Least-squares fit of the deltas against the commanded positions, with common slopes and one
// intercept per pogo:
//   delta_p,k = M c_p,k + b_p + residual
// (p the pogo, k its configurations). The intercepts b_p absorb each pogo's own zero (what its
// zero offset left over); M is estimated from how each pogo's delta changes between its
// configurations: with the pogo means removed, X = c - mean_p(c), Y = delta - mean_p(delta),
//   M^T = argmin ||X M^T - Y||^2,
// solved by column-pivoting QR on the columns that vary (scaled to unit rms). M(i, j) i != j is a
// misalignment (delta along i grows with travel along j, rad); M(i, i) is a scale error. The
// standard error of M(i, j) is s_i sqrt((X^T X)^-1_jj), s_i^2 = |R_i|^2 / (N - P - k). The
// residual R is then grouped by the absolute commanded coordinate of each axis (points sharing
// one commanded X, Y or Z): a nonlinearity of an axis is a function of that coordinate and is
// shared by the group, trigger noise and wear are not. For each delta axis the grouping that
// explains the largest share of |R_i|^2, sum_g n_g mean_g(R_i)^2 / |R_i|^2, is kept with the
// largest |mean_g(R_i)|. Groupings with fewer than 3 points per group on average are not used.
struct FixtureDeltaFit {
  std::string error;  // non-empty when the commanded positions cannot support the fit
  Eigen::Matrix3d slope = Eigen::Matrix3d::Zero();  // M(i, j), mm / mm
  Eigen::Matrix3d slope_standard_error = Eigen::Matrix3d::Zero();
  bool fitted[3] = {false, false, false};             // commanded axis j varies within some pogo
  Eigen::Vector3d span_mm = Eigen::Vector3d::Zero();  // largest within-pogo range of c_j
  Eigen::Vector3d residual_rms_mm = Eigen::Vector3d::Zero();  // per delta axis, sqrt(|R_i|^2 / N)
  Eigen::Vector3d systematic_residual_mm = Eigen::Vector3d::Zero();  // per delta axis
  Eigen::Vector3d systematic_fraction = Eigen::Vector3d::Zero();     // per delta axis
  int systematic_axis[3] = {-1, -1, -1};  // the commanded axis grouping it, -1 none
  int points = 0;
  int pogos = 0;
  int degrees_of_freedom = 0;
};
FixtureDeltaFit fit_fixture_deltas(const std::vector<PogoDelta>& points);

// Weekly fixture pre-calibration (kind FixturePreCalibration, parameter fixture_configuration = k):
// PASS when every delta of the pogos of configuration k lies in its tolerance; FAIL otherwise, with
// the deltas as zero offsets in result.correction. INVALID, with `reason` naming the field and the
// value, when the set or the config cannot support a verdict. Never throws for bad data.
CheckResult check_fixture_precalibration(const MeasurementSet& set, const MachineConfig& machine);

// Weekly fixture post-calibration (kind FixturePostCalibration), after the zero offsets: every
// post-calibration configuration, with the rows of pre-calibration configuration k when the set's
// parameters hold fixture_configuration = k, else every row. PASS when every delta lies in its
// tolerance; FAIL otherwise, the likely causes ordered by the fit of the deltas
// (fit_fixture_deltas):
//   significant misalignment slopes (and larger, relative to the tolerance, than the nonlinearity
//     evidence): misalignment, nonlinearity, wear;
//   significant scale slopes or a systematic residual: nonlinearity, misalignment, wear;
//   neither: wear, nonlinearity, misalignment.
CheckResult check_fixture_postcalibration(const MeasurementSet& set, const MachineConfig& machine);

}  // namespace ncqual::solver

// SPDX-License-Identifier: Apache-2.0
// Uncertainty of the monthly volumetric verification (Aguado et al., Sensors 2019): what a
// laser-tracker grid and the identification of the 21 rigid-body errors
// (ncqual/solver/volumetric_identification.hpp) leave uncompensated, by the Monte Carlo method of
// GUM Supplement 1; the error the tracker alone introduces at each point (the paper's eq. 23-24);
// and the tracker location that minimises it within an allowed region.
//
// What is propagated (per Monte Carlo trial, all draws independent and normal):
//   machine      the systematic errors `UncertaintySources::errors` (fixed, not drawn: the machine
//                being verified, e.g. the last identified errors or zero) and the repeatability:
//                each grid point lands off by N(0, sigma_k^2) along each axis k;
//   thermal      the true expansion during the verification: alpha_k ~ N(alpha_k, u(alpha_k)^2)
//                and Delta T_k ~ N(Delta T_k, u(Delta T_k)^2) per axis; the axis really moves to
//                (q_k + repeatability) (1 + alpha_k Delta T_k) (the paper's eq. 15-17). The
//                analysis corrects the commanded positions with the nominal alpha_k and the
//                measured Delta T_k, so that the identified model refers to 20 C: what it takes up
//                of the correction's error (s_true - s_nominal, s = alpha Delta T) stays in the
//                model as a scale error (see the measurand);
//   tracker      placement: its true position ~ N(position, sigma_pos^2 I) and its true
//                orientation = exp([w]x) R with w ~ N(0, sigma_rot^2 I) about the machine axes
//                (eq. 25-26; the identification fits the frame anyway, so placement acts only
//                through the geometry of the noise); noise in its own spherical coordinates:
//                range + N(0, ((sigma_r0 + sigma_r1 r) / sqrt(n))^2), azimuth and elevation each
//                + N(0, (sigma_angle / sqrt(n))^2), n = samples per point (eq. 23 is their
//                first-order image);
//   identification  the verification's analysis itself: the 21 errors and the tracker frame
//                identified from the noisy readings as identify_rigid_body_errors does it (same
//                gauge, candidate terms, identifiability test, Bayesian information criterion
//                for the orders with the design's assumed point sigma, unweighted), which is the
//                paper's fourth group (optimisation strategy).
// Not propagated: backlash and the wrist (the grid is a function of X, Y, Z only), the tracker's
// systematic errors (compensated by its own station, section 2.2.2), uncertainty of the sigmas
// themselves.
//
// The measurand: for every grid point (commanded q, tool offset t), the residual error of the
// identified model at the reference temperature 20 C,
//   e = (where the target truly is) - (where the identified model puts it),
// in the identified instrument frame (the frame the identification fits, so e is free of the
// gauge: what a compensation made with this verification would leave), along the machine axes
// (mm). "Where it truly is" is systematic: the machine's errors without the trial's repeatability
// draw (a compensation cannot and should not hold the next move's scatter) and without the
// tracker's noise. It is evaluated at the verification's own thermal state, where truth and model
// meet the readings, and carried to 20 C through the thermal correction's error:
//   e = e_verification - D (q - q_mid) o (s_true - s_nominal)
// D = d actual_position / d q (the exact chain, central differences), q_mid the middle of each
// axis' commanded range (the gauge puts the constant part of a scale error into the frame), o the
// per-axis product. So u(alpha) and u(Delta T) reach e as far as the identification takes up the
// mis-corrected scale: fully when the positioning scale terms (EXX, EYY, EZZ P1) are identified,
// not at all when the BIC drops them. A zero-noise verification of a machine whose errors the
// model represents in its gauge has e = 0 (terms outside the gauge, e.g. constant angular errors
// of X, are taken up by the frame and the gauge's terms to second order: ~(angle)^2 x lever).
//
// Method (MonteCarloOptions::method):
//   Linearised (default): the measurement model stays nonlinear: the exact chain of
//     volumetric::actual_position at the drawn thermal state (the repeatability's micrometres go
//     through D above: the chain's curvature leaves below 1e-9 mm), the drawn tracker pose, noise
//     added in spherical coordinates and converted back exactly. The identification is
//     linearised: each trial's readings are brought onto the nominal targets by an exact rigid
//     best fit (SVD; this removes the placement, a free frame of the identification anyway), then
//     the same linear least squares and BIC steps as identify_rigid_body_errors, with the
//     Jacobian of the model at zero errors about the nominal frame factorised once per call: a
//     trial costs matrix-vector products and rank-one downdates instead of a Ceres solve. Left
//     out is the identification's final nonlinear polish, second order in the errors:
//     (angle)^2 / 2 x lever arm + angle x translational error, about 1e-6 mm for 40 urad over
//     2 m (a thousandth of the micrometre residuals a tracker leaves).
//   Full: identify_rigid_body_errors (Ceres) on every trial; for validation and small designs.
// Why linearised: a full identification of the pm1 grid (864 points, 90 candidate parameters)
// took 6 to 8 ms on the shared 2-core development machine, so 1000 trials take 6 to 8 s on one
// core and 3 to 4 s on two, above the 2 s target; a linearised trial took 0.5 to 0.7 ms. On the
// same draws the two agree to about 1e-5 (relative) in each trial's mean and max residual (unit
// test and bench).
//
// Units: mm, rad, K (temperature deviations), 1/K (expansion coefficients). Frames: the machine
// frame of volumetric.hpp; the tracker's frame as in ncqual/sim/simulator_config.hpp (machine =
// R * tracker + position, R = Rz(yaw) Ry(pitch) Rx(roll)); spherical coordinates of the tracker:
// range r, azimuth about its z from its x, elevation from its x-y plane.
#pragma once

#include "ncqual/common/global_check.hpp"
#include "ncqual/common/volumetric.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace ncqual::solver {

// The laser tracker as the uncertainty model sees it: the tracker as planned in the plant config
// (ncqual/common/global_check.hpp: its pose, its noise, its placement sigmas, rotation()).
using TrackerUncertaintyModel = PlannedTrackerConfig;

// One verification point: the commanded X, Y, Z of the pivot and the target's offset from it
// (machine axes, mm), as identify_rigid_body_errors takes them.
struct DesignPoint {
  std::string label;
  Eigen::Vector3d commanded_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d tool_offset_mm = Eigen::Vector3d::Zero();
};

// The verification: its points and the analysis' settings (those of the monthly grid check:
// every point weighted alike with the assumed sigma, which sets the BIC's penalty scale).
struct VerificationDesign {
  std::vector<DesignPoint> points;
  double identification_sigma_mm = 0.01;  // the identification's assumed point sigma, > 0
  int max_degree = 6;                     // IdentificationOptions::max_degree (1..12)
  double rank_tolerance = 1e-8;           // IdentificationOptions::rank_tolerance (0..1)
};

// The grid points of the GlobalGrid program of `config` (labels grid:<i>:t<k>, in program order;
// the master-frame runs are not part of the identification), with each target's offset from the
// pivot at W = A = C = 0. Throws std::invalid_argument when the program has no grid point.
VerificationDesign grid_verification_design(const GlobalCheckConfig& config);

// u(alpha) by the rule of the paper (eq. 10, after ISO/TR 230-9): the range of alpha is taken as
// at least 10 % of |alpha| and never below 2e-6 1/K (0.002 um/(mm K)); a rectangular distribution
// of that full width gives u = width / (2 sqrt 3) (the paper's 0.002 -> 0.0006 um/(mm K)).
// Refuses (std::invalid_argument) a non-finite alpha.
double expansion_uncertainty_per_K(double alpha_per_K);

// The sources as configured (UncertaintySourcesConfig, ncqual/common/global_check.hpp:
// repeatability, expansion and its u(alpha), temperature deviation and its sigma, per axis X, Y, Z;
// the default u(alpha) is expansion_uncertainty_per_K(11.5e-6) = 5.77e-7 1/K) and the machine
// verified.
struct UncertaintySources : UncertaintySourcesConfig {
  volumetric::RigidBodyErrors errors;  // the machine verified (fixed)
};

enum class IdentificationMethod { Linearised, Full };

struct MonteCarloOptions {
  int trials = 1000;  // >= 1
  // Trial k draws from its own stream, seeded from (seed, k), and the statistics are merged in a
  // fixed order: the results depend on the seed, never on the thread count.
  std::uint64_t seed = 1;
  int threads = 1;                                                 // 1..64
  IdentificationMethod method = IdentificationMethod::Linearised;  // header comment: Method
};

// The error one tracker reading (averaged over samples_per_point) introduces at a point, eq. 23
// (first-order image of the spherical noise) and eq. 24.
struct TrackerPointUncertainty {
  double range_mm = 0, azimuth_rad = 0, elevation_rad = 0;
  // sigma along the tracker's x, y, z: u_x^2 = (cos e cos a)^2 u_r^2 + (r sin e cos a)^2 u_e^2
  // + (r cos e sin a)^2 u_a^2, and so on (eq. 23 with the polar angle = 90 deg - elevation).
  Eigen::Vector3d u_tracker_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d u_machine_mm = Eigen::Vector3d::Zero();  // the same along the machine axes
  double u_p_mm = 0;  // eq. 24: sqrt(u_r^2 + r^2 u_e^2 + r^2 cos^2 e u_a^2)
};

// Eq. 23-24 at `point_mm` (machine frame) for the tracker as given (its nominal pose; placement
// sigmas ignored). Refuses (std::invalid_argument naming field and value) non-finite input,
// negative sigmas, samples_per_point < 1, and a point within 1e-6 mm of the tracker.
TrackerPointUncertainty tracker_point_uncertainty(const TrackerUncertaintyModel& tracker,
                                                  const Eigen::Vector3d& point_mm);

// Summary of a sample: mean, standard deviation (n - 1), the 95 % quantile (the order statistic
// of rank ceil(0.95 n): the values are magnitudes, so the one-sided bound) and the maximum.
struct SampleSummary {
  double mean = 0, sigma = 0, quantile95 = 0, max = 0;
};

struct PointUncertainty {
  std::string label;
  Eigen::Vector3d commanded_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d tool_offset_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d mean_mm = Eigen::Vector3d::Zero();   // mean residual, machine axes
  Eigen::Vector3d sigma_mm = Eigen::Vector3d::Zero();  // its standard deviation per axis
  double rms_mm = 0;                                   // sqrt(mean |e|^2)
  double bound95_mm = 0;                               // 95 % quantile of |e|
  double tracker_u_mm = 0;  // u_p of eq. 24 at the nominal target (tracker at its nominal pose)
};

struct VerificationUncertainty {
  std::vector<PointUncertainty> points;  // in design order
  // Per trial: the mean and the max of |e| over the grid (the paper's "final mean volumetric
  // error" and "maximum final error"), and their distributions over the trials.
  std::vector<double> trial_mean_mm, trial_max_mm;
  SampleSummary mean_residual_mm, max_residual_mm;
  // The tracker alone (eq. 24 over the grid, nominal pose).
  double tracker_max_u_mm = 0, tracker_mean_u_mm = 0;
  // The identification: scalar observations (3 per point), candidate parameters (frame
  // included) after the identifiability test, and the mean number kept by the BIC.
  int trials = 0;
  int observations = 0;
  int candidate_parameters = 0;
  double mean_kept_parameters = 0;
  std::vector<std::string> unidentifiable;  // functions the design cannot determine
  IdentificationMethod method = IdentificationMethod::Linearised;
};

// N simulated verifications of `design` by `tracker` on the machine of `sources` (header
// comment: what is propagated, the measurand, the method). Pure: same inputs, same results,
// whatever options.threads. Refuses (std::invalid_argument naming field and value): an empty
// design, non-finite design points, duplicate (commanded, tool offset) pairs, an axis with fewer
// than 2 distinct positions, fewer observations than unknowns, a design that cannot fix the
// frame; identification settings out of range; non-finite tracker pose, negative or non-finite
// sigmas, samples_per_point < 1, a point at the tracker; non-finite or negative sources (alpha,
// Delta T may be of either sign); error functions with coefficients over an empty range;
// trials < 1, threads outside 1..64, trials x points above 5e7.
VerificationUncertainty evaluate_verification_uncertainty(const VerificationDesign& design,
                                                          const TrackerUncertaintyModel& tracker,
                                                          const UncertaintySources& sources,
                                                          const MonteCarloOptions& options = {});

// Where the tracker may stand (ncqual/common/global_check.hpp): a grid of candidate positions over
// the box [lo, hi] (steps per axis; one step = the box's middle on that axis), minus every position
// inside the working envelope (the bounding box of the design's nominal targets, commanded + tool
// offset) grown by envelope_clearance_mm, minus every position that sees a design point closer
// than min_range_mm or farther than max_range_mm (the tracker's range, paper: 0.5 m to 15 m).
using TrackerRegion = ncqual::TrackerRegion;

struct LocationSearchOptions {
  int report = 10;  // candidates reported, best first (>= 1; more than tried: all of them)
};

struct TrackerCandidate {
  Eigen::Vector3d position_mm = Eigen::Vector3d::Zero();
  double yaw_rad = 0;
  double max_u_mm = 0;  // the largest u_p over the design (eq. 24)
  double mean_u_mm = 0;
  int worst_point = 0;  // design index of that largest u_p
};

struct TrackerLocationSearch {
  TrackerUncertaintyModel best;              // the tracker at the best candidate, facing the centre
  double max_u_mm = 0, mean_u_mm = 0;        // of the best candidate
  double given_max_u_mm = 0;                 // of the tracker as given, for comparison
  std::vector<TrackerCandidate> candidates;  // best first (max_u, then mean_u, then grid order)
  int tried = 0;                             // candidates evaluated
  int excluded = 0;                          // grid positions excluded (envelope, range)
};

// The candidate of `region` that minimises the largest u_p over the design (eq. 23-24; no Monte
// Carlo). Each candidate faces the envelope's centre: yaw = atan2 of the horizontal direction to
// it; pitch and roll are those of `tracker` (its levelling), as are the sigmas. Refuses
// (std::invalid_argument naming field and value): an empty or non-finite design, a bad tracker
// (as tracker_point_uncertainty), a non-finite box or lo > hi, steps < 1 or more than 1e6
// candidates, negative clearance, min_range_mm < 0, max_range_mm <= min_range_mm, report < 1,
// and a region whose every candidate is excluded (counts named).
TrackerLocationSearch best_tracker_location(const VerificationDesign& design,
                                            const TrackerUncertaintyModel& tracker,
                                            const TrackerRegion& region,
                                            const LocationSearchOptions& options = {});

}  // namespace ncqual::solver

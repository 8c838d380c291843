// SPDX-License-Identifier: Apache-2.0
// Monte Carlo uncertainty of the volumetric verification (Aguado et al.; eq. 23-24 and the
// tracker location search: verification_tracker.cpp). See the header for what is propagated and
// how.
#include "ncqual/solver/verification_uncertainty.hpp"

#include "result_building.hpp"
#include "verification_tracker.hpp"
#include "volumetric_model.hpp"

#include "ncqual/common/kinematics.hpp"
#include "ncqual/solver/volumetric_identification.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <numeric>
#include <random>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace ncqual::solver {

namespace {

using detail::check_tracker;
using detail::check_tracker_sees;
using detail::Kind;
using detail::need_finite;
using detail::need_sigma;
using detail::noise_scale;
using detail::NoiseScale;
using detail::Param;
using detail::point_field;
using detail::point_uncertainty;
using detail::refuse;
using detail::skew;
using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using volumetric::kFunctionCount;

constexpr int kMaxDegree = detail::kMaxOrder;  // as IdentificationOptions accepts
constexpr int kMaxThreads = 64;
constexpr double kMaxSamples = 5e7;  // trials x points stored for the quantiles
constexpr int kBlockTrials = 50;     // trials per accumulation block (thread-independent)

// ----------------------------------------------------------------------------------------------
// Validation

void check_design(const VerificationDesign& d) {
  if (d.points.empty()) {
    throw std::invalid_argument("VerificationDesign.points: empty; a grid of points is needed");
  }
  for (std::size_t i = 0; i < d.points.size(); ++i) {
    need_finite(point_field(i, d.points[i], "commanded_mm"), d.points[i].commanded_mm);
    need_finite(point_field(i, d.points[i], "tool_offset_mm"), d.points[i].tool_offset_mm);
  }
  if (!(std::isfinite(d.identification_sigma_mm) && d.identification_sigma_mm > 0)) {
    refuse("VerificationDesign.identification_sigma_mm",
           detail::quote_number(d.identification_sigma_mm), "expected a finite value > 0");
  }
  if (d.max_degree < 1 || d.max_degree > kMaxDegree) {
    refuse("VerificationDesign.max_degree", std::to_string(d.max_degree),
           "expected 1.." + std::to_string(kMaxDegree));
  }
  if (!(d.rank_tolerance > 0 && d.rank_tolerance < 1)) {
    refuse("VerificationDesign.rank_tolerance", detail::quote_number(d.rank_tolerance),
           "expected 0 < tolerance < 1");
  }
}
void check_sources(const UncertaintySources& s, const VerificationDesign& d) {
  need_sigma("UncertaintySources.repeatability_sigma_mm", s.repeatability_sigma_mm);
  need_finite("UncertaintySources.expansion_per_K", s.expansion_per_K);
  need_sigma("UncertaintySources.expansion_sigma_per_K", s.expansion_sigma_per_K);
  need_finite("UncertaintySources.temperature_deviation_K", s.temperature_deviation_K);
  need_sigma("UncertaintySources.temperature_sigma_K", s.temperature_sigma_K);
  for (int f = 0; f < kFunctionCount; ++f) {
    const auto& fn = s.errors.functions[static_cast<std::size_t>(f)];
    for (std::size_t k = 0; k < fn.coefficients.size(); ++k) {
      if (!std::isfinite(fn.coefficients[k])) {
        refuse("UncertaintySources.errors." + std::string(volumetric::function_name(f)) +
                   ".coefficients[" + std::to_string(k) + "]",
               detail::quote_number(fn.coefficients[k]), "not finite");
      }
    }
  }
  need_finite("UncertaintySources.errors.ec0xy_rad", s.errors.ec0xy_rad);
  need_finite("UncertaintySources.errors.eb0xz_rad", s.errors.eb0xz_rad);
  need_finite("UncertaintySources.errors.ea0yz_rad", s.errors.ea0yz_rad);
  // Evaluates every function once: refuses coefficients over an empty range (names lo, hi).
  try {
    (void)volumetric::actual_position(s.errors, d.points.front().commanded_mm,
                                      d.points.front().tool_offset_mm);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("UncertaintySources.errors: ") + e.what());
  }
}

void check_options(const MonteCarloOptions& o, std::size_t points) {
  if (o.trials < 1) refuse("MonteCarloOptions.trials", std::to_string(o.trials), "expected >= 1");
  if (o.threads < 1 || o.threads > kMaxThreads) {
    refuse("MonteCarloOptions.threads", std::to_string(o.threads),
           "expected 1.." + std::to_string(kMaxThreads));
  }
  if (static_cast<double>(o.trials) * static_cast<double>(points) > kMaxSamples) {
    refuse("MonteCarloOptions.trials", std::to_string(o.trials),
           "times the " + std::to_string(points) + " design points exceeds " +
               detail::quote_number(kMaxSamples) + " stored residuals");
  }
}

// ----------------------------------------------------------------------------------------------
// The identification, linearised at zero errors about the nominal frame (the machine frame: each
// trial's readings are first brought onto the nominal targets by a rigid fit). Same candidate
// terms, order and identifiability test as identify_rigid_body_errors (volumetric_model.hpp).

struct LinearIdentification {
  int observations = 0;  // 3 n
  int candidates = 0;    // candidate parameters before the identifiability test
  MatrixXd J;            // 3n x na, accepted columns (machine frame)
  MatrixXd H_inverse;    // (J'J)^-1
  MatrixXd covariance;   // sigma^2 (J'J)^-1, the BIC's
  double penalty = 0;    // ln(observations)
  // Per function: accepted column indices by increasing order (BIC candidates for dropping).
  std::array<std::vector<int>, kFunctionCount> stacks;
  std::vector<std::string> unidentifiable;
};

// Refusals shared with the full identification: duplicates, too few positions per axis, too few
// observations, a frame the design cannot fix.
LinearIdentification linearise(const VerificationDesign& design,
                               const std::vector<Vector3d>& commanded) {
  const std::size_t n = design.points.size();
  std::vector<Vector3d> tool_offset;
  for (const DesignPoint& point : design.points) tool_offset.push_back(point.tool_offset_mm);
  if (const auto duplicate = detail::first_duplicate(commanded, tool_offset)) {
    const auto [a, b] = *duplicate;
    refuse(point_field(b, design.points[b], "(commanded_mm, tool_offset_mm)"),
           "(" + detail::quote_vector(design.points[b].commanded_mm) + ", " +
               detail::quote_vector(design.points[b].tool_offset_mm) + ")",
           "duplicates points[" + std::to_string(a) + "] ('" + design.points[a].label + "')");
  }
  const detail::AxisGauge gauge =
      detail::axis_gauge(commanded, design.max_degree, std::nullopt, [](char axis, int distinct) {
        return "VerificationDesign.points: commanded " + std::string(1, axis) + " = " +
               std::to_string(distinct) + " distinct position(s): at least " +
               std::to_string(detail::kMinimumAxisPositions) + " are needed per axis";
      });
  const std::vector<Param> params =
      detail::candidate_parameters(gauge.cap, detail::CandidateSet::TrackerPoints);
  const int p = static_cast<int>(params.size());
  const int m = 3 * static_cast<int>(n);
  detail::refuse_too_few("VerificationDesign.points: " + std::to_string(n) + " points", m, p,
                         design.max_degree);
  // Jacobian at zero errors: p = c + t, every rotation the identity.
  MatrixXd J = MatrixXd::Zero(m, p);
  for (std::size_t i = 0; i < n; ++i) {
    const Vector3d& c = commanded[i];
    const Vector3d& t = design.points[i].tool_offset_mm;
    const Vector3d pos = c + t;
    std::array<std::array<double, kMaxDegree + 1>, 3> leg{};
    for (int a = 0; a < 3; ++a) {
      const auto ua = static_cast<std::size_t>(a);
      const double u = volumetric::normalized_coordinate(c[a], gauge.lo[ua], gauge.hi[ua]);
      for (int k = 0; k <= gauge.cap[ua]; ++k)
        leg[ua][static_cast<std::size_t>(k)] = volumetric::legendre(k, u);
    }
    // Effect of a small rotation of each axis' carriage: -[w]x with w the vector it carries.
    const std::array<Matrix3d, 3> d_ang = {-skew(Vector3d(0, c.y(), c.z()) + t),
                                           -skew(Vector3d(0, 0, c.z()) + t), -skew(t)};
    const Matrix3d frame_rotation = -skew(pos);
    const auto row = static_cast<Eigen::Index>(3 * i);
    for (int j = 0; j < p; ++j) {
      const Param& q = params[static_cast<std::size_t>(j)];
      Vector3d col = Vector3d::Zero();
      switch (q.kind) {
        case Kind::FrameTranslation: col = Vector3d::Unit(q.index); break;
        case Kind::FrameRotation: col = frame_rotation.col(q.index); break;
        case Kind::Squareness:
          col = q.index == 0   ? Vector3d(-c.y(), 0, 0)
                : q.index == 1 ? Vector3d(c.z(), 0, 0)
                               : Vector3d(0, -c.z(), 0);
          break;
        case Kind::Coefficient: {
          const int axis = q.index / 6, comp = q.index % 6;
          const double P = leg[static_cast<std::size_t>(axis)][static_cast<std::size_t>(q.order)];
          col = comp < 3 ? Vector3d(Vector3d::Unit(comp) * P)
                         : Vector3d(d_ang[static_cast<std::size_t>(axis)].col(comp - 3) * P);
          break;
        }
      }
      J.block<3, 1>(row, j) = col;
    }
  }
  // Identifiability.
  const MatrixXd H = J.transpose() * J;
  const detail::Identifiability identifiable =
      detail::identifiable_columns(H, design.rank_tolerance);
  const std::vector<int>& accepted = identifiable.accepted;
  detail::refuse_undetermined_frame(params, identifiable.rejected,
                                    "VerificationDesign.points: the design");
  LinearIdentification out;
  out.unidentifiable = detail::rejected_terms(params, identifiable.rejected).unidentifiable;
  out.stacks = detail::order_stacks(params, accepted);
  const int na = static_cast<int>(accepted.size());
  out.observations = m;
  out.candidates = p;
  out.J.resize(m, na);
  VectorXd s(na);
  for (int a = 0; a < na; ++a) {
    const int j = accepted[static_cast<std::size_t>(a)];
    out.J.col(a) = J.col(j);
    s(a) = identifiable.scale(j);
  }
  // (J'J)^-1 through the column-normalised matrix (well conditioned once identifiable).
  MatrixXd Hn(na, na);
  for (int a = 0; a < na; ++a) {
    for (int b = 0; b < na; ++b) {
      Hn(a, b) = H(accepted[static_cast<std::size_t>(a)], accepted[static_cast<std::size_t>(b)]) *
                 s(a) * s(b);
    }
  }
  const MatrixXd Hn_inv = Hn.ldlt().solve(MatrixXd::Identity(na, na));
  out.H_inverse = s.asDiagonal() * Hn_inv * s.asDiagonal();
  out.covariance =
      out.H_inverse * (design.identification_sigma_mm * design.identification_sigma_mm);
  out.penalty = std::log(static_cast<double>(m));
  return out;
}

// ----------------------------------------------------------------------------------------------
// One trial: the draws and the simulated readings.

struct Fixed {
  const VerificationDesign* design = nullptr;
  const TrackerUncertaintyModel* tracker = nullptr;
  const UncertaintySources* sources = nullptr;
  std::vector<Vector3d> commanded;  // q (design)
  std::vector<Vector3d> analysed;   // q (1 + alpha Delta T): what the analysis identifies with
  std::vector<Vector3d> nominal;    // analysed + tool offset: the nominal targets (machine frame)
  std::vector<Matrix3d> chain_jacobian;       // d actual_position / d axis positions at analysed
  Vector3d nominal_scale = Vector3d::Ones();  // 1 + alpha Delta T as the analysis corrects
  Vector3d range_middle = Vector3d::Zero();   // middle of each axis' commanded range
  Matrix3d tracker_rotation = Matrix3d::Identity();
  NoiseScale noise{};
};

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// Fills `truth` (where the targets are, noise- and repeatability-free, tracker frame) and
// `measured` (the readings, tracker frame), 3 per point; returns the true thermal scale
// 1 + alpha Delta T per axis.
Vector3d simulate_trial(const Fixed& f, std::uint64_t seed, int trial, VectorXd& truth,
                        VectorXd& measured) {
  std::mt19937_64 rng(
      splitmix64(seed ^ splitmix64(static_cast<std::uint64_t>(trial) + 0x5851f42d4c957f2dULL)));
  std::normal_distribution<double> normal(0.0, 1.0);
  const UncertaintySources& s = *f.sources;
  const TrackerUncertaintyModel& t = *f.tracker;
  // Thermal state of this verification.
  Vector3d scale;
  for (int k = 0; k < 3; ++k) {
    const double alpha = s.expansion_per_K[k] + s.expansion_sigma_per_K[k] * normal(rng);
    const double dT = s.temperature_deviation_K[k] + s.temperature_sigma_K[k] * normal(rng);
    scale[k] = 1.0 + alpha * dT;
  }
  // Where the tracker really stands.
  Vector3d position = t.position_mm;
  Vector3d w;
  for (int k = 0; k < 3; ++k) position[k] += t.position_sigma_mm * normal(rng);
  for (int k = 0; k < 3; ++k) w[k] = t.orientation_sigma_rad * normal(rng);
  const Matrix3d machine_from_tracker = volumetric::rotation_from_vector(w) * f.tracker_rotation;
  const Matrix3d tracker_from_machine = machine_from_tracker.transpose();
  const std::size_t n = f.commanded.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vector3d& q = f.commanded[i];
    const Vector3d& tool = f.design->points[i].tool_offset_mm;
    Vector3d repeat;
    for (int k = 0; k < 3; ++k) repeat[k] = s.repeatability_sigma_mm[k] * normal(rng);
    // The exact chain where the axes truly are; the repeatability displacement (micrometres)
    // through the chain's Jacobian (its curvature leaves far below 1e-9 mm).
    const Vector3d actual = volumetric::actual_position(s.errors, q.cwiseProduct(scale), tool);
    const Vector3d systematic = tracker_from_machine * (actual - position);
    const Vector3d landed = tracker_from_machine *
                            (actual + f.chain_jacobian[i] * repeat.cwiseProduct(scale) - position);
    Vector3d sph = tracker_spherical(landed);
    const double r0 = sph[0];
    sph[0] += (f.noise.range0 + f.noise.range1_per_mm * r0) * normal(rng);
    sph[1] += f.noise.angle * normal(rng);
    sph[2] += f.noise.angle * normal(rng);
    const auto row = static_cast<Eigen::Index>(3 * i);
    truth.segment<3>(row) = systematic;
    measured.segment<3>(row) = tracker_cartesian(sph);
  }
  return scale;
}

struct Workspace {
  VectorXd truth, measured, e, aligned_truth, correction, g, b, col;
  MatrixXd C;
  std::array<int, kFunctionCount> remaining{};
};

// Linearised identification of one trial: residual (machine axes) per point into `residual`;
// returns the number of parameters kept.
int linear_trial(const Fixed& f, const LinearIdentification& lin, Workspace& w,
                 VectorXd& residual) {
  const std::size_t n = f.nominal.size();
  // Rigid best fit (unweighted): nominal ~ A measured.
  const Eigen::Isometry3d A = detail::rigid_fit(
      Eigen::Map<const Eigen::Matrix3Xd>(w.measured.data(), 3, static_cast<Eigen::Index>(n)),
      detail::as_columns(f.nominal));
  for (std::size_t i = 0; i < n; ++i) {
    const auto row = static_cast<Eigen::Index>(3 * i);
    w.e.segment<3>(row) = A * Vector3d(w.measured.segment<3>(row)) - f.nominal[i];
    w.aligned_truth.segment<3>(row) = A * Vector3d(w.truth.segment<3>(row));
  }
  // Full linear solution, then the BIC's backward elimination (as the identification does it).
  w.g.noalias() = lin.J.transpose() * w.e;
  w.b.noalias() = lin.H_inverse * w.g;
  w.C = lin.covariance;
  const int na = static_cast<int>(w.b.size());
  w.col.resize(na);
  int kept = na;
  for (int fn = 0; fn < kFunctionCount; ++fn) {
    w.remaining[static_cast<std::size_t>(fn)] =
        static_cast<int>(lin.stacks[static_cast<std::size_t>(fn)].size());
  }
  for (;;) {
    int best = -1;
    double best_rise = lin.penalty;
    for (int fn = 0; fn < kFunctionCount; ++fn) {
      const int left = w.remaining[static_cast<std::size_t>(fn)];
      if (left == 0) continue;
      const int j = lin.stacks[static_cast<std::size_t>(fn)][static_cast<std::size_t>(left - 1)];
      const double rise = w.b(j) * w.b(j) / w.C(j, j);
      if (rise < best_rise) {
        best_rise = rise;
        best = fn;
      }
    }
    if (best < 0) break;
    const int j =
        lin.stacks[static_cast<std::size_t>(best)]
                  [static_cast<std::size_t>(--w.remaining[static_cast<std::size_t>(best)])];
    // Only the lower triangle of C is kept up to date.
    w.col.head(j) = w.C.row(j).head(j).transpose();
    w.col.tail(na - j) = w.C.col(j).tail(na - j);
    const double cjj = w.col(j);
    w.b -= w.col * (w.b(j) / cjj);
    w.C.selfadjointView<Eigen::Lower>().rankUpdate(w.col, -1.0 / cjj);
    w.b(j) = 0;
    w.C.row(j).head(j).setZero();
    w.C.col(j).tail(na - j).setZero();
    --kept;
  }
  w.correction.noalias() = lin.J * w.b;
  for (std::size_t i = 0; i < n; ++i) {
    const auto row = static_cast<Eigen::Index>(3 * i);
    residual.segment<3>(row) =
        w.aligned_truth.segment<3>(row) - (f.nominal[i] + w.correction.segment<3>(row));
  }
  return kept;
}

// The full identification of one trial.
int full_trial(const Fixed& f, Workspace& w, VectorXd& residual) {
  const VerificationDesign& d = *f.design;
  const std::size_t n = d.points.size();
  std::vector<VolumetricPoint> points(n);
  for (std::size_t i = 0; i < n; ++i) {
    points[i].label = d.points[i].label;
    points[i].commanded_mm = f.analysed[i];
    points[i].tool_offset_mm = d.points[i].tool_offset_mm;
    points[i].measured_mm = w.measured.segment<3>(static_cast<Eigen::Index>(3 * i));
    points[i].sigma_mm = d.identification_sigma_mm;
  }
  IdentificationOptions options;
  options.max_degree = d.max_degree;
  options.rank_tolerance = d.rank_tolerance;
  const IdentifiedErrors id = identify_rigid_body_errors(points, options);
  const Matrix3d to_machine_axes = id.instrument_from_machine.linear().transpose();
  for (std::size_t i = 0; i < n; ++i) {
    const auto row = static_cast<Eigen::Index>(3 * i);
    // predicted = measured - after; residual = truth - predicted (instrument frame).
    const Vector3d predicted = points[i].measured_mm - id.point_residuals[i].after_mm;
    residual.segment<3>(row) = to_machine_axes * (Vector3d(w.truth.segment<3>(row)) - predicted);
  }
  return static_cast<int>(id.parameters.size());
}

// Per-block accumulators (Welford per point and axis), merged in block order.
struct Block {
  int count = 0;
  VectorXd mean, m2;  // 3n
  VectorXd sum_sq;    // n: sum of |e|^2
  double kept = 0;
};

SampleSummary summarise(std::vector<double> v) {
  SampleSummary s;
  const double n = static_cast<double>(v.size());
  s.mean = std::accumulate(v.begin(), v.end(), 0.0) / n;
  double ss = 0;
  for (double x : v) ss += (x - s.mean) * (x - s.mean);
  s.sigma = v.size() > 1 ? std::sqrt(ss / (n - 1)) : 0.0;
  s.max = *std::max_element(v.begin(), v.end());
  const std::size_t k = static_cast<std::size_t>(std::ceil(0.95 * n)) - 1;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  s.quantile95 = v[k];
  return s;
}

}  // namespace

// ------------------------------------------------------------------------------------------------

VerificationDesign grid_verification_design(const GlobalCheckConfig& config) {
  VerificationDesign d;
  for (const TrackerMove& move : global_check_program(CheckKind::GlobalGrid, config)) {
    if (move.label.rfind("grid:", 0) != 0) continue;
    if (move.target < 0 || move.target >= static_cast<int>(config.targets.size())) {
      refuse("GlobalCheckConfig.targets: move '" + move.label + "' target",
             std::to_string(move.target),
             "not one of the " + std::to_string(config.targets.size()) + " targets");
    }
    AxisPosition at = move.commanded;
    at.w_mm = 0;
    at.a_rad = 0;
    at.c_rad = 0;
    const Vector3d pivot(at.x_mm, at.y_mm, at.z_mm);
    DesignPoint p;
    p.label = move.label;
    p.commanded_mm = pivot;
    p.tool_offset_mm =
        stylus_ball_centre(at, config.targets[static_cast<std::size_t>(move.target)]) - pivot;
    d.points.push_back(std::move(p));
  }
  if (d.points.empty()) {
    throw std::invalid_argument(
        "GlobalCheckConfig: the GlobalGrid program has no grid point "
        "(grid_x_mm, grid_y_mm, grid_z_mm or targets empty)");
  }
  return d;
}

double expansion_uncertainty_per_K(double alpha_per_K) {
  need_finite("alpha_per_K", alpha_per_K);
  const double width = std::max(0.1 * std::abs(alpha_per_K), 2e-6);
  return width / (2.0 * std::sqrt(3.0));
}

VerificationUncertainty evaluate_verification_uncertainty(const VerificationDesign& design,
                                                          const TrackerUncertaintyModel& tracker,
                                                          const UncertaintySources& sources,
                                                          const MonteCarloOptions& options) {
  check_design(design);
  check_tracker(tracker);
  check_tracker_sees(design, tracker);
  check_sources(sources, design);
  check_options(options, design.points.size());

  const std::size_t n = design.points.size();
  Fixed f;
  f.design = &design;
  f.tracker = &tracker;
  f.sources = &sources;
  f.tracker_rotation = tracker.rotation();
  f.noise = noise_scale(tracker);
  f.nominal_scale =
      Vector3d::Ones() + sources.expansion_per_K.cwiseProduct(sources.temperature_deviation_K);
  Vector3d lo = design.points.front().commanded_mm, hi = lo;
  for (const DesignPoint& p : design.points) {
    lo = lo.cwiseMin(p.commanded_mm);
    hi = hi.cwiseMax(p.commanded_mm);
  }
  f.range_middle = (lo + hi) / 2;
  for (const DesignPoint& p : design.points) {
    f.commanded.push_back(p.commanded_mm);
    f.analysed.push_back(p.commanded_mm.cwiseProduct(f.nominal_scale));
    f.nominal.push_back(f.analysed.back() + p.tool_offset_mm);
    Matrix3d D;
    for (int k = 0; k < 3; ++k) {
      constexpr double h = 1.0;  // mm; central differences of a polynomial chain
      const Vector3d dq = Vector3d::Unit(k) * h;
      D.col(k) =
          (volumetric::actual_position(sources.errors, f.analysed.back() + dq, p.tool_offset_mm) -
           volumetric::actual_position(sources.errors, f.analysed.back() - dq, p.tool_offset_mm)) /
          (2 * h);
    }
    f.chain_jacobian.push_back(D);
  }
  // The linear identification also validates the design as the full one would.
  const LinearIdentification lin = linearise(design, f.analysed);

  const int trials = options.trials;
  const int blocks = (trials + kBlockTrials - 1) / kBlockTrials;
  std::vector<Block> block(static_cast<std::size_t>(blocks));
  std::vector<double> trial_mean(static_cast<std::size_t>(trials)),
      trial_max(static_cast<std::size_t>(trials));
  std::vector<double> magnitude(n * static_cast<std::size_t>(trials));  // point-major
  std::atomic<int> next{0};
  const int threads = std::min(options.threads, blocks);
  std::vector<std::exception_ptr> failure(static_cast<std::size_t>(threads));

  const auto worker = [&](int id) {
    try {
      Workspace w;
      const auto m = static_cast<Eigen::Index>(3 * n);
      w.truth.resize(m);
      w.measured.resize(m);
      w.e.resize(m);
      w.aligned_truth.resize(m);
      w.correction.resize(m);
      VectorXd residual(m);
      for (int bi; (bi = next.fetch_add(1)) < blocks;) {
        Block& B = block[static_cast<std::size_t>(bi)];
        B.mean = VectorXd::Zero(m);
        B.m2 = VectorXd::Zero(m);
        B.sum_sq = VectorXd::Zero(static_cast<Eigen::Index>(n));
        const int first = bi * kBlockTrials, last = std::min(trials, first + kBlockTrials);
        for (int k = first; k < last; ++k) {
          const Vector3d scale = simulate_trial(f, options.seed, k, w.truth, w.measured);
          const int kept = options.method == IdentificationMethod::Full
                               ? full_trial(f, w, residual)
                               : linear_trial(f, lin, w, residual);
          // From the verification's thermal state to 20 C: the model carries the thermal
          // correction's error as a scale about the middle of each axis' range.
          const Vector3d mis_scale = scale - f.nominal_scale;
          for (std::size_t i = 0; i < n; ++i) {
            residual.segment<3>(static_cast<Eigen::Index>(3 * i)) -=
                f.chain_jacobian[i] * (f.commanded[i] - f.range_middle).cwiseProduct(mis_scale);
          }
          B.kept += kept;
          ++B.count;
          const double inv = 1.0 / B.count;
          const VectorXd delta = residual - B.mean;
          B.mean += delta * inv;
          B.m2 += delta.cwiseProduct(residual - B.mean);
          double sum = 0, mx = 0;
          for (std::size_t i = 0; i < n; ++i) {
            const double sq = residual.segment<3>(static_cast<Eigen::Index>(3 * i)).squaredNorm();
            const double mag = std::sqrt(sq);
            B.sum_sq(static_cast<Eigen::Index>(i)) += sq;
            magnitude[i * static_cast<std::size_t>(trials) + static_cast<std::size_t>(k)] = mag;
            sum += mag;
            mx = std::max(mx, mag);
          }
          trial_mean[static_cast<std::size_t>(k)] = sum / static_cast<double>(n);
          trial_max[static_cast<std::size_t>(k)] = mx;
        }
      }
    } catch (...) {
      failure[static_cast<std::size_t>(id)] = std::current_exception();
    }
  };
  if (threads == 1) {
    worker(0);
  } else {
    std::vector<std::thread> pool;
    pool.reserve(static_cast<std::size_t>(threads));
    for (int id = 0; id < threads; ++id) pool.emplace_back(worker, id);
    for (auto& th : pool) th.join();
  }
  for (const auto& e : failure) {
    if (e) std::rethrow_exception(e);
  }

  // Merge the blocks in order (Chan et al.): independent of the thread count.
  Block total = block.front();
  for (std::size_t bi = 1; bi < block.size(); ++bi) {
    const Block& B = block[bi];
    const double na = total.count, nb = B.count, nt = na + nb;
    const VectorXd delta = B.mean - total.mean;
    total.m2 += B.m2 + delta.cwiseProduct(delta) * (na * nb / nt);
    total.mean += delta * (nb / nt);
    total.sum_sq += B.sum_sq;
    total.kept += B.kept;
    total.count += B.count;
  }

  VerificationUncertainty out;
  out.method = options.method;
  out.trials = trials;
  out.observations = lin.observations;
  out.candidate_parameters = static_cast<int>(lin.J.cols());
  out.mean_kept_parameters = total.kept / trials;
  out.unidentifiable = lin.unidentifiable;
  std::vector<double> column(static_cast<std::size_t>(trials));
  double u_sum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const DesignPoint& d = design.points[i];
    PointUncertainty p;
    p.label = d.label;
    p.commanded_mm = d.commanded_mm;
    p.tool_offset_mm = d.tool_offset_mm;
    const auto row = static_cast<Eigen::Index>(3 * i);
    p.mean_mm = total.mean.segment<3>(row);
    p.sigma_mm =
        trials > 1 ? Vector3d((total.m2.segment<3>(row) / (trials - 1.0)).cwiseMax(0.0).cwiseSqrt())
                   : Vector3d::Zero();
    p.rms_mm = std::sqrt(total.sum_sq(static_cast<Eigen::Index>(i)) / trials);
    std::copy_n(
        magnitude.begin() + static_cast<std::ptrdiff_t>(i * static_cast<std::size_t>(trials)),
        trials, column.begin());
    const std::size_t k = static_cast<std::size_t>(std::ceil(0.95 * trials)) - 1;
    std::nth_element(column.begin(), column.begin() + static_cast<std::ptrdiff_t>(k), column.end());
    p.bound95_mm = column[k];
    p.tracker_u_mm = point_uncertainty(f.noise, f.tracker_rotation, tracker.position_mm,
                                       d.commanded_mm + d.tool_offset_mm)
                         .u_p_mm;
    out.tracker_max_u_mm = std::max(out.tracker_max_u_mm, p.tracker_u_mm);
    u_sum += p.tracker_u_mm;
    out.points.push_back(std::move(p));
  }
  out.tracker_mean_u_mm = u_sum / static_cast<double>(n);
  out.mean_residual_mm = summarise(trial_mean);
  out.max_residual_mm = summarise(trial_max);
  out.trial_mean_mm = std::move(trial_mean);
  out.trial_max_mm = std::move(trial_max);
  return out;
}

}  // namespace ncqual::solver

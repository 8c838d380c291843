// SPDX-License-Identifier: Apache-2.0
// The identification of the 21 rigid-body errors from tracker points (A) or sequential-diagonal
// readings (B), and predictions with its result. One file on purpose: it is one estimator, whose
// parts (the parameter layout, the chain and its Jacobian, the observations, the common
// pipeline) serve both entries and predict_position alike and are of no use on their own.
#include "ncqual/solver/volumetric_identification.hpp"

#include "result_building.hpp"
#include "volumetric_model.hpp"

#include <ceres/ceres.h>

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>
#include <tuple>

namespace ncqual::solver {

namespace {

using detail::Kind;
using detail::kMaxOrder;
using detail::Param;
using detail::param_name;
using detail::skew;
using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using volumetric::kFunctionCount;
using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using Jacobian3 = Eigen::Matrix<double, 3, Eigen::Dynamic>;

constexpr double kUnitTolerance = 1e-6;  // |direction| = 1 within this

// ----------------------------------------------------------------------------------------------
// Parameter layout (Param, Kind: volumetric_model.hpp)

struct Layout {
  std::vector<Param> params;
  std::array<double, 3> lo{}, hi{};
  // Derived by index():
  std::array<int, 3> top_order{{-1, -1, -1}};
  int rotation = -1, translation = -1;  // first index of the 3 frame rotation / translation params
  std::array<int, 3> squareness{{-1, -1, -1}};
  std::array<std::vector<std::pair<int, int>>, kFunctionCount> terms;  // (param index, order)

  int size() const { return static_cast<int>(params.size()); }
  void index() {
    top_order = {{-1, -1, -1}};
    rotation = translation = -1;
    squareness = {{-1, -1, -1}};
    for (auto& t : terms) t.clear();
    for (int i = 0; i < size(); ++i) {
      const Param& p = params[static_cast<std::size_t>(i)];
      switch (p.kind) {
        case Kind::FrameRotation:
          if (p.index == 0) rotation = i;
          break;
        case Kind::FrameTranslation:
          if (p.index == 0) translation = i;
          break;
        case Kind::Squareness: squareness[static_cast<std::size_t>(p.index)] = i; break;
        case Kind::Coefficient: {
          terms[static_cast<std::size_t>(p.index)].emplace_back(i, p.order);
          int& top = top_order[static_cast<std::size_t>(p.index / 6)];
          top = std::max(top, p.order);
          break;
        }
      }
    }
  }
};

// ----------------------------------------------------------------------------------------------
// Small rotations

// Left Jacobian of the rotation vector: d(R(v) u)/dv = -[R(v) u]x J_l(v).
Matrix3d left_jacobian(const Vector3d& v) {
  const double th2 = v.squaredNorm();
  double a, b;
  if (th2 < 1e-4) {
    a = 0.5 - th2 / 24.0 + th2 * th2 / 720.0;
    b = 1.0 / 6.0 - th2 / 120.0 + th2 * th2 / 5040.0;
  } else {
    const double th = std::sqrt(th2);
    a = (1.0 - std::cos(th)) / th2;
    b = (th - std::sin(th)) / (th2 * th);
  }
  const Matrix3d k = skew(v);
  return Matrix3d::Identity() + a * k + b * k * k;
}

// ----------------------------------------------------------------------------------------------
// The chain of volumetric::actual_position and its Jacobian over the layout's error parameters
// (frame columns left untouched).

struct Model {
  Layout layout;
  Matrix3d r0 = Matrix3d::Identity();  // instrument_from_machine = (r0 exp(rot), t0 + trans)
  Vector3d t0 = Vector3d::Zero();
};

void chain(const Layout& L, const double* th, const Vector3d& c, const Vector3d& t, Vector3d& p,
           Jacobian3* jac) {
  std::array<std::array<double, kMaxOrder + 1>, 3> leg{};
  for (int a = 0; a < 3; ++a) {
    const int top = L.top_order[static_cast<std::size_t>(a)];
    if (top < 0) continue;
    auto& P = leg[static_cast<std::size_t>(a)];
    const double u =
        (2.0 * c[a] - L.lo[static_cast<std::size_t>(a)] - L.hi[static_cast<std::size_t>(a)]) /
        (L.hi[static_cast<std::size_t>(a)] - L.lo[static_cast<std::size_t>(a)]);
    P[0] = 1.0;
    if (top >= 1) P[1] = u;
    for (int n = 1; n < top; ++n) {
      P[static_cast<std::size_t>(n + 1)] = ((2.0 * n + 1.0) * u * P[static_cast<std::size_t>(n)] -
                                            n * P[static_cast<std::size_t>(n - 1)]) /
                                           (n + 1.0);
    }
  }
  std::array<double, kFunctionCount> v{};
  for (int f = 0; f < kFunctionCount; ++f) {
    const auto& P = leg[static_cast<std::size_t>(f / 6)];
    double s = 0;
    for (const auto& [i, k] : L.terms[static_cast<std::size_t>(f)])
      s += th[i] * P[static_cast<std::size_t>(k)];
    v[static_cast<std::size_t>(f)] = s;
  }
  const auto sq = [&](int i) {
    const int j = L.squareness[static_cast<std::size_t>(i)];
    return j >= 0 ? th[j] : 0.0;
  };
  const double x = c.x(), y = c.y(), z = c.z();
  const Vector3d o_x(x + v[0], v[1], v[2]);
  const Vector3d o_y(v[6] - sq(0) * y, y + v[7], v[8]);
  const Vector3d o_z(v[12] + sq(1) * z, v[13] - sq(2) * z, z + v[14]);
  const Vector3d r_x(v[3], v[4], v[5]), r_y(v[9], v[10], v[11]), r_z(v[15], v[16], v[17]);
  const Matrix3d R_x = volumetric::rotation_from_vector(r_x);
  const Matrix3d R_y = volumetric::rotation_from_vector(r_y);
  const Matrix3d R_z = volumetric::rotation_from_vector(r_z);
  const Vector3d w_z = R_z * t;
  const Vector3d s_y = o_z + w_z;
  const Vector3d w_y = R_y * s_y;
  const Vector3d s_x = o_y + w_y;
  const Vector3d w_x = R_x * s_x;
  p = o_x + w_x;
  if (jac == nullptr) return;

  const Matrix3d R_xy = R_x * R_y;
  // Directions of each function's effect on p: translational (d p / d o_K), angular (d p / d r_K).
  std::array<Matrix3d, 3> d_trans = {Matrix3d::Identity(), R_x, R_xy};
  std::array<Matrix3d, 3> d_ang;
  d_ang[0] = -skew(w_x) * left_jacobian(r_x);
  d_ang[1] = R_x * (-skew(w_y) * left_jacobian(r_y));
  d_ang[2] = R_xy * (-skew(w_z) * left_jacobian(r_z));
  for (int f = 0; f < kFunctionCount; ++f) {
    const int axis = f / 6, comp = f % 6;
    const auto& P = leg[static_cast<std::size_t>(axis)];
    const Vector3d dir = comp < 3 ? Vector3d(d_trans[static_cast<std::size_t>(axis)].col(comp))
                                  : Vector3d(d_ang[static_cast<std::size_t>(axis)].col(comp - 3));
    for (const auto& [i, k] : L.terms[static_cast<std::size_t>(f)]) {
      jac->col(i) = dir * P[static_cast<std::size_t>(k)];
    }
  }
  if (L.squareness[0] >= 0) jac->col(L.squareness[0]) = -y * R_x.col(0);
  if (L.squareness[1] >= 0) jac->col(L.squareness[1]) = z * R_xy.col(0);
  if (L.squareness[2] >= 0) jac->col(L.squareness[2]) = -z * R_xy.col(1);
}

Vector3d frame_rotation_increment(const Layout& L, const double* th) {
  return L.rotation >= 0 ? Vector3d(th[L.rotation], th[L.rotation + 1], th[L.rotation + 2])
                         : Vector3d::Zero();
}

// ----------------------------------------------------------------------------------------------
// Observations: blocks of weighted residuals (model - observed) / sigma with row-major Jacobians.

class Observations {
 public:
  virtual ~Observations() = default;
  virtual int count() const = 0;
  virtual int block_size() const = 0;
  virtual void evaluate(const Model& m, int block, const double* th, double* res,
                        double* jac) const = 0;
};

// A: tracker points, measured = R p + T.
class TrackerObservations final : public Observations {
 public:
  explicit TrackerObservations(const std::vector<VolumetricPoint>& points) : points_(points) {}
  int count() const override { return static_cast<int>(points_.size()); }
  int block_size() const override { return 3; }
  void evaluate(const Model& m, int block, const double* th, double* res,
                double* jac) const override {
    const VolumetricPoint& pt = points_[static_cast<std::size_t>(block)];
    const Layout& L = m.layout;
    const int n = L.size();
    Jacobian3 J;
    if (jac != nullptr) J.setZero(3, n);
    Vector3d p;
    chain(L, th, pt.commanded_mm, pt.tool_offset_mm, p, jac != nullptr ? &J : nullptr);
    const Vector3d delta = frame_rotation_increment(L, th);
    const Matrix3d E = volumetric::rotation_from_vector(delta);
    const Matrix3d R = m.r0 * E;
    Vector3d T = m.t0;
    if (L.translation >= 0)
      T += Vector3d(th[L.translation], th[L.translation + 1], th[L.translation + 2]);
    const double w = 1.0 / pt.sigma_mm;
    Eigen::Map<Vector3d> out_res(res);
    out_res = (R * p + T - pt.measured_mm) * w;
    if (jac == nullptr) return;
    Eigen::Map<Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>> out(jac, 3, n);
    out.noalias() = (R * w) * J;
    if (L.rotation >= 0) {
      out.middleCols(L.rotation, 3) = m.r0 * (-skew(E * p) * left_jacobian(delta)) * w;
    }
    if (L.translation >= 0) out.middleCols(L.translation, 3) = Matrix3d::Identity() * w;
  }

 private:
  const std::vector<VolumetricPoint>& points_;
};

// B: one moved reading, model = (R d) . (p(c) - p(c_start)), tool offset 0.
struct MovedReading {
  int diagonal = 0, reading = 0;
  Vector3d commanded, start, direction;
  double displacement = 0, sigma = 0;
};

class DiagonalObservations final : public Observations {
 public:
  explicit DiagonalObservations(const std::vector<MovedReading>& readings) : readings_(readings) {}
  int count() const override { return static_cast<int>(readings_.size()); }
  int block_size() const override { return 1; }
  void evaluate(const Model& m, int block, const double* th, double* res,
                double* jac) const override {
    const MovedReading& rd = readings_[static_cast<std::size_t>(block)];
    const Layout& L = m.layout;
    const int n = L.size();
    Jacobian3 J1, J0;
    if (jac != nullptr) {
      J1.setZero(3, n);
      J0.setZero(3, n);
    }
    Vector3d p1, p0;
    chain(L, th, rd.commanded, Vector3d::Zero(), p1, jac != nullptr ? &J1 : nullptr);
    chain(L, th, rd.start, Vector3d::Zero(), p0, jac != nullptr ? &J0 : nullptr);
    const Vector3d delta = frame_rotation_increment(L, th);
    const Matrix3d E = volumetric::rotation_from_vector(delta);
    const Vector3d beam = m.r0 * E * rd.direction;
    const Vector3d dp = p1 - p0;
    const double w = 1.0 / rd.sigma;
    res[0] = (beam.dot(dp) - rd.displacement) * w;
    if (jac == nullptr) return;
    Eigen::Map<Eigen::Matrix<double, 1, Eigen::Dynamic>> out(jac, 1, n);
    out.noalias() = (beam.transpose() * w) * (J1 - J0);
    if (L.rotation >= 0) {
      out.middleCols(L.rotation, 3) =
          dp.transpose() * (m.r0 * (-skew(E * rd.direction) * left_jacobian(delta))) * w;
    }
  }

 private:
  const std::vector<MovedReading>& readings_;
};

class ObservationCost final : public ceres::CostFunction {
 public:
  ObservationCost(const Observations* obs, const Model* model, int block)
      : obs_(obs), model_(model), block_(block) {
    set_num_residuals(obs->block_size());
    mutable_parameter_block_sizes()->push_back(model->layout.size());
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    double* jac = (jacobians != nullptr) ? jacobians[0] : nullptr;
    obs_->evaluate(*model_, block_, parameters[0], residuals, jac);
    return true;
  }

 private:
  const Observations* obs_;
  const Model* model_;
  int block_;
};

// Weighted residuals and (optionally) the row-major Jacobian of all observations.
void evaluate_all(const Observations& obs, const Model& m, const VectorXd& th, VectorXd& r,
                  RowMatrix* J) {
  const Eigen::Index bs = obs.block_size(), n = m.layout.size(), count = obs.count();
  r.resize(count * bs);
  if (J != nullptr) J->resize(count * bs, n);
  for (int b = 0; b < count; ++b) {
    obs.evaluate(m, b, th.data(), r.data() + b * bs,
                 J != nullptr ? J->data() + b * bs * n : nullptr);
  }
}

MatrixXd normal_matrix(const RowMatrix& J) {
  MatrixXd H = MatrixXd::Zero(J.cols(), J.cols());
  H.selfadjointView<Eigen::Lower>().rankUpdate(J.transpose());
  H.triangularView<Eigen::StrictlyUpper>() = H.transpose();
  return H;
}

// ----------------------------------------------------------------------------------------------
// The common pipeline of A and B.

struct Pipeline {
  const Observations& obs;
  Model candidate;  // candidate layout, frame at the initial guess
  const IdentificationOptions& options;
};

struct Solved {
  Model model;  // final layout, frame re-based to the solution (increments zero)
  VectorXd theta;
  VectorXd residual;  // weighted
  MatrixXd covariance;
  std::vector<std::string> unidentifiable, fixed_terms;
  int iterations = 0;
  double initial_cost = 0, final_cost = 0;
  bool converged = false;
};

Solved run(const Pipeline& in) {
  const Layout& C = in.candidate.layout;
  const int n = C.size();
  const int observations = in.obs.count() * in.obs.block_size();

  // Linearisation at zero errors around the initial frame.
  VectorXd th0 = VectorXd::Zero(n), r0;
  RowMatrix J0;
  evaluate_all(in.obs, in.candidate, th0, r0, &J0);
  const MatrixXd H = normal_matrix(J0);
  const VectorXd g = J0.transpose() * r0;

  // Identifiability, columns in layout (priority) order.
  const detail::Identifiability identifiable =
      detail::identifiable_columns(H, in.options.rank_tolerance);
  const std::vector<int>& accepted = identifiable.accepted;
  detail::refuse_undetermined_frame(C.params, identifiable.rejected,
                                    "volumetric identification: the data");
  detail::RejectedTerms rejected = detail::rejected_terms(C.params, identifiable.rejected);
  Solved out;
  out.unidentifiable = std::move(rejected.unidentifiable);
  out.fixed_terms = std::move(rejected.fixed_terms);

  // Full linear solution over the accepted columns and its covariance.
  const int na = static_cast<int>(accepted.size());
  MatrixXd Ha(na, na);
  VectorXd ga(na);
  for (int a = 0; a < na; ++a) {
    ga(a) = g(accepted[static_cast<std::size_t>(a)]);
    for (int b = 0; b < na; ++b)
      Ha(a, b) = H(accepted[static_cast<std::size_t>(a)], accepted[static_cast<std::size_t>(b)]);
  }
  const Eigen::LDLT<MatrixXd> full(Ha);
  const VectorXd beta = -full.solve(ga);
  const MatrixXd cov_full = full.solve(MatrixXd::Identity(na, na));

  // Orders by BIC, backward elimination: among the highest remaining order of every function,
  // drop the term whose removal raises chi^2 least (b_j^2 / C_jj, exact for the current model),
  // while that rise is below ln(observations); update the solution and covariance exactly
  // (rank-one downdate) after each drop.
  const double penalty = std::log(static_cast<double>(observations));
  std::vector<bool> active(static_cast<std::size_t>(na), true);
  VectorXd b_cur = beta;
  MatrixXd c_cur = cov_full;
  // Accepted indices by increasing order.
  std::array<std::vector<int>, kFunctionCount> stack = detail::order_stacks(C.params, accepted);
  for (;;) {
    int best_f = -1;
    double best_rise = penalty;
    for (int f = 0; f < kFunctionCount; ++f) {
      const auto& st = stack[static_cast<std::size_t>(f)];
      if (st.empty()) continue;
      const int j = st.back();
      const double rise = b_cur(j) * b_cur(j) / c_cur(j, j);
      if (rise < best_rise) {
        best_rise = rise;
        best_f = f;
      }
    }
    if (best_f < 0) break;
    const int j = stack[static_cast<std::size_t>(best_f)].back();
    stack[static_cast<std::size_t>(best_f)].pop_back();
    active[static_cast<std::size_t>(j)] = false;
    const VectorXd cj = c_cur.col(j);
    const double cjj = c_cur(j, j);
    b_cur -= cj * (b_cur(j) / cjj);
    c_cur -= cj * cj.transpose() / cjj;
    b_cur(j) = 0;
    c_cur.row(j).setZero();
    c_cur.col(j).setZero();
  }
  std::vector<bool> keep(static_cast<std::size_t>(n), false);
  for (int a = 0; a < na; ++a)
    keep[static_cast<std::size_t>(accepted[static_cast<std::size_t>(a)])] =
        active[static_cast<std::size_t>(a)];

  // Final layout and its linear start.
  std::vector<int> kept;
  for (int j = 0; j < n; ++j) {
    if (keep[static_cast<std::size_t>(j)]) kept.push_back(j);
  }
  const int nk = static_cast<int>(kept.size());
  Model model = in.candidate;
  model.layout.params.clear();
  for (int j : kept) model.layout.params.push_back(C.params[static_cast<std::size_t>(j)]);
  model.layout.index();
  MatrixXd Hk(nk, nk);
  VectorXd gk(nk);
  for (int a = 0; a < nk; ++a) {
    gk(a) = g(kept[static_cast<std::size_t>(a)]);
    for (int b = 0; b < nk; ++b)
      Hk(a, b) = H(kept[static_cast<std::size_t>(a)], kept[static_cast<std::size_t>(b)]);
  }
  VectorXd theta = -Hk.ldlt().solve(gk);

  // One Ceres solve of the exact model.
  {
    ceres::Problem::Options popt;
    ceres::Problem problem(popt);
    problem.AddParameterBlock(theta.data(), nk);
    for (int b = 0; b < in.obs.count(); ++b) {
      problem.AddResidualBlock(new ObservationCost(&in.obs, &model, b), nullptr, theta.data());
    }
    ceres::Solver::Options sopt;
    sopt.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
    sopt.max_num_iterations = in.options.max_iterations;
    sopt.num_threads = 1;
    sopt.logging_type = ceres::SILENT;
    sopt.minimizer_progress_to_stdout = false;
    // The start is the linear solution: one or two steps remove the (second-order) nonlinearity.
    // 1e-10 relative on chi^2 moves the parameters by < 1e-3 of their sigma.
    sopt.function_tolerance = 1e-10;
    sopt.gradient_tolerance = 1e-12;
    sopt.parameter_tolerance = 1e-10;
    ceres::Solver::Summary summary;
    ceres::Solve(sopt, &problem, &summary);

    out.iterations = summary.num_successful_steps + summary.num_unsuccessful_steps;
    out.initial_cost = summary.initial_cost;
    out.final_cost = summary.final_cost;
    out.converged = summary.termination_type == ceres::CONVERGENCE;
  }

  // Re-base the frame on the solution so the covariance is that of increments there.
  {
    const Layout& F = model.layout;
    const Vector3d delta = frame_rotation_increment(F, theta.data());
    model.r0 = model.r0 * volumetric::rotation_from_vector(delta);
    if (F.rotation >= 0) theta.segment(F.rotation, 3).setZero();
    if (F.translation >= 0) {
      model.t0 += theta.segment(F.translation, 3);
      theta.segment(F.translation, 3).setZero();
    }
  }
  RowMatrix J;
  evaluate_all(in.obs, model, theta, out.residual, &J);
  out.covariance = normal_matrix(J).ldlt().solve(MatrixXd::Identity(nk, nk));
  out.model = model;
  out.theta = theta;
  return out;
}

// ----------------------------------------------------------------------------------------------
// Validation helpers

void check_options(const IdentificationOptions& o) {
  if (o.max_degree < 1 || o.max_degree > kMaxOrder) {
    throw std::invalid_argument(
        "IdentificationOptions.max_degree = " + std::to_string(o.max_degree) + ": expected 1.." +
        std::to_string(kMaxOrder));
  }
  if (!(o.rank_tolerance > 0 && o.rank_tolerance < 1)) {
    std::ostringstream os;
    os << "IdentificationOptions.rank_tolerance = " << o.rank_tolerance
       << ": expected 0 < tolerance < 1";
    throw std::invalid_argument(os.str());
  }
  if (o.max_iterations < 1) {
    throw std::invalid_argument("IdentificationOptions.max_iterations = " +
                                std::to_string(o.max_iterations) + ": expected >= 1");
  }
  if (o.initial_instrument_from_machine) {
    const Eigen::Isometry3d& f = *o.initial_instrument_from_machine;
    const Matrix3d R = f.linear();
    if (!f.matrix().allFinite() || !(R.transpose() * R).isApprox(Matrix3d::Identity(), 1e-9) ||
        R.determinant() < 0) {
      throw std::invalid_argument(
          "IdentificationOptions.initial_instrument_from_machine: not a finite proper rigid "
          "transform");
    }
  }
  if (o.axis_range_mm) {
    for (int a = 0; a < 3; ++a) {
      const auto& r = (*o.axis_range_mm)[static_cast<std::size_t>(a)];
      if (!(std::isfinite(r[0]) && std::isfinite(r[1]) && r[1] > r[0])) {
        std::ostringstream os;
        os << "IdentificationOptions.axis_range_mm["
           << "XYZ"[a] << "] = [" << r[0] << ", " << r[1] << "]: expected finite lo < hi";
        throw std::invalid_argument(os.str());
      }
    }
  }
}

// The axis gauge of the commanded positions, refusing an axis with fewer than 2 distinct positions.
detail::AxisGauge axis_gauge(const std::vector<Vector3d>& commanded, const IdentificationOptions& o,
                             const std::string& field) {
  return detail::axis_gauge(commanded, o.max_degree, o.axis_range_mm, [&](char axis, int distinct) {
    return field + ": commanded " + std::string(1, axis) + " has " + std::to_string(distinct) +
           " distinct position(s); at least " + std::to_string(detail::kMinimumAxisPositions) +
           " are needed per axis";
  });
}

// The candidate layout: the gauge's axis ranges, the candidate parameters in priority order.
void set_candidates(Layout& L, const detail::AxisGauge& gauge, detail::CandidateSet set) {
  L.lo = gauge.lo;
  L.hi = gauge.hi;
  L.params = detail::candidate_parameters(gauge.cap, set);
  L.index();
}

// Fills everything but the residual summaries from a solved pipeline.
IdentifiedErrors fill(const Solved& s, int observations) {
  IdentifiedErrors out;
  const Layout& L = s.model.layout;
  const int n = L.size();
  out.instrument_from_machine = Eigen::Isometry3d::Identity();
  out.instrument_from_machine.linear() = s.model.r0;
  out.instrument_from_machine.translation() = s.model.t0;
  for (int f = 0; f < kFunctionCount; ++f) {
    auto& fn = out.errors.functions[static_cast<std::size_t>(f)];
    fn.lo_mm = L.lo[static_cast<std::size_t>(f / 6)];
    fn.hi_mm = L.hi[static_cast<std::size_t>(f / 6)];
    int top = -1;
    for (const auto& t : L.terms[static_cast<std::size_t>(f)]) top = std::max(top, t.second);
    out.degree[static_cast<std::size_t>(f)] = top;
    fn.coefficients.assign(static_cast<std::size_t>(top + 1), 0.0);
    MatrixXd cov = MatrixXd::Zero(top + 1, top + 1);
    for (const auto& [i, k] : L.terms[static_cast<std::size_t>(f)]) {
      fn.coefficients[static_cast<std::size_t>(k)] = s.theta(i);
      for (const auto& [i2, k2] : L.terms[static_cast<std::size_t>(f)])
        cov(k, k2) = s.covariance(i, i2);
    }
    out.coefficient_covariance[static_cast<std::size_t>(f)] = cov;
  }
  const auto sq = [&](int i, double& value) {
    const int j = L.squareness[static_cast<std::size_t>(i)];
    value = j >= 0 ? s.theta(j) : 0.0;
    out.squareness_sigma_rad(i) = j >= 0 ? std::sqrt(s.covariance(j, j)) : 0.0;
  };
  sq(0, out.errors.ec0xy_rad);
  sq(1, out.errors.eb0xz_rad);
  sq(2, out.errors.ea0yz_rad);
  const Eigen::AngleAxisd aa(s.model.r0);
  const Vector3d rotvec = aa.angle() * aa.axis();
  for (int i = 0; i < n; ++i) {
    const Param& p = L.params[static_cast<std::size_t>(i)];
    IdentifiedParameter ip;
    ip.name = param_name(p);
    ip.sigma = std::sqrt(s.covariance(i, i));
    switch (p.kind) {
      case Kind::FrameRotation:
        ip.frame = p.index;
        ip.value = rotvec(p.index);
        out.frame_sigma(p.index) = ip.sigma;
        break;
      case Kind::FrameTranslation:
        ip.frame = 3 + p.index;
        ip.value = s.model.t0(p.index);
        out.frame_sigma(3 + p.index) = ip.sigma;
        break;
      case Kind::Squareness:
        ip.squareness = p.index;
        ip.value = s.theta(i);
        break;
      case Kind::Coefficient:
        ip.function = p.index;
        ip.order = p.order;
        ip.value = s.theta(i);
        break;
    }
    out.parameters.push_back(ip);
  }
  out.covariance = s.covariance;
  out.unidentifiable = s.unidentifiable;
  out.fixed_terms = s.fixed_terms;
  out.observations = observations;
  out.degrees_of_freedom = observations - n;
  out.chi_square = s.residual.squaredNorm();
  out.iterations = s.iterations;
  out.initial_cost = s.initial_cost;
  out.final_cost = s.final_cost;
  out.converged = s.converged;
  return out;
}

}  // namespace

// ------------------------------------------------------------------------------------------------

double IdentifiedErrors::sigma_at(int index, double q_mm) const {
  if (index < 0 || index >= volumetric::kNameCount) {
    throw std::invalid_argument("IdentifiedErrors::sigma_at: index = " + std::to_string(index) +
                                ": expected 0..20");
  }
  if (index >= kFunctionCount) return squareness_sigma_rad(index - kFunctionCount);
  const auto& fn = errors.functions[static_cast<std::size_t>(index)];
  const MatrixXd& cov = coefficient_covariance[static_cast<std::size_t>(index)];
  if (fn.coefficients.empty() || cov.rows() == 0) return 0.0;
  const double u = volumetric::normalized_coordinate(q_mm, fn.lo_mm, fn.hi_mm);
  VectorXd p(cov.rows());
  for (int k = 0; k < cov.rows(); ++k) p(k) = volumetric::legendre(k, u);
  return std::sqrt(std::max(0.0, p.dot(cov * p)));
}

IdentifiedErrors identify_rigid_body_errors(const std::vector<VolumetricPoint>& points,
                                            const IdentificationOptions& options) {
  check_options(options);
  if (points.empty())
    throw std::invalid_argument("points: empty; a grid of tracker points is needed");
  for (std::size_t i = 0; i < points.size(); ++i) {
    const VolumetricPoint& p = points[i];
    const std::string where = "points[" + std::to_string(i) + "] ('" + p.label + "')";
    if (!p.commanded_mm.allFinite())
      throw std::invalid_argument(
          where + ".commanded_mm = " + detail::format_vector(p.commanded_mm) + ": not finite");
    if (!p.tool_offset_mm.allFinite())
      throw std::invalid_argument(
          where + ".tool_offset_mm = " + detail::format_vector(p.tool_offset_mm) + ": not finite");
    if (!p.measured_mm.allFinite())
      throw std::invalid_argument(where + ".measured_mm = " + detail::format_vector(p.measured_mm) +
                                  ": not finite");
    if (!(std::isfinite(p.sigma_mm) && p.sigma_mm > 0)) {
      std::ostringstream os;
      os << where << ".sigma_mm = " << p.sigma_mm << ": expected a finite value > 0";
      throw std::invalid_argument(os.str());
    }
  }
  std::vector<Vector3d> commanded, tool_offset, nominal, measured;
  std::vector<double> weight;
  for (const auto& p : points) {
    commanded.push_back(p.commanded_mm);
    tool_offset.push_back(p.tool_offset_mm);
    nominal.push_back(p.commanded_mm + p.tool_offset_mm);
    measured.push_back(p.measured_mm);
    weight.push_back(1.0 / (p.sigma_mm * p.sigma_mm));
  }
  if (const auto duplicate = detail::first_duplicate(commanded, tool_offset)) {
    const auto [i1, i2] = *duplicate;
    throw std::invalid_argument("points[" + std::to_string(i2) + "] ('" + points[i2].label +
                                "'): duplicate (commanded_mm, tool_offset_mm) = (" +
                                detail::format_vector(points[i2].commanded_mm) + ", " +
                                detail::format_vector(points[i2].tool_offset_mm) + ") of points[" +
                                std::to_string(i1) + "] ('" + points[i1].label + "')");
  }

  Model candidate;
  set_candidates(candidate.layout, axis_gauge(commanded, options, "points"),
                 detail::CandidateSet::TrackerPoints);
  const int observations = 3 * static_cast<int>(points.size());
  detail::refuse_too_few("points: " + std::to_string(points.size()) + " points", observations,
                         candidate.layout.size(), options.max_degree);

  const Eigen::Isometry3d rigid =
      detail::rigid_fit(detail::as_columns(nominal), detail::as_columns(measured), &weight);
  const Eigen::Isometry3d start = options.initial_instrument_from_machine.value_or(rigid);
  candidate.r0 = start.linear();
  candidate.t0 = start.translation();

  const TrackerObservations obs(points);
  const Solved s = run(Pipeline{obs, candidate, options});
  IdentifiedErrors out = fill(s, observations);

  double sb = 0, sa = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    PointResidual r;
    r.label = points[i].label;
    r.before_mm = measured[i] - rigid * nominal[i];
    r.after_mm = -s.residual.segment<3>(static_cast<Eigen::Index>(3 * i)) * points[i].sigma_mm;
    sb += r.before_mm.squaredNorm();
    sa += r.after_mm.squaredNorm();
    out.max_before_mm = std::max(out.max_before_mm, r.before_mm.norm());
    out.max_after_mm = std::max(out.max_after_mm, r.after_mm.norm());
    out.point_residuals.push_back(std::move(r));
  }
  out.rms_before_mm = std::sqrt(sb / static_cast<double>(points.size()));
  out.rms_after_mm = std::sqrt(sa / static_cast<double>(points.size()));
  return out;
}

IdentifiedErrors identify_from_diagonals(const std::vector<DiagonalReading>& readings,
                                         const IdentificationOptions& options) {
  check_options(options);
  if (readings.empty())
    throw std::invalid_argument("readings: empty; sequential-diagonal readings are needed");
  std::map<int, std::size_t> start_of;  // diagonal -> index of its start reading
  std::map<int, int> moves;             // diagonal -> readings so far
  std::map<int, std::vector<std::tuple<long long, long long, long long, std::size_t>>> seen;
  std::vector<MovedReading> moved;
  std::vector<Vector3d> commanded;
  for (std::size_t i = 0; i < readings.size(); ++i) {
    const DiagonalReading& r = readings[i];
    const std::string where = "readings[" + std::to_string(i) + "]";
    if (r.diagonal < 0 || r.diagonal > 3) {
      throw std::invalid_argument(where + ".diagonal = " + std::to_string(r.diagonal) +
                                  ": expected 0..3");
    }
    if (!r.commanded_mm.allFinite())
      throw std::invalid_argument(
          where + ".commanded_mm = " + detail::format_vector(r.commanded_mm) + ": not finite");
    if (!r.direction.allFinite() || std::abs(r.direction.norm() - 1.0) > kUnitTolerance) {
      throw std::invalid_argument(where + ".direction = " + detail::format_vector(r.direction) +
                                  ": expected a unit vector");
    }
    if (!std::isfinite(r.displacement_mm)) {
      std::ostringstream os;
      os << where << ".displacement_mm = " << r.displacement_mm << ": not finite";
      throw std::invalid_argument(os.str());
    }
    if (!(std::isfinite(r.sigma_mm) && r.sigma_mm > 0)) {
      std::ostringstream os;
      os << where << ".sigma_mm = " << r.sigma_mm << ": expected a finite value > 0";
      throw std::invalid_argument(os.str());
    }
    const auto key = [](double v) { return std::llround(v / detail::kDuplicateMm); };
    auto& s = seen[r.diagonal];
    const auto k = std::make_tuple(key(r.commanded_mm.x()), key(r.commanded_mm.y()),
                                   key(r.commanded_mm.z()), i);
    for (const auto& o : s) {
      if (std::get<0>(o) == std::get<0>(k) && std::get<1>(o) == std::get<1>(k) &&
          std::get<2>(o) == std::get<2>(k)) {
        throw std::invalid_argument(where +
                                    ".commanded_mm = " + detail::format_vector(r.commanded_mm) +
                                    ": repeats readings[" + std::to_string(std::get<3>(o)) +
                                    "] of diagonal " + std::to_string(r.diagonal));
      }
    }
    s.push_back(k);
    commanded.push_back(r.commanded_mm);
    const auto it = start_of.find(r.diagonal);
    if (it == start_of.end()) {
      if (r.displacement_mm != 0.0) {
        std::ostringstream os;
        os << where << ".displacement_mm = " << r.displacement_mm
           << ": the start reading of diagonal " << r.diagonal
           << " must be 0 (displacements are relative to it)";
        throw std::invalid_argument(os.str());
      }
      start_of[r.diagonal] = i;
      moves[r.diagonal] = 0;
      continue;
    }
    MovedReading m;
    m.diagonal = r.diagonal;
    m.reading = ++moves[r.diagonal];
    m.commanded = r.commanded_mm;
    m.start = readings[it->second].commanded_mm;
    m.direction = r.direction.normalized();
    m.displacement = r.displacement_mm;
    m.sigma = r.sigma_mm;
    moved.push_back(m);
  }

  Model candidate;
  set_candidates(candidate.layout, axis_gauge(commanded, options, "readings"),
                 detail::CandidateSet::DiagonalDisplacements);
  const int observations = static_cast<int>(moved.size());
  detail::refuse_too_few("readings: " + std::to_string(moved.size()) + " moved readings",
                         observations, candidate.layout.size(), options.max_degree);
  if (options.initial_instrument_from_machine)
    candidate.r0 = options.initial_instrument_from_machine->linear();

  const DiagonalObservations obs(moved);

  // Before compensation: the nominal model with only the beam-set rotation fitted (linear).
  VectorXd before;
  {
    Model rot_only = candidate;
    rot_only.layout.params.clear();
    for (int i = 0; i < 3; ++i) rot_only.layout.params.push_back({Kind::FrameRotation, i, -1});
    rot_only.layout.index();
    VectorXd r;
    RowMatrix J;
    evaluate_all(obs, rot_only, VectorXd::Zero(3), r, &J);
    const Eigen::Vector3d step = -(J.transpose() * J).ldlt().solve(J.transpose() * r);
    before = r + J * step;
  }

  const Solved s = run(Pipeline{obs, candidate, options});
  IdentifiedErrors out = fill(s, observations);
  for (int f = 0; f < kFunctionCount; ++f) {
    if (volumetric::is_angular(f)) out.lumped.emplace_back(volumetric::function_name(f));
  }
  double sb = 0, sa = 0;
  for (std::size_t i = 0; i < moved.size(); ++i) {
    ReadingResidual r;
    r.diagonal = moved[i].diagonal;
    r.reading = moved[i].reading;
    r.before_mm = -before(static_cast<Eigen::Index>(i)) * moved[i].sigma;
    r.after_mm = -s.residual(static_cast<Eigen::Index>(i)) * moved[i].sigma;
    sb += r.before_mm * r.before_mm;
    sa += r.after_mm * r.after_mm;
    out.max_before_mm = std::max(out.max_before_mm, std::abs(r.before_mm));
    out.max_after_mm = std::max(out.max_after_mm, std::abs(r.after_mm));
    out.reading_residuals.push_back(r);
  }
  out.rms_before_mm = std::sqrt(sb / static_cast<double>(moved.size()));
  out.rms_after_mm = std::sqrt(sa / static_cast<double>(moved.size()));
  return out;
}

VolumetricPrediction predict_position(const IdentifiedErrors& identified,
                                      const Eigen::Vector3d& commanded_mm,
                                      const Eigen::Vector3d& tool_offset_mm) {
  if (!commanded_mm.allFinite())
    throw std::invalid_argument(
        "predict_position: commanded_mm = " + detail::format_vector(commanded_mm) + ": not finite");
  if (!tool_offset_mm.allFinite())
    throw std::invalid_argument("predict_position: tool_offset_mm = " +
                                detail::format_vector(tool_offset_mm) + ": not finite");
  Layout L;
  for (int a = 0; a < 3; ++a) {
    L.lo[static_cast<std::size_t>(a)] =
        identified.errors.functions[static_cast<std::size_t>(a * 6)].lo_mm;
    L.hi[static_cast<std::size_t>(a)] =
        identified.errors.functions[static_cast<std::size_t>(a * 6)].hi_mm;
  }
  VectorXd th(static_cast<Eigen::Index>(identified.parameters.size()));
  for (std::size_t i = 0; i < identified.parameters.size(); ++i) {
    const IdentifiedParameter& p = identified.parameters[i];
    if (p.function >= 0) {
      L.params.push_back({Kind::Coefficient, p.function, p.order});
      th(static_cast<Eigen::Index>(i)) = p.value;
    } else if (p.squareness >= 0) {
      L.params.push_back({Kind::Squareness, p.squareness, -1});
      th(static_cast<Eigen::Index>(i)) = p.value;
    } else {
      L.params.push_back(
          {p.frame < 3 ? Kind::FrameRotation : Kind::FrameTranslation, p.frame % 3, -1});
      th(static_cast<Eigen::Index>(i)) = 0.0;  // increments at the identified frame
    }
  }
  L.index();
  const int n = L.size();
  if (identified.covariance.rows() != n || identified.covariance.cols() != n) {
    throw std::invalid_argument("predict_position: identified.covariance is " +
                                std::to_string(identified.covariance.rows()) + " x " +
                                std::to_string(identified.covariance.cols()) + ", expected " +
                                std::to_string(n) + " x " + std::to_string(n) +
                                " (the parameters)");
  }
  for (int a = 0; a < 3; ++a) {
    if (L.top_order[static_cast<std::size_t>(a)] >= 0 &&
        !(L.hi[static_cast<std::size_t>(a)] > L.lo[static_cast<std::size_t>(a)])) {
      throw std::invalid_argument("predict_position: the axis range of " +
                                  std::string(1, "XYZ"[a]) + " is empty");
    }
  }
  Jacobian3 J = Jacobian3::Zero(3, n);
  Vector3d p;
  chain(L, th.data(), commanded_mm, tool_offset_mm, p, &J);
  VolumetricPrediction out;
  out.actual_mm = p;
  out.in_instrument_mm = identified.instrument_from_machine * p;
  out.actual_covariance_mm2 = J * identified.covariance * J.transpose();  // frame columns are zero
  const Matrix3d R = identified.instrument_from_machine.linear();
  Jacobian3 Ji = R * J;
  if (L.rotation >= 0) Ji.middleCols(L.rotation, 3) = -R * skew(p);
  if (L.translation >= 0) Ji.middleCols(L.translation, 3) = Matrix3d::Identity();
  out.in_instrument_covariance_mm2 = Ji * identified.covariance * Ji.transpose();
  return out;
}

}  // namespace ncqual::solver

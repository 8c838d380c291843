// SPDX-License-Identifier: Apache-2.0
// The parameter model of the volumetric identification (internal to the solver library), shared
// by identify_rigid_body_errors / identify_from_diagonals (volumetric_identification.cpp) and the
// linearised identification of the verification's Monte Carlo (verification_uncertainty.cpp): the
// same candidate terms, in the same priority order, the same identifiability test and the same
// refusals. See ncqual/solver/volumetric_identification.hpp for the model. Units: mm, rad.
// Refusals throw std::invalid_argument; where the callers word one differently, they supply the
// wording.
#pragma once

#include "ncqual/common/volumetric.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SVD>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace ncqual::solver::detail {

inline constexpr int kMaxOrder = 12;          // highest Legendre order (max_degree 1..kMaxOrder)
inline constexpr double kDistinctMm = 1e-3;   // axis positions closer than this are one position
inline constexpr double kDuplicateMm = 1e-6;  // (commanded, tool offset) pairs equal within this

// One unknown: a frame component (index 0..2 = x, y, z; translation mm, small rotation rad), a
// squareness (index 0..2 = EC0XY, EB0XZ, EA0YZ; rad) or the coefficient of Legendre order
// `order` of error function `index` (0..17, volumetric::function_name order; order -1 otherwise).
enum class Kind { FrameTranslation, FrameRotation, Squareness, Coefficient };
struct Param {
  Kind kind;
  int index;
  int order;
};

// "frame tx" .. "frame rz", "EC0XY" .. "EA0YZ", or "<function> P<order>", e.g. "EXX P2".
inline std::string param_name(const Param& p) {
  static const char* const kFrame[2][3] = {{"frame tx", "frame ty", "frame tz"},
                                           {"frame rx", "frame ry", "frame rz"}};
  switch (p.kind) {
    case Kind::FrameTranslation: return kFrame[0][p.index];
    case Kind::FrameRotation: return kFrame[1][p.index];
    case Kind::Squareness:
      return std::string(volumetric::function_name(volumetric::kSquarenessEC0XY + p.index));
    case Kind::Coefficient:
      return std::string(volumetric::function_name(p.index)) + " P" + std::to_string(p.order);
  }
  return "";
}

// The cross-product matrix: skew(v) u = v x u.
inline Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d k;
  k << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return k;
}

// ----------------------------------------------------------------------------------------------
// The design

// The first pair (a, b), a < b, of points whose commanded position and tool offset (one entry
// per point in each vector) agree within kDuplicateMm per component, first in the sorted order
// of the rounded pairs; none when all differ.
inline std::optional<std::pair<std::size_t, std::size_t>> first_duplicate(
    const std::vector<Eigen::Vector3d>& commanded,
    const std::vector<Eigen::Vector3d>& tool_offset) {
  using Key = std::tuple<long long, long long, long long, long long, long long, long long>;
  const auto round = [](double v) { return std::llround(v / kDuplicateMm); };
  std::vector<std::pair<Key, std::size_t>> keys;
  for (std::size_t i = 0; i < commanded.size(); ++i) {
    const Eigen::Vector3d& c = commanded[i];
    const Eigen::Vector3d& t = tool_offset[i];
    keys.emplace_back(
        Key(round(c.x()), round(c.y()), round(c.z()), round(t.x()), round(t.y()), round(t.z())), i);
  }
  std::sort(keys.begin(), keys.end());
  for (std::size_t i = 1; i < keys.size(); ++i) {
    if (keys[i - 1].first == keys[i].first)
      return std::make_pair(keys[i - 1].second, keys[i].second);
  }
  return std::nullopt;
}

// Number of distinct values of q (a value within kDistinctMm of its sorted predecessor is not).
inline int distinct_positions(std::vector<double> q) {
  std::sort(q.begin(), q.end());
  int n = 0;
  for (std::size_t i = 0; i < q.size(); ++i) {
    if (i == 0 || q[i] - q[i - 1] > kDistinctMm) ++n;
  }
  return n;
}

// Per axis X, Y, Z: the range [lo, hi] (mm) the Legendre polynomials are normalised over and the
// highest order the design supports, min(max_degree, distinct positions - 1).
// The fewest distinct commanded positions an axis needs, the same for every identification.
inline constexpr int kMinimumAxisPositions = 2;

struct AxisGauge {
  std::array<double, 3> lo{}, hi{};
  std::array<int, 3> cap{};
};

// The AxisGauge of the commanded positions, [lo, hi] = `range` if given, else the commanded min
// and max. Refuses the first axis with fewer than 2 distinct positions with too_few(axis letter,
// distinct positions) as the message: two positions give an axis linear error functions (its
// scale, its squareness, linear straightness and angular terms), which is also all the affine
// grid analysis (global_grid.hpp) takes from them; one is refused by both.
inline AxisGauge axis_gauge(const std::vector<Eigen::Vector3d>& commanded, int max_degree,
                            const std::optional<std::array<std::array<double, 2>, 3>>& range,
                            const std::function<std::string(char axis, int distinct)>& too_few) {
  AxisGauge g;
  for (std::size_t a = 0; a < 3; ++a) {
    std::vector<double> q;
    q.reserve(commanded.size());
    for (const auto& c : commanded) q.push_back(c[static_cast<Eigen::Index>(a)]);
    const int distinct = distinct_positions(q);
    if (distinct < kMinimumAxisPositions) throw std::invalid_argument(too_few("XYZ"[a], distinct));
    const auto [mn, mx] = std::minmax_element(q.begin(), q.end());
    g.lo[a] = range ? (*range)[a][0] : *mn;
    g.hi[a] = range ? (*range)[a][1] : *mx;
    g.cap[a] = std::min(max_degree, distinct - 1);
  }
  return g;
}

// Refuses more unknowns than observations: "<what> give <observations> observations, fewer than
// the <unknowns> unknowns of the candidate model (max_degree = <max_degree>)".
inline void refuse_too_few(const std::string& what, int observations, int unknowns,
                           int max_degree) {
  if (observations < unknowns) {
    throw std::invalid_argument(
        what + " give " + std::to_string(observations) + " observations, fewer than the " +
        std::to_string(unknowns) +
        " unknowns of the candidate model (max_degree = " + std::to_string(max_degree) + ")");
  }
}

// ----------------------------------------------------------------------------------------------
// Candidate terms and identifiability

enum class CandidateSet {
  TrackerPoints,          // 3D points: the frame's translation and rotation, all 18 functions
  DiagonalDisplacements,  // displacements along beams: the beams' rotation only, angular lumped
};

// The candidate parameters in the identifiability test's priority order:
//   TrackerPoints:         frame tx, ty, tz, rx, ry, rz; squareness; translational; angular terms
//   DiagonalDisplacements: frame rx, ry, rz; squareness; translational terms.
// Squareness EC0XY, EB0XZ, EA0YZ. Translational terms per axis X, Y, Z and component x, y, z:
// positioning from P1, straightness from P2 (lower orders are the frame's); angular terms per
// axis and component a, b, c from P1, Z's from P0 (it keeps its constant); all up to cap[axis].
inline std::vector<Param> candidate_parameters(const std::array<int, 3>& cap, CandidateSet set) {
  const bool points = set == CandidateSet::TrackerPoints;
  std::vector<Param> params;
  for (int i = 0; i < 3 && points; ++i) params.push_back({Kind::FrameTranslation, i, -1});
  for (int i = 0; i < 3; ++i) params.push_back({Kind::FrameRotation, i, -1});
  for (int s = 0; s < 3; ++s) params.push_back({Kind::Squareness, s, -1});
  for (int comps = 0; comps < (points ? 2 : 1); ++comps) {  // translational, then angular
    for (int axis = 0; axis < 3; ++axis) {
      for (int comp = 3 * comps; comp < 3 * comps + 3; ++comp) {
        const int first =
            comps == 1 ? (axis == volumetric::kAxisZ ? 0 : 1) : (comp == axis ? 1 : 2);
        for (int k = first; k <= cap[static_cast<std::size_t>(axis)]; ++k) {
          params.push_back({Kind::Coefficient, axis * 6 + comp, k});
        }
      }
    }
  }
  return params;
}

struct Identifiability {
  std::vector<int> accepted;   // the columns kept, increasing
  std::vector<bool> rejected;  // per column: not kept
  Eigen::VectorXd scale;       // per column 1 / sqrt(H(j, j)), 0 where H(j, j) <= 0
};

// Incremental Cholesky of the column-normalised normal matrix H = J'J (its upper triangle is
// read), columns in index (priority) order: column j is kept when the squared sine of its angle
// to the span of the columns kept before it exceeds rank_tolerance; a zero column never is.
inline Identifiability identifiable_columns(const Eigen::MatrixXd& H, double rank_tolerance) {
  const auto n = static_cast<int>(H.cols());
  Identifiability out;
  out.rejected.assign(static_cast<std::size_t>(n), false);
  out.scale = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(n, n);
  for (int j = 0; j < n; ++j) {
    if (!(H(j, j) > 0)) {
      out.rejected[static_cast<std::size_t>(j)] = true;
      continue;
    }
    out.scale(j) = 1.0 / std::sqrt(H(j, j));
    const int m = static_cast<int>(out.accepted.size());
    Eigen::VectorXd l(m);
    for (int k = 0; k < m; ++k) {
      const int jk = out.accepted[static_cast<std::size_t>(k)];
      l(k) = H(jk, j) * out.scale(jk) * out.scale(j);
    }
    if (m > 0) L.topLeftCorner(m, m).triangularView<Eigen::Lower>().solveInPlace(l);
    const double d = 1.0 - l.squaredNorm();
    if (d > rank_tolerance) {
      L.block(m, 0, 1, m) = l.transpose();
      L(m, m) = std::sqrt(d);
      out.accepted.push_back(j);
    } else {
      out.rejected[static_cast<std::size_t>(j)] = true;
    }
  }
  return out;
}

// Refuses a rejected frame parameter: "<subject> cannot determine the instrument frame
// (<param_name>): the commanded positions (and tool offsets) do not span space".
inline void refuse_undetermined_frame(const std::vector<Param>& params,
                                      const std::vector<bool>& rejected,
                                      const std::string& subject) {
  for (std::size_t j = 0; j < params.size(); ++j) {
    if (rejected[j] &&
        (params[j].kind == Kind::FrameRotation || params[j].kind == Kind::FrameTranslation)) {
      throw std::invalid_argument(
          subject + " cannot determine the instrument frame (" + param_name(params[j]) +
          "): the commanded positions (and tool offsets) do not span space");
    }
  }
}

struct RejectedTerms {
  // The functions (function order) with candidate terms all rejected, then the rejected
  // squarenesses (candidate order), by volumetric::function_name.
  std::vector<std::string> unidentifiable;
  // param_name of the rejected terms of the other functions (function, then candidate order).
  std::vector<std::string> fixed_terms;
};

inline RejectedTerms rejected_terms(const std::vector<Param>& params,
                                    const std::vector<bool>& rejected) {
  RejectedTerms out;
  for (int f = 0; f < volumetric::kFunctionCount; ++f) {
    std::vector<std::size_t> terms;
    for (std::size_t j = 0; j < params.size(); ++j) {
      if (params[j].kind == Kind::Coefficient && params[j].index == f) terms.push_back(j);
    }
    if (!terms.empty() &&
        std::all_of(terms.begin(), terms.end(), [&](std::size_t j) { return rejected[j]; })) {
      out.unidentifiable.emplace_back(volumetric::function_name(f));
      continue;
    }
    for (std::size_t j : terms) {
      if (rejected[j]) out.fixed_terms.push_back(param_name(params[j]));
    }
  }
  for (std::size_t j = 0; j < params.size(); ++j) {
    if (params[j].kind == Kind::Squareness && rejected[j])
      out.unidentifiable.push_back(param_name(params[j]));
  }
  return out;
}

// Per function: the positions in `accepted` of its kept coefficient terms, by increasing order
// (candidate order): the stack the BIC's backward elimination drops from.
inline std::array<std::vector<int>, volumetric::kFunctionCount> order_stacks(
    const std::vector<Param>& params, const std::vector<int>& accepted) {
  std::array<std::vector<int>, volumetric::kFunctionCount> stacks;
  for (std::size_t a = 0; a < accepted.size(); ++a) {
    const Param& p = params[static_cast<std::size_t>(accepted[a])];
    if (p.kind == Kind::Coefficient)
      stacks[static_cast<std::size_t>(p.index)].push_back(static_cast<int>(a));
  }
  return stacks;
}

// ----------------------------------------------------------------------------------------------
// Rigid fit

// A vector of points as the columns of a 3 x n matrix (no copy).
inline Eigen::Map<const Eigen::Matrix3Xd> as_columns(const std::vector<Eigen::Vector3d>& v) {
  static_assert(sizeof(Eigen::Vector3d) == 3 * sizeof(double), "Vector3d is packed");
  return {v.empty() ? nullptr : v.front().data(), 3, static_cast<Eigen::Index>(v.size())};
}

// Weighted rigid best fit (SVD, proper rotation): the f minimising sum_i w_i |to_i - f from_i|^2
// over the columns of from, to (mm); weights w_i > 0, nullptr for all 1.
inline Eigen::Isometry3d rigid_fit(const Eigen::Ref<const Eigen::Matrix3Xd>& from,
                                   const Eigen::Ref<const Eigen::Matrix3Xd>& to,
                                   const std::vector<double>* weights = nullptr) {
  const auto w = [&](Eigen::Index i) {
    return weights ? (*weights)[static_cast<std::size_t>(i)] : 1.0;
  };
  double sw = 0;
  Eigen::Vector3d mf = Eigen::Vector3d::Zero(), mt = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < from.cols(); ++i) {
    sw += w(i);
    mf += w(i) * from.col(i);
    mt += w(i) * to.col(i);
  }
  mf /= sw;
  mt /= sw;
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  for (Eigen::Index i = 0; i < from.cols(); ++i)
    S += w(i) * (from.col(i) - mf) * (to.col(i) - mt).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(S, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1.0 : 1.0;
  Eigen::Isometry3d f = Eigen::Isometry3d::Identity();
  f.linear() = svd.matrixV() * D * svd.matrixU().transpose();
  f.translation() = mt - f.linear() * mf;
  return f;
}

}  // namespace ncqual::solver::detail

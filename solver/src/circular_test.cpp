// SPDX-License-Identifier: Apache-2.0
#include "ncqual/solver/circular_test.hpp"

#include "ncqual/common/enum_names.hpp"

#include "ncqual/common/units.hpp"
#include "result_building.hpp"

#include "ncqual/solver/circle_fit.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <tuple>

namespace ncqual::solver {
namespace {

using units::kPi;
constexpr int kMinPointsPerDirection = 8;
constexpr double kMaxGapRad = kPi / 3;  // 60°: a larger gap makes the path an arc
constexpr double kGapSlackRad = 1e-9;   // rounding allowance on the gap test
constexpr double kDuplicateAngleRad = 1e-9;
constexpr double kMaxShapeNoiseGain = 3;          // the 2θ terms are reported up to this gain
constexpr double kShortestArcRad = kPi / 2;       // ISO 230-4's shortest partial arc, 90°
constexpr double kSparsestSpacingRad = kPi / 18;  // one point every 10° of arc

double deg(double rad) { return rad * 180.0 / kPi; }

// An angle in degrees for messages, rounded to 1e-6 deg (no "5e-15" for 0).
std::string deg_text(double rad) {
  const double d = std::round(deg(rad) * 1e6) / 1e6;
  return detail::quote_number(d == 0 ? 0.0 : d);
}

// Angle of p about c in [0, 2π).
double angle_about(const Eigen::Vector2d& p, const Eigen::Vector2d& c) {
  double a = std::atan2(p.y() - c.y(), p.x() - c.x());
  if (a < 0) a += 2 * kPi;
  if (a >= 2 * kPi) a -= 2 * kPi;
  return a;
}

// The points of one path about a centre: angle, radius and index into the input.
struct Polar {
  double theta = 0;
  double r = 0;
  std::size_t index = 0;
};

std::vector<Polar> polar_sorted(const std::vector<CircularPoint>& points,
                                const std::vector<std::size_t>& indices,
                                const Eigen::Vector2d& centre) {
  std::vector<Polar> out;
  out.reserve(indices.size());
  for (std::size_t i : indices) {
    out.push_back(
        Polar{angle_about(points[i].uv_mm, centre), (points[i].uv_mm - centre).norm(), i});
  }
  std::sort(out.begin(), out.end(),
            [](const Polar& a, const Polar& b) { return a.theta < b.theta; });
  return out;
}

// Largest gap between neighbouring angles (the one across 0 included) and the position in
// `sorted` of the point that opens it.
std::pair<double, std::size_t> largest_gap(const std::vector<Polar>& sorted) {
  double gap = sorted.front().theta + 2 * kPi - sorted.back().theta;
  std::size_t at = sorted.size() - 1;
  for (std::size_t k = 1; k < sorted.size(); ++k) {
    const double g = sorted[k].theta - sorted[k - 1].theta;
    if (g > gap) {
      gap = g;
      at = k - 1;
    }
  }
  return {gap, at};
}

// The second largest gap (0 with fewer than 3 points) and the position of the point opening it.
std::pair<double, std::size_t> second_largest_gap(const std::vector<Polar>& sorted) {
  const auto first = largest_gap(sorted);
  double gap = 0;
  std::size_t at = 0;
  for (std::size_t k = 0; k < sorted.size(); ++k) {
    if (k == first.second) continue;
    const std::size_t next = (k + 1) % sorted.size();
    const double g = next == 0 ? sorted.front().theta + 2 * kPi - sorted.back().theta
                               : sorted[next].theta - sorted[k].theta;
    if (g > gap) {
      gap = g;
      at = k;
    }
  }
  return {gap, at};
}

// The part of the circle the sorted points cover (see CircularArc).
CircularArc arc_of(const std::vector<Polar>& sorted) {
  CircularArc arc;
  const auto [gap, at] = largest_gap(sorted);
  if (gap <= kMaxGapRad + kGapSlackRad) return arc;
  arc.full_circle = false;
  arc.from_rad = sorted[(at + 1) % sorted.size()].theta;
  arc.span_rad = 2 * kPi - gap;
  return arc;
}

// theta - from in [0, 2π).
double unwrapped(double theta, double from) {
  double t = std::fmod(theta - from, 2 * kPi);
  if (t < 0) t += 2 * kPi;
  return t;
}

// The length of the intersection of two arcs of a circle.
double arc_overlap(const CircularArc& a, const CircularArc& b) {
  if (a.full_circle) return b.span_rad;
  if (b.full_circle) return a.span_rad;
  const double d = unwrapped(b.from_rad, a.from_rad);  // b from, with a from at 0
  double len = std::max(0.0, std::min(a.span_rad, d + b.span_rad) - d);
  if (d + b.span_rad > 2 * kPi) len += std::min(a.span_rad, d + b.span_rad - 2 * kPi);
  return len;
}

std::vector<std::size_t> indices_of(const CircularTestInput& input, PathDirection d) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < input.points.size(); ++i) {
    if (input.points[i].direction == d) out.push_back(i);
  }
  return out;
}

std::vector<Eigen::Vector2d> coordinates(const CircularTestInput& input,
                                         const std::vector<std::size_t>& indices) {
  std::vector<Eigen::Vector2d> out;
  out.reserve(indices.size());
  for (std::size_t i : indices) out.push_back(input.points[i].uv_mm);
  return out;
}

std::string direction_prefix(PathDirection d) {
  return "direction " + std::string(to_string(d)) + ": ";
}

// The design of the radial fit: rows (1, cos θ, sin θ, cos 2θ, sin 2θ).
Eigen::MatrixXd harmonic_design(const std::vector<Polar>& polar) {
  const Eigen::Index n = static_cast<Eigen::Index>(polar.size());
  Eigen::MatrixXd design(n, 5);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = polar[static_cast<std::size_t>(i)].theta;
    design.row(i) << 1, std::cos(t), std::sin(t), std::cos(2 * t), std::sin(2 * t);
  }
  return design;
}

// The larger noise gain of a2 and b2 (the header: sqrt(n/2 [(AᵀA)⁻¹]_kk)); infinite when the
// angles do not resolve the five terms at all.
double shape_noise_gain(const std::vector<Polar>& polar) {
  const Eigen::MatrixXd design = harmonic_design(polar);
  const Eigen::MatrixXd normal = design.transpose() * design;
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(normal);
  if (!lu.isInvertible()) return INFINITY;
  const Eigen::MatrixXd inverse = lu.inverse();
  const double n = static_cast<double>(polar.size());
  const double gain = std::sqrt(n / 2 * std::max(inverse(3, 3), inverse(4, 4)));
  return std::isfinite(gain) ? gain : INFINITY;
}

// Least squares of r_i - R on (1, cos θ, sin θ, cos 2θ, sin 2θ); the caller has checked the
// angles resolve them (shape_noise_gain).
RadialHarmonics fit_harmonics(const std::vector<Polar>& polar, double radius) {
  const Eigen::MatrixXd design = harmonic_design(polar);
  Eigen::VectorXd rhs(design.rows());
  for (Eigen::Index i = 0; i < design.rows(); ++i) {
    rhs(i) = polar[static_cast<std::size_t>(i)].r - radius;
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(design);
  const Eigen::VectorXd c = qr.solve(rhs);
  RadialHarmonics h;
  h.a0_mm = c(0);
  h.a1_mm = c(1);
  h.b1_mm = c(2);
  h.a2_mm = c(3);
  h.b2_mm = c(4);
  h.residual_rms_mm =
      std::sqrt((design * c - rhs).squaredNorm() / static_cast<double>(design.rows()));
  return h;
}

// The shape figures of sorted points about an LSC of `radius`, when the points resolve them.
template <typename Figures>
void add_shape(const std::vector<Polar>& polar, double radius, Figures* f) {
  f->shape_noise_gain = shape_noise_gain(polar);
  if (!(f->shape_noise_gain <= kMaxShapeNoiseGain)) return;
  f->harmonics = fit_harmonics(polar, radius);
  f->scale_mismatch_um_per_m = 2 * f->harmonics->a2_mm / radius * 1e6;
  f->squareness_urad = -2 * f->harmonics->b2_mm / radius * 1e6;
}

CircleFit fit_or_throw(const std::vector<Eigen::Vector2d>& pts, const std::string& what) {
  CircleFit fit = fit_circle(pts);
  if (!fit.ok()) throw std::invalid_argument("evaluate_circular_test: " + what + fit.error);
  return fit;
}

RadialReference reference_for(const CircularTestInput& input, const CircleFit& fit) {
  RadialReference ref;
  ref.nominal_centre = input.nominal_centre_mm.has_value();
  ref.nominal_radius = input.nominal_radius_mm.has_value();
  ref.centre_mm = ref.nominal_centre ? *input.nominal_centre_mm : fit.centre;
  ref.radius_mm = ref.nominal_radius ? *input.nominal_radius_mm : fit.radius;
  return ref;
}

// F_max, F_min of the points about the reference.
std::pair<double, double> radial_deviation(const std::vector<Eigen::Vector2d>& pts,
                                           const RadialReference& ref) {
  double hi = -INFINITY, lo = INFINITY;
  for (const auto& p : pts) {
    const double f = radial_deviation_about(p, ref).deviation_mm;
    hi = std::max(hi, f);
    lo = std::min(lo, f);
  }
  return {hi, lo};
}

double spread(const std::vector<Polar>& polar) {
  double hi = -INFINITY, lo = INFINITY;
  for (const auto& p : polar) {
    hi = std::max(hi, p.r);
    lo = std::min(lo, p.r);
  }
  return hi - lo;
}

// A path about a centre: its points sorted by the angle from the start of its arc (a full circle
// starts at 0), and the arc.
struct PathAngles {
  std::vector<Polar> sorted;  // theta: from the arc's start, in [0, 2π)
  CircularArc arc;
};

PathAngles path_angles(std::vector<Polar> polar) {
  PathAngles p;
  p.arc = arc_of(polar);
  for (auto& q : polar) q.theta = unwrapped(q.theta, p.arc.from_rad);
  std::sort(polar.begin(), polar.end(),
            [](const Polar& a, const Polar& b) { return a.theta < b.theta; });
  p.sorted = std::move(polar);
  return p;
}

// Radius of the path at angle theta (about the same centre), interpolated linearly in θ between
// its two neighbours, round the circle for a full circle; nothing outside an arc.
std::optional<double> radius_at(const PathAngles& path, double theta) {
  const std::vector<Polar>& sorted = path.sorted;
  const double t = unwrapped(theta, path.arc.from_rad);
  if (!path.arc.full_circle && t > sorted.back().theta + kGapSlackRad) return std::nullopt;
  const auto it = std::upper_bound(sorted.begin(), sorted.end(), t,
                                   [](double x, const Polar& p) { return x < p.theta; });
  const std::size_t n = sorted.size();
  const std::size_t next = static_cast<std::size_t>(it - sorted.begin());
  if (!path.arc.full_circle && next == n) return sorted.back().r;  // at the arc's end
  const Polar& b = sorted[next % n];
  const Polar& a = sorted[(next + n - 1) % n];
  const double ta = next == 0 ? a.theta - 2 * kPi : a.theta;
  const double tb = next == n ? b.theta + 2 * kPi : b.theta;
  if (!(tb - ta > 1e-15)) return a.r;
  return a.r + (t - ta) / (tb - ta) * (b.r - a.r);
}

// Largest |r_a(θ) - r_b(θ)| at the points of either path where the other path was measured;
// nothing when the paths share no angle. `a` and `b` about the same centre, in input angles.
std::optional<double> hysteresis(const std::vector<Polar>& a, const std::vector<Polar>& b) {
  const PathAngles pa = path_angles(a), pb = path_angles(b);
  std::optional<double> h;
  const auto compare = [&h](const PathAngles& from, const PathAngles& with) {
    for (const auto& p : from.sorted) {
      if (const auto r = radius_at(with, p.theta + from.arc.from_rad)) {
        h = std::max(h.value_or(0.0), std::abs(p.r - *r));
      }
    }
  };
  compare(pa, pb);
  compare(pb, pa);
  return h;
}

CircularPathFigures path_figures(const CircularTestInput& input, PathDirection d,
                                 const std::vector<std::size_t>& indices) {
  const auto pts = coordinates(input, indices);
  const CircleFit fit = fit_or_throw(pts, direction_prefix(d));
  const auto polar = polar_sorted(input.points, indices, fit.centre);
  CircularPathFigures f;
  f.direction = d;
  f.point_count = static_cast<int>(indices.size());
  f.lsc_centre_mm = fit.centre;
  f.lsc_radius_mm = fit.radius;
  f.lsc_rms_mm = fit.rms_residual;
  f.G_mm = spread(polar);
  f.F_reference = reference_for(input, fit);
  std::tie(f.F_max_mm, f.F_min_mm) = radial_deviation(pts, f.F_reference);
  f.max_gap_rad = largest_gap(polar).first;
  f.arc = arc_of(polar);
  add_shape(polar, fit.radius, &f);
  return f;
}

}  // namespace

std::string_view to_string(Plane p) {
  constexpr std::array<std::string_view, 3> kNames = {"XY", "YZ", "XZ"};
  return name_of(kNames, p);
}

std::optional<Plane> parse_plane(std::string_view text) {
  std::string up(text);
  for (char& c : up) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (up == "XY") return Plane::XY;
  if (up == "YZ") return Plane::YZ;
  if (up == "XZ") return Plane::XZ;
  return std::nullopt;
}

std::string_view to_string(PathDirection d) { return d == PathDirection::Ccw ? "ccw" : "cw"; }

CircularPoint circular_point_from_polar(double theta_rad, double radius_mm,
                                        PathDirection direction) {
  return CircularPoint{radius_mm * Eigen::Vector2d(std::cos(theta_rad), std::sin(theta_rad)),
                       direction};
}

std::optional<CircularTestProblem> find_circular_test_problem(const CircularTestInput& input) {
  using P = CircularTestProblem;
  if (input.nominal_radius_mm &&
      !(std::isfinite(*input.nominal_radius_mm) && *input.nominal_radius_mm > 0)) {
    return P{std::nullopt, std::nullopt,
             "nominal_radius_mm = " + detail::quote_number(*input.nominal_radius_mm) +
                 ": must be a finite number > 0"};
  }
  if (input.nominal_centre_mm && !input.nominal_centre_mm->allFinite()) {
    return P{std::nullopt, std::nullopt,
             "nominal_centre_mm = (" + detail::quote_number(input.nominal_centre_mm->x()) + ", " +
                 detail::quote_number(input.nominal_centre_mm->y()) + "): not finite"};
  }
  if (input.points.empty()) return P{std::nullopt, std::nullopt, "no points"};
  for (std::size_t i = 0; i < input.points.size(); ++i) {
    const auto& p = input.points[i].uv_mm;
    if (!p.allFinite()) {
      return P{i, std::nullopt,
               "u_mm = " + detail::quote_number(p.x()) + ", v_mm = " + detail::quote_number(p.y()) +
                   ": not a finite point"};
    }
  }
  for (PathDirection d : {PathDirection::Ccw, PathDirection::Cw}) {
    const auto idx = indices_of(input, d);
    if (idx.empty()) continue;
    const std::string pre = direction_prefix(d);
    if (static_cast<int>(idx.size()) < kMinPointsPerDirection) {
      return P{idx.back(), std::nullopt,
               pre + std::to_string(idx.size()) + " points; a circular test needs at least " +
                   std::to_string(kMinPointsPerDirection) +
                   " per direction (the fit of the 2θ shape has 5 terms)"};
    }
    const CircleFit fit = fit_circle(coordinates(input, idx));
    if (!fit.ok()) return P{std::nullopt, std::nullopt, pre + fit.error};
    const auto polar = polar_sorted(input.points, idx, fit.centre);
    for (std::size_t k = 0; k < polar.size(); ++k) {
      const Polar& a = polar[k];
      const Polar& b = polar[(k + 1) % polar.size()];
      const double dt = k + 1 < polar.size() ? b.theta - a.theta : b.theta + 2 * kPi - a.theta;
      if (dt < kDuplicateAngleRad) {
        const std::size_t later = std::max(a.index, b.index);
        const auto& p = input.points[later].uv_mm;
        return P{later, std::min(a.index, b.index),
                 pre + "u_mm = " + detail::quote_number(p.x()) +
                     ", v_mm = " + detail::quote_number(p.y()) + " at " + deg_text(b.theta) +
                     " deg about the path's LSC centre: the same angle as another point"};
      }
    }
    const auto [gap, at] = second_largest_gap(polar);
    if (gap > kMaxGapRad + kGapSlackRad) {
      const auto largest = largest_gap(polar);
      const double from = polar[at].theta;
      const double to = polar[(at + 1) % polar.size()].theta;
      return P{polar[at].index, std::nullopt,
               pre + "no points between " + deg_text(from) + " and " + deg_text(to) +
                   " deg about the path's LSC centre, a gap of " + deg_text(gap) +
                   " deg besides the gap of " + deg_text(largest.first) +
                   " deg: the points form more than one arc; a circular test measures one "
                   "circle or one arc (no second gap above " +
                   deg_text(kMaxGapRad) + " deg)"};
    }
  }
  return std::nullopt;
}

RadialDeviation radial_deviation_about(const Eigen::Vector2d& p, const RadialReference& reference) {
  return {angle_about(p, reference.centre_mm),
          (p - reference.centre_mm).norm() - reference.radius_mm};
}

CircularTestResult evaluate_circular_test(const CircularTestInput& input) {
  if (const auto p = find_circular_test_problem(input)) {
    std::string what = "evaluate_circular_test: ";
    if (p->index) what += "points[" + std::to_string(*p->index) + "]: ";
    what += p->message;
    if (p->first_index) what += " (points[" + std::to_string(*p->first_index) + "])";
    throw std::invalid_argument(what);
  }
  CircularTestResult out;
  out.plane = input.plane;
  const auto ccw = indices_of(input, PathDirection::Ccw);
  const auto cw = indices_of(input, PathDirection::Cw);
  if (!ccw.empty()) out.ccw = path_figures(input, PathDirection::Ccw, ccw);
  if (!cw.empty()) out.cw = path_figures(input, PathDirection::Cw, cw);

  std::vector<std::size_t> all(input.points.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  const auto pts = coordinates(input, all);
  const CircleFit fit = fit_or_throw(pts, "all points: ");
  out.lsc_centre_mm = fit.centre;
  out.lsc_radius_mm = fit.radius;
  out.G_mm = std::max(out.ccw ? out.ccw->G_mm : 0.0, out.cw ? out.cw->G_mm : 0.0);
  out.F_reference = reference_for(input, fit);
  std::tie(out.F_max_mm, out.F_min_mm) = radial_deviation(pts, out.F_reference);
  const auto polar_all = polar_sorted(input.points, all, fit.centre);
  out.arc = arc_of(polar_all);
  add_shape(polar_all, fit.radius, &out);
  if (out.ccw && out.cw) {
    out.G_b_mm = spread(polar_all);
    const auto a = polar_sorted(input.points, ccw, fit.centre);
    const auto b = polar_sorted(input.points, cw, fit.centre);
    out.H_mm = hysteresis(a, b);
    out.H_overlap_rad = out.H_mm ? arc_overlap(arc_of(a), arc_of(b)) : 0.0;
  }
  return out;
}

std::vector<std::string> iso230_4_conformance(const CircularTestResult& r) {
  std::vector<std::string> out;
  const auto whole = [](double rad) {
    return detail::quote_number(std::round(deg(rad) * 10) / 10);
  };
  for (const auto* p : {&r.ccw, &r.cw}) {
    if (!*p) continue;
    const CircularPathFigures& f = **p;
    const std::string pre = direction_prefix(f.direction);
    if (!f.arc.full_circle && f.arc.span_rad < kShortestArcRad) {
      out.push_back(pre + "an arc of " + whole(f.arc.span_rad) +
                    " deg, shorter than ISO 230-4's shortest partial arc (90 deg): the "
                    "least-squares circle of so short an arc, and G about it, are poorly "
                    "determined; give the nominal centre and radius for F");
    }
    // Intervals between points: n over a full circle, n - 1 along an arc.
    const int intervals = f.arc.full_circle ? f.point_count : f.point_count - 1;
    const double spacing = f.arc.span_rad / std::max(1, intervals);
    // 2 % above: angles about a fitted centre jitter round the nominal spacing.
    if (spacing > 1.02 * kSparsestSpacingRad) {
      const int needed = static_cast<int>(std::ceil(f.arc.span_rad / kSparsestSpacingRad - 1e-9)) +
                         (f.arc.full_circle ? 0 : 1);
      out.push_back(pre + std::to_string(f.point_count) + " points over " + whole(f.arc.span_rad) +
                    " deg, one every " + whole(spacing) +
                    " deg: G, a max - min of the radii, needs one every 10 deg or closer (" +
                    std::to_string(needed) +
                    " here) to read a shape of up to 4 lobes per turn within 6 %, and misses "
                    "reversal spikes narrower than the spacing");
    }
    if (!f.scale_mismatch_um_per_m) {
      out.push_back(pre + "the arc of " + whole(f.arc.span_rad) +
                    " deg does not resolve the 2θ shape (noise gain " +
                    detail::quote_number(std::round(f.shape_noise_gain * 10) / 10) +
                    " against a full circle, at most 3 taken): no scale mismatch or squareness "
                    "from this direction");
    }
  }
  if (static_cast<bool>(r.ccw) != static_cast<bool>(r.cw)) {
    out.push_back(std::string("measured in one direction only (") + (r.ccw ? "ccw" : "cw") +
                  "): ISO 230-4 traces both for the hysteresis H and the bidirectional G(b); "
                  "the scale mismatch and squareness of one direction include its reversal "
                  "errors");
  }
  if (r.ccw && r.cw) {
    const double covered = std::max(r.ccw->arc.span_rad, r.cw->arc.span_rad);
    if (!r.H_mm) {
      out.push_back("the two directions cover arcs with no angle in common: no hysteresis H");
    } else if (r.H_overlap_rad < 0.9 * covered) {  // not the one arc both ways
      out.push_back("the two directions cover different arcs: H compares them over the " +
                    whole(r.H_overlap_rad) + " deg they share");
    }
  }
  return out;
}

}  // namespace ncqual::solver

// SPDX-License-Identifier: Apache-2.0
#include "ncqual/solver/rotary_axes.hpp"

#include "ncqual/common/kinematics.hpp"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace ncqual::solver {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kArcsec = kPi / (180 * 3600);  // rad
constexpr double kDeg = kPi / 180;

Eigen::Matrix3d rx(double a) {
  return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()).toRotationMatrix();
}
Eigen::Matrix3d rz(double a) {
  return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

// A rotation by the rotation vector theta.
Eigen::Matrix3d rotation_by(const Eigen::Vector3d& theta) {
  if (theta.norm() == 0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(theta.norm(), theta.normalized()).toRotationMatrix();
}

const Eigen::Vector3d kPivot(1500, 800, 600);

ProbeGeometry nominal_geometry() {
  ProbeGeometry g;
  g.tool_length_mm = 250;
  g.stylus_offset_mm = Eigen::Vector2d(8, -5);
  return g;
}

AxisPosition axes(double w, double a, double c) {
  AxisPosition p;
  p.x_mm = kPivot.x();
  p.y_mm = kPivot.y();
  p.z_mm = kPivot.z();
  p.w_mm = w;
  p.a_rad = a;
  p.c_rad = c;
  return p;
}

// ---- Truth, written independently of the code under test ------------------------------------
//
// The true wrist: the pivot displaced by `pivot_offset`; the true target at (ox, oy, -(L + w))
// in the body frame (a target length and offset differing from the nominal ones); the checked
// axis tilted by the rotation `tilt` (a rotation vector perpendicular to the nominal axis); its
// angle in error by `angle_error(commanded)`.
struct TruthWrist {
  Eigen::Vector3d pivot_offset = Eigen::Vector3d::Zero();
  double length = 250;
  Eigen::Vector2d offset = Eigen::Vector2d(8, -5);
  Eigen::Vector3d tilt = Eigen::Vector3d::Zero();
  std::function<double(double)> angle_error = [](double) { return 0.0; };

  Eigen::Vector3d body_target(double w) const { return {offset.x(), offset.y(), -(length + w)}; }

  // C turning about R_tilt Z: p = P + dP + R_tilt Rz(c + dc) Rx(a) q.
  Eigen::Vector3d c_check(const AxisPosition& ax) const {
    return kPivot + pivot_offset +
           rotation_by(tilt) * rz(ax.c_rad + angle_error(ax.c_rad)) * rx(ax.a_rad) *
               body_target(ax.w_mm);
  }
  // A turning about R_tilt Rz(c) X: p = P + dP + R_tilt Rz(c) Rx(a + da) q.
  Eigen::Vector3d a_check(const AxisPosition& ax) const {
    return kPivot + pivot_offset +
           rotation_by(tilt) * rz(ax.c_rad) * rx(ax.a_rad + angle_error(ax.a_rad)) *
               body_target(ax.w_mm);
  }
};

struct Noise {
  std::mt19937_64 rng;
  double sigma;
  Eigen::Vector3d operator()() {
    std::normal_distribution<double> g(0, sigma > 0 ? sigma : 1);
    if (sigma == 0) return Eigen::Vector3d::Zero();
    return {g(rng), g(rng), g(rng)};
  }
};

// Estimator standard deviations of the 3-D circle fit for N(0, sigma) noise per coordinate,
// from the linearised least-squares problems at the truth (the test's own derivation):
//  - in the plane, residual e_i = |p_i - c| - r with Jacobian rows (-cos t_i, -sin t_i, -1) in
//    (cx, cy, r): covariance sigma^2 (J^T J)^-1;
//  - across it, height h_i = s_u u_i + s_v v_i + h_0 with (u_i, v_i) = R (cos t_i, sin t_i) the
//    in-plane position relative to the centre: covariance sigma^2 (K^T K)^-1, K rows
//    (u_i, v_i, 1); the slopes are the axis tilt, h_0 the centre's axial position;
//  - dA_i = tangential noise / R + (centre error . tau_i) / R: the centre depends on the radial
//    noise only, independent of the tangential, so var = (sigma^2 + tau_i^T C tau_i) / R^2;
//    the mean of dA: (sigma^2 / n + tau_bar^T C tau_bar) / R^2.
struct CircleSigmas {
  double centre_in_plane = 0, radius = 0, tilt = 0, centre_axial = 0;
  double dA_max = 0, dA_mean = 0;
};

CircleSigmas circle_sigmas(const std::vector<double>& t, double radius, double sigma) {
  Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero(), ktk = Eigen::Matrix3d::Zero();
  for (double ti : t) {
    const Eigen::Vector3d j(-std::cos(ti), -std::sin(ti), -1);
    const Eigen::Vector3d k(radius * std::cos(ti), radius * std::sin(ti), 1);
    jtj += j * j.transpose();
    ktk += k * k.transpose();
  }
  const Eigen::Matrix3d c = sigma * sigma * jtj.inverse();
  const Eigen::Matrix3d h = sigma * sigma * ktk.inverse();
  CircleSigmas s;
  s.centre_in_plane = std::sqrt(std::max(c(0, 0), c(1, 1)));
  s.radius = std::sqrt(c(2, 2));
  s.tilt = std::sqrt(std::max(h(0, 0), h(1, 1)));
  s.centre_axial = std::sqrt(h(2, 2));
  Eigen::Vector2d tau_bar = Eigen::Vector2d::Zero();
  const Eigen::Matrix2d cc = c.topLeftCorner<2, 2>();
  for (double ti : t) {
    const Eigen::Vector2d tau(-std::sin(ti), std::cos(ti));
    tau_bar += tau / static_cast<double>(t.size());
    s.dA_max = std::max(s.dA_max, std::sqrt(sigma * sigma + tau.dot(cc * tau)) / radius);
  }
  s.dA_mean =
      std::sqrt(sigma * sigma / static_cast<double>(t.size()) + tau_bar.dot(cc * tau_bar)) / radius;
  return s;
}

template <typename F>
std::string refusal(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

// ---- C ---------------------------------------------------------------------------------------

// C stepped 0 .. 345 deg by 15 with A held at 45 deg, W = 0.
std::vector<RotaryPoint> c_points(const TruthWrist& truth, double sigma, std::uint64_t seed,
                                  double a = 45 * kDeg, int count = 24, double step = 15 * kDeg,
                                  double start = 0) {
  Noise noise{std::mt19937_64(seed), sigma};
  std::vector<RotaryPoint> pts;
  for (int i = 0; i < count; ++i) {
    const AxisPosition ax = axes(0, a, start + step * i);
    pts.push_back({"C" + std::to_string(i), ax, truth.c_check(ax) + noise()});
  }
  return pts;
}

TEST(RotaryAxes, PerfectCAxisGivesZero) {
  const RotaryCircleResult r =
      analyze_circle_axis(RotaryAxis::C, c_points(TruthWrist{}, 0, 1), nominal_geometry());
  // Nominal by hand: Rx(45) (8, -5, -250) = (8, -5 cos45 + 250 sin45, -5 sin45 - 250 cos45);
  // radius = |(8, 173.24)|, centre = P + (0, 0, -180.31).
  const double y = -5 * std::cos(kPi / 4) + 250 * std::sin(kPi / 4);
  const double z = -5 * std::sin(kPi / 4) - 250 * std::cos(kPi / 4);
  EXPECT_NEAR(r.nominal_radius_mm, std::hypot(8.0, y), 1e-9);
  EXPECT_NEAR((r.nominal_centre_mm - (kPivot + Eigen::Vector3d(0, 0, z))).norm(), 0, 1e-9);
  EXPECT_NEAR(r.radius_error_mm, 0, 1e-9);
  EXPECT_NEAR(r.centre_offset_mm.norm(), 0, 1e-9);
  EXPECT_NEAR(r.tilt_urad.norm(), 0, 1e-6);
  EXPECT_NEAR(r.dA_max_abs_arcsec, 0, 1e-6);
  EXPECT_NEAR(r.dR_max_abs_mm, 0, 1e-9);
  EXPECT_NEAR(r.axial_max_abs_mm, 0, 1e-9);
  EXPECT_NEAR(r.arc_coverage_rad, 2 * kPi - 15 * kDeg, 1e-12);
  EXPECT_EQ(r.points.size(), 24u);
}

// Hand-worked sign: every point measured where the nominal target would be at c + 0.001 rad: the
// axis turned further than commanded, dA = +0.001 rad = +206.26 arcsec everywhere, dR = 0.
TEST(RotaryAxes, CAxisTurningFurtherThanCommandedHasPositiveDa) {
  auto pts = c_points(TruthWrist{}, 0, 1);
  for (auto& p : pts) {
    AxisPosition moved = p.commanded;
    moved.c_rad += 0.001;
    p.measured_master_mm = stylus_ball_centre(moved, nominal_geometry());
  }
  const RotaryCircleResult r = analyze_circle_axis(RotaryAxis::C, pts, nominal_geometry());
  EXPECT_NEAR(r.dA_mean_arcsec, 0.001 / kArcsec, 1e-6);
  EXPECT_NEAR(r.dA_range_arcsec, 0, 1e-6);
  for (const auto& p : r.points) {
    EXPECT_NEAR(p.dA_rad, 0.001, 1e-12);
    EXPECT_NEAR(p.tangential_mm, 0.001 * r.nominal_radius_mm, 1e-9);
    EXPECT_NEAR(p.dR_mm, 0, 1e-9);
  }
}

// A C axis with every error at once, noise 3 um, several seeds. Expected values from the truth's
// geometry: tilt = the injected rotation vector's (X, Y) components; centre = P + dP +
// R_tilt (0, 0, (Rx(a) q_true)_z); radius = |(Rx(a) q_true)_xy|; dA_i = angle error at c_i plus
// the turn of the true zero direction (Rx(a) q_true)_xy from the nominal one (the target offset
// error); dR_i = the radius error. Bounds 5 sigma (circle_sigmas); dR_i: its own noise plus the
// centre's, 5 (sigma + sigma_centre).
TEST(RotaryAxes, CAxisRecoversTiltLocationZeroOffsetAndRadiusWithinNoiseBounds) {
  TruthWrist truth;
  truth.pivot_offset = Eigen::Vector3d(0.05, -0.03, 0.02);
  truth.length = 250.04;
  truth.offset = Eigen::Vector2d(8.02, -5.01);
  truth.tilt = Eigen::Vector3d(60e-6, -40e-6, 0);
  const double zero = 20 * kArcsec, twice = 8 * kArcsec;
  truth.angle_error = [=](double c) { return zero + twice * std::sin(2 * c); };
  const double a = 45 * kDeg, sigma = 0.003;
  const ProbeGeometry nominal = nominal_geometry();

  const Eigen::Vector3d q_true = rx(a) * truth.body_target(0);
  const Eigen::Vector3d q_nom = rx(a) * Eigen::Vector3d(8, -5, -250);
  const Eigen::Vector3d centre_nom = kPivot + Eigen::Vector3d(0, 0, q_nom.z());
  const Eigen::Vector3d centre_true =
      kPivot + truth.pivot_offset + rotation_by(truth.tilt) * Eigen::Vector3d(0, 0, q_true.z());
  const double radius_nom = q_nom.head<2>().norm(), radius_true = q_true.head<2>().norm();
  const double zero_turn = std::atan2(q_true.y(), q_true.x()) - std::atan2(q_nom.y(), q_nom.x());

  std::vector<double> t;
  for (int i = 0; i < 24; ++i) t.push_back(15 * kDeg * i);
  const CircleSigmas s = circle_sigmas(t, radius_nom, sigma);

  for (std::uint64_t seed : {101u, 102u, 103u, 104u, 105u}) {
    const RotaryCircleResult r =
        analyze_circle_axis(RotaryAxis::C, c_points(truth, sigma, seed), nominal);
    EXPECT_NEAR(r.tilt_urad(0), 60, 5 * s.tilt * 1e6) << seed;
    EXPECT_NEAR(r.tilt_urad(1), -40, 5 * s.tilt * 1e6) << seed;
    const Eigen::Vector3d offset = centre_true - centre_nom;
    const double centre_bound = 5 * std::hypot(s.centre_in_plane, s.centre_axial);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(r.centre_offset_mm(k), offset(k), centre_bound) << seed << " " << k;
    }
    EXPECT_NEAR(r.radius_error_mm, radius_true - radius_nom, 5 * s.radius) << seed;
    EXPECT_NEAR(r.dA_mean_arcsec, (zero + zero_turn) / kArcsec, 5 * s.dA_mean / kArcsec) << seed;
    for (const auto& p : r.points) {
      const double expected = zero + twice * std::sin(2 * p.commanded_rad) + zero_turn;
      EXPECT_NEAR(p.dA_rad, expected, 5 * s.dA_max) << seed << " " << p.label;
      EXPECT_NEAR(p.dR_mm, radius_true - radius_nom, 5 * (sigma + s.centre_in_plane)) << seed;
      EXPECT_LT(std::abs(p.axial_mm), 5 * (sigma + s.centre_axial + radius_nom * s.tilt));
    }
    // The 2-per-revolution error shows in the range: 2 * 8 arcsec, give or take the noise.
    EXPECT_NEAR(r.dA_range_arcsec, 16, 2 * 5 * s.dA_max / kArcsec) << seed;
    // The injected errors are well above the bounds (the test would notice them missing).
    EXPECT_GT(offset.norm(), 5 * centre_bound);
    EXPECT_GT(zero / kArcsec, 5 * 5 * s.dA_mean / kArcsec);
  }
}

// ---- A ---------------------------------------------------------------------------------------

// A stepped -90 .. +90 deg by 15 (13 points) with C held at 30 deg, W held at 20 mm.
std::vector<RotaryPoint> a_points(const TruthWrist& truth, double sigma, std::uint64_t seed,
                                  double c = 30 * kDeg) {
  Noise noise{std::mt19937_64(seed), sigma};
  std::vector<RotaryPoint> pts;
  for (int i = 0; i <= 12; ++i) {
    const AxisPosition ax = axes(20, -90 * kDeg + 15 * kDeg * i, c);
    pts.push_back({"A" + std::to_string(i), ax, truth.a_check(ax) + noise()});
  }
  return pts;
}

TEST(RotaryAxes, PerfectAAxisGivesZero) {
  const RotaryCircleResult r =
      analyze_circle_axis(RotaryAxis::A, a_points(TruthWrist{}, 0, 1), nominal_geometry());
  // Nominal by hand: axis Rz(30) X through P, centre P + 8 Rz(30) X, radius |(-5, -270)|.
  const Eigen::Vector3d k(std::cos(30 * kDeg), std::sin(30 * kDeg), 0);
  EXPECT_NEAR((r.nominal_axis_direction - k).norm(), 0, 1e-12);
  EXPECT_NEAR((r.nominal_centre_mm - (kPivot + 8 * k)).norm(), 0, 1e-9);
  EXPECT_NEAR(r.nominal_radius_mm, std::hypot(5.0, 270.0), 1e-9);
  EXPECT_NEAR(r.radius_error_mm, 0, 1e-9);
  EXPECT_NEAR(r.centre_offset_mm.norm(), 0, 1e-9);
  EXPECT_NEAR(r.tilt_urad.norm(), 0, 1e-6);
  EXPECT_NEAR(r.dA_max_abs_arcsec, 0, 1e-6);
  EXPECT_NEAR(r.arc_coverage_rad, kPi, 1e-12);
  // Hand-worked sign: nominal targets at a - 0.0005 rad: dA = -0.0005 rad = -103.13 arcsec.
  auto pts = a_points(TruthWrist{}, 0, 1);
  for (auto& p : pts) {
    AxisPosition moved = p.commanded;
    moved.a_rad -= 0.0005;
    p.measured_master_mm = stylus_ball_centre(moved, nominal_geometry());
  }
  const RotaryCircleResult lag = analyze_circle_axis(RotaryAxis::A, pts, nominal_geometry());
  EXPECT_NEAR(lag.dA_mean_arcsec, -0.0005 / kArcsec, 1e-6);
}

// An A axis with every error, on a half circle. Tilt components about (Rz(c) Y, Z); centre
// = P + dP + R_tilt Rz(c) (ox_true, 0, 0); radius |(oy, L + w)|_true; zero turn = the true body
// (y, z) direction of the target against the nominal, atan2(z, y); angle error: a zero offset and
// an angle scale error of 1e-4 rad/rad. Bounds from circle_sigmas on the half circle (whose
// centre is worse determined along its symmetry line: about 3.3 sigma / sqrt(n)).
TEST(RotaryAxes, AAxisRecoversTiltLocationZeroOffsetAndRadiusWithinNoiseBounds) {
  const double c = 30 * kDeg, sigma = 0.003, w = 20;
  const Eigen::Vector3d head_y(-std::sin(c), std::cos(c), 0);
  TruthWrist truth;
  truth.pivot_offset = Eigen::Vector3d(-0.04, 0.06, -0.03);
  truth.length = 249.97;
  truth.offset = Eigen::Vector2d(8.0, -4.98);
  truth.tilt = 80e-6 * head_y + (-50e-6) * Eigen::Vector3d::UnitZ();
  const double zero = -15 * kArcsec, per_rad = 1e-4;
  truth.angle_error = [=](double a) { return zero + per_rad * a; };
  const ProbeGeometry nominal = nominal_geometry();

  const Eigen::Vector3d k(std::cos(c), std::sin(c), 0);
  const Eigen::Vector3d centre_nom = kPivot + 8 * k;
  const Eigen::Vector3d centre_true =
      kPivot + truth.pivot_offset + rotation_by(truth.tilt) * rz(c) * Eigen::Vector3d(8.0, 0, 0);
  const double radius_nom = std::hypot(5.0, 250 + w);
  const double radius_true = std::hypot(truth.offset.y(), truth.length + w);
  const double zero_turn =
      std::atan2(-(truth.length + w), truth.offset.y()) - std::atan2(-(250 + w), -5.0);

  std::vector<double> t;
  for (int i = 0; i <= 12; ++i) t.push_back(-90 * kDeg + 15 * kDeg * i);
  const CircleSigmas s = circle_sigmas(t, radius_nom, sigma);

  for (std::uint64_t seed : {201u, 202u, 203u, 204u, 205u}) {
    const RotaryCircleResult r =
        analyze_circle_axis(RotaryAxis::A, a_points(truth, sigma, seed), nominal);
    EXPECT_NEAR((r.tilt_reference_1 - head_y).norm(), 0, 1e-12);
    EXPECT_NEAR(r.tilt_urad(0), 80, 5 * s.tilt * 1e6) << seed;
    EXPECT_NEAR(r.tilt_urad(1), -50, 5 * s.tilt * 1e6) << seed;
    const Eigen::Vector3d offset = centre_true - centre_nom;
    const double centre_bound = 5 * std::hypot(s.centre_in_plane, s.centre_axial);
    for (int j = 0; j < 3; ++j) {
      EXPECT_NEAR(r.centre_offset_mm(j), offset(j), centre_bound) << seed << " " << j;
    }
    EXPECT_NEAR(r.radius_error_mm, radius_true - radius_nom, 5 * s.radius) << seed;
    double mean_expected = 0;
    for (const auto& p : r.points) {
      const double expected = zero + per_rad * p.commanded_rad + zero_turn;
      mean_expected += expected / static_cast<double>(r.points.size());
      EXPECT_NEAR(p.dA_rad, expected, 5 * s.dA_max) << seed << " " << p.label;
      EXPECT_NEAR(p.dR_mm, radius_true - radius_nom, 5 * (sigma + s.centre_in_plane)) << seed;
    }
    EXPECT_NEAR(r.dA_mean_arcsec, mean_expected / kArcsec, 5 * s.dA_mean / kArcsec) << seed;
  }
}

// ---- W ---------------------------------------------------------------------------------------

// W stepped 0 .. 400 by 50 (9 points), A = 30 deg, C = -60 deg held. The true spindle moves along
// the tool direction turned by tilt = t1 body X + t2 body Y, (1 + scale) per commanded mm, with
// a straightness sag b (1 - ((w - 200)/200)^2) along body X.
struct TruthW {
  double t1 = 0, t2 = 0, scale = 0, sag = 0;
  Eigen::Vector3d pivot_offset = Eigen::Vector3d::Zero();
};

std::vector<RotaryPoint> w_points(const TruthW& truth, double sigma, std::uint64_t seed,
                                  std::vector<Eigen::Vector3d>* clean = nullptr) {
  const double a = 30 * kDeg, c = -60 * kDeg;
  const Eigen::Matrix3d body = rz(c) * rx(a);
  const Eigen::Vector3d d_nom = body * Eigen::Vector3d(0, 0, -1);
  const Eigen::Vector3d d_true =
      rotation_by(truth.t1 * body.col(0) + truth.t2 * body.col(1)) * d_nom;
  Noise noise{std::mt19937_64(seed), sigma};
  std::vector<RotaryPoint> pts;
  for (int i = 0; i <= 8; ++i) {
    const double w = 50.0 * i;
    const double u = (w - 200) / 200;
    const Eigen::Vector3d p = kPivot + truth.pivot_offset + body * Eigen::Vector3d(8, -5, -250) +
                              (1 + truth.scale) * w * d_true +
                              truth.sag * (1 - u * u) * body.col(0);
    if (clean) clean->push_back(p);
    pts.push_back({"W" + std::to_string(i), axes(w, a, c), p + noise()});
  }
  return pts;
}

TEST(RotaryAxes, PerfectWAxisGivesZero) {
  const WAxisResult r = analyze_w_axis(w_points(TruthW{}, 0, 1), nominal_geometry());
  EXPECT_NEAR((r.nominal_direction - tool_direction(30 * kDeg, -60 * kDeg)).norm(), 0, 1e-12);
  EXPECT_NEAR(r.tilt_urad.norm(), 0, 1e-6);
  EXPECT_NEAR(r.w_scale_um_per_m, 0, 1e-6);
  EXPECT_NEAR(r.straightness_mm, 0, 1e-9);
  EXPECT_NEAR(r.positioning_range_mm, 0, 1e-9);
  EXPECT_NEAR(r.mean_deviation_mm.norm(), 0, 1e-9);
}

// Bounds (5 sigma): the line's direction (each component) and the scale are least-squares slopes,
// sigma / sqrt(sum (w - mean w)^2) = 0.003 / 387 = 7.7 urad (um/m); the positioning error of
// point i is a difference of two noisy points along the line, sigma sqrt 2; the straightness is
// the largest perpendicular distance, moved by at most the norm of one point's 2-D perpendicular
// noise (per-component sigma at most; the norm exceeds 5 sigma with probability exp(-12.5)).
TEST(RotaryAxes, WAxisRecoversTiltScaleAndStraightnessWithinNoiseBounds) {
  TruthW truth;
  truth.t1 = 150e-6;
  truth.t2 = -90e-6;
  truth.scale = 200e-6;
  truth.sag = 0.03;
  truth.pivot_offset = Eigen::Vector3d(0.01, 0.02, -0.05);
  const double sigma = 0.003;
  double ss = 0;
  for (int i = 0; i <= 8; ++i) ss += std::pow(50.0 * i - 200, 2);
  const double slope_sigma = sigma / std::sqrt(ss);
  // Straightness of the clean sag about the TLS line (the line runs at the sag's mean offset):
  // max |s_i - mean s|.
  double mean_sag = 0;
  std::vector<double> sag;
  for (int i = 0; i <= 8; ++i) {
    const double u = (50.0 * i - 200) / 200;
    sag.push_back(truth.sag * (1 - u * u));
    mean_sag += sag.back() / 9;
  }
  double straightness = 0;
  for (double v : sag) straightness = std::max(straightness, std::abs(v - mean_sag));

  for (std::uint64_t seed : {301u, 302u, 303u, 304u, 305u}) {
    const WAxisResult r = analyze_w_axis(w_points(truth, sigma, seed), nominal_geometry());
    EXPECT_NEAR(r.tilt_urad(0), 150, 5 * slope_sigma * 1e6) << seed;
    EXPECT_NEAR(r.tilt_urad(1), -90, 5 * slope_sigma * 1e6) << seed;
    EXPECT_NEAR(r.w_scale_um_per_m, 200, 5 * slope_sigma * 1e6) << seed;
    EXPECT_NEAR(r.straightness_mm, straightness, 5 * sigma) << seed;
    for (const auto& p : r.points) {
      EXPECT_NEAR(p.positioning_error_mm, truth.scale * p.commanded_w_mm,
                  5 * sigma * std::sqrt(2.0))
          << seed << " " << p.label;
    }
    EXPECT_NEAR(r.positioning_range_mm, truth.scale * 400, 2 * 5 * sigma * std::sqrt(2.0));
  }
}

// ---- Dispatch ----------------------------------------------------------------------------------

TEST(RotaryAxes, AnalyzeRotaryAxisDispatches) {
  const RotaryAxisResult c =
      analyze_rotary_axis(RotaryAxis::C, c_points(TruthWrist{}, 0, 1), nominal_geometry());
  EXPECT_TRUE(c.circle.has_value());
  EXPECT_FALSE(c.w.has_value());
  const RotaryAxisResult w =
      analyze_rotary_axis(RotaryAxis::W, w_points(TruthW{}, 0, 1), nominal_geometry());
  EXPECT_TRUE(w.w.has_value());
  EXPECT_FALSE(w.circle.has_value());
  EXPECT_EQ(rotary_axis_name(RotaryAxis::A), "A");
}

// ---- Refusals ----------------------------------------------------------------------------------

TEST(RotaryAxesRefusals, TooFewPoints) {
  auto pts = c_points(TruthWrist{}, 0, 1);
  pts.resize(4);
  // 4 points at 0 .. 45 deg: the count is checked first.
  const std::string why =
      refusal([&] { analyze_circle_axis(RotaryAxis::C, pts, nominal_geometry()); });
  EXPECT_NE(why.find("4 points given; at least 5"), std::string::npos) << why;
  auto w = w_points(TruthW{}, 0, 1);
  w.resize(3);
  EXPECT_NE(refusal([&] { analyze_w_axis(w, nominal_geometry()); }).find("3 points given"),
            std::string::npos);
}

TEST(RotaryAxesRefusals, AxesNotHeld) {
  const ProbeGeometry g = nominal_geometry();
  auto pts = c_points(TruthWrist{}, 0, 1);
  pts[5].commanded.x_mm += 0.01;
  std::string why = refusal([&] { analyze_circle_axis(RotaryAxis::C, pts, g); });
  EXPECT_NE(why.find("point 'C5' commanded.x_mm = 1500.01"), std::string::npos) << why;
  pts = c_points(TruthWrist{}, 0, 1);
  pts[7].commanded.a_rad += 1e-3;  // C check: A must be held
  why = refusal([&] { analyze_circle_axis(RotaryAxis::C, pts, g); });
  EXPECT_NE(why.find("point 'C7' commanded.a_rad"), std::string::npos) << why;
  pts = c_points(TruthWrist{}, 0, 1);
  pts[2].commanded.w_mm = 5;  // and W
  EXPECT_NE(refusal([&] {
              analyze_circle_axis(RotaryAxis::C, pts, g);
            }).find("point 'C2' commanded.w_mm = 5"),
            std::string::npos);
  auto a = a_points(TruthWrist{}, 0, 1);
  a[3].commanded.c_rad += 1e-3;  // A check: C must be held
  EXPECT_NE(
      refusal([&] { analyze_circle_axis(RotaryAxis::A, a, g); }).find("point 'A3' commanded.c_rad"),
      std::string::npos);
  auto w = w_points(TruthW{}, 0, 1);
  w[4].commanded.c_rad += 1e-3;  // W check: A and C held
  EXPECT_NE(refusal([&] { analyze_w_axis(w, g); }).find("point 'W4' commanded.c_rad"),
            std::string::npos);
  w = w_points(TruthW{}, 0, 1);
  w[6].commanded.a_rad = 0;
  EXPECT_NE(refusal([&] { analyze_w_axis(w, g); }).find("point 'W6' commanded.a_rad = 0"),
            std::string::npos);
  w = w_points(TruthW{}, 0, 1);
  w[1].commanded.z_mm -= 1;
  EXPECT_NE(refusal([&] { analyze_w_axis(w, g); }).find("point 'W1' commanded.z_mm = 599"),
            std::string::npos);
}

TEST(RotaryAxesRefusals, NonFiniteValues) {
  const ProbeGeometry g = nominal_geometry();
  auto pts = c_points(TruthWrist{}, 0, 1);
  pts[3].measured_master_mm.y() = std::numeric_limits<double>::quiet_NaN();
  std::string why = refusal([&] { analyze_circle_axis(RotaryAxis::C, pts, g); });
  EXPECT_NE(why.find("point 'C3' measured_master_mm = ("), std::string::npos) << why;
  pts = c_points(TruthWrist{}, 0, 1);
  pts[9].commanded.c_rad = std::numeric_limits<double>::infinity();
  why = refusal([&] { analyze_circle_axis(RotaryAxis::C, pts, g); });
  EXPECT_NE(why.find("point 'C9' commanded.c_rad = inf"), std::string::npos) << why;
  ProbeGeometry bad = g;
  bad.tool_length_mm = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(refusal([&] {
              analyze_w_axis(w_points(TruthW{}, 0, 1), bad);
            }).find("geometry.tool_length_mm = nan"),
            std::string::npos);
}

TEST(RotaryAxesRefusals, DuplicatePositions) {
  const ProbeGeometry g = nominal_geometry();
  auto pts = c_points(TruthWrist{}, 0, 1);
  pts[6].commanded.c_rad = pts[0].commanded.c_rad + 2 * kPi;  // the same angle, one turn on
  std::string why = refusal([&] { analyze_circle_axis(RotaryAxis::C, pts, g); });
  EXPECT_NE(why.find("points 'C0' and 'C6' have the same commanded.c_rad"), std::string::npos)
      << why;
  auto w = w_points(TruthW{}, 0, 1);
  w[5].commanded.w_mm = w[2].commanded.w_mm;
  why = refusal([&] { analyze_w_axis(w, g); });
  EXPECT_NE(why.find("points 'W2' and 'W5' have the same commanded.w_mm = 100"), std::string::npos)
      << why;
}

TEST(RotaryAxesRefusals, ArcTooShort) {
  // 7 points 0 .. 60 deg: coverage 60 deg < 90.
  const auto pts = c_points(TruthWrist{}, 0, 1, 45 * kDeg, 7, 10 * kDeg);
  const std::string why =
      refusal([&] { analyze_circle_axis(RotaryAxis::C, pts, nominal_geometry()); });
  EXPECT_NE(why.find("cover an arc of 60 degrees"), std::string::npos) << why;
  // Coverage counts across 0: 330 .. 70 deg (11 points by 10 deg) covers 100 deg: accepted.
  const auto across = c_points(TruthWrist{}, 0, 1, 45 * kDeg, 11, 10 * kDeg, -30 * kDeg);
  EXPECT_EQ(refusal([&] { analyze_circle_axis(RotaryAxis::C, across, nominal_geometry()); }), "");
}

TEST(RotaryAxesRefusals, TargetOnTheAxisWrongAxisAndWrongTravel) {
  ProbeGeometry on_axis = nominal_geometry();
  on_axis.stylus_offset_mm = Eigen::Vector2d::Zero();
  // C check with A = 0 and no offset: the target sits on the C axis.
  const auto pts = c_points(TruthWrist{}, 0, 1, 0.0);
  std::string why = refusal([&] { analyze_circle_axis(RotaryAxis::C, pts, on_axis); });
  EXPECT_NE(why.find("the nominal target is 0 mm from the C axis"), std::string::npos) << why;
  why = refusal([&] { analyze_circle_axis(RotaryAxis::W, pts, nominal_geometry()); });
  EXPECT_NE(why.find("axis = W is not a rotary axis"), std::string::npos) << why;
  // W readings in inches.
  auto w = w_points(TruthW{}, 0, 1);
  for (auto& p : w) p.measured_master_mm /= 25.4;
  why = refusal([&] { analyze_w_axis(w, nominal_geometry()); });
  EXPECT_NE(why.find("measured travel along the fitted line is 0.039"), std::string::npos) << why;
}

TEST(RotaryAxesRefusals, MeasuredPointsThatAreNoCircle) {
  // All measured points at one place (the tracker lost the target and repeated its last reading).
  auto pts = c_points(TruthWrist{}, 0, 1);
  for (auto& p : pts) p.measured_master_mm = pts[0].measured_master_mm;
  std::string why = refusal([&] { analyze_circle_axis(RotaryAxis::C, pts, nominal_geometry()); });
  EXPECT_NE(why.find("analyze_circle_axis: the measured_master_mm of the C points all coincide"),
            std::string::npos)
      << why;
  // On a straight line.
  for (std::size_t i = 0; i < pts.size(); ++i) {
    pts[i].measured_master_mm = kPivot + Eigen::Vector3d(10.0 * static_cast<double>(i), 0, 0);
  }
  why = refusal([&] { analyze_circle_axis(RotaryAxis::C, pts, nominal_geometry()); });
  EXPECT_NE(why.find("are (nearly) collinear"), std::string::npos) << why;
}

}  // namespace
}  // namespace ncqual::solver

// SPDX-License-Identifier: Apache-2.0
// ISO 230-4 circular test evaluation: tiny paths worked by hand (G, G(b), F, H, the 2θ shape),
// simulated paths with known radius error, centre offset, scale mismatch, squareness, backlash
// and noise, and every refusal.
#include "ncqual/solver/circular_test.hpp"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace ncqual::solver {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kUm = 1e-3;     // mm per µm
constexpr double kExact = 1e-9;  // mm; hand-worked figures, up to the fit's convergence

double rad(double deg) { return deg * kPi / 180; }

// Points at angles_deg with radii 10 mm + dev_um[k] µm about (0, 0).
void add_path(CircularTestInput* in, PathDirection d, const std::vector<double>& angles_deg,
              const std::vector<double>& dev_um) {
  for (std::size_t k = 0; k < angles_deg.size(); ++k) {
    in->points.push_back(circular_point_from_polar(rad(angles_deg[k]), 10 + dev_um[k] * kUm, d));
  }
}

const std::vector<double> kEight{0, 45, 90, 135, 180, 225, 270, 315};

// The hand-worked case. Both paths at the angles 0, 45, ..., 315 deg, radius 10 mm plus (µm):
//   ccw: 2, 0, -2, 0, 2, 0, -2, 0  = 2 cos 2θ
//   cw:  1, 2, 1, 0, 1, 2, 1, 0    = 1 + sin 2θ
// On 8 evenly spaced angles cos 2θ and sin 2θ are orthogonal to cos θ and sin θ, so the
// geometric LSC condition Σ e_i (cos θ_i, sin θ_i) = 0 holds at centre (0, 0), and the LSC
// radius is the mean radius: ccw 10.000, cw 10.001, both paths 10.0005 mm.
CircularTestInput hand_case() {
  CircularTestInput in;
  in.plane = Plane::YZ;
  add_path(&in, PathDirection::Ccw, kEight, {2, 0, -2, 0, 2, 0, -2, 0});
  add_path(&in, PathDirection::Cw, kEight, {1, 2, 1, 0, 1, 2, 1, 0});
  return in;
}

TEST(CircularTest, HandWorkedDeviationsAboutTheLsc) {
  const CircularTestResult res = evaluate_circular_test(hand_case());
  EXPECT_EQ(res.plane, Plane::YZ);
  ASSERT_TRUE(res.ccw && res.cw);
  // ccw: G = 10.002 - 9.998 = 0.004; F about its LSC (10.000): +0.002 / -0.002.
  EXPECT_EQ(res.ccw->point_count, 8);
  EXPECT_NEAR(res.ccw->lsc_centre_mm.norm(), 0, kExact);
  EXPECT_NEAR(res.ccw->lsc_radius_mm, 10.0, kExact);
  EXPECT_NEAR(res.ccw->G_mm, 0.004, kExact);
  EXPECT_NEAR(res.ccw->F_max_mm, 0.002, kExact);
  EXPECT_NEAR(res.ccw->F_min_mm, -0.002, kExact);
  EXPECT_FALSE(res.ccw->F_reference.nominal_centre);
  EXPECT_FALSE(res.ccw->F_reference.nominal_radius);
  EXPECT_NEAR(res.ccw->max_gap_rad, rad(45), 1e-12);
  // cw: G = 10.002 - 10.000 = 0.002; F about its LSC (10.001): +0.001 / -0.001.
  EXPECT_NEAR(res.cw->lsc_radius_mm, 10.001, kExact);
  EXPECT_NEAR(res.cw->G_mm, 0.002, kExact);
  EXPECT_NEAR(res.cw->F_max_mm, 0.001, kExact);
  EXPECT_NEAR(res.cw->F_min_mm, -0.001, kExact);
  // Both: LSC 10.0005; G(b) = 10.002 - 9.998 = 0.004; F = 10.002 - 10.0005 = 0.0015 and
  // 9.998 - 10.0005 = -0.0025; G = max(0.004, 0.002).
  EXPECT_NEAR(res.lsc_centre_mm.norm(), 0, kExact);
  EXPECT_NEAR(res.lsc_radius_mm, 10.0005, kExact);
  EXPECT_NEAR(res.G_mm, 0.004, kExact);
  ASSERT_TRUE(res.G_b_mm && res.H_mm);
  EXPECT_NEAR(*res.G_b_mm, 0.004, kExact);
  EXPECT_NEAR(res.F_max_mm, 0.0015, kExact);
  EXPECT_NEAR(res.F_min_mm, -0.0025, kExact);
  // H: cw - ccw at each angle (µm): -1, 2, 3, 0, -1, 2, 3, 0 -> H = 3 µm.
  EXPECT_NEAR(*res.H_mm, 0.003, kExact);
}

TEST(CircularTest, HandWorkedShape) {
  const CircularTestResult res = evaluate_circular_test(hand_case());
  // ccw: r - R = 2 µm cos 2θ: a2 = 0.002, scale mismatch 2 a2 / R = 2 * 0.002 / 10 = 400 µm/m.
  EXPECT_NEAR(res.ccw->harmonics->a2_mm, 0.002, kExact);
  EXPECT_NEAR(res.ccw->harmonics->b2_mm, 0, kExact);
  EXPECT_NEAR(res.ccw->harmonics->a0_mm, 0, kExact);
  EXPECT_NEAR(res.ccw->harmonics->residual_rms_mm, 0, kExact);
  EXPECT_NEAR(res.ccw->scale_mismatch_um_per_m.value(), 400, 1e-4);
  EXPECT_NEAR(res.ccw->squareness_urad.value(), 0, 1e-4);
  // cw: r - 10.001 = 1 µm sin 2θ: b2 = 0.001, squareness -2 b2 / R = -2e-3 / 10.001 rad.
  EXPECT_NEAR(res.cw->harmonics->b2_mm, 0.001, kExact);
  EXPECT_NEAR(res.cw->squareness_urad.value(), -2e-3 / 10.001 * 1e6, 1e-4);
  EXPECT_NEAR(res.cw->scale_mismatch_um_per_m.value(), 0, 1e-4);
  // Both (same angles): the coefficients average: a2 = 1 µm, b2 = 0.5 µm about R = 10.0005.
  EXPECT_NEAR(res.harmonics->a2_mm, 0.001, kExact);
  EXPECT_NEAR(res.harmonics->b2_mm, 0.0005, kExact);
  EXPECT_NEAR(res.scale_mismatch_um_per_m.value(), 2 * 0.001 / 10.0005 * 1e6, 1e-4);
  EXPECT_NEAR(res.squareness_urad.value(), -2 * 0.0005 / 10.0005 * 1e6, 1e-4);
}

TEST(CircularTest, HandWorkedRadialDeviationAboutTheNominal) {
  CircularTestInput in = hand_case();
  in.nominal_radius_mm = 9.999;
  in.nominal_centre_mm = Eigen::Vector2d(0, 0);
  const CircularTestResult res = evaluate_circular_test(in);
  ASSERT_TRUE(res.ccw && res.cw);
  // About (0, 0), R0 = 9.999: ccw radii 9.998..10.002 -> +0.003 / -0.001; cw 10.000..10.002
  // -> +0.003 / +0.001; all -> +0.003 / -0.001.
  EXPECT_TRUE(res.F_reference.nominal_centre && res.F_reference.nominal_radius);
  EXPECT_NEAR(res.ccw->F_max_mm, 0.003, kExact);
  EXPECT_NEAR(res.ccw->F_min_mm, -0.001, kExact);
  EXPECT_NEAR(res.cw->F_max_mm, 0.003, kExact);
  EXPECT_NEAR(res.cw->F_min_mm, 0.001, kExact);
  EXPECT_NEAR(res.F_max_mm, 0.003, kExact);
  EXPECT_NEAR(res.F_min_mm, -0.001, kExact);
  EXPECT_DOUBLE_EQ(res.F_reference.radius_mm, 9.999);

  // Nominal centre (0.001, 0) and no R0: R0 is the LSC radius (ccw 10.000). The ccw point at
  // 180 deg, radius 10.002, lies 10.003 from that centre: F_max = +0.003; the points at 90 and
  // 270 deg (radius 9.998) lie sqrt(0.001² + 9.998²) from it, the nearest: F_min = that - 10.
  in.nominal_radius_mm.reset();
  in.nominal_centre_mm = Eigen::Vector2d(0.001, 0);
  const CircularTestResult off = evaluate_circular_test(in);
  ASSERT_TRUE(off.ccw);
  const CircularPathFigures& ccw = *off.ccw;
  EXPECT_TRUE(ccw.F_reference.nominal_centre);
  EXPECT_FALSE(ccw.F_reference.nominal_radius);
  EXPECT_NEAR(ccw.F_reference.radius_mm, 10.0, kExact);
  EXPECT_NEAR(ccw.F_max_mm, 0.003, kExact);
  EXPECT_NEAR(ccw.F_min_mm, std::sqrt(1e-6 + 9.998 * 9.998) - 10, kExact);
}

TEST(CircularTest, HysteresisInterpolatesTheOtherPath) {
  // Both paths on the same shape r = 10 mm + 2 µm cos 2θ, ccw sampled at 0, 45, ... and cw at
  // 22.5, 67.5, ...: no true hysteresis, H is the linear interpolation error alone. At ccw 0 deg
  // (2 µm) the cw neighbours at ±22.5 deg both have 2 cos 45° = √2 µm: difference 2 - √2. At cw
  // 22.5 deg (√2) the ccw neighbours 0 (2) and 45 deg (0) interpolate to 1: difference √2 - 1,
  // smaller. The 16 points are evenly spaced, so the common LSC is (0, 0), 10 mm.
  CircularTestInput in;
  std::vector<double> ccw_dev, cw_dev, cw_angles;
  for (double a : kEight) {
    ccw_dev.push_back(2 * std::cos(2 * rad(a)));
    cw_angles.push_back(a + 22.5);
    cw_dev.push_back(2 * std::cos(2 * rad(a + 22.5)));
  }
  add_path(&in, PathDirection::Ccw, kEight, ccw_dev);
  add_path(&in, PathDirection::Cw, cw_angles, cw_dev);
  const CircularTestResult res = evaluate_circular_test(in);
  ASSERT_TRUE(res.H_mm);
  EXPECT_NEAR(*res.H_mm, (2 - std::sqrt(2.0)) * kUm, kExact);
  EXPECT_NEAR(*res.G_b_mm, 0.004, kExact);
}

TEST(CircularTest, UnidirectionalDataHasNoBidirectionalFigures) {
  CircularTestInput in;
  add_path(&in, PathDirection::Cw, kEight, {1, 2, 1, 0, 1, 2, 1, 0});
  const CircularTestResult res = evaluate_circular_test(in);
  EXPECT_FALSE(res.ccw);
  ASSERT_TRUE(res.cw);
  EXPECT_FALSE(res.G_b_mm);
  EXPECT_FALSE(res.H_mm);
  EXPECT_NEAR(res.G_mm, 0.002, kExact);
  EXPECT_NEAR(res.lsc_radius_mm, 10.001, kExact);
}

// ---- Simulated machines -------------------------------------------------------------------------

struct Machine {
  Eigen::Vector2d nominal_centre{500, -300};
  double nominal_radius = 150;
  double radius_error = 0;  // commanded radius - nominal (e.g. compensation)
  Eigen::Vector2d centre_offset = Eigen::Vector2d::Zero();
  double scale_u = 0, scale_v = 0;        // actual / commanded travel - 1
  double squareness = 0;                  // rad; v moves along (-ε, 1)
  double backlash_u = 0, backlash_v = 0;  // mm; the axis lags its command by b/2
  double sigma = 0;                       // radial noise, mm
};

// N points per direction at θ_k = (k + 1/2) 360°/N, so none sits exactly at an axis reversal.
CircularTestInput simulate(const Machine& m, int n, bool ccw, bool cw, std::mt19937_64& rng,
                           std::vector<Eigen::Vector2d>* noiseless = nullptr) {
  std::normal_distribution<double> noise(0, 1);
  CircularTestInput in;
  for (PathDirection d : {PathDirection::Ccw, PathDirection::Cw}) {
    if ((d == PathDirection::Ccw && !ccw) || (d == PathDirection::Cw && !cw)) continue;
    const double sense = d == PathDirection::Ccw ? 1 : -1;
    for (int k = 0; k < n; ++k) {
      const double t = (k + 0.5) * 2 * kPi / n;
      const Eigen::Vector2d q =
          (m.nominal_radius + m.radius_error) * Eigen::Vector2d(std::cos(t), std::sin(t));
      Eigen::Vector2d p((1 + m.scale_u) * q.x() - m.squareness * q.y(), (1 + m.scale_v) * q.y());
      const double du = -sense * std::sin(t), dv = sense * std::cos(t);  // direction of travel
      p.x() -= m.backlash_u / 2 * (du > 0 ? 1 : -1);
      p.y() -= m.backlash_v / 2 * (dv > 0 ? 1 : -1);
      p += m.nominal_centre + m.centre_offset;
      if (noiseless) noiseless->push_back(p);
      p += m.sigma * noise(rng) * Eigen::Vector2d(std::cos(t), std::sin(t));
      in.points.push_back(CircularPoint{p, d});
    }
  }
  return in;
}

TEST(CircularTest, RecoversScaleMismatchAndSquarenessWithTheirSigns) {
  // No noise, one effect at a time: the first-order relations of the header, checked to 1 %
  // (the second-order terms are ~ s or ε of the effect, i.e. 1e-4 relative).
  std::mt19937_64 rng(1);
  for (double scale : {-80e-6, 50e-6}) {
    Machine m;
    m.scale_u = scale;
    const auto res = evaluate_circular_test(simulate(m, 72, true, false, rng));
    EXPECT_NEAR(res.scale_mismatch_um_per_m.value(), scale * 1e6, 0.01 * std::abs(scale) * 1e6);
    EXPECT_NEAR(res.squareness_urad.value(), 0, 0.01);
    m.scale_u = 0;
    m.scale_v = scale;  // the v axis long: mismatch u - v negative
    const auto res_v = evaluate_circular_test(simulate(m, 72, true, false, rng));
    EXPECT_NEAR(res_v.scale_mismatch_um_per_m.value(), -scale * 1e6, 0.01 * std::abs(scale) * 1e6);
  }
  for (double eps : {-40e-6, 25e-6}) {
    Machine m;
    m.squareness = eps;  // (u, v) -> (u - ε v, v): angle between the motions 90° + ε
    const auto res = evaluate_circular_test(simulate(m, 72, false, true, rng));
    EXPECT_NEAR(res.squareness_urad.value(), eps * 1e6, 0.01 * std::abs(eps) * 1e6);
    EXPECT_NEAR(res.scale_mismatch_um_per_m.value(), 0, 0.01);
  }
}

// Everything at once, with noise. Bounds (σ radial noise, N points per path, R radius), from the
// linearised least squares on evenly spaced angles, where the columns are orthogonal:
//   LSC centre: each coordinate has variance 2σ²/N_fit; radius σ²/N_fit;
//   a2, b2: variance 2σ²/N_fit, so scale mismatch and squareness have standard deviation
//   (2/R) σ √(2/N_fit) (× 1e6 for µm/m, µrad);
//   a figure that is a max (F_max, H) or a range (G) of noisy radii is off from its noiseless
//   value by at most the largest noise (5σ per reading, 5√2σ for a difference of two readings),
//   plus twice the centre error for G (radii about a fitted centre).
// All with 5 standard deviations. The truth: centre = nominal + offset; radius = (R0 + ΔR)
// (1 + (s_u + s_v)/2); mismatch s_u - s_v; squareness ε for both paths together, and
// ε ∓ 8 (b_u - b_v) / (3π R) for ccw/cw alone (the backlash's sin 2θ term, see the header);
// G, F and H from the noiseless simulated points about the true centre.
TEST(CircularTest, SimulatedMachinesRecoverTheTruthWithinTheNoise) {
  std::mt19937_64 rng(2304);
  auto u = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  const int n = 360;
  for (int run = 0; run < 6; ++run) {
    Machine m;
    m.radius_error = u(-0.01, 0.01);
    m.centre_offset = Eigen::Vector2d(u(-0.02, 0.02), u(-0.02, 0.02));
    m.scale_u = u(-50e-6, 50e-6);
    m.scale_v = u(-50e-6, 50e-6);
    m.squareness = u(-50e-6, 50e-6);
    m.backlash_u = u(0, 0.006);
    m.backlash_v = u(0, 0.006);
    m.sigma = 0.0005;
    std::vector<Eigen::Vector2d> truth_pts;
    CircularTestInput in = simulate(m, n, true, true, rng, &truth_pts);
    in.nominal_centre_mm = m.nominal_centre;
    in.nominal_radius_mm = m.nominal_radius;
    in.plane = Plane::XZ;
    const CircularTestResult res = evaluate_circular_test(in);
    const double R = m.nominal_radius;
    const double s = m.sigma;

    const Eigen::Vector2d centre = m.nominal_centre + m.centre_offset;
    const double radius = (R + m.radius_error) * (1 + (m.scale_u + m.scale_v) / 2);
    const int n_all = 2 * n;
    EXPECT_NEAR(res.lsc_centre_mm.x(), centre.x(), 5 * s * std::sqrt(2.0 / n_all)) << run;
    EXPECT_NEAR(res.lsc_centre_mm.y(), centre.y(), 5 * s * std::sqrt(2.0 / n_all)) << run;
    EXPECT_NEAR(res.lsc_radius_mm, radius, 5 * s * std::sqrt(1.0 / n_all)) << run;
    EXPECT_NEAR(res.ccw->lsc_centre_mm.x(), centre.x(), 5 * s * std::sqrt(2.0 / n)) << run;
    EXPECT_NEAR(res.cw->lsc_centre_mm.y(), centre.y(), 5 * s * std::sqrt(2.0 / n)) << run;

    const double shape_sd_all = 2 / R * s * std::sqrt(2.0 / n_all) * 1e6;
    const double shape_sd_one = 2 / R * s * std::sqrt(2.0 / n) * 1e6;
    EXPECT_NEAR(res.scale_mismatch_um_per_m.value(), (m.scale_u - m.scale_v) * 1e6,
                5 * shape_sd_all)
        << run;
    EXPECT_NEAR(res.squareness_urad.value(), m.squareness * 1e6, 5 * shape_sd_all) << run;
    const double backlash_urad = 8 * (m.backlash_u - m.backlash_v) / (3 * kPi * R) * 1e6;
    EXPECT_NEAR(res.ccw->squareness_urad.value(), m.squareness * 1e6 - backlash_urad,
                5 * shape_sd_one)
        << run;
    EXPECT_NEAR(res.cw->squareness_urad.value(), m.squareness * 1e6 + backlash_urad,
                5 * shape_sd_one)
        << run;
    EXPECT_NEAR(res.ccw->scale_mismatch_um_per_m.value(), (m.scale_u - m.scale_v) * 1e6,
                5 * shape_sd_one)
        << run;

    // Noiseless figures from the simulated points about the true centre.
    double g_ccw_hi = -1e9, g_ccw_lo = 1e9, f_hi = -1e9, f_lo = 1e9, h = 0;
    for (int k = 0; k < n; ++k) {
      const double r_ccw = (truth_pts[static_cast<std::size_t>(k)] - centre).norm();
      const double r_cw = (truth_pts[static_cast<std::size_t>(n + k)] - centre).norm();
      g_ccw_hi = std::max(g_ccw_hi, r_ccw);
      g_ccw_lo = std::min(g_ccw_lo, r_ccw);
      h = std::max(h, std::abs(r_ccw - r_cw));
      for (const auto& p :
           {truth_pts[static_cast<std::size_t>(k)], truth_pts[static_cast<std::size_t>(n + k)]}) {
        const double f = (p - m.nominal_centre).norm() - R;
        f_hi = std::max(f_hi, f);
        f_lo = std::min(f_lo, f);
      }
    }
    const double centre_err = 5 * s * std::sqrt(2.0 / n) * std::sqrt(2.0);
    EXPECT_NEAR(res.ccw->G_mm, g_ccw_hi - g_ccw_lo, 2 * 5 * s + 2 * centre_err) << run;
    EXPECT_NEAR(res.F_max_mm, f_hi, 5 * s) << run;
    EXPECT_NEAR(res.F_min_mm, f_lo, 5 * s) << run;
    ASSERT_TRUE(res.H_mm);
    EXPECT_NEAR(*res.H_mm, h, 5 * std::sqrt(2.0) * s) << run;
    // The backlash dominates H: b_u |cos θ| + ... peaks near max(b_u, b_v).
    EXPECT_GT(h, 0.9 * std::max(m.backlash_u, m.backlash_v)) << run;
  }
}

TEST(CircularTest, NoiselessHysteresisIsTheBacklash) {
  // A backlash b on u alone: the paths differ by b |cos θ| radially (ccw +b/2 sign(sin θ) cos θ,
  // cw the opposite), largest next to the reversals at 0 and 180 deg: b cos(0.5°) for the
  // samples at 0.5° from them.
  std::mt19937_64 rng(3);
  Machine m;
  m.backlash_u = 0.004;
  const auto res = evaluate_circular_test(simulate(m, 360, true, true, rng));
  EXPECT_NEAR(*res.H_mm, 0.004 * std::cos(rad(0.5)), 1e-7);
  EXPECT_NEAR(res.squareness_urad.value(), 0, 1e-3);
}

// ---- Refusals -----------------------------------------------------------------------------------

std::string refusal(const CircularTestInput& in) {
  try {
    evaluate_circular_test(in);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(accepted)";
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

TEST(CircularTest, RefusesFewerThanEightPointsPerDirection) {
  CircularTestInput in = hand_case();
  in.points.pop_back();  // cw keeps 7
  EXPECT_EQ(refusal(in),
            "evaluate_circular_test: points[14]: direction cw: 7 points; a circular test needs "
            "at least 8 per direction (the fit of the 2θ shape has 5 terms)");
  EXPECT_EQ(refusal(CircularTestInput{}), "evaluate_circular_test: no points");
}

TEST(CircularTest, RefusesPointsInMoreThanOneArc) {
  // 16 points every 22.5 deg with 5..7 and 11..12 left out: gaps of 90 and 67.5 deg.
  CircularTestInput in;
  for (int k = 0; k < 16; ++k) {
    if ((k >= 5 && k <= 7) || k == 11 || k == 12) continue;
    in.points.push_back(circular_point_from_polar(rad(22.5 * k), 10, PathDirection::Ccw));
  }
  const std::string why = refusal(in);
  EXPECT_TRUE(contains(why, "points[7]: direction ccw: no points between 225 and 292.5 deg"))
      << why;
  EXPECT_TRUE(contains(why, "a gap of 67.5 deg besides the gap of 90 deg")) << why;
  EXPECT_TRUE(contains(why, "more than one arc")) << why;
  // The same with 12 put back: one gap of 90 deg, a partial arc of 270 deg.
  in.points.clear();
  for (int k = 0; k < 16; ++k) {
    if ((k >= 5 && k <= 7) || k == 11) continue;
    in.points.push_back(circular_point_from_polar(rad(22.5 * k), 10, PathDirection::Ccw));
  }
  EXPECT_EQ(refusal(in), "(accepted)");
}

// ---- Partial arcs -------------------------------------------------------------------------------

// n points evenly from from_deg over span_deg (both ends included), radius 10 mm + dev(θ) mm.
template <typename Dev>
void add_arc(CircularTestInput* in, PathDirection d, double from_deg, double span_deg, int n,
             Dev dev) {
  for (int k = 0; k < n; ++k) {
    const double t = rad(from_deg + span_deg * k / (n - 1));
    in->points.push_back(circular_point_from_polar(t, 10 + dev(t), d));
  }
}

TEST(CircularTest, APartialArcIsEvaluatedOverTheArc) {
  // ISO 230-4's 220 deg test: 72 points from 160 deg counter-clockwise to 20 deg (through 270),
  // an exact circle: the arc, G = 0, and the shape resolved.
  CircularTestInput in;
  add_arc(&in, PathDirection::Ccw, 160, 220, 72, [](double) { return 0.0; });
  const CircularTestResult res = evaluate_circular_test(in);
  ASSERT_TRUE(res.ccw);
  EXPECT_FALSE(res.ccw->arc.full_circle);
  EXPECT_NEAR(res.ccw->arc.from_rad, rad(160), 1e-9);
  EXPECT_NEAR(res.ccw->arc.span_rad, rad(220), 1e-9);
  EXPECT_NEAR(res.ccw->max_gap_rad, rad(140), 1e-9);
  EXPECT_FALSE(res.arc.full_circle);
  EXPECT_NEAR(res.ccw->G_mm, 0, 1e-9);
  EXPECT_NEAR(res.ccw->lsc_radius_mm, 10, 1e-9);
  EXPECT_TRUE(res.ccw->scale_mismatch_um_per_m);
  // A full circle is one from 0 over 360 deg.
  const CircularTestResult full = evaluate_circular_test(hand_case());
  EXPECT_TRUE(full.ccw->arc.full_circle);
  EXPECT_EQ(full.ccw->arc.from_rad, 0);
  EXPECT_NEAR(full.ccw->arc.span_rad, 2 * kPi, 1e-15);
}

TEST(CircularTest, TheShapeIsGivenWhereTheArcResolvesIt) {
  // The noise gain of a2, b2 against a full circle, sqrt(n/2 [(AᵀA)⁻¹]_kk), for 72 points from
  // 0 deg over the span, worked independently (Gauss-Jordan inverse of AᵀA in Python):
  //   220 deg: a2 1.9981, b2 1.8148; 180 deg: 4.3238, 1.8388; 90 deg: 10.3813, 51.0803.
  // A noiseless squareness of 40 µrad and scale mismatch of 25 µm/m is recovered from 220 deg
  // (to first order, as from a full circle); 180 and 90 deg leave the shape out.
  const double eps = 40e-6, ds = 25e-6;
  const auto machine = [&](double t) {
    // |p'| - R for p = R (cos t, sin t), u scale ds, squareness eps (the header's derivation).
    return 10 * (ds * std::cos(t) * std::cos(t) - eps * std::cos(t) * std::sin(t));
  };
  const std::vector<std::pair<double, double>> cases{{220, 1.9981}, {180, 4.3238}, {90, 51.0803}};
  for (const auto& [span, gain] : cases) {
    CircularTestInput exact;  // the gain of the angles themselves, about the centre (0, 0)
    add_arc(&exact, PathDirection::Cw, 0, span, 72, [](double) { return 0.0; });
    EXPECT_NEAR(evaluate_circular_test(exact).cw->shape_noise_gain, gain, 1e-4 * gain) << span;
    CircularTestInput in;
    add_arc(&in, PathDirection::Cw, 0, span, 72, machine);
    const CircularTestResult res = evaluate_circular_test(in);
    ASSERT_TRUE(res.cw) << span;
    if (span == 220) {
      ASSERT_TRUE(res.cw->squareness_urad && res.cw->scale_mismatch_um_per_m);
      EXPECT_NEAR(*res.cw->squareness_urad, eps * 1e6, 0.01 * eps * 1e6);
      EXPECT_NEAR(*res.cw->scale_mismatch_um_per_m, ds * 1e6, 0.01 * ds * 1e6);
      EXPECT_TRUE(res.harmonics);
    } else {
      EXPECT_FALSE(res.cw->squareness_urad) << span;
      EXPECT_FALSE(res.cw->scale_mismatch_um_per_m) << span;
      EXPECT_FALSE(res.cw->harmonics) << span;
      EXPECT_FALSE(res.squareness_urad) << span;
    }
  }
}

TEST(CircularTest, HysteresisOfArcsComparesOnlyWhereBothWereMeasured) {
  // Both directions on a 220 deg arc: ccw at 0, 10, .., 220 deg, cw at 5, 15, .., 215 deg; the
  // radius ramps by 10 µm along the arc, cw 1 µm above ccw. Each cw point lies between two ccw
  // points (the ramp interpolates exactly): H = 1 µm. The ccw points at 0 and 220 deg lie outside
  // the cw arc and are not compared; across the 140 deg gap the ramp would differ by 10 µm.
  const auto ramp = [](double t) { return 0.010 * t / rad(220); };
  CircularTestInput in;
  add_arc(&in, PathDirection::Ccw, 0, 220, 23, ramp);
  add_arc(&in, PathDirection::Cw, 5, 210, 22, [&](double t) { return ramp(t) + 0.001; });
  const CircularTestResult res = evaluate_circular_test(in);
  ASSERT_TRUE(res.H_mm);
  // About the fitted common centre c the radii change by -c·(cos θ, sin θ) alike for both
  // paths; the linear interpolation of that between points 10 deg apart is off by at most
  // |c| (10 deg)² / 8 ≈ 0.0038 |c|.
  const double c = res.lsc_centre_mm.norm();
  EXPECT_GT(c, 1e-4);  // the ramp moves the centre: the bound below is not vacuous
  EXPECT_NEAR(*res.H_mm, 0.001, 0.004 * c);
  // The arcs (about that centre): ccw 220 deg, cw 210 deg inside it.
  EXPECT_NEAR(res.H_overlap_rad, rad(210), 1e-4);
  EXPECT_TRUE(iso230_4_conformance(res).empty());
  // cw shifted by 60 deg: H over the 160 deg both cover, and a warning.
  CircularTestInput shifted;
  add_arc(&shifted, PathDirection::Ccw, 0, 220, 23, [](double) { return 0.0; });
  add_arc(&shifted, PathDirection::Cw, 60, 220, 23, [](double) { return 0.001; });
  const CircularTestResult r1 = evaluate_circular_test(shifted);
  EXPECT_NEAR(r1.H_overlap_rad, rad(160), 1e-3);
  const auto w = iso230_4_conformance(r1);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0],
            "the two directions cover different arcs: H compares them over the 160 deg they share");

  // Arcs with no angle in common: no H, said so.
  CircularTestInput apart;
  add_arc(&apart, PathDirection::Ccw, 0, 90, 10, [](double) { return 0.0; });
  add_arc(&apart, PathDirection::Cw, 180, 90, 10, [](double) { return 0.0; });
  const CircularTestResult r2 = evaluate_circular_test(apart);
  EXPECT_FALSE(r2.H_mm);
  EXPECT_TRUE(r2.G_b_mm);
  const auto w2 = iso230_4_conformance(r2);
  EXPECT_TRUE(std::any_of(w2.begin(), w2.end(), [](const std::string& s) {
    return contains(s, "arcs with no angle in common: no hysteresis H");
  }));
}

TEST(CircularTest, ConformanceSaysWhereATestDepartsFromIso230_4) {
  const auto exact = [](double) { return 0.0; };
  // Both directions, 36 points round the circle: conforms.
  CircularTestInput full;
  for (int k = 0; k < 36; ++k) {
    full.points.push_back(circular_point_from_polar(rad(10.0 * k), 10, PathDirection::Ccw));
    full.points.push_back(circular_point_from_polar(rad(10.0 * k + 5), 10, PathDirection::Cw));
  }
  EXPECT_TRUE(iso230_4_conformance(evaluate_circular_test(full)).empty());
  // 24 points (every 15 deg), ccw only: too sparse (36 needed) and one direction.
  CircularTestInput sparse;
  for (int k = 0; k < 24; ++k) {
    sparse.points.push_back(circular_point_from_polar(rad(15.0 * k), 10, PathDirection::Ccw));
  }
  const auto w = iso230_4_conformance(evaluate_circular_test(sparse));
  ASSERT_EQ(w.size(), 2u);
  EXPECT_EQ(w[0],
            "direction ccw: 24 points over 360 deg, one every 15 deg: G, a max - min of the radii, "
            "needs one every 10 deg or closer (36 here) to read a shape of up to 4 lobes per turn "
            "within 6 %, and misses reversal spikes narrower than the spacing");
  EXPECT_TRUE(contains(w[1], "measured in one direction only (ccw): ISO 230-4 traces both"))
      << w[1];
  // Both ways over an arc from 0 deg of n points: the warnings.
  const auto both_ways = [&](double span_deg, int n) {
    CircularTestInput in;
    add_arc(&in, PathDirection::Ccw, 0, span_deg, n, exact);
    add_arc(&in, PathDirection::Cw, 0, span_deg, n, exact);
    return iso230_4_conformance(evaluate_circular_test(in));
  };
  // A 90 deg arc of 10 points (every 10 deg): the shape is not resolved, nothing else.
  const auto wq = both_ways(90, 10);
  ASSERT_EQ(wq.size(), 2u);
  EXPECT_TRUE(contains(wq[0], "direction ccw: the arc of 90 deg does not resolve the 2θ shape"))
      << wq[0];
  // A 60 deg arc: too short.
  const auto ws = both_ways(60, 13);
  ASSERT_FALSE(ws.empty());
  EXPECT_TRUE(contains(ws[0],
                       "direction ccw: an arc of 60 deg, shorter than ISO 230-4's shortest "
                       "partial arc (90 deg)"))
      << ws[0];
}

TEST(CircularTest, RefusesNonFiniteValues) {
  CircularTestInput in = hand_case();
  in.points[3].uv_mm.y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(contains(refusal(in), "points[3]: u_mm = ")) << refusal(in);
  EXPECT_TRUE(contains(refusal(in), "v_mm = nan: not a finite point")) << refusal(in);
  in = hand_case();
  in.nominal_radius_mm = std::numeric_limits<double>::infinity();
  EXPECT_EQ(refusal(in),
            "evaluate_circular_test: nominal_radius_mm = inf: must be a finite number > 0");
  in.nominal_radius_mm = -5;
  EXPECT_EQ(refusal(in),
            "evaluate_circular_test: nominal_radius_mm = -5: must be a finite number > 0");
  in.nominal_radius_mm.reset();
  in.nominal_centre_mm = Eigen::Vector2d(1, std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(refusal(in), "evaluate_circular_test: nominal_centre_mm = (1, nan): not finite");
}

TEST(CircularTest, RefusesDuplicateAnglesInOneDirection) {
  CircularTestInput in = hand_case();
  in.points.push_back(in.points[10]);  // cw at 90 deg again (points[16])
  const auto p = find_circular_test_problem(in);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->index, std::optional<std::size_t>(16));
  EXPECT_EQ(p->first_index, std::optional<std::size_t>(10));
  EXPECT_TRUE(contains(refusal(in), "points[16]: direction cw: ")) << refusal(in);
  EXPECT_TRUE(contains(refusal(in), "the same angle as another point (points[10])")) << refusal(in);
  // The same angle in the other direction is no duplicate.
  EXPECT_FALSE(find_circular_test_problem(hand_case()));
}

TEST(CircularTest, RefusesPointsThatAdmitNoCircle) {
  CircularTestInput in;
  for (int k = 0; k < 8; ++k) {
    in.points.push_back(CircularPoint{Eigen::Vector2d(k, 2 * k), PathDirection::Ccw});
  }
  EXPECT_TRUE(contains(refusal(in), "direction ccw: fit_circle: ")) << refusal(in);
}

TEST(CircularTest, PlaneNames) {
  EXPECT_EQ(parse_plane("xz"), std::optional<Plane>(Plane::XZ));
  EXPECT_EQ(parse_plane("YZ"), std::optional<Plane>(Plane::YZ));
  EXPECT_FALSE(parse_plane("ZX"));
  EXPECT_FALSE(parse_plane(""));
  EXPECT_EQ(to_string(Plane::XY), "XY");
  EXPECT_EQ(to_string(PathDirection::Cw), "cw");
  const CircularPoint p = circular_point_from_polar(rad(90), 2, PathDirection::Cw);
  EXPECT_NEAR(p.uv_mm.x(), 0, 1e-15);
  EXPECT_NEAR(p.uv_mm.y(), 2, 1e-15);
}

}  // namespace
}  // namespace ncqual::solver

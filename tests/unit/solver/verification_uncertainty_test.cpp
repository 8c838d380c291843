// SPDX-License-Identifier: Apache-2.0
// Monte Carlo uncertainty of the volumetric verification: zero noise leaves zero residual (for a
// machine the model represents, out-of-gauge terms and a thermal correction included), the
// residual is linear in the tracker noise, the thermal correction's error is a scale error about
// the middle of the range, eq. 23-24 by hand, the location search, the linearised identification
// against full identifications on the same draws, reproducibility and the refusals.
#include "ncqual/solver/verification_uncertainty.hpp"

#include "ncqual/common/config.hpp"
#include "ncqual/common/units.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

namespace ncqual::solver {
namespace {

using Eigen::Vector3d;
using volumetric::RigidBodyErrors;

constexpr double kLo[3] = {200, 200, 600};
constexpr double kHi[3] = {2200, 1400, 1200};

// A small grid: 5 x 4 x 3 positions, 4 targets (lever arms along -z, x and y) = 240 points.
VerificationDesign small_design() {
  const std::vector<Vector3d> offsets = {Vector3d(0, 0, -300), Vector3d(0, 0, -500),
                                         Vector3d(150, 0, -300), Vector3d(0, 150, -300)};
  const int steps[3] = {5, 4, 3};
  VerificationDesign d;
  for (std::size_t k = 0; k < offsets.size(); ++k) {
    for (int iz = 0; iz < steps[2]; ++iz) {
      for (int iy = 0; iy < steps[1]; ++iy) {
        for (int ix = 0; ix < steps[0]; ++ix) {
          const int idx[3] = {ix, iy, iz};
          Vector3d c;
          for (int a = 0; a < 3; ++a) c[a] = kLo[a] + (kHi[a] - kLo[a]) * idx[a] / (steps[a] - 1);
          d.points.push_back(
              {"p" + std::to_string(d.points.size()) + ":t" + std::to_string(k), c, offsets[k]});
        }
      }
    }
  }
  return d;
}

void set(RigidBodyErrors& e, const char* name, std::vector<double> coefficients) {
  for (int f = 0; f < volumetric::kFunctionCount; ++f) {
    if (volumetric::function_name(f) == name) {
      auto& s = e.functions[static_cast<std::size_t>(f)];
      const int axis = f / 6;
      s.lo_mm = kLo[axis];
      s.hi_mm = kHi[axis];
      s.coefficients = std::move(coefficients);
      return;
    }
  }
  throw std::logic_error(name);
}

// Errors within the model's reach on the small grid (orders up to 4, 3, 2 for X, Y, Z): every
// term is tens of sigma of the estimator at 1 um assumed point sigma, so the BIC keeps them all.
// With `out_of_gauge`, constants and linear straightness the frame and squareness absorb.
RigidBodyErrors machine(bool out_of_gauge) {
  RigidBodyErrors e;
  set(e, "EXX", {out_of_gauge ? 0.02 : 0.0, 0.012, -0.006, 0.004});
  set(e, "EYX", {out_of_gauge ? -0.015 : 0.0, out_of_gauge ? 0.01 : 0.0, 0.008, -0.005});
  set(e, "EZX", {0, 0, -0.006});
  set(e, "EAX", {out_of_gauge ? 20e-6 : 0.0, 15e-6, -8e-6});
  set(e, "EBX", {0, -12e-6, 6e-6});
  set(e, "ECX", {0, 10e-6, 8e-6});
  set(e, "EYY", {0, -0.008, 0.005});
  set(e, "EXY", {0, 0, 0.006});
  set(e, "EZY", {out_of_gauge ? 0.01 : 0.0, 0, 0.004});
  set(e, "EAY", {0, 10e-6});
  set(e, "EBY", {0, -8e-6});
  set(e, "ECY", {0, 40e-6});
  set(e, "EZZ", {0, 0.010, -0.004});
  set(e, "EXZ", {0, 0, 0.004});
  set(e, "EAZ", {20e-6, -10e-6});
  set(e, "EBZ", {-15e-6, 10e-6});
  set(e, "ECZ", {25e-6});
  e.ec0xy_rad = 20e-6;
  e.eb0xz_rad = -15e-6;
  e.ea0yz_rad = 10e-6;
  return e;
}

// Beside the small grid, facing it (pm1's arrangement), no noise.
TrackerUncertaintyModel quiet_tracker() {
  TrackerUncertaintyModel t;
  t.position_mm = Vector3d(1200, -1500, 900);
  t.ypr_rad = Vector3d(units::kPi / 2, 0.005, -0.003);
  t.angular_sigma_rad = 0;
  t.radial_sigma_mm = 0;
  t.radial_sigma_mm_per_m = 0;
  return t;
}

// Aguado et al.'s tracker, 16 readings a point (pm1), placed within a few mm and a mrad.
TrackerUncertaintyModel noisy_tracker() {
  TrackerUncertaintyModel t = quiet_tracker();
  t.angular_sigma_rad = 20e-6;
  t.radial_sigma_mm = 0.004;
  t.radial_sigma_mm_per_m = 0.0008;
  t.samples_per_point = 16;
  t.position_sigma_mm = 5;
  t.orientation_sigma_rad = 1e-3;
  return t;
}

UncertaintySources quiet_sources(bool out_of_gauge) {
  UncertaintySources s;
  s.errors = machine(out_of_gauge);
  s.expansion_sigma_per_K.setZero();
  s.temperature_deviation_K = Vector3d(0.5, 0.3, 0.8);  // corrected exactly: no effect
  return s;
}

double largest(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }

double mean(const std::vector<double>& v) {
  return std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

double sample_sd(const std::vector<double>& v) {
  const double m = mean(v);
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size() - 1));
}

// ------------------------------------------------------------------------------------------------

TEST(VerificationUncertainty, ZeroNoiseLeavesZeroResidual) {
  VerificationDesign design = small_design();
  design.identification_sigma_mm = 0.001;
  for (bool out_of_gauge : {false, true}) {
    for (auto method : {IdentificationMethod::Linearised, IdentificationMethod::Full}) {
      MonteCarloOptions o;
      o.trials = 2;
      o.method = method;
      const VerificationUncertainty u = evaluate_verification_uncertainty(
          design, quiet_tracker(), quiet_sources(out_of_gauge), o);
      // Linearised: second order in the errors, (40 urad)^2 / 2 x 2.5 m + 40 urad x 20 um
      // ~ 3e-6 mm at most. The full identification solves the exact model; out-of-gauge terms
      // (20 urad, 20 um) are absorbed by the frame and the gauge's terms to second order only:
      // (20 urad)^2 x 1 m ~ 4e-7 mm.
      const double bound =
          method == IdentificationMethod::Full ? (out_of_gauge ? 5e-7 : 1e-9) : 5e-6;
      std::printf("zero noise, out of gauge %d, %s: largest |e| %.3g mm\n", out_of_gauge,
                  method == IdentificationMethod::Full ? "full" : "linearised",
                  largest(u.trial_max_mm));
      EXPECT_LT(largest(u.trial_max_mm), bound)
          << "out_of_gauge " << out_of_gauge << " method " << static_cast<int>(method);
      EXPECT_EQ(u.points.size(), design.points.size());
      EXPECT_EQ(u.observations, 3 * static_cast<int>(design.points.size()));
      EXPECT_TRUE(u.unidentifiable.empty());
      EXPECT_EQ(u.tracker_max_u_mm, 0.0);
    }
  }
}

TEST(VerificationUncertainty, ResidualIsLinearInTrackerNoise) {
  // Angular noise only, a perfect machine: doubling the noise and the assumed point sigma (so
  // the BIC decides alike) doubles every residual of the same draws.
  const VerificationDesign design = small_design();
  UncertaintySources s;
  s.expansion_sigma_per_K.setZero();
  TrackerUncertaintyModel t = quiet_tracker();
  t.angular_sigma_rad = 20e-6;
  MonteCarloOptions o;
  o.trials = 40;
  const VerificationUncertainty a = evaluate_verification_uncertainty(design, t, s, o);
  VerificationDesign design2 = design;
  design2.identification_sigma_mm *= 2;
  TrackerUncertaintyModel t2 = t;
  t2.angular_sigma_rad *= 2;
  const VerificationUncertainty b = evaluate_verification_uncertainty(design2, t2, s, o);
  ASSERT_GT(a.mean_residual_mm.mean, 1e-4);  // noise reaches the residual
  for (int k = 0; k < o.trials; ++k) {
    // Spherical noise of tens of urad: nonlinearity ~ 1e-5 relative.
    EXPECT_NEAR(
        b.trial_mean_mm[static_cast<std::size_t>(k)] / a.trial_mean_mm[static_cast<std::size_t>(k)],
        2.0, 1e-3);
  }
  for (std::size_t i = 0; i < a.points.size(); i += 37) {
    EXPECT_NEAR(b.points[i].sigma_mm.norm() / a.points[i].sigma_mm.norm(), 2.0, 1e-3);
  }
  // Other draws (another seed): the means of the per-trial mean residual agree with twice the
  // first within 5 standard errors of their difference.
  MonteCarloOptions o2 = o;
  o2.seed = 77;
  const VerificationUncertainty c = evaluate_verification_uncertainty(design2, t2, s, o2);
  const double n = o.trials;
  const double se = std::sqrt(std::pow(sample_sd(c.trial_mean_mm), 2) / n +
                              4 * std::pow(sample_sd(a.trial_mean_mm), 2) / n);
  EXPECT_LT(std::abs(mean(c.trial_mean_mm) - 2 * mean(a.trial_mean_mm)), 5 * se);
  EXPECT_GT(mean(c.trial_mean_mm), 1.5 * mean(a.trial_mean_mm));
  std::printf(
      "noise x2: mean |e| %.3f -> %.3f um (same draws), %.3f um (other draws, 5 SE = %.3f um)\n",
      mean(a.trial_mean_mm) * 1e3, mean(b.trial_mean_mm) * 1e3, mean(c.trial_mean_mm) * 1e3,
      5 * se * 1e3);
}

TEST(VerificationUncertainty, ThermalCorrectionErrorIsAScaleAboutTheRangeMiddle) {
  // Only u(alpha_x), Delta T_x = 2 K, zero noise; the model identifies EXX P1 (the machine has a
  // 12 um scale term), so it takes up (alpha_true - alpha) 2 K as a scale error of X about the
  // middle of its range: e_x = -(alpha_true - alpha) 2 K (x - 1200), nothing along Y and Z.
  VerificationDesign design = small_design();
  design.identification_sigma_mm = 0.001;
  UncertaintySources s = quiet_sources(false);
  s.temperature_deviation_K = Vector3d(2, 0, 0);
  s.expansion_sigma_per_K = Vector3d(expansion_uncertainty_per_K(11.5e-6), 0, 0);
  MonteCarloOptions o;
  o.trials = 100;
  const VerificationUncertainty u =
      evaluate_verification_uncertainty(design, quiet_tracker(), s, o);
  const double mid = (kLo[0] + kHi[0]) / 2;
  const PointUncertainty* far = nullptr;
  for (const auto& p : u.points) {
    EXPECT_LT(p.sigma_mm.y(), 1e-6) << p.label;
    EXPECT_LT(p.sigma_mm.z(), 1e-6) << p.label;
    if (std::abs(p.commanded_mm.x() - mid) > 900) far = &p;
  }
  ASSERT_NE(far, nullptr);
  // The same draw moves every point in proportion to x - mid: the sigmas are in that ratio.
  for (const auto& p : u.points) {
    const double expected = far->sigma_mm.x() * std::abs(p.commanded_mm.x() - mid) /
                            std::abs(far->commanded_mm.x() - mid);
    EXPECT_NEAR(p.sigma_mm.x(), expected, 2e-6) << p.label;
  }
  // And the far point's sigma is u(alpha) 2 K 1000 mm within 5 standard errors of a sample sd.
  const double sigma = expansion_uncertainty_per_K(11.5e-6) * 2 * 1000;
  std::printf("thermal: sigma_x at |x - mid| = 1000 mm: %.3f um (u(alpha) 2 K 1000 mm = %.3f um)\n",
              far->sigma_mm.x() * 1e3, sigma * 1e3);
  EXPECT_NEAR(far->sigma_mm.x(), sigma, 5 * sigma / std::sqrt(2.0 * (o.trials - 1)));
}

TEST(VerificationUncertainty, ExpansionUncertaintyRule) {
  // 11.5e-6 /K: 10 % is 1.15e-6, below the 2e-6 floor: 2e-6 / (2 sqrt 3) = 5.77e-7 (the paper's
  // 0.0006 um/(mm K)); 30e-6 /K: 10 % = 3e-6 -> 8.66e-7.
  EXPECT_NEAR(expansion_uncertainty_per_K(11.5e-6), 5.7735e-7, 1e-10);
  EXPECT_NEAR(expansion_uncertainty_per_K(-11.5e-6), 5.7735e-7, 1e-10);
  EXPECT_NEAR(expansion_uncertainty_per_K(30e-6), 8.6603e-7, 1e-10);
  EXPECT_THROW(expansion_uncertainty_per_K(std::nan("")), std::invalid_argument);
}

TEST(VerificationUncertainty, TrackerPointUncertaintyByHand) {
  TrackerUncertaintyModel t;  // at the origin, axes = machine axes
  t.angular_sigma_rad = 20e-6;
  t.radial_sigma_mm = 0.004;
  t.radial_sigma_mm_per_m = 0.0008;
  t.samples_per_point = 4;  // noise / 2
  // Along the tracker's x axis, 3 m: u_x = u_r, u_y = r u_azimuth, u_z = r u_elevation.
  {
    const TrackerPointUncertainty u = tracker_point_uncertainty(t, Vector3d(3000, 0, 0));
    const double ur = (0.004 + 0.0008 * 3) / 2, ua = 20e-6 / 2;
    EXPECT_NEAR(u.range_mm, 3000, 1e-9);
    EXPECT_NEAR(u.u_tracker_mm.x(), ur, 1e-12);
    EXPECT_NEAR(u.u_tracker_mm.y(), 3000 * ua, 1e-12);
    EXPECT_NEAR(u.u_tracker_mm.z(), 3000 * ua, 1e-12);
    EXPECT_NEAR(u.u_p_mm, std::sqrt(ur * ur + 2 * 3000 * 3000 * ua * ua), 1e-12);
    EXPECT_NEAR((u.u_machine_mm - u.u_tracker_mm).norm(), 0, 1e-15);
  }
  // Straight up, 2 m: the azimuth does not move the point; u_x = r u_elevation, u_z = u_r.
  {
    const TrackerPointUncertainty u = tracker_point_uncertainty(t, Vector3d(0, 0, 2000));
    const double ur = (0.004 + 0.0008 * 2) / 2, ua = 20e-6 / 2;
    EXPECT_NEAR(u.elevation_rad, units::kPi / 2, 1e-12);
    EXPECT_NEAR(u.u_tracker_mm.x(), 2000 * ua, 1e-12);
    EXPECT_NEAR(u.u_tracker_mm.y(), 0, 1e-12);
    EXPECT_NEAR(u.u_tracker_mm.z(), ur, 1e-12);
    EXPECT_NEAR(u.u_p_mm, std::sqrt(ur * ur + 2000 * 2000 * ua * ua), 1e-12);
  }
  // 45 deg up in the x-z plane: u_z^2 = (sin e)^2 u_r^2 + (r cos e)^2 u_e^2 (eq. 23's third row
  // with the polar angle 45 deg).
  {
    const double r = 2500, e = units::kPi / 4;
    const TrackerPointUncertainty u =
        tracker_point_uncertainty(t, Vector3d(r * std::cos(e), 0, r * std::sin(e)));
    const double ur = (0.004 + 0.0008 * 2.5) / 2, ua = 20e-6 / 2;
    EXPECT_NEAR(u.u_tracker_mm.z(), std::sqrt(0.5 * ur * ur + 0.5 * r * r * ua * ua), 1e-12);
    EXPECT_NEAR(u.u_tracker_mm.y(), r * std::cos(e) * ua, 1e-12);
    EXPECT_NEAR(u.u_p_mm, std::sqrt(ur * ur + r * r * ua * ua * 1.5), 1e-12);
  }
  // Turned by yaw 90 deg: a point along machine +Y is on the tracker's x axis; along the machine
  // axes u_y = u_r and u_x = r u_azimuth.
  {
    TrackerUncertaintyModel turned = t;
    turned.position_mm = Vector3d(100, -200, 50);
    turned.ypr_rad = Vector3d(units::kPi / 2, 0, 0);
    const TrackerPointUncertainty u = tracker_point_uncertainty(turned, Vector3d(100, 2800, 50));
    const double ur = (0.004 + 0.0008 * 3) / 2, ua = 20e-6 / 2;
    EXPECT_NEAR(u.azimuth_rad, 0, 1e-12);
    EXPECT_NEAR(u.u_machine_mm.y(), ur, 1e-12);
    EXPECT_NEAR(u.u_machine_mm.x(), 3000 * ua, 1e-12);
    EXPECT_NEAR(u.u_machine_mm.z(), 3000 * ua, 1e-12);
  }
}

TEST(VerificationUncertainty, TrackerErrorGrowsWithRange) {
  const TrackerUncertaintyModel t = noisy_tracker();
  const Vector3d dir = Vector3d(0.3, 0.9, 0.2).normalized();
  double last = 0;
  for (double r : {600.0, 1000.0, 2000.0, 4000.0, 8000.0}) {
    const double u = tracker_point_uncertainty(t, t.position_mm + r * dir).u_p_mm;
    EXPECT_GT(u, last) << r;
    last = u;
  }
  // The Monte Carlo's per-point figure is eq. 24 at the nominal target.
  MonteCarloOptions o;
  o.trials = 1;
  const VerificationDesign d = small_design();
  const VerificationUncertainty v =
      evaluate_verification_uncertainty(d, t, quiet_sources(false), o);
  for (std::size_t i = 0; i < d.points.size(); i += 23) {
    EXPECT_DOUBLE_EQ(
        v.points[i].tracker_u_mm,
        tracker_point_uncertainty(t, d.points[i].commanded_mm + d.points[i].tool_offset_mm).u_p_mm);
  }
}

TEST(VerificationUncertainty, LocationSearchFindsTheBestCandidate) {
  const VerificationDesign design = small_design();
  const TrackerUncertaintyModel t = noisy_tracker();
  TrackerRegion region;
  region.lo_mm = Vector3d(-1500, -4000, 0);
  region.hi_mm = Vector3d(4000, 3000, 2000);
  region.steps = Eigen::Vector3i(6, 6, 3);
  LocationSearchOptions options;
  options.report = 1000;
  const TrackerLocationSearch s = best_tracker_location(design, t, region, options);
  ASSERT_EQ(static_cast<int>(s.candidates.size()), s.tried);
  EXPECT_EQ(s.tried + s.excluded, 6 * 6 * 3);
  EXPECT_GT(s.excluded, 0);  // the grid crosses the envelope (x 200..2350, y 200..1550, z 100..900)
  for (const auto& c : s.candidates) {
    EXPECT_LE(s.max_u_mm, c.max_u_mm);
    // No candidate inside the envelope grown by the clearance.
    const bool inside = c.position_mm.x() >= 200 - 200 && c.position_mm.x() <= 2350 + 200 &&
                        c.position_mm.y() >= 200 - 200 && c.position_mm.y() <= 1550 + 200 &&
                        c.position_mm.z() >= 100 - 200 && c.position_mm.z() <= 900 + 200;
    EXPECT_FALSE(inside) << c.position_mm.transpose();
  }
  // The figure of the best is eq. 24's maximum at that placement, facing the envelope's centre.
  double mx = 0;
  for (const auto& p : design.points) {
    mx = std::max(mx, tracker_point_uncertainty(s.best, p.commanded_mm + p.tool_offset_mm).u_p_mm);
  }
  EXPECT_NEAR(s.max_u_mm, mx, 1e-12);
  const Vector3d to_centre = Vector3d(1275, 875, 500) - s.best.position_mm;
  EXPECT_NEAR(s.best.ypr_rad[0], std::atan2(to_centre.y(), to_centre.x()), 1e-12);
  EXPECT_EQ(s.best.ypr_rad[1], t.ypr_rad[1]);
  // Better than a deliberately poor placement: a far corner of the region.
  TrackerUncertaintyModel poor = t;
  poor.position_mm = Vector3d(4000, -4000, 2000);
  double poor_max = 0;
  for (const auto& p : design.points) {
    poor_max = std::max(poor_max,
                        tracker_point_uncertainty(poor, p.commanded_mm + p.tool_offset_mm).u_p_mm);
  }
  std::printf(
      "location: best (%.0f, %.0f, %.0f) max u_p %.2f um of %d candidates (%d excluded); "
      "far corner %.2f um\n",
      s.best.position_mm.x(), s.best.position_mm.y(), s.best.position_mm.z(), s.max_u_mm * 1e3,
      s.tried, s.excluded, poor_max * 1e3);
  EXPECT_LT(s.max_u_mm, 0.8 * poor_max);
  // Reported best first, no more than asked.
  options.report = 3;
  const TrackerLocationSearch few = best_tracker_location(design, t, region, options);
  ASSERT_EQ(few.candidates.size(), 3u);
  EXPECT_EQ(few.candidates.front().position_mm, s.best.position_mm);
  EXPECT_LE(few.candidates[1].max_u_mm, few.candidates[2].max_u_mm);
}

TEST(VerificationUncertainty, LinearisedAgreesWithFullIdentification) {
  // Every source at once, the same draws: the linearised identification against Ceres.
  const VerificationDesign design = small_design();
  UncertaintySources s = quiet_sources(true);
  s.repeatability_sigma_mm = Vector3d::Constant(0.001);
  s.expansion_sigma_per_K = Vector3d::Constant(expansion_uncertainty_per_K(11.5e-6));
  s.temperature_sigma_K = Vector3d::Constant(0.2);
  MonteCarloOptions o;
  o.trials = 12;
  const VerificationUncertainty lin =
      evaluate_verification_uncertainty(design, noisy_tracker(), s, o);
  o.method = IdentificationMethod::Full;
  const VerificationUncertainty full =
      evaluate_verification_uncertainty(design, noisy_tracker(), s, o);
  ASSERT_EQ(full.method, IdentificationMethod::Full);
  for (int k = 0; k < o.trials; ++k) {
    const auto i = static_cast<std::size_t>(k);
    EXPECT_NEAR(lin.trial_mean_mm[i], full.trial_mean_mm[i], 1e-3 * full.trial_mean_mm[i] + 1e-7)
        << k;
    EXPECT_NEAR(lin.trial_max_mm[i], full.trial_max_mm[i], 1e-3 * full.trial_max_mm[i] + 1e-7) << k;
  }
  double worst_mean = 0, worst_max = 0;
  for (int k = 0; k < o.trials; ++k) {
    const auto i = static_cast<std::size_t>(k);
    worst_mean = std::max(worst_mean, std::abs(lin.trial_mean_mm[i] / full.trial_mean_mm[i] - 1));
    worst_max = std::max(worst_max, std::abs(lin.trial_max_mm[i] / full.trial_max_mm[i] - 1));
  }
  std::printf(
      "linearised vs full, %d trials: mean |e| %.3f vs %.3f um (worst relative difference of a "
      "trial %.2g), max |e| %.3f vs %.3f um (%.2g); %.1f vs %.1f parameters kept\n",
      o.trials, lin.mean_residual_mm.mean * 1e3, full.mean_residual_mm.mean * 1e3, worst_mean,
      lin.max_residual_mm.mean * 1e3, full.max_residual_mm.mean * 1e3, worst_max,
      lin.mean_kept_parameters, full.mean_kept_parameters);
  EXPECT_NEAR(lin.mean_kept_parameters, full.mean_kept_parameters, 1e-9);
  for (std::size_t i = 0; i < design.points.size(); i += 17) {
    EXPECT_NEAR((lin.points[i].mean_mm - full.points[i].mean_mm).norm(), 0, 1e-6) << i;
    EXPECT_NEAR((lin.points[i].sigma_mm - full.points[i].sigma_mm).norm(), 0, 1e-6) << i;
  }
}

TEST(VerificationUncertainty, ReproducibleWithASeedWhateverTheThreads) {
  const VerificationDesign design = small_design();
  UncertaintySources s = quiet_sources(false);
  s.repeatability_sigma_mm = Vector3d::Constant(0.001);
  MonteCarloOptions o;
  o.trials = 120;  // more than two accumulation blocks
  o.seed = 5;
  const VerificationUncertainty a =
      evaluate_verification_uncertainty(design, noisy_tracker(), s, o);
  const VerificationUncertainty b =
      evaluate_verification_uncertainty(design, noisy_tracker(), s, o);
  o.threads = 2;
  const VerificationUncertainty c =
      evaluate_verification_uncertainty(design, noisy_tracker(), s, o);
  EXPECT_EQ(a.trial_mean_mm, b.trial_mean_mm);
  EXPECT_EQ(a.trial_mean_mm, c.trial_mean_mm);
  EXPECT_EQ(a.trial_max_mm, c.trial_max_mm);
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].mean_mm, c.points[i].mean_mm);
    EXPECT_EQ(a.points[i].sigma_mm, c.points[i].sigma_mm);
    EXPECT_EQ(a.points[i].bound95_mm, c.points[i].bound95_mm);
  }
  EXPECT_EQ(a.max_residual_mm.quantile95, c.max_residual_mm.quantile95);
  o.seed = 6;
  const VerificationUncertainty d =
      evaluate_verification_uncertainty(design, noisy_tracker(), s, o);
  EXPECT_NE(a.trial_mean_mm, d.trial_mean_mm);
  // Summaries are those of the per-trial values; the 95 % bound is an order statistic.
  EXPECT_NEAR(a.mean_residual_mm.mean, mean(a.trial_mean_mm), 1e-15);
  EXPECT_NEAR(a.max_residual_mm.sigma, sample_sd(a.trial_max_mm), 1e-15);
  EXPECT_EQ(a.max_residual_mm.max, largest(a.trial_max_mm));
  std::vector<double> sorted = a.trial_max_mm;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(a.max_residual_mm.quantile95, sorted[113]);  // rank ceil(0.95 * 120) = 114
}

TEST(VerificationUncertainty, Pm1GridDesign) {
  const MachineConfig m =
      load_machine_config(std::string(NCQUAL_SOURCE_DIR) + "/deploy/machines/pm1.yaml");
  ASSERT_TRUE(m.global_check.has_value());
  const VerificationDesign d = grid_verification_design(*m.global_check);
  ASSERT_EQ(d.points.size(), 864u);  // 9 x 6 x 4 grid x 4 targets
  int with_offset[4] = {0, 0, 0, 0};
  for (const auto& p : d.points) {
    EXPECT_EQ(p.label.rfind("grid:", 0), 0u) << p.label;
    const int k = p.label.back() - '0';
    ASSERT_GE(k, 0);
    ASSERT_LT(k, 4);
    ++with_offset[k];
    const Vector3d expected = k == 0   ? Vector3d(0, 0, -300)
                              : k == 1 ? Vector3d(0, 0, -500)
                              : k == 2 ? Vector3d(150, 0, -300)
                                       : Vector3d(0, 150, -300);
    EXPECT_NEAR((p.tool_offset_mm - expected).norm(), 0, 1e-9) << p.label;
  }
  for (int k = 0; k < 4; ++k) EXPECT_EQ(with_offset[k], 216);
}

TEST(VerificationUncertainty, Refusals) {
  const VerificationDesign design = small_design();
  const TrackerUncertaintyModel t = noisy_tracker();
  const UncertaintySources s = quiet_sources(false);
  MonteCarloOptions o;
  o.trials = 1;
  const auto refused = [&](const VerificationDesign& d, const TrackerUncertaintyModel& tr,
                           const UncertaintySources& so, const MonteCarloOptions& op,
                           const std::string& mention) {
    try {
      (void)evaluate_verification_uncertainty(d, tr, so, op);
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
      return;
    }
    ADD_FAILURE() << "not refused: " << mention;
  };
  MonteCarloOptions bad = o;
  bad.trials = 0;
  refused(design, t, s, bad, "MonteCarloOptions.trials = 0");
  bad = o;
  bad.threads = 0;
  refused(design, t, s, bad, "MonteCarloOptions.threads = 0");
  bad = o;
  bad.trials = 1000000;
  refused(design, t, s, bad, "MonteCarloOptions.trials = 1000000");
  TrackerUncertaintyModel bt = t;
  bt.angular_sigma_rad = -1e-6;
  refused(design, bt, s, o, "TrackerUncertaintyModel.angular_sigma_rad = -1e-06");
  bt = t;
  bt.radial_sigma_mm_per_m = std::nan("");
  refused(design, bt, s, o, "TrackerUncertaintyModel.radial_sigma_mm_per_m = nan");
  bt = t;
  bt.samples_per_point = 0;
  refused(design, bt, s, o, "TrackerUncertaintyModel.samples_per_point = 0");
  bt = t;
  bt.position_mm = design.points[5].commanded_mm + design.points[5].tool_offset_mm;
  refused(design, bt, s, o, "at the tracker's position");
  UncertaintySources bs = s;
  bs.repeatability_sigma_mm.y() = -0.001;
  refused(design, t, bs, o, "UncertaintySources.repeatability_sigma_mm = (0, -0.001, 0)");
  bs = s;
  bs.temperature_sigma_K.z() = -1;
  refused(design, t, bs, o, "UncertaintySources.temperature_sigma_K");
  bs = s;
  bs.errors.functions[0].hi_mm = bs.errors.functions[0].lo_mm;
  refused(design, t, bs, o, "lo_mm");
  refused(VerificationDesign{}, t, s, o, "VerificationDesign.points: empty");
  VerificationDesign bd = design;
  bd.identification_sigma_mm = 0;
  refused(bd, t, s, o, "VerificationDesign.identification_sigma_mm = 0");
  bd = design;
  bd.max_degree = 13;
  refused(bd, t, s, o, "VerificationDesign.max_degree = 13");
  bd = design;
  bd.points[3].commanded_mm.x() = std::nan("");
  refused(bd, t, s, o, "VerificationDesign.points[3] ('p3:t0').commanded_mm = (nan");
  bd = design;
  bd.points[7] = bd.points[2];
  refused(bd, t, s, o, "duplicates points[2]");
  bd.points.clear();
  for (const auto& p : design.points) {
    if (p.commanded_mm.z() == design.points.front().commanded_mm.z()) bd.points.push_back(p);
  }
  refused(bd, t, s, o, "commanded Z = 1 distinct position(s): at least 2");

  // The location search.
  TrackerRegion region;
  region.lo_mm = Vector3d(-1500, -4000, 0);
  region.hi_mm = Vector3d(4000, -1000, 2000);
  TrackerRegion r = region;
  r.lo_mm = Vector3d(300, 400, 700);  // inside the envelope only
  r.hi_mm = Vector3d(2000, 1200, 1000);
  EXPECT_THROW(
      {
        try {
          (void)best_tracker_location(design, t, r);
        } catch (const std::invalid_argument& e) {
          EXPECT_NE(
              std::string(e.what()).find("TrackerRegion: all 75 candidate positions are excluded"),
              std::string::npos)
              << e.what();
          throw;
        }
      },
      std::invalid_argument);
  r = region;
  r.max_range_mm = 600;  // every candidate sees some point farther
  EXPECT_THROW((void)best_tracker_location(design, t, r), std::invalid_argument);
  r = region;
  r.lo_mm.x() = 5000;
  EXPECT_THROW((void)best_tracker_location(design, t, r), std::invalid_argument);
  r = region;
  r.steps.y() = 0;
  EXPECT_THROW((void)best_tracker_location(design, t, r), std::invalid_argument);
  r = region;
  r.envelope_clearance_mm = -1;
  EXPECT_THROW((void)best_tracker_location(design, t, r), std::invalid_argument);
  LocationSearchOptions lo;
  lo.report = 0;
  EXPECT_THROW((void)best_tracker_location(design, t, region, lo), std::invalid_argument);
  EXPECT_THROW((void)best_tracker_location(VerificationDesign{}, t, region), std::invalid_argument);
  EXPECT_THROW((void)tracker_point_uncertainty(t, t.position_mm), std::invalid_argument);
}

}  // namespace
}  // namespace ncqual::solver

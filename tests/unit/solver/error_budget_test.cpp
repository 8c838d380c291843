// SPDX-License-Identifier: Apache-2.0
// The error budget (ncqual/solver/error_budget.hpp): the patent's geometry and example numbers,
// root sum square totals computed by hand, allocation, Monte Carlo against the RSS it must
// converge to, Weibull sampling against its closed-form mean, capability from history,
// consumption, and the config's error messages.
#include "ncqual/solver/error_budget.hpp"

#include "ncqual/common/config.hpp"
#include "ncqual/common/units.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace ncqual::solver {
namespace {

using units::deg_to_rad;
using units::inch_to_mm;

constexpr double kPi = units::kPi;

// A measured source along one axis with a default capability (tool-tip mm).
BudgetSource measured(const std::string& name, BudgetDirection dir, SourceError bound,
                      BudgetAxis metric_axis, const std::string& metric) {
  BudgetSource s;
  s.name = name;
  s.direction = dir;
  s.bound = bound;
  BudgetMetric m;
  m.name = metric;
  m.axis = metric_axis;
  m.unit = "mm";
  s.metrics.push_back(m);
  return s;
}

BudgetSource fixed(const std::string& name, BudgetDirection dir, SourceError allowance) {
  BudgetSource s;
  s.name = name;
  s.direction = dir;
  s.bound = allowance;
  return s;
}

ErrorBudgetConfig config(double allowable_mm, double theta_max_deg,
                         std::vector<BudgetSource> sources, double theta_min_deg = 0) {
  ErrorBudgetConfig c;
  c.where = "test.yaml";
  c.allowable_total_mm = allowable_mm;
  c.panel_radius_mm = inch_to_mm(74);
  c.theta_min_rad = deg_to_rad(theta_min_deg);
  c.theta_max_rad = deg_to_rad(theta_max_deg);
  c.sources = std::move(sources);
  return c;
}

SourceError y(double mm) { return {mm, 0, 0}; }
SourceError z(double mm) { return {0, mm, 0}; }
SourceError s(double mm) { return {0, 0, mm}; }

std::vector<SourceError> bounds_of(const ErrorBudgetConfig& c) {
  std::vector<SourceError> out;
  for (const auto& src : c.sources) out.push_back(src.bound);
  return out;
}

// ---- Geometry: the patent's equations -------------------------------------------------------

TEST(ErrorBudgetGeometry, PatentExampleYAndZAtTwentyFiveDegrees) {
  // A ΔY of 0.01 in at θ = 25° moves the hole 0.01 cos 25° = 0.009063 in along the panel; a ΔZ
  // of 0.01 in moves it 0.01 sin 25° = 0.004226 in.
  const double theta = deg_to_rad(25);
  EXPECT_NEAR(units::mm_to_inch(contribution_mm(y(inch_to_mm(0.01)), theta)), 0.0090631, 1e-7);
  EXPECT_NEAR(units::mm_to_inch(contribution_mm(z(inch_to_mm(0.01)), theta)), 0.0042262, 1e-7);
  EXPECT_DOUBLE_EQ(axis_sensitivity(BudgetAxis::Y, theta), std::cos(theta));
  EXPECT_DOUBLE_EQ(axis_sensitivity(BudgetAxis::Z, theta), std::sin(theta));
  EXPECT_DOUBLE_EQ(axis_sensitivity(BudgetAxis::S, theta), 1.0);
  // At θ = 0 a Z error does not move the hole along the panel at all, a Y error fully.
  EXPECT_DOUBLE_EQ(contribution_mm(z(0.3), 0), 0);
  EXPECT_DOUBLE_EQ(contribution_mm(y(0.3), 0), 0.3);
  // Along the surface: whatever θ.
  EXPECT_DOUBLE_EQ(contribution_mm(s(0.2), theta), 0.2);
}

TEST(ErrorBudgetGeometry, BothComponentsOfOneSourceAddAsRootSumSquare) {
  // Pogos and vacuum cups: ΔS = sqrt((ΔY cos θ)² + (ΔZ sin θ)²).
  const double theta = deg_to_rad(25);
  const SourceError e{0.2, 0.3, 0};
  EXPECT_NEAR(contribution_mm(e, theta), std::hypot(0.2 * std::cos(theta), 0.3 * std::sin(theta)),
              1e-15);
}

TEST(ErrorBudgetGeometry, CriticalAnglesAreTheEndsAndZeroWhenSpanned) {
  auto deg = [](const std::vector<double>& v) {
    std::vector<double> out;
    for (double r : v) out.push_back(std::round(units::rad_to_deg(r) * 1e9) / 1e9);
    return out;
  };
  EXPECT_EQ(deg(critical_angles(0, deg_to_rad(25))), (std::vector<double>{0, 25}));
  EXPECT_EQ(deg(critical_angles(deg_to_rad(-10), deg_to_rad(25))),
            (std::vector<double>{-10, 0, 25}));
  EXPECT_EQ(deg(critical_angles(deg_to_rad(5), deg_to_rad(25))), (std::vector<double>{5, 25}));
  EXPECT_EQ(deg(critical_angles(deg_to_rad(10), deg_to_rad(10))), (std::vector<double>{10}));

  const AxisWorst wy = worst_axis_sensitivity(BudgetAxis::Y, deg_to_rad(5), deg_to_rad(25));
  EXPECT_DOUBLE_EQ(wy.sensitivity, std::cos(deg_to_rad(5)));
  const AxisWorst wz = worst_axis_sensitivity(BudgetAxis::Z, deg_to_rad(-30), deg_to_rad(25));
  EXPECT_DOUBLE_EQ(wz.sensitivity, std::sin(deg_to_rad(30)));
  EXPECT_DOUBLE_EQ(wz.theta_rad, deg_to_rad(-30));
}

// ---- RSS totals ------------------------------------------------------------------------------

TEST(ErrorBudgetRss, KnownValuesByHand) {
  // Y errors of 3, 4 and 12 (thousandths of an inch) at θ = 0: sqrt(9 + 16 + 144) = 13.
  const std::vector<SourceError> e{y(3), y(4), y(12)};
  EXPECT_DOUBLE_EQ(rss_total_mm(e, 0), 13);
  // At 25°: each scales by cos 25°.
  EXPECT_NEAR(rss_total_mm(e, deg_to_rad(25)), 13 * std::cos(deg_to_rad(25)), 1e-12);
  // Mixed: Y 0.003, Z 0.004, S 0.002 at θ = 25°.
  const double t = deg_to_rad(25);
  const double by_hand = std::sqrt(std::pow(0.003 * std::cos(t), 2) +
                                   std::pow(0.004 * std::sin(t), 2) + 0.002 * 0.002);
  EXPECT_NEAR(rss_total_mm({y(0.003), z(0.004), s(0.002)}, t), by_hand, 1e-15);
}

TEST(ErrorBudgetRss, WorstInclinationMatchesADenseScan) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 0.3);
  std::uniform_real_distribution<double> angle(-60, 60);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<SourceError> e;
    for (int i = 0; i < 6; ++i) e.push_back({u(rng), u(rng), trial % 3 == 0 ? u(rng) : 0});
    double a = deg_to_rad(angle(rng)), b = deg_to_rad(angle(rng));
    if (a > b) std::swap(a, b);
    const WorstTotal w = worst_rss_total(e, a, b);
    double scan = 0;
    for (int k = 0; k <= 2000; ++k) scan = std::max(scan, rss_total_mm(e, a + (b - a) * k / 2000));
    EXPECT_GE(w.total_mm, scan - 1e-12) << trial;
    EXPECT_NEAR(w.total_mm, rss_total_mm(e, w.theta_rad), 1e-15);
    EXPECT_GE(w.theta_rad, a);
    EXPECT_LE(w.theta_rad, b);
  }
}

// ---- Allocation ----------------------------------------------------------------------------

TEST(ErrorBudgetAllocation, OnlyYSourcesGiveThePlainFormula) {
  // θ in [0, 25°], only Y sources: the worst θ is 0 and a_i = T c_i / sqrt(Σ c_j²).
  const auto c = config(0.762, 25,
                        {measured("a", BudgetDirection::Y, y(0.05), BudgetAxis::Y, "a_mm"),
                         measured("b", BudgetDirection::Y, y(0.10), BudgetAxis::Y, "b_mm"),
                         measured("c", BudgetDirection::Y, y(0.20), BudgetAxis::Y, "c_mm")});
  const Allocation a = allocate_budget(c, bounds_of(c));
  ASSERT_TRUE(a.feasible);
  const double norm = std::sqrt(0.05 * 0.05 + 0.1 * 0.1 + 0.2 * 0.2);
  EXPECT_NEAR(a.allowances[0].y_mm, 0.762 * 0.05 / norm, 1e-12);
  EXPECT_NEAR(a.allowances[1].y_mm, 0.762 * 0.10 / norm, 1e-12);
  EXPECT_NEAR(a.allowances[2].y_mm, 0.762 * 0.20 / norm, 1e-12);
  EXPECT_DOUBLE_EQ(a.theta_rad, 0);
  EXPECT_NEAR(rss_total_mm(a.allowances, 0), 0.762, 1e-12);
}

TEST(ErrorBudgetAllocation, FixedAllowancesComeOffFirst) {
  // T' = sqrt(T² - Σ f²), then a_i = T' c_i / sqrt(Σ c²).
  const auto c = config(
      1.0, 25,
      {measured("a", BudgetDirection::Y, y(0.3), BudgetAxis::Y, "a_mm"),
       measured("b", BudgetDirection::Y, y(0.4), BudgetAxis::Y, "b_mm"),
       fixed("pin", BudgetDirection::Y, y(0.6)), fixed("wander", BudgetDirection::S, s(0.0))});
  const Allocation a = allocate_budget(c, bounds_of(c));
  const double t_prime = std::sqrt(1.0 - 0.36);  // 0.8
  EXPECT_NEAR(a.allowances[0].y_mm, t_prime * 0.3 / 0.5, 1e-12);
  EXPECT_NEAR(a.allowances[1].y_mm, t_prime * 0.4 / 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(a.allowances[2].y_mm, 0.6);
  EXPECT_NEAR(a.scale, 1.6, 1e-12);
}

TEST(ErrorBudgetAllocation, RssOfAllowancesEqualsTheAllowableAtTheWorstInclination) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.01, 0.2);
  for (int trial = 0; trial < 100; ++trial) {
    std::vector<BudgetSource> sources;
    for (int i = 0; i < 5; ++i) {
      const auto dir = static_cast<BudgetDirection>(i % 4);
      const SourceError b{dir == BudgetDirection::Y || dir == BudgetDirection::YZ ? u(rng) : 0,
                          dir == BudgetDirection::Z || dir == BudgetDirection::YZ ? u(rng) : 0,
                          dir == BudgetDirection::S ? u(rng) : 0};
      sources.push_back(measured("m" + std::to_string(i), dir, b,
                                 dir == BudgetDirection::Z   ? BudgetAxis::Z
                                 : dir == BudgetDirection::S ? BudgetAxis::S
                                                             : BudgetAxis::Y,
                                 "m" + std::to_string(i) + "_mm"));
    }
    sources.push_back(fixed("f", BudgetDirection::YZ, {u(rng) / 4, u(rng) / 4, 0}));
    const double theta_min = trial % 2 ? -15 : 0;
    const auto c = config(0.762, 25 + trial % 20, sources, theta_min);
    const Allocation a = allocate_budget(c, bounds_of(c));
    ASSERT_TRUE(a.feasible) << a.why;
    const WorstTotal w = worst_rss_total(a.allowances, c.theta_min_rad, c.theta_max_rad);
    EXPECT_NEAR(w.total_mm, 0.762, 1e-12) << trial;
    EXPECT_NEAR(rss_total_mm(a.allowances, a.theta_rad), 0.762, 1e-12) << trial;
    for (int k = 0; k <= 200; ++k) {
      const double t = c.theta_min_rad + (c.theta_max_rad - c.theta_min_rad) * k / 200;
      EXPECT_LE(rss_total_mm(a.allowances, t), 0.762 + 1e-12) << trial << " at " << t;
    }
  }
}

TEST(ErrorBudgetAllocation, SharesFollowCapability) {
  // Every measured source gets the same margin k = allowance / capability: the allocation
  // follows the capability, component by component.
  const auto c = config(0.762, 25,
                        {measured("tight", BudgetDirection::Y, y(0.02), BudgetAxis::Y, "t_mm"),
                         measured("loose", BudgetDirection::Y, y(0.08), BudgetAxis::Y, "l_mm"),
                         measured("z", BudgetDirection::Z, z(0.05), BudgetAxis::Z, "z_mm"),
                         fixed("wander", BudgetDirection::S, s(0.127))});
  const Allocation a = allocate_budget(c, bounds_of(c));
  EXPECT_NEAR(a.allowances[0].y_mm / 0.02, a.scale, 1e-12);
  EXPECT_NEAR(a.allowances[1].y_mm / 0.08, a.scale, 1e-12);
  EXPECT_NEAR(a.allowances[2].z_mm / 0.05, a.scale, 1e-12);
  EXPECT_NEAR(a.allowances[1].y_mm / a.allowances[0].y_mm, 4.0, 1e-12);
  EXPECT_DOUBLE_EQ(a.allowances[3].s_mm, 0.127);

  // A source that shows a better capability gets a tighter allowance, the others more.
  std::vector<SourceError> better = bounds_of(c);
  better[1].y_mm = 0.04;
  const Allocation b = allocate_budget(c, better);
  EXPECT_LT(b.allowances[1].y_mm, a.allowances[1].y_mm);
  EXPECT_GT(b.allowances[0].y_mm, a.allowances[0].y_mm);
}

TEST(ErrorBudgetAllocation, FixedAllowancesOverTheAllowableAreInfeasible) {
  const auto c = config(0.5, 25,
                        {measured("a", BudgetDirection::Y, y(0.1), BudgetAxis::Y, "a_mm"),
                         fixed("wander", BudgetDirection::S, s(0.6))});
  const Allocation a = allocate_budget(c, bounds_of(c));
  EXPECT_FALSE(a.feasible);
  EXPECT_NE(a.why.find("fixed allowances"), std::string::npos) << a.why;
  EXPECT_DOUBLE_EQ(a.allowances[0].y_mm, 0);
}

TEST(ErrorBudgetAllocation, DerivedToleranceAndSensitivity) {
  // A Z metric in mm: ΔS per mm is sin θ, largest at 25°; its tolerance is the Z allowance.
  BudgetMetric dz{"face_dz_mm", BudgetAxis::Z, "mm", false, 0, 1.0};
  const AxisWorst sz = metric_sensitivity(dz, 0, deg_to_rad(25));
  EXPECT_DOUBLE_EQ(sz.sensitivity, std::sin(deg_to_rad(25)));
  EXPECT_DOUBLE_EQ(sz.theta_rad, deg_to_rad(25));
  EXPECT_DOUBLE_EQ(derived_tolerance(dz, {0.4, 0.25, 0}), 0.25);
  // Equivalently: the source's allowed ΔS at the metric's worst θ over the sensitivity there.
  EXPECT_NEAR(contribution_mm(z(0.25), sz.theta_rad) / sz.sensitivity, 0.25, 1e-15);

  // An angle metric in arcsec with a lever arm L = 350 mm: 1 arcsec moves the tip
  // 350 π / (180 · 3600) mm; a Y allowance of 0.0254 mm is 14.97 arcsec.
  const double mm_per_arcsec = 350 * units::kRadPerArcsec;
  BudgetMetric dc{"c_angle_error_arcsec", BudgetAxis::Y, "arcsec", true, 350, mm_per_arcsec};
  EXPECT_NEAR(metric_sensitivity(dc, 0, deg_to_rad(25)).sensitivity, mm_per_arcsec, 1e-18);
  EXPECT_NEAR(derived_tolerance(dc, y(0.0254)), 0.0254 / mm_per_arcsec, 1e-9);
  EXPECT_NEAR(derived_tolerance(dc, y(0.0254)), 14.968, 1e-3);
}

// ---- Monte Carlo ---------------------------------------------------------------------------

TEST(ErrorBudgetMonteCarlo, CoverageFactors) {
  EXPECT_NEAR(normal_coverage_factor(0.9973), 3.0, 1e-3);
  EXPECT_NEAR(normal_coverage_factor(0.95), 1.959964, 1e-6);
  EXPECT_NEAR(std::erf(normal_coverage_factor(0.9) / std::sqrt(2.0)), 0.9, 1e-12);
}

// Standard error of the p-quantile of |N(0, σ²)| from n draws: sqrt(p (1 - p) / n) / f(q) with
// f(q) = 2 φ(q / σ) / σ the density of |N| at its quantile q = k_p σ.
double quantile_standard_error(double sigma, double p, int n) {
  const double k = normal_coverage_factor(p);
  const double density = 2 * std::exp(-k * k / 2) / std::sqrt(2 * kPi) / sigma;
  return std::sqrt(p * (1 - p) / n) / density;
}

TEST(ErrorBudgetMonteCarlo, NormalSourcesConvergeToTheRss) {
  // Bounds are k_p σ; a sum of independent normals has σ_T = sqrt(Σ σ_i² s_i²), so its
  // p-quantile of |ΔS| is k_p σ_T = RSS of the bounds.
  for (double p : {0.9973, 0.95}) {
    auto c = config(0.762, 25,
                    {measured("a", BudgetDirection::Y, y(0.10), BudgetAxis::Y, "a_mm"),
                     measured("b", BudgetDirection::Y, y(0.05), BudgetAxis::Y, "b_mm"),
                     measured("c", BudgetDirection::S, s(0.08), BudgetAxis::S, "c_mm"),
                     fixed("d", BudgetDirection::Y, y(0.12))});
    c.coverage = p;
    c.samples = 400000;
    c.seed = 12345;
    const double rss = worst_rss_total(bounds_of(c), c.theta_min_rad, c.theta_max_rad).total_mm;
    const MonteCarloTotal mc = monte_carlo_total(c, bounds_of(c));
    const double sigma_total = rss / normal_coverage_factor(p);
    const double se = quantile_standard_error(sigma_total, p, c.samples);
    EXPECT_NEAR(mc.total_mm, rss, 4 * se) << "coverage " << p << " se " << se;
    EXPECT_DOUBLE_EQ(mc.theta_rad, 0);  // Y and S only: worst at θ = 0
    EXPECT_EQ(mc.samples, c.samples);
  }
}

TEST(ErrorBudgetMonteCarlo, NormalSourcesInYAndZConvergeToTheRssAtTheWorstAngle) {
  auto c = config(0.762, 25,
                  {measured("y", BudgetDirection::Y, y(0.05), BudgetAxis::Y, "y_mm"),
                   measured("z", BudgetDirection::Z, z(0.30), BudgetAxis::Z, "z_mm"),
                   measured("p", BudgetDirection::YZ, {0.04, 0.2, 0}, BudgetAxis::Y, "p_mm")});
  c.samples = 400000;
  const WorstTotal rss = worst_rss_total(bounds_of(c), c.theta_min_rad, c.theta_max_rad);
  EXPECT_DOUBLE_EQ(rss.theta_rad, deg_to_rad(25));
  const MonteCarloTotal mc = monte_carlo_total(c, bounds_of(c));
  const double se = quantile_standard_error(rss.total_mm / normal_coverage_factor(c.coverage),
                                            c.coverage, c.samples);
  // The maximum over several (strongly correlated) angles may sit slightly above the quantile at
  // the worst one: allow 5 standard errors.
  EXPECT_NEAR(mc.total_mm, rss.total_mm, 5 * se);
  EXPECT_NEAR(mc.theta_rad, deg_to_rad(25), deg_to_rad(3.2));
}

TEST(ErrorBudgetMonteCarlo, SeededAndRepeatable) {
  auto c = config(0.762, 25,
                  {measured("a", BudgetDirection::Y, y(0.1), BudgetAxis::Y, "a_mm"),
                   fixed("w", BudgetDirection::S, s(0.1))});
  c.sources[1].distribution = BudgetDistribution::Weibull;
  c.sources[1].weibull_shape = 2;
  c.samples = 20000;
  const double first = monte_carlo_total(c, bounds_of(c)).total_mm;
  EXPECT_EQ(monte_carlo_total(c, bounds_of(c)).total_mm, first);
  c.seed = 2;
  EXPECT_NE(monte_carlo_total(c, bounds_of(c)).total_mm, first);
}

TEST(ErrorBudgetMonteCarlo, WeibullSamplingMatchesItsClosedForm) {
  // |e| ~ Weibull(β, λ) with λ chosen so that P(|e| <= b) = p:
  //   E|e| = λ Γ(1 + 1/β),  Var|e| = λ² (Γ(1 + 2/β) - Γ(1 + 1/β)²).
  const double b = 0.127, p = 0.9973;
  for (double beta : {1.0, 1.5, 2.0, 3.5}) {
    const double lambda = weibull_scale_for_bound(b, beta, p);
    EXPECT_NEAR(1 - std::exp(-std::pow(b / lambda, beta)), p, 1e-12);
    std::mt19937_64 rng(99);
    const int n = 200000;
    double sum_abs = 0, sum = 0;
    int within = 0;
    for (int i = 0; i < n; ++i) {
      const double e = draw_signed_error(BudgetDistribution::Weibull, beta, b, p, rng);
      sum_abs += std::abs(e);
      sum += e;
      within += std::abs(e) <= b ? 1 : 0;
    }
    const double g1 = std::tgamma(1 + 1 / beta), g2 = std::tgamma(1 + 2 / beta);
    const double mean = lambda * g1, sd = lambda * std::sqrt(g2 - g1 * g1);
    EXPECT_NEAR(sum_abs / n, mean, 4 * sd / std::sqrt(n)) << "beta " << beta;
    // Symmetric sign: the signed mean is 0 within the spread of |e| (sd of e is sqrt(E e²)).
    EXPECT_NEAR(sum / n, 0, 4 * lambda * std::sqrt(g2) / std::sqrt(n)) << "beta " << beta;
    EXPECT_NEAR(static_cast<double>(within) / n, p, 4 * std::sqrt(p * (1 - p) / n))
        << "beta " << beta;
  }
}

TEST(ErrorBudgetMonteCarlo, UniformStaysWithinItsBoundAndNormalHasSigmaBoundOverK) {
  std::mt19937_64 rng(5);
  const int n = 100000;
  double sum_sq = 0;
  for (int i = 0; i < n; ++i) {
    const double u = draw_signed_error(BudgetDistribution::Uniform, 0, 0.2, 0.9973, rng);
    ASSERT_LE(std::abs(u), 0.2);
    const double g = draw_signed_error(BudgetDistribution::Normal, 0, 0.3, 0.9973, rng);
    sum_sq += g * g;
  }
  const double sigma = 0.3 / normal_coverage_factor(0.9973);
  // Var of the sample variance of a normal: 2 σ⁴ / n.
  EXPECT_NEAR(sum_sq / n, sigma * sigma, 4 * std::sqrt(2.0 / n) * sigma * sigma);
}

TEST(ErrorBudgetMonteCarlo, MonteCarloAllocationMatchesRssForNormalSources) {
  auto c = config(0.762, 25,
                  {measured("a", BudgetDirection::Y, y(0.05), BudgetAxis::Y, "a_mm"),
                   measured("b", BudgetDirection::Z, z(0.10), BudgetAxis::Z, "b_mm"),
                   fixed("f", BudgetDirection::Y, y(0.2))});
  const Allocation rss = allocate_budget(c, bounds_of(c));
  c.method = BudgetMethod::MonteCarlo;
  c.samples = 200000;
  const Allocation mc = allocate_budget(c, bounds_of(c));
  ASSERT_TRUE(mc.feasible);
  EXPECT_NEAR(mc.scale, rss.scale, 0.02 * rss.scale);
  // By construction the Monte Carlo total of the allowances is the allowable.
  EXPECT_NEAR(monte_carlo_total(c, mc.allowances).total_mm, 0.762, 1e-6);
}

// ---- Capability from history -----------------------------------------------------------------

TEST(ErrorBudgetCapability, MeanPlusKSigmaOrLargestSeen) {
  const std::vector<double> v{0.01, -0.01, 0.02, 0.0, 0.01};
  const MetricCapability c = capability_from_history(v, 30, 0.05, 0.9973);
  EXPECT_EQ(c.samples, 5);
  EXPECT_NEAR(c.mean, 0.006, 1e-15);
  EXPECT_NEAR(c.sigma, std::sqrt(520e-6 / 4), 1e-15);
  EXPECT_NEAR(c.max_abs, 0.02, 1e-15);
  EXPECT_NEAR(c.capability, 0.006 + normal_coverage_factor(0.9973) * c.sigma, 1e-15);
  EXPECT_EQ(c.basis, CapabilityBasis::History);

  // One outlier larger than |mean| + 3σ of the rest: the largest value seen wins.
  const MetricCapability o =
      capability_from_history({0.001, 0.001, 0.001, 0.001, 0.001, 0.001, 0.05}, 30, 0.01, 0.9973);
  EXPECT_GE(o.capability, 0.05);
}

TEST(ErrorBudgetCapability, DefaultsUntilEnoughValuesAndUsesOnlyTheNewest) {
  EXPECT_EQ(capability_from_history({}, 30, 0.05, 0.9973).capability, 0.05);
  EXPECT_EQ(capability_from_history({}, 30, 0.05, 0.9973).basis, CapabilityBasis::Default);
  // Four values: not enough to trust σ; the default, or a larger value seen.
  const MetricCapability few = capability_from_history({0.01, 0.07, 0.0, 0.0}, 30, 0.05, 0.9973);
  EXPECT_EQ(few.basis, CapabilityBasis::Default);
  EXPECT_DOUBLE_EQ(few.capability, 0.07);
  // last_n = 5 ignores the old, large values behind the newest five.
  const std::vector<double> v{0.01, 0.012, 0.009, 0.011, 0.01, 0.5, 0.6, 0.7};
  const MetricCapability newest = capability_from_history(v, 5, 0.05, 0.9973);
  EXPECT_EQ(newest.samples, 5);
  EXPECT_LT(newest.capability, 0.02);
  // A run of identical values does not claim better than a quarter of the default.
  const MetricCapability flat =
      capability_from_history(std::vector<double>(10, 0.0), 30, 0.05, 0.9973);
  EXPECT_DOUBLE_EQ(flat.capability, kCapabilityFloorFraction * 0.05);
}

// ---- Consumption -----------------------------------------------------------------------------

TEST(ErrorBudgetConsumption, LargestConsumerFirstAndSharesOfTheSquare) {
  const auto c = config(1.0, 25,
                        {measured("a", BudgetDirection::Y, y(0.1), BudgetAxis::Y, "a_mm"),
                         measured("b", BudgetDirection::Y, y(0.1), BudgetAxis::Y, "b_mm"),
                         measured("c", BudgetDirection::Z, z(0.1), BudgetAxis::Z, "c_mm"),
                         fixed("d", BudgetDirection::S, s(0.1))});
  // Today at the worst θ (0, Y dominates): a 0.3, b 0.6, c 0 (Z at θ = 0), d 0.2.
  const Consumption today = budget_consumption(c, {y(0.3), y(0.6), z(0.2), s(0.2)});
  ASSERT_EQ(today.items.size(), 4u);
  EXPECT_DOUBLE_EQ(today.theta_rad, 0);
  EXPECT_EQ(today.items[0].source, 1u);
  EXPECT_EQ(today.items[1].source, 0u);
  EXPECT_EQ(today.items[2].source, 3u);
  EXPECT_EQ(today.items[3].source, 2u);
  EXPECT_NEAR(today.items[0].share, 0.36, 1e-12);
  EXPECT_NEAR(today.items[1].share, 0.09, 1e-12);
  EXPECT_NEAR(today.rss_total_mm, std::sqrt(0.09 + 0.36 + 0.04), 1e-12);
  double shares = 0;
  for (const auto& item : today.items) shares += item.share;
  EXPECT_NEAR(shares, std::pow(today.rss_total_mm / 1.0, 2), 1e-12);
  EXPECT_TRUE(today.within_budget);

  const Consumption over = budget_consumption(c, {y(0.8), y(0.6), z(0), s(0.2)});
  EXPECT_FALSE(over.within_budget);
  EXPECT_GT(over.rss_total_mm, 1.0);
}

// A held machine is never within budget (issue 37, point 4): the total of 0.3 mm of an allowable
// 1 mm is within the arithmetic, but the machine's hold or a budget metric that failed its check
// makes the verdict HELD, whatever the total; over the allowable and not held is OVER_BUDGET.
TEST(ErrorBudgetVerdict, AHeldMachineOrAFailedMetricIsNeverWithinBudget) {
  const auto c =
      config(1.0, 25, {measured("a", BudgetDirection::Y, y(0.1), BudgetAxis::Y, "a_mm")});
  const Consumption small = budget_consumption(c, {y(0.3)});
  ASSERT_TRUE(small.within_budget);
  EXPECT_EQ(judge_budget(small, {}).verdict, BudgetVerdict::WithinBudget);
  EXPECT_TRUE(judge_budget(small, {}).why.empty());

  BudgetMachineStanding held;
  held.held = true;
  held.held_why = "NEEDS_INTERVENTION since 2026-02-09 06:00 UTC: monument_positioning FAIL";
  const BudgetJudgement j = judge_budget(small, held);
  EXPECT_EQ(j.verdict, BudgetVerdict::Held);
  EXPECT_EQ(to_string(j.verdict), "HELD");
  ASSERT_EQ(j.why.size(), 1u);
  EXPECT_EQ(j.why[0], "the machine is held: " + held.held_why);

  BudgetMachineStanding failed;
  failed.failed_metrics.push_back("a_mm = 0.3 mm out of [-0.025, 0.025]");
  EXPECT_EQ(judge_budget(small, failed).verdict, BudgetVerdict::Held);
  EXPECT_EQ(judge_budget(small, failed).why.at(0),
            "its newest check failed: a_mm = 0.3 mm out of [-0.025, 0.025]");

  const Consumption over = budget_consumption(c, {y(1.5)});
  const BudgetJudgement o = judge_budget(over, {});
  EXPECT_EQ(o.verdict, BudgetVerdict::OverBudget);
  ASSERT_EQ(o.why.size(), 1u);
  EXPECT_EQ(o.why[0], "today's total 1.5 mm is over the allowable 1 mm (150 % of it)");
  EXPECT_EQ(judge_budget(over, held).verdict, BudgetVerdict::Held);
  EXPECT_EQ(judge_budget(over, held).why.size(), 2u);
}

// ---- Everything at once ----------------------------------------------------------------------

TEST(ErrorBudgetReport, CapabilityTodayAndToleranceFromHistory) {
  auto c = config(0.762, 25,
                  {measured("machine_y", BudgetDirection::Y, y(0.1), BudgetAxis::Y, "center_dy_mm"),
                   measured("machine_z", BudgetDirection::Z, z(0.1), BudgetAxis::Z, "face_dz_mm"),
                   fixed("wander", BudgetDirection::S, s(0.127))});
  c.samples = 5000;
  MetricHistories h;
  h["center_dy_mm"] = {0.02, 0.01, -0.01, 0.0, 0.01, 0.015};
  // face_dz_mm: no values: default capability, today = capability.
  const ErrorBudgetReport r = evaluate_error_budget(c, h, 30);
  ASSERT_EQ(r.sources.size(), 3u);
  const SourceReport* my = nullptr;
  for (const auto& s : r.sources) {
    if (s.name == "machine_y") my = &s;
  }
  ASSERT_NE(my, nullptr);
  EXPECT_EQ(my->capability_basis, CapabilityBasis::History);
  const MetricCapability expected = capability_from_history(h["center_dy_mm"], 30, 0.1, 0.9973);
  EXPECT_DOUBLE_EQ(my->capability.y_mm, expected.capability);
  EXPECT_DOUBLE_EQ(my->today.y_mm, 0.02);
  EXPECT_TRUE(my->today_measured);
  ASSERT_EQ(my->metrics.size(), 1u);
  EXPECT_DOUBLE_EQ(*my->metrics[0].today_value, 0.02);
  EXPECT_DOUBLE_EQ(my->metrics[0].derived_tolerance, my->allocation.y_mm);
  EXPECT_NEAR(my->allocation.y_mm, r.allocation.scale * my->capability.y_mm, 1e-15);
  EXPECT_NEAR(r.allocation_rss.total_mm, 0.762, 1e-12);
  // Sorted: largest consumer today first.
  for (std::size_t i = 1; i < r.sources.size(); ++i) {
    EXPECT_GE(r.sources[i - 1].today_contribution_mm, r.sources[i].today_contribution_mm);
  }
  for (const auto& s : r.sources) {
    if (s.name == "machine_z") {
      EXPECT_FALSE(s.today_measured);
      EXPECT_DOUBLE_EQ(s.today.z_mm, 0.1);
      EXPECT_FALSE(s.metrics[0].today_value.has_value());
    }
    if (s.name == "wander") {
      EXPECT_EQ(s.capability_basis, CapabilityBasis::Fixed);
    }
  }
}

// ---- Config -------------------------------------------------------------------------------

TEST(ErrorBudgetConfig, ReadsTheExampleMachine) {
  const MachineConfig m = load_machine_config(NCQUAL_SOURCE_DIR "/deploy/machines/pm1.yaml");
  ASSERT_TRUE(m.budget);
  const ErrorBudgetConfig& c = *m.budget;
  EXPECT_NEAR(c.allowable_total_mm, inch_to_mm(0.03), 1e-12);
  EXPECT_NEAR(c.panel_radius_mm, inch_to_mm(74), 1e-9);
  EXPECT_NEAR(c.theta_max_rad, deg_to_rad(25), 1e-15);
  EXPECT_EQ(c.method, BudgetMethod::Rss);
  std::vector<std::string> metrics;
  for (const auto& s : c.sources) {
    for (const auto& mm : s.metrics) metrics.push_back(mm.name);
  }
  for (const char* name :
       {"probe_c_offset_mm", "c_align_dx_mm", "c_align_dy_mm", "tool_length_error_mm",
        "center_dy_mm", "face_dz_mm", "c_angle_error_arcsec", "fixture_max_dy_mm",
        "fixture_max_dz_mm", "setpoint_max_dev_mm"}) {
    EXPECT_NE(std::find(metrics.begin(), metrics.end(), name), metrics.end()) << name;
  }
  for (const auto& s : c.sources) {
    if (s.name == "c_axis_rotation") {
      // 15 arcsec × L = 350 mm.
      EXPECT_NEAR(s.bound.y_mm, units::arcsec_to_rad(15) * 350, 1e-12);
      EXPECT_TRUE(s.metrics[0].angle);
    }
    if (s.name == "drill_wander") {
      EXPECT_TRUE(s.fixed());
      EXPECT_EQ(s.distribution, BudgetDistribution::Weibull);
    }
  }
  // The default capabilities leave room: a feasible allocation that fills the allowable.
  const Allocation a = allocate_budget(c, bounds_of(c));
  ASSERT_TRUE(a.feasible) << a.why;
  EXPECT_GT(a.scale, 1.0);
  EXPECT_NEAR(worst_rss_total(a.allowances, c.theta_min_rad, c.theta_max_rad).total_mm,
              c.allowable_total_mm, 1e-12);
}

TEST(ErrorBudgetConfig, ReadsEveryKey) {
  const ErrorBudgetConfig c = parse_error_budget(R"(
allowable_total: 0.5
part: {panel_radius: "2 m", theta_min: "-10 deg", theta_max: 0.3}
statistics: {method: monte_carlo, coverage: 0.95, samples: 5000, seed: 9}
sources:
  - name: pogos
    direction: yz
    metrics: [{name: dy_mm, axis: y}, {name: dz_um, axis: z}]
    capability_y: "0.001 in"
    capability_z: 0.03
  - name: c_rot
    direction: y
    metrics: [{name: c_err, unit: arcsec, lever_arm: "10 in"}]
    capability: "20 arcsec"
    distribution: uniform
  - name: wander
    direction: s
    allowance: 0.1
    distribution: weibull
    weibull_shape: 1.5
)",
                                                 "t.yaml");
  EXPECT_DOUBLE_EQ(c.allowable_total_mm, 0.5);
  EXPECT_DOUBLE_EQ(c.panel_radius_mm, 2000);
  EXPECT_NEAR(c.theta_min_rad, deg_to_rad(-10), 1e-15);
  EXPECT_DOUBLE_EQ(c.theta_max_rad, 0.3);
  EXPECT_EQ(c.method, BudgetMethod::MonteCarlo);
  EXPECT_DOUBLE_EQ(c.coverage, 0.95);
  EXPECT_EQ(c.samples, 5000);
  EXPECT_EQ(c.seed, 9u);
  ASSERT_EQ(c.sources.size(), 3u);
  EXPECT_EQ(c.sources[0].direction, BudgetDirection::YZ);
  EXPECT_NEAR(c.sources[0].bound.y_mm, 0.0254, 1e-15);
  EXPECT_DOUBLE_EQ(c.sources[0].bound.z_mm, 0.03);
  EXPECT_EQ(c.sources[0].metrics[1].axis, BudgetAxis::Z);
  EXPECT_EQ(c.sources[0].metrics[1].unit, "um");
  EXPECT_DOUBLE_EQ(c.sources[0].metrics[1].mm_per_unit, 1e-3);
  EXPECT_NEAR(c.sources[1].metrics[0].mm_per_unit, units::kRadPerArcsec * 254, 1e-15);
  EXPECT_NEAR(c.sources[1].bound.y_mm, units::arcsec_to_rad(20) * 254, 1e-15);
  EXPECT_EQ(c.sources[1].distribution, BudgetDistribution::Uniform);
  EXPECT_TRUE(c.sources[2].fixed());
  EXPECT_DOUBLE_EQ(c.sources[2].bound.s_mm, 0.1);
  EXPECT_DOUBLE_EQ(c.sources[2].weibull_shape, 1.5);
}

struct BadBudget {
  const char* yaml;
  std::vector<std::string> message_must_name;
};

TEST(ErrorBudgetConfig, RefusesBadValuesNamingFileKeyAndValue) {
  const BadBudget cases[] = {
      {"~", {"m.yaml", "budget", "no error budget"}},
      {"[1, 2]", {"budget", "mapping"}},
      {"{allowable: 1}", {"budget.allowable", "unknown key"}},
      {"{part: {panel_radius: 1, theta_max: 0.1}, sources: []}",
       {"budget.allowable_total", "required"}},
      {"{allowable_total: -1}", {"budget.allowable_total", "'-1'", "positive"}},
      {"{allowable_total: 1 furlong}", {"budget.allowable_total", "'1 furlong'", "furlong"}},
      {"{allowable_total: 1, sources: []}", {"budget.part", "required"}},
      {"{allowable_total: 1, part: {theta_max: 0.1}}", {"budget.part.panel_radius", "required"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 100 deg}}",
       {"budget.part.theta_max", "'100 deg'", "90 deg"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_min: 30 deg, theta_max: 25 deg}}",
       {"budget.part.theta_min", "'30 deg'"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1, radius: 1}}",
       {"budget.part.radius", "unknown key"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, statistics: {method: "
       "weibull}}",
       {"budget.statistics.method", "'weibull'", "rss or monte_carlo"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, statistics: {coverage: 1.5}}",
       {"budget.statistics.coverage", "'1.5'"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, statistics: {samples: 10}}",
       {"budget.statistics.samples", "'10'"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, statistics: {seed: x}}",
       {"budget.statistics.seed", "'x'"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, sources: []}",
       {"budget.sources", "non-empty"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, sources: [{name: a, "
       "direction: x, allowance: 1}]}",
       {"budget.sources[0].direction", "'x'"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, sources: [{name: a, "
       "direction: y, allowance: 1, colour: red}]}",
       {"budget.sources[0].colour", "unknown key"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, sources: [{name: a, "
       "direction: y}]}",
       {"budget.sources[0].allowance", "required"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, sources: [{name: a, "
       "direction: y, capability: 1}]}",
       {"budget.sources[0].capability", "no metrics", "allowance"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, sources: [{name: a, "
       "direction: y, metrics: [a_mm], allowance: 1}]}",
       {"budget.sources[0].allowance", "capability"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, sources: [{name: a, "
       "direction: yz, metrics: [a_mm], capability: 1}]}",
       {"budget.sources[0].metrics[0].axis", "yz"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, sources: [{name: a, "
       "direction: y, metrics: [{name: a_mm, axis: z}], capability: 1}]}",
       {"budget.sources[0].metrics[0].axis", "'z'"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, sources: [{name: a, "
       "direction: y, metrics: [speed], capability: 1}]}",
       {"budget.sources[0].metrics[0].unit", "speed"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, sources: [{name: a, "
       "direction: y, metrics: [c_arcsec], capability: 1}]}",
       {"budget.sources[0].metrics[0].lever_arm", "required"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, sources: [{name: a, "
       "direction: y, metrics: [{name: a_mm, lever_arm: 3}], capability: 1}]}",
       {"budget.sources[0].metrics[0].lever_arm", "'3'", "angle"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, sources: [{name: a, "
       "direction: y, metrics: [a_mm], capability: 15 arcsec}]}",
       {"budget.sources[0].capability", "'15 arcsec'", "angle metric"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, sources: [{name: a, "
       "direction: y, metrics: [a_mm], capability: 0}]}",
       {"budget.sources[0].capability", "'0'", "positive"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, sources: [{name: a, "
       "direction: y, metrics: [a_mm], capability: 1, capability_z: 1}]}",
       {"budget.sources[0].capability_z", "direction is 'y'"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, sources: [{name: a, "
       "direction: yz, allowance: 1, allowance_y: 2}]}",
       {"budget.sources[0].allowance_y", "give one"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, sources: [{name: a, "
       "direction: y, allowance: 1, distribution: gamma}]}",
       {"budget.sources[0].distribution", "'gamma'"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, sources: [{name: a, "
       "direction: y, allowance: 1, distribution: weibull}]}",
       {"budget.sources[0].weibull_shape", "required"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, sources: [{name: a, "
       "direction: y, allowance: 1, distribution: weibull, weibull_shape: -2}]}",
       {"budget.sources[0].weibull_shape", "'-2'"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, sources: [{name: a, "
       "direction: y, allowance: 1, weibull_shape: 2}]}",
       {"budget.sources[0].weibull_shape", "only for"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, sources: [{name: a, "
       "direction: y, allowance: 1}, {name: a, direction: z, allowance: 1}]}",
       {"budget.sources[1].name", "'a'", "another source"}},
      {"{allowable_total: 1, part: {panel_radius: 1, theta_max: 0.1}, sources: [{name: a, "
       "direction: y, metrics: [m_mm], capability: 1}, {name: b, direction: z, metrics: [m_mm], "
       "capability: 1}]}",
       {"budget.sources[1].metrics[0]", "m_mm", "another source"}},
  };
  for (const auto& bad : cases) {
    try {
      parse_error_budget(bad.yaml, "m.yaml");
      ADD_FAILURE() << "accepted: " << bad.yaml;
    } catch (const ConfigError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind("m.yaml: ", 0), 0u) << what;
      for (const auto& part : bad.message_must_name) {
        EXPECT_NE(what.find(part), std::string::npos)
            << "message '" << what << "' does not name '" << part << "' for: " << bad.yaml;
      }
    }
  }
}

// evaluate_error_budget draws the capability's and the allocation's Monte Carlo totals in one
// pass of random numbers: each must be exactly what a run of its own gives (the same unit draws,
// scaled by its own bounds), with every distribution in the mix.
TEST(ErrorBudgetReport, BothMonteCarloTotalsOfOnePassAreThoseOfTheirOwnRuns) {
  auto c = config(
      0.762, 25,
      {measured("machine_y", BudgetDirection::Y, y(0.1), BudgetAxis::Y, "center_dy_mm"),
       measured("machine_z", BudgetDirection::Z, z(0.08), BudgetAxis::Z, "face_dz_mm"),
       fixed("wander", BudgetDirection::S, s(0.127)), fixed("pin", BudgetDirection::Y, y(0.05))});
  c.sources[1].distribution = BudgetDistribution::Uniform;
  c.sources[2].distribution = BudgetDistribution::Weibull;
  c.sources[2].weibull_shape = 2;
  c.samples = 20000;
  MetricHistories h;
  h["center_dy_mm"] = {0.02, 0.01, -0.01, 0.0, 0.01, 0.015};
  const ErrorBudgetReport r = evaluate_error_budget(c, h, 30);
  std::vector<SourceError> capabilities(c.sources.size());
  for (const auto& s : r.sources) capabilities[s.index] = s.capability;
  EXPECT_EQ(r.capability_monte_carlo.total_mm, monte_carlo_total(c, capabilities).total_mm);
  EXPECT_EQ(r.capability_monte_carlo.theta_rad, monte_carlo_total(c, capabilities).theta_rad);
  EXPECT_EQ(r.allocation_monte_carlo.total_mm,
            monte_carlo_total(c, r.allocation.allowances).total_mm);
  EXPECT_EQ(r.allocation_monte_carlo.samples, 20000);
  // The two sets differ (the allocation scales the measured sources), and so do their totals.
  EXPECT_NE(r.capability_monte_carlo.total_mm, r.allocation_monte_carlo.total_mm);
}

}  // namespace
}  // namespace ncqual::solver

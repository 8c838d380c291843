// SPDX-License-Identifier: Apache-2.0
// The error budget (patent: "Math Model Relating Production Part Accuracy to Machine System
// Parameters"). In the order of the model:
//   1. the budget as configured (read at load by the configuration layer,
//   ncqual/common/config/budget.hpp);
//   2. geometry: the ΔS of each source's error at inclination θ;
//   3. totals: root sum square, or Monte Carlo with other distributions;
//   4. capability of each source from the historian;
//   5. allocation of the allowable total, and the tolerances it implies for each check metric;
//   6. consumption: how much of the budget today's errors take.
#include "ncqual/solver/error_budget.hpp"

#include "ncqual/common/enum_names.hpp"
#include "result_building.hpp"

#include "ncqual/common/units.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <initializer_list>
#include <set>
#include <stdexcept>

namespace ncqual::solver {
namespace {

// ---- Step 3 helpers ------------------------------------------------------------------------

// Signed errors for a bound of 1 (see BudgetDistribution); callers scale them by the bound, so the
// stream of draws is the same for every bound, 0 included. Holds the per-coverage constants so a
// Monte Carlo run computes them once.
class UnitErrorSampler {
 public:
  explicit UnitErrorSampler(double coverage) : coverage_(coverage) {}

  double draw(BudgetDistribution distribution, double weibull_shape, std::mt19937_64& rng) {
    switch (distribution) {
      case BudgetDistribution::Normal:
        if (normal_sigma_ <= 0) normal_sigma_ = 1.0 / normal_coverage_factor(coverage_);
        return normal_sigma_ * normal_(rng);
      case BudgetDistribution::Uniform: return uniform_(rng);
      case BudgetDistribution::Weibull: {
        // The scale depends on the shape only (the bound is 1): computed once per shape, not per
        // draw (a pow and a log each time were a fifth of a budget's Monte Carlo).
        if (weibull_shape != weibull_shape_) {
          weibull_shape_ = weibull_shape;
          weibull_scale_ = weibull_scale_for_bound(1.0, weibull_shape, coverage_);
        }
        std::weibull_distribution<double> weibull(weibull_shape, weibull_scale_);
        const double magnitude = weibull(rng);
        return sign_(rng) ? magnitude : -magnitude;
      }
    }
    return 0;
  }

 private:
  double coverage_;
  double normal_sigma_ = 0;  // 1 / k_p, computed on the first normal draw
  double weibull_shape_ = std::numeric_limits<double>::quiet_NaN();  // of weibull_scale_
  double weibull_scale_ = 0;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::uniform_real_distribution<double> uniform_{-1.0, 1.0};
  std::bernoulli_distribution sign_{0.5};
};

// The p-quantile of |x| (x is reordered): the smallest value with at least p n values at or
// below it.
double abs_quantile(std::vector<double>& x, double p) {
  for (double& v : x) v = std::abs(v);
  const std::size_t n = x.size();
  std::size_t index = static_cast<std::size_t>(std::ceil(p * static_cast<double>(n)));
  index = std::clamp<std::size_t>(index, 1, n) - 1;
  std::nth_element(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(index), x.end());
  return x[index];
}

// Inclinations a Monte Carlo total is evaluated at: the critical angles and 9 evenly spaced (a
// quantile of non-normal sums need not follow the A + (B - A) sin²θ shape exactly).
std::vector<double> monte_carlo_angles(double theta_min, double theta_max) {
  std::vector<double> angles = critical_angles(theta_min, theta_max);
  for (int i = 0; i <= 8; ++i) angles.push_back(theta_min + (theta_max - theta_min) * i / 8.0);
  std::sort(angles.begin(), angles.end());
  angles.erase(std::unique(angles.begin(), angles.end()), angles.end());
  return angles;
}

// The draws of the error sums, split into the measured sources (scaled by a common factor during
// allocation) and the fixed ones: per draw j, ΣY_j, ΣZ_j and ΣS_j of each part, from which
// ΔS_j(θ) = ΣY_j cos θ + ΣZ_j sin θ + ΣS_j at any angle (six numbers a draw, not one per angle:
// a tenth of the memory to fill).
struct MonteCarloDraws {
  std::vector<double> angles;
  std::array<std::vector<double>, 3> measured;  // [Y, Z, S][draw]
  std::array<std::vector<double>, 3> fixed;     // [Y, Z, S][draw]
};

// The draws for each set of bounds, from one stream of random numbers: draw j of source i is the
// same unit errors for every set (each scaled by its own bound), so one pass gives each set
// exactly what a pass of its own would.
std::vector<MonteCarloDraws> draw_sets(const ErrorBudgetConfig& config,
                                       const std::vector<const std::vector<SourceError>*>& sets) {
  const std::vector<double> angles = monte_carlo_angles(config.theta_min_rad, config.theta_max_rad);
  const std::size_t n = static_cast<std::size_t>(std::max(config.samples, 1));
  std::vector<MonteCarloDraws> out(sets.size());
  for (MonteCarloDraws& d : out) {
    d.angles = angles;
    for (auto& sums : d.measured) sums.assign(n, 0.0);
    for (auto& sums : d.fixed) sums.assign(n, 0.0);
  }
  std::mt19937_64 rng(config.seed);
  UnitErrorSampler sampler(config.coverage);
  for (std::size_t j = 0; j < n; ++j) {
    for (std::size_t i = 0; i < config.sources.size(); ++i) {
      const BudgetSource& s = config.sources[i];
      // Every component is drawn, even a zero one, so that draw j of source i is the same
      // random numbers whatever the bounds.
      const double uy = sampler.draw(s.distribution, s.weibull_shape, rng);
      const double uz = sampler.draw(s.distribution, s.weibull_shape, rng);
      const double us = sampler.draw(s.distribution, s.weibull_shape, rng);
      for (std::size_t k = 0; k < sets.size(); ++k) {
        const SourceError& bound = (*sets[k])[i];
        auto& sums = s.fixed() ? out[k].fixed : out[k].measured;
        sums[0][j] += uy * bound.y_mm;
        sums[1][j] += uz * bound.z_mm;
        sums[2][j] += us * bound.s_mm;
      }
    }
  }
  return out;
}

MonteCarloDraws draw_totals(const ErrorBudgetConfig& config,
                            const std::vector<SourceError>& bounds) {
  return std::move(draw_sets(config, {&bounds}).front());
}

// The Monte Carlo total with the measured part scaled by k: max over θ of the quantile of
// |k X(θ) + F(θ)|.
MonteCarloTotal scaled_total(const MonteCarloDraws& d, double k, double coverage) {
  MonteCarloTotal best;
  const std::size_t n = d.measured[0].size();
  std::vector<double> x(n);
  for (std::size_t a = 0; a < d.angles.size(); ++a) {
    const double c = std::cos(d.angles[a]), s = std::sin(d.angles[a]);
    const auto& [my, mz, ms] = d.measured;
    const auto& [fy, fz, fs] = d.fixed;
    for (std::size_t j = 0; j < n; ++j) {
      x[j] = k * (my[j] * c + mz[j] * s + ms[j]) + (fy[j] * c + fz[j] * s + fs[j]);
    }
    const double q = abs_quantile(x, coverage);
    if (a == 0 || q > best.total_mm) {
      best.total_mm = q;
      best.theta_rad = d.angles[a];
    }
  }
  best.samples = static_cast<int>(n);
  return best;
}

SourceError scaled(const SourceError& e, double k) { return {e.y_mm * k, e.z_mm * k, e.s_mm * k}; }

}  // namespace

// ---- Names -------------------------------------------------------------------------------------

std::string_view to_string(CapabilityBasis basis) {
  constexpr std::array<std::string_view, 3> kNames = {"default", "history", "fixed"};
  return name_of(kNames, basis);
}

// ---- Step 2: geometry --------------------------------------------------------------------------

double axis_sensitivity(BudgetAxis axis, double theta_rad) {
  switch (axis) {
    case BudgetAxis::Y: return std::abs(std::cos(theta_rad));  // ΔS = ΔY cos θ
    case BudgetAxis::Z: return std::abs(std::sin(theta_rad));  // ΔS = ΔZ sin θ
    case BudgetAxis::S: return 1.0;                            // along the surface
  }
  return 0;
}

double contribution_mm(const SourceError& e, double theta_rad) {
  const double y = e.y_mm * std::cos(theta_rad);
  const double z = e.z_mm * std::sin(theta_rad);
  return std::sqrt(y * y + z * z + e.s_mm * e.s_mm);
}

std::vector<double> critical_angles(double theta_min, double theta_max) {
  std::vector<double> out{theta_min, theta_max};
  if (theta_min < 0 && theta_max > 0) out.push_back(0.0);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

AxisWorst worst_axis_sensitivity(BudgetAxis axis, double theta_min, double theta_max) {
  AxisWorst best;
  bool first = true;
  for (double t : critical_angles(theta_min, theta_max)) {
    const double s = axis_sensitivity(axis, t);
    if (first || s > best.sensitivity) best = {s, t};
    first = false;
  }
  return best;
}

// ---- Step 3: totals ----------------------------------------------------------------------------

double rss_total_mm(const std::vector<SourceError>& errors, double theta_rad) {
  double sum = 0;
  for (const auto& e : errors) {
    const double c = contribution_mm(e, theta_rad);
    sum += c * c;
  }
  return std::sqrt(sum);
}

WorstTotal worst_rss_total(const std::vector<SourceError>& errors, double theta_min,
                           double theta_max) {
  WorstTotal best;
  bool first = true;
  for (double t : critical_angles(theta_min, theta_max)) {
    const double total = rss_total_mm(errors, t);
    if (first || total > best.total_mm) best = {total, t};
    first = false;
  }
  return best;
}

double normal_coverage_factor(double coverage) {
  if (!(coverage > 0 && coverage < 1)) {
    throw std::invalid_argument("normal_coverage_factor: coverage must lie in (0, 1)");
  }
  // erf(k / sqrt 2) rises monotonically from 0 at k = 0: bisect.
  double lo = 0, hi = 40;
  for (int i = 0; i < 200 && hi - lo > 1e-15; ++i) {
    const double mid = 0.5 * (lo + hi);
    (std::erf(mid / std::sqrt(2.0)) < coverage ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double weibull_scale_for_bound(double bound, double shape, double coverage) {
  return bound / std::pow(-std::log1p(-coverage), 1.0 / shape);
}

double draw_signed_error(BudgetDistribution distribution, double weibull_shape, double bound,
                         double coverage, std::mt19937_64& rng) {
  UnitErrorSampler sampler(coverage);
  return sampler.draw(distribution, weibull_shape, rng) * bound;
}

MonteCarloTotal monte_carlo_total(const ErrorBudgetConfig& config,
                                  const std::vector<SourceError>& bounds) {
  if (bounds.size() != config.sources.size()) {
    throw std::invalid_argument("monte_carlo_total: one bound per source expected");
  }
  return scaled_total(draw_totals(config, bounds), 1.0, config.coverage);
}

// ---- Step 4: capability from the historian ------------------------------------------------------

MetricCapability capability_from_history(const std::vector<double>& values_newest_first, int last_n,
                                         double default_capability, double coverage) {
  MetricCapability c;
  std::size_t n = values_newest_first.size();
  if (last_n > 0) n = std::min(n, static_cast<std::size_t>(last_n));
  c.samples = static_cast<int>(n);
  if (n == 0) {
    c.capability = default_capability;
    return c;
  }
  double sum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sum += values_newest_first[i];
    c.max_abs = std::max(c.max_abs, std::abs(values_newest_first[i]));
  }
  c.mean = sum / static_cast<double>(n);
  if (n > 1) {
    double ss = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double d = values_newest_first[i] - c.mean;
      ss += d * d;
    }
    c.sigma = std::sqrt(ss / static_cast<double>(n - 1));
  }
  if (c.samples >= kMinHistorySamples) {
    const double k = normal_coverage_factor(coverage);
    c.capability = std::max(
        {std::abs(c.mean) + k * c.sigma, c.max_abs, kCapabilityFloorFraction * default_capability});
    c.basis = CapabilityBasis::History;
  } else {
    c.capability = std::max(default_capability, c.max_abs);
    c.basis = CapabilityBasis::Default;
  }
  return c;
}

// ---- Step 5: allocation and derived tolerances
// ----------------------------------------------------

Allocation allocate_budget(const ErrorBudgetConfig& config,
                           const std::vector<SourceError>& capabilities) {
  if (capabilities.size() != config.sources.size()) {
    throw std::invalid_argument("allocate_budget: one capability per source expected");
  }
  const double T = config.allowable_total_mm;
  std::vector<SourceError> measured(config.sources.size()), fixed(config.sources.size());
  for (std::size_t i = 0; i < config.sources.size(); ++i) {
    (config.sources[i].fixed() ? fixed : measured)[i] = capabilities[i];
  }

  Allocation a;
  // RSS: k = min over θ of sqrt((T² - F(θ)²) / C(θ)²). Both C² and F² have the form
  // A + (B - A) sin²θ, so the binding θ is one of the critical angles.
  double k = std::numeric_limits<double>::infinity();
  for (double t : critical_angles(config.theta_min_rad, config.theta_max_rad)) {
    const double F = rss_total_mm(fixed, t);
    const double C = rss_total_mm(measured, t);
    if (F > T) {
      a.feasible = false;
      a.why = "the fixed allowances alone total " + std::to_string(F) +
              " mm at θ = " + std::to_string(units::rad_to_deg(t)) + " deg, over the allowable " +
              std::to_string(T) + " mm";
      k = 0;
      a.theta_rad = t;
      break;
    }
    if (C <= 0) continue;
    const double k_t = std::sqrt((T * T - F * F) / (C * C));
    if (k_t < k) {
      k = k_t;
      a.theta_rad = t;
    }
  }
  if (!std::isfinite(k)) k = 0;  // no measured source has any capability: nothing to share

  if (a.feasible && k > 0 && config.method == BudgetMethod::MonteCarlo) {
    // Monte Carlo: the same draws for every k (common random numbers); bisect on k until the
    // coverage quantile of |k X + F| at the worst θ equals T.
    const MonteCarloDraws draws = draw_totals(config, capabilities);
    const MonteCarloTotal at_zero = scaled_total(draws, 0.0, config.coverage);
    if (at_zero.total_mm > T) {
      a.feasible = false;
      a.why = "the fixed allowances alone give a Monte Carlo total of " +
              std::to_string(at_zero.total_mm) + " mm, over the allowable " + std::to_string(T) +
              " mm";
      k = 0;
      a.theta_rad = at_zero.theta_rad;
    } else {
      double lo = 0, hi = k;
      while (scaled_total(draws, hi, config.coverage).total_mm < T && hi < 1e9) hi *= 2;
      for (int i = 0; i < 60 && hi - lo > 1e-9 * hi; ++i) {
        const double mid = 0.5 * (lo + hi);
        (scaled_total(draws, mid, config.coverage).total_mm < T ? lo : hi) = mid;
      }
      k = 0.5 * (lo + hi);
      a.theta_rad = scaled_total(draws, k, config.coverage).theta_rad;
    }
  }

  a.scale = k;
  for (std::size_t i = 0; i < config.sources.size(); ++i) {
    a.allowances.push_back(config.sources[i].fixed() ? capabilities[i]
                                                     : scaled(capabilities[i], k));
  }
  return a;
}

AxisWorst metric_sensitivity(const BudgetMetric& metric, double theta_min, double theta_max) {
  AxisWorst w = worst_axis_sensitivity(metric.axis, theta_min, theta_max);
  w.sensitivity *= metric.mm_per_unit;
  return w;
}

double derived_tolerance(const BudgetMetric& metric, const SourceError& allowance) {
  return allowance.along(metric.axis) / metric.mm_per_unit;
}

// ---- Step 6: consumption
// ---------------------------------------------------------------------------

Consumption budget_consumption(const ErrorBudgetConfig& config,
                               const std::vector<SourceError>& today) {
  Consumption c;
  c.allowable_total_mm = config.allowable_total_mm;
  const WorstTotal worst = worst_rss_total(today, config.theta_min_rad, config.theta_max_rad);
  c.theta_rad = worst.theta_rad;
  c.rss_total_mm = worst.total_mm;
  const double T2 = config.allowable_total_mm * config.allowable_total_mm;
  for (std::size_t i = 0; i < today.size(); ++i) {
    const double ds = contribution_mm(today[i], c.theta_rad);
    c.items.push_back({i, ds, ds * ds / T2});
  }
  std::stable_sort(c.items.begin(), c.items.end(), [](const auto& a, const auto& b) {
    return a.contribution_mm > b.contribution_mm;
  });
  c.within_budget = c.rss_total_mm <= config.allowable_total_mm;
  return c;
}

// ---- The budget's verdict
// ---------------------------------------------------------------------------

std::string_view to_string(BudgetVerdict verdict) {
  constexpr std::array<std::string_view, 3> kNames = {"WITHIN_BUDGET", "OVER_BUDGET", "HELD"};
  return name_of(kNames, verdict);
}

BudgetJudgement judge_budget(const Consumption& today, const BudgetMachineStanding& machine) {
  BudgetJudgement j;
  if (machine.held) j.why.push_back("the machine is held: " + machine.held_why);
  for (const std::string& m : machine.failed_metrics) {
    j.why.push_back("its newest check failed: " + m);
  }
  const double percent = 100 * today.rss_total_mm / today.allowable_total_mm;
  if (!today.within_budget) {
    j.why.push_back("today's total " + detail::format_number(today.rss_total_mm, 4) +
                    " mm is over the allowable " +
                    detail::format_number(today.allowable_total_mm, 4) + " mm (" +
                    detail::format_number(percent, 3) + " % of it)");
  }
  j.verdict = machine.held || !machine.failed_metrics.empty() ? BudgetVerdict::Held
              : today.within_budget                           ? BudgetVerdict::WithinBudget
                                                              : BudgetVerdict::OverBudget;
  return j;
}

// ---- Everything at once
// ---------------------------------------------------------------------------

ErrorBudgetReport evaluate_error_budget(const ErrorBudgetConfig& config,
                                        const MetricHistories& histories, int last_n) {
  ErrorBudgetReport r;
  r.allowable_total_mm = config.allowable_total_mm;
  r.method = config.method;
  r.coverage = config.coverage;

  std::vector<SourceReport> sources;
  std::vector<SourceError> capabilities, today;
  for (std::size_t i = 0; i < config.sources.size(); ++i) {
    const BudgetSource& s = config.sources[i];
    SourceReport sr;
    sr.index = i;
    sr.name = s.name;
    sr.description = s.description;
    sr.direction = s.direction;
    sr.fixed = s.fixed();
    sr.capability = s.bound;
    sr.today = s.bound;
    sr.capability_basis = s.fixed() ? CapabilityBasis::Fixed : CapabilityBasis::Default;
    sr.today_measured = !s.fixed();

    SourceError from_history, newest;
    std::set<BudgetAxis> axes_with_history, axes_with_today;
    for (const BudgetMetric& m : s.metrics) {
      MetricReport mr;
      mr.name = m.name;
      mr.axis = m.axis;
      mr.unit = m.unit;
      mr.mm_per_unit = m.mm_per_unit;
      mr.sensitivity = metric_sensitivity(m, config.theta_min_rad, config.theta_max_rad);
      static const std::vector<double> kNone;
      const auto it = histories.find(m.name);
      const std::vector<double>& values = it == histories.end() ? kNone : it->second;
      const double default_in_unit = s.bound.along(m.axis) / m.mm_per_unit;
      mr.capability = capability_from_history(values, last_n, default_in_unit, config.coverage);
      if (mr.capability.samples > 0) {
        // Each axis: the largest capability among its metrics that have values.
        double& h = from_history.along(m.axis);
        h = std::max(h, mr.capability.capability * m.mm_per_unit);
        axes_with_history.insert(m.axis);
        if (mr.capability.basis == CapabilityBasis::History) {
          sr.capability_basis = CapabilityBasis::History;
        }
        mr.today_value = values.front();
        double& t = newest.along(m.axis);
        t = std::max(t, std::abs(values.front()) * m.mm_per_unit);
        axes_with_today.insert(m.axis);
      }
      sr.metrics.push_back(std::move(mr));
    }
    for (BudgetAxis axis : axes_with_history) sr.capability.along(axis) = from_history.along(axis);
    for (BudgetAxis axis : axes_of(s.direction)) {
      if (s.fixed()) break;
      if (axes_with_today.count(axis)) {
        sr.today.along(axis) = newest.along(axis);
      } else {
        sr.today.along(axis) = sr.capability.along(axis);  // nothing measured yet
        sr.today_measured = false;
      }
    }
    capabilities.push_back(sr.capability);
    today.push_back(sr.today);
    sources.push_back(std::move(sr));
  }

  r.allocation = allocate_budget(config, capabilities);
  r.capability_rss = worst_rss_total(capabilities, config.theta_min_rad, config.theta_max_rad);
  r.allocation_rss =
      worst_rss_total(r.allocation.allowances, config.theta_min_rad, config.theta_max_rad);
  {
    // Both Monte Carlo totals from one pass of draws: the same figures as two monte_carlo_total
    // calls, at half the cost (the draws are most of a page's budget).
    const std::vector<MonteCarloDraws> draws =
        draw_sets(config, {&capabilities, &r.allocation.allowances});
    r.capability_monte_carlo = scaled_total(draws[0], 1.0, config.coverage);
    r.allocation_monte_carlo = scaled_total(draws[1], 1.0, config.coverage);
  }
  r.today = budget_consumption(config, today);

  for (SourceReport& sr : sources) {
    const BudgetSource& s = config.sources[sr.index];
    sr.allocation = r.allocation.allowances[sr.index];
    sr.capability_contribution_mm = contribution_mm(sr.capability, r.allocation.theta_rad);
    sr.allocation_contribution_mm = contribution_mm(sr.allocation, r.allocation.theta_rad);
    for (std::size_t k = 0; k < s.metrics.size(); ++k) {
      MetricReport& mr = sr.metrics[k];
      mr.derived_tolerance = derived_tolerance(s.metrics[k], sr.allocation);
      mr.today_within_tolerance =
          !mr.today_value || std::abs(*mr.today_value) <= mr.derived_tolerance;
    }
  }
  for (const ConsumptionItem& item : r.today.items) {
    SourceReport& sr = sources[item.source];
    sr.today_contribution_mm = item.contribution_mm;
    sr.share = item.share;
    r.sources.push_back(std::move(sr));
  }
  return r;
}

}  // namespace ncqual::solver

// SPDX-License-Identifier: Apache-2.0
// The error budget: how each machine and fixture error moves the hole on the part, how they add
// up, and how much of the part tolerance each error source may take.
//
// Patent ("Math Model Relating Production Part Accuracy to Machine System Parameters"): a panel
// of radius R is drilled at a point B at inclination θ from the horizontal plane; a hole is
// mislocated along the panel by ΔS. An error ΔY in Y moves it by
//     ΔS = ΔY · cos θ,
// an error ΔZ in Z by
//     ΔS = ΔZ · sin θ,
// and every source of error (pogos and vacuum cups, set-point block, C-axis alignment, composite
// tool length ΔL, the W, A and C axes, machine Y and Z positioning, locator pin, drill wander,
// panel bowing, ...) contributes its ΔS_i that way. Assuming the sources independent and
// normally distributed, the total is the root sum square
//     ΔS_T = sqrt(Σ ΔS_i²);
// other statistics (e.g. Weibull) may be used instead. A maximum allowable total is set from the
// part tolerance (e.g. 0.03 in for a 74 in radius panel with θ up to 25°) and shared among the
// sources so that the total stays within it, each source getting an allowance it can
// realistically hold.
//
// Everything here is a pure function of its arguments: no files, no clocks, no storage. Units are
// mm and rad inside; the config may write inches, degrees and arc-seconds.
#pragma once

#include "ncqual/common/config/budget.hpp"

#include <cstdint>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

namespace ncqual::solver {

// The configuration (BudgetAxis, BudgetSource, ErrorBudgetConfig, ...) is in
// ncqual/common/config/budget.hpp: a machine config holds it as MachineConfig::budget.

// ---- Geometry -----------------------------------------------------------------------------------

// |ΔS| per unit of error along `axis` at inclination θ: |cos θ| (Y), |sin θ| (Z), 1 (S).
double axis_sensitivity(BudgetAxis axis, double theta_rad);

// ΔS of one source's error at θ. The components of one source are independent, so they add as
// a root sum square (for the pogos and vacuum cups, patent ΔS_1):
//   ΔS_i(θ) = sqrt((ΔY cos θ)² + (ΔZ sin θ)² + ΔS_s²).
double contribution_mm(const SourceError& error, double theta_rad);

// Inclinations at which a budget total can be largest over θ_min..θ_max. Every total here has
// the form ΔS_T(θ)² = A cos²θ + B sin²θ + C = A + C + (B - A) sin²θ, so its extremes lie where
// sin²θ is smallest (θ = 0 when the range spans it, else the end nearest 0) or largest (the end
// furthest from 0). Sorted, without repeats.
std::vector<double> critical_angles(double theta_min_rad, double theta_max_rad);

// Largest |ΔS| per unit of error along `axis` over θ_min..θ_max, and where.
struct AxisWorst {
  double sensitivity = 0;
  double theta_rad = 0;
};
AxisWorst worst_axis_sensitivity(BudgetAxis axis, double theta_min_rad, double theta_max_rad);

// ---- Totals -------------------------------------------------------------------------------------

// Patent: ΔS_T(θ) = sqrt(Σ_i ΔS_i(θ)²).
double rss_total_mm(const std::vector<SourceError>& errors, double theta_rad);

struct WorstTotal {
  double total_mm = 0;
  double theta_rad = 0;
};
// max over θ_min..θ_max of rss_total_mm (evaluated at critical_angles; the first on ties).
WorstTotal worst_rss_total(const std::vector<SourceError>& errors, double theta_min_rad,
                           double theta_max_rad);

// k with P(|N(0,1)| <= k) = coverage, i.e. erf(k / sqrt 2) = coverage; 3.0 for 0.9973,
// 1.96 for 0.95. coverage in (0, 1).
double normal_coverage_factor(double coverage);

// Weibull scale λ such that P(|e| <= bound) = coverage for |e| ~ Weibull(shape, λ):
//   1 - exp(-(b/λ)^β) = p  =>  λ = b / (-ln(1 - p))^(1/β).
double weibull_scale_for_bound(double bound, double shape, double coverage);

// One signed error drawn from `distribution` scaled to `bound` (see BudgetDistribution).
// A bound of 0 gives 0 (after drawing, so that the stream of draws does not depend on it).
double draw_signed_error(BudgetDistribution distribution, double weibull_shape, double bound,
                         double coverage, std::mt19937_64& rng);

struct MonteCarloTotal {
  double total_mm = 0;   // the coverage quantile of |ΔS| at the worst inclination
  double theta_rad = 0;  // that inclination
  int samples = 0;
};
// Monte Carlo total: per draw, a signed error for every component of every source from its
// distribution scaled to `bounds[i]` (one per config.sources, in order), then
//   ΔS(θ) = Σ_i (e_iY cos θ + e_iZ sin θ + e_iS),
// for θ at the critical angles and 9 evenly spaced ones; the result is the largest over θ of the
// `config.coverage` quantile of |ΔS|. Seeded with config.seed: the same inputs give the same
// answer. With normal sources it converges to the RSS of the bounds (both are k_p σ_T).
MonteCarloTotal monte_carlo_total(const ErrorBudgetConfig& config,
                                  const std::vector<SourceError>& bounds);

// ---- Capability from the historian -----------------------------------------------------------

// A source holds its default capability until a metric has this many values.
inline constexpr int kMinHistorySamples = 5;
// History never claims a source better than this fraction of its default capability: a run of
// identical values (a simulator without noise) would otherwise leave the source no allowance.
inline constexpr double kCapabilityFloorFraction = 0.25;

enum class CapabilityBasis { Default, History, Fixed };
std::string_view to_string(CapabilityBasis basis);

struct MetricCapability {
  int samples = 0;   // values used (the newest `last_n`)
  double mean = 0;   // in the metric's unit
  double sigma = 0;  // sample standard deviation (n - 1), 0 for one value
  double max_abs = 0;
  // The bound the metric's values stay within at the configured coverage, in the metric's unit:
  //   samples >= kMinHistorySamples:  max(|mean| + k_p σ, max |value|, floor)
  //   otherwise:                      max(default, max |value|)
  // with k_p = normal_coverage_factor(coverage) (the same k that reads bounds as k_p σ
  // everywhere else) and floor = kCapabilityFloorFraction · default. |mean| + k_p σ covers a
  // normal process at coverage p, bias included; max |value| keeps a short history honest about
  // what it has actually seen.
  double capability = 0;
  CapabilityBasis basis = CapabilityBasis::Default;
};
// `values_newest_first` in the metric's unit; only the first `last_n` are used (all if <= 0).
// `default_capability` in the metric's unit.
MetricCapability capability_from_history(const std::vector<double>& values_newest_first, int last_n,
                                         double default_capability, double coverage);

// ---- Allocation and derived tolerances ---------------------------------------------------------

struct Allocation {
  // Per source (config order): its allowance, tool-tip mm. Fixed sources keep their allowance;
  // measured ones get scale · capability.
  std::vector<SourceError> allowances;
  double scale = 0;      // k: allowance / capability of every measured source
  double theta_rad = 0;  // where the total of the allowances reaches the allowable
  bool feasible = true;  // false when the fixed allowances alone exceed the allowable
  std::string why;       // when not feasible, in words
};
// Shares the allowable total T among the measured sources in proportion to their capabilities
// c_i, after the fixed allowances f_j have taken theirs:
//   a_i = k · c_i,  k = min over θ of sqrt((T² - F(θ)²) / C(θ)²),
// with C(θ) = sqrt(Σ ΔS_i(θ; c_i)²) over measured sources and F(θ) likewise over fixed ones.
// The RSS of all allowances then equals T at the worst inclination and stays under it elsewhere.
// Every source gets the same margin k over what it has shown it can hold: a source that holds
// tightly gets a tight allowance, one that wanders a looser one, and none is asked for an accuracy
// it has never demonstrated. With only Y sources at θ = 0 this is the plain a_i = T' c_i / sqrt(Σ
// c_j²) (T'² = T² - Σ f_j²). With method monte_carlo, k is found by bisection instead so that the
// Monte Carlo total of the allowances equals T (same draws for every k).
Allocation allocate_budget(const ErrorBudgetConfig& config,
                           const std::vector<SourceError>& capabilities);

// ΔS per unit of `metric` at the inclination where that metric matters most:
//   sensitivity = mm_per_unit · max over θ of axis_sensitivity(axis, θ)   (mm per metric unit).
AxisWorst metric_sensitivity(const BudgetMetric& metric, double theta_min_rad,
                             double theta_max_rad);

// The tolerance (±, in the metric's unit) a check should hold the metric to so that its source
// stays within `allowance`: the allowance along the metric's axis over the tool-tip displacement
// per unit of the metric. Equivalently: the source's allowed ΔS at the metric's worst θ divided by
// the metric's sensitivity there.
double derived_tolerance(const BudgetMetric& metric, const SourceError& allowance);

// ---- Consumption --------------------------------------------------------------------------------

struct ConsumptionItem {
  std::size_t source = 0;      // index into config.sources
  double contribution_mm = 0;  // ΔS_i at the consumption's θ
  double share = 0;            // ΔS_i² / T²: its part of the allowable (shares add up to
                               // (ΔS_T / T)², 1 exactly at the limit)
};
struct Consumption {
  std::vector<ConsumptionItem> items;  // largest consumer first
  double theta_rad = 0;                // the inclination where today's total is largest
  double rss_total_mm = 0;             // ΔS_T of today's errors there
  double allowable_total_mm = 0;
  bool within_budget = true;  // rss_total_mm <= allowable_total_mm: the arithmetic alone; the
                              // verdict, with the machine's standing, is judge_budget's
};
// How much of the budget today's errors (one per config.sources, tool-tip mm) use. Today is one
// state, not a distribution, so the total is the patent's RSS whatever the configured method.
Consumption budget_consumption(const ErrorBudgetConfig& config,
                               const std::vector<SourceError>& today);

// ---- The budget's verdict -----------------------------------------------------------------------

// What the budget's arithmetic cannot see: the machine's own standing in the historian. The budget
// shares the part's tolerance among error sources; a machine held by its qualification process
// (NEEDS_INTERVENTION), or whose newest value of a budget metric failed its check, is not released
// to cut parts however small its errors' total is, so the budget never calls it within budget.
struct BudgetMachineStanding {
  // The machine's newest stored status is NEEDS_INTERVENTION; `held_why` says since when and why
  // ("NEEDS_INTERVENTION since <time>: <detail>").
  bool held = false;
  std::string held_why;
  // Budget metrics whose newest value failed the configured tolerance of its check, in words
  // ("face_dz_mm = 0.0512 mm out of [-0.025, 0.025] (monument_positioning, FAIL)").
  std::vector<std::string> failed_metrics;
};

enum class BudgetVerdict {
  WithinBudget,  // today's total within the allowable, the machine not held, no metric failed
  OverBudget,    // today's total over the allowable (the machine not held)
  Held,          // the machine is held or a budget metric's newest check failed: never "within"
};
std::string_view to_string(BudgetVerdict verdict);  // "WITHIN_BUDGET", "OVER_BUDGET", "HELD"

struct BudgetJudgement {
  BudgetVerdict verdict = BudgetVerdict::WithinBudget;
  std::vector<std::string> why;  // each reason in words, the machine's standing first
};
// The verdict of `today` (budget_consumption) given the machine's standing: Held when the machine
// is held or any budget metric failed (whatever the total), else OverBudget when the total is over
// the allowable, else WithinBudget.
BudgetJudgement judge_budget(const Consumption& today, const BudgetMachineStanding& machine);

// ---- Everything at once -------------------------------------------------------------------------

// Values of each metric from the historian, newest first, in the metric's unit.
using MetricHistories = std::map<std::string, std::vector<double>>;

struct MetricReport {
  std::string name;
  BudgetAxis axis = BudgetAxis::Y;
  std::string unit;
  double mm_per_unit = 1;
  AxisWorst sensitivity;               // mm of ΔS per metric unit, and where
  MetricCapability capability;         // metric unit
  std::optional<double> today_value;   // the newest value, signed, metric unit
  double derived_tolerance = 0;        // ±, metric unit
  bool today_within_tolerance = true;  // |today_value| <= derived_tolerance (true without a value)
};

struct SourceReport {
  std::size_t index = 0;  // into config.sources
  std::string name;
  std::string description;
  BudgetDirection direction = BudgetDirection::Y;
  bool fixed = false;
  SourceError capability;                                       // tool-tip mm
  CapabilityBasis capability_basis = CapabilityBasis::Default;  // History when any metric has
                                                                // enough values
  SourceError allocation;                                       // tool-tip mm
  double capability_contribution_mm = 0;                        // ΔS at the allocation's θ
  double allocation_contribution_mm = 0;                        // ΔS at the allocation's θ
  SourceError today;                 // tool-tip mm: newest values, else the capability
  bool today_measured = false;       // every axis of the source has a newest value
  double today_contribution_mm = 0;  // ΔS at today's θ
  double share = 0;                  // today_contribution² / T²
  std::vector<MetricReport> metrics;
};

struct ErrorBudgetReport {
  double allowable_total_mm = 0;
  BudgetMethod method = BudgetMethod::Rss;
  double coverage = 0;
  WorstTotal capability_rss;  // RSS of the capabilities at their worst θ
  MonteCarloTotal capability_monte_carlo;
  WorstTotal allocation_rss;  // equals the allowable when feasible (method rss)
  MonteCarloTotal allocation_monte_carlo;
  Allocation allocation;
  Consumption today;
  std::vector<SourceReport> sources;  // largest consumer today first
};

// Capability of every source from the newest `last_n` values of its metrics (each axis: the
// largest capability, in tool-tip mm, among its metrics that have values; the default when none
// has), the allocation, the derived tolerance of every metric, today's consumption (each axis:
// the largest |newest value| of its metrics; the capability for an axis with no value yet; the
// allowance for fixed sources) and the totals.
ErrorBudgetReport evaluate_error_budget(const ErrorBudgetConfig& config,
                                        const MetricHistories& histories, int last_n);

}  // namespace ncqual::solver

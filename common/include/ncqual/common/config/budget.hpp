// SPDX-License-Identifier: Apache-2.0
// The error budget's section of a machine config (`budget:`), as read by the configuration layer
// (common/src/config/budget_section.cpp; see deploy/machines/pm1.yaml for a documented example).
// The model that uses it, and what each field means to it, is ncqual/solver/error_budget.hpp; the
// section lives here because a machine config holds it typed, read and checked at load.
//
// Read rules: `allowable_total`, `part: {panel_radius, theta_min, theta_max}` and a non-empty list
// of `sources` are required; `statistics: {method: rss | monte_carlo, coverage, samples, seed}` is
// optional. A source has a name (unique), a direction (y, z, s, yz) and either metrics (the checks'
// metrics that measure it; each metric in one source only) with a default `capability`, or no
// metrics and a fixed `allowance`; per-axis bounds as `capability_y` etc. Unknown keys are refused.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace ncqual::solver {

// ---- Configuration ----------------------------------------------------------------------------

// The component of the tool-tip displacement a measurement or a source error lies along.
//   Y: across the panel, ΔS = ΔY · cos θ;
//   Z: vertical, ΔS = ΔZ · sin θ;
//   S: along the panel surface itself (e.g. drill wander on entry), ΔS = ΔS_s, whatever θ.
enum class BudgetAxis { Y, Z, S };

// How a source moves the tool tip: along one axis, or in Y and Z at once (pogos and vacuum cups).
enum class BudgetDirection { Y, Z, S, YZ };

enum class BudgetMethod { Rss, MonteCarlo };

// The distribution of a source's signed error for the Monte Carlo total. The source's bound b
// (capability or allowance) is read as the value its error stays within with the configured
// coverage p:
//   normal:  e ~ N(0, σ²) with σ = b / k_p, k_p = normal_coverage_factor(p) (3 for p = 0.9973);
//   uniform: e ~ U(-b, b) (b is a hard limit: P(|e| <= b) = 1);
//   weibull: |e| ~ Weibull(shape β, scale λ), random sign, λ = weibull_scale_for_bound(b, β, p)
//            so that P(|e| <= b) = p.
enum class BudgetDistribution { Normal, Uniform, Weibull };

std::string_view to_string(BudgetAxis axis);
std::string_view to_string(BudgetDirection direction);
std::string_view to_string(BudgetMethod method);
std::string_view to_string(BudgetDistribution distribution);

// The axes a direction moves the tool tip along: Y, Z, S, or Y and Z.
std::vector<BudgetAxis> axes_of(BudgetDirection direction);

// A tool-tip displacement (mm) split into the components the budget knows.
struct SourceError {
  double y_mm = 0;
  double z_mm = 0;
  double s_mm = 0;

  double along(BudgetAxis axis) const;
  double& along(BudgetAxis axis);
};

// A metric published by a check (historian name) and how one unit of it moves the tool tip.
struct BudgetMetric {
  std::string name;  // e.g. "center_dy_mm", "c_angle_error_arcsec"
  BudgetAxis axis = BudgetAxis::Y;
  std::string unit;         // unit of the metric's values: "mm", "um", "in", "arcsec", "deg", ...
  bool angle = false;       // an angle metric (unit rad, mrad, urad, deg, arcsec)
  double lever_arm_mm = 0;  // angle metrics: tool-tip displacement = angle (rad) · lever arm
  // Tool-tip displacement (mm) per unit of the metric: the length factor of `unit`, or the angle
  // factor of `unit` (rad per unit) times the lever arm.
  double mm_per_unit = 1;
};

struct BudgetSource {
  std::string name;
  std::string description;
  BudgetDirection direction = BudgetDirection::Y;
  // The checks' metrics that measure this source; empty for a source no check measures (drill
  // wander, locator pin, ...), which then holds a fixed allowance.
  std::vector<BudgetMetric> metrics;
  // Measured sources: the default capability, the error the source realistically holds, used
  // until the historian has enough data. Unmeasured sources: the fixed allowance. Tool-tip mm;
  // only the components of `direction` are non-zero.
  SourceError bound;
  BudgetDistribution distribution = BudgetDistribution::Normal;
  double weibull_shape = 0;  // β, weibull only

  bool fixed() const { return metrics.empty(); }
};

struct ErrorBudgetConfig {
  std::string where;              // file it was read from, for messages
  double allowable_total_mm = 0;  // maximum allowable ΔS_T
  double panel_radius_mm = 0;     // R, to say where on the panel the worst hole is (S = R θ)
  double theta_min_rad = 0;       // hole inclinations on the part: θ_min <= θ <= θ_max
  double theta_max_rad = 0;
  BudgetMethod method = BudgetMethod::Rss;
  double coverage = 0.9973;  // probability the bounds and totals stand for
  int samples = 100000;      // Monte Carlo draws
  std::uint64_t seed = 1;    // Monte Carlo seed (std::mt19937_64)
  std::vector<BudgetSource> sources;
};

}  // namespace ncqual::solver

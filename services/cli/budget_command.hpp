// `ncqual budget`: the machine's error budget against its history.
//
//   ncqual budget --machine M [--plant F] [--db F] [--last N] [--json]
//
// Reads the machine's `budget:` section from the plant config (--plant or NCQUAL_PLANT), the
// newest N (default 30) values of every budget metric from the historian (--db, else the plant's
// historian database; read only, never written), and prints per source its capability, its
// allowance and its share of today's budget (largest consumer first), per check metric the
// derived tolerance beside the configured one, and the RSS and Monte Carlo totals. The math is
// ncqual::solver::evaluate_error_budget; this command only gathers and prints.
//
// --json prints one document; its names are a public interface (append, never rename):
//   {"machine_id", "config", "database" (null when there is no historian file), "last",
//    "method": "rss" | "monte_carlo", "coverage",
//    "allowable_total_mm", "allowable_total_in", "panel_radius_mm", "theta_min_deg",
//    "theta_max_deg",
//    "rss_total_mm", "rss_total_in", "rss_theta_deg": today's total (RSS of the newest values),
//    "within_budget": rss_total_mm <= allowable_total_mm,
//    "monte_carlo_total_mm", "monte_carlo_theta_deg", "monte_carlo_samples": the Monte Carlo total
//        of the capabilities at the coverage,
//    "capability_rss_total_mm", "capability_rss_theta_deg", "allocation_rss_total_mm",
//    "allocation_monte_carlo_total_mm",
//    "allocation": {"scale", "theta_deg", "feasible", "why"},
//    "sources": [largest consumer today first: {"name", "description", "direction", "fixed",
//        "capability_basis": "default" | "history" | "fixed",
//        "capability_mm": {"y", "z", "s"}, "allocation_mm": {"y", "z", "s"}  (tool-tip mm),
//        "capability_contribution_mm", "allocation_contribution_mm"  (ΔS at allocation.theta_deg),
//        "today_mm": {"y", "z", "s"}, "today_measured", "today_contribution_mm" (ΔS at
//        rss_theta_deg), "share" (today_contribution² / allowable²),
//        "metrics": [{"name", "axis", "unit", "sensitivity" (mm of ΔS per unit),
//            "sensitivity_theta_deg", "samples", "mean", "sigma", "max_abs", "capability",
//            "capability_basis", "derived_tolerance" (±, metric unit),
//            "configured_tolerance": {"lower", "upper"} | null (metric unit),
//            "today_value" | null, "today_time_ns" | null, "today_within_derived_tolerance"}]}]}
//
// Returns 0 when it printed, 1 on an error it reported (unknown machine, no budget section, bad
// config, unreadable historian). Throws ArgError for bad usage (the caller prints it and exits 2).
#pragma once

#include "ncqual/args.hpp"

#include <set>
#include <string>

namespace ncqual {

// The flags `ncqual budget` takes with a value, and its switches.
inline const std::set<std::string> kBudgetFlagsWithValue{"plant", "db", "machine", "last"};
inline const std::set<std::string> kBudgetSwitches{"json"};

int run_budget_command(const Args& args);

}  // namespace ncqual

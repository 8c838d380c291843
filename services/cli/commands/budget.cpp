// SPDX-License-Identifier: Apache-2.0
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
// --json prints one document (BudgetDocument below); its names are a public interface (append,
// never rename):
//   {"machine_id", "config", "database" (null when there is no historian file), "last",
//    "method": "rss" | "monte_carlo", "coverage",
//    "allowable_total_mm", "allowable_total_in", "panel_radius_mm", "theta_min_deg",
//    "theta_max_deg",
//    "rss_total_mm", "rss_total_in", "rss_theta_deg": today's total (RSS of the newest values),
//    "within_budget": the budget's verdict is WITHIN_BUDGET (never for a held machine),
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
//            "today_value" | null, "today_time_ns" | null, "today_within_derived_tolerance"}]}],
//    "total_within_allowable": rss_total_mm <= allowable_total_mm (the arithmetic alone),
//    "verdict": "WITHIN_BUDGET" | "OVER_BUDGET" | "HELD" (solver::judge_budget: HELD when the
//        machine's newest status is NEEDS_INTERVENTION or a budget metric's newest value failed
//        its check, whatever the total), "verdict_why": [text], "held": the machine's status,
//    "failed_metrics": [text] (budget metrics whose newest value failed its check)}
//
// What the figures mean (also printed under the table): a source's share is its ΔS² over the
// allowable's square (the shares add up to (total / allowable)², 100 % at the limit); a metric's
// derived tolerance is how far it may read before its source uses its allowance of the part's
// tolerance (the allowance over ΔS per unit of the metric), the part's view, which differs from the
// configured tolerance, the check's own (the machine's qualification standard, usually tighter):
// checks are judged against the configured one.
//
// Returns 0 when it printed, 1 on an error it reported (no budget section, bad config, unreadable
// historian), 2 on bad usage (and a machine the plant does not configure).
#include "commands.hpp"

#include "ncqual/common/config.hpp"
#include "ncqual/common/json.hpp"
#include "ncqual/report/budget_history.hpp"
#include "ncqual/solver/error_budget.hpp"
#include "ncqual/storage/database.hpp"
#include "ncqual/common/units.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace ncqual::cli {
namespace {

using solver::ErrorBudgetConfig;
using solver::ErrorBudgetReport;

// What the historian holds for the budget's metrics (shared with `ncqual report`).
using GatheredHistory = report::BudgetHistory;

GatheredHistory gather_history(storage::Database& db, const std::string& machine_id,
                               const ErrorBudgetConfig& budget) {
  return report::gather_budget_history(db, machine_id, budget);
}

double deg(double rad) { return units::rad_to_deg(rad); }

// The configured tolerance of a metric in the metric's unit: length tolerances are stored in mm.
std::optional<Tolerance> configured_tolerance(const MachineConfig& machine,
                                              const solver::MetricReport& m) {
  const auto it = machine.tolerances.find(m.name);
  if (it == machine.tolerances.end()) return std::nullopt;
  Tolerance t = it->second;
  if (const auto f = units::to_internal_factor(units::Dimension::Length, m.unit)) {
    t.lower /= *f;
    t.upper /= *f;
  }
  return t;
}

// ---- JSON ---------------------------------------------------------------------------------------

// The --json document (names: the file comment above). A non-finite tolerance bound, a
// one-sided band, is null (ncqual/common/json.hpp).
struct ComponentsDocument {
  double y = 0, z = 0, s = 0;
};
struct ToleranceDocument {
  double lower = 0, upper = 0;
};
struct MetricDocument {
  std::string name, axis, unit;
  double sensitivity = 0, sensitivity_theta_deg = 0;
  int samples = 0;
  double mean = 0, sigma = 0, max_abs = 0, capability = 0;
  std::string capability_basis;
  double derived_tolerance = 0;
  std::optional<ToleranceDocument> configured_tolerance;
  std::optional<double> today_value;
  std::optional<std::int64_t> today_time_ns;
  bool today_within_derived_tolerance = true;
};
struct SourceDocument {
  std::string name, description, direction;
  bool fixed = false;
  std::string capability_basis;
  ComponentsDocument capability_mm, allocation_mm;
  double capability_contribution_mm = 0, allocation_contribution_mm = 0;
  ComponentsDocument today_mm;
  bool today_measured = false;
  double today_contribution_mm = 0, share = 0;
  std::vector<MetricDocument> metrics;
};
struct AllocationDocument {
  double scale = 0, theta_deg = 0;
  bool feasible = true;
  std::string why;
};
struct BudgetDocument {
  std::string machine_id, config;
  std::optional<std::string> database;
  int last = 0;
  std::string method;
  double coverage = 0, allowable_total_mm = 0, allowable_total_in = 0, panel_radius_mm = 0;
  double theta_min_deg = 0, theta_max_deg = 0;
  double rss_total_mm = 0, rss_total_in = 0, rss_theta_deg = 0;
  bool within_budget = false;
  double monte_carlo_total_mm = 0, monte_carlo_theta_deg = 0;
  int monte_carlo_samples = 0;
  double capability_rss_total_mm = 0, capability_rss_theta_deg = 0;
  double allocation_rss_total_mm = 0, allocation_monte_carlo_total_mm = 0;
  AllocationDocument allocation;
  std::vector<SourceDocument> sources;
  bool total_within_allowable = false;
  std::string verdict;
  std::vector<std::string> verdict_why;
  bool held = false;
  std::vector<std::string> failed_metrics;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(ComponentsDocument, y, z, s)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(ToleranceDocument, lower, upper)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(MetricDocument, name, axis, unit, sensitivity,
                                   sensitivity_theta_deg, samples, mean, sigma, max_abs, capability,
                                   capability_basis, derived_tolerance, configured_tolerance,
                                   today_value, today_time_ns, today_within_derived_tolerance)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(SourceDocument, name, description, direction, fixed,
                                   capability_basis, capability_mm, allocation_mm,
                                   capability_contribution_mm, allocation_contribution_mm, today_mm,
                                   today_measured, today_contribution_mm, share, metrics)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(AllocationDocument, scale, theta_deg, feasible, why)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(BudgetDocument, machine_id, config, database, last, method,
                                   coverage, allowable_total_mm, allowable_total_in,
                                   panel_radius_mm, theta_min_deg, theta_max_deg, rss_total_mm,
                                   rss_total_in, rss_theta_deg, within_budget, monte_carlo_total_mm,
                                   monte_carlo_theta_deg, monte_carlo_samples,
                                   capability_rss_total_mm, capability_rss_theta_deg,
                                   allocation_rss_total_mm, allocation_monte_carlo_total_mm,
                                   allocation, sources, total_within_allowable, verdict,
                                   verdict_why, held, failed_metrics)

ComponentsDocument components(const solver::SourceError& e) { return {e.y_mm, e.z_mm, e.s_mm}; }

MetricDocument metric_document(const solver::MetricReport& m, const MachineConfig& machine,
                               const GatheredHistory& history) {
  MetricDocument d;
  d.name = m.name;
  d.axis = to_string(m.axis);
  d.unit = m.unit;
  d.sensitivity = m.sensitivity.sensitivity;
  d.sensitivity_theta_deg = deg(m.sensitivity.theta_rad);
  d.samples = m.capability.samples;
  d.mean = m.capability.mean;
  d.sigma = m.capability.sigma;
  d.max_abs = m.capability.max_abs;
  d.capability = m.capability.capability;
  d.capability_basis = to_string(m.capability.basis);
  d.derived_tolerance = m.derived_tolerance;
  if (const auto t = configured_tolerance(machine, m))
    d.configured_tolerance = {t->lower, t->upper};
  d.today_value = m.today_value;
  if (const auto time = history.newest_time_ns.find(m.name); time != history.newest_time_ns.end()) {
    d.today_time_ns = time->second;
  }
  d.today_within_derived_tolerance = m.today_within_tolerance;
  return d;
}

BudgetDocument document_of(const ErrorBudgetReport& r, const ErrorBudgetConfig& c,
                           const MachineConfig& machine, const std::optional<std::string>& database,
                           const GatheredHistory& history, int last,
                           const solver::BudgetMachineStanding& standing,
                           const solver::BudgetJudgement& judgement) {
  BudgetDocument d;
  d.machine_id = machine.machine_id;
  d.config = machine.source_path;
  d.database = database;
  d.last = last;
  d.method = to_string(c.method);
  d.coverage = c.coverage;
  d.allowable_total_mm = c.allowable_total_mm;
  d.allowable_total_in = units::mm_to_inch(c.allowable_total_mm);
  d.panel_radius_mm = c.panel_radius_mm;
  d.theta_min_deg = deg(c.theta_min_rad);
  d.theta_max_deg = deg(c.theta_max_rad);
  d.rss_total_mm = r.today.rss_total_mm;
  d.rss_total_in = units::mm_to_inch(r.today.rss_total_mm);
  d.rss_theta_deg = deg(r.today.theta_rad);
  d.within_budget = judgement.verdict == solver::BudgetVerdict::WithinBudget;
  d.total_within_allowable = r.today.within_budget;
  d.verdict = to_string(judgement.verdict);
  d.verdict_why = judgement.why;
  d.held = standing.held;
  d.failed_metrics = standing.failed_metrics;
  d.monte_carlo_total_mm = r.capability_monte_carlo.total_mm;
  d.monte_carlo_theta_deg = deg(r.capability_monte_carlo.theta_rad);
  d.monte_carlo_samples = r.capability_monte_carlo.samples;
  d.capability_rss_total_mm = r.capability_rss.total_mm;
  d.capability_rss_theta_deg = deg(r.capability_rss.theta_rad);
  d.allocation_rss_total_mm = r.allocation_rss.total_mm;
  d.allocation_monte_carlo_total_mm = r.allocation_monte_carlo.total_mm;
  d.allocation = {r.allocation.scale, deg(r.allocation.theta_rad), r.allocation.feasible,
                  r.allocation.why};
  for (const auto& s : r.sources) {
    SourceDocument& source = d.sources.emplace_back();
    source.name = s.name;
    source.description = s.description;
    source.direction = to_string(s.direction);
    source.fixed = s.fixed;
    source.capability_basis = to_string(s.capability_basis);
    source.capability_mm = components(s.capability);
    source.allocation_mm = components(s.allocation);
    source.capability_contribution_mm = s.capability_contribution_mm;
    source.allocation_contribution_mm = s.allocation_contribution_mm;
    source.today_mm = components(s.today);
    source.today_measured = s.today_measured;
    source.today_contribution_mm = s.today_contribution_mm;
    source.share = s.share;
    for (const auto& m : s.metrics) source.metrics.push_back(metric_document(m, machine, history));
  }
  return d;
}

// ---- Table --------------------------------------------------------------------------------------

// "0.2540 mm (0.0100 in)"
std::string mm_in(double mm) {
  return fmt::format("{:.4f} mm ({:.4f} in)", mm, units::mm_to_inch(mm));
}

// A value in a metric's unit with sensible decimals: 4 for mm and in, 1 for arcsec, else 4
// significant.
std::string in_unit(double v, const std::string& unit) {
  if (unit == "mm" || unit == "in") return fmt::format("{:.4f} {}", v, unit);
  if (unit == "arcsec" || unit == "um") return fmt::format("{:.1f} {}", v, unit);
  return fmt::format("{:.4g} {}", v, unit);
}

std::string tolerance_text(const std::optional<Tolerance>& t, const std::string& unit) {
  if (!t) return "-";
  if (std::abs(t->lower + t->upper) <= 1e-12 * std::max(1.0, std::abs(t->upper))) {
    return "±" + in_unit(t->upper, unit);
  }
  return fmt::format("[{:.4g}, {:.4g}] {}", t->lower, t->upper, unit);
}

// One table row: the cells left-aligned in their widths (fmt counts the columns of ΔS, θ, ±,
// not their bytes), separated by a space.
std::string row(const std::vector<std::pair<std::string, std::size_t>>& cells) {
  std::string out;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    out += i + 1 < cells.size() ? fmt::format("{:<{}} ", cells[i].first, cells[i].second)
                                : cells[i].first;
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

// The configured tolerance is looser than the budget can afford on either side.
bool looser_than_derived(const std::optional<Tolerance>& t, double derived) {
  return t && (t->upper > derived * (1 + 1e-9) || t->lower < -derived * (1 + 1e-9));
}

void print_table(const ErrorBudgetReport& r, const ErrorBudgetConfig& c,
                 const MachineConfig& machine, const std::optional<std::string>& database, int last,
                 const solver::BudgetJudgement& judgement) {
  fmt::print("Error budget of {} ({})\n", machine.machine_id, machine.source_path);
  fmt::print(
      "  allowable ΔS {} on a panel of R {:.1f} mm ({:.1f} in), holes at θ {:.1f} .. {:.1f} "
      "deg\n",
      mm_in(c.allowable_total_mm), c.panel_radius_mm, units::mm_to_inch(c.panel_radius_mm),
      deg(c.theta_min_rad), deg(c.theta_max_rad));
  const std::string from =
      database ? "the newest " + std::to_string(last) + " values of each metric in " + *database
               : "the configured defaults (no historian file)";
  fmt::print("  method {}, coverage {:.2f} %; capabilities: {}\n", to_string(c.method),
             100 * c.coverage, from);
  if (!r.allocation.feasible) {
    fmt::print("  ALLOCATION IMPOSSIBLE: {}\n", r.allocation.why);
  } else {
    fmt::print(
        "  allowance = {:.3f} × capability for every measured source (binding at θ = {:.1f} "
        "deg)\n",
        r.allocation.scale, deg(r.allocation.theta_rad));
  }

  fmt::print(
      "\nSources, largest consumer today first (ΔS of capability and allowance at "
      "θ = {:.1f} deg, today's at θ = {:.1f} deg)\n",
      deg(r.allocation.theta_rad), deg(r.today.theta_rad));
  const std::vector<std::size_t> sw{3, 20, 3, 8, 11, 11, 22, 7};
  fmt::print("{}\n", row({{"#", sw[0]},
                          {"source", sw[1]},
                          {"dir", sw[2]},
                          {"basis", sw[3]},
                          {"capab. ΔS", sw[4]},
                          {"allow. ΔS", sw[5]},
                          {"today ΔS", sw[6]},
                          {"share", sw[7]},
                          {"", 0}}));
  int rank = 0;
  for (const auto& s : r.sources) {
    fmt::print("{}\n",
               row({{std::to_string(++rank), sw[0]},
                    {s.name, sw[1]},
                    {std::string(to_string(s.direction)), sw[2]},
                    {std::string(to_string(s.capability_basis)), sw[3]},
                    {fmt::format("{:.4f} mm", s.capability_contribution_mm), sw[4]},
                    {fmt::format("{:.4f} mm", s.allocation_contribution_mm), sw[5]},
                    {mm_in(s.today_contribution_mm), sw[6]},
                    {fmt::format("{:5.1f} %", 100 * s.share), sw[7]},
                    {s.fixed ? "fixed allowance" : (s.today_measured ? "" : "no value yet"), 0}}));
  }

  fmt::print(
      "  share: the source's ΔS today squared over the allowable squared; the shares add up to\n"
      "  (today's total / allowable)², 100 % when the total reaches the allowable\n");

  fmt::print("\nCheck metrics (derived tolerance: the source's allowance in the metric's unit)\n");
  const std::vector<std::size_t> mw{22, 19, 4, 4, 12, 13, 13, 12};
  fmt::print("{}\n", row({{"metric", mw[0]},
                          {"source", mw[1]},
                          {"axis", mw[2]},
                          {"n", mw[3]},
                          {"capability", mw[4]},
                          {"derived tol.", mw[5]},
                          {"configured", mw[6]},
                          {"today", mw[7]},
                          {"", 0}}));
  for (const auto& s : r.sources) {
    for (const auto& m : s.metrics) {
      fmt::print("{}\n",
                 row({{m.name, mw[0]},
                      {s.name, mw[1]},
                      {std::string(to_string(m.axis)), mw[2]},
                      {std::to_string(m.capability.samples), mw[3]},
                      {in_unit(m.capability.capability, m.unit), mw[4]},
                      {"±" + in_unit(m.derived_tolerance, m.unit), mw[5]},
                      {tolerance_text(configured_tolerance(machine, m), m.unit), mw[6]},
                      {m.today_value ? in_unit(*m.today_value, m.unit) : "-", mw[7]},
                      {m.today_within_tolerance ? ""
                       : looser_than_derived(configured_tolerance(machine, m), m.derived_tolerance)
                           ? "OVER ITS ALLOWANCE; configured looser than the budget"
                           : "OVER ITS ALLOWANCE",
                       0}}));
      if (m.today_within_tolerance &&
          looser_than_derived(configured_tolerance(machine, m), m.derived_tolerance)) {
        fmt::print("  {}: its configured tolerance is looser than the budget affords\n", m.name);
      }
    }
  }
  fmt::print(
      "  derived tol.: how far the metric may read before its source uses up its allowance of\n"
      "  the part's allowable ΔS, {}: the allowance over ΔS per unit of the metric\n"
      "  where it matters most (a Z error moves a hole by ΔZ·sin θ only, at most {:.2f} ΔZ here).\n"
      "  It is the part's view of the metric, not the machine's: the configured tolerance is the\n"
      "  check's own (its qualification standard, usually much tighter), and every check's\n"
      "  verdict is judged against it\n",
      mm_in(c.allowable_total_mm),
      solver::worst_axis_sensitivity(solver::BudgetAxis::Z, c.theta_min_rad, c.theta_max_rad)
          .sensitivity);

  fmt::print("\nTotals (ΔS)\n");
  auto total = [](const std::string& what, double mm, const std::string& rest) {
    fmt::print("  {}\n", row({{what, 40}, {mm_in(mm), 22}, {rest, 0}}));
  };
  total("allowable", c.allowable_total_mm, "");
  total("today (RSS of the newest values)", r.today.rss_total_mm,
        fmt::format("at θ = {:.1f} deg: {:.1f} % of the allowable ({:.1f} % of its square, the "
                    "sum of the shares)",
                    deg(r.today.theta_rad), 100 * r.today.rss_total_mm / c.allowable_total_mm,
                    100 * std::pow(r.today.rss_total_mm / c.allowable_total_mm, 2)));
  total("capability (RSS)", r.capability_rss.total_mm,
        fmt::format("at θ = {:.1f} deg", deg(r.capability_rss.theta_rad)));
  total("capability (Monte Carlo, " + std::to_string(r.capability_monte_carlo.samples) + " draws)",
        r.capability_monte_carlo.total_mm,
        fmt::format("at θ = {:.1f} deg", deg(r.capability_monte_carlo.theta_rad)));
  total("allowances (RSS)", r.allocation_rss.total_mm, "");
  total("allowances (Monte Carlo)", r.allocation_monte_carlo.total_mm, "");

  const char* verdict = judgement.verdict == solver::BudgetVerdict::WithinBudget ? "WITHIN BUDGET"
                        : judgement.verdict == solver::BudgetVerdict::OverBudget ? "OVER BUDGET"
                                                                                 : "HELD";
  fmt::print("\nVerdict: {}", verdict);
  if (judgement.verdict == solver::BudgetVerdict::Held) {
    fmt::print(" (not within budget whatever the total: a held machine is not released)");
  } else if (judgement.verdict == solver::BudgetVerdict::WithinBudget) {
    fmt::print(
        " (today's total within the allowable; the machine is not held and no budget\n"
        "  metric's newest check failed)");
  }
  fmt::print("\n");
  for (const auto& why : judgement.why) fmt::print("  {}\n", why);
}

struct Options {
  std::string plant, machine;
  std::optional<std::string> db;
  int last = 30;
  bool json = false;
};

int run(const Options& o) {
  const std::string plant_file = plant_config_path(o.plant);
  if (plant_file.empty()) throw UsageError("pass --plant FILE (or set NCQUAL_PLANT)");
  const std::string& machine_id = o.machine;
  const int last = o.last;

  const PlantConfig plant = load_plant_config(plant_file);
  const MachineConfig* machine = &configured_machine(plant, machine_id);
  if (!machine->budget) {
    std::cerr << "ncqual budget: machine '" << machine_id << "' (" << machine->source_path
              << ") has no budget: section\n";
    return kExitError;
  }
  const ErrorBudgetConfig& budget = *machine->budget;

  // The historian, read only. Without a file (a plant that has not run yet) the budget still
  // stands on the default capabilities; a --db that does not exist is a mistake.
  const std::optional<std::string>& db_flag = o.db;
  const std::string db_path = db_flag ? *db_flag : plant.historian_database;
  std::optional<std::string> database;
  GatheredHistory history;
  solver::BudgetMachineStanding standing;  // the machine's hold and failed metrics
  if (std::filesystem::exists(db_path)) {
    auto db = storage::Database::open_readonly(db_path);
    history = gather_history(db, machine_id, budget);
    const Calendar calendar(plant.calendar.value_or(default_calendar_config()));
    standing = report::budget_machine_standing(db, machine_id, history,
                                               std::numeric_limits<std::int64_t>::max(), &calendar);
    database = db_path;
  } else if (db_flag) {
    std::cerr << "ncqual budget: --db " << db_path << ": no such file\n";
    return kExitError;
  } else {
    std::cerr << "ncqual budget: no historian at " << db_path
              << "; capabilities are the configured defaults\n";
  }
  if (history.unconvertible > 0) {
    std::cerr << "ncqual budget: skipped " << history.unconvertible
              << " stored values whose unit differs from the budget's\n";
  }

  const ErrorBudgetReport report = solver::evaluate_error_budget(budget, history.values, last);
  const solver::BudgetJudgement judgement = solver::judge_budget(report.today, standing);
  if (o.json) {
    std::cout << nlohmann::json(document_of(report, budget, *machine, database, history, last,
                                            standing, judgement))
                     .dump(2)
              << "\n";
  } else {
    print_table(report, budget, *machine, database, last, judgement);
  }
  return kExitOk;
}

}  // namespace

void add_budget(CLI::App& app, Commands& commands) {
  auto [cmd, o] = add_command(
      app, commands, "budget",
      "the error budget: capability, allowance and today's share of every error source,\n"
      "derived tolerances of the check metrics, RSS and Monte Carlo totals",
      run);
  add_machine_option(cmd, o->machine, "the machine whose budget: section to evaluate");
  add_plant_option(cmd, o->plant);
  add_db_option(cmd, o->db);
  cmd->add_option("--last", o->last,
                  "the newest N (>= 1) values of each metric make its capability")
      ->type_name("N")
      ->capture_default_str()
      ->check(CLI::PositiveNumber.description(""));
  add_json_flag(cmd, o->json);
}

}  // namespace ncqual::cli

// SPDX-License-Identifier: Apache-2.0
// The report's data (machine_report.hpp): read from the historian, evaluated with the solver's
// own evaluations (solver::evaluate_global_grid, evaluate_circle, evaluate_linear_axis_run,
// evaluate_error_budget) and the trend library (metric_trend). Nothing is computed here twice.
#include "ncqual/report/budget_history.hpp"
#include "ncqual/report/machine_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

namespace ncqual::report {
namespace {

// The time a check is shown at: its result's, else its set's, else its request's.
std::int64_t check_time(const storage::CheckRecord& r) {
  if (r.result) return r.result->time_ns;
  if (r.measurement) return r.measurement->time_ns;
  return r.request ? r.request->time_ns : 0;
}

ReportedCheck reported(const storage::CheckRecord& r) {
  ReportedCheck c;
  c.request_id = r.request_id;
  c.kind = r.kind;
  c.time_ns = check_time(r);
  if (r.result) c.verdict = r.result->verdict;
  c.origin = storage::origin_of(r);
  return c;
}

std::optional<double> upper_of(const storage::CheckRecord& r, const std::string& metric) {
  if (!r.result) return std::nullopt;
  const Metric* m = find_metric(*r.result, metric);
  if (!m || !std::isfinite(m->upper)) return std::nullopt;
  return m->upper;
}

// The newest check of `kind` among `checks` (newest first) that has a measurement set.
const storage::CheckRecord* newest_of(const std::vector<storage::CheckRecord>& checks,
                                      CheckKind kind) {
  for (const auto& r : checks) {
    if (r.kind == kind && r.measurement) return &r;
  }
  return nullptr;
}

// The stored set of `record` with its points, ready to evaluate; else why not (in `error`).
std::optional<MeasurementSet> set_to_evaluate(storage::Database& db,
                                              const storage::CheckRecord& record,
                                              const MachineConfig* machine, std::string* error) {
  if (!machine) {
    *error = "its charts need the machine's configuration (the plant config's nominal positions)";
    return std::nullopt;
  }
  if (record.measurement && record.measurement->points_thinned_ns) {
    *error = "its tracker points were thinned by retention";
    return std::nullopt;
  }
  if (record.measurement && !record.measurement->error.empty()) {
    *error = "the instrument could not measure it: " + record.measurement->error;
    return std::nullopt;
  }
  auto set = db.load_measurement_set(record.request_id);
  if (!set) *error = "its measurement set is not stored";
  return set;
}

std::optional<GridSection> grid_section(storage::Database& db,
                                        const std::vector<storage::CheckRecord>& checks,
                                        const MachineConfig* machine) {
  const storage::CheckRecord* r = newest_of(checks, CheckKind::GlobalGrid);
  if (!r) return std::nullopt;
  GridSection s;
  s.check = reported(*r);
  s.tolerance_mm = upper_of(*r, "grid_max_deviation_mm");
  const auto set = set_to_evaluate(db, *r, machine, &s.check.error);
  if (!set) return s;
  try {
    const solver::GlobalGridEvaluation e = solver::evaluate_global_grid(*set, *machine);
    for (const auto& plane : e.grid.planes) s.planes.push_back({plane.z_mm, {}});
    // Each point to the plane the evaluation grouped it into: the nearest plane Z.
    for (const auto& p : e.grid.points) {
      auto nearest = std::min_element(s.planes.begin(), s.planes.end(), [&](auto& a, auto& b) {
        return std::abs(a.z_mm - p.commanded_mm.z()) < std::abs(b.z_mm - p.commanded_mm.z());
      });
      if (nearest != s.planes.end()) nearest->points.push_back(p);
    }
  } catch (const std::invalid_argument& e) {
    s.check.error = e.what();
  }
  return s;
}

std::string plane_metric(CheckKind kind) {
  return kind == CheckKind::CircleXY   ? "circle_xy_G_mm"
         : kind == CheckKind::CircleYZ ? "circle_yz_G_mm"
                                       : "circle_xz_G_mm";
}

std::vector<CircleSection> circle_sections(storage::Database& db,
                                           const std::vector<storage::CheckRecord>& checks,
                                           const MachineConfig* machine) {
  std::vector<CircleSection> out;
  for (CheckKind kind : {CheckKind::CircleXY, CheckKind::CircleYZ, CheckKind::CircleXZ}) {
    const storage::CheckRecord* r = newest_of(checks, kind);
    if (!r) continue;
    CircleSection s;
    s.check = reported(*r);
    s.tolerance_mm = upper_of(*r, plane_metric(kind));
    if (const auto set = set_to_evaluate(db, *r, machine, &s.check.error)) {
      try {
        s.evaluation = solver::evaluate_circle(*set, *machine);
      } catch (const std::invalid_argument& e) {
        s.check.error = e.what();
      }
    }
    out.push_back(std::move(s));
  }
  return out;
}

std::optional<LinearRunSection> linear_run_section(storage::Database& db,
                                                   const std::vector<storage::CheckRecord>& checks,
                                                   const MachineConfig* machine) {
  const storage::CheckRecord* r = newest_of(checks, CheckKind::LinearAxisRun);
  if (!r) return std::nullopt;
  LinearRunSection s;
  s.check = reported(*r);
  s.tolerance_mm = upper_of(*r, "linear_A_mm");
  if (const auto set = set_to_evaluate(db, *r, machine, &s.check.error)) {
    try {
      s.evaluation = solver::evaluate_linear_axis_run(*set, *machine);
    } catch (const std::invalid_argument& e) {
      s.check.error = e.what();
    }
  }
  return s;
}

}  // namespace

std::string budget_fingerprint(const solver::ErrorBudgetConfig& c) {
  std::string f;
  const auto add = [&f](auto value) { f += fmt::format("{};", value); };
  add(c.allowable_total_mm);
  add(c.panel_radius_mm);
  add(c.theta_min_rad);
  add(c.theta_max_rad);
  add(static_cast<int>(c.method));
  add(c.coverage);
  add(c.samples);
  add(c.seed);
  for (const auto& s : c.sources) {
    f += s.name + ';';
    add(static_cast<int>(s.direction));
    add(s.bound.y_mm);
    add(s.bound.z_mm);
    add(s.bound.s_mm);
    add(static_cast<int>(s.distribution));
    add(s.weibull_shape);
    for (const auto& m : s.metrics) {
      f += m.name + ';' + m.unit + ';';
      add(static_cast<int>(m.axis));
      add(m.angle);
      add(m.lever_arm_mm);
      add(m.mm_per_unit);
    }
    f += '|';
  }
  return f;  // fmt prints doubles in their shortest exact form: equal text, equal value
}

std::optional<BudgetSection> BudgetMemo::find(const std::string& machine_id, const Key& key) const {
  const std::lock_guard lock(mutex_);
  const auto it = newest_.find(machine_id);
  if (it == newest_.end() || !(it->second.first == key)) return std::nullopt;
  ++hits_;
  return it->second.second;
}

void BudgetMemo::keep(const std::string& machine_id, Key key, BudgetSection section) {
  const std::lock_guard lock(mutex_);
  ++evaluations_;
  newest_[machine_id] = {std::move(key), std::move(section)};
}

std::size_t BudgetMemo::hits() const {
  const std::lock_guard lock(mutex_);
  return hits_;
}

std::size_t BudgetMemo::evaluations() const {
  const std::lock_guard lock(mutex_);
  return evaluations_;
}

BudgetSection machine_budget(storage::Database& db, const std::string& machine_id,
                             const MachineConfig* machine, std::int64_t until_ns, BudgetMemo* memo,
                             const Calendar* calendar) {
  BudgetSection s;
  s.until_ns = until_ns;
  if (!machine) {
    s.error = "The error budget needs the machine's configuration (its budget: section).";
    return s;
  }
  if (!machine->budget) {
    s.error = "The machine's configuration has no budget: section.";
    return s;
  }
  std::optional<BudgetMemo::Key> key;
  if (memo) {
    key = BudgetMemo::Key{budget_fingerprint(*machine->budget),
                          storage::results_up_to(db, machine_id, until_ns)};
    if (auto kept = memo->find(machine_id, *key)) {
      kept->until_ns = until_ns;
      // An intervention changes the machine's hold without a new result: read it again.
      read_machine_hold(db, machine_id, until_ns, kept->standing, calendar);
      if (kept->evaluation)
        kept->judgement = solver::judge_budget(kept->evaluation->today, kept->standing);
      return std::move(*kept);
    }
  }
  s.config = *machine->budget;
  const BudgetHistory history = gather_budget_history(db, machine_id, *s.config, until_ns);
  for (const auto& [name, values] : history.values) s.values += static_cast<int>(values.size());
  try {
    s.evaluation = solver::evaluate_error_budget(*s.config, history.values, s.last);
    s.standing = budget_machine_standing(db, machine_id, history, until_ns, calendar);
    s.judgement = solver::judge_budget(s.evaluation->today, s.standing);
  } catch (const std::invalid_argument& e) {
    s.error = std::string("The error budget could not be evaluated: ") + e.what();
  }
  if (memo) memo->keep(machine_id, std::move(*key), s);
  return s;
}

double tolerance_usage(double value, double lower, double upper) {
  if (!std::isfinite(value)) return 0;
  double used = 0;
  // Each side against the nominal 0 (deviations are measured from it): |value| / |limit| on the
  // side the value lies; a value beyond a limit that does not hold 0 is out of tolerance (> 1).
  if (value >= 0 && std::isfinite(upper)) used = upper > 0 ? value / upper : 1.0 + value - upper;
  if (value < 0 && std::isfinite(lower)) used = lower < 0 ? value / lower : 1.0 + lower - value;
  if (value > upper || value < lower) used = std::max(used, 1.0 + 1e-12);
  return used;
}

MachineReport gather_machine_report(storage::Database& db, const MachineReportQuery& query) {
  if (!db.machine(query.machine_id)) {
    throw std::invalid_argument("machine '" + query.machine_id +
                                "': the historian has nothing of it");
  }
  MachineReport out;
  out.machine_id = query.machine_id;
  out.now_ns = query.now_ns;
  out.configured = query.machine != nullptr;
  if (query.calendar) out.calendar = *query.calendar;
  std::int64_t until_ns = query.now_ns;
  if (query.check_id) {
    auto record = db.find_check(*query.check_id);
    if (!record || record->machine_id != query.machine_id) {
      throw std::invalid_argument("check '" + *query.check_id +
                                  "': the historian has no check of " + query.machine_id +
                                  " with that request id");
    }
    out.check_id = query.check_id;
    until_ns = std::max(check_time(*record), query.now_ns);
    out.checks.push_back(std::move(*record));
  } else {
    if (query.since_ns != std::numeric_limits<std::int64_t>::min()) out.since_ns = query.since_ns;
    storage::HistoryQuery h;
    h.machine_id = query.machine_id;
    h.since_ns = query.since_ns;
    h.limit = 0;
    out.checks = db.history(h);
  }
  out.status = db.latest_status(query.machine_id);
  storage::TrendWarningQuery w;
  w.machine_id = query.machine_id;
  std::size_t ended = 0;
  for (auto& warning : storage::trend_warnings(db, w)) {  // active first, then newest raised
    if (!warning.active() && ++ended > kEndedWarningsListed) {
      ++out.ended_warnings_not_listed;
      continue;
    }
    out.warnings.push_back(std::move(warning));
  }

  out.grid = grid_section(db, out.checks, query.machine);
  out.circles = circle_sections(db, out.checks, query.machine);
  out.linear_run = linear_run_section(db, out.checks, query.machine);

  // Every metric the checks in range report, with how near its tolerance it came; a chart for
  // the few that need looking at, a row of a table for the rest.
  std::map<std::string, MetricUsage> usage_of;
  for (const auto& r : out.checks) {
    if (!r.result) continue;
    for (const auto& m : r.result->metrics) {
      MetricUsage& u = usage_of[m.name];
      u.metric = m.name;
      u.kind = r.kind;
      u.unit = m.unit;
      if (!std::isfinite(m.value)) continue;
      ++u.checks;
      const double used = tolerance_usage(m.value, m.lower, m.upper);
      if (u.checks == 1 || used > u.usage) {
        u.usage = used;
        u.value = m.value;
        u.lower = m.lower;
        u.upper = m.upper;
        u.time_ns = r.result->time_ns;
      }
    }
  }
  std::set<std::string> warned;
  for (const auto& w : out.warnings) {
    const bool in_range = w.active() || !out.since_ns || w.ended_ns.value_or(0) >= *out.since_ns;
    if (in_range && usage_of.count(w.metric)) warned.insert(w.metric);
  }
  std::vector<const MetricUsage*> ranked;
  ranked.reserve(usage_of.size());
  for (const auto& [name, u] : usage_of) ranked.push_back(&u);
  // Warned first, then out of tolerance (usage above 1), then the nearest; by name on ties.
  std::stable_sort(ranked.begin(), ranked.end(), [&](const MetricUsage* a, const MetricUsage* b) {
    const bool wa = warned.count(a->metric) > 0, wb = warned.count(b->metric) > 0;
    if (wa != wb) return wa;
    return a->usage > b->usage;
  });
  std::set<std::string> charted;
  for (const MetricUsage* u : ranked) {
    if (charted.size() < kMaxTrendCharts) {
      charted.insert(u->metric);
    } else {
      out.other_metrics.push_back(*u);
    }
  }
  std::set<std::string> done;
  for (const auto& info : storage::machine_metrics(db, query.machine_id)) {
    if (!charted.count(info.name) || !done.insert(info.name).second) continue;
    MetricTrendQuery q;
    q.machine_id = query.machine_id;
    q.metric = info.name;
    if (out.since_ns) q.since_ns = out.since_ns;
    if (query.check_id) q.until_ns = check_time(out.checks.front());
    out.trends.push_back(metric_trend(db, q));
  }
  for (const auto& i : db.interventions(query.machine_id)) {
    out.markers.push_back({i.time_ns, "intervention " + i.intervention_id, std::nullopt});
  }
  for (const auto& c : db.compensations(query.machine_id)) {
    out.markers.push_back(
        {c.time_ns, "compensation " + c.correction.target, compensation_kind(c.correction.target)});
  }
  std::sort(out.markers.begin(), out.markers.end(),
            [](const auto& a, const auto& b) { return a.time_ns < b.time_ns; });

  out.budget = machine_budget(db, query.machine_id, query.machine, until_ns, query.budget_memo,
                              query.calendar);
  return out;
}

}  // namespace ncqual::report

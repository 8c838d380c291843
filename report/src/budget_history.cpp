// SPDX-License-Identifier: Apache-2.0
#include "ncqual/report/budget_history.hpp"

#include "ncqual/storage/trend.hpp"
#include "ncqual/common/units.hpp"
#include "ncqual/charts/axis.hpp"

#include <fmt/format.h>

namespace ncqual::report {

std::optional<double> unit_factor(const std::string& from, const std::string& to) {
  if (from == to || from.empty()) return 1.0;
  for (auto dim : {units::Dimension::Length, units::Dimension::Angle}) {
    const auto f = units::to_internal_factor(dim, from);
    const auto t = units::to_internal_factor(dim, to);
    if (f && t) return *f / *t;
  }
  return std::nullopt;
}

BudgetHistory gather_budget_history(storage::Database& db, const std::string& machine_id,
                                    const solver::ErrorBudgetConfig& budget,
                                    std::int64_t until_ns) {
  std::map<std::string, const solver::BudgetMetric*> wanted;
  for (const auto& s : budget.sources) {
    for (const auto& m : s.metrics) wanted[m.name] = &m;
  }
  // Each metric's series (storage::metric_series: every kind of check that ever reported it),
  // newest first; an INVALID check's values are not the machine's.
  BudgetHistory h;
  for (const auto& [name, metric] : wanted) {
    storage::MetricQuery q;
    q.machine_id = machine_id;
    q.metric = name;
    q.until_ns = until_ns;
    const std::vector<storage::MetricValue> series = storage::metric_series(db, q);
    for (auto it = series.rbegin(); it != series.rend(); ++it) {
      if (it->verdict == Verdict::Invalid) continue;
      const auto factor = unit_factor(it->unit, metric->unit);
      if (!factor) {
        ++h.unconvertible;
        continue;
      }
      auto& values = h.values[name];
      if (values.empty()) {
        h.newest_time_ns[name] = it->time_ns;
        h.newest[name] = *it;
      }
      values.push_back(it->value * *factor);
    }
  }
  return h;
}

namespace {

// "2026-03-16 06:00 +01:00 CET" in the plant's zone, or "2026-03-16 05:00 UTC" without one.
std::string time_text(std::int64_t ns, const Calendar* calendar) {
  return calendar ? calendar->local_text(ns) : charts::utc_date_time(ns) + " UTC";
}

}  // namespace

void read_machine_hold(storage::Database& db, const std::string& machine_id, std::int64_t until_ns,
                       solver::BudgetMachineStanding& standing, const Calendar* calendar) {
  std::optional<MachineStatus> status;
  if (until_ns == std::numeric_limits<std::int64_t>::max()) {
    status = db.latest_status(machine_id);
  } else {
    for (const MachineStatus& m : db.status_history(machine_id)) {  // oldest first
      if (m.time_ns <= until_ns) status = m;
    }
  }
  standing.held = status && status->state == MachineState::NeedsIntervention;
  standing.held_why.clear();
  if (standing.held) {
    standing.held_why = std::string(to_string(status->state)) + " since " +
                        time_text(status->time_ns, calendar) +
                        (status->detail.empty() ? "" : ": " + status->detail);
  }
}

solver::BudgetMachineStanding budget_machine_standing(storage::Database& db,
                                                      const std::string& machine_id,
                                                      const BudgetHistory& history,
                                                      std::int64_t until_ns,
                                                      const Calendar* calendar) {
  solver::BudgetMachineStanding s;
  read_machine_hold(db, machine_id, until_ns, s, calendar);
  for (const auto& [name, v] : history.newest) {
    if (v.pass) continue;
    s.failed_metrics.push_back(fmt::format(
        "{} = {:.4g} {} out of [{:.4g}, {:.4g}] ({} {}, {})", name, v.value, v.unit, v.lower,
        v.upper, to_string(v.kind), to_string(v.verdict), time_text(v.time_ns, calendar)));
  }
  return s;
}

}  // namespace ncqual::report

// SPDX-License-Identifier: Apache-2.0
#include "ncqual/report/budget_history.hpp"

#include "ncqual/units.hpp"

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
  // Every check's result, not storage::metric_series: that finds a metric's series by the newest
  // result of its kind, and an INVALID newest result that reports only some metrics hides the
  // others' values.
  storage::HistoryQuery q;
  q.machine_id = machine_id;
  q.limit = 0;  // every check: the newest N values of each metric may lie far apart
  BudgetHistory h;
  for (const auto& record : db.history(q)) {  // newest first
    if (!record.result || record.result->verdict == Verdict::Invalid) continue;
    if (record.result->time_ns > until_ns) continue;
    for (const Metric& metric : record.result->metrics) {
      const auto it = wanted.find(metric.name);
      if (it == wanted.end()) continue;
      const auto factor = unit_factor(metric.unit, it->second->unit);
      if (!factor) {
        ++h.unconvertible;
        continue;
      }
      auto& values = h.values[metric.name];
      if (values.empty()) h.newest_time_ns[metric.name] = record.result->time_ns;
      values.push_back(metric.value * *factor);
    }
  }
  return h;
}

}  // namespace ncqual::report

// SPDX-License-Identifier: Apache-2.0
#include "ncqual/report/budget_history.hpp"

#include "ncqual/storage/trend.hpp"
#include "ncqual/common/units.hpp"

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
      if (values.empty()) h.newest_time_ns[name] = it->time_ns;
      values.push_back(it->value * *factor);
    }
  }
  return h;
}

}  // namespace ncqual::report

// SPDX-License-Identifier: Apache-2.0
#include "trend_watch.hpp"

#include "ncqual/report/warnings.hpp"

#include <algorithm>
#include <set>

namespace ncqual::historian {

TrendWatch::TrendWatch(trend::AssessOptions options) : options_(options) {}

trend::AssessOptions TrendWatch::default_options() {
  trend::AssessOptions o;
  o.theil_sen = false;
  return o;
}

void TrendWatch::assess_metric(storage::Database& db, const std::string& machine_id,
                               const std::string& metric, const std::string& by, std::int64_t at_ns,
                               std::vector<TrendWarning>& out) {
  const std::vector<storage::MetricValue> series = storage::metric_series(db, {machine_id, metric});
  if (series.empty()) return;
  std::vector<trend::Point> points;
  points.reserve(series.size());
  for (const auto& v : series) points.push_back({v.time_ns, v.value});
  const storage::MetricValue& newest = series.back();
  const trend::Band band{newest.lower, newest.upper};
  const std::vector<std::int64_t> restarts = storage::restart_times(db, machine_id, newest.kind);
  const std::int64_t now = trend::assessed_as_of(newest.time_ns, restarts);
  const trend::Assessment a = trend::assess(points, band, restarts, now, options_);
  if (!a.ok()) return;  // a band the statistics cannot use: nothing to warn of
  const storage::TrendWarningChanges changes = storage::apply_trend_warnings(
      db, machine_id, metric,
      report::active_records(a, machine_id, metric, newest.kind, newest.unit, band), by, at_ns);
  // Started and ended warnings are announced; an active one's new dates and text are only
  // stored (they move with every check).
  for (const auto* list : {&changes.raised, &changes.ended}) {
    for (const auto& r : *list) out.push_back(report::to_sample(r, at_ns));
  }
}

std::vector<TrendWarning> TrendWatch::after_result(storage::Database& db,
                                                   const CheckResult& result) {
  std::vector<TrendWarning> out;
  std::set<std::string> seen;
  for (const Metric& m : result.metrics) {
    if (!seen.insert(m.name).second) continue;
    assess_metric(db, result.machine_id, m.name, result.request_id, result.time_ns, out);
  }
  return out;
}

std::vector<TrendWarning> TrendWatch::after_restart(storage::Database& db,
                                                    const std::string& machine_id,
                                                    const std::string& by, std::int64_t at_ns) {
  std::vector<TrendWarning> out;
  std::set<std::string> seen;
  for (const auto& m : storage::machine_metrics(db, machine_id)) {
    if (!seen.insert(m.name).second) continue;
    assess_metric(db, machine_id, m.name, by, at_ns, out);
  }
  return out;
}

}  // namespace ncqual::historian

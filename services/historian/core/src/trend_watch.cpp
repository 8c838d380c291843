// SPDX-License-Identifier: Apache-2.0
#include "ncqual/historian/trend_watch.hpp"

#include "ncqual/common/check_kinds.hpp"
#include "ncqual/report/warnings.hpp"

#include <algorithm>
#include <limits>
#include <map>
#include <set>

namespace ncqual::historian {

struct TrendWatch::Context {
  std::string machine_id;
  // Per (kind, metric) series, read when first needed.
  std::map<std::pair<CheckKind, std::string>, std::vector<std::int64_t>> restarts;
  std::set<std::string> warning_metrics;  // with a stored active warning

  Context(storage::Database& db, std::string machine) : machine_id(std::move(machine)) {
    storage::TrendWarningQuery q;
    q.machine_id = machine_id;
    q.active_only = true;
    for (const auto& w : storage::trend_warnings(db, q)) warning_metrics.insert(w.metric);
  }
  const std::vector<std::int64_t>& restarts_of(storage::Database& db, CheckKind kind,
                                               const std::string& metric) {
    auto key = std::make_pair(kind, metric);
    auto it = restarts.find(key);
    if (it == restarts.end()) {
      it = restarts.emplace(std::move(key), storage::restart_times(db, machine_id, kind, metric))
               .first;
    }
    return it->second;
  }
};

TrendWatch::TrendWatch(trend::AssessOptions options) : options_(options) {}

trend::AssessOptions TrendWatch::default_options() {
  trend::AssessOptions o;
  o.theil_sen = false;
  return o;
}

void TrendWatch::assess_metric(storage::Database& db, Context& context, const std::string& metric,
                               const Event& event, std::vector<TrendWarning>& out) {
  const std::string& machine_id = context.machine_id;
  std::int64_t& through =
      assessed_through_.try_emplace({machine_id, metric}, std::numeric_limits<std::int64_t>::min())
          .first->second;
  // In order (the usual case, and a burst that the watch follows behind): the series as it was
  // at the event, so each check raises or ends what it did. Late (the metric was assessed past
  // it already): as of the newest stored event, which changes nothing unless the late one does.
  const bool in_order = event.at_ns >= through;
  storage::MetricQuery query{machine_id, metric};
  if (in_order) query.until_ns = event.at_ns;
  const std::vector<storage::MetricValue> series = storage::metric_series(db, query);
  if (series.empty()) return;
  std::vector<trend::Point> points;
  points.reserve(series.size());
  for (const auto& v : series) points.push_back({v.time_ns, v.value});
  const storage::MetricValue& newest = series.back();
  const trend::Band band{newest.lower, newest.upper};
  std::vector<std::int64_t> restarts = context.restarts_of(db, newest.kind, metric);
  if (in_order) {
    restarts.erase(std::upper_bound(restarts.begin(), restarts.end(), event.at_ns), restarts.end());
  }
  const std::int64_t now = trend::assessed_as_of(newest.time_ns, restarts);
  std::string by = event.by;
  std::int64_t at_ns = event.at_ns;
  if (!in_order) {
    // The changes are the newest event's: its check, or a restart after it; a restart's are its
    // own job's (queued behind this one when this is a result's).
    if (now == newest.time_ns) {
      by = newest.request_id;
      at_ns = newest.time_ns;
    } else if (!event.restart || event.at_ns != now) {
      return;
    }
  }
  through = std::max(through, now);
  const trend::Assessment a = trend::assess(points, band, restarts, now, options_);
  if (!a.ok()) return;  // a band the statistics cannot use: nothing to warn of
  const std::vector<storage::TrendWarningRecord> active =
      report::active_records(a, machine_id, metric, newest.kind, newest.unit, band);
  // Nothing stored, nothing now: no write transaction (most metrics, most of the time).
  if (active.empty() && context.warning_metrics.count(metric) == 0) return;
  const storage::TrendWarningChanges changes =
      storage::apply_trend_warnings(db, machine_id, metric, active, by, at_ns);
  if (!changes.raised.empty()) context.warning_metrics.insert(metric);
  // Started and ended warnings are announced; an active one's new dates and text are only
  // stored (they move with every check).
  for (const auto* list : {&changes.raised, &changes.ended}) {
    for (const auto& r : *list) out.push_back(report::to_sample(r, at_ns));
  }
}

std::vector<TrendWarning> TrendWatch::after_result(storage::Database& db,
                                                   const CheckResult& result) {
  std::vector<TrendWarning> out;
  Context context(db, result.machine_id);
  std::set<std::string> seen;
  for (const Metric& m : result.metrics) {
    if (!seen.insert(m.name).second) continue;
    assess_metric(db, context, m.name, Event{result.request_id, result.time_ns, false}, out);
  }
  return out;
}

std::vector<TrendWarning> TrendWatch::after_intervention(storage::Database& db,
                                                         const Intervention& intervention) {
  return after_restart(db, intervention.machine_id, intervention.intervention_id,
                       intervention.time_ns, std::nullopt);
}

std::vector<TrendWarning> TrendWatch::after_compensation(storage::Database& db,
                                                         const Compensation& compensation) {
  return after_restart(db, compensation.machine_id, compensation.request_id, compensation.time_ns,
                       compensation_kind(compensation.correction.target));
}

std::vector<TrendWarning> TrendWatch::after_restart(storage::Database& db,
                                                    const std::string& machine_id,
                                                    const std::string& by, std::int64_t at_ns,
                                                    std::optional<CompensationKind> compensation) {
  std::vector<TrendWarning> out;
  Context context(db, machine_id);
  const Event restart{by, at_ns, true};
  std::set<std::string> seen;
  for (const auto& m : storage::machine_metrics(db, machine_id)) {
    if (!restarts_series(compensation, m.kind, m.name)) continue;
    if (!seen.insert(m.name).second) continue;
    assess_metric(db, context, m.name, restart, out);
  }
  return out;
}

}  // namespace ncqual::historian

// SPDX-License-Identifier: Apache-2.0
// The historian's rows as a metric's history: the series a trend is computed over (one value
// per check, oldest first), the times that restart a series (interventions and compensations),
// and the trend warnings the historian raises and ends (docs/trends.md, "Warnings"). Free
// functions over a Database connection (read-only connections may read; only the historian
// writes warnings). Every statement is prepared once per connection and walks an index
// (StorageQueryPlans.* checks the plans).
#pragma once

#include "ncqual/common/model.hpp"
#include "ncqual/storage/database.hpp"

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ncqual::storage {

// One check's value of one metric.
struct MetricValue {
  std::string request_id;
  CheckKind kind = CheckKind::MonumentPositioning;
  std::int64_t time_ns = 0;  // the result's time
  Verdict verdict = Verdict::Pass;
  double value = 0;  // NaN: the check could not evaluate it (stored NULL)
  std::string unit;
  double lower = 0, upper = 0;  // the tolerance band the check judged it against
  bool pass = true;
  DataOrigin origin = DataOrigin::Unknown;  // the result's: measured, simulated, or not recorded
};

struct MetricQuery {
  std::string machine_id;
  std::string metric;                                                // "center_dy_mm"
  std::int64_t since_ns = std::numeric_limits<std::int64_t>::min();  // result time >= since
  std::int64_t until_ns = std::numeric_limits<std::int64_t>::max();  // result time <= until
  int last = 0;  // > 0: only the newest `last` values of the range
};

// Oldest first (by result time, then request id), from every kind of check that ever reported the
// metric (not only those whose newest result does). Empty when the machine never reported it.
std::vector<MetricValue> metric_series(Database& db, const MetricQuery& query);

// A metric a machine reports, with the band and unit of its newest value.
struct MetricInfo {
  std::string name;
  CheckKind kind = CheckKind::MonumentPositioning;
  std::string unit;
  double lower = 0, upper = 0;
  std::int64_t count = 0;    // checks that reported it
  std::int64_t last_ns = 0;  // the newest such check's result time
};

// Every metric the machine's results of each kind ever carried (a metric of two kinds: once per
// kind), by check kind, then the place its newest value had in its check, then name.
std::vector<MetricInfo> machine_metrics(Database& db, const std::string& machine_id);

// What restarts the series of `metric` reported by `series` checks (docs/trends.md, "What
// restarts a series"): the times of the machine's interventions and compensations that
// restarts_series says restart it (a compensation by its target's kind), ascending, each once.
std::vector<std::int64_t> restart_times(Database& db, const std::string& machine_id,
                                        CheckKind series, std::string_view metric);

// One trend warning as the historian keeps it: raised at a stored result when the assessment of
// a metric finds it active, ended at the result (or intervention, compensation) after which it
// is no longer. Identity: (machine, metric, kind, started_ns).
struct TrendWarningRecord {
  std::string machine_id;
  std::string metric;
  CheckKind check_kind = CheckKind::MonumentPositioning;  // the kind whose checks report the metric
  std::string kind;             // trend::to_string(WarningKind): "forecast", "cusum_up", ...
  std::string side;             // "above" or "below" (forecast: the limit the line heads to)
  std::int64_t started_ns = 0;  // the check where the current episode first held
  std::string raised_by;        // the request whose result raised it
  std::int64_t raised_ns = 0;   // that result's time
  std::optional<std::string> ended_by;  // the request, intervention or compensation that ended it
  std::optional<std::int64_t> ended_ns;
  // forecast: where the fitted line and where its near 95 % prediction bound reach the limit,
  // as of the latest result that assessed it (kept up to date while active)
  std::optional<std::int64_t> expected_crossing_ns;
  std::optional<std::int64_t> earliest_crossing_ns;
  std::string text;  // one sentence for people, with the figures
  bool active() const { return !ended_ns.has_value(); }
};

struct TrendWarningQuery {
  std::optional<std::string> machine_id;  // every machine when empty
  std::optional<std::string> metric;
  bool active_only = false;
  std::int64_t since_ns = std::numeric_limits<std::int64_t>::min();  // raised or ended since
  int limit = 0;                                                     // <= 0: all
};

// Active ones first, then the most recently raised first.
std::vector<TrendWarningRecord> trend_warnings(Database& db, const TrendWarningQuery& query);

// What one assessment changed.
struct TrendWarningChanges {
  std::vector<TrendWarningRecord> raised;   // newly active
  std::vector<TrendWarningRecord> ended;    // no longer active (ended_by/ended_ns filled)
  std::vector<TrendWarningRecord> updated;  // still active, forecast dates or text changed
  bool empty() const { return raised.empty() && ended.empty() && updated.empty(); }
};

// Brings the stored warnings of (machine, metric) to `active`, the warnings active after the
// result `by` at `at_ns`: one of `active` not stored as active (by kind and started_ns) is
// raised; a stored active one not in `active` is ended by `by` at `at_ns`; one in both keeps its
// raise and takes the new dates and text. In one write transaction. Idempotent: the same call
// again changes nothing.
TrendWarningChanges apply_trend_warnings(Database& db, const std::string& machine_id,
                                         const std::string& metric,
                                         const std::vector<TrendWarningRecord>& active,
                                         const std::string& by, std::int64_t at_ns);

}  // namespace ncqual::storage

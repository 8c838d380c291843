// SPDX-License-Identifier: Apache-2.0
// The historian's trend watch (docs/trends.md, "Warnings"): after each stored result it assesses
// the series of every metric the result reports (trend::assess over the machine's stored
// values, restarted at its interventions and the compensations that concern it), keeps the
// warnings that start, move or end in the trend_warnings table, and returns each change as a
// TrendWarning to publish. An intervention re-assesses every metric of the machine, a
// compensation those whose series it restarts (restarts_series, by its target): the warnings of the
// series they restart end. No DDS here: the historian publishes what comes back (a warning
// raised or ended; an active warning's new figures are only stored). Cheap when nothing warns:
// a metric with no stored active warning and none now costs its reads, no write transaction.
//
// Each assessment is "as of" the event (the result or the restart): the series as it was then,
// so that a watch running behind a burst of results (the historian runs it on a thread of its
// own, watch_worker.hpp) raises and ends each warning at the check that did. A result that
// arrives late (a replay, a restarted producer's resend: the metric was assessed past it
// already) is assessed as of the newest stored value or restart instead, in its place, and
// changes are by that newest event; assessing twice changes nothing.
#pragma once

#include "ncqual/common/check_kinds.hpp"
#include "ncqual/common/model.hpp"
#include "ncqual/storage/database.hpp"
#include "ncqual/storage/trend.hpp"
#include "ncqual/trend/assess.hpp"

#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace ncqual::historian {

class TrendWatch {
 public:
  explicit TrendWatch(trend::AssessOptions options = default_options());
  // The assessment the historian runs: the defaults of docs/trends.md, without Theil-Sen (no
  // warning uses it).
  static trend::AssessOptions default_options();

  // After `result` was stored: its metrics assessed, the warnings brought up to date (an active
  // forecast's dates and text too), the warnings raised and ended returned, each once. Throws
  // StorageError (the database).
  std::vector<TrendWarning> after_result(storage::Database& db, const CheckResult& result);
  // After an intervention was stored: every metric of the machine is assessed again, so the
  // warnings of its series end (by the intervention), and a result after it that arrived first
  // may still warn.
  std::vector<TrendWarning> after_intervention(storage::Database& db,
                                               const Intervention& intervention);
  // After a compensation was stored: the metrics of the series it restarts (by the kind of the
  // check that issued it; every metric when that check is unknown), the same way.
  std::vector<TrendWarning> after_compensation(storage::Database& db,
                                               const Compensation& compensation);

 private:
  // The metrics of the series a restart restarts (restarts_series: an intervention when
  // `compensation` is empty), assessed again after `by` at `at_ns`.
  std::vector<TrendWarning> after_restart(storage::Database& db, const std::string& machine_id,
                                          const std::string& by, std::int64_t at_ns,
                                          std::optional<CompensationKind> compensation);
  // What one call reads once: the machine's restart times per series (kind, metric), and the
  // metrics with a stored active warning.
  struct Context;
  // What the warnings change by: a stored result, or a restart (an intervention, a compensation).
  struct Event {
    std::string by;
    std::int64_t at_ns = 0;
    bool restart = false;
  };
  // One metric: assessed as of `event` (or, when the metric was assessed past it already, as of
  // its newest value or restart) and applied; the changes appended.
  void assess_metric(storage::Database& db, Context& context, const std::string& metric,
                     const Event& event, std::vector<TrendWarning>& out);
  trend::AssessOptions options_;
  // Per (machine, metric): the time of the newest event it was assessed as of, by this process.
  std::map<std::pair<std::string, std::string>, std::int64_t> assessed_through_;
};

}  // namespace ncqual::historian

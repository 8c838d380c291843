// SPDX-License-Identifier: Apache-2.0
// The historian's trend watch (docs/trends.md, "Warnings"): after each stored result it assesses
// the series of every metric the result reports (trend::assess over the machine's stored
// values, restarted at its interventions and the compensations that concern it), keeps the
// warnings that start, move or end in the trend_warnings table, and returns each change as a
// TrendWarning to publish. An intervention or a compensation re-assesses the machine's metrics:
// the warnings of the series it restarts end. No DDS here: the historian's main publishes what
// comes back (a warning raised or ended; an active warning's new figures are only stored).
//
// Each assessment is "as of" the newest stored value of the metric (or the machine's latest
// restart, when that is newer), so a result that arrives late (a replay, a restarted producer's
// resend) is assessed in its place, and assessing twice changes nothing.
#pragma once

#include "ncqual/model.hpp"
#include "ncqual/storage.hpp"
#include "ncqual/storage_trend.hpp"
#include "ncqual/trend/assess.hpp"

#include <cstdint>
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
  // After an intervention or a compensation of `machine_id` at `at_ns` (named `by`) was stored:
  // every metric of the machine is assessed again, so the warnings of the series it restarts end
  // (by `by`), and a result after it that arrived first may still warn.
  std::vector<TrendWarning> after_restart(storage::Database& db, const std::string& machine_id,
                                          const std::string& by, std::int64_t at_ns);

 private:
  // One metric: assessed as of its newest value and applied; the changes appended.
  void assess_metric(storage::Database& db, const std::string& machine_id,
                     const std::string& metric, const std::string& by, std::int64_t at_ns,
                     std::vector<TrendWarning>& out);
  trend::AssessOptions options_;
};

}  // namespace ncqual::historian

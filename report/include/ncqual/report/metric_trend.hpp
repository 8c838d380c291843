// SPDX-License-Identifier: Apache-2.0
// One metric of one machine over time, with every figure of docs/trends.md: the selected checks
// and, over the segment since the last restart, the control chart, EWMA, CUSUM, Western Electric
// signals, capability, the least-squares and Theil-Sen forecasts, the pass rate and the warnings
// active now, beside the warnings the historian raised. `ncqual trend --metric` prints it (text,
// JSON, CSV of the points); the report and the dashboard draw it. The document's names are a
// public interface (append, never rename).
#pragma once

#include "ncqual/common/model.hpp"
#include "ncqual/storage/database.hpp"
#include "ncqual/storage/trend.hpp"
#include "ncqual/trend/assess.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace ncqual::report {

struct TrendPoint {
  std::string request_id;
  CheckKind kind = CheckKind::MonumentPositioning;
  std::int64_t time_ns = 0;
  std::optional<double> value;         // null: the check could not evaluate it
  std::optional<double> lower, upper;  // the band it was judged against; null: no limit
  Verdict verdict = Verdict::Pass;
  bool in_segment = false;  // after the last restart: the statistics describe it
  // At this point of the segment (null outside it, or without a baseline):
  std::optional<double> ewma, ewma_lower, ewma_upper;
  std::optional<double> cusum_upper, cusum_lower;  // C+, C-
  // Its check's numbers: measured, simulated by ncqual's simulator, or unknown (not recorded).
  DataOrigin origin = DataOrigin::Unknown;
};

struct TrendDate {
  std::string status;  // trend::to_string(DateStatus): date, already_beyond, never, ...
  std::optional<std::int64_t> time_ns;
};

struct TrendBaseline {
  std::string error;
  std::size_t points = 0;
  double mean = 0, sigma_within = 0, sigma_overall = 0;
  double lower_control_limit = 0, upper_control_limit = 0;
  // A one-sided metric (an upper limit only, a magnitude toleranced [0, U]; trend::watched_side):
  // "above" (or "below"), the only side its rules, EWMA and CUSUM warn on, and the only control
  // limit the charts draw; "": both.
  std::string watched;
};

struct TrendSignal {
  int rule = 0;  // Western Electric rule 1..4
  std::int64_t time_ns = 0;
  std::string side;
};

struct TrendCapability {
  std::string error;
  std::size_t points = 0;
  std::optional<double> cp, cpk, cpu, cpl, pp, ppk, ppu, ppl;
};

struct TrendForecast {
  std::string method;  // least_squares, theil_sen
  std::string error;
  std::size_t points = 0;
  std::int64_t reference_ns = 0;                            // x = 0 of the line, in days
  double intercept = 0;                                     // at reference_ns
  double slope_per_day = 0, slope_low = 0, slope_high = 0;  // 95 % interval
  bool trend = false;                                       // the slope's interval excludes zero
  std::optional<std::string> heading;                       // above, below
  std::optional<double> limit;                              // the limit it heads to
  std::optional<double> residual_sd;                        // least squares
  TrendDate expected, earliest, latest;  // earliest and latest: least squares only
};

struct TrendPassRate {
  std::size_t pass = 0, fail = 0, invalid = 0;
  std::optional<double> rate, lower, upper;  // 95 % Wilson interval
};

struct TrendWarningNow {
  std::string kind;
  std::string side;
  std::int64_t since_ns = 0;
  std::optional<std::int64_t> expected_ns, earliest_ns;
  std::string text;
};

struct StoredTrendWarning {
  std::string kind, side;
  std::int64_t started_ns = 0;
  std::string raised_by;
  std::int64_t raised_ns = 0;
  std::optional<std::string> ended_by;
  std::optional<std::int64_t> ended_ns;
  std::optional<std::int64_t> expected_crossing_ns, earliest_crossing_ns;
  std::string text;
};

// One time of the least-squares line with its prediction interval (the metric's unit).
struct TrendPrediction {
  std::int64_t time_ns = 0;
  double fitted = 0, lower = 0, upper = 0;
};

struct MetricTrend {
  std::string machine_id;
  std::string metric;
  std::string unit;
  std::vector<CheckKind> check_kinds;  // that report it, in the selection
  std::optional<double> lower, upper;  // the newest check's band; null: no limit on that side
  std::optional<std::int64_t> since_ns, until_ns;  // the selection asked for
  std::optional<int> last;
  std::int64_t now_ns = 0;                 // the statistics are as of this time
  std::optional<std::int64_t> restart_ns;  // the segment follows this restart
  std::size_t checks = 0;                  // selected
  std::size_t not_evaluated = 0;           // of them, without a value
  std::size_t segment_points = 0;
  TrendBaseline baseline;
  std::vector<TrendSignal> signals;  // Western Electric, over the segment
  TrendCapability capability;
  TrendForecast least_squares, theil_sen;
  TrendPassRate pass_rate;                 // over the selection
  std::vector<TrendWarningNow> warnings;   // active as of now_ns
  std::vector<StoredTrendWarning> raised;  // what the historian raised for the metric, newest first
  std::vector<TrendPoint> points;          // oldest first
  std::size_t simulated = 0;  // of the points, those of checks ncqual's simulator produced
  std::string error;  // the statistics could not be computed (e.g. no band); points still given
  // For charts (not in the JSON document): the least-squares line of the segment and its 95 %
  // prediction interval (trend::prediction_interval) from the segment's first check to the
  // horizon (the later of now + AssessOptions::horizon_days and the expected crossing, when that
  // lies within a year of now); empty without a forecast.
  std::vector<TrendPrediction> prediction;
};

struct MetricTrendQuery {
  std::string machine_id;
  std::string metric;
  std::optional<std::int64_t> since_ns, until_ns;
  std::optional<int> last;  // the newest N of the range
};

// The document; nothing selected gives checks == 0 and no figures (not an error).
MetricTrend metric_trend(storage::Database& db, const MetricTrendQuery& query,
                         const trend::AssessOptions& options = {});

void to_json(nlohmann::json& j, const MetricTrend& v);

// The points as CSV, written like `ncqual export`'s files (storage/csv_fields.hpp: RFC 4180,
// CRLF, reals to the shortest round-trip digits, time_utc to the nanosecond, null an empty
// field): time_ns, time_utc, request_id, kind, value, lower, upper, verdict, in_segment, ewma,
// ewma_lower, ewma_upper, cusum_upper, cusum_lower, origin (measured, simulated, unknown).
std::string points_csv(const MetricTrend& trend);

}  // namespace ncqual::report

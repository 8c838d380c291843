// SPDX-License-Identifier: Apache-2.0
#include "ncqual/report/metric_trend.hpp"

#include "ncqual/report/warnings.hpp"

#include "ncqual/storage/csv_fields.hpp"
#include "ncqual/common/json.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace ncqual::report {
namespace {

std::optional<double> finite(double v) {
  return std::isfinite(v) ? std::optional<double>(v) : std::nullopt;
}

TrendDate date_of(const trend::LimitDate& d) {
  return {std::string(trend::to_string(d.status)), d.time_ns};
}

std::string side_name(trend::Side side) { return std::string(trend::to_string(side)); }

// What both lines give (trend::LinearForecast and trend::TheilSen name them alike).
template <typename Line>
TrendForecast line_of(const char* method, const Line& f) {
  TrendForecast out;
  out.method = method;
  out.error = f.error;
  out.points = f.points;
  if (!f.ok()) return out;
  out.reference_ns = f.reference_ns;
  out.intercept = f.intercept;
  out.slope_per_day = f.slope;
  out.slope_low = f.slope_low;
  out.slope_high = f.slope_high;
  out.trend = f.trend;
  if (f.heading) out.heading = side_name(*f.heading);
  out.limit = f.limit;
  out.expected = date_of(f.expected);
  return out;
}

TrendForecast least_squares_of(const trend::LinearForecast& f) {
  TrendForecast out = line_of("least_squares", f);
  if (!f.ok()) return out;
  out.residual_sd = f.residual_sd;
  out.earliest = date_of(f.earliest);
  out.latest = date_of(f.latest);
  return out;
}

}  // namespace

NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(TrendPoint, request_id, kind, time_ns, value, lower, upper,
                                   verdict, in_segment, ewma, ewma_lower, ewma_upper, cusum_upper,
                                   cusum_lower, origin)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(TrendDate, status, time_ns)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(TrendBaseline, error, points, mean, sigma_within, sigma_overall,
                                   lower_control_limit, upper_control_limit, watched)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(TrendSignal, rule, time_ns, side)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(TrendCapability, error, points, cp, cpk, cpu, cpl, pp, ppk, ppu,
                                   ppl)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(TrendForecast, method, error, points, reference_ns, intercept,
                                   slope_per_day, slope_low, slope_high, trend, heading, limit,
                                   residual_sd, expected, earliest, latest)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(TrendPassRate, pass, fail, invalid, rate, lower, upper)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(TrendWarningNow, kind, side, since_ns, expected_ns, earliest_ns,
                                   text)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(StoredTrendWarning, kind, side, started_ns, raised_by, raised_ns,
                                   ended_by, ended_ns, expected_crossing_ns, earliest_crossing_ns,
                                   text)

void to_json(nlohmann::json& j, const MetricTrend& v) {
  j = nlohmann::json{{"machine_id", v.machine_id},
                     {"metric", v.metric},
                     {"unit", v.unit},
                     {"check_kinds", v.check_kinds},
                     {"lower", v.lower},
                     {"upper", v.upper},
                     {"since_ns", v.since_ns},
                     {"until_ns", v.until_ns},
                     {"last", v.last},
                     {"now_ns", v.now_ns},
                     {"restart_ns", v.restart_ns},
                     {"checks", v.checks},
                     {"not_evaluated", v.not_evaluated},
                     {"segment_points", v.segment_points},
                     {"baseline", v.baseline},
                     {"signals", v.signals},
                     {"capability", v.capability},
                     {"least_squares", v.least_squares},
                     {"theil_sen", v.theil_sen},
                     {"pass_rate", v.pass_rate},
                     {"warnings", v.warnings},
                     {"raised", v.raised},
                     {"points", v.points},
                     {"simulated", v.simulated},
                     {"error", v.error}};
}

MetricTrend metric_trend(storage::Database& db, const MetricTrendQuery& query,
                         const trend::AssessOptions& options) {
  MetricTrend out;
  out.machine_id = query.machine_id;
  out.metric = query.metric;
  out.since_ns = query.since_ns;
  out.until_ns = query.until_ns;
  out.last = query.last;
  storage::MetricQuery q{query.machine_id, query.metric};
  if (query.since_ns) q.since_ns = *query.since_ns;
  if (query.until_ns) q.until_ns = *query.until_ns;
  if (query.last) q.last = *query.last;
  const std::vector<storage::MetricValue> series = storage::metric_series(db, q);
  for (const auto& w : storage::trend_warnings(db, {query.machine_id, query.metric})) {
    out.raised.push_back({w.kind, w.side, w.started_ns, w.raised_by, w.raised_ns, w.ended_by,
                          w.ended_ns, w.expected_crossing_ns, w.earliest_crossing_ns, w.text});
  }
  out.checks = series.size();
  if (series.empty()) return out;

  std::set<CheckKind> kinds;
  trend::VerdictCounts verdicts;
  std::vector<trend::Point> points;
  for (const auto& v : series) {
    kinds.insert(v.kind);
    (v.verdict == Verdict::Pass   ? verdicts.pass
     : v.verdict == Verdict::Fail ? verdicts.fail
                                  : verdicts.invalid)++;
    if (!std::isfinite(v.value)) ++out.not_evaluated;
    points.push_back({v.time_ns, v.value});
  }
  out.check_kinds.assign(kinds.begin(), kinds.end());
  const storage::MetricValue& newest = series.back();
  out.unit = newest.unit;
  out.lower = finite(newest.lower);
  out.upper = finite(newest.upper);
  const trend::PassRate rate = trend::pass_rate(verdicts);
  out.pass_rate = {verdicts.pass, verdicts.fail, verdicts.invalid,
                   rate.rate,     rate.lower,    rate.upper};

  // As the historian assesses: as of the newest check, or of the latest restart after it.
  const std::vector<std::int64_t> restarts =
      storage::restart_times(db, query.machine_id, newest.kind, query.metric);
  const std::int64_t now = trend::assessed_as_of(
      newest.time_ns, restarts, query.until_ns.value_or(std::numeric_limits<std::int64_t>::max()));
  out.now_ns = now;
  const trend::Assessment a =
      trend::assess(points, trend::Band{newest.lower, newest.upper}, restarts, now, options);
  out.restart_ns = trend::last_restart(restarts, now);
  for (const auto& v : series) {
    TrendPoint p;
    p.request_id = v.request_id;
    p.kind = v.kind;
    p.time_ns = v.time_ns;
    p.value = finite(v.value);
    p.lower = finite(v.lower);
    p.upper = finite(v.upper);
    p.verdict = v.verdict;
    p.origin = v.origin;
    if (v.origin == DataOrigin::Simulated) ++out.simulated;
    p.in_segment = (!out.restart_ns || v.time_ns > *out.restart_ns) && v.time_ns <= now;
    out.points.push_back(std::move(p));
  }
  if (!a.ok()) {
    out.error = a.error;
    return out;
  }
  out.segment_points = a.segment.points.size();
  const trend::Baseline& b = a.baseline;
  out.baseline = {b.error,
                  b.points,
                  b.mean,
                  b.sigma_within,
                  b.sigma_overall,
                  b.lower_control_limit,
                  b.upper_control_limit,
                  a.watched ? side_name(*a.watched) : std::string()};
  for (const auto& s : a.rules) {
    out.signals.push_back({s.rule, a.segment.points.at(s.index).time_ns, side_name(s.side)});
  }
  const trend::Capability& c = a.capability;
  out.capability = {c.error, c.points, c.cp, c.cpk, c.cpu, c.cpl, c.pp, c.ppk, c.ppu, c.ppl};
  out.least_squares = least_squares_of(a.forecast);
  out.theil_sen = line_of("theil_sen", a.theil_sen);
  const trend::Band band{newest.lower, newest.upper};
  for (const auto& w : a.warnings) {
    out.warnings.push_back({std::string(trend::to_string(w.kind)), side_name(w.side), w.since_ns,
                            w.expected_ns, w.earliest_ns,
                            warning_text(w, a, query.metric, newest.unit, band)});
  }
  if (a.forecast.ok() && !a.segment.points.empty()) {
    const std::int64_t from = a.segment.points.front().time_ns;
    const auto day = static_cast<std::int64_t>(trend::kNanosecondsPerDay);
    std::int64_t to = now + static_cast<std::int64_t>(options.horizon_days) * day;
    const auto& expected = a.forecast.expected;
    if (expected.status == trend::DateStatus::Date && expected.time_ns && *expected.time_ns > to &&
        *expected.time_ns <= now + 365 * day) {
      to = *expected.time_ns + (*expected.time_ns - from) / 20;
    }
    constexpr int kSamples = 48;
    for (int i = 0; i <= kSamples && to > from; ++i) {
      const std::int64_t t =
          from + static_cast<std::int64_t>(static_cast<double>(to - from) * i / kSamples);
      const trend::Interval band_at = trend::prediction_interval(a.forecast, t);
      out.prediction.push_back({t, band_at.fitted, band_at.lower, band_at.upper});
    }
  }
  // The segment's charts, point by point: the segment is the finite in-segment points in order.
  std::size_t k = 0;
  for (TrendPoint& p : out.points) {
    if (!p.in_segment || !p.value) continue;
    if (k < a.ewma.z.size() && a.ewma.error.empty()) {
      p.ewma = a.ewma.z[k];
      p.ewma_lower = a.ewma.lower_limit.at(k);
      p.ewma_upper = a.ewma.upper_limit.at(k);
    }
    if (k < a.cusum.upper.size() && a.cusum.error.empty()) {
      p.cusum_upper = a.cusum.upper[k];
      p.cusum_lower = a.cusum.lower.at(k);
    }
    ++k;
  }
  return out;
}

std::string points_csv(const MetricTrend& t) {
  using namespace storage::csv;
  const auto real_or = [](std::string& out, const std::optional<double>& v, double none) {
    if (v || std::isfinite(none)) append_real(out, v.value_or(none));
  };
  std::string out =
      "time_ns,time_utc,request_id,kind,value,lower,upper,verdict,in_segment,ewma,ewma_lower,"
      "ewma_upper,cusum_upper,cusum_lower,origin\r\n";
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const TrendPoint& p : t.points) {
    append_int(out, p.time_ns);
    out += ',';
    append_utc(out, p.time_ns);
    out += ',';
    append_text(out, p.request_id);
    out += ',';
    append_text(out, to_string(p.kind));
    out += ',';
    real_or(out, p.value, nan);
    out += ',';
    real_or(out, p.lower, -inf);
    out += ',';
    real_or(out, p.upper, inf);
    out += ',';
    append_text(out, to_string(p.verdict));
    out += p.in_segment ? ",1" : ",0";
    for (const auto* v : {&p.ewma, &p.ewma_lower, &p.ewma_upper, &p.cusum_upper, &p.cusum_lower}) {
      out += ',';
      real_or(out, *v, nan);
    }
    out += ',';
    append_text(out, to_string(p.origin));
    out += "\r\n";
  }
  return out;
}

}  // namespace ncqual::report

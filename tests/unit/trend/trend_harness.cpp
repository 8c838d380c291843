// SPDX-License-Identifier: Apache-2.0
// trend_harness: the library's figures for series read as JSON on stdin, printed as JSON on
// stdout, for against_scipy.py to compare with its independent implementation (SciPy, NumPy).
//
// Input:  {"series": [{"name": s, "times_ns": [int], "values": [number or null (NaN)],
//          "lower": number or null (no lower limit), "upper": number or null,
//          "restarts": [int], "now_ns": int, "predict_at_ns": [int],
//          "verdicts": {"pass": int, "fail": int, "invalid": int},
//          "options": {"baseline_points", "min_points", "horizon_days", "ewma_lambda",
//                      "ewma_width", "cusum_k", "cusum_h"} (each optional)}]}
// Output: {"series": [{"name": s, ...assess()'s figures...}]}; NaN and infinities print as null.
#include "ncqual/trend/assess.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <iostream>
#include <limits>

namespace {

using nlohmann::json;
using namespace ncqual::trend;

json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json optional_number(const std::optional<double>& v) { return v ? number(*v) : json(nullptr); }

json date(const LimitDate& d) {
  return {{"status", to_string(d.status)},
          {"time_ns", d.time_ns ? json(*d.time_ns) : json(nullptr)}};
}

json side(const std::optional<Side>& s) { return s ? json(to_string(*s)) : json(nullptr); }

template <typename T>
json optional_index(const std::optional<T>& v) {
  return v ? json(*v) : json(nullptr);
}

json numbers(const std::vector<double>& v) {
  json out = json::array();
  for (double x : v) out.push_back(number(x));
  return out;
}

json figures(const json& in) {
  std::vector<Point> points;
  const auto& times = in.at("times_ns");
  const auto& values = in.at("values");
  for (std::size_t i = 0; i < times.size(); ++i) {
    const double v =
        values[i].is_null() ? std::numeric_limits<double>::quiet_NaN() : values[i].get<double>();
    points.push_back({times[i].get<std::int64_t>(), v});
  }
  Band band;
  if (!in.at("lower").is_null()) band.lower = in.at("lower").get<double>();
  if (!in.at("upper").is_null()) band.upper = in.at("upper").get<double>();
  AssessOptions o;
  if (in.contains("options")) {
    const json& j = in.at("options");
    o.baseline_points = j.value("baseline_points", o.baseline_points);
    o.min_points = j.value("min_points", o.min_points);
    o.horizon_days = j.value("horizon_days", o.horizon_days);
    o.ewma_lambda = j.value("ewma_lambda", o.ewma_lambda);
    o.ewma_width = j.value("ewma_width", o.ewma_width);
    o.cusum_k = j.value("cusum_k", o.cusum_k);
    o.cusum_h = j.value("cusum_h", o.cusum_h);
  }
  const auto restarts = in.value("restarts", std::vector<std::int64_t>{});
  const Assessment a = assess(points, band, restarts, in.at("now_ns").get<std::int64_t>(), o);

  json out;
  out["name"] = in.at("name");
  out["error"] = a.error;
  out["segment_times_ns"] = json::array();
  for (const Point& p : a.segment.points) out["segment_times_ns"].push_back(p.time_ns);
  out["skipped"] = a.segment.skipped;

  const Baseline& b = a.baseline;
  out["baseline"] = {{"error", b.error},
                     {"points", b.points},
                     {"mean", number(b.mean)},
                     {"mean_moving_range", number(b.mean_moving_range)},
                     {"sigma_within", number(b.sigma_within)},
                     {"sigma_overall", number(b.sigma_overall)},
                     {"ucl", number(b.upper_control_limit)},
                     {"lcl", number(b.lower_control_limit)}};
  out["rules"] = json::array();
  for (const RuleSignal& s : a.rules) {
    out["rules"].push_back({s.rule, s.index, to_string(s.side)});
  }
  out["ewma"] = {{"error", a.ewma.error},
                 {"z", numbers(a.ewma.z)},
                 {"lower", numbers(a.ewma.lower_limit)},
                 {"upper", numbers(a.ewma.upper_limit)},
                 {"first_signal", optional_index(a.ewma.first_signal)}};
  out["cusum"] = {{"error", a.cusum.error},
                  {"upper", numbers(a.cusum.upper)},
                  {"lower", numbers(a.cusum.lower)},
                  {"upper_count", a.cusum.upper_count},
                  {"lower_count", a.cusum.lower_count},
                  {"first_up", optional_index(a.cusum.first_up)},
                  {"first_down", optional_index(a.cusum.first_down)},
                  {"mean_at_first_up", optional_number(a.cusum.mean_at_first_up)},
                  {"mean_at_first_down", optional_number(a.cusum.mean_at_first_down)}};
  const Capability& c = a.capability;
  out["capability"] = {{"error", c.error},
                       {"mean", number(c.mean)},
                       {"sigma_within", number(c.sigma_within)},
                       {"sigma_overall", number(c.sigma_overall)},
                       {"cp", optional_number(c.cp)},
                       {"cpk", optional_number(c.cpk)},
                       {"cpu", optional_number(c.cpu)},
                       {"cpl", optional_number(c.cpl)},
                       {"pp", optional_number(c.pp)},
                       {"ppk", optional_number(c.ppk)},
                       {"ppu", optional_number(c.ppu)},
                       {"ppl", optional_number(c.ppl)}};
  const LinearForecast& f = a.forecast;
  json predictions = json::array();
  for (const auto& t : in.value("predict_at_ns", std::vector<std::int64_t>{})) {
    const Interval i = prediction_interval(f, t);
    predictions.push_back({{"time_ns", t},
                           {"fitted", number(i.fitted)},
                           {"lower", number(i.lower)},
                           {"upper", number(i.upper)}});
  }
  out["forecast"] = {{"error", f.error},
                     {"points", f.points},
                     {"reference_ns", f.reference_ns},
                     {"last_x", number(f.last_x)},
                     {"intercept", number(f.intercept)},
                     {"slope", number(f.slope)},
                     {"residual_sd", number(f.residual_sd)},
                     {"slope_se", number(f.slope_se)},
                     {"intercept_se", number(f.intercept_se)},
                     {"t_quantile", number(f.t_quantile)},
                     {"slope_low", number(f.slope_low)},
                     {"slope_high", number(f.slope_high)},
                     {"trend", f.trend},
                     {"heading", side(f.heading)},
                     {"limit", optional_number(f.limit)},
                     {"expected", date(f.expected)},
                     {"earliest", date(f.earliest)},
                     {"latest", date(f.latest)},
                     {"predictions", predictions}};
  const TheilSen& t = a.theil_sen;
  out["theil_sen"] = {{"error", t.error},
                      {"slope", number(t.slope)},
                      {"intercept", number(t.intercept)},
                      {"slope_low", number(t.slope_low)},
                      {"slope_high", number(t.slope_high)},
                      {"trend", t.trend},
                      {"heading", side(t.heading)},
                      {"expected", date(t.expected)}};
  out["warnings"] = json::array();
  for (const Warning& w : a.warnings) {
    out["warnings"].push_back({{"kind", to_string(w.kind)},
                               {"side", to_string(w.side)},
                               {"since_index", w.since_index},
                               {"since_ns", w.since_ns},
                               {"expected_ns", optional_index(w.expected_ns)},
                               {"earliest_ns", optional_index(w.earliest_ns)}});
  }
  if (in.contains("verdicts")) {
    const json& v = in.at("verdicts");
    const PassRate r = pass_rate({v.at("pass").get<std::size_t>(), v.at("fail").get<std::size_t>(),
                                  v.at("invalid").get<std::size_t>()});
    out["pass_rate"] = {{"judged", r.judged},
                        {"rate", optional_number(r.rate)},
                        {"lower", optional_number(r.lower)},
                        {"upper", optional_number(r.upper)}};
  }
  return out;
}

}  // namespace

int main() {
  try {
    const json in = json::parse(std::cin);
    json out;
    out["series"] = json::array();
    for (const json& s : in.at("series")) out["series"].push_back(figures(s));
    std::cout << out.dump() << "\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "trend_harness: " << e.what() << "\n";
    return 2;
  }
}

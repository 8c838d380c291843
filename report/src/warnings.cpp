// SPDX-License-Identifier: Apache-2.0
#include "ncqual/report/warnings.hpp"

#include "ncqual/common/clock.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace ncqual::report {
namespace {

std::string date_text(std::int64_t ns) {
  char buffer[32];
  return std::string(format_iso8601(ns, buffer).substr(0, 10));
}

// A value of the metric with the decimals its band calls for, and its unit.
struct ValueText {
  Metric shape;
  std::string operator()(double value) const {
    Metric m = shape;
    m.value = value;
    return format_metric_value(m) + (m.unit.empty() ? "" : " " + m.unit);
  }
  // A rate per day: two more decimals than a value (a day's drift is small against the band).
  std::string per_day(double value) const {
    const int decimals = std::min(metric_decimals(shape) + 2, 9);
    return fmt::format("{:+.{}f} {}/day", value, decimals, shape.unit);
  }
};

std::string side_word(trend::Side side) { return side == trend::Side::Above ? "above" : "below"; }

std::string forecast_text(const trend::LinearForecast& f, const std::string& metric,
                          const ValueText& value) {
  std::string text = fmt::format("{} drifts {} (95 %: {} to {})", metric, value.per_day(f.slope),
                                 value.per_day(f.slope_low), value.per_day(f.slope_high));
  const std::string limit = f.limit ? value(*f.limit) : std::string("its limit");
  if (f.earliest.status == trend::DateStatus::AlreadyBeyond) {
    text += fmt::format("; a check may already be beyond {}", limit);
  } else if (f.earliest.time_ns) {
    text +=
        fmt::format("; a check may be beyond {} from {}", limit, date_text(*f.earliest.time_ns));
  }
  if (f.expected.status == trend::DateStatus::AlreadyBeyond) {
    text += ", the line is past it";
  } else if (f.expected.time_ns) {
    text += fmt::format(", the line reaches it on {}", date_text(*f.expected.time_ns));
  }
  return text;
}

}  // namespace

std::string warning_text(const trend::Warning& w, const trend::Assessment& a,
                         const std::string& metric, const std::string& unit,
                         const trend::Band& band) {
  const ValueText value{Metric{metric, 0, unit, band.lower, band.upper, true}};
  const auto& points = a.segment.points;
  const double last = points.empty() ? 0 : points.back().value;
  const trend::Baseline& b = a.baseline;
  const std::string since = date_text(w.since_ns);
  switch (w.kind) {
    case trend::WarningKind::ControlLimit:
      return fmt::format(
          "{} {} is {} its control limit {} (centre {}, 3 sigma {})", metric, value(last),
          w.side == trend::Side::Above ? "above" : "below",
          value(w.side == trend::Side::Above ? b.upper_control_limit : b.lower_control_limit),
          value(b.mean), value(3 * b.sigma_within));
    case trend::WarningKind::WesternElectric2:
      return fmt::format(
          "{}: 2 of the last 3 checks are beyond 2 sigma {} the centre {} (since {})", metric,
          side_word(w.side), value(b.mean), since);
    case trend::WarningKind::WesternElectric3:
      return fmt::format(
          "{}: 4 of the last 5 checks are beyond 1 sigma {} the centre {} (since {})", metric,
          side_word(w.side), value(b.mean), since);
    case trend::WarningKind::WesternElectric4:
      return fmt::format("{}: the last 8 checks are all {} the centre {} (since {})", metric,
                         side_word(w.side), value(b.mean), since);
    case trend::WarningKind::Ewma: {
      const auto& e = a.ewma;
      const double z = e.z.empty() ? last : e.z.back();
      const double limit = w.side == trend::Side::Above
                               ? (e.upper_limit.empty() ? 0 : e.upper_limit.back())
                               : (e.lower_limit.empty() ? 0 : e.lower_limit.back());
      return fmt::format("{}: its moving average (EWMA) {} is {} its limit {} since {}", metric,
                         value(z), side_word(w.side), value(limit), since);
    }
    case trend::WarningKind::CusumUp:
    case trend::WarningKind::CusumDown: {
      const bool up = w.kind == trend::WarningKind::CusumUp;
      const auto& c = a.cusum;
      const auto& sums = up ? c.upper : c.lower;
      const auto& counts = up ? c.upper_count : c.lower_count;
      std::string text = fmt::format(
          "{} has shifted {} since about {} (CUSUM {:.1f} sigma, limit {:.1f})", metric,
          up ? "up" : "down", since, sums.empty() || !(c.sigma > 0) ? 0.0 : sums.back() / c.sigma,
          c.sigma > 0 ? c.h / c.sigma : 0.0);
      if (!sums.empty() && !counts.empty() && counts.back() > 0) {
        const double shift = sums.back() / static_cast<double>(counts.back());
        text += fmt::format("; the mean is now about {}",
                            value(up ? c.centre + c.k + shift : c.centre - c.k - shift));
      }
      return text;
    }
    case trend::WarningKind::Forecast: return forecast_text(a.forecast, metric, value);
  }
  return metric;
}

std::vector<storage::TrendWarningRecord> active_records(
    const trend::Assessment& a, const std::string& machine_id, const std::string& metric,
    CheckKind check_kind, const std::string& unit, const trend::Band& band) {
  std::vector<storage::TrendWarningRecord> out;
  for (const trend::Warning& w : a.warnings) {
    storage::TrendWarningRecord r;
    r.machine_id = machine_id;
    r.metric = metric;
    r.check_kind = check_kind;
    r.kind = std::string(trend::to_string(w.kind));
    r.side = side_word(w.side);
    r.started_ns = w.since_ns;
    r.expected_crossing_ns = w.expected_ns;
    r.earliest_crossing_ns = w.earliest_ns;
    r.text = warning_text(w, a, metric, unit, band);
    out.push_back(std::move(r));
  }
  return out;
}

TrendWarning to_sample(const storage::TrendWarningRecord& r, std::int64_t at_ns) {
  TrendWarning w;
  w.machine_id = r.machine_id;
  w.metric = r.metric;
  w.check_kind = r.check_kind;
  w.kind = r.kind;
  w.side = r.side;
  w.active = r.active();
  w.started_ns = r.started_ns;
  w.raised_by = r.raised_by;
  w.ended_by = r.ended_by.value_or("");
  w.expected_crossing_ns = r.expected_crossing_ns;
  w.earliest_crossing_ns = r.earliest_crossing_ns;
  w.text = r.text;
  w.time_ns = at_ns;
  return w;
}

}  // namespace ncqual::report

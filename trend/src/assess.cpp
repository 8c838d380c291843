// SPDX-License-Identifier: Apache-2.0
#include "ncqual/trend/assess.hpp"

#include "fit.hpp"

#include <array>
#include <cmath>
#include <limits>

namespace ncqual::trend {

namespace {

constexpr std::array<std::string_view, kWarningKindCount> kNames{
    "control_limit", "western_electric_2", "western_electric_3", "western_electric_4",
    "ewma",          "cusum_up",           "cusum_down",         "forecast"};

// Per point of the segment: the side a condition holds on, if it holds.
using Track = std::vector<std::optional<Side>>;

// The warning of a track that holds at its last point: from the start of that run.
std::optional<Warning> active(WarningKind kind, const Track& track,
                              const std::vector<Point>& points) {
  if (track.empty() || !track.back()) return std::nullopt;
  const Side side = *track.back();
  std::size_t since = track.size() - 1;
  while (since > 0 && track[since - 1] == side) --since;
  Warning w;
  w.kind = kind;
  w.side = side;
  w.since_index = since;
  w.since_ns = points[since].time_ns;
  return w;
}

// The forecast warning's condition for one fit at one "now".
std::optional<Side> forecast_condition(const LinearForecast& f, std::int64_t now_ns,
                                       double horizon_days) {
  if (!f.ok() || !f.trend || !f.heading) return std::nullopt;
  const LimitDate& e = f.earliest;
  if (e.status != DateStatus::Date && e.status != DateStatus::AlreadyBeyond) return std::nullopt;
  if (!e.time_ns || days_between(now_ns, *e.time_ns) > horizon_days) return std::nullopt;
  return f.heading;
}

std::string check(const AssessOptions& o) {
  if (o.min_points < 3) return "min_points must be at least 3";
  if (o.baseline_points < kMinBaselinePoints) {
    return "baseline_points must be at least " + std::to_string(kMinBaselinePoints);
  }
  if (!(o.horizon_days >= 0) || !std::isfinite(o.horizon_days)) {
    return "horizon_days must be a number >= 0";
  }
  if (!(o.confidence > 0 && o.confidence < 1)) return "confidence must be between 0 and 1";
  if (!(o.ewma_lambda > 0 && o.ewma_lambda <= 1) || !(o.ewma_width > 0) ||
      !std::isfinite(o.ewma_width)) {
    return "EWMA needs 0 < lambda <= 1 and L > 0";
  }
  if (!(o.cusum_k >= 0) || !std::isfinite(o.cusum_k) || !(o.cusum_h > 0) ||
      !std::isfinite(o.cusum_h)) {
    return "CUSUM needs k >= 0 and h > 0";
  }
  return {};
}

}  // namespace

std::string_view to_string(WarningKind kind) {
  const auto i = static_cast<std::size_t>(kind);
  return i < kNames.size() ? kNames[i] : "unknown";
}

std::optional<WarningKind> parse_warning_kind(std::string_view name) {
  for (std::size_t i = 0; i < kNames.size(); ++i) {
    if (kNames[i] == name) return static_cast<WarningKind>(i);
  }
  return std::nullopt;
}

const Warning* Assessment::warning(WarningKind kind) const {
  for (const Warning& w : warnings) {
    if (w.kind == kind) return &w;
  }
  return nullptr;
}

Assessment assess(const std::vector<Point>& points, const Band& band,
                  const std::vector<std::int64_t>& restart_times, std::int64_t now_ns,
                  const AssessOptions& options) {
  Assessment a;
  a.now_ns = now_ns;
  a.error = check(options);
  if (a.error.empty()) a.error = detail::check_band(band);
  if (!a.error.empty()) return a;
  // A magnitude [0, U] is judged as the one-sided band it is; the charts watch its side only.
  const Band judged = judged_band(band);
  a.watched = watched_side(judged);

  a.restart_ns = last_restart(restart_times, now_ns);
  if (a.restart_ns && *a.restart_ns == std::numeric_limits<std::int64_t>::max()) {
    a.segment = between(points, 1, 0);  // nothing after the end of time
  } else {
    a.segment =
        between(points, a.restart_ns ? *a.restart_ns + 1 : std::numeric_limits<std::int64_t>::min(),
                now_ns);
  }
  const std::vector<Point>& seg = a.segment.points;
  const std::size_t n = seg.size();
  const std::vector<double> values = values_of(seg);

  a.baseline = baseline(values, options.baseline_points);
  if (a.baseline.ok()) {
    a.rules = western_electric(values, a.baseline, a.watched);
    a.ewma = ewma(values, a.baseline.mean, a.baseline.sigma_within, options.ewma_lambda,
                  options.ewma_width);
    a.cusum =
        cusum(values, a.baseline.mean, a.baseline.sigma_within, options.cusum_k, options.cusum_h);
  } else {
    a.ewma.error = a.cusum.error = "no baseline: " + a.baseline.error;
  }
  a.capability = capability(values, judged, options.min_points);
  const ForecastOptions forecast_options{options.min_points, options.confidence};
  const std::vector<double> x = detail::days_from_first(seg.data(), n);
  a.forecast =
      detail::fit_sorted(seg.data(), x.data(), n, a.segment.skipped, judged, forecast_options);
  if (options.theil_sen) {
    if (n > options.theil_sen_max_points) {
      const std::vector<Point> recent(
          seg.end() - static_cast<std::ptrdiff_t>(options.theil_sen_max_points), seg.end());
      a.theil_sen = theil_sen(recent, judged, forecast_options);
    } else {
      a.theil_sen = theil_sen(seg, judged, forecast_options);
    }
    a.theil_sen.skipped = a.segment.skipped;
  } else {
    a.theil_sen.error = "not computed (AssessOptions::theil_sen is false)";
  }

  if (a.baseline.ok() && n > 0) {
    std::array<Track, 4> rule_tracks;
    for (Track& t : rule_tracks) t.assign(n, std::nullopt);
    for (const RuleSignal& s : a.rules) {
      rule_tracks[static_cast<std::size_t>(s.rule - 1)][s.index] = s.side;
    }
    Track ewma_track(n), up_track(n), down_track(n);
    for (std::size_t i = 0; i < n; ++i) {
      const bool above = a.watched != Side::Below, below = a.watched != Side::Above;
      if (a.ewma.ok()) {
        const std::optional<Side> side = a.ewma.signal_at(i);
        if (side == Side::Above ? above : below) ewma_track[i] = side;
      }
      if (above && a.cusum.ok() && a.cusum.upper[i] > a.cusum.h) up_track[i] = Side::Above;
      if (below && a.cusum.ok() && a.cusum.lower[i] > a.cusum.h) down_track[i] = Side::Below;
    }
    const std::array<std::pair<WarningKind, const Track*>, 7> spc{{
        {WarningKind::ControlLimit, &rule_tracks[0]},
        {WarningKind::WesternElectric2, &rule_tracks[1]},
        {WarningKind::WesternElectric3, &rule_tracks[2]},
        {WarningKind::WesternElectric4, &rule_tracks[3]},
        {WarningKind::Ewma, &ewma_track},
        {WarningKind::CusumUp, &up_track},
        {WarningKind::CusumDown, &down_track},
    }};
    for (const auto& [kind, track] : spc) {
      if (auto w = active(kind, *track, seg)) a.warnings.push_back(*w);
    }
  }

  if (auto side = forecast_condition(a.forecast, now_ns, options.horizon_days)) {
    // Walk back over the prefixes while the condition held on the same side (each prefix's
    // fit from running moments: O(1) a prefix).
    const std::vector<detail::Moments> moments = detail::prefix_moments(seg.data(), x.data(), n);
    std::size_t since = n - 1;
    while (since > 0) {
      const LinearForecast earlier = detail::fit_prefix(
          seg.data(), x.data(), since, moments[since - 1], judged, forecast_options);
      if (forecast_condition(earlier, seg[since - 1].time_ns, options.horizon_days) != side) {
        break;
      }
      --since;
    }
    Warning w;
    w.kind = WarningKind::Forecast;
    w.side = *side;
    w.since_index = since;
    w.since_ns = seg[since].time_ns;
    w.expected_ns = a.forecast.expected.time_ns;
    w.earliest_ns = a.forecast.earliest.time_ns;
    a.warnings.push_back(w);
  }
  return a;
}

}  // namespace ncqual::trend

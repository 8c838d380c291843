// SPDX-License-Identifier: Apache-2.0
// The assessment of one metric of one machine at one moment: every figure of spc.hpp and
// forecast.hpp over the segment since the last intervention or compensation, and the warnings
// active now (docs/trends.md). The historian calls it after each stored result and publishes a
// TrendWarning when a warning starts or ends; it is deterministic (the same input gives the same
// output, whatever the wall clock) and cheap (a year of daily checks in well under a
// millisecond).
//
// The segment: the finite points with last restart < time_ns <= now_ns, where the last restart
// is the latest restart time at or before now_ns (restart_after). Points and restarts after
// now_ns are ignored, so an assessment "as of" a past moment is reproducible.
//
// The charts: the baseline is the segment's first `baseline_points` finite values (no SPC
// warning until there are that many); the Western Electric rules, the EWMA (centre = baseline
// mean, sigma = baseline sigma_within) and the CUSUM (the same) run over the whole segment,
// baseline included. Capability is over the whole segment; the forecasts too (Theil-Sen over
// its last theil_sen_max_points checks).
//
// A one-sided metric (an upper limit only, or a magnitude toleranced [0, U]: judged_band) is
// watched on its limit's side only (watched_side): the rules, the EWMA and the CUSUM warn only
// above (below) the centre line, and its 0 is no limit for capability and the forecasts.
//
// A warning is active when its condition holds at the last point of the segment:
//   control_limit        rule 1: the last point is beyond 3 sigma
//   western_electric_2   rule 2: 2 of the last 3 points beyond 2 sigma, one side
//   western_electric_3   rule 3: 4 of the last 5 points beyond 1 sigma, one side
//   western_electric_4   rule 4: the last 8 points on one side of the centre line
//   ewma                 the last EWMA value is beyond its limit
//   cusum_up/cusum_down  the upper (lower) CUSUM is above H at the last point (the sums are not
//                        reset after a signal: they fall back below H when the shift ends)
//   forecast             the least-squares line has a trend, and the earliest date (the near
//                        95 % prediction bound reaching the limit the line heads to) is at or
//                        before now + horizon_days (a limit already reached counts)
// Its start (since) is the first point of the uninterrupted run of points, ending at the last
// one, at which the condition held on the same side: where it first fired in its current
// episode. For the forecast, the condition at an earlier point k is the forecast of the
// segment's points up to k, with "now" = that point's time. So a warning ends by itself when
// the condition stops holding (a one-off outlier ends its control_limit warning at the next
// check), and every warning ends at a restart.
#pragma once

#include "ncqual/trend/forecast.hpp"
#include "ncqual/trend/series.hpp"
#include "ncqual/trend/spc.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ncqual::trend {

// The kinds of warning. The text names are stable (TrendWarning, logs, JSON): never rename.
enum class WarningKind : int {
  ControlLimit = 0,
  WesternElectric2 = 1,
  WesternElectric3 = 2,
  WesternElectric4 = 3,
  Ewma = 4,
  CusumUp = 5,
  CusumDown = 6,
  Forecast = 7,
};
inline constexpr int kWarningKindCount = 8;
// "control_limit", "western_electric_2", "western_electric_3", "western_electric_4", "ewma",
// "cusum_up", "cusum_down", "forecast"
std::string_view to_string(WarningKind kind);
std::optional<WarningKind> parse_warning_kind(std::string_view name);

struct Warning {
  WarningKind kind = WarningKind::ControlLimit;
  Side side = Side::Above;      // of the centre line; for forecast, the limit it heads to
  std::size_t since_index = 0;  // in Assessment::segment.points
  std::int64_t since_ns = 0;    // that point's time
  // forecast only: the dates of Assessment::forecast (expected may be absent: TooFar, or a
  // limit crossed longer than kMaxForecastDays ago).
  std::optional<std::int64_t> expected_ns;
  std::optional<std::int64_t> earliest_ns;
};

struct AssessOptions {
  std::size_t baseline_points = 10;  // at least kMinBaselinePoints
  std::size_t min_points = 5;        // of the forecasts and of capability (at least 3)
  double horizon_days = 30;          // forecast warning: earliest date within now + this
  double confidence = 0.95;          // of the forecasts' intervals
  double ewma_lambda = 0.2;
  double ewma_width = 3;  // L
  double cusum_k = 0.5;   // in sigmas
  double cusum_h = 5;     // in sigmas
  // Compute Assessment::theil_sen. It is the costliest figure (n(n-1)/2 pairwise slopes: a
  // third of a millisecond for a year of daily checks) and no warning uses it, so a caller that
  // wants only the warnings can leave it out.
  bool theil_sen = true;
  // Theil-Sen over the segment's last this many checks at most: its time and memory grow with
  // the square of the count (1000 checks are 499,500 slopes, 4 MB, some 10 ms).
  std::size_t theil_sen_max_points = 1000;
};

struct Assessment {
  std::string error;  // the band or the options cannot be used; nothing else is filled
  std::int64_t now_ns = 0;
  std::optional<std::int64_t> restart_ns;  // the restart the segment follows
  // A one-sided metric (watched_side of judged_band: a magnitude [0, U] too): the side its
  // rules, EWMA and CUSUM warn on; none: both. Capability and the forecasts use judged_band.
  std::optional<Side> watched;
  Series segment;
  Baseline baseline;
  std::vector<RuleSignal> rules;  // western_electric over the segment
  Ewma ewma;                      // error set when there is no baseline
  Cusum cusum;                    // error set when there is no baseline
  Capability capability;
  LinearForecast forecast;
  TheilSen theil_sen;             // error set when AssessOptions::theil_sen is false
  std::vector<Warning> warnings;  // the active ones, in WarningKind order

  bool ok() const { return error.empty(); }
  // The active warning of a kind; nullptr when it is not active.
  const Warning* warning(WarningKind kind) const;
};

Assessment assess(const std::vector<Point>& points, const Band& band,
                  const std::vector<std::int64_t>& restart_times, std::int64_t now_ns,
                  const AssessOptions& options = {});

}  // namespace ncqual::trend

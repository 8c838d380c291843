// SPDX-License-Identifier: Apache-2.0
// The trend chart: one metric of one machine over time, check by check, against its tolerance,
// with optional SPC control limits, a forecast (the fitted line carried on to a future time with
// its prediction band and the expected date it crosses a limit), and the interventions and
// compensations that explain a step in the data.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "ncqual/charts/axis.hpp"
#include "ncqual/charts/chart.hpp"

namespace ncqual::charts {

inline constexpr double kNoLimit = std::numeric_limits<double>::infinity();

// A tolerance band in the caller's unit: pass when lower <= value <= upper. A side without a
// limit is -kNoLimit / +kNoLimit (a NaN counts as no limit too); only finite limits are drawn.
struct ToleranceBand {
  double lower = -kNoLimit;
  double upper = kNoLimit;
};

// One check: its time, the metric's value (caller's unit), whether the check failed (its
// verdict; a value outside the tolerance band is drawn as failed whatever this says), and a
// label for the marker's tooltip (e.g. the request id).
struct TrendPoint {
  std::int64_t time_ns = 0;
  double value = 0;
  bool failed = false;
  std::string label;
};

// SPC limits (caller's unit): the centre line and the lower and upper control limits. A
// non-finite one is not drawn.
struct ControlLimits {
  double centre = 0;
  double lower = 0;
  double upper = 0;
};

// One time of the forecast: the fitted value and the prediction band around it (caller's unit).
struct ForecastSample {
  std::int64_t time_ns = 0;
  double fitted = 0;
  double lower = 0;
  double upper = 0;
};

// The fitted line over the samples (ascending times, usually from the fit's first check to the
// horizon), the prediction band as a shaded area, and the expected crossing of a tolerance
// limit, when there is one, as a marked date.
struct Forecast {
  std::vector<ForecastSample> samples;
  std::string band_label = "95 % prediction band";
  std::optional<std::int64_t> crossing_ns;
};

enum class MarkerKind { Intervention, Compensation };

// A vertical line at a time with a short label (an intervention on the machine, a compensation
// the solver issued). Give a chart only the markers that restart its series (restarts_series):
// the others explain nothing on it. Markers of one kind closer than 6 px are drawn as one line
// (class "marker intervention" or "marker compensation"; data-count, the group's size;
// data-time, its latest marker; data-first-time, its first) at the latest one, with a pale strip
// ("marker-span") along the plot's top over the time they span and the count as its label;
// interventions and compensations are grouped apart, and the groups widen until the lines and
// labels cover at most a tenth of the plot's width.
struct TimeMarker {
  std::int64_t time_ns = 0;
  std::string label;
  MarkerKind kind = MarkerKind::Intervention;
};

// The time zone of a time axis: its ticks fall on the zone's round times (local midnights for
// days) and its labels and texts read its wall clock. Empty: UTC. The charts stay free of a tz
// database: the caller gives the conversions (e.g. ncqual::Calendar's wall_ns, from_wall_ns and
// local_text).
struct TimeZone {
  std::function<std::int64_t(std::int64_t)> to_wall;    // instant -> wall clock read as UTC
  std::function<std::int64_t(std::int64_t)> from_wall;  // and back
  TimeFormatter text;  // a time in texts and tooltips, e.g. "2027-01-15 09:00 +01:00 CET"
};

struct TrendChart {
  std::string title;        // the visible title and the SVG's <title>
  std::string description;  // appended to the generated <desc>
  std::string quantity;     // the y axis' name, e.g. "centre dx"
  DisplayUnit unit;         // e.g. values in mm shown in µm: {1000, "µm"}
  std::vector<TrendPoint> points;
  ToleranceBand tolerance;
  std::optional<ControlLimits> control;
  std::optional<Forecast> forecast;
  std::vector<TimeMarker> markers;
  TimeFormatter time_label;  // tick labels and dates in texts; empty: dates of `zone`
  TimeZone zone;             // empty: UTC
  std::string time_title = "date (UTC)";
  Size size;  // default 720 × 360
};

inline constexpr Size kTrendSize{720, 360};

// The chart as an <svg> element (data-chart="trend"). Points with a non-finite value are skipped
// and counted in the <desc>; without any point the frame says "no data". Markers: class "point
// pass" or "point fail", data-time (ns), data-value (caller's unit, exact).
std::string trend_chart(const TrendChart& chart);

}  // namespace ncqual::charts

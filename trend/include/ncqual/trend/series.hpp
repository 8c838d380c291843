// SPDX-License-Identifier: Apache-2.0
// The time series the trend statistics work on: one metric of one machine, one value per check
// (docs/trends.md).
//
// Times are int64 nanoseconds since the Unix epoch (UTC), as everywhere in ncqual; values stay in
// the metric's unit (mm, rad): nothing in ncqual_trend converts units. Regressions work in days
// (days_between), because "0.4 µm per day" is the figure people read.
//
// A value that is not a finite number (NaN: the metric could not be evaluated; ±infinity) is
// never used: every selection below leaves it out and counts it in Series::skipped, and every
// statistic in spc.hpp and forecast.hpp skips it too, so no input makes them crash or return a
// NaN date.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string_view>
#include <vector>

namespace ncqual::trend {

// One check result of one metric.
struct Point {
  std::int64_t time_ns = 0;
  double value = 0;
};

// The side of a centre line, or of a band, a signal or a trend is on: Above is towards the upper
// limit.
enum class Side { Above, Below };
std::string_view to_string(Side side);  // "above", "below"

// A tolerance band: a value passes when lower <= value <= upper (ncqual::Metric's lower and
// upper). A one-sided metric has lower = -infinity (only an upper limit, e.g. a flatness) or
// upper = +infinity.
struct Band {
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
};

// A one-sided metric as the statistics read it (docs/trends.md, "One-sided metrics"): a
// magnitude toleranced [0, upper] (a flatness, a distance, a range: its values cannot be below
// 0, so 0 is where they end, not a limit a drift could cross) is the band (-infinity, upper];
// every other band is itself.
Band judged_band(const Band& band);
// The side of the centre line on which a metric can go wrong: Above for a band with only an
// upper limit (after judged_band: a magnitude too), Below for one with only a lower limit, none
// for a two-sided band (or none at all). The SPC rules, EWMA and CUSUM of a one-sided metric
// warn on that side only: on the other the metric improves.
std::optional<Side> watched_side(const Band& band);

// Finite points in time order (stable: equal times keep their input order), and how many points
// of the selection were left out because their value was not finite.
struct Series {
  std::vector<Point> points;
  std::size_t skipped = 0;
};

inline constexpr double kNanosecondsPerDay = 86400e9;

// (to - from) in days, exact up to the double rounding of the nanosecond difference.
double days_between(std::int64_t from_ns, std::int64_t to_ns);
// from_ns + days, rounded to the nearest nanosecond; std::nullopt when not finite or outside the
// int64 range (about years 1678 to 2262).
std::optional<std::int64_t> add_days(std::int64_t from_ns, double days);

// Every finite point, in time order.
Series finite_points(const std::vector<Point>& points);
// The finite points with from_ns <= time_ns <= to_ns.
Series between(const std::vector<Point>& points, std::int64_t from_ns, std::int64_t to_ns);
// The last n finite points (all of them when there are fewer); skipped counts the non-finite
// points at or after the first one kept (all of them when none is kept).
Series last_n(const std::vector<Point>& points, std::size_t n);
// The latest restart time (an intervention, a compensation) at or before up_to_ns; std::nullopt
// when there is none.
std::optional<std::int64_t> last_restart(const std::vector<std::int64_t>& restart_times,
                                         std::int64_t up_to_ns);
// The time a series is assessed at: its newest point, or the latest restart after it (at or
// before up_to_ns) when there is one, so that a check from before an intervention that arrives
// after it is not judged in the segment the intervention ended.
std::int64_t assessed_as_of(std::int64_t newest_ns, const std::vector<std::int64_t>& restart_times,
                            std::int64_t up_to_ns = std::numeric_limits<std::int64_t>::max());
// The segment the statistics describe: the finite points strictly after the latest restart time
// (every point when restart_times is empty). A check stamped at the very nanosecond of an
// intervention belongs to the series before it: the intervention is recorded when it is done,
// and a check that follows it is stamped later.
Series restart_after(const std::vector<Point>& points,
                     const std::vector<std::int64_t>& restart_times);
// The values of points, in order.
std::vector<double> values_of(const std::vector<Point>& points);

}  // namespace ncqual::trend

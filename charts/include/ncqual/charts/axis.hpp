// SPDX-License-Identifier: Apache-2.0
// Axes: the mapping of data to pixels, "nice" tick values (1, 2 or 5 × 10^k) for numbers, and
// calendar-aligned ticks for times (int64 ns since the Unix epoch, UTC).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ncqual::charts {

// Maps the domain [d0, d1] linearly onto the pixels [p0, p1] (p0 > p1 for a y axis, whose pixels
// grow downwards). A degenerate domain maps everything to the middle of the pixels.
class LinearScale {
 public:
  LinearScale() = default;
  LinearScale(double d0, double d1, double p0, double p1) : d0_(d0), d1_(d1), p0_(p0), p1_(p1) {}
  double operator()(double v) const;
  // Pixels per unit of the domain (negative when the pixels run against it).
  double pixels_per_unit() const;
  double domain_lo() const { return d0_; }
  double domain_hi() const { return d1_; }

 private:
  double d0_ = 0, d1_ = 1, p0_ = 0, p1_ = 1;
};

// A tick spacing m × 10^e with m in {1, 2, 5}.
struct TickStep {
  int mantissa = 1;
  int exponent = 0;
  double value() const;
  // The i-th multiple, i × m × 10^e, computed so that it is the double nearest the decimal
  // number (3 × 0.005 gives exactly 0.015).
  double multiple(long long i) const;
  // Decimals that show every multiple exactly: max(0, -e).
  int decimals() const { return exponent < 0 ? -exponent : 0; }
};

// The smallest step of the 1-2-5 series that is >= `rough` (> 0, finite).
TickStep nice_step(double rough);

// The multiples of `step` within [lo, hi] (ends included up to rounding), ascending.
std::vector<double> ticks_within(double lo, double hi, const TickStep& step);

// A numeric axis: its domain extended outwards to multiples of the step, and the ticks.
struct NiceAxis {
  double lo = 0;
  double hi = 1;
  TickStep step;
  std::vector<double> ticks;  // lo, lo + step, ..., hi
};

// The axis over [lo, hi] (any order) with about `target_intervals` intervals (at least 1): step =
// nice_step((hi - lo) / target_intervals), ends rounded out to multiples of it. An empty range
// (lo == hi) is widened by 10 % of |lo| on each side (±1 around 0) first. 0..0.025 with 5
// intervals gives 0, 0.005, ..., 0.025.
NiceAxis nice_axis(double lo, double hi, int target_intervals = 5);

// A tick label: v with the step's decimals and U+2212 for the minus sign.
std::string tick_label(double v, const TickStep& step);

// ---- Times ---------------------------------------------------------------------------------

// Turns a time (ns since the Unix epoch) into the text of a tick label.
using TimeFormatter = std::function<std::string(std::int64_t)>;

// "2026-11-25" (UTC).
std::string utc_date(std::int64_t time_ns);
// "2026-11-25 06:30" (UTC).
std::string utc_date_time(std::int64_t time_ns);

// Ticks of a time axis: every tick on a round UTC boundary of the chosen step (seconds,
// minutes, hours, days, Mondays for weeks, first of the month for months, 1 January for years).
struct TimeTicks {
  std::vector<std::int64_t> ticks;  // ns, ascending, within [lo, hi]
  std::int64_t step_ns = 0;         // nominal (a month counts as 30 days)
  bool whole_days = false;          // every tick at 00:00 UTC
};

// The finest calendar step that gives at most `max_ticks` (>= 2) ticks within [lo, hi].
TimeTicks time_ticks(std::int64_t lo_ns, std::int64_t hi_ns, int max_ticks);

// The default tick label: utc_date when the ticks are whole days, utc_date_time otherwise.
std::string default_time_label(const TimeTicks& ticks, std::int64_t time_ns);

}  // namespace ncqual::charts

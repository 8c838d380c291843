// SPDX-License-Identifier: Apache-2.0
#include "ncqual/charts/axis.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "ncqual/charts/svg.hpp"

namespace ncqual::charts {
namespace {

// 10^|e| as a double: exact for |e| <= 22.
double power_of_ten(int e) {
  double p = 1;
  for (int i = 0; i < std::abs(e); ++i) p *= 10;
  return p;
}

constexpr std::int64_t kNsPerSecond = 1'000'000'000;
constexpr std::int64_t kSecondsPerDay = 86'400;
constexpr std::int64_t kNsPerDay = kSecondsPerDay * kNsPerSecond;

// floor(a / b) for b > 0.
std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}

// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's days_from_civil).
std::int64_t days_from_civil(std::int64_t y, unsigned m, unsigned d) {
  y -= m <= 2 ? 1 : 0;
  const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
  const auto yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m > 2 ? m - 3 : m + 9) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<std::int64_t>(doe) - 719468;
}

struct Civil {
  std::int64_t year;
  unsigned month;  // 1..12
  unsigned day;    // 1..31
};

// The date of a day count since 1970-01-01 (H. Hinnant's civil_from_days).
Civil civil_from_days(std::int64_t z) {
  z += 719468;
  const std::int64_t era = (z >= 0 ? z : z - 146096) / 146097;
  const auto doe = static_cast<unsigned>(z - era * 146097);
  const unsigned yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const std::int64_t y = static_cast<std::int64_t>(yoe) + era * 400;
  const unsigned doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const unsigned mp = (5 * doy + 2) / 153;
  const unsigned d = doy - (153 * mp + 2) / 5 + 1;
  const unsigned m = mp < 10 ? mp + 3 : mp - 9;
  return {y + (m <= 2 ? 1 : 0), m, d};
}

// Ticks every `step_s` seconds on the boundaries offset by `offset_s` from the epoch.
std::vector<std::int64_t> fixed_ticks(std::int64_t lo, std::int64_t hi, std::int64_t step_s,
                                      std::int64_t offset_s, std::size_t limit) {
  const std::int64_t step = step_s * kNsPerSecond;
  const std::int64_t offset = offset_s * kNsPerSecond;
  std::vector<std::int64_t> out;
  std::int64_t k = floor_div(lo - offset, step);
  if (k * step + offset < lo) ++k;
  for (std::int64_t t = k * step + offset; t <= hi; t += step) {
    out.push_back(t);
    if (out.size() > limit) break;
  }
  return out;
}

// Ticks on the first of every `months`-th month (aligned to multiples of `months` counted from
// January of year 0).
std::vector<std::int64_t> month_ticks(std::int64_t lo, std::int64_t hi, int months,
                                      std::size_t limit) {
  const Civil c = civil_from_days(floor_div(lo, kNsPerDay));
  std::int64_t index = c.year * 12 + static_cast<std::int64_t>(c.month) - 1;
  index = floor_div(index, months) * months;
  std::vector<std::int64_t> out;
  for (;; index += months) {
    const std::int64_t y = floor_div(index, 12);
    const auto m = static_cast<unsigned>(index - y * 12 + 1);
    const std::int64_t t = days_from_civil(y, m, 1) * kNsPerDay;
    if (t > hi) break;
    if (t >= lo) out.push_back(t);
    if (out.size() > limit) break;
  }
  return out;
}

std::string format_civil(std::int64_t time_ns, bool with_time) {
  const std::int64_t days = floor_div(time_ns, kNsPerDay);
  const std::int64_t second_of_day = floor_div(time_ns - days * kNsPerDay, kNsPerSecond);
  const Civil c = civil_from_days(days);
  std::array<char, 64> buf{};
  if (with_time) {
    std::snprintf(buf.data(), buf.size(), "%04lld-%02u-%02u %02lld:%02lld",
                  static_cast<long long>(c.year), c.month, c.day,
                  static_cast<long long>(second_of_day / 3600),
                  static_cast<long long>(second_of_day / 60 % 60));
  } else {
    std::snprintf(buf.data(), buf.size(), "%04lld-%02u-%02u", static_cast<long long>(c.year),
                  c.month, c.day);
  }
  return buf.data();
}

}  // namespace

double LinearScale::operator()(double v) const {
  if (d1_ == d0_) return (p0_ + p1_) / 2;
  return p0_ + (v - d0_) * (p1_ - p0_) / (d1_ - d0_);
}

double LinearScale::pixels_per_unit() const {
  if (d1_ == d0_) return 0;
  return (p1_ - p0_) / (d1_ - d0_);
}

double TickStep::value() const { return multiple(1); }

double TickStep::multiple(long long i) const {
  const double n = static_cast<double>(i * mantissa);
  return exponent >= 0 ? n * power_of_ten(exponent) : n / power_of_ten(exponent);
}

TickStep nice_step(double rough) {
  if (!(rough > 0) || !std::isfinite(rough)) return {};
  // A rough step that is a nice number up to rounding (0.025 / 5) keeps that number.
  const double target = rough * (1 - 1e-9);
  int e = static_cast<int>(std::floor(std::log10(target)));
  for (;; ++e) {
    for (const int m : {1, 2, 5}) {
      const TickStep s{m, e};
      if (s.value() >= target) return s;
    }
  }
}

std::vector<double> ticks_within(double lo, double hi, const TickStep& step) {
  if (lo > hi) std::swap(lo, hi);
  const double v = step.value();
  const double slack = 1e-9;
  const auto first = static_cast<long long>(std::ceil(lo / v - slack));
  const auto last = static_cast<long long>(std::floor(hi / v + slack));
  std::vector<double> out;
  for (long long i = first; i <= last && out.size() < 1000; ++i) out.push_back(step.multiple(i));
  return out;
}

NiceAxis nice_axis(double lo, double hi, int target_intervals) {
  if (lo > hi) std::swap(lo, hi);
  if (!std::isfinite(lo) || !std::isfinite(hi)) lo = 0, hi = 1;
  if (hi - lo <= std::max(std::abs(lo), std::abs(hi)) * 1e-12) {
    const double pad = lo == 0 ? 1 : std::abs(lo) * 0.1;
    lo -= pad;
    hi += pad;
  }
  target_intervals = std::max(1, target_intervals);
  NiceAxis axis;
  axis.step = nice_step((hi - lo) / target_intervals);
  const double v = axis.step.value();
  const double slack = 1e-9;
  const auto first = static_cast<long long>(std::floor(lo / v + slack));
  const auto last = static_cast<long long>(std::ceil(hi / v - slack));
  axis.lo = axis.step.multiple(first);
  axis.hi = axis.step.multiple(last);
  for (long long i = first; i <= last; ++i) axis.ticks.push_back(axis.step.multiple(i));
  return axis;
}

std::string tick_label(double v, const TickStep& step) {
  return svg::typographic_minus(svg::fixed(v, step.decimals()));
}

std::string utc_date(std::int64_t time_ns) { return format_civil(time_ns, false); }

std::string utc_date_time(std::int64_t time_ns) { return format_civil(time_ns, true); }

TimeTicks time_ticks(std::int64_t lo_ns, std::int64_t hi_ns, int max_ticks) {
  if (lo_ns > hi_ns) std::swap(lo_ns, hi_ns);
  const auto limit = static_cast<std::size_t>(std::max(2, max_ticks));
  struct Fixed {
    std::int64_t step_s;
    std::int64_t offset_s;
  };
  // Weeks start on Monday: 1970-01-05 was one.
  static constexpr std::array<Fixed, 21> kFixed = {{{1, 0},
                                                    {2, 0},
                                                    {5, 0},
                                                    {10, 0},
                                                    {15, 0},
                                                    {30, 0},
                                                    {60, 0},
                                                    {120, 0},
                                                    {300, 0},
                                                    {600, 0},
                                                    {900, 0},
                                                    {1800, 0},
                                                    {3600, 0},
                                                    {7200, 0},
                                                    {10800, 0},
                                                    {21600, 0},
                                                    {43200, 0},
                                                    {kSecondsPerDay, 0},
                                                    {2 * kSecondsPerDay, 0},
                                                    {7 * kSecondsPerDay, 4 * kSecondsPerDay},
                                                    {14 * kSecondsPerDay, 4 * kSecondsPerDay}}};
  TimeTicks out;
  for (const Fixed& f : kFixed) {
    auto ticks = fixed_ticks(lo_ns, hi_ns, f.step_s, f.offset_s, limit);
    if (ticks.size() <= limit) {
      out.ticks = std::move(ticks);
      out.step_ns = f.step_s * kNsPerSecond;
      out.whole_days = f.step_s % kSecondsPerDay == 0;
      return out;
    }
  }
  for (const int months : {1, 2, 3, 6, 12, 24, 60, 120, 240, 600, 1200}) {
    auto ticks = month_ticks(lo_ns, hi_ns, months, limit);
    if (ticks.size() <= limit || months == 1200) {
      out.ticks = std::move(ticks);
      out.step_ns = static_cast<std::int64_t>(months) * 30 * kNsPerDay;
      out.whole_days = true;
      return out;
    }
  }
  return out;
}

std::string default_time_label(const TimeTicks& ticks, std::int64_t time_ns) {
  return ticks.whole_days ? utc_date(time_ns) : utc_date_time(time_ns);
}

}  // namespace ncqual::charts

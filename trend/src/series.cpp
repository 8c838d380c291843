// SPDX-License-Identifier: Apache-2.0
#include "ncqual/trend/series.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace ncqual::trend {

namespace {

bool earlier(const Point& a, const Point& b) { return a.time_ns < b.time_ns; }

// The points for which keep(point) holds, in time order, split into finite and skipped.
template <typename Keep>
Series select(const std::vector<Point>& points, Keep keep) {
  Series out;
  out.points.reserve(points.size());
  for (const Point& p : points) {
    if (!keep(p)) continue;
    if (std::isfinite(p.value)) {
      out.points.push_back(p);
    } else {
      ++out.skipped;
    }
  }
  if (!std::is_sorted(out.points.begin(), out.points.end(), earlier)) {
    std::stable_sort(out.points.begin(), out.points.end(), earlier);
  }
  return out;
}

}  // namespace

std::string_view to_string(Side side) { return side == Side::Above ? "above" : "below"; }

double days_between(std::int64_t from_ns, std::int64_t to_ns) {
  std::int64_t difference = 0;
  if (!__builtin_sub_overflow(to_ns, from_ns, &difference)) {
    return static_cast<double>(difference) / kNanosecondsPerDay;
  }
  return (static_cast<double>(to_ns) - static_cast<double>(from_ns)) / kNanosecondsPerDay;
}

std::optional<std::int64_t> add_days(std::int64_t from_ns, double days) {
  if (!std::isfinite(days)) return std::nullopt;
  const double offset = std::round(days * kNanosecondsPerDay);
  // 2^63 is exactly representable; every double below it converts without overflow.
  constexpr double kLimit = 9223372036854775808.0;
  if (!(offset > -kLimit && offset < kLimit)) return std::nullopt;
  std::int64_t sum = 0;
  if (__builtin_add_overflow(from_ns, static_cast<std::int64_t>(offset), &sum)) {
    return std::nullopt;
  }
  return sum;
}

Band judged_band(const Band& band) {
  if (band.lower == 0 && std::isfinite(band.upper) && band.upper > 0) {
    return {-std::numeric_limits<double>::infinity(), band.upper};
  }
  return band;
}

std::optional<Side> watched_side(const Band& band) {
  const Band b = judged_band(band);
  const bool lower = std::isfinite(b.lower), upper = std::isfinite(b.upper);
  if (upper && !lower) return Side::Above;
  if (lower && !upper) return Side::Below;
  return std::nullopt;
}

Series finite_points(const std::vector<Point>& points) {
  return select(points, [](const Point&) { return true; });
}

Series between(const std::vector<Point>& points, std::int64_t from_ns, std::int64_t to_ns) {
  return select(points, [&](const Point& p) { return p.time_ns >= from_ns && p.time_ns <= to_ns; });
}

Series last_n(const std::vector<Point>& points, std::size_t n) {
  Series all = finite_points(points);
  if (all.points.size() <= n) return all;
  Series out;
  out.points.assign(all.points.end() - static_cast<std::ptrdiff_t>(n), all.points.end());
  if (n == 0) {
    out.skipped = all.skipped;
    return out;
  }
  const std::int64_t first = out.points.front().time_ns;
  out.skipped = static_cast<std::size_t>(std::count_if(points.begin(), points.end(), [&](auto& p) {
    return !std::isfinite(p.value) && p.time_ns >= first;
  }));
  return out;
}

std::optional<std::int64_t> last_restart(const std::vector<std::int64_t>& restart_times,
                                         std::int64_t up_to_ns) {
  std::optional<std::int64_t> latest;
  for (std::int64_t t : restart_times) {
    if (t <= up_to_ns && (!latest || t > *latest)) latest = t;
  }
  return latest;
}

Series restart_after(const std::vector<Point>& points,
                     const std::vector<std::int64_t>& restart_times) {
  const auto restart = last_restart(restart_times, std::numeric_limits<std::int64_t>::max());
  if (!restart) return finite_points(points);
  return select(points, [&](const Point& p) { return p.time_ns > *restart; });
}

std::vector<double> values_of(const std::vector<Point>& points) {
  std::vector<double> values;
  values.reserve(points.size());
  std::transform(points.begin(), points.end(), std::back_inserter(values),
                 [](const Point& p) { return p.value; });
  return values;
}

std::int64_t assessed_as_of(std::int64_t newest_ns, const std::vector<std::int64_t>& restart_times,
                            std::int64_t up_to_ns) {
  const std::optional<std::int64_t> restart = last_restart(restart_times, up_to_ns);
  return restart && *restart > newest_ns ? *restart : newest_ns;
}

}  // namespace ncqual::trend

// SPDX-License-Identifier: Apache-2.0
#include "ncqual/trend/forecast.hpp"

#include "fit.hpp"
#include "quantiles.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace ncqual::trend {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string not_enough(std::size_t have, std::size_t need) {
  return "not enough points: " + std::to_string(have) + " of " + std::to_string(need);
}

// The limit a line of this slope heads to, and the side.
void heading_of(double slope, const Band& band, std::optional<Side>& heading,
                std::optional<double>& limit) {
  heading.reset();
  limit.reset();
  if (slope > 0) {
    heading = Side::Above;
    if (std::isfinite(band.upper)) limit = band.upper;
  } else if (slope < 0) {
    heading = Side::Below;
    if (std::isfinite(band.lower)) limit = band.lower;
  }
}

// A date x days after reference, unless it is more than kMaxForecastDays after last_x.
LimitDate date_at(std::int64_t reference_ns, double x, double last_x) {
  if (!(x - last_x <= kMaxForecastDays)) return {DateStatus::TooFar, std::nullopt};
  auto time = add_days(reference_ns, x);
  if (!time) return {DateStatus::TooFar, std::nullopt};
  return {DateStatus::Date, time};
}

// Where the line intercept + slope x reaches the limit it heads to.
LimitDate line_crossing(bool trend, const std::optional<Side>& heading,
                        const std::optional<double>& limit, double intercept, double slope,
                        std::int64_t reference_ns, double last_x) {
  if (!heading) return {DateStatus::NoTrend, std::nullopt};
  if (!limit) return {DateStatus::NoLimit, std::nullopt};
  if (!trend) return {DateStatus::NoTrend, std::nullopt};
  const double x = (*limit - intercept) / slope;
  if (x <= last_x) {
    // The fitted line is at or beyond the limit at the last point: say when it crossed.
    std::optional<std::int64_t> when;
    if (last_x - x <= kMaxForecastDays) when = add_days(reference_ns, x);
    return {DateStatus::AlreadyBeyond, when};
  }
  return date_at(reference_ns, x, last_x);
}

// The real roots of a u² + 2 h u + c = 0 (h = half the linear coefficient), in increasing order,
// computed without cancellation (Numerical Recipes §5.6); `quarter_discriminant` = h² - a c,
// passed in because the caller has it in a cancellation-free form.
std::vector<double> quadratic_roots(double a, double h, double c, double quarter_discriminant) {
  std::vector<double> roots;
  if (a == 0) {
    if (h != 0) roots.push_back(-c / (2 * h));
    return roots;
  }
  if (quarter_discriminant < 0) return roots;
  const double q = -(h + std::copysign(std::sqrt(quarter_discriminant), h));
  if (q == 0) {
    // h = 0 and discriminant 0: c = 0, a double root at 0.
    roots.push_back(0);
  } else {
    roots.push_back(q / a);
    roots.push_back(c / q);
  }
  std::sort(roots.begin(), roots.end());
  return roots;
}

// The earliest and latest dates of the inverse prediction (forecast.hpp).
void inverse_prediction(LinearForecast& f, std::size_t n, std::int64_t last_ns) {
  if (!f.heading) {
    f.earliest = f.latest = {DateStatus::NoTrend, std::nullopt};
    return;
  }
  if (!f.limit) {
    f.earliest = f.latest = {DateStatus::NoLimit, std::nullopt};
    return;
  }
  // Mirror a downward line so that it heads up: y -> -y.
  const double sign = *f.heading == Side::Above ? 1.0 : -1.0;
  const double b = sign * f.slope;  // > 0
  const double d = sign * (*f.limit - f.mean_y);
  const double ts = f.t_quantile * f.residual_sd;
  const double c0 = 1 + 1 / static_cast<double>(n);
  const double u_last = f.last_x - f.mean_x;
  auto half_width = [&](double u) { return ts * std::sqrt(c0 + u * u / f.sxx); };
  const double g = (f.t_quantile * f.slope_se) * (f.t_quantile * f.slope_se);
  const double a = b * b - g;
  const double c = d * d - ts * ts * c0;
  const double quarter = g * d * d + a * ts * ts * c0;
  const std::vector<double> roots = quadratic_roots(a, -d * b, c, quarter);
  auto at = [&](double u) { return date_at(f.reference_ns, f.mean_x + u, f.last_x); };
  const LimitDate already{DateStatus::AlreadyBeyond, last_ns};

  // Near bound b u + half_width(u): convex, and it rises without end (its slope tends to
  // b + t se(b) > 0), so below the limit at the last point it meets the limit exactly once
  // after it. Every other root after the last point is the far bound's, which lies above the
  // near one, so the near bound's is the smallest root after u_last.
  if (b * u_last + half_width(u_last) >= d) {
    f.earliest = already;
  } else {
    auto after = std::find_if(roots.begin(), roots.end(), [&](double r) { return r > u_last; });
    f.earliest = after == roots.end() ? LimitDate{DateStatus::Never, std::nullopt} : at(*after);
  }
  // Far bound b u - half_width(u): it rises without end only when b > t se(b) (a > 0, a
  // trend); then it is increasing and meets the limit once, at the larger root.
  if (!(a > 0)) {
    f.latest = {DateStatus::Never, std::nullopt};
  } else if (b * u_last - half_width(u_last) >= d || roots.empty() || roots.back() <= u_last) {
    f.latest = already;
  } else {
    f.latest = at(roots.back());
  }
}

// The values at ranks (ascending; each < v.size()) of v in sorted order: successive
// std::nth_element calls, each on what lies above the previous rank (a rank right after the
// previous one is the minimum of that rest); v is reordered.
std::vector<double> select_ranks(std::vector<double>& v, const std::vector<std::size_t>& ranks) {
  std::vector<double> out;
  std::size_t from = 0;
  for (std::size_t rank : ranks) {
    const auto at = v.begin() + static_cast<std::ptrdiff_t>(rank);
    if (rank >= from) {
      const auto rest = v.begin() + static_cast<std::ptrdiff_t>(from);
      if (rank == from && from > 0) {
        std::iter_swap(at, std::min_element(rest, v.end()));
      } else {
        std::nth_element(rest, at, v.end());
      }
      from = rank + 1;
    }
    out.push_back(*at);
  }
  return out;
}

double median_of_sorted(const std::vector<double>& v) {
  const std::size_t m = v.size() / 2;
  return v.size() % 2 == 1 ? v[m] : (v[m - 1] + v[m]) / 2;
}

// Σ t(t-1)(2t+5) over the runs of equal values of a sorted vector: Sen's correction for ties.
double tie_term(const std::vector<double>& sorted) {
  double sum = 0;
  std::size_t i = 0;
  while (i < sorted.size()) {
    std::size_t j = i + 1;
    while (j < sorted.size() && sorted[j] == sorted[i]) ++j;
    const auto t = static_cast<double>(j - i);
    if (j - i > 1) sum += t * (t - 1) * (2 * t + 5);
    i = j;
  }
  return sum;
}

}  // namespace

std::string_view to_string(DateStatus status) {
  switch (status) {
    case DateStatus::Date: return "date";
    case DateStatus::AlreadyBeyond: return "already_beyond";
    case DateStatus::Never: return "never";
    case DateStatus::NoTrend: return "no_trend";
    case DateStatus::NoLimit: return "no_limit";
    case DateStatus::TooFar: return "too_far";
    case DateStatus::NotEnoughPoints: return "not_enough_points";
  }
  return "unknown";
}

namespace detail {

std::string check_band(const Band& band) {
  if (std::isnan(band.lower) || std::isnan(band.upper) || band.lower > band.upper ||
      band.lower == kInf || band.upper == -kInf) {
    return "invalid tolerance band";
  }
  return {};
}

std::string check_options(const ForecastOptions& options) {
  if (options.min_points < 3) return "a forecast needs min_points >= 3";
  if (!(options.confidence > 0 && options.confidence < 1)) {
    return "the confidence must be between 0 and 1";
  }
  return {};
}

std::vector<double> days_from_first(const Point* points, std::size_t count) {
  std::vector<double> x(count);
  for (std::size_t i = 0; i < count; ++i) x[i] = days_between(points[0].time_ns, points[i].time_ns);
  return x;
}

namespace {

// The fit's checks of options, band and count; false (with f.error set) when there is no fit.
bool start_fit(LinearForecast& f, std::size_t count, std::size_t skipped, const Band& band,
               const ForecastOptions& options) {
  f.points = count;
  f.skipped = skipped;
  f.error = check_options(options);
  if (f.error.empty()) f.error = check_band(band);
  if (f.error.empty() && count < options.min_points) {
    f.error = not_enough(count, options.min_points);
  }
  return f.error.empty();
}

// Everything after the moments (mean_x, mean_y, sxx, last_x, reference_ns set), from the slope's
// numerator Sxy and the residual sum of squares.
void finish_fit(LinearForecast& f, double sxy, double sse, std::int64_t last_ns, const Band& band,
                const ForecastOptions& options) {
  if (!(f.sxx > 0)) {
    f.error = "every point is at the same time: no slope";
    return;
  }
  const auto n = static_cast<double>(f.points);
  f.slope = sxy / f.sxx;
  f.intercept = f.mean_y - f.slope * f.mean_x;
  const double df = n - 2;
  f.residual_sd = std::sqrt(sse / df);
  f.slope_se = f.residual_sd / std::sqrt(f.sxx);
  f.intercept_se = f.residual_sd * std::sqrt(1 / n + f.mean_x * f.mean_x / f.sxx);
  f.t_quantile = detail::t_quantile(0.5 + 0.5 * options.confidence, df);
  f.slope_low = f.slope - f.t_quantile * f.slope_se;
  f.slope_high = f.slope + f.t_quantile * f.slope_se;
  f.trend = f.slope_low > 0 || f.slope_high < 0;
  heading_of(f.slope, band, f.heading, f.limit);
  f.expected =
      line_crossing(f.trend, f.heading, f.limit, f.intercept, f.slope, f.reference_ns, f.last_x);
  inverse_prediction(f, f.points, last_ns);
}

}  // namespace

LinearForecast fit_sorted(const Point* points, const double* x, std::size_t count,
                          std::size_t skipped, const Band& band, const ForecastOptions& options) {
  LinearForecast f;
  if (!start_fit(f, count, skipped, band, options)) return f;
  // x from the first point's time; y from the first value (so that a constant series has a
  // slope of exactly 0, and small drifts on a large offset keep their digits). Two passes for
  // the moments, a third for the residuals.
  f.reference_ns = points[0].time_ns;
  const double y0 = points[0].value;
  const auto n = static_cast<double>(count);
  double sum_x = 0, sum_dy = 0;
  for (std::size_t i = 0; i < count; ++i) {
    sum_x += x[i];
    sum_dy += points[i].value - y0;
  }
  f.mean_x = sum_x / n;
  const double mean_dy = sum_dy / n;
  f.mean_y = y0 + mean_dy;
  f.last_x = x[count - 1];
  double sxy = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const double dx = x[i] - f.mean_x;
    f.sxx += dx * dx;
    sxy += dx * ((points[i].value - y0) - mean_dy);
  }
  double sse = 0;
  if (f.sxx > 0) {
    const double slope = sxy / f.sxx;
    const double intercept = f.mean_y - slope * f.mean_x;
    for (std::size_t i = 0; i < count; ++i) {
      const double r = points[i].value - (intercept + slope * x[i]);
      sse += r * r;
    }
  }
  finish_fit(f, sxy, sse, points[count - 1].time_ns, band, options);
  return f;
}

std::vector<Moments> prefix_moments(const Point* points, const double* x, std::size_t count) {
  std::vector<Moments> out(count);
  Moments m;
  const double y0 = count > 0 ? points[0].value : 0;
  for (std::size_t i = 0; i < count; ++i) {
    // Welford's updates of the means and the co-moments (Welford 1962; Knuth TAOCP vol. 2,
    // 4.2.2): C_k = C_{k-1} + (x_k - mean_{k-1})(y_k - mean_k), stable without a second pass.
    const double k = static_cast<double>(i + 1);
    const double dy_value = points[i].value - y0;
    const double dx = x[i] - m.mean_x;
    const double dy = dy_value - m.mean_dy;
    m.mean_x += dx / k;
    m.mean_dy += dy / k;
    m.sxx += dx * (x[i] - m.mean_x);
    m.sxy += dx * (dy_value - m.mean_dy);
    m.syy += dy * (dy_value - m.mean_dy);
    out[i] = m;
  }
  return out;
}

LinearForecast fit_prefix(const Point* points, const double* x, std::size_t count, const Moments& m,
                          const Band& band, const ForecastOptions& options) {
  LinearForecast f;
  if (!start_fit(f, count, 0, band, options)) return f;
  f.reference_ns = points[0].time_ns;
  f.mean_x = m.mean_x;
  f.mean_y = points[0].value + m.mean_dy;
  f.sxx = m.sxx;
  f.last_x = x[count - 1];
  const double sse = f.sxx > 0 ? std::max(0.0, m.syy - m.sxy / f.sxx * m.sxy) : 0.0;
  finish_fit(f, m.sxy, sse, points[count - 1].time_ns, band, options);
  return f;
}

}  // namespace detail

double LinearForecast::value_at(std::int64_t time_ns) const {
  return intercept + slope * days_between(reference_ns, time_ns);
}

LinearForecast linear_forecast(const std::vector<Point>& points, const Band& band,
                               const ForecastOptions& options) {
  const Series s = finite_points(points);
  const std::vector<double> x = detail::days_from_first(s.points.data(), s.points.size());
  return detail::fit_sorted(s.points.data(), x.data(), s.points.size(), s.skipped, band, options);
}

Interval prediction_interval(const LinearForecast& fit, std::int64_t time_ns) {
  Interval out;
  if (!fit.ok()) {
    out.fitted = out.lower = out.upper = std::numeric_limits<double>::quiet_NaN();
    return out;
  }
  const double x = days_between(fit.reference_ns, time_ns);
  const double u = x - fit.mean_x;
  const double half = fit.t_quantile * fit.residual_sd *
                      std::sqrt(1 + 1 / static_cast<double>(fit.points) + u * u / fit.sxx);
  out.fitted = fit.intercept + fit.slope * x;
  out.lower = out.fitted - half;
  out.upper = out.fitted + half;
  return out;
}

TheilSen theil_sen(const std::vector<Point>& points, const Band& band,
                   const ForecastOptions& options) {
  TheilSen r;
  const Series s = finite_points(points);
  r.points = s.points.size();
  r.skipped = s.skipped;
  r.error = detail::check_options(options);
  if (r.error.empty()) r.error = detail::check_band(band);
  if (r.error.empty() && r.points < options.min_points) {
    r.error = not_enough(r.points, options.min_points);
  }
  if (!r.error.empty()) return r;

  const std::size_t n = r.points;
  r.reference_ns = s.points.front().time_ns;
  std::vector<double> x(n), y(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = days_between(r.reference_ns, s.points[i].time_ns);
    y[i] = s.points[i].value;
  }
  r.last_x = x.back();
  std::vector<double> slopes;
  slopes.reserve(n * (n - 1) / 2);
  for (std::size_t j = 1; j < n; ++j) {
    for (std::size_t i = 0; i < j; ++i) {
      if (x[j] > x[i]) slopes.push_back((y[j] - y[i]) / (x[j] - x[i]));
    }
  }
  if (slopes.empty()) {
    r.error = "every point is at the same time: no slope";
    return r;
  }
  const std::size_t count = slopes.size();
  const auto nd = static_cast<double>(n);
  // Sen (1968) eq. 2.6, in scipy's order of operations (1/18 * ...), so that the rounding of
  // the ranks agrees with it exactly.
  std::vector<double> sorted_y = y;
  std::sort(sorted_y.begin(), sorted_y.end());
  const double variance =
      1 / 18. * (nd * (nd - 1) * (2 * nd + 5) - tie_term(x) - tie_term(sorted_y));
  const double z = detail::normal_quantile((1 - options.confidence) / 2);
  const double sigma = std::sqrt(variance);
  const auto nt = static_cast<double>(count);
  const auto last = static_cast<double>(count - 1);
  const double high_rank = std::min(std::nearbyint((nt - z * sigma) / 2.), last);
  const double low_rank = std::max(std::nearbyint((nt + z * sigma) / 2.) - 1, 0.0);
  // The order statistics needed: low, the median's one or two, high (ascending ranks).
  const std::size_t mid = count / 2;
  const auto low_index = static_cast<std::size_t>(low_rank);
  const auto high_index = static_cast<std::size_t>(high_rank);
  std::vector<std::size_t> ranks{low_index, count % 2 == 0 ? mid - 1 : mid, mid, high_index};
  std::sort(ranks.begin(), ranks.end());
  const std::vector<double> values = select_ranks(slopes, ranks);
  auto at = [&](std::size_t rank) {
    return values[static_cast<std::size_t>(std::find(ranks.begin(), ranks.end(), rank) -
                                           ranks.begin())];
  };
  r.slope = count % 2 == 1 ? at(mid) : (at(mid - 1) + at(mid)) / 2;
  r.slope_low = at(low_index);
  r.slope_high = at(high_index);
  // x is sorted already (the points are).
  r.intercept = median_of_sorted(sorted_y) - r.slope * median_of_sorted(x);
  r.trend = r.slope_low > 0 || r.slope_high < 0;
  heading_of(r.slope, band, r.heading, r.limit);
  r.expected =
      line_crossing(r.trend, r.heading, r.limit, r.intercept, r.slope, r.reference_ns, r.last_x);
  return r;
}

}  // namespace ncqual::trend

// SPDX-License-Identifier: Apache-2.0
#include "ncqual/trend/spc.hpp"

#include "quantiles.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace ncqual::trend {

namespace {

// Indices of the finite entries of values.
std::vector<std::size_t> finite_indices(const std::vector<double>& values) {
  std::vector<std::size_t> indices;
  indices.reserve(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (std::isfinite(values[i])) indices.push_back(i);
  }
  return indices;
}

struct Spread {
  double mean = 0;
  double mean_moving_range = 0;
  double sd = 0;  // sample standard deviation (n - 1); 0 for one value
};

// Mean, mean moving range and sample standard deviation of finite values: two passes over the
// values less the first one, so that equal values give a standard deviation of exactly 0.
Spread spread_of(const std::vector<double>& x) {
  Spread s;
  const auto n = static_cast<double>(x.size());
  if (x.empty()) return s;
  const double x0 = x.front();
  double sum = 0;
  for (double v : x) sum += v - x0;
  const double mean_offset = sum / n;
  s.mean = x0 + mean_offset;
  double squares = 0;
  for (double v : x) squares += ((v - x0) - mean_offset) * ((v - x0) - mean_offset);
  if (x.size() > 1) {
    s.sd = std::sqrt(squares / (n - 1));
    double ranges = 0;
    for (std::size_t i = 1; i < x.size(); ++i) ranges += std::abs(x[i] - x[i - 1]);
    s.mean_moving_range = ranges / (n - 1);
  }
  return s;
}

std::string not_enough(std::size_t have, std::size_t need) {
  return "not enough points: " + std::to_string(have) + " of " + std::to_string(need);
}

}  // namespace

Baseline baseline(const std::vector<double>& values, std::size_t points) {
  Baseline b;
  if (points < kMinBaselinePoints) {
    b.error = "a baseline needs at least " + std::to_string(kMinBaselinePoints) + " points, " +
              std::to_string(points) + " asked for";
    return b;
  }
  std::vector<double> first;
  first.reserve(points);
  for (double v : values) {
    if (first.size() == points) break;
    if (std::isfinite(v)) first.push_back(v);
  }
  b.points = first.size();
  if (first.size() < points) {
    b.error = not_enough(first.size(), points);
    return b;
  }
  const Spread s = spread_of(first);
  b.mean = s.mean;
  b.mean_moving_range = s.mean_moving_range;
  b.sigma_within = s.mean_moving_range / kD2;
  b.sigma_overall = s.sd;
  b.upper_control_limit = b.mean + 3 * b.sigma_within;
  b.lower_control_limit = b.mean - 3 * b.sigma_within;
  if (!(b.sigma_within > 0) || !std::isfinite(b.sigma_within)) {
    b.error = "the baseline has no variation (every moving range is 0): no control limits";
  }
  return b;
}

std::vector<RuleSignal> western_electric(const std::vector<double>& values, const Baseline& base,
                                         std::optional<Side> only) {
  std::vector<RuleSignal> signals;
  if (!base.ok()) return signals;
  const std::vector<std::size_t> at = finite_indices(values);
  // z-scores of the finite values, and for each rule the window and count it needs.
  std::vector<double> z(at.size());
  for (std::size_t j = 0; j < at.size(); ++j) {
    z[j] = (values[at[j]] - base.mean) / base.sigma_within;
  }
  struct Rule {
    int number;
    std::size_t window;
    std::size_t needed;
    double beyond;  // |z| > beyond, on the same side
  };
  // Rule 4 ("8 in a row on one side of the centre") is 8 of 8 beyond 0.
  constexpr std::array<Rule, 4> kRules{
      {{1, 1, 1, 3.0}, {2, 3, 2, 2.0}, {3, 5, 4, 1.0}, {4, 8, 8, 0.0}}};
  for (std::size_t j = 0; j < z.size(); ++j) {
    for (const Rule& rule : kRules) {
      if (j + 1 < rule.window) continue;
      std::size_t above = 0, below = 0;
      for (std::size_t w = j + 1 - rule.window; w <= j; ++w) {
        if (z[w] > rule.beyond) ++above;
        if (z[w] < -rule.beyond) ++below;
      }
      if (above >= rule.needed && only != Side::Below) {
        signals.push_back({rule.number, at[j], Side::Above});
      } else if (below >= rule.needed && only != Side::Above) {
        signals.push_back({rule.number, at[j], Side::Below});
      }
    }
  }
  return signals;
}

std::optional<RuleSignal> first_signal(const std::vector<RuleSignal>& signals, int rule) {
  for (const RuleSignal& s : signals) {
    if (s.rule == rule) return s;
  }
  return std::nullopt;
}

std::optional<Side> Ewma::signal_at(std::size_t index) const {
  if (index >= z.size()) return std::nullopt;
  if (z[index] > upper_limit[index]) return Side::Above;
  if (z[index] < lower_limit[index]) return Side::Below;
  return std::nullopt;
}

Ewma ewma(const std::vector<double>& values, double centre, double sigma, double lambda,
          double width) {
  Ewma e;
  e.lambda = lambda;
  e.width = width;
  e.centre = centre;
  e.sigma = sigma;
  if (!(lambda > 0 && lambda <= 1) || !(width > 0) || !std::isfinite(width)) {
    e.error = "EWMA needs 0 < lambda <= 1 and L > 0";
    return e;
  }
  if (!(sigma > 0) || !std::isfinite(sigma) || !std::isfinite(centre)) {
    e.error = "EWMA needs a finite centre and a sigma > 0";
    return e;
  }
  e.z.resize(values.size());
  e.lower_limit.resize(values.size());
  e.upper_limit.resize(values.size());
  const double asymptote = lambda / (2 - lambda);
  double z = centre, half = 0;
  double decay = 1;  // (1 - lambda)^(2i)
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (std::isfinite(values[i])) {
      z = lambda * values[i] + (1 - lambda) * z;
      decay *= (1 - lambda) * (1 - lambda);
      half = width * sigma * std::sqrt(asymptote * (1 - decay));
    }
    e.z[i] = z;
    e.lower_limit[i] = centre - half;
    e.upper_limit[i] = centre + half;
    if (!e.first_signal && std::isfinite(values[i])) {
      if (auto side = e.signal_at(i)) {
        e.first_signal = i;
        e.first_side = *side;
      }
    }
  }
  return e;
}

double Cusum::estimated_mean(std::size_t index, Side side) const {
  if (index >= upper.size()) return centre;
  if (side == Side::Above) {
    if (upper_count[index] == 0) return centre;
    return centre + k + upper[index] / static_cast<double>(upper_count[index]);
  }
  if (lower_count[index] == 0) return centre;
  return centre - k - lower[index] / static_cast<double>(lower_count[index]);
}

Cusum cusum(const std::vector<double>& values, double centre, double sigma, double k, double h) {
  Cusum c;
  c.centre = centre;
  c.sigma = sigma;
  c.k = k * sigma;
  c.h = h * sigma;
  if (!(k >= 0) || !std::isfinite(k) || !(h > 0) || !std::isfinite(h)) {
    c.error = "CUSUM needs k >= 0 and h > 0";
    return c;
  }
  if (!(sigma > 0) || !std::isfinite(sigma) || !std::isfinite(centre)) {
    c.error = "CUSUM needs a finite centre and a sigma > 0";
    return c;
  }
  const std::size_t n = values.size();
  c.upper.resize(n);
  c.lower.resize(n);
  c.upper_count.resize(n);
  c.lower_count.resize(n);
  double up = 0, down = 0;
  std::size_t up_count = 0, down_count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = values[i];
    if (std::isfinite(x)) {
      up = std::max(0.0, x - (centre + c.k) + up);
      down = std::max(0.0, (centre - c.k) - x + down);
      up_count = up > 0 ? up_count + 1 : 0;
      down_count = down > 0 ? down_count + 1 : 0;
    }
    c.upper[i] = up;
    c.lower[i] = down;
    c.upper_count[i] = up_count;
    c.lower_count[i] = down_count;
    if (!std::isfinite(x)) continue;
    if (!c.first_up && up > c.h) {
      c.first_up = i;
      c.mean_at_first_up = c.estimated_mean(i, Side::Above);
    }
    if (!c.first_down && down > c.h) {
      c.first_down = i;
      c.mean_at_first_down = c.estimated_mean(i, Side::Below);
    }
  }
  return c;
}

Capability capability(const std::vector<double>& values, const Band& band, std::size_t min_points) {
  Capability c;
  if (std::isnan(band.lower) || std::isnan(band.upper) || band.lower > band.upper ||
      band.lower == std::numeric_limits<double>::infinity() ||
      band.upper == -std::numeric_limits<double>::infinity()) {
    c.error = "invalid tolerance band";
    return c;
  }
  std::vector<double> x;
  x.reserve(values.size());
  for (double v : values) {
    if (std::isfinite(v)) x.push_back(v);
  }
  c.points = x.size();
  const std::size_t need = std::max<std::size_t>(min_points, 2);
  if (x.size() < need) {
    c.error = not_enough(x.size(), need);
    return c;
  }
  const Spread s = spread_of(x);
  c.mean = s.mean;
  c.sigma_within = s.mean_moving_range / kD2;
  c.sigma_overall = s.sd;
  const bool has_lower = std::isfinite(band.lower);
  const bool has_upper = std::isfinite(band.upper);
  auto ratios = [&](double sigma, std::optional<double>& whole, std::optional<double>& k,
                    std::optional<double>& upper, std::optional<double>& lower) {
    if (!(sigma > 0)) return;
    if (has_upper) upper = (band.upper - c.mean) / (3 * sigma);
    if (has_lower) lower = (c.mean - band.lower) / (3 * sigma);
    if (has_upper && has_lower) {
      whole = (band.upper - band.lower) / (6 * sigma);
      k = std::min(*upper, *lower);
    } else if (upper) {
      k = upper;
    } else if (lower) {
      k = lower;
    }
  };
  ratios(c.sigma_within, c.cp, c.cpk, c.cpu, c.cpl);
  ratios(c.sigma_overall, c.pp, c.ppk, c.ppu, c.ppl);
  return c;
}

PassRate pass_rate(const VerdictCounts& counts, double confidence) {
  PassRate r;
  r.judged = counts.pass + counts.fail;
  if (r.judged == 0 || !(confidence > 0 && confidence < 1)) return r;
  const auto n = static_cast<double>(r.judged);
  const double p = static_cast<double>(counts.pass) / n;
  const double z = detail::normal_quantile(0.5 + 0.5 * confidence);
  // Wilson's score interval, in Newcombe's (1998) arrangement.
  const double denominator = 2 * (n + z * z);
  const double centre = (2 * n * p + z * z) / denominator;
  const double half = z / denominator * std::sqrt(4 * n * p * (1 - p) + z * z);
  r.rate = p;
  r.lower = counts.pass == 0 ? 0.0 : centre - half;
  r.upper = counts.pass == r.judged ? 1.0 : centre + half;
  return r;
}

}  // namespace ncqual::trend

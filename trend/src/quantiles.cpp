// SPDX-License-Identifier: Apache-2.0
#include "quantiles.hpp"

#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>

#include <array>
#include <atomic>
#include <cmath>
#include <limits>

namespace ncqual::trend::detail {

namespace {

double compute_t_quantile(double p, double df) {
  const boost::math::students_t_distribution<double> t(df);
  return boost::math::quantile(t, p);
}

// Filled on first use per entry; 0 means not computed yet (no t quantile at p = 0.975 is 0).
// Two threads computing the same entry store the same value, so relaxed ordering is enough.
constexpr int kMemoized = 1024;
std::array<std::atomic<double>, kMemoized + 1> memo_975{};

}  // namespace

double t_quantile(double p, double df) {
  if (p == 0.975 && df >= 1 && df <= kMemoized && df == std::floor(df)) {
    auto& slot = memo_975[static_cast<std::size_t>(df)];
    double value = slot.load(std::memory_order_relaxed);
    if (value == 0) {
      value = compute_t_quantile(p, df);
      slot.store(value, std::memory_order_relaxed);
    }
    return value;
  }
  return compute_t_quantile(p, df);
}

double normal_quantile(double p) {
  const boost::math::normal_distribution<double> normal;
  return boost::math::quantile(normal, p);
}

}  // namespace ncqual::trend::detail

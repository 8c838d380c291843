// SPDX-License-Identifier: Apache-2.0
// Shared by the solver's checks' tests: the bookkeeping of the seeded end-to-end tests against the
// simulator's ground truth, the spread of their standardised errors, and corrupting a measurement
// set the way the "random garbage" tests do.
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/common/model.hpp"
#include "test_machines.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <random>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace ncqual::testing {

// The spread of standardised errors ((measured - truth) / sigma), to compare with standard
// normals': their rms (1 for standard normals) and how many lie beyond 3 (0.27 % of them).
struct NoiseSpread {
  double n = 0;  // how many errors
  double rms = 0;
  int beyond_3 = 0;
};

inline NoiseSpread noise_spread(const std::vector<double>& standardised) {
  double sum_sq = 0;
  int beyond_3 = 0;
  for (double z : standardised) {
    sum_sq += z * z;
    beyond_3 += std::abs(z) > 3 ? 1 : 0;
  }
  const double n = static_cast<double>(standardised.size());
  return {n, std::sqrt(sum_sq / n), beyond_3};
}

// A metric the check must recover: its true value and the standard deviation of the trigger
// noise in it.
struct Expectation {
  std::string_view name;
  double truth;
  double sigma;
};

// Shared bookkeeping of the seeded end-to-end tests: each metric within 5 sigma per case (with
// hundreds of comparisons a 3 sigma bound would be exceeded by chance), the 3 sigma statistics
// over the whole sample, verdicts where the truth is clearly in or out of the band, and the
// first cause on failure.
class GroundTruthTally {
 public:
  explicit GroundTruthTally(std::string first_cause) : first_cause_(std::move(first_cause)) {}

  void check(const CheckResult& result, const MachineConfig& m,
             const std::vector<Expectation>& expectations, int i) {
    ASSERT_NE(result.verdict, Verdict::Invalid) << "case " << i << ": " << result.reason;
    constexpr double k = 5;
    bool must_fail = false, must_pass = true;
    for (const auto& e : expectations) {
      const Metric& mt = metric(result, e.name);
      EXPECT_NEAR(mt.value, e.truth, k * e.sigma) << e.name << " case " << i;
      standardised_.push_back((mt.value - e.truth) / e.sigma);
      const Tolerance& band = m.tolerances.at(std::string(e.name));
      EXPECT_EQ(mt.pass, band.contains(mt.value)) << e.name;
      const double margin = k * e.sigma;
      if (e.truth > band.upper + margin || e.truth < band.lower - margin) must_fail = true;
      if (e.truth > band.upper - margin || e.truth < band.lower + margin) must_pass = false;
    }
    if (must_fail) {
      EXPECT_EQ(result.verdict, Verdict::Fail) << "case " << i;
    }
    if (must_pass) {
      EXPECT_EQ(result.verdict, Verdict::Pass) << "case " << i << ": " << result.reason;
    }
    if (result.verdict == Verdict::Fail) {
      ++fails_;
      ASSERT_FALSE(result.likely_causes.empty());
      EXPECT_EQ(result.likely_causes[0], first_cause_);
      EXPECT_FALSE(result.reason.empty());
    } else {
      ++passes_;
      EXPECT_TRUE(result.likely_causes.empty());
    }
  }

  int passes() const { return passes_; }
  int fails() const { return fails_; }
  NoiseSpread spread() const { return noise_spread(standardised_); }

  // Both verdicts seen more than 20 times, and the errors the trigger noise and nothing else:
  // standard normal after scaling.
  void expect_noise_statistics() const {
    EXPECT_GT(passes_, 20);
    EXPECT_GT(fails_, 20);
    const NoiseSpread s = spread();
    // The rms of n standard normals has a standard error of about 1/sqrt(2n).
    EXPECT_NEAR(s.rms, 1.0, 5 / std::sqrt(2 * s.n));
    // P(|z| > 3) = 0.0027.
    EXPECT_LE(s.beyond_3, 0.0027 * s.n + 5 * std::sqrt(0.0027 * s.n) + 1);
  }

 private:
  std::string first_cause_;
  std::vector<double> standardised_;
  int passes_ = 0, fails_ = 0;
};

// Sets one field of one touch of `set` to `value`, both drawn with `rng` (first the touch, then
// its readout x, y, z, w, a or c or a component of its approach direction): the corruption of
// the "random garbage" tests.
inline void spoil_random_field(MeasurementSet& set, std::mt19937_64& rng, double value) {
  Touch& t =
      set.touches[std::uniform_int_distribution<std::size_t>(0, set.touches.size() - 1)(rng)];
  double* fields[] = {&t.axes.x_mm,    &t.axes.y_mm,    &t.axes.z_mm,
                      &t.axes.w_mm,    &t.axes.a_rad,   &t.axes.c_rad,
                      &t.approach.x(), &t.approach.y(), &t.approach.z()};
  *fields[std::uniform_int_distribution<int>(0, 8)(rng)] = value;
}

}  // namespace ncqual::testing

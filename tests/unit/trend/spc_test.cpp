// SPDX-License-Identifier: Apache-2.0
// SPC of one metric, on data sets worked by hand (in the comments) and on Montgomery's textbook
// data set for the CUSUM and EWMA charts.
#include "ncqual/trend/spc.hpp"
#include "trend_test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace ncqual::trend {
namespace {

using namespace testing;  // trend_test_support.hpp

// A baseline of 10 values alternating +0.564, -0.564: mean exactly 0, every moving range 1.128,
// so sigma_within = 1.128 / d2 = 1 exactly and the rules' thresholds are 1, 2, 3.
std::vector<double> unit_baseline() {
  std::vector<double> v;
  for (int i = 0; i < 10; ++i) v.push_back(i % 2 == 0 ? 0.564 : -0.564);
  return v;
}

std::vector<double> with(std::vector<double> v, std::initializer_list<double> more) {
  v.insert(v.end(), more);
  return v;
}

std::vector<std::size_t> indices_of(const std::vector<RuleSignal>& s, int rule) {
  std::vector<std::size_t> out;
  for (const RuleSignal& r : s) {
    if (r.rule == rule) out.push_back(r.index);
  }
  return out;
}

TEST(Spc, BaselineByHand) {
  // x = 2, 4, 3, 5, 6: mean 20/5 = 4; moving ranges 2, 1, 2, 1, MR-bar = 1.5,
  // sigma_within = 1.5 / 1.128 = 1.3297872; deviations -2, 0, -1, 1, 2, squares sum 10,
  // s = sqrt(10 / 4) = 1.5811388; limits 4 ± 3 * 1.3297872 = 0.0106383, 7.9893617.
  const Baseline b = baseline({2, 4, 3, 5, 6, 100}, 5);
  ASSERT_TRUE(b.ok()) << b.error;
  EXPECT_EQ(b.points, 5u);
  EXPECT_DOUBLE_EQ(b.mean, 4.0);
  EXPECT_DOUBLE_EQ(b.mean_moving_range, 1.5);
  EXPECT_NEAR(b.sigma_within, 1.3297872, 1e-7);
  EXPECT_NEAR(b.sigma_overall, 1.5811388, 1e-7);
  EXPECT_NEAR(b.upper_control_limit, 7.9893617, 1e-7);
  EXPECT_NEAR(b.lower_control_limit, 0.0106383, 1e-7);
}

TEST(Spc, BaselineSkipsNaNAndRefusesWhatItCannotEstimate) {
  const Baseline b = baseline({2, kNaN, 4, 3, kInf, 5, 6}, 5);
  ASSERT_TRUE(b.ok()) << b.error;
  EXPECT_DOUBLE_EQ(b.mean, 4.0);
  EXPECT_DOUBLE_EQ(b.mean_moving_range, 1.5);

  EXPECT_EQ(baseline({1, 2, 3, 4, 5, 6, 7}, 10).error, "not enough points: 7 of 10");
  EXPECT_FALSE(baseline({1, 2, 3, 4}, 4).ok());  // fewer than kMinBaselinePoints asked for
  const Baseline flat = baseline({3, 3, 3, 3, 3}, 5);
  EXPECT_FALSE(flat.ok());
  EXPECT_NE(flat.error.find("no variation"), std::string::npos);
  EXPECT_TRUE(western_electric({3, 3, 3, 3, 3, 9}, flat).empty());
}

TEST(Spc, UnitBaselineIsExact) {
  const Baseline b = baseline(unit_baseline());
  ASSERT_TRUE(b.ok());
  EXPECT_EQ(b.mean, 0.0);
  EXPECT_EQ(b.sigma_within, 1.0);
}

TEST(Spc, Rule1FiresBeyondThreeSigmaAndNotBefore) {
  const Baseline b = baseline(unit_baseline());
  // Index 10 at 2.9 sigma: not rule 1; index 11 at 3.1: rule 1, above. Index 12 at -3.2: below.
  const auto s = western_electric(with(unit_baseline(), {2.9, 3.1, -3.2}), b);
  EXPECT_EQ(indices_of(s, 1), (std::vector<std::size_t>{11, 12}));
  EXPECT_EQ(first_signal(s, 1)->side, Side::Above);
  const RuleSignal last_rule_1 =
      *std::find_if(s.rbegin(), s.rend(), [](auto& r) { return r.rule == 1; });
  EXPECT_EQ(last_rule_1.index, 12u);
  EXPECT_EQ(last_rule_1.side, Side::Below);
}

TEST(Spc, Rule2FiresOnTwoOfThreeBeyondTwoSigma) {
  const Baseline b = baseline(unit_baseline());
  // Index 9 is -0.564. Windows: at 11 {-0.564, 2.5, 0}: one beyond 2 sigma; at 12 {2.5, 0, 2.5}:
  // two, same side: rule 2 fires at 12 (and at 13, whose window {0, 2.5, 0} has only one: no).
  const auto s = western_electric(with(unit_baseline(), {2.5, 0.0, 2.5, 0.0}), b);
  EXPECT_EQ(indices_of(s, 2), (std::vector<std::size_t>{12}));
  EXPECT_TRUE(indices_of(s, 1).empty());
  EXPECT_TRUE(indices_of(s, 3).empty());
  // Two beyond 2 sigma on opposite sides is not rule 2.
  EXPECT_TRUE(indices_of(western_electric(with(unit_baseline(), {2.5, 0.0, -2.5}), b), 2).empty());
}

TEST(Spc, Rule3FiresOnFourOfFiveBeyondOneSigma) {
  const Baseline b = baseline(unit_baseline());
  // Indices 10..14 = 1.5, 1.5, 0.2, 1.5, 1.5. At 13 the window 9..13 {-0.564, 1.5, 1.5, 0.2,
  // 1.5} has three beyond 1 sigma; at 14 the window 10..14 has four: rule 3 fires at 14.
  const auto s = western_electric(with(unit_baseline(), {1.5, 1.5, 0.2, 1.5, 1.5}), b);
  EXPECT_EQ(indices_of(s, 3), (std::vector<std::size_t>{14}));
  EXPECT_TRUE(indices_of(s, 2).empty());
  EXPECT_TRUE(indices_of(s, 4).empty());
}

TEST(Spc, Rule4FiresOnEightInARowOnOneSide) {
  const Baseline b = baseline(unit_baseline());
  // Indices 10..17 = -0.5. Index 9 (-0.564) is below the centre too, so the window 9..16 is 8
  // below: rule 4 fires at 16; at 15 the window 8..15 starts with index 8 (+0.564): no.
  const auto below =
      western_electric(with(unit_baseline(), {-0.5, -0.5, -0.5, -0.5, -0.5, -0.5, -0.5, -0.5}), b);
  EXPECT_EQ(first_signal(below, 4)->index, 16u);
  EXPECT_EQ(first_signal(below, 4)->side, Side::Below);
  // Above: index 9 is below the centre, so the run of 8 above ends at 17 and not at 16.
  const auto above =
      western_electric(with(unit_baseline(), {0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5}), b);
  EXPECT_EQ(indices_of(above, 4), (std::vector<std::size_t>{17}));
  EXPECT_TRUE(indices_of(above, 3).empty());  // 0.5 is within 1 sigma
  // A point on the centre line breaks a run.
  const auto broken =
      western_electric(with(unit_baseline(), {0.5, 0.5, 0.5, 0.0, 0.5, 0.5, 0.5, 0.5}), b);
  EXPECT_TRUE(indices_of(broken, 4).empty());
}

TEST(Spc, RulesSkipNaNAndKeepTheCallersIndices) {
  const Baseline b = baseline(unit_baseline());
  // A NaN at index 13 inside a run of 0.5: the run of 8 finite values above ends at index 18.
  const auto s =
      western_electric(with(unit_baseline(), {0.5, 0.5, 0.5, kNaN, 0.5, 0.5, 0.5, 0.5, 0.5}), b);
  EXPECT_EQ(indices_of(s, 4), (std::vector<std::size_t>{18}));
}

// D. C. Montgomery, Introduction to Statistical Quality Control, Table 9.1: 30 individual
// observations, the first 20 from N(10, 1), the last 10 from N(11, 1) (the same data as IMSL's
// EWMA example, which cites Montgomery p. 428).
const std::vector<double> kMontgomery{9.45,  7.99,  9.29,  11.66, 12.16, 10.18, 8.04,  11.46,
                                      9.20,  10.34, 9.03,  11.47, 10.51, 9.40,  10.08, 9.37,
                                      10.62, 10.31, 8.52,  10.84, 10.90, 9.33,  12.29, 11.50,
                                      10.60, 11.08, 10.38, 11.62, 11.31, 10.52};

TEST(Spc, CusumMontgomeryExample91) {
  // Example 9.1: mu0 = 10, sigma = 1, K = 0.5, H = 5. By hand: C+_1 = max(0, 9.45 - 10.5) = 0,
  // C-_1 = max(0, 9.5 - 9.45) = 0.05, C-_2 = max(0, 9.5 - 7.99 + 0.05) = 1.56. The textbook's
  // table ends C+_28 = 4.47 (N+ = 6), C+_29 = 5.28 > H (N+ = 7): the chart signals at period 29,
  // the shift began after period 22, and the new mean is estimated at
  // 10 + 0.5 + 5.28 / 7 = 11.25. C- never exceeds H.
  const Cusum c = cusum(kMontgomery, 10.0, 1.0, 0.5, 5.0);
  ASSERT_TRUE(c.ok());
  EXPECT_DOUBLE_EQ(c.k, 0.5);
  EXPECT_DOUBLE_EQ(c.h, 5.0);
  EXPECT_EQ(c.upper[0], 0.0);
  EXPECT_NEAR(c.lower[0], 0.05, 1e-12);
  EXPECT_NEAR(c.lower[1], 1.56, 1e-12);
  EXPECT_NEAR(c.upper[27], 4.47, 1e-9);
  EXPECT_EQ(c.upper_count[27], 6u);
  ASSERT_TRUE(c.first_up.has_value());
  EXPECT_EQ(*c.first_up, 28u);  // period 29
  EXPECT_NEAR(c.upper[28], 5.28, 1e-9);
  EXPECT_EQ(c.upper_count[28], 7u);
  EXPECT_NEAR(*c.mean_at_first_up, 11.254285714, 1e-8);
  EXPECT_FALSE(c.first_down.has_value());
}

TEST(Spc, CusumScalesWithSigmaAndSkipsNaN) {
  // The same data in units of 0.001 around 0: the same signal.
  std::vector<double> scaled;
  for (double v : kMontgomery) scaled.push_back((v - 10) * 0.001);
  scaled.insert(scaled.begin() + 5, kNaN);
  const Cusum c = cusum(scaled, 0.0, 0.001);
  ASSERT_TRUE(c.ok());
  EXPECT_EQ(*c.first_up, 29u);  // one later: the NaN at index 5
  EXPECT_EQ(c.upper[5], c.upper[4]);
  EXPECT_FALSE(cusum(scaled, 0.0, 0.0).ok());
  EXPECT_FALSE(cusum(scaled, 0.0, 0.001, 0.5, 0.0).ok());
}

TEST(Spc, EwmaMontgomeryData) {
  // Montgomery's Example 9.2 chart: lambda = 0.1, L = 2.7 on the data of Table 9.1, mu0 = 10,
  // sigma = 1. By hand: z_1 = 0.1 * 9.45 + 0.9 * 10 = 9.945, its limit 10 + 2.7 sqrt(0.1 / 1.9 *
  // (1 - 0.9^2)) = 10 + 2.7 * 0.1 = 10.27; z_2 = 0.799 + 0.9 * 9.945 = 9.7495. Further on,
  // z_28 = 0.1 * 11.62 + 0.9 * z_27 (10.4568) = 10.5731, below its limit
  // 10 + 2.7 sqrt(0.1/1.9 (1 - 0.9^56)) = 10.6186; z_29 = 1.131 + 0.9 * 10.5731 = 10.6468, above
  // 10.6187: the first signal is period 29.
  const Ewma e = ewma(kMontgomery, 10.0, 1.0, 0.1, 2.7);
  ASSERT_TRUE(e.ok());
  EXPECT_NEAR(e.z[0], 9.945, 1e-12);
  EXPECT_NEAR(e.upper_limit[0], 10.27, 1e-12);
  EXPECT_NEAR(e.lower_limit[0], 9.73, 1e-12);
  EXPECT_NEAR(e.z[1], 9.7495, 1e-12);
  EXPECT_NEAR(e.z[27], 10.5731, 1e-4);
  EXPECT_NEAR(e.upper_limit[27], 10.6186, 1e-4);
  EXPECT_NEAR(e.z[28], 10.6468, 1e-4);
  EXPECT_NEAR(e.upper_limit[28], 10.6187, 1e-4);
  ASSERT_TRUE(e.first_signal.has_value());
  EXPECT_EQ(*e.first_signal, 28u);
  EXPECT_EQ(e.first_side, Side::Above);
  EXPECT_FALSE(e.signal_at(27).has_value());
  // The limits widen to the asymptote 10 + 2.7 sqrt(0.1 / 1.9) = 10.61942.
  EXPECT_LT(e.upper_limit[29], 10.61942);
  EXPECT_GT(e.upper_limit[29], e.upper_limit[0]);
  EXPECT_FALSE(ewma(kMontgomery, 10.0, 1.0, 0.0, 3).ok());
  EXPECT_FALSE(ewma(kMontgomery, 10.0, 0.0).ok());
}

TEST(Spc, CapabilityByHand) {
  // x = 2, 4, 3, 5, 6 against [-2, 11]: mean 4, sigma_within = 1.5 / 1.128, s = sqrt(2.5).
  //   Cp  = 13 / (6 * 1.5 / 1.128) = 14.664 / 9 = 1.6293333   Cpu = 7 * 1.128 / 4.5 = 1.7546667
  //   Cpl = 6 * 1.128 / 4.5 = 1.504, Cpk = min = 1.504
  //   Pp  = 13 / (6 sqrt(2.5)) = 1.3703203  Ppu = 7 / (3 sqrt(2.5)) = 1.4757296
  //   Ppl = 6 / (3 sqrt(2.5)) = 1.2649111   Ppk = 1.2649111
  const Capability c = capability({2, 4, 3, 5, 6}, {-2, 11});
  ASSERT_TRUE(c.ok()) << c.error;
  EXPECT_NEAR(*c.cp, 1.6293333, 1e-7);
  EXPECT_NEAR(*c.cpu, 1.7546667, 1e-7);
  EXPECT_NEAR(*c.cpl, 1.504, 1e-12);
  EXPECT_NEAR(*c.cpk, 1.504, 1e-12);
  EXPECT_NEAR(*c.pp, 1.3703203, 1e-7);
  EXPECT_NEAR(*c.ppu, 1.4757296, 1e-7);
  EXPECT_NEAR(*c.ppl, 1.2649111, 1e-7);
  EXPECT_NEAR(*c.ppk, 1.2649111, 1e-7);
}

TEST(Spc, OneSidedCapability) {
  // Upper limit only (e.g. a flatness): Cpu = 7 * 1.128 / 4.5, no Cp, no Cpl; Cpk = Cpu.
  const Capability up = capability({2, 4, 3, 5, 6}, {-kInf, 11});
  ASSERT_TRUE(up.ok());
  EXPECT_FALSE(up.cp.has_value());
  EXPECT_FALSE(up.pp.has_value());
  EXPECT_FALSE(up.cpl.has_value());
  EXPECT_NEAR(*up.cpu, 1.7546667, 1e-7);
  EXPECT_EQ(*up.cpk, *up.cpu);
  EXPECT_EQ(*up.ppk, *up.ppu);
  // Lower limit only.
  const Capability low = capability({2, 4, 3, 5, 6}, {-2, kInf});
  EXPECT_FALSE(low.cp.has_value());
  EXPECT_FALSE(low.cpu.has_value());
  EXPECT_NEAR(*low.cpl, 1.504, 1e-12);
  EXPECT_EQ(*low.cpk, *low.cpl);
  // No limit at all: nothing to compare with.
  const Capability none = capability({2, 4, 3, 5, 6}, {});
  EXPECT_TRUE(none.ok());
  EXPECT_FALSE(none.cpk.has_value());
}

TEST(Spc, CapabilityRefusals) {
  EXPECT_EQ(capability({1, 2, kNaN, 3, 4}, {0, 5}).error, "not enough points: 4 of 5");
  EXPECT_FALSE(capability({1, 2, 3, 4, 5}, {5, 0}).ok());
  EXPECT_FALSE(capability({1, 2, 3, 4, 5}, {kNaN, 5}).ok());
  // No variation: the ratios are undefined, not infinite.
  const Capability flat = capability({3, 3, 3, 3, 3}, {0, 5});
  ASSERT_TRUE(flat.ok());
  EXPECT_EQ(flat.sigma_overall, 0.0);
  EXPECT_FALSE(flat.cp.has_value());
  EXPECT_FALSE(flat.ppk.has_value());
}

TEST(Spc, PassRateWilsonByHand) {
  // 9 pass, 1 fail (2 invalid, not counted): p = 0.9, n = 10, z = 1.959964, z^2 = 3.841459.
  // centre = (18 + 3.841459) / (2 * 13.841459) = 21.841459 / 27.682918 = 0.7889868,
  // half = 1.959964 / 27.682918 * sqrt(3.6 + 3.841459) = 0.0708004 * 2.7278991 = 0.1931369:
  // [0.59585, 0.98212].
  const PassRate r = pass_rate({9, 1, 2});
  EXPECT_EQ(r.judged, 10u);
  EXPECT_DOUBLE_EQ(*r.rate, 0.9);
  EXPECT_NEAR(*r.lower, 0.59585, 1e-5);
  EXPECT_NEAR(*r.upper, 0.98212, 1e-5);
  // All pass: the upper bound is 1; nothing judged: no rate.
  EXPECT_EQ(*pass_rate({5, 0, 0}).upper, 1.0);
  EXPECT_EQ(*pass_rate({0, 5, 0}).lower, 0.0);
  EXPECT_FALSE(pass_rate({0, 0, 3}).rate.has_value());
  // 900 of 1000 is known much better than 9 of 10.
  const PassRate many = pass_rate({900, 100, 0});
  EXPECT_LT(*many.upper - *many.lower, (*r.upper - *r.lower) / 3);
}

}  // namespace
}  // namespace ncqual::trend

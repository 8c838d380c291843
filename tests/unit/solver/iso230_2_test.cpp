// SPDX-License-Identifier: Apache-2.0
// ISO 230-2 evaluation: two runs worked by hand, a unidirectional run, simulated runs with a
// known systematic error curve, reversal and noise, and every refusal.
#include "ncqual/solver/iso230_2.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace ncqual::solver {
namespace {

constexpr double kUm = 1e-3;      // mm per µm
constexpr double kExact = 1e-12;  // mm; the hand-worked figures are exact up to rounding
constexpr double kPi = 3.14159265358979323846;

using R = PositioningReading;

// Readings of `target_mm` in direction `d`, deviations given in µm, cycles numbered 1, 2, ...
void add(std::vector<R>* out, double target_mm, Approach d, const std::vector<double>& dev_um) {
  int cycle = 0;
  for (double x : dev_um) out->push_back(R{target_mm, ++cycle, d, target_mm + x * kUm});
}

// Example 1: 3 targets x 3 cycles, both directions. Deviations x_ij in µm:
//   P = 0:   up  1, 2, 3   mean 2, s = sqrt((1 + 0 + 1) / 2) = 1
//            down -2,-1, 0  mean -1, s = 1
//   P = 100: up  4, 6, 8   mean 6, s = sqrt((4 + 0 + 4) / 2) = 2
//            down 2, 3, 4  mean 3, s = 1
//   P = 200: up -1, 0, 1   mean 0, s = 1
//            down -3,-2,-1 mean -2, s = 1
std::vector<R> example_1(bool with_down = true, bool with_up = true) {
  std::vector<R> r;
  const auto Up = Approach::Up, Down = Approach::Down;
  if (with_up) {
    add(&r, 0, Up, {1, 2, 3});
    add(&r, 100, Up, {4, 6, 8});
    add(&r, 200, Up, {-1, 0, 1});
  }
  if (with_down) {
    add(&r, 0, Down, {-2, -1, 0});
    add(&r, 100, Down, {2, 3, 4});
    add(&r, 200, Down, {-3, -2, -1});
  }
  return r;
}

TEST(Iso230_2, HandWorkedExampleOne) {
  const Iso230_2Result res = evaluate_iso230_2(example_1());
  // Per target (µm):
  //   B_i = x̄↑ - x̄↓:             0: 2 - (-1) = 3;   100: 6 - 3 = 3;   200: 0 - (-2) = 2
  //   R_i↑ = 4 s↑:               4, 8, 4;           R_i↓ = 4, 4, 4
  //   R_i = max(2s↑+2s↓+|B|, R↑, R↓): 0: max(2+2+3, 4, 4) = 7; 100: max(4+2+3, 8, 4) = 9;
  //                                   200: max(2+2+2, 4, 4) = 6
  //   x̄_i = (x̄↑ + x̄↓)/2:         0.5, 4.5, -1
  ASSERT_EQ(res.targets.size(), 3u);
  EXPECT_EQ(res.cycles, 3);
  EXPECT_TRUE(res.has_up && res.has_down);
  const double exp_target[] = {0, 100, 200};
  const double exp_mean_up[] = {2, 6, 0}, exp_s_up[] = {1, 2, 1};
  const double exp_mean_down[] = {-1, 3, -2}, exp_s_down[] = {1, 1, 1};
  const double exp_B[] = {3, 3, 2}, exp_R[] = {7, 9, 6}, exp_mean[] = {0.5, 4.5, -1};
  for (int i = 0; i < 3; ++i) {
    const TargetFigures& t = res.targets[static_cast<std::size_t>(i)];
    EXPECT_DOUBLE_EQ(t.target_mm, exp_target[i]);
    ASSERT_TRUE(t.up && t.down && t.B_mm && t.R_mm && t.mean_mm);
    EXPECT_EQ(t.up->cycles, 3);
    EXPECT_NEAR(t.up->mean_mm, exp_mean_up[i] * kUm, kExact) << i;
    EXPECT_NEAR(t.up->s_mm, exp_s_up[i] * kUm, kExact) << i;
    EXPECT_NEAR(t.up->R_mm, 4 * exp_s_up[i] * kUm, kExact) << i;
    EXPECT_NEAR(t.down->mean_mm, exp_mean_down[i] * kUm, kExact) << i;
    EXPECT_NEAR(t.down->s_mm, exp_s_down[i] * kUm, kExact) << i;
    EXPECT_NEAR(*t.B_mm, exp_B[i] * kUm, kExact) << i;
    EXPECT_NEAR(*t.R_mm, exp_R[i] * kUm, kExact) << i;
    EXPECT_NEAR(*t.mean_mm, exp_mean[i] * kUm, kExact) << i;
  }
  EXPECT_NEAR(res.targets[1].up->min_mm, 4 * kUm, kExact);
  EXPECT_NEAR(res.targets[1].up->max_mm, 8 * kUm, kExact);
  // Axis (µm):
  //   B = max|B_i| = 3;  B̄ = (3 + 3 + 2)/3 = 8/3;  R↑ = 8, R↓ = 4, R = 9
  //   E↑ = 6 - 0 = 6;  E↓ = 3 - (-2) = 5;  E = max(2,6,0,-1,3,-2) - min(...) = 6 - (-2) = 8
  //   M = 4.5 - (-1) = 5.5
  //   A↑ = max(2+2, 6+4, 0+2) - min(2-2, 6-4, 0-2) = 10 - (-2) = 12
  //   A↓ = max(-1+2, 3+2, -2+2) - min(-1-2, 3-2, -2-2) = 5 - (-4) = 9
  //   A  = max(10, 5) - min(-2, -4) = 14
  EXPECT_NEAR(*res.B_mm, 3 * kUm, kExact);
  EXPECT_NEAR(*res.B_mean_mm, 8.0 / 3 * kUm, kExact);
  EXPECT_NEAR(*res.R_up_mm, 8 * kUm, kExact);
  EXPECT_NEAR(*res.R_down_mm, 4 * kUm, kExact);
  EXPECT_NEAR(*res.R_mm, 9 * kUm, kExact);
  EXPECT_NEAR(*res.E_up_mm, 6 * kUm, kExact);
  EXPECT_NEAR(*res.E_down_mm, 5 * kUm, kExact);
  EXPECT_NEAR(*res.E_mm, 8 * kUm, kExact);
  EXPECT_NEAR(*res.M_mm, 5.5 * kUm, kExact);
  EXPECT_NEAR(*res.A_up_mm, 12 * kUm, kExact);
  EXPECT_NEAR(*res.A_down_mm, 9 * kUm, kExact);
  EXPECT_NEAR(*res.A_mm, 14 * kUm, kExact);
}

// Example 2: 3 targets x 4 cycles, given in shuffled order, reversal of both signs, and a
// target where R_i↑ (not 2s↑ + 2s↓ + |B|) is the bidirectional repeatability. Deviations (µm):
//   P = -50: up   4, 4, 4, 8   mean 5, residuals -1,-1,-1,3: s = sqrt(12/3) = 2
//            down 7, 7, 7, 7   mean 7, s = 0
//   P = 0:   up   0, 0, 0, 0   mean 0, s = 0
//            down -2, 2, 2, 2  mean 1, residuals -3,1,1,1: s = 2
//   P = 50:  up   3, 3, 3, 7   mean 4, s = 2
//            down -5,-1,-1,-1  mean -2, s = 2
TEST(Iso230_2, HandWorkedExampleTwoInAnyOrder) {
  std::vector<R> r;
  const auto Up = Approach::Up, Down = Approach::Down;
  add(&r, 50, Down, {-5, -1, -1, -1});
  add(&r, -50, Up, {4, 4, 4, 8});
  add(&r, 0, Down, {-2, 2, 2, 2});
  add(&r, 50, Up, {3, 3, 3, 7});
  add(&r, -50, Down, {7, 7, 7, 7});
  add(&r, 0, Up, {0, 0, 0, 0});
  std::mt19937_64 rng(7);
  std::shuffle(r.begin(), r.end(), rng);
  const Iso230_2Result res = evaluate_iso230_2(r);
  // Per target (µm):
  //   B_i: -50: 5 - 7 = -2;  0: 0 - 1 = -1;  50: 4 - (-2) = 6
  //   R_i: -50: max(4 + 0 + 2, 8, 0) = 8;  0: max(0 + 4 + 1, 0, 8) = 8;  50: max(4+4+6, 8, 8) = 14
  //   x̄_i: 6, 0.5, 1
  ASSERT_EQ(res.targets.size(), 3u);
  EXPECT_EQ(res.cycles, 4);
  const double exp_B[] = {-2, -1, 6}, exp_R[] = {8, 8, 14}, exp_mean[] = {6, 0.5, 1};
  for (int i = 0; i < 3; ++i) {
    const TargetFigures& t = res.targets[static_cast<std::size_t>(i)];
    EXPECT_DOUBLE_EQ(t.target_mm, -50.0 + 50 * i);
    EXPECT_NEAR(*t.B_mm, exp_B[i] * kUm, kExact) << i;
    EXPECT_NEAR(*t.R_mm, exp_R[i] * kUm, kExact) << i;
    EXPECT_NEAR(*t.mean_mm, exp_mean[i] * kUm, kExact) << i;
  }
  EXPECT_NEAR(res.targets[0].down->s_mm, 0, kExact);
  EXPECT_NEAR(res.targets[1].down->s_mm, 2 * kUm, kExact);
  // Axis (µm): B = max(2, 1, 6) = 6;  B̄ = (-2 - 1 + 6)/3 = 1 (signed; the mean of |B_i| is 3)
  //   R↑ = max(8, 0, 8) = 8;  R↓ = max(0, 8, 8) = 8;  R = 14
  //   E↑ = 5 - 0 = 5;  E↓ = 7 - (-2) = 9;  E = max(5,0,4,7,1,-2) - min(...) = 7 - (-2) = 9
  //   M = 6 - 0.5 = 5.5
  //   A↑ = max(9, 0, 8) - min(1, 0, 0) = 9;  A↓ = max(7, 5, 2) - min(7, -3, -6) = 13
  //   A  = max(9, 7) - min(0, -6) = 15
  EXPECT_NEAR(*res.B_mm, 6 * kUm, kExact);
  EXPECT_NEAR(*res.B_mean_mm, 1 * kUm, kExact);
  EXPECT_NEAR(*res.R_up_mm, 8 * kUm, kExact);
  EXPECT_NEAR(*res.R_down_mm, 8 * kUm, kExact);
  EXPECT_NEAR(*res.R_mm, 14 * kUm, kExact);
  EXPECT_NEAR(*res.E_up_mm, 5 * kUm, kExact);
  EXPECT_NEAR(*res.E_down_mm, 9 * kUm, kExact);
  EXPECT_NEAR(*res.E_mm, 9 * kUm, kExact);
  EXPECT_NEAR(*res.M_mm, 5.5 * kUm, kExact);
  EXPECT_NEAR(*res.A_up_mm, 9 * kUm, kExact);
  EXPECT_NEAR(*res.A_down_mm, 13 * kUm, kExact);
  EXPECT_NEAR(*res.A_mm, 15 * kUm, kExact);
}

TEST(Iso230_2, UnidirectionalRunHasNoBidirectionalFigures) {
  // Example 1, up only: E↑ = 6, R↑ = 8, A↑ = 12 µm as worked above.
  const Iso230_2Result up = evaluate_iso230_2(example_1(/*with_down=*/false));
  EXPECT_TRUE(up.has_up);
  EXPECT_FALSE(up.has_down);
  EXPECT_NEAR(*up.E_up_mm, 6 * kUm, kExact);
  EXPECT_NEAR(*up.R_up_mm, 8 * kUm, kExact);
  EXPECT_NEAR(*up.A_up_mm, 12 * kUm, kExact);
  for (const auto& f : {up.E_down_mm, up.R_down_mm, up.A_down_mm, up.A_mm, up.E_mm, up.M_mm,
                        up.R_mm, up.B_mm, up.B_mean_mm}) {
    EXPECT_FALSE(f.has_value());
  }
  for (const auto& t : up.targets) {
    EXPECT_TRUE(t.up.has_value());
    EXPECT_FALSE(t.down || t.B_mm || t.R_mm || t.mean_mm);
  }
  // Down only: E↓ = 5, R↓ = 4, A↓ = 9 µm.
  const Iso230_2Result down = evaluate_iso230_2(example_1(true, /*with_up=*/false));
  EXPECT_FALSE(down.has_up);
  EXPECT_NEAR(*down.E_down_mm, 5 * kUm, kExact);
  EXPECT_NEAR(*down.R_down_mm, 4 * kUm, kExact);
  EXPECT_NEAR(*down.A_down_mm, 9 * kUm, kExact);
  EXPECT_FALSE(down.E_up_mm || down.A_mm || down.B_mean_mm);
}

// Simulated runs: m targets, n cycles, systematic error e(P), reversal b (up reads e + b/2,
// down e - b/2) and N(0, sigma) noise on every reading. Then x̄_i↑ = e_i + b/2 + N(0, σ²/n),
// x̄_i = e_i + N(0, σ²/(2n)), B_i = b + N(0, 2σ²/n) and B̄ = b + N(0, 2σ²/(n m)). A max or min
// of estimates is off by at most the largest estimation error, so with every error inside 5 of
// its standard deviations (probability of a miss < 1e-6 per estimate):
//   |E - E_true| <= 2 · 5σ/√n,  |M - M_true| <= 2 · 5σ/√(2n),  |B - b| <= 5σ√(2/n),
//   |B̄ - b| <= 5σ√(2/(n m)).
TEST(Iso230_2, SimulatedRunsRecoverTheSystematicCurveAndReversal) {
  const int m = 11, n = 10;
  const double sigma = 1.0 * kUm;
  std::mt19937_64 rng(2302);
  std::normal_distribution<double> noise(0, sigma);
  for (int run = 0; run < 20; ++run) {
    const double b = std::uniform_real_distribution<double>(-8, 8)(rng) * kUm;
    const double amp = std::uniform_real_distribution<double>(5, 15)(rng) * kUm;
    const double slope = std::uniform_real_distribution<double>(-20e-6, 20e-6)(rng);  // mm/mm
    auto e = [&](double p) { return amp * std::sin(2 * kPi * p / 770.0) + slope * p; };
    std::vector<R> r;
    double e_min = 1e9, e_max = -1e9;
    for (int i = 0; i < m; ++i) {
      const double p = 100.0 * i;
      e_min = std::min(e_min, e(p));
      e_max = std::max(e_max, e(p));
      for (int j = 1; j <= n; ++j) {
        r.push_back(R{p, j, Approach::Up, p + e(p) + b / 2 + noise(rng)});
        r.push_back(R{p, j, Approach::Down, p + e(p) - b / 2 + noise(rng)});
      }
    }
    const Iso230_2Result res = evaluate_iso230_2(r);
    const double E_true = (e_max - e_min) + std::abs(b);
    const double M_true = e_max - e_min;
    EXPECT_NEAR(*res.E_mm, E_true, 2 * 5 * sigma / std::sqrt(n)) << run;
    EXPECT_NEAR(*res.M_mm, M_true, 2 * 5 * sigma / std::sqrt(2.0 * n)) << run;
    EXPECT_NEAR(*res.B_mean_mm, b, 5 * sigma * std::sqrt(2.0 / (n * m))) << run;
    EXPECT_NEAR(*res.B_mm, std::abs(b), 5 * sigma * std::sqrt(2.0 / n)) << run;
    // The unidirectional E↑ sees the curve alone: max/min of e_i + b/2.
    EXPECT_NEAR(*res.E_up_mm, M_true, 2 * 5 * sigma / std::sqrt(n)) << run;
    // Pooled variance (1/2m) Σ s_i² estimates σ² with relative standard deviation
    // sqrt(2 / (2m (n-1))) = 0.10; within 5 of those.
    double pooled = 0;
    for (const auto& t : res.targets)
      pooled += t.up->s_mm * t.up->s_mm + t.down->s_mm * t.down->s_mm;
    pooled /= 2 * m;
    EXPECT_NEAR(pooled / (sigma * sigma), 1.0, 5 * std::sqrt(2.0 / (2 * m * (n - 1)))) << run;
  }
}

std::string refusal(const std::vector<R>& r) {
  try {
    evaluate_iso230_2(r);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(Iso230_2, RefusesFewerThanTwoTargets) {
  std::vector<R> r;
  add(&r, 100, Approach::Up, {1, 2, 3});
  add(&r, 100, Approach::Down, {1, 2, 3});
  EXPECT_EQ(refusal(r),
            "evaluate_iso230_2: only 1 target (target_mm = 100); ISO 230-2 needs at least 2 "
            "targets");
  EXPECT_EQ(refusal({}), "evaluate_iso230_2: no readings");
}

TEST(Iso230_2, RefusesATargetAndDirectionWithOneCycle) {
  auto r = example_1();
  // Keep one down reading at 100 mm: indices 12..14 are (100, down, cycles 1..3).
  ASSERT_EQ(r[12].target_mm, 100);
  ASSERT_EQ(r[12].direction, Approach::Down);
  r.erase(r.begin() + 13, r.begin() + 15);
  EXPECT_EQ(refusal(r),
            "evaluate_iso230_2: readings[12]: target_mm = 100, direction = down: 1 cycle; at "
            "least 2 are needed for the standard uncertainty s (n - 1 in its denominator)");
}

TEST(Iso230_2, RefusesATargetMeasuredInOneDirectionOnly) {
  auto r = example_1();
  add(&r, 300, Approach::Up, {0, 1, 2});  // readings 18..20
  const auto p = find_iso230_2_problem(r);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->index, std::optional<std::size_t>(18));
  EXPECT_EQ(refusal(r),
            "evaluate_iso230_2: readings[18]: target_mm = 300 has up readings but no down "
            "readings, while other targets do");
}

TEST(Iso230_2, RefusesNonFiniteNumbers) {
  auto r = example_1();
  r[4].measured_mm = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(refusal(r), "evaluate_iso230_2: readings[4]: measured_mm = nan is not a finite number");
  r = example_1();
  r[2].target_mm = std::numeric_limits<double>::infinity();
  EXPECT_EQ(refusal(r), "evaluate_iso230_2: readings[2]: target_mm = inf is not a finite number");
}

TEST(Iso230_2, RefusesDuplicateTargetCycleDirection) {
  auto r = example_1();
  r.push_back(R{200, 2, Approach::Up, 200.0});  // repeats readings[7]
  const auto p = find_iso230_2_problem(r);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->index, std::optional<std::size_t>(18));
  EXPECT_EQ(p->first_index, std::optional<std::size_t>(7));
  EXPECT_EQ(refusal(r),
            "evaluate_iso230_2: readings[18]: target_mm = 200, cycle = 2, direction = up: a "
            "second reading of the same target, cycle and direction (first at readings[7])");
  EXPECT_FALSE(find_iso230_2_problem(example_1()));
}

}  // namespace
}  // namespace ncqual::solver

namespace ncqual::solver {
namespace {

// Where a plan departs from ISO 230-2, worked by hand:
//  - example 1: 3 cycles, 3 targets over 200 mm (5 needed in all), every 100 mm;
//  - up only: also the missing direction;
//  - 5 cycles at 6 uneven targets over 1000 mm: conforms; over 1500 mm the travel needs 8.
TEST(Iso230_2, ConformanceSaysWhereThePlanDepartsFromTheStandard) {
  EXPECT_EQ(iso230_2_conformance(evaluate_iso230_2(example_1())),
            (std::vector<std::string>{
                "3 approach(es) at target 0 mm up (+): ISO 230-2 asks for 5 in each direction "
                "at each target",
                "3 targets over 200 mm of travel: ISO 230-2 asks for at least 5 per metre and 5 "
                "in all (5 here)",
                "targets at one even interval of 100 mm: ISO 230-2 spaces them unevenly (e.g. at "
                "random) so that periodic errors, a ball screw's pitch or a scale's period, are "
                "not sampled at one phase"}));
  const auto up_only = iso230_2_conformance(evaluate_iso230_2(example_1(false)));
  ASSERT_EQ(up_only.size(), 4u);
  EXPECT_EQ(up_only[1],
            "measured in one direction only (up): ISO 230-2 approaches each target in both; the "
            "bidirectional figures and the reversal B are not given");

  const auto plan = [](double scale) {
    std::vector<R> r;
    for (double p : {0.0, 180.0, 410.0, 590.0, 820.0, 1000.0}) {
      add(&r, p * scale, Approach::Up, {1, 2, 3, 2, 1});
      add(&r, p * scale, Approach::Down, {-1, 0, 1, 0, -1});
    }
    return evaluate_iso230_2(r);
  };
  EXPECT_EQ(iso230_2_conformance(plan(1.0)), std::vector<std::string>{});
  EXPECT_EQ(iso230_2_conformance(plan(1.5)),
            std::vector<std::string>{"6 targets over 1500 mm of travel: ISO 230-2 asks for at "
                                     "least 5 per metre and 5 in all (8 here)"});
}

}  // namespace
}  // namespace ncqual::solver

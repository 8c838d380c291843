// SPDX-License-Identifier: Apache-2.0
#include "ncqual/solver/monument_positioning.hpp"

#include "ncqual/sim/machine_simulator.hpp"
#include "ncqual/solver/solve.hpp"
#include "solver_test_support.hpp"
#include "test_machines.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace ncqual::solver {
namespace {

using testing::Expectation;
using testing::GroundTruthTally;
using testing::metric;
using testing::NoiseSpread;
using testing::pm1_like_machine;
using testing::random_machine;
using testing::request;
using testing::simulator_config;
using testing::spoil_random_field;
using testing::uniform;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

MeasurementSet simulate(const MachineConfig& m, const sim::SimulatorConfig& c,
                        const std::string& id) {
  return sim::MachineSimulator(m, c).perform(request(m.machine_id, id), 1000);
}

// ---- End to end against the simulator's ground truth ----------------------------------------

TEST(RepeatablePositioning, RecoversInjectedShiftsAcrossRandomMachines) {
  // Truth: a machine shifted by s_m reads every point s_m short, a monument shifted by s_g is
  // s_g further, so the measured deviations are d = s_g - s_m on each axis.
  // Noise: the centre of N evenly spaced touches with trigger noise sigma_t has a standard
  // deviation sigma_t sqrt(2/N) per axis
  // (CircleFit.CentreOfEvenlySpacedTouchesHasSigmaSqrtTwoOverN); the single face touch gives
  // sigma_t.
  std::mt19937_64 rng(201);
  const int cases = 200;
  GroundTruthTally tally("machine shifted along its axes");
  for (int i = 0; i < cases; ++i) {
    const MachineConfig m = random_machine(rng, "m" + std::to_string(i % 7));
    sim::SimulatorConfig c = simulator_config(uniform(rng, 0.0005, 0.002), rng());
    for (int k = 0; k < 3; ++k) {
      c.errors.machine_shift_mm[k] = uniform(rng, -0.02, 0.02);
      c.errors.monument_shift_mm[k] = uniform(rng, -0.02, 0.02);
    }
    const sim::MachineSimulator simulator(m, c);
    const MeasurementSet set =
        simulator.perform(request(m.machine_id, "e2e-" + std::to_string(i)), 1000);
    ASSERT_TRUE(set.error.empty()) << set.error;
    const CheckResult result = check_repeatable_positioning(set, m);
    ASSERT_NE(result.verdict, Verdict::Invalid) << result.reason;

    const sim::SimulatorErrors& truth = simulator.ground_truth();
    const Eigen::Vector3d expected = truth.monument_shift_mm - truth.machine_shift_mm;
    const double sigma_t = c.trigger_noise_sigma_mm;
    const double sigma_centre = sigma_t * std::sqrt(2.0 / m.monument.hole_touches);
    // Per-case bound 5 sigma: with 600 comparisons a 3 sigma bound would be exceeded by chance
    // about twice; the 3 sigma statistics are checked over the whole sample below.
    const std::vector<Expectation> checks = {{positioning::kCenterDx, expected.x(), sigma_centre},
                                             {positioning::kCenterDy, expected.y(), sigma_centre},
                                             {positioning::kFaceDz, expected.z(), sigma_t}};
    tally.check(result, m, checks, i);
    for (const auto& check : checks) {
      const Metric& mt = metric(result, check.name);
      const Tolerance& band = m.tolerances.at(std::string(check.name));
      EXPECT_EQ(mt.lower, band.lower);
      EXPECT_EQ(mt.upper, band.upper);
    }
    if (result.verdict == Verdict::Fail) {
      ASSERT_GE(result.likely_causes.size(), 2u);
      EXPECT_EQ(result.likely_causes[1], "monument shifted");
    }
  }
  // Both verdicts must have been exercised.
  EXPECT_GT(tally.passes(), 30);
  EXPECT_GT(tally.fails(), 30);
  // The errors are the trigger noise and nothing else: standard normal after scaling.
  const NoiseSpread spread = tally.spread();
  // 600 values: the rms of standard normals has a standard error of ~0.03.
  EXPECT_NEAR(spread.rms, 1.0, 0.15);
  // P(|z| > 3) = 0.0027: ~1.6 expected of 600.
  EXPECT_LE(spread.beyond_3, 7);
}

TEST(RepeatablePositioning, PerfectMachinePasses) {
  std::mt19937_64 rng(202);
  for (int i = 0; i < 50; ++i) {
    const MachineConfig m = random_machine(rng);
    const MeasurementSet set = simulate(m, simulator_config(0.001), "perfect-" + std::to_string(i));
    const CheckResult r = check_repeatable_positioning(set, m);
    EXPECT_EQ(r.verdict, Verdict::Pass) << r.reason;
    EXPECT_TRUE(r.reason.empty());
    EXPECT_TRUE(r.likely_causes.empty());
    EXPECT_EQ(r.metrics.size(), 3u);
    for (const Metric& mt : r.metrics) {
      EXPECT_TRUE(mt.pass) << mt.name;
      EXPECT_EQ(mt.unit, "mm");
    }
    EXPECT_EQ(r.machine_id, m.machine_id);
    EXPECT_EQ(r.request_id, "perfect-" + std::to_string(i));
    EXPECT_EQ(r.kind, CheckKind::MonumentPositioning);
  }
}

TEST(RepeatablePositioning, FailureNamesTheMetricAndTheExcess) {
  const MachineConfig m = pm1_like_machine();
  sim::SimulatorConfig c = simulator_config(0.0);
  c.errors.machine_shift_mm = Eigen::Vector3d(-0.04, 0, 0);  // centre reads +0.04 in X
  const CheckResult r = check_repeatable_positioning(simulate(m, c, "x-out"), m);
  ASSERT_EQ(r.verdict, Verdict::Fail) << r.reason;
  EXPECT_NEAR(metric(r, "center_dx_mm").value, 0.04, 1e-9);
  EXPECT_FALSE(metric(r, "center_dx_mm").pass);
  EXPECT_TRUE(metric(r, "center_dy_mm").pass);
  EXPECT_TRUE(metric(r, "face_dz_mm").pass);
  EXPECT_NE(r.reason.find("center_dx_mm = 0.04 mm"), std::string::npos) << r.reason;
  EXPECT_NE(r.reason.find("upper limit 0.025 mm by 0.015 mm"), std::string::npos) << r.reason;
  EXPECT_EQ(r.reason.find("center_dy_mm"), std::string::npos) << r.reason;
  EXPECT_EQ(r.likely_causes,
            (std::vector<std::string>{"machine shifted along its axes", "monument shifted"}));

  c.errors.machine_shift_mm = Eigen::Vector3d(0, 0, 0.03);  // face reads -0.03 in Z
  const CheckResult low = check_repeatable_positioning(simulate(m, c, "z-out"), m);
  ASSERT_EQ(low.verdict, Verdict::Fail);
  EXPECT_NE(low.reason.find("face_dz_mm = -0.03 mm is below the lower limit -0.025 mm by 0.005 mm"),
            std::string::npos)
      << low.reason;
}

TEST(RepeatablePositioning, AsymmetricToleranceBandIsHonoured) {
  MachineConfig m = pm1_like_machine();
  m.tolerances["face_dz_mm"] = Tolerance{-0.005, 0.05};
  sim::SimulatorConfig c = simulator_config(0.0);
  c.errors.monument_shift_mm = Eigen::Vector3d(0, 0, 0.04);
  EXPECT_EQ(check_repeatable_positioning(simulate(m, c, "a"), m).verdict, Verdict::Pass);
  c.errors.monument_shift_mm = Eigen::Vector3d(0, 0, -0.01);
  EXPECT_EQ(check_repeatable_positioning(simulate(m, c, "b"), m).verdict, Verdict::Fail);
}

TEST(RepeatablePositioning, HoleDiameterMetricOnlyWhenConfigured) {
  MachineConfig m = pm1_like_machine();
  const MeasurementSet set = simulate(m, simulator_config(0.001), "dia");
  EXPECT_EQ(find_metric(check_repeatable_positioning(set, m), "hole_diameter_error_mm"), nullptr);

  m.tolerances["hole_diameter_error_mm"] = Tolerance{-0.01, 0.01};
  const CheckResult r = check_repeatable_positioning(set, m);
  EXPECT_EQ(r.verdict, Verdict::Pass) << r.reason;
  // Radius from 4 touches: sigma_t / 2; the diameter doubles it.
  EXPECT_NEAR(metric(r, "hole_diameter_error_mm").value, 0, 5 * 0.001);

  // The gauge is really 0.2 mm larger than the config says: only the diameter fails, and the
  // probe is added to the causes.
  MachineConfig bigger = pm1_like_machine();
  bigger.monument.hole_diameter_mm += 0.2;
  const MeasurementSet big_set = simulate(bigger, simulator_config(0.0), "dia-big");
  const CheckResult big = check_repeatable_positioning(big_set, m);
  ASSERT_EQ(big.verdict, Verdict::Fail) << big.reason;
  EXPECT_NEAR(metric(big, "hole_diameter_error_mm").value, 0.2, 1e-9);
  EXPECT_TRUE(metric(big, "center_dx_mm").pass);
  EXPECT_NE(big.reason.find("hole_diameter_error_mm"), std::string::npos);
  ASSERT_EQ(big.likely_causes.size(), 3u);
  EXPECT_EQ(big.likely_causes[0], "machine shifted along its axes");
  EXPECT_EQ(big.likely_causes[2], positioning::kCauseProbeCalibration);
}

TEST(RepeatablePositioning, SeveralFaceTouchesAreAveraged) {
  const MachineConfig m = pm1_like_machine();
  MeasurementSet set = simulate(m, simulator_config(0.0), "faces");
  Touch second = set.touches.back();
  ASSERT_EQ(second.feature, "face");
  second.axes.z_mm += 0.01;
  set.touches.push_back(second);
  const CheckResult r = check_repeatable_positioning(set, m);
  ASSERT_NE(r.verdict, Verdict::Invalid) << r.reason;
  EXPECT_NEAR(metric(r, "face_dz_mm").value, 0.005, 1e-9);
}

TEST(RepeatablePositioning, ThreeEdgeTouchesAsInThePatentSuffice) {
  MachineConfig m = pm1_like_machine();
  m.monument.hole_touches = 3;
  sim::SimulatorConfig c = simulator_config(0.0);
  c.errors.monument_shift_mm = Eigen::Vector3d(0.01, -0.012, 0.003);
  const CheckResult r = check_repeatable_positioning(simulate(m, c, "three"), m);
  ASSERT_EQ(r.verdict, Verdict::Pass) << r.reason;
  EXPECT_NEAR(metric(r, "center_dx_mm").value, 0.01, 1e-9);
  EXPECT_NEAR(metric(r, "center_dy_mm").value, -0.012, 1e-9);
  EXPECT_NEAR(metric(r, "face_dz_mm").value, 0.003, 1e-9);
}

TEST(RepeatablePositioning, HeadAngleAtTouchTimeIsTakenIntoAccount) {
  // Touches taken with the head turned (same angle for all): the nominal kinematics put the
  // ball back where it was, so a perfect machine still passes.
  const MachineConfig m = pm1_like_machine();
  MeasurementSet set = simulate(m, simulator_config(0.0), "turned");
  const double a = 0.3, c = 1.1;
  for (Touch& t : set.touches) {
    const Eigen::Vector3d b = stylus_ball_centre(t.axes, m.probe);
    const Eigen::Vector3d pivot =
        b - wrist_rotation(a, c) * Eigen::Vector3d(0, 0, -m.probe.tool_length_mm);
    t.axes = AxisPosition{pivot.x(), pivot.y(), pivot.z(), 0, a, c};
  }
  const CheckResult r = check_repeatable_positioning(set, m);
  EXPECT_EQ(r.verdict, Verdict::Pass) << r.reason;
  EXPECT_NEAR(metric(r, "center_dx_mm").value, 0, 1e-9);
}

// ---- Input that cannot support a verdict -----------------------------------------------------

struct InvalidCase {
  std::string name;
  std::function<void(MeasurementSet&, MachineConfig&)> spoil;
  std::string reason_must_contain;
};

TEST(RepeatablePositioning, InvalidInputsGiveInvalidWithAReasonNamingTheField) {
  const std::vector<InvalidCase> cases = {
      {"empty set", [](MeasurementSet& s, MachineConfig&) { s.touches.clear(); },
       "MeasurementSet.touches is empty"},
      {"instrument error", [](MeasurementSet& s, MachineConfig&) { s.error = "probe battery low"; },
       "MeasurementSet.error: probe battery low"},
      {"two hole touches",
       [](MeasurementSet& s, MachineConfig&) {
         s.touches.erase(s.touches.begin(), s.touches.begin() + 2);
       },
       "MeasurementSet.touches: 2 'hole_edge' touches, check 3 needs at least 3"},
      {"NaN axis", [](MeasurementSet& s, MachineConfig&) { s.touches[1].axes.x_mm = kNaN; },
       "MeasurementSet.touches[1].axes.x_mm = nan"},
      {"inf axis",
       [](MeasurementSet& s, MachineConfig&) {
         s.touches[0].axes.c_rad = std::numeric_limits<double>::infinity();
       },
       "MeasurementSet.touches[0].axes.c_rad = inf"},
      {"NaN approach", [](MeasurementSet& s, MachineConfig&) { s.touches[2].approach.y() = kNaN; },
       "MeasurementSet.touches[2].approach = (-1, nan, 0) is not finite"},
      {"approach not unit", [](MeasurementSet& s, MachineConfig&) { s.touches[0].approach *= 2; },
       "MeasurementSet.touches[0].approach = (2, 0, 0) has length 2, expected a unit vector"},
      {"zero approach", [](MeasurementSet& s, MachineConfig&) { s.touches[3].approach.setZero(); },
       "touches[3].approach = (0, 0, 0) has length 0"},
      {"face approached upwards",
       [](MeasurementSet& s, MachineConfig&) {
         s.touches.back().approach = Eigen::Vector3d::UnitZ();
       },
       "MeasurementSet.touches[4].approach = (0, 0, 1): a 'face' touch must approach along -Z"},
      {"no face touch", [](MeasurementSet& s, MachineConfig&) { s.touches.pop_back(); },
       "MeasurementSet.touches: 0 'face' touches, check 3 needs at least 1"},
      {"unknown feature", [](MeasurementSet& s, MachineConfig&) { s.touches[1].feature = "rim"; },
       "MeasurementSet.touches[1].feature = 'rim'"},
      {"mixed head angles",
       [](MeasurementSet& s, MachineConfig&) { s.touches[2].axes.a_rad += 2e-6; },
       "MeasurementSet.touches[2].axes: head at A = 2e-06 rad"},
      {"mixed C angles", [](MeasurementSet& s, MachineConfig&) { s.touches[4].axes.c_rad = 0.5; },
       "MeasurementSet.touches[4].axes: head at A = 0 rad, C = 0.5 rad differs from touches[0]"},
      {"wrong kind",
       [](MeasurementSet& s, MachineConfig&) { s.kind = CheckKind::MonumentToolLength; },
       "MeasurementSet.kind = 'monument_tool_length': check 3 needs 'monument_positioning'"},
      {"zero hole diameter",
       [](MeasurementSet&, MachineConfig& m) { m.monument.hole_diameter_mm = 0; },
       "monument.hole_diameter_mm = 0 must be positive"},
      {"negative hole diameter",
       [](MeasurementSet&, MachineConfig& m) { m.monument.hole_diameter_mm = -50; },
       "monument.hole_diameter_mm = -50"},
      {"hole no larger than the ball",
       [](MeasurementSet&, MachineConfig& m) { m.monument.hole_diameter_mm = 6; },
       "monument.hole_diameter_mm = 6 does not exceed the stylus ball diameter 6"},
      {"NaN ball radius", [](MeasurementSet&, MachineConfig& m) { m.probe.ball_radius_mm = kNaN; },
       "probe.ball_radius_mm = nan"},
      {"NaN taught centre",
       [](MeasurementSet&, MachineConfig& m) { m.monument.hole_center_mm.x() = kNaN; },
       "monument.hole_center_mm = (nan, 800)"},
      {"missing tolerance",
       [](MeasurementSet&, MachineConfig& m) { m.tolerances.erase("face_dz_mm"); },
       "machine 'pm1' (test:pm1): tolerances.face_dz_mm is not configured"},
      {"touches missed the hole (config says a smaller hole)",
       [](MeasurementSet&, MachineConfig& m) { m.monument.hole_diameter_mm = 40; },
       "the touches missed the hole edge"},
      {"touches all at one point",
       [](MeasurementSet& s, MachineConfig&) {
         for (int i = 1; i < 4; ++i)
           s.touches[static_cast<std::size_t>(i)].axes = s.touches[0].axes;
       },
       "'hole_edge' touches give no circle: fit_circle: all points coincide"},
  };
  for (const auto& c : cases) {
    MachineConfig m = pm1_like_machine();
    MeasurementSet set = simulate(m, simulator_config(0.001), "invalid");
    ASSERT_EQ(check_repeatable_positioning(set, m).verdict, Verdict::Pass) << c.name;
    c.spoil(set, m);
    CheckResult r;
    ASSERT_NO_THROW(r = check_repeatable_positioning(set, m)) << c.name;
    EXPECT_EQ(r.verdict, Verdict::Invalid) << c.name << ": " << r.reason;
    EXPECT_NE(r.reason.find(c.reason_must_contain), std::string::npos)
        << c.name << ": reason '" << r.reason << "' lacks '" << c.reason_must_contain << "'";
    EXPECT_TRUE(r.metrics.empty()) << c.name;
    // Through the entry point too, never a PASS.
    const CheckResult via_solve = solve(set, m, 7);
    EXPECT_EQ(via_solve.verdict, Verdict::Invalid) << c.name << ": " << via_solve.reason;
  }
}

TEST(RepeatablePositioning, RandomGarbageIsNeverPass) {
  // Random corruptions of one field of a valid set never give PASS unless the corruption left
  // the set valid; NaN and infinities always give INVALID, and nothing throws.
  std::mt19937_64 rng(203);
  const MachineConfig m = pm1_like_machine();
  const double poison[] = {kNaN, std::numeric_limits<double>::infinity(),
                           -std::numeric_limits<double>::infinity()};
  for (int i = 0; i < 300; ++i) {
    MeasurementSet set = simulate(m, simulator_config(0.001), "garbage-" + std::to_string(i));
    spoil_random_field(set, rng, poison[i % 3]);
    CheckResult r;
    ASSERT_NO_THROW(r = check_repeatable_positioning(set, m));
    EXPECT_EQ(r.verdict, Verdict::Invalid) << r.reason;
    EXPECT_NE(r.reason.find("MeasurementSet.touches["), std::string::npos) << r.reason;
  }
}

TEST(RepeatablePositioning, SimulatorAlarmBecomesInvalid) {
  MachineConfig m = pm1_like_machine();
  const sim::SimulatorConfig c = simulator_config(0.001);
  m.monument.probe_depth_mm = c.plate_thickness_mm + 10;  // below the plate
  const MeasurementSet set = simulate(m, c, "deep");
  ASSERT_FALSE(set.error.empty());
  const CheckResult r = solve(set, m, 1);
  EXPECT_EQ(r.verdict, Verdict::Invalid);
  EXPECT_NE(r.reason.find("MeasurementSet.error: probe alarm"), std::string::npos) << r.reason;
  EXPECT_EQ(check_repeatable_positioning(set, m).verdict, Verdict::Invalid);
}

}  // namespace
}  // namespace ncqual::solver

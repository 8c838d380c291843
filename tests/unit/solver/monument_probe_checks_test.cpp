// SPDX-License-Identifier: Apache-2.0
// Probe checks 1, 2 and 4 against the simulator's ground truth. Every case injects ALL the
// simulator's errors at once (machine and monument shift, stylus offset, tool length, C angle,
// A home): each check must see its own error and be blind to the others, as the procedure
// intends.
#include "ncqual/solver/monument_probe_checks.hpp"

#include "ncqual/common/kinematics.hpp"
#include "ncqual/sim/machine_simulator.hpp"
#include "ncqual/solver/solve.hpp"
#include "ncqual/common/units.hpp"
#include "solver_test_support.hpp"
#include "test_machines.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace ncqual::solver {
namespace {

using testing::GroundTruthTally;
using testing::metric;
using testing::pm1_like_machine;
using testing::random_machine;
using testing::request;
using testing::simulator_config;
using testing::uniform;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The tolerances of checks 1, 2 and 4 (pm1's, deploy/machines/pm1.yaml).
MachineConfig with_probe_tolerances(MachineConfig m) {
  m.tolerances["c_align_dx_mm"] = {-0.015, 0.015};
  m.tolerances["c_align_dy_mm"] = {-0.015, 0.015};
  m.tolerances["probe_c_offset_mm"] = {0.0, 0.015};
  m.tolerances["tool_length_error_mm"] = {-0.025, 0.025};
  m.tolerances["c_angle_error_arcsec"] = {-8.0, 8.0};
  return m;
}

// Every error the simulator knows, drawn at once; some cases beyond tolerance, most within.
sim::SimulatorConfig random_errors(std::mt19937_64& rng) {
  sim::SimulatorConfig c = simulator_config(uniform(rng, 0.0005, 0.002), rng());
  for (int k = 0; k < 3; ++k) {
    c.errors.machine_shift_mm[k] = uniform(rng, -0.05, 0.05);
    c.errors.monument_shift_mm[k] = uniform(rng, -0.05, 0.05);
  }
  c.errors.stylus_offset_mm = Eigen::Vector2d(uniform(rng, -0.02, 0.02), uniform(rng, -0.02, 0.02));
  c.errors.tool_length_error_mm = uniform(rng, -0.05, 0.05);
  c.errors.c_angle_error_rad = units::arcsec_to_rad(uniform(rng, -15, 15));
  c.errors.a_home_error_rad = units::arcsec_to_rad(uniform(rng, -15, 15));
  return c;
}

// Case i of a seeded end-to-end test: the simulated machine (its config: m) and what it measured.
struct Case {
  const sim::MachineSimulator& simulator;
  const MachineConfig& m;
  const MeasurementSet& set;
  GroundTruthTally& tally;
  int i;
};

// A seeded end-to-end test of the check `kind`: 200 cases, each a random machine with the probe
// tolerances (ids m0 to m4) and every simulator error at once, measured (request ids
// "<prefix>-<i>") with no error; measured(case) checks each. Then the tally's noise statistics.
// Stops at the first fatal failure, as an ASSERT in the test would.
void expect_ground_truth(std::uint64_t seed, CheckKind kind, const std::string& prefix,
                         const std::string& first_cause,
                         const std::function<void(const Case&)>& measured) {
  std::mt19937_64 rng(seed);
  GroundTruthTally tally(first_cause);
  for (int i = 0; i < 200; ++i) {
    const MachineConfig m = with_probe_tolerances(random_machine(rng, "m" + std::to_string(i % 5)));
    const sim::MachineSimulator simulator(m, random_errors(rng));
    const MeasurementSet set =
        simulator.perform(request(m.machine_id, prefix + "-" + std::to_string(i), kind), 1000);
    ASSERT_TRUE(set.error.empty()) << set.error;
    measured(Case{simulator, m, set, tally, i});
    if (::testing::Test::HasFatalFailure()) return;
  }
  tally.expect_noise_statistics();
}

// ---- Check 1 ----------------------------------------------------------------------------------

// Truth of check 1: with the head at C = 0 the true ball sits at Rz(e_c) Rx(e_a) (o', -L')
// from the pivot where the control believes (o, -L); at C = 180 deg at minus that in XY. The
// apparent hole centres differ by twice v = [Rz(e_c) Rx(e_a) (o', -L') - (o, -L)]_xy, and
// machine and monument shifts move both centres alike.
Eigen::Vector2d true_c_alignment_offset(const sim::MachineSimulator& s) {
  const sim::SimulatorErrors& e = s.ground_truth();
  const ProbeGeometry& t = s.true_probe();
  const ProbeGeometry& n = s.machine().probe;
  const Eigen::Vector3d true_arm =
      wrist_rotation(e.a_home_error_rad, e.c_angle_error_rad) *
      Eigen::Vector3d(t.stylus_offset_mm.x(), t.stylus_offset_mm.y(), -t.tool_length_mm);
  return true_arm.head<2>() - n.stylus_offset_mm;
}

TEST(CAxisAlignment, RecoversTheProbeOffsetWithAllErrorsInjected) {
  // Noise: each centre from N evenly spaced touches has sigma_t sqrt(2/N) per axis; the offset
  // is half the difference of two such centres: sigma_t sqrt(2/N) sqrt(2) / 2 = sigma_t/sqrt(N).
  expect_ground_truth(301, CheckKind::MonumentCAlignment, "c1", "bent stylus", [](const Case& c) {
    ASSERT_EQ(c.set.touches.size(), 2u * c.m.monument.hole_touches);
    const CheckResult result = check_c_axis_alignment(c.set, c.m);
    const Eigen::Vector2d truth = true_c_alignment_offset(c.simulator);
    const double sigma =
        c.simulator.config().trigger_noise_sigma_mm / std::sqrt(c.m.monument.hole_touches);
    // |v| has the per-axis sigma along v (for |v| >> sigma).
    c.tally.check(result, c.m,
                  {{c_alignment::kDx, truth.x(), sigma},
                   {c_alignment::kDy, truth.y(), sigma},
                   {c_alignment::kOffset, truth.norm(), sigma}},
                  c.i);
  });
}

TEST(CAxisAlignment, ABodyOffItsHomeLooksLikeAnOffsetAcrossTheAAxis) {
  // With A off home by e the tip swings by L sin e across the A axis (machine Y at C = 0).
  MachineConfig m = with_probe_tolerances(pm1_like_machine());
  sim::SimulatorConfig c = simulator_config(0.0);
  c.errors.a_home_error_rad = units::arcsec_to_rad(20);
  const CheckResult r =
      check_c_axis_alignment(sim::MachineSimulator(m, c).perform(
                                 request("pm1", "a-home", CheckKind::MonumentCAlignment), 1),
                             m);
  EXPECT_NEAR(metric(r, c_alignment::kDx).value, 0, 1e-9);
  EXPECT_NEAR(metric(r, c_alignment::kDy).value, 350.0 * std::sin(units::arcsec_to_rad(20)), 1e-9);
  EXPECT_EQ(r.verdict, Verdict::Fail);
  ASSERT_EQ(r.likely_causes.size(), 4u);
  EXPECT_EQ(r.likely_causes[2], "body not at its A home position");
  EXPECT_EQ(r.likely_causes[3], "A axis not perpendicular to C");
}

TEST(CAxisAlignment, ConsistencyOfTheFourthTouchIsReportedWhenConfigured) {
  MachineConfig m = with_probe_tolerances(pm1_like_machine());
  m.tolerances["c_align_consistency_mm"] = {0.0, 0.005};
  MeasurementSet set = sim::MachineSimulator(m, simulator_config(0.0))
                           .perform(request("pm1", "cons", CheckKind::MonumentCAlignment), 1);
  CheckResult r = check_c_axis_alignment(set, m);
  EXPECT_EQ(r.verdict, Verdict::Pass) << r.reason;
  EXPECT_NEAR(metric(r, c_alignment::kConsistency).value, 0, 1e-9);
  // A touch latched 20 um late: the circle through the other three disagrees with it.
  set.touches[1].axes.x_mm += 0.02 * set.touches[1].approach.x();
  set.touches[1].axes.y_mm += 0.02 * set.touches[1].approach.y();
  r = check_c_axis_alignment(set, m);
  EXPECT_EQ(r.verdict, Verdict::Fail);
  EXPECT_NEAR(metric(r, c_alignment::kConsistency).value, 0.02, 1e-3);
  // Half a millimetre off: the touch cannot have been on the hole edge.
  set.touches[1].axes.x_mm += 0.5 * set.touches[1].approach.x();
  set.touches[1].axes.y_mm += 0.5 * set.touches[1].approach.y();
  r = check_c_axis_alignment(set, m);
  EXPECT_EQ(r.verdict, Verdict::Invalid);
  EXPECT_NE(r.reason.find("the hole-edge touches at C = 0 disagree"), std::string::npos)
      << r.reason;
  EXPECT_NE(r.reason.find("did not land on the hole edge"), std::string::npos) << r.reason;
}

TEST(CAxisAlignment, ConsistencyFollowsTheTriggerNoise) {
  // With four touches at 90 deg the disagreement of any one with the circle through the other
  // three is e1 + e3 - e2 - e4 (radial trigger errors, in turn around the hole): sigma 2 sigma_t.
  // The metric is the larger of the two head angles' |.|, so its mean square is 4 sigma_t^2.
  MachineConfig m = with_probe_tolerances(pm1_like_machine());
  m.tolerances["c_align_consistency_mm"] = {0.0, 1.0};
  const sim::MachineSimulator simulator(m, simulator_config(0.001, 11));
  double sum_sq = 0;
  const int n = 400;
  for (int i = 0; i < n; ++i) {
    const CheckResult r = check_c_axis_alignment(
        simulator.perform(
            request("pm1", "noise-" + std::to_string(i), CheckKind::MonumentCAlignment), 1),
        m);
    const double c = metric(r, c_alignment::kConsistency).value / 0.001;
    sum_sq += c * c;
  }
  // E[max(X1^2, X2^2)] for X ~ N(0, 4): 4 (1 + 2/pi) = 6.55.
  EXPECT_NEAR(sum_sq / n, 4 * (1 + 2 / units::kPi), 1.0);
}

// ---- Check 2 ----------------------------------------------------------------------------------

TEST(CompositeToolLength, RecoversTheLengthErrorWithAllErrorsInjected) {
  // Noise: the length error is half the difference of two single touches: sigma_t / sqrt(2).
  // Truth: the injected length error; the other errors enter only to second order (below
  // 1e-5 mm for the ranges drawn here).
  expect_ground_truth(
      302, CheckKind::MonumentToolLength, "c2", "body (spindle housing) shifted",
      [](const Case& c) {
        const CheckResult result = check_composite_tool_length(c.set, c.m);
        const double truth = c.simulator.ground_truth().tool_length_error_mm;
        const double sigma = c.simulator.config().trigger_noise_sigma_mm / std::sqrt(2.0);
        c.tally.check(result, c.m, {{tool_length::kError, truth, sigma}}, c.i);
        EXPECT_NEAR(metric(result, tool_length::kLength).value - c.m.probe.tool_length_mm,
                    metric(result, tool_length::kError).value, 1e-9);
      });
}

TEST(CompositeToolLength, LengthBandFollowsTheErrorBandUnlessConfigured) {
  MachineConfig m = with_probe_tolerances(pm1_like_machine());
  sim::SimulatorConfig c = simulator_config(0.0);
  c.errors.tool_length_error_mm = 0.04;
  const MeasurementSet set =
      sim::MachineSimulator(m, c).perform(request("pm1", "len", CheckKind::MonumentToolLength), 1);
  CheckResult r = check_composite_tool_length(set, m);
  EXPECT_NEAR(metric(r, tool_length::kLength).value, 350.04, 1e-9);
  EXPECT_DOUBLE_EQ(metric(r, tool_length::kLength).lower, 350.0 - 0.025);
  EXPECT_DOUBLE_EQ(metric(r, tool_length::kLength).upper, 350.0 + 0.025);
  EXPECT_EQ(r.verdict, Verdict::Fail);
  EXPECT_EQ(r.likely_causes,
            (std::vector<std::string>{"body (spindle housing) shifted",
                                      "W-axis servo drive not at its home position",
                                      "probe (stylus length or seating in the spindle)"}));
  m.tolerances["tool_length_mm"] = {349.9, 350.1};
  r = check_composite_tool_length(set, m);
  EXPECT_TRUE(metric(r, tool_length::kLength).pass);
  EXPECT_FALSE(metric(r, tool_length::kError).pass);
}

// ---- Check 4 ----------------------------------------------------------------------------------

TEST(CRotation, RecoversTheCAngleErrorWithAllErrorsInjected) {
  // Truth: the tips differ in Y by 2 L' cos(e_a) sin(e_c) with the true length L', which the
  // check divides by 2 L: e = asin(L'/L cos(e_a) sin(e_c)).
  // Noise: the difference of two single touches over 2 L: sigma_t sqrt(2) / (2 L) rad.
  expect_ground_truth(304, CheckKind::MonumentCRotation, "c4",
                      "rotation about C more or less than commanded", [](const Case& c) {
                        const CheckResult result = check_c_rotation(c.set, c.m);
                        const sim::SimulatorErrors& e = c.simulator.ground_truth();
                        const double L = c.m.probe.tool_length_mm;
                        const double truth = units::rad_to_arcsec(std::asin(
                            c.simulator.true_probe().tool_length_mm / L *
                            std::cos(e.a_home_error_rad) * std::sin(e.c_angle_error_rad)));
                        const double sigma = units::rad_to_arcsec(
                            c.simulator.config().trigger_noise_sigma_mm * std::sqrt(2.0) / (2 * L));
                        c.tally.check(result, c.m, {{c_rotation::kAngleError, truth, sigma}}, c.i);
                        EXPECT_EQ(metric(result, c_rotation::kAngleError).unit, "arcsec");
                      });
}

// ---- Bad input: INVALID with a reason, never a wrong PASS --------------------------------------

struct BadCase {
  const char* name;
  CheckKind kind;
  std::function<void(MeasurementSet&, MachineConfig&)> spoil;
  const char* reason_contains;
};

TEST(MonumentProbeChecks, BadInputIsInvalidWithTheFieldNamed) {
  const std::vector<BadCase> cases = {
      {"c1 touches at C=180 missing", CheckKind::MonumentCAlignment,
       [](MeasurementSet& s, MachineConfig&) { s.touches.resize(4); },
       "0 'hole_edge' touches with the head at C = 180 deg"},
      {"c1 touch from the wrong head angle", CheckKind::MonumentCAlignment,
       [](MeasurementSet& s, MachineConfig&) { s.touches[5].axes.c_rad = units::kPi / 2; },
       "MeasurementSet.touches[5].axes: head at A = 0 rad, C = 1.5708 rad"},
      {"c1 wrong feature", CheckKind::MonumentCAlignment,
       [](MeasurementSet& s, MachineConfig&) { s.touches[0].feature = "face"; },
       "MeasurementSet.touches[0].feature = 'face'"},
      {"c1 NaN readout", CheckKind::MonumentCAlignment,
       [](MeasurementSet& s, MachineConfig&) { s.touches[2].axes.y_mm = kNaN; },
       "MeasurementSet.touches[2].axes.y_mm = nan"},
      {"c1 no touches", CheckKind::MonumentCAlignment,
       [](MeasurementSet& s, MachineConfig&) { s.touches.clear(); },
       "MeasurementSet.touches is empty"},
      {"c1 tolerance missing", CheckKind::MonumentCAlignment,
       [](MeasurementSet&, MachineConfig& m) { m.tolerances.erase("probe_c_offset_mm"); },
       "tolerances.probe_c_offset_mm is not configured"},
      {"c2 gauge width zero", CheckKind::MonumentToolLength,
       [](MeasurementSet&, MachineConfig& m) { m.monument.gauge_width_mm = 0; },
       "monument.gauge_width_mm = 0"},
      {"c2 missing the -x edge", CheckKind::MonumentToolLength,
       [](MeasurementSet& s, MachineConfig&) { s.touches.pop_back(); },
       "1 'gauge_edge_+x' and 0 'gauge_edge_-x' touches"},
      {"c2 touch with the head at A=0", CheckKind::MonumentToolLength,
       [](MeasurementSet& s, MachineConfig&) { s.touches[1].axes.a_rad = 0; },
       "MeasurementSet.touches[1].axes: head at A = 0 rad"},
      {"c2 approach reversed", CheckKind::MonumentToolLength,
       [](MeasurementSet& s, MachineConfig&) { s.touches[0].approach = Eigen::Vector3d::UnitX(); },
       "MeasurementSet.touches[0].approach = (1, 0, 0)"},
      {"c4 gauge width zero", CheckKind::MonumentCRotation,
       [](MeasurementSet&, MachineConfig& m) { m.monument.gauge_width_mm = 0; },
       "monument.gauge_width_mm = 0"},
      {"c4 both touches from one side", CheckKind::MonumentCRotation,
       [](MeasurementSet& s, MachineConfig&) { s.touches[1] = s.touches[0]; },
       "2 touches with the probe along -X and 0 along +X"},
      {"c4 head at C=0", CheckKind::MonumentCRotation,
       [](MeasurementSet& s, MachineConfig&) { s.touches[0].axes.c_rad = 0; },
       "MeasurementSet.touches[0].axes: head at A = 1.5708 rad, C = 0 rad"},
      {"c4 probe alarm", CheckKind::MonumentCRotation,
       [](MeasurementSet& s, MachineConfig&) { s.error = "probe alarm: move 1"; },
       "MeasurementSet.error: probe alarm: move 1"},
      {"c4 wrong kind", CheckKind::MonumentCRotation,
       [](MeasurementSet& s, MachineConfig&) { s.kind = CheckKind::MonumentToolLength; },
       "check 2 uses only 'gauge_edge_+x'"},
  };
  for (const auto& bad : cases) {
    MachineConfig m = with_probe_tolerances(pm1_like_machine());
    sim::SimulatorConfig c = simulator_config(0.001);
    c.errors.stylus_offset_mm = Eigen::Vector2d(0.003, 0.0);
    MeasurementSet set = sim::MachineSimulator(m, c).perform(request("pm1", bad.name, bad.kind), 1);
    ASSERT_TRUE(set.error.empty()) << bad.name << ": " << set.error;
    ASSERT_EQ(solve(set, m, 5).verdict, Verdict::Pass) << bad.name;  // unspoilt: a verdict
    bad.spoil(set, m);
    const CheckResult r = solve(set, m, 5);
    EXPECT_EQ(r.verdict, Verdict::Invalid) << bad.name;
    EXPECT_NE(r.reason.find(bad.reason_contains), std::string::npos)
        << bad.name << ": " << r.reason;
    EXPECT_TRUE(r.metrics.empty()) << bad.name;
  }
}

TEST(MonumentProbeChecks, EveryDailyCheckIsImplementedAndDispatched) {
  for (CheckKind kind : {CheckKind::MonumentCAlignment, CheckKind::MonumentToolLength,
                         CheckKind::MonumentPositioning, CheckKind::MonumentCRotation}) {
    EXPECT_TRUE(is_implemented(kind)) << to_string(kind);
    const MachineConfig m = with_probe_tolerances(pm1_like_machine());
    const MeasurementSet set =
        sim::MachineSimulator(m, simulator_config(0.001)).perform(request("pm1", "d", kind), 1);
    const CheckResult r = solve(set, m, 9);
    EXPECT_EQ(r.verdict, Verdict::Pass) << to_string(kind) << ": " << r.reason;
    EXPECT_EQ(r.kind, kind);
    EXPECT_EQ(r.time_ns, 9);
  }
}

}  // namespace
}  // namespace ncqual::solver

// SPDX-License-Identifier: Apache-2.0
#include "ncqual/solver/fixture_checks.hpp"

#include "ncqual/common/fixture.hpp"
#include "ncqual/sim/fixture_simulator.hpp"
#include "ncqual/sim/machine_simulator.hpp"
#include "solver_test_support.hpp"
#include "test_fixtures.hpp"
#include "test_machines.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace ncqual::solver {
namespace {

using namespace testing;  // test_machines.hpp, test_fixtures.hpp, solver_test_support.hpp

constexpr CheckKind kPre = CheckKind::FixturePreCalibration;
constexpr CheckKind kPost = CheckKind::FixturePostCalibration;
constexpr double kTol = 0.025;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

const std::string kZeroDrift(fixture_checks::kCauseZeroDrift);
const std::string kMisaligned(fixture_checks::kCauseMisaligned);
const std::string kNonlinear(fixture_checks::kCauseNonlinear);
const std::string kWear(fixture_checks::kCauseWear);

MachineConfig with_fixture(MachineConfig m, const FixtureConfig& f) {
  m.fixture = f;
  m.tolerances["fixture_delta_mm"] = Tolerance{-kTol, kTol};
  return m;
}

MeasurementSet run(const sim::MachineSimulator& machine, const sim::FixtureSimulator& fixture,
                   CheckKind kind, const std::string& id, std::optional<int> k) {
  return sim::perform_fixture_check(
      machine, fixture, fixture_request(machine.machine().machine_id, id, kind, k), 1000);
}

// The three post-calibration causes, each once.
void expect_all_three_causes(const CheckResult& r, const std::string& first,
                             const std::string& context) {
  ASSERT_EQ(r.likely_causes.size(), 3u) << context;
  EXPECT_EQ(r.likely_causes[0], first) << context << ": " << r.reason;
  EXPECT_EQ(std::set<std::string>(r.likely_causes.begin(), r.likely_causes.end()),
            (std::set<std::string>{kMisaligned, kNonlinear, kWear}))
      << context;
}

// Largest |true delta| of the post-calibration (rows of k) with the fixture's current zero
// offsets, as a perfect probe on the given (shifted) machine would see it.
double worst_true_post_delta(const sim::FixtureSimulator& fixture, int k,
                             const Eigen::Vector3d& machine_shift) {
  double worst = 0;
  const FixtureConfig& f = fixture.fixture();
  for (const auto& configuration : postcalibration_configurations(f, precalibration_rows(f, k))) {
    for (const auto& p : configuration) {
      worst = std::max(worst, (fixture.true_delta_mm(p) - machine_shift).cwiseAbs().maxCoeff());
    }
  }
  return worst;
}

// ---- Pre-calibration against the simulator's ground truth ---------------------------------------

TEST(FixturePreCalibration, RecoversInjectedOffsetsWithinTheTriggerNoise) {
  // Truth: a pogo whose reference block truly is at p while commanded at c reads, on a machine
  // shifted by s (which reads every point s short), delta = (p - c) - s.
  // Noise: each touch's latched readouts move by n ~ N(0, sigma_t^2) along its approach, so its
  // face point moves by n along the approach. x = (x_{x-} + x_{x+}) / 2 with x_{x-} = X- + n1
  // (approach +X) and x_{x+} = X+ - n2 (approach -X): x = X + (n1 - n2) / 2, sigma_x =
  // sigma_t / sqrt(2); likewise y; z = Z - n3 (approach -Z): sigma_z = sigma_t.
  std::mt19937_64 rng(401);
  const int cases = 100;
  std::vector<double> standardised;
  int passes = 0, fails = 0;
  for (int i = 0; i < cases; ++i) {
    const MachineConfig base = random_machine(rng, "m" + std::to_string(i % 5));
    const MachineConfig m = with_fixture(base, random_fixture(rng));
    const FixtureConfig& f = *m.fixture;
    sim::SimulatorConfig c = simulator_config(uniform(rng, 0.0005, 0.002), rng());
    const double size = uniform(rng, 0.0, 0.04);  // some cases pass, most fail
    for (int a = 0; a < 3; ++a) c.errors.machine_shift_mm[a] = uniform(rng, -0.005, 0.005);
    c.fixture.column_x.offset_mm = uniform(rng, -size, size);
    c.fixture.pogo_y.offset_mm = uniform(rng, -size, size);
    c.fixture.pogo_z.offset_mm = uniform(rng, -size, size);
    for (int col = 1; col <= f.columns(); ++col) {
      for (int row = 1; row <= f.rows(); ++row) {
        c.fixture.pogo_offsets_mm[pogo_label(col, row)] = Eigen::Vector3d(
            uniform(rng, -size, size), uniform(rng, -size, size), uniform(rng, -size, size));
      }
    }
    const sim::MachineSimulator machine(m, c);
    const sim::FixtureSimulator fixture = sim::FixtureSimulator::for_machine(m, c);
    const int k = std::uniform_int_distribution<int>(0, 9)(rng);
    const MeasurementSet set = run(machine, fixture, kPre, "pre-" + std::to_string(i), k);
    ASSERT_TRUE(set.error.empty()) << set.error;
    const CheckResult r = check_fixture_precalibration(set, m);
    ASSERT_NE(r.verdict, Verdict::Invalid) << r.reason;
    EXPECT_EQ(r.kind, kPre);
    EXPECT_EQ(r.request_id, set.request_id);

    const double sigma_t = c.trigger_noise_sigma_mm;
    const double sigma[3] = {sigma_t / std::sqrt(2.0), sigma_t / std::sqrt(2.0), sigma_t};
    constexpr double kBound = 5;  // per metric; the sample's statistics are checked below
    bool must_fail = false, must_pass = true;
    const auto placements = precalibration_configuration(f, k);
    ASSERT_EQ(r.metrics.size(), 3 * placements.size() + 3);
    for (const auto& p : placements) {
      const Eigen::Vector3d truth = fixture.true_delta_mm(p) - c.errors.machine_shift_mm;
      for (int a = 0; a < 3; ++a) {
        const Metric& mt = metric(r, fixture_checks::pogo_metric_name(p.pogo, a));
        EXPECT_NEAR(mt.value, truth[a], kBound * sigma[a]) << mt.name << " case " << i;
        standardised.push_back((mt.value - truth[a]) / sigma[a]);
        EXPECT_EQ(mt.unit, "mm");
        EXPECT_EQ(mt.upper, kTol);
        EXPECT_EQ(mt.pass, std::abs(mt.value) <= kTol);
        const double margin = kBound * sigma[a];
        if (std::abs(truth[a]) > kTol + margin) must_fail = true;
        if (std::abs(truth[a]) > kTol - margin) must_pass = false;
      }
    }
    if (must_fail) {
      EXPECT_EQ(r.verdict, Verdict::Fail) << "case " << i;
    }
    if (must_pass) {
      EXPECT_EQ(r.verdict, Verdict::Pass) << "case " << i << ": " << r.reason;
    }
    if (r.verdict == Verdict::Pass) {
      ++passes;
      EXPECT_FALSE(r.correction) << "case " << i;
      EXPECT_TRUE(r.likely_causes.empty());
      EXPECT_TRUE(r.reason.empty());
      continue;
    }
    ++fails;
    EXPECT_EQ(r.likely_causes, std::vector<std::string>{kZeroDrift});
    // The correction: every probed pogo's delta along each axis, as zero offsets.
    ASSERT_TRUE(r.correction) << "case " << i;
    EXPECT_EQ(r.correction->target, "fixture:" + f.fixture_id);
    ASSERT_EQ(r.correction->offsets.size(), 3 * placements.size());
    for (const NamedValue& offset : r.correction->offsets) {
      const auto name = parse_zero_offset_name(offset.name);
      ASSERT_TRUE(name) << offset.name;
      EXPECT_EQ(offset.unit, "mm");
      EXPECT_EQ(offset.value,
                metric(r, fixture_checks::pogo_metric_name(name->pogo, name->axis)).value);
    }
    EXPECT_NE(r.reason.find("metrics out of tolerance"), std::string::npos) << r.reason;
    EXPECT_NE(r.reason.find("zero offsets to fixture:" + f.fixture_id), std::string::npos)
        << r.reason;
  }
  EXPECT_GT(passes, 10);
  EXPECT_GT(fails, 30);
  const NoiseSpread spread = noise_spread(standardised);
  // Thousands of standard normals: the rms has a standard error below 0.02.
  EXPECT_NEAR(spread.rms, 1.0, 0.08);
  EXPECT_LE(spread.beyond_3, 0.0027 * spread.n + 4 * std::sqrt(0.0027 * spread.n) + 2);
}

TEST(FixturePreCalibration, WorstCaseSummariesAreTheSignedLargestDeltas) {
  const MachineConfig m = pm1_with_fixture();
  sim::SimulatorConfig c = simulator_config(0.0);
  c.fixture.pogo_offsets_mm["C2R3"] = Eigen::Vector3d(0.01, -0.04, 0.002);
  c.fixture.pogo_offsets_mm["C4R5"] = Eigen::Vector3d(-0.03, 0.02, -0.001);
  const sim::MachineSimulator machine(m, c);
  const auto fixture = sim::FixtureSimulator::for_machine(m, c);
  const CheckResult r = check_fixture_precalibration(run(machine, fixture, kPre, "worst", 0), m);
  ASSERT_EQ(r.verdict, Verdict::Fail) << r.reason;
  EXPECT_NEAR(metric(r, "fixture_max_dx_mm").value, -0.03, 1e-9);
  EXPECT_NEAR(metric(r, "fixture_max_dy_mm").value, -0.04, 1e-9);
  EXPECT_NEAR(metric(r, "fixture_max_dz_mm").value, 0.002, 1e-9);
  EXPECT_FALSE(metric(r, "fixture_max_dx_mm").pass);
  EXPECT_TRUE(metric(r, "fixture_max_dz_mm").pass);
  EXPECT_NEAR(metric(r, "pogo_C2R3_dy_mm").value, -0.04, 1e-9);
  EXPECT_FALSE(metric(r, "pogo_C2R3_dy_mm").pass);
  EXPECT_TRUE(metric(r, "pogo_C2R3_dx_mm").pass);
  EXPECT_NEAR(metric(r, "pogo_C1R1_dz_mm").value, 0, 1e-9);
  EXPECT_EQ(find_metric(r, "pogo_C1R2_dx_mm"), nullptr);  // even rows are not probed at k = 0
  EXPECT_NE(r.reason.find("4 of 39 metrics out of tolerance: pogo_C2R3_dy_mm = -0.04 mm is below "
                          "the lower limit -0.025 mm by 0.015 mm"),
            std::string::npos)
      << r.reason;
}

TEST(FixturePreCalibration, PerAxisTolerancesOverrideTheCommonOne) {
  MachineConfig m = pm1_with_fixture();
  m.tolerances["fixture_dz_mm"] = Tolerance{-0.1, 0.1};
  sim::SimulatorConfig c = simulator_config(0.0);
  c.fixture.pogo_z.offset_mm = 0.05;
  const sim::MachineSimulator machine(m, c);
  const auto fixture = sim::FixtureSimulator::for_machine(m, c);
  const MeasurementSet set = run(machine, fixture, kPre, "axes", 7);
  const CheckResult r = check_fixture_precalibration(set, m);
  EXPECT_EQ(r.verdict, Verdict::Pass) << r.reason;
  EXPECT_EQ(metric(r, "pogo_C1R2_dz_mm").upper, 0.1);
  EXPECT_EQ(metric(r, "pogo_C1R2_dx_mm").upper, kTol);
  m.tolerances["fixture_dz_mm"] = Tolerance{-0.01, 0.04};
  EXPECT_EQ(check_fixture_precalibration(set, m).verdict, Verdict::Fail);
}

// ---- The weekly sequence: pre-calibration, zero offsets, post-calibration --------------------

TEST(FixtureCalibration, PureOffsetsFailPreAndPassPostOnceZeroed) {
  std::mt19937_64 rng(402);
  for (int i = 0; i < 40; ++i) {
    const MachineConfig base = random_machine(rng);
    const MachineConfig m = with_fixture(base, random_fixture(rng));
    const FixtureConfig& f = *m.fixture;
    sim::SimulatorConfig c = simulator_config(uniform(rng, 0.0005, 0.002), rng());
    for (int a = 0; a < 3; ++a) c.errors.machine_shift_mm[a] = uniform(rng, -0.01, 0.01);
    c.fixture.column_x.offset_mm = uniform(rng, -0.2, 0.2);
    c.fixture.pogo_y.offset_mm = uniform(rng, -0.2, 0.2);
    c.fixture.pogo_z.offset_mm = (i % 2 ? 1 : -1) * uniform(rng, 0.05, 0.2);  // always out
    for (int col = 1; col <= f.columns(); ++col) {
      for (int row = 1; row <= f.rows(); ++row) {
        c.fixture.pogo_offsets_mm[pogo_label(col, row)] = Eigen::Vector3d(
            uniform(rng, -0.1, 0.1), uniform(rng, -0.1, 0.1), uniform(rng, -0.02, 0.02));
      }
    }
    const sim::MachineSimulator machine(m, c);
    sim::FixtureSimulator fixture = sim::FixtureSimulator::for_machine(m, c);
    const int k = std::uniform_int_distribution<int>(0, 9)(rng);
    const std::string id = "offsets-" + std::to_string(i);

    const CheckResult pre =
        check_fixture_precalibration(run(machine, fixture, kPre, id + "-pre", k), m);
    ASSERT_EQ(pre.verdict, Verdict::Fail) << pre.reason;
    ASSERT_TRUE(pre.correction);
    EXPECT_EQ(pre.likely_causes, std::vector<std::string>{kZeroDrift});

    // Without the offsets the post-calibration fails as well.
    const CheckResult unzeroed =
        check_fixture_postcalibration(run(machine, fixture, kPost, id + "-post0", k), m);
    ASSERT_EQ(unzeroed.verdict, Verdict::Fail) << unzeroed.reason;
    EXPECT_EQ(unzeroed.likely_causes.size(), 3u);

    fixture.apply_zero_offsets(*pre.correction);
    const CheckResult post =
        check_fixture_postcalibration(run(machine, fixture, kPost, id + "-post", k), m);
    ASSERT_EQ(post.verdict, Verdict::Pass) << "case " << i << ": " << post.reason;
    EXPECT_TRUE(post.likely_causes.empty());
    EXPECT_FALSE(post.correction);
    const std::size_t pogos = precalibration_configuration(f, k).size();
    EXPECT_EQ(post.metrics.size(), 3 * pogos * f.postcalibration_configuration_count() + 3);
    // The same rows at another plane pass too.
    const int other = (k + 1) % 5 + (k < 5 ? 0 : 5);
    const CheckResult again =
        check_fixture_precalibration(run(machine, fixture, kPre, id + "-again", other), m);
    EXPECT_EQ(again.verdict, Verdict::Pass) << again.reason;
  }
}

// The errors a case injects after its pre-calibration zero offsets, and the cause expected first.
struct PostCase {
  std::string name;
  std::function<void(std::mt19937_64&, sim::FixtureErrors&)> inject;
  std::string first_cause;
};

double signed_uniform(std::mt19937_64& rng, double lo, double hi) {
  return (uniform(rng, 0, 1) < 0.5 ? -1 : 1) * uniform(rng, lo, hi);
}

void run_post_cases(const std::vector<PostCase>& kinds, std::uint64_t seed, int cases) {
  std::mt19937_64 rng(seed);
  int failed = 0;
  for (int i = 0; i < cases; ++i) {
    const PostCase& kind = kinds[static_cast<std::size_t>(i) % kinds.size()];
    const MachineConfig m = with_fixture(random_machine(rng), pm1_fixture());
    sim::SimulatorConfig c = simulator_config(uniform(rng, 0.0005, 0.0015), rng());
    for (int a = 0; a < 3; ++a) c.errors.machine_shift_mm[a] = uniform(rng, -0.01, 0.01);
    c.fixture.column_x.offset_mm = uniform(rng, -0.05, 0.05);  // some drift on top
    c.fixture.pogo_z.offset_mm = uniform(rng, -0.05, 0.05);
    kind.inject(rng, c.fixture);
    const sim::MachineSimulator machine(m, c);
    sim::FixtureSimulator fixture = sim::FixtureSimulator::for_machine(m, c);
    const int k = std::uniform_int_distribution<int>(0, 9)(rng);
    const std::string id = kind.name + "-" + std::to_string(i);
    const std::string context =
        "case " + std::to_string(i) + " (" + kind.name + ", k " + std::to_string(k) + ")";

    const CheckResult pre =
        check_fixture_precalibration(run(machine, fixture, kPre, id + "-pre", k), m);
    ASSERT_NE(pre.verdict, Verdict::Invalid) << context << ": " << pre.reason;
    if (pre.correction) fixture.apply_zero_offsets(*pre.correction);
    const CheckResult post =
        check_fixture_postcalibration(run(machine, fixture, kPost, id + "-post", k), m);
    ASSERT_NE(post.verdict, Verdict::Invalid) << context << ": " << post.reason;
    // Must fail when a perfect probe would see a delta beyond the tolerance by more than the
    // noise of the pre- and post-calibration touches together (sqrt 2 sigma_t, 6 of them).
    const double margin = 6 * std::sqrt(2.0) * c.trigger_noise_sigma_mm;
    if (worst_true_post_delta(fixture, k, c.errors.machine_shift_mm) > kTol + margin) {
      EXPECT_EQ(post.verdict, Verdict::Fail) << context;
    }
    if (post.verdict != Verdict::Fail) continue;
    ++failed;
    expect_all_three_causes(post, kind.first_cause, context);
    EXPECT_NE(post.reason.find("fit of the deltas against the commanded positions"),
              std::string::npos);
  }
  // The injected errors are large enough to fail nearly always.
  EXPECT_GE(failed, cases * 9 / 10);
}

TEST(FixtureCalibration, ScaleOrNonlinearityFailsPostWithNonlinearityFirst) {
  const std::vector<PostCase> kinds = {
      {"x-scale", [](auto& rng, auto& e) { e.column_x.scale_ppm = signed_uniform(rng, 300, 600); },
       kNonlinear},
      {"y-scale", [](auto& rng, auto& e) { e.pogo_y.scale_ppm = signed_uniform(rng, 500, 900); },
       kNonlinear},
      {"z-scale", [](auto& rng, auto& e) { e.pogo_z.scale_ppm = signed_uniform(rng, 300, 600); },
       kNonlinear},
      {"x-curvature",
       [](auto& rng, auto& e) { e.column_x.curvature_um_per_m2 = signed_uniform(rng, 80, 150); },
       kNonlinear},
      {"z-curvature",
       [](auto& rng, auto& e) { e.pogo_z.curvature_um_per_m2 = signed_uniform(rng, 400, 800); },
       kNonlinear},
      {"y-sine",
       [](auto& rng, auto& e) {
         e.pogo_y.sine_amplitude_mm = signed_uniform(rng, 0.04, 0.08);
         e.pogo_y.sine_period_mm = uniform(rng, 300, 600);
         e.pogo_y.sine_phase_rad = uniform(rng, -3.1, 3.1);
       },
       kNonlinear},
      {"x-sine",
       [](auto& rng, auto& e) {
         e.column_x.sine_amplitude_mm = signed_uniform(rng, 0.04, 0.08);
         e.column_x.sine_period_mm = uniform(rng, 400, 900);
         e.column_x.sine_phase_rad = uniform(rng, -3.1, 3.1);
       },
       kNonlinear},
  };
  run_post_cases(kinds, 403, 70);
}

TEST(FixtureCalibration, MisalignedFixtureFailsPostWithMisalignmentFirst) {
  const std::vector<PostCase> kinds = {
      {"z-tilt-x",
       [](auto& rng, auto& e) {
         e.pogo_z.misalignment_rad.x() = signed_uniform(rng, 300e-6, 600e-6);
       },
       kMisaligned},
      {"z-tilt-y",
       [](auto& rng, auto& e) {
         e.pogo_z.misalignment_rad.y() = signed_uniform(rng, 300e-6, 600e-6);
       },
       kMisaligned},
      {"x-travel-y",
       [](auto& rng, auto& e) {
         e.column_x.misalignment_rad.y() = signed_uniform(rng, 300e-6, 500e-6);
       },
       kMisaligned},
      {"x-travel-z",
       [](auto& rng, auto& e) {
         e.column_x.misalignment_rad.z() = signed_uniform(rng, 300e-6, 500e-6);
       },
       kMisaligned},
      {"y-travel-x",
       [](auto& rng, auto& e) {
         e.pogo_y.misalignment_rad.x() = signed_uniform(rng, 600e-6, 1000e-6);
       },
       kMisaligned},
      {"y-travel-z",
       [](auto& rng, auto& e) {
         e.pogo_y.misalignment_rad.z() = signed_uniform(rng, 600e-6, 1000e-6);
       },
       kMisaligned},
  };
  run_post_cases(kinds, 404, 60);
}

TEST(FixtureCalibration, ScatteredErrorsFailPostWithWearFirst) {
  const std::vector<PostCase> kinds = {
      {"wear", [](auto& rng, auto& e) { e.wear_sigma_mm = uniform(rng, 0.02, 0.04); }, kWear},
  };
  run_post_cases(kinds, 405, 30);
}

TEST(FixtureCalibration, PerfectFixturePassesBoth) {
  std::mt19937_64 rng(406);
  for (int i = 0; i < 30; ++i) {
    const MachineConfig base = random_machine(rng);
    const MachineConfig m = with_fixture(base, random_fixture(rng));
    const sim::SimulatorConfig c = simulator_config(uniform(rng, 0.0005, 0.002), rng());
    const sim::MachineSimulator machine(m, c);
    const auto fixture = sim::FixtureSimulator::for_machine(m, c);
    const int k = std::uniform_int_distribution<int>(0, 9)(rng);
    const std::string id = "perfect-" + std::to_string(i);
    const CheckResult pre =
        check_fixture_precalibration(run(machine, fixture, kPre, id + "-pre", k), m);
    EXPECT_EQ(pre.verdict, Verdict::Pass) << pre.reason;
    EXPECT_FALSE(pre.correction);
    EXPECT_TRUE(pre.reason.empty());
    for (const Metric& mt : pre.metrics) EXPECT_TRUE(mt.pass) << mt.name;
    // Post-calibration of the same rows, and of every row.
    for (const std::optional<int> rows : {std::optional<int>(k), std::optional<int>()}) {
      const CheckResult post =
          check_fixture_postcalibration(run(machine, fixture, kPost, id + "-post", rows), m);
      EXPECT_EQ(post.verdict, Verdict::Pass) << post.reason;
      EXPECT_TRUE(post.likely_causes.empty());
      const std::size_t pogos =
          rows ? precalibration_configuration(*m.fixture, k).size()
               : static_cast<std::size_t>(m.fixture->columns() * m.fixture->rows());
      EXPECT_EQ(post.metrics.size(), 3 * pogos * 12 + 3);
      EXPECT_NE(
          find_metric(post, "cfg11_pogo_C1R" + std::string(rows && k >= 5 ? "2" : "1") + "_dz_mm"),
          nullptr);
    }
  }
}

TEST(FixtureCalibration, PostFailureReportsTheFittedMisalignment) {
  // Noise-free, the Z extension tilted 400 urad towards +X: after the zero offsets at plane 0,
  //   dx = 400e-6 (z - z_0), at 6 in and 18 in: 0.061 and 0.183 mm.
  MachineConfig m = pm1_with_fixture();
  m.tolerances["fixture_fit_dx_per_z_urad"] = Tolerance{-100, 100};
  m.tolerances["fixture_fit_dz_per_z_ppm"] = Tolerance{-100, 100};
  m.tolerances["fixture_fit_systematic_residual_mm"] = Tolerance{0, 0.01};
  sim::SimulatorConfig c = simulator_config(0.0);
  c.fixture.pogo_z.misalignment_rad.x() = 400e-6;
  c.fixture.pogo_z.offset_mm = 0.04;
  const sim::MachineSimulator machine(m, c);
  auto fixture = sim::FixtureSimulator::for_machine(m, c);
  const CheckResult pre =
      check_fixture_precalibration(run(machine, fixture, kPre, "tilt-pre", 0), m);
  ASSERT_EQ(pre.verdict, Verdict::Fail);
  fixture.apply_zero_offsets(*pre.correction);
  const CheckResult post =
      check_fixture_postcalibration(run(machine, fixture, kPost, "tilt-post", 0), m);
  ASSERT_EQ(post.verdict, Verdict::Fail);
  EXPECT_EQ(post.likely_causes, (std::vector<std::string>{kMisaligned, kNonlinear, kWear}));
  // (less 400e-6 x 0.04 mm: the X zero offset took the tilt of the 0.04 mm Z offset at plane 0)
  EXPECT_NEAR(metric(post, "cfg0_pogo_C1R1_dx_mm").value, 400e-6 * (6 * 25.4 - 0.04), 1e-9);
  EXPECT_NEAR(metric(post, "cfg11_pogo_C4R5_dx_mm").value, 400e-6 * (18 * 25.4 - 0.04), 1e-9);
  EXPECT_NEAR(metric(post, "fixture_max_dx_mm").value, 400e-6 * (18 * 25.4 - 0.04), 1e-9);
  EXPECT_NEAR(metric(post, "fixture_fit_dx_per_z_urad").value, 400, 1e-3);
  EXPECT_FALSE(metric(post, "fixture_fit_dx_per_z_urad").pass);
  EXPECT_NEAR(metric(post, "fixture_fit_dz_per_z_ppm").value, 0, 1e-3);
  EXPECT_TRUE(metric(post, "fixture_fit_dz_per_z_ppm").pass);
  EXPECT_TRUE(metric(post, "fixture_fit_systematic_residual_mm").pass);
  EXPECT_EQ(find_metric(post, "fixture_fit_dy_per_x_urad"), nullptr);  // not configured
  EXPECT_NE(
      post.reason.find("significant: dx/dZ = 400 urad moves dx by 0.12192 mm over the 304.8 mm "
                       "of Z travel probed (misalignment)"),
      std::string::npos)
      << post.reason;
  EXPECT_NE(post.reason.find("144 points, 12 pogos"), std::string::npos) << post.reason;
}

// ---- The fit on synthetic data ------------------------------------------------------------------

std::vector<PogoDelta> factorial_points(
    std::mt19937_64& rng, const Eigen::Matrix3d& M,
    const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& extra, double noise) {
  std::vector<PogoDelta> points;
  std::normal_distribution<double> normal(0, 1);
  for (int p = 0; p < 10; ++p) {
    const Eigen::Vector3d home(1000 + 500 * (p % 5), 200 + 300 * (p / 5), 0);
    const Eigen::Vector3d intercept(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    int j = 0;
    for (double z : {150.0, 450.0}) {
      for (double dy : {-75.0, 75.0}) {
        for (double dx : {-150.0, 0.0, 150.0}) {
          const Eigen::Vector3d c = home + Eigen::Vector3d(dx, dy, z);
          Eigen::Vector3d d = M * c + intercept + extra(c);
          for (int a = 0; a < 3; ++a) d[a] += noise * normal(rng);
          points.push_back({"P" + std::to_string(p), j++, c, d});
        }
      }
    }
  }
  return points;
}

TEST(FixtureDeltaFit, RecoversSlopesWithPerPogoIntercepts) {
  std::mt19937_64 rng(407);
  for (int i = 0; i < 50; ++i) {
    Eigen::Matrix3d M;
    for (int a = 0; a < 9; ++a) M(a / 3, a % 3) = uniform(rng, -1e-3, 1e-3);
    const auto points = factorial_points(
        rng, M, [](const Eigen::Vector3d&) { return Eigen::Vector3d::Zero(); }, 0);
    const FixtureDeltaFit fit = fit_fixture_deltas(points);
    ASSERT_TRUE(fit.error.empty()) << fit.error;
    EXPECT_EQ(fit.points, 120);
    EXPECT_EQ(fit.pogos, 10);
    EXPECT_EQ(fit.degrees_of_freedom, 120 - 10 - 3);
    EXPECT_LT((fit.slope - M).cwiseAbs().maxCoeff(), 1e-12) << i;
    EXPECT_TRUE(fit.span_mm.isApprox(Eigen::Vector3d(300, 150, 300)));
    EXPECT_LT(fit.residual_rms_mm.maxCoeff(), 1e-9);
    for (bool f : fit.fitted) EXPECT_TRUE(f);
  }
}

TEST(FixtureDeltaFit, StandardErrorsMatchTheScatterOfTheSlopes) {
  // 200 noisy repetitions: the slopes scatter about the truth as their standard errors say.
  std::mt19937_64 rng(408);
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  M(0, 2) = 3e-4;
  double sum_sq = 0;
  int n = 0;
  for (int i = 0; i < 200; ++i) {
    const auto points = factorial_points(
        rng, M, [](const Eigen::Vector3d&) { return Eigen::Vector3d::Zero(); }, 0.002);
    const FixtureDeltaFit fit = fit_fixture_deltas(points);
    for (int a = 0; a < 9; ++a) {
      const double z =
          (fit.slope(a / 3, a % 3) - M(a / 3, a % 3)) / fit.slope_standard_error(a / 3, a % 3);
      sum_sq += z * z;
      ++n;
    }
    // Noise only: no systematic residual along any axis.
    EXPECT_LT(fit.systematic_fraction.maxCoeff(), 0.5);
    EXPECT_NEAR(fit.residual_rms_mm.mean(), 0.002 * std::sqrt(107.0 / 120), 0.0006);
  }
  EXPECT_NEAR(std::sqrt(sum_sq / n), 1.0, 0.08);
}

TEST(FixtureDeltaFit, ResidualSharedAlongOneAxisIsSystematic) {
  std::mt19937_64 rng(409);
  // dx follows a sine of the commanded X: a nonlinearity of the X travel.
  const auto points = factorial_points(
      rng, Eigen::Matrix3d::Zero(),
      [](const Eigen::Vector3d& c) { return Eigen::Vector3d(0.03 * std::sin(c.x() / 90), 0, 0); },
      0.0005);
  const FixtureDeltaFit fit = fit_fixture_deltas(points);
  ASSERT_TRUE(fit.error.empty());
  EXPECT_EQ(fit.systematic_axis[0], 0);
  EXPECT_GT(fit.systematic_fraction[0], 0.9);
  EXPECT_GT(fit.systematic_residual_mm[0], 0.01);
  EXPECT_LT(fit.systematic_residual_mm[1], 0.002);
}

TEST(FixtureDeltaFit, DegenerateDesignsSayWhy) {
  std::vector<PogoDelta> one_configuration = {{"P1", 0, {1, 2, 3}, {0, 0, 0}},
                                              {"P2", 0, {5, 2, 3}, {1, 0, 0}}};
  EXPECT_NE(fit_fixture_deltas(one_configuration).error.find("do not change within any pogo"),
            std::string::npos);
  EXPECT_NE(fit_fixture_deltas({}).error.find("no points"), std::string::npos);
  // X and Y always move together: their slopes cannot be told apart.
  std::vector<PogoDelta> together;
  for (int j = 0; j < 4; ++j) together.push_back({"P1", j, {10.0 * j, 10.0 * j, 0}, {0, 0, 0}});
  EXPECT_NE(fit_fixture_deltas(together).error.find("do not change independently"),
            std::string::npos);
  // Only Z varies: only the Z column is fitted.
  std::vector<PogoDelta> z_only;
  for (int j = 0; j < 4; ++j) z_only.push_back({"P1", j, {0, 0, 100.0 * j}, {0.001 * j, 0, 0}});
  const FixtureDeltaFit fit = fit_fixture_deltas(z_only);
  EXPECT_TRUE(fit.error.empty()) << fit.error;
  EXPECT_FALSE(fit.fitted[0]);
  EXPECT_TRUE(fit.fitted[2]);
  EXPECT_NEAR(fit.slope(0, 2), 1e-5, 1e-15);
}

// ---- Input that cannot support a verdict --------------------------------------------------------

struct InvalidCase {
  std::string name;
  CheckKind kind;
  std::function<void(MeasurementSet&, MachineConfig&)> spoil;
  std::string reason_must_contain;
};

std::size_t index_of(const MeasurementSet& s, const std::string& feature) {
  for (std::size_t i = 0; i < s.touches.size(); ++i) {
    if (s.touches[i].feature == feature) return i;
  }
  throw std::runtime_error("no touch " + feature);
}

TEST(FixtureChecks, InvalidInputsGiveInvalidWithAReasonNamingTheField) {
  using S = MeasurementSet;
  using M = MachineConfig;
  const std::vector<InvalidCase> cases = {
      {"empty set", kPre, [](S& s, M&) { s.touches.clear(); }, "MeasurementSet.touches is empty"},
      {"instrument error", kPost, [](S& s, M&) { s.error = "probe alarm: x"; },
       "MeasurementSet.error: probe alarm: x"},
      {"wrong kind", kPre, [](S& s, M&) { s.kind = kPost; },
       "MeasurementSet.kind = 'fixture_postcal': the fixture pre-calibration needs "
       "'fixture_precal'"},
      {"no fixture", kPre, [](S&, M& m) { m.fixture.reset(); },
       "machine 'pm1' (test:pm1): has no `fixture:` section"},
      {"no tolerance", kPost, [](S&, M& m) { m.tolerances.erase("fixture_delta_mm"); },
       "tolerances.fixture_dx_mm (or tolerances.fixture_delta_mm) is not configured"},
      {"missing configuration", kPre, [](S& s, M&) { s.parameters.clear(); },
       "MeasurementSet.parameters: no 'fixture_configuration'"},
      {"configuration out of range", kPre, [](S& s, M&) { s.parameters[0].value = 10; },
       "MeasurementSet.parameters['fixture_configuration'] = 10 is not an integer in 0..9"},
      {"fractional configuration", kPost, [](S& s, M&) { s.parameters[0].value = 2.5; },
       "['fixture_configuration'] = 2.5 is not an integer"},
      {"NaN configuration", kPre, [](S& s, M&) { s.parameters[0].value = kNaN; },
       "['fixture_configuration'] = nan"},
      {"garbled feature", kPre, [](S& s, M&) { s.touches[3].feature = "pogo:C1R1:x-"; },
       "MeasurementSet.touches[3].feature = 'pogo:C1R1:x-': expected 'pogo:<C#R#>:cfg<index>:"},
      {"unknown pogo", kPre, [](S& s, M&) { s.touches[0].feature = "pogo:C9R1:cfg3:top"; },
       "MeasurementSet.touches[0].feature = 'pogo:C9R1:cfg3:top': fixture 'UHF1' has no pogo C9R1 "
       "(C1R1 to C4R6)"},
      {"other configuration", kPre, [](S& s, M&) { s.touches[0].feature = "pogo:C1R1:cfg2:top"; },
       "configuration 2, but the set is of pre-calibration configuration 3"},
      {"row not probed", kPre, [](S& s, M&) { s.touches[0].feature = "pogo:C1R2:cfg3:top"; },
       "pogo C1R2 is not probed in the fixture pre-calibration configuration 3 (odd rows)"},
      {"post configuration out of range", kPost,
       [](S& s, M&) { s.touches[0].feature = "pogo:C1R1:cfg12:top"; },
       "configuration 12 is not a post-calibration configuration of fixture 'UHF1' (0..11)"},
      {"post row not probed", kPost, [](S& s, M&) { s.touches[0].feature = "pogo:C1R4:cfg0:top"; },
       "pogo C1R4 is not probed in the fixture post-calibration configuration 0 (odd rows)"},
      {"missing face", kPre,
       [](S& s, M&) { s.touches.erase(s.touches.begin() + index_of(s, "pogo:C3R5:cfg3:y+")); },
       "MeasurementSet.touches: pogo C3R5 of the fixture pre-calibration configuration 3 has no "
       "'y+' touch"},
      {"missing pogo", kPost,
       [](S& s, M&) {
         const std::size_t at = index_of(s, "pogo:C2R3:cfg7:top");
         s.touches.erase(s.touches.begin() + at, s.touches.begin() + at + 5);
       },
       "pogo C2R3 of the fixture post-calibration configuration 7 has no 'top' touch"},
      {"NaN readout", kPre, [](S& s, M&) { s.touches[7].axes.y_mm = kNaN; },
       "MeasurementSet.touches[7].axes.y_mm = nan is not finite"},
      {"infinite W", kPost, [](S& s, M&) { s.touches[2].axes.w_mm = INFINITY; },
       "MeasurementSet.touches[2].axes.w_mm = inf"},
      {"head turned", kPre, [](S& s, M&) { s.touches[4].axes.c_rad = 0.5; },
       "MeasurementSet.touches[4].axes: head at A = 0 rad, C = 0.5 rad; the fixture is probed with "
       "the head at home"},
      {"head tilted", kPost, [](S& s, M&) { s.touches[1].axes.a_rad = -1e-5; },
       "touches[1].axes: head at A = -1e-05 rad"},
      {"approach reversed", kPre,
       [](S& s, M&) { s.touches[1].approach = Eigen::Vector3d(-1, 0, 0); },
       "MeasurementSet.touches[1].approach = (-1, 0, 0): a 'x-' touch must approach along (1, 0, "
       "0)"},
      {"approach not unit", kPre, [](S& s, M&) { s.touches[0].approach *= 3; },
       "MeasurementSet.touches[0].approach = (0, 0, -3) has length 3"},
      {"touch off the block", kPre,
       [](S& s, M&) { s.touches[index_of(s, "pogo:C2R1:cfg3:x+")].axes.x_mm += 5; },
       "pogo C2R1 of the fixture pre-calibration configuration 3: its 'x-' and 'x+' faces are 105 "
       "mm apart"},
  };
  for (const auto& c : cases) {
    MachineConfig m = pm1_with_fixture();
    const sim::MachineSimulator machine(m, simulator_config(0.0));
    const auto fixture = sim::FixtureSimulator::for_machine(m, sim::SimulatorConfig{});
    MeasurementSet set = run(machine, fixture, c.kind, "invalid", 3);
    const auto check =
        c.kind == kPre ? check_fixture_precalibration : check_fixture_postcalibration;
    ASSERT_EQ(check(set, m).verdict, Verdict::Pass) << c.name;
    c.spoil(set, m);
    CheckResult r;
    ASSERT_NO_THROW(r = check(set, m)) << c.name;
    EXPECT_EQ(r.verdict, Verdict::Invalid) << c.name << ": " << r.reason;
    EXPECT_NE(r.reason.find(c.reason_must_contain), std::string::npos)
        << c.name << ": reason '" << r.reason << "' lacks '" << c.reason_must_contain << "'";
    EXPECT_TRUE(r.metrics.empty()) << c.name;
    EXPECT_FALSE(r.correction) << c.name;
  }
}

TEST(FixtureChecks, RandomGarbageIsNeverPass) {
  std::mt19937_64 rng(410);
  const MachineConfig m = pm1_with_fixture();
  const sim::MachineSimulator machine(m, simulator_config(0.001));
  const auto fixture = sim::FixtureSimulator::for_machine(m, sim::SimulatorConfig{});
  const MeasurementSet clean = run(machine, fixture, kPre, "garbage", 6);
  const double poison[] = {kNaN, INFINITY, -INFINITY};
  for (int i = 0; i < 300; ++i) {
    MeasurementSet set = clean;
    spoil_random_field(set, rng, poison[i % 3]);
    CheckResult r;
    ASSERT_NO_THROW(r = check_fixture_precalibration(set, m));
    EXPECT_EQ(r.verdict, Verdict::Invalid) << r.reason;
    EXPECT_NE(r.reason.find("MeasurementSet.touches["), std::string::npos) << r.reason;
  }
}

}  // namespace
}  // namespace ncqual::solver

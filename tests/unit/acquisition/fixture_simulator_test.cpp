// SPDX-License-Identifier: Apache-2.0
#include "ncqual/sim/fixture_simulator.hpp"

#include "ncqual/common/kinematics.hpp"
#include "ncqual/common/units.hpp"
#include "test_fixtures.hpp"
#include "test_machines.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <string>
#include <tuple>

namespace ncqual::sim {
namespace {

using namespace testing;  // test_machines.hpp, test_fixtures.hpp

constexpr CheckKind kPre = CheckKind::FixturePreCalibration;
constexpr CheckKind kPost = CheckKind::FixturePostCalibration;

MachineConfig random_machine_with_fixture(std::mt19937_64& rng) {
  MachineConfig m = random_machine(rng);
  m.fixture = random_fixture(rng);
  return m;
}

FixtureAxisErrors random_axis_errors(std::mt19937_64& rng, int axis) {
  FixtureAxisErrors e;
  e.offset_mm = uniform(rng, -0.3, 0.3);
  e.scale_ppm = uniform(rng, -100, 100);
  e.curvature_um_per_m2 = uniform(rng, -20, 20);
  e.sine_amplitude_mm = uniform(rng, -0.02, 0.02);
  e.sine_period_mm = uniform(rng, 200, 800);
  e.sine_phase_rad = uniform(rng, -3, 3);
  for (int j = 0; j < 3; ++j) {
    if (j != axis) e.misalignment_rad[j] = uniform(rng, -3e-4, 3e-4);
  }
  return e;
}

FixtureErrors random_fixture_errors(std::mt19937_64& rng, const FixtureConfig& f) {
  FixtureErrors e;
  e.column_x = random_axis_errors(rng, 0);
  e.pogo_y = random_axis_errors(rng, 1);
  e.pogo_z = random_axis_errors(rng, 2);
  for (int c = 1; c <= f.columns(); ++c) {
    for (int r = 1; r <= f.rows(); ++r) {
      if (uniform(rng, 0, 1) < 0.5) {
        e.pogo_offsets_mm[pogo_label(c, r)] = Eigen::Vector3d(
            uniform(rng, -0.3, 0.3), uniform(rng, -0.3, 0.3), uniform(rng, -0.3, 0.3));
      }
    }
  }
  return e;
}

// The point of the face a touch met, by the nominal kinematics: p = b + r u.
Eigen::Vector3d face_point(const Touch& t, const ProbeGeometry& nominal) {
  return stylus_ball_centre(t.axes, nominal) + nominal.ball_radius_mm * t.approach;
}

int normal_axis(PogoFace face) {
  const Eigen::Vector3d n = outward_normal(face);
  return std::abs(n.x()) > 0.5 ? 0 : std::abs(n.y()) > 0.5 ? 1 : 2;
}

// The placement of (configuration, pogo) in what the simulator was asked.
std::map<std::pair<int, std::string>, PogoPlacement> placements_of(const FixtureConfig& f,
                                                                   CheckKind kind, int k) {
  std::map<std::pair<int, std::string>, PogoPlacement> out;
  if (kind == kPre) {
    for (const auto& p : precalibration_configuration(f, k)) out[{k, p.pogo}] = p;
  } else {
    const auto configurations = postcalibration_configurations(f, precalibration_rows(f, k));
    for (std::size_t j = 0; j < configurations.size(); ++j) {
      for (const auto& p : configurations[j]) out[{static_cast<int>(j), p.pogo}] = p;
    }
  }
  return out;
}

// ---- Configurations ---------------------------------------------------------------------------

TEST(FixtureConfigurations, PreCalibrationRotatesOddAndEvenRowsThroughThePlanes) {
  const FixtureConfig f = pm1_fixture();
  ASSERT_EQ(f.precalibration_configuration_count(), 10);
  for (int k = 0; k < 10; ++k) {
    const auto placements = precalibration_configuration(f, k);
    ASSERT_EQ(placements.size(), 12u) << k;  // 4 columns x 3 alternate rows
    for (const auto& p : placements) {
      EXPECT_EQ(p.row % 2, k < 5 ? 1 : 0) << "k " << k << " " << p.pogo;
      EXPECT_EQ(p.pogo, pogo_label(p.column, p.row));
      EXPECT_DOUBLE_EQ(p.commanded_mm.x(),
                       f.column_home_x_mm[static_cast<std::size_t>(p.column - 1)]);
      EXPECT_DOUBLE_EQ(p.commanded_mm.y(), f.row_home_y_mm[static_cast<std::size_t>(p.row - 1)]);
      EXPECT_DOUBLE_EQ(p.commanded_mm.z(), units::inch_to_mm(6.0 * (k % 5)));
    }
    EXPECT_EQ(placements.front().pogo, k < 5 ? "C1R1" : "C1R2");
    EXPECT_EQ(placements.back().pogo, k < 5 ? "C4R5" : "C4R6");
  }
  EXPECT_THROW(precalibration_configuration(f, -1), std::out_of_range);
  try {
    precalibration_configuration(f, 10);
    FAIL() << "accepted configuration 10";
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("configuration 10 is not in 0..9"), std::string::npos)
        << e.what();
  }
}

TEST(FixtureConfigurations, PostCalibrationCoversTwoZTwoYThreeX) {
  const FixtureConfig f = pm1_fixture();
  ASSERT_EQ(f.postcalibration_configuration_count(), 12);
  const auto all = postcalibration_configurations(f);
  const auto odd = postcalibration_configurations(f, RowSelection::Odd);
  const auto even = postcalibration_configurations(f, RowSelection::Even);
  ASSERT_EQ(all.size(), 12u);
  ASSERT_EQ(odd.size(), 12u);
  std::set<std::tuple<double, double, double>> offsets;
  for (int iz = 0; iz < 2; ++iz) {
    for (int iy = 0; iy < 2; ++iy) {
      for (int ix = 0; ix < 3; ++ix) {
        const std::size_t j = static_cast<std::size_t>((iz * 2 + iy) * 3 + ix);
        ASSERT_EQ(all[j].size(), 24u);
        EXPECT_EQ(odd[j].size(), 12u);
        EXPECT_EQ(even[j].size(), 12u);
        for (const auto& p : all[j]) {
          EXPECT_DOUBLE_EQ(p.commanded_mm.z(),
                           f.postcalibration.z_mm[static_cast<std::size_t>(iz)]);
          EXPECT_DOUBLE_EQ(
              p.commanded_mm.y() - f.row_home_y_mm[static_cast<std::size_t>(p.row - 1)],
              f.postcalibration.y_offsets_mm[static_cast<std::size_t>(iy)]);
          EXPECT_DOUBLE_EQ(
              p.commanded_mm.x() - f.column_home_x_mm[static_cast<std::size_t>(p.column - 1)],
              f.postcalibration.x_offsets_mm[static_cast<std::size_t>(ix)]);
        }
        for (const auto& p : odd[j]) EXPECT_EQ(p.row % 2, 1);
        for (const auto& p : even[j]) EXPECT_EQ(p.row % 2, 0);
        offsets.insert(
            {all[j][0].commanded_mm.x(), all[j][0].commanded_mm.y(), all[j][0].commanded_mm.z()});
      }
    }
  }
  EXPECT_EQ(offsets.size(), 12u);  // every configuration differs
}

// ---- The probing program on a perfect fixture ---------------------------------------------------

TEST(FixtureSimulator, PerfectFixtureTouchesLandOnTheCommandedFaces) {
  std::mt19937_64 rng(301);
  for (int i = 0; i < 40; ++i) {
    const MachineConfig m = random_machine_with_fixture(rng);
    const FixtureConfig& f = *m.fixture;
    const MachineSimulator machine(m, simulator_config(0.0));
    const FixtureSimulator fixture(f, FixtureErrors{});
    const int k = std::uniform_int_distribution<int>(0, 9)(rng);
    const CheckKind kind = i % 2 ? kPost : kPre;
    const CheckRequest req = fixture_request(m.machine_id, "perfect-" + std::to_string(i), kind, k);
    const MeasurementSet set = perform_fixture_check(machine, fixture, req, 4242);
    ASSERT_TRUE(set.error.empty()) << set.error;
    EXPECT_EQ(set.machine_id, m.machine_id);
    EXPECT_EQ(set.request_id, req.request_id);
    EXPECT_EQ(set.kind, kind);
    EXPECT_EQ(set.instrument, "touch_probe");
    EXPECT_EQ(set.frame, "machine");
    EXPECT_EQ(set.time_ns, 4242);
    ASSERT_EQ(set.parameters.size(), 1u);
    EXPECT_EQ(set.parameters[0].name, "fixture_configuration");
    EXPECT_EQ(set.parameters[0].value, k);

    const auto placements = placements_of(f, kind, k);
    ASSERT_EQ(set.touches.size(), 5 * placements.size());
    std::set<std::string> features;
    const double r = m.probe.ball_radius_mm;
    for (const Touch& t : set.touches) {
      features.insert(t.feature);
      const auto feature = parse_pogo_touch_feature(t.feature);
      ASSERT_TRUE(feature) << t.feature;
      if (kind == kPre) {
        EXPECT_EQ(feature->configuration, k);
      }
      const auto it = placements.find({feature->configuration, feature->pogo});
      ASSERT_NE(it, placements.end()) << t.feature;
      EXPECT_EQ(t.axes.a_rad, 0);
      EXPECT_EQ(t.axes.c_rad, 0);
      EXPECT_EQ(t.axes.w_mm, 0);
      const Eigen::Vector3d n = outward_normal(feature->face);
      EXPECT_NEAR((t.approach + n).norm(), 0, 1e-15) << t.feature;
      // The nominal ball centre sits one radius off the commanded face, on its outside.
      const Eigen::Vector3d face =
          f.to_machine(it->second.commanded_mm) + face_offset(f, feature->face);
      const Eigen::Vector3d b = stylus_ball_centre(t.axes, m.probe);
      EXPECT_NEAR((b - (face + r * n)).norm(), 0, 1e-9) << t.feature;
    }
    EXPECT_EQ(features.size(), set.touches.size());  // no feature twice
  }
}

TEST(FixtureSimulator, TouchesFollowTheTrueFixtureAndTheTrueMachine) {
  // Noise-free: each touch's face point by the nominal kinematics equals the true face less the
  // machine's shift (a machine shifted by s reads every point s short).
  std::mt19937_64 rng(302);
  for (int i = 0; i < 60; ++i) {
    const MachineConfig m = random_machine_with_fixture(rng);
    const FixtureConfig& f = *m.fixture;
    SimulatorConfig c = simulator_config(0.0, rng());
    for (int a = 0; a < 3; ++a) c.errors.machine_shift_mm[a] = uniform(rng, -0.5, 0.5);
    const MachineSimulator machine(m, c);
    FixtureSimulator fixture(f, random_fixture_errors(rng, f));
    const int k = std::uniform_int_distribution<int>(0, 9)(rng);
    if (i % 3 == 0) {
      // Some zero offsets in force: the actuators are driven to c - o.
      Correction zero{"fixture:" + f.fixture_id, {}};
      for (const auto& p : precalibration_configuration(f, k)) {
        for (int a = 0; a < 3; ++a)
          zero.offsets.push_back({zero_offset_name(p.pogo, a), uniform(rng, -0.2, 0.2), "mm"});
      }
      fixture.apply_zero_offsets(zero);
    }
    const CheckKind kind = i % 2 ? kPost : kPre;
    const MeasurementSet set = perform_fixture_check(
        machine, fixture, fixture_request(m.machine_id, "true-" + std::to_string(i), kind, k), 1);
    ASSERT_TRUE(set.error.empty()) << set.error;
    const auto placements = placements_of(f, kind, k);
    ASSERT_EQ(set.touches.size(), 5 * placements.size());
    for (const Touch& t : set.touches) {
      const auto feature = parse_pogo_touch_feature(t.feature);
      ASSERT_TRUE(feature);
      const PogoPlacement& placement = placements.at({feature->configuration, feature->pogo});
      const Eigen::Vector3d truth = fixture.true_reference_point_mm(placement) +
                                    face_offset(f, feature->face) - c.errors.machine_shift_mm;
      const int axis = normal_axis(feature->face);
      EXPECT_NEAR(face_point(t, m.probe)[axis], truth[axis], 1e-9) << t.feature << " case " << i;
    }
  }
}

TEST(FixtureSimulator, TriggerNoiseIsReproducibleAndAlongTheApproach) {
  const MachineConfig m = pm1_with_fixture();
  const FixtureConfig& f = *m.fixture;
  const double sigma = 0.002;
  const MachineSimulator machine(m, simulator_config(sigma, 99));
  const FixtureSimulator fixture(f, FixtureErrors{});
  const auto a =
      perform_fixture_check(machine, fixture, fixture_request("pm1", "n-1", kPost, 3), 1);
  const auto b =
      perform_fixture_check(machine, fixture, fixture_request("pm1", "n-1", kPost, 3), 2);
  const auto c =
      perform_fixture_check(machine, fixture, fixture_request("pm1", "n-2", kPost, 3), 1);
  ASSERT_EQ(a.touches.size(), 12u * 12u * 5u);
  ASSERT_EQ(a.touches.size(), b.touches.size());
  int differing = 0;
  double sum_sq = 0;
  const auto placements = placements_of(f, kPost, 3);
  for (std::size_t i = 0; i < a.touches.size(); ++i) {
    EXPECT_EQ(a.touches[i].axes.x_mm, b.touches[i].axes.x_mm);
    EXPECT_EQ(a.touches[i].axes.z_mm, b.touches[i].axes.z_mm);
    differing += a.touches[i].axes.x_mm != c.touches[i].axes.x_mm ||
                 a.touches[i].axes.y_mm != c.touches[i].axes.y_mm ||
                 a.touches[i].axes.z_mm != c.touches[i].axes.z_mm;
    // The noise moves the latched readouts along the approach only: the face point error along
    // the approach is the noise (positive: the probe triggered late, past the face).
    const auto feature = parse_pogo_touch_feature(a.touches[i].feature);
    const PogoPlacement& placement = placements.at({feature->configuration, feature->pogo});
    const Eigen::Vector3d truth =
        f.to_machine(placement.commanded_mm) + face_offset(f, feature->face);
    const Eigen::Vector3d error = face_point(a.touches[i], m.probe) - truth;
    const Eigen::Vector3d u = a.touches[i].approach;
    EXPECT_NEAR((error - error.dot(u) * u).norm(), 0, 1e-9);
    sum_sq += std::pow(error.dot(u) / sigma, 2);
  }
  EXPECT_GT(differing, static_cast<int>(a.touches.size()) * 9 / 10);
  // 720 standard normal deviates: the rms has a standard error of ~0.026.
  EXPECT_NEAR(std::sqrt(sum_sq / a.touches.size()), 1.0, 0.1);
}

// ---- Zero offsets
// --------------------------------------------------------------------------------

// The correction the pre-calibration would issue with a perfect probe: each pogo's true delta.
Correction true_zero_offsets(const FixtureSimulator& fixture, int k) {
  Correction c{"fixture:" + fixture.fixture().fixture_id, {}};
  for (const auto& p : precalibration_configuration(fixture.fixture(), k)) {
    const Eigen::Vector3d d = fixture.true_delta_mm(p);
    for (int a = 0; a < 3; ++a) c.offsets.push_back({zero_offset_name(p.pogo, a), d[a], "mm"});
  }
  return c;
}

TEST(FixtureSimulator, ZeroOffsetsCancelPureOffsetsAtEveryConfiguration) {
  std::mt19937_64 rng(303);
  for (int i = 0; i < 100; ++i) {
    const FixtureConfig f = random_fixture(rng);
    FixtureErrors e;
    e.column_x.offset_mm = uniform(rng, -0.2, 0.2);
    e.pogo_y.offset_mm = uniform(rng, -0.2, 0.2);
    e.pogo_z.offset_mm = uniform(rng, -0.2, 0.2);
    for (int c = 1; c <= f.columns(); ++c) {
      for (int r = 1; r <= f.rows(); ++r) {
        e.pogo_offsets_mm[pogo_label(c, r)] = Eigen::Vector3d(
            uniform(rng, -0.1, 0.1), uniform(rng, -0.1, 0.1), uniform(rng, -0.1, 0.1));
      }
    }
    FixtureSimulator fixture(f, e);
    const int k = std::uniform_int_distribution<int>(0, 9)(rng);
    double before = 0;
    for (const auto& p : precalibration_configuration(f, k)) {
      before = std::max(before, fixture.true_delta_mm(p).cwiseAbs().maxCoeff());
    }
    EXPECT_GT(before, 0.01);
    fixture.apply_zero_offsets(true_zero_offsets(fixture, k));
    // Every configuration of the same rows: pre-calibration at every plane, post-calibration.
    const RowSelection rows = precalibration_rows(f, k);
    for (int other = 0; other < 10; ++other) {
      if (precalibration_rows(f, other) != rows) continue;
      for (const auto& p : precalibration_configuration(f, other)) {
        EXPECT_LT(fixture.true_delta_mm(p).norm(), 1e-9) << p.pogo << " cfg " << other;
      }
    }
    for (const auto& configuration : postcalibration_configurations(f, rows)) {
      for (const auto& p : configuration)
        EXPECT_LT(fixture.true_delta_mm(p).norm(), 1e-9) << p.pogo;
    }
    fixture.clear_zero_offsets();
    EXPECT_TRUE(fixture.zero_offsets().empty());
    for (const auto& p : precalibration_configuration(f, k)) {
      EXPECT_GT(fixture.true_delta_mm(p).norm(), 0) << p.pogo;
    }
  }
}

TEST(FixtureSimulator, ZeroOffsetsLeaveScaleMisalignmentAndNonlinearity) {
  const FixtureConfig f = pm1_fixture();
  FixtureErrors e;
  e.column_x.offset_mm = 0.05;
  e.column_x.scale_ppm = 200;                                 // dx grows 200 um/m with X
  e.pogo_z.misalignment_rad = Eigen::Vector3d(300e-6, 0, 0);  // X moves 300 urad with Z
  e.pogo_y.curvature_um_per_m2 = 100;
  FixtureSimulator fixture(f, e);
  const int k = 2;  // odd rows at 12 in
  fixture.apply_zero_offsets(true_zero_offsets(fixture, k));
  const auto home = precalibration_configuration(f, k);
  // At the probed positions the offsets cancel all but the errors' slopes acting on the offsets
  // themselves (e.g. 200 ppm x 0.86 mm): second order.
  for (const auto& p : home) EXPECT_LT(fixture.true_delta_mm(p).norm(), 5e-4);
  double largest = 0;
  for (const auto& configuration : postcalibration_configurations(f, RowSelection::Odd)) {
    for (const auto& p : configuration) {
      const PogoPlacement& pre = *std::find_if(
          home.begin(), home.end(), [&](const PogoPlacement& h) { return h.pogo == p.pogo; });
      const Eigen::Vector3d dc = p.commanded_mm - pre.commanded_mm;
      const Eigen::Vector3d d = fixture.true_delta_mm(p);
      // To first order: dx = scale dX + tilt dZ; dy = curvature (y^2 - y0^2); dz = 0. The second
      // order (the errors' slopes times the offsets, < 1 mm x 1e-3) stays below 5e-4 mm.
      EXPECT_NEAR(d.x(), 200e-6 * dc.x() + 300e-6 * dc.z(), 5e-4) << p.pogo;
      const double y = p.commanded_mm.y(), y0 = pre.commanded_mm.y();
      EXPECT_NEAR(d.y(), 100e-3 * (y * y - y0 * y0) / 1e6, 5e-4) << p.pogo;
      EXPECT_NEAR(d.z(), 0, 1e-9) << p.pogo;
      largest = std::max(largest, d.cwiseAbs().maxCoeff());
    }
  }
  EXPECT_GT(largest, 0.03);  // they remain: 200 ppm x 150 mm, 300 urad x 152 mm, ...
}

TEST(FixtureSimulator, ApplyZeroOffsetsAccumulatesAndRefusesForeignCorrections) {
  FixtureSimulator fixture(pm1_fixture(), FixtureErrors{});
  fixture.apply_zero_offsets({"fixture:UHF1", {{"C2R3.dx", 0.01, "mm"}, {"C2R3.dz", -0.02, "mm"}}});
  fixture.apply_zero_offsets({"fixture:UHF1", {{"C2R3.dx", 0.005, "mm"}}});
  EXPECT_TRUE(fixture.zero_offset_mm("C2R3").isApprox(Eigen::Vector3d(0.015, 0, -0.02)));
  EXPECT_TRUE(fixture.zero_offset_mm("C1R1").isZero());
  const PogoPlacement p{"C2R3", 2, 3, Eigen::Vector3d(2400, 850, 100)};
  EXPECT_TRUE(fixture.actuator_command_mm(p).isApprox(Eigen::Vector3d(2400 - 0.015, 850, 100.02)));

  const struct {
    Correction correction;
    std::string message;
  } bad[] = {
      {{"fixture:UHF2", {{"C1R1.dx", 0.01, "mm"}}}, "Correction.target = 'fixture:UHF2'"},
      {{"machine:work_offset", {}}, "this fixture's control unit takes 'fixture:UHF1'"},
      {{"fixture:UHF1", {{"C1R1.dx", 0.01, "mm"}, {"C1R1.dw", 0.01, "mm"}}},
       "Correction.offsets[1].name = 'C1R1.dw'"},
      {{"fixture:UHF1", {{"C9R1.dx", 0.01, "mm"}}}, "fixture 'UHF1' has no pogo C9R1"},
      {{"fixture:UHF1", {{"C1R7.dy", 0.01, "mm"}}}, "has no pogo C1R7"},
      {{"fixture:UHF1", {{"C1R1.dz", 0.01, "in"}}}, "Correction.offsets[0].unit = 'in'"},
      {{"fixture:UHF1", {{"C1R1.dz", std::numeric_limits<double>::quiet_NaN(), "mm"}}},
       "Correction.offsets[0].value = nan"},
  };
  for (const auto& b : bad) {
    try {
      fixture.apply_zero_offsets(b.correction);
      FAIL() << "accepted: " << b.message;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(b.message), std::string::npos) << e.what();
    }
    // All or nothing: nothing of a refused correction is applied.
    EXPECT_TRUE(fixture.zero_offset_mm("C1R1").isZero());
    EXPECT_TRUE(fixture.zero_offset_mm("C2R3").isApprox(Eigen::Vector3d(0.015, 0, -0.02)));
  }
}

TEST(FixtureSimulator, TiltedZExtensionMovesThePogoSidewaysWithZ) {
  const FixtureConfig f = pm1_fixture();
  FixtureErrors e;
  e.pogo_z.misalignment_rad = Eigen::Vector3d(0, -250e-6, 0);  // Z travel moves -Y
  const FixtureSimulator fixture(f, e);
  const auto low = precalibration_configuration(f, 0);
  const auto high = precalibration_configuration(f, 4);
  for (std::size_t i = 0; i < low.size(); ++i) {
    const Eigen::Vector3d d = fixture.true_delta_mm(high[i]) - fixture.true_delta_mm(low[i]);
    EXPECT_NEAR(d.y(), -250e-6 * units::inch_to_mm(24), 1e-12);
    EXPECT_NEAR(d.x(), 0, 1e-12);
    EXPECT_NEAR(d.z(), 0, 1e-12);
  }
}

TEST(FixtureSimulator, WearScattersEveryPlacement) {
  MachineConfig m = pm1_with_fixture();
  const MachineSimulator machine(m, simulator_config(0.0, 5));
  FixtureErrors e;
  e.wear_sigma_mm = 0.02;
  const FixtureSimulator fixture(*m.fixture, e);
  const auto placements = placements_of(*m.fixture, kPost, 0);
  double sum_sq = 0;
  int n = 0;
  for (int i = 0; i < 3; ++i) {
    const auto set = perform_fixture_check(
        machine, fixture, fixture_request("pm1", "wear-" + std::to_string(i), kPost, 0), 1);
    ASSERT_TRUE(set.error.empty()) << set.error;
    for (const Touch& t : set.touches) {
      const auto feature = parse_pogo_touch_feature(t.feature);
      if (feature->face != PogoFace::Top) continue;
      const PogoPlacement& p = placements.at({feature->configuration, feature->pogo});
      const double dz = face_point(t, m.probe).z() - m.fixture->to_machine(p.commanded_mm).z();
      sum_sq += dz * dz;
      ++n;
    }
  }
  ASSERT_EQ(n, 3 * 144);
  // 432 deviates of sigma 0.02: the rms lies within ~0.0014 of it (2 standard errors).
  EXPECT_NEAR(std::sqrt(sum_sq / n), 0.02, 0.002);
}

// ---- Bad requests and alarms
// ---------------------------------------------------------------------

TEST(FixtureSimulator, BadRequestsYieldNoTouchesAndSayWhy) {
  const MachineConfig m = pm1_with_fixture();
  const MachineSimulator machine(m, simulator_config(0.001));
  const FixtureSimulator fixture(*m.fixture, FixtureErrors{});
  const struct {
    CheckRequest request;
    std::string message;
  } cases[] = {
      {fixture_request("pm1", "a", kPre, std::nullopt),
       "a fixture pre-calibration request needs the parameter fixture_configuration (0..9)"},
      {fixture_request("pm1", "b", kPre, 10),
       "the request's parameter fixture_configuration = 10 is not an integer in 0..9"},
      {fixture_request("pm1", "c", kPost, -1), "fixture_configuration = -1 is not an integer"},
      {fixture_request("pm1", "d", CheckKind::MonumentPositioning, 1),
       "is for 'fixture_precal' and 'fixture_postcal', not 'monument_positioning'"},
      {fixture_request("pm2", "e", kPre, 1), "the request is for machine 'pm2'"},
  };
  for (const auto& c : cases) {
    const MeasurementSet set = perform_fixture_check(machine, fixture, c.request, 1);
    EXPECT_TRUE(set.touches.empty()) << c.message;
    EXPECT_NE(set.error.find(c.message), std::string::npos) << set.error;
  }
  CheckRequest fractional = fixture_request("pm1", "f", kPre, std::nullopt);
  fractional.parameters.push_back({"fixture_configuration", 2.5, ""});
  EXPECT_NE(
      perform_fixture_check(machine, fixture, fractional, 1).error.find("= 2.5 is not an integer"),
      std::string::npos);
  // Post-calibration without a configuration probes every row.
  const auto all =
      perform_fixture_check(machine, fixture, fixture_request("pm1", "g", kPost, std::nullopt), 1);
  EXPECT_TRUE(all.error.empty()) << all.error;
  EXPECT_EQ(all.touches.size(), 12u * 24u * 5u);
}

TEST(FixtureSimulator, AMisplacedPogoRaisesAProbeAlarmNamingTheMove) {
  const MachineConfig m = pm1_with_fixture();
  const MachineSimulator machine(m, simulator_config(0.001));
  FixtureErrors high;
  high.pogo_offsets_mm["C1R1"] = Eigen::Vector3d(0, 0, 20);  // block top above the top start
  const auto up = perform_fixture_check(machine, FixtureSimulator(*m.fixture, high),
                                        fixture_request("pm1", "up", kPre, 0), 1);
  EXPECT_NE(up.error.find("probe alarm: move 0 ('pogo:C1R1:cfg0:top'): the probe was deflected"),
            std::string::npos)
      << up.error;
  EXPECT_EQ(up.touches.size(), 12u * 5u - 1u);  // its sides are still met, 20 mm too high
  FixtureErrors low;
  low.pogo_offsets_mm["C2R3"] = Eigen::Vector3d(0, 0, -30);  // block far below the search
  const auto down = perform_fixture_check(machine, FixtureSimulator(*m.fixture, low),
                                          fixture_request("pm1", "down", kPre, 0), 1);
  EXPECT_NE(down.error.find("('pogo:C2R3:cfg0:top'): the probe did not trigger within 10 mm"),
            std::string::npos)
      << down.error;
  EXPECT_NE(down.error.find("('pogo:C2R3:cfg0:x-'): the probe did not trigger"), std::string::npos)
      << down.error;
  EXPECT_EQ(down.touches.size(), 12u * 5u - 5u);
  for (const Touch& t : down.touches) EXPECT_EQ(t.feature.find("C2R3"), std::string::npos);
}

// ---- The simulator's `fixture:` section ---------------------------------------------------------

MachineConfig machine_yaml(const std::string& tail) {
  const std::string text = R"(
machine_id: t1
probe: {tool_length_mm: 300, ball_radius_mm: 2}
monument: {hole_center_mm: [10, 20], hole_diameter_mm: 40, face_z_mm: 100}
fixture:
  fixture_id: F1
  columns: {count: 3, first_x_mm: 1000, pitch_mm: 500}
  rows: {count: 4, first_y_mm: 200, pitch_mm: 250}
  reference_block: {size_mm: 80, height_mm: 30}
  probe_depth_mm: 8
)" + tail;
  return parse_machine_config(text, "t1.yaml");
}

TEST(SimulatorConfigFixture, ReadsEveryFixtureErrorWithItsUnits) {
  const SimulatorConfig c = machine_yaml(R"(
simulator:
  fixture:
    column_x: {offset_mm: "0.001 in", scale_ppm: 12, misalignment_y_urad: 40, misalignment_z_arcsec: 3}
    pogo_y: {curvature_um_per_m2: 50, sine_amplitude_mm: "5 um", sine_period_mm: 400, sine_phase_deg: 90}
    pogo_z: {misalignment_x_rad: 0.0002, misalignment_y_deg: 0.01}
    pogo_offsets_mm: {C3R4: [0.01, "-2 um", 0], C1R1: [0, 0, 0.02]}
    wear_sigma_mm: "3 um"
)")
                                .simulator;
  const FixtureErrors& e = c.fixture;
  EXPECT_DOUBLE_EQ(e.column_x.offset_mm, 0.0254);
  EXPECT_DOUBLE_EQ(e.column_x.scale_ppm, 12);
  EXPECT_NEAR(e.column_x.misalignment_rad.y(), 40e-6, 1e-18);
  EXPECT_NEAR(e.column_x.misalignment_rad.z(), units::arcsec_to_rad(3), 1e-18);
  EXPECT_EQ(e.column_x.misalignment_rad.x(), 0);
  EXPECT_DOUBLE_EQ(e.pogo_y.curvature_um_per_m2, 50);
  EXPECT_NEAR(e.pogo_y.sine_amplitude_mm, 0.005, 1e-15);
  EXPECT_DOUBLE_EQ(e.pogo_y.sine_period_mm, 400);
  EXPECT_NEAR(e.pogo_y.sine_phase_rad, units::kPi / 2, 1e-15);
  EXPECT_DOUBLE_EQ(e.pogo_z.misalignment_rad.x(), 0.0002);
  EXPECT_NEAR(e.pogo_z.misalignment_rad.y(), units::deg_to_rad(0.01), 1e-15);
  ASSERT_EQ(e.pogo_offsets_mm.size(), 2u);
  EXPECT_TRUE(e.pogo_offsets_mm.at("C3R4").isApprox(Eigen::Vector3d(0.01, -0.002, 0)));
  EXPECT_NEAR(e.wear_sigma_mm, 0.003, 1e-15);
  // error(u) = offset + scale u + curvature (u/1000)^2 + amplitude sin(2 pi u / period + phase)
  EXPECT_NEAR(e.column_x.error_mm(2000), 0.0254 + 12e-6 * 2000, 1e-12);
  EXPECT_NEAR(e.pogo_y.error_mm(100),
              50e-3 * 0.01 + 0.005 * std::sin(units::kPi / 2 + units::kPi / 2), 1e-12);
  EXPECT_TRUE(e.pogo_z.direction(2).isApprox(Eigen::Vector3d(0.0002, units::deg_to_rad(0.01), 1)));
}

TEST(SimulatorConfigFixture, AbsentMeansAPerfectFixture) {
  const SimulatorConfig c = machine_yaml("simulator: {seed: 3}\n").simulator;
  EXPECT_EQ(c.fixture.column_x.offset_mm, 0);
  EXPECT_EQ(c.fixture.pogo_z.misalignment_rad, Eigen::Vector3d::Zero());
  EXPECT_TRUE(c.fixture.pogo_offsets_mm.empty());
  EXPECT_EQ(c.fixture.wear_sigma_mm, 0);
  for (double u : {-500.0, 0.0, 1234.5}) EXPECT_EQ(c.fixture.pogo_y.error_mm(u), 0);
}

TEST(SimulatorConfigFixture, RefusesUnknownKeysAndBadValuesNamingThem) {
  const struct {
    std::string yaml;
    std::string message;
  } cases[] = {
      {"simulator:\n  fixture:\n    colum_x: {offset_mm: 1}\n",
       "colum_x = (not a single value): unknown key"},
      {"simulator:\n  fixture:\n    column_x: {misalignment_x_urad: 1}\n",
       "simulator.fixture.column_x.misalignment_x_urad = '1': unknown key"},
      {"simulator:\n  fixture:\n    pogo_z: {scale_ppm: lots}\n",
       "scale_ppm = 'lots': expected a number"},
      {"simulator:\n  fixture:\n    pogo_y: {sine_amplitude_mm: 0.01}\n",
       "sine_period_mm = (missing): must be positive when sine_amplitude_mm is not zero"},
      {"simulator:\n  fixture:\n    pogo_offsets_mm: {C4R1: [0, 0, 0]}\n",
       "pogo_offsets_mm.C4R1 = (not a single value): not a pogo of fixture 'F1' (C1R1 to C3R4)"},
      {"simulator:\n  fixture:\n    pogo_offsets_mm: {pogo1: [0, 0, 0]}\n",
       "pogo_offsets_mm.pogo1"},
      {"simulator:\n  fixture:\n    pogo_offsets_mm: {C1R1: [0, 0]}\n",
       "expected a list of 3 lengths"},
      {"simulator:\n  fixture:\n    wear_sigma_mm: -1\n",
       "wear_sigma_mm = '-1': must not be negative"},
      {"simulator:\n  fixture:\n    pogo_z: {misalignment_x_urad: 1, misalignment_x_deg: 1}\n",
       "misalignment_x_urad = '1': also given as misalignment_x_deg; give one"},
  };
  for (const auto& c : cases) {
    try {
      machine_yaml(c.yaml).simulator;
      FAIL() << "accepted " << c.yaml;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("t1.yaml"), std::string::npos) << e.what();
    }
  }
  // A simulated fixture needs the machine's fixture.
  MachineConfig no_fixture = machine_yaml("");
  no_fixture.fixture.reset();
  try {
    parse_simulator_config("simulator:\n  fixture:\n    wear_sigma_mm: 0\n", no_fixture);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("the machine has no `fixture:` section"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(FixtureSimulator::for_machine(no_fixture, SimulatorConfig{}), ConfigError);
}

TEST(SimulatorConfigFixture, TheExampleMachineHasAPerfectFixture) {
  const MachineConfig m = load_machine_config(NCQUAL_SOURCE_DIR "/deploy/machines/pm1.yaml");
  ASSERT_TRUE(m.fixture);
  const SimulatorConfig c = m.simulator;
  const FixtureSimulator fixture = FixtureSimulator::for_machine(m, c);
  EXPECT_EQ(fixture.fixture().fixture_id, "UHF1");
  const MachineSimulator machine(m, c);
  for (int k = 0; k < 10; ++k) {
    for (const auto& p : precalibration_configuration(fixture.fixture(), k)) {
      EXPECT_TRUE(fixture.true_delta_mm(p).isZero()) << p.pogo;
    }
    const auto set = perform_fixture_check(
        machine, fixture, fixture_request("pm1", "pm1-" + std::to_string(k), kPre, k), 1);
    EXPECT_TRUE(set.error.empty()) << set.error;
    EXPECT_EQ(set.touches.size(), 60u);
  }
}

}  // namespace
}  // namespace ncqual::sim

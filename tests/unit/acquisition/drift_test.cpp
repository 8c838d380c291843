// SPDX-License-Identifier: Apache-2.0
// Drift of the simulator's ground truth with time (simulator.drift): the section's parsing and
// refusals, the truth at a time (errors_at and friends: nothing before `since`, then linear), the
// touch probe, fixture and tracker measuring the truth of their measurement time, bit-identical
// measurements without drift, and the drift scenario's failure day.
#include "ncqual/common/clock.hpp"
#include "ncqual/common/fixture.hpp"
#include "ncqual/common/kinematics.hpp"
#include "ncqual/sim/fixture_simulator.hpp"
#include "ncqual/sim/machine_simulator.hpp"
#include "ncqual/sim/simulator_config.hpp"
#include "ncqual/sim/tracker_simulator.hpp"
#include "ncqual/common/units.hpp"
#include "test_fixtures.hpp"
#include "test_machines.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace ncqual::sim {
namespace {

using testing::pm1_like_machine;
using testing::pm1_with_fixture;
using testing::request;
using testing::simulator_config;
using testing::uniform;

// 2026-01-05T00:00:00Z: 20458 days after 1970-01-01 (56 years with 14 leap days to 2026-01-01,
// then 4 days), worked by hand rather than with the parser under test.
constexpr std::int64_t kSinceNs = 20458LL * 86400 * 1000000000;
constexpr std::int64_t kDayNs = 86400LL * 1000000000;

// `m` with its simulator section replaced by the `simulator:` of `yaml`.
MachineConfig with_simulator(MachineConfig m, const std::string& yaml) {
  m.simulator = parse_simulator_config(yaml, m);
  return m;
}

SimulatorConfig parse(const MachineConfig& m, const std::string& yaml) {
  return with_simulator(m, yaml).simulator;
}

void expect_same_axes(const AxisPosition& a, const AxisPosition& b, const std::string& what) {
  EXPECT_EQ(a.x_mm, b.x_mm) << what;
  EXPECT_EQ(a.y_mm, b.y_mm) << what;
  EXPECT_EQ(a.z_mm, b.z_mm) << what;
  EXPECT_EQ(a.w_mm, b.w_mm) << what;
  EXPECT_EQ(a.a_rad, b.a_rad) << what;
  EXPECT_EQ(a.c_rad, b.c_rad) << what;
}

// Every field of two measurement sets, to the bit (time_ns only when `same_time`).
void expect_same_set(const MeasurementSet& a, const MeasurementSet& b, bool same_time = true) {
  EXPECT_EQ(a.machine_id, b.machine_id);
  EXPECT_EQ(a.request_id, b.request_id);
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.instrument, b.instrument);
  EXPECT_EQ(a.frame, b.frame);
  if (same_time) {
    EXPECT_EQ(a.time_ns, b.time_ns);
  }
  EXPECT_EQ(a.error, b.error);
  ASSERT_EQ(a.touches.size(), b.touches.size());
  for (std::size_t i = 0; i < a.touches.size(); ++i) {
    EXPECT_EQ(a.touches[i].feature, b.touches[i].feature) << i;
    expect_same_axes(a.touches[i].axes, b.touches[i].axes, "touch " + std::to_string(i));
    EXPECT_EQ(a.touches[i].approach, b.touches[i].approach) << i;
  }
  ASSERT_EQ(a.tracker_points.size(), b.tracker_points.size());
  for (std::size_t i = 0; i < a.tracker_points.size(); ++i) {
    EXPECT_EQ(a.tracker_points[i].label, b.tracker_points[i].label) << i;
    EXPECT_EQ(a.tracker_points[i].measured_mm, b.tracker_points[i].measured_mm) << i;
  }
  ASSERT_EQ(a.parameters.size(), b.parameters.size());
}

// ---- What a check sees, by the formulas of the checks' headers (nominal kinematics) ----------

// Check 2: L' - L = (x+ - x- - w) / 2 with x+- the contact points of the gauge's +X and -X edges
// (ball centre + r approach).
double measured_tool_length_error(const MeasurementSet& set, const MachineConfig& m) {
  double x_plus = NAN, x_minus = NAN;
  for (const Touch& t : set.touches) {
    const double x =
        (stylus_ball_centre(t.axes, m.probe) + m.probe.ball_radius_mm * t.approach).x();
    if (t.feature == "gauge_edge_+x") x_plus = x;
    if (t.feature == "gauge_edge_-x") x_minus = x;
  }
  return (x_plus - x_minus - m.monument.gauge_width_mm) / 2;
}

// Check 3 with four hole touches at 0, 90, 180, 270 deg: each pair of opposite touches is a chord
// through the taught centre, parallel to X or Y, whose midpoint lies on the true centre's line
// (exact whatever the offset); the face's Z from the face touch. Returns measured - taught
// (center_dx, center_dy, face_dz).
Eigen::Vector3d measured_positioning(const MeasurementSet& set, const MachineConfig& m) {
  std::vector<Eigen::Vector3d> edge;
  double face = NAN;
  for (const Touch& t : set.touches) {
    const Eigen::Vector3d b = stylus_ball_centre(t.axes, m.probe);
    if (t.feature == "hole_edge") edge.push_back(b);
    if (t.feature == "face") face = b.z() - m.probe.ball_radius_mm;
  }
  if (edge.size() != 4) return Eigen::Vector3d::Constant(NAN);
  return Eigen::Vector3d((edge[0].x() + edge[2].x()) / 2 - m.monument.hole_center_mm.x(),
                         (edge[1].y() + edge[3].y()) / 2 - m.monument.hole_center_mm.y(),
                         face - m.monument.face_z_mm);
}

// Fixture checks: per pogo, measured - commanded: X and Y from the two side touches' mean (the
// block's centre, whatever its size), Z from the top touch.
std::map<std::string, Eigen::Vector3d> measured_pogo_deltas(const MeasurementSet& set,
                                                            const MachineConfig& m, int k) {
  const FixtureConfig& f = *m.fixture;
  std::map<std::string, Eigen::Vector3d> sum;
  for (const Touch& t : set.touches) {
    const auto feature = parse_pogo_touch_feature(t.feature);
    if (!feature) continue;
    const Eigen::Vector3d p =
        stylus_ball_centre(t.axes, m.probe) + m.probe.ball_radius_mm * t.approach;
    Eigen::Vector3d& s = sum.try_emplace(feature->pogo, Eigen::Vector3d::Zero()).first->second;
    switch (feature->face) {
      case PogoFace::Top: s.z() += p.z(); break;
      case PogoFace::XMinus:
      case PogoFace::XPlus: s.x() += p.x() / 2; break;
      default: s.y() += p.y() / 2; break;
    }
  }
  std::map<std::string, Eigen::Vector3d> deltas;
  for (const PogoPlacement& placement : precalibration_configuration(f, k)) {
    deltas[placement.pogo] = sum.at(placement.pogo) - f.to_machine(placement.commanded_mm);
  }
  return deltas;
}

// The Correction a failed pre-calibration issues: every probed pogo and axis, measured delta.
Correction zero_offsets_from(const std::map<std::string, Eigen::Vector3d>& deltas,
                             const FixtureConfig& f) {
  Correction c;
  c.target = "fixture:" + f.fixture_id;
  for (const auto& [pogo, d] : deltas) {
    for (int axis = 0; axis < 3; ++axis) {
      c.offsets.push_back({zero_offset_name(pogo, axis), d[axis], "mm"});
    }
  }
  return c;
}

double largest_magnitude(const std::map<std::string, Eigen::Vector3d>& deltas, int axis) {
  double worst = 0;
  for (const auto& [pogo, d] : deltas) worst = std::max(worst, std::abs(d[axis]));
  return worst;
}

// ---- Parsing -----------------------------------------------------------------------------------

TEST(DriftConfig, AbsentOrNullSectionMeansNoDrift) {
  for (const std::string yaml : {"simulator: {seed: 3}\n", "simulator: {drift: ~}\n"}) {
    EXPECT_FALSE(parse(pm1_like_machine(), yaml).drift.has_value()) << yaml;
  }
  const MachineConfig pm1 = load_machine_config(NCQUAL_SOURCE_DIR "/deploy/machines/pm1.yaml");
  EXPECT_FALSE(pm1.simulator.drift.has_value());
}

TEST(DriftConfig, ReadsEveryRateInItsKeysUnit) {
  const SimulatorConfig c = parse(pm1_with_fixture(), R"(
simulator:
  drift:
    since: "2026-01-05T00:00:00Z"
    machine_shift_mm_per_day: [0.001, "2 um", -0.0005]
    monument_shift_mm_per_day: [0, "0.0001 in", 0.003]
    tool_length_error_mm_per_day: "0.7 um"
    c_angle_error_arcsec_per_day: 0.5
    a_home_error_urad_per_day: 2
    fixture_column_x_offset_mm_per_day: 0.0015
    fixture_pogo_y_offset_mm_per_day: "-1 um"
    fixture_pogo_z_offset_mm_per_day: 0.002
    squareness_ec0xy_urad_per_day: 0.4
)");
  ASSERT_TRUE(c.drift.has_value());
  const SimulatorDrift& d = *c.drift;
  EXPECT_EQ(d.since_ns, kSinceNs);
  EXPECT_TRUE(d.machine_shift_mm_per_day.isApprox(Eigen::Vector3d(0.001, 0.002, -0.0005), 1e-15));
  EXPECT_TRUE(d.monument_shift_mm_per_day.isApprox(Eigen::Vector3d(0, 0.00254, 0.003), 1e-15));
  EXPECT_NEAR(d.tool_length_error_mm_per_day, 0.0007, 1e-18);
  EXPECT_NEAR(d.c_angle_error_rad_per_day, 0.5 * 3.14159265358979323846 / 648000, 1e-20);
  EXPECT_NEAR(d.a_home_error_rad_per_day, 2e-6, 1e-20);
  EXPECT_EQ(d.fixture_column_x_offset_mm_per_day, 0.0015);
  EXPECT_NEAR(d.fixture_pogo_y_offset_mm_per_day, -0.001, 1e-18);
  EXPECT_EQ(d.fixture_pogo_z_offset_mm_per_day, 0.002);
  EXPECT_NEAR(d.squareness_ec0xy_rad_per_day, 0.4e-6, 1e-20);
  // The rest of the section keeps its defaults.
  EXPECT_TRUE(c.errors.machine_shift_mm.isZero());
}

TEST(DriftConfig, RatesMissingFromTheSectionAreZeroAndAngleKeysTakeAnyUnit) {
  const SimulatorConfig c = parse(pm1_like_machine(), R"(
simulator:
  drift:
    since: "2026-01-05 06:30Z"
    c_angle_error_deg_per_day: "1 arcsec"
)");
  ASSERT_TRUE(c.drift.has_value());
  EXPECT_EQ(c.drift->since_ns, kSinceNs + (6 * 60 + 30) * 60 * 1000000000LL);
  EXPECT_NEAR(c.drift->c_angle_error_rad_per_day, units::arcsec_to_rad(1), 1e-20);
  EXPECT_TRUE(c.drift->machine_shift_mm_per_day.isZero());
  EXPECT_EQ(c.drift->tool_length_error_mm_per_day, 0);
  EXPECT_EQ(c.drift->a_home_error_rad_per_day, 0);
  EXPECT_EQ(c.drift->squareness_ec0xy_rad_per_day, 0);
}

struct BadDrift {
  const char* drift_yaml;  // under `simulator:`
  std::vector<std::string> message_must_name;
  bool with_fixture = true;
};

TEST(DriftConfig, RefusesBadValuesNamingFileKeyAndValue) {
  const BadDrift cases[] = {
      {"drift: 3", {"test:pm1", "simulator.drift", "'3'", "mapping"}},
      {"drift: {}", {"simulator.drift.since", "required"}},
      {"drift: {tool_length_error_mm_per_day: 0.001}", {"since", "required"}},
      {"drift: {since: yesterday}", {"since", "'yesterday'", "ISO 8601"}},
      {"drift: {since: '2026-02-30T00:00:00Z'}", {"since", "'2026-02-30T00:00:00Z'", "ISO 8601"}},
      {"drift: {since: '2026-01-05T00:00:00'}", {"since", "'2026-01-05T00:00:00'", "ISO 8601"}},
      {"drift: {since: '9999-01-01T00:00:00Z'}",
       {"since", "'9999-01-01T00:00:00Z'", "1900 to 2200"}},
      {"drift: {since: [2026, 1, 5]}", {"since", "ISO 8601"}},
      {"drift: {since: '2026-01-05T00:00Z', tool_length_error_mm_per_day: fast}",
       {"tool_length_error_mm_per_day", "'fast'"}},
      {"drift: {since: '2026-01-05T00:00Z', tool_length_error_mm_per_day: 2 furlong}",
       {"tool_length_error_mm_per_day", "'2 furlong'", "furlong"}},
      {"drift: {since: '2026-01-05T00:00Z', tool_length_error_mm_per_day: [1]}",
       {"tool_length_error_mm_per_day", "number"}},
      {"drift: {since: '2026-01-05T00:00Z', machine_shift_mm_per_day: [0.001, 0]}",
       {"simulator.drift.machine_shift_mm_per_day", "list of 3"}},
      {"drift: {since: '2026-01-05T00:00Z', monument_shift_mm_per_day: [0, x, 0]}",
       {"monument_shift_mm_per_day[1]", "'x'"}},
      {"drift: {since: '2026-01-05T00:00Z', c_angle_error_arcsec_per_day: 1 mm}",
       {"c_angle_error_arcsec_per_day", "'1 mm'"}},
      {"drift: {since: '2026-01-05T00:00Z', a_home_error_arcsec_per_day: 1, "
       "a_home_error_deg_per_day: 0}",
       {"a_home_error_deg_per_day", "a_home_error_arcsec_per_day", "give one"}},
      {"drift: {since: '2026-01-05T00:00Z', tool_length_mm_per_day: 0.001}",
       {"tool_length_mm_per_day", "'0.001'", "unknown key"}},
      {"drift: {since: '2026-01-05T00:00Z', setpoint_shift_mm_per_day: {primary: [0, 0, 0]}}",
       {"setpoint_shift_mm_per_day", "unknown key"}},
      {"drift: {since: '2026-01-05T00:00Z', fixture_column_x_offset_mm_per_day: 0.001}",
       {"fixture_column_x_offset_mm_per_day", "'0.001'", "no `fixture:`"},
       false},
  };
  for (const auto& bad : cases) {
    const std::string yaml = std::string("simulator:\n  ") + bad.drift_yaml + "\n";
    MachineConfig m = bad.with_fixture ? pm1_with_fixture() : pm1_like_machine();
    try {
      parse(m, yaml);
      ADD_FAILURE() << "accepted: " << yaml;
    } catch (const ConfigError& e) {
      const std::string what = e.what();
      for (const auto& part : bad.message_must_name) {
        EXPECT_NE(what.find(part), std::string::npos)
            << "message '" << what << "' does not name '" << part << "' for: " << yaml;
      }
    }
  }
}

// ---- The truth at a time ------------------------------------------------------------------------

SimulatorDrift example_drift() {
  SimulatorDrift d;
  d.since_ns = kSinceNs;
  d.machine_shift_mm_per_day = Eigen::Vector3d(0.001, -0.002, 0.0005);
  d.monument_shift_mm_per_day = Eigen::Vector3d(-0.0003, 0.0004, 0.0001);
  d.tool_length_error_mm_per_day = 0.0015;
  d.c_angle_error_rad_per_day = 2e-6;
  d.a_home_error_rad_per_day = -3e-6;
  d.fixture_column_x_offset_mm_per_day = 0.002;
  d.fixture_pogo_y_offset_mm_per_day = -0.0005;
  d.fixture_pogo_z_offset_mm_per_day = 0.001;
  d.squareness_ec0xy_rad_per_day = 0.5e-6;
  return d;
}

SimulatorErrors random_errors(std::mt19937_64& rng) {
  SimulatorErrors e;
  for (int i = 0; i < 3; ++i) {
    e.machine_shift_mm[i] = uniform(rng, -0.05, 0.05);
    e.monument_shift_mm[i] = uniform(rng, -0.05, 0.05);
  }
  e.stylus_offset_mm = Eigen::Vector2d(uniform(rng, -0.01, 0.01), uniform(rng, -0.01, 0.01));
  e.tool_length_error_mm = uniform(rng, -0.03, 0.03);
  e.c_angle_error_rad = uniform(rng, -1e-4, 1e-4);
  e.a_home_error_rad = uniform(rng, -1e-4, 1e-4);
  e.setpoint_shift_mm["primary"] = Eigen::Vector3d(0.01, -0.02, 0.03);
  return e;
}

void expect_identical(const SimulatorErrors& a, const SimulatorErrors& b, const std::string& when) {
  EXPECT_EQ(a.machine_shift_mm, b.machine_shift_mm) << when;
  EXPECT_EQ(a.monument_shift_mm, b.monument_shift_mm) << when;
  EXPECT_EQ(a.stylus_offset_mm, b.stylus_offset_mm) << when;
  EXPECT_EQ(a.tool_length_error_mm, b.tool_length_error_mm) << when;
  EXPECT_EQ(a.c_angle_error_rad, b.c_angle_error_rad) << when;
  EXPECT_EQ(a.a_home_error_rad, b.a_home_error_rad) << when;
  EXPECT_EQ(a.setpoint_shift_mm, b.setpoint_shift_mm) << when;
}

TEST(DriftTruth, DriftDaysAreZeroUntilSinceThenExactElapsedDays) {
  const SimulatorDrift d = example_drift();
  EXPECT_EQ(drift_days(d, kSinceNs - 1), 0.0);
  EXPECT_EQ(drift_days(d, 0), 0.0);
  EXPECT_EQ(drift_days(d, kSinceNs), 0.0);
  EXPECT_EQ(drift_days(d, kSinceNs + kDayNs / 2), 0.5);
  EXPECT_EQ(drift_days(d, kSinceNs + 20 * kDayNs), 20.0);
  EXPECT_NEAR(drift_days(d, kSinceNs + 1), 1 / 86400e9, 1e-30);
  // A `since` before 1970 and a `now` after it: the difference crosses zero without overflow.
  SimulatorDrift old = d;
  old.since_ns = -3653LL * kDayNs;  // 1960-01-01: ten years with the leap days of 1960, 64, 68
  EXPECT_EQ(drift_days(old, 0), 3653.0);
}

TEST(DriftTruth, ErrorsAreTheBaseUntilSinceThenGrowLinearly) {
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    SimulatorConfig c;
    c.errors = random_errors(rng);
    c.drift = example_drift();
    const SimulatorDrift& d = *c.drift;
    // Before and at `since`: the very same bits.
    expect_identical(errors_at(c, kSinceNs - kDayNs), c.errors, "a day before since");
    expect_identical(errors_at(c, kSinceNs), c.errors, "at since");
    // After: base + rate * days.
    const double days = uniform(rng, 0.1, 60);
    const std::int64_t now = kSinceNs + static_cast<std::int64_t>(days * kDayNs);
    const double elapsed = static_cast<double>(now - kSinceNs) / kDayNs;
    const SimulatorErrors e = errors_at(c, now);
    EXPECT_NEAR(
        (e.machine_shift_mm - c.errors.machine_shift_mm - d.machine_shift_mm_per_day * elapsed)
            .norm(),
        0, 1e-15);
    EXPECT_NEAR(
        (e.monument_shift_mm - c.errors.monument_shift_mm - d.monument_shift_mm_per_day * elapsed)
            .norm(),
        0, 1e-15);
    EXPECT_NEAR(e.tool_length_error_mm,
                c.errors.tool_length_error_mm + d.tool_length_error_mm_per_day * elapsed, 1e-15);
    EXPECT_NEAR(e.c_angle_error_rad,
                c.errors.c_angle_error_rad + d.c_angle_error_rad_per_day * elapsed, 1e-17);
    EXPECT_NEAR(e.a_home_error_rad,
                c.errors.a_home_error_rad + d.a_home_error_rad_per_day * elapsed, 1e-17);
    // What has no rate does not drift.
    EXPECT_EQ(e.stylus_offset_mm, c.errors.stylus_offset_mm);
    EXPECT_EQ(e.setpoint_shift_mm, c.errors.setpoint_shift_mm);
  }
  // Without drift: the base at every time.
  SimulatorConfig still;
  still.errors = random_errors(rng);
  expect_identical(errors_at(still, kSinceNs + 100 * kDayNs), still.errors, "no drift");
}

TEST(DriftTruth, FixtureZeroAndSquarenessDriftTheRestStays) {
  FixtureErrors base;
  base.column_x.offset_mm = 0.01;
  base.column_x.scale_ppm = 5;
  base.pogo_y.offset_mm = -0.02;
  base.pogo_z.misalignment_rad = Eigen::Vector3d(1e-5, 0, 0);
  base.pogo_offsets_mm["C2R3"] = Eigen::Vector3d(0.01, 0, -0.02);
  base.wear_sigma_mm = 0.001;
  const std::optional<SimulatorDrift> d = example_drift();
  const FixtureErrors before = fixture_errors_at(base, d, kSinceNs);
  EXPECT_EQ(before.column_x.offset_mm, 0.01);
  EXPECT_EQ(before.pogo_y.offset_mm, -0.02);
  EXPECT_EQ(before.pogo_z.offset_mm, 0.0);
  const FixtureErrors later = fixture_errors_at(base, d, kSinceNs + 10 * kDayNs);
  EXPECT_NEAR(later.column_x.offset_mm, 0.01 + 10 * 0.002, 1e-16);
  EXPECT_NEAR(later.pogo_y.offset_mm, -0.02 - 10 * 0.0005, 1e-16);
  EXPECT_NEAR(later.pogo_z.offset_mm, 10 * 0.001, 1e-16);
  EXPECT_EQ(later.column_x.scale_ppm, 5);
  EXPECT_EQ(later.pogo_z.misalignment_rad, base.pogo_z.misalignment_rad);
  EXPECT_EQ(later.pogo_offsets_mm, base.pogo_offsets_mm);
  EXPECT_EQ(later.wear_sigma_mm, 0.001);

  VolumetricTruth v;
  v.rigid_body.ec0xy_rad = 12e-6;
  v.rigid_body.eb0xz_rad = -8e-6;
  EXPECT_EQ(volumetric_at(v, d, kSinceNs).rigid_body.ec0xy_rad, 12e-6);
  const VolumetricTruth vl = volumetric_at(v, d, kSinceNs + 10 * kDayNs);
  EXPECT_NEAR(vl.rigid_body.ec0xy_rad, 12e-6 + 10 * 0.5e-6, 1e-18);
  EXPECT_EQ(vl.rigid_body.eb0xz_rad, -8e-6);
}

TEST(DriftTruth, ConfigAtFreezesTheTruthAndClearsTheDrift) {
  SimulatorConfig c = simulator_config(0.002, 77);
  c.drift = example_drift();
  const SimulatorConfig frozen = config_at(c, kSinceNs + 4 * kDayNs);
  EXPECT_FALSE(frozen.drift.has_value());
  EXPECT_EQ(frozen.seed, 77u);
  EXPECT_EQ(frozen.trigger_noise_sigma_mm, 0.002);
  EXPECT_NEAR(frozen.errors.tool_length_error_mm, 4 * 0.0015, 1e-16);
  EXPECT_NEAR(frozen.fixture.column_x.offset_mm, 4 * 0.002, 1e-16);
  EXPECT_NEAR(frozen.volumetric.rigid_body.ec0xy_rad, 4 * 0.5e-6, 1e-18);
  // Frozen, it holds at every time.
  expect_identical(errors_at(frozen, kSinceNs + 40 * kDayNs), frozen.errors, "frozen");
}

// ---- The touch probe on the monument ------------------------------------------------------------

TEST(DriftTouchProbe, ToolLengthCheckSeesTheGrowthOfTwentyDays) {
  const MachineConfig m = pm1_like_machine();
  const double sigma = 0.001;
  SimulatorConfig c = simulator_config(sigma, 21);
  c.errors.tool_length_error_mm = 0.004;
  c.drift = SimulatorDrift{};
  c.drift->since_ns = kSinceNs;
  c.drift->tool_length_error_mm_per_day = 0.0015;  // 1.5 um a day: 0.030 mm in 20 days
  const MachineSimulator sim(m, c);
  const std::int64_t day0 = kSinceNs, day20 = kSinceNs + 20 * kDayNs;
  EXPECT_NEAR(sim.ground_truth_at(day20).tool_length_error_mm, 0.034, 1e-15);
  EXPECT_EQ(sim.ground_truth().tool_length_error_mm, 0.004);

  const MeasurementSet s0 =
      sim.perform(request("pm1", "tl-0", CheckKind::MonumentToolLength), day0);
  const MeasurementSet s20 =
      sim.perform(request("pm1", "tl-20", CheckKind::MonumentToolLength), day20);
  ASSERT_TRUE(s0.error.empty()) << s0.error;
  ASSERT_TRUE(s20.error.empty()) << s20.error;
  EXPECT_EQ(s20.time_ns, day20);
  const double e0 = measured_tool_length_error(s0, m), e20 = measured_tool_length_error(s20, m);
  // Each estimate is half the difference of two touches: sigma / sqrt(2); their difference
  // (independent noise, different request ids) has sigma.
  EXPECT_NEAR(e0, 0.004, 5 * sigma / std::sqrt(2.0));
  EXPECT_NEAR(e20, 0.034, 5 * sigma / std::sqrt(2.0));
  EXPECT_NEAR(e20 - e0, 20 * 0.0015, 5 * sigma);
  std::printf(
      "  tool length error: day 0 %.5f mm, day 20 %.5f mm, growth %.5f mm (truth 0.03000)\n", e0,
      e20, e20 - e0);

  // The same request id draws the same noise: the growth comes out exactly.
  const MeasurementSet again =
      sim.perform(request("pm1", "tl-0", CheckKind::MonumentToolLength), day20);
  EXPECT_NEAR(measured_tool_length_error(again, m) - e0, 0.03, 1e-9);
}

TEST(DriftTouchProbe, PositioningCheckSeesMachineAndMonumentDriftApart) {
  const MachineConfig m = pm1_like_machine();
  const double sigma = 0.001;
  SimulatorConfig c = simulator_config(sigma, 22);
  c.drift = SimulatorDrift{};
  c.drift->since_ns = kSinceNs;
  c.drift->machine_shift_mm_per_day = Eigen::Vector3d(0.001, -0.002, 0.002);
  c.drift->monument_shift_mm_per_day = Eigen::Vector3d(-0.0005, 0.0005, 0);
  const MachineSimulator sim(m, c);
  const MeasurementSet s0 = sim.perform(request("pm1", "pos-0"), kSinceNs - kDayNs);  // before
  const MeasurementSet s20 = sim.perform(request("pm1", "pos-20"), kSinceNs + 20 * kDayNs);
  ASSERT_TRUE(s0.error.empty()) << s0.error;
  ASSERT_TRUE(s20.error.empty()) << s20.error;
  // measured - taught = monument shift - machine shift: 20 days of (mon - mach) rates.
  const Eigen::Vector3d expected(-0.03, 0.05, -0.04);
  const Eigen::Vector3d d = measured_positioning(s20, m) - measured_positioning(s0, m);
  // Centre: mean of two opposite touches (sigma / sqrt(2)), difference of two days: sigma.
  // Face: one touch (sigma), difference: sqrt(2) sigma.
  EXPECT_NEAR(d.x(), expected.x(), 5 * sigma);
  EXPECT_NEAR(d.y(), expected.y(), 5 * sigma);
  EXPECT_NEAR(d.z(), expected.z(), 5 * std::sqrt(2.0) * sigma);
  std::printf(
      "  positioning change over 20 days: (%.5f, %.5f, %.5f) mm, truth (-0.03, 0.05, -0.04)\n",
      d.x(), d.y(), d.z());
}

TEST(DriftTouchProbe, ADriftingSimulatorMeasuresAsTheOneFrozenAtTheMeasurementTime) {
  const MachineConfig m = testing::pm1_with_fixture();
  SimulatorConfig c = simulator_config(0.001, 23);
  c.part_seating_sigma_mm = 0.003;
  c.drift = example_drift();
  MachineConfig with_setpoints = m;
  with_setpoints.setpoints.points = {{"primary", Eigen::Vector3d(150, 1000, 450)}};
  const MachineSimulator sim(with_setpoints, c);
  const std::int64_t t = kSinceNs + 13 * kDayNs + 5 * 3600LL * 1000000000;
  for (CheckKind kind :
       {CheckKind::MonumentCAlignment, CheckKind::MonumentToolLength,
        CheckKind::MonumentPositioning, CheckKind::MonumentCRotation, CheckKind::PartSetPoints}) {
    const CheckRequest r =
        request("pm1", std::string("frozen-") + std::string(to_string(kind)), kind);
    const MeasurementSet drifting = sim.perform(r, t);
    ASSERT_TRUE(drifting.error.empty()) << to_string(kind) << ": " << drifting.error;
    expect_same_set(drifting, MachineSimulator(with_setpoints, config_at(c, t)).perform(r, t));
    expect_same_set(drifting, sim.at(t).perform(r, t));
  }
}

TEST(DriftTouchProbe, NoDriftSectionGivesTheSameSetsAsToday) {
  // Without drift (and with a drift section before its `since`) every measurement is the one the
  // simulator gave before drift existed: the same touches, to the bit, at any time.
  const MachineConfig m = load_machine_config(NCQUAL_SOURCE_DIR "/deploy/machines/pm1.yaml");
  SimulatorConfig c = m.simulator;
  c.errors.tool_length_error_mm = 0.01;
  c.errors.machine_shift_mm = Eigen::Vector3d(0.004, -0.003, 0.002);
  ASSERT_FALSE(c.drift.has_value());
  const MachineSimulator plain(m, c);
  SimulatorConfig not_yet = c;
  not_yet.drift = example_drift();
  not_yet.drift->since_ns = kSinceNs + 365 * kDayNs;
  const MachineSimulator waiting(m, not_yet);
  SimulatorConfig zero_rates = c;
  zero_rates.drift = SimulatorDrift{};
  const MachineSimulator flat(m, zero_rates);
  for (CheckKind kind :
       {CheckKind::MonumentCAlignment, CheckKind::MonumentToolLength,
        CheckKind::MonumentPositioning, CheckKind::MonumentCRotation, CheckKind::PartSetPoints}) {
    const CheckRequest r = request("pm1", "today", kind);
    const MeasurementSet a = plain.perform(r, 0);
    ASSERT_TRUE(a.error.empty()) << a.error;
    expect_same_set(a, plain.perform(r, kSinceNs + 30 * kDayNs), false);
    expect_same_set(a, waiting.perform(r, kSinceNs + 30 * kDayNs), false);
    expect_same_set(a, flat.perform(r, 0));
  }
  // The fixture and the tracker likewise.
  const FixtureSimulator fixture = FixtureSimulator::for_machine(m, c);
  const FixtureSimulator fixture_waiting = FixtureSimulator::for_machine(m, not_yet);
  const CheckRequest pre =
      testing::fixture_request("pm1", "today-pre", CheckKind::FixturePreCalibration, 2);
  const MeasurementSet p = perform_fixture_check(plain, fixture, pre, 0);
  ASSERT_TRUE(p.error.empty()) << p.error;
  expect_same_set(p, perform_fixture_check(waiting, fixture_waiting, pre, kSinceNs), false);
  const TrackerSimulator tracker(m, c), tracker_waiting(m, not_yet);
  const CheckRequest circle = request("pm1", "today-circle", CheckKind::CircleXY);
  expect_same_set(tracker.perform(circle, 0), tracker_waiting.perform(circle, kSinceNs), false);
}

// ---- The fixture --------------------------------------------------------------------------------

TEST(DriftFixture, PreCalibrationSeesTheZeroDriftAndZeroOffsetsCancelItUntilThen) {
  const MachineConfig m = pm1_with_fixture();
  const double sigma = 0.001;
  SimulatorConfig c = simulator_config(sigma, 24);
  c.drift = SimulatorDrift{};
  c.drift->since_ns = kSinceNs;
  c.drift->fixture_column_x_offset_mm_per_day = 0.002;
  c.drift->fixture_pogo_z_offset_mm_per_day = -0.001;
  const MachineSimulator machine(m, c);
  FixtureSimulator fixture = FixtureSimulator::for_machine(m, c);
  EXPECT_NEAR(fixture.ground_truth_at(kSinceNs + 20 * kDayNs).column_x.offset_mm, 0.04, 1e-15);
  EXPECT_EQ(fixture.ground_truth().column_x.offset_mm, 0.0);

  auto precal = [&](const std::string& id, int k, std::int64_t t) {
    const MeasurementSet set = perform_fixture_check(
        machine, fixture, testing::fixture_request("pm1", id, CheckKind::FixturePreCalibration, k),
        t);
    EXPECT_TRUE(set.error.empty()) << set.error;
    return measured_pogo_deltas(set, m, k);
  };
  const auto d0 = precal("pre-0", 0, kSinceNs);
  const auto d20 = precal("pre-20", 0, kSinceNs + 20 * kDayNs);
  ASSERT_EQ(d0.size(), 12u);
  // X, Y: mean of two side touches (sigma / sqrt(2)), two days apart: sigma. Z: one touch each.
  double worst_x = 0;
  for (const auto& [pogo, a] : d0) {
    const Eigen::Vector3d growth = d20.at(pogo) - a;
    EXPECT_NEAR(growth.x(), 0.04, 5 * sigma) << pogo;
    EXPECT_NEAR(growth.y(), 0.0, 5 * sigma) << pogo;
    EXPECT_NEAR(growth.z(), -0.02, 5 * std::sqrt(2.0) * sigma) << pogo;
    worst_x = std::max(worst_x, std::abs(growth.x() - 0.04));
  }
  std::printf("  fixture dx growth over 20 days: 0.04 mm within %.5f mm on 12 pogos\n", worst_x);

  // The pre-calibration's zero offsets (its measured deltas) cancel what had drifted by day 20;
  // a week later seven days' worth is back: 0.014 mm in X, -0.007 mm in Z.
  fixture.apply_zero_offsets(zero_offsets_from(d20, *m.fixture));
  const auto d27 = precal("pre-27", 0, kSinceNs + 27 * kDayNs);
  for (const auto& [pogo, d] : d27) {
    EXPECT_NEAR(d.x(), 0.014, 5 * sigma) << pogo;
    EXPECT_NEAR(d.y(), 0.0, 5 * sigma) << pogo;
    EXPECT_NEAR(d.z(), -0.007, 5 * std::sqrt(2.0) * sigma) << pogo;
  }
  // at() keeps the control unit's zero offsets.
  EXPECT_EQ(fixture.at(kSinceNs).zero_offsets(), fixture.zero_offsets());
}

// ---- The tracker --------------------------------------------------------------------------------

TEST(DriftTracker, SquarenessGrowsAndTheGridMeasuresTheTruthOfItsTime) {
  const MachineConfig m = load_machine_config(NCQUAL_SOURCE_DIR "/deploy/machines/pm1.yaml");
  SimulatorConfig c = m.simulator;
  c.volumetric = VolumetricTruth{};  // a perfect machine but for the squareness
  c.volumetric.rigid_body.ec0xy_rad = 12e-6;
  c.drift = SimulatorDrift{};
  c.drift->since_ns = kSinceNs;
  c.drift->squareness_ec0xy_rad_per_day = 0.5e-6;
  const TrackerSimulator tracker(m, c);
  const std::int64_t t = kSinceNs + 20 * kDayNs;
  // EC(0X)Y > 0 turns the Y axis line towards -X: moving Y by dy moves X by -EC(0X)Y dy.
  AxisPosition low, high;
  low.x_mm = high.x_mm = 2200;
  low.z_mm = high.z_mm = 900;
  low.y_mm = 200;
  high.y_mm = 1700;
  const ProbeGeometry& target = m.global_check->targets.front();
  for (const auto& [when, ec] : {std::pair<std::int64_t, double>{kSinceNs, 12e-6}, {t, 22e-6}}) {
    const TrackerSimulator frozen = tracker.at(when);
    const Eigen::Vector3d dp = frozen.true_target(high, target) - frozen.true_target(low, target);
    EXPECT_NEAR(dp.x(), -ec * 1500, 1e-9);
    EXPECT_NEAR(dp.y(), 1500, 1e-6);
  }
  const CheckRequest grid = request("pm1", "grid-20", CheckKind::GlobalGrid);
  const MeasurementSet drifting = tracker.perform(grid, t);
  ASSERT_TRUE(drifting.error.empty()) << drifting.error;
  expect_same_set(drifting, TrackerSimulator(m, config_at(c, t)).perform(grid, t));
}

// ---- The scenario deploy/scenarios/drift.yaml ---------------------------------------------------

TEST(DriftScenario, CheckThreeStartsFailingAfterFourToSixWeeksAndTheFixtureIsCorrectedBefore) {
  const MachineConfig m = load_machine_config(NCQUAL_SOURCE_DIR "/deploy/scenarios/drift.yaml");
  const SimulatorConfig c = m.simulator;
  ASSERT_TRUE(c.drift.has_value());
  EXPECT_EQ(c.drift->since_ns, kSinceNs);
  const double tol = m.tolerances.at("center_dy_mm").upper;
  const double rate = std::abs(c.drift->machine_shift_mm_per_day.y());
  ASSERT_GT(rate, 0);
  const double crossing = tol / rate;  // days until |center_dy| = tolerance, noise aside
  EXPECT_GT(crossing, 28);
  EXPECT_LT(crossing, 42);

  // The daily check 3 of the plant calendar (Monday to Friday, first shift 06:00 Berlin = 05:00
  // UTC, measured at about 05:18 after checks 1 and 2), 8 weeks, with the scenario's seed.
  const MachineSimulator sim(m, c);
  const std::int64_t at_0518 = (5 * 60 + 18) * 60LL * 1000000000;
  int first_fail = -1, last_pass = -1;
  for (int day = 0; day < 56; ++day) {
    if (day % 7 >= 5) continue;  // 2026-01-05 is a Monday
    const std::int64_t t = kSinceNs + day * kDayNs + at_0518;
    const MeasurementSet set = sim.perform(request("pm1", "daily3-" + std::to_string(day)), t);
    ASSERT_TRUE(set.error.empty()) << set.error;
    const double dy = measured_positioning(set, m).y();
    if (std::abs(dy) > tol) {
      if (first_fail < 0) first_fail = day;
    } else {
      last_pass = day;
    }
  }
  std::printf(
      "  scenario: |center_dy| reaches %.3f mm after %.1f days; first failing check 3 on "
      "day %d, last passing on day %d\n",
      tol, crossing, first_fail, last_pass);
  EXPECT_GE(first_fail, 28);
  EXPECT_LE(first_fail, 42);
  EXPECT_LT(last_pass, 42);

  // The weekly pre-calibration (Mondays after the daily checks, about 05:45 UTC; configuration k
  // in week k): passes in week 3 (day 14), fails on the fixture's zero drift in week 4 (day 21)
  // and, with the zero offsets it issues, passes in week 5 (day 28, odd rows again).
  ASSERT_TRUE(m.fixture.has_value());
  const double fixture_tol = m.tolerances.at("fixture_delta_mm").upper;
  FixtureSimulator fixture = FixtureSimulator::for_machine(m, c);
  const std::int64_t at_0545 = (5 * 60 + 45) * 60LL * 1000000000;
  auto precal = [&](int week) {
    const std::int64_t t = kSinceNs + week * 7 * kDayNs + at_0545;
    const MeasurementSet set =
        perform_fixture_check(sim, fixture,
                              testing::fixture_request("pm1", "weekly-" + std::to_string(week),
                                                       CheckKind::FixturePreCalibration, week),
                              t);
    EXPECT_TRUE(set.error.empty()) << set.error;
    return measured_pogo_deltas(set, m, week);
  };
  auto worst = [&](const std::map<std::string, Eigen::Vector3d>& d) {
    return std::max({largest_magnitude(d, 0), largest_magnitude(d, 1), largest_magnitude(d, 2)});
  };
  const auto week2 = precal(2), week3 = precal(3);
  EXPECT_LT(worst(week2), fixture_tol);
  EXPECT_GT(largest_magnitude(week3, 0), fixture_tol);
  fixture.apply_zero_offsets(zero_offsets_from(week3, *m.fixture));
  const auto week4 = precal(4);
  EXPECT_LT(worst(week4), fixture_tol);
  std::printf(
      "  scenario fixture: largest delta %.4f mm (day 14), dx %.4f mm (day 21), "
      "%.4f mm after zero offsets (day 28)\n",
      worst(week2), largest_magnitude(week3, 0), worst(week4));
}

}  // namespace
}  // namespace ncqual::sim

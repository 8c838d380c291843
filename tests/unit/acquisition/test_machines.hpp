// SPDX-License-Identifier: Apache-2.0
// Machine configs, simulator configs and requests for the solver and simulator unit tests.
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/common/model.hpp"
#include "ncqual/sim/simulator_config.hpp"

#include <random>
#include <stdexcept>
#include <string>
#include <string_view>

namespace ncqual::testing {

// The metric of `name` in a result; throws (failing the test) with the result's reason when
// the check did not report it.
inline const Metric& metric(const CheckResult& r, std::string_view name) {
  const Metric* m = find_metric(r, name);
  if (!m) throw std::runtime_error("no metric " + std::string(name) + ": " + r.reason);
  return *m;
}

inline double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

// A machine like deploy/machines/pm1.yaml, built in code.
inline MachineConfig pm1_like_machine() {
  MachineConfig m;
  m.machine_id = "pm1";
  m.source_path = "test:pm1";
  m.probe.tool_length_mm = 350.0;
  m.probe.ball_radius_mm = 3.0;
  m.monument.hole_center_mm = Eigen::Vector2d(1200.0, 800.0);
  m.monument.hole_diameter_mm = 50.0;
  m.monument.face_z_mm = 150.0;
  m.monument.probe_depth_mm = 5.0;
  m.monument.gauge_width_mm = 200.0;
  m.monument.face_offset_mm = 35.0;
  m.monument.hole_touches = 4;
  for (const char* metric : {"center_dx_mm", "center_dy_mm", "face_dz_mm"}) {
    m.tolerances[metric] = Tolerance{-0.025, 0.025};
  }
  return m;
}

// A random but sensible machine and monument: the hole leaves the ball at least 5 mm of room,
// the edge touches land on the plate's wall, the face touch lands on the plate.
inline MachineConfig random_machine(std::mt19937_64& rng, const std::string& id = "m1") {
  MachineConfig m = pm1_like_machine();
  m.machine_id = id;
  m.probe.tool_length_mm = uniform(rng, 150, 450);
  m.probe.ball_radius_mm = uniform(rng, 1, 4);
  m.monument.hole_center_mm = Eigen::Vector2d(uniform(rng, -2000, 2000), uniform(rng, -2000, 2000));
  m.monument.hole_diameter_mm = 2 * (m.probe.ball_radius_mm + uniform(rng, 5, 35));
  m.monument.face_z_mm = uniform(rng, -500, 500);
  m.monument.probe_depth_mm = uniform(rng, 2, 15);
  m.monument.gauge_width_mm = m.monument.hole_diameter_mm + uniform(rng, 60, 200);
  m.monument.face_offset_mm = m.monument.hole_diameter_mm / 2 + uniform(rng, 5, 25);
  m.monument.hole_touches = std::uniform_int_distribution<int>(3, 8)(rng);
  return m;
}

inline sim::SimulatorConfig simulator_config(double sigma_mm, std::uint64_t seed = 7) {
  sim::SimulatorConfig c;
  c.seed = seed;
  c.trigger_noise_sigma_mm = sigma_mm;
  c.plate_thickness_mm = 20.0;
  return c;
}

inline CheckRequest request(const std::string& machine_id, const std::string& request_id,
                            CheckKind kind = CheckKind::MonumentPositioning) {
  CheckRequest r;
  r.machine_id = machine_id;
  r.request_id = request_id;
  r.kind = kind;
  r.requested_by = "test";
  r.time_ns = 1'700'000'000'000'000'000;
  return r;
}

}  // namespace ncqual::testing

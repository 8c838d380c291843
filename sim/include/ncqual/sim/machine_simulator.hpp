// SPDX-License-Identifier: Apache-2.0
// The instrument simulator: stands in for a five-axis post mill with a touch-trigger probe and
// its monument. It runs the probing program of a check on a true machine that differs from the
// nominal one by known errors, and returns raw touches (axis readouts) as the real control
// would, never the answer. Its errors are exposed as ground truth for tests.
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/common/kinematics.hpp"
#include "ncqual/common/model.hpp"
#include "ncqual/sim/contact.hpp"
#include "ncqual/probing/plan.hpp"
#include "ncqual/sim/simulator_config.hpp"

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>

namespace ncqual::sim {

using probing::ProbingMove;

class MachineSimulator {
 public:
  MachineSimulator(MachineConfig machine, SimulatorConfig config);

  // Performs the check `request` asks for, measured at `time_ns` (ns since the Unix epoch, UTC):
  // on the truth at that time (at(time_ns); without a drift section the truth is the same at
  // every time). The touches are reproducible: the noise comes from a generator seeded by
  // (config seed, request_id) alone. A touch whose move meets no surface is left out and `error`
  // says so; a kind the simulator cannot perform yields no touches and error "the simulator
  // cannot perform check kind '<name>' yet".
  MeasurementSet perform(const CheckRequest& request, std::int64_t time_ns) const;

  // The configured (base) errors: the truth without drift, or at and before drift.since.
  const SimulatorErrors& ground_truth() const { return config_.errors; }
  // The errors at `now_ns`: errors_at(config(), now_ns).
  SimulatorErrors ground_truth_at(std::int64_t now_ns) const { return errors_at(config_, now_ns); }
  const MachineConfig& machine() const { return machine_; }
  const SimulatorConfig& config() const { return config_; }

  // The simulator frozen at `now_ns`: the same machine, seed and noise with the truth of that
  // time (config_at(config(), now_ns), drift cleared). Without drift, an identical copy.
  MachineSimulator at(std::int64_t now_ns) const;

  // ---- The true world (for tests and demonstrations) ----
  // These hold the base truth (ground_truth()); for the truth at a time ask at(now_ns).
  // True axes: pivot = readout + machine_shift, A = a + a_home_error, C = c + c_angle_error.
  AxisPosition true_axes(const AxisPosition& readouts) const;
  // True probe: L = nominal + tool_length_error, offset = nominal + stylus_offset error.
  const ProbeGeometry& true_probe() const { return true_probe_; }
  // True ball centre for given readouts: the nominal kinematics formula, true parameters.
  Eigen::Vector3d true_ball_centre(const AxisPosition& readouts) const;
  // True monument: the taught one moved by monument_shift.
  const RingGaugePlate& true_monument() const { return true_monument_; }

  // True set-point blocks of the part loaded for `request_id`: intended corner + the block's
  // shift + the part's seating offset for that request (reproducible, like the touch noise).
  std::map<std::string, SetPointBlock> true_setpoint_blocks(const std::string& request_id) const;
  // The seating offset of the part loaded for `request_id`.
  Eigen::Vector3d part_seating_mm(const std::string& request_id) const;

  // Runs one probing move on the true machine against the monument (or `block`). `noise_mm`
  // displaces the latched readouts along the move. Returns the touch, or std::nullopt with
  // `*why` set when the probe alarms.
  std::optional<Touch> execute(const ProbingMove& move, double noise_mm, std::string* why) const;
  std::optional<Touch> execute(const ProbingMove& move, double noise_mm, const SetPointBlock& block,
                               std::string* why) const;

  // The same against any body: `find_contact` gives the first contact of the true ball's move
  // within its travel (std::nullopt: none), `cuts_into` whether a ball at (centre, radius)
  // already cuts into the body at the start, when the probe deflects at once. `body` names it
  // in the alarm ("the monument", ...).
  using ContactFinder = std::function<std::optional<Contact>(const BallMove&)>;
  using StartCheck = std::function<bool(const Eigen::Vector3d& centre, double radius)>;
  std::optional<Touch> execute(const ProbingMove& move, double noise_mm,
                               const ContactFinder& find_contact, const StartCheck& cuts_into,
                               const std::string& body, std::string* why) const;

 private:
  MachineConfig machine_;
  SimulatorConfig config_;
  ProbeGeometry true_probe_;
  RingGaugePlate true_monument_;
};

}  // namespace ncqual::sim

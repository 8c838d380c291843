// SPDX-License-Identifier: Apache-2.0
#include "ncqual/sim/machine_simulator.hpp"

#include "ncqual/sim/request_random.hpp"

#include <cmath>
#include <cstdio>
#include <vector>

namespace ncqual::sim {
namespace {

std::string format_vector(const Eigen::Vector3d& v) {
  char buffer[128];
  std::snprintf(buffer, sizeof buffer, "(%.6f, %.6f, %.6f)", v.x(), v.y(), v.z());
  return buffer;
}

// The instrument a check kind uses and the frame its coordinates are in.
void describe_instrument(CheckKind kind, MeasurementSet* set) {
  const bool tracker = is_tracker_check(kind);
  set->instrument = tracker ? "laser_tracker" : "touch_probe";
  set->frame = tracker ? "tracker" : "machine";
}

ProbeGeometry make_true_probe(const ProbeGeometry& nominal, const SimulatorErrors& e) {
  ProbeGeometry p = nominal;
  p.tool_length_mm += e.tool_length_error_mm;
  p.stylus_offset_mm += e.stylus_offset_mm;
  return p;
}

RingGaugePlate make_true_monument(const MonumentConfig& taught, const SimulatorConfig& c) {
  RingGaugePlate plate;
  plate.hole_centre_mm = taught.hole_center_mm + c.errors.monument_shift_mm.head<2>();
  plate.hole_radius_mm = taught.hole_diameter_mm / 2;
  plate.face_z_mm = taught.face_z_mm + c.errors.monument_shift_mm.z();
  plate.thickness_mm = c.plate_thickness_mm;
  plate.width_mm = taught.gauge_width_mm;
  return plate;
}

AxisPosition moved(AxisPosition axes, const Eigen::Vector3d& by) {
  axes.x_mm += by.x();
  axes.y_mm += by.y();
  axes.z_mm += by.z();
  return axes;
}

}  // namespace

MachineSimulator::MachineSimulator(MachineConfig machine, SimulatorConfig config)
    : machine_(std::move(machine)),
      config_(std::move(config)),
      true_probe_(make_true_probe(machine_.probe, config_.errors)),
      true_monument_(make_true_monument(machine_.monument, config_)) {}

MachineSimulator MachineSimulator::at(std::int64_t now_ns) const {
  return MachineSimulator(machine_, config_at(config_, now_ns));
}

AxisPosition MachineSimulator::true_axes(const AxisPosition& readouts) const {
  AxisPosition t = moved(readouts, config_.errors.machine_shift_mm);
  t.a_rad += config_.errors.a_home_error_rad;
  t.c_rad += config_.errors.c_angle_error_rad;
  return t;
}

Eigen::Vector3d MachineSimulator::true_ball_centre(const AxisPosition& readouts) const {
  return stylus_ball_centre(true_axes(readouts), true_probe_);
}

Eigen::Vector3d MachineSimulator::part_seating_mm(const std::string& request_id) const {
  if (config_.part_seating_sigma_mm <= 0) return Eigen::Vector3d::Zero();
  // Its own stream, so that seating does not change the touch noise of the request.
  NormalSource seating(request_seed(config_.seed ^ 0x5ea7ed5ea7ULL, request_id));
  Eigen::Vector3d offset;
  for (int k = 0; k < 3; ++k) offset[k] = config_.part_seating_sigma_mm * seating.next();
  return offset;
}

std::map<std::string, SetPointBlock> MachineSimulator::true_setpoint_blocks(
    const std::string& request_id) const {
  const Eigen::Vector3d seating = part_seating_mm(request_id);
  std::map<std::string, SetPointBlock> blocks;
  for (const SetPointConfig& point : machine_.setpoints.points) {
    SetPointBlock block;
    block.corner_mm = point.intended_mm + seating;
    if (auto it = config_.errors.setpoint_shift_mm.find(point.name);
        it != config_.errors.setpoint_shift_mm.end()) {
      block.corner_mm += it->second;
    }
    blocks[point.name] = block;
  }
  return blocks;
}

std::optional<Touch> MachineSimulator::execute(const ProbingMove& move, double noise_mm,
                                               std::string* why) const {
  return execute(
      move, noise_mm, [&](const BallMove& ball) { return first_contact(true_monument_, ball); },
      [&](const Eigen::Vector3d& c, double r) { return true_monument_.overlaps_ball(c, r); },
      "the monument", why);
}

std::optional<Touch> MachineSimulator::execute(const ProbingMove& move, double noise_mm,
                                               const SetPointBlock& block, std::string* why) const {
  return execute(
      move, noise_mm, [&](const BallMove& ball) { return first_contact(block, ball); },
      [&](const Eigen::Vector3d& c, double r) { return block.contains(c, r); },
      "the set-point block", why);
}

std::optional<Touch> MachineSimulator::execute(const ProbingMove& move, double noise_mm,
                                               const ContactFinder& find_contact,
                                               const StartCheck& cuts_into, const std::string& body,
                                               std::string* why) const {
  // The axes move the readouts along u; the true ball centre then moves along
  //   b(s) = b(start + s u) = b0 + s t,  t = b(start + u) - b(start),
  // exact while the true machine is an affine map of the readouts (the errors modelled so
  // far). |t| converts readout travel into true travel (1 without scale errors).
  const Eigen::Vector3d b0 = true_ball_centre(move.start);
  const Eigen::Vector3d t = true_ball_centre(moved(move.start, move.direction)) - b0;
  const double scale = t.norm();

  BallMove ball;
  ball.start = b0;
  ball.direction = t / scale;
  ball.travel_mm = move.travel_mm * scale;
  ball.ball_radius_mm = true_probe_.ball_radius_mm;

  if (cuts_into(b0, ball.ball_radius_mm)) {
    *why = "the probe was deflected at the start of the move at " + format_vector(b0) +
           " (stylus ball inside " + body + ")";
    return std::nullopt;
  }
  const auto contact = find_contact(ball);
  if (!contact) {
    char travel[32];
    std::snprintf(travel, sizeof travel, "%.6g", move.travel_mm);
    *why = "the probe did not trigger within " + std::string(travel) + " mm of travel from " +
           "X, Y, Z = " +
           format_vector(Eigen::Vector3d(move.start.x_mm, move.start.y_mm, move.start.z_mm)) +
           " along " + format_vector(move.direction) + " (no surface met)";
    return std::nullopt;
  }
  // Latched readouts: where the axes were when the ball met the surface, displaced along the
  // move by the trigger noise.
  const double readout_travel = contact->distance_mm / scale + noise_mm;
  Touch touch;
  touch.feature = move.feature;
  touch.axes = moved(move.start, readout_travel * move.direction);
  touch.approach = move.direction;
  return touch;
}

MeasurementSet MachineSimulator::perform(const CheckRequest& request, std::int64_t time_ns) const {
  // A drifting truth: measure on the simulator frozen at the measurement time (no drift there).
  if (config_.drift) return at(time_ns).perform(request, time_ns);
  MeasurementSet set = measurement_set_for(request, time_ns);
  set.origin = DataOrigin::Simulated;  // every set of the simulator, also one it cannot measure
  describe_instrument(request.kind, &set);

  if (request.machine_id != machine_.machine_id) {
    set.error = "the request is for machine '" + request.machine_id +
                "' but this simulator is machine '" + machine_.machine_id + "'";
    return set;
  }
  // The monument and set-point plans run here; the fixture's are perform_fixture_check's.
  const probing::TouchPlan plan = probing::touch_plan(request, machine_);
  const std::optional<std::vector<ProbingMove>> program =
      plan.error.empty() && !is_fixture_check(request.kind) ? std::optional(plan.moves)
                                                            : std::nullopt;
  if (!program) {
    set.error = "the simulator cannot perform check kind '" + std::string(to_string(request.kind)) +
                "' yet";
    return set;
  }

  NormalSource noise(request_seed(config_.seed, request.request_id));
  std::map<std::string, SetPointBlock> blocks;
  if (request.kind == CheckKind::PartSetPoints) blocks = true_setpoint_blocks(request.request_id);
  // Set-point touches ("setpoint:<name>:<axis>") meet their block, the others the monument.
  auto run = [&](const ProbingMove& move, double noise_mm, std::string* why) {
    if (request.kind != CheckKind::PartSetPoints) return execute(move, noise_mm, why);
    const std::size_t first = move.feature.find(':'), last = move.feature.rfind(':');
    const auto block = blocks.find(move.feature.substr(first + 1, last - first - 1));
    return execute(move, noise_mm, block->second, why);
  };
  std::vector<std::string> alarms;
  for (std::size_t i = 0; i < program->size(); ++i) {
    const ProbingMove& move = (*program)[i];
    // One deviate per move, drawn whether or not it triggers, so the noise of a touch depends
    // only on its place in the program.
    const double noise_mm = config_.trigger_noise_sigma_mm * noise.next();
    std::string why;
    if (auto touch = run(move, noise_mm, &why)) {
      set.touches.push_back(std::move(*touch));
    } else {
      alarms.push_back("move " + std::to_string(i) + " ('" + move.feature + "'): " + why);
    }
  }
  for (std::size_t i = 0; i < alarms.size(); ++i) {
    set.error += (i ? "; " : "probe alarm: ") + alarms[i];
  }
  return set;
}

}  // namespace ncqual::sim

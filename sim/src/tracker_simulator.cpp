// SPDX-License-Identifier: Apache-2.0
#include "ncqual/sim/tracker_simulator.hpp"

#include "ncqual/common/kinematics.hpp"
#include "ncqual/sim/request_random.hpp"
#include "ncqual/common/units.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <stdexcept>

namespace ncqual::sim {
namespace {

Eigen::Matrix3d rotation_about(const Eigen::Vector3d& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

}  // namespace

TrackerSimulator::TrackerSimulator(MachineConfig machine, SimulatorConfig config)
    : machine_(std::move(machine)), config_(std::move(config)) {
  if (!machine_.global_check) {
    throw std::invalid_argument("machine '" + machine_.machine_id +
                                "' has no global_check: section; the tracker has nothing to run");
  }
}

TrackerSimulator TrackerSimulator::at(std::int64_t now_ns) const {
  return TrackerSimulator(machine_, config_at(config_, now_ns));
}

Eigen::Vector3d TrackerSimulator::true_target(const AxisPosition& axes, const ProbeGeometry& target,
                                              const Eigen::Vector3i& direction) const {
  const VolumetricTruth& v = config_.volumetric;
  const SimulatorErrors& e = config_.errors;
  // Linear axes: reversal (the axis lags the command by half the backlash), thermal expansion of
  // the scales about the axis zero, then the 21 rigid-body errors carry the wrist.
  Eigen::Vector3d q(axes.x_mm, axes.y_mm, axes.z_mm);
  for (int k = 0; k < 3; ++k) {
    q[k] -= direction[k] * v.backlash_mm[k] / 2;
    q[k] *= 1 + v.expansion_per_K[k] * (v.temperature_C[k] - 20.0);
  }
  q += e.machine_shift_mm;
  // The wrist: C about its (tilted) axis, A about its (tilted) axis in the head, W along its
  // (tilted) travel; angles with their zero errors and once-per-turn errors.
  const Eigen::Vector3d c_axis =
      (Eigen::AngleAxisd(v.c_axis_tilt_rad[0], Eigen::Vector3d::UnitX()) *
       Eigen::AngleAxisd(v.c_axis_tilt_rad[1], Eigen::Vector3d::UnitY())) *
      Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d a_axis =
      (Eigen::AngleAxisd(v.a_axis_tilt_rad[0], Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(v.a_axis_tilt_rad[1], Eigen::Vector3d::UnitZ())) *
      Eigen::Vector3d::UnitX();
  const double c = axes.c_rad + e.c_angle_error_rad +
                   v.c_periodic_rad * std::sin(axes.c_rad + v.c_periodic_phase_rad);
  const double a = axes.a_rad + e.a_home_error_rad + v.a_periodic_rad * std::sin(axes.a_rad);
  const Eigen::Vector3d w_dir =
      Eigen::Vector3d(v.w_misalignment_rad[0], v.w_misalignment_rad[1], 1.0).normalized();
  const Eigen::Vector3d in_body(target.stylus_offset_mm.x(), target.stylus_offset_mm.y(),
                                -target.tool_length_mm);
  const Eigen::Vector3d body = in_body - axes.w_mm * (1 + v.w_scale_ppm * 1e-6) * w_dir;
  const Eigen::Vector3d tool_offset = rotation_about(c_axis, c) * rotation_about(a_axis, a) * body;
  return volumetric::actual_position(v.rigid_body, q, tool_offset);
}

MeasurementSet TrackerSimulator::perform(const CheckRequest& request, std::int64_t time_ns) const {
  // A drifting truth: measure on the simulator frozen at the measurement time (no drift there).
  if (config_.drift) return at(time_ns).perform(request, time_ns);
  MeasurementSet set = measurement_set_for(request, time_ns);
  set.origin = DataOrigin::Simulated;
  set.instrument = "laser_tracker";
  set.frame = "tracker";
  if (!is_tracker_check(request.kind)) {
    set.error = "the laser tracker cannot perform check kind '" +
                std::string(to_string(request.kind)) + "'";
    return set;
  }
  const GlobalCheckConfig& gc = *machine_.global_check;
  NormalSource normal(request_seed(config_.seed, request.request_id));
  const TrackerModel& tracker = config_.tracker;
  Eigen::Matrix3d to_machine = tracker.rotation();
  Eigen::Vector3d station = tracker.position_mm;
  double range_sigma_0 = tracker.radial_sigma_mm, range_sigma_per_m = tracker.radial_sigma_mm_per_m;
  if (request.kind == CheckKind::LinearAxisRun) {
    // Second station: on the line of the run's target, before the first target, its x axis along
    // the machine axis; range in interferometer mode.
    const LinearRunConfig& run = gc.linear_run;
    Eigen::Vector3d before = run.at_mm;
    before[run.axis] = run.targets_mm.front() - tracker.linear_run_standoff_mm;
    AxisPosition start;
    start.x_mm = before.x();
    start.y_mm = before.y();
    start.z_mm = before.z();
    station = stylus_ball_centre(start, gc.targets.front());
    to_machine = Eigen::Matrix3d::Identity();
    if (run.axis == 1)
      to_machine = Eigen::AngleAxisd(units::kPi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    if (run.axis == 2)
      to_machine = Eigen::AngleAxisd(-units::kPi / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
    range_sigma_0 = tracker.ifm_sigma_mm;
    range_sigma_per_m = tracker.ifm_sigma_mm_per_m;
  }
  const double repeat = config_.volumetric.repeatability_sigma_mm;

  Eigen::Vector3i direction = Eigen::Vector3i::Ones();
  Eigen::Vector3d last = Eigen::Vector3d::Constant(std::nan(""));
  for (const TrackerMove& move : global_check_program(request.kind, gc)) {
    const Eigen::Vector3d cmd(move.commanded.x_mm, move.commanded.y_mm, move.commanded.z_mm);
    for (int k = 0; k < 3; ++k) {
      if (!std::isnan(last[k]) && cmd[k] != last[k]) direction[k] = cmd[k] > last[k] ? 1 : -1;
    }
    last = cmd;
    if (move.label.empty()) continue;
    AxisPosition landed = move.commanded;
    landed.x_mm += repeat * normal.next();
    landed.y_mm += repeat * normal.next();
    landed.z_mm += repeat * normal.next();
    const ProbeGeometry& target = gc.targets.at(static_cast<std::size_t>(move.target));
    const Eigen::Vector3d in_tracker =
        to_machine.transpose() * (true_target(landed, target, direction) - station);
    Eigen::Vector3d s = tracker_spherical(in_tracker);
    const double averaged = 1 / std::sqrt(static_cast<double>(tracker.samples_per_point));
    const double range_sigma = (range_sigma_0 + range_sigma_per_m * s[0] / 1000) * averaged;
    s[0] += range_sigma * normal.next();
    s[1] += tracker.angular_sigma_rad * averaged * normal.next();
    s[2] += tracker.angular_sigma_rad * averaged * normal.next();
    TrackerPoint point;
    point.label = move.label;
    point.commanded = move.commanded;
    point.measured_mm = tracker_cartesian(s);
    set.tracker_points.push_back(std::move(point));
  }
  return set;
}

}  // namespace ncqual::sim

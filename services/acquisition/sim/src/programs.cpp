// SPDX-License-Identifier: Apache-2.0
#include "ncqual/sim/programs.hpp"

#include "ncqual/kinematics.hpp"
#include "ncqual/units.hpp"

#include <cmath>

namespace ncqual::sim {

AxisPosition axes_placing_ball_at(const Eigen::Vector3d& ball_centre, double a_rad, double c_rad,
                                  double w_mm, const ProbeGeometry& nominal_probe) {
  const Eigen::Vector3d in_body(nominal_probe.stylus_offset_mm.x(),
                                nominal_probe.stylus_offset_mm.y(),
                                -(nominal_probe.tool_length_mm + w_mm));
  const Eigen::Vector3d pivot = ball_centre - wrist_rotation(a_rad, c_rad) * in_body;
  AxisPosition axes;
  axes.x_mm = pivot.x();
  axes.y_mm = pivot.y();
  axes.z_mm = pivot.z();
  axes.w_mm = w_mm;
  axes.a_rad = a_rad;
  axes.c_rad = c_rad;
  return axes;
}

namespace {

// Radial touches of the hole edge with the head at C = c (A = 0): from the hole centre
// outward; the ball meets the wall after R_hole - r_ball, the search goes kSearchOvertravelMm
// beyond.
void add_hole_edge_touches(const MachineConfig& machine, double c_rad,
                           std::vector<ProbingMove>* program) {
  const MonumentConfig& taught = machine.monument;
  const ProbeGeometry& probe = machine.probe;
  const Eigen::Vector3d inside_hole(taught.hole_center_mm.x(), taught.hole_center_mm.y(),
                                    taught.face_z_mm - taught.probe_depth_mm);
  const AxisPosition edge_start = axes_placing_ball_at(inside_hole, 0, c_rad, 0, probe);
  const double edge_travel =
      taught.hole_diameter_mm / 2 - probe.ball_radius_mm + kSearchOvertravelMm;
  const int n = taught.hole_touches;
  for (int k = 0; k < n; ++k) {
    const double theta = 2 * units::kPi * k / n;
    program->push_back({"hole_edge", edge_start,
                        Eigen::Vector3d(std::cos(theta), std::sin(theta), 0), edge_travel});
  }
}

// One touch of a vertical gauge edge: the ball starts `clearance` + r outside the edge plane
// at `on_edge` (a point of the edge plane), head at (a, c), and moves along `direction`.
ProbingMove gauge_edge_touch(const MachineConfig& machine, const char* feature,
                             const Eigen::Vector3d& on_edge, const Eigen::Vector3d& direction,
                             double a_rad, double c_rad) {
  const double gap = machine.probe.ball_radius_mm + kEdgeApproachClearanceMm;
  const Eigen::Vector3d start = on_edge - gap * direction;
  return {feature, axes_placing_ball_at(start, a_rad, c_rad, 0, machine.probe), direction,
          kEdgeApproachClearanceMm + kSearchOvertravelMm};
}

Eigen::Vector3d gauge_point(const MonumentConfig& taught, double dx, double dy) {
  return {taught.hole_center_mm.x() + dx, taught.hole_center_mm.y() + dy,
          taught.face_z_mm - taught.probe_depth_mm};
}

}  // namespace

std::vector<ProbingMove> monument_c_alignment_program(const MachineConfig& machine) {
  std::vector<ProbingMove> program;
  add_hole_edge_touches(machine, 0, &program);
  add_hole_edge_touches(machine, units::kPi, &program);
  return program;
}

std::vector<ProbingMove> monument_tool_length_program(const MachineConfig& machine) {
  const MonumentConfig& taught = machine.monument;
  const double half = taught.gauge_width_mm / 2;
  const double c = units::kPi / 2;
  return {gauge_edge_touch(machine, "gauge_edge_+x", gauge_point(taught, half, 0),
                           -Eigen::Vector3d::UnitX(), units::kPi / 2, c),
          gauge_edge_touch(machine, "gauge_edge_-x", gauge_point(taught, -half, 0),
                           Eigen::Vector3d::UnitX(), -units::kPi / 2, c)};
}

std::vector<ProbingMove> monument_c_rotation_program(const MachineConfig& machine) {
  const MonumentConfig& taught = machine.monument;
  const Eigen::Vector3d upper_edge = gauge_point(taught, 0, taught.gauge_width_mm / 2);
  const double c = units::kPi / 2;
  return {gauge_edge_touch(machine, "gauge_edge_+y", upper_edge, -Eigen::Vector3d::UnitY(),
                           units::kPi / 2, c),
          gauge_edge_touch(machine, "gauge_edge_+y", upper_edge, -Eigen::Vector3d::UnitY(),
                           -units::kPi / 2, c)};
}

std::vector<ProbingMove> part_setpoints_program(const MachineConfig& machine) {
  const PartSetPointsConfig& sp = machine.setpoints;
  const double gap = machine.probe.ball_radius_mm + kEdgeApproachClearanceMm;
  const double travel = kEdgeApproachClearanceMm + kSearchOvertravelMm;
  std::vector<ProbingMove> program;
  for (const SetPointConfig& point : sp.points) {
    const Eigen::Vector3d& c = point.intended_mm;
    const std::string prefix = "setpoint:" + point.name + ":";
    const struct {
      const char* axis;
      Eigen::Vector3d ball_start;
      Eigen::Vector3d direction;
    } touches[] = {
        {"z", {c.x() + sp.inset_mm, c.y() + sp.inset_mm, c.z() + gap}, -Eigen::Vector3d::UnitZ()},
        {"x",
         {c.x() - gap, c.y() + sp.inset_mm, c.z() - sp.probe_depth_mm},
         Eigen::Vector3d::UnitX()},
        {"y",
         {c.x() + sp.inset_mm, c.y() - gap, c.z() - sp.probe_depth_mm},
         Eigen::Vector3d::UnitY()},
    };
    for (const auto& t : touches) {
      program.push_back({prefix + t.axis,
                         axes_placing_ball_at(t.ball_start, 0, 0, 0, machine.probe), t.direction,
                         travel});
    }
  }
  return program;
}

std::vector<ProbingMove> monument_positioning_program(const MachineConfig& machine) {
  const MonumentConfig& taught = machine.monument;
  const ProbeGeometry& probe = machine.probe;
  const double ball_r = probe.ball_radius_mm;
  std::vector<ProbingMove> program;
  add_hole_edge_touches(machine, 0, &program);

  // Face touch: down along -Z onto the face beside the hole.
  const Eigen::Vector3d above_face(taught.hole_center_mm.x() + taught.face_offset_mm,
                                   taught.hole_center_mm.y(),
                                   taught.face_z_mm + ball_r + kFaceApproachClearanceMm);
  program.push_back({"face", axes_placing_ball_at(above_face, 0, 0, 0, probe),
                     -Eigen::Vector3d::UnitZ(), kFaceApproachClearanceMm + kSearchOvertravelMm});
  return program;
}

std::optional<std::vector<ProbingMove>> program_for(CheckKind kind, const MachineConfig& machine) {
  switch (kind) {
    case CheckKind::MonumentCAlignment: return monument_c_alignment_program(machine);
    case CheckKind::MonumentToolLength: return monument_tool_length_program(machine);
    case CheckKind::MonumentPositioning: return monument_positioning_program(machine);
    case CheckKind::MonumentCRotation: return monument_c_rotation_program(machine);
    case CheckKind::PartSetPoints:
      if (machine.setpoints.points.empty()) return std::nullopt;
      return part_setpoints_program(machine);
    default: return std::nullopt;
  }
}

}  // namespace ncqual::sim

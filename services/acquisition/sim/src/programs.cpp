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

std::vector<ProbingMove> monument_positioning_program(const MachineConfig& machine) {
  const MonumentConfig& taught = machine.monument;
  const ProbeGeometry& probe = machine.probe;
  const double ball_r = probe.ball_radius_mm;
  std::vector<ProbingMove> program;

  // Edge touches: from the hole centre radially outward; the ball meets the wall after
  // R_hole - r_ball, the search goes kSearchOvertravelMm beyond.
  const Eigen::Vector3d inside_hole(taught.hole_center_mm.x(), taught.hole_center_mm.y(),
                                    taught.face_z_mm - taught.probe_depth_mm);
  const AxisPosition edge_start = axes_placing_ball_at(inside_hole, 0, 0, 0, probe);
  const double edge_travel = taught.hole_diameter_mm / 2 - ball_r + kSearchOvertravelMm;
  const int n = taught.hole_touches;
  for (int k = 0; k < n; ++k) {
    const double theta = 2 * units::kPi * k / n;
    program.push_back(
        {"hole_edge", edge_start, Eigen::Vector3d(std::cos(theta), std::sin(theta), 0),
         edge_travel});
  }

  // Face touch: down along -Z onto the face beside the hole.
  const Eigen::Vector3d above_face(taught.hole_center_mm.x() + taught.face_offset_mm,
                                   taught.hole_center_mm.y(),
                                   taught.face_z_mm + ball_r + kFaceApproachClearanceMm);
  program.push_back({"face", axes_placing_ball_at(above_face, 0, 0, 0, probe),
                     -Eigen::Vector3d::UnitZ(),
                     kFaceApproachClearanceMm + kSearchOvertravelMm});
  return program;
}

std::optional<std::vector<ProbingMove>> program_for(CheckKind kind, const MachineConfig& machine) {
  switch (kind) {
    case CheckKind::MonumentPositioning:
      return monument_positioning_program(machine);
    default:
      return std::nullopt;
  }
}

}  // namespace ncqual::sim

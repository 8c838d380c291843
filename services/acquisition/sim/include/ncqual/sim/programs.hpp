// SPDX-License-Identifier: Apache-2.0
// Probing programs: the moves the machine's control runs for each check, written as a real
// part program would be, against the nominal probe and the taught monument (the control knows
// nothing better). The simulator executes them on the true machine.
#pragma once

#include "ncqual/config.hpp"
#include "ncqual/model.hpp"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace ncqual::sim {

// One probing move: X, Y, Z travel from `start` along the unit `direction` (machine frame) by
// at most `travel_mm`; W, A and C stay where `start` has them. `feature` labels the touch.
struct ProbingMove {
  std::string feature;
  AxisPosition start;
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();
  double travel_mm = 0;
};

// How far past the expected contact a probing move searches before the probe alarms.
inline constexpr double kSearchOvertravelMm = 5.0;
// Height above the face at which the face touch starts (ball bottom to face).
inline constexpr double kFaceApproachClearanceMm = 5.0;

// Axis readouts that put the nominal ball centre at `ball_centre` with the head at (a, c) and
// the spindle at w: the inverse of the nominal kinematics,
//   P = b - Rz(c) Rx(a) ((ox, oy, 0) - (L + w) e_z).
AxisPosition axes_placing_ball_at(const Eigen::Vector3d& ball_centre, double a_rad, double c_rad,
                                  double w_mm, const ProbeGeometry& nominal_probe);

// Daily probe check 3 (repeatable positioning). Head at home (A = C = 0, W = 0).
//  - monument.hole_touches edge touches at angles theta_k = 2 pi k / N: each starts with the
//    ball centre at the taught hole centre, probe_depth below the taught face, and moves
//    radially outward along (cos theta_k, sin theta_k, 0);
//  - one face touch: starts above the taught face at taught centre + (face_offset, 0) and
//    moves along -Z.
std::vector<ProbingMove> monument_positioning_program(const MachineConfig& machine);

// Daily probe check 1 (probe alignment with the C axis). Body at A = 0; with the head at C = 0
// and then at C = 180 deg, monument.hole_touches radial edge touches as in check 3 (ball centre
// placed at the taught hole centre, probe_depth below the face, moving outward).
std::vector<ProbingMove> monument_c_alignment_program(const MachineConfig& machine);

// Daily probe check 2 (composite tool length). Head at C = 90 deg, W at home. With A = +90 deg
// (probe along -X) the ball starts kEdgeApproachClearanceMm outside the gauge edge at
// +gauge_width/2 and moves along -X; with A = -90 deg (probe along +X) it starts outside the
// edge at -gauge_width/2 and moves along +X. Both at the hole's Y, probe_depth below the face.
std::vector<ProbingMove> monument_tool_length_program(const MachineConfig& machine);

// Daily probe check 4 (C-axis rotational accuracy). Head at C = 90 deg; the ball starts
// kEdgeApproachClearanceMm above the gauge's upper edge (+gauge_width/2 in Y) at the hole's X,
// probe_depth below the face, and moves along -Y: once with A = +90 deg, once with A = -90 deg.
std::vector<ProbingMove> monument_c_rotation_program(const MachineConfig& machine);

// Per-part set points. Head at home (A = C = 0, W = 0). For each configured set point, with c
// its intended reference corner, i = setpoints.inset_mm and d = setpoints.probe_depth_mm:
//  - "setpoint:<name>:z": ball above the top face at (c.x + i, c.y + i), moving along -Z;
//  - "setpoint:<name>:x": ball clear of the -X face at (y = c.y + i, z = c.z - d), along +X;
//  - "setpoint:<name>:y": ball clear of the -Y face at (x = c.x + i, z = c.z - d), along +Y.
std::vector<ProbingMove> part_setpoints_program(const MachineConfig& machine);

// Gap between the ball and a gauge edge at the start of an edge touch.
inline constexpr double kEdgeApproachClearanceMm = 5.0;

// The program for `kind`, or std::nullopt when the simulator cannot perform it yet.
std::optional<std::vector<ProbingMove>> program_for(CheckKind kind, const MachineConfig& machine);

}  // namespace ncqual::sim

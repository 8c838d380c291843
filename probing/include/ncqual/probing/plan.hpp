// SPDX-License-Identifier: Apache-2.0
// Touch plans: the probing moves the machine's control runs for each probe check (the daily
// monument checks, the weekly fixture checks, the per-part set points), against the nominal probe,
// the taught monument and the commanded fixture and part (the control knows nothing better). The
// simulator executes them on its true machine; ncqual/probing/program.hpp writes them as part
// programs for real controls. One plan, so that a real machine and the simulator measure alike.
//
// Clearance (the gap between ball and surface at a move's start) and overtravel (how far past the
// expected contact the search goes before the probe alarms) come from the machine's `probing:`
// section (ProbingConfig; defaults kDefaultProbingClearanceMm, kDefaultProbingOvertravelMm).
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/common/fixture.hpp"
#include "ncqual/common/model.hpp"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace ncqual::probing {

// One probing move: X, Y, Z (the wrist pivot, machine coordinates) travel from `start` along the
// unit `direction` by at most `travel_mm`; W, A and C stay where `start` has them. `feature`
// labels the touch with the solver's feature name.
struct ProbingMove {
  std::string feature;
  AxisPosition start;
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();
  double travel_mm = 0;
};

// Axis readouts that put the nominal ball centre at `ball_centre` with the head at (a, c) and
// the spindle at w: the inverse of the nominal kinematics,
//   P = b - Rz(c) Rx(a) ((ox, oy, 0) - (L + w) e_z).
AxisPosition axes_placing_ball_at(const Eigen::Vector3d& ball_centre, double a_rad, double c_rad,
                                  double w_mm, const ProbeGeometry& nominal_probe);

// In the plans below g = probing.clearance_mm and o = probing.overtravel_mm.
//
// Daily probe check 3 (repeatable positioning). Head at home (A = C = 0, W = 0).
//  - monument.hole_touches edge touches at angles theta_k = 2 pi k / N: each starts with the
//    ball centre at the taught hole centre, probe_depth below the taught face, and moves
//    radially outward along (cos theta_k, sin theta_k, 0) by R_hole - r_ball + o;
//  - one face touch: starts g above the taught face (ball bottom to face) at taught centre +
//    (face_offset, 0) and moves along -Z by g + o.
std::vector<ProbingMove> monument_positioning_program(const MachineConfig& machine);

// Daily probe check 1 (probe alignment with the C axis). Body at A = 0; with the head at C = 0
// and then at C = 180 deg, monument.hole_touches radial edge touches as in check 3.
std::vector<ProbingMove> monument_c_alignment_program(const MachineConfig& machine);

// Daily probe check 2 (composite tool length). Head at C = 90 deg, W at home. With A = +90 deg
// (probe along -X) the ball starts g outside the gauge edge at +gauge_width/2 and moves along -X;
// with A = -90 deg (probe along +X) it starts g outside the edge at -gauge_width/2 and moves
// along +X. Both at the hole's Y, probe_depth below the face; travel g + o.
std::vector<ProbingMove> monument_tool_length_program(const MachineConfig& machine);

// Daily probe check 4 (C-axis rotational accuracy). Head at C = 90 deg; the ball starts g above
// the gauge's upper edge (+gauge_width/2 in Y) at the hole's X, probe_depth below the face, and
// moves along -Y: once with A = +90 deg, once with A = -90 deg; travel g + o.
std::vector<ProbingMove> monument_c_rotation_program(const MachineConfig& machine);

// Per-part set points. Head at home (A = C = 0, W = 0). For each configured set point, with c
// its intended reference corner, i = setpoints.inset_mm and d = setpoints.probe_depth_mm, each
// starting g from its face and travelling g + o:
//  - "setpoint:<name>:z": ball above the top face at (c.x + i, c.y + i), moving along -Z;
//  - "setpoint:<name>:x": ball clear of the -X face at (y = c.y + i, z = c.z - d), along +X;
//  - "setpoint:<name>:y": ball clear of the -Y face at (x = c.x + i, z = c.z - d), along +Y.
std::vector<ProbingMove> part_setpoints_program(const MachineConfig& machine);

// One move of a fixture plan and the pogo placement it probes.
struct FixtureMove {
  ProbingMove move;
  std::size_t placement = 0;  // index into FixturePlan::placements
  PogoFace face = PogoFace::Top;
};

struct FixturePlan {
  std::vector<PogoPlacement> placements;  // every probed placement, configurations in order
  std::vector<FixtureMove> moves;
  std::string error;  // non-empty when the request cannot be planned
};

// The weekly fixture checks (kinds FixturePreCalibration and FixturePostCalibration), head at
// home (A = C = 0, W = 0), for every probed pogo of every configuration, with q = origin + c its
// commanded top-face centre in the machine frame, h the block half size, d the fixture's probe
// depth and r the nominal ball radius:
//   top: ball centre from q + (0, 0, r + g) along -Z;
//   side face with outward normal n: from q + (h + r + g) n - d e_z along -n;
// travel g + o. Both sides in X and in Y, so the pogo's centre, the mean of the two side
// contacts, does not depend on the ball radius. Features "pogo:<label>:cfg<index>:<face>"
// (ncqual/common/fixture.hpp). Pre-calibration probes configuration k of the request's parameter
// "fixture_configuration" (required, an integer in 0 .. 2n-1); post-calibration every
// post-calibration configuration j in order, with the rows of pre-calibration configuration k
// when the parameter is given, else every row.
FixturePlan fixture_plan(const FixtureConfig& fixture, const ProbeGeometry& nominal_probe,
                         const ProbingConfig& probing, const CheckRequest& request);

// The touch plan of any probe check: `moves`, or `error` saying why the request cannot be
// planned (a kind measured by the tracker, a machine without the section the kind needs, a bad
// fixture configuration).
struct TouchPlan {
  std::vector<ProbingMove> moves;
  std::string error;
};
TouchPlan touch_plan(const CheckRequest& request, const MachineConfig& machine);

}  // namespace ncqual::probing

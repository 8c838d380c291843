// SPDX-License-Identifier: Apache-2.0
// The monthly global check with a laser tracker, as checks: a tracker MeasurementSet in, a
// CheckResult out. The point labels and the programs are those of ncqual/common/global_check.hpp;
// the evaluations are the pure functions of master_frame.hpp, global_grid.hpp, rotary_axes.hpp,
// circular_test.hpp, iso230_2.hpp and volumetric_identification.hpp. Every set but the master
// frame's own carries the master-frame runs of its session, so each check is judged on its own.
//
// Commanded target positions come from the commanded axes and the target's geometry
// (machine.global_check.targets[k], label suffix ":t<k>", k = 0 when absent) through the nominal
// kinematics (stylus_ball_centre).
//
// Metrics (each needs a tolerance in the machine config):
//   master frame   master_orthogonality_urad, master_x_straightness_mm, master_y_straightness_mm
//   grid           grid_max_deviation_mm, grid_rms_deviation_mm, grid_squareness_{xy,yz,zx}_urad,
//                  grid_scale_{x,y,z}_um_per_m, volumetric_residual_after_mm (when the grid has
//                  enough targets and points to identify the 21 errors)
//   rotary C / A   {c,a}_dA_mean_arcsec, {c,a}_dA_range_arcsec, {c,a}_dR_max_mm,
//   {c,a}_axis_tilt_urad rotary W       w_scale_um_per_m, w_misalignment_urad, w_straightness_mm
//   circles        circle_{xy,yz,xz}_G_mm, circle_{..}_H_mm (bidirectional runs)
//   linear run     linear_A_mm, linear_E_mm, linear_R_mm, linear_B_mm
// INVALID (never a throw) for a machine without a global_check section, a point label the
// program does not make, a non-finite reading, too few points, or anything the evaluations
// refuse; the reason names the field and value.
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/common/model.hpp"
#include "ncqual/solver/circular_test.hpp"
#include "ncqual/solver/global_grid.hpp"
#include "ncqual/solver/iso230_2.hpp"
#include "ncqual/solver/master_frame.hpp"

#include <vector>

namespace ncqual::solver {

CheckResult check_global_master_frame(const MeasurementSet& set, const MachineConfig& machine);
CheckResult check_global_grid(const MeasurementSet& set, const MachineConfig& machine);
CheckResult check_rotary_axis(const MeasurementSet& set, const MachineConfig& machine);
CheckResult check_circle(const MeasurementSet& set, const MachineConfig& machine);
CheckResult check_linear_axis_run(const MeasurementSet& set, const MachineConfig& machine);

// What three of these checks evaluate before they judge, for charts (the report's, the
// dashboard's): the same points, frame and evaluation the check's figures come from. Tolerances
// are not needed. Each throws std::invalid_argument with the reason the check would give for
// INVALID (no global_check section, a label the programs do not make, too few points, ...).
struct GlobalGridEvaluation {
  MasterFrame frame;  // of the set's own x_run and y_run
  GridAnalysis grid;  // the main target's grid points (grid:<i>:t0) in the master frame
};
GlobalGridEvaluation evaluate_global_grid(const MeasurementSet& set, const MachineConfig& machine);

struct CircleEvaluation {
  CircularTestInput input;  // the points in the plane (master frame), the nominal circle
  CircularTestResult result;
};
// A set of kind CircleXY, CircleYZ or CircleXZ.
CircleEvaluation evaluate_circle(const MeasurementSet& set, const MachineConfig& machine);

struct LinearRunEvaluation {
  int axis = 0;                              // 0, 1, 2 = X, Y, Z
  std::vector<PositioningReading> readings;  // as the check evaluates them
  Iso230_2Result result;
};
LinearRunEvaluation evaluate_linear_axis_run(const MeasurementSet& set,
                                             const MachineConfig& machine);

}  // namespace ncqual::solver

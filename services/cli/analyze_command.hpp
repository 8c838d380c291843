// `ncqual analyze`: the evaluations of instrument exports, run by a metrologist on a file, with
// no service, plant config or historian.
//
//   ncqual analyze iso230-2 FILE [--json]
//       a linear-axis positioning run (laser interferometer), evaluated per ISO 230-2:2014
//       (ncqual::solver::evaluate_iso230_2; file format: ncqual/solver/instrument_files.hpp)
//   ncqual analyze circle FILE [--plane XY|YZ|XZ] [--nominal-radius-mm R] [--centre-mm U,V]
//                              [--json]
//       a circular test (ballbar, grid encoder, tracker), evaluated per ISO 230-4
//       (ncqual::solver::evaluate_circular_test). --plane is needed for angle_deg,radius_mm and
//       u_mm,v_mm files, and must agree with an x_mm,y_mm-like header; --nominal-radius-mm and
//       --centre-mm (in the plane's u, v) are the reference of the radial deviation F (default:
//       the least-squares circle).
//
//   ncqual analyze grid --x-run F --y-run F --grid F [--json]
//       the monthly laser-tracker grid: the master frame from the X and Y runs
//       (ncqual::solver::fit_master_frame), then the grid's deviations, squareness and scale in it
//       (ncqual::solver::analyze_grid); files: point,x_cmd,y_cmd,z_cmd,x_meas,y_meas,z_meas (mm,
//       commanded in machine axes, measured in the tracker frame).
//
// Without --json a table of the figures in mm (4 decimals) is printed. --json prints one
// document; its names are a public interface (append, never rename); lengths in mm, absent
// figures null:
//   iso230-2: {"standard": "ISO 230-2:2014", "file", "unit": "mm", "targets" (m), "cycles"
//     (largest n), "directions": ["up", "down"] (those measured),
//     "A", "A_up", "A_down", "E", "E_up", "E_down", "M", "R", "R_up", "R_down", "B", "B_mean",
//     "per_target": [{"target_mm", "up": {"n", "mean", "s", "R", "min", "max"} | null,
//                     "down": {...} | null, "B", "R", "mean" (x̄_i)}]}
//   circle: {"standard": "ISO 230-4", "file", "unit": "mm", "plane", "layout": "polar" |
//     "coordinates", "points", "lsc_centre_mm": [u, v], "lsc_radius_mm" (all points),
//     "G_mm" (the larger of the directions), "G_b_mm", "H_mm" (null unless both directions),
//     "F_max_mm", "F_min_mm", "F_reference": {"centre": "nominal" | "lsc", "radius": "nominal" |
//     "lsc", "centre_mm": [u, v], "radius_mm"}, "scale_mismatch_um_per_m", "squareness_urad"
//     (from all points), "harmonics_mm": {"a0", "a1", "b1", "a2", "b2", "residual_rms"},
//     "directions": {"ccw": {...} | null, "cw": {...} | null} with per direction "points",
//     "lsc_centre_mm", "lsc_radius_mm", "lsc_rms_mm", "G_mm", "F_max_mm", "F_min_mm",
//     "F_reference", "max_gap_deg", "scale_mismatch_um_per_m", "squareness_urad",
//     "harmonics_mm"}
//   grid: {"unit": "mm", "grid_file", "points", "max_deviation_mm", "max_deviation_point",
//     "rms_deviation_mm", "max_abs_dx_mm", "max_abs_dy_mm", "max_abs_dz_mm",
//     "squareness_xy_urad", "squareness_yz_urad", "squareness_zx_urad" (out-of-squareness of
//     the fitted axis motions, positive when wider than 90 degrees), "scale_x_um_per_m",
//     "scale_y_um_per_m", "scale_z_um_per_m", "affine_residual_rms_mm", "master_frame":
//     {"orthogonality_urad", "origin_rms_mm", "x_run" / "y_run": {"file", "points",
//     "straightness_mm": [2], "max_distance_mm", "scale_um_per_m"}}, "worst_points": [point],
//     "planes": [{"z_mm", "points", "worst_point", "worst_deviation_mm", "rms_deviation_mm"}],
//     "per_point": [{"point", "commanded_mm", "master_mm", "deviation_mm", "deviation_norm_mm"}]}
//
// Exit codes: 0 printed; 1 the file was refused (the CsvError "<file>:<line>:<column>: message"
// on stderr, or "<file>: message" for a refusal of the evaluation); 2 bad usage (the message
// and the usage of `ncqual analyze` on stderr).
#pragma once

#include <string>
#include <vector>

namespace ncqual {

// The usage lines of `ncqual analyze` (each subcommand and what it does).
extern const char* const kAnalyzeUsage;

// Runs `ncqual analyze <args>`; `args` are the words after "analyze". Returns the exit code.
int run_analyze(const std::vector<std::string>& args);

}  // namespace ncqual

// SPDX-License-Identifier: Apache-2.0
// `ncqual analyze`: the evaluations of instrument exports, run by a metrologist on a file, with
// no service, plant config or historian. Each subcommand is its file, analyze_<subcommand>.cpp
// (touches and points, both judged as the solver judges: analyze_judged.cpp); what they share
// and the table of the subcommands are here (analyze.hpp).
//
//   ncqual analyze iso230-2 FILE [--json]
//       a linear-axis positioning run (laser interferometer), evaluated per ISO 230-2:2014
//       (ncqual::solver::evaluate_iso230_2; file format: ncqual/solver/instrument_files.hpp)
//   ncqual analyze circle FILE [--plane XY|YZ|XZ] [--nominal-radius-mm R] [--centre-mm U,V]
//                              [--json]
//       a circular test (ballbar, grid encoder, tracker), evaluated per ISO 230-4
//       (ncqual::solver::evaluate_circular_test). --plane is needed for angle_deg,radius_mm and
//       u_mm,v_mm files that do not declare it ('# Plane: XZ'), and must agree with an
//       x_mm,y_mm-like header; --nominal-radius-mm (default: the radius the file declares,
//       '# Radius: 150 mm') and --centre-mm (in the plane's u, v) are the reference of the radial
//       deviation F (default: the least-squares circle).
//
//   ncqual analyze grid --x-run F --y-run F --grid F [--machine M [--plant F]] [--json]
//       the monthly laser-tracker grid: the master frame from the X and Y runs
//       (ncqual::solver::fit_master_frame), then the grid's deviations, squareness and scale in it
//       (ncqual::solver::analyze_grid); files: point,x_cmd,y_cmd,z_cmd,x_meas,y_meas,z_meas (mm,
//       commanded in machine axes, measured in the tracker frame), or, with --machine, the
//       tracker's point exports (name, x, y, z) paired by name with the machine's monthly
//       program (solver::grid_points_from_export). With --machine the grid is also judged as the
//       solver service judges the monthly global_grid check (the set `ncqual import grid`
//       publishes, through solver::solve: the machine's tolerances, verdict, likely causes);
//       exit code: its verdict.
//
//   ncqual analyze cmm FILE [--json]
//       a CMM report of a part (solver::read_cmm_results: PC-DMIS's text report or a table),
//       each characteristic against its own tolerance, and the tolerance-weighted best-fit
//       displacement (and turn) of the part whose opposite is the work offset's correction
//       (solver::inspect_part, after Gu & Agapiou's global offset). Exit 0 PASS or no
//       tolerances in the report, 3 FAIL.
//
//   ncqual analyze touches LOG --program PROG --machine M [--plant F] [--json]
//       a real control's touch log of a probing program written by `ncqual program` (or the
//       control-files instrument), judged exactly as the solver service judges the check: the
//       same metrics against the machine's tolerances, verdict, likely causes and correction.
//       --json: the check record of `ncqual history --json` (ncqual/storage/json.hpp).
//
//   ncqual analyze points EXPORT --nominals LIST --machine M [--plant F] [--json]
//       a laser tracker's point export (a name and x, y, z per point, any declared unit) of a
//       tracker check whose nominal list `ncqual program --check KIND` wrote, each point paired
//       by name with the machine's program (points_from_files), judged exactly as the solver
//       service judges the check; output as for touches.
//
// Without --json a table of the figures in mm (4 decimals) is printed. --json prints one
// document (the *Document structs below); its names are a public interface (append, never
// rename); lengths in mm, absent figures null:
//   iso230-2: {"standard": "ISO 230-2:2014", "file", "unit": "mm", "targets" (m), "cycles"
//     (largest n), "directions": ["up", "down"] (those measured),
//     "A", "A_up", "A_down", "E", "E_up", "E_down", "M", "R", "R_up", "R_down", "B", "B_mean",
//     "per_target": [{"target_mm", "up": {"n", "mean", "s", "R", "min", "max"} | null,
//                     "down": {...} | null, "B", "R", "mean" (x̄_i)}],
//     "warnings": [text] (where the run departs from ISO 230-2, solver::iso230_2_conformance)}
//   circle: {"standard": "ISO 230-4", "file", "unit": "mm", "plane", "layout": "polar" |
//     "deviations" (polar, radial deviations from the nominal radius) | "coordinates", "points",
//     "lsc_centre_mm": [u, v], "lsc_radius_mm" (all points), "G_mm" (the larger of the directions),
//     "G_b_mm", "H_mm" (null unless both directions), "F_max_mm", "F_min_mm", "F_reference":
//     {"centre": "nominal" | "lsc", "radius": "nominal" | "lsc", "centre_mm": [u, v], "radius_mm"},
//     "scale_mismatch_um_per_m", "squareness_urad" (from all points), "harmonics_mm": {"a0", "a1",
//     "b1", "a2", "b2", "residual_rms"}, "directions": {"ccw": {...} | null, "cw": {...} | null}
//     with per direction "points", "lsc_centre_mm", "lsc_radius_mm", "lsc_rms_mm", "G_mm",
//     "F_max_mm", "F_min_mm", "F_reference", "max_gap_deg", "scale_mismatch_um_per_m",
//     "squareness_urad", "harmonics_mm", "arc", "shape_noise_gain"}, "arc": {"full_circle",
//     "from_deg", "span_deg"} (the part of the circle measured; a partial arc per ISO 230-4), the
//     shape figures (scale mismatch, squareness, harmonics) null where the arc does not resolve
//     them
//     ("shape_noise_gain" above 3, solver/circular_test.hpp), "H_overlap_deg" (the angles both
//     directions cover, where H compares them), "warnings": [text] (where the test departs from
//     ISO 230-4, solver::iso230_4_conformance)
//   grid: {"unit": "mm", "grid_file", "points", "max_deviation_mm", "max_deviation_point",
//     "rms_deviation_mm", "max_abs_dx_mm", "max_abs_dy_mm", "max_abs_dz_mm",
//     "squareness_xy_urad", "squareness_yz_urad", "squareness_zx_urad" (out-of-squareness of
//     the fitted axis motions, positive when wider than 90 degrees), "scale_x_um_per_m",
//     "scale_y_um_per_m", "scale_z_um_per_m", "affine_residual_rms_mm", "master_frame":
//     {"orthogonality_urad", "origin_rms_mm", "x_run" / "y_run": {"file", "points",
//     "straightness_mm": [2], "max_distance_mm", "scale_um_per_m"}}, "worst_points": [point],
//     "planes": [{"z_mm", "points", "worst_point", "worst_deviation_mm", "rms_deviation_mm"}],
//     "per_point": [{"point", "commanded_mm", "master_mm", "deviation_mm", "deviation_norm_mm"}],
//     "verdict": "PASS" | "FAIL" | "INVALID" | null (with --machine: the global_grid check's),
//     "check": the check record of `ncqual history --json` | null (with --machine)}
//
//   cmm: {"file", "format": "PC-DMIS text" | "table", "unit": "mm", "characteristics", "judged",
//     "out_of_tolerance", "verdict": "PASS" | "FAIL" | null, "per_characteristic": [{"feature",
//     "axis", "line", "nominal_mm", "actual_mm", "deviation_mm", "lower_mm", "upper_mm" (the band
//     of the deviation), "in_tolerance", "after_offset_mm", "in_tolerance_after"}], "offset":
//     {"translation_mm": [3], "rotation_urad": [3] | null, "work_offset_correction_mm": [3],
//     "axis_resolved": [3], "characteristics", "out_of_tolerance_after", "max_abs_after_mm",
//     "left_out": [text], "constraining": [3] (characteristics used along X, Y, Z), "warnings":
//     [text] (a direction one characteristic alone constrains)} | null}
//
// Exit codes: 0 printed (touches, points, cmm, grid --machine: PASS); 3 FAIL (touches, points, cmm,
// grid --machine) and 4 INVALID (touches, points, grid --machine); 1 the
// file was refused (the CsvError "<file>:<line>:<column>: message" on stderr, or "<file>: message"
// for a refusal of the evaluation), or not found; 2 bad usage (the message and the usage of `ncqual
// analyze` on stderr).
#include "analyze.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/common/version.hpp"
#include "ncqual/solver/solve.hpp"
#include "ncqual/storage/json.hpp"

#include <fmt/format.h>

#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

namespace ncqual::cli {
namespace analysis {

std::string mm(double v) { return fmt::format("{:.4f}", v); }
std::string mm(const std::optional<double>& v) { return v ? mm(*v) : "-"; }

int refusing(const std::string& file, int (*run)(const Options&), const Options& o) {
  try {
    return run(o);
  } catch (const std::invalid_argument& e) {
    std::cerr << (file.empty() ? "" : file + ": ") << e.what() << "\n";
    return kExitError;
  }
}

}  // namespace analysis

void add_analyze(CLI::App& app, Commands& commands) {
  auto o = std::make_shared<analysis::Options>();
  CLI::App* analyze = app.add_subcommand(
      "analyze",
      "evaluate an instrument export (ISO 230-2 positioning run, ISO 230-4 circular test,\n"
      "tracker grid, a CMM report, a control's touch log, a tracker's point export) on its\n"
      "own, without services");
  analyze->require_subcommand(1);
  // Each subcommand: its name and help, the positional file it reads into o->file (none for
  // grid), what runs it (an evaluation refused is reported by `refusing`) and its own options.
  struct Analysis {
    const char* name;
    const char* help;
    int (*run)(const analysis::Options&);
    const char* file;
    const char* file_help;
    void (*options)(CLI::App*, analysis::Options&);
  };
  const Analysis analyses[] = {
      {"iso230-2",
       "evaluate a linear-axis positioning run (target_mm,cycle,direction,measured_mm; or\n"
       "error_um, inches, ';' with the decimal comma, +/-) per ISO 230-2:2014: A, E, M, R, B",
       analysis::run_iso230_2, "FILE", "the run's CSV file", nullptr},
      {"circle",
       "evaluate a circular test (angle_deg,radius_mm or x_mm,y_mm | y_mm,z_mm | x_mm,z_mm |\n"
       "u_mm,v_mm, optional direction ccw/cw) per ISO 230-4: G, G(b), H, F, scale mismatch\n"
       "and squareness of the two axes",
       analysis::run_circle, "FILE", "the test's CSV file", analysis::circle_options},
      {"grid",
       "the monthly tracker grid (point,x_cmd,y_cmd,z_cmd,x_meas,y_meas,z_meas; commanded in\n"
       "machine axes, measured in the tracker frame; or the tracker's point exports, name and\n"
       "x, y, z, with --machine): master frame from the X and Y runs, per-point deviations,\n"
       "squareness and scale of the axes",
       analysis::run_grid, nullptr, nullptr, analysis::grid_options},
      {"cmm",
       "judge a CMM report of a part (PC-DMIS text report, or a table of feature, axis,\n"
       "nominal, actual and tolerances) and fit the work offset that would centre it",
       analysis::run_cmm, "FILE", "the CMM report", nullptr},
      {"touches",
       "judge a real control's touch log of a program written by `ncqual program`, exactly as\n"
       "the solver service judges the check (exit code: its verdict)",
       analysis::run_touches, "LOG", "the control's touch log", analysis::touches_options},
      {"points",
       "judge a laser tracker's point export of a tracker check (a name and x, y, z per point)\n"
       "against the nominal list `ncqual program` wrote for it, exactly as the solver service\n"
       "judges the check (exit code: its verdict)",
       analysis::run_points, "EXPORT", "the tracker software's point export",
       analysis::points_options},
  };
  for (const Analysis& a : analyses) {
    CLI::App* command = analyze->add_subcommand(a.name, a.help);
    if (a.file != nullptr) command->add_option(a.file, o->file, a.file_help)->required();
    if (a.options != nullptr) a.options(command, *o);
    add_json_flag(command, o->json);
    commands.push_back(
        {command, [o, run = a.run] { return analysis::refusing(o->file, run, *o); }});
  }
}

}  // namespace ncqual::cli

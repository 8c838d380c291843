// SPDX-License-Identifier: Apache-2.0
// `ncqual analyze grid`: the monthly laser-tracker grid, its master frame from the X and Y runs
// and its deviations, squareness and scale in it, printed as a table or as its --json document.
#include "analyze.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/common/csv.hpp"
#include "ncqual/common/version.hpp"
#include "ncqual/common/json.hpp"
#include "ncqual/solver/global_grid.hpp"
#include "ncqual/solver/instrument_files.hpp"
#include "ncqual/solver/solve.hpp"

#include <fmt/format.h>

#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace ncqual::cli::analysis {
namespace {

using nlohmann::json;

// One of the grid's parts as frame points, refusing one with fewer than `minimum` points at its
// last line.
std::vector<solver::FramePoint> frame_points(const GridPart& part, const std::string& path,
                                             std::size_t minimum, const std::string& what) {
  if (part.points.size() < minimum) {
    throw CsvError(path, part.last_line, 0,
                   std::to_string(part.points.size()) + " points; " + what + " needs at least " +
                       std::to_string(minimum));
  }
  std::vector<solver::FramePoint> out;
  out.reserve(part.points.size());
  for (const auto& p : part.points) out.push_back({p.point, p.commanded_mm, p.measured_mm});
  return out;
}

// The --json document of grid (names: the comment at the top of analyze.cpp).
struct RunDocument {
  std::string file;
  std::size_t points = 0;
  Eigen::Vector2d straightness_mm = Eigen::Vector2d::Zero();
  double max_distance_mm = 0, scale_um_per_m = 0;
};
struct MasterFrameDocument {
  double orthogonality_urad = 0, origin_rms_mm = 0;
  RunDocument x_run, y_run;
};
struct GridPointDocument {
  std::string point;
  Eigen::Vector3d commanded_mm, master_mm, deviation_mm;
  double deviation_norm_mm = 0;
};
struct GridPlaneDocument {
  double z_mm = 0;
  int points = 0;
  std::string worst_point;
  double worst_deviation_mm = 0, rms_deviation_mm = 0;
};
struct GridDocument {
  std::string unit = "mm";
  std::string grid_file;
  std::size_t points = 0;
  double max_deviation_mm = 0;
  std::string max_deviation_point;
  double rms_deviation_mm = 0, max_abs_dx_mm = 0, max_abs_dy_mm = 0, max_abs_dz_mm = 0;
  double squareness_xy_urad = 0, squareness_yz_urad = 0, squareness_zx_urad = 0;
  double scale_x_um_per_m = 0, scale_y_um_per_m = 0, scale_z_um_per_m = 0;
  double affine_residual_rms_mm = 0;
  MasterFrameDocument master_frame;
  std::vector<std::string> worst_points;
  std::vector<GridPlaneDocument> planes;
  std::vector<GridPointDocument> per_point;
  // With --machine: the global_grid check's verdict against the machine's tolerances and its
  // check record (`ncqual history --json`); null without.
  std::optional<std::string> verdict;
  std::optional<nlohmann::json> check;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(RunDocument, file, points, straightness_mm, max_distance_mm,
                                   scale_um_per_m)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(MasterFrameDocument, orthogonality_urad, origin_rms_mm, x_run,
                                   y_run)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(GridPointDocument, point, commanded_mm, master_mm, deviation_mm,
                                   deviation_norm_mm)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(GridPlaneDocument, z_mm, points, worst_point, worst_deviation_mm,
                                   rms_deviation_mm)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(GridDocument, unit, grid_file, points, max_deviation_mm,
                                   max_deviation_point, rms_deviation_mm, max_abs_dx_mm,
                                   max_abs_dy_mm, max_abs_dz_mm, squareness_xy_urad,
                                   squareness_yz_urad, squareness_zx_urad, scale_x_um_per_m,
                                   scale_y_um_per_m, scale_z_um_per_m, affine_residual_rms_mm,
                                   master_frame, worst_points, planes, per_point, verdict, check)

RunDocument run_document(const solver::RunFit& run, const std::string& file) {
  return {file, run.points.size(), run.straightness_mm, run.max_distance_mm, run.scale_um_per_m};
}

GridDocument document_of(const solver::GridAnalysis& r, const solver::MasterFrame& frame,
                         const std::string& x_file, const std::string& y_file,
                         const std::string& g_file) {
  GridDocument d;
  d.grid_file = g_file;
  d.points = r.points.size();
  d.max_deviation_mm = r.max_deviation_mm;
  d.max_deviation_point = r.max_deviation_label;
  d.rms_deviation_mm = r.rms_deviation_mm;
  d.max_abs_dx_mm = r.max_abs_dx_mm;
  d.max_abs_dy_mm = r.max_abs_dy_mm;
  d.max_abs_dz_mm = r.max_abs_dz_mm;
  d.squareness_xy_urad = r.affine.squareness_xy_urad;
  d.squareness_yz_urad = r.affine.squareness_yz_urad;
  d.squareness_zx_urad = r.affine.squareness_zx_urad;
  d.scale_x_um_per_m = r.affine.scale_x_um_per_m;
  d.scale_y_um_per_m = r.affine.scale_y_um_per_m;
  d.scale_z_um_per_m = r.affine.scale_z_um_per_m;
  d.affine_residual_rms_mm = r.affine.residual_rms_mm;
  d.master_frame = {frame.orthogonality_urad, frame.origin_rms_mm,
                    run_document(frame.x_run, x_file), run_document(frame.y_run, y_file)};
  for (std::size_t i : r.worst_points) d.worst_points.push_back(r.points[i].label);
  for (const auto& pl : r.planes) {
    d.planes.push_back(
        {pl.z_mm, pl.point_count, pl.worst_label, pl.worst_deviation_mm, pl.rms_deviation_mm});
  }
  for (const auto& p : r.points) {
    d.per_point.push_back(
        {p.label, p.commanded_mm, p.master_mm, p.deviation_mm, p.deviation_norm_mm});
  }
  return d;
}

}  // namespace

int run_grid(const Options& o) {
  const std::string &x_file = o.x_run, &y_file = o.y_run, &g_file = o.grid;
  // The fewest points each part can take: a line needs 3 to show straightness, the affine fit
  // of the grid has 12 unknowns (4 points) and needs a fifth to leave a residual.
  std::optional<PlantConfig> plant;
  const MachineConfig* machine = nullptr;
  if (o.grid_machine) {
    plant = plant_from(o.plant);
    machine = &configured_machine(*plant, *o.grid_machine);
  }
  const GridPart x_part = read_grid_file(x_file, "x_run", machine);
  const GridPart y_part = read_grid_file(y_file, "y_run", machine);
  const GridPart g_part = read_grid_file(g_file, "grid", machine);
  const auto x_run = frame_points(x_part, x_file, 3, "an X run");
  const auto y_run = frame_points(y_part, y_file, 3, "a Y run");
  const auto grid = frame_points(g_part, g_file, 5, "the grid (12 affine unknowns)");
  solver::MasterFrame frame;
  try {
    frame = solver::fit_master_frame(x_run, y_run);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(x_file + ", " + y_file + ": master frame: " + e.what());
  }
  solver::GridAnalysis r;
  try {
    r = solver::analyze_grid(frame, grid);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(g_file + ": grid: " + e.what());
  }
  // With a machine: the files as the global_grid set `ncqual import grid` publishes, judged as
  // the solver service judges the monthly check (solver::solve, its tolerances and verdict rules).
  std::optional<MeasurementSet> set;
  std::optional<CheckResult> judged;
  if (machine) {
    if (!machine->global_check) {
      throw UsageError("machine '" + machine->machine_id + "' has no global_check: section (" +
                       machine->source_path + "): its grid cannot be judged");
    }
    const std::int64_t now = WallClock().now_ns();
    set.emplace();
    set->machine_id = machine->machine_id;
    set->request_id = new_sample_id("analyze", machine->machine_id);
    set->kind = CheckKind::GlobalGrid;
    set->instrument = kImportedInstrument;
    set->frame = "tracker";
    set->time_ns = now;
    set->tracker_points = solver::tracker_points_for_grid(
        x_part.points, y_part.points, g_part.points, machine->global_check->targets.front());
    judged = solver::solve(*set, *machine, now);
    judged->produced_by = version_line("ncqual analyze");
  }
  if (o.json) {
    GridDocument d = document_of(r, frame, x_file, y_file, g_file);
    if (judged) {
      d.verdict = std::string(to_string(judged->verdict));
      d.check = check_record_json(*judged, *set);
    }
    std::cout << json(d).dump(2) << "\n";
    return judged ? exit_code_of(judged->verdict) : kExitOk;
  }
  fmt::print("grid {}: {} points in the master frame of {} and {}\n", g_file, r.points.size(),
             x_file, y_file);
  fmt::print("  max deviation   {} mm at {}, rms {} mm\n", mm(r.max_deviation_mm),
             r.max_deviation_label, mm(r.rms_deviation_mm));
  fmt::print("  max |dx| |dy| |dz| {} {} {} mm\n", mm(r.max_abs_dx_mm), mm(r.max_abs_dy_mm),
             mm(r.max_abs_dz_mm));
  fmt::print("  squareness xy {:.1f}  yz {:.1f}  zx {:.1f} urad (positive: wider than 90 deg)\n",
             r.affine.squareness_xy_urad, r.affine.squareness_yz_urad, r.affine.squareness_zx_urad);
  fmt::print("  scale x {:.1f}  y {:.1f}  z {:.1f} um/m\n", r.affine.scale_x_um_per_m,
             r.affine.scale_y_um_per_m, r.affine.scale_z_um_per_m);
  fmt::print("  master frame: X and Y runs {:.1f} urad from square\n", frame.orthogonality_urad);
  for (const auto& pl : r.planes) {
    fmt::print("  plane Z {:.1f}: worst {} ({} mm), rms {} mm\n", pl.z_mm, pl.worst_label,
               mm(pl.worst_deviation_mm), mm(pl.rms_deviation_mm));
  }
  if (!judged) {
    fmt::print("verdict: none (pass --machine M to judge the grid against M's tolerances)\n");
    return kExitOk;
  }
  fmt::print("global_grid on {}, judged as the solver judges the monthly check: {}\n",
             judged->machine_id, to_string(judged->verdict));
  print_judgement(*judged);
  return exit_code_of(judged->verdict);
}

void grid_options(CLI::App* grid, Options& o) {
  grid->add_option("--x-run", o.x_run, "the X run of the master frame")->type_name("F")->required();
  grid->add_option("--y-run", o.y_run, "the Y run of the master frame")->type_name("F")->required();
  grid->add_option("--grid", o.grid, "the grid's points")->type_name("F")->required();
  add_machine_option(
      grid, o.grid_machine,
      "the machine whose tolerances judge the grid (the global_grid check's verdict) "
      "and whose monthly program gives the commanded positions of point exports");
  add_plant_option(grid, o.plant);
}

}  // namespace ncqual::cli::analysis

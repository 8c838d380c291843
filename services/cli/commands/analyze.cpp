// SPDX-License-Identifier: Apache-2.0
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
//       program (solver::grid_points_from_export).
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
//     "per_point": [{"point", "commanded_mm", "master_mm", "deviation_mm", "deviation_norm_mm"}]}
//
//   cmm: {"file", "format": "PC-DMIS text" | "table", "unit": "mm", "characteristics", "judged",
//     "out_of_tolerance", "verdict": "PASS" | "FAIL" | null, "per_characteristic": [{"feature",
//     "axis", "line", "nominal_mm", "actual_mm", "deviation_mm", "lower_mm", "upper_mm" (the band
//     of the deviation), "in_tolerance", "after_offset_mm", "in_tolerance_after"}], "offset":
//     {"translation_mm": [3], "rotation_urad": [3] | null, "work_offset_correction_mm": [3],
//     "axis_resolved": [3], "characteristics", "out_of_tolerance_after", "max_abs_after_mm",
//     "left_out": [text]} | null}
//
// Exit codes: 0 printed (touches, points, cmm: PASS); 3 FAIL (touches, points, cmm) and 4 INVALID
// (touches, points); 1 the
// file was refused (the CsvError "<file>:<line>:<column>: message" on stderr, or "<file>: message"
// for a refusal of the evaluation), or not found; 2 bad usage (the message and the usage of `ncqual
// analyze` on stderr).
#include "commands.hpp"

#include "ncqual/common/csv.hpp"
#include "ncqual/common/json.hpp"
#include "ncqual/common/units.hpp"
#include "ncqual/solver/circular_test.hpp"
#include "ncqual/solver/global_grid.hpp"
#include "ncqual/solver/instrument_files.hpp"
#include "ncqual/solver/iso230_2.hpp"
#include "ncqual/solver/part_inspection.hpp"
#include "ncqual/common/text.hpp"
#include "ncqual/solver/solve.hpp"
#include "ncqual/common/clock.hpp"
#include "ncqual/storage/json.hpp"
#include "ncqual/common/version.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace ncqual::cli {
namespace {

using units::kPi;

using nlohmann::json;

// ---- Formatting ---------------------------------------------------------------------------------

std::string mm(double v) { return fmt::format("{:.4f}", v); }
std::string mm(const std::optional<double>& v) { return v ? mm(*v) : "-"; }

std::string fixed(double v, int decimals) { return fmt::format("{:.{}f}", v, decimals); }
std::string fixed(const std::optional<double>& v, int decimals) {
  return v ? fixed(*v, decimals) : "-";
}

// ---- iso230-2 -----------------------------------------------------------------------------------

// The --json document of iso230-2 (names: the file comment above).
struct DirectionDocument {
  int n = 0;
  double mean = 0, s = 0, R = 0, min = 0, max = 0;
};
struct TargetDocument {
  double target_mm = 0;
  std::optional<DirectionDocument> up, down;
  std::optional<double> B, R, mean;
};
struct Iso230_2Document {
  std::string standard = "ISO 230-2:2014";
  std::string file;
  std::string unit = "mm";
  std::size_t targets = 0;
  int cycles = 0;
  std::vector<std::string> directions;
  std::optional<double> A, A_up, A_down, E, E_up, E_down, M, R, R_up, R_down, B, B_mean;
  std::vector<TargetDocument> per_target;
  std::vector<std::string> warnings;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(DirectionDocument, n, mean, s, R, min, max)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(TargetDocument, target_mm, up, down, B, R, mean)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(Iso230_2Document, standard, file, unit, targets, cycles,
                                   directions, A, A_up, A_down, E, E_up, E_down, M, R, R_up, R_down,
                                   B, B_mean, per_target, warnings)

std::optional<DirectionDocument> direction_document(
    const std::optional<solver::DirectionFigures>& d) {
  if (!d) return std::nullopt;
  return DirectionDocument{d->cycles, d->mean_mm, d->s_mm, d->R_mm, d->min_mm, d->max_mm};
}

Iso230_2Document document_of(const solver::Iso230_2Result& r, const std::string& file) {
  Iso230_2Document d;
  d.file = file;
  d.targets = r.targets.size();
  d.cycles = r.cycles;
  if (r.has_up) d.directions.emplace_back("up");
  if (r.has_down) d.directions.emplace_back("down");
  d.A = r.A_mm, d.A_up = r.A_up_mm, d.A_down = r.A_down_mm;
  d.E = r.E_mm, d.E_up = r.E_up_mm, d.E_down = r.E_down_mm;
  d.M = r.M_mm;
  d.R = r.R_mm, d.R_up = r.R_up_mm, d.R_down = r.R_down_mm;
  d.B = r.B_mm, d.B_mean = r.B_mean_mm;
  for (const auto& t : r.targets) {
    d.per_target.push_back({t.target_mm, direction_document(t.up), direction_document(t.down),
                            t.B_mm, t.R_mm, t.mean_mm});
  }
  d.warnings = solver::iso230_2_conformance(r);
  return d;
}

void print_iso230_2(const solver::Iso230_2Result& r, const std::string& file) {
  const std::string dirs = r.has_up && r.has_down ? "both directions"
                           : r.has_up             ? "up (+) only"
                                                  : "down (-) only";
  fmt::print("ISO 230-2:2014 positioning test: {}\n", file);
  fmt::print("  {} targets ({} .. {} mm), {} cycles, {}\n\n", r.targets.size(),
             mm(r.targets.front().target_mm), mm(r.targets.back().target_mm), r.cycles, dirs);
  fmt::print("Axis (mm)            bidirectional       up (+)     down (-)\n");
  auto axis_row = [](const char* name, const std::optional<double>& both,
                     const std::optional<double>& up, const std::optional<double>& down) {
    fmt::print("  {:<20}{:>12}{:>13}{:>13}\n", name, mm(both), mm(up), mm(down));
  };
  axis_row("A  accuracy", r.A_mm, r.A_up_mm, r.A_down_mm);
  axis_row("E  systematic dev.", r.E_mm, r.E_up_mm, r.E_down_mm);
  axis_row("R  repeatability", r.R_mm, r.R_up_mm, r.R_down_mm);
  axis_row("M  range of mean x_i", r.M_mm, std::nullopt, std::nullopt);
  axis_row("B  reversal", r.B_mm, std::nullopt, std::nullopt);
  axis_row("B_mean mean reversal", r.B_mean_mm, std::nullopt, std::nullopt);

  fmt::print(
      "\nPer target (mm): mean = mean deviation, s = standard uncertainty, R = 4 s;\n"
      "  B_i = reversal, R_i = bidirectional repeatability, x_i = mean bidirectional "
      "deviation\n");
  const std::vector<std::pair<std::string, std::size_t>> cols{
      {"target", 12}, {"n↑", 4}, {"mean↑", 9}, {"s↑", 8},  {"R↑", 8},  {"n↓", 4},
      {"mean↓", 9},   {"s↓", 8}, {"R↓", 8},    {"B_i", 9}, {"R_i", 8}, {"x_i", 9}};
  std::string header = " ";
  // The arrows are 3 bytes and one column wide: fmt pads by columns.
  for (const auto& [name, width] : cols) header += fmt::format("{:>{}}", name, width);
  fmt::print("{}\n", header);
  for (const auto& t : r.targets) {
    std::string line = fmt::format(" {:>12}", mm(t.target_mm));
    for (const auto* d : {&t.up, &t.down}) {
      line += *d ? fmt::format("{:>4}{:>9}{:>8}{:>8}", (*d)->cycles, mm((*d)->mean_mm),
                               mm((*d)->s_mm), mm((*d)->R_mm))
                 : fmt::format("{:>4}{:>9}{:>8}{:>8}", "-", "-", "-", "-");
    }
    line += fmt::format("{:>9}{:>8}{:>9}", mm(t.B_mm), mm(t.R_mm), mm(t.mean_mm));
    fmt::print("{}\n", line);
  }
  const std::vector<std::string> warnings = solver::iso230_2_conformance(r);
  fmt::print("\nConformance to ISO 230-2:2014: {}\n",
             warnings.empty() ? "the test plan conforms" : "the figures above are given, but");
  for (const auto& w : warnings) fmt::print("  warning: {}\n", w);
}

// What the analyses take on the command line.
struct Options {
  std::string file;  // iso230-2 and circle
  bool json = false;
  std::optional<std::string> plane;         // circle
  std::optional<double> nominal_radius_mm;  // circle
  std::optional<std::string> centre_mm;     // circle
  std::string x_run, y_run, grid;           // grid
  std::optional<std::string> grid_machine;  // grid: the machine of tracker point exports
  std::string program, machine, plant;      // touches (program), points (the nominal list);
                                            // plant: grid too
};

// ---- touches ------------------------------------------------------------------------------------

// The set of a file (o.file) and the program or nominal list it answers (o.program), read by
// `from_files` (touches_from_files, points_from_files), judged as the solver service judges it
// and printed (or its check record with --json). `what`: "touches" or "points"; `answers`:
// "program" or "nominals".
using SetFromFiles = MeasurementSet (*)(const std::string&, const std::string&,
                                        const MachineConfig&, std::int64_t);
int judge_files(const Options& o, SetFromFiles from_files, const char* what, const char* answers) {
  const PlantConfig plant = plant_from(o.plant);
  const MachineConfig& machine = configured_machine(plant, o.machine);
  const std::int64_t now = WallClock().now_ns();
  const MeasurementSet set = from_files(o.file, o.program, machine, now);
  CheckResult r = solver::solve(set, machine, now);
  r.produced_by = version_line("ncqual analyze");
  if (o.json) {
    storage::CheckRecord rec;
    rec.machine_id = r.machine_id;
    rec.request_id = r.request_id;
    rec.kind = r.kind;
    rec.result = r;
    storage::MeasurementSummary measured;
    measured.instrument = set.instrument;
    measured.frame = set.frame;
    measured.time_ns = set.time_ns;
    measured.touches = static_cast<std::int64_t>(set.touches.size());
    measured.tracker_points = static_cast<std::int64_t>(set.tracker_points.size());
    rec.measurement = measured;
    std::cout << storage::to_json(rec).dump(2) << "\n";
  } else {
    fmt::print("{} on {}: {} {} of {} ({} {}, request {}): {}\n", to_string(r.kind), r.machine_id,
               set.touches.size() + set.tracker_points.size(), what, o.file, answers, o.program,
               r.request_id, to_string(r.verdict));
    for (const Metric& m : r.metrics) {
      fmt::print("  {:<28} {:>12} {:<6} [{}, {}]{}\n", m.name, format_metric_value(m), m.unit,
                 format_metric_value(Metric{m.name, m.lower, m.unit, m.lower, m.upper, true}),
                 format_metric_value(Metric{m.name, m.upper, m.unit, m.lower, m.upper, true}),
                 m.pass ? "" : "  (!) out of tolerance");
    }
    if (!r.reason.empty()) fmt::print("reason: {}\n", r.reason);
    for (std::size_t i = 0; i < r.likely_causes.size(); ++i) {
      fmt::print("likely cause {}: {}\n", i + 1, r.likely_causes[i]);
    }
    if (r.correction) {
      for (const auto& c : r.correction->offsets) {
        fmt::print("correction {}: {} = {} {}\n", r.correction->target, c.name, c.value, c.unit);
      }
    }
  }
  return r.verdict == Verdict::Pass   ? kExitOk
         : r.verdict == Verdict::Fail ? kExitFail
                                      : kExitInvalid;
}

int run_touches(const Options& o) {
  return judge_files(o, touches_from_files, "touches", "program");
}

// ---- points -------------------------------------------------------------------------------------

int run_points(const Options& o) { return judge_files(o, points_from_files, "points", "nominals"); }

int run_iso230_2(const Options& o) {
  const std::string& file = o.file;
  const solver::Iso230_2File data = solver::read_iso230_2_csv(read_csv_file(file));
  const solver::Iso230_2Result r = solver::evaluate_iso230_2(data.readings);
  if (o.json) {
    std::cout << json(document_of(r, file)).dump(2) << "\n";
  } else {
    print_iso230_2(r, file);
  }
  return kExitOk;
}

// ---- circle -------------------------------------------------------------------------------------

// The --json document of circle (names: the file comment above).
struct HarmonicsDocument {
  double a0 = 0, a1 = 0, b1 = 0, a2 = 0, b2 = 0, residual_rms = 0;
};
struct ReferenceDocument {
  std::string centre, radius;  // "nominal" or "lsc"
  Eigen::Vector2d centre_mm = Eigen::Vector2d::Zero();
  double radius_mm = 0;
};
struct ArcDocument {
  bool full_circle = true;
  double from_deg = 0, span_deg = 360;
};
struct PathDocument {
  int points = 0;
  Eigen::Vector2d lsc_centre_mm = Eigen::Vector2d::Zero();
  double lsc_radius_mm = 0, lsc_rms_mm = 0, G_mm = 0, F_max_mm = 0, F_min_mm = 0;
  ReferenceDocument F_reference;
  double max_gap_deg = 0;
  std::optional<double> scale_mismatch_um_per_m, squareness_urad;
  std::optional<HarmonicsDocument> harmonics_mm;
  ArcDocument arc;
  double shape_noise_gain = 1;
};
struct DirectionsDocument {
  std::optional<PathDocument> ccw, cw;
};
struct CircleDocument {
  std::string standard = "ISO 230-4";
  std::string file;
  std::string unit = "mm";
  std::string plane, layout;
  std::size_t points = 0;
  Eigen::Vector2d lsc_centre_mm = Eigen::Vector2d::Zero();
  double lsc_radius_mm = 0, G_mm = 0;
  std::optional<double> G_b_mm, H_mm;
  double F_max_mm = 0, F_min_mm = 0;
  ReferenceDocument F_reference;
  std::optional<double> scale_mismatch_um_per_m, squareness_urad;
  std::optional<HarmonicsDocument> harmonics_mm;
  DirectionsDocument directions;
  ArcDocument arc;
  double shape_noise_gain = 1;
  std::optional<double> H_overlap_deg;
  std::vector<std::string> warnings;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(HarmonicsDocument, a0, a1, b1, a2, b2, residual_rms)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(ReferenceDocument, centre, radius, centre_mm, radius_mm)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(ArcDocument, full_circle, from_deg, span_deg)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(PathDocument, points, lsc_centre_mm, lsc_radius_mm, lsc_rms_mm,
                                   G_mm, F_max_mm, F_min_mm, F_reference, max_gap_deg,
                                   scale_mismatch_um_per_m, squareness_urad, harmonics_mm, arc,
                                   shape_noise_gain)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(DirectionsDocument, ccw, cw)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(CircleDocument, standard, file, unit, plane, layout, points,
                                   lsc_centre_mm, lsc_radius_mm, G_mm, G_b_mm, H_mm, F_max_mm,
                                   F_min_mm, F_reference, scale_mismatch_um_per_m, squareness_urad,
                                   harmonics_mm, directions, arc, shape_noise_gain, H_overlap_deg,
                                   warnings)

std::optional<HarmonicsDocument> harmonics_document(
    const std::optional<solver::RadialHarmonics>& h) {
  if (!h) return std::nullopt;
  return HarmonicsDocument{h->a0_mm, h->a1_mm, h->b1_mm, h->a2_mm, h->b2_mm, h->residual_rms_mm};
}

ArcDocument arc_document(const solver::CircularArc& a) {
  return {a.full_circle, a.from_rad * 180.0 / kPi, a.span_rad * 180.0 / kPi};
}

ReferenceDocument reference_document(const solver::RadialReference& ref) {
  return {ref.nominal_centre ? "nominal" : "lsc", ref.nominal_radius ? "nominal" : "lsc",
          ref.centre_mm, ref.radius_mm};
}

std::optional<PathDocument> path_document(const std::optional<solver::CircularPathFigures>& p) {
  if (!p) return std::nullopt;
  return PathDocument{p->point_count,
                      p->lsc_centre_mm,
                      p->lsc_radius_mm,
                      p->lsc_rms_mm,
                      p->G_mm,
                      p->F_max_mm,
                      p->F_min_mm,
                      reference_document(p->F_reference),
                      p->max_gap_rad * 180.0 / kPi,
                      p->scale_mismatch_um_per_m,
                      p->squareness_urad,
                      harmonics_document(p->harmonics),
                      arc_document(p->arc),
                      p->shape_noise_gain};
}

CircleDocument document_of(const solver::CircularTestResult& r, const solver::CircleFile& data,
                           const std::string& file) {
  CircleDocument d;
  d.file = file;
  d.plane = solver::to_string(r.plane);
  d.layout = data.deviations ? "deviations" : data.polar ? "polar" : "coordinates";
  d.points = data.input.points.size();
  d.lsc_centre_mm = r.lsc_centre_mm;
  d.lsc_radius_mm = r.lsc_radius_mm;
  d.G_mm = r.G_mm;
  d.G_b_mm = r.G_b_mm;
  d.H_mm = r.H_mm;
  d.F_max_mm = r.F_max_mm;
  d.F_min_mm = r.F_min_mm;
  d.F_reference = reference_document(r.F_reference);
  d.scale_mismatch_um_per_m = r.scale_mismatch_um_per_m;
  d.squareness_urad = r.squareness_urad;
  d.harmonics_mm = harmonics_document(r.harmonics);
  d.directions = {path_document(r.ccw), path_document(r.cw)};
  d.arc = arc_document(r.arc);
  d.shape_noise_gain = r.shape_noise_gain;
  if (r.H_mm) d.H_overlap_deg = r.H_overlap_rad * 180.0 / kPi;
  d.warnings = solver::iso230_4_conformance(r);
  return d;
}

std::string reference_text(const solver::RadialReference& ref) {
  return (ref.nominal_centre ? "nominal centre (" : "LSC centre (") + mm(ref.centre_mm.x()) + ", " +
         mm(ref.centre_mm.y()) + ") mm, " +
         (ref.nominal_radius ? "nominal radius R0 " : "LSC radius ") + mm(ref.radius_mm) + " mm";
}

void print_circle(const solver::CircularTestResult& r, const solver::CircleFile& data,
                  const std::string& file) {
  const std::string plane(solver::to_string(r.plane));
  const std::string u(1, plane[0]), v(1, plane[1]);
  fmt::print("ISO 230-4 circular test: {}\n", file);
  fmt::print("  plane {} (u = {}, v = {}), {} points ({}), directions:{}{}\n", plane, u, v,
             data.input.points.size(),
             data.deviations ? "angle, radial deviation"
             : data.polar    ? "angle, radius"
                             : "coordinates",
             r.ccw ? " ccw" : "", r.cw ? " cw" : "");
  if (!r.arc.full_circle) {
    fmt::print(
        "  a partial arc of {} deg, from {} deg counter-clockwise (angles from +{} towards +{})\n",
        fixed(r.arc.span_rad * 180.0 / kPi, 1),
        // 359.97 deg is 0.0, not 360.0
        fixed(std::fmod(std::round(r.arc.from_rad * 1800.0 / kPi) / 10.0, 360.0), 1), u, v);
  }
  fmt::print("  least-squares circle of all points: centre ({}, {}) = ({}, {}) mm, radius {} mm\n",
             u, v, mm(r.lsc_centre_mm.x()), mm(r.lsc_centre_mm.y()), mm(r.lsc_radius_mm));
  fmt::print("  F measured from the {}\n\n", reference_text(r.F_reference));

  auto path_value = [](const std::optional<solver::CircularPathFigures>& p, auto get) {
    return p ? get(*p) : std::string("-");
  };
  fmt::print("{:34}{:>12}{:>12}{:>12}\n", "", "ccw", "cw", "both");
  auto row = [&](const char* name, const std::string& ccw, const std::string& cw,
                 const std::string& both) {
    // The names are padded in bytes, as they always were (the degree sign is two).
    fmt::print("  {:<32}{:>12}{:>12}{:>12}\n", fmt::bytes(name), ccw, cw, both);
  };
  using P = solver::CircularPathFigures;
  row("points", path_value(r.ccw, [](const P& p) { return std::to_string(p.point_count); }),
      path_value(r.cw, [](const P& p) { return std::to_string(p.point_count); }),
      std::to_string(data.input.points.size()));
  row("LSC radius (mm)", path_value(r.ccw, [](const P& p) { return mm(p.lsc_radius_mm); }),
      path_value(r.cw, [](const P& p) { return mm(p.lsc_radius_mm); }), mm(r.lsc_radius_mm));
  row("G  circular deviation (mm)", path_value(r.ccw, [](const P& p) { return mm(p.G_mm); }),
      path_value(r.cw, [](const P& p) { return mm(p.G_mm); }), "-");
  row("G(b) bidirectional (mm)", "-", "-", mm(r.G_b_mm));
  row("H  circular hysteresis (mm)", "-", "-", mm(r.H_mm));
  row("F_max radial deviation (mm)", path_value(r.ccw, [](const P& p) { return mm(p.F_max_mm); }),
      path_value(r.cw, [](const P& p) { return mm(p.F_max_mm); }), mm(r.F_max_mm));
  row("F_min radial deviation (mm)", path_value(r.ccw, [](const P& p) { return mm(p.F_min_mm); }),
      path_value(r.cw, [](const P& p) { return mm(p.F_min_mm); }), mm(r.F_min_mm));
  row("scale mismatch u - v (um/m)",
      path_value(r.ccw, [](const P& p) { return fixed(p.scale_mismatch_um_per_m, 1); }),
      path_value(r.cw, [](const P& p) { return fixed(p.scale_mismatch_um_per_m, 1); }),
      fixed(r.scale_mismatch_um_per_m, 1));
  row("squareness (urad, >0: over 90°)",
      path_value(r.ccw, [](const P& p) { return fixed(p.squareness_urad, 1); }),
      path_value(r.cw, [](const P& p) { return fixed(p.squareness_urad, 1); }),
      fixed(r.squareness_urad, 1));
  const auto arc_text = [](const solver::CircularArc& a) {
    return a.full_circle ? std::string("360") : fixed(a.span_rad * 180.0 / kPi, 1);
  };
  row("arc measured (deg)", path_value(r.ccw, [&](const P& p) { return arc_text(p.arc); }),
      path_value(r.cw, [&](const P& p) { return arc_text(p.arc); }), arc_text(r.arc));
  row("largest angular gap (deg)",
      path_value(r.ccw, [](const P& p) { return fixed(p.max_gap_rad * 180.0 / kPi, 1); }),
      path_value(r.cw, [](const P& p) { return fixed(p.max_gap_rad * 180.0 / kPi, 1); }), "-");
  if (r.ccw && r.cw) {
    fmt::print(
        "\n  The scale mismatch and squareness of one direction include its reversal "
        "errors;\n  those of both directions together cancel them.\n");
  }
  const std::vector<std::string> warnings = solver::iso230_4_conformance(r);
  fmt::print("\nConformance to ISO 230-4: {}\n",
             warnings.empty() ? "the test conforms" : "the figures above are given, but");
  for (const auto& w : warnings) fmt::print("  warning: {}\n", w);
}

int run_circle(const Options& o) {
  const std::string& file = o.file;
  const std::optional<solver::Plane> plane = plane_option(o.plane);
  const std::optional<double> nominal_radius = o.nominal_radius_mm;
  if (nominal_radius && !(std::isfinite(*nominal_radius) && *nominal_radius > 0)) {
    throw UsageError(
        fmt::format("--nominal-radius-mm {}: expected a radius > 0 (mm)", *nominal_radius));
  }
  std::optional<Eigen::Vector2d> centre;
  if (o.centre_mm) {
    const auto [u, v] = centre_option(*o.centre_mm);
    centre = Eigen::Vector2d(u, v);
  }

  solver::CircleFile data = solver::read_circle_csv(read_csv_file(file), plane, nominal_radius);
  data.input.nominal_centre_mm = centre;
  const solver::CircularTestResult r = solver::evaluate_circular_test(data.input);
  if (o.json) {
    std::cout << json(document_of(r, data, file)).dump(2) << "\n";
  } else {
    print_circle(r, data, file);
  }
  return kExitOk;
}

// ---- grid ---------------------------------------------------------------------------------------

// One of the grid's files as frame points, refusing one with fewer than `minimum` points at its
// last line.
std::vector<solver::FramePoint> grid_file(const std::string& path, const std::string& prefix,
                                          const MachineConfig* machine, std::size_t minimum,
                                          const std::string& what) {
  const CsvTable table = read_csv_file(path);
  const std::vector<solver::GridFilePoint> points = read_grid_part(table, prefix, machine);
  if (points.size() < minimum) {
    const int last = table.rows.empty() ? table.header_line : table.rows.back().line;
    throw CsvError(path, last, 0,
                   std::to_string(points.size()) + " points; " + what + " needs at least " +
                       std::to_string(minimum));
  }
  std::vector<solver::FramePoint> out;
  out.reserve(points.size());
  for (const auto& p : points) out.push_back({p.point, p.commanded_mm, p.measured_mm});
  return out;
}

// The --json document of grid (names: the file comment above).
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
                                   master_frame, worst_points, planes, per_point)

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
  const auto x_run = grid_file(x_file, "x_run", machine, 3, "an X run");
  const auto y_run = grid_file(y_file, "y_run", machine, 3, "a Y run");
  const auto grid = grid_file(g_file, "grid", machine, 5, "the grid (12 affine unknowns)");
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
  if (o.json) {
    std::cout << json(document_of(r, frame, x_file, y_file, g_file)).dump(2) << "\n";
    return kExitOk;
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
  return kExitOk;
}

// ---- cmm ----------------------------------------------------------------------------------------

// The --json document of cmm (names: the file comment above).
struct CmmCharacteristicDocument {
  std::string feature, axis;
  int line = 0;
  double nominal_mm = 0, actual_mm = 0, deviation_mm = 0;
  std::optional<double> lower_mm, upper_mm;
  std::optional<bool> in_tolerance;
  std::optional<double> after_offset_mm;
  std::optional<bool> in_tolerance_after;
};
struct CmmOffsetDocument {
  Eigen::Vector3d translation_mm = Eigen::Vector3d::Zero();
  std::optional<Eigen::Vector3d> rotation_urad;
  Eigen::Vector3d work_offset_correction_mm = Eigen::Vector3d::Zero();
  std::vector<bool> axis_resolved;
  int characteristics = 0, out_of_tolerance_after = 0;
  double max_abs_after_mm = 0;
  std::vector<std::string> left_out;
};
struct CmmDocument {
  std::string file, format, unit = "mm";
  int characteristics = 0, judged = 0, out_of_tolerance = 0;
  std::optional<std::string> verdict;
  std::vector<CmmCharacteristicDocument> per_characteristic;
  std::optional<CmmOffsetDocument> offset;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(CmmCharacteristicDocument, feature, axis, line, nominal_mm,
                                   actual_mm, deviation_mm, lower_mm, upper_mm, in_tolerance,
                                   after_offset_mm, in_tolerance_after)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(CmmOffsetDocument, translation_mm, rotation_urad,
                                   work_offset_correction_mm, axis_resolved, characteristics,
                                   out_of_tolerance_after, max_abs_after_mm, left_out)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(CmmDocument, file, format, unit, characteristics, judged,
                                   out_of_tolerance, verdict, per_characteristic, offset)

CmmDocument document_of(const solver::PartInspection& p, const solver::CmmReport& report,
                        const std::string& file) {
  CmmDocument d;
  d.file = file;
  d.format = report.format;
  d.characteristics = static_cast<int>(p.characteristics.size());
  d.judged = p.judged;
  d.out_of_tolerance = p.out_of_tolerance;
  if (p.pass) d.verdict = *p.pass ? "PASS" : "FAIL";
  for (const auto& r : p.characteristics) {
    CmmCharacteristicDocument c;
    c.feature = r.characteristic.feature;
    c.axis = r.characteristic.axis;
    c.line = r.characteristic.line;
    c.nominal_mm = r.characteristic.nominal_mm;
    c.actual_mm = r.characteristic.actual_mm;
    c.deviation_mm = r.deviation_mm;
    c.lower_mm = r.characteristic.lower_mm;
    c.upper_mm = r.characteristic.upper_mm;
    c.in_tolerance = r.in_tolerance;
    c.after_offset_mm = r.after_offset_mm;
    c.in_tolerance_after = r.in_tolerance_after;
    d.per_characteristic.push_back(c);
  }
  if (p.fit) {
    CmmOffsetDocument o;
    o.translation_mm = p.fit->translation_mm;
    if (p.fit->rotation_rad) o.rotation_urad = Eigen::Vector3d(*p.fit->rotation_rad * 1e6);
    o.work_offset_correction_mm = -p.fit->translation_mm;
    o.axis_resolved = p.fit->axis_resolved;
    o.characteristics = p.fit->characteristics;
    o.out_of_tolerance_after = p.fit->out_of_tolerance_after;
    o.max_abs_after_mm = p.fit->max_abs_after_mm;
    o.left_out = p.fit->left_out;
    d.offset = o;
  }
  return d;
}

std::string signed_mm(double v) { return fmt::format("{:+.4f}", v == 0 ? 0.0 : v); }

void print_cmm(const solver::PartInspection& p, const solver::CmmReport& report,
               const std::string& file) {
  std::cout << "CMM report " << file << " (" << report.format << "): " << p.characteristics.size()
            << " characteristics, " << p.judged << " with a tolerance\n";
  std::cout << fmt::format("  {:<12} {:<4} {:>11} {:>11} {:>9}  {:<19} {:<4} {:>12}\n", "feature",
                           "axis", "nominal mm", "actual mm", "dev mm", "tolerance mm", "in",
                           "after offset");
  std::vector<std::string> out;
  for (const auto& r : p.characteristics) {
    const auto& c = r.characteristic;
    const std::string band =
        c.lower_mm ? signed_mm(*c.lower_mm) + " .. " + signed_mm(*c.upper_mm) : "-";
    const std::string in = r.in_tolerance ? (*r.in_tolerance ? "yes" : "NO") : "-";
    if (r.in_tolerance && !*r.in_tolerance) out.push_back(c.feature + " " + c.axis);
    std::cout << fmt::format("  {:<12} {:<4} {:>11} {:>11} {:>9}  {:<19} {:<4} {:>12}\n", c.feature,
                             c.axis.empty() ? "-" : c.axis, mm(c.nominal_mm), mm(c.actual_mm),
                             signed_mm(r.deviation_mm), band, in,
                             r.after_offset_mm ? signed_mm(*r.after_offset_mm) : "-");
  }
  if (!p.pass) {
    std::cout << "verdict: none (the report gives no tolerances)\n";
  } else if (*p.pass) {
    std::cout << "verdict: PASS (all " << p.judged << " in tolerance)\n";
  } else {
    std::cout << "verdict: FAIL (" << p.out_of_tolerance << " of " << p.judged
              << " out of tolerance:";
    for (std::size_t k = 0; k < out.size(); ++k) std::cout << (k ? ", " : " ") << out[k];
    std::cout << ")\n";
  }
  if (!p.fit) return;
  const solver::PartOffsetFit& f = *p.fit;
  std::cout << "best-fit offset of the part (tolerance-weighted, " << f.characteristics
            << " X, Y, Z characteristics):\n";
  const char* const axes = "xyz";
  std::cout << "  displacement";
  for (int k = 0; k < 3; ++k) {
    std::cout << "  d" << axes[k] << " "
              << (f.axis_resolved[static_cast<std::size_t>(k)] ? signed_mm(f.translation_mm(k))
                                                               : "-");
  }
  std::cout << " mm (the work offset's correction is its opposite)\n";
  if (f.rotation_rad) {
    std::cout << "  rotation     "
              << fmt::format("about x {:+.1f}  y {:+.1f}  z {:+.1f} urad",
                             f.rotation_rad->x() * 1e6, f.rotation_rad->y() * 1e6,
                             f.rotation_rad->z() * 1e6)
              << " (about the report's origin)\n";
  } else {
    std::cout << "  rotation     not fitted (fewer than three features with X, Y and Z nominals "
                 "spanning a plane)\n";
  }
  for (const auto& why : f.left_out) std::cout << "  left out: " << why << "\n";
  std::cout << "  after it: " << f.out_of_tolerance_after
            << " out of tolerance, largest remaining deviation " << mm(f.max_abs_after_mm)
            << " mm\n";
}

int run_cmm(const Options& o) {
  std::string why;
  const std::optional<std::string> text = read_text_file(o.file, &why);
  if (!text) throw CsvError(o.file, 0, 0, "cannot read: " + why);
  const solver::CmmReport report = solver::read_cmm_results(*text, o.file);
  const solver::PartInspection p = solver::inspect_part(report);
  if (o.json) {
    std::cout << json(document_of(p, report, o.file)).dump(2) << "\n";
  } else {
    print_cmm(p, report, o.file);
  }
  return p.pass && !*p.pass ? kExitFail : kExitOk;
}

// An evaluation refused (std::invalid_argument) is reported as "<file>: message", exit 1.
int refusing(const std::string& file, int (*run)(const Options&), const Options& o) {
  try {
    return run(o);
  } catch (const std::invalid_argument& e) {
    std::cerr << (file.empty() ? "" : file + ": ") << e.what() << "\n";
    return kExitError;
  }
}

}  // namespace

void add_analyze(CLI::App& app, Commands& commands) {
  auto o = std::make_shared<Options>();
  CLI::App* analyze = app.add_subcommand(
      "analyze",
      "evaluate an instrument export (ISO 230-2 positioning run, ISO 230-4 circular test,\n"
      "tracker grid, a CMM report, a control's touch log, a tracker's point export) on its\n"
      "own, without services");
  analyze->require_subcommand(1);

  CLI::App* iso = analyze->add_subcommand(
      "iso230-2",
      "evaluate a linear-axis positioning run (target_mm,cycle,direction,measured_mm; or\n"
      "error_um, inches, ';' with the decimal comma, +/-) per ISO 230-2:2014: A, E, M, R, B");
  iso->add_option("FILE", o->file, "the run's CSV file")->required();
  add_json_flag(iso, o->json);
  commands.push_back({iso, [o] { return refusing(o->file, run_iso230_2, *o); }});

  CLI::App* circle = analyze->add_subcommand(
      "circle",
      "evaluate a circular test (angle_deg,radius_mm or x_mm,y_mm | y_mm,z_mm | x_mm,z_mm |\n"
      "u_mm,v_mm, optional direction ccw/cw) per ISO 230-4: G, G(b), H, F, scale mismatch\n"
      "and squareness of the two axes");
  circle->add_option("FILE", o->file, "the test's CSV file")->required();
  circle
      ->add_option("--plane", o->plane,
                   "the plane (needed for angle_deg,radius_mm and u_mm,v_mm files)")
      ->type_name("XY|YZ|XZ");
  circle
      ->add_option(
          "--nominal-radius-mm", o->nominal_radius_mm,
          "F about this radius (default: the file's '# Radius:', else the least-squares circle's)")
      ->type_name("R");
  circle
      ->add_option("--centre-mm", o->centre_mm,
                   "F about this centre in the plane's u, v (default: the least-squares one)")
      ->type_name("U,V");
  add_json_flag(circle, o->json);
  commands.push_back({circle, [o] { return refusing(o->file, run_circle, *o); }});

  CLI::App* grid = analyze->add_subcommand(
      "grid",
      "the monthly tracker grid (point,x_cmd,y_cmd,z_cmd,x_meas,y_meas,z_meas; commanded in\n"
      "machine axes, measured in the tracker frame; or the tracker's point exports, name and\n"
      "x, y, z, with --machine): master frame from the X and Y runs, per-point deviations,\n"
      "squareness and scale of the axes");
  grid->add_option("--x-run", o->x_run, "the X run of the master frame")
      ->type_name("F")
      ->required();
  grid->add_option("--y-run", o->y_run, "the Y run of the master frame")
      ->type_name("F")
      ->required();
  grid->add_option("--grid", o->grid, "the grid's points")->type_name("F")->required();
  add_machine_option(grid, o->grid_machine,
                     "the machine whose monthly program gives the commanded positions of "
                     "point exports");
  add_plant_option(grid, o->plant);
  add_json_flag(grid, o->json);
  commands.push_back({grid, [o] { return refusing("", run_grid, *o); }});

  CLI::App* cmm = analyze->add_subcommand(
      "cmm",
      "judge a CMM report of a part (PC-DMIS text report, or a table of feature, axis,\n"
      "nominal, actual and tolerances) and fit the work offset that would centre it");
  cmm->add_option("FILE", o->file, "the CMM report")->required();
  add_json_flag(cmm, o->json);
  commands.push_back({cmm, [o] { return refusing(o->file, run_cmm, *o); }});

  CLI::App* touches = analyze->add_subcommand(
      "touches",
      "judge a real control's touch log of a program written by `ncqual program`, exactly as\n"
      "the solver service judges the check (exit code: its verdict)");
  touches->add_option("LOG", o->file, "the control's touch log")->required();
  touches->add_option("--program", o->program, "the program that wrote it")
      ->type_name("PROG")
      ->required();
  add_machine_option(touches, o->machine, "the machine that ran it");
  add_plant_option(touches, o->plant);
  add_json_flag(touches, o->json);
  commands.push_back({touches, [o] { return refusing(o->file, run_touches, *o); }});

  CLI::App* points = analyze->add_subcommand(
      "points",
      "judge a laser tracker's point export of a tracker check (a name and x, y, z per point)\n"
      "against the nominal list `ncqual program` wrote for it, exactly as the solver service\n"
      "judges the check (exit code: its verdict)");
  points->add_option("EXPORT", o->file, "the tracker software's point export")->required();
  points->add_option("--nominals", o->program, "the nominal list the points were measured to")
      ->type_name("LIST")
      ->required();
  add_machine_option(points, o->machine, "the machine measured");
  add_plant_option(points, o->plant);
  add_json_flag(points, o->json);
  commands.push_back({points, [o] { return refusing(o->file, run_points, *o); }});
}

}  // namespace ncqual::cli

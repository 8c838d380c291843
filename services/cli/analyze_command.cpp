// `ncqual analyze`: reads an instrument file, hands it to the solver's evaluation, prints the
// figures. See analyze_command.hpp. Each subcommand is one entry of kSubcommands (its options
// and its runner), so another evaluation (e.g. `grid`) is one more entry.
#include "analyze_command.hpp"

#include "ncqual/args.hpp"
#include "ncqual/csv.hpp"
#include "ncqual/units.hpp"
#include "ncqual/solver/circular_test.hpp"
#include "ncqual/solver/global_grid.hpp"
#include "ncqual/solver/instrument_files.hpp"
#include "ncqual/solver/iso230_2.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace ncqual {

const char* const kAnalyzeUsage =
    "  analyze iso230-2 FILE [--json]\n"
    "      evaluate a linear-axis positioning run (target_mm,cycle,direction,measured_mm)\n"
    "      per ISO 230-2:2014: A, E, M, R, B per axis and per target\n"
    "  analyze circle FILE [--plane XY|YZ|XZ] [--nominal-radius-mm R] [--centre-mm U,V] [--json]\n"
    "      evaluate a circular test (angle_deg,radius_mm or x_mm,y_mm | y_mm,z_mm | x_mm,z_mm |\n"
    "      u_mm,v_mm, optional direction ccw/cw) per ISO 230-4: G, G(b), H, F, scale mismatch\n"
    "      and squareness of the two axes\n"
    "  analyze grid --x-run F --y-run F --grid F [--json]\n"
    "      the monthly tracker grid (point,x_cmd,y_cmd,z_cmd,x_meas,y_meas,z_meas; commanded in\n"
    "      machine axes, measured in the tracker frame): master frame from the X and Y runs,\n"
    "      per-point deviations, squareness and scale of the axes\n";

namespace {

constexpr int kExitError = 1, kExitUsage = 2;
using units::kPi;

using nlohmann::json;

// ---- Formatting ---------------------------------------------------------------------------------

json or_null(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

std::string mm(double v) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.4f", v);
  return buf;
}
std::string mm(const std::optional<double>& v) { return v ? mm(*v) : "-"; }

std::string fixed(double v, int decimals) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

// Right-aligned in `width`.
std::string right(const std::string& s, std::size_t width) {
  return s.size() >= width ? s : std::string(width - s.size(), ' ') + s;
}
std::string left(const std::string& s, std::size_t width) {
  return s.size() >= width ? s : s + std::string(width - s.size(), ' ');
}

// ---- iso230-2 -----------------------------------------------------------------------------------

json direction_json(const std::optional<solver::DirectionFigures>& d) {
  if (!d) return nullptr;
  return {{"n", d->cycles}, {"mean", d->mean_mm}, {"s", d->s_mm},
          {"R", d->R_mm},   {"min", d->min_mm},   {"max", d->max_mm}};
}

json to_json(const solver::Iso230_2Result& r, const std::string& file) {
  json per_target = json::array();
  for (const auto& t : r.targets) {
    per_target.push_back({{"target_mm", t.target_mm},
                          {"up", direction_json(t.up)},
                          {"down", direction_json(t.down)},
                          {"B", or_null(t.B_mm)},
                          {"R", or_null(t.R_mm)},
                          {"mean", or_null(t.mean_mm)}});
  }
  json directions = json::array();
  if (r.has_up) directions.push_back("up");
  if (r.has_down) directions.push_back("down");
  return {{"standard", "ISO 230-2:2014"},
          {"file", file},
          {"unit", "mm"},
          {"targets", r.targets.size()},
          {"cycles", r.cycles},
          {"directions", directions},
          {"A", or_null(r.A_mm)},
          {"A_up", or_null(r.A_up_mm)},
          {"A_down", or_null(r.A_down_mm)},
          {"E", or_null(r.E_mm)},
          {"E_up", or_null(r.E_up_mm)},
          {"E_down", or_null(r.E_down_mm)},
          {"M", or_null(r.M_mm)},
          {"R", or_null(r.R_mm)},
          {"R_up", or_null(r.R_up_mm)},
          {"R_down", or_null(r.R_down_mm)},
          {"B", or_null(r.B_mm)},
          {"B_mean", or_null(r.B_mean_mm)},
          {"per_target", per_target}};
}

void print_iso230_2(const solver::Iso230_2Result& r, const std::string& file) {
  const std::string dirs = r.has_up && r.has_down ? "both directions"
                           : r.has_up             ? "up (+) only"
                                                  : "down (-) only";
  std::printf("ISO 230-2:2014 positioning test: %s\n", file.c_str());
  std::printf("  %zu targets (%s .. %s mm), %d cycles, %s\n\n", r.targets.size(),
              mm(r.targets.front().target_mm).c_str(), mm(r.targets.back().target_mm).c_str(),
              r.cycles, dirs.c_str());
  std::printf("Axis (mm)            bidirectional       up (+)     down (-)\n");
  auto axis_row = [](const char* name, const std::optional<double>& both,
                     const std::optional<double>& up, const std::optional<double>& down) {
    std::printf("  %s%s%s%s\n", left(name, 20).c_str(), right(mm(both), 12).c_str(),
                right(mm(up), 13).c_str(), right(mm(down), 13).c_str());
  };
  axis_row("A  accuracy", r.A_mm, r.A_up_mm, r.A_down_mm);
  axis_row("E  systematic dev.", r.E_mm, r.E_up_mm, r.E_down_mm);
  axis_row("R  repeatability", r.R_mm, r.R_up_mm, r.R_down_mm);
  axis_row("M  range of mean x_i", r.M_mm, std::nullopt, std::nullopt);
  axis_row("B  reversal", r.B_mm, std::nullopt, std::nullopt);
  axis_row("B_mean mean reversal", r.B_mean_mm, std::nullopt, std::nullopt);

  std::printf("\nPer target (mm): mean = mean deviation, s = standard uncertainty, R = 4 s;\n"
              "  B_i = reversal, R_i = bidirectional repeatability, x_i = mean bidirectional "
              "deviation\n");
  const std::vector<std::pair<std::string, std::size_t>> cols{
      {"target", 12}, {"n↑", 4},  {"mean↑", 9}, {"s↑", 8},   {"R↑", 8}, {"n↓", 4},
      {"mean↓", 9},   {"s↓", 8},  {"R↓", 8},    {"B_i", 9},  {"R_i", 8}, {"x_i", 9}};
  std::string header = " ";
  for (const auto& [name, width] : cols) {
    // The arrows are 3 bytes and one column wide.
    std::size_t chars = 0;
    for (unsigned char ch : name) chars += (ch & 0xC0) != 0x80 ? 1 : 0;
    header += std::string(width > chars ? width - chars : 0, ' ') + name;
  }
  std::printf("%s\n", header.c_str());
  for (const auto& t : r.targets) {
    std::string line = " " + right(mm(t.target_mm), 12);
    for (const auto* d : {&t.up, &t.down}) {
      if (*d) {
        line += right(std::to_string((*d)->cycles), 4) + right(mm((*d)->mean_mm), 9) +
                right(mm((*d)->s_mm), 8) + right(mm((*d)->R_mm), 8);
      } else {
        line += right("-", 4) + right("-", 9) + right("-", 8) + right("-", 8);
      }
    }
    line += right(mm(t.B_mm), 9) + right(mm(t.R_mm), 8) + right(mm(t.mean_mm), 9);
    std::printf("%s\n", line.c_str());
  }
}

int run_iso230_2(const std::string& file, const Args& args) {
  const solver::Iso230_2File data = solver::read_iso230_2_csv(read_csv_file(file));
  const solver::Iso230_2Result r = solver::evaluate_iso230_2(data.readings);
  if (args.has("json")) {
    std::cout << to_json(r, file).dump(2) << "\n";
  } else {
    print_iso230_2(r, file);
  }
  return 0;
}

// ---- circle -------------------------------------------------------------------------------------

json vec(const Eigen::Vector2d& v) { return json::array({v.x(), v.y()}); }

json harmonics_json(const solver::RadialHarmonics& h) {
  return {{"a0", h.a0_mm}, {"a1", h.a1_mm}, {"b1", h.b1_mm},
          {"a2", h.a2_mm}, {"b2", h.b2_mm}, {"residual_rms", h.residual_rms_mm}};
}

json reference_json(const solver::RadialReference& ref) {
  return {{"centre", ref.nominal_centre ? "nominal" : "lsc"},
          {"radius", ref.nominal_radius ? "nominal" : "lsc"},
          {"centre_mm", vec(ref.centre_mm)},
          {"radius_mm", ref.radius_mm}};
}

json path_json(const std::optional<solver::CircularPathFigures>& p) {
  if (!p) return nullptr;
  return {{"points", p->point_count},
          {"lsc_centre_mm", vec(p->lsc_centre_mm)},
          {"lsc_radius_mm", p->lsc_radius_mm},
          {"lsc_rms_mm", p->lsc_rms_mm},
          {"G_mm", p->G_mm},
          {"F_max_mm", p->F_max_mm},
          {"F_min_mm", p->F_min_mm},
          {"F_reference", reference_json(p->F_reference)},
          {"max_gap_deg", p->max_gap_rad * 180.0 / kPi},
          {"scale_mismatch_um_per_m", p->scale_mismatch_um_per_m},
          {"squareness_urad", p->squareness_urad},
          {"harmonics_mm", harmonics_json(p->harmonics)}};
}

json to_json(const solver::CircularTestResult& r, const solver::CircleFile& data,
             const std::string& file) {
  return {{"standard", "ISO 230-4"},
          {"file", file},
          {"unit", "mm"},
          {"plane", std::string(solver::to_string(r.plane))},
          {"layout", data.polar ? "polar" : "coordinates"},
          {"points", data.input.points.size()},
          {"lsc_centre_mm", vec(r.lsc_centre_mm)},
          {"lsc_radius_mm", r.lsc_radius_mm},
          {"G_mm", r.G_mm},
          {"G_b_mm", or_null(r.G_b_mm)},
          {"H_mm", or_null(r.H_mm)},
          {"F_max_mm", r.F_max_mm},
          {"F_min_mm", r.F_min_mm},
          {"F_reference", reference_json(r.F_reference)},
          {"scale_mismatch_um_per_m", r.scale_mismatch_um_per_m},
          {"squareness_urad", r.squareness_urad},
          {"harmonics_mm", harmonics_json(r.harmonics)},
          {"directions", {{"ccw", path_json(r.ccw)}, {"cw", path_json(r.cw)}}}};
}

std::string reference_text(const solver::RadialReference& ref) {
  return (ref.nominal_centre ? "nominal centre (" : "LSC centre (") + mm(ref.centre_mm.x()) +
         ", " + mm(ref.centre_mm.y()) + ") mm, " +
         (ref.nominal_radius ? "nominal radius R0 " : "LSC radius ") + mm(ref.radius_mm) + " mm";
}

void print_circle(const solver::CircularTestResult& r, const solver::CircleFile& data,
                  const std::string& file) {
  const std::string plane(solver::to_string(r.plane));
  const std::string u(1, plane[0]), v(1, plane[1]);
  std::printf("ISO 230-4 circular test: %s\n", file.c_str());
  std::printf("  plane %s (u = %s, v = %s), %zu points (%s), directions:%s%s\n", plane.c_str(),
              u.c_str(), v.c_str(), data.input.points.size(),
              data.polar ? "angle_deg, radius_mm" : "coordinates", r.ccw ? " ccw" : "",
              r.cw ? " cw" : "");
  std::printf("  least-squares circle of all points: centre (%s, %s) = (%s, %s) mm, radius %s "
              "mm\n",
              u.c_str(), v.c_str(), mm(r.lsc_centre_mm.x()).c_str(),
              mm(r.lsc_centre_mm.y()).c_str(), mm(r.lsc_radius_mm).c_str());
  std::printf("  F measured from the %s\n\n", reference_text(r.F_reference).c_str());

  auto path_value = [](const std::optional<solver::CircularPathFigures>& p, auto get) {
    return p ? get(*p) : std::string("-");
  };
  std::printf("%s%s%s%s\n", left("", 34).c_str(), right("ccw", 12).c_str(),
              right("cw", 12).c_str(), right("both", 12).c_str());
  auto row = [&](const char* name, const std::string& ccw, const std::string& cw,
                 const std::string& both) {
    std::printf("  %s%s%s%s\n", left(name, 32).c_str(), right(ccw, 12).c_str(),
                right(cw, 12).c_str(), right(both, 12).c_str());
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
  row("largest angular gap (deg)",
      path_value(r.ccw, [](const P& p) { return fixed(p.max_gap_rad * 180.0 / kPi, 1); }),
      path_value(r.cw, [](const P& p) { return fixed(p.max_gap_rad * 180.0 / kPi, 1); }), "-");
  if (r.ccw && r.cw) {
    std::printf("\n  The scale mismatch and squareness of one direction include its reversal "
                "errors;\n  those of both directions together cancel them.\n");
  }
}

// "U,V" -> (U, V); ArgError naming the flag otherwise.
Eigen::Vector2d parse_centre(const std::string& text) {
  const auto comma = text.find(',');
  auto number = [&](const std::string& part) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(part, &used);
    } catch (const std::logic_error&) {
      used = 0;
    }
    while (used < part.size() && part[used] == ' ') ++used;
    if (used == 0 || used != part.size() || !std::isfinite(v)) {
      throw ArgError("--centre-mm '" + text + "': expected two numbers U,V (mm)");
    }
    return v;
  };
  if (comma == std::string::npos || text.find(',', comma + 1) != std::string::npos) {
    throw ArgError("--centre-mm '" + text + "': expected two numbers U,V (mm)");
  }
  return {number(text.substr(0, comma)), number(text.substr(comma + 1))};
}

int run_circle(const std::string& file, const Args& args) {
  std::optional<solver::Plane> plane;
  if (const auto p = args.get("plane")) {
    plane = solver::parse_plane(*p);
    if (!plane) throw ArgError("--plane '" + *p + "': expected XY, YZ or XZ");
  }
  std::optional<double> nominal_radius;
  if (args.has("nominal-radius-mm")) {
    nominal_radius = args.get_double("nominal-radius-mm", 0);
    if (!(std::isfinite(*nominal_radius) && *nominal_radius > 0)) {
      throw ArgError("--nominal-radius-mm " + *args.get("nominal-radius-mm") +
                     ": expected a radius > 0 (mm)");
    }
  }
  std::optional<Eigen::Vector2d> centre;
  if (const auto c = args.get("centre-mm")) centre = parse_centre(*c);

  solver::CircleFile data = solver::read_circle_csv(read_csv_file(file), plane);
  data.input.nominal_radius_mm = nominal_radius;
  data.input.nominal_centre_mm = centre;
  const solver::CircularTestResult r = solver::evaluate_circular_test(data.input);
  if (args.has("json")) {
    std::cout << to_json(r, data, file).dump(2) << "\n";
  } else {
    print_circle(r, data, file);
  }
  return 0;
}

// ---- grid ---------------------------------------------------------------------------------------

json vec3(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

// One of the grid's files as frame points, refusing one with fewer than `minimum` points at its
// last line.
std::vector<solver::FramePoint> grid_file(const std::string& path, std::size_t minimum,
                                          const std::string& what) {
  const CsvTable table = read_csv_file(path);
  const std::vector<solver::GridFilePoint> points = solver::read_grid_csv(table);
  if (points.size() < minimum) {
    const int last = table.rows.empty() ? table.header_line : table.rows.back().line;
    throw CsvError(path, last, 0,
                   std::to_string(points.size()) + " points; " + what + " needs at least " +
                       std::to_string(minimum));
  }
  std::vector<solver::FramePoint> out;
  for (const auto& p : points) out.push_back({p.point, p.commanded_mm, p.measured_mm});
  return out;
}

json run_json(const solver::RunFit& run, const std::string& file) {
  return {{"file", file},
          {"points", run.points.size()},
          {"straightness_mm", json::array({run.straightness_mm[0], run.straightness_mm[1]})},
          {"max_distance_mm", run.max_distance_mm},
          {"scale_um_per_m", run.scale_um_per_m}};
}

int run_grid(const std::string&, const Args& args) {
  const std::string x_file = args.require("x-run"), y_file = args.require("y-run"),
                    g_file = args.require("grid");
  // The fewest points each part can take: a line needs 3 to show straightness, the affine fit
  // of the grid has 12 unknowns (4 points) and needs a fifth to leave a residual.
  const auto x_run = grid_file(x_file, 3, "an X run");
  const auto y_run = grid_file(y_file, 3, "a Y run");
  const auto grid = grid_file(g_file, 5, "the grid (12 affine unknowns)");
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
  if (args.has("json")) {
    json points = json::array();
    for (const auto& p : r.points) {
      points.push_back({{"point", p.label},
                        {"commanded_mm", vec3(p.commanded_mm)},
                        {"master_mm", vec3(p.master_mm)},
                        {"deviation_mm", vec3(p.deviation_mm)},
                        {"deviation_norm_mm", p.deviation_norm_mm}});
    }
    json worst = json::array();
    for (std::size_t i : r.worst_points) worst.push_back(r.points[i].label);
    json planes = json::array();
    for (const auto& pl : r.planes) {
      planes.push_back({{"z_mm", pl.z_mm},
                        {"points", pl.point_count},
                        {"worst_point", pl.worst_label},
                        {"worst_deviation_mm", pl.worst_deviation_mm},
                        {"rms_deviation_mm", pl.rms_deviation_mm}});
    }
    const json out = {
        {"unit", "mm"},
        {"grid_file", g_file},
        {"points", r.points.size()},
        {"max_deviation_mm", r.max_deviation_mm},
        {"max_deviation_point", r.max_deviation_label},
        {"rms_deviation_mm", r.rms_deviation_mm},
        {"max_abs_dx_mm", r.max_abs_dx_mm},
        {"max_abs_dy_mm", r.max_abs_dy_mm},
        {"max_abs_dz_mm", r.max_abs_dz_mm},
        {"squareness_xy_urad", r.affine.squareness_xy_urad},
        {"squareness_yz_urad", r.affine.squareness_yz_urad},
        {"squareness_zx_urad", r.affine.squareness_zx_urad},
        {"scale_x_um_per_m", r.affine.scale_x_um_per_m},
        {"scale_y_um_per_m", r.affine.scale_y_um_per_m},
        {"scale_z_um_per_m", r.affine.scale_z_um_per_m},
        {"affine_residual_rms_mm", r.affine.residual_rms_mm},
        {"master_frame",
         {{"orthogonality_urad", frame.orthogonality_urad},
          {"origin_rms_mm", frame.origin_rms_mm},
          {"x_run", run_json(frame.x_run, x_file)},
          {"y_run", run_json(frame.y_run, y_file)}}},
        {"worst_points", worst},
        {"planes", planes},
        {"per_point", points}};
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  std::printf("grid %s: %zu points in the master frame of %s and %s\n", g_file.c_str(),
              r.points.size(), x_file.c_str(), y_file.c_str());
  std::printf("  max deviation   %s mm at %s, rms %s mm\n", mm(r.max_deviation_mm).c_str(),
              r.max_deviation_label.c_str(), mm(r.rms_deviation_mm).c_str());
  std::printf("  max |dx| |dy| |dz| %s %s %s mm\n", mm(r.max_abs_dx_mm).c_str(),
              mm(r.max_abs_dy_mm).c_str(), mm(r.max_abs_dz_mm).c_str());
  std::printf("  squareness xy %s  yz %s  zx %s urad (positive: wider than 90 deg)\n",
              fixed(r.affine.squareness_xy_urad, 1).c_str(),
              fixed(r.affine.squareness_yz_urad, 1).c_str(),
              fixed(r.affine.squareness_zx_urad, 1).c_str());
  std::printf("  scale x %s  y %s  z %s um/m\n", fixed(r.affine.scale_x_um_per_m, 1).c_str(),
              fixed(r.affine.scale_y_um_per_m, 1).c_str(),
              fixed(r.affine.scale_z_um_per_m, 1).c_str());
  std::printf("  master frame: X and Y runs %s urad from square\n",
              fixed(frame.orthogonality_urad, 1).c_str());
  for (const auto& pl : r.planes) {
    std::printf("  plane Z %s: worst %s (%s mm), rms %s mm\n", fixed(pl.z_mm, 1).c_str(),
                pl.worst_label.c_str(), mm(pl.worst_deviation_mm).c_str(),
                mm(pl.rms_deviation_mm).c_str());
  }
  return 0;
}

// ---- Dispatch -----------------------------------------------------------------------------------

struct Subcommand {
  const char* name;
  std::set<std::string> with_value;
  std::set<std::string> switches;
  int (*run)(const std::string& file, const Args& args);
  bool takes_file = true;  // one positional FILE; else every file is an option
};

const std::vector<Subcommand>& subcommands() {
  static const std::vector<Subcommand> all{
      {"iso230-2", {}, {"json"}, run_iso230_2},
      {"circle", {"plane", "nominal-radius-mm", "centre-mm"}, {"json"}, run_circle},
      {"grid", {"x-run", "y-run", "grid"}, {"json"}, run_grid, false},
  };
  return all;
}

int usage_error(const std::string& message) {
  std::cerr << "ncqual analyze: " << message << "\nusage: ncqual analyze <what> FILE [options]\n"
            << kAnalyzeUsage;
  return kExitUsage;
}

}  // namespace

int run_analyze(const std::vector<std::string>& args) {
  if (args.empty()) return usage_error("say what to analyze");
  if (args[0] == "help" || std::find(args.begin(), args.end(), "--help") != args.end()) {
    std::cout << "usage: ncqual analyze <what> FILE [options]\n" << kAnalyzeUsage;
    return 0;
  }
  const Subcommand* sub = nullptr;
  for (const auto& s : subcommands()) {
    if (args[0] == s.name) sub = &s;
  }
  if (!sub) return usage_error("unknown analysis '" + args[0] + "'");

  std::string file;
  try {
    const Args parsed(std::vector<std::string>(args.begin() + 1, args.end()), sub->with_value,
                      sub->switches);
    if (!sub->takes_file) {
      if (!parsed.positional().empty()) {
        throw ArgError("takes its files as options, not '" + parsed.positional().front() + "'");
      }
      return sub->run("", parsed);
    }
    if (parsed.positional().size() != 1) {
      throw ArgError(parsed.positional().empty()
                         ? "give the FILE to analyze"
                         : "one FILE at a time (got " +
                               std::to_string(parsed.positional().size()) + ")");
    }
    file = parsed.positional().front();
    return sub->run(file, parsed);
  } catch (const ArgError& e) {
    return usage_error(std::string(sub->name) + ": " + e.what());
  } catch (const CsvError& e) {
    std::cerr << e.what() << "\n";
    return kExitError;
  } catch (const std::invalid_argument& e) {
    std::cerr << file << ": " << e.what() << "\n";
    return kExitError;
  }
}

}  // namespace ncqual

// SPDX-License-Identifier: Apache-2.0
#include "ncqual/solver/instrument_files.hpp"

#include "ncqual/check_kinds.hpp"
#include "ncqual/units.hpp"
#include "result_building.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <tuple>

namespace ncqual::solver {
namespace {

// No machine tool or tracker measures a kilometre: a reading beyond is a broken export (1e300
// would pass as finite and turn every figure into inf and nan).
constexpr double kMaxLengthMm = 1e6;
constexpr double kMaxAngleDeg = 1e5;  // about 280 turns of a circle test

// The cell in mm, from a column in `unit` (`to_mm` mm each).
double length_mm(const CsvTable& t, const CsvRow& row, std::size_t column, double to_mm = 1,
                 const std::string& unit = "mm") {
  return t.number_within(row, column, kMaxLengthMm / to_mm, unit,
                         "no machine or instrument reaches 1 km") *
         to_mm;
}

using units::kPi;

// The line a whole-data problem is reported at: the last data row, or the header.
int last_line(const CsvTable& t) { return t.rows.empty() ? t.header_line : t.rows.back().line; }

// Turns a problem found by the solver (indices into the data) into a CsvError at file lines.
[[noreturn]] void fail_at_lines(const CsvTable& t, const std::vector<int>& lines,
                                const std::optional<std::size_t>& index,
                                const std::optional<std::size_t>& first_index,
                                const std::string& message) {
  const int line = index ? lines[*index] : last_line(t);
  std::string text = message;
  if (first_index) text += " (first at line " + std::to_string(lines[*first_index]) + ")";
  throw CsvError(t.file, line, 0, text);
}

std::string column_list(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

[[noreturn]] void fail_header(const CsvTable& t, const std::string& why) {
  throw CsvError(t.file, t.header_line, 0, why + "; the header has: " + column_list(t.header));
}

struct CoordinatePair {
  Plane plane;
  const char* u;
  const char* v;
};
constexpr CoordinatePair kPairs[] = {
    {Plane::XY, "x_mm", "y_mm"}, {Plane::YZ, "y_mm", "z_mm"}, {Plane::XZ, "x_mm", "z_mm"}};

// The columns of a grid file: commanded and measured X, Y, Z.
struct GridColumns {
  std::array<std::size_t, 3> commanded{}, measured{};
};
GridColumns grid_columns(const CsvTable& t) {
  GridColumns c;
  const char* const cmd_names[] = {"x_cmd", "y_cmd", "z_cmd"};
  const char* const meas_names[] = {"x_meas", "y_meas", "z_meas"};
  for (int k = 0; k < 3; ++k) c.commanded[k] = t.require_column(cmd_names[k]);
  for (int k = 0; k < 3; ++k) c.measured[k] = t.require_column(meas_names[k]);
  return c;
}

// A length column of an instrument export and the unit its header names.
struct LengthColumn {
  std::size_t index = 0;
  double to_mm = 1;
  std::string unit = "mm";  // as the header names it: mm, um, in
  bool deviation = false;   // the error from the target, not the position
};

// A header name without case, spaces and '_' / '-' around the unit: "Target (mm)" -> "target(mm)".
std::string normalised(std::string_view name) {
  std::string out;
  for (std::size_t i = 0; i < name.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(name[i]);
    if (c == ' ' || c == '\t') continue;
    // U+00B5 (micro sign) and U+03BC (Greek mu) as 'u'.
    if ((c == 0xC2 && i + 1 < name.size() && static_cast<unsigned char>(name[i + 1]) == 0xB5) ||
        (c == 0xCE && i + 1 < name.size() && static_cast<unsigned char>(name[i + 1]) == 0xBC)) {
      out += 'u';
      ++i;
      continue;
    }
    out += static_cast<char>(std::tolower(c));
  }
  return out;
}

// The millimetres of one `unit` ("mm", "um", "in", "inch"); nothing for another word.
std::optional<double> mm_per(std::string_view unit) {
  if (unit == "mm") return 1.0;
  if (unit == "um" || unit == "micron" || unit == "microns") return 1e-3;
  if (unit == "in" || unit == "inch" || unit == "inches") return 25.4;
  return std::nullopt;
}

// The first column named <base> with a unit, "<base>_<unit>", "<base>(<unit>)" or
// "<base>[<unit>]" (any case and spacing), for each base in order. A column named <base> alone
// is refused: its unit would be a guess.
std::optional<LengthColumn> find_length_column(const CsvTable& t,
                                               std::initializer_list<const char*> bases,
                                               const std::string& example) {
  for (const char* base : bases) {
    const std::string b = base;
    for (std::size_t c = 0; c < t.header.size(); ++c) {
      const std::string n = normalised(t.header[c]);
      if (n.rfind(b, 0) != 0) continue;
      std::string unit = n.substr(b.size());
      if (unit.empty()) {
        t.fail(t.header_line, c,
               "column '" + t.header[c] + "' names no unit: write it as " + example);
      }
      if ((unit.front() == '(' && unit.back() == ')') ||
          (unit.front() == '[' && unit.back() == ']')) {
        unit = unit.substr(1, unit.size() - 2);
      } else if (unit.front() == '_' || unit.front() == '-') {
        unit = unit.substr(1);
      } else {
        continue;  // another word that starts like the base ("targets", "errorcode")
      }
      const auto scale = mm_per(unit);
      if (!scale) {
        t.fail(t.header_line, c,
               "column '" + t.header[c] + "': unit '" + unit + "' is not mm, um or in");
      }
      LengthColumn col;
      col.index = c;
      col.to_mm = *scale;
      col.unit = *scale == 1.0 ? "mm" : *scale < 1 ? "um" : "in";
      return col;
    }
  }
  return std::nullopt;
}

// The columns of an ISO 230-2 run: the target, and the measured position or the deviation from
// the target, each in the unit its header names; the cycle and the direction.
struct Iso230_2Columns {
  LengthColumn target, measured;
  std::size_t cycle = 0, direction = 0;
};

// `words`: also the cycle and direction columns (the envelope check reads lengths only).
Iso230_2Columns iso230_2_columns(const CsvTable& t, bool words = true) {
  Iso230_2Columns c;
  const auto target = find_length_column(t, {"target", "nominal"},
                                         "target_mm, target_um or target_in ('Target (mm)')");
  if (!target) {
    fail_header(t, "no target column: expected target_mm (or target_in, target_um, 'Target (mm)')");
  }
  c.target = *target;
  if (auto measured = find_length_column(t, {"measured", "actual"},
                                         "measured_mm, measured_um or measured_in")) {
    c.measured = *measured;
  } else if (auto deviation =
                 find_length_column(t, {"error", "deviation"}, "error_um, error_mm or error_in")) {
    c.measured = *deviation;
    c.measured.deviation = true;
  } else {
    fail_header(t,
                "no measured column: expected measured_mm (or measured_in, measured_um), or the "
                "deviation from the target as error_um (or error_mm, error_in, deviation_um)");
  }
  const auto word_column = [&](std::initializer_list<const char*> names, const char* what) {
    for (const char* name : names) {
      for (std::size_t k = 0; k < t.header.size(); ++k) {
        if (normalised(t.header[k]) == name) return k;
      }
    }
    fail_header(t, std::string("no ") + what + " column: expected '" + *names.begin() + "'");
  };
  if (!words) return c;
  c.cycle = word_column({"cycle", "run"}, "cycle");
  c.direction = word_column({"direction", "dir"}, "direction");
  return c;
}

double length_mm(const CsvTable& t, const CsvRow& row, const LengthColumn& c) {
  return length_mm(t, row, c.index, c.to_mm, c.unit);
}

double target_mm(const CsvTable& t, const CsvRow& row, const Iso230_2Columns& c) {
  return length_mm(t, row, c.target);
}

double measured_mm(const CsvTable& t, const CsvRow& row, const Iso230_2Columns& c) {
  const double v = length_mm(t, row, c.measured);
  return c.measured.deviation ? target_mm(t, row, c) + v : v;
}

// The words of an approach in + and in -, as instruments write them.
const std::vector<std::string> kUpWords = {"up", "+", "fwd", "forward", "pos", "positive"};
const std::vector<std::string> kDownWords = {"down", "-",       "bwd", "back",    "backward",
                                             "rev",  "reverse", "neg", "negative"};

}  // namespace

// ---- ISO 230-2 ----------------------------------------------------------------------------------

Iso230_2File read_iso230_2_csv(const CsvTable& t) {
  const Iso230_2Columns c = iso230_2_columns(t);
  std::vector<std::string> words = kUpWords;
  words.insert(words.end(), kDownWords.begin(), kDownWords.end());
  Iso230_2File out;
  out.file = t.file;
  for (const CsvRow& row : t.rows) {
    PositioningReading r;
    r.target_mm = target_mm(t, row, c);
    r.cycle = t.integer(row, c.cycle);
    const std::string word = t.word(row, c.direction, words);
    r.direction = std::find(kUpWords.begin(), kUpWords.end(), word) != kUpWords.end()
                      ? Approach::Up
                      : Approach::Down;
    r.measured_mm = measured_mm(t, row, c);
    out.readings.push_back(r);
    out.lines.push_back(row.line);
  }
  if (const auto p = find_iso230_2_problem(out.readings)) {
    fail_at_lines(t, out.lines, p->index, p->first_index, p->message);
  }
  return out;
}

Iso230_2File read_iso230_2_csv(std::string_view text, const std::string& file) {
  return read_iso230_2_csv(read_csv(text, file));
}

// ---- Circle -------------------------------------------------------------------------------------

CircleFile read_circle_csv(const CsvTable& t, std::optional<Plane> plane) {
  const bool has_angle = t.find_column("angle_deg").has_value();
  const bool has_radius = t.find_column("radius_mm").has_value();
  const bool has_uv = t.find_column("u_mm") && t.find_column("v_mm");
  std::vector<const CoordinatePair*> pairs;
  for (const auto& p : kPairs) {
    if (t.find_column(p.u) && t.find_column(p.v)) pairs.push_back(&p);
  }
  const bool polar = has_angle || has_radius;
  const bool coordinates = has_uv || !pairs.empty();
  const std::string plane_needed = "pass the plane (XY, YZ or XZ)";

  CircleFile out;
  out.file = t.file;
  out.polar = polar;
  std::size_t c_a = 0, c_b = 0;  // angle/radius or u/v
  if (polar && coordinates) {
    fail_header(t,
                "both polar (angle_deg, radius_mm) and coordinate columns; a circle file has "
                "one layout");
  }
  if (polar) {
    c_a = t.require_column("angle_deg");
    c_b = t.require_column("radius_mm");
    if (!plane) fail_header(t, "angle_deg, radius_mm do not name the plane: " + plane_needed);
    out.input.plane = *plane;
  } else if (has_uv) {
    if (!pairs.empty()) {
      fail_header(t, "both u_mm, v_mm and " + std::string(pairs.front()->u) + ", " +
                         pairs.front()->v + "; a circle file has one coordinate pair");
    }
    if (!plane) fail_header(t, "u_mm, v_mm do not name the plane: " + plane_needed);
    c_a = *t.find_column("u_mm");
    c_b = *t.find_column("v_mm");
    out.input.plane = *plane;
  } else if (!pairs.empty()) {
    const CoordinatePair* chosen = nullptr;
    if (plane) {
      for (const auto* p : pairs) {
        if (p->plane == *plane) chosen = p;
      }
      if (!chosen) {
        const CoordinatePair* named = pairs.front();
        throw CsvError(t.file, t.header_line, static_cast<int>(*t.find_column(named->u)) + 1,
                       std::string("the header's ") + named->u + ", " + named->v + " name plane " +
                           std::string(to_string(named->plane)) + ", but plane " +
                           std::string(to_string(*plane)) + " was asked for");
      }
    } else if (pairs.size() > 1) {
      fail_header(t, "x_mm, y_mm and z_mm name more than one plane: " + plane_needed);
    } else {
      chosen = pairs.front();
    }
    c_a = *t.find_column(chosen->u);
    c_b = *t.find_column(chosen->v);
    out.input.plane = chosen->plane;
  } else {
    fail_header(t,
                "no circle columns: expected angle_deg,radius_mm or a coordinate pair x_mm,y_mm "
                "| y_mm,z_mm | x_mm,z_mm | u_mm,v_mm");
  }

  const std::optional<std::size_t> c_direction = t.find_column("direction");
  // First line of each (direction, angle modulo 360) of a polar file.
  std::map<std::pair<PathDirection, double>, int> angles_seen;
  for (const CsvRow& row : t.rows) {
    PathDirection d = PathDirection::Ccw;
    if (c_direction)
      d = t.word(row, *c_direction, {"ccw", "cw"}) == "ccw" ? PathDirection::Ccw
                                                            : PathDirection::Cw;
    const double a = polar ? t.number_within(row, c_a, kMaxAngleDeg, "deg",
                                             "a circle test turns a few times, not hundreds")
                           : length_mm(t, row, c_a);
    const double b = length_mm(t, row, c_b);
    CircularPoint p;
    if (polar) {
      if (!(b > 0))
        t.fail(row.line, c_b,
               "column 'radius_mm' = '" + t.cell(row, c_b) + "': a radius must be > 0");
      double wrapped = std::fmod(a, 360.0);
      if (wrapped < 0) wrapped += 360.0;
      if (wrapped == 0) wrapped = 0;  // -0 and 360 are 0
      const auto [it, fresh] = angles_seen.emplace(std::make_pair(d, wrapped), row.line);
      if (!fresh) {
        t.fail(row.line, c_a,
               "angle_deg = " + detail::quote_number(a) + ", direction " +
                   std::string(to_string(d)) + ": the same angle as line " +
                   std::to_string(it->second));
      }
      p = circular_point_from_polar(a * kPi / 180.0, b, d);
    } else {
      p = CircularPoint{Eigen::Vector2d(a, b), d};
    }
    out.input.points.push_back(p);
    out.lines.push_back(row.line);
  }
  if (const auto p = find_circular_test_problem(out.input)) {
    fail_at_lines(t, out.lines, p->index, p->first_index, p->message);
  }
  return out;
}

CircleFile read_circle_csv(std::string_view text, const std::string& file,
                           std::optional<Plane> plane) {
  return read_circle_csv(read_csv(text, file), plane);
}

// ---- Grid ---------------------------------------------------------------------------------------

std::vector<GridFilePoint> read_grid_csv(const CsvTable& t) {
  const std::size_t c_point = t.require_column("point");
  const GridColumns c = grid_columns(t);

  std::vector<GridFilePoint> out;
  std::map<std::string, int> names;
  std::map<std::tuple<double, double, double>, std::pair<std::string, int>> positions;
  for (const CsvRow& row : t.rows) {
    GridFilePoint g;
    g.line = row.line;
    g.point = t.cell(row, c_point);
    if (g.point.empty()) t.fail(row.line, c_point, "column 'point' is empty: name the point");
    for (int k = 0; k < 3; ++k) g.commanded_mm(k) = length_mm(t, row, c.commanded[k]);
    for (int k = 0; k < 3; ++k) g.measured_mm(k) = length_mm(t, row, c.measured[k]);
    const auto [name_it, fresh_name] = names.emplace(g.point, row.line);
    if (!fresh_name) {
      t.fail(row.line, c_point,
             "point '" + g.point + "' repeats line " + std::to_string(name_it->second));
    }
    const auto key = std::make_tuple(g.commanded_mm.x(), g.commanded_mm.y(), g.commanded_mm.z());
    const auto [pos_it, fresh_pos] = positions.emplace(key, std::make_pair(g.point, row.line));
    if (!fresh_pos) {
      t.fail(row.line, c.commanded[0],
             "point '" + g.point + "': commanded position (" +
                 detail::quote_number(g.commanded_mm.x()) + ", " +
                 detail::quote_number(g.commanded_mm.y()) + ", " +
                 detail::quote_number(g.commanded_mm.z()) + ") repeats point '" +
                 pos_it->second.first + "' on line " + std::to_string(pos_it->second.second));
    }
    out.push_back(g);
  }
  if (out.empty()) throw CsvError(t.file, t.header_line, 0, "no points after the header");
  return out;
}

std::vector<GridFilePoint> read_grid_csv(std::string_view text, const std::string& file) {
  return read_grid_csv(read_csv(text, file));
}

// ---- Imports -----------------------------------------------------------------------------------

namespace {

TrackerPoint tracker_point(std::string label, const Eigen::Vector3d& commanded_target,
                           const Eigen::Vector3d& measured, const ProbeGeometry& target) {
  // stylus_ball_centre at A = C = W = 0 is pivot + (ox, oy, -L).
  const Eigen::Vector3d pivot =
      commanded_target - Eigen::Vector3d(target.stylus_offset_mm.x(), target.stylus_offset_mm.y(),
                                         -target.tool_length_mm);
  TrackerPoint p;
  p.label = std::move(label);
  p.commanded.x_mm = pivot.x();
  p.commanded.y_mm = pivot.y();
  p.commanded.z_mm = pivot.z();
  p.measured_mm = measured;
  return p;
}

}  // namespace

std::vector<TrackerPoint> tracker_points_for_grid(const std::vector<GridFilePoint>& x_run,
                                                  const std::vector<GridFilePoint>& y_run,
                                                  const std::vector<GridFilePoint>& grid,
                                                  const ProbeGeometry& target) {
  std::vector<TrackerPoint> out;
  for (std::size_t i = 0; i < x_run.size(); ++i) {
    out.push_back(tracker_point("x_run:" + std::to_string(i), x_run[i].commanded_mm,
                                x_run[i].measured_mm, target));
  }
  for (std::size_t i = 0; i < y_run.size(); ++i) {
    out.push_back(tracker_point("y_run:" + std::to_string(i), y_run[i].commanded_mm,
                                y_run[i].measured_mm, target));
  }
  for (std::size_t i = 0; i < grid.size(); ++i) {
    out.push_back(tracker_point("grid:" + std::to_string(i) + ":t0", grid[i].commanded_mm,
                                grid[i].measured_mm, target));
  }
  return out;
}

std::vector<TrackerPoint> tracker_points_for_linear_run(const Iso230_2File& run, int axis,
                                                        const Eigen::Vector3d& at_mm,
                                                        const ProbeGeometry& target) {
  if (axis < 0 || axis > 2)
    throw std::invalid_argument("axis " + std::to_string(axis) + ": expected 0, 1 or 2");
  std::vector<double> targets;
  for (const auto& r : run.readings) targets.push_back(r.target_mm);
  std::sort(targets.begin(), targets.end());
  targets.erase(std::unique(targets.begin(), targets.end()), targets.end());
  std::vector<TrackerPoint> out;
  for (const auto& r : run.readings) {
    const auto rank =
        std::lower_bound(targets.begin(), targets.end(), r.target_mm) - targets.begin();
    Eigen::Vector3d commanded = at_mm, measured = at_mm;
    commanded[axis] = r.target_mm;
    measured[axis] = r.measured_mm;
    out.push_back(tracker_point("run:" + std::to_string(r.cycle) + ":" +
                                    std::string(to_string(r.direction)) + ":" +
                                    std::to_string(rank),
                                commanded, measured, target));
  }
  return out;
}

std::vector<TrackerPoint> tracker_points_for_circle(const CircleFile& circle,
                                                    const Eigen::Vector3d& centre_mm,
                                                    const ProbeGeometry& target) {
  const int u = circle.input.plane == Plane::YZ ? 1 : 0;
  const int v = circle.input.plane == Plane::XY ? 1 : 2;
  std::vector<TrackerPoint> out;
  int counts[2] = {0, 0};
  for (const auto& p : circle.input.points) {
    const bool ccw = p.direction == PathDirection::Ccw;
    Eigen::Vector3d at = centre_mm;
    at[u] += p.uv_mm.x();
    at[v] += p.uv_mm.y();
    out.push_back(tracker_point(std::string(ccw ? "ccw:" : "cw:") + std::to_string(counts[ccw]++),
                                at, at, target));
  }
  return out;
}

// ---- Plausibility against the machine ----------------------------------------------------------

double Envelope::span_mm() const { return std::max(100.0, (hi_mm - lo_mm).maxCoeff()); }

Envelope machine_envelope(const GlobalCheckConfig& config) {
  Envelope e;
  e.lo_mm = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  e.hi_mm = -e.lo_mm;
  for (const auto& info : check_kinds()) {
    if (!is_tracker_check(info.kind)) continue;
    for (const TrackerMove& m : global_check_program(info.kind, config)) {
      const Eigen::Vector3d p(m.commanded.x_mm, m.commanded.y_mm, m.commanded.z_mm);
      e.lo_mm = e.lo_mm.cwiseMin(p);
      e.hi_mm = e.hi_mm.cwiseMax(p);
    }
  }
  if (!e.lo_mm.allFinite()) e.lo_mm = e.hi_mm = Eigen::Vector3d::Zero();
  return e;
}

namespace {

using detail::format_number;

constexpr double kSpansBeyond = 10;      // how far beyond the envelope a position may lie
constexpr double kDeviationShare = 0.1;  // how large a deviation may be, as a share of the span

std::string mm(double v) { return format_number(v) + " mm"; }

std::string envelope_text(const Envelope& e) {
  std::string out = "the machine's envelope";
  const char* const axes = "XYZ";
  for (int k = 0; k < 3; ++k) {
    out += std::string(k ? "," : "") + " " + axes[k] + " " + format_number(e.lo_mm[k]) + ".." +
           format_number(e.hi_mm[k]);
  }
  return out + " mm (span " + mm(e.span_mm()) + ", from its monthly programs)";
}

// A position in column `c` of `row` on machine axis `axis` (-1: an offset about the centre,
// compared with ten spans either way).
void check_position(const CsvTable& t, const CsvRow& row, std::size_t c, int axis,
                    const Envelope& e, double to_mm = 1) {
  const double v = t.number(row, c) * to_mm;
  const double reach = kSpansBeyond * e.span_mm();
  const double lo = axis < 0 ? -reach : e.lo_mm[axis] - reach;
  const double hi = axis < 0 ? reach : e.hi_mm[axis] + reach;
  if (v >= lo && v <= hi) return;
  t.fail(row.line, c,
         "column '" + t.header[c] + "' = '" + t.cell(row, c) + "': beyond " + format_number(lo) +
             ".." + format_number(hi) + " mm, ten spans round " + envelope_text(e) +
             "; a file in another unit?");
}

}  // namespace

void check_iso230_2_envelope(const CsvTable& t, int axis, const Envelope& e) {
  const Iso230_2Columns c = iso230_2_columns(t, false);
  const double most = kDeviationShare * e.span_mm();
  for (const CsvRow& row : t.rows) {
    check_position(t, row, c.target.index, axis, e, c.target.to_mm);
    const double deviation = measured_mm(t, row, c) - target_mm(t, row, c);
    if (std::abs(deviation) > most) {
      t.fail(row.line, c.measured.index,
             "column '" + t.header[c.measured.index] + "' = '" + t.cell(row, c.measured.index) +
                 "': " + mm(deviation) + " from " + t.header[c.target.index] + " " +
                 t.cell(row, c.target.index) + ", more than " + mm(most) +
                 ", a tenth of the span of " + envelope_text(e));
    }
  }
}

void check_circle_envelope(const CsvTable& t, const Envelope& e) {
  for (const char* name : {"x_mm", "y_mm", "z_mm", "u_mm", "v_mm", "radius_mm"}) {
    const std::optional<std::size_t> c = t.find_column(name);
    if (!c) continue;
    for (const CsvRow& row : t.rows) check_position(t, row, *c, -1, e);
  }
}

void check_grid_envelope(const CsvTable& t, const Envelope& e) {
  if (t.rows.empty()) return;
  const GridColumns c = grid_columns(t);
  const auto vector = [&](const CsvRow& row, const std::array<std::size_t, 3>& columns) {
    return Eigen::Vector3d(t.number(row, columns[0]), t.number(row, columns[1]),
                           t.number(row, columns[2]));
  };
  const double most = kDeviationShare * e.span_mm();
  const CsvRow& first = t.rows.front();
  const Eigen::Vector3d first_commanded = vector(first, c.commanded);
  const Eigen::Vector3d first_measured = vector(first, c.measured);
  for (const CsvRow& row : t.rows) {
    for (int k = 0; k < 3; ++k) check_position(t, row, c.commanded[k], k, e);
    const double commanded = (vector(row, c.commanded) - first_commanded).norm();
    const double measured = (vector(row, c.measured) - first_measured).norm();
    if (std::abs(measured - commanded) > most) {
      t.fail(row.line, c.measured[0],
             "measured " + mm(measured) + " from the first point (line " +
                 std::to_string(first.line) + ") where commanded " + mm(commanded) +
                 ": more than " + mm(most) + " apart, a tenth of the span of " + envelope_text(e) +
                 "; a file in another unit?");
    }
  }
}

}  // namespace ncqual::solver

// SPDX-License-Identifier: Apache-2.0
#include "ncqual/solver/instrument_files.hpp"

#include "ncqual/common/check_kinds.hpp"
#include "ncqual/common/text.hpp"
#include "ncqual/common/units.hpp"
#include "result_building.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <limits>
#include <map>
#include <set>
#include <regex>
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
  if (unit == "mm" || unit == "millimetre" || unit == "millimetres" || unit == "millimeter" ||
      unit == "millimeters") {
    return 1.0;
  }
  if (unit == "um" || unit == "micron" || unit == "microns") return 1e-3;
  if (unit == "in" || unit == "inch" || unit == "inches") return 25.4;
  return std::nullopt;
}

LengthColumn length_column(std::size_t index, double to_mm) {
  LengthColumn col;
  col.index = index;
  col.to_mm = to_mm;
  col.unit = to_mm == 1.0 ? "mm" : to_mm < 1 ? "um" : "in";
  return col;
}

// The value of a comment "<key>: <value>" (or "<key> = <value>") before the header, with its
// line: an instrument's own header ("# Units: um", "# Values: deviation"). Keys any case.
std::optional<std::pair<int, std::string>> declared(const CsvTable& t,
                                                    std::initializer_list<const char*> keys) {
  for (const auto& [line, text] : t.comments) {
    const std::size_t at = text.find_first_of(":=");
    if (at == std::string::npos) continue;
    const std::string key = normalised(text.substr(0, at));
    for (const char* k : keys) {
      if (key == k) {
        std::string value = normalised(text.substr(at + 1));
        return std::make_pair(line, value);
      }
    }
  }
  return std::nullopt;
}

// The length unit the file declares in a comment before its header ("# Units: um"), in mm per
// unit; nothing when it declares none. A declared unit that is not a length unit is refused at
// its line.
std::optional<double> declared_unit(const CsvTable& t) {
  const auto d = declared(t, {"unit", "units", "lengthunit", "lengthunits"});
  if (!d) return std::nullopt;
  const auto scale = mm_per(d->second);
  if (!scale) {
    throw CsvError(t.file, d->first, 0,
                   "the comment declares unit '" + d->second + "': expected mm, um or in");
  }
  return scale;
}

// The unit of a header that is `base` with a unit ("x_mm", "x(mm)", "x[in]", "x-um"): "" for the
// base alone, the unit's text otherwise; nothing for another name ("x_cmd" is no x column). The
// header normalised (see normalised()).
std::optional<std::string> unit_after(const std::string& n, const std::string& base) {
  if (n == base) return std::string();
  if (n.size() <= base.size() + 1 || n.compare(0, base.size(), base) != 0) return std::nullopt;
  std::string rest = n.substr(base.size());
  if ((rest.front() == '(' && rest.back() == ')') || (rest.front() == '[' && rest.back() == ']')) {
    return rest.substr(1, rest.size() - 2);
  }
  if (rest.front() == '_' || rest.front() == '-') return rest.substr(1);
  return std::nullopt;
}

// What a column named <base> with a unit that is not a length does: refuse it (an ISO 230-2
// target or reading in an unknown unit), or skip it (a circle or point export's "x_cmd" is no x
// coordinate).
enum class OtherUnit { Refuse, Skip };

// The first column named <base> with a unit, "<base>_<unit>", "<base>(<unit>)" or
// "<base>[<unit>]" (any case and spacing), for each base in order. A column named <base> alone
// takes the unit a comment before the header declares ("# Units: um"), else it is refused: its
// unit would be a guess; the refusal says to write it as `example` (empty: the column's name
// with " (mm)").
std::optional<LengthColumn> find_length_column(const CsvTable& t,
                                               std::initializer_list<const char*> bases,
                                               const std::string& example,
                                               OtherUnit other = OtherUnit::Refuse) {
  for (const char* base : bases) {
    for (std::size_t c = 0; c < t.header.size(); ++c) {
      const auto unit = unit_after(normalised(t.header[c]), base);
      if (!unit) continue;  // another word that starts like the base ("targets", "errorcode")
      if (unit->empty()) {
        if (const auto scale = declared_unit(t)) return length_column(c, *scale);
        t.fail(t.header_line, c,
               "column '" + t.header[c] + "' names no unit: write it as " +
                   (example.empty() ? "'" + t.header[c] + " (mm)' (or um, in)" : example) +
                   ", or declare the file's unit in a comment before the header ('# Units: mm')");
      }
      if (const auto scale = mm_per(*unit)) return length_column(c, *scale);
      if (other == OtherUnit::Refuse) {
        t.fail(t.header_line, c,
               "column '" + t.header[c] + "': unit '" + *unit + "' is not mm, um or in");
      }
    }
  }
  return std::nullopt;
}

// A circle's or a point export's length column: other units skipped, the refusal of a bare name
// says to write "<name> (mm)".
std::optional<LengthColumn> find_coordinate_column(const CsvTable& t,
                                                   std::initializer_list<const char*> bases) {
  return find_length_column(t, bases, "", OtherUnit::Skip);
}

// The words of an approach in + and in -, as instruments write them.
const std::vector<std::string> kUpWords = {"up", "+", "fwd", "forward", "pos", "positive"};
const std::vector<std::string> kDownWords = {"down", "-",       "bwd", "back",    "backward",
                                             "rev",  "reverse", "neg", "negative"};

// One column of a wide-form run: its readings' cycle and direction, and the unit and kind of its
// values.
struct RunColumn {
  LengthColumn value;
  int cycle = 0;
  Approach direction = Approach::Up;
};

// The columns of an ISO 230-2 run: the target, each in the unit its header names; then either
// (long form) the measured position or the deviation from the target, the cycle and the
// direction, or (wide form) one column per run and direction.
struct Iso230_2Columns {
  LengthColumn target, measured;
  std::size_t cycle = 0, direction = 0;
  std::vector<RunColumn> runs;  // the wide form; empty for the long form
};

// The wide form's run columns ("Run 1 Fwd (um)", "run_2_down_error_mm", "Cycle 3 - (in)", "R1
// up"): run or cycle and its number, a direction word, optionally what the values are (error,
// deviation; measured, actual, position) and a unit; what the column does not say comes from the
// comments before the header ("# Units: um", "# Values: deviation"), else the column is refused.
std::vector<RunColumn> run_columns(const CsvTable& t) {
  static const std::regex kRun(
      R"(^(run|cycle|r)[_-]?([0-9]+)[_-]?(up|down|fwd|forward|bwd|backward|back|reverse|rev|positive|pos|negative|neg|\+|-)[_-]?(error|deviation|dev|measured|actual|position)?[_-]?(\((mm|um|in)\)|\[(mm|um|in)\]|_(mm|um|in))?$)");
  std::vector<RunColumn> out;
  for (std::size_t c = 0; c < t.header.size(); ++c) {
    const std::string n = normalised(t.header[c]);
    std::smatch m;
    if (!std::regex_match(n, m, kRun)) continue;
    RunColumn r;
    r.cycle = std::stoi(m[2].str());
    const std::string dir = m[3].str();
    r.direction = std::find(kUpWords.begin(), kUpWords.end(), dir) != kUpWords.end()
                      ? Approach::Up
                      : Approach::Down;
    const std::string unit = m[6].matched ? m[6].str() : m[7].matched ? m[7].str() : m[8].str();
    std::optional<double> scale = unit.empty() ? declared_unit(t) : mm_per(unit);
    if (!scale) {
      t.fail(t.header_line, c,
             "column '" + t.header[c] + "' names no unit: write it as '" + t.header[c] +
                 " (um)' (or mm, in), or declare the file's unit in a comment before the header "
                 "('# Units: um')");
    }
    r.value = length_column(c, *scale);
    std::string kind = m[4].str();
    if (kind.empty()) {
      if (const auto d = declared(t, {"values", "value", "data", "readings"})) kind = d->second;
    }
    if (kind == "error" || kind == "deviation" || kind == "dev" || kind == "errors" ||
        kind == "deviations") {
      r.value.deviation = true;
    } else if (kind != "measured" && kind != "actual" && kind != "position" &&
               kind != "positions") {
      t.fail(t.header_line, c,
             "column '" + t.header[c] +
                 "' does not say whether it holds deviations from the target or measured "
                 "positions: name it like 'Run 1 Fwd Error (um)' or 'Run 1 Fwd Measured (mm)', "
                 "or say it in a comment before the header ('# Values: deviation' or '# Values: "
                 "measured')");
    }
    out.push_back(r);
  }
  return out;
}

// `words`: also the cycle and direction columns of the long form (the envelope check reads
// lengths only).
Iso230_2Columns iso230_2_columns(const CsvTable& t, bool words = true) {
  Iso230_2Columns c;
  const auto target = find_length_column(t, {"target", "nominal"},
                                         "target_mm, target_um or target_in ('Target (mm)')");
  if (!target) {
    fail_header(t, "no target column: expected target_mm (or target_in, target_um, 'Target (mm)')");
  }
  c.target = *target;
  const auto word_column = [&](std::initializer_list<const char*> names) {
    for (const char* name : names) {
      for (std::size_t k = 0; k < t.header.size(); ++k) {
        if (normalised(t.header[k]) == name) return std::optional<std::size_t>(k);
      }
    }
    return std::optional<std::size_t>();
  };
  const auto cycle = word_column({"cycle", "run"});
  const auto direction = word_column({"direction", "dir"});
  if (!cycle && !direction) {
    c.runs = run_columns(t);
    if (!c.runs.empty()) return c;  // the wide form
  }
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
                "deviation from the target as error_um (or error_mm, error_in, deviation_um); or, "
                "in the wide form, one column per run and direction ('Run 1 Fwd (um)')");
  }
  if (!words) return c;
  if (!cycle) fail_header(t, "no cycle column: expected 'cycle' (or 'run')");
  if (!direction) fail_header(t, "no direction column: expected 'direction' (or 'dir')");
  c.cycle = *cycle;
  c.direction = *direction;
  return c;
}

double length_mm(const CsvTable& t, const CsvRow& row, const LengthColumn& c) {
  return length_mm(t, row, c.index, c.to_mm, c.unit);
}

// One reading as the file has it: its row, the target's column and the value's (the measured
// position or the deviation), its cycle and direction.
struct ReadingCells {
  const CsvRow* row = nullptr;
  const LengthColumn* target = nullptr;
  const LengthColumn* value = nullptr;
  int cycle = 0;
  Approach direction = Approach::Up;
};

// Every reading of the run, row by row (in the wide form, the row's run columns left to right;
// an empty cell there is a reading the run did not take). `read_words`: read the long form's
// cycle and direction too (else they are left 0 and Up).
std::vector<ReadingCells> reading_cells(const CsvTable& t, const Iso230_2Columns& c,
                                        bool read_words = true) {
  std::vector<std::string> words = kUpWords;
  words.insert(words.end(), kDownWords.begin(), kDownWords.end());
  std::vector<ReadingCells> out;
  for (const CsvRow& row : t.rows) {
    if (c.runs.empty()) {
      ReadingCells r;
      r.row = &row;
      r.target = &c.target;
      r.value = &c.measured;
      if (read_words) {
        r.cycle = t.integer(row, c.cycle);
        const std::string word = t.word(row, c.direction, words);
        r.direction = std::find(kUpWords.begin(), kUpWords.end(), word) != kUpWords.end()
                          ? Approach::Up
                          : Approach::Down;
      }
      out.push_back(r);
      continue;
    }
    for (const RunColumn& run : c.runs) {
      if (t.cell(row, run.value.index).empty()) continue;
      ReadingCells r;
      r.row = &row;
      r.target = &c.target;
      r.value = &run.value;
      r.cycle = run.cycle;
      r.direction = run.direction;
      out.push_back(r);
    }
  }
  return out;
}

double target_mm(const CsvTable& t, const ReadingCells& r) {
  return length_mm(t, *r.row, *r.target);
}

double measured_mm(const CsvTable& t, const ReadingCells& r) {
  const double v = length_mm(t, *r.row, *r.value);
  return r.value->deviation ? target_mm(t, r) + v : v;
}

}  // namespace

// ---- ISO 230-2 ----------------------------------------------------------------------------------

Iso230_2File read_iso230_2_csv(const CsvTable& t) {
  const Iso230_2Columns c = iso230_2_columns(t);
  Iso230_2File out;
  out.file = t.file;
  for (const ReadingCells& cells : reading_cells(t, c)) {
    PositioningReading r;
    r.target_mm = target_mm(t, cells);
    r.cycle = cells.cycle;
    r.direction = cells.direction;
    r.measured_mm = measured_mm(t, cells);
    out.readings.push_back(r);
    out.lines.push_back(cells.row->line);
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

namespace {

// A circle file's columns (the layouts of the header comment of instrument_files.hpp).
struct CircleColumns {
  Plane plane = Plane::XY;
  bool polar = false;
  std::size_t angle = 0;
  double rad_per_angle_unit = kPi / 180;
  std::optional<LengthColumn> radius;     // polar: the radius
  std::optional<LengthColumn> deviation;  // polar: the radial deviation from the nominal radius
  LengthColumn u, v;                      // coordinates
  std::optional<std::size_t> direction;
  std::optional<double> nominal_radius_mm;  // declared in a comment or given
};

const std::vector<std::string> kCcwWords = {
    "ccw", "counterclockwise", "counter-clockwise", "anticlockwise", "anti-clockwise", "g3"};
const std::vector<std::string> kCwWords = {"cw", "clockwise", "g2"};

// The nominal radius a comment before the header declares ("# Radius: 150 mm", "# Ballbar
// length = 4 in"; a bare number takes the declared unit), in mm, with its line.
std::optional<double> declared_radius_mm(const CsvTable& t) {
  const auto d = declared(
      t, {"radius", "nominalradius", "ballbarlength", "ballbarradius", "testradius", "r0"});
  if (!d) return std::nullopt;
  const std::string& text = d->second;  // normalised: "150mm"
  std::size_t used = 0;
  double value = NAN;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  const std::string unit = text.substr(used);
  std::optional<double> scale = unit.empty() ? declared_unit(t) : mm_per(unit);
  if (used == 0 || !scale || !(value > 0) || !std::isfinite(value)) {
    throw CsvError(t.file, d->first, 0,
                   "the comment declares radius '" + text +
                       "': expected a number > 0 and its unit, e.g. '# Radius: 150 mm' (mm, um, "
                       "in)");
  }
  return value * *scale;
}

// `reading`: the columns to read the points (else to check their sizes: neither the plane nor
// the nominal radius is needed).
CircleColumns circle_columns(const CsvTable& t, std::optional<Plane> plane,
                             std::optional<double> nominal_radius_mm, bool reading = true) {
  CircleColumns c;
  // A plane declared in a comment ("# Plane: XZ") stands for the argument; both must agree.
  if (const auto d = declared(t, {"plane"})) {
    const auto named = parse_plane(d->second);
    if (!named) {
      throw CsvError(t.file, d->first, 0,
                     "the comment declares plane '" + d->second + "': expected XY, YZ or XZ");
    }
    if (plane && *plane != *named) {
      throw CsvError(t.file, d->first, 0,
                     "the comment declares plane " + std::string(to_string(*named)) +
                         ", but plane " + std::string(to_string(*plane)) + " was asked for");
    }
    plane = named;
  }
  // Polar columns: the angle (degrees unless the header says rad), a radius or a deviation.
  std::optional<std::size_t> angle;
  for (const char* base : {"angle", "theta"}) {
    for (std::size_t k = 0; k < t.header.size() && !angle; ++k) {
      const auto unit = unit_after(normalised(t.header[k]), base);
      if (!unit) continue;
      if (unit->empty() || *unit == "deg" || *unit == "degree" || *unit == "degrees") {
        angle = k;
      } else if (*unit == "rad" || *unit == "radian" || *unit == "radians") {
        angle = k;
        c.rad_per_angle_unit = 1;
      }
    }
  }
  c.radius = find_coordinate_column(t, {"radius"});
  c.deviation = find_coordinate_column(t, {"radialdeviation", "radial_deviation", "radialerror",
                                           "radial_error", "deviation", "error"});
  // Coordinates: x, y, z (each pair names a plane) or u, v (the plane's axes).
  std::array<std::optional<LengthColumn>, 3> xyz{find_coordinate_column(t, {"x"}),
                                                 find_coordinate_column(t, {"y"}),
                                                 find_coordinate_column(t, {"z"})};
  const auto u = find_coordinate_column(t, {"u"});
  const auto v = find_coordinate_column(t, {"v"});
  const bool polar = angle || c.radius || c.deviation;
  const int axes = static_cast<int>(xyz[0].has_value()) + static_cast<int>(xyz[1].has_value()) +
                   static_cast<int>(xyz[2].has_value());
  const bool coordinates = (u && v) || axes >= 2;
  const std::string plane_needed = "pass the plane (XY, YZ or XZ)";
  if (polar && coordinates) {
    fail_header(t,
                "both polar (angle, radius or deviation) and coordinate columns; a circle file "
                "has one layout");
  }
  if (polar) {
    c.polar = true;
    if (!angle)
      fail_header(t, "a radius but no angle column: expected 'angle_deg' or 'Angle (deg)'");
    c.angle = *angle;
    if (!c.radius && !c.deviation) {
      fail_header(t,
                  "an angle but no radius column: expected 'radius_mm' ('Radius (mm)'), or the "
                  "radial deviation from the nominal radius ('Deviation (um)')");
    }
    if (c.radius && c.deviation) {
      fail_header(t, "both a radius and a radial deviation column; a circle file has one");
    }
    c.nominal_radius_mm = nominal_radius_mm ? nominal_radius_mm : declared_radius_mm(t);
    if (c.deviation && !c.nominal_radius_mm && reading) {
      t.fail(t.header_line, c.deviation->index,
             "column '" + t.header[c.deviation->index] +
                 "' holds radial deviations from the nominal radius, which the file does not "
                 "declare: declare it in a comment before the header ('# Radius: 150 mm') or "
                 "pass it (--nominal-radius-mm)");
    }
    if (!plane && reading) {
      const std::size_t r = c.radius ? c.radius->index : c.deviation->index;
      fail_header(
          t, t.header[c.angle] + ", " + t.header[r] + " do not name the plane: " + plane_needed);
    }
    c.plane = plane.value_or(Plane::XY);
  } else if (u && v) {
    if (axes > 0) {
      fail_header(t, "both u, v and x, y or z coordinates; a circle file has one coordinate pair");
    }
    if (!plane && reading) {
      fail_header(t, t.header[u->index] + ", " + t.header[v->index] +
                         " do not name the plane: " + plane_needed);
    }
    c.u = *u;
    c.v = *v;
    c.plane = plane.value_or(Plane::XY);
  } else if (axes >= 2) {
    struct Pair {
      Plane plane;
      int a, b;
    };
    const Pair pairs[] = {{Plane::XY, 0, 1}, {Plane::YZ, 1, 2}, {Plane::XZ, 0, 2}};
    const Pair* chosen = nullptr;
    if (plane) {
      for (const auto& p : pairs) {
        if (p.plane == *plane && xyz[p.a] && xyz[p.b]) chosen = &p;
      }
      if (!chosen) {
        const Pair* named = nullptr;
        for (const auto& p : pairs) {
          if (!named && xyz[p.a] && xyz[p.b]) named = &p;
        }
        const std::size_t column = xyz[named->a]->index;
        throw CsvError(t.file, t.header_line, static_cast<int>(column) + 1,
                       "the header's " + t.header[column] + ", " + t.header[xyz[named->b]->index] +
                           " name plane " + std::string(to_string(named->plane)) + ", but plane " +
                           std::string(to_string(*plane)) + " was asked for");
      }
    } else if (axes == 3 && reading) {
      fail_header(t, t.header[xyz[0]->index] + ", " + t.header[xyz[1]->index] + " and " +
                         t.header[xyz[2]->index] + " name more than one plane: " + plane_needed);
    } else {
      for (const auto& p : pairs) {
        if (!chosen && xyz[p.a] && xyz[p.b]) chosen = &p;
      }
    }
    c.u = *xyz[chosen->a];
    c.v = *xyz[chosen->b];
    c.plane = chosen->plane;
  } else {
    fail_header(t,
                "no circle columns: expected an angle and a radius ('angle_deg,radius_mm'), an "
                "angle and the radial deviation ('Angle (deg),Deviation (um)' with the radius "
                "declared), or a coordinate pair x_mm,y_mm | y_mm,z_mm | x_mm,z_mm | u_mm,v_mm "
                "(any length unit: mm, um, in)");
  }
  if (!c.polar) c.nominal_radius_mm = nominal_radius_mm ? nominal_radius_mm : declared_radius_mm(t);
  for (const char* name : {"direction", "dir"}) {
    for (std::size_t k = 0; k < t.header.size() && !c.direction; ++k) {
      if (normalised(t.header[k]) == name) c.direction = k;
    }
  }
  return c;
}

}  // namespace

CircleFile read_circle_csv(const CsvTable& t, std::optional<Plane> plane,
                           std::optional<double> nominal_radius_mm) {
  const CircleColumns c = circle_columns(t, plane, nominal_radius_mm);
  CircleFile out;
  out.file = t.file;
  out.polar = c.polar;
  out.deviations = c.deviation.has_value();
  out.input.plane = c.plane;
  out.input.nominal_radius_mm = c.nominal_radius_mm;
  std::vector<std::string> words = kCcwWords;
  words.insert(words.end(), kCwWords.begin(), kCwWords.end());
  // First line of each (direction, angle modulo 360) of a polar file.
  std::map<std::pair<PathDirection, double>, int> angles_seen;
  for (const CsvRow& row : t.rows) {
    PathDirection d = PathDirection::Ccw;
    if (c.direction) {
      const std::string w = t.word(row, *c.direction, words);
      d = std::find(kCwWords.begin(), kCwWords.end(), w) != kCwWords.end() ? PathDirection::Cw
                                                                           : PathDirection::Ccw;
    }
    CircularPoint p;
    if (c.polar) {
      const double per_turn = 2 * kPi / c.rad_per_angle_unit;  // 360 or 2π
      const double a =
          t.number_within(row, c.angle, kMaxAngleDeg * kPi / 180 / c.rad_per_angle_unit,
                          c.rad_per_angle_unit == 1 ? "rad" : "deg",
                          "a circle test turns a few times, not hundreds");
      const LengthColumn& rc = c.radius ? *c.radius : *c.deviation;
      const double value = length_mm(t, row, rc);
      const double r = c.radius ? value : *c.nominal_radius_mm + value;
      if (!(r > 0)) {
        t.fail(row.line, rc.index,
               "column '" + t.header[rc.index] + "' = '" + t.cell(row, rc.index) +
                   (c.radius ? "': a radius must be > 0"
                             : "': the radius it gives, " + detail::quote_number(r) +
                                   " mm, must be > 0"));
      }
      double wrapped = std::fmod(a, per_turn);
      if (wrapped < 0) wrapped += per_turn;
      if (wrapped == 0) wrapped = 0;  // -0 and 360 are 0
      const auto [it, fresh] = angles_seen.emplace(std::make_pair(d, wrapped), row.line);
      if (!fresh) {
        t.fail(row.line, c.angle,
               "column '" + t.header[c.angle] + "' = " + detail::quote_number(a) + ", direction " +
                   std::string(to_string(d)) + ": the same angle as line " +
                   std::to_string(it->second));
      }
      p = circular_point_from_polar(a * c.rad_per_angle_unit, r, d);
    } else {
      p = CircularPoint{Eigen::Vector2d(length_mm(t, row, c.u), length_mm(t, row, c.v)), d};
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
                           std::optional<Plane> plane, std::optional<double> nominal_radius_mm) {
  return read_circle_csv(read_csv(text, file), plane, nominal_radius_mm);
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

// ---- Tracker point exports ---------------------------------------------------------------------

namespace {

// A point name as the program's labels are compared: lower case, letters and numbers only, a
// number without its leading zeros ("X_RUN_03" and "x_run:3" are both "xrun3").
std::string canonical_point_name(std::string_view name) {
  std::string out, digits;
  const auto flush = [&] {
    if (digits.empty()) return;
    const std::size_t first = digits.find_first_not_of('0');
    out += first == std::string::npos ? "0" : digits.substr(first);
    digits.clear();
  };
  for (char ch : name) {
    const auto c = static_cast<unsigned char>(ch);
    if (std::isdigit(c)) {
      digits += static_cast<char>(c);
      continue;
    }
    flush();
    if (std::isalpha(c)) out += static_cast<char>(std::tolower(c));
  }
  flush();
  return out;
}

// Whether the header has a column `base` with or without a unit ("x", "X (mm)", "x_in").
bool has_axis_column(const CsvTable& t, const std::string& base) {
  return std::any_of(t.header.begin(), t.header.end(), [&](const std::string& h) {
    const auto unit = unit_after(normalised(h), base);
    return unit && (unit->empty() || mm_per(*unit));
  });
}

// The first column whose normalised name is one of `names`, tried in order.
std::optional<std::size_t> column_named(const CsvTable& t,
                                        std::initializer_list<const char*> names) {
  for (const char* name : names) {
    for (std::size_t k = 0; k < t.header.size(); ++k) {
      if (normalised(t.header[k]) == name) return k;
    }
  }
  return std::nullopt;
}

// The column of the point's name.
std::optional<std::size_t> point_name_column(const CsvTable& t) {
  return column_named(t, {"point", "pointname", "point_name", "name", "id", "label", "target"});
}

}  // namespace

bool is_tracker_point_export(const CsvTable& t) {
  return !t.find_column("x_cmd") && point_name_column(t).has_value() && has_axis_column(t, "x") &&
         has_axis_column(t, "y") && has_axis_column(t, "z");
}

std::vector<TrackerExportPoint> read_tracker_points_csv(const CsvTable& t) {
  const auto c_name = point_name_column(t);
  if (!c_name) {
    fail_header(t, "no point name column: expected 'Point' (or 'Name', 'Point Name', 'ID')");
  }
  std::array<LengthColumn, 3> axes;
  const char* const names[] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    const auto c = find_coordinate_column(t, {names[k]});
    if (!c) {
      fail_header(t, std::string("no ") + names[k] + " column: expected '" + names[k] +
                         "_mm' (or 'X (in)', '" + names[k] +
                         "' with the unit declared in a comment, '# Units: in')");
    }
    axes[static_cast<std::size_t>(k)] = *c;
  }
  std::vector<TrackerExportPoint> out;
  std::map<std::string, int> seen;  // canonical name -> line
  for (const CsvRow& row : t.rows) {
    TrackerExportPoint p;
    p.line = row.line;
    p.name = t.cell(row, *c_name);
    if (p.name.empty()) t.fail(row.line, *c_name, "the point name is empty: name the point");
    for (int k = 0; k < 3; ++k) {
      p.measured_mm(k) = length_mm(t, row, axes[static_cast<std::size_t>(k)]);
    }
    const auto [it, fresh] = seen.emplace(canonical_point_name(p.name), row.line);
    if (!fresh) {
      t.fail(row.line, *c_name,
             "point '" + p.name + "' repeats the point of line " + std::to_string(it->second));
    }
    out.push_back(p);
  }
  if (out.empty()) throw CsvError(t.file, t.header_line, 0, "no points after the header");
  return out;
}

namespace {

// A measured move of a monthly program as a point export may name it.
struct ProgramPoint {
  const TrackerMove* move = nullptr;
  std::string label;               // as the program labels it ("grid:17:t0")
  std::vector<std::string> names;  // the canonical names it answers to
};

// The canonical names of a label: itself, and without a main-reflector suffix (":t0": "Grid 17").
std::vector<std::string> names_of(const std::string& label) {
  std::vector<std::string> names{canonical_point_name(label)};
  if (label.size() > 3 && label.compare(label.size() - 3, 3, ":t0") == 0) {
    names.push_back(canonical_point_name(label.substr(0, label.size() - 3)));
  }
  return names;
}

// How the first point may be written, to show that case, separators and leading zeros do not
// matter: "x_run:0" -> "X_RUN_00".
std::string example_name(const std::string& label) {
  std::string out;
  for (std::size_t i = 0; i < label.size(); ++i) {
    const auto c = static_cast<unsigned char>(label[i]);
    const bool number_starts =
        std::isdigit(c) && (i == 0 || !std::isdigit(static_cast<unsigned char>(label[i - 1])));
    const bool single_digit =
        number_starts &&
        (i + 1 == label.size() || !std::isdigit(static_cast<unsigned char>(label[i + 1])));
    if (single_digit) out += '0';
    out += std::isalpha(c) ? static_cast<char>(std::toupper(c)) : std::isdigit(c) ? label[i] : '_';
  }
  return out;
}

// Each of `planned` paired by name with an exported point (the index into `points`), in the
// program's order; exported points none of `planned` names are `ignored` unless their canonical
// name is in `elsewhere` (another run's point of the same session). A planned point missing
// from the export is refused (naming up to five, at the last line). `what`: "x_run points",
// "rotary_c points".
struct Pairing {
  std::vector<std::size_t> found;  // per planned point
  std::vector<TrackerExportPoint> ignored;
};
Pairing pair_by_name(const CsvTable& t, const std::vector<TrackerExportPoint>& points,
                     const std::vector<ProgramPoint>& planned,
                     const std::set<std::string>& elsewhere, const std::string& what) {
  std::map<std::string, std::size_t> by_name;  // canonical name -> index into planned
  for (std::size_t i = 0; i < planned.size(); ++i) {
    for (const std::string& n : planned[i].names) by_name.emplace(n, i);
  }
  std::vector<std::optional<std::size_t>> found(planned.size());
  Pairing out;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const std::string name = canonical_point_name(points[k].name);
    const auto it = by_name.find(name);
    if (it != by_name.end()) {
      found[it->second] = k;
    } else if (!elsewhere.count(name)) {
      out.ignored.push_back(points[k]);
    }
  }
  std::string missing;
  int n_missing = 0;
  for (std::size_t i = 0; i < planned.size(); ++i) {
    if (found[i]) {
      out.found.push_back(*found[i]);
    } else if (++n_missing <= 5) {
      missing += (missing.empty() ? "" : ", ") + planned[i].label;
    }
  }
  if (n_missing > 0) {
    throw CsvError(t.file, last_line(t), 0,
                   std::to_string(n_missing) + " of the program's " +
                       std::to_string(planned.size()) + " " + what + " are not in the export (" +
                       missing + (n_missing > 5 ? ", ..." : "") +
                       "): name each point as the program labels it ('" + planned.front().label +
                       "'; case, separators and leading zeros do not matter: '" +
                       example_name(planned.front().label) + "')");
  }
  return out;
}

}  // namespace

GridFromExport grid_points_from_export(const CsvTable& t, const std::string& prefix,
                                       const GlobalCheckConfig& config) {
  const std::vector<TrackerExportPoint> points = read_tracker_points_csv(t);
  const std::vector<TrackerMove> program = global_check_program(CheckKind::GlobalGrid, config);
  // The program's moves of this part with the main reflector: label prefix:<i>.
  std::vector<ProgramPoint> planned;
  std::set<std::string> elsewhere;  // the other runs' points, by any name
  for (const TrackerMove& m : program) {
    if (m.label.empty()) continue;
    std::vector<std::string> names = names_of(m.label);
    if (m.label.rfind(prefix + ":", 0) != 0) {
      elsewhere.insert(names.begin(), names.end());
      continue;
    }
    if (m.target != 0) continue;  // another reflector: reported as ignored when exported
    std::string label = m.label;  // a grid point is named without its reflector
    if (names.size() > 1) label.resize(label.size() - 3);
    planned.push_back({&m, label, std::move(names)});
  }
  const Pairing pairing = pair_by_name(t, points, planned, elsewhere, prefix + " points");
  GridFromExport out;
  out.ignored = pairing.ignored;
  for (std::size_t i = 0; i < planned.size(); ++i) {
    const TrackerExportPoint& p = points[pairing.found[i]];
    GridFilePoint g;
    g.point = p.name;
    g.line = p.line;
    g.commanded_mm = stylus_ball_centre(planned[i].move->commanded, config.targets.front());
    g.measured_mm = p.measured_mm;
    out.points.push_back(g);
  }
  return out;
}

TrackerPointsFromExport tracker_points_from_export(const CsvTable& t, CheckKind kind,
                                                   const GlobalCheckConfig& config) {
  if (!is_tracker_check(kind)) {
    throw std::invalid_argument(std::string(to_string(kind)) +
                                " is not measured by the laser tracker: it has no point export");
  }
  const std::vector<TrackerExportPoint> points = read_tracker_points_csv(t);
  const std::vector<TrackerMove> program = global_check_program(kind, config);
  std::vector<ProgramPoint> planned;
  for (const TrackerMove& m : program) {
    if (!m.label.empty()) planned.push_back({&m, m.label, names_of(m.label)});
  }
  const Pairing pairing =
      pair_by_name(t, points, planned, {}, std::string(to_string(kind)) + " points");
  TrackerPointsFromExport out;
  out.ignored = pairing.ignored;
  for (std::size_t i = 0; i < planned.size(); ++i) {
    const TrackerExportPoint& p = points[pairing.found[i]];
    const TrackerMove& m = *planned[i].move;
    TrackerPoint point;
    point.label = m.label;
    point.commanded = m.commanded;
    point.measured_mm = p.measured_mm;
    out.points.push_back(point);
    GridFilePoint g;
    g.point = p.name;
    g.line = p.line;
    g.commanded_mm =
        stylus_ball_centre(m.commanded, config.targets.at(static_cast<std::size_t>(m.target)));
    g.measured_mm = p.measured_mm;
    out.located.push_back(g);
  }
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

// ---- CMM results --------------------------------------------------------------------------------

namespace {

// Digits printed after the decimal mark ("0.0120" -> 4, "12" -> 0, "1.5e-3" -> 1).
int decimals_of(const std::string& cell) {
  const std::size_t mark = cell.find_first_of(".,");
  if (mark == std::string::npos) return 0;
  int n = 0;
  for (std::size_t k = mark + 1;
       k < cell.size() && std::isdigit(static_cast<unsigned char>(cell[k])); ++k) {
    ++n;
  }
  return n;
}

// Half a unit in the last printed digit, in mm: the rounding of a printed value.
double rounding_mm(const std::string& cell, double to_mm) {
  return 0.5 * std::pow(10.0, -decimals_of(cell)) * to_mm;
}

// Axes whose values are angles in a CMM report (PC-DMIS: A angle, PA polar angle; RN, RS, ...
// are lengths): not lengths, left out.
bool is_angle_axis(const std::string& axis) {
  return axis == "A" || axis == "PA" || axis == "ANG" || axis == "ANGLE";
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// "PNT1.X", "PNT1_X", "PNT1 X", "PNT1-X" -> ("PNT1", "X"), and a diameter "CIR1.D"; other names
// have no axis.
std::pair<std::string, std::string> split_axis(const std::string& name) {
  if (name.size() >= 3) {
    const char a = static_cast<char>(std::toupper(static_cast<unsigned char>(name.back())));
    const char sep = name[name.size() - 2];
    if ((a == 'X' || a == 'Y' || a == 'Z' || a == 'D') &&
        (sep == '.' || sep == '_' || sep == ' ' || sep == '-')) {
      return {name.substr(0, name.size() - 2), std::string(1, a)};
    }
  }
  return {name, ""};
}

// Adds `c`, refusing a feature and axis seen before; `fail` reports at c.line.
template <typename Fail>
void add_characteristic(CmmReport& report, std::map<std::string, int>& seen, CmmCharacteristic c,
                        const Fail& fail) {
  const auto [it, fresh] = seen.emplace(upper(c.feature) + "\n" + c.axis, c.line);
  if (!fresh) {
    fail("feature '" + c.feature + "'" + (c.axis.empty() ? "" : " axis " + c.axis) +
         " repeats the characteristic of line " + std::to_string(it->second));
  }
  report.characteristics.push_back(std::move(c));
}

// Why a printed deviation is not the characteristic's actual - nominal within `rounding_mm` (the
// rounding of the three printed cells); nothing when it is.
std::optional<std::string> deviation_disagreement(const CmmCharacteristic& c, double printed_mm,
                                                  double rounding_mm) {
  if (std::abs(printed_mm - c.deviation_mm()) <= rounding_mm + 1e-9) return std::nullopt;
  return "the report's deviation " + detail::format_number(printed_mm) +
         " mm is not actual - nominal (" + detail::format_number(c.deviation_mm()) +
         " mm): a report that writes nominal - actual would be read with its signs backwards; "
         "export the deviation as actual - nominal, or leave the column out";
}

CmmReport read_cmm_table(const CsvTable& t) {
  const auto feature = column_named(
      t, {"feature", "name", "id", "characteristic", "point", "element", "featurename", "label"});
  if (!feature) {
    fail_header(t,
                "no feature column: expected 'Feature' (or 'Name', 'ID', 'Characteristic', "
                "'Point')");
  }
  const auto axis = column_named(t, {"axis", "ax", "coordinate"});
  const auto nominal = find_length_column(t, {"nominal", "nom"}, "'Nominal (mm)'");
  const auto actual = find_length_column(t, {"actual", "measured", "meas", "act"}, "'Actual (mm)'");
  if (!nominal || !actual) {
    fail_header(t, std::string("no ") + (nominal ? "actual" : "nominal") +
                       " column: a CMM report needs 'Nominal' and 'Actual' (or 'Measured')");
  }
  const auto deviation = find_length_column(t, {"deviation", "dev"}, "'Deviation (mm)'");
  const auto upper_tol = find_length_column(t, {"uppertol", "uppertolerance", "utol", "upperlimit"},
                                            "'Upper Tol (mm)'");
  const auto lower_tol = find_length_column(t, {"lowertol", "lowertolerance", "ltol", "lowerlimit"},
                                            "'Lower Tol (mm)'");
  const auto plus_tol = find_length_column(t, {"+tol", "plustol", "tol+"}, "'+Tol (mm)'");
  const auto minus_tol = find_length_column(t, {"-tol", "minustol", "tol-"}, "'-Tol (mm)'");
  const auto both_tol = find_length_column(t, {"tol", "tolerance", "+/-tol"}, "'Tol (mm)'");
  if (upper_tol.has_value() != lower_tol.has_value() ||
      plus_tol.has_value() != minus_tol.has_value()) {
    fail_header(t,
                "one side of the tolerance only: give 'Upper Tol' with 'Lower Tol' (signed), or "
                "'+Tol' with '-Tol' (magnitudes), or one symmetric 'Tol'");
  }
  CmmReport report;
  report.format = "table";
  std::map<std::string, int> seen;
  for (const CsvRow& row : t.rows) {
    CmmCharacteristic c;
    c.line = row.line;
    const std::string name = t.cell(row, *feature);
    if (name.empty()) t.fail(row.line, *feature, "the feature name is empty: name the feature");
    if (axis) {
      c.feature = name;
      c.axis = upper(t.cell(row, *axis));
    } else {
      std::tie(c.feature, c.axis) = split_axis(name);
    }
    if (is_angle_axis(c.axis)) {
      t.fail(row.line, axis ? *axis : *feature,
             "feature '" + c.feature + "' axis " + c.axis +
                 " is an angle: ncqual reads the lengths of a CMM report; leave the angle out");
    }
    c.nominal_mm = length_mm(t, row, *nominal);
    c.actual_mm = length_mm(t, row, *actual);
    const auto blank = [&](const std::optional<LengthColumn>& col) {
      return !col || t.cell(row, col->index).empty();
    };
    if (!blank(deviation)) {
      const auto rounding = [&](const LengthColumn& col) {
        return rounding_mm(t.cell(row, col.index), col.to_mm);
      };
      if (const auto why = deviation_disagreement(
              c, length_mm(t, row, *deviation),
              rounding(*deviation) + rounding(*nominal) + rounding(*actual))) {
        t.fail(row.line, deviation->index, *why);
      }
    }
    if (!blank(upper_tol) && !blank(lower_tol)) {
      c.upper_mm = length_mm(t, row, *upper_tol);
      c.lower_mm = length_mm(t, row, *lower_tol);
    } else if (!blank(plus_tol) && !blank(minus_tol)) {
      c.upper_mm = length_mm(t, row, *plus_tol);
      c.lower_mm = -std::abs(length_mm(t, row, *minus_tol));
    } else if (!blank(both_tol)) {
      c.upper_mm = std::abs(length_mm(t, row, *both_tol));
      c.lower_mm = -*c.upper_mm;
    }
    if (c.upper_mm && *c.lower_mm > *c.upper_mm) {
      t.fail(row.line,
             (upper_tol  ? upper_tol
              : plus_tol ? plus_tol
                         : both_tol)
                 ->index,
             "the tolerance band " + detail::format_number(*c.lower_mm) + " .. " +
                 detail::format_number(*c.upper_mm) + " mm is empty: lower above upper");
    }
    add_characteristic(report, seen, std::move(c),
                       [&](const std::string& why) { t.fail(row.line, *feature, why); });
  }
  return report;
}

std::vector<std::string> words_of(const std::string& line) {
  std::vector<std::string> out;
  std::string word;
  for (char ch : line) {
    if (ch == ' ' || ch == '\t' || ch == '\r') {
      if (!word.empty()) out.push_back(std::move(word));
      word.clear();
    } else {
      word += ch;
    }
  }
  if (!word.empty()) out.push_back(std::move(word));
  return out;
}

// PC-DMIS's text report: a "DIM" line and an "AX" header.
bool is_pc_dmis_text(const std::vector<std::string>& lines) {
  bool dim = false, ax = false;
  for (const std::string& line : lines) {
    const std::vector<std::string> w = words_of(line);
    if (!w.empty() && upper(w[0]) == "DIM") dim = true;
    if (!w.empty() && upper(w[0]) == "AX") ax = true;
  }
  return dim && ax;
}

CmmReport read_pc_dmis_text(const std::vector<std::string>& lines, const std::string& file) {
  CmmReport report;
  report.format = "PC-DMIS text";
  std::map<std::string, int> seen;
  std::string feature;
  std::optional<double> to_mm;
  std::map<std::string, std::size_t> columns;  // header word -> index of the row's words
  int line_no = 0;
  for (const std::string& line : lines) {
    ++line_no;
    const std::vector<std::string> w = words_of(line);
    if (w.empty()) continue;
    const std::string first = upper(w[0]);
    const auto fail = [&](const std::string& why) { throw CsvError(file, line_no, 0, why); };
    if (first == "DIM") {
      const std::string up = upper(line);
      const std::size_t eq = line.find('=');
      feature = eq == std::string::npos ? "" : std::string(words_of(line.substr(3, eq - 3)).at(0));
      const std::size_t of = up.find(" OF ");
      if (of != std::string::npos) {
        const std::vector<std::string> after = words_of(line.substr(of + 4));
        if (after.size() >= 2 && upper(after[1]).rfind("UNITS", 0) != 0) feature = after[1];
      }
      if (feature.empty()) fail("a DIM line without its id: expected 'DIM LOC1= ...'");
      while (!feature.empty() && (feature.back() == ',' || feature.back() == '$')) {
        feature.pop_back();
      }
      const std::size_t u = up.find("UNITS=");
      if (u == std::string::npos) {
        fail("DIM " + feature + " names no unit: expected UNITS=MM or UNITS=IN on its line");
      }
      std::string unit;
      for (std::size_t k = u + 6; k < up.size() && std::isalpha(static_cast<unsigned char>(up[k]));
           ++k) {
        unit += static_cast<char>(std::tolower(static_cast<unsigned char>(up[k])));
      }
      to_mm = mm_per(unit);
      if (!to_mm) fail("UNITS=" + upper(unit) + ": expected MM or IN");
      columns.clear();
      continue;
    }
    if (first == "AX") {
      if (!to_mm) fail("an AX header before any DIM line");
      columns.clear();
      for (std::size_t k = 1; k < w.size(); ++k) columns[upper(w[k])] = k;
      for (const char* need : {"NOMINAL", "MEAS"}) {
        if (!columns.count(need)) {
          fail(std::string("the AX header has no ") + need + " column: expected 'AX NOMINAL " +
               "+TOL -TOL MEAS DEV OUTTOL'");
        }
      }
      continue;
    }
    // A characteristic: an axis word, then numbers, under an AX header.
    if (columns.empty() || w.size() < 2 || !parse_finite_number(w[1]) ||
        !std::isalpha(static_cast<unsigned char>(w[0][0]))) {
      continue;  // titles, GRAPH=..., page headers, "END OF DIMENSION"
    }
    const auto value = [&](const char* name) -> std::optional<std::pair<double, std::string>> {
      const auto it = columns.find(name);
      if (it == columns.end()) return std::nullopt;
      if (it->second >= w.size()) {
        fail("DIM " + feature + " axis " + first + ": no " + name + " value (" +
             std::to_string(w.size() - 1) + " values on the line)");
      }
      const auto v = parse_finite_number(w[it->second]);
      if (!v)
        fail("DIM " + feature + " axis " + first + ": " + name + " = '" + w[it->second] +
             "': expected a number");
      return std::make_pair(*v * *to_mm, w[it->second]);
    };
    CmmCharacteristic c;
    c.feature = feature;
    c.axis = first;
    c.line = line_no;
    if (is_angle_axis(c.axis)) {
      fail("DIM " + feature + " axis " + c.axis +
           " is an angle: ncqual reads the lengths of a CMM report; leave the angle out");
    }
    const auto nominal = value("NOMINAL");
    const auto actual = value("MEAS");
    c.nominal_mm = nominal->first;
    c.actual_mm = actual->first;
    if (const auto dev = value("DEV")) {
      const double rounding = rounding_mm(dev->second, *to_mm) +
                              rounding_mm(nominal->second, *to_mm) +
                              rounding_mm(actual->second, *to_mm);
      if (const auto why = deviation_disagreement(c, dev->first, rounding)) {
        fail("DIM " + feature + " axis " + c.axis + ": " + *why);
      }
    }
    const auto plus = value("+TOL");
    const auto minus = value("-TOL");
    if (plus && minus) {
      c.upper_mm = plus->first;
      c.lower_mm = -std::abs(minus->first);
    }
    add_characteristic(report, seen, std::move(c), fail);
  }
  return report;
}

}  // namespace

CmmReport read_cmm_results(std::string_view text, const std::string& file) {
  const std::string_view bom = "\xEF\xBB\xBF";
  const std::vector<std::string> lines =
      split_at(text.substr(0, 3) == bom ? text.substr(3) : text, '\n');  // words_of drops '\r'
  CmmReport report = is_pc_dmis_text(lines) ? read_pc_dmis_text(lines, file)
                                            : read_cmm_table(read_csv(text, file));
  if (report.characteristics.empty()) {
    throw CsvError(file, 0, 0,
                   "no characteristics: a CMM report needs at least one row of a feature with its "
                   "nominal and actual");
  }
  return report;
}

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
  for (const ReadingCells& r : reading_cells(t, c, false)) {
    const CsvRow& row = *r.row;
    check_position(t, row, c.target.index, axis, e, c.target.to_mm);
    const double deviation = measured_mm(t, r) - target_mm(t, r);
    if (std::abs(deviation) > most) {
      t.fail(row.line, r.value->index,
             "column '" + t.header[r.value->index] + "' = '" + t.cell(row, r.value->index) +
                 "': " + mm(deviation) + " from " + t.header[c.target.index] + " " +
                 t.cell(row, c.target.index) + ", more than " + mm(most) +
                 ", a tenth of the span of " + envelope_text(e));
    }
  }
}

void check_circle_envelope(const CsvTable& t, const Envelope& e, std::optional<Plane> plane,
                           std::optional<double> nominal_radius_mm) {
  const CircleColumns c = circle_columns(t, plane, nominal_radius_mm, false);
  const double most = kDeviationShare * e.span_mm();
  for (const CsvRow& row : t.rows) {
    if (!c.polar) {
      check_position(t, row, c.u.index, -1, e, c.u.to_mm);
      check_position(t, row, c.v.index, -1, e, c.v.to_mm);
    } else if (c.radius) {
      check_position(t, row, c.radius->index, -1, e, c.radius->to_mm);
    } else {
      const double deviation = length_mm(t, row, *c.deviation);
      if (std::abs(deviation) > most) {
        t.fail(row.line, c.deviation->index,
               "column '" + t.header[c.deviation->index] + "' = '" +
                   t.cell(row, c.deviation->index) + "': a radial deviation of " + mm(deviation) +
                   ", more than " + mm(most) + ", a tenth of the span of " + envelope_text(e) +
                   "; a file in another unit?");
      }
    }
  }
}

void check_grid_envelope(const CsvTable& t, const std::vector<GridFilePoint>& points,
                         const Envelope& e) {
  if (points.empty()) return;
  // The cells of the measured x: a grid file's x_meas, an export's x.
  const bool exported = is_tracker_point_export(t);
  std::size_t x_column = 0;
  if (exported) {  // an export's commanded positions are the program's
    x_column = find_coordinate_column(t, {"x"})->index;
  } else {  // a grid file's are its own
    const GridColumns c = grid_columns(t);
    x_column = c.measured[0];
    for (const CsvRow& row : t.rows) {
      for (int k = 0; k < 3; ++k) check_position(t, row, c.commanded[k], k, e);
    }
  }
  const double most = kDeviationShare * e.span_mm();
  const GridFilePoint& first = points.front();
  for (const GridFilePoint& p : points) {
    const double commanded = (p.commanded_mm - first.commanded_mm).norm();
    const double measured = (p.measured_mm - first.measured_mm).norm();
    if (std::abs(measured - commanded) > most) {
      t.fail(p.line, x_column,
             "measured " + mm(measured) + " from the first point (" + first.point + ", line " +
                 std::to_string(first.line) + ") where " +
                 (exported ? "the program commands " : "commanded ") + mm(commanded) +
                 ": more than " + mm(most) + " apart, a tenth of the span of " + envelope_text(e) +
                 "; a file in another unit?");
    }
  }
}

}  // namespace ncqual::solver

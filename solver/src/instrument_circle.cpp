// SPDX-License-Identifier: Apache-2.0
// Circular tests (ballbar, grid encoder, tracker) in any of their layouts: the file's columns
// (instrument_columns.hpp), and read_circle_csv.
#include "ncqual/solver/instrument_files.hpp"

#include "instrument_columns.hpp"
#include "result_building.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ncqual::solver {

using namespace detail;  // instrument_columns.hpp

namespace {

using units::kPi;

constexpr double kMaxAngleDeg = 1e5;  // about 280 turns of a circle test

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

}  // namespace

CircleColumns detail::circle_columns(const CsvTable& t, std::optional<Plane> plane,
                                     std::optional<double> nominal_radius_mm, bool reading) {
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

}  // namespace ncqual::solver

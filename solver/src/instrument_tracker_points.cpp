// SPDX-License-Identifier: Apache-2.0
// A laser tracker's point exports (a name and x, y, z): read, and paired by name with the points
// of the machine's monthly programs (grid_points_from_export, tracker_points_from_export).
#include "ncqual/solver/instrument_files.hpp"

#include "instrument_columns.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace ncqual::solver {

using namespace detail;  // instrument_columns.hpp

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

}  // namespace ncqual::solver

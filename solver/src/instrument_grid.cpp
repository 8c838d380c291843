// SPDX-License-Identifier: Apache-2.0
// Grid and master-frame runs of a laser tracker (point, x_cmd .. z_meas): the file's columns
// (instrument_columns.hpp), and read_grid_csv.
#include "ncqual/solver/instrument_files.hpp"

#include "instrument_columns.hpp"
#include "result_building.hpp"

#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace ncqual::solver {

using namespace detail;  // instrument_columns.hpp

GridColumns detail::grid_columns(const CsvTable& t) {
  GridColumns c;
  const char* const cmd_names[] = {"x_cmd", "y_cmd", "z_cmd"};
  const char* const meas_names[] = {"x_meas", "y_meas", "z_meas"};
  for (int k = 0; k < 3; ++k) c.commanded[k] = t.require_column(cmd_names[k]);
  for (int k = 0; k < 3; ++k) c.measured[k] = t.require_column(meas_names[k]);
  return c;
}

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

}  // namespace ncqual::solver

// SPDX-License-Identifier: Apache-2.0
// Tests of `ncqual analyze|import points`: the rows of a nominal list `ncqual program` wrote, read
// here with the test's own parser (not ncqual's), and a tracker's point export made from them as a
// tracker's software writes one: its own names, micrometres, tab-separated, rows in reverse.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace ncqual::testing {

// One row of a nominal list: Point,X (mm),Y (mm),Z (mm),Reflector,Machine X (mm),Machine Y (mm),
// Machine Z (mm),A (deg),C (deg),W (mm).
struct NominalRow {
  std::string point;
  Eigen::Vector3d nominal_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d machine_mm = Eigen::Vector3d::Zero();
};

inline std::vector<NominalRow> read_nominal_rows(const std::string& path) {
  std::ifstream in(path);
  std::vector<NominalRow> rows;
  std::string line;
  bool header = false;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (!header) {
      header = true;  // Point,X (mm),...
      continue;
    }
    std::vector<std::string> cells;
    std::stringstream cut(line);
    for (std::string cell; std::getline(cut, cell, ',');) cells.push_back(cell);
    if (cells.size() < 8) continue;
    NominalRow r;
    r.point = cells[0];
    for (int k = 0; k < 3; ++k) {
      r.nominal_mm(k) = std::stod(cells[1 + static_cast<std::size_t>(k)]);
      r.machine_mm(k) = std::stod(cells[5 + static_cast<std::size_t>(k)]);
    }
    rows.push_back(r);
  }
  return rows;
}

// "c:3" -> "C-03", "grid:17:t1" -> "GRID-17-T1": the names a tracker operator types.
inline std::string operator_name_of(const std::string& label) {
  std::string out, digits;
  const auto flush = [&] {
    if (digits.size() == 1) out += '0';
    out += digits;
    digits.clear();
  };
  for (char c : label) {
    if (c >= '0' && c <= '9') {
      digits += c;
      continue;
    }
    flush();
    out += c == ':' ? '-' : static_cast<char>(c >= 'a' && c <= 'z' ? c - 'a' + 'A' : c);
  }
  flush();
  return out;
}

// The export of `rows`, each measured where `measured(row)` says, in micrometres to 1 nm, rows in
// reverse order, names as an operator types them; rows whose `measured` is empty are left out.
inline std::string point_export(
    const std::vector<NominalRow>& rows,
    const std::function<std::vector<Eigen::Vector3d>(const NominalRow&)>& measured) {
  std::string text = "Point Name\tX (um)\tY (um)\tZ (um)\n";
  for (auto r = rows.rbegin(); r != rows.rend(); ++r) {
    for (const Eigen::Vector3d& p : measured(*r)) {
      char line[200];
      std::snprintf(line, sizeof line, "%s\t%.3f\t%.3f\t%.3f\n", operator_name_of(r->point).c_str(),
                    p.x() * 1000, p.y() * 1000, p.z() * 1000);
      text += line;
    }
  }
  return text;
}

// `row`'s nominal turned by `angle_rad` about the vertical line through its machine X, Y (the C
// axis of a head machine, through the wrist pivot): what a C axis that lags by -angle reads.
inline Eigen::Vector3d turned_about_c(const NominalRow& row, double angle_rad) {
  const Eigen::Vector3d axis_point(row.machine_mm.x(), row.machine_mm.y(), 0);
  return axis_point +
         Eigen::AngleAxisd(angle_rad, Eigen::Vector3d::UnitZ()) * (row.nominal_mm - axis_point);
}

}  // namespace ncqual::testing

// SPDX-License-Identifier: Apache-2.0
// A CMM's report of a part, as a table or as PC-DMIS's text report: read_cmm_results.
#include "ncqual/solver/instrument_files.hpp"

#include "instrument_columns.hpp"
#include "ncqual/common/text.hpp"
#include "result_building.hpp"

#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

namespace ncqual::solver {

using namespace detail;  // instrument_columns.hpp

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

}  // namespace ncqual::solver

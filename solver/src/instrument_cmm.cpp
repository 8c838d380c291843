// SPDX-License-Identifier: Apache-2.0
// A CMM's report of a part, as a table or as PC-DMIS's text report: read_cmm_results.
#include "ncqual/solver/instrument_files.hpp"

#include "instrument_columns.hpp"
#include "ncqual/common/text.hpp"
#include "result_building.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <set>
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

// A word of a line and the columns it spans, [begin, end) (tabs expanded to every 8th column).
struct Word {
  std::string text;
  std::size_t begin = 0, end = 0;
};

std::vector<Word> spans_of(const std::string& line) {
  std::vector<Word> out;
  std::size_t column = 0;
  Word word;
  const auto close = [&] {
    if (word.text.empty()) return;
    word.end = column;
    out.push_back(std::move(word));
    word = Word{};
  };
  for (char ch : line) {
    if (ch == ' ' || ch == '\t' || ch == '\r') {
      close();
      column = ch == '\t' ? (column / 8 + 1) * 8 : column + (ch == ' ' ? 1 : 0);
    } else {
      if (word.text.empty()) word.begin = column;
      word.text += ch;
      ++column;
    }
  }
  close();
  return out;
}

std::vector<std::string> words_of(const std::string& line) {
  std::vector<std::string> out;
  for (Word& w : spans_of(line)) out.push_back(std::move(w.text));
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

// The material condition PC-DMIS prints in a TRUE POSITION block's TP row where other rows have
// their nominal.
bool is_material_condition(const std::string& word) {
  const std::string w = upper(word);
  return w == "MMC" || w == "LMC" || w == "RFS" || w == "MMB" || w == "LMB" || w == "RMB";
}

// PC-DMIS's graph of a deviation after a row's values: "----#----", "--------->".
bool is_graph(const std::string& word) {
  return word.find_first_not_of("-#<>+*|") == std::string::npos;
}

// The values of a row: its words after the axis, without the graph that may end it.
std::vector<const Word*> values_of(const std::vector<Word>& row) {
  std::size_t end = row.size();
  while (end > 1 && is_graph(row[end - 1].text)) --end;
  std::vector<const Word*> values;
  for (std::size_t i = 1; i < end; ++i) values.push_back(&row[i]);
  return values;
}

// The cells of a row under an AX header, by header name. A row with a value in every column is read
// in the header's order; a row with blank cells (the X and Y rows of a TRUE POSITION block have no
// tolerance) is read by where its values stand: each belongs to the header column it overlaps
// most (PC-DMIS aligns them), else to the one whose end is nearest. Nothing when a value cannot be
// placed: two values under one column; `why` says which.
std::optional<std::map<std::string, std::string>> cells_of(const std::vector<Word>& row,
                                                           const std::vector<Word>& header,
                                                           std::string* why) {
  const std::vector<const Word*> values = values_of(row);
  std::map<std::string, std::string> cells;
  if (values.size() + 1 >= header.size()) {
    for (std::size_t k = 1; k < header.size(); ++k) cells[header[k].text] = values[k - 1]->text;
    return cells;
  }
  for (const Word* value : values) {
    const Word& w = *value;
    std::size_t best = 0;
    std::size_t best_overlap = 0, best_distance = std::string::npos;
    for (std::size_t k = 1; k < header.size(); ++k) {
      const Word& h = header[k];
      const std::size_t lo = std::max(w.begin, h.begin), hi = std::min(w.end, h.end);
      const std::size_t overlap = hi > lo ? hi - lo : 0;
      const std::size_t distance = w.end > h.end ? w.end - h.end : h.end - w.end;
      if (overlap > best_overlap ||
          (best_overlap == 0 && overlap == 0 && distance < best_distance)) {
        best = k;
        best_overlap = overlap;
        best_distance = distance;
      }
    }
    const std::string& column = header[best].text;
    if (cells.count(column)) {
      *why = "'" + cells[column] + "' and '" + w.text + "' both stand under " + column +
             ": align the values with the AX header's columns";
      return std::nullopt;
    }
    cells[column] = w.text;
  }
  return cells;
}

CmmReport read_pc_dmis_text(const std::vector<std::string>& lines, const std::string& file) {
  CmmReport report;
  report.format = "PC-DMIS text";
  std::map<std::string, int> seen;
  std::string feature;
  std::optional<double> to_mm;
  std::vector<Word> header;    // the AX header's words (upper case) where they stand
  bool true_position = false;  // the DIM is a TRUE POSITION block
  int line_no = 0;
  for (const std::string& line : lines) {
    ++line_no;
    const std::vector<Word> row = spans_of(line);
    if (row.empty()) continue;
    const std::string first = upper(row[0].text);
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
      header.clear();
      true_position = up.find("TRUE POSITION") != std::string::npos;
      continue;
    }
    if (first == "AX") {
      if (!to_mm) fail("an AX header before any DIM line");
      header = row;
      std::set<std::string> names;
      for (Word& h : header) {
        h.text = upper(h.text);
        if (!names.insert(h.text).second) fail("the AX header names " + h.text + " twice");
      }
      if (!names.count("NOMINAL") || (!names.count("MEAS") && !names.count("DEV"))) {
        fail(std::string("the AX header has no ") + (names.count("NOMINAL") ? "MEAS" : "NOMINAL") +
             " column: expected 'AX NOMINAL +TOL -TOL MEAS DEV OUTTOL'");
      }
      continue;
    }
    // A characteristic: an axis word, then numbers (a TRUE POSITION block's TP row: its material
    // condition first), under an AX header.
    if (header.empty() || row.size() < 2 ||
        !std::isalpha(static_cast<unsigned char>(row[0].text[0])) ||
        !(parse_finite_number(row[1].text) ||
          (first == "TP" && is_material_condition(row[1].text)))) {
      continue;  // titles, GRAPH=..., page headers, "END OF DIMENSION"
    }
    const std::string where = "DIM " + feature + " axis " + first;
    std::string why;
    const auto cells = cells_of(row, header, &why);
    if (!cells) fail(where + ": " + why);
    const auto value = [&](const char* name) -> std::optional<std::pair<double, std::string>> {
      const auto it = cells->find(name);
      if (it == cells->end()) return std::nullopt;
      const auto v = parse_finite_number(it->second);
      if (!v) fail(where + ": " + name + " = '" + it->second + "': expected a number");
      return std::make_pair(*v * *to_mm, it->second);
    };
    CmmCharacteristic c;
    c.feature = feature;
    c.axis = first;
    c.line = line_no;
    if (is_angle_axis(c.axis)) {
      fail(where + " is an angle: ncqual reads the lengths of a CMM report; leave the angle out");
    }
    const std::size_t values = values_of(row).size();
    const auto missing = [&](const std::string& what) {
      fail(where + ": no " + what + " value (" + std::to_string(values) + " value" +
           (values == 1 ? "" : "s") + " on the line under " + std::to_string(header.size() - 1) +
           " columns)");
    };
    const bool tp = first == "TP";
    std::optional<std::pair<double, std::string>> nominal;
    if (tp && cells->count("NOMINAL") && is_material_condition(cells->at("NOMINAL"))) {
      nominal = std::make_pair(0.0, std::string());  // from the true position: exact
    } else {
      nominal = value("NOMINAL");
    }
    if (!nominal) missing(tp ? "NOMINAL (or material condition)" : "NOMINAL");
    const auto actual = value("MEAS");
    const auto dev = value("DEV");
    if (!actual && !dev) missing("MEAS or DEV");
    c.nominal_mm = nominal->first;
    // A position row without MEAS: the nominal and the deviation give it.
    c.actual_mm = actual ? actual->first : nominal->first + dev->first;
    double rounding = nominal->second.empty() ? 0.0 : rounding_mm(nominal->second, *to_mm);
    if (actual) rounding += rounding_mm(actual->second, *to_mm);
    if (dev) rounding += rounding_mm(dev->second, *to_mm);
    // A TRUE POSITION block may print its axes' deviations as magnitudes (the report of issue 37
    // does: Y 45.000, MEAS 44.991, DEV 0.009): with the MEAS beside it, a magnitude that fits is
    // read from MEAS; without MEAS, the DEV is taken as actual - nominal.
    const bool magnitude =
        true_position && actual && dev &&
        std::abs(std::abs(dev->first) - std::abs(c.deviation_mm())) <= rounding + 1e-9;
    if (actual && dev && !magnitude) {
      if (const auto disagree = deviation_disagreement(c, dev->first, rounding)) {
        fail(where + ": " + *disagree);
      }
    }
    const auto plus = value("+TOL");
    const auto minus = value("-TOL");
    if (tp) {
      // The position's deviation (diametral) against its tolerance zone, enlarged by the bonus
      // the report gives the row.
      if (!plus) missing("+TOL");
      const auto bonus = value("BONUS");
      c.lower_mm = 0;
      c.upper_mm = plus->first + (bonus ? bonus->first : 0);
      rounding +=
          rounding_mm(plus->second, *to_mm) + (bonus ? rounding_mm(bonus->second, *to_mm) : 0);
    } else if (plus && minus) {
      c.upper_mm = plus->first;
      c.lower_mm = -std::abs(minus->first);
      rounding += rounding_mm(plus->second, *to_mm) + rounding_mm(minus->second, *to_mm);
    } else if (plus || minus) {
      missing(plus ? "-TOL" : "+TOL");
    }
    // The report's own OUTTOL must be what the band read here gives: a column misread, or a bonus
    // this reader does not see, would otherwise judge the part against another band than the
    // report's.
    if (const auto outtol = value("OUTTOL"); outtol && c.upper_mm) {
      const double d = c.deviation_mm();
      const double over = std::max({0.0, d - *c.upper_mm, *c.lower_mm - d});
      if (std::abs(std::abs(outtol->first) - over) >
          rounding + rounding_mm(outtol->second, *to_mm) + 1e-9) {
        fail(where + ": the report's OUTTOL " + detail::format_number(outtol->first) +
             " mm is not what the band " + detail::format_number(*c.lower_mm) + " .. " +
             detail::format_number(*c.upper_mm) + " mm gives the deviation " +
             detail::format_number(d) + " mm (" + detail::format_number(over) +
             " mm): a column is not where this reader looks" +
             (tp ? ", or the report counts a bonus its TP row does not print" : ""));
      }
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

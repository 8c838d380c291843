// SPDX-License-Identifier: Apache-2.0
// What the readers of instrument exports share: a column found by its name and unit, a length
// cell read in mm, a refusal at the file's lines (declared in instrument_columns.hpp).
#include "instrument_columns.hpp"

#include <cctype>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace ncqual::solver::detail {
namespace {

// No machine tool or tracker measures a kilometre: a reading beyond is a broken export (1e300
// would pass as finite and turn every figure into inf and nan).
constexpr double kMaxLengthMm = 1e6;

std::string column_list(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

}  // namespace

double length_mm(const CsvTable& t, const CsvRow& row, std::size_t column, double to_mm,
                 const std::string& unit) {
  return t.number_within(row, column, kMaxLengthMm / to_mm, unit,
                         "no machine or instrument reaches 1 km") *
         to_mm;
}

double length_mm(const CsvTable& t, const CsvRow& row, const LengthColumn& c) {
  return length_mm(t, row, c.index, c.to_mm, c.unit);
}

int last_line(const CsvTable& t) { return t.rows.empty() ? t.header_line : t.rows.back().line; }

[[noreturn]] void fail_at_lines(const CsvTable& t, const std::vector<int>& lines,
                                const std::optional<std::size_t>& index,
                                const std::optional<std::size_t>& first_index,
                                const std::string& message) {
  const int line = index ? lines[*index] : last_line(t);
  std::string text = message;
  if (first_index) text += " (first at line " + std::to_string(lines[*first_index]) + ")";
  throw CsvError(t.file, line, 0, text);
}

[[noreturn]] void fail_header(const CsvTable& t, const std::string& why) {
  throw CsvError(t.file, t.header_line, 0, why + "; the header has: " + column_list(t.header));
}

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

std::optional<LengthColumn> find_length_column(const CsvTable& t,
                                               std::initializer_list<const char*> bases,
                                               const std::string& example, OtherUnit other) {
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

std::optional<LengthColumn> find_coordinate_column(const CsvTable& t,
                                                   std::initializer_list<const char*> bases) {
  return find_length_column(t, bases, "", OtherUnit::Skip);
}

std::optional<std::size_t> column_named(const CsvTable& t,
                                        std::initializer_list<const char*> names) {
  for (const char* name : names) {
    for (std::size_t k = 0; k < t.header.size(); ++k) {
      if (normalised(t.header[k]) == name) return k;
    }
  }
  return std::nullopt;
}

}  // namespace ncqual::solver::detail

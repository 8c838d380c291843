// SPDX-License-Identifier: Apache-2.0
#include "ncqual/common/csv.hpp"

#include "ncqual/common/text.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <map>
#include <sstream>

namespace ncqual {
namespace {

bool is_blank_char(char c) { return c == ' ' || c == '\t'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_blank_char(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_blank_char(s.back())) s.remove_suffix(1);
  return s;
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// The separator of a file, from its header line: ';' or a tab when the header has one outside
// quotes (exports of spreadsheets and of instruments set to a decimal comma), else ','.
char separator_of(std::string_view header) {
  bool quoted = false, semicolon = false, tab = false;
  for (char c : header) {
    if (c == '"') quoted = !quoted;
    if (quoted) continue;
    semicolon |= c == ';';
    tab |= c == '\t';
  }
  return semicolon ? ';' : tab ? '\t' : ',';
}

// Splits one line (no line ending) into trimmed cells at `sep`, unquoting quoted cells.
std::vector<std::string> split_cells(std::string_view line, char sep, const std::string& file,
                                     int line_no) {
  std::vector<std::string> cells;
  std::size_t i = 0;
  const std::size_t n = line.size();
  const auto blank = [sep](char c) { return c == ' ' || (c == '\t' && sep != '\t'); };
  while (true) {
    const int column = static_cast<int>(cells.size()) + 1;
    while (i < n && blank(line[i])) ++i;
    std::string cell;
    if (i < n && line[i] == '"') {
      ++i;
      bool closed = false;
      while (i < n) {
        if (line[i] == '"') {
          if (i + 1 < n && line[i + 1] == '"') {
            cell += '"';
            i += 2;
            continue;
          }
          ++i;
          closed = true;
          break;
        }
        cell += line[i++];
      }
      if (!closed) {
        throw CsvError(file, line_no, column,
                       "unterminated quote (a quoted cell must end on its line)");
      }
      while (i < n && blank(line[i])) ++i;
      if (i < n && line[i] != sep) {
        throw CsvError(file, line_no, column,
                       "text after the closing quote: '" + std::string(line.substr(i)) + "'");
      }
    } else {
      const std::size_t start = i;
      while (i < n && line[i] != sep) ++i;
      cell = std::string(trim(line.substr(start, i - start)));
    }
    cells.push_back(std::move(cell));
    if (i >= n) break;
    ++i;  // the separator; a line ending in one has an empty last cell
  }
  return cells;
}

std::string in_quotes(std::string_view s) { return "'" + std::string(s) + "'"; }

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& name : names) out += (out.empty() ? "" : ", ") + name;
  return out;
}

}  // namespace

std::string csv_location(const std::string& file, int line, int column) {
  std::string out = file;
  if (line > 0) {
    out += ":" + std::to_string(line);
    if (column > 0) out += ":" + std::to_string(column);
  }
  return out + ": ";
}

CsvError::CsvError(const std::string& file, int line, int column, const std::string& message)
    : Error(csv_location(file, line, column) + message),
      file_(file),
      line_(line),
      column_(line > 0 ? column : 0),
      message_(message) {}

std::optional<std::size_t> CsvTable::find_column(std::string_view name) const {
  for (std::size_t i = 0; i < header.size(); ++i) {
    if (header[i] == name) return i;
  }
  return std::nullopt;
}

std::size_t CsvTable::require_column(std::string_view name) const {
  if (auto i = find_column(name)) return *i;
  throw CsvError(file, header_line, 0,
                 "missing column '" + std::string(name) + "'; the header has: " + join(header));
}

const std::string& CsvTable::cell(const CsvRow& row, std::size_t column) const {
  if (column >= row.cells.size()) {
    fail(row.line, kNoColumn,
         "no column " + std::to_string(column + 1) + " (the row has " +
             std::to_string(row.cells.size()) + " cells)");
  }
  return row.cells[column];
}

void CsvTable::fail(int line, std::size_t column, const std::string& message) const {
  throw CsvError(file, line, column == kNoColumn ? 0 : static_cast<int>(column) + 1, message);
}

double CsvTable::number(const CsvRow& row, std::size_t column) const {
  const std::string& text = cell(row, column);
  const std::string what = "column '" + header[column] + "' = " + in_quotes(text) + ": ";
  if (text.empty()) fail(row.line, column, what + "expected a number, the cell is empty");
  std::string comma_text;
  std::string_view digits = text;
  if (decimal_comma && text.find(',') != std::string::npos) {
    if (text.find('.') != std::string::npos || text.find(',') != text.rfind(',')) {
      fail(row.line, column,
           what + "expected a number with one decimal comma (no thousands separators)");
    }
    comma_text = text;
    comma_text[comma_text.find(',')] = '.';
    digits = comma_text;
  }
  if (digits.size() > 1 && digits.front() == '+' && digits[1] != '-' && digits[1] != '+') {
    digits.remove_prefix(1);  // from_chars takes no '+'
  }
  double value = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value,
                                         std::chars_format::general);
  if (ec == std::errc::result_out_of_range) {
    fail(row.line, column, what + "out of the range of a double");
  }
  if (ec != std::errc() || end != digits.data() + digits.size()) {
    fail(row.line, column, what + "expected a number");
  }
  if (!std::isfinite(value)) fail(row.line, column, what + "expected a finite number");
  return value;
}

double CsvTable::number_within(const CsvRow& row, std::size_t column, double limit,
                               const std::string& unit, const std::string& why) const {
  const double value = number(row, column);
  if (std::abs(value) > limit) {
    std::ostringstream bound;
    bound << limit;
    fail(row.line, column,
         "column '" + header[column] + "' = " + in_quotes(cell(row, column)) + ": beyond ±" +
             bound.str() + " " + unit + ": " + why);
  }
  return value;
}

int CsvTable::integer(const CsvRow& row, std::size_t column) const {
  const std::string& text = cell(row, column);
  const std::string what = "column '" + header[column] + "' = " + in_quotes(text) + ": ";
  if (text.empty()) fail(row.line, column, what + "expected an integer, the cell is empty");
  std::string_view digits = text;
  if (digits.size() > 1 && digits.front() == '+' && digits[1] != '-' && digits[1] != '+') {
    digits.remove_prefix(1);
  }
  int value = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ec == std::errc::result_out_of_range) {
    fail(row.line, column, what + "out of the range of an int");
  }
  if (ec != std::errc() || end != digits.data() + digits.size()) {
    fail(row.line, column, what + "expected an integer");
  }
  return value;
}

std::string CsvTable::word(const CsvRow& row, std::size_t column,
                           const std::vector<std::string>& words) const {
  const std::string& text = cell(row, column);
  const std::string key = lower(text);
  for (const auto& w : words) {
    if (lower(w) == key) return w;
  }
  fail(row.line, column,
       "column '" + header[column] + "' = " + in_quotes(text) + ": expected one of " + join(words));
}

CsvTable read_csv(std::string_view text, const std::string& file) {
  CsvTable table;
  table.file = file;
  if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);

  int line_no = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const std::string_view content = trim(line);
    if (!content.empty() && content.front() == '#' && table.header_line == 0) {
      table.comments.emplace_back(line_no, std::string(trim(content.substr(1))));
    }
    if (content.empty() || content.front() == '#') continue;

    if (table.header_line == 0) {
      table.separator = separator_of(line);
      table.decimal_comma = table.separator != ',';
    }
    std::vector<std::string> cells = split_cells(line, table.separator, file, line_no);
    if (table.header_line == 0) {
      std::map<std::string, std::size_t> seen;
      for (std::size_t c = 0; c < cells.size(); ++c) {
        if (cells[c].empty()) {
          throw CsvError(file, line_no, static_cast<int>(c) + 1, "empty column name in the header");
        }
        const auto [it, fresh] = seen.emplace(cells[c], c);
        if (!fresh) {
          throw CsvError(
              file, line_no, static_cast<int>(c) + 1,
              "column name '" + cells[c] + "' repeats column " + std::to_string(it->second + 1));
        }
      }
      table.header_line = line_no;
      table.header = std::move(cells);
      continue;
    }
    if (cells.size() != table.header.size()) {
      // The column of the first extra cell, or of the first missing one.
      const int column = static_cast<int>(std::min(cells.size(), table.header.size())) + 1;
      throw CsvError(file, line_no, column,
                     std::to_string(cells.size()) + " cells, but the header (line " +
                         std::to_string(table.header_line) + ") has " +
                         std::to_string(table.header.size()) + " columns: " + join(table.header));
    }
    table.rows.push_back(CsvRow{line_no, std::move(cells)});
  }
  if (table.header_line == 0) {
    throw CsvError(file, 0, 0,
                   line_no == 0 ? "the file is empty; expected a header line"
                                : "no header line (only blank and # comment lines)");
  }
  return table;
}

CsvTable read_csv_file(const std::string& path) {
  std::string why;
  const std::optional<std::string> text = read_text_file(path, &why);
  if (!text) throw CsvError(path, 0, 0, "cannot read: " + why);
  return read_csv(*text, path);
}

}  // namespace ncqual

// SPDX-License-Identifier: Apache-2.0
// A small CSV reader for instrument exports (laser interferometer runs, ballbar circles, tracker
// grids): one header line naming the columns, then one row per reading.
//
// Format:
//   - Lines end in LF or CRLF. Blank lines and lines whose first non-blank character is '#' are
//     skipped everywhere (comments may carry the instrument's own header; those before the header
//     line are kept in CsvTable::comments for readers that take a declared unit). A UTF-8 byte
//     order mark at the start of the file is ignored.
//   - The first other line is the header. Column names are trimmed and case-sensitive; an empty
//     or repeated name is refused.
//   - Cells are separated by ',', or by ';' or a tab when the header line has one (outside
//     quotes): the separators of spreadsheet and instrument exports set to a decimal comma. With
//     ';' or a tab, numbers may use the decimal comma ("0,0012"); a number with both '.' and ','
//     or with two commas is refused (no thousands separators). Cells are trimmed of spaces (and of
//     tabs, unless the tab separates). A cell may be quoted ("a, b" with "" for a quote inside);
//     a quoted cell cannot span lines.
//   - Every row has as many cells as the header; a row with more or fewer is refused.
//
// Every problem is a CsvError whose what() is "<file>:<line>:<column>: <message>", line 1-based
// in the file (comments and blank lines counted), column the 1-based CSV column (1 = first cell).
// When no column applies (a whole row or a whole file is wrong) the column is 0 and left out:
// "<file>:<line>: <message>"; when no line applies either (an unreadable or empty file) the
// line is 0 and left out too: "<file>: <message>".
#pragma once

#include "ncqual/common/error.hpp"

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace ncqual {

class CsvError : public Error {
 public:
  // line and column 1-based, 0 when they do not apply (see above).
  CsvError(const std::string& file, int line, int column, const std::string& message);

  const std::string& file() const { return file_; }
  int line() const { return line_; }
  int column() const { return column_; }
  // The message without the "<file>:<line>:<column>: " prefix.
  const std::string& message() const { return message_; }

 private:
  std::string file_;
  int line_ = 0;
  int column_ = 0;
  std::string message_;
};

// "<file>:<line>:<column>: " (with the parts that are 0 left out), the prefix of CsvError::what().
std::string csv_location(const std::string& file, int line, int column);

struct CsvRow {
  int line = 0;                    // 1-based line number in the file
  std::vector<std::string> cells;  // trimmed (quoted cells unquoted), one per header column
};

// A parsed file. Column indices in this API are 0-based (index into header and cells); error
// messages report them 1-based.
struct CsvTable {
  // A column argument meaning "no column applies" (a whole-row problem).
  static constexpr std::size_t kNoColumn = static_cast<std::size_t>(-1);

  std::string file;                 // as given to read_csv, used in every error
  int header_line = 0;              // 1-based
  std::vector<std::string> header;  // trimmed column names
  std::vector<CsvRow> rows;         // data rows in file order
  // The '#' comment lines before the header (an instrument's own header: units, settings), as
  // (line, text after the '#', trimmed).
  std::vector<std::pair<int, std::string>> comments;
  char separator = ',';        // ',', ';' or '\t', from the header line
  bool decimal_comma = false;  // numbers may write ',' for '.' (separator ';' or tab)

  // Index of the column named `name` (exact, case-sensitive), or nullopt.
  std::optional<std::size_t> find_column(std::string_view name) const;
  // Index of the column named `name`; throws CsvError at the header line ("missing column
  // 'name'; the header has: a, b, c").
  std::size_t require_column(std::string_view name) const;

  // The cell of `row` in column `column` (0-based); the row has one cell per header column.
  const std::string& cell(const CsvRow& row, std::size_t column) const;
  // The cell as a finite number (decimal or exponent notation, optional sign). Refuses an empty
  // cell, text ("abc", "1.5mm"), "nan", "inf" and values out of double range, quoting the cell:
  // "<file>:<line>:<col>: column 'x_mm' = 'abc': expected a number".
  double number(const CsvRow& row, std::size_t column) const;
  // number(), also refusing a value beyond ±`limit` (a reading no instrument could have made):
  // "<file>:<line>:<col>: column 'x_mm' = '1e300': beyond ±1e+06 <unit>: <why>".
  double number_within(const CsvRow& row, std::size_t column, double limit, const std::string& unit,
                       const std::string& why) const;
  // The cell as an integer (optional sign, digits only: "3", "-2"; "3.0" is refused).
  int integer(const CsvRow& row, std::size_t column) const;
  // The cell as one of `words`, compared case-insensitively; returns the word as written in
  // `words` (e.g. "up" for a cell "Up"). Refuses anything else, listing the words.
  std::string word(const CsvRow& row, std::size_t column,
                   const std::vector<std::string>& words) const;

  // Throws CsvError("<file>:<line>:<column + 1>: message"); pass column = kNoColumn for a
  // whole-row problem (the column is then left out of the prefix).
  [[noreturn]] void fail(int line, std::size_t column, const std::string& message) const;
};

// Parses `text` (the whole file). `file` names it in errors. Refuses: no header (empty file or
// only blank/comment lines), an empty or repeated column name, a row with a different number
// of cells than the header, an unterminated quote or text after a closing quote. A file with a
// header and no data rows is returned with no rows (the caller decides whether that is enough).
CsvTable read_csv(std::string_view text, const std::string& file);

// Reads the file at `path` and parses it with read_csv (errors name `path`). An unreadable file
// (missing, a directory, no permission) is a CsvError "<path>: cannot read: <reason>".
CsvTable read_csv_file(const std::string& path);

}  // namespace ncqual

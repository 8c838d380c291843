// SPDX-License-Identifier: Apache-2.0
// ISO 230-2 runs of a laser interferometer, long and wide form: their columns and readings
// (instrument_columns.hpp), and read_iso230_2_csv.
#include "ncqual/solver/instrument_files.hpp"

#include "instrument_columns.hpp"

#include <algorithm>
#include <optional>
#include <regex>
#include <string>
#include <vector>

namespace ncqual::solver {

using namespace detail;  // instrument_columns.hpp

namespace {

// The words of an approach in + and in -, as instruments write them.
const std::vector<std::string> kUpWords = {"up", "+", "fwd", "forward", "pos", "positive"};
const std::vector<std::string> kDownWords = {"down", "-",       "bwd", "back",    "backward",
                                             "rev",  "reverse", "neg", "negative"};

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

}  // namespace

Iso230_2Columns detail::iso230_2_columns(const CsvTable& t, bool words) {
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

std::vector<ReadingCells> detail::reading_cells(const CsvTable& t, const Iso230_2Columns& c,
                                                bool read_words) {
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

double detail::target_mm(const CsvTable& t, const ReadingCells& r) {
  return length_mm(t, *r.row, *r.target);
}

double detail::measured_mm(const CsvTable& t, const ReadingCells& r) {
  const double v = length_mm(t, *r.row, *r.value);
  return r.value->deviation ? target_mm(t, r) + v : v;
}

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

}  // namespace ncqual::solver

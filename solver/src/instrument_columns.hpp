// SPDX-License-Identifier: Apache-2.0
// What the readers of instrument exports share (internal to the solver library): finding a
// column by its name and unit, reading a length cell, refusing at file lines
// (instrument_columns.cpp); and the columns of the ISO 230-2, circle and grid files, which their
// readers and the plausibility checks (instrument_plausibility.cpp) both read. The formats:
// ncqual/solver/instrument_files.hpp.
#pragma once

#include "ncqual/common/csv.hpp"
#include "ncqual/common/units.hpp"
#include "ncqual/solver/circular_test.hpp"
#include "ncqual/solver/iso230_2.hpp"

#include <array>
#include <cstddef>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace ncqual::solver::detail {

// ---- Columns, units and refusals (instrument_columns.cpp) ---------------------------------------

// The cell in mm, from a column in `unit` (`to_mm` mm each).
double length_mm(const CsvTable& t, const CsvRow& row, std::size_t column, double to_mm = 1,
                 const std::string& unit = "mm");

// The line a whole-data problem is reported at: the last data row, or the header.
int last_line(const CsvTable& t);

// Turns a problem found by the solver (indices into the data) into a CsvError at file lines.
[[noreturn]] void fail_at_lines(const CsvTable& t, const std::vector<int>& lines,
                                const std::optional<std::size_t>& index,
                                const std::optional<std::size_t>& first_index,
                                const std::string& message);

[[noreturn]] void fail_header(const CsvTable& t, const std::string& why);

// A length column of an instrument export and the unit its header names.
struct LengthColumn {
  std::size_t index = 0;
  double to_mm = 1;
  std::string unit = "mm";  // as the header names it: mm, um, in
  bool deviation = false;   // the error from the target, not the position
};

double length_mm(const CsvTable& t, const CsvRow& row, const LengthColumn& c);

// A header name without case, spaces and '_' / '-' around the unit: "Target (mm)" -> "target(mm)".
std::string normalised(std::string_view name);

// The millimetres of one `unit` ("mm", "um", "in", "inch"); nothing for another word.
std::optional<double> mm_per(std::string_view unit);

LengthColumn length_column(std::size_t index, double to_mm);

// The value of a comment "<key>: <value>" (or "<key> = <value>") before the header, with its
// line: an instrument's own header ("# Units: um", "# Values: deviation"). Keys any case.
std::optional<std::pair<int, std::string>> declared(const CsvTable& t,
                                                    std::initializer_list<const char*> keys);

// The length unit the file declares in a comment before its header ("# Units: um"), in mm per
// unit; nothing when it declares none. A declared unit that is not a length unit is refused at
// its line.
std::optional<double> declared_unit(const CsvTable& t);

// The unit of a header that is `base` with a unit ("x_mm", "x(mm)", "x[in]", "x-um"): "" for the
// base alone, the unit's text otherwise; nothing for another name ("x_cmd" is no x column). The
// header normalised (see normalised()).
std::optional<std::string> unit_after(const std::string& n, const std::string& base);

// What a column named <base> with a unit that is not a length does: refuse it (an ISO 230-2
// target or reading in an unknown unit), or skip it (a circle or point export's "x_cmd" is no x
// coordinate).
enum class OtherUnit { Refuse, Skip };

// The first column named <base> with a unit, "<base>_<unit>", "<base>(<unit>)" or
// "<base>[<unit>]" (any case and spacing), for each base in order. A column named <base> alone
// takes the unit a comment before the header declares ("# Units: um"), else it is refused: its
// unit would be a guess; the refusal says to write it as `example` (empty: the column's name
// with " (mm)").
std::optional<LengthColumn> find_length_column(const CsvTable& t,
                                               std::initializer_list<const char*> bases,
                                               const std::string& example,
                                               OtherUnit other = OtherUnit::Refuse);

// A circle's or a point export's length column: other units skipped, the refusal of a bare name
// says to write "<name> (mm)".
std::optional<LengthColumn> find_coordinate_column(const CsvTable& t,
                                                   std::initializer_list<const char*> bases);

// The first column whose normalised name is one of `names`, tried in order.
std::optional<std::size_t> column_named(const CsvTable& t,
                                        std::initializer_list<const char*> names);

// ---- ISO 230-2 runs (instrument_iso230_2.cpp) ---------------------------------------------------

// One column of a wide-form run: its readings' cycle and direction, and the unit and kind of its
// values.
struct RunColumn {
  LengthColumn value;
  int cycle = 0;
  Approach direction = Approach::Up;
};

// The columns of an ISO 230-2 run: the target, each in the unit its header names; then either
// (long form) the measured position or the deviation from the target, the cycle and the
// direction, or (wide form) one column per run and direction.
struct Iso230_2Columns {
  LengthColumn target, measured;
  std::size_t cycle = 0, direction = 0;
  std::vector<RunColumn> runs;  // the wide form; empty for the long form
};

// `words`: also the cycle and direction columns of the long form (the envelope check reads
// lengths only).
Iso230_2Columns iso230_2_columns(const CsvTable& t, bool words = true);

// One reading as the file has it: its row, the target's column and the value's (the measured
// position or the deviation), its cycle and direction.
struct ReadingCells {
  const CsvRow* row = nullptr;
  const LengthColumn* target = nullptr;
  const LengthColumn* value = nullptr;
  int cycle = 0;
  Approach direction = Approach::Up;
};

// Every reading of the run, row by row (in the wide form, the row's run columns left to right;
// an empty cell there is a reading the run did not take). `read_words`: read the long form's
// cycle and direction too (else they are left 0 and Up).
std::vector<ReadingCells> reading_cells(const CsvTable& t, const Iso230_2Columns& c,
                                        bool read_words = true);

double target_mm(const CsvTable& t, const ReadingCells& r);
double measured_mm(const CsvTable& t, const ReadingCells& r);

// ---- Circles (instrument_circle.cpp) ------------------------------------------------------------

// A circle file's columns (the layouts of the header comment of instrument_files.hpp).
struct CircleColumns {
  Plane plane = Plane::XY;
  bool polar = false;
  std::size_t angle = 0;
  double rad_per_angle_unit = units::kPi / 180;
  std::optional<LengthColumn> radius;     // polar: the radius
  std::optional<LengthColumn> deviation;  // polar: the radial deviation from the nominal radius
  LengthColumn u, v;                      // coordinates
  std::optional<std::size_t> direction;
  std::optional<double> nominal_radius_mm;  // declared in a comment or given
};

// `reading`: the columns to read the points (else to check their sizes: neither the plane nor
// the nominal radius is needed).
CircleColumns circle_columns(const CsvTable& t, std::optional<Plane> plane,
                             std::optional<double> nominal_radius_mm, bool reading = true);

// ---- Grids (instrument_grid.cpp) ----------------------------------------------------------------

// The columns of a grid file: commanded and measured X, Y, Z.
struct GridColumns {
  std::array<std::size_t, 3> commanded{}, measured{};
};
GridColumns grid_columns(const CsvTable& t);

}  // namespace ncqual::solver::detail

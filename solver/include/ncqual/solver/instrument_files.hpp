// SPDX-License-Identifier: Apache-2.0
// Readers of instrument exports (CSV, see ncqual/common/csv.hpp for the common format): text (or a
// parsed CsvTable) in, typed data out, no file I/O here (the caller reads the file, e.g. with
// ncqual::read_csv_file, and passes the table); every problem a CsvError "<file>:<line>:<column>:
// <message>" (column left out when a whole row is wrong, line too when the whole file is). Columns
// are found by name, in any order; columns the format does not name are ignored (instrument exports
// carry extras: temperatures, time stamps). Lengths in mm, angles in degrees in the file, radians
// inside.
//
// ISO 230-2 run (laser interferometer), long form:
//     target_mm,cycle,direction,measured_mm
//     0,1,up,0.0012
//   The lengths take the unit their header names: target_mm | target_um | target_in, also
//   written "Target (mm)" or "target [in]" (any case and spacing; "nominal" for "target"); the
//   measured position measured_* ("actual"), or instead the deviation from the target error_*
//   ("deviation"), e.g. "Error (µm)". A length column without a unit, or in another unit, is
//   refused at the header, never guessed. cycle (or "run") an integer; direction (or "dir") up,
//   +, fwd, forward, pos, positive (approach in +) or down, -, bwd, back, backward, rev, reverse,
//   neg, negative (in -), any case. Separators and the decimal comma: ncqual/common/csv.hpp.
//   A length column without a unit takes the unit a comment before the header declares
//   ("# Units: um", "# unit = in"; mm, um, in and their long names).
// ISO 230-2 run, wide form (one row per target, one column per run and direction):
//     Target (mm),Run 1 Fwd Error (µm),Run 1 Bwd Error (µm),Run 2 Fwd Error (µm),...
//   taken when the header has no cycle and direction columns but has run columns: "run", "cycle"
//   or "r", its number, a direction word as above, optionally what the values are ("error",
//   "deviation": from the target; "measured", "actual", "position") and a unit. What a column
//   does not say comes from the comments before the header ("# Units: um", "# Values:
//   deviation"), else the column is refused saying what to write. An empty cell is a reading the
//   run did not take. The readings come row by row, each row's run columns left to right.
//   Refused besides cell errors, with the line of the offending reading: a repeated (target,
//   cycle, direction) naming the first line too; a target and direction with a single cycle; a
//   target measured in one direction only while other targets have both; and, at the last
//   data line (the header line when there is none), fewer than 2 targets.
//
// Circle (ballbar, grid encoder, tracker), one of the layouts
//     angle_deg,radius_mm        polar about the instrument's centre (0, 0) of the plane
//     angle_deg,deviation_um     polar, the radial deviation from the nominal radius (a
//                                ballbar's export): the radius is declared in a comment before
//                                the header ("# Radius: 150 mm", "# Ballbar length = 4 in") or
//                                given (`nominal_radius_mm`), else the column is refused
//     x_mm,y_mm | y_mm,z_mm | x_mm,z_mm   coordinates; the pair names the plane (XY, YZ, XZ)
//     u_mm,v_mm                  coordinates in the plane's first and second axis
//   Column names any case and spacing. Every length column takes the unit its header names
//   (x_in, "X (mm)", "Radius [in]", "Deviation (µm)"; a name without a unit takes the unit a
//   comment declares, "# Units: in", else it is refused); columns named otherwise ("x_cmd") are
//   ignored. The angle "angle" or "theta", in degrees ("Angle (deg)", or none said) or radians
//   ("angle_rad"). The deviation "deviation", "error", "radial deviation", "radial error". An
//   optional direction column ("direction" or "dir": ccw, counterclockwise, anticlockwise, g3
//   or cw, clockwise, g2, any case; default ccw). The plane comes from the header's coordinate
//   pair, a comment ("# Plane: XZ") or the `plane` argument (which must agree); angle/radius and
//   u/v need one of the last two. A nominal radius declared or given is the file's
//   input.nominal_radius_mm (F about it). Partial arcs (ISO 230-4's 90° and 220° tests) are
//   read as arcs (circular_test.hpp). Refused besides cell errors: no layout in the header (the
//   error lists the layouts), both polar and coordinate columns, both a radius and a deviation,
//   a pair that names another plane than the argument, x, y and z without a plane (which
//   pair?), a radius <= 0, a repeated angle (equal modulo one turn, same direction; naming the
//   first line), and the refusals of evaluate_circular_test (fewer than 8 points in a
//   direction, at its last line; points in more than one arc; ...).
//
// Grid / master-frame run (laser tracker):
//     point,x_cmd,y_cmd,z_cmd,x_meas,y_meas,z_meas
//   commanded target position in machine axes and measured position in the instrument frame,
//   mm. Refused besides cell errors: an empty point name, a repeated point name or a repeated
//   commanded position (naming both lines), a file with no points.
#pragma once

#include "ncqual/common/csv.hpp"
#include "ncqual/common/global_check.hpp"
#include "ncqual/common/kinematics.hpp"
#include "ncqual/common/model.hpp"
#include "ncqual/solver/circular_test.hpp"
#include "ncqual/solver/iso230_2.hpp"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ncqual::solver {

struct Iso230_2File {
  std::string file;
  std::vector<PositioningReading> readings;  // in file order, ready for evaluate_iso230_2
  std::vector<int> lines;                    // lines[k]: the file line of readings[k]
};

// Parses an ISO 230-2 run; `file` names it in errors. The readings it returns pass
// find_iso230_2_problem.
Iso230_2File read_iso230_2_csv(std::string_view text, const std::string& file);
Iso230_2File read_iso230_2_csv(const CsvTable& table);

struct CircleFile {
  std::string file;
  CircularTestInput input;  // plane and points; nominal radius and centre left unset
  std::vector<int> lines;   // lines[k]: the file line of input.points[k]
  bool polar = false;       // an angle and a radius or deviation (else coordinates)
  bool deviations = false;  // polar, radial deviations from the nominal radius
};

// Parses a circle file; `plane` is the caller's plane (nullopt: take it from the header or a
// comment), `nominal_radius_mm` the caller's nominal radius (nullopt: the one a comment
// declares, if any). The input it returns passes find_circular_test_problem; its
// nominal_radius_mm is the caller's or the declared one, its nominal centre unset.
CircleFile read_circle_csv(std::string_view text, const std::string& file,
                           std::optional<Plane> plane,
                           std::optional<double> nominal_radius_mm = std::nullopt);
CircleFile read_circle_csv(const CsvTable& table, std::optional<Plane> plane,
                           std::optional<double> nominal_radius_mm = std::nullopt);

struct GridFilePoint {
  std::string point;                                       // name, unique in the file
  Eigen::Vector3d commanded_mm = Eigen::Vector3d::Zero();  // machine axes
  Eigen::Vector3d measured_mm = Eigen::Vector3d::Zero();   // instrument frame
  int line = 0;                                            // file line
};

// Parses a grid / master-frame run, points in file order.
std::vector<GridFilePoint> read_grid_csv(std::string_view text, const std::string& file);
std::vector<GridFilePoint> read_grid_csv(const CsvTable& table);

// ---- Tracker point exports ---------------------------------------------------------------------
// What a tracker's software (or a CMM's) exports of measured points: a name and x, y, z,
//     Point,X (mm),Y (mm),Z (mm)        or  # Units: in / Name<TAB>X<TAB>Y<TAB>Z
// the name column "point", "name", "point name", "id", "label" or "target"; each coordinate in
// the unit its header names or the comments declare (as for circles; a coordinate whose unit
// nothing names is refused). Refused besides cell errors: an empty name, two points whose names
// are the same as the program compares them (below; naming the first line), no points.
struct TrackerExportPoint {
  std::string name;
  Eigen::Vector3d measured_mm = Eigen::Vector3d::Zero();  // instrument frame
  int line = 0;
};
std::vector<TrackerExportPoint> read_tracker_points_csv(const CsvTable& table);

// Whether the table is a point export (a name and x, y, z, no x_cmd): the grid commands take
// one in place of a grid file when the machine is known.
bool is_tracker_point_export(const CsvTable& table);

// A master-frame run or the grid from a point export, the commanded positions from the machine's
// monthly program (global_check_program(GlobalGrid)): each exported point is the move whose label
// has the same name ("x_run:3", "y_run:0", "grid:17", "grid:17:t0"), compared without case,
// separators and leading zeros ("X_RUN_03", "Grid 17"); the commanded position is the main
// target's nominal position at that move. `prefix`: "x_run", "y_run" or "grid". The points in the
// program's order; a point of the program missing from the export is refused (naming up to five,
// at the last line); exported points this run does not take (a drift nest, a reference point,
// the grid's other reflectors) are returned as `ignored` for the caller to report, except the
// points of the program's other runs (a whole session's export is given for every run).
struct GridFromExport {
  std::vector<GridFilePoint> points;
  std::vector<TrackerExportPoint> ignored;
};
GridFromExport grid_points_from_export(const CsvTable& table, const std::string& prefix,
                                       const GlobalCheckConfig& config);

// Every measured point of a tracker check from a point export: each labelled move of the
// machine's program of `kind` (global_check_program; every reflector, the master-frame runs of
// the session) paired by name as above ("c:3" or "C_03", "grid:17:t1", "run:2:down:4"), the
// commanded axes the move's. What the tracker simulator measures, from a real tracker: the
// solver judges it as it judges a simulated set. `points` in the program's order; `located`: the
// same points with the reflector's nominal position as commanded_mm (for check_grid_envelope);
// `ignored`: exported points the program does not name. A program point missing from the export
// is refused as above; std::invalid_argument when `kind` is not a tracker check.
struct TrackerPointsFromExport {
  std::vector<TrackerPoint> points;
  std::vector<GridFilePoint> located;
  std::vector<TrackerExportPoint> ignored;
};
TrackerPointsFromExport tracker_points_from_export(const CsvTable& table, CheckKind kind,
                                                   const GlobalCheckConfig& config);

// ---- CMM results --------------------------------------------------------------------------------
// A coordinate measuring machine's report of a part (or a fixture, a set-point block): per
// characteristic, a feature's coordinate or size with its nominal, the measured value and the
// tolerance band. Lengths only (an angle characteristic is refused naming it), in mm.
struct CmmCharacteristic {
  std::string feature;  // "PNT1", "HOLE_3": as the report names it
  std::string axis;     // "X", "Y", "Z" of a location; a size or distance as written ("D", "M"),
                        // upper case; "" where the report names none
  double nominal_mm = 0, actual_mm = 0;
  // The band of actual - nominal, where the report gives one: lower <= deviation <= upper.
  std::optional<double> lower_mm, upper_mm;
  int line = 0;  // file line
  double deviation_mm() const { return actual_mm - nominal_mm; }
};
struct CmmReport {
  std::string format;                              // "table" or "PC-DMIS text"
  std::vector<CmmCharacteristic> characteristics;  // in file order
};

// Reads a CMM report in either shape:
//  - a table (comma, semicolon or tab; PC-DMIS's and Calypso's table exports, a spreadsheet):
//    a feature column ("Feature", "Name", "ID", "Characteristic", "Point", "Element"), an
//    optional "Axis" column (else the axis is the name's suffix: "PNT1.X", "PNT1_X", "PNT1 X",
//    "CIR1.D" for a diameter),
//    "Nominal", "Actual" (or "Measured", "Meas"), optionally "Deviation" ("Dev"), and the
//    tolerance as "Upper Tol" with "Lower Tol" (signed: the band is nominal + lower .. nominal +
//    upper, as Calypso writes it), "+Tol" with "-Tol" (magnitudes: nominal - tol .. nominal + tol,
//    as PC-DMIS writes it) or one symmetric "Tol". Lengths in the unit the header names
//    ("Nominal (in)") or a comment declares ('# Units: mm'), refused when nothing names it.
//  - PC-DMIS's text report: "DIM <id>= LOCATION OF POINT <name>  UNITS=MM" blocks, each with
//    an "AX NOMINAL +TOL -TOL MEAS DEV OUTTOL" header (columns in any order, BONUS too) and one
//    line per axis; a block's feature is the name after "OF <type>", else the dimension's id. A
//    line with a value in every column is read in the header's order; one with blank cells by
//    where its values stand under the header (PC-DMIS aligns them). A line without MEAS is
//    NOMINAL + DEV. A "TRUE POSITION" block gives X, Y, Z lines (no band), a DF size and a TP
//    line: its material condition (MMC, LMC, RFS) for the nominal (0), the measured position
//    deviation as the actual, judged in 0 .. +TOL + BONUS; there an axis' DEV may be printed as
//    the magnitude of MEAS - NOMINAL. A printed OUTTOL must be what the band gives the deviation.
// A deviation the report prints must be actual - nominal within the rounding of the cells (a
// report that writes nominal - actual is refused: its signs would be read backwards). Refused
// besides cell errors: no characteristics, a feature and axis twice (naming the first line), a
// line missing what it needs ("DIM CIR2 axis X: no MEAS or DEV value ..."): the whole report is
// refused, naming file and line, rather than judged without one of its characteristics.
CmmReport read_cmm_results(std::string_view text, const std::string& file);

// ---- Imports: instrument exports as the tracker points of a MeasurementSet ---------------------
// Labelled as the monthly programs label them (ncqual/common/global_check.hpp), so an export goes
// through the same solver check as a simulated measurement (`ncqual import`). Commanded axes are
// the pivot positions that put `target` (the reflector's geometry, usually the machine's
// global_check.targets[0]) at the file's commanded position, A = C = W = 0.

// x_run:<i>, y_run:<i>, grid:<i>:t0; measured in the file's instrument frame.
std::vector<TrackerPoint> tracker_points_for_grid(const std::vector<GridFilePoint>& x_run,
                                                  const std::vector<GridFilePoint>& y_run,
                                                  const std::vector<GridFilePoint>& grid,
                                                  const ProbeGeometry& target);

// run:<cycle>:<up|down>:<i> (i: the target's rank), along machine axis `axis` (0, 1, 2) from
// `at_mm` (the other two coordinates); the 1-D reading becomes a point on the axis line.
std::vector<TrackerPoint> tracker_points_for_linear_run(const Iso230_2File& run, int axis,
                                                        const Eigen::Vector3d& at_mm,
                                                        const ProbeGeometry& target);

// ccw:<i>, cw:<i>; the file's (u, v) in the plane's two machine axes about `centre_mm`.
std::vector<TrackerPoint> tracker_points_for_circle(const CircleFile& circle,
                                                    const Eigen::Vector3d& centre_mm,
                                                    const ProbeGeometry& target);

// ---- Plausibility against the machine -----------------------------------------------------------
// A reading can be finite and still impossible on this machine: a file in micrometres read as
// millimetres, a broken export. `ncqual import` refuses those before anything is published.

// The box the machine's monthly programs move the spindle's pivot in (the commanded positions of
// every tracker check kind `config` plans, ncqual/common/global_check.hpp).
struct Envelope {
  Eigen::Vector3d lo_mm = Eigen::Vector3d::Zero(), hi_mm = Eigen::Vector3d::Zero();
  // Its largest side, at least 100 mm (a program over a single point still has a machine round it).
  double span_mm() const;
};
Envelope machine_envelope(const GlobalCheckConfig& config);

// Refused, as a CsvError at the cell (file:line:column, the value, the envelope): a position more
// than ten spans beyond the envelope (an order of magnitude), and a deviation from the commanded
// position, or a circle's radius deviation, of more than a tenth of the span (two orders and more
// above any machine error).
//   ISO 230-2 (axis 0, 1, 2: the run's machine axis): target_mm within the envelope's extent on
//     that axis grown by ten spans; measured_mm - target_mm within a tenth of the span.
//   Circle: every coordinate (u, v or radius about the centre) within ten spans; a radial
//     deviation within a tenth of the span. `plane` and `nominal_radius_mm` as for
//     read_circle_csv.
//   Grid (`points` as read_grid_csv or grid_points_from_export read them from `table`): a grid
//     file's x_cmd, y_cmd, z_cmd within the envelope grown by ten spans; the measured distance of
//     each point from the first point (the tracker frame is the machine frame moved rigidly)
//     within a tenth of the span of the commanded one. For a point export the commanded
//     positions are the program's, so a unit declared wrongly ('# Units: mm' over inches) shows
//     as distances 25.4 times too short.
void check_iso230_2_envelope(const CsvTable& table, int axis, const Envelope& envelope);
void check_circle_envelope(const CsvTable& table, const Envelope& envelope,
                           std::optional<Plane> plane = std::nullopt,
                           std::optional<double> nominal_radius_mm = std::nullopt);
void check_grid_envelope(const CsvTable& table, const std::vector<GridFilePoint>& points,
                         const Envelope& envelope);

}  // namespace ncqual::solver

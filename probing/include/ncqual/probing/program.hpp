// SPDX-License-Identifier: Apache-2.0
// Probing programs for real NC controls and the touch logs they write back
// (docs/connecting-a-machine.md has the conventions for people).
//
// A program runs the touch plan of one request (plan.hpp) in a control's language:
//   - header comments: (NCQUAL PROGRAM machine=.. check=.. request=.. dialect=.. units=mm|inch
//     work_offset=G54 touches=N results=FILE version=..), one (NCQUAL PARAMETER name=value) per
//     request parameter, then the conventions in words;
//   - the set-up line: units (G21/G20), absolute, feed per minute, XY plane, no cutter or tool
//     length compensation (G40 G49), the work offset; never G10, G92, G52 or G68;
//   - from any state: up to probing.retract_z_mm in machine coordinates (G53), then every head axis
//     the control has (probing.axes: W, A, C, G53) before X or Y move; the head turns only there;
//   - per touch n (from 1): the structured comment (NCQUAL TOUCH n feature=.. approach=dx,dy,dz
//     w=.. a=.. c=..) on the line before its probing move (approach: the move's unit direction;
//     w in program units, a and c in degrees); before it, over its start at the safe Z, a guarded
//     move down to the start ((NCQUAL GUARD to=x,y,z), then LinuxCNC G38.3 + #5070 + ABORT, Fanuc
//     G31 + #3000, generic-csv a plain G1); after it a straight G1 back to the start along its own
//     path, and a guarded move up to the safe Z when the next touch starts elsewhere. Touches
//     that start where the previous one started (same head) skip the trip. X, Y, Z are the wrist
//     pivot in the work offset's coordinates (pivot = program + work_offset_mm), in program units.
// Dialects:
//   linuxcnc     G38.2 (alarms when it does not trip); the touches go to LinuxCNC's probe log,
//                (PROBEOPEN ncqual-<request>.txt) .. (PROBECLOSE): one line per G38 move
//                (touches and guarded moves), "X Y Z A B C U V W" with %f, work coordinates,
//                program units.
//   fanuc        G31 with the skip positions #5061..#5063; a move that did not trip raises #3000;
//                the program writes with POPEN/DPRNT/PCLOS: first line "NCQUAL <request>", then
//                per touch "T<n> X<x> Y<y> Z<z>" (4 decimals in mm, 5 in inch).
//   generic-csv  G31 moves, each followed by (NCQUAL LOG n): the control (or its macro) writes one
//                line "n,x,y,z" per touch to ncqual-<request>.csv; '#' lines are comments, and a
//                comment "# request <id>" names the program's request.
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/common/error.hpp"
#include "ncqual/common/model.hpp"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ncqual::probing {

// The dialects, their names and the one list of them are ncqual/common/config.hpp's (a machine's
// `instrument:` section names one).
using Dialect = ControlDialect;
inline std::optional<Dialect> dialect_from(std::string_view name) {
  return control_dialect_from(name);
}
inline std::string dialect_names() { return control_dialect_names(); }
using ncqual::to_string;

// A program or log that cannot be used: what() is "<file>:<line>: <message>" (line 0 left out).
class ProgramError : public Error {
 public:
  ProgramError(const std::string& file, int line, const std::string& message);
};

// Writes the program of `request` for `machine` in `dialect`; `version` names the ncqual that
// wrote it. Throws std::invalid_argument with the plan's error when the request has no touch
// plan (plan.hpp: touch_plan).
std::string write_program(const CheckRequest& request, const MachineConfig& machine,
                          Dialect dialect, const std::string& version);

// The name of the results file a program of `request` has the control write ("ncqual-<request
// id>.txt" or ".csv"; for Fanuc the control's own file, whose first line names the request).
std::string results_file_name(const std::string& request_id, Dialect dialect);

// The file a program of `request` is handed to a control in: "ncqual-<request id>.ngc" for
// LinuxCNC, ".nc" for the others.
std::string program_file_name(const std::string& request_id, Dialect dialect);

// One touch as a program describes it.
struct ProgramTouch {
  int number = 0;
  std::string feature;
  Eigen::Vector3d approach = Eigen::Vector3d::UnitX();  // unit direction of the probing move
  double w_mm = 0, a_rad = 0, c_rad = 0;
};

// One probing move of a program in its order: a touch (its number) or a guarded move (0, and
// where it goes, program coordinates and units), as LinuxCNC's probe log has a line for each.
struct ProbeMove {
  int touch = 0;
  Eigen::Vector3d guard_to = Eigen::Vector3d::Zero();
};

// What a program says about itself, read back from its NCQUAL comments.
struct ProgramDescription {
  std::string machine_id, request_id, version, results_file;
  CheckKind kind = CheckKind::MonumentPositioning;
  Dialect dialect = Dialect::LinuxCnc;
  bool inch = false;
  std::string work_offset = "G54";
  std::vector<NamedValue> parameters;
  std::vector<ProgramTouch> touches;   // in program order, numbered 1..N
  std::vector<ProbeMove> probe_moves;  // the touches and the guarded moves, in program order
};

// Reads a program's NCQUAL comments; `file` names it in errors. Throws ProgramError naming the
// line and field when a comment is malformed, the header is missing, or the touches are not
// numbered 1..N in order.
ProgramDescription read_program(const std::string& text, const std::string& file);

// One line of a control's touch log: the touch number where the dialect writes it, and X, Y, Z
// in program units.
struct LoggedTouch {
  std::optional<int> number;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  // LinuxCNC's log: A and C (degrees) and W (program units) where the probe tripped.
  std::optional<Eigen::Vector3d> head;
  int line = 0;
};

struct TouchLog {
  std::optional<std::string> request_id;  // where the log names its program's request
  std::vector<LoggedTouch> touches;
};

// Reads a touch log of `dialect`; throws ProgramError "<file>:<line>: ..." naming the field and
// value that cannot be read. Blank lines, '#' comments (generic-csv), a UTF-8 BOM and CRLF are
// taken.
TouchLog read_touch_log(const std::string& text, const std::string& file, Dialect dialect);

// The MeasurementSet of a program and its log: touch n's feature, head and approach from the
// program, its pivot from the log (converted to mm, plus the machine's work_offset_mm). Refuses
// (ProgramError naming the log) a log of another program (a different request id, in the log or
// in its file name) and a log whose touches do not match the program's: how many were expected
// and found and, where the lines carry touch numbers, the first missing one or the line out of
// order. `machine` must be the program's machine (refused otherwise).
// Its origin is Measured: a control's probe touched the machine.
MeasurementSet measurement_set_from_log(const ProgramDescription& program, const TouchLog& log,
                                        const std::string& log_file, const MachineConfig& machine,
                                        std::int64_t time_ns);

}  // namespace ncqual::probing

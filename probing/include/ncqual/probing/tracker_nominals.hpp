// SPDX-License-Identifier: Apache-2.0
// The nominal point list of a monthly tracker check, for the tracker's software (Spatial
// Analyzer, PolyWorks, Metrolog and the like import a list of named nominals to measure against)
// and for whoever writes the machine's moves (docs/connecting-a-machine.md).
//
// One row per measurement of the check's program (ncqual/common/global_check.hpp:
// global_check_program), in the order the machine runs them:
//   Point,X (mm),Y (mm),Z (mm),Reflector,Machine X (mm),Machine Y (mm),Machine Z (mm),A (deg),
//   C (deg),W (mm)
// Point is the program's label ("x_run:3", "grid:17:t0"); X, Y, Z the reflector's nominal
// position in the machine frame (the machine's pivot at the commanded axes plus the reflector's
// tool length and offset); Reflector the index of global_check.targets; the machine columns the
// commanded axes. Header comments name machine, check, request, version and the number of
// points: "# NCQUAL TRACKER NOMINALS machine=pm1 check=global_grid request=.. points=N
// version=..". The file reads back as a tracker point export (solver/instrument_files.hpp), so
// an export that keeps the point names pairs with the program point for point.
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/common/model.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace ncqual::probing {

// Throws std::invalid_argument when `request.kind` is not a tracker check or the machine has no
// global_check section.
std::string write_tracker_nominals(const CheckRequest& request, const MachineConfig& machine,
                                   const std::string& version);

// What a nominal list says about itself, read back from its NCQUAL comments: the machine, the
// check and the request it was written for, how many points it lists, the request's parameters.
struct TrackerNominalsDescription {
  std::string machine_id, request_id, version;
  CheckKind kind = CheckKind::GlobalGrid;
  std::size_t points = 0;
  std::vector<NamedValue> parameters;
};

// Throws ProgramError (ncqual/probing/program.hpp) naming the file, line and field when the
// "# NCQUAL TRACKER NOMINALS" line is missing or malformed, or names no tracker check. The
// points themselves read as a tracker point export (solver::read_tracker_points_csv).
TrackerNominalsDescription read_tracker_nominals(const std::string& text, const std::string& file);

// "ncqual-<request id>-nominals.csv"
std::string tracker_nominals_file_name(const std::string& request_id);

}  // namespace ncqual::probing

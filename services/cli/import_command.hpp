// `ncqual import`: a real instrument's export published as a MeasurementSet, so it goes through
// the whole service chain (the solver judges it, the historian stores set and result) like a
// simulated measurement. The files are those of `ncqual analyze` (analyze_command.hpp); the
// points are labelled as the monthly programs label them (solver/instrument_files.hpp).
//
//   ncqual import iso230-2 FILE --machine M [--axis x|y|z] [--plant F] [--domain N]
//       kind linear_axis_run; the run along --axis (default the machine's linear_run axis) at
//       the machine's linear_run position
//   ncqual import circle FILE --machine M [--plane XY|YZ|XZ] [--nominal-radius-mm R]
//                         [--centre-mm U,V] [--plant F] [--domain N]
//       kind circle_xy|yz|xz; F about the given reference, else the least-squares circle
//   ncqual import grid --x-run F --y-run F --grid F --machine M [--plant F] [--domain N]
//       kind global_grid with its master-frame runs
//
// Prints the request id of the set (`ncqual wait --request ID` waits for its result). Exit
// codes: 0 published, 1 refused file (file:line:column on stderr) or no solver/historian
// listening, 2 bad usage.
#pragma once

#include <string>
#include <vector>

namespace ncqual {

extern const char* const kImportUsage;
int run_import(const std::vector<std::string>& args);

}  // namespace ncqual

// SPDX-License-Identifier: Apache-2.0
// A stand-in for a machine's NC control, for tests of the control-files driver and of touch logs:
// it "runs" the probing programs it finds on ncqual's simulator (the machine config's
// simulator: section is its true machine) and writes each control's touch log as that control
// formats it. Physics only: it knows nothing of the acquisition's code paths beyond the files.
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/common/model.hpp"
#include "ncqual/probing/program.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace ncqual::testing {

// The touch log the control of `dialect` writes for `touches` (axis readouts, machine
// coordinates) of the program of `request_id` on machine `m`: in the work offset's coordinates
// and the program's units, formatted as that control does (LinuxCNC: "%f" x 9; Fanuc: DPRNT's
// "T<n> X.. Y.. Z.." with CRLF; generic-csv: "n,x,y,z").
// LinuxCNC logs every probing move: with the program's `moves` (ProgramDescription::probe_moves)
// the guarded moves' lines are written too, at their targets (they did not trip), with the head
// of the touch before them when they follow one, else of the touch after them.
std::string control_log(ControlDialect dialect, const std::string& request_id,
                        const std::vector<Touch>& touches, const MachineConfig& m,
                        const std::vector<probing::ProbeMove>& moves = {});

// One look at `m`'s instrument outbox: every probing program there whose results file is not in
// the inbox yet is run on the simulator (measured at `time_ns`) and its log written into the
// inbox, in two writes as a control appends it. Returns the request ids answered.
std::vector<std::string> answer_programs(const MachineConfig& m, std::int64_t time_ns);

}  // namespace ncqual::testing

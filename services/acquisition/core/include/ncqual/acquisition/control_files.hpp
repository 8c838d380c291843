// SPDX-License-Identifier: Apache-2.0
// The control-files driver (`instrument: driver: control-files`): the machine's own NC control
// measures, through files in two folders it shares with the acquisition.
//
//   measure(request)  the request's probing program (ncqual/probing/program.hpp, the machine's
//                     dialect) is written atomically into the outbox as ncqual-<request>.ngc
//                     (LinuxCNC) or .nc; the control (its operator, a DNC link, a watcher) runs
//                     it, and its probe log names the results file the program asks for.
//   poll()            for each program handed over: its results file in the inbox is read up to
//                     its last complete line. All touches there: the MeasurementSet. A line that
//                     cannot be read, a touch too many or out of order, a log of another request:
//                     a MeasurementSet with that error at once. Too few touches: the control may
//                     still be probing, so it waits. Nothing complete after timeout_s: a
//                     MeasurementSet whose error says what was found (no file; n of N touches,
//                     the first missing one) and where. Program and results then go to the
//                     archive folder, kept for the audit trail.
//   apply(fixture)    the fixture's zero offsets are written for its control unit into the
//                     outbox as <fixture>-zero-offsets.txt (one "name value_mm" line each).
//
// A program handed over by an earlier run of the acquisition that never came back is written
// again when its request comes again (the same text), and results already in the inbox are taken.
#pragma once

#include "ncqual/acquisition/instruments.hpp"
#include "ncqual/common/clock.hpp"
#include "ncqual/probing/program.hpp"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace ncqual::acquisition {

class ControlFilesInstruments : public Instruments {
 public:
  // `machine.instrument` names the dialect, the folders and the timeout; `clock` times the
  // timeout (the service's wall clock; a simulated one in tests); `version` is written into each
  // program's header.
  ControlFilesInstruments(const MachineConfig& machine, const Clock& clock, std::string version);

  std::optional<MeasurementSet> measure(const CheckRequest& request, std::int64_t time_ns) override;
  std::vector<MeasurementSet> poll() override;
  std::string apply(const Correction& correction) override;
  // The machine's own control and probe measured it.
  DataOrigin origin() const override { return DataOrigin::Measured; }

  // The programs handed over whose results have not come back.
  std::size_t running() const { return running_.size(); }

 private:
  struct Running {
    CheckRequest request;
    probing::ProgramDescription program;
    std::string program_path, results_path;
    std::int64_t deadline_ns = 0;
  };
  // The set when `r`'s results are complete or unusable; nothing while the control may still be
  // writing them.
  std::optional<MeasurementSet> collect(const Running& r, std::int64_t now_ns) const;
  // Moves the program and its results file into the archive folder (logged when it cannot).
  void archive(const Running& r) const;

  const MachineConfig machine_;
  const Clock& clock_;
  const std::string version_;
  std::map<std::string, Running> running_;  // by request id
};

}  // namespace ncqual::acquisition

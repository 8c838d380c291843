// SPDX-License-Identifier: Apache-2.0
// The instruments of one machine tool, as the acquisition's stations see them: measure a request,
// apply a software correction. A small interface so that a plant can put its own instruments
// behind a station (an MTConnect or OPC UA source, a vendor's probing cycle) without touching the
// rest; docs/connecting-a-machine.md, "Adding an instrument driver", says how. Two exist:
//   SimulatedInstruments     (instrument: driver simulator) measures at once, in this process;
//   ControlFilesInstruments  (driver control-files, control_files.hpp) hands the control a
//                            probing program and collects its touch log later, through poll().
// A driver is called on the acquisition's one thread and must never block it for long: every
// machine the process serves waits while it does.
#pragma once

#include "ncqual/common/clock.hpp"
#include "ncqual/common/config.hpp"
#include "ncqual/common/model.hpp"
#include "ncqual/sim/fixture_simulator.hpp"
#include "ncqual/sim/machine_simulator.hpp"
#include "ncqual/sim/tracker_simulator.hpp"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace ncqual::acquisition {

class Instruments {
 public:
  virtual ~Instruments() = default;

  // Measures `request`, stamped `time_ns` (ns since the epoch, UTC): the raw touches or tracker
  // points, never a verdict. Returns the set when it is measured at once, or nothing when the
  // measurement goes on outside this call (a control running a program): the set then comes from
  // poll(). What cannot be measured (a check the machine has no instrument or config section for,
  // a program that cannot be handed over) comes back as a MeasurementSet whose `error` says why,
  // never as an exception.
  virtual std::optional<MeasurementSet> measure(const CheckRequest& request,
                                                std::int64_t time_ns) = 0;

  // The measurements begun by measure() that ended since the last call: measured, or with their
  // `error` (no results in time, a malformed results file). Called about once a second; must not
  // block. Each request measure() left running comes back exactly once.
  virtual std::vector<MeasurementSet> poll() { return {}; }

  // Applies a software correction for this machine (zero offsets of its fixture, "fixture:<id>").
  // Returns "" when applied or when it is not for an instrument of this machine to apply (a
  // work offset is the control's), else why it was refused.
  virtual std::string apply(const Correction& correction) = 0;

  // A correction an earlier run of the acquisition applied, at start, oldest first. A control
  // keeps its offsets itself, so by default nothing is done; instruments that forget them when
  // the process ends (the simulator) apply it again. "" or why it was refused, as apply().
  virtual std::string restore(const Correction& /*correction*/) { return ""; }

  // Whether its sets are measured by a real instrument or simulated: the station stamps it on
  // every set it publishes (also on one with an error), so a verdict on simulated numbers is never
  // taken for a machine's. No default: a driver says which it is.
  virtual DataOrigin origin() const = 0;
};

// The simulated machine, touch probe, monument, fixture and laser tracker of one machine config
// (ncqual/sim): the touch probe measures the monument and set-point checks, the fixture
// simulator the fixture checks when the config has a fixture, the tracker the monthly checks when
// it has a global_check section.
class SimulatedInstruments : public Instruments {
 public:
  explicit SimulatedInstruments(const MachineConfig& machine);

  std::optional<MeasurementSet> measure(const CheckRequest& request, std::int64_t time_ns) override;
  std::string apply(const Correction& correction) override;
  // The simulated fixture's zeros live in this process: applied again.
  std::string restore(const Correction& correction) override { return apply(correction); }
  DataOrigin origin() const override { return DataOrigin::Simulated; }

 private:
  MeasurementSet simulate(const CheckRequest& request, std::int64_t time_ns);
  const MachineConfig machine_;
  const sim::MachineSimulator simulator_;
  std::optional<sim::FixtureSimulator> fixture_;
  std::optional<sim::TrackerSimulator> tracker_;
};

// The instruments the machine's `instrument:` section names: the simulator, or the
// control-files driver timed by `clock` and writing `version` into its programs.
std::unique_ptr<Instruments> make_instruments(const MachineConfig& machine, const Clock& clock,
                                              const std::string& version);

// A MeasurementSet for `request` with nothing measured and `error` saying why.
MeasurementSet unmeasured(const CheckRequest& request, std::int64_t time_ns,
                          const std::string& error);

}  // namespace ncqual::acquisition
